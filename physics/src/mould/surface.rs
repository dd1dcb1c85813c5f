//! Triangulated mould surfaces: read from STL (ASCII or binary) or from a 2-D physical group of a
//! Gmsh `.msh` file (triangles, or quadrangles split in two), checked, and queried with
//! `parry3d-f64` (a BVH over the triangles, projection with the feature hit, pseudo-normals).
//!
//! Orientation: a triangle (a, b, c) has the normal (b − a) × (c − a) (right-hand rule), which
//! must point **out of the mould**, into the solid (STL's convention for a solid's facets).
//!
//! Vertices closer than [`WELD_TOLERANCE`] × the surface's bounding-box diagonal are welded
//! into one (`check.rs`). The loader refuses, naming the file, the element and the reason: a
//! non-finite coordinate, a degenerate triangle (area ≤ 1e-12 × its longest edge², or two of its
//! vertices welded into one), an edge shared by more than two triangles (not a surface), two
//! triangles that run through their shared edge the same way (inconsistent orientation), two
//! triangles folded onto each other across their shared edge (normals opposite within
//! [`FOLD_TOLERANCE`]: the edge's pseudo-normal would be zero and the gap undefined), a vertex
//! whose pseudo-normal is zero (its triangles' normals cancel), and an STL facet whose written
//! normal opposes its vertex order (`stl.rs`).
//!
//! **Open surfaces** are accepted: a sheet (the ribbed face of a mould, with the steel behind
//! it) is the usual case. [`SurfaceMesh::open_edges`] counts the edges of one triangle (the
//! rim), and [`super::open_surface_warnings`] reports them. A node beyond the rim projects onto
//! the rim, whose pseudo-normal is its one triangle's normal: there the gap is the distance
//! along that normal from the plane of the rim's triangle, so the mould acts as that plane
//! extended beyond its rim. That is right for a node that stays in front of the sheet and wrong
//! for one that reaches around the rim behind it; a closed surface has no rim.

mod check;
mod faces;
mod near;
mod stl;

pub use check::{check_surface, Topology, FOLD_TOLERANCE, WELD_TOLERANCE};
pub use faces::{Faces, MAX_FACES};
pub use near::{NearLists, NearStats, NEAR_CAPACITY, NEAR_REACH, NEAR_TOLERANCE};
pub use stl::{read_stl, Triangles};

use super::Projection;
use crate::mesh::norm;
use parry3d_f64::math::Point;
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{TriMesh, TriMeshFlags, TrianglePointLocation};

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
    /// The edges of one triangle only (the rim of an open surface; 0 when closed).
    pub open_edges: usize,
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
    /// Checks the triangles and welds the vertices ([`check_surface`]), builds the BVH and the
    /// pseudo-normals, and refuses a vertex whose pseudo-normal is zero.
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
        let Topology { id, open_edges } =
            check_surface(&vertices, &triangles, element).map_err(err)?;
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
        let welded: Vec<[u32; 3]> = (triangles.iter())
            .map(|t| t.map(|v| new_index[id[v as usize] as usize]))
            .collect();
        let mesh = TriMesh::with_flags(points, welded.clone(), TriMeshFlags::ORIENTED)
            .map_err(|e| err(format!("cannot build the triangle mesh: {e}")))?;
        // A vertex whose triangles' normals cancel (angle-weighted) has no normal: a node closest
        // to it would get a NaN gap. Unused vertices have none and are never closest.
        if let Some(pn) = mesh.pseudo_normals_if_oriented() {
            for &v in welded.iter().flatten() {
                let n = pn.vertices_pseudo_normal[v as usize];
                if !(n.norm() > FOLD_TOLERANCE) {
                    let around: Vec<String> = (welded.iter().enumerate())
                        .filter(|(_, t)| t.contains(&v))
                        .map(|(k, _)| element(k))
                        .collect();
                    return Err(err(format!(
                        "the normals of the triangles around a vertex cancel ({}): its pseudo-normal is zero and the gap of a node closest to it undefined; the surface folds back onto itself there",
                        around.join(", ")
                    )));
                }
            }
        }
        Ok(SurfaceMesh {
            file: file.to_string(),
            group,
            scale,
            mesh,
            open_edges,
        })
    }

    /// Closest point p and the pseudo-normal n of its feature (face, edge or vertex), in the
    /// mould's frame at t = 0 (module docs of [`super`]): the full BVH query (best-first).
    pub fn project(&self, x: [f64; 3]) -> Projection {
        self.project_triangle(x).0
    }

    /// [`SurfaceMesh::project`] and the triangle that holds the closest point.
    pub fn project_triangle(&self, x: [f64; 3]) -> (Projection, u32) {
        let (proj, (tri, loc)) =
            (self.mesh).project_local_point_and_get_location(&Point::new(x[0], x[1], x[2]), false);
        (self.projection(proj.point, tri, loc), tri)
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
