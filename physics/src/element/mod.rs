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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::{cross, dot, sub};

    /// The nodes of a reference element mapped by X = A ξ + b (det A > 0), so
    /// that its faces stay planar and its volume is det A times the reference one.
    fn mapped(reference: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let a = [[1.1, 0.2, -0.1], [0.05, 0.9, 0.3], [0.0, -0.2, 1.3]];
        (reference.iter())
            .map(|xi| std::array::from_fn(|i| dot(a[i], *xi) + [0.3, -1.0, 2.0][i]))
            .collect()
    }

    /// Checks an element type's declaration on an affinely mapped element of reference volume
    /// `v_ref`: its faces are outward (each face's area vector, by the shoelace sum of its
    /// corners, points away from the element's centroid), every edge borders exactly two faces
    /// and every side of a face is an edge (a closed surface: V − E + F = 2), and the lumped
    /// volumes add up to det A · v_ref (exact for an affine map, to round-off).
    fn check<E: Element>(reference: &[[f64; 3]], v_ref: f64) {
        assert_eq!(reference.len(), E::NODES, "{}", E::NAME);
        let x = mapped(reference);
        let centroid: [f64; 3] =
            std::array::from_fn(|i| x.iter().map(|p| p[i]).sum::<f64>() / x.len() as f64);
        let mut sides = vec![0usize; E::EDGES.len()];
        for face in E::FACES {
            let mut area = [0.0; 3];
            for (k, &a) in face.iter().enumerate() {
                let b = face[(k + 1) % face.len()];
                let c = cross(x[a], x[b]);
                area = std::array::from_fn(|i| area[i] + 0.5 * c[i]);
                let edge = (E::EDGES.iter())
                    .position(|&(p, q)| (p, q) == (a, b) || (p, q) == (b, a))
                    .unwrap_or_else(|| panic!("{}: face side {a}–{b} is no edge", E::NAME));
                sides[edge] += 1;
            }
            let face_centre: [f64; 3] = std::array::from_fn(|i| {
                face.iter().map(|&a| x[a][i]).sum::<f64>() / face.len() as f64
            });
            assert!(
                dot(area, sub(face_centre, centroid)) > 0.0,
                "{}: face {face:?} points inward",
                E::NAME
            );
        }
        assert!(sides.iter().all(|&s| s == 2), "{}: {sides:?}", E::NAME);
        assert_eq!(E::NODES + E::FACES.len(), E::EDGES.len() + 2, "{}", E::NAME);
        let r = E::reference(&x).unwrap_or_else(|d| panic!("{}: det {d}", E::NAME));
        let mut lumped = vec![0.0; E::NODES];
        E::lumped_volumes(&r, &mut lumped);
        let det_a = 1.1 * (0.9 * 1.3 + 0.2 * 0.3) - 0.2 * (0.05 * 1.3) + (-0.1) * (0.05 * -0.2);
        let v = lumped.iter().sum::<f64>();
        assert!(
            (v - det_a * v_ref).abs() <= 1e-14 * v,
            "{}: {v} against {}",
            E::NAME,
            det_a * v_ref
        );
        // Mirrored (an inverted element), the reference data is refused.
        let mirrored: Vec<[f64; 3]> = x.iter().map(|p| [-p[0], p[1], p[2]]).collect();
        assert!(E::reference(&mirrored).is_err(), "{}", E::NAME);
    }

    #[test]
    fn hexahedron_and_tetrahedron_declare_a_closed_outward_surface_and_their_volume() {
        check::<Hex8>(&hex8::HEX_CORNERS, 8.0);
        let unit = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        check::<Tet4>(&unit, 1.0 / 6.0);
    }
}
