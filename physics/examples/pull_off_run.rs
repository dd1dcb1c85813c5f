//! The pull-off run (model §9) with the physics crate alone: what `decohesion run
//! scenes/pull_off.toml --set mesh.cells=[N,N,N] --summary` measures, without building the root
//! package (Rerun, egui). It parses `scenes/pull_off.toml` with the cells overridden the way
//! `--set` does, runs to the end on the global rayon pool (2 threads on the 2-core machine,
//! `RAYON_NUM_THREADS` to change it) and prints the steps, the h_crit estimates, their Lanczos
//! iterations, the stage times of `Simulation::stats.stage_times` (the summary's
//! `stage_seconds`), h_crit's share of the steps' time, and the physics the goldens guard
//! (D, rupture time, residual), so that a change of the estimates can be checked not to move
//! them.
//!
//! ```sh
//! cargo run --release -p decohesion-physics --example pull_off_run -- [CELLS] [SET ...]
//! # default 28; extra arguments are further --set overrides, e.g. scheme.time_step_factor=0.9
//! ```
//!
//! Wall-clock figures: on a shared machine say so ("loaded") and quote the load average.

use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;
use std::path::Path;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let cells: usize = args
        .next()
        .map(|a| a.parse().expect("CELLS: a positive integer"))
        .unwrap_or(28);
    let mut set = vec![format!("mesh.cells=[{cells},{cells},{cells}]")];
    set.extend(args);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/pull_off.toml");
    let scene = load_scene(&path, &set).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let elements = scene.model.mesh.elements.len();
    let t0 = Instant::now();
    let mut sim = Simulation::new(scene.model).unwrap_or_else(|e| panic!("{e}"));
    let setup = t0.elapsed().as_secs_f64();
    sim.run(|_| true).unwrap_or_else(|e| panic!("{e}"));
    let wall = t0.elapsed().as_secs_f64();
    let s = &sim.stats.clone();
    let st = &s.stage_times.clone();
    let steps_wall = s.steps_wall.as_secs_f64();
    println!(
        "pull_off {cells}³ ({elements} elements, {} threads), set {set:?}",
        rayon::current_num_threads()
    );
    println!(
        "steps {}  h {:.4e} … {:.4e} s ({} changes)  h_crit initial {:.4e} min {:.4e} s",
        sim.state.step_count, s.h_min, s.h_max, s.step_changes, s.h_crit_initial, s.h_crit_min
    );
    println!(
        "estimates {}  Lanczos iterations {}  certified by the element bound {}",
        s.h_crit_estimates, s.h_crit_estimate_iterations, s.h_crit_certified
    );
    println!(
        "wall {wall:.3} s (setup {setup:.3} s, steps {steps_wall:.3} s)  {:.1} ns per element-step",
        1e9 * steps_wall / (sim.state.step_count as f64 * elements as f64)
    );
    println!(
        "stage_seconds: positions {:.3}  internal_forces {:.3}  h_crit {:.3}  free_velocity {:.3}  interface_contact {:.3}  bookkeeping {:.3}",
        st.positions,
        st.internal_forces,
        st.h_crit,
        st.free_velocity,
        st.interface_contact,
        st.bookkeeping
    );
    let per_assembly = st.internal_forces / sim.state.step_count as f64;
    println!(
        "h_crit share {:.2} % of the steps' time; {:.2} assemblies per Lanczos iteration",
        100.0 * st.h_crit / steps_wall,
        st.h_crit / (per_assembly * s.h_crit_estimate_iterations.max(1) as f64)
    );
    let t = Instant::now();
    let mut bound = 0.0;
    for _ in 0..10 {
        bound = sim.stiffness_bound();
    }
    let bound_seconds = t.elapsed().as_secs_f64() / 10.0;
    let conv = sim.converged_stable_step();
    println!(
        "element bound at the end: {:.3} ms = {:.2} assemblies; ω_b² / θ_converged = {:.3}",
        1e3 * bound_seconds,
        bound_seconds / per_assembly,
        bound / conv.ritz_value
    );
    println!(
        "D {:.6} J  full rupture {:?} s  max relative residual {:.3e}",
        sim.state.ledger.damage_dissipated,
        s.time_full_rupture,
        sim.state.ledger.max_relative_residual
    );
}
