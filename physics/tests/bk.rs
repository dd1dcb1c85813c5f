//! The Benzeggagh–Kenane law (`bk`, model §2.11). At a single node driven along a prescribed
//! jump history with the law's own stage-8 update: a full opening dissipates G_Ic in mode I,
//! G_IIc in mode II and G_c(B) = G_Ic + (G_IIc − G_Ic) B^η at the mixities B = 0.25, 0.5, 0.75,
//! for several η, r_T and either mode-II onset; α never decreases and every dissipation
//! increment is ≥ 0 on random non-proportional histories (proptest); with G_IIc = G_Ic it is the
//! `bilinear` law. Through the solver: a block glued by `bk` to a plane that moves away normally,
//! tangentially or at 45° dissipates G_Ic·A, G_IIc·A, G_c(½)·A, and the ledger closes.

use decohesion_physics::law::{Delay, ParamValues, StiffnessLaw};
use decohesion_physics::scene::parse_scene;
use decohesion_physics::solver::Simulation;
use proptest::prelude::*;

use crate::validation::{record, Tol};

const N: [f64; 3] = [0.0, 0.0, 1.0];

/// A `bk` law; `alpha_e_ii` = 0 takes Turon's onset.
fn bk(g_ic: f64, g_iic: f64, eta: f64, r_t: f64, alpha_e_ii: f64) -> StiffnessLaw {
    let values = (ParamValues::default().with("g_n0", 2.5e8))
        .with("alpha_e", 1e-3)
        .with("g_ic", g_ic)
        .with("g_iic", g_iic)
        .with("eta", eta)
        .with("r_t", r_t)
        .with("alpha_e_ii", alpha_e_ii);
    StiffnessLaw::build("bk", &values).unwrap_or_else(|e| panic!("{e}"))
}

/// G_c(B) written here from its definition.
fn bk_energy(g_ic: f64, g_iic: f64, eta: f64, b: f64) -> f64 {
    g_ic + (g_iic - g_ic) * b.powf(eta)
}

/// What a drive gives: the trapezoid work of the traction, Σ ΔD, the final stored energy and α.
#[derive(Debug, Default)]
struct Drive {
    work: f64,
    dissipated: f64,
    stored: f64,
    alpha: f64,
    alphas: Vec<f64>,
}

/// Drives a unit-area node through `jumps` (one per step of `h`), checking that α never
/// decreases and that ΔD ≥ −1e-12 × the stored scale wherever the loaded jump turns by less
/// than 90° in the step (model §5.5).
fn drive(law: &StiffnessLaw, jumps: &[[f64; 3]], h: f64) -> Drive {
    let (mut alpha, mut alpha_s) = (0.0, 0.0);
    let mut out = Drive::default();
    let (mut k_prev, mut u_prev) = (law.g_n(0.0), jumps[0]);
    let mut r_prev = law.cohesive_traction(k_prev, u_prev, N);
    for &u in &jumps[1..] {
        let next = law.next_damage(alpha, &mut alpha_s, u, N, h);
        assert!(next >= alpha, "{law}: α decreased at {u:?}");
        assert!(next <= law.u_r, "{law}: α = {next} > u_r");
        alpha = next;
        out.alphas.push(alpha);
        let k = law.g_n(alpha);
        let r = law.cohesive_traction(k, u, N);
        out.work += (0..3)
            .map(|c| 0.5 * (r_prev[c] + r[c]) * (u[c] - u_prev[c]))
            .sum::<f64>();
        let dd = law
            .loading()
            .dissipation_increment(1.0, k_prev, k, u_prev, u, N);
        let scale = law.stored_energy(1.0, law.g_n0, u, N).max(1e-300);
        let l = law.loading();
        let turned = u_prev[2] * u[2] + l.ratio * (u_prev[0] * u[0] + u_prev[1] * u[1]);
        if turned >= 0.0 {
            assert!(dd >= -1e-12 * scale, "{law}: ΔD = {dd} at {u:?}");
        }
        out.dissipated += dd;
        (k_prev, u_prev, r_prev) = (k, u, r);
    }
    out.stored = law.stored_energy(1.0, k_prev, u_prev, N);
    out.alpha = alpha;
    out
}

