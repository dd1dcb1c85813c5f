//! The RCCM interface stiffness law g_N(α) and everything derived from it (model §2).
//!
//! Conventions: α is the damage variable in metres (the largest jump norm ever reached, capped
//! at u_r), g_N is a stiffness per unit area in Pa/m, tractions are in Pa, energies per unit area
//! in J/m². The undamaged stiffness is always written `g_n0` = g_N(0).
//!
//! A law is built from its family's row of the table ([`families`], [`family`]) and parameter
//! values ([`ParamValues`]); each family is one file of `interface/laws/`.

use serde::Serialize;
use std::fmt;

pub use super::damage::Loading;
use super::damage::{damage_update, weighted_damage_measure, weighted_damage_split};
pub use super::delay::Delay;
pub use super::family::{
    families, family, family_or_error, DamageStep, Family, FamilySpec, Knots, NumberParam, Param,
    ParamKind, ParamValue, ParamValues, Range, R_T,
};
pub use super::laws::LawKind;

/// A validated stiffness law: a non-increasing g_N on [0, u_r] with g_N(α ≥ u_r) = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct StiffnessLaw {
    kind: LawKind,
    /// Undamaged stiffness g_N(0) [Pa/m].
    pub g_n0: f64,
    /// End of the elastic range α_e [m].
    pub alpha_e: f64,
    /// Rupture opening u_r [m].
    pub u_r: f64,
    /// How the jump is loaded: g_T/g_N and the normal jump on opening only (`damage.rs`).
    loading: Loading,
    /// `[interface.delay]`, if any: the damage follows eq. 12 at a bounded rate.
    delay: Option<Delay>,
}

/// Why a law is not admissible (model §2.5). `key` names the offending
/// parameter so the scene loader can point at it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {reason}")]
pub struct LawError {
    pub key: String,
    pub value: String,
    /// What is admissible.
    pub reason: String,
}

