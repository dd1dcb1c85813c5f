//! Triangulated mould surfaces: read from STL (ASCII or binary) or from a 2-D physical group of a
//! Gmsh `.msh` file (triangles, or quadrangles split in two), checked, and queried with
//! `parry3d-f64` (a BVH over the triangles, projection with the feature hit, pseudo-normals).
//!
//! Orientation: a triangle (a, b, c) has the normal (b − a) × (c − a) (right-hand rule), which
//! must point **out of the mould**, into the solid (STL's convention for a solid's facets).
//! The loader refuses, naming the file, the element and the reason: a degenerate triangle
//! (area ≤ 1e-12 × its longest edge², or a repeated vertex), an edge shared by more than two
//! triangles (not a surface), two triangles that run through their shared edge the same way
//! (inconsistent orientation), and an STL facet whose written normal opposes its vertex order.

use super::Projection;
use crate::mesh::{cross, dot, norm, sub};
use nalgebra::{SimdPartialOrd, SimdValue};
use parry3d_f64::bounding_volume::SimdAabb;
use parry3d_f64::math::{Point, SimdReal, SIMD_WIDTH};
use parry3d_f64::partitioning::SimdVisitStatus;
use parry3d_f64::query::{PointProjection, PointQueryWithLocation};
use parry3d_f64::shape::{TriMesh, TriMeshFlags, TrianglePointLocation};
use std::collections::HashMap;

/// Why a surface could not be used; the message names the file and the element.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{file}: {message}")]
pub struct SurfaceError {
    pub file: String,
    pub message: String,
}

/// A checked triangulated surface and its BVH.
pub struct SurfaceMesh {
    /// The file it was read from, its physical group (Gmsh) and the scale applied.
    pub file: String,
    pub group: Option<String>,
    pub scale: f64,
    pub mesh: TriMesh,
}

impl std::fmt::Debug for SurfaceMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "SurfaceMesh({}, {:?}, ×{}, {} triangles)",
            self.file,
            self.group,
            self.scale,
            self.mesh.num_triangles()
        )
    }
}

/// Two surfaces are equal when read from the same source with the same scale.
impl PartialEq for SurfaceMesh {
    fn eq(&self, o: &Self) -> bool {
        (
            &self.file,
            &self.group,
            self.scale,
            self.mesh.num_triangles(),
        ) == (&o.file, &o.group, o.scale, o.mesh.num_triangles())
    }
}

impl serde::Serialize for SurfaceMesh {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("SurfaceMesh", 4)?;
        st.serialize_field("file", &self.file)?;
        st.serialize_field("group", &self.group)?;
        st.serialize_field("scale", &self.scale)?;
        st.serialize_field("triangles", &self.mesh.num_triangles())?;
        st.end()
    }
}

impl SurfaceMesh {
    /// Checks the triangles ([`check_orientation`]) and builds the BVH and pseudo-normals.
    /// `element[k]` names triangle k in messages.
    pub fn new(
        file: &str,
        group: Option<String>,
        scale: f64,
        vertices: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        element: &dyn Fn(usize) -> String,
    ) -> Result<SurfaceMesh, SurfaceError> {
        let err = |message: String| SurfaceError {
            file: file.to_string(),
            message,
        };
        if triangles.is_empty() {
            return Err(err("the surface has no triangle".into()));
        }
        let vertices: Vec<[f64; 3]> = vertices.iter().map(|v| v.map(|c| c * scale)).collect();
        let id = check_orientation(&vertices, &triangles, element).map_err(err)?;
        // Shared vertices once (an STL repeats them per facet): the pseudo-normals of edges and
        // vertices need the triangles around them.
        let mut new_index = vec![u32::MAX; vertices.len()];
        let mut points = Vec::new();
        for (i, &c) in id.iter().enumerate() {
            if new_index[c as usize] == u32::MAX {
                new_index[c as usize] = points.len() as u32;
                let v = vertices[i];
                points.push(Point::new(v[0], v[1], v[2]));
            }
        }
        let triangles = (triangles.iter())
            .map(|t| t.map(|v| new_index[id[v as usize] as usize]))
            .collect();
        let mesh = TriMesh::with_flags(points, triangles, TriMeshFlags::ORIENTED)
            .map_err(|e| err(format!("cannot build the triangle mesh: {e}")))?;
        Ok(SurfaceMesh {
            file: file.to_string(),
            group,
            scale,
            mesh,
        })
    }

