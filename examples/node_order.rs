//! How much the node numbering matters to the step: the pull-off physics on a 28³ box with its
//! nodes in the box's natural order, randomly permuted (elements unchanged), and permuted then
//! renumbered by `Mesh::with_nodes_in_slabs` (what the Gmsh reader does); one-point and full
//! integration, ns per element-step (median of 5 × 200 steps, interleaved).
//!
//! ```sh
//! cargo run --release --example node_order
//! ```

use decohesion::scene::load_scene;
use decohesion::solver::Simulation;
use std::time::Instant;

fn main() {
    let n = 28;
    for rule in ["reduced", "full"] {
        let set = vec![
            format!("mesh.cells=[{n},{n},{n}]"),
            "scheme.h_crit_update_interval=0".into(),
            format!("scheme.integration=\"{rule}\""),
        ];
        let scene = load_scene("scenes/pull_off.toml".as_ref(), &set).unwrap();
        // A fixed pseudo-random permutation (64-bit LCG, Fisher–Yates).
        let count = scene.model.mesh.nodes.len();
        let mut p: Vec<u32> = (0..count as u32).collect();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for i in (1..count).rev() {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            p.swap(i, (state >> 33) as usize % (i + 1));
        }
        let mut shuffled = (*scene.model).clone();
        shuffled.mesh = scene.model.mesh.renumbered(&p);
        let mut resorted = shuffled.clone();
        resorted.mesh = resorted.mesh.with_nodes_in_slabs();
        let mut sims = [
            ("natural", Simulation::new(scene.model.clone()).unwrap()),
            ("random", Simulation::new(shuffled).unwrap()),
            ("random, then in slabs", Simulation::new(resorted).unwrap()),
        ];
        let mut ns = [vec![], vec![], vec![]];
        for _ in 0..5 {
            for (k, (_, sim)) in sims.iter_mut().enumerate() {
                let t = Instant::now();
                for _ in 0..200 {
                    sim.step().unwrap();
                }
                let e = sim.model.mesh.elements.len() as f64;
                ns[k].push(t.elapsed().as_secs_f64() * 1e9 / (200.0 * e));
            }
        }
        for (k, (name, sim)) in sims.iter().enumerate() {
            ns[k].sort_by(f64::total_cmp);
            println!(
                "{rule:>8} {name:>22} node order: {:.1} ns/element-step (runs {:.1}–{:.1}); dissipation {:.6e} J",
                ns[k][2],
                ns[k][0],
                ns[k][4],
                sim.state.ledger.damage_dissipated
            );
        }
    }
}
