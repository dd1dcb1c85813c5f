//! `bk`, mixed-mode bilinear softening with the Benzeggagh–Kenane criterion (model §2.11):
//! fracture energies G_Ic and G_IIc, and at mode mixity B = r_T|[u]_T|²/f² (the shear share of
//! the stored energy, f the damage measure of `damage.rs`)
//!
//! G_c(B) = G_Ic + (G_IIc − G_Ic) B^η,   f₀(B)² = f₀,I² + (f₀,II² − f₀,I²) B^η,
//! f_f(B) = 2 G_c(B) / (g_N(0) f₀(B))
//!
//! (Camanho–Dávila; Turon et al. 2010 for the onset), with the damage of a bilinear law in f,
//! d(f, B) = f_f (f − f₀) / (f (f_f − f₀)) on (f₀, f_f), 0 before, 1 after.
//!
//! **On the α machinery.** The node keeps, in its α slot, the *mode-I-equivalent opening*: the
//! opening α̂ at which the mode-I law (onset f₀,I = α_e, final u_r = 2 G_Ic/(g_N(0) α_e)) has the
//! damage d(f, B), α̂ = u_r α_e / (u_r − d (u_r − α_e)) (α̂ = f α_e/f₀(B) before the onset), and
//! α' = min(u_r, max(α, α̂)) (eq. 12 on α̂). g_N(α) is the bilinear g_N(0) α_e (u_r − α) /
//! (α (u_r − α_e)) = g_N(0)(1 − d_I(α)): a non-increasing function of a history that never
//! decreases, so D = −½ g_N′(α) α̇ f² ≥ 0 under any path, mixity changes included. Under
//! proportional loading g_N(α) = g_N(0)(1 − d(f, B)) is the mixed-mode bilinear law in f, whose
//! work of separation is ½ g_N(0) f₀(B) f_f(B) = G_c(B): G_Ic in mode I, G_IIc in mode II.
//!
//! With the default mode-II onset (Turon's consistency condition for the one stiffness g_N of f,
//! f₀,II = α_e √(G_IIc/G_Ic), i.e. the shear strength τ₀ = σ₀ √(r_T G_IIc/G_Ic)), f₀(B) and
//! f_f(B) are the mode-I ones times s(B) = √(G_c(B)/G_Ic), and α̂ = f/s(B) exactly; with
//! G_IIc = G_Ic, s = 1 and the law is `bilinear`'s.

use crate::interface::family::{
    DamageStep, Family, Knots, Param, ParamValues, Range, ALPHA_E, G_N0, R_T,
};
use crate::interface::law::{LawError, StiffnessLaw};

/// G_Ic, G_IIc, η, the mode-II onset as given, and f₀,II.
#[derive(Debug, Clone, PartialEq)]
pub struct Bk {
    /// Mode-I fracture energy G_Ic [J/m²].
    pub g_ic: f64,
    /// Mode-II fracture energy G_IIc [J/m²].
    pub g_iic: f64,
    /// Benzeggagh–Kenane exponent η [–].
    pub eta: f64,
    /// Tangential jump at the mode-II onset as the scene gives it [m]; 0: Turon's default.
    pub alpha_e_ii: f64,
    /// The mode-II onset of the damage measure, f₀,II = √r_T α_e,II (Turon's α_e √(G_IIc/G_Ic)
    /// by default) [m].
    f0_ii: f64,
}

const G_IC: Param = Param::number("g_ic", "G_Ic", "J/m²", Range::above(0.0), 2e3)
    .meaning("mode-I fracture energy (pure opening); sets u_r = 2 G_Ic/(g_N(0) α_e)")
    .editor([1e-2, 1e6], true);
const G_IIC: Param = Param::number("g_iic", "G_IIc", "J/m²", Range::above(0.0), 4e3)
    .meaning("mode-II fracture energy (pure shear)")
    .editor([1e-2, 1e6], true);
const ETA: Param = Param::number("eta", "η", "–", Range::above(0.0), 2.0)
    .meaning("Benzeggagh–Kenane exponent: G_c(B) = G_Ic + (G_IIc − G_Ic) B^η")
    .editor([0.2, 10.0], true)
    .optional();