    /// Closest point p and the pseudo-normal n of its feature (face, edge or vertex), in the
    /// mould's frame at t = 0 (module docs of [`super`]): the full BVH query (best-first).
    pub fn project(&self, x: [f64; 3]) -> Projection {
        let (proj, (tri, loc)) =
            (self.mesh).project_local_point_and_get_location(&Point::new(x[0], x[1], x[2]), false);
        self.projection(proj.point, tri, loc)
    }

    /// [`SurfaceMesh::project`] warm-started from the triangle `feature` found at the node's
    /// last query (the cache, [`NO_FEATURE`] when there is none; updated to the triangle found).
    ///
    /// Let d₀ = |x − p₀| be the distance to the cached triangle's closest point (one triangle
    /// projection, the same arithmetic as the BVH's leaf test, so the same bits). The closest
    /// point of the surface is at a distance d* ≤ d₀, so asking the BVH only for a point closer
    /// than d_max = d₀(1 + 10⁻¹²) prunes every node whose box is farther, without losing the
    /// answer: the best-first traversal starts with its best cost at d_max instead of ∞, and
    /// keeps a triangle only when strictly closer than the best so far, as the cold query does. The result is the cold query's: the same
    /// triangle (hence the same point and pseudo-normal) whenever the closest triangle is
    /// unique. Ties: a point on the surface (d* = 0) is at distance 0 from every triangle
    /// around it, and parry reports it on one's face or on another's edge, with different
    /// normals, the choice set by the visit order, which the pruning changes: there the warm
    /// query calls the cold one (a node exactly on its mould: at t = 0 and rarely after). Off
    /// the surface, several triangles at exactly the same distance d* > 0 share the closest
    /// feature (a vertex or an edge: the point is in its Voronoi region), each query keeps the
    /// first it visits, and the visit orders can differ; a shared vertex gives the same point
    /// (the vertex) and the same vertex pseudo-normal from any of its triangles, a shared edge
    /// the same edge pseudo-normal (parry stores one per edge) and a point computed from
    /// either end of the edge, equal in exact arithmetic: so warm and cold can differ there in
    /// the last bit of p only (`physics/tests/mould_cache.rs` checks vertices, edge midpoints,
    /// centroids, on and off the surface, and random walks, bit for bit: no difference seen
    /// there; a run of a sheet sliding over sine ribs found one, two faces whose distances
    /// differ by one ulp, which is why the step uses [`SurfaceMesh::project_near`], whose
    /// ties take the cold query).
    /// No allocation but the traversal's own queue (parry's, as in the cold query).
    pub fn project_cached(&self, x: [f64; 3], feature: &mut u32) -> Projection {
        let pt = Point::new(x[0], x[1], x[2]);
        let warm = (*feature < self.mesh.num_triangles() as u32).then(|| {
            let p0 = (self.mesh.triangle(*feature))
                .project_local_point_and_get_location(&pt, false)
                .0
                .point;
            let d0 = nalgebra::distance(&pt, &p0);
            let max_dist = d0 * (1.0 + 1e-12);
            (d0 > 0.0).then(|| {
                (self.mesh).project_local_point_and_get_location_with_max_dist(&pt, false, max_dist)
            })
        });
        // A point on the surface (d = 0) is at the same distance from every triangle around
        // it, and parry reports it on the face of one or on the edge of another (different
        // normals): the cold query decides. So does it when round-off in a box's distance
        // prunes the cached triangle's own leaf (never seen).
        let (proj, (tri, loc)) = match warm.flatten().flatten() {
            Some(found) if found.0.point != pt => found,
            _ => self.mesh.project_local_point_and_get_location(&pt, false),
        };
        *feature = tri;
        self.projection(proj.point, tri, loc)
    }

