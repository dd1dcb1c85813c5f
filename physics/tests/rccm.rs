//! The original RCCM law (`rccm`, model §2.10) and the tangential ratio r_T of
//! the g_N(α) families, at a single node driven along a prescribed jump history with the law's
//! own stage-8 update: the work of separation is w in modes I, II and at 45° (b = 0), the peak
//! normal traction √(w C_N) at √(w/C_N); the work grows with the rate when b > 0; β never
//! increases, μ stays in [0, μ_inf], every dissipation increment is ≥ 0 (proptest over random
//! laws and histories); shear loads with C_T (r_T g_N), normal opening with C_N (g_N).

use decohesion_physics::law::{families, Delay, Knots, ParamValues, StiffnessLaw};
use proptest::prelude::*;

use crate::validation::{record, Tol};

const N: [f64; 3] = [0.0, 0.0, 1.0];

/// The law with β_min = 1e-7, below every β these drives reach: β only tends to 0.
fn rccm(c_n: f64, c_t: f64, w: f64, b: f64) -> StiffnessLaw {
    rccm_cut(c_n, c_t, w, b, 1e-7)
}

fn rccm_cut(c_n: f64, c_t: f64, w: f64, b: f64, beta_min: f64) -> StiffnessLaw {
    let values = (ParamValues::default().with("c_n", c_n).with("c_t", c_t))
        .with("w", w)
        .with("b", b)
        .with("beta_min", beta_min);
    StiffnessLaw::build("rccm", &values).unwrap()
}

/// β of the node from its α slot: g_N(α) = C_N β².
fn beta(law: &StiffnessLaw, alpha: f64) -> f64 {
    (law.g_n(alpha) / law.g_n0).sqrt()
}

/// What a drive along a jump history gives: the trapezoid work of the traction, Σ of the
/// ledger's dissipation increments, the final stored energy, the peak |R| and where, the final
/// α.
#[derive(Debug, Default)]
struct Drive {
    work: f64,
    dissipated: f64,
    stored: f64,
    peak: (f64, [f64; 3]),
    alpha: f64,
}

/// Drives a unit-area node through `jumps` (one per step of `h`), checking at every step that
/// α never decreases (β never increases), μ ∈ [0, μ_inf] and ΔD ≥ −1e-12 × the stored scale.
fn drive(law: &StiffnessLaw, jumps: &[[f64; 3]], h: f64) -> Drive {
    let (mut alpha, mut alpha_s) = (0.0, 0.0);
    let mut out = Drive::default();
    let (mut k_prev, mut u_prev) = (law.g_n(0.0), jumps[0]);
    let mut r_prev = law.cohesive_traction(k_prev, u_prev, N);
    for &u in &jumps[1..] {
        // Stage 8 predicts α at this configuration, stage 5 loads with it.
        let next = law.next_damage(alpha, &mut alpha_s, u, N, h);
        assert!(next >= alpha, "{law}: α decreased (β increased) at {u:?}");
        alpha = next;
        let mu = law.mu(alpha, 0.7);
        assert!((0.0..=0.7).contains(&mu), "{law}: μ = {mu}");
        let k = law.g_n(alpha);
        let r = law.cohesive_traction(k, u, N);
        out.work += (0..3)
            .map(|c| 0.5 * (r_prev[c] + r[c]) * (u[c] - u_prev[c]))
            .sum::<f64>();
        let dd = law
            .loading()
            .dissipation_increment(1.0, k_prev, k, u_prev, u, N);
        let scale = law.stored_energy(1.0, law.g_n0, u, N).max(1e-300);
        // Model §5.5: ΔD ≥ 0 while the loaded jump turns by less than 90° in the step (a
        // history through [u] = 0 turns by 180° there, where the stiffness of a delayed law may
        // still fall).
        if loaded_product(law, u_prev, u) >= 0.0 {
            assert!(dd >= -1e-12 * scale, "{law}: ΔD = {dd} at {u:?}");
        }
        out.dissipated += dd;
        let norm = r.iter().map(|c| c * c).sum::<f64>().sqrt();
        if norm > out.peak.0 {
            out.peak = (norm, u);
        }
        (k_prev, u_prev, r_prev) = (k, u, r);
    }
    out.stored = law.stored_energy(1.0, k_prev, u_prev, N);
    out.alpha = alpha;
    out
}

