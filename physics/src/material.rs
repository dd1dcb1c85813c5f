//! Hyperelastic bulk materials (PHYSICS.md §2) and the per-element internal-force kernel.
//!
//! Total Lagrangian: F = I + ∂U/∂X, E = ½(FᵀF − I), P = F·S, fₐ = Σ_q w_q det J₀ P ∇ₓNₐ.
//! The kernel evaluates the 8 Gauss points of an element as 8 SIMD lanes.

use crate::mesh::{CentreData, GaussData};
use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

/// Constitutive model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialModel {
    /// Saint-Venant–Kirchhoff: S = λ tr(E) I + 2μE, ψ = ½λ(tr E)² + μ E:E.
    Svk,
    /// Compressible neo-Hookean: S = μ(I − C⁻¹) + λ ln J C⁻¹,
    /// ψ = ½μ(tr C − 3) − μ ln J + ½λ(ln J)².
    NeoHookean,
}

/// An isotropic hyperelastic material with its Lamé constants.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Material {
    pub model: MaterialModel,
    /// Young's modulus E [Pa].
    pub young: f64,
    /// Poisson's ratio ν [-].
    pub poisson: f64,
    /// Reference density ρ₀ [kg/m³].
    pub density: f64,
    /// First Lamé constant λ = Eν/((1+ν)(1−2ν)) [Pa].
    pub lambda: f64,
    /// Shear modulus μ = E/(2(1+ν)) [Pa].
    pub mu: f64,
}

impl Material {
    /// Derives the Lamé constants from (E, ν). Validity (E > 0, −1 < ν < ½, ρ > 0) is checked by
    /// the scene loader, which knows the keys to name.
    pub fn new(model: MaterialModel, young: f64, poisson: f64, density: f64) -> Self {
        Material {
            model,
            young,
            poisson,
            density,
            lambda: young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
            mu: young / (2.0 * (1.0 + poisson)),
        }
    }

    /// Dilatational (P-) wave speed c_d = √((λ + 2μ)/ρ₀) [m/s].
    pub fn wave_speed(&self) -> f64 {
        ((self.lambda + 2.0 * self.mu) / self.density).sqrt()
    }

    /// Cauchy stress σ = J⁻¹ F S Fᵀ at one point, J = det F (PHYSICS.md §2) [Pa]
    /// (post-processing only; J ≤ 0 gives a meaningless or infinite σ, not a panic).
    pub fn cauchy_stress(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        let (s, _) = self.stress_energy(f);
        f * s * f.transpose() / f.determinant()
    }

    /// Von Mises equivalent of the Cauchy stress at one point, [`von_mises_equivalent`] of
    /// [`Material::cauchy_stress`] [Pa] (post-processing only).
    pub fn von_mises(&self, f: &Matrix3<f64>) -> f64 {
        von_mises_equivalent(&self.cauchy_stress(f))
    }

    /// Second Piola–Kirchhoff stress S(F) and energy density ψ(F) at one point (reference
    /// implementation used by tests and diagnostics; the time loop uses [`element_forces`]).
    pub fn stress_energy(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, f64) {
        let c = f.transpose() * f;
        let id = Matrix3::identity();
        match self.model {
            MaterialModel::Svk => {
                let e = (c - id) * 0.5;
                let tr = e.trace();
                let s = id * (self.lambda * tr) + e * (2.0 * self.mu);
                (
                    s,
                    0.5 * self.lambda * tr * tr + self.mu * e.component_mul(&e).sum(),
                )
            }
            MaterialModel::NeoHookean => {
                let j = f.determinant();
                let cinv = c
                    .try_inverse()
                    .unwrap_or_else(|| Matrix3::from_element(f64::NAN));
                let lnj = j.ln();
                let s = (id - cinv) * self.mu + cinv * (self.lambda * lnj);
                let psi = 0.5 * self.mu * (c.trace() - 3.0) - self.mu * lnj
                    + 0.5 * self.lambda * lnj * lnj;
                (s, psi)
            }
        }
    }
}