    /// [`SurfaceMesh::project`] from the node's list of nearby triangles (list `j` of `lists`,
    /// in the mould's frame, built here and kept between calls): the cold query's triangle,
    /// point and pseudo-normal, bit for bit, at about one triangle projection per call while
    /// the node stays near where the list was built. `feature` is the node's last triangle, as
    /// for [`SurfaceMesh::project_cached`] (updated).
    ///
    /// **The list and why it holds the answer** (model §7.5: p is the closest
    /// point of x on the surface). Built at x_ref, where the closest triangle T₀ is at the
    /// distance d₀ = dist(x_ref, T₀): the list holds, sorted by r_T = dist(x_ref, T), every
    /// triangle T with r_T ≤ R = d₀ + 2δ (at most [`NEAR_CAPACITY`]; when more, R is lowered
    /// to the r_T of the first left out). At x, with s = |x − x_ref|, any triangle T outside
    /// the list has, by the triangle inequality,
    ///
    /// dist(x, T) ≥ dist(x_ref, T) − s > R − s,                                        (1)
    ///
    /// and every listed T beyond the first ones evaluated has dist(x, T) ≥ r_T − s. So the
    /// triangles are evaluated in the list's order (one triangle projection each, parry's own,
    /// the same arithmetic as the BVH's leaf test), keeping the least distance w₁, until the
    /// next one's bound r_T − s exceeds w₁: the rest cannot be closer. When R − s > w₁ the
    /// closest triangle is in the list (while s < δ this always holds: w₁ ≤ dist(x, T₀) ≤
    /// d₀ + s < d₀ + 2δ − s = R − s; it is δ's meaning); otherwise the list is rebuilt at x.
    ///
    /// **Same bits as the cold query.** Every bound above is taken with a margin
    /// ε = 10⁻⁹(|x|∞ + the surface's largest coordinate), far above the round-off of a
    /// distance (≈ 10⁻¹⁶ of the coordinates) and far below any facet. When every triangle
    /// other than the closest one, T₁ at the computed distance w₁, is farther than w₁ + ε
    /// (evaluated, or by (1) or the list's bound), the cold best-first query returns T₁ with
    /// the same projection: the boxes above T₁ are at most w₁ (plus round-off) away, every
    /// other leaf's cost exceeds w₁ + ε, so T₁'s branch is never pruned and nothing replaces
    /// it. When other triangles are within ε of w₁ (an edge or a vertex shared by the closest
    /// triangles, a node on the surface at an edge: a tie that the cold query breaks by its
    /// visit order), the result is still the cold query's if each of them gives the same
    /// point and pseudo-normal, bit for bit (a shared vertex: the vertex and its
    /// pseudo-normal); otherwise the call takes the cold query itself (the only case that
    /// allocates, parry's queue, with a node's first build). Not the bounded query
    /// [`SurfaceMesh::project_cached`]: in a tie its pruning can keep the other triangle, and
    /// `physics/tests/mould_cache.rs`'s sliding run found one (two triangles 10⁻¹⁹ m apart,
    /// their points one ulp apart).
    ///
    /// **δ.** δ = (√(d₀² + ρ²) − d₀)/2 with ρ = [`NEAR_REACH`] × the longest edge of T₀: the
    /// sphere of radius d₀ + 2δ cuts a plane at distance d₀ in a disc of radius ρ, so the list
    /// holds the triangles within about ρ of the node's foot point whatever d₀ (δ = ρ/2 on
    /// the surface, ≈ ρ²/4d₀ far from it). A rebuild collects the candidates with parry's BVH
    /// (a depth-first traversal with a reused stack, boxes within d' + 2δ' of x, d' ≥ d₀ the
    /// distance to the closest triangle of the old list, or the full query's at the first
    /// build), projects each and sorts them; the lists are allocated when `lists` is
    /// ([`NearLists::new`]) and the candidates' buffer is reused, so a call allocates nothing
    /// but at a node's first build (the full query) and on a tie.
    pub fn project_near(
        &self,
        x: [f64; 3],
        feature: &mut u32,
        lists: &mut NearLists,
        j: usize,
    ) -> Projection {
        let pt = Point::new(x[0], x[1], x[2]);
        let aabb = self.mesh.local_aabb();
        let reach = (0..3)
            .map(|k| x[k].abs().max(aabb.mins[k].abs()).max(aabb.maxs[k].abs()))
            .fold(0.0, f64::max);
        let eps = NEAR_TOLERANCE * reach;
        lists.stats.queries += 1;
        let found = match self.near_from_list(&pt, eps, lists, j) {
            Near::Found(found) => Some(found),
            Near::Tie => None,
            Near::Rebuild(hint) => self.near_rebuild(&pt, eps, hint, lists, j),
        };
        match found {
            Some((proj, tri, loc)) => {
                *feature = tri;
                self.projection(proj.point, tri, loc)
            }
            None => {
                lists.stats.ties += 1;
                let (proj, (tri, loc)) = self.mesh.project_local_point_and_get_location(&pt, false);
                *feature = tri;
                self.projection(proj.point, tri, loc)
            }
        }
    }

