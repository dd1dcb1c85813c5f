//! The compressible neo-Hookean (model §1.4): its stress and energy density over any [`Real`],
//! and the bound of its tangent modulus that certifies the stable step (model §6.4).

use super::Compressible;
use crate::material::kinematics::cofactor;
use crate::material::{gershgorin, gershgorin_lane, Deformation, Law, Mat3, Material, Real};

/// The compressible neo-Hookean as a [`Law`]: P and ψ of [`neo_hookean`] from F and J.
pub struct NeoHookean;

impl Compressible for NeoHookean {
    const LABEL: &'static str = "compressible neo-Hookean";
}

impl Law for NeoHookean {
    #[inline(always)]
    fn piola<T: Real, const ENERGY: bool, const FMA: bool>(
        mat: &Material,
        d: &Deformation<T>,
    ) -> (Mat3<T>, T) {
        neo_hookean::<T, ENERGY>(mat.lambda, mat.mu, &d.f, d.j)
    }

    /// P = μF + (λ ln J − μ)F⁻ᵀ: G:A:G = μ|G|² + λ(tr B)² + (μ − λ ln J) tr(B²) with B = F⁻¹G,
    /// tr B = F⁻ᵀ:G, so (tr B)² ≤ |F⁻ᵀ|²|G|² = tr C⁻¹ |G|², |tr B²| ≤ |B|² ≤ ŝ|G|²:
    /// a = μ + max(λ, 0) tr C⁻¹ + |μ − λ ln J| ŝ, C⁻¹ = adj C/J², ŝ ≥ λ_max(C⁻¹) by Gershgorin's
    /// row sums. 3λ + 2μ at F = I; +∞ for a non-positive J (an inverted element: no bound).
    #[inline(always)]
    fn modulus_bound(mat: &Material, f: &[[f64; 3]; 3], c: &[[f64; 3]; 3]) -> f64 {
        let (lambda, mu) = (mat.lambda, mat.mu);
        let j = f[0][0] * (f[1][1] * f[2][2] - f[1][2] * f[2][1])
            - f[0][1] * (f[1][0] * f[2][2] - f[1][2] * f[2][0])
            + f[0][2] * (f[1][0] * f[2][1] - f[1][1] * f[2][0]);
        if !(j > 0.0) {
            return f64::INFINITY;
        }
        // C⁻¹ = adj(C)/det C, det C = J².
        let adj = [
            [
                c[1][1] * c[2][2] - c[1][2] * c[2][1],
                c[0][2] * c[2][1] - c[0][1] * c[2][2],
                c[0][1] * c[1][2] - c[0][2] * c[1][1],
            ],
            [
                c[1][2] * c[2][0] - c[1][0] * c[2][2],
                c[0][0] * c[2][2] - c[0][2] * c[2][0],
                c[0][2] * c[1][0] - c[0][0] * c[1][2],
            ],
            [
                c[1][0] * c[2][1] - c[1][1] * c[2][0],
                c[0][1] * c[2][0] - c[0][0] * c[2][1],
                c[0][0] * c[1][1] - c[0][1] * c[1][0],
            ],
        ];
        let s_hat = gershgorin(&adj) / (j * j);
        let tr_c_inv = (adj[0][0] + adj[1][1] + adj[2][2]) / (j * j);
        mu + lambda.max(0.0) * tr_c_inv + (mu - lambda * j.ln()).abs() * s_hat
    }

    /// Only ln J is called lane by lane. When a lane has a non-positive J it gives +∞ and the
    /// others 0.
    #[inline(always)]
    fn modulus_lanes(mat: &Material, f: &Mat3<[f64; 8]>, c: &Mat3<[f64; 8]>) -> [f64; 8] {
        type Lanes = [f64; 8];
        let (lambda, mu) = (mat.lambda, mat.mu);
        let mut a: Lanes = [0.0; 8];
        let mut j: Lanes = [0.0; 8];
        let mut adj = [[[0.0f64; 8]; 3]; 3];
        for q in 0..8 {
            let m = |r: usize, s: usize| c[r][s][q];
            for r in 0..3 {
                for s in 0..3 {
                    let (r1, r2, s1, s2) = ((s + 1) % 3, (s + 2) % 3, (r + 1) % 3, (r + 2) % 3);
                    adj[r][s][q] = m(r1, s1) * m(r2, s2) - m(r1, s2) * m(r2, s1);
                }
            }
            let fm = |r: usize, s: usize| f[r][s][q];
            j[q] = fm(0, 0) * (fm(1, 1) * fm(2, 2) - fm(1, 2) * fm(2, 1))
                - fm(0, 1) * (fm(1, 0) * fm(2, 2) - fm(1, 2) * fm(2, 0))
                + fm(0, 2) * (fm(1, 0) * fm(2, 1) - fm(1, 1) * fm(2, 0));
        }
        if j.iter().any(|&jq| !(jq > 0.0)) {
            return j.map(|jq| if jq > 0.0 { 0.0 } else { f64::INFINITY });
        }
        let ln_j: Lanes = j.map(f64::ln);
        for q in 0..8 {
            let s_hat = gershgorin_lane(&adj, q) / (j[q] * j[q]);
            let tr_c_inv = (adj[0][0][q] + adj[1][1][q] + adj[2][2][q]) / (j[q] * j[q]);
            a[q] = mu + lambda.max(0.0) * tr_c_inv + (mu - lambda * ln_j[q]).abs() * s_hat;
        }
        a
    }
}

/// Compressible neo-Hookean (model §1.4): ψ = ½μ(tr C − 3) − μ ln J + ½λ(ln J)² and
/// S = μ(I − C⁻¹) + λ ln J C⁻¹, C = FᵀF, evaluated as the first Piola–Kirchhoff stress
/// P = F·S = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ with F⁻ᵀ = cof(F)/J, i.e. P = μF + (λ ln J − μ)·(1/J)·cof F,
/// and tr C = Σᵢₖ Fᵢₖ². ψ only if `ENERGY` (else 0). J ≤ 0 (an inverted element) gives NaN or
/// infinities: the caller checks J. The one definition of the model: every kernel calls it.
#[inline(always)]
pub fn neo_hookean<T: Real, const ENERGY: bool>(
    lambda: f64,
    mu: f64,
    f: &Mat3<T>,
    j: T,
) -> (Mat3<T>, T) {
    let lnj = j.ln();
    let cof = cofactor(f);
    let coef = (T::splat(lambda) * lnj - T::splat(mu)) * (T::splat(1.0) / j);
    let mut p = cof;
    let mut trc = T::splat(0.0);
    for i in 0..3 {
        for k in 0..3 {
            p[i][k] = T::splat(mu) * f[i][k] + coef * cof[i][k];
            trc = trc + f[i][k] * f[i][k];
        }
    }
    let mut psi = T::splat(0.0);
    if ENERGY {
        psi = T::splat(0.5 * mu) * (trc - T::splat(3.0)) - T::splat(mu) * lnj
            + T::splat(0.5 * lambda) * lnj * lnj;
    }
    (p, psi)
}
