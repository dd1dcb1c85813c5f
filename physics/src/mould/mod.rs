//! Rigid moulds of any shape (model §7): the shapes, one file each with its closest-point
//! query ([`shapes`]), and their prescribed rigid motion ([`motion`]). A `[[plane]]` is the
//! half-space shape.
//!
//! **Contact and glue on a curved or faceted mould** (model §7.1, §7.4, §7.5, generalising
//! the plane of §2.1 and §3): at a point x of the solid, p is the closest point of the
//! mould's surface and n the mould's outward unit normal there (pointing out of the mould, into
//! the solid); the gap is g = n·(x − p) (> 0 open). On a faceted surface n is the
//! angle-weighted pseudo-normal of the feature p lies on (face: the face's normal; edge: the
//! sum of its two faces' normals; vertex: the angle-weighted sum of its faces' normals,
//! Bærentzen–Aanæs 2005), so that the sign of g is right at a rib's edge. A half-space has
//! n = its normal and p the orthogonal projection; a box, sphere and capped cylinder have their
//! exact closest point (an edge or rim of a box or cylinder: n = (x − p)/|x − p| outside).
//!
//! Every query works in the mould's frame at t = 0: x is taken back by the pose,
//! X = c₀ + Rᵀ(x − c), projected, and p, n carried forward, p = c + R(P − c₀), n = R N.

pub mod motion;
pub mod shapes;
pub mod step;
pub mod surface;

use crate::mesh::dot;
use crate::piecewise::PiecewiseLinear;
pub use motion::{Pose, RigidMotion};
use serde::Serialize;
pub use shapes::{MouldMesh, Shape};
pub use surface::{SurfaceError, SurfaceMesh};

/// One warning per mould of an open triangulated surface: its name, file and number of open
/// edges, and what the mould does beyond its rim (module docs of [`surface`]). Not part of the
/// run's advisories: a property of the input, printed by `check` and `run`.
pub fn open_surface_warnings(moulds: &[Mould]) -> Vec<String> {
    (moulds.iter())
        .filter_map(|m| match &m.shape {
            Shape::Surface(s) if s.open_edges > 0 => Some(format!(
                "mould `{}`: the surface of {} is open ({} edges belong to one triangle only): beyond its rim the mould acts as the plane of the rim's triangles extended, right for a node in front of the surface, wrong for one that reaches around the rim behind it",
                m.name, s.file, s.open_edges
            )),
            _ => None,
        })
        .collect()
}

/// The closest point of a surface and the mould's outward normal there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Closest point p of the mould's surface [m].
    pub point: [f64; 3],
    /// Outward unit normal n of the mould at p (into the solid).
    pub normal: [f64; 3],
}

impl Projection {
    /// g = n·(x − p).
    #[inline]
    pub fn gap(&self, x: [f64; 3]) -> f64 {
        dot(
            self.normal,
            [
                x[0] - self.point[0],
                x[1] - self.point[1],
                x[2] - self.point[2],
            ],
        )
    }
}

/// A rigid mould (model §7): a shape ([`Shape`]) moved by a prescribed rigid motion. A
/// `[[plane]]` is the half-space shape: points x with n·(x − p(t)) > 0 are on the solid's side.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Mould {
    pub name: String,
    /// A point of the plane at t = 0 [m] (half-space); for another shape, its pivot c₀.
    pub point: [f64; 3],
    /// Unit normal pointing into the solid (half-space); [0, 0, 0] for another shape.
    pub normal: [f64; 3],
    /// Prescribed velocity history [m/s] of `point` (the pivot); `None` for a fixed mould.
    pub velocity: Option<PiecewiseLinear<3>>,
    /// The shape, in the mould's frame at t = 0. Default: the half-space of `point`, `normal`.
    #[serde(flatten)]
    pub shape: Shape,
    /// Angular velocity history ω(t) [rad/s] about the pivot (which moves with `velocity`);
    /// `None`: the mould does not turn.
    pub angular_velocity: Option<PiecewiseLinear<3>>,
    /// The pivot c₀ at t = 0 [m]; `None`: `point`.
    pub pivot: Option<[f64; 3]>,
}

impl Mould {
    /// Rigid displacement of the plane (of the pivot) since t = 0 [m].
    pub fn displacement(&self, t: f64) -> [f64; 3] {
        match &self.velocity {
            None => [0.0; 3],
            Some(v) => v.integral(t),
        }
    }

    /// True for the path of today's planes: a half-space that does not turn (its gaps and
    /// velocities are the plane's, the same at every node: the plain plane of model §7.2).
    pub fn is_plane(&self) -> bool {
        self.shape.is_half_space() && self.angular_velocity.is_none()
    }

    /// Its motion: translation of `point` and rotation about it ([`RigidMotion`]).
    pub fn motion(&self) -> RigidMotion {
        RigidMotion {
            velocity: self.velocity.clone(),
            angular_velocity: self.angular_velocity.clone(),
            pivot: self.pivot(),
        }
    }

    /// The pivot c₀ of the rotation at t = 0.
    pub fn pivot(&self) -> [f64; 3] {
        self.pivot.unwrap_or(self.point)
    }

    /// Closest point and outward normal at x in the mould's frame at t = 0.
    pub fn project0(&self, x: [f64; 3]) -> Projection {
        self.shape.project(self.point, self.normal, x)
    }
}

/// What the glue and the contact need of a rigid mould at one point x at t = 0 (model §7.1,
/// §7.4, [`crate::mould`]): the closest point p of the mould's surface
/// to x and the mould's outward unit normal n there (into the solid), so that the gap is
/// g = n·(x − p). For a plane p is the orthogonal projection and n the plane's normal, the same
/// at every point; on a faceted surface n is the pseudo-normal of the feature hit.
pub fn mould_closest_point(plane: &Mould, x: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let pr = plane.project0(x);
    (pr.point, pr.normal)
}
