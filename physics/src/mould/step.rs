//! The moulds during a run: their poses at tₙ, tₙ₊₁, tₙ₊₂ (composed step by step,
//! [`super::motion`]), the velocity of a mould's material point over the intervals before and
//! after tₙ₊₁, the geometry of each glued and contact node against a mould that is not a plain
//! plane, and each mould's work.
//!
//! **Velocity of the mould at a point p** (the relative velocity of contact, the glue's
//! anchor): the secant of the material point that is at p at tₙ₊₁ over the step,
//! v̄ = (x_p(tₙ₊₂) − p)/h_{n+3/2} with x_p(tₙ₊₂) = c(tₙ₊₂) + R(tₙ₊₂)R(tₙ₊₁)ᵀ(p − c(tₙ₊₁)),
//! i.e. v + ω × (p − c) of the step's constant v̄, ω̄ taken exactly over the step (to O(h) the
//! instantaneous v + ω × (p − c)); the interval before uses the poses at tₙ and tₙ₊₁. With
//! this secant, a node that moves with the mould keeps exactly its place on the mould (a rigid
//! motion of the body with the mould gives no jump), and a mould's work is force · velocity at
//! the contact points, moments included (Σ P·(v + ω × (p − c)) = F·v + M_c·ω).

use super::motion::{mat_mul_t, mat_vec, Mat3, Pose, RigidMotion};
use super::surface::{Faces, NearLists, NO_FEATURE};

use super::{Mould, Shape};
use crate::energy::Work;
pub use crate::tunables::SMALL_SURFACE;

/// A node's geometry against a mould that is not a plain plane, at tₙ₊₁.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct NodeGeometry {
    /// Glued nodes: the mould's outward normal at the anchor at t = 0 (in the mould's frame).
    pub normal0: [f64; 3],
    /// Glued nodes: that normal turned with the mould, R(tₙ₊₁)N₀; and the anchor's place.
    pub glue_normal: [f64; 3],
    pub anchor: [f64; 3],
    /// Closest mould point p to the node and the outward normal there (contact).
    pub point: [f64; 3],
    pub normal: [f64; 3],
    /// The triangle of a triangulated mould that held the closest point at the last query
    /// (the warm start of [`super::SurfaceMesh::project_cached`]; [`NO_FEATURE`] before the
    /// first, unused on other shapes).
    pub feature: u32,
    /// On a triangulated mould, the faces the node is behind at a concave edge or vertex
    /// (model §7.5, [`super::SurfaceMesh::concave_faces`]): when there are any, they are the
    /// node's constraints instead of the closest feature's normal.
    pub faces: Faces,
}

impl Default for NodeGeometry {
    fn default() -> Self {
        NodeGeometry {
            normal0: [0.0; 3],
            glue_normal: [0.0; 3],
            anchor: [0.0; 3],
            point: [0.0; 3],
            normal: [0.0; 3],
            feature: NO_FEATURE,
            faces: Faces::default(),
        }
    }
}

/// The moulds' poses and per-node geometry of the current step (see the module docs).
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct MouldStep {
    /// Per mould: true for a plain plane (half-space, no rotation: today's fast path).
    pub plane: Vec<bool>,
    /// Some mould is not a plain plane.
    general: bool,
    /// Poses at tₙ, tₙ₊₁ and tₙ₊₂ of each mould.
    pub prev: Vec<Pose>,
    pub cur: Vec<Pose>,
    pub next: Vec<Pose>,
    /// R(tₙ₊₂)R(tₙ₊₁)ᵀ and R(tₙ)R(tₙ₊₁)ᵀ of each mould.
    d_next: Vec<Mat3>,
    d_prev: Vec<Mat3>,
    /// h_{n+½} (0 at the start: nothing moved before t₀), h_{n+3/2}, and h̄ of the last pass.
    pub h_old: f64,
    pub h_new: f64,
    pub h_bar: f64,
    /// Per interface node and per contact node (empty when every mould is a plain plane).
    pub interface: Vec<NodeGeometry>,
    pub contact: Vec<NodeGeometry>,
    /// Each mould's work (force · velocity of the mould at the points it acts on) [J].
    pub work: Vec<Work>,
    /// Each mould's friction work (tangential contact impulse · velocity of the node relative
    /// to the mould) [J]: minus the friction dissipated on it.
    pub friction: Vec<Work>,
    /// Each mould's share of the glue's torque work over the interval just taken (model §5.5)
    /// [J], summed by the ledger's interface pass for the per-mould works.
    pub torque: Vec<f64>,
    /// Per interface node and per contact node on a triangulated mould: its list of nearby
    /// triangles ([`super::SurfaceMesh::project_near`]; empty when no mould is triangulated).
    pub near_interface: NearLists,
    pub near_contact: NearLists,
}

impl MouldStep {
    /// The moulds at t₀ = `t` (identity rotation).
    pub fn new(moulds: &[Mould], t: f64) -> MouldStep {
        let start: Vec<Pose> = moulds.iter().map(|m| m.motion().start(t)).collect();
        MouldStep {
            plane: moulds.iter().map(Mould::is_plane).collect(),
            general: !moulds.iter().all(Mould::is_plane),
            prev: start.clone(),
            cur: start.clone(),
            next: start,
            d_next: vec![super::motion::IDENTITY; moulds.len()],
            d_prev: vec![super::motion::IDENTITY; moulds.len()],
            work: vec![Work::default(); moulds.len()],
            friction: vec![Work::default(); moulds.len()],
            torque: vec![0.0; moulds.len()],
            ..Default::default()
        }
    }

