//! Glue that forms on contact (model §8), `scenes/indent_adhesive.toml` — Hertz on loading, a
//! tensile pull-off on lifting, and the hysteresis of the cycle as the glue's damage
//! dissipation.

use crate::common::*;
use crate::hertz;
use crate::validation::{self, record, Tol};
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;

/// (time [s], δ [m], F [N]) samples: F the sphere's force on the full pad (4 × the quarter),
/// compressive positive.
type Curve = Vec<(f64, f64, f64)>;

/// Runs the scene; the (t, δ, F) samples of every step and the simulation at the end. F is
/// read from the interface nodes (the face set's glue and contact entries): the contact
/// impulse W R_c and the glue's −h̄ W R_d, over h̄ = (h_{n+½} + h_{n+3/2})/2.
fn run() -> (Curve, Simulation) {
    let scene = load_scene(&scene_file("indent_adhesive.toml"), &[]).unwrap();
    let mut sim = Simulation::new(scene.model).unwrap();
    let mut h_prev = sim.state.h;
    let mut curve = vec![];
    sim.run(|s| {
        let h_bar = 0.5 * (h_prev + s.state.h);
        h_prev = s.state.h;
        let ball = &s.model.moulds[1];
        let delta = -ball.displacement(s.state.time)[2];
        let fz: f64 = (s.state.interface_nodes.iter())
            .filter(|n| s.model.interfaces[n.interface as usize].plane == 1)
            .map(|n| n.area * (n.contact_impulse[2] / h_bar - n.cohesive_traction[2]))
            .sum();
        curve.push((s.state.time, delta, -4.0 * fz));
        true
    })
    .unwrap();
    (curve, sim)
}

/// The glue that formed on the sphere (face set `z+`): (Σ W of the formed nodes, Σ W of the
/// ruptured ones) [m²] on the quarter.
fn glued_areas(sim: &Simulation) -> (f64, f64) {
    let (mut formed, mut ruptured) = (0.0, 0.0);
    for n in &sim.state.interface_nodes {
        let spec = &sim.model.interfaces[n.interface as usize];
        if spec.forms_on_contact.is_some() && n.formed {
            formed += n.area;
            if n.alpha >= spec.law.u_r {
                ruptured += n.area;
            }
        }
    }
    (formed, ruptured)
}