/// The unit direction of the jump (x tangential, z normal) at mixity B for the ratio r: f = s
/// along s·d, and r d_x²/f² = B.
fn direction(b: f64, r_t: f64) -> [f64; 3] {
    [(b / r_t).sqrt(), 0.0, (1.0 - b).sqrt()]
}

/// The jumps s·d: 2000 even steps of s to `s0`, then geometric steps of ratio 1 + 1e-4 to
/// `s_max` (s0 itself is a node of the path).
fn path(d: [f64; 3], s0: f64, s_max: f64) -> Vec<[f64; 3]> {
    let mut s: Vec<f64> = (0..=2000).map(|k| s0 * k as f64 / 2000.0).collect();
    while *s.last().unwrap() < s_max {
        s.push(s.last().unwrap() * (1.0 + 1e-4));
    }
    s.iter().map(|&x| d.map(|c| c * x)).collect()
}

/// (f₀(B), f_f(B)) written here from Turon's and BK's definitions: f₀² = f₀,I² + (f₀,II² −
/// f₀,I²)B^η with f₀,II = √r α_e,II (Turon's α_e √(G_IIc/G_Ic) when α_e,II = 0), and
/// f_f = 2 G_c(B)/(g_N(0) f₀).
fn onset_final(law: &StiffnessLaw, g: [f64; 3], r_t: f64, alpha_e_ii: f64, b: f64) -> [f64; 2] {
    let [g_ic, g_iic, eta] = g;
    let f0_ii = if alpha_e_ii == 0.0 {
        law.alpha_e * (g_iic / g_ic).sqrt()
    } else {
        r_t.sqrt() * alpha_e_ii
    };
    let x = b.powf(eta);
    let f0 = (law.alpha_e.powi(2) + (f0_ii.powi(2) - law.alpha_e.powi(2)) * x).sqrt();
    [f0, 2.0 * bk_energy(g_ic, g_iic, eta, b) / (law.g_n0 * f0)]
}

/// Proportional opening to past rupture at B = 0 (mode I), 0.25, 0.5, 0.75, 1 (mode II): the
/// node dissipates G_c(B), with Turon's onset and with an explicit mode-II onset, at r_T = 1,
/// 0.3 and 4, and G_IIc above and below G_Ic. T(s) is piecewise linear in s (bilinear in f,
/// f = s) and the path has f₀(B) as a node, so the trapezoid work is exact but for the step
/// that straddles f_f(B), whose error is ≤ ½ (slope·Δs)·Δs, relative (Δs/f_f)²·f_f/(f_f − f₀)
/// ≈ 1e-8 with Δs = 1e-4 f_f: tolerance 1e-6 G_c(B). Nothing is stored at the end (α = u_r).
#[test]
fn a_full_opening_dissipates_the_bk_energy_at_every_mixity() {
    let cases = [
        // (G_Ic, G_IIc, η, r_T, α_e,II)
        (250.0, 750.0, 2.0, 1.0, 0.0),
        (250.0, 750.0, 2.0, 0.3, 0.0),
        (250.0, 750.0, 1.45, 4.0, 0.0),
        (250.0, 750.0, 2.0, 1.0, 1.5e-3),
        (250.0, 750.0, 3.0, 0.3, 0.5e-3),
        (600.0, 300.0, 1.0, 1.0, 0.0),
        (600.0, 300.0, 2.0, 2.0, 0.8e-3),
    ];
    let mut worst = 0.0f64;
    for (g_ic, g_iic, eta, r_t, a2) in cases {
        let law = bk(g_ic, g_iic, eta, r_t, a2);
        for b in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let [f0, ff] = onset_final(&law, [g_ic, g_iic, eta], r_t, a2, b);
            let run = drive(&law, &path(direction(b, r_t), f0, 1.01 * ff), 1.0);
            let expected = bk_energy(g_ic, g_iic, eta, b);
            let at = format!("{law}, B = {b}");
            assert_eq!(run.alpha, law.u_r, "{at}: not ruptured");
            assert!(run.stored == 0.0, "{at}: {} stored", run.stored);
            let err = (run.dissipated / expected - 1.0).abs();
            worst = worst.max(err);
            assert!(
                err < 1e-6,
                "{at}: dissipated {} vs G_c(B) = {expected}",
                run.dissipated
            );
            // The ledger's ΔD closes the trapezoid work exactly (linear springs).
            assert!((run.work - run.dissipated - run.stored).abs() < 1e-9 * expected);
            // Before the onset nothing is dissipated, and g_N(α) = g_N(0)(1 − d(f, B)) with
            // the mixed-mode bilinear damage past it: the node's stiffness is the law's in f.
            let k = |s: f64| {
                law.g_n(law.next_damage(0.0, &mut 0.0, direction(b, r_t).map(|c| c * s), N, 1.0))
            };
            for frac in [0.3, 0.99] {
                assert_eq!(k(frac * f0), law.g_n0, "{at}");
            }
            for t in [0.1, 0.5, 0.9] {
                let s = f0 + t * (ff - f0);
                let d = ff * (s - f0) / (s * (ff - f0));
                let by_hand = law.g_n0 * (1.0 - d);
                assert!(
                    (k(s) - by_hand).abs() <= 1e-9 * law.g_n0,
                    "{at}: g_N {} vs {by_hand} at f = {s}",
                    k(s)
                );
            }
        }
    }
    record(
        "bk",
        "largest |D/G_c(B) − 1|, proportional opening, B ∈ {0, ¼, ½, ¾, 1}",
        0.0,
        "Benzeggagh–Kenane G_c(B) = G_Ic + (G_IIc − G_Ic)B^η",
        worst,
        Tol::Abs(1e-6),
    );
    eprintln!("bk: worst |D/G_c(B) − 1| over the proportional openings {worst:.2e}");
}

