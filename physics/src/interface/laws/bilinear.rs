//! `bilinear`, the usual linear-softening cohesive law (model §2.6): past α_e,
//! g_N(α) = g_N(0) α_e (u_r − α) / (α (u_r − α_e)), so that T(δ) = g_N(δ)δ falls linearly from
//! g_N(0)α_e at α_e to 0 at u_r.

use crate::interface::family::{Family, Knots, Param, ParamValues, Range, ALPHA_E, G_N0, R_T, U_R};
use crate::interface::law::{LawError, StiffnessLaw};

/// Linear-softening traction; no data beyond g_N(0), α_e, u_r.
#[derive(Debug, Clone, PartialEq)]
pub struct Bilinear;

impl Family for Bilinear {
    const KEY: &'static str = "bilinear";
    const LABEL: &'static str = "bilinear (linear-softening traction)";
    const DESCRIPTION: &'static str = "Linear-softening traction: past α_e, g_N(α) = g_N(0) α_e (u_r − α) / (α (u_r − α_e)), so that T = g_N δ falls linearly from g_N(0) α_e at α_e to 0 at u_r.";
    const PARAMS: &'static [Param] = &[
        G_N0,
        ALPHA_E.narrowed(
            Range::above(0.0),
            "the bilinear law's peak traction is g_N(0)·α_e",
        ),
        U_R,
        R_T,
    ];

    /// Admissible as soon as g_N(0) > 0, α_e > 0 and u_r > α_e: g_N is then non-increasing
    /// (T falls while δ grows) and g_N(u_r) = 0.
    fn build(values: &ParamValues) -> Result<(Self, Knots), LawError> {
        Ok((Bilinear, Knots::from_values(values)?))
    }

    /// g_N(α) = g_N(0) α_e (u_r − α) / (α (u_r − α_e)).
    #[inline]
    fn softening(&self, law: &StiffnessLaw, alpha: f64) -> f64 {
        let span = law.u_r - law.alpha_e;
        law.g_n0 * law.alpha_e * (law.u_r - alpha) / (alpha * span)
    }

    /// G_c = ½ g_N(0) α_e u_r: the triangle under T(δ) (plateau ½ g_N(0)α_e² plus the softening
    /// ½ g_N(0)α_e (u_r − α_e)).
    fn fracture_energy(&self, law: &StiffnessLaw) -> f64 {
        0.5 * law.g_n0 * law.alpha_e * law.u_r
    }
}
