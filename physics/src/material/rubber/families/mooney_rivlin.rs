//! Mooney–Rivlin rubber (model §1.10): ψ_iso = C₁₀(Ī₁ − 3) + C₀₁(Ī₂ − 3), μ₀ = 2(C₁₀ + C₀₁).

use super::{
    admit, invariant_stress, Family, IsoPoint, Matrix, ParamError, RubberParam, RubberSpec,
};
use super::{RubberValues, Volumetric, FINITE};
use serde::Serialize;

const C10: RubberParam = RubberParam {
    range: FINITE,
    ..super::neo_hookean::C10
};

const C01: RubberParam = RubberParam {
    key: "c01",
    symbol: "C₀₁",
    unit: "Pa",
    meaning: "coefficient of (Ī₂ − 3)",
    range: FINITE,
    list: false,
    optional: false,
};

pub const SPEC: RubberSpec = RubberSpec {
    key: "mooney_rivlin",
    label: "Mooney–Rivlin",
    energy: "ψ_iso = C₁₀(Ī₁ − 3) + C₀₁(Ī₂ − 3); μ₀ = 2(C₁₀ + C₀₁) > 0",
    params: &[C10, C01],
};

/// ψ_iso = C₁₀(Ī₁ − 3) + C₀₁(Ī₂ − 3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MooneyRivlin {
    pub c10: f64,
    pub c01: f64,
}

impl MooneyRivlin {
    /// (ψ_iso, ∂ψ_iso/∂Ī₁, ∂ψ_iso/∂Ī₂) at (Ī₁, Ī₂).
    #[inline(always)]
    pub fn psi(&self, i1: f64, i2: f64) -> (f64, f64, f64) {
        (
            self.c10 * (i1 - 3.0) + self.c01 * (i2 - 3.0),
            self.c10,
            self.c01,
        )
    }
}

impl Family for MooneyRivlin {
    const SPEC: RubberSpec = SPEC;

    /// The two constants; μ₀ = 2(C₁₀ + C₀₁) must be positive (else the material is unstable at
    /// the reference state).
    fn from_values(v: &dyn RubberValues) -> Result<Self, ParamError> {
        let m = MooneyRivlin {
            c10: admit(&C10, v.number("c10"), SPEC.key)?,
            c01: admit(&C01, v.number("c01"), SPEC.key)?,
        };
        if !(m.initial_shear_modulus() > 0.0) {
            return Err(ParamError {
                key: "c01",
                value: format!("{:?}", m.c01),
                reason: format!(
                    "the initial shear modulus μ₀ = 2(C₁₀ + C₀₁) = {:?} Pa must be > 0 (C₁₀ = {:?} Pa): the material would be unstable at rest",
                    m.initial_shear_modulus(),
                    m.c10
                ),
            });
        }
        Ok(m)
    }

    /// μ₀ = 2(C₁₀ + C₀₁).
    fn initial_shear_modulus(&self) -> f64 {
        2.0 * (self.c10 + self.c01)
    }

    fn describe(&self) -> Vec<String> {
        vec![
            format!("C₁₀ = {:.4e} Pa", self.c10),
            format!("C₀₁ = {:.4e} Pa", self.c01),
        ]
    }

    #[inline(always)]
    fn piola_iso<const ENERGY: bool>(&self, x: &IsoPoint) -> (Matrix, f64) {
        invariant_stress::<ENERGY>(x, |i1, i2| self.psi(i1, i2))
    }

    fn example() -> (Self, Volumetric) {
        let m = MooneyRivlin {
            c10: 0.3e6,
            c01: 0.05e6,
        };
        (m, Volumetric::Log)
    }

    fn scaled(&self, s: f64) -> Self {
        MooneyRivlin {
            c10: s * self.c10,
            c01: s * self.c01,
        }
    }
}