/// The glue forms on contact, and the cycle shows it:
/// (a) loading (t < 0.1 s) follows Hertz to the tolerance of `indent.toml`'s test
///     ([`hertz::check_loading`]): the glue forms only inside the contact, where it holds the
///     surface to the sphere tangentially (a stuck contact instead of a frictionless one,
///     which at ν = 0.3 changes the Hertz force by well under the 1 % left for it) and pulls
///     nothing outside, so no adhesive (JKR) lowering of the load;
/// (b) on lifting the force turns tensile, and its most negative value, the pull-off force,
///     lies between JKR's 1.5πRw and DMT's 2πRw, w = G_c: Maugis' limits of a rigid sphere on
///     an elastic half-space, for any Tabor/Maugis parameter (here λ = 0.75). They hold for
///     this mesh and pad: the glue formed over the Hertz contact (a_max = 9.6 mm), wider than
///     JKR's contact radius at pull-off a_c = (9πwR²/8E*)^{1/3} = 6.9 mm, so the peeling front
///     crosses glued ground as in the theory; the pad is 80 mm thick and 80 mm wide (a_c/H =
///     0.09: the half-space limit to order 10 % of the force, less than the band's width of
///     29 %); the cohesive zone (≈ 6 mm) spans two elements, so the peel is not governed by
///     one node's strength;
/// (c) hysteresis: the loop's work ∮F dδ (trapezoid over the samples) is the sphere's work of
///     the ledger to 1 % (sampling), all of it the glue's damage dissipation D but what the
///     pad keeps ringing and contact dissipated (≤ 2 % of D, ledger to 1e-9); and
///     D = G_c × the torn area: every formed node tore, each dissipating G_c W (1 %: the
///     damage increments' O(h) quadrature), and that area is the Hertz contact area π a²/4 of
///     the quarter at δ_max within the mesh's area quantisation: the tributary squares of the
///     nodes (half-diagonal Δx/√2) differ from the quarter disc only within Δx/√2 of its arc,
///     a quarter annulus of area π a Δx/√2;
/// (d) the ledger closes to 1e-9 of the largest energy, as every scene.
#[test]
fn hertz_loading_adhesive_pull_off_and_the_glue_s_hysteresis() {
    let (curve, sim) = run();
    let model = &sim.model;
    let spec = (model.interfaces.iter())
        .find(|i| i.forms_on_contact.is_some())
        .unwrap();
    let (w, r, dx) = (spec.law.fracture_energy(), 0.1f64, 2.5e-3f64);
    assert!((w - 10.0).abs() < 1e-9, "G_c = {w}");
    // (a)
    let load: Vec<(f64, f64)> = (curve.iter())
        .filter(|p| p.0 < 0.1)
        .map(|p| (p.1, p.2))
        .collect();
    hertz::check_loading("hertz_adhesive", &load);
    // (b)
    let pi = std::f64::consts::PI;
    let pull_off = -curve.iter().map(|p| p.2).fold(f64::INFINITY, f64::min);
    let (jkr, dmt) = (1.5 * pi * r * w, 2.0 * pi * r * w);
    let deltas: Vec<f64> = curve.iter().map(|p| 1e3 * p.1).collect();
    let e_star = 1e6 / (1.0 - 0.3 * 0.3);
    validation::curve(
        "hertz_adhesive",
        "cycle",
        &deltas,
        &curve.iter().map(|p| p.2).collect::<Vec<_>>(),
        &curve
            .iter()
            .map(|p| {
                if p.0 < 0.1 {
                    4.0 / 3.0 * e_star * r.sqrt() * p.1.max(0.0).powf(1.5)
                } else {
                    f64::NAN
                }
            })
            .collect::<Vec<_>>(),
        "indentation δ [mm]",
        "force F [N] (Hertz on loading)",
    );
    record(
        "hertz_adhesive",
        "pull-off force [N] (reference: the band's middle, 1.75πRw)",
        0.5 * (jkr + dmt),
        "JKR 1971 (1.5πRw) / DMT 1975 (2πRw), Maugis 1992",
        pull_off,
        Tol::Between(jkr, dmt),
    );
    assert!(
        pull_off >= jkr && pull_off <= dmt,
        "pull-off {pull_off:.4} N outside [{jkr:.4}, {dmt:.4}] N"
    );
    // (c)
    let loop_work: f64 = (curve.windows(2))
        .map(|q| 0.5 * (q[0].2 + q[1].2) * (q[1].1 - q[0].1))
        .sum();
    let ball = 4.0 * sim.mould_works()[1].1;
    assert!(
        (loop_work - ball).abs() <= 0.01 * ball,
        "loop {loop_work:e} J, sphere's work {ball:e} J"
    );
    let en = sim.energies();
    let d = 4.0 * en.damage_dissipated;
    let rest = 4.0 * (en.kinetic + en.strain + en.interface_stored + en.contact_normal_dissipated);
    assert!(rest <= 0.02 * d, "kept and contact {rest:e} J, D {d:e} J");
    assert!(
        (ball - d - rest).abs() <= 1e-9 * ball,
        "sphere {ball:e} J = D {d:e} J + {rest:e} J"
    );
    let (formed, ruptured) = glued_areas(&sim);
    assert!(
        formed > 0.0 && ruptured == formed,
        "formed {formed:e}, torn {ruptured:e} m²"
    );
    let d_quarter = en.damage_dissipated;
    record(
        "hertz_adhesive",
        "damage dissipation on the quarter [J]",
        w * ruptured,
        "G_c × the torn area",
        d_quarter,
        Tol::Rel(0.01),
    );
    assert!(
        (d_quarter - w * ruptured).abs() <= 0.01 * d_quarter,
        "D {d_quarter:e} J, G_c × torn area {:e} J",
        w * ruptured
    );
    let delta_max = curve.iter().map(|p| p.1).fold(0.0, f64::max);
    let a = (r * delta_max).sqrt();
    let hertz_area = pi * a * a / 4.0;
    record(
        "hertz_adhesive",
        "torn area on the quarter [m²]",
        hertz_area,
        "Hertz 1882 (contact area πRδ_max, quarter)",
        ruptured,
        Tol::Abs(pi * a * dx / 2f64.sqrt()),
    );
    assert!(
        (ruptured - hertz_area).abs() <= pi * a * dx / 2f64.sqrt(),
        "torn {ruptured:e} m², Hertz contact {hertz_area:e} m²"
    );
    // (d)
    assert!(
        en.relative_residual.abs() <= 1e-9,
        "{}",
        en.relative_residual
    );
}
