//! Closest points from per-node lists of nearby triangles ([`SurfaceMesh::project_near`]): the
//! lists, their bounds and their rebuilds.

use super::SurfaceMesh;
use crate::mould::Projection;
pub use crate::tunables::{NEAR_CAPACITY, NEAR_REACH, NEAR_TOLERANCE};
use nalgebra::{SimdPartialOrd, SimdValue};
use parry3d_f64::bounding_volume::SimdAabb;
use parry3d_f64::math::{Point, SimdReal, SIMD_WIDTH};
use parry3d_f64::partitioning::SimdVisitStatus;
use parry3d_f64::query::{PointProjection, PointQueryWithLocation};
use parry3d_f64::shape::TrianglePointLocation;

impl SurfaceMesh {
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
}

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
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
struct NearList {
    x_ref: [f64; 3],
    radius: f64,
    len: u32,
}

/// A listed triangle and its distance r_T from x_ref (rounded down).
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
struct NearEntry {
    tri: u32,
    r: f32,
}

/// Counts of [`SurfaceMesh::project_near`]'s work since the lists were made.
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
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
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct NearLists {
    lists: Vec<NearList>,
    entries: Vec<NearEntry>,
    candidates: Vec<(f64, u32)>,
    stack: Vec<u32>,
    pub stats: NearStats,
}

impl NearLists {
    /// The triangles of list `j` (none before its first build, or when the lists are not
    /// allocated).
    pub fn listed(&self, j: usize) -> impl Iterator<Item = u32> + '_ {
        let len = self.lists.get(j).map_or(0, |l| l.len as usize);
        let start = j * NEAR_CAPACITY;
        self.entries[start.min(self.entries.len())..(start + len).min(self.entries.len())]
            .iter()
            .map(|e| e.tri)
    }

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
