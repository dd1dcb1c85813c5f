//! `exponential` (model §2.6): past α_e, g_N(α) = g_N(0) exp(−k (α − α_e)/(u_r − α_e)), cut
//! to 0 at u_r; k is the decay over the softening range (dimensionless).

use crate::interface::family::{Family, Knots, Param, ParamValues, Range, ALPHA_E, G_N0, R_T, U_R};
use crate::interface::law::{LawError, StiffnessLaw};

/// Exponential decrease of the stiffness past α_e.
#[derive(Debug, Clone, PartialEq)]
pub struct Exponential {
    /// Decay exponent k over the softening range (dimensionless, > 0).
    pub decay: f64,
}

/// The decay k: a scene may leave it out (k = 5: g_N falls to 0.7 % of g_N(0) just before u_r).
const DECAY: Param = Param::number("decay", "k", "–", Range::above(0.0), 5.0)
    .meaning("decay exponent over the softening range")
    .editor([0.1, 50.0], false)
    .optional();

impl Family for Exponential {
    const KEY: &'static str = "exponential";
    const LABEL: &'static str = "exponential (cut to 0 at u_r)";
    const DESCRIPTION: &'static str =
        "Past α_e, g_N(α) = g_N(0) exp(−k (α − α_e)/(u_r − α_e)), cut to 0 at u_r.";
    const PARAMS: &'static [Param] = &[G_N0, ALPHA_E, U_R, DECAY, R_T];

    /// Admissible as soon as g_N(0) > 0, α_e ≥ 0, u_r > α_e and k > 0: g_N then decreases and
    /// is cut to 0 at u_r.
    fn build(values: &ParamValues) -> Result<(Self, Knots), LawError> {
        let decay = values.number(DECAY.key)?;
        Ok((Exponential { decay }, Knots::from_values(values)?))
    }

    fn values(&self, law: &StiffnessLaw) -> ParamValues {
        law.knots().values().with(DECAY.key, self.decay)
    }

    /// g_N(α) = g_N(0) exp(−k (α − α_e)/(u_r − α_e)).
    #[inline]
    fn softening(&self, law: &StiffnessLaw, alpha: f64) -> f64 {
        let span = law.u_r - law.alpha_e;
        law.g_n0 * (-self.decay * (alpha - law.alpha_e) / span).exp()
    }

    /// G_c = ½ g_N(0) α_e² + g_N(0) [α_e L (1 − e^{−k})/k + L² (1 − e^{−k}(1 + k))/k²],
    /// L = u_r − α_e.
    fn fracture_energy(&self, law: &StiffnessLaw) -> f64 {
        let (g0, ae, ur) = (law.g_n0, law.alpha_e, law.u_r);
        let (k, l) = (self.decay, ur - ae);
        let e = (-k).exp();
        law.elastic_energy()
            + g0 * (ae * l * (1.0 - e) / k + l * l * (1.0 - e * (1.0 + k)) / (k * k))
    }
}
