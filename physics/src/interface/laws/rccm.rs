//! `rccm`, the original RCCM law (Raous–Cangémi–Cocou–Monerie, after Frémond; model
//! §2.10): an adhesion intensity β ∈ [0, 1] (1 sound), R_N = C_N β² ⟨[u]_N⟩₊ on
//! opening, R_T = C_T β² [u]_T, and Frémond's evolution with the Dupré energy w and viscosity b,
//!
//! b β̇ = −[w − β (C_N ⟨[u]_N⟩₊² + C_T |[u]_T|²)]⁻,   β irreversible (β̇ ≤ 0).
//!
//! **On the α machinery.** With r = C_T/C_N and f = (⟨[u]_N⟩₊² + r|[u]_T|²)^½ (the damage
//! measure of `damage.rs`), the energy release is Y = C_N f². The node keeps, in its α slot, the
//! *equivalent opening* α = u₀/√β (α ≤ u₀ while β = 1), u₀ = √(w/C_N): the mode-I opening at
//! which the rate-independent law has that β. Then g_N(α) = C_N β² = C_N min(1, (u₀/α)⁴) is a
//! non-increasing stiffness of α like every family's, α never decreases (β never increases),
//! μ(α) = μ_inf(1 − g_N/g_N(0)) = μ_inf(1 − β²) (eq. 21) and the ledger's
//! ΔD = ½W(g_N⁻ − g_N)(…) is the released spring energy, −∫ β̇ β Y = w(1 − β) + ∫ b β̇² ≥ 0:
//! the Dupré energy plus the viscous dissipation. With b = 0, β = min(β, w/Y) is α' = max(α, f),
//! eq. 12 without the cap, so the work of separation is w in every mode (T(δ) = C_N δ up to u₀,
//! then w²/(C_N δ³)): peak √(w C_N) at δ = u₀.
//!
//! **States and rupture.** β reaches 0 at no finite opening (with b = 0, β = u₀²/f²), so the law
//! takes a parameter β_min ∈ (0, 1) (model §2.10): a β that falls below β_min is set to 0 and the
//! node is ruptured. The knots are α_e = u₀ (elastic while β = 1) and u_r = u₀/√β_min, and g_N
//! is cut at u_r like every family's. At b = 0 in mode I the work of separation is then
//! w(1 − β_min/2): the traction's work up to u_r, of which β_min w/2 is still stored there and
//! released by the cut.

use crate::interface::family::{DamageStep, Family, Knots, Param, ParamValues, Range};
use crate::interface::law::{LawError, StiffnessLaw};

/// C_N, C_T, w, b, β_min of the law (C_N is also its g_N(0)).
#[derive(Debug, Clone, PartialEq)]
pub struct Rccm {
    /// Normal stiffness C_N [Pa/m].
    pub c_n: f64,
    /// Tangential stiffness C_T [Pa/m].
    pub c_t: f64,
    /// Dupré energy w [J/m²].
    pub w: f64,
    /// Frémond's viscosity b [J·s/m²] (0: rate-independent).
    pub b: f64,
    /// Adhesion intensity below which β is set to 0, the node ruptured [-].
    pub beta_min: f64,
}

const C_N: Param = Param::number("c_n", "C_N", "Pa/m", Range::above(0.0), 5e8)
    .meaning("normal stiffness of the sound glue")
    .editor([1e5, 1e12], true);
const C_T: Param = Param::number("c_t", "C_T", "Pa/m", Range::above(0.0), 5e8)
    .meaning("tangential stiffness of the sound glue")
    .editor([1e5, 1e12], true);
const W: Param = Param::number("w", "w", "J/m²", Range::above(0.0), 2e3)
    .meaning("Dupré energy (work of separation at b = 0)")
    .editor([1e-2, 1e6], true);
const B: Param = Param::number("b", "b", "J·s/m²", Range::at_least(0.0), 0.0)
    .meaning("Frémond's viscosity (0: rate-independent)")
    .editor([0.0, 1e3], true)
    .optional();
const BETA_MIN: Param = Param::number(
    "beta_min",
    "β_min",
    "-",
    Range::between(0.0, true, 1.0, true),
    0.05,
)
.meaning("adhesion intensity below which β is set to 0: the node is ruptured")
.editor([1e-4, 0.5], true)
.optional();

