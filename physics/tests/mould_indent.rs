//! A curved mould (model §7): `scenes/indent.toml`, a rigid sphere pressed into a glued rubber pad
//! and lifted — Hertz on loading, the ledger closing with the sphere's work.

use crate::common::*;
use crate::hertz;
use crate::validation::{record, Tol};
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;

/// Runs the indentation; returns (δ, F) on loading and on unloading (full pad: 4 × the quarter)
/// and the simulation at the end.
/// (δ [m], F [N]) samples.
type Curve = Vec<(f64, f64)>;

fn indent() -> (Curve, Curve, Simulation) {
    let scene = load_scene(&scene_file("indent.toml"), &[]).unwrap();
    let mut sim = Simulation::new(scene.model).unwrap();
    let (mut load, mut unload) = (vec![], vec![]);
    sim.run(|s| {
        let ball = &s.model.moulds[1];
        let delta = -ball.displacement(s.state.time)[2];
        let f: f64 = (s.state.contact_nodes.iter())
            .map(|c| c.contact_impulse[2] * c.area)
            .sum::<f64>()
            / s.state.h;
        let row = (delta, -4.0 * f);
        if s.state.time < 0.1 {
            load.push(row);
        } else {
            unload.push(row);
        }
        true
    })
    .unwrap();
    (load, unload, sim)
}

/// Hertz on loading, F = (4/3)E*√R δ^{3/2}, E* = E/(1 − ν²) (rigid sphere), for
/// δ ∈ [0.25, 0.95] mm (a = √(Rδ) from 2Δx to 3.9Δx, 5 to 9.7 mm), within
/// tol(δ) = q(δ) + a/H + 1 %:
/// - q(δ), the node-based contact's quadrature error of the Hertz pressure on this grid
///   (`hertz::quadrature_error`, 0.5–4 % here);
/// - a/H (0.06–0.12), a bound on the finite pad: Hertz is the half-space limit and a layer of
///   thickness H bonded to a rigid base is stiffer by a relative amount of order a/H, while
///   its free sides at 4a make it softer by less (the pad's full width is 8a ≥ 8 × the
///   contact radius, so that the half-space assumption holds to a few %);
/// - 1 % for the dynamics: the load takes 45 wave crossings of the pad (kinetic energy
///   ≤ 1e-3 of the work), and the large-strain neo-Hookean body against linear Hertz at
///   δ/a ≤ 0.1.
///
/// Unloading: the sphere's work over the cycle (the ledger's mould work) is the area between
/// the loading and unloading curves, ∮F dδ from the samples (trapezoid), to 5 % of the work
/// in, and it is what the pad keeps (kinetic + strain + stored) plus what contact dissipated:
/// the ledger closes to 1e-9 of the largest energy.
#[test]
fn hertz_on_loading_and_the_work_of_the_cycle() {
    let (load, unload, sim) = indent();
    hertz::check_loading("hertz_indent", &load);
    // The cycle: ∮F dδ by the trapezoid over load then unload.
    let cycle: Vec<(f64, f64)> = load.iter().chain(&unload).copied().collect();
    let loop_area: f64 = cycle
        .windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum();
    let work_in: f64 = load
        .windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum();
    let works = sim.mould_works();
    assert_eq!(works[1].0, "ball");
    let ball = 4.0 * works[1].1;
    record(
        "hertz_indent",
        "loop area ∮F dδ [J] (tolerance 5 % of the work in)",
        ball,
        "the sphere's work (energy ledger)",
        loop_area,
        Tol::Abs(0.05 * work_in),
    );
    assert!(
        (ball - loop_area).abs() <= 0.05 * work_in,
        "mould work {ball:e} J, loop {loop_area:e} J, in {work_in:e} J"
    );
    let en = sim.energies();
    let kept = en.kinetic + en.strain + en.interface_stored + en.contact_normal_dissipated;
    assert!(
        (4.0 * kept - ball).abs() <= 1e-9 * 4.0 * work_in,
        "kept {kept:e} vs work {:e}",
        ball / 4.0
    );
    record(
        "ledger_indent",
        "relative residual of the energy balance at the end",
        0.0,
        "energy balance (model §5.10)",
        en.relative_residual,
        Tol::Abs(1e-9),
    );
    assert!(
        en.relative_residual.abs() <= 1e-9,
        "{}",
        en.relative_residual
    );
    assert!(
        ball > 0.0 && ball < 0.05 * work_in,
        "hysteresis {ball:e} J of {work_in:e} J"
    );
}