/// Von Mises equivalent stress σ_vm = √(3/2 s:s), s = σ − ⅓ tr σ I the deviator of σ [Pa].
pub fn von_mises_equivalent(sigma: &Matrix3<f64>) -> f64 {
    let dev = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
    (1.5 * dev.component_mul(&dev).sum()).sqrt()
}

/// Hourglass stiffness of one element, k = κ (λ + 2μ) V Σₐ bₐ·bₐ / 8 [N/m] (Flanagan–Belytschko
/// stiffness form; κ is the scene's `scheme.hourglass_coefficient`).
pub fn hourglass_stiffness(mat: &Material, cd: &CentreData, kappa: f64) -> f64 {
    kappa * (mat.lambda + 2.0 * mat.mu) * cd.volume * cd.bb / 8.0
}

/// Internal forces of one element with one-point integration and Flanagan–Belytschko hourglass
/// control (PHYSICS.md §2, the faster option):
/// F = I + Σₐ uₐ ⊗ bₐ, fₐ = V P(F) bₐ + k Σᵅ γₐᵅ qᵅ with qᵅ = Σₐ γₐᵅ uₐ,
/// hourglass energy Ψ_hg = ½ k Σᵅ |qᵅ|². Returns (strain energy V ψ(F), Ψ_hg, J) — the
/// energies only if `ENERGY`.
#[inline(always)]
pub fn element_forces_reduced<const ENERGY: bool>(
    mat: &Material,
    cd: &CentreData,
    k_hg: f64,
    u: &[[f64; 3]; 8],
    f: &mut [[f64; 3]; 8],
) -> (f64, f64, f64) {
    let mut h = [[0.0; 3]; 3];
    for a in 0..8 {
        for i in 0..3 {
            for j in 0..3 {
                h[i][j] += u[a][i] * cd.b[a][j];
            }
        }
    }
    let ff = [
        [1.0 + h[0][0], h[0][1], h[0][2]],
        [h[1][0], 1.0 + h[1][1], h[1][2]],
        [h[2][0], h[2][1], 1.0 + h[2][2]],
    ];
    let det = ff[0][0] * (ff[1][1] * ff[2][2] - ff[1][2] * ff[2][1])
        - ff[0][1] * (ff[1][0] * ff[2][2] - ff[1][2] * ff[2][0])
        + ff[0][2] * (ff[1][0] * ff[2][1] - ff[1][1] * ff[2][0]);
    let (lam, mu) = (mat.lambda, mat.mu);
    let mut p = [[0.0; 3]; 3];
    let mut psi = 0.0;
    match mat.model {
        MaterialModel::Svk => {
            // E = ½(H + Hᵀ + HᵀH), S = λ tr E I + 2μ E, P = S + H S (as the full kernel).
            let mut e = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    let c = h[0][i] * h[0][j] + h[1][i] * h[1][j] + h[2][i] * h[2][j];
                    e[i][j] = 0.5 * ((h[i][j] + h[j][i]) + c);
                }
            }
            let tr = e[0][0] + e[1][1] + e[2][2];
            let mut s = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    s[i][j] = 2.0 * mu * e[i][j] + if i == j { lam * tr } else { 0.0 };
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    p[i][j] = s[i][j] + h[i][0] * s[0][j] + h[i][1] * s[1][j] + h[i][2] * s[2][j];
                }
            }
            if ENERGY {
                let ee: f64 = e.iter().flatten().map(|v| v * v).sum();
                psi = 0.5 * lam * tr * tr + mu * ee;
            }
        }
        MaterialModel::NeoHookean => {
            // P = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ, F⁻ᵀ = cof(F)/J.
            let lnj = det.ln();
            let cof = cofactor(|i, k| ff[i][k]);
            let coef = (lam * lnj - mu) / det;
            let mut trc = 0.0;
            for i in 0..3 {
                for k in 0..3 {
                    p[i][k] = mu * ff[i][k] + coef * cof[i][k];
                    trc += ff[i][k] * ff[i][k];
                }
            }
            if ENERGY {
                psi = 0.5 * mu * (trc - 3.0) - mu * lnj + 0.5 * lam * lnj * lnj;
            }
        }
    }
    let v = cd.volume;
    let mut q = [[0.0; 3]; 4];
    for al in 0..4 {
        for a in 0..8 {
            for i in 0..3 {
                q[al][i] += cd.gamma[al][a] * u[a][i];
            }
        }
    }
    for a in 0..8 {
        for i in 0..3 {
            let mut fa = v * (p[i][0] * cd.b[a][0] + p[i][1] * cd.b[a][1] + p[i][2] * cd.b[a][2]);
            for al in 0..4 {
                fa += k_hg * cd.gamma[al][a] * q[al][i];
            }
            f[a][i] = fa;
        }
    }
    let mut e_hg = 0.0;
    if ENERGY {
        for qa in &q {
            e_hg += qa[0] * qa[0] + qa[1] * qa[1] + qa[2] * qa[2];
        }
        e_hg *= 0.5 * k_hg;
    }
    (v * psi, e_hg, det)
}

