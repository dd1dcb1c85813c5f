//! The element types (model §1.5, §1.13), one folder each: what an element is by itself, apart
//! from any mesh — its topology (nodes, faces, edges), its reference data computed once from
//! its node coordinates (with the Jacobian check that refuses an inverted element), its lumped
//! volumes and the kernels that compute its internal forces.
//!
//! - [`hex8`]: the 8-node trilinear hexahedron, full 2×2×2 or one-point integration;
//! - [`tet4`]: the linear 4-node tetrahedron.
//!
//! The bottom layer of the crate with [`crate::material`]: a mesh ([`crate::mesh`]) is made of
//! elements, the assembly loops ([`crate::kernels`]) run their kernels.

pub mod hex8;
pub mod tet4;

pub use hex8::Hex8;
pub use tet4::Tet4;

/// What an element type declares about itself (model §1.5, §1.13), so that the mesh's loops
/// (boundary faces, edges, lumped volumes, the Jacobian check), the Gmsh reader and the ParaView
/// writer need no case per type: implemented by [`Hex8`] and [`Tet4`].
pub trait Element {
    /// What messages call it ("8-node hexahedron").
    const NAME: &'static str;
    /// Its number of nodes.
    const NODES: usize;
    /// Its element type in Gmsh's `.msh` format.
    const GMSH_TYPE: i32;
    /// Its VTK cell type (ParaView), whose node order is ours.
    const VTK_TYPE: u8;
    /// Its faces as local node numbers, each counter-clockwise seen from outside (outward
    /// normal): what bounds the body, carries glue and contact, and is drawn.
    const FACES: &'static [&'static [usize]];
    /// Its edges as pairs of local node numbers (the mesh's edge lengths and aspect ratios).
    const EDGES: &'static [(usize, usize)];
    /// What the total Lagrangian formulation computes once from the element's reference node
    /// coordinates (shape-function gradients, weights).
    type Reference;

    /// The reference data of an element whose nodes are at `x` (`Self::NODES` points) [m], or
    /// `Err(det)` with the determinant of ∂X/∂ξ that shows it inverted or degenerate (≤ 0 or
    /// NaN at a point where the element is integrated).
    fn reference(x: &[[f64; 3]]) -> Result<Self::Reference, f64>;

    /// Its lumped volumes ∫ Nₐ dV (model §1.7; the nodal masses per unit density) [m³], into
    /// `out` (`Self::NODES` entries).
    fn lumped_volumes(r: &Self::Reference, out: &mut [f64]);
}
