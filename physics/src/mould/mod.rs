//! Rigid moulds of any shape (model §7): the shapes, their closest-point queries, and their
//! prescribed rigid motion ([`motion`]). A `[[plane]]` is the half-space shape.
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
pub mod step;
pub mod surface;

use crate::mesh::{dot, norm};
use crate::piecewise::PiecewiseLinear;
pub use motion::{Pose, RigidMotion};
use serde::Serialize;
use std::sync::Arc;
pub use surface::{SurfaceError, SurfaceMesh};

/// The shape of a mould in its frame at t = 0. The mould is the solid region: the body lies
/// outside it (on the side its outward normal points to).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
#[serde(rename_all = "snake_case", tag = "shape")]
pub enum Shape {
    /// The half-space n·(x − p) ≤ 0 of the mould's `point` and `normal` (a `[[plane]]`).
    #[default]
    HalfSpace,
    /// An axis-aligned box, centre and half-sizes [m].
    Box {
        centre: [f64; 3],
        half_size: [f64; 3],
    },
    /// A ball, centre and radius [m].
    Sphere { centre: [f64; 3], radius: f64 },
    /// A capped cylinder: centre of its axis, unit axis, radius and half-length [m].
    Cylinder {
        centre: [f64; 3],
        axis: [f64; 3],
        radius: f64,
        half_length: f64,
    },
    /// A triangulated surface (STL or Gmsh), its solid side given by its face orientation.
    Surface(Arc<SurfaceMesh>),
}

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

/// The unit vector along d, or `fallback` when d is 0.
fn unit_or(d: [f64; 3], fallback: [f64; 3]) -> [f64; 3] {
    let l = norm(d);
    if l > 0.0 {
        d.map(|c| c / l)
    } else {
        fallback
    }
}

impl Shape {
    /// Closest point and outward normal of the shape at x, in the mould's frame at t = 0
    /// (`point`, `normal`: the half-space's plane).
    pub fn project(&self, point: [f64; 3], normal: [f64; 3], x: [f64; 3]) -> Projection {
        match self {
            Shape::HalfSpace => {
                let g = dot(normal, std::array::from_fn(|c| x[c] - point[c]));
                Projection {
                    point: std::array::from_fn(|c| x[c] - g * normal[c]),
                    normal,
                }
            }
            Shape::Sphere { centre, radius } => {
                let q: [f64; 3] = std::array::from_fn(|c| x[c] - centre[c]);
                let n = unit_or(q, [0.0, 0.0, 1.0]);
                Projection {
                    point: std::array::from_fn(|c| centre[c] + radius * n[c]),
                    normal: n,
                }
            }
            Shape::Box { centre, half_size } => {
                let q: [f64; 3] = std::array::from_fn(|c| x[c] - centre[c]);
                let (p, n) = project_box(q, *half_size);
                Projection {
                    point: std::array::from_fn(|c| centre[c] + p[c]),
                    normal: n,
                }
            }
            Shape::Cylinder {
                centre,
                axis,
                radius,
                half_length,
            } => project_cylinder(*centre, *axis, *radius, *half_length, x),
            Shape::Surface(s) => s.project(x),
        }
    }
}

/// Closest point of the boundary of the box |qᵢ| ≤ hᵢ to q, and the outward normal there.
/// Outside: p = clamp(q), n = (q − p)/|q − p| (a face, edge or corner region). Inside or on it:
/// the nearest face (smallest hᵢ − |qᵢ|), n = ±eᵢ.
fn project_box(q: [f64; 3], h: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let p: [f64; 3] = std::array::from_fn(|c| q[c].clamp(-h[c], h[c]));
    let d: [f64; 3] = std::array::from_fn(|c| q[c] - p[c]);
    if d != [0.0; 3] {
        return (p, unit_or(d, [0.0; 3]));
    }
    let i = (0..3)
        .min_by(|&a, &b| (h[a] - q[a].abs()).total_cmp(&(h[b] - q[b].abs())))
        .unwrap_or(0);
    let s = if q[i] < 0.0 { -1.0 } else { 1.0 };
    let mut p = q;
    p[i] = s * h[i];
    let mut n = [0.0; 3];
    n[i] = s;
    (p, n)
}

