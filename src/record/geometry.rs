//! The per-frame geometry of a recording: the body's surface (extracted once from the mesh's
//! boundary faces; positions x = X + U and colours per frame), the viridis colour map of the
//! colouring field, the moving planes, and the interface and contact nodes with their arrows.

use super::layout::path_part;
use super::stream::Columns;
use super::{ColourField, Statics, ARROW_FRACTION};
use crate::law::InterfaceState;
use crate::mesh::norm;
use crate::model::{Model, Shape};
use crate::output::fields::{centre_scalar, Scalar};
use crate::output::Snapshot;
use crate::solver::ContactStatus;
use rerun::{Arrows3D, ComponentDescriptor, Mesh3D, Points3D, Transform3D};

/// The body's surface: the nodes of the boundary faces, renumbered as vertices.
pub(super) struct Surface {
    /// Global node index of each surface vertex.
    nodes: Vec<u32>,
    /// Two triangles per boundary face, in vertex numbers.
    pub(super) triangles: Vec<[u32; 3]>,
    /// Surface elements, where element fields are evaluated.
    elements: Vec<u32>,
    /// Elements around each surface vertex (CSR: offsets, indices into `elements`).
    vertex_elements: (Vec<u32>, Vec<u32>),
}

impl Surface {
    pub(super) fn extract(m: &Model) -> Surface {
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
            triangles.push([v[0], v[2], v[3]]);
        }
        // Elements around each surface vertex (only surface elements touch the surface).
        let mut offsets = vec![0u32; nodes.len() + 1];
        for &e in &elements {
            for &n in &m.mesh.elements[e as usize] {
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
            for &n in &m.mesh.elements[e as usize] {
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

    /// The colouring field at each vertex: |U| at the node, or an element field at the centres
    /// of the surface elements around it, averaged.
    fn values(&self, m: &Model, u: &[[f64; 3]], colour: ColourField) -> Vec<f64> {
        let field = match colour {
            ColourField::Displacement => {
                return self.nodes.iter().map(|&n| norm(u[n as usize])).collect()
            }
            ColourField::VonMises => Scalar::VonMises,
            ColourField::Jacobian => Scalar::Jacobian,
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

/// Sizes of the drawing, from the reference mesh.
pub(super) struct Scales {
    /// Largest side of the bounding box [m].
    pub(super) extent: f64,
    /// Centre of the bounding box [m].
    pub(super) centre: [f64; 3],
    /// Arrow length per pascal [m/Pa].
    pub(super) arrow_scale: f64,
    pub(super) point_radius: f32,
}

impl Scales {
    pub(super) fn of(m: &Model) -> Scales {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for x in &m.mesh.nodes {
            for i in 0..3 {
                lo[i] = lo[i].min(x[i]);
                hi[i] = hi[i].max(x[i]);
            }
        }
        let extent = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
        let t_max = m
            .interfaces
            .iter()
            .map(|i| i.law.peak_traction().0)
            .fold(0.0, f64::max);
        // No glue: contact pressures are scaled by the stiffness E.
        let t_ref = if t_max > 0.0 { t_max } else { m.material.young };
        Scales {
            extent,
            centre: [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i])),
            arrow_scale: ARROW_FRACTION * extent / t_ref,
            point_radius: (0.15 * m.mesh.min_edge()) as f32,
        }
    }
}

/// What the recording draws in 3-D at every frame.
pub(super) struct Geometry {
    pub(super) surface: Surface,
    pub(super) scales: Scales,
    colour: ColourField,
    /// Smallest and largest finite value of the colouring field so far.
    colour_range: (f64, f64),
    /// Planes with a prescribed velocity: their translation is logged per frame.
    moving_planes: Vec<usize>,
}

/// Position x = X + U of node `n` in a snapshot [m].
fn position(m: &Model, s: &Snapshot, n: u32) -> [f32; 3] {
    let x = m.mesh.nodes[n as usize];
    let u = s.u[n as usize];
    [
        (x[0] + u[0]) as f32,
        (x[1] + u[1]) as f32,
        (x[2] + u[2]) as f32,
    ]
}

/// Class id of a contact status in the annotation context ([`super::layout`]).
fn contact_class(c: ContactStatus) -> u16 {
    match c {
        ContactStatus::Open => 10,
        ContactStatus::Stick => 11,
        ContactStatus::Slip => 12,
    }
}

impl Geometry {
    pub(super) fn new(m: &Model, colour: ColourField) -> Geometry {
        Geometry {
            surface: Surface::extract(m),
            scales: Scales::of(m),
            colour,
            colour_range: (f64::INFINITY, f64::NEG_INFINITY),
            moving_planes: m
                .planes
                .iter()
                .enumerate()
                .filter(|p| p.1.velocity.is_some() && p.1.shape == Shape::HalfSpace)
                .map(|p| p.0)
                .collect(),
        }
    }

    /// Buffers one frame's geometry; returns the range of the colouring field so far.
    pub(super) fn frame(&mut self, cols: &mut Columns, st: &Statics, s: &Snapshot) -> (f64, f64) {
        let m = &st.model;
        self.surface_frame(cols, m, s);
        for &p in &self.moving_planes {
            let plane = &m.planes[p];
            let d = plane.displacement(s.time);
            cols.push(
                &format!("planes/{}", path_part(&plane.name)),
                Transform3D::descriptor_translation(),
                3,
                &[d[0] as f32, d[1] as f32, d[2] as f32],
            );
        }
        if !s.interface.is_empty() {
            self.interface_frame(cols, st, s);
        }
        if !s.contact.is_empty() {
            self.contact_frame(cols, st, s);
        }
        self.colour_range
    }

    /// Body surface: positions and colours (the topology is static).
    fn surface_frame(&mut self, cols: &mut Columns, m: &Model, s: &Snapshot) {
        let nodes = &self.surface.nodes;
        let flat: Vec<f32> = nodes.iter().flat_map(|&n| position(m, s, n)).collect();
        cols.push(
            "body/surface",
            Mesh3D::descriptor_vertex_positions(),
            3,
            &flat,
        );
        let values = self.surface.values(m, &s.u, self.colour);
        for &v in &values {
            if v.is_finite() {
                self.colour_range.0 = self.colour_range.0.min(v);
                self.colour_range.1 = self.colour_range.1.max(v);
            }
        }
        let (lo, hi) = self.colour_range;
        let span = if hi > lo { hi - lo } else { 1.0 };
        let colours: Vec<u32> = values
            .iter()
            .map(|&v| rgba(viridis((v - lo) / span)))
            .collect();
        cols.push(
            "body/surface",
            Mesh3D::descriptor_vertex_colors(),
            1,
            &colours,
        );
    }

    /// Interface nodes: state, contact status, α and gap per node; −R_d on the solid and
    /// R_c/h, both in Pa, as arrows (times the arrow scale).
    fn interface_frame(&self, cols: &mut Columns, st: &Statics, s: &Snapshot) {
        let m = &st.model;
        let h = s.h.max(f64::MIN_POSITIVE);
        let scale = self.scales.arrow_scale;
        let nodes = &st.interface_nodes;
        let pts: Vec<f32> = nodes.iter().flat_map(|&(n, _)| position(m, s, n)).collect();
        let state: Vec<u16> = nodes
            .iter()
            .zip(&s.interface)
            .map(
                |(&(_, itf), snap)| match m.interfaces[itf as usize].law.state(snap.alpha) {
                    InterfaceState::Elastic => 0,
                    InterfaceState::Transition => 1,
                    InterfaceState::Ruptured => 2,
                },
            )
            .collect();
        let contact: Vec<u16> = s
            .interface
            .iter()
            .map(|n| contact_class(n.contact))
            .collect();
        let alpha: Vec<f64> = s.interface.iter().map(|n| n.alpha).collect();
        let gap: Vec<f64> = s.interface.iter().map(|n| n.gap).collect();
        let cohesive: Vec<f32> = s
            .interface
            .iter()
            .flat_map(|n| n.cohesive_traction.map(|t| (-t * scale) as f32))
            .collect();
        let pressure: Vec<f32> = s
            .interface
            .iter()
            .flat_map(|n| n.contact_impulse.map(|r| (r / h * scale) as f32))
            .collect();
        cols.push("interface/nodes", Points3D::descriptor_positions(), 3, &pts);
        cols.push(
            "interface/nodes",
            Points3D::descriptor_class_ids(),
            1,
            &state,
        );
        let partial = ComponentDescriptor::partial;
        cols.push("interface/nodes", partial("alpha_m"), 1, &alpha);
        cols.push("interface/nodes", partial("gap_m"), 1, &gap);
        let status = "interface/contact_status";
        cols.push(status, Points3D::descriptor_positions(), 3, &pts);
        cols.push(status, Points3D::descriptor_class_ids(), 1, &contact);
        for (path, vectors) in [
            ("interface/cohesive_traction", &cohesive),
            ("interface/contact_pressure", &pressure),
        ] {
            cols.push(path, Arrows3D::descriptor_vectors(), 3, vectors);
            cols.push(path, Arrows3D::descriptor_origins(), 3, &pts);
        }
    }

    /// Contact-only nodes: status, and R_c/h as arrows.
    fn contact_frame(&self, cols: &mut Columns, st: &Statics, s: &Snapshot) {
        let m = &st.model;
        let h = s.h.max(f64::MIN_POSITIVE);
        let scale = self.scales.arrow_scale;
        let pts: Vec<f32> = st
            .contact_nodes
            .iter()
            .flat_map(|&n| position(m, s, n))
            .collect();
        let class: Vec<u16> = s.contact.iter().map(|c| contact_class(c.0)).collect();
        let pressure: Vec<f32> = s
            .contact
            .iter()
            .flat_map(|c| c.1.map(|r| (r / h * scale) as f32))
            .collect();
        cols.push("contact/nodes", Points3D::descriptor_positions(), 3, &pts);
        cols.push("contact/nodes", Points3D::descriptor_class_ids(), 1, &class);
        cols.push(
            "contact/pressure",
            Arrows3D::descriptor_vectors(),
            3,
            &pressure,
        );
        cols.push("contact/pressure", Arrows3D::descriptor_origins(), 3, &pts);
    }
}

/// Viridis, 9 samples (matplotlib), interpolated linearly.
pub(super) fn viridis(t: f64) -> [u8; 3] {
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

fn rgba(c: [u8; 3]) -> u32 {
    u32::from_be_bytes([c[0], c[1], c[2], 255])
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
