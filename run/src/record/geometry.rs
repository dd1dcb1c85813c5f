//! The per-frame geometry of a recording: the body's surface (extracted once from the mesh's
//! boundary faces; positions x = X + U and colours per frame), the viridis colour map of the
//! colouring field, the moving moulds (a rigid transform per frame), and the interface and
//! contact nodes with their arrows: tractions, and the mould's normal where a node touches.

use super::layout::path_part;
use super::stream::Columns;
use super::{ColourField, Statics, ARROW_FRACTION, NORMAL_FRACTION};
use crate::interface::contact::ContactStatus;
use crate::law::InterfaceState;
use crate::model::Model;
use crate::output::fields::Scalar;
use crate::output::surface::mould::{body_box, mould_normal};
use crate::output::surface::{viridis, Surface};
use crate::output::Snapshot;
use rerun::{Arrows3D, ComponentDescriptor, Mesh3D, Points3D, Transform3D};

/// Sizes of the drawing, from the reference mesh.
pub(super) struct Scales {
    /// Largest side of the bounding box [m].
    pub(super) extent: f64,
    /// Arrow length per pascal [m/Pa].
    pub(super) arrow_scale: f64,
    pub(super) point_radius: f32,
}

impl Scales {
    pub(super) fn of(m: &Model) -> Scales {
        let (lo, hi) = body_box(m);
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
    /// Moulds with a prescribed motion: (index, turns) — their translation is logged per
    /// frame, and their rotation when they turn.
    moving_moulds: Vec<(usize, bool)>,
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
            moving_moulds: m
                .moulds
                .iter()
                .enumerate()
                .filter(|p| p.1.velocity.is_some() || p.1.angular_velocity.is_some())
                .map(|(k, p)| (k, p.angular_velocity.is_some()))
                .collect(),
        }
    }

    /// Buffers one frame's geometry; returns the range of the colouring field so far.
    pub(super) fn frame(&mut self, cols: &mut Columns, st: &Statics, s: &Snapshot) -> (f64, f64) {
        let m = &st.model;
        self.surface_frame(cols, m, s);
        for &(k, turns) in &self.moving_moulds {
            // x = R x₀ + T of the step's own pose (`Simulation::mould_pose`); the mesh logged
            // at t = 0 is static, only this transform moves.
            let (r, t) = s.moulds[k];
            let path = format!("planes/{}", path_part(&m.moulds[k].name));
            cols.push(
                &path,
                Transform3D::descriptor_translation(),
                3,
                &t.map(|c| c as f32),
            );
            if turns {
                // Rerun's Mat3x3 is column-major.
                let columns: [f32; 9] = std::array::from_fn(|i| r[i % 3][i / 3] as f32);
                cols.push(&path, Transform3D::descriptor_mat3x3(), 9, &columns);
            }
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
        let field = match self.colour {
            ColourField::Displacement => None,
            ColourField::VonMises => Some(Scalar::VonMises),
            ColourField::Jacobian => Some(Scalar::Jacobian),
        };
        let values = self.surface.values(m, &s.u[..], field);
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
    /// R_c/h, both in Pa, as arrows (times the arrow scale); the mould's normal where in contact.
    fn interface_frame(&self, cols: &mut Columns, st: &Statics, s: &Snapshot) {
        let m = &st.model;
        let h = s.h.max(f64::MIN_POSITIVE);
        let scale = self.scales.arrow_scale;
        let nodes = &st.interface_nodes;
        let pts: Vec<f32> = nodes.iter().flat_map(|&(n, _)| position(m, s, n)).collect();
        let state: Vec<u16> = nodes
            .iter()
            .zip(&s.interface)
            .map(|(_, snap)| match snap.state {
                InterfaceState::Elastic => 0,
                InterfaceState::Transition => 1,
                InterfaceState::Ruptured => 2,
                InterfaceState::Unformed => 3,
            })
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
        let touching = nodes.iter().zip(&s.interface).map(|(&(n, itf), snap)| {
            let k = m.interfaces[itf as usize].plane;
            (n, k, snap.contact)
        });
        self.normals(cols, "interface/contact_normal", m, s, touching);
    }

    /// The mould's outward unit normal × [`NORMAL_FRACTION`] of the body's extent, at the
    /// nodes in contact (stick or slip; none at an open node), class = their contact status:
    /// `(node, mould, status)` of each node ([`mould_normal`] at x = X + U in the frame's pose
    /// of the mould).
    fn normals(
        &self,
        cols: &mut Columns,
        path: &str,
        m: &Model,
        s: &Snapshot,
        nodes: impl Iterator<Item = (u32, usize, ContactStatus)>,
    ) {
        let length = NORMAL_FRACTION * self.scales.extent;
        let (mut origins, mut vectors, mut class) = (vec![], vec![], vec![]);
        for (n, k, status) in nodes {
            if status == ContactStatus::Open {
                continue;
            }
            let x = position(m, s, n);
            let normal = mould_normal(&m.moulds[k], &s.moulds[k], x.map(f64::from));
            origins.extend(x);
            vectors.extend(normal.map(|c| (c * length) as f32));
            class.push(contact_class(status));
        }
        cols.push(path, Arrows3D::descriptor_origins(), 3, &origins);
        cols.push(path, Arrows3D::descriptor_vectors(), 3, &vectors);
        cols.push(path, Arrows3D::descriptor_class_ids(), 1, &class);
    }

    /// Contact-only nodes: status, R_c/h as arrows, and the mould's normal where in contact.
    fn contact_frame(&self, cols: &mut Columns, st: &Statics, s: &Snapshot) {
        let m = &st.model;
        let h = s.h.max(f64::MIN_POSITIVE);
        let scale = self.scales.arrow_scale;
        let pts: Vec<f32> = st
            .contact_nodes
            .iter()
            .flat_map(|&(n, _)| position(m, s, n))
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
        let touching = st
            .contact_nodes
            .iter()
            .zip(&s.contact)
            .map(|(&(n, k), c)| (n, k as usize, c.0));
        self.normals(cols, "contact/normal", m, s, touching);
    }
}

fn rgba(c: [u8; 3]) -> u32 {
    u32::from_be_bytes([c[0], c[1], c[2], 255])
}