/// η dependence: at B = ½ with G_IIc = 3 G_Ic, G_c(½) = G_Ic(1 + 2·2^−η) falls with η from
/// 2 G_Ic (η = 1) towards G_Ic; the node's dissipation follows it (1e-6, as above) and falls
/// with η.
#[test]
fn the_dissipation_follows_eta() {
    let mut previous = f64::INFINITY;
    for eta in [0.5, 1.0, 1.45, 2.0, 3.0, 6.0] {
        let law = bk(250.0, 750.0, eta, 1.0, 0.0);
        let [f0, ff] = onset_final(&law, [250.0, 750.0, eta], 1.0, 0.0, 0.5);
        let run = drive(&law, &path(direction(0.5, 1.0), f0, 1.01 * ff), 1.0);
        let expected = 250.0 * (1.0 + 2.0 * 0.5f64.powf(eta));
        assert!(
            (run.dissipated / expected - 1.0).abs() < 1e-6,
            "η = {eta}: {} vs {expected}",
            run.dissipated
        );
        assert!(run.dissipated < previous, "η = {eta}");
        previous = run.dissipated;
    }
}

/// With G_IIc = G_Ic the criterion is the same energy at every mixity, s(B) = 1, and `bk` is
/// `bilinear` with u_r = 2 G_Ic/(g_N(0) α_e): with Turon's onset the same α bit for bit along a
/// 3-D history, whatever η and r_T; with the mode-II onset given as Turon's value (f₀,II = α_e)
/// the same to round-off (1e-12 u_r: the general branch's d(f, B) → α̂ map).
#[test]
fn equal_energies_give_the_bilinear_law() {
    for (eta, r_t) in [(0.7, 1.0), (2.0, 0.3), (3.5, 5.0)] {
        let law = bk(250.0, 250.0, eta, r_t, 0.0);
        let explicit = bk(250.0, 250.0, eta, r_t, 1e-3 / r_t.sqrt());
        let knots = (ParamValues::default().with("g_n0", 2.5e8))
            .with("alpha_e", 1e-3)
            .with("u_r", law.u_r)
            .with("r_t", r_t);
        let bilinear = StiffnessLaw::build("bilinear", &knots).unwrap();
        assert!((law.u_r / 2e-3 - 1.0).abs() < 1e-15);
        assert!((law.fracture_energy() / bilinear.fracture_energy() - 1.0).abs() < 1e-15);
        let jumps: Vec<[f64; 3]> = (0..4000)
            .map(|k| {
                let t = k as f64 / 4000.0 * 6.3;
                [
                    2e-3 * (1.3 * t).sin(),
                    1e-3 * (0.4 * t + 1.0).sin(),
                    2.5e-3 * (0.8 * t).sin(),
                ]
            })
            .collect();
        let (a, b) = (drive(&law, &jumps, 1.0), drive(&bilinear, &jumps, 1.0));
        let c = drive(&explicit, &jumps, 1.0);
        assert_eq!(a.alphas, b.alphas, "η = {eta}, r_T = {r_t}");
        assert_eq!(a.dissipated, b.dissipated);
        for (x, y) in c.alphas.iter().zip(&b.alphas) {
            assert!((x - y).abs() <= 1e-12 * law.u_r, "{x} vs {y}");
        }
    }
}

