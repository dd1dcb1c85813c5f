//! Irreversibility and admissibility as properties (model §2.4, §2.5, §3.2, §5.5): for random
//! admissible laws and random (non-monotonic, mixed-mode) pull histories, α never decreases,
//! α ≤ u_r, μ(α) ∈ [0, μ_inf], every damage dissipation increment is ≥ 0, and every contact
//! impulse applied lies in the Coulomb cone of its node's μ(α). The histories are scaled so
//! that they do damage the glue: at least half of the cases must take some node past α_e (a
//! property test whose histories never leave the elastic range would test nothing).

use crate::common::*;
use decohesion_physics::interface::contact::ContactStatus;
use decohesion_physics::law::{Knots, ParamValues, StiffnessLaw};
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::model::{Interface, PiecewiseLinear, PrescribedDisplacement};
use decohesion_physics::solver::Simulation;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

fn law_strategy() -> impl Strategy<Value = StiffnessLaw> {
    (
        0usize..4,
        1e8f64..1e10,
        1e-4f64..2e-3,
        1.01f64..5.0,
        0.5f64..6.0,
    )
        .prop_map(|(fam, g0, ae, ratio, k)| {
            let ur = ae * ratio;
            let knots = Knots {
                g_n0: g0,
                alpha_e: ae,
                u_r: ur,
            }
            .values();
            let (family, values) = match fam {
                0 => ("plateau_linear", knots),
                1 => ("bilinear", knots),
                2 => ("exponential", knots.with("decay", k)),
                _ => {
                    let points = vec![
                        [0.0, g0],
                        [ae, g0],
                        [0.5 * (ae + ur), g0 / k.max(1.0)],
                        [ur, 0.0],
                    ];
                    ("table", ParamValues::default().with("points", points))
                }
            };
            StiffnessLaw::build(family, &values).unwrap()
        })
}

/// What one random case showed.
struct Case {
    /// Some node went past α_e.
    damaged: bool,
    /// Constrained contact impulses checked against the cone.
    contacts: usize,
}

/// Runs one case: a 0.1 m cube glued by `law` with friction μ_inf, its top face driven by
/// piecewise-linear normal and tangential histories through the values `zs`, `xs` (in units
/// of u_r times the bulk-to-glue compliance ratio, so that the jump, not only the top face,
/// reaches the scale of u_r), and checks the properties at every step.
fn run_case(law: &StiffnessLaw, mu_inf: f64, zs: &[f64], xs: &[f64]) -> Result<Case, String> {
    let (t_end, size, young) = (0.02, 0.1, 1e8);
    let mat = Material::new(MaterialModel::Svk, young, 0.3, 1000.0);
    let mut m = bare_box([size; 3], [1, 1, 1], mat, t_end);
    m.moulds.push(mould());
    m.interfaces.push(Interface {
        faces: "z-".into(),
        plane: 0,
        law: law.clone(),
        mu_inf,
        initial_damage: 0.0,
        forms_on_contact: None,
    });
    // Top-face displacement per unit jump: the glue (g_N(0)) in series with the bulk (E/L).
    let scale = law.u_r * (1.0 + law.g_n0 * size / young);
    let hist = |vals: &[f64]| PiecewiseLinear {
        points: std::iter::once((0.0, [0.0]))
            .chain(
                vals.iter()
                    .enumerate()
                    .map(|(i, v)| ((i + 1) as f64 * t_end / 4.0, [v * scale])),
            )
            .collect(),
    };
    for (component, vals) in [(2, zs), (0, xs)] {
        m.displacements.push(PrescribedDisplacement {
            faces: "z+".into(),
            component,
            history: hist(vals),
        });
    }
    let mut sim = Simulation::new(m).map_err(|e| e.to_string())?;
    let mut alpha_prev: Vec<f64> = sim.state.interface_nodes.iter().map(|i| i.alpha).collect();
    let mut d_prev = sim.state.ledger.damage_dissipated;
    let mut case = Case {
        damaged: false,
        contacts: 0,
    };
    let n = [0.0, 0.0, 1.0];
    while !sim.finished() {
        sim.step().map_err(|e| e.to_string())?;
        for (itf, a0) in sim.state.interface_nodes.iter().zip(alpha_prev.iter_mut()) {
            if itf.alpha < *a0 || itf.alpha > law.u_r {
                return Err(format!(
                    "α = {} after {} (u_r = {})",
                    itf.alpha, a0, law.u_r
                ));
            }
            let mu = law.mu(itf.alpha, mu_inf);
            if !(0.0..=mu_inf).contains(&mu) {
                return Err(format!("μ = {mu} outside [0, {mu_inf}]"));
            }
            case.damaged |= itf.alpha > law.alpha_e;
            *a0 = itf.alpha;
            // The impulse applied (per unit area): R_N = R·n ≥ 0 and |R_T| ≤ μ(α) R_N, with
            // equality when sliding; round-off allowance 1e-12 of |R|.
            let r = itf.contact_impulse;
            let rn = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
            let rt = ((r[0] - rn * n[0]).powi(2) + (r[1] - rn * n[1]).powi(2)).sqrt();
            let tol = 1e-12 * (rn.abs() + rt);
            match itf.contact {
                ContactStatus::Open if r != [0.0; 3] => {
                    return Err(format!("open node with impulse {r:?}"))
                }
                ContactStatus::Open => {}
                status => {
                    case.contacts += 1;
                    if rn < -tol || rt > mu * rn + tol {
                        return Err(format!("impulse {r:?} outside the cone μ = {mu}"));
                    }
                    if status == ContactStatus::Slip && (rt - mu * rn).abs() > tol {
                        return Err(format!("slip with |R_T| = {rt} ≠ μ R_N = {}", mu * rn));
                    }
                }
            }
        }
        let d = sim.state.ledger.damage_dissipated;
        if d < d_prev {
            return Err(format!("damage dissipation decreased: {d_prev} -> {d}"));
        }
        d_prev = d;
    }
    Ok(case)
}

/// 24 random cases (deterministic seed): each satisfies the properties; at least half damage
/// the glue and some press it into contact (friction checked against the cone).
#[test]
fn damage_is_irreversible_and_dissipative_and_contact_stays_in_the_cone() {
    let strategy = (
        law_strategy(),
        0.0f64..2.0,
        proptest::collection::vec(-1.0f64..3.0, 4),
        proptest::collection::vec(-1.0f64..1.0, 4),
    );
    let mut runner = TestRunner::deterministic();
    let (cases, mut damaged, mut with_contact) = (24, 0, 0);
    for k in 0..cases {
        let (law, mu_inf, zs, xs) = strategy.new_tree(&mut runner).unwrap().current();
        let case = run_case(&law, mu_inf, &zs, &xs)
            .unwrap_or_else(|e| panic!("case {k} ({law:?}, μ_inf {mu_inf}, {zs:?}, {xs:?}): {e}"));
        damaged += case.damaged as usize;
        with_contact += (case.contacts > 0) as usize;
    }
    eprintln!("{damaged} of {cases} cases damaged the glue, {with_contact} had contact");
    assert!(
        2 * damaged >= cases,
        "only {damaged} of {cases} cases went past α_e"
    );
    assert!(with_contact > 0, "no case pressed the glue into contact");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn admissible_laws_never_increase(law in law_strategy(), a in 0.0f64..1.0, b in 0.0f64..1.0) {
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        let span = 1.2 * law.u_r;
        prop_assert!(law.g_n(hi * span) <= law.g_n(lo * span));
        prop_assert_eq!(law.g_n(law.u_r), 0.0);
        prop_assert_eq!(law.g_n(0.0), law.g_n0);
    }
}
