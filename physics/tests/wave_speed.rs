//! Wave speed: a velocity step imposed on one end of a bar must reach the other end after L/c,
//! with c = √(E/ρ) the bar speed (ν = 0, so the bar speed and the dilatational speed coincide
//! and free lateral faces change nothing).
//!
//! The discrete front is not sharp. The lumped-mass linear lattice integrated by central
//! differences has the dispersion relation sin(ωh/2) = r sin(kL_e/2), r = ch/L_e, i.e.
//! ω ≈ ck − βk³ with β = cL_e²(1 − r²)/24 for long waves. A velocity step then travels as
//! v(x, t) = V ∫_{(x−ct)/w}^∞ Ai(s) ds with the front width w = (3βt)^{1/3}
//! = (ct L_e²(1 − r²)/8)^{1/3}: 1.55 L_e after 40 elements at r = ½. Its mid-height,
//! ∫_z^∞ Ai = ½ at z = −0.4096, trails the characteristic x = ct by 0.41 w. That is the
//! test's yardstick: the arrival must be within one front width of L/c, and its lag must be the
//! predicted one.

use crate::common::bare_box;
use crate::validation::{curve, record, Tol};
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::model::{Model, PiecewiseLinear, PrescribedDisplacement};
use decohesion_physics::solver::Simulation;

const E: f64 = 2.0e11;
const RHO: f64 = 7800.0;
const LENGTH: f64 = 1.0;
const SIDE: f64 = 0.05;
/// Imposed velocity of the z- end [m/s]: strain v/c ≈ 2e-4, well inside the linear range.
const V_IMP: f64 = 1.0;
/// z such that ∫_z^∞ Ai(s) ds = ½ (computed once from the Maclaurin series of Ai).
const AIRY_HALF: f64 = -0.4096;

fn bar_model(cells: usize, end_time: f64) -> Model {
    let mat = Material::new(MaterialModel::Svk, E, 0.0, RHO);
    let mut m = bare_box([SIDE, SIDE, LENGTH], [1, 1, cells], mat, end_time);
    m.name = "wave_speed".into();
    m.description = "velocity step on the z- end of a free bar".into();
    // Ū(t) = V_IMP·t: a ramp starting at full speed, i.e. a velocity step at t = 0. The last
    // point lies beyond the end of the run (the history is constant past it).
    m.displacements.push(PrescribedDisplacement {
        faces: "z-".into(),
        component: 2,
        history: PiecewiseLinear {
            points: vec![(0.0, [0.0]), (10.0 * end_time, [10.0 * end_time * V_IMP])],
        },
    });
    m
}

struct Front {
    /// Time at which the mean z-velocity of the z+ nodes first exceeds V_IMP [s].
    arrival: f64,
    /// Largest |v_z| of the z+ nodes before 0.75 L/c [m/s].
    precursor: f64,
    /// Mean z-velocity of the z+ nodes, time-averaged over [1.2, 1.5] L/c [m/s].
    plateau: f64,
    /// Courant number r = c h / L_e.
    courant: f64,
    /// (t, mean z-velocity of the z+ nodes) at every half step [s, m/s].
    samples: Vec<(f64, f64)>,
}

fn run(cells: usize) -> Front {
    let c = (E / RHO).sqrt();
    let transit = LENGTH / c;
    let model = bar_model(cells, 1.5 * transit);
    let far: Vec<usize> = model
        .mesh
        .face_set_nodes(&model.mesh.face_sets["z+"])
        .iter()
        .map(|&n| n as usize)
        .collect();
    let mut sim = Simulation::new(model).expect("valid model");
    assert!(
        (sim.state.h / sim.state.h_crit - 0.5).abs() < 1e-12,
        "default factor 0.5"
    );
    let courant = c * sim.state.h / (LENGTH / cells as f64);

    let mean_vz =
        |s: &Simulation| far.iter().map(|&i| s.state.v.get(i)[2]).sum::<f64>() / far.len() as f64;
    // V_{n+½} lives at tₙ + h/2.
    let mut prev = (sim.state.time + 0.5 * sim.state.h, mean_vz(&sim));
    let mut arrival = None;
    let mut samples = vec![prev];
    let mut precursor = 0.0f64;
    let (mut plateau_sum, mut plateau_time) = (0.0, 0.0);
    while !sim.finished() {
        sim.step().expect("stable run");
        let cur = (sim.state.time + 0.5 * sim.state.h, mean_vz(&sim));
        samples.push(cur);
        if cur.0 < 0.75 * transit {
            precursor = precursor.max(cur.1.abs());
        }
        if cur.0 > 1.2 * transit {
            plateau_sum += cur.1 * (cur.0 - prev.0);
            plateau_time += cur.0 - prev.0;
        }
        if arrival.is_none() && cur.1 > V_IMP {
            // The free end doubles the incident velocity: crossing V_IMP is the passage of the
            // front's mid-height. Linear interpolation between the two half-step samples.
            let s = (V_IMP - prev.1) / (cur.1 - prev.1);
            arrival = Some(prev.0 + s * (cur.0 - prev.0));
        }
        prev = cur;
    }
    Front {
        arrival: arrival.expect("the front never reached the free end"),
        precursor,
        plateau: plateau_sum / plateau_time,
        courant,
        samples,
    }
}