/// Mixity changing mid-way: opened in mode I to the middle of its softening, turned to mode II at
/// constant f, then opened in mode II to rupture. With G_IIc > G_Ic the turn at constant f does
/// not damage (the mode-II damage at that f is lower: α̂ falls below α); the total lies between
/// G_Ic and G_IIc; every ΔD ≥ 0 (checked in `drive`).
#[test]
fn a_change_of_mixity_never_heals_and_never_dissipates_negatively() {
    let law = bk(250.0, 750.0, 2.0, 1.0, 0.0);
    let mid = 0.5 * (law.alpha_e + law.u_r);
    let mut jumps: Vec<[f64; 3]> = (0..=4000)
        .map(|k| [0.0, 0.0, mid * k as f64 / 4000.0])
        .collect();
    let turn: Vec<[f64; 3]> = (1..=4000)
        .map(|k| {
            let th = std::f64::consts::FRAC_PI_2 * k as f64 / 4000.0;
            [mid * th.sin(), 0.0, mid * th.cos()]
        })
        .collect();
    jumps.extend(&turn);
    let before_turn = drive(&law, &jumps[..=4000], 1.0);
    let after_turn = drive(&law, &jumps, 1.0);
    assert_eq!(after_turn.alpha, before_turn.alpha, "the turn damaged");
    let ff_ii = law.u_r * 3f64.sqrt();
    jumps.extend((1..=8000).map(|k| [mid + (1.01 * ff_ii - mid) * k as f64 / 8000.0, 0.0, 0.0]));
    let run = drive(&law, &jumps, 1.0);
    assert_eq!(run.alpha, law.u_r);
    assert!(
        run.dissipated > 250.0 && run.dissipated < 750.0,
        "{}",
        run.dissipated
    );
}

/// With a delay (model §2.9) the same node, opened slowly in mode II (h ≫ τ_c: the delay has
/// caught up at every step), dissipates G_IIc (1e-6, as above); opened fast and then held until
/// it ruptures it dissipates more (the jump runs ahead of the damage, the traction is higher
/// on the way), and α never decreases either way.
#[test]
fn the_delay_applies_to_the_mode_i_equivalent_opening() {
    let law = bk(250.0, 750.0, 2.0, 1.0, 0.0);
    let ff = law.u_r * 3f64.sqrt();
    let slow = law
        .clone()
        .with_delay(Some(Delay::new(1e-6, 3.0).unwrap()))
        .unwrap();
    let jumps = path(direction(1.0, 1.0), law.alpha_e * 3f64.sqrt(), 1.01 * ff);
    let run = drive(&slow, &jumps, 1.0);
    assert!(
        (run.dissipated / 750.0 - 1.0).abs() < 1e-6,
        "{}",
        run.dissipated
    );
    let fast = law.with_delay(Some(Delay::new(1.0, 3.0).unwrap())).unwrap();
    let mut long = jumps.clone();
    // Held at the last jump for 20 τ_c: the lag falls by e^{−a h/τ_c} a step and α ends at
    // α_s = u_r once a step makes no representable progress (§2.9).
    long.extend(std::iter::repeat_n(*jumps.last().unwrap(), 200_000));
    let run = drive(&fast, &long, 1e-4);
    assert_eq!(run.alpha, fast.u_r);
    assert!(run.dissipated > 750.0, "{}", run.dissipated);
}