/// ũ_N ũ'_N + r [u]_T·[u]'_T, written here from its definition (model §5.5).
fn loaded_product(law: &StiffnessLaw, a: [f64; 3], b: [f64; 3]) -> f64 {
    let l = law.loading();
    let normal = |u: [f64; 3]| if l.opening_only { u[2].max(0.0) } else { u[2] };
    normal(a) * normal(b) + l.ratio * (a[0] * b[0] + a[1] * b[1])
}

/// Openings s along the unit direction `d`: 2000 even steps to `s0`, then geometric steps of
/// ratio 1 + 1e-4 to `s_max` (s0 itself is a node of the path).
fn path(d: [f64; 3], s0: f64, s_max: f64) -> Vec<[f64; 3]> {
    let mut s: Vec<f64> = (0..=2000).map(|k| s0 * k as f64 / 2000.0).collect();
    while *s.last().unwrap() < s_max {
        s.push(s.last().unwrap() * (1.0 + 1e-4));
    }
    s.iter().map(|&x| d.map(|c| c * x)).collect()
}

/// b = 0, C_T = C_N/4: in mode I, mode II and at 45° (the jump in the xz plane), the energy
/// release is Y = C_N⟨u_N⟩₊² + C_T|u_T|² = C_eff s² along the path, β = 1 up to s₀ = √(w/C_eff),
/// then β = s₀²/s²: the dissipated energy up to s is w(1 − β) exactly (what is left, ½wβ
/// stored and ½wβ of work still to come, tends to 0), whatever the mode. Opened to 1000 s₀
/// (β = 1e-6). Trapezoid rule on the piecewise-smooth T(s) with steps ≤ 1e-4 s: relative error
/// ~1e-8; tolerance 1e-6 w.
#[test]
fn work_of_separation_is_w_in_every_mode() {
    let (c_n, c_t, w) = (4e8, 1e8, 300.0);
    let law = rccm(c_n, c_t, w, 0.0);
    let r = std::f64::consts::FRAC_1_SQRT_2;
    for (mode, d, c_eff) in [
        ("I", N, c_n),
        ("II", [1.0, 0.0, 0.0], c_t),
        ("45°", [r, 0.0, r], 0.5 * (c_n + c_t)),
    ] {
        let s0 = (w / c_eff).sqrt();
        let run = drive(&law, &path(d, s0, 1000.0 * s0), 1.0);
        let b_end = beta(&law, run.alpha);
        assert!((b_end - 1e-6).abs() < 1e-8, "mode {mode}: β = {b_end}");
        let expected = w * (1.0 - b_end);
        record(
            "rccm",
            &format!("dissipated energy, mode {mode} [J/m²]"),
            expected,
            "Frémond's RCCM, closed form at b = 0 (w(1 − β))",
            run.dissipated,
            Tol::Abs(1e-6 * w),
        );
        assert!(
            (run.dissipated - expected).abs() < 1e-6 * w,
            "mode {mode}: dissipated {} vs w(1 − β) = {expected}",
            run.dissipated
        );
        // The ledger's ΔD closes the trapezoid work exactly (linear springs, no sign change).
        assert!((run.work - run.dissipated - run.stored).abs() < 1e-9 * w);
        assert!(
            (run.stored - 0.5 * w * b_end).abs() < 1e-6 * w,
            "mode {mode}"
        );
        // The peak of |R| is √(w C_eff)·(C-weighted direction) at s₀: in mode I √(w C_N).
        if mode == "I" {
            record(
                "rccm",
                "peak normal traction, mode I [Pa]",
                (w * c_n).sqrt(),
                "Frémond's RCCM, closed form (√(w C_N))",
                run.peak.0,
                Tol::Rel(1e-12),
            );
            assert!(
                (run.peak.0 / (w * c_n).sqrt() - 1.0).abs() < 1e-12,
                "{:?}",
                run.peak
            );
            assert!(
                (run.peak.1[2] / (w / c_n).sqrt() - 1.0).abs() < 1e-12,
                "{:?}",
                run.peak
            );
        }
    }
}