/// Closest point of a capped cylinder's boundary (axis a through `centre`, radius r,
/// half-length l) and the outward normal there: with z = a·q and ρ = q − z a,
/// beyond the rim (|z| > l, |ρ| > r) the rim point and n = (x − p)/|x − p|; beyond a cap only,
/// the cap (n = ±a); beyond the side only, the side (n = ρ/|ρ|); inside, the nearer of the cap
/// and the side.
fn project_cylinder(centre: [f64; 3], a: [f64; 3], r: f64, l: f64, x: [f64; 3]) -> Projection {
    let q: [f64; 3] = std::array::from_fn(|c| x[c] - centre[c]);
    let z = dot(q, a);
    let rho: [f64; 3] = std::array::from_fn(|c| q[c] - z * a[c]);
    // A radial direction even on the axis: any unit vector ⊥ a.
    let any_perp = {
        let t = if a[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let s = dot(t, a);
        unit_or(std::array::from_fn(|c| t[c] - s * a[c]), [0.0; 3])
    };
    let er = unit_or(rho, any_perp);
    let rr = norm(rho);
    let s = if z < 0.0 { -1.0 } else { 1.0 };
    let (dz, dr) = (z.abs() - l, rr - r);
    let at = |zz: f64, radial: f64| -> [f64; 3] {
        std::array::from_fn(|c| centre[c] + zz * a[c] + radial * er[c])
    };
    let (point, normal) = if dz > 0.0 && dr > 0.0 {
        let p = at(s * l, r);
        (p, unit_or(std::array::from_fn(|c| x[c] - p[c]), er))
    } else if dz > 0.0 || (dr <= 0.0 && dz >= dr) {
        (at(s * l, rr), a.map(|c| s * c))
    } else {
        (at(z, r), er)
    };
    Projection { point, normal }
}

/// A rigid mould (model §7): a shape ([`Shape`]) moved by a prescribed rigid motion. A
/// `[[plane]]` is the half-space shape: points x with n·(x − p(t)) > 0 are on the solid's side.
/// The name `RigidPlane` is kept for the code that knew only planes; [`Mould`] is the same type.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct RigidPlane {
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

/// A rigid mould: the same type as [`RigidPlane`].
pub type Mould = RigidPlane;

impl RigidPlane {
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
        matches!(self.shape, Shape::HalfSpace) && self.angular_velocity.is_none()
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
pub fn mould_closest_point(plane: &RigidPlane, x: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let pr = plane.project0(x);
    (pr.point, pr.normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Box and cylinder: outside, on an edge region and inside, against the values worked out by
    /// hand (gap = signed distance to the surface).
    #[test]
    fn analytic_shapes_give_the_signed_distance() {
        let bx = Shape::Box {
            centre: [0.0; 3],
            half_size: [1.0, 2.0, 3.0],
        };
        let pr = bx.project([0.0; 3], [0.0; 3], [2.0, 0.5, 0.0]);
        assert_eq!((pr.point, pr.normal), ([1.0, 0.5, 0.0], [1.0, 0.0, 0.0]));
        let pr = bx.project([0.0; 3], [0.0; 3], [4.0, 6.0, 0.0]);
        assert_eq!(pr.point, [1.0, 2.0, 0.0]);
        assert!((pr.gap([4.0, 6.0, 0.0]) - 5.0).abs() < 1e-15);
        let pr = bx.project([0.0; 3], [0.0; 3], [0.0, 1.5, 0.0]);
        assert_eq!((pr.point, pr.normal), ([0.0, 2.0, 0.0], [0.0, 1.0, 0.0]));
        assert_eq!(pr.gap([0.0, 1.5, 0.0]), -0.5);
        let cy = Shape::Cylinder {
            centre: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            radius: 1.0,
            half_length: 2.0,
        };
        let x = [3.0, 0.0, 0.5];
        assert_eq!(cy.project([0.0; 3], [0.0; 3], x).gap(x), 2.0);
        let x = [0.0, 0.5, -2.5];
        let pr = cy.project([0.0; 3], [0.0; 3], x);
        assert_eq!((pr.normal, pr.gap(x)), ([0.0, 0.0, -1.0], 0.5));
        let x = [4.0, 0.0, 6.0];
        assert!((cy.project([0.0; 3], [0.0; 3], x).gap(x) - 5.0).abs() < 1e-15);
        let x = [0.0, 0.9, 0.0];
        assert!((cy.project([0.0; 3], [0.0; 3], x).gap(x) + 0.1).abs() < 1e-15);
    }
}
