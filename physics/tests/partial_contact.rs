//! Contact and friction on nodes with some components prescribed (model §3.5):
//! a symmetry plane x = 0 on the friction test's sliding steel block (0.1 m cube,
//! 2×2×2 hex8, ν = 0, μ = 0.3, on the plane z = 0 under gravity), launched at v₀ along y.
//!
//! The symmetry condition U_x = 0 on the `x-` face is exact for this block (ν = 0: nothing
//! moves sideways), so the solution is the free block's: the centre of mass slides
//! d = v₀²/(2μg) and the base carries Mg. The three base nodes on the symmetry face have x
//! prescribed and y, z free: they must still get contact (z) and friction (y). Skipping them
//! (as the solver did) lets those nodes sink through the floor under their share of the
//! block's weight and slide without friction on that edge.

use crate::common::{centre_of_mass, face_nodes, on_floor};
use decohesion_physics::interface::contact::ContactStatus;
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::model::PiecewiseLinear;
use decohesion_physics::model::PrescribedDisplacement;
use decohesion_physics::solver::Simulation;

const E: f64 = 2.0e11;
const RHO: f64 = 7800.0;
const SIZE: f64 = 0.1;
const MU: f64 = 0.3;
const G: f64 = 9.81;

#[test]
fn a_symmetry_edge_keeps_contact_and_friction_on_its_free_components() {
    let v0 = 1.0;
    let stop_time = v0 / (MU * G);
    let distance = v0 * v0 / (2.0 * MU * G);
    let mut model = on_floor(
        [SIZE; 3],
        [2; 3],
        Material::new(MaterialModel::Svk, E, 0.0, RHO),
        MU,
        0.8 * stop_time,
    );
    model.gravity = [0.0, 0.0, -G];
    model.displacements.push(PrescribedDisplacement {
        faces: "x-".into(),
        component: 0,
        history: PiecewiseLinear::constant([0.0]),
    });
    // The static state under gravity (exact for ν = 0, see friction.rs).
    let u0: Vec<[f64; 3]> = (model.mesh.nodes.iter())
        .map(|x| [0.0, 0.0, -RHO * G / E * (SIZE * x[2] - 0.5 * x[2] * x[2])])
        .collect();
    let n = u0.len();
    let edge: Vec<usize> = face_nodes(&model, "x-")
        .into_iter()
        .filter(|&i| model.mesh.nodes[i][2] == 0.0)
        .collect();
    assert_eq!(edge.len(), 3);
    let mut sim = Simulation::with_initial_state(model, u0, vec![[0.0, v0, 0.0]; n]).unwrap();
    let h = sim.state.h;
    let (mut min_gap, mut min_gap_free) = (f64::INFINITY, f64::INFINITY);
    let (mut edge_slip_steps, mut other_slip_steps) = (0, 0);
    let mut edge_impulse = [0.0; 3];
    while !sim.finished() {
        sim.step().expect("stable run");
        for cn in sim
            .state
            .contact_nodes
            .iter()
            .filter(|c| !edge.contains(&(c.node as usize)))
        {
            min_gap_free = min_gap_free.min(cn.gap);
            other_slip_steps += usize::from(cn.contact == ContactStatus::Slip);
        }
        for cn in sim
            .state
            .contact_nodes
            .iter()
            .filter(|c| edge.contains(&(c.node as usize)))
        {
            min_gap = min_gap.min(cn.gap);
            for (sum, r) in edge_impulse.iter_mut().zip(cn.contact_impulse) {
                *sum += r;
            }
            if cn.contact == ContactStatus::Slip {
                edge_slip_steps += 1;
                // Slip on an edge node: friction along −y only (x is held), on the cone.
                let r = cn.contact_impulse;
                assert_eq!(r[0], 0.0, "an impulse on the prescribed component");
                assert!(r[1] < 0.0, "friction does not oppose the sliding: {r:?}");
                assert!(
                    (r[1].abs() - MU * r[2]).abs() <= 1e-12 * r[2],
                    "off the cone: {r:?}"
                );
            }
        }
    }
    let t = sim.state.time;
    // Constant deceleration μg: y_cm(t) = v₀t − ½μgt² (tolerance as the friction test's 1e-4
    // of the distance: the t₀ impulse's half step and the elastic motion of the base).
    let expect = v0 * t - 0.5 * MU * G * t * t;
    let travelled = centre_of_mass(&sim, &sim.state.u, 1);
    eprintln!(
        "y_cm {travelled:.7} m at t = {t:.5} s vs {expect:.7} m (d = {distance:.5}); lowest edge \
         gap {min_gap:.3e} m (other base nodes {min_gap_free:.3e} m; h·v_fall would be {:.1e}); edge slip steps {edge_slip_steps}",
        h * G * t
    );
    assert!(
        (travelled / expect - 1.0).abs() <= 1e-4,
        "slid {travelled} m, expected {expect} m"
    );
    // The edge nodes stay on the floor like the other base nodes: a gap below zero only
    // within the velocity-level contact's drift (one step's travel at the base's vibration
    // velocity, nanometres here), nowhere near what a node left to fall would reach,
    // ½g t² ≈ 0.36 m (or a step's fall h·g·t ≈ 1e-5 m).
    assert!(
        min_gap >= 2.0 * min_gap_free.min(0.0) - 1e-12 && min_gap > -1e-7,
        "an edge node went {min_gap:.3e} m into the floor (other base nodes {min_gap_free:.3e} m)"
    );
    // They slid with friction as the other base nodes did (the base's vibration makes any
    // base node stick or lift now and then): the same share of slipping node-steps, within
    // 10 %, and over the run a friction impulse of μ times the normal one, within 2 % (the
    // sticking steps carry less than μ).
    let edge_share = edge_slip_steps as f64 / (3 * sim.state.step_count) as f64;
    let other_share = other_slip_steps as f64 / (6 * sim.state.step_count) as f64;
    let ratio = -edge_impulse[1] / edge_impulse[2];
    eprintln!(
        "slipping node-steps: edge {edge_share:.3}, other base nodes {other_share:.3}; edge \
         friction/normal impulse {ratio:.4} (μ = {MU})"
    );
    assert!((edge_share / other_share - 1.0).abs() <= 0.1);
    assert!(
        (0.98 * MU..=MU * (1.0 + 1e-12)).contains(&ratio),
        "ratio {ratio}"
    );
    assert_eq!(edge_impulse[0], 0.0);
    // Symmetry held exactly.
    assert!(edge.iter().all(|&i| sim.state.u.get(i)[0] == 0.0));
}