const ALPHA_E_II: Param = Param::number("alpha_e_ii", "α_e,II", "m", Range::at_least(0.0), 0.0)
    .meaning(
        "tangential jump at the mode-II onset; 0: Turon's τ₀ = σ₀ √(r_T G_IIc/G_Ic), \
         i.e. α_e √(G_IIc/(r_T G_Ic))",
    )
    .editor([0.0, 0.05], false)
    .optional();

impl Bk {
    /// G_c(B) = G_Ic + (G_IIc − G_Ic) B^η [J/m²] at the mode mixity B ∈ [0, 1].
    pub fn critical_energy(&self, b: f64) -> f64 {
        self.g_ic + (self.g_iic - self.g_ic) * b.powf(self.eta)
    }

    /// (f₀(B), f_f(B)) [m]: the onset and the final value of the damage measure at mixity B.
    pub fn onset_and_final(&self, law: &StiffnessLaw, b: f64) -> (f64, f64) {
        let x = b.powf(self.eta);
        let f0 = (law.alpha_e.powi(2) + (self.f0_ii.powi(2) - law.alpha_e.powi(2)) * x).sqrt();
        let gc = self.g_ic + (self.g_iic - self.g_ic) * x;
        (f0, 2.0 * gc / (law.g_n0 * f0))
    }

    /// The mode mixity B = r|[u]_T|²/f² ∈ [0, 1] (0 at f = 0).
    #[inline]
    pub fn mixity(f: f64, shear: f64) -> f64 {
        if f > 0.0 {
            (shear / (f * f)).min(1.0)
        } else {
            0.0
        }
    }
}

