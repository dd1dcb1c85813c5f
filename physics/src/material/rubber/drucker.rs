//! Drucker stability of a rubber material's isochoric part (model §1.10) over the stretches of
//! the three standard tests.
//!
//! On the incompressible manifold, with the logarithmic strains e₁, e₂ (e₃ = −e₁ − e₂) and
//! W(e₁, e₂) = ψ_iso(e^{e₁}, e^{e₂}, e^{−e₁−e₂}), the stress differences are tᵢ = ∂W/∂eᵢ =
//! τᵢ − τ₃ (τ the principal Kirchhoff stresses; the pressure drops out) and
//! dσ : dε = Σᵢⱼ Dᵢⱼ deᵢ deⱼ with D = ∂t/∂e, the Hessian of W. Drucker's condition
//! dσ : dε > 0 for every de holds when D is positive definite: D₁₁ + D₂₂ > 0 and
//! D₁₁D₂₂ − D₁₂D₂₁ > 0 (the check of Abaqus' "hyperelastic material stability"). D is formed by
//! central differences of t, t from the material's own stress ([`super::piola_energy`] with
//! K = 0), along the uniaxial (λ, λ^{-½}, λ^{-½}), equibiaxial (λ, λ, λ^{-2}) and planar
//! (λ, 1, λ^{-1}) paths, from λ = 1 out to [`DRUCKER_STRETCH_MAX`] and in to 1/[`DRUCKER_STRETCH_MAX`].

use super::{piola_energy, Rubber};
pub use crate::tunables::DRUCKER_STRETCH_MAX;
use crate::tunables::{DRUCKER_SAMPLES, DRUCKER_STEP};

/// A standard homogeneous test of an incompressible material.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// (λ, λ^{-½}, λ^{-½}).
    Uniaxial,
    /// (λ, λ, λ^{-2}).
    Equibiaxial,
    /// (λ, 1, λ^{-1}), pure shear.
    Planar,
}

impl Mode {
    pub const ALL: [Mode; 3] = [Mode::Uniaxial, Mode::Equibiaxial, Mode::Planar];

    /// (e₁, e₂) at stretch λ.
    pub fn strains(self, stretch: f64) -> [f64; 2] {
        let e = stretch.ln();
        match self {
            Mode::Uniaxial => [e, -0.5 * e],
            Mode::Equibiaxial => [e, e],
            Mode::Planar => [e, 0.0],
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Mode::Uniaxial => "uniaxial",
            Mode::Equibiaxial => "equibiaxial",
            Mode::Planar => "planar",
        }
    }
}

/// The first stretch, going out from λ = 1, at which the material is not Drucker-stable in a
/// mode (in tension, λ > 1, or in compression, λ < 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instability {
    pub mode: Mode,
    pub stretch: f64,
}

impl std::fmt::Display for Instability {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let sense = if self.stretch > 1.0 {
            "tension"
        } else {
            "compression"
        };
        write!(
            f,
            "{} {sense} from λ = {:.3}",
            self.mode.name(),
            self.stretch
        )
    }
}

/// t = (τ₁ − τ₃, τ₂ − τ₃) of the isochoric part at the logarithmic strains (e₁, e₂).
pub fn stress_differences(r: &Rubber, e: [f64; 2]) -> [f64; 2] {
    let iso = Rubber { bulk: 0.0, ..*r };
    let l = [e[0].exp(), e[1].exp(), (-e[0] - e[1]).exp()];
    let f = [[l[0], 0.0, 0.0], [0.0, l[1], 0.0], [0.0, 0.0, l[2]]];
    let (p, _) = piola_energy::<false>(&iso, &f, l[0] * l[1] * l[2]);
    let tau: [f64; 3] = std::array::from_fn(|a| p[a][a] * l[a]);
    [tau[0] - tau[2], tau[1] - tau[2]]
}

/// D = ∂t/∂e at (e₁, e₂) by central differences, symmetrised.
pub fn tangent(r: &Rubber, e: [f64; 2]) -> [[f64; 2]; 2] {
    let mut d = [[0.0; 2]; 2];
    for j in 0..2 {
        let (mut ep, mut em) = (e, e);
        ep[j] += DRUCKER_STEP;
        em[j] -= DRUCKER_STEP;
        let (tp, tm) = (stress_differences(r, ep), stress_differences(r, em));
        for i in 0..2 {
            d[i][j] = (tp[i] - tm[i]) / (2.0 * DRUCKER_STEP);
        }
    }
    let off = 0.5 * (d[0][1] + d[1][0]);
    [[d[0][0], off], [off, d[1][1]]]
}

/// Whether D at (e₁, e₂) is positive definite.
pub fn stable_at(r: &Rubber, e: [f64; 2]) -> bool {
    let d = tangent(r, e);
    d[0][0] + d[1][1] > 0.0 && d[0][0] * d[1][1] - d[0][1] * d[1][0] > 0.0
}

/// The first unstable stretch of every mode and sense (tension, compression) that has one,
/// over 1/[`DRUCKER_STRETCH_MAX`] ≤ λ ≤ [`DRUCKER_STRETCH_MAX`]; empty for a material stable throughout.
pub fn check(r: &Rubber) -> Vec<Instability> {
    let mut out = Vec::new();
    for mode in Mode::ALL {
        for sense in [1.0, -1.0] {
            let first = (0..=DRUCKER_SAMPLES)
                .map(|k| {
                    (sense * DRUCKER_STRETCH_MAX.ln() * k as f64 / DRUCKER_SAMPLES as f64).exp()
                })
                .find(|&stretch| !stable_at(r, mode.strains(stretch)));
            if let Some(stretch) = first {
                out.push(Instability { mode, stretch });
            }
        }
    }
    out
}
