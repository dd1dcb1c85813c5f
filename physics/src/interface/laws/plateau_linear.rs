//! `plateau_linear`, the paper's fig. 5 (model §2.6): g_N = g_N(0) on [0, α_e], then a linear
//! decrease to 0 at u_r.

use crate::interface::family::{Family, Knots, Param, ParamValues, ALPHA_E, G_N0, R_T, U_R};
use crate::interface::law::{LawError, StiffnessLaw};

/// Plateau then linear decrease of the stiffness; no data beyond g_N(0), α_e, u_r.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateauLinear;

impl Family for PlateauLinear {
    const KEY: &'static str = "plateau_linear";
    const LABEL: &'static str = "plateau–linear (paper fig. 5)";
    const DESCRIPTION: &'static str = "g_N = g_N(0) on [0, α_e], then linear to 0 at u_r.";
    const PARAMS: &'static [Param] = &[G_N0, ALPHA_E, U_R, R_T];

    /// Admissible as soon as g_N(0) > 0, α_e ≥ 0 and u_r > α_e: g_N is then non-increasing
    /// and g_N(u_r) = 0 by construction.
    fn build(values: &ParamValues) -> Result<(Self, Knots), LawError> {
        Ok((PlateauLinear, Knots::from_values(values)?))
    }

    /// g_N(α) = g_N(0) (u_r − α)/(u_r − α_e).
    #[inline]
    fn softening(&self, law: &StiffnessLaw, alpha: f64) -> f64 {
        let span = law.u_r - law.alpha_e;
        law.g_n0 * (law.u_r - alpha) / span
    }

    /// G_c = ½ g_N(0) α_e² + g_N(0)/(u_r − α_e) · [u_r (u_r² − α_e²)/2 − (u_r³ − α_e³)/3].
    fn fracture_energy(&self, law: &StiffnessLaw) -> f64 {
        let (g0, ae, ur) = (law.g_n0, law.alpha_e, law.u_r);
        law.elastic_energy()
            + g0 / (ur - ae)
                * (ur * (ur * ur - ae * ae) / 2.0 - (ur * ur * ur - ae * ae * ae) / 3.0)
    }

    /// T(δ) = g_N(0) δ (u_r − δ)/(u_r − α_e) peaks at δ = u_r/2 when that is past α_e.
    fn peak_candidates(&self, law: &StiffnessLaw, consider: &mut dyn FnMut(f64)) {
        if law.u_r > 2.0 * law.alpha_e {
            consider(law.u_r / 2.0);
        }
    }
}