    /// The closest triangle from list `j` (see [`SurfaceMesh::project_near`]).
    fn near_from_list(&self, pt: &Point<f64>, eps: f64, lists: &mut NearLists, j: usize) -> Near {
        let list = lists.lists[j];
        if list.len == 0 {
            return Near::Rebuild(None);
        }
        let x_ref = Point::from(list.x_ref);
        let s = nalgebra::distance(pt, &x_ref);
        let entries = &lists.entries[j * NEAR_CAPACITY..j * NEAR_CAPACITY + list.len as usize];
        let (mut best, mut w1, mut w2) = (None, f64::INFINITY, f64::INFINITY);
        let mut bound = list.radius - s - eps; // below every triangle not yet evaluated
        let mut evaluated = entries.len();
        for (n, e) in entries.iter().enumerate() {
            let lower = e.r as f64 - s - eps;
            if lower > w1 + eps {
                (bound, evaluated) = (lower, n);
                break;
            }
            let (proj, loc) =
                (self.mesh.triangle(e.tri)).project_local_point_and_get_location(pt, false);
            let w = nalgebra::distance(pt, &proj.point);
            lists.stats.projections += 1;
            if w < w1 {
                (w2, w1) = (w1, w);
                best = Some((proj, e.tri, loc));
            } else {
                w2 = w2.min(w);
            }
        }
        let agree = |b: &Found| {
            let others = entries[..evaluated].iter().map(|e| e.tri);
            self.ties_agree(pt, eps, w1, b, others)
        };
        match best {
            _ if !(bound > w1 + eps) => Near::Rebuild(best.map(|b| (b.1, w1))),
            Some(found) if w2 > w1 + eps || agree(&found) => Near::Found(found),
            _ => Near::Tie,
        }
    }

    /// True when every triangle of `others` within ε of the least distance w₁ projects `pt`
    /// to the same point with the same pseudo-normal as the closest one, `best`, bit for bit
    /// (a vertex shared by the tied triangles: the same vertex, the same vertex
    /// pseudo-normal): then the cold query's choice among them, set by its visit order, does
    /// not change its result.
    fn ties_agree(
        &self,
        pt: &Point<f64>,
        eps: f64,
        w1: f64,
        best: &Found,
        others: impl Iterator<Item = u32>,
    ) -> bool {
        let bits = |p: Projection| (p.point.map(f64::to_bits), p.normal.map(f64::to_bits));
        let want = bits(self.projection(best.0.point, best.1, best.2));
        others.filter(|&t| t != best.1).all(|t| {
            let (proj, loc) =
                (self.mesh.triangle(t)).project_local_point_and_get_location(pt, false);
            nalgebra::distance(pt, &proj.point) > w1 + eps
                || bits(self.projection(proj.point, t, loc)) == want
        })
    }

