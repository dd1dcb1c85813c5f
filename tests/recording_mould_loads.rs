//! What the capture plots of each mould (model §5.7, §7.6), on `roller_peel` (a fixed
//! plate and a turning, translating roller, both rubbing on the strip):
//! - the friction dissipated on each mould, one series per mould in the energy view
//!   (`energy/mould_friction`), ends at the summary's per-mould values and sums to the
//!   ledger's `friction_dissipated`;
//! - the force the strip exerts on the moving roller (`reaction/mould_roller`, no prescribed
//!   displacement in this scene, so nothing else is in the reaction view) is, in the steady
//!   peel, Kendall's peel force at the angle it makes — the check `physics/tests/roller_peel.rs`
//!   makes with the loads rebuilt at every step, here on the plotted frames; and its moment
//!   about the roller's axis is logged (`mould_moment/roller`).

use crate::common;

use crate::common::capture::{read_capture, rows_on};
use crate::common::cli::{decohesion_ok, summary};
use decohesion::output::surface::mould::body_box;
use decohesion::scene::load_scene;
use rerun::ChunkStore;
use std::path::Path;

const SCENE: &str = "scenes/roller_peel.toml";

/// Every row of a Scalars entity on the `sim_time` timeline: (t [s], values), in time order.
fn series(store: &ChunkStore, entity: &str) -> Vec<(f64, Vec<f64>)> {
    let component = rerun::Scalars::descriptor_scalars().component;
    (rows_on::<f64>(store, entity, component, "sim_time").into_iter())
        .map(|(t, v)| (1e-9 * t as f64, v))
        .collect()
}

/// The whole run, captured every 20 steps (~1100 frames, ~270 in the steady window: the
/// force drops by about half each time a node pair lets go, every ~2 ms, so the window's mean
/// needs many frames per release).
fn capture() -> (ChunkStore, serde_json::Value) {
    let dir = common::cli::scratch("rec", "mould_loads");
    let (rrd, json) = (dir.join("roller_peel.rrd"), dir.join("roller_peel.json"));
    decohesion_ok(&[
        "run",
        SCENE,
        "--quiet",
        "--every",
        "20",
        "--save",
        rrd.to_str().unwrap(),
        "--summary",
        json.to_str().unwrap(),
    ]);
    (read_capture(&rrd), summary(&json))
}

#[test]
fn roller_peel_plots_each_mould_s_friction_and_the_roller_s_load() {
    let (store, s) = capture();

    // Friction per mould: the last frame (the run's last step) is the summary's value. Both
    // are the same f64 (Scalars are stored as f64; the JSON prints the shortest round-trip
    // decimal), so they agree to the last bit.
    let friction = series(&store, "/energy/mould_friction");
    let (_, last) = friction.last().expect("a per-mould friction series");
    let listed = s["mould_friction"].as_array().unwrap();
    assert_eq!(last.len(), listed.len());
    for (value, entry) in last.iter().zip(listed) {
        let (name, want) = (&entry[0], entry[1].as_f64().unwrap());
        assert_eq!(*value, want, "friction on {name}");
        assert!(want > 0.0, "{name} rubs on the strip");
    }
    // The moulds' frictions add up to the ledger's total to round-off (the contact impulses
    // are read back per unit area): 1e-12 of it.
    let energy = series(&store, "/energy");
    let total = energy.last().unwrap().1[6];
    let sum: f64 = last.iter().sum();
    assert!((sum - total).abs() <= 1e-12 * total, "Σ {sum} vs {total}");

    // The roller's load in the steady peel against Kendall's balance at the front, with the
    // arm's stretch and the kinetic energy it carries away (physics/tests/roller_peel.rs):
    // (F/b)(1 − cos θ) + (F/b)²/(2Et) = G_c + ρtV²(1 − cos θ), θ the angle of the mean force.
    let model = load_scene(Path::new(SCENE), &[]).unwrap().model;
    let (gc, young, rho) = (
        model.interfaces[0].law.fracture_energy(),
        model.material.young,
        model.material.density,
    );
    // The strip's width b and thickness t: its box's y and z extents.
    let (lo, hi) = body_box(&model);
    let (b, t) = (hi[1] - lo[1], hi[2] - lo[2]);
    let roller = model.moulds.iter().find(|p| p.name == "roller").unwrap();
    let v = roller.velocity.as_ref().unwrap().value(0.1)[0];
    let force = series(&store, "/reaction/mould_roller");
    assert_eq!(force.len(), friction.len(), "a force at every frame");
    let steady: Vec<&Vec<f64>> = (force.iter())
        .filter(|(time, _)| *time >= 0.06)
        .map(|r| &r.1)
        .collect();
    assert!(steady.len() > 200, "{} frames", steady.len());
    let mean = |c: usize| steady.iter().map(|f| f[c]).sum::<f64>() / steady.len() as f64;
    let f = [mean(0), mean(1), mean(2)];
    let f_abs = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    let c1 = 1.0 - f[0] / f_abs;
    let a = 1.0 / (2.0 * young * t);
    let rhs = gc + rho * t * v * v * c1;
    let kendall = b * (-c1 + (c1 * c1 + 4.0 * a * rhs).sqrt()) / (2.0 * a);
    eprintln!(
        "roller: mean F = {f:?} N over {} frames, |F| = {f_abs:.4} N, Kendall {kendall:.4} N \
         ({:+.2} %), θ = {:.2}°",
        steady.len(),
        100.0 * (f_abs / kendall - 1.0),
        (1.0 - c1).acos().to_degrees()
    );
    // 3 %, the physics test's tolerance (the force drops by ~half at each release, ~20 in
    // the window).
    assert!(
        (f_abs / kendall - 1.0).abs() <= 0.03,
        "{f_abs} N vs {kendall} N"
    );
    // A peel over the roller's back: 90° < θ < 150°.
    assert!(
        (1.0 - c1) < 0.0 && (1.0 - c1) > -0.866,
        "cos θ = {}",
        1.0 - c1
    );

    // The moment about the roller's axis (y): the strip winds on, pulling the roller's
    // surface back against its turn, so M_y opposes ω_y; |M_y| is the arm's pull times a
    // lever of at most the wound radius R + t (the force acts on the roller's surface).
    let omega = roller.angular_velocity.as_ref().unwrap().value(0.1)[1];
    let moment = series(&store, "/mould_moment/roller");
    assert_eq!(moment.len(), force.len());
    let m_y = (moment.iter())
        .filter(|(time, _)| *time >= 0.06)
        .map(|r| r.1[1])
        .sum::<f64>()
        / steady.len() as f64;
    let radius = match roller.shape {
        decohesion::model::Shape::Cylinder(c) => c.radius,
        _ => panic!("the roller is a cylinder"),
    };
    assert!(m_y * omega < 0.0, "M_y = {m_y} N·m against ω_y = {omega}");
    assert!(
        m_y.abs() <= f_abs * (radius + t),
        "M_y = {m_y} N·m, F = {f_abs} N"
    );
}
