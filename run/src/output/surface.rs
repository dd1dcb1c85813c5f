//! The body's surface as the outputs draw it — the Rerun recording ([`crate::record`]) and the
//! explorer's 3-D view (`decohesion::gui`): the nodes of the mesh's boundary faces renumbered as
//! vertices, two triangles per face, the colouring field at each vertex (|U| at the node, or an
//! element field of [`super::fields`] at the centres of the surface elements around it,
//! averaged), the viridis colour map, and the colours of the interface states and contact
//! statuses; the moulds' drawing is [`mould`]. Uses neither the Rerun SDK nor egui.

pub mod mould;

use super::fields::{centre_scalar, Scalar};
use crate::interface::contact::ContactStatus;
use crate::kernels::NodalField;
use crate::law::InterfaceState;
use crate::mesh::norm;
use crate::model::Model;

/// Colour of an interface node by the state of its law at α (model §2.8): elastic,
/// transition, ruptured; dark grey for glue that forms on contact, not formed yet.
pub fn state_rgb(s: InterfaceState) -> [u8; 3] {
    match s {
        InterfaceState::Elastic => [46, 160, 67],
        InterfaceState::Transition => [245, 166, 35],
        InterfaceState::Ruptured => [208, 2, 27],
        InterfaceState::Unformed => [90, 90, 90],
    }
}

/// Colour of a node by its contact status: open, stick, slip.
pub fn contact_rgb(c: ContactStatus) -> [u8; 3] {
    match c {
        ContactStatus::Open => [160, 160, 160],
        ContactStatus::Stick => [30, 120, 220],
        ContactStatus::Slip => [200, 60, 200],
    }
}

/// The body's surface: the nodes of the boundary faces, renumbered as vertices.
pub struct Surface {
    /// Global node index of each surface vertex.
    pub nodes: Vec<u32>,
    /// Two triangles per boundary face, in vertex numbers.
    pub triangles: Vec<[u32; 3]>,
    /// Surface elements, where element fields are evaluated.
    elements: Vec<u32>,
    /// Elements around each surface vertex (CSR: offsets, indices into `elements`).
    vertex_elements: (Vec<u32>, Vec<u32>),
}

impl Surface {
    pub fn extract(m: &Model) -> Surface {
        let faces = m.mesh.boundary_faces();
        let mut index_of = vec![u32::MAX; m.mesh.nodes.len()];
        let mut nodes = Vec::new();
        let mut triangles = Vec::with_capacity(2 * faces.len());
        let mut elements: Vec<u32> = faces.iter().map(|f| f.1).collect();
        elements.sort_unstable();
        elements.dedup();
        for (q, _) in &faces {
            let v = q.map(|n| {
                if index_of[n as usize] == u32::MAX {
                    index_of[n as usize] = nodes.len() as u32;
                    nodes.push(n);
                }
                index_of[n as usize]
            });
            triangles.push([v[0], v[1], v[2]]);
            // A tetrahedron's face is the degenerate quad [a, b, c, c]: one triangle.
            if q[2] != q[3] {
                triangles.push([v[0], v[2], v[3]]);
            }
        }
        // Elements around each surface vertex (only surface elements touch the surface).
        let mut offsets = vec![0u32; nodes.len() + 1];
        for &e in &elements {
            for &n in m.mesh.element_nodes(e as usize) {
                let v = index_of[n as usize];
                if v != u32::MAX {
                    offsets[v as usize + 1] += 1;
                }
            }
        }
        for i in 1..offsets.len() {
            offsets[i] += offsets[i - 1];
        }
        let mut fill = offsets.clone();
        let mut adjacent = vec![0u32; *offsets.last().unwrap_or(&0) as usize];
        for (k, &e) in elements.iter().enumerate() {
            for &n in m.mesh.element_nodes(e as usize) {
                let v = index_of[n as usize];
                if v != u32::MAX {
                    adjacent[fill[v as usize] as usize] = k as u32;
                    fill[v as usize] += 1;
                }
            }
        }
        Surface {
            nodes,
            triangles,
            elements,
            vertex_elements: (offsets, adjacent),
        }
    }

    /// The colouring field at each vertex: `None`, |U| at the node; an element field at the
    /// centres of the surface elements around it, averaged.
    pub fn values<U: NodalField + ?Sized>(
        &self,
        m: &Model,
        u: &U,
        field: Option<Scalar>,
    ) -> Vec<f64> {
        let Some(field) = field else {
            return self.nodes.iter().map(|&n| norm(u.at(n as usize))).collect();
        };
        let per_element: Vec<f64> = self
            .elements
            .iter()
            .map(|&e| centre_scalar(m, e as usize, u, field))
            .collect();
        let (offsets, adjacent) = &self.vertex_elements;
        (0..self.nodes.len())
            .map(|v| {
                let r = offsets[v] as usize..offsets[v + 1] as usize;
                let k = r.len().max(1) as f64;
                adjacent[r]
                    .iter()
                    .map(|&i| per_element[i as usize])
                    .sum::<f64>()
                    / k
            })
            .collect()
    }
}

/// " + N tet4" for a mesh with tetrahedra (model §1.13), nothing for hexahedra alone (the
/// labels of the recording and of `check`).
pub fn tet_count(mesh: &crate::mesh::Mesh) -> String {
    if mesh.tets.is_empty() {
        String::new()
    } else {
        format!(" + {} tet4", mesh.tets.len())
    }
}

/// Viridis, 9 samples (matplotlib), interpolated linearly.
pub fn viridis(t: f64) -> [u8; 3] {
    const C: [[f64; 3]; 9] = [
        [68.0, 1.0, 84.0],
        [71.0, 44.0, 122.0],
        [59.0, 81.0, 139.0],
        [44.0, 113.0, 142.0],
        [33.0, 144.0, 141.0],
        [39.0, 173.0, 129.0],
        [92.0, 200.0, 99.0],
        [170.0, 220.0, 50.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * 8.0;
    let i = (x.floor() as usize).min(7);
    let f = x - i as f64;
    let c = |k: usize| (C[i][k] * (1.0 - f) + C[i + 1][k] * f).round() as u8;
    [c(0), c(1), c(2)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_clamps() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        assert_eq!(viridis(0.5), [33, 144, 141]);
    }
}
