//! The time step allocates nothing once its buffers exist: a
//! counting global allocator sees zero allocations over 200 steps of the pull-off on
//! an explicit two-thread team (14³, interface, prescribed face, both quadratures), h_crit
//! estimates off (an estimate builds its Lanczos vectors). The team is asked for explicitly, so
//! a one-core machine tests it too. Then the same over 200 steps of a sheet on a sliding
//! triangulated mould (model §7.1): the closest points come from the nodes' lists of nearby
//! triangles, used and rebuilt without allocating (only a tie, which takes parry's full
//! query, would allocate: the scene has none, which the test checks too). And the same over
//! 200 steps of the pull-off cut into tetrahedra (model §1.13) in a nearly incompressible
//! rubber, whose average nodal pressure keeps its points and nodal fields between steps.

mod common;
use common::scene_file;

#[allow(dead_code)]
#[path = "../../examples/shared/sine_ribs.rs"]
mod sine_ribs;

use decohesion_physics::material::rubber::{
    neo_hookean::NeoHookean, Isochoric, Rubber, Volumetric,
};
use decohesion_physics::material::Material;
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn steps_allocate_nothing() {
    for integration in ["full", "reduced"] {
        let set = vec![
            "mesh.cells=[14,14,14]".to_string(),
            "scheme.h_crit_update_interval=0".to_string(),
            format!("scheme.integration=\"{integration}\""),
        ];
        let scene = load_scene(&scene_file("pull_off.toml"), &set).unwrap();
        let mut sim = Simulation::new(scene.model).unwrap();
        sim.use_threads(2);
        assert_eq!(sim.threads(), 2);
        // The first steps size the reused buffers.
        for _ in 0..3 {
            sim.step().unwrap();
        }
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for _ in 0..200 {
            sim.step().unwrap();
        }
        let during = ALLOCATIONS.load(Ordering::SeqCst) - before;
        assert_eq!(
            during, 0,
            "{integration}: {during} allocations in 200 steps"
        );
    }
    triangulated_mould_steps_allocate_nothing();
    tet_steps_allocate_nothing();
}

/// The pull-off at 8³ cells cut into 3072 tetrahedra (Kuhn) and its glued face into triangles,
/// in an isochoric neo-Hookean rubber of the scene's E at ν = 0.499 (so the average nodal
/// pressure runs), on an explicit two-thread team.
fn tet_steps_allocate_nothing() {
    let set = vec![
        "mesh.cells=[8,8,8]".to_string(),
        "scheme.h_crit_update_interval=0".to_string(),
    ];
    let scene = load_scene(&scene_file("pull_off.toml"), &set).unwrap();
    let mut m = (*scene.model).clone();
    m.mesh = m.mesh.kuhn_tets();
    let (e, nu) = (m.material.young, 0.499);
    m.material = Material::rubber(
        Rubber {
            iso: Isochoric::NeoHookean(NeoHookean {
                c10: e / (4.0 * (1.0 + nu)),
            }),
            bulk: e / (3.0 * (1.0 - 2.0 * nu)),
            volumetric: Volumetric::Quadratic,
        },
        m.material.density,
    );
    let mut sim = Simulation::new(m).unwrap();
    sim.use_threads(2);
    assert_eq!(sim.threads(), 2);
    assert!(sim.model.mesh.elements.is_empty() && !sim.model.mesh.tets.is_empty());
    for _ in 0..3 {
        sim.step().unwrap();
    }
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    for _ in 0..200 {
        sim.step().unwrap();
    }
    let during = ALLOCATIONS.load(Ordering::SeqCst) - before;
    assert_eq!(during, 0, "tetrahedra: {during} allocations in 200 steps");
}

/// A 10 × 10 × 1 mm sheet (10 × 10 × 1 hex8) on a flat triangulated mould (2 × 20² triangles,
/// 1.5 mm squares) that rises into it at 0.05 m/s and slides under it at 3 m/s (more than a
/// list's margin δ ≈ 0.5 mm over the 200 steps: lists are rebuilt); the sheet's nodes (every
/// 1 mm, offset by 0.2 and 0.45 mm) start off the triangles' edges and diagonals, and a node
/// that slides exactly onto an edge at a step's end would be a tie: none does.
fn triangulated_mould_steps_allocate_nothing() {
    let scene = sine_ribs::Sheet {
        name: "sliding_plane",
        file: "flat.stl",
        velocity: Some("[[0.0, 0.0, 0.0, 0.0], [1.0e-4, 3.0, 0.0, 0.05], [1.0, 3.0, 0.0, 0.05]]"),
        gravity: false,
        origin: [2.0e-4, 4.5e-4, 0.0],
        size: [0.01, 0.01, 0.001],
        cells: [10, 10, 1],
    }
    .toml();
    let dir = std::env::temp_dir().join(format!("allocation_test_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (v, t) = sine_ribs::sine_ribs(20, -0.01, 0.03, 0.0, 0.01);
    std::fs::write(dir.join("flat.stl"), sine_ribs::to_stl(&v, &t)).unwrap();
    std::fs::write(dir.join("sliding.toml"), scene).unwrap();
    let scene = load_scene(&dir.join("sliding.toml"), &[]).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let mut sim = Simulation::new(scene.model).unwrap();
    for _ in 0..3 {
        sim.step().unwrap();
    }
    let start = sim.mould_near_stats()[1];
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    let mut touching = 0;
    for _ in 0..200 {
        sim.step().unwrap();
        touching += (sim.state.contact_nodes.iter())
            .filter(|c| c.gap <= 0.0)
            .count();
    }
    let during = ALLOCATIONS.load(Ordering::SeqCst) - before;
    let end = sim.mould_near_stats()[1];
    let nodes = sim.state.contact_nodes.len() as u64;
    assert_eq!(
        during, 0,
        "triangulated mould: {during} allocations in 200 steps"
    );
    // The lists were used and rebuilt in those steps, with no tie, and the mould touched.
    assert_eq!(end.ties, start.ties, "{end:?}");
    assert!(
        end.rebuilds >= start.rebuilds + nodes,
        "{start:?} → {end:?}"
    );
    assert_eq!(end.queries - start.queries, 200 * nodes, "{end:?}");
    assert!(touching > 0, "no node touched the mould");
}
