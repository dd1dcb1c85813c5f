//! The nearly incompressible cantilever of `scenes/extreme/incompressible_beam.toml` (0.5 m ×
//! 0.1 m × 0.1 m, clamped at x = 0, under its weight) on Kuhn-cut boxes of 10n × n × n cells
//! (60n³ tetrahedra, model §1.13), an isochoric neo-Hookean rubber of the scene's E at
//! Poisson's ratio ν (μ₀ = E/(2(1 + ν)), K = E/(3(1 − 2ν)), U = ½K(J − 1)²), relaxed to its
//! static state by kinetic damping (Cundall: every velocity zeroed when the kinetic energy has
//! passed a peak), as `physics/tests/tets.rs` does. Prints the tip sag over Euler–Bernoulli's
//! qL⁴/(8EI), the kinetic energy at the last peak over the strain energy (the relaxation's
//! residue), the steps and the wall time: the measurements of the roadmap's "Rubber (issue
//! 39)" and the performance log.
//!
//! ```sh
//! cargo run --release -p decohesion-physics --example tet_cantilever -- [N] [NU] [END_TIME]
//! # defaults 2, 0.499, 0.5
//! ```
//!
//! `N = bits` instead steps the 20 × 2 × 2 cut beam at ν = 0.499 300 times without relaxation
//! and prints a digest of the displacement bits and the strain energy: a refactoring of the
//! tetrahedra's kernel that must not move bits is checked by the same digest before and after.

use decohesion_physics::material::rubber::{
    neo_hookean::NeoHookean, Isochoric, Rubber, Volumetric,
};
use decohesion_physics::material::Material;
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;
use std::path::Path;
use std::time::Instant;

fn rubber(e: f64, nu: f64, density: f64) -> Material {
    let mu = e / (2.0 * (1.0 + nu));
    Material::rubber(
        Rubber {
            iso: Isochoric::NeoHookean(NeoHookean { c10: 0.5 * mu }),
            bulk: e / (3.0 * (1.0 - 2.0 * nu)),
            volumetric: Volumetric::Quadratic,
        },
        density,
    )
}

fn beam(n: usize, nu: f64, end_time: f64) -> Simulation {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/extreme/incompressible_beam.toml");
    let set = vec![
        format!("end_time={end_time}"),
        format!("mesh.cells=[{},{n},{n}]", 10 * n),
    ];
    let scene = load_scene(&path, &set).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut m = (*scene.model).clone();
    m.mesh = m.mesh.kuhn_tets();
    m.material = rubber(m.material.young, nu, m.material.density);
    Simulation::new(m).unwrap_or_else(|e| panic!("{e}"))
}

fn main() {
    let mut args = std::env::args().skip(1);
    let first = args.next().unwrap_or_else(|| "2".into());
    if first == "bits" {
        let mut sim = beam(2, 0.499, 0.5);
        let mut digest = 0u64;
        for _ in 0..300 {
            sim.step().unwrap();
        }
        for p in sim.state.u.planes() {
            for x in p {
                digest = digest.rotate_left(5) ^ x.to_bits();
            }
        }
        println!(
            "digest {digest:016x}, strain energy {:e}",
            sim.energies().strain
        );
        return;
    }
    let n: usize = first.parse().expect("N: a positive integer");
    let nu: f64 = args
        .next()
        .map_or(0.499, |a| a.parse().expect("NU: a number"));
    let end: f64 = args
        .next()
        .map_or(0.5, |a| a.parse().expect("END_TIME: seconds"));
    let t0 = Instant::now();
    let mut sim = beam(n, nu, end);
    let tip: Vec<usize> = (sim
        .model
        .mesh
        .face_set_nodes(&sim.model.mesh.face_sets["x+"]))
    .iter()
    .map(|&i| i as usize)
    .collect();
    let (mut last, mut share) = (0.0, f64::INFINITY);
    while !sim.finished() {
        sim.step().unwrap();
        let e = sim.energies();
        if e.kinetic < last {
            share = last / e.strain;
            for p in sim.state.v.planes_mut() {
                p.fill(0.0);
            }
            last = 0.0;
        } else {
            last = e.kinetic;
        }
    }
    let s = -tip.iter().map(|&i| sim.state.u.get(i)[2]).sum::<f64>() / tip.len() as f64;
    let m = &sim.model.material;
    let (l, b) = (0.5f64, 0.1f64);
    let q = m.density * 9.81 * b * b;
    let delta = q * l.powi(4) / (8.0 * m.young * b.powi(4) / 12.0);
    println!(
        "n = {n}, ν = {nu}: sag {s:.6} m = {:.4} × Euler–Bernoulli {delta:.6} m; K/Ψ at the last peak {share:.1e}; {} steps, {:.1} s",
        s / delta,
        sim.state.step_count,
        t0.elapsed().as_secs_f64()
    );
}
