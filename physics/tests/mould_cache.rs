//! The closest-point caches of triangulated moulds (the closest point of model §7.5, from each
//! node's last feature): the bounded query ([`SurfaceMesh::project_cached`], started from the
//! triangle a node found at its last step, the BVH asked only for a point closer than that
//! triangle's) and the list query ([`SurfaceMesh::project_near`], from the node's list of nearby
//! triangles, rebuilt when the node leaves its validity) return the cold query's closest point and
//! pseudo-normal, bit for bit, whatever the cached triangle — on vertices, edge midpoints and face
//! centroids (where several triangles tie), off them, along random walks that carry the caches from
//! point to point, walks that swing in and out of a list's validity, and from a wrong cached
//! triangle. Each case also asserts that every path of the list query was taken (from the list,
//! rebuilt, tie). A golden run (`tread_demould`) being unchanged is the scene-level check.

use crate::common::scene_file;

use decohesion_physics::mould::surface::{read_stl, NearLists, NearStats, NO_FEATURE};
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

/// A node's caches: its last triangle for the bounded query, and for the list query its last
/// triangle and its list.
struct Warm {
    bounded: u32,
    near: u32,
    lists: NearLists,
}

impl Warm {
    fn new(feature: u32) -> Warm {
        Warm {
            bounded: feature,
            near: feature,
            lists: NearLists::new(1),
        }
    }
}

/// Checks both warm queries against the cold one at x with the caches `w` (updated); returns
/// the number of points checked (1).
fn check(s: &SurfaceMesh, x: [f64; 3], w: &mut Warm) -> usize {
    let cold = s.project(x);
    let bits = |p: decohesion_physics::mould::Projection| {
        (p.point.map(f64::to_bits), p.normal.map(f64::to_bits))
    };
    let from = (w.bounded, w.near);
    let warm = s.project_cached(x, &mut w.bounded);
    assert_eq!(
        bits(warm),
        bits(cold),
        "x = {x:?}, cached triangle {from:?}: bounded {warm:?}, cold {cold:?}"
    );
    let near = s.project_near(x, &mut w.near, &mut w.lists, 0);
    assert_eq!(
        bits(near),
        bits(cold),
        "x = {x:?}, cached triangle {from:?}: from the list {near:?}, cold {cold:?}"
    );
    assert!((w.bounded as usize) < s.mesh.num_triangles());
    assert!((w.near as usize) < s.mesh.num_triangles());
    1
}

fn add_stats(total: &mut NearStats, w: &Warm) {
    let st = w.lists.stats;
    total.queries += st.queries;
    total.rebuilds += st.rebuilds;
    total.ties += st.ties;
    total.projections += st.projections;
    total.listed += st.listed;
    total.candidates += st.candidates;
}

/// Every vertex, edge midpoint and face centroid, on the surface and moved off it by `off`
/// (random directions), from the right triangle, a wrong one and none; then random walks of
/// steps `step` long that carry the caches along, and walks that swing about a point with an
/// amplitude `swing` (of the order of the lists' margin δ: in and out of a list's validity)
/// by steps of swing/20. Returns the points checked and what the lists did.
fn warm_equals_cold(
    s: &SurfaceMesh,
    off: f64,
    step: f64,
    swing: f64,
    rng: &mut Lcg,
) -> (usize, NearStats) {
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
    let mut stats = NearStats::default();
    for x in points {
        for y in [x, add(x, rng.vector(off))] {
            let mut w = Warm::new(NO_FEATURE);
            checked += check(s, y, &mut w);
            checked += check(s, y, &mut w); // from its own triangle and list
            add_stats(&mut stats, &w);
            let mut wrong = Warm::new((rng.next() * nt) as u32);
            checked += check(s, y, &mut wrong);
            add_stats(&mut stats, &wrong);
        }
    }
    for _ in 0..20 {
        let mut x = p((rng.next() * v.len() as f64) as u32);
        let mut w = Warm::new(NO_FEATURE);
        for _ in 0..500 {
            x = add(x, rng.vector(step));
            checked += check(s, x, &mut w);
        }
        add_stats(&mut stats, &w);
    }
    for _ in 0..20 {
        let x0 = add(p((rng.next() * v.len() as f64) as u32), rng.vector(off));
        let dir = rng.vector(swing);
        let mut w = Warm::new(NO_FEATURE);
        for k in 0..400 {
            let a = (k as f64 * std::f64::consts::PI / 20.0).sin();
            let x = add(add(x0, dir.map(|c| a * c)), rng.vector(0.01 * swing));
            checked += check(s, x, &mut w);
        }
        add_stats(&mut stats, &w);
    }
    // Every path of the list query was taken: from the list, rebuilt, tie (the bounded query).
    eprintln!("{stats:?}");
    assert!(stats.rebuilds > 0 && stats.ties > 0, "{stats:?}");
    assert!(stats.queries > stats.rebuilds + stats.ties, "{stats:?}");
    (checked, stats)
}

