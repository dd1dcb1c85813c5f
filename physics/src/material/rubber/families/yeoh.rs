//! Yeoh rubber (model §1.10): ψ_iso = C₁₀(Ī₁ − 3) + C₂₀(Ī₁ − 3)² + C₃₀(Ī₁ − 3)³, μ₀ = 2C₁₀.

use super::{
    admit, invariant_stress, Family, IsoPoint, Matrix, ParamError, RubberParam, RubberSpec,
};
use super::{RubberValues, Volumetric, FINITE};
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

impl Family for Yeoh {
    const SPEC: RubberSpec = SPEC;

    /// C₁₀ > 0 (μ₀ > 0); C₂₀ and C₃₀ any, 0 when left out.
    fn from_values(v: &dyn RubberValues) -> Result<Self, ParamError> {
        Ok(Yeoh {
            c10: admit(&super::neo_hookean::C10, v.number("c10"), SPEC.key)?,
            c20: admit(&C20, v.number("c20"), SPEC.key)?,
            c30: admit(&C30, v.number("c30"), SPEC.key)?,
        })
    }

    /// μ₀ = 2C₁₀.
    fn initial_shear_modulus(&self) -> f64 {
        2.0 * self.c10
    }

    fn describe(&self) -> Vec<String> {
        vec![
            format!("C₁₀ = {:.4e} Pa", self.c10),
            format!("C₂₀ = {:.4e} Pa", self.c20),
            format!("C₃₀ = {:.4e} Pa", self.c30),
        ]
    }

    #[inline(always)]
    fn piola_iso<const ENERGY: bool>(&self, x: &IsoPoint) -> (Matrix, f64) {
        invariant_stress::<ENERGY>(x, |i1, _| self.psi(i1))
    }

    fn example() -> (Self, Volumetric) {
        let m = Yeoh {
            c10: 0.5e6,
            c20: -0.02e6,
            c30: 0.001e6,
        };
        (m, Volumetric::Quadratic)
    }

    fn scaled(&self, s: f64) -> Self {
        Yeoh {
            c10: s * self.c10,
            c20: s * self.c20,
            c30: s * self.c30,
        }
    }
}
