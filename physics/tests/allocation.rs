//! The time step allocates nothing once its buffers exist (issue 5: "no allocation in the
//! step"): a counting global allocator sees zero allocations over 200 steps of the pull-off on
//! an explicit two-thread team (14³, interface, prescribed face, both quadratures), h_crit
//! estimates off (an estimate builds its Lanczos vectors). The team is asked for explicitly, so
//! a one-core machine tests it too.

mod common;
use common::scene_file;

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
}
