//! Meshes of hexahedra and tetrahedra: nodes, 8-node trilinear elements, 4-node linear
//! tetrahedra ([`tet`], model §1.13), named boundary face sets, and the
//! reference-configuration quantities that the total Lagrangian formulation computes once (model
//! §1.5, §1.7, §2.1): shape-function gradients ∇ₓNₐ and weights w·det J₀ at the Gauss points,
//! lumped masses, tributary areas of boundary faces.
//!
//! Node numbering of an element follows the usual convention: nodes 0–3 on the ζ = −1 face
//! counter-clockwise seen from +ζ, nodes 4–7 above them.

use std::collections::BTreeMap;
mod classes;
mod order;
pub mod planes;
pub mod rows;
pub mod split;
pub mod tet;

pub use crate::element::hex8::{
    corner_bound_constant, gauss_points, hourglass_vectors, shape, shape_derivatives, CentreData,
    GaussData, CORNER_EDGES, HEX_CORNERS, ORIENTED_EDGES,
};
use crate::element::{Element, Hex8, Tet4};
pub use crate::vec3::{cross, dot, norm, sub};
pub use classes::{ElementClasses, GeometryError};
pub use order::Slabs;
pub use planes::{NodalField, Planes};
pub use tet::TetData;

/// A mesh of hexahedra and tetrahedra in its reference configuration. Lengths in metres.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Reference positions X of the nodes [m].
    pub nodes: Vec<[f64; 3]>,
    /// Hexahedron connectivity (8 node indices, see module docs for the order).
    pub elements: Vec<[u32; 8]>,
    /// Tetrahedron connectivity (4 node indices, positive volume, [`tet`]). Element indices in
    /// messages number the hexahedra first, then these ([`Mesh::element_count`]).
    pub tets: Vec<[u32; 4]>,
    /// Named boundary face sets: quadrilaterals whose node order gives an outward normal. A
    /// triangle [a, b, c] is stored as the degenerate quadrilateral [a, b, c, c]: its bilinear
    /// map integrates ∫Nₐ dA = A/3 exactly at every corner ([`Mesh::nodal_areas`]) and its
    /// diagonals give the triangle's normal ([`Mesh::quad_normal`]).
    pub face_sets: BTreeMap<String, Vec<[u32; 4]>>,
}

