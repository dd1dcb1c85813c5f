//! The drawing of the moulds, shared by the outputs (the Rerun recording, the ParaView series,
//! the explorer's 3-D view): each mould's surface as triangles in its frame at t = 0 — a
//! half-space as a finite square around the body, the other shapes as meshes — placed at a
//! frame by its pose (R, T), x = R x₀ + T (`Simulation::mould_pose`), and the mould's outward
//! normal at a point of the body, for the contact arrows. Uses neither the Rerun SDK nor egui.

use crate::mesh::{cross, dot, norm, sub};
use crate::model::{Model, Mould, Shape};

/// A pose (R, T) of a mould: x = R x₀ + T for a point x₀ of the mould at t = 0.
pub type MouldPose = ([[f64; 3]; 3], [f64; 3]);

pub use crate::tunables::HALF_SPACE_MARGIN;

/// The body's reference bounding box (lowest and highest corner) [m].
pub fn body_box(m: &Model) -> ([f64; 3], [f64; 3]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for x in &m.mesh.nodes {
        for i in 0..3 {
            lo[i] = lo[i].min(x[i]);
            hi[i] = hi[i].max(x[i]);
        }
    }
    (lo, hi)
}

/// x = R x₀ + T.
pub fn place(pose: &MouldPose, x0: [f64; 3]) -> [f64; 3] {
    let (r, t) = pose;
    std::array::from_fn(|i| r[i][0] * x0[0] + r[i][1] * x0[1] + r[i][2] * x0[2] + t[i])
}

/// The mould's outward unit normal n at the point of its surface closest to x, in the pose
/// (R, T): x is taken back to the mould's frame at t = 0, X = Rᵀ(x − T), projected there
/// (`Mould::project0`, the closest-point query of the step) and the normal carried
/// forward, n = R N (the same construction as the step's, `mould::step::MouldStep::project`).
pub fn mould_normal(p: &Mould, pose: &MouldPose, x: [f64; 3]) -> [f64; 3] {
    let (r, t) = pose;
    let d = sub(x, *t);
    let x0: [f64; 3] = std::array::from_fn(|j| r[0][j] * d[0] + r[1][j] * d[1] + r[2][j] * d[2]);
    let n0 = p.project0(x0).normal;
    std::array::from_fn(|i| r[i][0] * n0[0] + r[i][1] * n0[1] + r[i][2] * n0[2])
}

/// The drawing of mould `p` at t = 0: [`mould_mesh`] for a shape, and for a half-space the
/// square of its plane that covers the body's bounding box `(lo, hi)` projected on the plane,
/// with a margin of [`HALF_SPACE_MARGIN`] × the body's extent on every side (so a wall of a
/// cavity is drawn as large as the block's side, not as a floor that sets the view's zoom);
/// its two triangles wind along the normal, which every vertex carries.
pub fn mould_drawing(p: &Mould, body: ([f64; 3], [f64; 3])) -> MouldMesh {
    if !p.shape.is_half_space() {
        return mould_mesh(&p.shape);
    }
    let (lo, hi) = body;
    let n = p.normal;
    let a = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    // t₁ × t₂ = n: the quad (−−, +−, ++, −+) in (t₁, t₂) winds along n.
    let t1 = normalise(cross(n, a));
    let t2 = cross(n, t1);
    let (mut s_lo, mut s_hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for corner in 0..8 {
        let x: [f64; 3] = std::array::from_fn(|i| if corner >> i & 1 == 0 { lo[i] } else { hi[i] });
        let d = sub(x, p.point);
        for (k, t) in [t1, t2].iter().enumerate() {
            s_lo[k] = s_lo[k].min(dot(d, *t));
            s_hi[k] = s_hi[k].max(dot(d, *t));
        }
    }
    let extent = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    let margin = HALF_SPACE_MARGIN * extent;
    let at = |a: f64, b: f64| -> [f64; 3] {
        std::array::from_fn(|i| p.point[i] + a * t1[i] + b * t2[i])
    };
    let (a0, a1) = (s_lo[0] - margin, s_hi[0] + margin);
    let (b0, b1) = (s_lo[1] - margin, s_hi[1] + margin);
    MouldMesh {
        vertices: vec![at(a0, b0), at(a1, b0), at(a1, b1), at(a0, b1)],
        normals: vec![n; 4],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

pub use decohesion_physics::mould::shapes::cylinder::CYLINDER_SEGMENTS;
pub use decohesion_physics::mould::shapes::sphere::{SPHERE_MERIDIANS, SPHERE_RINGS};
pub use decohesion_physics::mould::MouldMesh;

/// The drawing of a mould shape other than the half-space (empty for a half-space): the
/// shape's own ([`Shape::drawing`], each shape's file in `physics/src/mould/shapes/`).
pub fn mould_mesh(shape: &Shape) -> MouldMesh {
    shape.drawing()
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

#[cfg(test)]
mod tests {
    use super::*;
    use decohesion_physics::mould::shapes::{cylinder::Cylinder, r#box::Box, sphere::Sphere};

    /// Every drawn triangle winds outwards (its (b − a) × (c − a) along the vertex normals),
    /// normals are unit, a sphere's vertices are on it, and the counts are the documented ones.
    #[test]
    fn mould_meshes_are_closed_outward_and_on_the_shape() {
        let shapes = [
            Shape::Box(Box {
                centre: [1.0, 2.0, 3.0],
                half_size: [0.5, 1.0, 2.0],
            }),
            Shape::Sphere(Sphere {
                centre: [0.0, 0.0, 0.18],
                radius: 0.1,
            }),
            Shape::Cylinder(Cylinder {
                centre: [0.0, 1.0, 0.0],
                axis: [0.6, 0.0, 0.8],
                radius: 0.3,
                half_length: 1.0,
            }),
        ];
        let counts = [(24, 12), (482, 960), (194, 192)];
        for (shape, (nv, nt)) in shapes.iter().zip(counts) {
            let m = mould_mesh(shape);
            assert_eq!((m.vertices.len(), m.triangles.len()), (nv, nt), "{shape:?}");
            assert_eq!(m.normals.len(), nv);
            assert!(m.normals.iter().all(|n| (norm(*n) - 1.0).abs() < 1e-12));
            for t in &m.triangles {
                let [a, b, c] = t.map(|v| m.vertices[v as usize]);
                let f = cross(sub(b, a), sub(c, a));
                let n = t.iter().fold([0.0; 3], |s, &v| {
                    let n = m.normals[v as usize];
                    [s[0] + n[0], s[1] + n[1], s[2] + n[2]]
                });
                assert!(dot(f, n) > 0.0, "{shape:?}: {t:?} winds inwards");
            }
        }
        let m = mould_mesh(&shapes[1]);
        for x in &m.vertices {
            assert!((norm(sub(*x, [0.0, 0.0, 0.18])) - 0.1).abs() < 1e-15);
        }
        assert!(mould_mesh(&Shape::default()).vertices.is_empty());
    }
}
