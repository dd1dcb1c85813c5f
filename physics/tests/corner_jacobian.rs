//! One-point integration checks the corner Jacobians (model §1.9): the
//! one-point rule sees F only at the element centre, where an hourglass mode has no gradient,
//! so an element can turn inside out at its corners while J(0) stays 1.
//!
//! A single 1 m cube element, one-point integration with no hourglass control (κ = 0), launched
//! in the ξη hourglass mode v_x = V₀ s_ξ s_η (s the corner signs). That field has no centre
//! gradient, so F(0) = I and no force acts: the nodes fly at constant velocity and
//! u_x = V₀t s_ξ s_η exactly. The corner Jacobians are then J_a = 1 + 2V₀t s_η (the corner's
//! x-edge stretches by 2V₀t s_η, its other edges keep their length and direction in the edge
//! determinant): the four corners with s_η = −1 (nodes 0, 1, 4, 5) invert at t = 1/(2V₀).

use crate::common::bare_box;
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::mesh::HEX_CORNERS;
use decohesion_physics::model::Integration;
use decohesion_physics::solver::{Simulation, SolverError};

#[test]
fn an_hourglassing_element_stops_the_run_at_its_inverted_corner() {
    let v0 = 10.0;
    let t_inv = 0.5 / v0;
    for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
        let mut m = bare_box(
            [1.0; 3],
            [1; 3],
            Material::new(model, 5e6, 0.3, 1100.0),
            2.0 * t_inv,
        );
        m.scheme.integration = Integration::Reduced;
        m.scheme.hourglass_coefficient = 0.0;
        // The box's node order is the reference element's (HEX_CORNERS).
        let v: Vec<[f64; 3]> = (m.mesh.elements[0].iter()).map(|_| [0.0; 3]).collect();
        let mut v = v;
        for (a, &node) in m.mesh.elements[0].iter().enumerate() {
            let c = HEX_CORNERS[a];
            v[node as usize] = [v0 * c[0] * c[1], 0.0, 0.0];
        }
        let n = v.len();
        let mut sim = Simulation::with_initial_state(m, vec![[0.0; 3]; n], v).unwrap();
        let h = sim.state.h;
        let err = sim.run(|s| {
            // Until the corners turn, the centre sees nothing: F(0) = I, J = 1.
            assert!((s.state.min_jacobian - (1.0 - 2.0 * v0 * s.state.time)).abs() <= 1e-9);
            true
        });
        match err {
            Err(SolverError::Inverted {
                element,
                j,
                ref at,
                time,
                ..
            }) => {
                let msg = err.as_ref().unwrap_err().to_string();
                eprintln!("{model:?}: {msg}");
                assert_eq!(element, 0);
                // Stopped at the first step with t ≥ 1/(2V₀), J = 1 − 2V₀t there.
                assert!(
                    time >= t_inv - 1e-12 && time < t_inv + h,
                    "t = {time}, h = {h}"
                );
                assert!((j - (1.0 - 2.0 * v0 * time)).abs() <= 1e-9, "J = {j}");
                let corner: usize = at
                    .strip_prefix("at its corner ")
                    .and_then(|r| r.split(',').next())
                    .and_then(|k| k.parse().ok())
                    .unwrap_or_else(|| panic!("no corner in {at:?}"));
                assert_eq!(HEX_CORNERS[corner][1], -1.0, "corner {corner} has s_η = +1");
                assert!(at.contains("J = 1.000e0 at the centre"), "{at}");
            }
            other => panic!("{model:?}: ran on with inverted corners: {other:?}"),
        }
    }
}
