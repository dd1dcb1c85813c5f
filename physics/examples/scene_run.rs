//! Runs any scene file to its end with the physics crate alone (no Rerun, no explorer: a
//! quick measure of a scene's cost before it is made a golden one) and prints its steps, wall
//! time, glued entries ruptured, damage dissipation and the ledger's largest relative residual.
//!
//! ```sh
//! cargo run --release -p decohesion-physics --example scene_run -- SCENE.toml [SET ...]
//! ```
//!
//! Wall-clock figures: on a shared machine say so ("loaded") and quote the load average.

use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;
use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().expect("usage: scene_run SCENE.toml [SET ...]"));
    let set: Vec<String> = args.collect();
    let scene = load_scene(&path, &set).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (hexes, tets) = (scene.model.mesh.elements.len(), scene.model.mesh.tets.len());
    let t0 = Instant::now();
    let mut sim = Simulation::new(scene.model).unwrap_or_else(|e| panic!("{e}"));
    for w in sim.advisories() {
        println!("advisory: {w}");
    }
    let outcome = sim.run(|_| true);
    let counts = sim.state_counts();
    let ledger = &sim.state.ledger;
    println!(
        "{}: {hexes} hexahedra, {tets} tetrahedra; {} steps of h = {:.3e} s in {:.1} s; \
         ruptured {} of {} glued entries; D = {:.4e} J; max relative residual {:.2e}; {:?}",
        path.display(),
        sim.state.step_count,
        sim.state.h,
        t0.elapsed().as_secs_f64(),
        counts.ruptured,
        sim.state.interface_nodes.len(),
        ledger.damage_dissipated,
        ledger.max_relative_residual,
        outcome.err()
    );
}