impl Family for Bk {
    const KEY: &'static str = "bk";
    const LABEL: &'static str = "Benzeggagh–Kenane (mixed-mode bilinear: G_Ic, G_IIc, η)";
    const DESCRIPTION: &'static str = "Mixed-mode bilinear softening with the Benzeggagh–Kenane criterion: at mode mixity B = r_T|[u]_T|²/f² the work of separation is G_c(B) = G_Ic + (G_IIc − G_Ic) B^η (G_Ic in pure opening, G_IIc in pure shear). Its α (recorded, `initial_damage`) is the mode-I-equivalent opening: the opening at which the mode-I bilinear law (onset α_e, rupture u_r = 2 G_Ic/(g_N(0) α_e)) has the same damage; g_N(α) is that law's, g_N(0) α_e (u_r − α)/(α (u_r − α_e)), and α never decreases, so D ≥ 0 under any path.";
    const PARAMS: &'static [Param] = &[
        G_N0,
        ALPHA_E.narrowed(Range::above(0.0), "the mode-I peak traction is g_N(0)·α_e"),
        G_IC,
        G_IIC,
        ETA,
        R_T,
        ALPHA_E_II,
    ];

    /// Admissible when each pure mode has a softening range, f_f > f₀: mode I
    /// 2 G_Ic > g_N(0) α_e² (u_r > α_e), mode II 2 G_IIc > g_N(0) f₀,II². 2 G_c(B) − g_N(0) f₀(B)²
    /// is affine in B^η ∈ [0, 1], so it is then > 0 at every mixity: f_f(B) > f₀(B), d(f, B) is
    /// increasing in f, and g_N is the bilinear law's (non-increasing, 0 at u_r).
    fn build(values: &ParamValues) -> Result<(Self, Knots), LawError> {
        let (g_n0, alpha_e) = (values.number(G_N0.key)?, values.number(ALPHA_E.key)?);
        let (g_ic, g_iic) = (values.number(G_IC.key)?, values.number(G_IIC.key)?);
        let (eta, r_t) = (values.number(ETA.key)?, values.number(R_T.key)?);
        let alpha_e_ii = values.number(ALPHA_E_II.key)?;
        let u_r = 2.0 * g_ic / (g_n0 * alpha_e);
        if !(u_r.is_finite() && u_r > alpha_e) {
            return Err(LawError::new(
                G_IC.key,
                g_ic,
                format!(
                    "G_Ic must be > ½ g_N(0) α_e² = {} J/m² (the energy stored at the mode-I \
                     onset; u_r = 2 G_Ic/(g_N(0) α_e) must be finite and > α_e)",
                    0.5 * g_n0 * alpha_e * alpha_e
                ),
            ));
        }
        let f0_ii = if alpha_e_ii == 0.0 {
            alpha_e * (g_iic / g_ic).sqrt()
        } else {
            r_t.sqrt() * alpha_e_ii
        };
        // With Turon's onset this is the mode-I condition again (mode II is mode I scaled by
        // √(G_IIc/G_Ic)), up to round-off at its edge.
        if !(2.0 * g_iic > g_n0 * f0_ii * f0_ii) {
            let (key, value) = match alpha_e_ii {
                0.0 => (G_IIC.key, g_iic),
                _ => (ALPHA_E_II.key, alpha_e_ii),
            };
            return Err(LawError::new(
                key,
                value,
                format!(
                    "the mode-II softening range is empty: the energy stored at the mode-II \
                     onset, ½ g_N(0) r_T α_e,II² = {} J/m², must be < G_IIc = {g_iic} J/m², i.e. \
                     α_e,II < √(2 G_IIc/(g_N(0) r_T)) = {} m",
                    0.5 * g_n0 * f0_ii * f0_ii,
                    (2.0 * g_iic / (g_n0 * r_t)).sqrt()
                ),
            ));
        }
        let own = Bk {
            g_ic,
            g_iic,
            eta,
            alpha_e_ii,
            f0_ii,
        };
        Ok((own, Knots { g_n0, alpha_e, u_r }))
    }

    fn values(&self, law: &StiffnessLaw) -> ParamValues {
        ParamValues::default()
            .with(G_N0.key, law.g_n0)
            .with(ALPHA_E.key, law.alpha_e)
            .with(G_IC.key, self.g_ic)
            .with(G_IIC.key, self.g_iic)
            .with(ETA.key, self.eta)
            .with(ALPHA_E_II.key, self.alpha_e_ii)
    }

    /// g_N(α) = g_N(0) α_e (u_r − α) / (α (u_r − α_e)): the mode-I bilinear law of the
    /// mode-I-equivalent opening α.
    #[inline]
    fn softening(&self, law: &StiffnessLaw, alpha: f64) -> f64 {
        let span = law.u_r - law.alpha_e;
        law.g_n0 * law.alpha_e * (law.u_r - alpha) / (alpha * span)
    }

    /// The mode-I one, G_Ic = ½ g_N(0) α_e u_r (to round-off); mode II dissipates G_IIc and
    /// mixity B dissipates G_c(B) (model §2.11).
    fn fracture_energy(&self, law: &StiffnessLaw) -> f64 {
        0.5 * law.g_n0 * law.alpha_e * law.u_r
    }

    /// Eq. 12 (or its delay, §2.9) on the mode-I-equivalent opening of f at its mixity.
    #[inline]
    fn next_damage(&self, law: &StiffnessLaw, s: DamageStep, alpha_s: &mut f64) -> f64 {
        let f = self.damage_opening(law, s.f, s.shear);
        law.rate_independent_or_delayed(DamageStep { f, ..s }, alpha_s)
    }

    /// α̂ with d_I(α̂) = d(f, B) (module doc): f/s(B) with Turon's onset, else
    /// f α_e/f₀(B) before the onset, u_r α_e/(u_r − d (u_r − α_e)) on the softening branch,
    /// u_r from f_f(B) on.
    #[inline]
    fn damage_opening(&self, law: &StiffnessLaw, f: f64, shear: f64) -> f64 {
        let b = Bk::mixity(f, shear);
        if self.alpha_e_ii == 0.0 {
            let ratio = 1.0 + (self.g_iic / self.g_ic - 1.0) * b.powf(self.eta);
            return f / ratio.sqrt();
        }
        let (f0, ff) = self.onset_and_final(law, b);
        if f <= f0 {
            f * law.alpha_e / f0
        } else if f >= ff {
            law.u_r
        } else {
            let d = ff * (f - f0) / (f * (ff - f0));
            law.u_r * law.alpha_e / (law.u_r - d * (law.u_r - law.alpha_e))
        }
    }
}