impl Mesh {
    /// A structured box [origin, origin + size] with `cells` hexahedra per axis, and the six face
    /// sets `x-`, `x+`, `y-`, `y+`, `z-`, `z+`.
    pub fn boxed(origin: [f64; 3], size: [f64; 3], cells: [usize; 3]) -> Mesh {
        let [nx, ny, nz] = cells;
        let nid = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as u32;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    nodes.push([
                        origin[0] + size[0] * i as f64 / nx as f64,
                        origin[1] + size[1] * j as f64 / ny as f64,
                        origin[2] + size[2] * k as f64 / nz as f64,
                    ]);
                }
            }
        }
        let mut elements = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    elements.push([
                        nid(i, j, k),
                        nid(i + 1, j, k),
                        nid(i + 1, j + 1, k),
                        nid(i, j + 1, k),
                        nid(i, j, k + 1),
                        nid(i + 1, j, k + 1),
                        nid(i + 1, j + 1, k + 1),
                        nid(i, j + 1, k + 1),
                    ]);
                }
            }
        }
        let mut face_sets = BTreeMap::new();
        // Each quad is ordered counter-clockwise seen from outside (outward normal).
        let mut xm = vec![];
        let mut xp = vec![];
        for k in 0..nz {
            for j in 0..ny {
                xm.push([
                    nid(0, j, k),
                    nid(0, j, k + 1),
                    nid(0, j + 1, k + 1),
                    nid(0, j + 1, k),
                ]);
                xp.push([
                    nid(nx, j, k),
                    nid(nx, j + 1, k),
                    nid(nx, j + 1, k + 1),
                    nid(nx, j, k + 1),
                ]);
            }
        }
        let mut ym = vec![];
        let mut yp = vec![];
        for k in 0..nz {
            for i in 0..nx {
                ym.push([
                    nid(i, 0, k),
                    nid(i + 1, 0, k),
                    nid(i + 1, 0, k + 1),
                    nid(i, 0, k + 1),
                ]);
                yp.push([
                    nid(i, ny, k),
                    nid(i, ny, k + 1),
                    nid(i + 1, ny, k + 1),
                    nid(i + 1, ny, k),
                ]);
            }
        }
        let mut zm = vec![];
        let mut zp = vec![];
        for j in 0..ny {
            for i in 0..nx {
                zm.push([
                    nid(i, j, 0),
                    nid(i, j + 1, 0),
                    nid(i + 1, j + 1, 0),
                    nid(i + 1, j, 0),
                ]);
                zp.push([
                    nid(i, j, nz),
                    nid(i + 1, j, nz),
                    nid(i + 1, j + 1, nz),
                    nid(i, j + 1, nz),
                ]);
            }
        }
        for (name, set) in [
            ("x-", xm),
            ("x+", xp),
            ("y-", ym),
            ("y+", yp),
            ("z-", zm),
            ("z+", zp),
        ] {
            face_sets.insert(name.to_string(), set);
        }
        Mesh {
            nodes,
            elements,
            tets: Vec::new(),
            face_sets,
        }
    }
    /// Distinct nodes of a face set, in increasing order.
    pub fn face_set_nodes(&self, quads: &[[u32; 4]]) -> Vec<u32> {
        let mut v: Vec<u32> = quads.iter().flatten().copied().collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Tributary reference areas W_a = ∫ Nₐ dA over the quads of a face set (2×2 Gauss on each
    /// bilinear quad), as (node, W) pairs sorted by node (model §2.1: reference W).
    pub fn nodal_areas(&self, quads: &[[u32; 4]]) -> Vec<(u32, f64)> {
        let mut acc: BTreeMap<u32, f64> = BTreeMap::new();
        let g = 1.0 / 3f64.sqrt();
        for quad in quads {
            let x = quad.map(|n| self.nodes[n as usize]);
            for (s, t) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
                let n = [
                    0.25 * (1.0 - s) * (1.0 - t),
                    0.25 * (1.0 + s) * (1.0 - t),
                    0.25 * (1.0 + s) * (1.0 + t),
                    0.25 * (1.0 - s) * (1.0 + t),
                ];
                let ds = [-(1.0 - t), 1.0 - t, 1.0 + t, -(1.0 + t)].map(|v| 0.25 * v);
                let dt = [-(1.0 - s), -(1.0 + s), 1.0 + s, 1.0 - s].map(|v| 0.25 * v);
                let mut a = [0.0; 3];
                let mut b = [0.0; 3];
                for k in 0..4 {
                    for c in 0..3 {
                        a[c] += ds[k] * x[k][c];
                        b[c] += dt[k] * x[k][c];
                    }
                }
                let cr = cross(a, b);
                let da = norm(cr);
                for k in 0..4 {
                    *acc.entry(quad[k]).or_insert(0.0) += n[k] * da;
                }
            }
        }
        acc.into_iter().collect()
    }

    /// Outward unit normal of a quad in the reference configuration (from its diagonals).
    pub fn quad_normal(&self, quad: &[u32; 4]) -> [f64; 3] {
        let x = quad.map(|n| self.nodes[n as usize]);
        let d1 = sub(x[2], x[0]);
        let d2 = sub(x[3], x[1]);
        let c = cross(d1, d2);
        let l = norm(c);
        [c[0] / l, c[1] / l, c[2] / l]
    }

    /// Smallest edge length of the mesh [m] (for messages and scales).
    /// Faces of the hexahedra that belong to one element only: the boundary of the body, each
    /// quad ordered counter-clockwise seen from outside (outward normal), and the element it
    /// belongs to. Used to draw the surface; not needed by the time loop.
    pub fn boundary_faces(&self) -> Vec<([u32; 4], u32)> {
        let mut out = exposed_faces(self.nodes.len(), &self.elements, Hex8::FACES);
        out.sort_unstable_by_key(|v| (v.1, v.0));
        // The tetrahedra's faces, as degenerate quads [a, b, c, c], numbered after the
        // hexahedra ([`Mesh::element_count`]).
        let first = self.elements.len() as u32;
        let tets = exposed_faces(self.nodes.len(), &self.tets, Tet4::FACES);
        out.extend(tets.into_iter().map(|(q, e)| (q, first + e)));
        out
    }

    /// Every element's nodes with its type's topology: the hexahedra, then the tetrahedra (the
    /// numbering of [`Mesh::element_count`]).
    pub fn cells(&self) -> impl Iterator<Item = (&[u32], Topology)> + '_ {
        let hex = Topology::of::<Hex8>();
        let tet = Topology::of::<Tet4>();
        (self.elements.iter().map(move |c| (&c[..], hex)))
            .chain(self.tets.iter().map(move |c| (&c[..], tet)))
    }

    /// The nodes of element `e` in the numbering of [`Mesh::element_count`]: a hexahedron's 8,
    /// or a tetrahedron's 4.
    pub fn element_nodes(&self, e: usize) -> &[u32] {
        match self.elements.get(e) {
            Some(conn) => conn,
            None => &self.tets[e - self.elements.len()],
        }
    }

    /// Deformation gradient F = I + Σₐ uₐ ⊗ ∇ₓNₐ at the centre (ξ = 0) of element `e`
    /// (model §1.2), for post-processing (von Mises stress, J) of a displacement field `u`.
    /// A tetrahedron (e ≥ `elements.len()`): its constant F = I + Σₐ uₐ ⊗ ∇ₓNₐ (model §1.13).
    pub fn centre_deformation_gradient<U: NodalField + ?Sized>(
        &self,
        e: usize,
        u: &U,
    ) -> [[f64; 3]; 3] {
        if e >= self.elements.len() {
            let t = e - self.elements.len();
            let (_, g) = crate::element::tet4::tet_gradients(&self.tet_coords(t));
            let ue = self.tets[t].map(|n| u.at(n as usize));
            return crate::element::tet4::tet_deformation_gradient(&g, &ue);
        }
        let x = self.element_coords(e);
        let d = shape_derivatives([0.0; 3]);
        // J₀ = ∂X/∂ξ, then ∇ₓNₐ = J₀⁻ᵀ ∂Nₐ/∂ξ.
        let mut j0 = nalgebra::Matrix3::<f64>::zeros();
        for a in 0..8 {
            for i in 0..3 {
                for k in 0..3 {
                    j0[(i, k)] += x[a][i] * d[a][k];
                }
            }
        }
        let inv_t = j0
            .try_inverse()
            .unwrap_or_else(|| nalgebra::Matrix3::from_element(f64::NAN))
            .transpose();
        let mut f = [[0.0; 3]; 3];
        for (i, row) in f.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        for a in 0..8 {
            let g = inv_t * nalgebra::Vector3::new(d[a][0], d[a][1], d[a][2]);
            let ua = u.at(self.elements[e][a] as usize);
            for i in 0..3 {
                for j in 0..3 {
                    f[i][j] += ua[i] * g[j];
                }
            }
        }
        f
    }

    /// Centre of volume X_c = ∫X dV / ∫dV of the reference mesh (the centre of mass for a
    /// uniform density), from the lumped nodal volumes: row-sum lumping keeps first moments,
    /// Σₐ Vₐ Xₐ = ∫ Σₐ Nₐ Xₐ dV = ∫ X dV.
    pub fn centre_of_volume(&self) -> Result<[f64; 3], GeometryError> {
        let classes = self.element_classes()?;
        let (mut moment, mut volume) = ([0.0; 3], 0.0);
        for (e, conn) in self.elements.iter().enumerate() {
            let lv = classes.data[classes.class_of[e] as usize].lumped_volumes();
            for a in 0..8 {
                let x = self.nodes[conn[a] as usize];
                for c in 0..3 {
                    moment[c] += lv[a] * x[c];
                }
                volume += lv[a];
            }
        }
        // A tetrahedron's lumped volumes are V/4 (model §1.13).
        let tets = self.tet_data()?;
        for (conn, v) in self.tets.iter().zip(&tets.volume) {
            for &a in conn {
                let x = self.nodes[a as usize];
                for c in 0..3 {
                    moment[c] += 0.25 * v * x[c];
                }
                volume += 0.25 * v;
            }
        }
        Ok(moment.map(|m| m / volume))
    }

    /// Largest ratio of the longest to the shortest edge over the elements (1 for cubes).
    pub fn max_aspect_ratio(&self) -> f64 {
        self.cells()
            .map(|(conn, top)| {
                let (lo, hi) =
                    (top.edges.iter()).fold((f64::INFINITY, 0.0f64), |(lo, hi), &(a, b)| {
                        let l = norm(sub(
                            self.nodes[conn[a] as usize],
                            self.nodes[conn[b] as usize],
                        ));
                        (lo.min(l), hi.max(l))
                    });
                hi / lo
            })
            .fold(0.0, f64::max)
    }

    pub fn min_edge(&self) -> f64 {
        let mut m = f64::INFINITY;
        for (conn, top) in self.cells() {
            for &(a, b) in top.edges {
                m = m.min(norm(sub(
                    self.nodes[conn[a] as usize],
                    self.nodes[conn[b] as usize],
                )));
            }
        }
        m
    }
}