impl Rccm {
    /// β = min(1, (u₀/α)²) of an equivalent opening α (module doc).
    #[inline]
    pub fn beta(law: &StiffnessLaw, alpha: f64) -> f64 {
        if alpha <= law.alpha_e {
            1.0
        } else {
            let s = law.alpha_e / alpha;
            s * s
        }
    }
}

impl Family for Rccm {
    const KEY: &'static str = "rccm";
    const LABEL: &'static str = "RCCM (original: β, C_N, C_T, w, b)";
    const DESCRIPTION: &'static str = "The original RCCM law: adhesion intensity β ∈ [0, 1], R_N = C_N β² ⟨[u]_N⟩₊ on opening, R_T = C_T β² [u]_T, Frémond's evolution b β̇ = −[w − β (C_N ⟨[u]_N⟩₊² + C_T |[u]_T|²)]⁻. Its α (recorded, `initial_damage`) is the equivalent opening u₀/√β, u₀ = √(w/C_N): elastic while β = 1; a β below β_min is set to 0 (ruptured, g_N cut at u_r = u₀/√β_min), so the work of separation is w(1 − β_min/2).";
    const PARAMS: &'static [Param] = &[C_N, C_T, W, B, BETA_MIN];
    const OPENING_ONLY: bool = true;

    /// C_N, C_T, w > 0, b ≥ 0 and 0 < β_min < 1 (their ranges) are all it needs: g_N = C_N β²
    /// is then non-increasing in α (and 0 from u_r = u₀/√β_min on) and Frémond's update never
    /// raises β.
    fn build(values: &ParamValues) -> Result<(Self, Knots), LawError> {
        let (c_n, w) = (values.number(C_N.key)?, values.number(W.key)?);
        let u0 = (w / c_n).sqrt();
        let own = Rccm {
            c_n,
            c_t: values.number(C_T.key)?,
            w,
            b: values.number(B.key)?,
            beta_min: values.number(BETA_MIN.key)?,
        };
        let knots = Knots {
            g_n0: c_n,
            alpha_e: u0,
            u_r: u0 / own.beta_min.sqrt(),
        };
        Ok((own, knots))
    }

    fn values(&self, _law: &StiffnessLaw) -> ParamValues {
        ParamValues::default()
            .with(C_N.key, self.c_n)
            .with(C_T.key, self.c_t)
            .with(W.key, self.w)
            .with(B.key, self.b)
            .with(BETA_MIN.key, self.beta_min)
    }

    /// g_N(α) = C_N β² = C_N (u₀/α)⁴ past u₀ (0 from u_r on: the cut every family has).
    #[inline]
    fn softening(&self, law: &StiffnessLaw, alpha: f64) -> f64 {
        let beta = Rccm::beta(law, alpha);
        law.g_n0 * beta * beta
    }

    /// The work of separation ∫₀^{u_r} T dδ = ½ C_N u₀² + ∫_{u₀}^{u_r} w²/(C_N δ³) dδ
    /// = w/2 + (w/2)(1 − u₀²/u_r²) = w(1 − β_min/2).
    fn fracture_energy(&self, _law: &StiffnessLaw) -> f64 {
        self.w * (1.0 - 0.5 * self.beta_min)
    }

    /// r = C_T/C_N.
    fn tangential_ratio(&self) -> f64 {
        self.c_t / self.c_n
    }

    /// Frémond's evolution by the implicit (backward Euler) step over h, in closed form: with
    /// β = β(α) and Y = C_N f² at the end of the step, nothing happens while βY ≤ w, else
    /// b(β' − β)/h = w − β'Y gives β' = (bβ + hw)/(b + hY) ∈ (0, β) for any h (and β'Y ≥ w, the
    /// branch is consistent); b = 0 gives β' = w/Y, i.e. α' = max(α, f). α' = u₀/√β'.
    fn next_damage(&self, law: &StiffnessLaw, s: DamageStep, _alpha_s: &mut f64) -> f64 {
        let DamageStep { alpha, f, h, .. } = s;
        if self.b == 0.0 {
            return alpha.max(f);
        }
        let beta = Rccm::beta(law, alpha);
        let y = law.g_n0 * f * f;
        if beta * y <= self.w {
            return alpha;
        }
        let beta_next = (self.b * beta + h * self.w) / (self.b + h * y);
        alpha.max(law.alpha_e / beta_next.sqrt())
    }

    fn refuses_delay(&self) -> Option<&'static str> {
        Some("the `rccm` law takes no [interface.delay]: its rate effect is Frémond's viscosity b (`interface.law.b`)")
    }
}