/// β_min (model §2.10): a β that falls below it is set to 0, so the node opened past
/// u_r = u₀/√β_min keeps no stiffness and nothing stored, and the energy spent in mode I at b = 0
/// is w(1 − β_min) up to u_r plus the β_min w/2 still stored there, released by the cut:
/// w(1 − β_min/2), the law's G_c. Same trapezoid error as above (tolerance 1e-6 w). The default
/// β_min is the family's table's.
#[test]
fn beta_below_beta_min_is_set_to_zero() {
    let (c_n, w): (f64, f64) = (4e8, 300.0);
    let s0 = (w / c_n).sqrt();
    for beta_min in [0.05, 1e-3] {
        let law = rccm_cut(c_n, c_n, w, 0.0, beta_min);
        assert!((law.u_r / (s0 / beta_min.sqrt()) - 1.0).abs() < 1e-12);
        let run = drive(&law, &path(N, s0, 2.0 * law.u_r), 1.0);
        assert_eq!(law.g_n(run.alpha), 0.0, "β_min {beta_min}: not cut");
        assert_eq!(run.stored, 0.0);
        let g_c = law.fracture_energy();
        assert!((g_c - w * (1.0 - 0.5 * beta_min)).abs() < 1e-12 * w);
        record(
            "rccm",
            &format!("energy spent through the cut, β_min = {beta_min} [J/m²]"),
            g_c,
            "Frémond's RCCM with β_min, closed form (w(1 − β_min/2))",
            run.dissipated,
            Tol::Abs(1e-6 * w),
        );
        assert!(
            (run.dissipated - g_c).abs() < 1e-6 * w,
            "β_min {beta_min}: spent {} vs {g_c}",
            run.dissipated
        );
    }
    let default = families().iter().find(|f| f.key == "rccm").unwrap();
    let law = default.build(&default.defaults()).unwrap();
    let beta_min = law.values().number("beta_min").unwrap();
    assert!(beta_min > 0.0 && beta_min < 1.0);
}

/// b > 0: β lags behind w/Y, the springs hold more and the viscous dissipation ∫bβ̇² adds to
/// w(1 − β): the work spent up to 100 s₀ grows with the opening rate, and tends to the b = 0
/// value w(1 − 1e-4) as the rate → 0 (b/(rate-scale) → 0). Steps of ds = 1e-4 s: the implicit
/// update's error is O(h).
#[test]
fn viscous_rccm_spends_more_the_faster_it_opens() {
    let (c_n, w, b) = (4e8, 300.0, 1.0);
    let law = rccm(c_n, c_n, w, b);
    let s0 = (w / c_n).sqrt();
    let jumps = path(N, s0, 100.0 * s0);
    // Uniform time steps would waste most on the tail: h follows the path's steps.
    let spent = |rate: f64| drive_timed(&law, &jumps, rate).dissipated;
    let runs: Vec<f64> = [1e-6, 1e-4, 1e-2, 1.0].map(spent).to_vec();
    for p in runs.windows(2) {
        assert!(p[1] > p[0], "not growing with the rate: {runs:?}");
    }
    record(
        "rccm",
        "b > 0: energy spent at 1e-6 m/s, the rate-independent limit [J/m²]",
        w * (1.0 - 1e-4),
        "Frémond's RCCM, closed form at b = 0 (w(1 − β), β = 1e-4)",
        runs[0],
        Tol::Rel(1e-3),
    );
    assert!(
        (runs[0] / (w * (1.0 - 1e-4)) - 1.0).abs() < 1e-3,
        "{runs:?}"
    );
    assert!(runs[3] > 1.2 * w, "{runs:?}");
}

/// [`drive`] with the step h of each segment = its length / `rate`.
fn drive_timed(law: &StiffnessLaw, jumps: &[[f64; 3]], rate: f64) -> Drive {
    let (mut alpha, mut alpha_s) = (0.0, 0.0);
    let mut out = Drive::default();
    let mut k_prev = law.g_n(0.0);
    for p in jumps.windows(2) {
        let h = (p[1][2] - p[0][2]).abs() / rate;
        let next = law.next_damage(alpha, &mut alpha_s, p[1], N, h);
        assert!(next >= alpha);
        alpha = next;
        let k = law.g_n(alpha);
        out.dissipated += law
            .loading()
            .dissipation_increment(1.0, k_prev, k, p[0], p[1], N);
        k_prev = k;
    }
    out.alpha = alpha;
    out
}

