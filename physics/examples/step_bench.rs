//! The whole step and its stages per element-step on the n³ pull-off, built as
//! `decohesion bench` builds it (`scenes/pull_off.toml`, `mesh.cells = [n, n, n]`, no h_crit
//! re-estimates, the interface on), but from the physics crate alone, so that a kernel change
//! can be measured without building the root package (docs: performance log).
//!
//! ```sh
//! cargo run --release -p decohesion-physics --example step_bench -- [N] [STEPS] [REPEATS] [RULE] [SKIP]
//! # defaults 28 200 7 reduced 0: RULE is reduced or full; SKIP steps run first, untimed
//! ```
//!
//! One simulation per thread count (2 and 1), stepped round-robin: a repetition is STEPS steps
//! on each, so a burst of load on the shared machine lands in one repetition of both (the
//! medians see it as an outlier). Prints the medians over REPEATS of ns per element-step of the
//! whole step and of each stage ([`decohesion_physics::solver::StageTimes`]), and the share of
//! the one-point lane groups whose exact corner check the cheap bound let skip (model
//! §1.9, [`decohesion_physics::kernels::corner_bound`]). Wall-clock figures: on a shared machine
//! say "loaded" and quote the load average next to them. `DECOHESION_ISA=avx2|avx512|portable`
//! forces a build of the kernels.

use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::{Simulation, StageTimes};
use decohesion_physics::timing::median;
use std::path::Path;
use std::time::Instant;

/// The stage times as (name, seconds) pairs.
fn stages(s: &StageTimes) -> [(&'static str, f64); 6] {
    [
        ("positions", s.positions),
        ("elements", s.internal_forces),
        ("h_crit", s.h_crit),
        ("free_vel", s.free_velocity),
        ("boundary", s.interface_contact),
        ("bookkeep", s.bookkeeping),
    ]
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: &str| args.get(i).cloned().unwrap_or_else(|| d.to_string());
    let n: usize = arg(0, "28").parse().expect("N: cells per side");
    let steps: usize = arg(1, "200").parse().expect("STEPS");
    let repeats: usize = arg(2, "7").parse().expect("REPEATS");
    let rule = arg(3, "reduced");
    let skip: usize = arg(4, "0").parse().expect("SKIP");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/pull_off.toml");
    let set = vec![
        format!("mesh.cells=[{n},{n},{n}]"),
        "scheme.h_crit_update_interval=0".into(),
        format!("scheme.integration=\"{rule}\""),
    ];
    let threads = [2usize, 1];
    let mut sims: Vec<Simulation> = threads
        .iter()
        .map(|&t| {
            let scene = load_scene(&scene, &set).unwrap_or_else(|e| panic!("{e}"));
            let mut sim = Simulation::new(scene.model).unwrap_or_else(|e| panic!("{e}"));
            sim.use_threads(t);
            for _ in 0..skip {
                sim.step().unwrap_or_else(|e| panic!("{e}"));
            }
            sim
        })
        .collect();
    let elements = sims[0].model.mesh.elements.len() as f64;
    let mut whole = vec![Vec::new(); threads.len()];
    let mut per_stage = vec![vec![Vec::new(); 6]; threads.len()];
    for _ in 0..repeats {
        for (k, sim) in sims.iter_mut().enumerate() {
            let before = stages(&sim.stats.stage_times);
            let t = Instant::now();
            for _ in 0..steps {
                sim.step().unwrap_or_else(|e| panic!("{e}"));
            }
            let dt = t.elapsed().as_secs_f64();
            let per = 1e9 / (steps as f64 * elements);
            whole[k].push(dt * per);
            for (s, (b, a)) in before
                .iter()
                .zip(stages(&sim.stats.stage_times))
                .enumerate()
            {
                per_stage[k][s].push((a.1 - b.1) * per);
            }
        }
    }
    println!(
        "step_bench: {n}³ pull-off ({rule}), {elements} elements, {steps} steps × {repeats} repetitions, ISA {}",
        std::env::var("DECOHESION_ISA").unwrap_or_else(|_| "auto".into())
    );
    print!("{:>8} {:>8}", "threads", "step");
    for (name, _) in stages(&StageTimes::default()) {
        print!(" {name:>9}");
    }
    println!("   (ns per element-step, medians)");
    for (k, &t) in threads.iter().enumerate() {
        print!("{t:>8} {:>8.2}", median(&mut whole[k]));
        for stage in per_stage[k].iter_mut() {
            print!(" {:>9.2}", median(stage));
        }
        println!();
    }
    let c = &sims[0].stats.corner_checks;
    if c.groups > 0 {
        println!(
            "corner check skipped by the bound: {} of {} lane groups ({:.1} %)",
            c.skipped,
            c.groups,
            100.0 * c.skipped as f64 / c.groups as f64
        );
    }
}
