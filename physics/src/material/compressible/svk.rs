//! Saint-Venant–Kirchhoff (model §1.3, paper eq. 9): its stress and energy density over any
//! [`Real`], and the bound of its tangent modulus that certifies the stable step (model §6.4).

use super::Compressible;
use crate::material::kinematics::{doubled_green_lagrange, f_times_s};
use crate::material::{gershgorin, gershgorin_lane, Deformation, Law, Mat3, Material, Real};

/// Saint-Venant–Kirchhoff as a [`Law`]: P = F·S with S of [`saint_venant_kirchhoff`].
pub struct Svk;

impl Compressible for Svk {
    const LABEL: &'static str = "Saint-Venant–Kirchhoff";
}

impl Law for Svk {
    /// 2E = H + Hᵀ + HᵀH, S of [`saint_venant_kirchhoff`], then P = F·S = S + H·S.
    #[inline(always)]
    fn piola<T: Real, const ENERGY: bool, const FMA: bool>(
        mat: &Material,
        d: &Deformation<T>,
    ) -> (Mat3<T>, T) {
        let g = doubled_green_lagrange::<T, FMA>(&d.h);
        let (s, psi) = saint_venant_kirchhoff::<T, ENERGY, FMA>(mat.lambda, mat.mu, &g);
        (f_times_s::<T, FMA>(&d.h, &s), psi)
    }

    /// P = F S, S = λ tr E I + 2μE: G:A:G = S:(GᵀG) + λ(tr Y)² + 2μ|Y|² with Y = sym(FᵀG),
    /// tr Y = F:G, so (tr Y)² ≤ tr C |G|² (Cauchy–Schwarz), |Y|² ≤ ĉ|G|² and
    /// λ_max(S) ≤ λ tr E + μ(ĉ − 1): a = max(λ, 0) tr C + 2μĉ + λ tr E + μ(ĉ − 1), ĉ ≥ λ_max(C)
    /// by Gershgorin's row sums (exact for a diagonal C). 3λ + 2μ at F = I.
    #[inline(always)]
    fn modulus_bound(mat: &Material, _: &[[f64; 3]; 3], c: &[[f64; 3]; 3]) -> f64 {
        let (lambda, mu) = (mat.lambda, mat.mu);
        let c_hat = gershgorin(c);
        let tr_c = c[0][0] + c[1][1] + c[2][2];
        let tr_e = 0.5 * (tr_c - 3.0);
        lambda.max(0.0) * tr_c + 2.0 * mu * c_hat + lambda * tr_e + mu * (c_hat - 1.0)
    }

    #[inline(always)]
    fn modulus_lanes(mat: &Material, _: &Mat3<[f64; 8]>, c: &Mat3<[f64; 8]>) -> [f64; 8] {
        let (lambda, mu) = (mat.lambda, mat.mu);
        let mut a = [0.0; 8];
        for q in 0..8 {
            let c_hat = gershgorin_lane(c, q);
            let tr_c = c[0][0][q] + c[1][1][q] + c[2][2][q];
            let tr_e = 0.5 * (tr_c - 3.0);
            a[q] = lambda.max(0.0) * tr_c + 2.0 * mu * c_hat + lambda * tr_e + mu * (c_hat - 1.0);
        }
        a
    }
}

/// Saint-Venant–Kirchhoff (model §1.3, paper eq. 9): second Piola–Kirchhoff stress
/// S = λ tr(E) I + 2μE and energy density ψ = ½λ(tr E)² + μ E:E, from G = 2E
/// (`kinematics::doubled_green_lagrange`): S = ½λ tr(G) I + μG and
/// ψ = ⅛λ(tr G)² + ¼μ G:G with G:G = (G₀₀² + G₁₁² + G₂₂²) + 2(G₀₁² + G₀₂² + G₁₂²) (G symmetric:
/// only its entries i ≤ j are read, and S is formed on them and mirrored). Multiply–adds fused
/// when `FMA`. ψ only if `ENERGY` (else 0). The one definition of the model: every kernel
/// calls it.
#[inline(always)]
pub fn saint_venant_kirchhoff<T: Real, const ENERGY: bool, const FMA: bool>(
    lambda: f64,
    mu: f64,
    g: &Mat3<T>,
) -> (Mat3<T>, T) {
    let m = T::splat(mu);
    let tr = (g[0][0] + g[1][1]) + g[2][2];
    let lt = T::splat(0.5 * lambda) * tr;
    let mut s = *g;
    for i in 0..3 {
        s[i][i] = m.fmadd::<FMA>(g[i][i], lt);
        for j in i + 1..3 {
            s[i][j] = m * g[i][j];
            s[j][i] = s[i][j];
        }
    }
    let mut psi = T::splat(0.0);
    if ENERGY {
        let diag = g[2][2].fmadd::<FMA>(g[2][2], g[1][1].fmadd::<FMA>(g[1][1], g[0][0] * g[0][0]));
        let off = g[1][2].fmadd::<FMA>(g[1][2], g[0][2].fmadd::<FMA>(g[0][2], g[0][1] * g[0][1]));
        let gg = off.fmadd::<FMA>(T::splat(2.0), diag);
        psi = (T::splat(0.125 * lambda) * tr).fmadd::<FMA>(tr, T::splat(0.25 * mu) * gg);
    }
    (s, psi)
}