/// In the elastic range a pure shear jump is loaded with C_T (rccm) or r_T g_N(0) (the g_N(α)
/// families), a pure normal one with C_N or g_N(0), and a closing normal jump with C_N only
/// for the g_N families (rccm loads the normal jump on opening only).
#[test]
fn shear_loads_with_the_tangential_stiffness_and_opening_with_the_normal_one() {
    let knots = Knots {
        g_n0: 1e9,
        alpha_e: 1e-3,
        u_r: 3e-3,
    };
    let bilinear = StiffnessLaw::build("bilinear", &knots.values().with("r_t", 0.25)).unwrap();
    let laws = [
        (rccm(4e8, 1e8, 300.0, 0.0), 4e8, 1e8),
        (bilinear, 1e9, 2.5e8),
    ];
    for (law, k_n, k_t) in laws {
        let k = law.g_n(0.0);
        let (u, s) = (1e-5, [1e-5, 0.0, 0.0]);
        assert_eq!(law.cohesive_traction(k, s, N), [k_t * u, 0.0, 0.0], "{law}");
        assert_eq!(
            law.cohesive_traction(k, [0.0, 0.0, u], N),
            [0.0, 0.0, k_n * u]
        );
        let closing = law.cohesive_traction(k, [0.0, 0.0, -u], N)[2];
        let opening_only = law.spec().key == "rccm";
        assert_eq!(closing, if opening_only { 0.0 } else { -k_n * u }, "{law}");
        let stored = law.stored_energy(2.0, k, s, N);
        assert!(
            (stored / (k_t * u * u) - 1.0).abs() < 1e-15,
            "{law}: {stored}"
        );
    }
}

/// r_T ≠ 1: the damage measure f = (⟨u_N⟩₊² + r_T u_T²)^½ makes pure shear open the same
/// softening curve in f, so the shear work of separation is G_c and the shear peak is
/// √r_T T_max at u_T = δ_peak/√r_T. Path steps ≤ 1e-4 of the opening: 1e-6 relative.
#[test]
fn r_t_keeps_g_c_in_shear_and_scales_the_shear_peak() {
    let knots = Knots {
        g_n0: 1e9,
        alpha_e: 1e-3,
        u_r: 3e-3,
    };
    let r_t = 0.25;
    let law = StiffnessLaw::build("bilinear", &knots.values().with("r_t", r_t)).unwrap();
    let run = drive(&law, &path([1.0, 0.0, 0.0], 1e-3 / r_t.sqrt(), 7e-3), 1.0);
    let g_c = law.fracture_energy();
    assert!(
        (run.dissipated / g_c - 1.0).abs() < 1e-6,
        "{} vs {g_c}",
        run.dissipated
    );
    let (t_max, at) = law.peak_traction();
    assert!(
        (run.peak.0 / (r_t.sqrt() * t_max) - 1.0).abs() < 1e-9,
        "{:?}",
        run.peak
    );
    assert!(
        (run.peak.1[0] * r_t.sqrt() / at - 1.0).abs() < 1e-9,
        "{:?}",
        run.peak
    );
}

