//! Bulk viscosity (model §4.12, §5.11): the damping it gives a mode against the damped
//! oscillator's logarithmic decrement, the ledger's dissipation, and the step it allows.

use crate::common::{damping_ratio, scene_file};
use decohesion_physics::scene::{load_scene, parse_scene};
use decohesion_physics::solver::Simulation;

/// One free unit cube (one hex8, SVK) with bulk viscosity b₁ = `linear` (b₂ = 0) at step
/// factor `factor`, set breathing: V₀ = ε̇₀ (X − X_c).
fn breathing_cube(linear: f64, factor: f64, rate: f64, end: f64) -> Simulation {
    let text = format!(
        r#"
end_time = {end:e}
[mesh]
size = [1.0, 1.0, 1.0]
cells = [1, 1, 1]
[material]
model = "svk"
young = 5.0e6
poisson = 0.3
density = 1000.0
[scheme]
time_step_factor = {factor}
h_crit_update_interval = 0
[bulk_viscosity]
linear = {linear}
quadratic = 0.0
"#
    );
    let scene = parse_scene(&text, "breathing_cube.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
    let nodes = scene.model.mesh.nodes.clone();
    let v0 = nodes.iter().map(|x| x.map(|c| rate * (c - 0.5))).collect();
    Simulation::with_initial_state(scene.model, vec![[0.0; 3]; nodes.len()], v0)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The breathing mode of a free cube element, x = ε (X − X_c), is an eigenmode of the stiffness
/// (uniform stress (3λ + 2μ)ε, nodal forces ∝ bₐ ∝ Xₐ − X_c) and of the viscous forces, so the
/// cube is one damped oscillator: ω² = 4(3λ + 2μ)/(ρa²) and, with q = ρ L b₁ c_d ε̇_v,
/// ε̇_v = 3ε̇, c_m = 12 L b₁ c_d/a² per unit mass. L = c_d h_e with h_e = 2/ω (the element
/// bound at rest is this mode, g = 4/(ρa²)), so ξ = c_m/(2ω) = b₁ (λ + 2μ)/K: 1.615 b₁ at
/// ν = 0.3. The logarithmic decrement of the displacement's successive maxima gives it back:
/// δ = ln(xₖ/xₖ₊₁) = 2πξ/√(1 − ξ²). 150 steps a period (factor 0.02) leave central
/// differences' O((ωh)²) errors at 2e-4 and the sampled maxima 2e-4 low; strains of 1e-7 keep
/// SVK linear to 1e-7: 1 % is far above both.
#[test]
fn a_breathing_cube_decays_with_the_damping_ratio_of_the_model() {
    let (young, nu, rho): (f64, f64, f64) = (5.0e6, 0.3, 1000.0);
    let lambda = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = young / (2.0 * (1.0 + nu));
    let k = lambda + 2.0 * mu / 3.0;
    let omega = (4.0 * 3.0 * k / rho).sqrt();
    let b1 = 0.02;
    let xi = b1 * (lambda + 2.0 * mu) / k;
    let period = 2.0 * std::f64::consts::PI / omega;
    let mut sim = breathing_cube(b1, 0.02, 1e-7 * omega, 4.0 * period);
    // The corner node at X = (1, 1, 1): its x displacement follows the mode.
    let corner = (sim.model.mesh.nodes.iter())
        .position(|x| *x == [1.0, 1.0, 1.0])
        .expect("a corner at (1, 1, 1)");
    let mut xs = vec![];
    while !sim.finished() {
        sim.step().unwrap();
        xs.push(sim.state.u.get(corner)[0]);
    }
    let measured = damping_ratio(&xs);
    assert!(
        (measured / xi - 1.0).abs() <= 0.01,
        "damping ratio {measured:.5}, model {xi:.5} (b₁ (λ + 2μ)/K)"
    );
    // The ledger: what left the cube is the viscous dissipation, and it closes.
    let e = sim.energies();
    assert!(e.bulk_viscous_dissipated > 0.0);
    assert!(
        sim.state.ledger.max_relative_residual <= 1e-4,
        "residual {:.2e}",
        sim.state.ledger.max_relative_residual
    );
}

/// At a step factor of 0.99 the undamped cube is stable, and a viscosity of ξ = 0.5 would make
/// it unstable at h = 0.99 h_crit ((√(1 + ξ²) − ξ) = 0.62): the step is capped by the damping,
/// so the run completes, decaying, with the ledger closed.
#[test]
fn the_step_is_shortened_by_the_damping_and_the_run_stays_stable() {
    let (young, nu): (f64, f64) = (5.0e6, 0.3);
    let lambda = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = young / (2.0 * (1.0 + nu));
    let k = lambda + 2.0 * mu / 3.0;
    let b1 = 0.5 * k / (lambda + 2.0 * mu);
    let omega = (4.0 * 3.0 * k / 1000.0).sqrt();
    let period = 2.0 * std::f64::consts::PI / omega;
    let mut sim = breathing_cube(b1, 0.99, 1e-7 * omega, 20.0 * period);
    let h_undamped = 0.99 * sim.state.h_crit;
    assert!(sim.state.h < 0.7 * h_undamped, "h {:.4e} s", sim.state.h);
    sim.run(|_| true).unwrap();
    let e = sim.energies();
    assert!(e.kinetic + e.strain < 1e-3 * e.bulk_viscous_dissipated);
    assert!(sim.state.ledger.max_relative_residual <= 1e-4);
}

/// The bar dropped on a plane (scenes/impact.toml) with Abaqus/Explicit's default bulk
/// viscosity: the impact's compression wave is damped, the viscosity dissipates, and the
/// ledger closes to the impact test's own bound (5e-5, model §5.10): the viscous impulses are
/// booked by the same trapezoid as every other force.
#[test]
fn the_ledger_closes_with_bulk_viscosity_in_an_impact() {
    let set = ["bulk_viscosity.linear=0.06".to_string()];
    let scene = load_scene(&scene_file("impact.toml"), &set).unwrap();
    let mut sim = Simulation::new(scene.model).unwrap();
    sim.run(|_| true).unwrap();
    let e = sim.energies();
    assert!(e.bulk_viscous_dissipated > 0.0);
    assert!(
        sim.state.ledger.max_relative_residual <= 5e-5,
        "max relative residual {:.3e}",
        sim.state.ledger.max_relative_residual
    );
}