#[test]
fn velocity_front_reaches_the_free_end_after_l_over_c() {
    let c = (E / RHO).sqrt();
    let transit = LENGTH / c;
    let mut lags = vec![];
    for cells in [40, 80] {
        let f = run(cells);
        let element_transit = transit / cells as f64;
        let lag = f.arrival - transit;
        // Front width (in element transits) and predicted mid-height lag, see the header.
        let width = (cells as f64 * (1.0 - f.courant * f.courant) / 8.0).cbrt();
        let predicted = -AIRY_HALF * width;
        eprintln!(
            "{cells} cells: L/c = {transit:.6e} s, arrival = {:.6e} s, lag = {:.3} L_e/c \
             ({:.3} %), predicted lag = {predicted:.3} L_e/c, front width = {width:.3} L_e, \
             r = {:.3}, precursor = {:.3e} m/s, plateau = {:.5} m/s",
            f.arrival,
            lag / element_transit,
            100.0 * lag / transit,
            f.courant,
            f.precursor,
            f.plateau
        );
        let case = format!("wave_speed_{cells}");
        let ts: Vec<f64> = f.samples.iter().map(|s| s.0 / transit).collect();
        curve(
            &case,
            "free end",
            &ts,
            &f.samples.iter().map(|s| s.1).collect::<Vec<_>>(),
            &ts.iter()
                .map(|&t| if t < 1.0 { 0.0 } else { 2.0 * V_IMP })
                .collect::<Vec<_>>(),
            "t / (L/c)",
            "velocity of the free end [m/s]",
        );
        record(
            &case,
            "arrival of the front at the free end [s]",
            transit,
            "analytic (1-D wave, L/c, c = √(E/ρ))",
            f.arrival,
            Tol::Abs(width * element_transit),
        );
        record(
            &case,
            "lag of the front's mid-height [L_e/c]",
            predicted,
            "analytic (lattice dispersion, Airy front)",
            lag / element_transit,
            Tol::Abs(0.2),
        );
        record(
            &case,
            "free-end velocity after reflection [m/s]",
            2.0 * V_IMP,
            "analytic (free end: 2V)",
            f.plateau,
            Tol::Abs(0.02 * 2.0 * V_IMP),
        );
        // The arrival is within one front width of L/c (2.4 % of L/c at 40 cells, 1.5 % at
        // 80). A wrong modulus would not pass: the confined speed √((λ+2μ)/ρ) at ν = 0.3
        // is 16 % faster, a lumped-mass error of a factor 2 is 41 % off.
        assert!(
            lag.abs() <= width * element_transit,
            "{cells} cells: arrival {:.6e} s vs L/c = {transit:.6e} s: off by {:.2} element \
             transits, more than the front width {width:.2}",
            f.arrival,
            lag / element_transit
        );
        // The lag is the lattice dispersion's: the prediction neglects O((kL_e)⁴) terms and the
        // end node's reflection, and V is sampled at half steps (h = L_e/(2c) here, a time
        // resolution of ±0.25 L_e/c before interpolation): agreement within 0.2 L_e/c.
        assert!(
            (lag / element_transit - predicted).abs() <= 0.2,
            "{cells} cells: lag {:.3} L_e/c, lattice dispersion predicts {predicted:.3}",
            lag / element_transit
        );
        // Causality: 0.25 L/c before the arrival the front is ≥ 10 L_e away, ≥ 6 front widths;
        // the Airy tail there is below exp(−⅔·6^{3/2}) ≈ 6e-5 of the step.
        assert!(
            f.precursor <= 1e-4 * V_IMP,
            "{cells} cells: the far end moved at {:.3e} m/s before the front could arrive",
            f.precursor
        );
        // A free end reflects the step with the same sign: the end moves at 2 V_IMP. The
        // time average over 0.3 L/c smooths the Gibbs ringing behind the front (its amplitude
        // decays like the Airy tail, ~1/z^{3/4}); 2 % of 2 V_IMP allows the residual ringing.
        assert!(
            (f.plateau - 2.0 * V_IMP).abs() <= 0.02 * 2.0 * V_IMP,
            "{cells} cells: far-end velocity after reflection {:.4} m/s, expected 2 V = {:.4}",
            f.plateau,
            2.0 * V_IMP
        );
        lags.push(lag);
    }
    // Refining the mesh shortens the lag like the front width, L_e^{2/3}: ratio 2^{-2/3} = 0.63
    // from 40 to 80 cells. Accept [0.5, 0.75]: a lag that did not shrink with the mesh would
    // be a wave-speed error, not dispersion.
    let ratio = lags[1] / lags[0];
    eprintln!("lag(80 cells) / lag(40 cells) = {ratio:.3} (dispersion: 0.63)");
    assert!(
        (0.5..=0.75).contains(&ratio),
        "lag ratio {ratio:.3} on refinement, dispersion predicts 2^(-2/3) = 0.63"
    );
}
