//! The drawing of the moulds, shared by the outputs (the Rerun recording, the ParaView series,
//! the explorer's 3-D view): each mould's surface as triangles in its frame at t = 0 — a
//! half-space as a finite square around the body, the other shapes as meshes — placed at a
//! frame by its pose (R, T), x = R x₀ + T (`Simulation::mould_pose`), and the mould's outward
//! normal at a point of the body, for the contact arrows. Uses neither the Rerun SDK nor egui.

use crate::mesh::{cross, dot, norm, sub};
use crate::model::{Model, RigidPlane, Shape};

/// A pose (R, T) of a mould: x = R x₀ + T for a point x₀ of the mould at t = 0.
pub type MouldPose = ([[f64; 3]; 3], [f64; 3]);

/// Margin of a half-space's square beyond the body's bounding box projected on it, as a
/// fraction of the body's largest extent.
pub const HALF_SPACE_MARGIN: f64 = 0.15;

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
/// (`RigidPlane::project0`, the closest-point query of the step) and the normal carried
/// forward, n = R N (the same construction as the step's, `mould::step::MouldStep::project`).
pub fn mould_normal(p: &RigidPlane, pose: &MouldPose, x: [f64; 3]) -> [f64; 3] {
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
pub fn mould_drawing(p: &RigidPlane, body: ([f64; 3], [f64; 3])) -> MouldMesh {
    if p.shape != Shape::HalfSpace {
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

/// A mould's surface as triangles, in its frame at t = 0, wound so that (b − a) × (c − a)
/// points out of the mould (into the solid), with a unit normal per vertex.
pub struct MouldMesh {
    pub vertices: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// Rings (pole to pole) and meridians of a sphere's drawing: 2 + 15 × 32 = 482 vertices,
/// 960 triangles; each pole is a vertex, so the point of a sphere pressed along its axis is
/// exact.
pub const SPHERE_RINGS: usize = 16;
pub const SPHERE_MERIDIANS: usize = 32;
/// Segments around a cylinder's drawing.
pub const CYLINDER_SEGMENTS: usize = 48;

/// The drawing of a mould shape other than the half-space (empty for a half-space): a box as
/// 6 faces of 4 vertices (12 triangles, flat normals); a sphere as a UV sphere about z
/// ([`SPHERE_RINGS`] × [`SPHERE_MERIDIANS`], vertices on the sphere); a capped cylinder as its
/// side ([`CYLINDER_SEGMENTS`] quads, radial normals) and two fans for the caps (axial
/// normals); a triangulated surface as its own triangles with parry's angle-weighted vertex
/// pseudo-normals.
pub fn mould_mesh(shape: &Shape) -> MouldMesh {
    let mut mesh = MouldMesh {
        vertices: vec![],
        normals: vec![],
        triangles: vec![],
    };
    match shape {
        Shape::HalfSpace => {}
        Shape::Box { centre, half_size } => {
            // Each face: its normal axis i, sign s, and two tangent axes (j, k) with
            // e_j × e_k = s e_i, so the quad (−−, +−, ++, −+) in (j, k) winds outwards.
            for i in 0..3 {
                for s in [1.0, -1.0] {
                    let (j, k) = if s > 0.0 {
                        ((i + 1) % 3, (i + 2) % 3)
                    } else {
                        ((i + 2) % 3, (i + 1) % 3)
                    };
                    let base = mesh.vertices.len() as u32;
                    for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                        let mut x = *centre;
                        x[i] += s * half_size[i];
                        x[j] += a * half_size[j];
                        x[k] += b * half_size[k];
                        mesh.vertices.push(x);
                        let mut n = [0.0; 3];
                        n[i] = s;
                        mesh.normals.push(n);
                    }
                    mesh.triangles
                        .extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
                }
            }
        }
        Shape::Sphere { centre, radius } => {
            let (nr, nm) = (SPHERE_RINGS, SPHERE_MERIDIANS);
            let mut push = |n: [f64; 3]| {
                mesh.vertices
                    .push(std::array::from_fn(|c| centre[c] + radius * n[c]));
                mesh.normals.push(n);
            };
            push([0.0, 0.0, 1.0]);
            for r in 1..nr {
                let theta = std::f64::consts::PI * r as f64 / nr as f64;
                for k in 0..nm {
                    let phi = 2.0 * std::f64::consts::PI * k as f64 / nm as f64;
                    push([
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    ]);
                }
            }
            push([0.0, 0.0, -1.0]);
            let (nm32, south) = (nm as u32, (1 + (nr - 1) * nm) as u32);
            let ring = |r: u32, k: u32| 1 + r * nm32 + k % nm32;
            for k in 0..nm32 {
                mesh.triangles.push([0, ring(0, k), ring(0, k + 1)]);
                for r in 0..(nr as u32 - 2) {
                    let (a, b) = (ring(r, k), ring(r, k + 1));
                    let (c, d) = (ring(r + 1, k), ring(r + 1, k + 1));
                    mesh.triangles.extend([[a, c, d], [a, d, b]]);
                }
                let last = nr as u32 - 2;
                mesh.triangles
                    .push([south, ring(last, k + 1), ring(last, k)]);
            }
        }
        Shape::Cylinder {
            centre,
            axis,
            radius,
            half_length,
        } => {
            let a = normalise(*axis);
            let e1 = normalise(cross(
                a,
                if a[0].abs() < 0.9 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                },
            ));
            let e2 = cross(a, e1);
            let ns = CYLINDER_SEGMENTS as u32;
            let radial = |k: u32| -> [f64; 3] {
                let phi = 2.0 * std::f64::consts::PI * k as f64 / ns as f64;
                std::array::from_fn(|c| phi.cos() * e1[c] + phi.sin() * e2[c])
            };
            let at = |z: f64, r: f64, n: [f64; 3]| -> [f64; 3] {
                std::array::from_fn(|c| centre[c] + z * a[c] + r * n[c])
            };
            let l = *half_length;
            // Side: vertices 2k (bottom, z = −l) and 2k + 1 (top).
            for k in 0..ns {
                let n = radial(k);
                mesh.vertices
                    .extend([at(-l, *radius, n), at(l, *radius, n)]);
                mesh.normals.extend([n, n]);
            }
            for k in 0..ns {
                let (b0, t0) = (2 * k, 2 * k + 1);
                let (b1, t1) = (2 * ((k + 1) % ns), 2 * ((k + 1) % ns) + 1);
                mesh.triangles.extend([[b0, b1, t1], [b0, t1, t0]]);
            }
            // Caps: a centre and a ring each, normal ±a.
            for s in [1.0, -1.0] {
                let n = a.map(|c| s * c);
                let base = mesh.vertices.len() as u32;
                mesh.vertices.push(at(s * l, 0.0, n));
                mesh.normals.push(n);
                for k in 0..ns {
                    mesh.vertices.push(at(s * l, *radius, radial(k)));
                    mesh.normals.push(n);
                }
                for k in 0..ns {
                    let (p, q) = (base + 1 + k, base + 1 + (k + 1) % ns);
                    mesh.triangles
                        .push(if s > 0.0 { [base, p, q] } else { [base, q, p] });
                }
            }
        }
        Shape::Surface(s) => {
            let tri = &s.mesh;
            mesh.vertices = tri.vertices().iter().map(|p| [p.x, p.y, p.z]).collect();
            mesh.triangles = tri.indices().to_vec();
            mesh.normals = match tri.pseudo_normals() {
                Some(pn) => pn
                    .vertices_pseudo_normal
                    .iter()
                    .map(|n| normalise([n.x, n.y, n.z]))
                    .collect(),
                // Without pseudo-normals (not built oriented): the area-weighted face normals.
                None => {
                    let mut acc = vec![[0.0; 3]; mesh.vertices.len()];
                    for t in &mesh.triangles {
                        let [a, b, c] = t.map(|v| mesh.vertices[v as usize]);
                        let n = cross(sub(b, a), sub(c, a));
                        for &v in t {
                            for i in 0..3 {
                                acc[v as usize][i] += n[i];
                            }
                        }
                    }
                    acc.into_iter().map(normalise).collect()
                }
            };
        }
    }
    mesh
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every drawn triangle winds outwards (its (b − a) × (c − a) along the vertex normals),
    /// normals are unit, a sphere's vertices are on it, and the counts are the documented ones.
    #[test]
    fn mould_meshes_are_closed_outward_and_on_the_shape() {
        let shapes = [
            Shape::Box {
                centre: [1.0, 2.0, 3.0],
                half_size: [0.5, 1.0, 2.0],
            },
            Shape::Sphere {
                centre: [0.0, 0.0, 0.18],
                radius: 0.1,
            },
            Shape::Cylinder {
                centre: [0.0, 1.0, 0.0],
                axis: [0.6, 0.0, 0.8],
                radius: 0.3,
                half_length: 1.0,
            },
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
        assert!(mould_mesh(&Shape::HalfSpace).vertices.is_empty());
    }
}