/// Inadmissible combinations are refused naming the key, the value and what is admissible.
#[test]
fn inadmissible_bk_laws_are_refused_with_the_reason() {
    let base = (ParamValues::default().with("g_n0", 2.5e8))
        .with("alpha_e", 1e-3)
        .with("g_ic", 250.0)
        .with("g_iic", 750.0);
    let build = |v: ParamValues| StiffnessLaw::build("bk", &v).unwrap_err();
    // ½ g_N(0) α_e² = 125 J/m²: G_Ic at or below it leaves mode I no softening.
    let e = build(base.clone().with("g_ic", 125.0));
    assert_eq!((e.key.as_str(), e.value.as_str()), ("g_ic", "125"));
    assert!(e.reason.contains("> ½ g_N(0) α_e² = 125 J/m²"), "{e}");
    // Mode II: ½ g_N(0) r_T α_e,II² < G_IIc needs α_e,II < √(2·750/2.5e8) = 2.449… mm.
    let e = build(base.clone().with("alpha_e_ii", 2.5e-3));
    assert_eq!(e.key, "alpha_e_ii");
    assert!(
        e.reason
            .contains("α_e,II < √(2 G_IIc/(g_N(0) r_T)) = 0.00244"),
        "{e}"
    );
    let e = build(base.clone().with("eta", 0.0));
    assert_eq!(e.key, "eta");
    assert!(e.reason.contains("η must be finite and > 0"), "{e}");
    let e = build(base.clone().with("g_iic", -1.0));
    assert_eq!(e.key, "g_iic");
    let e = build(base.clone().with("u_r", 2e-3));
    assert!(e.reason.contains("not a parameter of the `bk` law"), "{e}");
    let e = build(base.with("alpha_e", 0.0));
    assert_eq!(e.key, "alpha_e");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// α never decreases and every ΔD ≥ 0 (checked in `drive`) on random non-proportional
    /// histories: sums of sinusoids of random amplitudes (up to 3 × the mode-II final opening),
    /// phases and frequencies in 3-D, so the mixity wanders over [0, 1] while the node loads,
    /// unloads and reloads; random G_IIc/G_Ic in [0.3, 5], η in [0.3, 4], r_T in [0.1, 10],
    /// Turon's or a random admissible mode-II onset, with and without a delay.
    #[test]
    fn alpha_never_decreases_and_every_dissipation_increment_is_nonnegative(
        x in prop::array::uniform6(0.0f64..1.0),
        amp in prop::array::uniform3(0.0f64..3.0), phase in prop::array::uniform3(0.0f64..6.3),
        freq in prop::array::uniform3(0.2f64..3.0), log_h in -7.0f64..-2.0
    ) {
        let (g_n0, alpha_e) = (10f64.powf(7.0 + 3.0 * x[0]), 1e-3 * (0.05 + x[1]));
        let g_ic = 0.5 * g_n0 * alpha_e * alpha_e * (1.2 + 4.0 * x[2]);
        let g_iic = g_ic * (0.3 + 4.7 * x[3]);
        let r_t = 10f64.powf(2.0 * x[4] - 1.0);
        // A mode-II onset at a fraction of its admissible bound, or Turon's.
        let a2 = if x[5] < 0.4 { 0.0 } else { x[5] * (2.0 * g_iic / (g_n0 * r_t)).sqrt() };
        let values = (ParamValues::default().with("g_n0", g_n0))
            .with("alpha_e", alpha_e)
            .with("g_ic", g_ic)
            .with("g_iic", g_iic)
            .with("eta", 0.3 + 3.7 * x[5])
            .with("r_t", r_t)
            .with("alpha_e_ii", a2);
        let law = StiffnessLaw::build("bk", &values).unwrap();
        let delay = (x[0] > 0.6).then(|| Delay::new(1e-3 * x[1] + 1e-6, 3.0).unwrap());
        let law = law.with_delay(delay).unwrap();
        let scale = law.u_r * (g_iic / g_ic).max(1.0).sqrt() / r_t.sqrt().min(1.0);
        let jumps: Vec<[f64; 3]> = (0..4000)
            .map(|k| {
                let t = k as f64 / 4000.0 * 6.3;
                std::array::from_fn(|c| scale * amp[c] * (freq[c] * t + phase[c]).sin())
            })
            .collect();
        let run = drive(&law, &jumps, 10f64.powf(log_h));
        prop_assert!(run.dissipated >= 0.0);
    }
}

