//! The closest-point cache of triangulated moulds (issue 13, "cache each node's last feature"):
//! the warm query ([`SurfaceMesh::project_cached`], started from the triangle a node found at
//! its last step, the BVH asked only for a point closer than that triangle's) returns the cold
//! query's closest point and pseudo-normal, bit for bit, whatever the cached triangle — on
//! vertices, edge midpoints and face centroids (where several triangles tie), off them, along
//! random walks that carry the cache from point to point, and from a wrong cached triangle.
//! A golden run (`tread_demould`) being unchanged is the scene-level check.

mod common;
use common::scene_file;

use decohesion_physics::mould::surface::{read_stl, NO_FEATURE};
use decohesion_physics::mould::SurfaceMesh;

#[allow(dead_code)]
#[path = "../../examples/shared/sine_ribs.rs"]
mod sine_ribs;

/// A small deterministic generator (64-bit LCG, the top 53 bits): uniform in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = (self.0)
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn vector(&mut self, scale: f64) -> [f64; 3] {
        [0, 1, 2].map(|_| scale * (2.0 * self.next() - 1.0))
    }
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Checks warm against cold at x with the cache `feature` (updated); returns the number of
/// points checked (1).
fn check(s: &SurfaceMesh, x: [f64; 3], feature: &mut u32) -> usize {
    let cold = s.project(x);
    let from = *feature;
    let warm = s.project_cached(x, feature);
    assert_eq!(
        (warm.point.map(f64::to_bits), warm.normal.map(f64::to_bits)),
        (cold.point.map(f64::to_bits), cold.normal.map(f64::to_bits)),
        "x = {x:?}, cached triangle {from}: warm {warm:?}, cold {cold:?}"
    );
    assert!((*feature as usize) < s.mesh.num_triangles());
    1
}

/// Every vertex, edge midpoint and face centroid, on the surface and moved off it by `off`
/// (random directions), from the right triangle, a wrong one and none; then random walks of
/// steps `step` long that carry the cache along.
fn warm_equals_cold(s: &SurfaceMesh, off: f64, step: f64, rng: &mut Lcg) -> usize {
    let (v, t) = (s.mesh.vertices(), s.mesh.indices());
    let p = |i: u32| [v[i as usize].x, v[i as usize].y, v[i as usize].z];
    let mut points = Vec::new();
    for tri in t {
        let [a, b, c] = tri.map(p);
        let mid = |u: [f64; 3], w: [f64; 3]| [0, 1, 2].map(|k| 0.5 * (u[k] + w[k]));
        points.extend([a, mid(a, b), mid(b, c), mid(c, a)]);
        points.push([0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0));
    }
    let nt = t.len() as f64;
    let mut checked = 0;
    for x in points {
        for y in [x, add(x, rng.vector(off))] {
            let mut f = NO_FEATURE;
            checked += check(s, y, &mut f);
            checked += check(s, y, &mut f); // from its own triangle
            let mut wrong = (rng.next() * nt) as u32;
            checked += check(s, y, &mut wrong);
        }
    }
    for _ in 0..20 {
        let mut x = p((rng.next() * v.len() as f64) as u32);
        let mut f = NO_FEATURE;
        for _ in 0..500 {
            x = add(x, rng.vector(step));
            checked += check(s, x, &mut f);
        }
    }
    checked
}

#[test]
fn warm_query_is_the_cold_query_on_sine_ribs() {
    // 2 × 30² triangles over 30 mm, ribs 1 mm high every 10 mm (facets 1 mm wide).
    let (v, t) = sine_ribs::sine_ribs(30, 0.0, 0.03, 1e-3, 0.01);
    let s = SurfaceMesh::new("sine", None, 1.0, v, t, &|k| format!("triangle {k}")).unwrap();
    let n = warm_equals_cold(&s, 3e-4, 2e-4, &mut Lcg(1));
    assert!(n > 50_000, "{n} points");
}

#[test]
fn warm_query_is_the_cold_query_on_the_ribbed_mould() {
    // The tread's mould (mm): sharp rib edges, walls drafted 14°, long thin triangles.
    let file = scene_file("meshes/ribbed_mould.stl");
    let bytes = std::fs::read(&file).unwrap();
    let (v, t) = read_stl(&bytes, "ribbed_mould.stl").unwrap();
    let s = SurfaceMesh::new("ribbed", None, 1.0, v, t, &|k| format!("facet {k}")).unwrap();
    let n = warm_equals_cold(&s, 2.0, 0.5, &mut Lcg(2));
    assert!(n > 10_000, "{n} points");
}