    /// Rebuilds list `j` at `pt` and returns the closest triangle (None on a tie), see
    /// [`SurfaceMesh::project_near`].
    fn near_rebuild(
        &self,
        pt: &Point<f64>,
        eps: f64,
        hint: Option<(u32, f64)>,
        lists: &mut NearLists,
        j: usize,
    ) -> Option<Found> {
        lists.stats.rebuilds += 1;
        // d' ≥ d₀: the distance to the closest triangle of the old list (the full query's at
        // the first build).
        let (last, d_last) = hint.unwrap_or_else(|| {
            let (proj, (tri, _)) = self.mesh.project_local_point_and_get_location(pt, false);
            (tri, nalgebra::distance(pt, &proj.point))
        });
        let delta = |d0: f64, tri: u32| {
            let [a, b, c] = self.mesh.triangle(tri).vertices().map(|v| v.coords);
            let edge = ((b - a).norm()).max((c - b).norm()).max((a - c).norm());
            let rho = NEAR_REACH * edge;
            // (√(d₀² + ρ²) − d₀)/2 without the cancellation.
            0.5 * rho * rho / ((d0 * d0 + rho * rho).sqrt() + d0)
        };
        let radius = d_last + 2.0 * delta(d_last, last) + eps;
        // The candidates: every triangle whose box is within `radius` (parry's BVH).
        let NearLists {
            candidates, stack, ..
        } = lists;
        candidates.clear();
        let simd_pt = Point::<SimdReal>::splat(*pt);
        let simd_radius = SimdReal::splat(radius);
        let mut visit = |aabb: &SimdAabb, data: Option<[Option<&u32>; SIMD_WIDTH]>| {
            let mask = aabb.distance_to_local_point(&simd_pt).simd_le(simd_radius);
            if let Some(data) = data {
                for (ii, t) in data.iter().enumerate() {
                    if let (true, Some(&t)) = (mask.extract(ii), t) {
                        candidates.push((0.0, t));
                    }
                }
            }
            SimdVisitStatus::MaybeContinue(mask)
        };
        self.mesh
            .qbvh()
            .traverse_depth_first_with_stack(&mut visit, stack);
        // Their distances, the closest and the next.
        let (mut best, mut w1, mut w2) = (None, f64::INFINITY, f64::INFINITY);
        for c in candidates.iter_mut() {
            let (proj, loc) =
                (self.mesh.triangle(c.1)).project_local_point_and_get_location(pt, false);
            c.0 = nalgebra::distance(pt, &proj.point);
            if c.0 < w1 {
                (w2, w1) = (w1, c.0);
                best = Some((proj, c.1, loc));
            } else {
                w2 = w2.min(c.0);
            }
        }
        lists.stats.projections += candidates.len() as u64;
        lists.stats.candidates += candidates.len() as u64;
        let (_, tri, _) = best?; // the last triangle is always a candidate
                                 // The list: the candidates within w₁ + 2δ (δ of the closest triangle), sorted.
        candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut bound = (w1 + 2.0 * delta(w1, tri)).min(radius);
        let mut len = candidates.partition_point(|c| c.0 <= bound);
        if len > NEAR_CAPACITY {
            len = NEAR_CAPACITY;
            bound = candidates[len].0;
        }
        let slots = &mut lists.entries[j * NEAR_CAPACITY..j * NEAR_CAPACITY + len];
        for (e, &(r, t)) in slots.iter_mut().zip(candidates.iter()) {
            // r rounded down to f32: still a lower bound, half the memory.
            let r32 = r as f32;
            let r32 = if r32 as f64 > r { r32.next_down() } else { r32 };
            *e = NearEntry { tri: t, r: r32 };
        }
        lists.stats.listed += len as u64;
        lists.lists[j] = NearList {
            x_ref: [pt.x, pt.y, pt.z],
            radius: bound,
            len: len as u32,
        };
        // The closest is the cold query's unless a second one is within ε and projects
        // elsewhere (a tie): every triangle not a candidate is farther than
        // radius − ε ≥ d' + 2δ' ≥ w₁ + 2δ'. The list is
        // complete below `bound`: the candidates left out are beyond it or beyond the first
        // left out, the others beyond `radius`.
        let found = best?;
        let near_ties = candidates.iter().filter(|c| c.0 <= w1 + eps).map(|c| c.1);
        (w2 > w1 + eps || self.ties_agree(pt, eps, w1, &found, near_ties)).then_some(found)
    }

    /// The projection onto triangle `tri` at `loc` as a [`Projection`]: the point and the
    /// unit pseudo-normal of the feature.
    fn projection(&self, p: Point<f64>, tri: u32, loc: TrianglePointLocation) -> Projection {
        let face = || self.mesh.triangle(tri).scaled_normal();
        let pn = self.mesh.pseudo_normals_if_oriented();
        let n = match (loc, pn) {
            (TrianglePointLocation::OnEdge(i, _), Some(pn)) => {
                pn.edges_pseudo_normal[tri as usize][i as usize]
            }
            (TrianglePointLocation::OnVertex(i), Some(pn)) => {
                let v = self.mesh.indices()[tri as usize][i as usize];
                pn.vertices_pseudo_normal[v as usize]
            }
            _ => face(),
        };
        let n = [n.x, n.y, n.z];
        let l = norm(n);
        Projection {
            point: [p.x, p.y, p.z],
            normal: n.map(|c| c / l),
        }
    }
}

/// No cached feature yet ([`SurfaceMesh::project_cached`]).
pub const NO_FEATURE: u32 = u32::MAX;

/// The most triangles a node's list holds ([`SurfaceMesh::project_near`]).
pub const NEAR_CAPACITY: usize = 16;

/// ρ/(longest edge of the node's closest triangle): the list reaches about ρ around the node's
/// foot point on the surface ([`SurfaceMesh::project_near`]).
pub const NEAR_REACH: f64 = 0.5;

