//! The kinematics shared by the element kernels, over any [`Real`] (model §1.2, total
//! Lagrangian): H = ∂U/∂X = Σₐ uₐ ⊗ gₐ, F = I + H, J = det F, cof F, 2E = H + Hᵀ + HᵀH,
//! P = S + H·S, the row products P·g, and the hourglass modes qᵅ = Σₐ γₐᵅ uₐ. Each is the one
//! operation order every kernel that uses it shares; `FMA` says whether its multiply–adds are
//! fused (the builds for CPUs that have FMA) or not (the portable build, the scalar one-point
//! kernel).

use super::real::{F64x8, Mat3, Real};

/// H = ∂U/∂X = Σₐ uₐ ⊗ gₐ, `u(a, i)` the displacement of node a, `g(a, j)` = ∂Nₐ/∂Xⱼ;
/// accumulated node after node (a·b + c fused when `FMA`).
#[inline(always)]
pub(crate) fn displacement_gradient<T: Real, const FMA: bool>(
    u: impl Fn(usize, usize) -> T,
    g: impl Fn(usize, usize) -> T,
) -> Mat3<T> {
    let mut h = [[T::splat(0.0); 3]; 3];
    for a in 0..8 {
        for i in 0..3 {
            let ua = u(a, i);
            for j in 0..3 {
                h[i][j] = ua.fmadd::<FMA>(g(a, j), h[i][j]);
            }
        }
    }
    h
}

/// The kinematics at a point: H = ∂U/∂X, F = I + H, J = det F.
pub struct Deformation<T> {
    pub h: Mat3<T>,
    pub f: Mat3<T>,
    pub j: T,
}

impl<T: Real> Deformation<T> {
    /// F = I + H and J = det F from H ([`determinant`], fused when `FMA`).
    #[inline(always)]
    pub fn of<const FMA: bool>(h: Mat3<T>) -> Self {
        let f = deformation_gradient(&h);
        let j = determinant::<T, FMA>(&f);
        Deformation { h, f, j }
    }
}

/// δᵢⱼ, the identity's entries.
#[inline(always)]
pub(crate) fn id(i: usize, j: usize) -> f64 {
    if i == j {
        1.0
    } else {
        0.0
    }
}

/// F = I + H.
#[inline(always)]
pub(crate) fn deformation_gradient<T: Real>(h: &Mat3<T>) -> Mat3<T> {
    let mut f = *h;
    for i in 0..3 {
        f[i][i] = f[i][i] + T::splat(1.0);
    }
    f
}

/// J = det F as the difference of its two triple sums (Sarrus),
/// J = ((F₀₀F₁₁)F₂₂ + (F₀₁F₁₂)F₂₀ + (F₀₂F₁₀)F₂₁) − ((F₀₀F₁₂)F₂₁ + (F₀₁F₁₀)F₂₂ + (F₀₂F₁₁)F₂₀),
/// each sum accumulated left to right by multiply–adds (fused when `FMA`): 17 flops in 11
/// instructions, where the cofactor expansion takes 14 flops in 14 instructions unfused and
/// could fuse its minors only through a negation (which the kernels avoid: NaNs of both signs
/// would make the builds' bits depend on the compiler's operand order, see `tensor`).
#[inline(always)]
pub(crate) fn determinant<T: Real, const FMA: bool>(f: &Mat3<T>) -> T {
    let plus = (f[0][2] * f[1][0]).fmadd::<FMA>(
        f[2][1],
        (f[0][1] * f[1][2]).fmadd::<FMA>(f[2][0], f[0][0] * f[1][1] * f[2][2]),
    );
    let minus = (f[0][2] * f[1][1]).fmadd::<FMA>(
        f[2][0],
        (f[0][1] * f[1][0]).fmadd::<FMA>(f[2][2], f[0][0] * f[1][2] * f[2][1]),
    );
    plus - minus
}

/// Cofactor matrix cof F = J F⁻ᵀ.
#[inline(always)]
pub(crate) fn cofactor<T: Real>(f: &Mat3<T>) -> Mat3<T> {
    [
        [
            f[1][1] * f[2][2] - f[1][2] * f[2][1],
            f[1][2] * f[2][0] - f[1][0] * f[2][2],
            f[1][0] * f[2][1] - f[1][1] * f[2][0],
        ],
        [
            f[0][2] * f[2][1] - f[0][1] * f[2][2],
            f[0][0] * f[2][2] - f[0][2] * f[2][0],
            f[0][1] * f[2][0] - f[0][0] * f[2][1],
        ],
        [
            f[0][1] * f[1][2] - f[0][2] * f[1][1],
            f[0][2] * f[1][0] - f[0][0] * f[1][2],
            f[0][0] * f[1][1] - f[0][1] * f[1][0],
        ],
    ]
}