/// The scene: a 100 × 100 × 50 mm aluminium block (a rigid link next to the glue, as in
/// `scenes/mixed_mode.toml`) glued by `bk` (g_N(0) = 2.5e8 Pa/m, α_e = 1 mm, G_Ic = 250,
/// G_IIc = 750 J/m², η = 2) to a base that moves away with the velocity (vx, vz) [m/s], ramped
/// over 2 ms; the top is held in x and z.
fn scene(vx: f64, vz: f64, end_time: f64) -> String {
    format!(
        r#"
name = "bk_block"
end_time = {end_time}
[mesh]
origin = [0.0, 0.0, 0.0]
size = [0.1, 0.1, 0.05]
cells = [2, 2, 1]
[material]
model = "svk"
young = 7.0e10
poisson = 0.33
density = 2700.0
[[plane]]
name = "base"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
velocity = [[0.0, 0.0, 0.0, 0.0], [0.002, {vx}, 0.0, {vz}]]
[[interface]]
faces = "z-"
plane = "base"
[interface.law]
family = "bk"
g_n0 = 2.5e8
alpha_e = 1.0e-3
g_ic = 250.0
g_iic = 750.0
eta = 2.0
[[displacement]]
faces = "z+"
component = "x"
table = [[0.0, 0.0]]
[[displacement]]
faces = "z+"
component = "z"
table = [[0.0, 0.0]]
"#
    )
}

/// Pure normal, pure tangential and 45° openings of the block: every node ruptures and the
/// ledger's damage dissipation is G_c(B)·A with B = 0, 1, ½ (G_Ic·A = 2.5 J, G_IIc·A = 7.5 J,
/// G_c(½)·A = 3.75 J). Tolerance 1e-3: the discrete rupture steps, O(v h/f_f) ≈ 2e-4 as in
/// `mixed_mode`, plus, at 45°, the block's compliance in series with the glue, which tilts the
/// jump by (1 + g_N(0)H/M)/(1 + g_N(0)H/G) − 1 ≈ −3.5e-4 and so B by ≈ −1.8e-4, G_c(B) by
/// (G_IIc − G_Ic) η B^{η−1} ΔB/G_c(½) ≈ 2.3e-4. The ledger's largest relative residual ≤ 1e-4
/// as in the other scenes.
#[test]
fn a_block_pulled_off_dissipates_the_bk_energy_in_each_mode() {
    let area = 0.1 * 0.1;
    for (mode, vx, vz, b) in [
        ("I", 0.0f64, -0.2f64, 0.0f64),
        ("II", -0.2, 0.0, 1.0),
        ("45°", -0.2, -0.2, 0.5),
    ] {
        let g_c = bk_energy(250.0, 750.0, 2.0, b);
        // The opening at rupture, f_f(B) = u_r √(G_c(B)/G_Ic) (Turon's onset), reached by a base
        // displacement f_f/|v|·… : run to 1.3 × that time after the 2 ms ramp.
        let ff = 2e-3 * (g_c / 250.0).sqrt();
        let speed = (vx * vx + vz * vz).sqrt();
        let end = 1.3 * (0.001 + ff / speed);
        let text = scene(vx, vz, end);
        let scene = parse_scene(&text, "bk_block.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
        let mut sim = Simulation::new(scene.model).unwrap();
        while !sim.finished() {
            sim.step().unwrap();
        }
        let e = sim.energies();
        assert!(
            sim.stats.time_full_rupture.is_some(),
            "mode {mode}: not ruptured"
        );
        let expected = g_c * area;
        eprintln!(
            "bk block, mode {mode}: damage {:.6} J vs G_c(B)·A {expected:.6} J (rel {:.2e}); \
             plane work {:.6} J; max relative residual {:.2e}; h = {:.2e} s",
            e.damage_dissipated,
            e.damage_dissipated / expected - 1.0,
            e.plane_work,
            sim.state.ledger.max_relative_residual,
            sim.state.h
        );
        record(
            "bk_scene",
            &format!("damage dissipation, mode {mode} [J]"),
            expected,
            "Benzeggagh–Kenane G_c(B)·A (every node ruptured)",
            e.damage_dissipated,
            Tol::Rel(1e-3),
        );
        assert!(
            (e.damage_dissipated / expected - 1.0).abs() <= 1e-3,
            "mode {mode}: dissipated {} J, G_c(B)·A = {expected} J",
            e.damage_dissipated
        );
        assert!(sim.state.ledger.max_relative_residual <= 1e-4);
    }
}