/// The one-point kernel of [`element_forces_reduced`] on 8 elements at once, one per SIMD lane
/// (`x[..][lane]`): same equations, SVK and neo-Hookean. Returns per lane (V ψ, Ψ_hg, J); the
/// energies only if `ENERGY`.
#[inline(always)]
#[allow(clippy::type_complexity)]
pub fn element_forces_reduced_lanes<const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    b: &[[[f64; 8]; 3]; 8],
    gamma: &[[[f64; 8]; 8]; 4],
    vol: &[f64; 8],
    k_hg: &[f64; 8],
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[[f64; 8]; 3]; 8],
) -> ([f64; 8], [f64; 8], [f64; 8]) {
    let mut h: Lanes = [[[0.0; 8]; 3]; 3];
    for a in 0..8 {
        for i in 0..3 {
            for j in 0..3 {
                for l in 0..8 {
                    h[i][j][l] = fmadd::<FMA>(u[a][i][l], b[a][j][l], h[i][j][l]);
                }
            }
        }
    }
    let mut ff: Lanes = h;
    for i in 0..3 {
        for l in 0..8 {
            ff[i][i][l] += 1.0;
        }
    }
    let mut det = [0.0; 8];
    for l in 0..8 {
        det[l] = ff[0][0][l] * (ff[1][1][l] * ff[2][2][l] - ff[1][2][l] * ff[2][1][l])
            - ff[0][1][l] * (ff[1][0][l] * ff[2][2][l] - ff[1][2][l] * ff[2][0][l])
            + ff[0][2][l] * (ff[1][0][l] * ff[2][1][l] - ff[1][1][l] * ff[2][0][l]);
    }
    let (lam, mu) = (mat.lambda, mat.mu);
    let mut p: Lanes = [[[0.0; 8]; 3]; 3];
    let mut psi = [0.0; 8];
    match mat.model {
        MaterialModel::Svk => {
            let mut e: Lanes = [[[0.0; 8]; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    for l in 0..8 {
                        let c = h[0][i][l] * h[0][j][l]
                            + h[1][i][l] * h[1][j][l]
                            + h[2][i][l] * h[2][j][l];
                        e[i][j][l] = 0.5 * ((h[i][j][l] + h[j][i][l]) + c);
                    }
                }
            }
            let mut s: Lanes = [[[0.0; 8]; 3]; 3];
            for l in 0..8 {
                let tr = e[0][0][l] + e[1][1][l] + e[2][2][l];
                for i in 0..3 {
                    for j in 0..3 {
                        s[i][j][l] = 2.0 * mu * e[i][j][l] + if i == j { lam * tr } else { 0.0 };
                    }
                }
                if ENERGY {
                    let mut ee = 0.0;
                    for i in 0..3 {
                        for j in 0..3 {
                            ee += e[i][j][l] * e[i][j][l];
                        }
                    }
                    psi[l] = 0.5 * lam * tr * tr + mu * ee;
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    for l in 0..8 {
                        p[i][j][l] = s[i][j][l]
                            + fmadd::<FMA>(
                                h[i][2][l],
                                s[2][j][l],
                                fmadd::<FMA>(h[i][1][l], s[1][j][l], h[i][0][l] * s[0][j][l]),
                            );
                    }
                }
            }
        }
        MaterialModel::NeoHookean => {
            for l in 0..8 {
                let fl = |i: usize, k: usize| ff[i][k][l];
                let cof = cofactor(fl);
                let lnj = det[l].ln();
                let coef = (lam * lnj - mu) / det[l];
                let mut trc = 0.0;
                for i in 0..3 {
                    for k in 0..3 {
                        p[i][k][l] = mu * fl(i, k) + coef * cof[i][k];
                        trc += fl(i, k) * fl(i, k);
                    }
                }
                if ENERGY {
                    psi[l] = 0.5 * mu * (trc - 3.0) - mu * lnj + 0.5 * lam * lnj * lnj;
                }
            }
        }
    }
    let mut q = [[[0.0; 8]; 3]; 4];
    for al in 0..4 {
        for a in 0..8 {
            for i in 0..3 {
                for l in 0..8 {
                    q[al][i][l] = fmadd::<FMA>(gamma[al][a][l], u[a][i][l], q[al][i][l]);
                }
            }
        }
    }
    for a in 0..8 {
        for i in 0..3 {
            for l in 0..8 {
                let pb = fmadd::<FMA>(
                    p[i][2][l],
                    b[a][2][l],
                    fmadd::<FMA>(p[i][1][l], b[a][1][l], p[i][0][l] * b[a][0][l]),
                );
                let mut hg = 0.0;
                for al in 0..4 {
                    hg = fmadd::<FMA>(gamma[al][a][l], q[al][i][l], hg);
                }
                f[a][i][l] = fmadd::<FMA>(vol[l], pb, k_hg[l] * hg);
            }
        }
    }
    let mut e_hg = [0.0; 8];
    let mut strain = [0.0; 8];
    if ENERGY {
        for l in 0..8 {
            let mut qq = 0.0;
            for qa in &q {
                qq += qa[0][l] * qa[0][l] + qa[1][l] * qa[1][l] + qa[2][l] * qa[2][l];
            }
            e_hg[l] = 0.5 * k_hg[l] * qq;
            strain[l] = vol[l] * psi[l];
        }
    }
    (strain, e_hg, det)
}

