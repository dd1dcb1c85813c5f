//! Yeoh rubber (model §1.10): ψ_iso = C₁₀(Ī₁ − 3) + C₂₀(Ī₁ − 3)² + C₃₀(Ī₁ − 3)³, μ₀ = 2C₁₀.

use super::{admit, ParamError, RubberParam, RubberSpec, RubberValues, FINITE};
use serde::Serialize;

const C20: RubberParam = RubberParam {
    key: "c20",
    symbol: "C₂₀",
    unit: "Pa",
    meaning: "coefficient of (Ī₁ − 3)²",
    range: FINITE,
    list: false,
    optional: true,
};

const C30: RubberParam = RubberParam {
    key: "c30",
    symbol: "C₃₀",
    unit: "Pa",
    meaning: "coefficient of (Ī₁ − 3)³",
    range: FINITE,
    list: false,
    optional: true,
};

pub const SPEC: RubberSpec = RubberSpec {
    key: "yeoh",
    label: "Yeoh",
    energy: "ψ_iso = C₁₀(Ī₁ − 3) + C₂₀(Ī₁ − 3)² + C₃₀(Ī₁ − 3)³; μ₀ = 2C₁₀",
    params: &[super::neo_hookean::C10, C20, C30],
};

/// ψ_iso = C₁₀(Ī₁ − 3) + C₂₀(Ī₁ − 3)² + C₃₀(Ī₁ − 3)³.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Yeoh {
    pub c10: f64,
    pub c20: f64,
    pub c30: f64,
}

impl Yeoh {
    /// C₁₀ > 0 (μ₀ > 0); C₂₀ and C₃₀ any, 0 when left out.
    pub fn from_values(v: &dyn RubberValues) -> Result<Self, ParamError> {
        Ok(Yeoh {
            c10: admit(&super::neo_hookean::C10, v.number("c10"), SPEC.key)?,
            c20: admit(&C20, v.number("c20"), SPEC.key)?,
            c30: admit(&C30, v.number("c30"), SPEC.key)?,
        })
    }

    /// μ₀ = 2C₁₀.
    pub fn initial_shear_modulus(&self) -> f64 {
        2.0 * self.c10
    }

    /// (ψ_iso, ∂ψ_iso/∂Ī₁, ∂ψ_iso/∂Ī₂) at Ī₁: with x = Ī₁ − 3,
    /// ψ₁ = C₁₀ + 2C₂₀x + 3C₃₀x².
    #[inline(always)]
    pub fn psi(&self, i1: f64) -> (f64, f64, f64) {
        let x = i1 - 3.0;
        let w = x * (self.c10 + x * (self.c20 + x * self.c30));
        let w1 = self.c10 + x * (2.0 * self.c20 + x * 3.0 * self.c30);
        (w, w1, 0.0)
    }
}