    /// True when some mould is not a plain plane (the per-node geometry is in use).
    #[inline]
    pub fn any_general(&self) -> bool {
        self.general
    }

    /// Once h_{n+3/2} is fixed at tₙ₊₁ = `t`: the poses move on by one step (`first`: the start,
    /// where the pose at t₀ is the current one and nothing moved before).
    pub fn advance(&mut self, moulds: &[Mould], t: f64, h_next: f64, h_prev: f64, first: bool) {
        for (k, m) in moulds.iter().enumerate() {
            if self.plane[k] {
                continue; // a plain plane's velocities are the plane's (`plane_v_*`)
            }
            if !first {
                self.prev[k] = self.cur[k];
                self.cur[k] = self.next[k];
            }
            // The current pose must be at t (it is, by construction; a start is at t₀).
            // The histories borrowed, not copied (`m.motion()` clones them: an allocation
            // per step, which `tests/allocation.rs` found).
            let (v, w) = (m.velocity.as_ref(), m.angular_velocity.as_ref());
            let pivot = m.pivot();
            self.next[k] = RigidMotion::advance_histories(v, w, pivot, &self.cur[k], t + h_next);
            self.d_next[k] = mat_mul_t(&self.next[k].rotation, &self.cur[k].rotation);
            self.d_prev[k] = mat_mul_t(&self.prev[k].rotation, &self.cur[k].rotation);
        }
        self.h_new = h_next;
        self.h_old = if first { 0.0 } else { h_prev };
    }

    /// Velocity of mould `k` at the point p (at tₙ₊₁) over the next interval.
    #[inline]
    pub fn velocity_new(&self, k: usize, p: [f64; 3]) -> [f64; 3] {
        let (c, n) = (self.cur[k].centre, self.next[k].centre);
        let r = mat_vec(&self.d_next[k], std::array::from_fn(|i| p[i] - c[i]));
        std::array::from_fn(|i| (n[i] + r[i] - p[i]) / self.h_new)
    }

    /// Velocity of mould `k` at the point p (at tₙ₊₁) over the interval just taken (0 at the
    /// start).
    #[inline]
    pub fn velocity_old(&self, k: usize, p: [f64; 3]) -> [f64; 3] {
        if self.h_old <= 0.0 {
            return [0.0; 3];
        }
        let (c, o) = (self.cur[k].centre, self.prev[k].centre);
        let r = mat_vec(&self.d_prev[k], std::array::from_fn(|i| p[i] - c[i]));
        std::array::from_fn(|i| (p[i] - o[i] - r[i]) / self.h_old)
    }

    /// The glue normal at tₙ, R(tₙ)N₀ (the start of the interval the ledger closes at tₙ₊₁).
    #[inline]
    pub fn glue_normal_prev(&self, k: usize, normal0: [f64; 3]) -> [f64; 3] {
        mat_vec(&self.prev[k].rotation, normal0)
    }

    /// The glue normal at tₙ₊₂, R(tₙ₊₂)N₀ (stage 8's next jump).
    #[inline]
    pub fn glue_normal_next(&self, k: usize, normal0: [f64; 3]) -> [f64; 3] {
        mat_vec(&self.next[k].rotation, normal0)
    }

    /// The pose of mould `k` at `t`, the time of stage 2: the pose `next` of the last
    /// [`MouldStep::advance`] once the positions have moved to it (the same sum tₙ + h, so the
    /// same bits), the current one at the start.
    #[inline]
    pub fn pose_at(&self, k: usize, t: f64) -> Pose {
        if self.next[k].time == t {
            self.next[k]
        } else {
            self.cur[k]
        }
    }

    /// Closest point and outward normal of mould `m` at x in the pose `pose` (model §7.5);
    /// on a triangulated mould of more than [`SMALL_SURFACE`] triangles from
    /// the node's list `near` of nearby triangles and its last triangle `feature`
    /// ([`super::SurfaceMesh::project_near`]: the cold query's result at about one triangle
    /// projection), unless `cold`. On a triangulated mould, also the faces the node is behind
    /// at a concave edge or vertex ([`super::SurfaceMesh::concave_faces`], gaps within `tol`
    /// taken as 0; none on other shapes).
    pub fn project(
        m: &Mould,
        pose: &Pose,
        x: [f64; 3],
        feature: &mut u32,
        near: (&mut NearLists, usize),
        cold: bool,
        tol: f64,
    ) -> (super::Projection, Faces) {
        let x0 = pose.unplace(m.pivot(), x);
        let (pr, faces) = match &m.shape {
            Shape::Surface(s) if !cold && s.mesh.num_triangles() > SMALL_SURFACE => {
                let pr = s.project_near(x0, feature, near.0, near.1);
                let listed = Some((&*near.0, near.1));
                (pr, s.concave_faces(x0, &pr, *feature, listed, tol))
            }
            Shape::Surface(s) => {
                let (pr, tri) = s.project_triangle(x0);
                (pr, s.concave_faces(x0, &pr, tri, None, tol))
            }
            _ => (m.project0(x0), Faces::default()),
        };
        let turn = |n: [f64; 3]| mat_vec(&pose.rotation, n);
        let placed = super::Projection {
            point: pose.place(m.pivot(), pr.point),
            normal: turn(pr.normal),
        };
        (placed, faces.turned(turn))
    }
}