/// Cofactor matrix cof(F) = J F⁻ᵀ of a 3×3 matrix given by its entries.
#[inline(always)]
fn cofactor(f: impl Fn(usize, usize) -> f64) -> [[f64; 3]; 3] {
    [
        [
            f(1, 1) * f(2, 2) - f(1, 2) * f(2, 1),
            f(1, 2) * f(2, 0) - f(1, 0) * f(2, 2),
            f(1, 0) * f(2, 1) - f(1, 1) * f(2, 0),
        ],
        [
            f(0, 2) * f(2, 1) - f(0, 1) * f(2, 2),
            f(0, 0) * f(2, 2) - f(0, 2) * f(2, 0),
            f(0, 1) * f(2, 0) - f(0, 0) * f(2, 1),
        ],
        [
            f(0, 1) * f(1, 2) - f(0, 2) * f(1, 1),
            f(0, 2) * f(1, 0) - f(0, 0) * f(1, 2),
            f(0, 0) * f(1, 1) - f(0, 1) * f(1, 0),
        ],
    ]
}

/// a·b + c, fused when `FMA` (one rounding) — the choice is fixed per CPU, so results stay
/// bit-identical across thread counts.
#[inline(always)]
fn fmadd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// Per-lane 3×3 tensors: `t[i][j][q]` is component (i, j) at Gauss point q.
type Lanes = [[[f64; 8]; 3]; 3];

