//! Ogden rubber (model §1.10): ψ_iso = Σᵢ (μᵢ/αᵢ)(λ̄₁^αᵢ + λ̄₂^αᵢ + λ̄₃^αᵢ − 3), N ≤ 3 pairs,
//! λ̄ₐ = J^{-1/3} λₐ the isochoric principal stretches, μ₀ = ½ Σᵢ μᵢαᵢ.

use super::{
    admit, right_cauchy_green, symmetric_eigen, IsoPoint, Matrix, ParamError, RubberParam,
    RubberSpec,
};
use super::{Family, RubberValues, Volumetric, FINITE};
use serde::Serialize;

const MU: RubberParam = RubberParam {
    key: "mu",
    symbol: "μᵢ",
    unit: "Pa",
    meaning: "moduli μ₁ … μ_N (1 to 3)",
    range: FINITE,
    list: true,
    optional: false,
};

const ALPHA: RubberParam = RubberParam {
    key: "alpha",
    symbol: "αᵢ",
    unit: "–",
    meaning: "exponents α₁ … α_N, non-zero, as many as μᵢ",
    range: FINITE,
    list: true,
    optional: false,
};

pub const SPEC: RubberSpec = RubberSpec {
    key: "ogden",
    label: "Ogden",
    energy: "ψ_iso = Σᵢ (μᵢ/αᵢ)(λ̄₁^αᵢ + λ̄₂^αᵢ + λ̄₃^αᵢ − 3), N ≤ 3; μ₀ = ½Σμᵢαᵢ > 0",
    params: &[MU, ALPHA],
};

/// The N ≤ 3 pairs (μᵢ, αᵢ); the pairs past `n` are unused.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Ogden {
    pub n: usize,
    pub mu: [f64; 3],
    pub alpha: [f64; 3],
}

impl Ogden {
    /// Σᵢ μᵢ λ̄^αᵢ from λ̄² (= λ̄ ∂w/∂λ̄ for w(λ̄) = Σᵢ (μᵢ/αᵢ)λ̄^αᵢ), and w(λ̄).
    #[inline(always)]
    fn beta_w(&self, lb2: f64) -> (f64, f64) {
        let (mut b, mut w) = (0.0, 0.0);
        for i in 0..self.n {
            let x = lb2.powf(0.5 * self.alpha[i]);
            b += self.mu[i] * x;
            w += self.mu[i] / self.alpha[i] * (x - 1.0);
        }
        (b, w)
    }

    /// (P_iso, ψ_iso) from F and J^{-2/3} (model §1.10): C = FᵀF = Σₐ cₐ Nₐ⊗Nₐ
    /// ([`symmetric_eigen`]), λ̄ₐ² = J^{-2/3}cₐ, βₐ = Σᵢ μᵢ λ̄ₐ^αᵢ, β̄ = ⅓Σₐβₐ; the isochoric
    /// principal Kirchhoff stresses τₐ = βₐ − β̄, S_iso = Σₐ (τₐ/cₐ) Nₐ⊗Nₐ, P_iso = F S_iso;
    /// ψ_iso = Σₐ w(λ̄ₐ). (S_iso is the same whichever basis of a repeated eigenvalue's space:
    /// equal cₐ give equal τₐ/cₐ.) ψ only if `ENERGY`.
    #[inline]
    pub fn stress<const ENERGY: bool>(&self, f: &[[f64; 3]; 3], j23: f64) -> ([[f64; 3]; 3], f64) {
        let (c, v) = symmetric_eigen(right_cauchy_green(f));
        let mut beta = [0.0; 3];
        let mut psi = 0.0;
        for a in 0..3 {
            let (b, w) = self.beta_w(j23 * c[a]);
            beta[a] = b;
            psi += w;
        }
        let mean = (beta[0] + beta[1] + beta[2]) / 3.0;
        let coef: [f64; 3] = std::array::from_fn(|a| (beta[a] - mean) / c[a]);
        let mut s = [[0.0; 3]; 3];
        for (i, si) in s.iter_mut().enumerate() {
            for (k, sik) in si.iter_mut().enumerate() {
                *sik = coef[0] * v[i][0] * v[k][0]
                    + coef[1] * v[i][1] * v[k][1]
                    + coef[2] * v[i][2] * v[k][2];
            }
        }
        let p = std::array::from_fn(|i| {
            std::array::from_fn(|k| f[i][0] * s[0][k] + f[i][1] * s[1][k] + f[i][2] * s[2][k])
        });
        (p, if ENERGY { psi } else { 0.0 })
    }
}

