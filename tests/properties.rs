//! Irreversibility and admissibility as properties (PHYSICS.md §3 and §5): for random
//! admissible laws and random (non-monotonic, mixed-mode) pull histories, α never decreases,
//! α ≤ u_r, μ(α) ∈ [0, μ_inf], and every damage dissipation increment is ≥ 0.

mod common;
use common::*;
use decohesion::law::{LawFamily, StiffnessLaw};
use decohesion::material::{Material, MaterialModel};
use decohesion::model::{Interface, PiecewiseLinear, PrescribedDisplacement};
use decohesion::solver::Simulation;
use proptest::prelude::*;

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
            match fam {
                0 => StiffnessLaw::new(LawFamily::PlateauLinear, g0, ae, ur).unwrap(),
                1 => StiffnessLaw::new(LawFamily::Bilinear, g0, ae, ur).unwrap(),
                2 => StiffnessLaw::new(LawFamily::Exponential { decay: k }, g0, ae, ur).unwrap(),
                _ => StiffnessLaw::from_table(vec![
                    [0.0, g0],
                    [ae, g0],
                    [0.5 * (ae + ur), g0 / k.max(1.0)],
                    [ur, 0.0],
                ])
                .unwrap(),
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn damage_is_irreversible_and_dissipative(
        law in law_strategy(),
        mu_inf in 0.0f64..2.0,
        zs in proptest::collection::vec(-1.0f64..3.0, 4),
        xs in proptest::collection::vec(-1.0f64..1.0, 4),
    ) {
        let t_end = 0.02;
        let mut m = bare_box([0.1; 3], [1, 1, 1], Material::new(MaterialModel::Svk, 1e8, 0.3, 1000.0), t_end);
        m.planes.push(mould());
        m.interfaces.push(Interface { faces: "z-".into(), plane: 0, law: law.clone(), mu_inf, initial_damage: 0.0 });
        // Random piecewise-linear histories of the top face, normal and tangential, that go up
        // and down (unloading and reloading) around the interface's scale u_r.
        let hist = |vals: &[f64]| PiecewiseLinear {
            points: std::iter::once((0.0, [0.0]))
                .chain(vals.iter().enumerate().map(|(i, v)| ((i + 1) as f64 * t_end / 4.0, [v * law.u_r])))
                .collect(),
        };
        m.displacements.push(PrescribedDisplacement { faces: "z+".into(), component: 2, history: hist(&zs) });
        m.displacements.push(PrescribedDisplacement { faces: "z+".into(), component: 0, history: hist(&xs) });
        let mut sim = Simulation::new(m).unwrap();
        let mut alpha_prev: Vec<f64> = sim.interface_nodes.iter().map(|i| i.alpha).collect();
        let mut d_prev = sim.ledger.damage_dissipated;
        while !sim.finished() {
            sim.step().unwrap();
            for (itf, a0) in sim.interface_nodes.iter().zip(alpha_prev.iter_mut()) {
                prop_assert!(itf.alpha >= *a0, "α decreased: {} -> {}", a0, itf.alpha);
                prop_assert!(itf.alpha <= law.u_r);
                let mu = law.mu(itf.alpha, mu_inf);
                prop_assert!((0.0..=mu_inf).contains(&mu), "μ = {} outside [0, {}]", mu, mu_inf);
                *a0 = itf.alpha;
            }
            let d = sim.ledger.damage_dissipated;
            prop_assert!(d >= d_prev, "damage dissipation decreased: {} -> {}", d_prev, d);
            d_prev = d;
        }
    }

    #[test]
    fn admissible_laws_never_increase(law in law_strategy(), a in 0.0f64..1.0, b in 0.0f64..1.0) {
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        let span = 1.2 * law.u_r;
        prop_assert!(law.g_n(hi * span) <= law.g_n(lo * span));
        prop_assert_eq!(law.g_n(law.u_r), 0.0);
        prop_assert_eq!(law.g_n(0.0), law.g_n0);
    }
}