impl LawError {
    pub fn new(key: &str, value: impl ToString, reason: impl Into<String>) -> Self {
        LawError {
            key: key.to_string(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

impl StiffnessLaw {
    /// Builds and checks a law of the family of that key (see [`FamilySpec::build`]).
    pub fn build(key: &str, values: &ParamValues) -> Result<Self, LawError> {
        family_or_error(key)?.build(values)
    }

    /// A law of family `F` (see [`FamilySpec::build`]).
    pub fn of<F: Family>(values: &ParamValues) -> Result<Self, LawError> {
        FamilySpec::of::<F>().build(values)
    }

    /// The law of `kind` with these knots and loading, checked by its family.
    pub(super) fn from_parts(kind: LawKind, knots: Knots, loading: Loading) -> Self {
        StiffnessLaw {
            kind,
            g_n0: knots.g_n0,
            alpha_e: knots.alpha_e,
            u_r: knots.u_r,
            loading,
            delay: None,
        }
    }

    /// This law with delayed damage (`Some`) or rate-independent (`None`); refused, naming
    /// `delay`, by a family with a rate effect of its own (`rccm`).
    pub fn with_delay(mut self, delay: Option<Delay>) -> Result<Self, LawError> {
        if let (Some(d), Some(reason)) = (delay, self.kind.refuses_delay()) {
            return Err(LawError::new(
                "delay",
                format!("tau_c = {}", d.tau_c),
                reason,
            ));
        }
        self.delay = delay;
        self.loading.nonnegative_dissipation = delay.is_some();
        Ok(self)
    }

    /// The delay of `[interface.delay]`, if any.
    pub fn delay(&self) -> Option<Delay> {
        self.delay
    }

    /// How the jump is loaded: g_T/g_N and whether the normal jump is loaded on opening only;
    /// its [`Loading::dissipation_increment`] is the ledger's ΔD for this law.
    pub fn loading(&self) -> Loading {
        self.loading
    }

    /// Its family, with the family's own data.
    pub fn kind(&self) -> &LawKind {
        &self.kind
    }

    /// Its family's row of the table: key, label, parameters.
    pub fn spec(&self) -> &'static FamilySpec {
        self.kind.spec()
    }

    /// The parameter values that build this law again (a scene's `[interface.law]` table
    /// without `family`); r_T only when it is not its default 1.
    pub fn values(&self) -> ParamValues {
        let values = self.kind.values(self);
        match self.spec().param(R_T.key) {
            Some(_) if self.loading.ratio != 1.0 => values.with(R_T.key, self.loading.ratio),
            _ => values,
        }
    }

    /// g_N(0), α_e, u_r.
    pub fn knots(&self) -> Knots {
        Knots {
            g_n0: self.g_n0,
            alpha_e: self.alpha_e,
            u_r: self.u_r,
        }
    }

    /// Interface stiffness g_N(α) [Pa/m] (model §2.6): g_N(0) on [0, α_e], 0 for α ≥ u_r,
    /// non-increasing in between according to the family.
    #[inline]
    pub fn g_n(&self, alpha: f64) -> f64 {
        if alpha <= self.alpha_e {
            return self.g_n0;
        }
        if alpha >= self.u_r {
            return 0.0;
        }
        self.kind.softening(self, alpha)
    }

    /// The stiffest spring of the node, max(g_N, g_T)(α) = max(1, r) g_N(α) [Pa/m]: what the
    /// stable-step estimate (model §6.1) puts on the diagonal.
    #[inline]
    pub fn spring_stiffness(&self, alpha: f64) -> f64 {
        self.g_n(alpha) * self.loading.ratio.max(1.0)
    }

    /// Damage measure f = (⟨[u]_N⟩₊² + r|[u]_T|²)^½ of a jump (`damage.rs`).
    #[inline]
    pub fn damage_measure(&self, jump: [f64; 3], n: [f64; 3]) -> f64 {
        weighted_damage_measure(jump, n, self.loading.ratio)
    }

    /// α₀ = min(u_r, max(initial damage, f₀)) (eq. 12 with the damage the interface had before
    /// the run; for `bk`, f₀ mapped to its mode-I-equivalent opening, model §2.11); a delayed
    /// law starts with α = α_s = α₀.
    pub fn initial_damage(&self, initial: f64, jump: [f64; 3], n: [f64; 3]) -> f64 {
        let (f, shear) = weighted_damage_split(jump, n, self.loading.ratio);
        damage_update(initial, self.kind.damage_opening(self, f, shear), self.u_r)
    }

    /// Stage 8 (model §4.8): α at the end of an interval `h` over which the jump reaches
    /// `jump`, from α and α_s (updated here when the law is delayed), by the family's update.
    #[inline]
    pub fn next_damage(
        &self,
        alpha: f64,
        alpha_s: &mut f64,
        jump: [f64; 3],
        n: [f64; 3],
        h: f64,
    ) -> f64 {
        let (f, shear) = weighted_damage_split(jump, n, self.loading.ratio);
        let step = DamageStep { alpha, f, h, shear };
        self.kind.next_damage(self, step, alpha_s)
    }

    /// Eq. 12, α' = min(u_r, max(α, f)), without a delay (α_s is α: `alpha_s` is neither read
    /// nor written); with one, α_s' = min(u_r, max(α_s, f)) and α' = α advanced towards α_s'
    /// over `h` by the exact solution of the delay ODE ([`Delay::advance`]).
    #[inline]
    pub fn rate_independent_or_delayed(&self, s: DamageStep, alpha_s: &mut f64) -> f64 {
        let DamageStep { alpha, f, h, .. } = s;
        match &self.delay {
            None => damage_update(alpha, f, self.u_r),
            Some(d) => {
                *alpha_s = damage_update(*alpha_s, f, self.u_r);
                d.advance(alpha, *alpha_s, self.u_r, h)
            }
        }
    }

    /// Cohesive traction R_d [Pa] at stiffness g_N(α) = `stiffness` (`damage.rs`).
    #[inline]
    pub fn cohesive_traction(&self, stiffness: f64, jump: [f64; 3], n: [f64; 3]) -> [f64; 3] {
        self.loading.traction(stiffness, jump, n)
    }

    /// Stored energy Ψ_d of one node [J] (`damage.rs`, model §2.2).
    #[inline]
    pub fn stored_energy(&self, area: f64, stiffness: f64, jump: [f64; 3], n: [f64; 3]) -> f64 {
        self.loading.stored_energy(area, stiffness, jump, n)
    }

    /// T(δ) under pure normal opening at the constant rate `rate` [m/s], with the law's own
    /// update (the delay, `rccm`'s viscosity): (δ, T) at `steps` + 1 openings over
    /// [0, `delta_max`]. Without a rate effect it is [`StiffnessLaw::traction`].
    pub fn traction_at_rate(&self, rate: f64, delta_max: f64, steps: usize) -> Vec<[f64; 2]> {
        let (n, dt) = ([0.0, 0.0, 1.0], delta_max / (steps as f64 * rate));
        let (mut alpha, mut alpha_s) = (0.0, 0.0);
        (0..=steps)
            .map(|k| {
                let delta = delta_max * k as f64 / steps as f64;
                if k > 0 {
                    alpha = self.next_damage(alpha, &mut alpha_s, [0.0, 0.0, delta], n, dt);
                }
                [delta, self.g_n(alpha) * delta]
            })
            .collect()
    }

    /// Friction coefficient grown by damage, paper eq. 21: μ(α) = μ_inf (1 − g_N(α)/g_N(0)).
    #[inline]
    pub fn mu(&self, alpha: f64, mu_inf: f64) -> f64 {
        mu_inf * (1.0 - self.g_n(alpha) / self.g_n0)
    }

    /// Traction under monotonic opening, T(δ) = g_N(δ) δ [Pa] (model §2.7).
    #[inline]
    pub fn traction(&self, delta: f64) -> f64 {
        self.g_n(delta) * delta
    }

    /// Energy stored at the end of the elastic range, ½ g_N(0) α_e² [J/m²]: the plateau's share
    /// of G_c.
    pub fn elastic_energy(&self) -> f64 {
        0.5 * self.g_n0 * self.alpha_e * self.alpha_e
    }

    /// Fracture energy G_c = ∫₀^{u_r} g_N(δ) δ dδ [J/m²], in closed form for each family
    /// (model §2.7; the bilinear value is ½ g_N(0) α_e u_r).
    pub fn fracture_energy(&self) -> f64 {
        self.kind.fracture_energy(self)
    }

    /// Peak of T(δ) over [0, u_r] and where it is reached: (T_max [Pa], δ [m]). Evaluated on a
    /// fine sampling and the family's candidates (relative accuracy ~1e-8 for the smooth
    /// families).
    pub fn peak_traction(&self) -> (f64, f64) {
        let mut best = (self.traction(self.alpha_e), self.alpha_e);
        let mut consider = |d: f64| {
            let t = self.traction(d);
            if t > best.0 {
                best = (t, d);
            }
        };
        let n = 20_000;
        for i in 0..=n {
            consider(self.u_r * i as f64 / n as f64 * (1.0 - 1e-15));
        }
        self.kind.peak_candidates(self, &mut consider);
        best
    }

    /// Elastic / transition / ruptured classification of a node, paper fig. 6 (model §2.8).
    #[inline]
    pub fn state(&self, alpha: f64) -> InterfaceState {
        if alpha <= self.alpha_e {
            InterfaceState::Elastic
        } else if alpha < self.u_r {
            InterfaceState::Transition
        } else {
            InterfaceState::Ruptured
        }
    }
}

/// As a scene's `[interface.law]` table: `family` and the parameter values.
impl Serialize for StiffnessLaw {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Table<'a> {
            family: &'a str,
            #[serde(flatten)]
            values: ParamValues,
        }
        Table {
            family: self.spec().key,
            values: self.values(),
        }
        .serialize(s)
    }
}

/// One line for labels, the parameters in the family's order: `exponential (g_n0 = 200000000,
/// alpha_e = 0.001, u_r = 0.003, decay = 5)`, `table (4 points)`.
impl fmt::Display for StiffnessLaw {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let (spec, values) = (self.spec(), self.values());
        let shown: Vec<String> = (spec.params.iter())
            .filter_map(|p| match values.get(p.key)? {
                ParamValue::Number(x) => Some(format!("{} = {x}", p.key)),
                ParamValue::Points(points) => Some(format!("{} {}", points.len(), p.key)),
            })
            .collect();
        write!(f, "{} ({})", spec.key, shown.join(", "))?;
        match self.delay {
            Some(d) => write!(f, " delayed (tau_c = {}, a = {})", d.tau_c, d.a),
            None => Ok(()),
        }
    }
}

