//! The 8-node trilinear hexahedron (model §1.5, §1.6): its reference data ([`reference`]), the
//! sum-factorised algebra of its trilinear field ([`tensor`]) and its internal-force kernels on
//! one element or on 8 elements in lanes ([`forces`]).

pub mod forces;
pub mod reference;
pub(crate) mod tensor;

#[cfg(target_arch = "wasm32")]
pub(crate) use forces::element_forces_law;
pub(crate) use forces::first_piola_lanes_into;
pub use forces::{
    centre_norms_of, element_forces, element_forces_reduced, element_forces_reduced_lanes,
    element_forces_reduced_lanes_in, hourglass_stiffness, LaneElements, OnePointScratch,
};
pub use reference::{
    corner_bound_constant, gauss_points, hourglass_vectors, shape, shape_derivatives, CentreData,
    GaussData, CORNER_EDGES, HEX_CORNERS, ORIENTED_EDGES,
};
pub use reference::{EDGES, FACES};
pub(crate) use tensor::{
    box_factors, box_forces, box_gradient, modes_to_nodes, node_modes, parent_forces,
    parent_gradient,
};

/// The 8-node trilinear hexahedron: nodes 0–3 on the ζ = −1 face counter-clockwise seen from
/// +ζ, nodes 4–7 above them ([`HEX_CORNERS`]).
pub struct Hex8;

impl super::Element for Hex8 {
    const NAME: &'static str = "8-node hexahedron";
    const NODES: usize = 8;
    const GMSH_TYPE: i32 = 5;
    const VTK_TYPE: u8 = 12;
    const FACES: &'static [&'static [usize]] = &[
        &FACES[0], &FACES[1], &FACES[2], &FACES[3], &FACES[4], &FACES[5],
    ];
    const EDGES: &'static [(usize, usize)] = &EDGES;
    type Reference = GaussData;

    /// [`GaussData::new`]: J₀ at the 8 Gauss points must have a positive determinant.
    fn reference(x: &[[f64; 3]]) -> Result<GaussData, f64> {
        GaussData::new(&std::array::from_fn(|a| x[a]))
    }

    fn lumped_volumes(r: &GaussData, out: &mut [f64]) {
        out.copy_from_slice(&r.lumped_volumes());
    }
}