impl Family for Ogden {
    const SPEC: RubberSpec = SPEC;

    /// 1 to 3 pairs, αᵢ ≠ 0, μ₀ = ½Σμᵢαᵢ > 0 (else the material is unstable at rest).
    fn from_values(v: &dyn RubberValues) -> Result<Self, ParamError> {
        let list = |p: &RubberParam| -> Result<Vec<f64>, ParamError> {
            let Some(x) = v.list(p.key) else {
                return Err(ParamError {
                    key: p.key,
                    value: "(missing)".into(),
                    reason: format!("the `ogden` model takes {}: {}", p.symbol, p.meaning),
                });
            };
            if x.is_empty() || x.len() > 3 {
                return Err(ParamError {
                    key: p.key,
                    value: format!("{x:?}"),
                    reason: format!("{}: 1 to 3 numbers", p.meaning),
                });
            }
            for &xi in &x {
                admit(p, Some(xi), SPEC.key)?;
            }
            Ok(x)
        };
        let (mu, alpha) = (list(&MU)?, list(&ALPHA)?);
        if mu.len() != alpha.len() {
            return Err(ParamError {
                key: "alpha",
                value: format!("{alpha:?}"),
                reason: format!("as many exponents αᵢ as moduli μᵢ ({} given)", mu.len()),
            });
        }
        if alpha.contains(&0.0) {
            return Err(ParamError {
                key: "alpha",
                value: format!("{alpha:?}"),
                reason: "every αᵢ must be non-zero (ψ_iso divides by it)".into(),
            });
        }
        let mut o = Ogden {
            n: mu.len(),
            mu: [0.0; 3],
            alpha: [1.0; 3],
        };
        o.mu[..o.n].copy_from_slice(&mu);
        o.alpha[..o.n].copy_from_slice(&alpha);
        let mu0 = o.initial_shear_modulus();
        if !(mu0 > 0.0) {
            return Err(ParamError {
                key: "mu",
                value: format!("{mu:?}"),
                reason: format!(
                    "the initial shear modulus μ₀ = ½Σμᵢαᵢ = {mu0:?} Pa (α = {alpha:?}) must be > 0: the set fails Drucker's stability at rest"
                ),
            });
        }
        Ok(o)
    }

    /// μ₀ = ½ Σᵢ μᵢαᵢ.
    fn initial_shear_modulus(&self) -> f64 {
        0.5 * (0..self.n).map(|i| self.mu[i] * self.alpha[i]).sum::<f64>()
    }

    fn describe(&self) -> Vec<String> {
        let list = |x: &[f64]| {
            let v: Vec<String> = x.iter().map(|x| format!("{x:.4e}")).collect();
            format!("[{}]", v.join(", "))
        };
        vec![
            format!("μᵢ = {} Pa", list(&self.mu[..self.n])),
            format!("αᵢ = {}", list(&self.alpha[..self.n])),
        ]
    }

    #[inline(always)]
    fn piola_iso<const ENERGY: bool>(&self, x: &IsoPoint) -> (Matrix, f64) {
        self.stress::<ENERGY>(x.f, x.j23)
    }

    fn example() -> (Self, Volumetric) {
        let m = Ogden {
            n: 3,
            mu: [0.63e6, 0.0012e6, -0.01e6],
            alpha: [1.3, 5.0, -2.0],
        };
        (m, Volumetric::Log)
    }

    fn scaled(&self, s: f64) -> Self {
        Ogden {
            mu: self.mu.map(|x| s * x),
            ..*self
        }
    }
}