/// A random admissible law: a family of the table at random parameters, with r_T, a delay, or
/// rccm's C_T and b drawn too.
fn random_law(pick: usize, x: [f64; 5]) -> StiffnessLaw {
    let spec = &families()[pick % families().len()];
    let g_n0 = 10f64.powf(7.0 + 3.0 * x[0]);
    let values = match spec.key {
        "rccm" => (ParamValues::default().with("c_n", g_n0))
            .with("c_t", g_n0 * 10f64.powf(2.0 * x[1] - 1.0))
            .with("w", 10f64.powf(4.0 * x[2]))
            .with(
                "b",
                if x[3] < 0.3 {
                    0.0
                } else {
                    10f64.powf(4.0 * x[3] - 2.0)
                },
            ),
        "table" => ParamValues::default()
            .with(
                "points",
                vec![[0.0, g_n0], [1e-3 * (0.1 + x[1]), g_n0 * x[2]], [4e-3, 0.0]],
            )
            .with("r_t", 10f64.powf(2.0 * x[4] - 1.0)),
        // G_Ic for u_r = α_e (1.5 … 4.5) as the others', G_IIc from 0.5 to 4.5 × G_Ic.
        "bk" => {
            let alpha_e = 1e-3 * (0.05 + x[1]);
            let g_ic = 0.5 * g_n0 * alpha_e * alpha_e * (1.5 + 3.0 * x[2]);
            (spec.defaults().with("g_n0", g_n0).with("alpha_e", alpha_e))
                .with("g_ic", g_ic)
                .with("g_iic", g_ic * (0.5 + 4.0 * x[3]))
                .with("r_t", 10f64.powf(2.0 * x[4] - 1.0))
        }
        _ => {
            let alpha_e = 1e-3 * (0.05 + x[1]);
            let mut v = spec.defaults().with("g_n0", g_n0).with("alpha_e", alpha_e);
            v = v.with("u_r", alpha_e * (1.5 + 3.0 * x[2]));
            v.with("r_t", 10f64.powf(2.0 * x[4] - 1.0))
        }
    };
    let law = spec
        .build(&values)
        .unwrap_or_else(|e| panic!("{}: {e}", spec.key));
    let delay =
        (spec.key != "rccm" && x[3] > 0.5).then(|| Delay::new(1e-3 * x[3], 5.0 * x[0] + 0.1));
    law.with_delay(delay.map(Result::unwrap)).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Every dissipation increment ≥ 0, β never increases and μ ∈ [0, μ_inf] (checked in
    /// `drive`) along a smooth random jump history: sums of sinusoids of random amplitudes (up
    /// to 3 × u_r), phases and frequencies in 3-D, 4000 steps over ≤ 3 periods (the jump turns
    /// by far less than 90° per step), at a random pace h.
    #[test]
    fn every_dissipation_increment_is_nonnegative(
        pick in 0usize..16, x in prop::array::uniform5(0.0f64..1.0),
        amp in prop::array::uniform3(0.0f64..3.0), phase in prop::array::uniform3(0.0f64..6.3),
        freq in prop::array::uniform3(0.2f64..3.0), log_h in -7.0f64..-2.0
    ) {
        let law = random_law(pick, x);
        let jumps: Vec<[f64; 3]> = (0..4000)
            .map(|k| {
                let t = k as f64 / 4000.0 * 6.3;
                std::array::from_fn(|c| law.u_r * amp[c] * (freq[c] * t + phase[c]).sin())
            })
            .collect();
        drive(&law, &jumps, 10f64.powf(log_h));
    }
}

/// `scenes/rccm_shear.toml`: the pressed pad sheared on the RCCM glue with C_T = C_N/20. The
/// normal jump stays closed (no normal cohesion: R_N = C_N β²⟨[u]_N⟩₊), so the shear loads with
/// C_T: the tangential force peaks between ½√(w C_T) A (the edges soften before the centre is
/// loaded) and (√(w C_T) + μ_inf p) A, far below the √(w C_N) A the normal stiffness would give;
/// each node spends w(1 − β_min/2) once β falls below β_min (b = 0, any mode, model §2.10): with
/// every node ruptured at the end, nothing is stored and the damage dissipated is G_c A within 1 %
/// (the time discretisation and the dynamics); then the pad slides at μ_inf × normal force = 300 N.
#[test]
fn rccm_shear_scene_loads_with_c_t_and_spends_g_c() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/rccm_shear.toml");
    let scene = decohesion_physics::scene::load_scene(&path, &[]).unwrap();
    let (w, c_n, c_t, area, p, mu_inf) = (200.0, 1e9, 5e7, 0.01, 1e5, 0.3);
    let itf = &scene.model.interfaces[0];
    assert_eq!((itf.law.spec().key, itf.mu_inf), ("rccm", mu_inf));
    assert_eq!(itf.law.loading().ratio, c_t / c_n);
    let mut sim = decohesion_physics::solver::Simulation::new(scene.model).unwrap();
    let (mut closed, mut late) = (true, vec![]);
    while !sim.finished() {
        sim.step().unwrap();
        for n in &sim.state.interface_nodes {
            // Pressed: no normal cohesion wherever the normal jump is closed.
            closed &= n.jump[2] > 0.0 || n.cohesive_traction[2] == 0.0;
        }
        if sim.state.time > sim.model.end_time - 0.01 {
            late.push(sim.stats.reactions[0].abs());
        }
    }
    assert!(closed);
    let peak = sim.stats.peaks[0].force.abs();
    let (glue, friction) = ((w * c_t).sqrt() * area, mu_inf * p * area);
    assert!(peak > 0.5 * glue && peak < glue + friction, "peak {peak} N");
    assert!(peak < 0.5 * (w * c_n).sqrt() * area, "peak {peak} N");
    assert_eq!(sim.state_counts().ruptured, sim.state.interface_nodes.len());
    let g_c = sim.model.interfaces[0].law.fracture_energy();
    assert!(g_c < w);
    assert_eq!(sim.state.ledger.interface_stored, 0.0);
    let spent = sim.state.ledger.damage_dissipated;
    assert!(
        (spent / (g_c * area) - 1.0).abs() < 0.01,
        "spent {spent} J, G_c A = {} J",
        g_c * area
    );
    let sliding = late.iter().sum::<f64>() / late.len() as f64;
    assert!(
        (sliding / friction - 1.0).abs() < 0.05,
        "sliding force {sliding} N"
    );
}
