//! The one-point hexahedron with physical hourglass stabilisation (`scheme.integration =
//! "reduced_physical"`, model §1.12): the nearly incompressible cantilever against
//! Euler–Bernoulli with no coefficient set, the leapfrog invariant with its hourglass energy,
//! and the pull-off against G_c·A with its ledger closing to second order in h.

use crate::common::*;
use crate::fbar::cantilever_within_euler_bernoulli;
use crate::reduced::free_vibration_drift;
use crate::validation::{record, Tol};
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::model::Integration;
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;

/// The cantilever of `incompressible_beam` (0.5 m × 0.1 m × 0.1 m, 20×2×2, clamped at x = 0,
/// under its weight) at ν = 0.499 (K/G = 500) and 0.4999 (K/G = 5000), the hourglass stiffness
/// the element's own (no κ): the static tip sag within 5 % of Euler–Bernoulli's qL⁴/(8EI).
///
/// Why 5 %: as for F-bar (`fbar::fbar_cantilever_does_not_lock_near_incompressibility`), the
/// shear deflection qL²/(2κGA) adds +4.8 % at ν → 0.5 and the two-element depth is stiffer than
/// the continuum; locking, or the κ(λ + 2μ) of §1.6 at its default, is a factor 2 or more.
#[test]
fn physical_cantilever_does_not_lock_near_incompressibility() {
    cantilever_within_euler_bernoulli("reduced_physical", "physical_cantilever");
}

/// The leapfrog invariant K + Ψ + Ψ_hg is conserved with the physical stabilisation as with
/// §1.6's (free vibration at strain 1e-10, where the system is linear to 1e-10, of a field
/// with hourglass content): within 1e-9. Saint-Venant–Kirchhoff at ν = 0.499: its ψ is formed
/// from E = ½(H + Hᵀ + HᵀH) without cancellation, where the neo-Hookean ψ at strain 1e-10 is a
/// difference of terms 10¹⁰ times larger (its round-off alone is 10³ times the energy).
#[test]
fn free_vibration_conserves_energy_with_physical_stabilisation() {
    let worst = free_vibration_drift(
        Integration::ReducedPhysical,
        Material::new(MaterialModel::Svk, 5e6, 0.499, 1100.0),
    );
    assert!(worst < 1e-9, "K + Ψ + Ψ_hg drifted by {worst:e}");
}

/// The pull-off with the physical stabilisation: every node ruptures, the damage dissipation
/// is G_c·A within [−2 %, +8 %] (the time-continuous value exactly, plus the scheme's O(h)
/// excess; the bounds and G_c = 7000/3 J/m² are derived in
/// `reduced::pull_off_with_one_point_integration`), and the ledger, with its non-linear
/// hourglass energy, closes to second order: halving the step factor cuts the largest residual
/// by ≥ 3 (order ≥ 1.58; a first-order leak gives 2).
#[test]
fn pull_off_with_physical_stabilisation() {
    let run = |factor: f64| {
        let set = vec![
            "scheme.integration=\"reduced_physical\"".to_string(),
            format!("scheme.time_step_factor={factor}"),
        ];
        let scene = load_scene(&scene_file("pull_off.toml"), &set).unwrap();
        let mut sim = Simulation::new(scene.model).unwrap();
        sim.run(|_| true).unwrap();
        sim
    };
    let sim = run(0.5);
    assert_eq!(sim.state_counts().ruptured, 64);
    let d = sim.state.ledger.damage_dissipated;
    let gc_area = 7000.0 / 3.0;
    let excess = d / gc_area - 1.0;
    record(
        "physical_pull_off",
        "damage dissipation over G_c·A",
        1.0,
        "G_c·A (time-continuous limit)",
        d / gc_area,
        Tol::Between(0.98, 1.08),
    );
    assert!(
        (-0.02..=0.08).contains(&excess),
        "D = {d} J is {:+.2} % of G_c·A",
        100.0 * excess
    );
    let r = [
        sim.state.ledger.max_relative_residual,
        run(0.25).state.ledger.max_relative_residual,
        run(0.125).state.ledger.max_relative_residual,
    ];
    eprintln!("physical pull-off: D = {:+.2} % of G_c·A; ledger residual at h/h_crit = 0.5, 0.25, 0.125: {r:?}", 100.0 * excess);
    assert!(
        r[0] / r[1] >= 3.0 && r[1] / r[2] >= 3.0,
        "residual at factor 0.5, 0.25, 0.125: {r:?}"
    );
}