/// ε/(the largest coordinate of the node and the surface): the margin of the list's bounds and
/// of a tie ([`SurfaceMesh::project_near`]).
pub const NEAR_TOLERANCE: f64 = 1e-9;

/// A triangle's projection of a point: the point, the triangle, the feature.
type Found = (PointProjection, u32, TrianglePointLocation);

/// What a node's list gives.
enum Near {
    Found(Found),
    Tie,
    /// With the closest listed triangle evaluated and its distance, when there was a list.
    Rebuild(Option<(u32, f64)>),
}

/// Where a node's list was built, the bound R below which it is complete, its length.
#[derive(Debug, Clone, Copy, Default)]
struct NearList {
    x_ref: [f64; 3],
    radius: f64,
    len: u32,
}

/// A listed triangle and its distance r_T from x_ref (rounded down).
#[derive(Debug, Clone, Copy, Default)]
struct NearEntry {
    tri: u32,
    r: f32,
}

/// Counts of [`SurfaceMesh::project_near`]'s work since the lists were made.
#[derive(Debug, Clone, Copy, Default)]
pub struct NearStats {
    /// Calls; triangle projections (from the lists and in rebuilds, not the second look at
    /// near-ties); rebuilds (a node's first build included); ties (the full query taken);
    /// triangles put in lists; candidates the rebuilds projected.
    pub queries: u64,
    pub projections: u64,
    pub rebuilds: u64,
    pub ties: u64,
    pub listed: u64,
    pub candidates: u64,
}

/// Per node, its list of nearby triangles on its triangulated mould
/// ([`SurfaceMesh::project_near`]), allocated once ([`NEAR_CAPACITY`] slots per node), and the
/// rebuilds' reused buffers.
#[derive(Debug, Clone, Default)]
pub struct NearLists {
    lists: Vec<NearList>,
    entries: Vec<NearEntry>,
    candidates: Vec<(f64, u32)>,
    stack: Vec<u32>,
    pub stats: NearStats,
}

impl NearLists {
    /// Empty lists for `nodes` nodes (each built at its first query).
    pub fn new(nodes: usize) -> NearLists {
        NearLists {
            lists: vec![NearList::default(); nodes],
            entries: vec![NearEntry::default(); nodes * NEAR_CAPACITY],
            candidates: Vec::with_capacity(256),
            stack: Vec::with_capacity(64),
            stats: NearStats::default(),
        }
    }
}

/// Refuses degenerate triangles, edges of more than two triangles and inconsistently oriented
/// neighbours (module docs). Vertices that coincide exactly are one vertex: returns, per
/// vertex, the index of the first vertex at its position.
pub fn check_orientation(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    element: &dyn Fn(usize) -> String,
) -> Result<Vec<u32>, String> {
    let mut canon: HashMap<[u64; 3], u32> = HashMap::new();
    let id: Vec<u32> = vertices
        .iter()
        .enumerate()
        .map(|(i, v)| *canon.entry(v.map(f64::to_bits)).or_insert(i as u32))
        .collect();
    // Directed edge (a, b) → the triangle that runs through it, and undirected use counts.
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
    for (k, t) in triangles.iter().enumerate() {
        if t.iter().any(|&v| v as usize >= vertices.len()) {
            return Err(format!(
                "{} refers to a vertex that does not exist",
                element(k)
            ));
        }
        let [a, b, c] = t.map(|v| vertices[v as usize]);
        let area2 = norm(cross(sub(b, a), sub(c, a)));
        let longest = [
            dot(sub(b, a), sub(b, a)),
            dot(sub(c, b), sub(c, b)),
            dot(sub(a, c), sub(a, c)),
        ]
        .into_iter()
        .fold(0.0f64, f64::max);
        let v = t.map(|v| id[v as usize]);
        if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || !(area2 > 1e-12 * longest) {
            return Err(format!(
                "{} is degenerate (zero area or a repeated vertex): its orientation is undefined",
                element(k)
            ));
        }
        for e in 0..3 {
            let (p, q) = (v[e], v[(e + 1) % 3]);
            if let Some(j) = directed.insert((p, q), k) {
                return Err(format!(
                    "{} and {} run through their shared edge the same way: the surface's orientation is inconsistent (one of them is flipped; the normal (b − a) × (c − a) must point out of the mould)",
                    element(j),
                    element(k)
                ));
            }
            let n = uses.entry((p.min(q), p.max(q))).or_insert(0);
            *n += 1;
            if *n > 2 {
                return Err(format!(
                    "{} shares an edge with two other triangles: not a surface (an edge belongs to at most two triangles)",
                    element(k)
                ));
            }
        }
    }
    Ok(id)
}