/// Internal nodal forces of one element, fₐ = Σ_q w_q det J₀ P(F_q) ∇ₓNₐ(ξ_q)
/// (PHYSICS.md §2, "Per step and per element only F → E → S → P = F·S → fₐ += w P ∇ₓNₐ").
///
/// `u` holds the displacements of the 8 nodes. Writes the forces into `f` and returns
/// (strain energy Σ_q w_q det J₀ ψ_q if `ENERGY`, else 0; min_q J_q).
/// `FMA` selects fused multiply–adds (used only in code compiled for CPUs that have them).
#[inline(always)]
pub fn element_forces<const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    gd: &GaussData,
    u: &[[f64; 3]; 8],
    f: &mut [[f64; 3]; 8],
) -> (f64, f64) {
    // H = ∂U/∂X = Σ_a u_a ⊗ ∇N_a (F = I + H). Strains are formed from H, not from FᵀF − I,
    // so small strains keep full relative precision.
    let mut hh: Lanes = [[[0.0; 8]; 3]; 3];
    for a in 0..8 {
        for i in 0..3 {
            let ua = u[a][i];
            for j in 0..3 {
                for q in 0..8 {
                    hh[i][j][q] = fmadd::<FMA>(ua, gd.grad[a][j][q], hh[i][j][q]);
                }
            }
        }
    }
    let mut ff: Lanes = hh;
    for i in 0..3 {
        for q in 0..8 {
            ff[i][i][q] += 1.0;
        }
    }
    // J = det F (inversion check for both models).
    let mut det = [0.0; 8];
    for q in 0..8 {
        det[q] = ff[0][0][q] * (ff[1][1][q] * ff[2][2][q] - ff[1][2][q] * ff[2][1][q])
            - ff[0][1][q] * (ff[1][0][q] * ff[2][2][q] - ff[1][2][q] * ff[2][0][q])
            + ff[0][2][q] * (ff[1][0][q] * ff[2][1][q] - ff[1][1][q] * ff[2][0][q]);
    }
    let mut min_j = det[0];
    for d in det.iter().skip(1) {
        min_j = min_j.min(*d);
    }
    let mut p: Lanes = [[[0.0; 8]; 3]; 3];
    let mut psi = [0.0; 8];
    let (lam, mu) = (mat.lambda, mat.mu);
    match mat.model {
        MaterialModel::Svk => {
            // E = ½(H + Hᵀ + HᵀH) = ½(FᵀF − I), S = λ tr E I + 2μ E, P = F S = S + H S.
            let mut e: Lanes = [[[0.0; 8]; 3]; 3];
            for i in 0..3 {
                for j in i..3 {
                    for q in 0..8 {
                        let c = hh[0][i][q] * hh[0][j][q]
                            + hh[1][i][q] * hh[1][j][q]
                            + hh[2][i][q] * hh[2][j][q];
                        e[i][j][q] = 0.5 * ((hh[i][j][q] + hh[j][i][q]) + c);
                    }
                }
            }
            let mut s: Lanes = [[[0.0; 8]; 3]; 3];
            for q in 0..8 {
                let tr = e[0][0][q] + e[1][1][q] + e[2][2][q];
                for i in 0..3 {
                    s[i][i][q] = lam * tr + 2.0 * mu * e[i][i][q];
                }
                s[0][1][q] = 2.0 * mu * e[0][1][q];
                s[0][2][q] = 2.0 * mu * e[0][2][q];
                s[1][2][q] = 2.0 * mu * e[1][2][q];
                s[1][0][q] = s[0][1][q];
                s[2][0][q] = s[0][2][q];
                s[2][1][q] = s[1][2][q];
                if ENERGY {
                    let ee = e[0][0][q] * e[0][0][q]
                        + e[1][1][q] * e[1][1][q]
                        + e[2][2][q] * e[2][2][q]
                        + 2.0
                            * (e[0][1][q] * e[0][1][q]
                                + e[0][2][q] * e[0][2][q]
                                + e[1][2][q] * e[1][2][q]);
                    psi[q] = 0.5 * lam * tr * tr + mu * ee;
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    for q in 0..8 {
                        p[i][j][q] = s[i][j][q]
                            + fmadd::<FMA>(
                                hh[i][2][q],
                                s[2][j][q],
                                fmadd::<FMA>(hh[i][1][q], s[1][j][q], hh[i][0][q] * s[0][j][q]),
                            );
                    }
                }
            }
        }
        MaterialModel::NeoHookean => {
            // P = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ, F⁻ᵀ = cof(F)/J.
            for q in 0..8 {
                let j = det[q];
                let lnj = j.ln();
                let inv_j = 1.0 / j;
                let f = |i: usize, k: usize| ff[i][k][q];
                let cof = cofactor(f);
                let coef = (lam * lnj - mu) * inv_j;
                let mut trc = 0.0;
                for i in 0..3 {
                    for k in 0..3 {
                        p[i][k][q] = mu * f(i, k) + coef * cof[i][k];
                        trc += f(i, k) * f(i, k);
                    }
                }
                if ENERGY {
                    psi[q] = 0.5 * mu * (trc - 3.0) - mu * lnj + 0.5 * lam * lnj * lnj;
                }
            }
        }
    }
    // f_a = Σ_q Σ_j P_ij w det J₀ ∂N_a/∂X_j.
    for a in 0..8 {
        for i in 0..3 {
            let mut acc = [0.0; 8];
            for q in 0..8 {
                acc[q] = fmadd::<FMA>(
                    p[i][2][q],
                    gd.wgrad[a][2][q],
                    fmadd::<FMA>(
                        p[i][1][q],
                        gd.wgrad[a][1][q],
                        p[i][0][q] * gd.wgrad[a][0][q],
                    ),
                );
            }
            f[a][i] =
                ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
        }
    }
    let mut energy = 0.0;
    if ENERGY {
        for q in 0..8 {
            energy += psi[q] * gd.wdet[q];
        }
    }
    (energy, min_j)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{GaussData, HEX_CORNERS};

    /// The 8-lane one-point kernel gives the scalar kernel's forces and energies on 8
    /// different distorted elements with large displacements (both models, with and without
    /// FMA: only rounding differs, 1e-12 relative).
    #[test]
    fn lane_kernel_matches_scalar_one_point_kernel() {
        use crate::mesh::CentreData;
        let mut b = [[[0.0; 8]; 3]; 8];
        let mut gamma = [[[0.0; 8]; 8]; 4];
        let mut vol = [0.0; 8];
        let mut k = [0.0; 8];
        let mut ul = [[[0.0; 8]; 3]; 8];
        let mut cds = vec![];
        let mut us = vec![];
        for l in 0..8 {
            let mut x = HEX_CORNERS.map(|c| [c[0] * 0.3, c[1] * 0.2, c[2] * 0.25]);
            x[(l + 3) % 8][l % 3] += 0.03 * (l as f64 + 1.0).sin();
            let gd = GaussData::new(&x).unwrap();
            let cd = CentreData::new(&x, &gd);
            let u: [[f64; 3]; 8] = std::array::from_fn(|a| {
                let t = (a * 7 + l * 3) as f64;
                [
                    0.02 * t.sin(),
                    0.015 * (1.3 * t).cos(),
                    -0.01 * (0.7 * t).sin(),
                ]
            });
            for a in 0..8 {
                for j in 0..3 {
                    b[a][j][l] = cd.b[a][j];
                    ul[a][j][l] = u[a][j];
                }
            }
            for al in 0..4 {
                for a in 0..8 {
                    gamma[al][a][l] = cd.gamma[al][a];
                }
            }
            vol[l] = cd.volume;
            k[l] = 1e5 * (1.0 + l as f64);
            cds.push(cd);
            us.push(u);
        }
        for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
            let mat = Material::new(model, 5e6, 0.45, 1100.0);
            let mut fl = [[[0.0; 8]; 3]; 8];
            for fma in [false, true] {
                let (en, hg, det) = if fma {
                    element_forces_reduced_lanes::<true, true>(
                        &mat, &b, &gamma, &vol, &k, &ul, &mut fl,
                    )
                } else {
                    element_forces_reduced_lanes::<true, false>(
                        &mat, &b, &gamma, &vol, &k, &ul, &mut fl,
                    )
                };
                for l in 0..8 {
                    let mut f = [[0.0; 3]; 8];
                    let (e1, h1, j1) =
                        element_forces_reduced::<true>(&mat, &cds[l], k[l], &us[l], &mut f);
                    let scale = f.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                    for a in 0..8 {
                        for i in 0..3 {
                            assert!(
                                (fl[a][i][l] - f[a][i]).abs() <= 1e-12 * scale,
                                "{model:?} lane {l} node {a}"
                            );
                        }
                    }
                    assert!((en[l] - e1).abs() <= 1e-12 * e1.abs());
                    assert!((hg[l] - h1).abs() <= 1e-12 * h1.abs());
                    assert!((det[l] - j1).abs() <= 1e-14);
                }
            }
        }
    }

    /// Von Mises: zero under a pure dilatation, √3 μ γ in small simple shear (to O(γ²)).
    #[test]
    fn von_mises_of_dilatation_and_shear() {
        let mat = Material::new(MaterialModel::Svk, 5e6, 0.45, 1100.0);
        assert!(mat.von_mises(&(Matrix3::identity() * 1.01)) < 1e-6 * mat.mu);
        let gamma = 1e-5;
        let mut f = Matrix3::identity();
        f[(0, 1)] = gamma;
        let expect = 3f64.sqrt() * mat.mu * gamma;
        assert!((mat.von_mises(&f) - expect).abs() < 1e-4 * expect);
    }

    /// Kernel against the pointwise reference on a homogeneous deformation of a distorted
    /// element: the nodal forces are Σ_q wdet P ∇N (checked through equilibrium of the sum and
    /// the virtual work of a linear field), and the energy is ψ × volume.
    #[test]
    fn kernel_matches_pointwise_stress_for_homogeneous_deformation() {
        let mut x = HEX_CORNERS.map(|c| [c[0] * 0.4, c[1] * 0.25, c[2] * 0.3]);
        x[5][1] += 0.05;
        let gd = GaussData::new(&x).unwrap();
        let f_def = Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, 0.0, -0.12, 1.2);
        for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
            let mat = Material::new(model, 5e6, 0.45, 1100.0);
            let mut u = [[0.0; 3]; 8];
            for a in 0..8 {
                let xa = nalgebra::Vector3::from(x[a]);
                let ua = (f_def - Matrix3::identity()) * xa;
                u[a] = [ua[0], ua[1], ua[2]];
            }
            let mut f = [[0.0; 3]; 8];
            let (energy, min_j) = element_forces::<true, false>(&mat, &gd, &u, &mut f);
            let (s, psi) = mat.stress_energy(&f_def);
            let p = f_def * s;
            let vol = gd.volume();
            assert!((energy - psi * vol).abs() <= 1e-12 * psi * vol, "{model:?}");
            assert!((min_j - f_def.determinant()).abs() < 1e-12);
            // Virtual work of δu = G X for any G: Σ_a f_a·(G X_a) = vol P:G.
            let g = Matrix3::new(0.3, -1.0, 0.2, 0.5, 0.1, -0.7, 0.4, 0.9, -0.2);
            let mut vw = 0.0;
            for a in 0..8 {
                let d = g * nalgebra::Vector3::from(x[a]);
                vw += f[a][0] * d[0] + f[a][1] * d[1] + f[a][2] * d[2];
            }
            let expect = vol * p.component_mul(&g).sum();
            assert!(
                (vw - expect).abs() <= 1e-10 * expect.abs().max(1.0),
                "{model:?}: {vw} vs {expect}"
            );
        }
    }
}
