//! The faces of a triangulated mould a node is behind at a concave edge or vertex (model §7.5):
//! each is a constraint of its own in stage 7, where the closest feature's pseudo-normal alone
//! would let the node slide into one of them.

use super::{NearLists, SurfaceMesh, NEAR_CAPACITY, NEAR_TOLERANCE};
use crate::mesh::{dot, norm};
use crate::mould::Projection;
use parry3d_f64::math::Point;
use parry3d_f64::query::PointQueryWithLocation;

/// The most faces one entry keeps at a concave edge or vertex (model §7.5): the deepest ones
/// when the node is behind more distinct face planes (three independent normals already leave
/// the node no direction into the mould).
pub const MAX_FACES: usize = 3;

/// The faces of a triangulated mould a node is behind at a concave edge or vertex (model §7.5):
/// each face's outward unit normal n_T and the node's gap g_T = n_T·(x − p) from its plane
/// (≤ 0, snapped as every gap), `len` of them, one per distinct plane; `len` is 0 when the node
/// keeps its one closest-feature constraint (never 1).
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
pub struct Faces {
    pub len: u8,
    pub normal: [[f64; 3]; MAX_FACES],
    pub gap: [f64; MAX_FACES],
}

impl Faces {
    /// The faces with their normals turned by `rotate` (the mould's pose).
    pub fn turned(mut self, rotate: impl Fn([f64; 3]) -> [f64; 3]) -> Faces {
        for n in &mut self.normal[..self.len as usize] {
            *n = rotate(*n);
        }
        self
    }
}

impl SurfaceMesh {
    /// The faces node x is behind at its closest point (model §7.5), in the mould's frame:
    /// `pr` is x's projection (closest point p, pseudo-normal n̂) on triangle `tri`, `tol` the
    /// round-off below which a gap is 0 (model §3.8).
    ///
    /// When x is inside the mould, n̂·(x − p) < −tol, and p is not inside a face (n̂ is not
    /// `tri`'s face normal: p is on an edge or a vertex), every triangle T through p (its
    /// closest point to x within ε of p, ε as in [`SurfaceMesh::project_near`]) whose plane x
    /// is behind, g_T = n_T·(x − p) ≤ tol, gives a face (n_T, g_T); coplanar triangles give one
    /// (normals within 1e-9). Two or more distinct faces are returned (the MAX_FACES deepest),
    /// fewer as none. At a convex edge or vertex the closest feature is an edge or a vertex
    /// only for a node in front of all its faces (outside), so none is returned there; at a
    /// concave one, a node inside is behind the faces that meet there. The triangles looked at
    /// are the node's list `near` (every triangle within ε of the closest distance is in it
    /// after [`SurfaceMesh::project_near`]), or every triangle (`None`: a small surface, or
    /// the cold query); those through p are taken in the order of their index, so the two give
    /// the same faces.
    pub fn concave_faces(
        &self,
        x: [f64; 3],
        pr: &Projection,
        tri: u32,
        near: Option<(&NearLists, usize)>,
        tol: f64,
    ) -> Faces {
        let mut out = Faces::default();
        if !(pr.gap(x) < -tol) || tri >= self.mesh.num_triangles() as u32 {
            return out;
        }
        let unit = |t: u32| {
            let n = self.mesh.triangle(t).scaled_normal();
            let n = [n.x, n.y, n.z];
            let l = norm(n);
            n.map(|c| c / l)
        };
        if unit(tri) == pr.normal {
            return out; // p inside a face: its normal is the constraint
        }
        let aabb = self.mesh.local_aabb();
        let scale = (0..3)
            .map(|k| x[k].abs().max(aabb.mins[k].abs()).max(aabb.maxs[k].abs()))
            .fold(0.0, f64::max);
        let eps = NEAR_TOLERANCE * scale;
        let pt = Point::new(x[0], x[1], x[2]);
        let p = Point::new(pr.point[0], pr.point[1], pr.point[2]);
        let d = std::array::from_fn::<f64, 3, _>(|c| x[c] - pr.point[c]);
        // The triangles through p, in the order of their index.
        let (mut through, mut n_through) = ([0u32; NEAR_CAPACITY], 0);
        let mut take = |t: u32| {
            let (proj, _) =
                (self.mesh.triangle(t)).project_local_point_and_get_location(&pt, false);
            if nalgebra::distance(&proj.point, &p) <= eps && n_through < NEAR_CAPACITY {
                through[n_through] = t;
                n_through += 1;
            }
        };
        match near {
            Some((lists, j)) => lists.listed(j).for_each(&mut take),
            None => (0..self.mesh.num_triangles() as u32).for_each(&mut take),
        }
        let through = &mut through[..n_through];
        through.sort_unstable();
        let mut n = 0;
        for &t in through.iter() {
            let nt = unit(t);
            let g = dot(nt, d);
            if g > tol {
                continue; // in front of this face's plane
            }
            let g = if g.abs() <= tol { 0.0 } else { g };
            let same = |m: &[f64; 3]| (0..3).all(|c| (m[c] - nt[c]).abs() <= 1e-9);
            if out.normal[..n].iter().any(same) {
                continue;
            }
            if n < MAX_FACES {
                (out.normal[n], out.gap[n]) = (nt, g);
                n += 1;
            } else {
                // Full: the new face replaces the shallowest when deeper.
                let (s, &gs) = (out.gap.iter().enumerate())
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .expect("MAX_FACES > 0");
                if g < gs {
                    (out.normal[s], out.gap[s]) = (nt, g);
                }
            }
        }
        if n >= 2 {
            out.len = n as u8;
        }
        out
    }
}
