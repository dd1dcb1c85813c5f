//! Isochoric neo-Hookean rubber (model §1.10): ψ_iso = C₁₀(Ī₁ − 3), μ₀ = 2C₁₀.

use super::Volumetric;
use super::{
    admit, invariant_stress, Family, IsoPoint, Matrix, ParamError, RubberParam, RubberSpec,
    RubberValues,
};
use crate::interface::family::Range;
use serde::Serialize;

/// C₁₀, shared with the other invariant families.
pub const C10: RubberParam = RubberParam {
    key: "c10",
    symbol: "C₁₀",
    unit: "Pa",
    meaning: "coefficient of (Ī₁ − 3)",
    range: Range::above(0.0),
    list: false,
    optional: false,
};

pub const SPEC: RubberSpec = RubberSpec {
    key: "isochoric_neo_hookean",
    label: "neo-Hookean (isochoric/volumetric split)",
    energy: "ψ_iso = C₁₀(Ī₁ − 3); μ₀ = 2C₁₀",
    params: &[C10],
};

/// ψ_iso = C₁₀(Ī₁ − 3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NeoHookean {
    pub c10: f64,
}

impl NeoHookean {
    /// (ψ_iso, ∂ψ_iso/∂Ī₁, ∂ψ_iso/∂Ī₂) at Ī₁.
    #[inline(always)]
    pub fn psi(&self, i1: f64) -> (f64, f64, f64) {
        (self.c10 * (i1 - 3.0), self.c10, 0.0)
    }
}

impl Family for NeoHookean {
    const SPEC: RubberSpec = SPEC;

    fn from_values(v: &dyn RubberValues) -> Result<Self, ParamError> {
        Ok(NeoHookean {
            c10: admit(&C10, v.number("c10"), SPEC.key)?,
        })
    }

    /// μ₀ = 2C₁₀.
    fn initial_shear_modulus(&self) -> f64 {
        2.0 * self.c10
    }

    fn describe(&self) -> Vec<String> {
        vec![format!("C₁₀ = {:.4e} Pa", self.c10)]
    }

    #[inline(always)]
    fn piola_iso<const ENERGY: bool>(&self, x: &IsoPoint) -> (Matrix, f64) {
        invariant_stress::<ENERGY>(x, |i1, _| self.psi(i1))
    }

    fn example() -> (Self, Volumetric) {
        (NeoHookean { c10: 0.4e6 }, Volumetric::Quadratic)
    }

    fn scaled(&self, s: f64) -> Self {
        NeoHookean { c10: s * self.c10 }
    }
}