/// Twice the Green–Lagrange strain, G = 2E = FᵀF − I = H + Hᵀ + HᵀH, formed from H so that
/// small strains keep their full relative precision:
/// G_ij = (((H_ij + H_ji) + H_0i H_0j) + H_1i H_1j) + H_2i H_2j, a sum and three multiply–adds
/// (fused when `FMA`). The 6 entries i ≤ j are formed (7 flops each) and mirrored. The ½ of E
/// goes into the constants of [`crate::material::saint_venant_kirchhoff`], which takes G.
#[inline(always)]
pub(crate) fn doubled_green_lagrange<T: Real, const FMA: bool>(h: &Mat3<T>) -> Mat3<T> {
    let mut g = *h;
    for i in 0..3 {
        for j in i..3 {
            let mut gij = h[i][j] + h[j][i];
            for k in 0..3 {
                gij = h[k][i].fmadd::<FMA>(h[k][j], gij);
            }
            g[i][j] = gij;
            g[j][i] = gij;
        }
    }
    g
}

/// The first Piola–Kirchhoff stress P = F·S = S + H·S from H and S,
/// P_ij = ((S_ij + H_i0 S_0j) + H_i1 S_1j) + H_i2 S_2j: three multiply–adds (fused when `FMA`).
#[inline(always)]
pub(crate) fn f_times_s<T: Real, const FMA: bool>(h: &Mat3<T>, s: &Mat3<T>) -> Mat3<T> {
    let mut p = *s;
    for i in 0..3 {
        for j in 0..3 {
            let mut pij = s[i][j];
            for k in 0..3 {
                pij = h[i][k].fmadd::<FMA>(s[k][j], pij);
            }
            p[i][j] = pij;
        }
    }
    p
}

/// r·g = (r₀g₀ + r₁g₁) + r₂g₂ (fused when `FMA`): a row of P against a gradient ∇Nₐ.
#[inline(always)]
pub(crate) fn row_dot<T: Real, const FMA: bool>(r: &[T; 3], g: [T; 3]) -> T {
    r[2].fmadd::<FMA>(g[2], r[1].fmadd::<FMA>(g[1], r[0] * g[0]))
}

/// Hourglass mode amplitudes qᵅ = Σₐ γₐᵅ uₐ (α = 0..4), `gamma(α, a)` = γₐᵅ
/// (Flanagan–Belytschko; fused when `FMA`).
#[inline(always)]
pub(crate) fn hourglass_modes<T: Real, const FMA: bool>(
    gamma: impl Fn(usize, usize) -> T,
    u: impl Fn(usize, usize) -> T,
) -> [[T; 3]; 4] {
    let mut q = [[T::splat(0.0); 3]; 4];
    for al in 0..4 {
        for a in 0..8 {
            for i in 0..3 {
                q[al][i] = gamma(al, a).fmadd::<FMA>(u(a, i), q[al][i]);
            }
        }
    }
    q
}

/// The R × C sums out[r][c] = Σₐ x(a, r) y(a, c) of 8 lanes, each accumulated node after node
/// (a = 0..8, x·y + s fused when `FMA`), computed 4 lanes at a time: H = Σₐ uₐ ⊗ gₐ
/// (x = u, y = g) and the hourglass modes qᵅ = Σₐ γₐᵅ uₐ (x = γ, y = u; the product
/// commutes exactly) with the bits of [`displacement_gradient`] and [`hourglass_modes`] on
/// [`F64x8`]. For AVX2: the nine (twelve) sums of 4 lanes stay in registers, where the sums of
/// 8 lanes (18 or 24 of its 16 registers) went through the stack at every node. The lanes
/// are read by reference: an [`F64x8`] by value was copied to the stack first.
#[inline(always)]
pub(crate) fn lane_sums_by_halves<'a, const R: usize, const C: usize, const FMA: bool>(
    x: impl Fn(usize, usize) -> &'a [f64; 8],
    y: impl Fn(usize, usize) -> &'a [f64; 8],
    out: &mut [[F64x8; C]; R],
) {
    for half in [0, 4] {
        let mut acc = [[[0.0f64; 4]; C]; R];
        for a in 0..8 {
            for (r, acc_r) in acc.iter_mut().enumerate() {
                let xr = x(a, r);
                for (c, acc_rc) in acc_r.iter_mut().enumerate() {
                    let yc = y(a, c);
                    for (l, s) in acc_rc.iter_mut().enumerate() {
                        *s = xr[half + l].fmadd::<FMA>(yc[half + l], *s);
                    }
                }
            }
        }
        for r in 0..R {
            for c in 0..C {
                for l in 0..4 {
                    out[r][c].0[half + l] = acc[r][c][l];
                }
            }
        }
    }
}

/// Hourglass energy Ψ_hg = ½ k Σᵅ |qᵅ|².
#[inline(always)]
pub(crate) fn hourglass_energy<T: Real>(k: T, q: &[[T; 3]; 4]) -> T {
    let mut qq = T::splat(0.0);
    for qa in q {
        qq = qq + (qa[0] * qa[0] + qa[1] * qa[1] + qa[2] * qa[2]);
    }
    T::splat(0.5) * k * qq
}
