//! Moulds in rigid motion (model §7.2, §7.4): a body glued to a mould that translates and turns
//! with it (a rigid motion of everything) — no jump, no strain, no damage, no dissipation; and the
//! ledger, with the mould's work, closing while a sphere is pressed into a pad.

use crate::common::*;
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::model::*;
use decohesion_physics::solver::Simulation;

const L: f64 = 0.1;

/// A 0.1 m cube (2³ cells, Saint-Venant–Kirchhoff — its energy is quadratic in the strain, so
/// a round-off strain gives a round-off² energy —, E = 1e8 Pa, ρ = 1000) glued by its bottom to the top face (z = 0) of a
/// box mould, mould and body given the same velocity v and angular velocity ω about the cube's
/// centre.
fn riding(v: [f64; 3], w: [f64; 3], end_time: f64) -> Model {
    let mat = Material::new(MaterialModel::Svk, 1e8, 0.3, 1000.0);
    let mut m = bare_box([L; 3], [2, 2, 2], mat, end_time);
    let c = [0.5 * L, 0.5 * L, 0.5 * L];
    m.initial_velocity = v;
    m.initial_angular_velocity = w;
    m.moulds.push(Mould {
        name: "tray".into(),
        point: [0.5 * L, 0.5 * L, -0.5 * L],
        shape: Shape::Box(decohesion_physics::mould::shapes::r#box::Box {
            centre: [0.5 * L, 0.5 * L, -0.5 * L],
            half_size: [L, L, 0.5 * L],
        }),
        velocity: Some(PiecewiseLinear::constant(v)),
        angular_velocity: (w != [0.0; 3]).then(|| PiecewiseLinear::constant(w)),
        pivot: Some(c),
        ..Default::default()
    });
    // The pull-off cube's glue (plateau–linear, g_N(0) = 5e8 Pa/m, α_e = 2 mm) on the bottom.
    m.interfaces
        .push(pull_off(1, end_time).interfaces[0].clone());
    m
}

/// Largest |[u]| of the glued nodes.
fn max_jump(sim: &Simulation) -> f64 {
    (sim.state.interface_nodes.iter())
        .map(|n| n.jump.iter().map(|c| c * c).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

/// Translation at 1 m/s for 0.05 s (800 steps): the nodes and their anchors
/// move by the same exact increments, so the jump, the strain energy and every dissipation
/// stay at round-off: |[u]| ≤ 1e-12 L (≈ 1e4 ε × the coordinates), strain energy ≤ 1e-20 J
/// (E |[u]/L|² L³ ~ 1e8 × 1e-24 × 1e-3), no damage, dissipations ≤ 1e-15 of the kinetic energy.
#[test]
fn translating_mould_and_body_stay_unstrained() {
    let mut sim = Simulation::new(riding([0.6, -0.8, 0.0], [0.0; 3], 0.05)).unwrap();
    sim.run(|_| true).unwrap();
    assert!(sim.state.step_count > 500, "{} steps", sim.state.step_count);
    let e = sim.energies();
    assert!(max_jump(&sim) <= 1e-12 * L, "|[u]| = {:e}", max_jump(&sim));
    assert!(e.strain <= 1e-20, "strain energy {:e}", e.strain);
    let diss =
        e.damage_dissipated.abs() + e.contact_normal_dissipated.abs() + e.friction_dissipated.abs();
    assert!(
        diss <= 1e-15 * e.kinetic,
        "{diss:e} J dissipated, K = {:e}",
        e.kinetic
    );
    assert!(sim
        .state
        .interface_nodes
        .iter()
        .all(|n| n.alpha < 1e-9 * 2e-3));
    // And the body went where the mould went: x = X + v t.
    let x = sim.state.u.get(0);
    assert!(
        (x[0] - 0.6 * sim.state.time).abs() < 1e-12 && (x[1] + 0.8 * sim.state.time).abs() < 1e-12,
        "{x:?}"
    );
}

/// Translating and turning together, ω = 5 rad/s about z through the cube's centre, for
/// 0.2 s (one radian): the mould's pose is composed exactly per step, so the anchors follow a
/// true rotation; the body, an elastic solid, needs a centripetal force ρω²r that only its own
/// stress and the glue give, i.e. a strain of order ε_c = ρω²L²/E = 2.5e-7 (physical, not an
/// error), started from rest: the body vibrates about its centrifugal deformation ε_c L and the
/// rigid mould holds its bottom, so the jump is of that order (a load applied at once
/// overshoots to twice its static deflection). Bounds: |[u]| ≤ 2ε_c L = 5e-8 m, strain energy
/// ≤ 10 × ½E ε_c² L³ = 3e-8 J; no damage (α ≪ α_e = 2 mm, so no damage dissipation at all);
/// the contact of the glued face may take part of that vibration's energy (the bottom nodes,
/// vibrating by ε_c L, touch the mould inelastically), so contact dissipation ≤ the same
/// 3e-8 J (4e-7 of the kinetic energy 0.08 J); and the body has turned by the
/// mould's angle: the top corner's position matches the rotation to ε_c L (×10).
#[test]
fn turning_mould_and_body_stay_unstrained() {
    let (v, w) = ([0.3, 0.0, 0.1], [0.0, 0.0, 5.0]);
    let t_end = 0.2;
    let mut sim = Simulation::new(riding(v, w, t_end)).unwrap();
    sim.run(|_| true).unwrap();
    let e = sim.energies();
    assert!(max_jump(&sim) <= 5e-8, "|[u]| = {:e}", max_jump(&sim));
    assert!(e.strain <= 3e-8, "strain energy {:e}", e.strain);
    let diss =
        e.damage_dissipated.abs() + e.contact_normal_dissipated.abs() + e.friction_dissipated.abs();
    assert!(diss <= 3e-8, "{diss:e} J dissipated, K = {:e}", e.kinetic);
    assert_eq!(e.damage_dissipated, 0.0);
    assert!(sim
        .state
        .interface_nodes
        .iter()
        .all(|n| n.alpha < 1e-3 * 2e-3));
    let t = sim.state.time;
    let (th, c) = (5.0 * t, [0.5 * L, 0.5 * L, 0.5 * L]);
    let nodes = &sim.model.mesh.nodes;
    let i = (0..nodes.len())
        .max_by(|&a, &b| {
            nodes[a]
                .iter()
                .sum::<f64>()
                .total_cmp(&nodes[b].iter().sum())
        })
        .unwrap(); // (L, L, L)
    let x0 = sim.model.mesh.nodes[i];
    let r = [x0[0] - c[0], x0[1] - c[1]];
    let exact = [
        c[0] + v[0] * t + th.cos() * r[0] - th.sin() * r[1],
        c[1] + v[1] * t + th.sin() * r[0] + th.cos() * r[1],
        x0[2] + v[2] * t,
    ];
    for k in 0..3 {
        let x = x0[k] + sim.state.u.get(i)[k];
        assert!(
            (x - exact[k]).abs() <= 10.0 * 2.5e-7 * L,
            "{k}: {x} vs {}",
            exact[k]
        );
    }
}
