//! Linear 4-node tetrahedra (model §1.13): the reference quantities computed once — the
//! constant shape-function gradients ∇ₓNₐ, the volume V_e, the nodal volumes
//! Vₐ = Σ_{e∋a} V_e/4 of the average-nodal-pressure element — and the tetrahedron's faces.
//!
//! Node numbering: Gmsh's, with a positive volume V = det[X₁ − X₀, X₂ − X₀, X₃ − X₀]/6.

use super::{GeometryError, Mesh};
use crate::element::tet4::tet_gradients;
use crate::element::{Element, Tet4};

/// Reference data of the tetrahedra of a mesh (model §1.13), one entry per tetrahedron in the
/// order of [`Mesh::tets`].
#[derive(Debug, Clone, Default)]
pub struct TetData {
    /// ∇ₓNₐ of each tetrahedron (constant over the element) [1/m].
    pub grad: Vec<[[f64; 3]; 4]>,
    /// Reference volume V_e [m³].
    pub volume: Vec<f64>,
    /// Per mesh node: Vₐ = Σ_{e∋a} V_e/4 over the tetrahedra around it (0 at a node of no
    /// tetrahedron) [m³].
    pub node_volume: Vec<f64>,
}

impl Mesh {
    /// The same body with each hexahedron cut into the 6 tetrahedra of Kuhn's (Freudenthal's)
    /// decomposition — the paths from the local corner (−1, −1, −1) to (1, 1, 1) along the
    /// three axes in each order — and each face-set quadrilateral into the 2 triangles of that
    /// face (stored as [a, b, c, c]). Every tetrahedron's edges join corners ordered along all
    /// three local axes, so a face's diagonal joins its lowest and highest corners and two
    /// hexahedra numbered alike ([`Mesh::boxed`]) cut their common face the same way: the
    /// tetrahedral mesh is conforming. For meshes whose hexahedra share the local axes (boxes
    /// and their smooth maps); the face sets' diagonals are taken from the same lowest corner
    /// (that of the smallest X + Y + Z, as in a box).
    pub fn kuhn_tets(&self) -> Mesh {
        // Local index of the corner with bits (x, y, z) in [`super::HEX_CORNERS`].
        const AT: [[[usize; 2]; 2]; 2] = [[[0, 4], [3, 7]], [[1, 5], [2, 6]]];
        let orders = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        let mut tets = Vec::with_capacity(6 * self.elements.len() + self.tets.len());
        for conn in &self.elements {
            for order in orders {
                let mut bits = [0usize; 3];
                let mut t = [conn[0]; 4];
                for (k, &axis) in order.iter().enumerate() {
                    bits[axis] = 1;
                    t[k + 1] = conn[AT[bits[0]][bits[1]][bits[2]]];
                }
                let x = t.map(|n| self.nodes[n as usize]);
                if tet_gradients(&x).0 < 0.0 {
                    t.swap(2, 3);
                }
                tets.push(t);
            }
        }
        tets.extend_from_slice(&self.tets);
        let lowest = |q: &[u32; 4]| {
            (0..4)
                .min_by(|&a, &b| {
                    let s = |k: usize| self.nodes[q[k] as usize].iter().sum::<f64>();
                    s(a).total_cmp(&s(b))
                })
                .unwrap_or(0)
        };
        let face_sets = (self.face_sets.iter())
            .map(|(name, quads)| {
                let tris = quads
                    .iter()
                    .flat_map(|q| {
                        if q[2] == q[3] {
                            return vec![*q];
                        }
                        let k = lowest(q);
                        let r = |i: usize| q[(k + i) % 4];
                        vec![[r(0), r(1), r(2), r(2)], [r(0), r(2), r(3), r(3)]]
                    })
                    .collect();
                (name.clone(), tris)
            })
            .collect();
        Mesh {
            nodes: self.nodes.clone(),
            elements: Vec::new(),
            tets,
            face_sets,
        }
    }

    /// Reference coordinates of the nodes of tetrahedron `t`.
    pub fn tet_coords(&self, t: usize) -> [[f64; 3]; 4] {
        self.tets[t].map(|n| self.nodes[n as usize])
    }

    /// Number of elements of every kind: the hexahedra, then the tetrahedra. An element index
    /// `e` ≥ `elements.len()` names tetrahedron `e − elements.len()` (messages, J checks).
    pub fn element_count(&self) -> usize {
        self.elements.len() + self.tets.len()
    }

    /// The reference data of the tetrahedra; a tetrahedron of non-positive volume is refused
    /// (its element index is `elements.len()` + its index among the tetrahedra, det J₀ = 6V).
    pub fn tet_data(&self) -> Result<TetData, GeometryError> {
        let mut data = TetData {
            grad: Vec::with_capacity(self.tets.len()),
            volume: Vec::with_capacity(self.tets.len()),
            node_volume: vec![
                0.0;
                if self.tets.is_empty() {
                    0
                } else {
                    self.nodes.len()
                }
            ],
        };
        for (t, conn) in self.tets.iter().enumerate() {
            let r = Tet4::reference(&self.tet_coords(t)).map_err(|det_j0| GeometryError {
                element: self.elements.len() + t,
                det_j0,
            })?;
            let mut lumped = [0.0; 4];
            Tet4::lumped_volumes(&r, &mut lumped);
            for (&a, v) in conn.iter().zip(lumped) {
                data.node_volume[a as usize] += v;
            }
            data.grad.push(r.grad);
            data.volume.push(r.volume);
        }
        Ok(data)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tet4::TET_FACES;

    /// Σₐ Xₐ ⊗ ∇ₓNₐ = I and Σₐ ∇ₓNₐ = 0 on a distorted tetrahedron; V of the unit corner
    /// tetrahedron is 1/6; the faces point away from the opposite node.
    #[test]
    fn gradients_reproduce_linear_fields_and_faces_point_out() {
        let x = [
            [0.1, -0.2, 0.05],
            [1.3, 0.1, -0.1],
            [0.2, 0.9, 0.15],
            [-0.1, 0.3, 1.1],
        ];
        let (det, g) = tet_gradients(&x);
        assert!(det > 0.0);
        for i in 0..3 {
            for j in 0..3 {
                let s: f64 = (0..4).map(|a| x[a][i] * g[a][j]).sum();
                assert!((s - if i == j { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
            assert!((0..4).map(|a| g[a][i]).sum::<f64>().abs() < 1e-14);
        }
        let unit = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!((tet_gradients(&unit).0 / 6.0 - 1.0 / 6.0).abs() < 1e-16);
        for (k, f) in TET_FACES.iter().enumerate() {
            let opposite = [3, 2, 0, 1][k];
            let p = f.map(|a| x[a]);
            let n =
                super::super::cross(super::super::sub(p[1], p[0]), super::super::sub(p[2], p[0]));
            let out = super::super::sub(p[0], x[opposite]);
            assert!(super::super::dot(n, out) > 0.0, "face {k}");
            assert!(!f.contains(&opposite));
        }
    }
}