/// An element type's faces and edges, as the mesh's loops read them ([`Element`]).
#[derive(Debug, Clone, Copy)]
pub struct Topology {
    /// [`Element::FACES`].
    pub faces: &'static [&'static [usize]],
    /// [`Element::EDGES`].
    pub edges: &'static [(usize, usize)],
    /// [`Element::VTK_TYPE`].
    pub vtk_type: u8,
}

impl Topology {
    pub const fn of<E: Element>() -> Topology {
        Topology {
            faces: E::FACES,
            edges: E::EDGES,
            vtk_type: E::VTK_TYPE,
        }
    }

    /// Local face `f` of the element of nodes `conn` as mesh nodes, a triangle [a, b, c] as the
    /// degenerate quadrilateral [a, b, c, c] of the face sets ([`Mesh::face_sets`]).
    pub fn face(conn: &[u32], f: &[usize]) -> [u32; 4] {
        [conn[f[0]], conn[f[1]], conn[f[2]], conn[f[f.len() - 1]]]
    }
}

/// The faces (`faces`, [`Element::FACES`]) of the elements `conns` that belong to one of them
/// only, as [`Topology::face`] quadrilaterals with their element's index in `conns`, by element
/// and in the order of `faces`. A face is interior when another element holds its nodes; the
/// candidates are the few elements around its first node (compressed rows, 4 bytes per node and
/// per element node: a hash map of every face took many times that at its peak, while the
/// recorder starts beside the solver's set-up).
fn exposed_faces<const N: usize>(
    nodes: usize,
    conns: &[[u32; N]],
    faces: &[&[usize]],
) -> Vec<([u32; 4], u32)> {
    let mut start = vec![0u32; nodes + 1];
    for conn in conns {
        for &a in conn {
            start[a as usize + 1] += 1;
        }
    }
    for i in 0..nodes {
        start[i + 1] += start[i];
    }
    let mut around = vec![0u32; start[nodes] as usize];
    let mut fill = start.clone();
    for (e, conn) in conns.iter().enumerate() {
        for &a in conn {
            around[fill[a as usize] as usize] = e as u32;
            fill[a as usize] += 1;
        }
    }
    drop(fill);
    let mut out = Vec::new();
    for (e, conn) in conns.iter().enumerate() {
        for f in faces {
            let quad = Topology::face(conn, f);
            let a0 = quad[0] as usize;
            let shared = (around[start[a0] as usize..start[a0 + 1] as usize].iter())
                .any(|&e2| e2 as usize != e && quad.iter().all(|q| conns[e2 as usize].contains(q)));
            if !shared {
                out.push((quad, e as u32));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The boundary faces are the faces that belong to one element only, counted over every
    /// face (the definition, with a map of sorted node sets), on a box with a notch and a
    /// hole, so that interior, notch and hole faces all occur; in the same order.
    #[test]
    fn boundary_faces_are_the_faces_of_one_element() {
        let mut m = Mesh::boxed([0.0; 3], [1.0, 1.0, 1.0], [4, 3, 3]);
        // Remove a corner element and a central one (the latter leaves an inner cavity).
        let centre = m.elements.len() / 2;
        m.elements = m
            .elements
            .iter()
            .enumerate()
            .filter(|&(e, _)| e != 0 && e != centre)
            .map(|(_, c)| *c)
            .collect();
        let mut count: std::collections::HashMap<[u32; 4], (usize, [u32; 4], u32)> =
            std::collections::HashMap::new();
        for (e, conn) in m.elements.iter().enumerate() {
            for f in crate::element::hex8::FACES {
                let quad = f.map(|a| conn[a]);
                let mut key = quad;
                key.sort_unstable();
                count
                    .entry(key)
                    .and_modify(|v| v.0 += 1)
                    .or_insert((1, quad, e as u32));
            }
        }
        let mut expect: Vec<([u32; 4], u32)> = count
            .into_values()
            .filter(|v| v.0 == 1)
            .map(|v| (v.1, v.2))
            .collect();
        expect.sort_unstable_by_key(|v| (v.1, v.0));
        // 2(12 + 9 + 12) outside, the notch trades 3 faces for 3, the cavity adds 6.
        assert_eq!(expect.len(), 66 + 6);
        assert_eq!(m.boundary_faces(), expect);
    }

    /// The boundary of an n₁×n₂×n₃ box has 2(n₁n₂ + n₂n₃ + n₁n₃) quads, each pointing away
    /// from the centre of its element; F at the centre is exact for an affine field.
    #[test]
    fn boundary_faces_and_centre_gradient() {
        let mut m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        m.nodes[30][0] += 0.05; // a distorted interior node must not matter
        let faces = m.boundary_faces();
        assert_eq!(faces.len(), 2 * (3 * 4 + 4 * 5 + 3 * 5));
        for (q, e) in &faces {
            let c_face = q.iter().fold([0.0; 3], |acc, &n| {
                let x = m.nodes[n as usize];
                [
                    acc[0] + x[0] / 4.0,
                    acc[1] + x[1] / 4.0,
                    acc[2] + x[2] / 4.0,
                ]
            });
            let c_el = m.elements[*e as usize].iter().fold([0.0; 3], |acc, &n| {
                let x = m.nodes[n as usize];
                [
                    acc[0] + x[0] / 8.0,
                    acc[1] + x[1] / 8.0,
                    acc[2] + x[2] / 8.0,
                ]
            });
            assert!(dot(m.quad_normal(q), sub(c_face, c_el)) > 0.0);
        }
        let g = [[0.1, -0.02, 0.03], [0.05, 0.2, 0.0], [0.0, 0.01, -0.1]];
        let u: Vec<[f64; 3]> = m
            .nodes
            .iter()
            .map(|x| [dot(g[0], *x), dot(g[1], *x), dot(g[2], *x)])
            .collect();
        for e in [0, 17, 59] {
            let f = m.centre_deformation_gradient(e, &u[..]);
            for i in 0..3 {
                for j in 0..3 {
                    let expect = g[i][j] + if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (f[i][j] - expect).abs() < 1e-13,
                        "F[{i}][{j}] of element {e}"
                    );
                }
            }
        }
    }

    #[test]
    fn face_areas_and_normals() {
        let m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        let expect = [
            ("x-", 6.0, [-1.0, 0.0, 0.0]),
            ("y+", 3.0, [0.0, 1.0, 0.0]),
            ("z-", 2.0, [0.0, 0.0, -1.0]),
        ];
        for (name, area, normal) in expect {
            let quads = &m.face_sets[name];
            let w: f64 = m.nodal_areas(quads).iter().map(|p| p.1).sum();
            assert!((w - area).abs() < 1e-12, "{name}: {w}");
            for q in quads {
                let n = m.quad_normal(q);
                assert!(norm(sub(n, normal)) < 1e-12, "{name}: {n:?}");
            }
        }
    }
}