/// State of an interface node as the paper's figure 6 plots it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InterfaceState {
    /// α ≤ α_e: undamaged stiffness.
    Elastic,
    /// α_e < α < u_r: softening.
    Transition,
    /// α ≥ u_r: no cohesion left, unilateral contact with friction μ_inf.
    Ruptured,
    /// Glue that forms on contact (a `[[contact]]` entry with a `[contact.law]`) not formed
    /// yet: a contact node with Coulomb μ, no glue (g_N = 0, α = 0); not one of fig. 6's
    /// states, which are the glue's ([`crate::solver::InterfaceNode::state`]).
    Unformed,
}

#[cfg(test)]
mod tests {
    use super::super::laws::{bilinear::Bilinear, exponential::Exponential};
    use super::super::laws::{plateau_linear::PlateauLinear, rccm::Rccm, table::Table};
    use super::*;

    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut s = f(a) + f(b);
        for i in 1..n {
            s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    fn knots(g_n0: f64, alpha_e: f64, u_r: f64) -> ParamValues {
        Knots { g_n0, alpha_e, u_r }.values()
    }

    fn table(points: &[[f64; 2]]) -> Result<StiffnessLaw, LawError> {
        StiffnessLaw::of::<Table>(&ParamValues::default().with("points", points.to_vec()))
    }

    /// Some laws of each family, and every family at its defaults.
    fn laws() -> Vec<StiffnessLaw> {
        let mut laws = vec![
            StiffnessLaw::of::<PlateauLinear>(&knots(2e9, 5e-4, 1e-3)).unwrap(),
            StiffnessLaw::of::<Bilinear>(&knots(2e9, 5e-4, 3e-3)).unwrap(),
            StiffnessLaw::of::<Exponential>(&knots(2e9, 5e-4, 3e-3).with("decay", 4.0)).unwrap(),
            table(&[[0.0, 1e9], [1e-4, 1e9], [5e-4, 4e8], [2e-3, 0.0]]).unwrap(),
            StiffnessLaw::of::<Bilinear>(&knots(2e9, 5e-4, 3e-3).with("r_t", 0.3)).unwrap(),
            StiffnessLaw::of::<Rccm>(
                &ParamValues::default()
                    .with("c_n", 1e9)
                    .with("c_t", 3e8)
                    .with("w", 150.0)
                    .with("b", 2.0),
            )
            .unwrap(),
        ];
        laws.extend(families().iter().map(|f| f.build(&f.defaults()).unwrap()));
        laws
    }

    #[test]
    fn closed_form_fracture_energy_matches_quadrature() {
        for law in &laws() {
            // Integrate piecewise so the kink at α_e (and the table's points) falls on a node.
            let mut cuts = vec![0.0, law.alpha_e, law.u_r];
            law.kind.peak_candidates(law, &mut |d| cuts.push(d));
            cuts.sort_by(f64::total_cmp);
            cuts.dedup();
            let num: f64 = cuts
                .windows(2)
                .map(|w| {
                    simpson(
                        |d| law.traction(d.min(w[1] * (1.0 - 1e-14))),
                        w[0],
                        w[1],
                        2000,
                    )
                })
                .sum::<f64>()
                + tail(law);
            let exact = law.fracture_energy();
            // Simpson on smooth pieces with 2000 panels: error ≪ 1e-9 relative.
            assert!(
                (num - exact).abs() <= 1e-8 * exact,
                "{law}: {num} vs {exact}"
            );
        }
    }

    /// ∫_{u_r}^∞ T dδ (0 for a law cut at u_r), by δ = u_r/s: ∫₀¹ T(u_r/s) u_r/s² ds, whose
    /// integrand is smooth (∝ s for `rccm`'s T ∝ δ⁻³).
    fn tail(law: &StiffnessLaw) -> f64 {
        let f = |s: f64| {
            if s == 0.0 {
                0.0
            } else {
                law.traction(law.u_r / s) * law.u_r / (s * s)
            }
        };
        simpson(f, 0.0, 1.0, 2000)
    }

    /// Model §2.6: g_N(0) on [0, α_e], non-increasing, 0 from u_r on; and the values a law gives back build the same law.
    #[test]
    fn every_law_is_admissible_and_rebuilds_from_its_values() {
        for law in &laws() {
            let n = 1000;
            let mut previous = law.g_n(0.0);
            assert_eq!(previous, law.g_n0, "{law}");
            assert_eq!(law.g_n(law.alpha_e), law.g_n0, "{law}");
            for i in 1..=n {
                let g = law.g_n(law.u_r * i as f64 / n as f64);
                assert!(g <= previous && g >= 0.0, "{law}: g_N grows at step {i}");
                previous = g;
            }
            assert_eq!(law.g_n(law.u_r), 0.0, "{law}");
            assert_eq!(
                &StiffnessLaw::build(law.spec().key, &law.values()).unwrap(),
                law
            );
        }
    }

    #[test]
    fn inadmissible_laws_are_refused_with_the_reason() {
        let e = StiffnessLaw::of::<PlateauLinear>(&knots(1e9, 1e-3, 1e-3)).unwrap_err();
        assert_eq!(e.key, "u_r");
        assert!(e.reason.contains("> α_e = 0.001 m"), "{e}");
        let e = StiffnessLaw::of::<PlateauLinear>(&knots(-1.0, 1e-4, 1e-3)).unwrap_err();
        assert_eq!((e.key.as_str(), e.value.as_str()), ("g_n0", "-1"));
        assert_eq!(e.reason, "g_N(0) must be finite and > 0 (Pa/m)");
        let e = StiffnessLaw::of::<Bilinear>(&knots(1e9, 0.0, 1e-3)).unwrap_err();
        assert_eq!(e.key, "alpha_e");
        assert!(e.reason.contains("> 0 (m); the bilinear law"), "{e}");
        let e =
            StiffnessLaw::of::<Exponential>(&knots(1e9, 0.0, 1e-3).with("decay", 0.0)).unwrap_err();
        assert_eq!(e.reason, "k must be finite and > 0 (–)");
        let e = table(&[[0.0, 1.0], [1.0, 2.0], [2.0, 0.0]]).unwrap_err();
        assert!(e.reason.contains("non-increasing"), "{e}");
        let e = table(&[[0.0, 1.0], [1.0, 0.5]]).unwrap_err();
        assert!(e.reason.contains("g_N = 0"), "{e}");
        let e = StiffnessLaw::of::<Table>(&knots(1e9, 0.0, 1e-3)).unwrap_err();
        assert!(
            e.reason.contains("not a parameter of the `table` law"),
            "{e}"
        );
        let e = StiffnessLaw::of::<Bilinear>(&ParamValues::default()).unwrap_err();
        assert_eq!((e.key.as_str(), e.value.as_str()), ("g_n0", "(missing)"));
        let e = StiffnessLaw::build("linear", &ParamValues::default()).unwrap_err();
        assert!(e.reason.contains("admissible: `"), "{e}");
        assert!(e.reason.contains("`bilinear`"), "{e}");
    }

    #[test]
    fn an_omitted_decay_takes_its_default() {
        let law = StiffnessLaw::of::<Exponential>(&knots(1e9, 0.0, 1e-3)).unwrap();
        assert_eq!(law.values().number("decay").unwrap(), 5.0);
    }

    #[test]
    fn bilinear_traction_is_linear_softening() {
        let law = StiffnessLaw::of::<Bilinear>(&knots(2e9, 5e-4, 3e-3)).unwrap();
        // T(δ) falls linearly from g0 α_e at α_e to 0 at u_r.
        let t = |d: f64| law.traction(d);
        let mid = 0.5 * (5e-4 + 3e-3);
        assert!((t(mid) - 0.5 * 2e9 * 5e-4).abs() < 1e-6 * 1e6);
        assert_eq!(law.peak_traction().0, 2e9 * 5e-4);
    }
}