#[test]
fn warm_query_is_the_cold_query_on_sine_ribs() {
    // 2 × 30² triangles over 30 mm, ribs 1 mm high every 10 mm (facets 1 mm wide).
    let (v, t) = sine_ribs::sine_ribs(30, 0.0, 0.03, 1e-3, 0.01);
    let s = SurfaceMesh::new("sine", None, 1.0, v, t, &|k| format!("triangle {k}")).unwrap();
    // δ = ρ/2 = 0.25 × the longest edge (≈ 1.4 mm) on the surface: swing 0.5 mm.
    let (n, st) = warm_equals_cold(&s, 3e-4, 2e-4, 5e-4, &mut Lcg(1));
    assert!(n > 50_000, "{n} points");
    eprintln!("sine ribs: {n} points, {st:?}");
}

#[test]
fn warm_query_is_the_cold_query_on_the_ribbed_mould() {
    // The tread's mould (mm): sharp rib edges, walls drafted 14°, long thin triangles.
    let file = scene_file("meshes/ribbed_mould.stl");
    let bytes = std::fs::read(&file).unwrap();
    let (v, t) = read_stl(&bytes, "ribbed_mould.stl").unwrap();
    let s = SurfaceMesh::new("ribbed", None, 1.0, v, t, &|k| format!("facet {k}")).unwrap();
    let (n, st) = warm_equals_cold(&s, 2.0, 0.5, 3.0, &mut Lcg(2));
    assert!(n > 10_000, "{n} points");
    eprintln!("ribbed mould: {n} points, {st:?}");
}

/// A 20 × 20 × 1 mm sheet (20 × 20 × 1 hex8) whose bottom is a contact face set on a sine-ribs
/// surface (2 × 20² triangles, 1.5 mm squares, ribs 1 mm high every 10 mm) that rises into it
/// at 0.2 m/s and slides under it at 1 m/s: over 400 steps the bottom nodes travel about a
/// millimetre over the mould, several lists' margins δ (≈ 0.4 mm), so the lists are rebuilt
/// along the run as well as used. The nodes lie every 1 mm, the mould's vertices every
/// 1.5 mm: a third of the nodes sit above a column of vertices, where two faces of a valley
/// are at the same distance to round-off (ties). This run is what showed that the bounded
/// query (`project_cached`) can pick the other face of such a tie, one ulp away.
fn sliding() -> String {
    sine_ribs::Sheet {
        name: "sliding_ribs",
        file: "ribs.stl",
        velocity: Some("[[0.0, 0.0, 0.0, 0.0], [2.0e-4, 1.0, 0.0, 0.2], [1.0, 1.0, 0.0, 0.2]]"),
        gravity: false,
        origin: [0.0, 0.0, 1.0e-3],
        size: [0.02, 0.02, 0.001],
        cells: [20, 20, 1],
    }
    .toml()
}

#[test]
fn a_run_from_the_lists_is_the_cold_run_bit_for_bit() {
    use decohesion_physics::scene::load_scene;
    use decohesion_physics::solver::Simulation;
    let dir = std::env::temp_dir().join(format!("mould_cache_test_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (v, t) = sine_ribs::sine_ribs(20, -0.005, 0.03, 1e-3, 0.01);
    std::fs::write(dir.join("ribs.stl"), sine_ribs::to_stl(&v, &t)).unwrap();
    std::fs::write(dir.join("sliding.toml"), sliding()).unwrap();
    let sim = |cold: bool| {
        let scene = load_scene(&dir.join("sliding.toml"), &[]).unwrap();
        let mut sim = Simulation::new(scene.model).unwrap();
        sim.set_mould_queries_cold(cold);
        sim
    };
    let (mut cold, mut warm) = (sim(true), sim(false));
    let nodes = warm.state.contact_nodes.len();
    let mut touching = 0;
    for step in 0..400 {
        cold.step().unwrap();
        warm.step().unwrap();
        let gaps = |s: &Simulation| -> Vec<u64> {
            s.state
                .contact_nodes
                .iter()
                .map(|c| c.gap.to_bits())
                .collect()
        };
        assert_eq!(gaps(&warm), gaps(&cold), "step {step}: the gaps differ");
        touching += warm
            .state
            .contact_nodes
            .iter()
            .filter(|c| c.gap <= 0.0)
            .count();
    }
    let bits = |s: &Simulation| -> Vec<u64> {
        (s.state.u.rows().chain(s.state.v.rows()).flatten())
            .map(|x| x.to_bits())
            .collect()
    };
    assert!(bits(&warm) == bits(&cold), "the final states differ");
    std::fs::remove_dir_all(&dir).ok();
    // The run exercised the lists: contact happened, every node queried at the start and at
    // each step, lists rebuilt after the first builds (one per node) and used far more often
    // than rebuilt, ties taken by the cold query.
    let st = warm.mould_near_stats()[1];
    eprintln!("{nodes} contact nodes, {touching} node-steps touching, {st:?}");
    assert!(touching > 2 * nodes, "{touching} node-steps touching");
    assert_eq!(st.queries, 400 * nodes as u64 + nodes as u64, "{st:?}");
    assert!(st.rebuilds > 2 * nodes as u64, "{st:?}");
    assert!(st.queries > 10 * st.rebuilds && st.ties > 0, "{st:?}");
}