/// The triangles of an STL file (binary when it is not ASCII `solid … facet`), checked with the
/// file's facet normals: a written normal (non-zero) that opposes the vertex order's normal is
/// refused. Returns (vertices, triangles), three vertices per triangle.
pub fn read_stl(bytes: &[u8], file: &str) -> Result<Triangles, SurfaceError> {
    let err = |message: String| SurfaceError {
        file: file.to_string(),
        message,
    };
    let text = std::str::from_utf8(bytes).ok();
    let ascii = text.filter(|t| t.trim_start().starts_with("solid") && t.contains("facet"));
    let facets: Vec<([f64; 3], [[f64; 3]; 3])> = match ascii {
        Some(t) => read_ascii_stl(t).map_err(err)?,
        None => read_binary_stl(bytes).map_err(err)?,
    };
    if facets.is_empty() {
        return Err(err("not an STL file with triangles (no facet found)".into()));
    }
    let mut vertices = Vec::with_capacity(3 * facets.len());
    for (k, (n, v)) in facets.iter().enumerate() {
        let computed = cross(sub(v[1], v[0]), sub(v[2], v[0]));
        if dot(*n, computed) < 0.0 {
            return Err(err(format!(
                "facet {k}: its written normal {n:?} opposes the normal of its vertex order (counter-clockwise seen from outside): inconsistent orientation"
            )));
        }
        vertices.extend_from_slice(v);
    }
    let triangles = (0..facets.len() as u32)
        .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
        .collect();
    Ok((vertices, triangles))
}

type Facet = ([f64; 3], [[f64; 3]; 3]);

/// Vertices and triangles (indices into the vertices).
pub type Triangles = (Vec<[f64; 3]>, Vec<[u32; 3]>);

fn read_ascii_stl(text: &str) -> Result<Vec<Facet>, String> {
    let mut out = Vec::new();
    let mut words = text.split_whitespace().enumerate().peekable();
    let triple = |words: &mut std::iter::Peekable<_>, what: &str| -> Result<[f64; 3], String> {
        let mut v = [0.0; 3];
        for c in &mut v {
            let (_, w): (usize, &str) = words
                .next()
                .ok_or_else(|| format!("ASCII STL ends inside a {what}"))?;
            *c = w
                .parse()
                .map_err(|_| format!("ASCII STL: expected a number in a {what}, found {w:?}"))?;
        }
        Ok(v)
    };
    while let Some((_, w)) = words.next() {
        if w != "facet" {
            continue;
        }
        match words.next() {
            Some((_, "normal")) => {}
            _ => {
                return Err(format!(
                    "ASCII STL facet {}: expected `facet normal`",
                    out.len()
                ))
            }
        }
        let n = triple(&mut words, "facet normal")?;
        let mut v = [[0.0; 3]; 3];
        let mut k = 0;
        while k < 3 {
            match words.next() {
                Some((_, "vertex")) => {
                    v[k] = triple(&mut words, "vertex")?;
                    k += 1;
                }
                Some((_, "endfacet")) | None => {
                    return Err(format!(
                        "ASCII STL facet {}: fewer than 3 vertices",
                        out.len()
                    ))
                }
                _ => {}
            }
        }
        out.push((n, v));
    }
    Ok(out)
}

fn read_binary_stl(bytes: &[u8]) -> Result<Vec<Facet>, String> {
    if bytes.len() < 84 {
        return Err(format!(
            "not an STL file: {} bytes, neither ASCII (`solid … facet …`) nor a binary STL (80-byte header and a triangle count)",
            bytes.len()
        ));
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    let expected = 84 + 50 * count;
    if bytes.len() != expected {
        return Err(format!(
            "not an STL file: a binary STL with {count} triangles has {expected} bytes, this file has {}",
            bytes.len()
        ));
    }
    let f =
        |o: usize| f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]) as f64;
    let v3 = |o: usize| [f(o), f(o + 4), f(o + 8)];
    Ok((0..count)
        .map(|k| {
            let o = 84 + 50 * k;
            (v3(o), [v3(o + 12), v3(o + 24), v3(o + 36)])
        })
        .collect())
}
