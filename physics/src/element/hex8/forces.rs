//! The element kernels (model §1.5, §1.6): internal nodal forces and energies of hex8 elements,
//! with full 2×2×2 integration ([`element_forces`], the 8 Gauss points as the lanes of an
//! [`F64x8`]) or one point with Flanagan–Belytschko hourglass control, on one element
//! ([`element_forces_reduced`], `f64`) or on 8 elements at once ([`element_forces_reduced_lanes`],
//! one per lane; on axis-aligned boxes through the modes of the trilinear field,
//! [`element_forces_reduced_lanes_in`]). The stress comes from [`first_piola`], the kinematics from
//! [`super::kinematics`]; what stays here is each kernel's data layout and its sums. The lane
//! kernels are compiled once per [`Law`], so that their bodies are straight-line code.

use super::reference::{CentreData, GaussData};
use super::tensor::{
    box_factors, box_forces, box_gradient, modes_to_nodes, node_modes, parent_forces,
    parent_gradient, HOURGLASS_AT, NODE_AT,
};
use crate::material::kinematics::{
    displacement_gradient, hourglass_energy, hourglass_modes, lane_sums_by_halves, row_dot,
    Deformation,
};
use crate::material::{first_piola, with_law, Law, Material};
use crate::material::{F64x8, Lanes, Mat3, Real};

/// Hourglass stiffness of one element, k = κ M V Σₐ bₐ·bₐ / 8 [N/m] with
/// M = [`Material::hourglass_modulus`] (λ + 2μ; 11μ₀ for a rubber, model §1.10)
/// (Flanagan–Belytschko stiffness form; κ is the scene's `scheme.hourglass_coefficient`).
pub fn hourglass_stiffness(mat: &Material, cd: &CentreData, kappa: f64) -> f64 {
    kappa * mat.hourglass_modulus() * cd.volume * cd.bb / 8.0
}

/// The three components of a per-lane vector (`x[j][lane]`) as [`F64x8`]s.
#[inline(always)]
fn lanes3(x: &[[f64; 8]; 3]) -> [F64x8; 3] {
    [F64x8(x[0]), F64x8(x[1]), F64x8(x[2])]
}

/// J = det F, P and ψ of [`first_piola`] (ψ only if `ENERGY`) at the 8 points held in the lanes
/// of H, evaluated point after point on `f64` (fused when `FMA`): a loop over the
/// lanes with the whole pointwise update inside, which the compiler vectorises across the
/// lanes. (The same update written on [`F64x8`] tensors left the vectoriser to regroup ~100
/// separate lane-wise operations, which it did only partly, and the full kernel ran slower;
/// docs: performance log.)
/// P is written into `p` (every component): a kernel that keeps P in its own array avoids a
/// zeroed temporary and a copy, which the AVX2 build does not keep in registers (two 576-byte
/// `memset`/`memcpy` calls per point there). Returns (ψ, J) per lane.
#[inline(always)]
pub(crate) fn first_piola_lanes_into<L: Law, const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    h: &Mat3<F64x8>,
    p: &mut Mat3<F64x8>,
) -> (F64x8, F64x8) {
    let (mut psi, mut det) = (F64x8::splat(0.0), F64x8::splat(0.0));
    for l in 0..8 {
        let d = Deformation::of::<FMA>(std::array::from_fn(|i| {
            std::array::from_fn(|j| h[i][j].0[l])
        }));
        let (pl, psil) = first_piola::<L, f64, ENERGY, FMA>(mat, &d);
        for i in 0..3 {
            for j in 0..3 {
                p[i][j].0[l] = pl[i][j];
            }
        }
        (psi.0[l], det.0[l]) = (psil, d.j);
    }
    (psi, det)
}

/// Internal nodal forces of one element, fₐ = Σ_q w_q det J₀ P(F_q) ∇ₓNₐ(ξ_q)
/// (model §1.5: per step and per element only F → E → S → P = F·S → fₐ),
/// the 8 Gauss points q being the 8 lanes.
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
    with_law!(mat.model, L => full::<L, ENERGY, FMA>(mat, gd, u, f))
}

/// [`element_forces`] for the law `L` (the web page's chunk remainders call it per law:
/// `kernels::scalar_element`).
#[cfg(target_arch = "wasm32")]
#[inline(always)]
pub(crate) fn element_forces_law<L: Law, const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    gd: &GaussData,
    u: &[[f64; 3]; 8],
    f: &mut [[f64; 3]; 8],
) -> (f64, f64) {
    full::<L, ENERGY, FMA>(mat, gd, u, f)
}

/// [`element_forces`] for the law `L`: the parent derivatives by sum factorisation
/// ([`parent_gradient`], (T1) of `element::hex8::tensor`), H_q = D_q·(⅛ J₀⁻¹) and P at the 8 points
/// in lanes, Q_q = P_q·(w_q det J₀ ⅛ J₀⁻ᵀ), the forces by the transpose ([`parent_forces`], (T2));
/// on an axis-aligned box H and the forces through the modes of the trilinear field
/// ([`box_gradient`], [`box_forces`]: (T4) of `element::hex8::tensor` and its transpose).
#[inline(always)]
fn full<L: Law, const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    gd: &GaussData,
    u: &[[f64; 3]; 8],
    f: &mut [[f64; 3]; 8],
) -> (f64, f64) {
    // Plain loops, not `std::array::from_fn`: its closures were not inlined here (36 calls per
    // element in the builds' chunk remainders, and every element of the portable build).
    // An axis-aligned box's ⅛ J₀⁻¹ and ⅛ w det J₀ J₀⁻ᵀ are one diagonal at every point: H and
    // the forces through the modes of the trilinear field, as the lane kernel does.
    let diag = gd.axis_aligned;
    let mut dq = [[[0.0f64; 3]; 3]; 8];
    if diag {
        let k = box_factors([gd.jinv[0][0][0], gd.jinv[1][1][0], gd.jinv[2][2][0]]);
        box_gradient(|a, i| u[a][i], &k, &mut dq);
    } else {
        parent_gradient::<f64, FMA>(|a, i| u[a][i], &mut dq);
    }
    let zero = F64x8([0.0; 8]);
    // The parent derivatives (on a box H itself), the 8 points in the lanes.
    let mut d: Mat3<F64x8> = [[zero; 3]; 3];
    for (q, dq_q) in dq.iter().enumerate() {
        for i in 0..3 {
            for k in 0..3 {
                d[i][k].0[q] = dq_q[i][k];
            }
        }
    }
    let h = if diag {
        d
    } else {
        let mut h: Mat3<F64x8> = [[zero; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let jinv = [
                    F64x8(gd.jinv[0][j]),
                    F64x8(gd.jinv[1][j]),
                    F64x8(gd.jinv[2][j]),
                ];
                h[i][j] = row_dot::<_, FMA>(&d[i], jinv);
            }
        }
        h
    };
    let mut p: Mat3<F64x8> = [[zero; 3]; 3];
    let (psi, det) = first_piola_lanes_into::<L, ENERGY, FMA>(mat, &h, &mut p);
    if diag {
        let k = box_factors([gd.wjinv[0][0][0], gd.wjinv[1][1][0], gd.wjinv[2][2][0]]);
        box_forces(|pt, i, d| p[i][d].0[pt], &k, f);
    } else {
        let mut q: Mat3<F64x8> = [[zero; 3]; 3];
        for i in 0..3 {
            for k in 0..3 {
                q[i][k] = row_dot::<_, FMA>(&p[i], lanes3(&gd.wjinv[k]));
            }
        }
        parent_forces::<f64, FMA>(|pt, i, k| q[i][k].0[pt], f);
    }
    let mut energy = 0.0;
    if ENERGY {
        for q in 0..8 {
            energy += psi.0[q] * gd.wdet[q];
        }
    }
    (energy, det.min_lane())
}

/// Internal forces of one element with one-point integration and Flanagan–Belytschko hourglass
/// control (model §1.6):
/// F = I + Σₐ uₐ ⊗ bₐ, fₐ = V P(F) bₐ + k Σᵅ γₐᵅ qᵅ with qᵅ = Σₐ γₐᵅ uₐ,
/// hourglass energy Ψ_hg = ½ k Σᵅ |qᵅ|². Returns (strain energy V ψ(F), Ψ_hg, J) — the
/// energies only if `ENERGY`. No fused operation (the stress is [`first_piola`] with
/// `FMA = false`) and the hourglass force term by term.
#[inline(always)]
pub fn element_forces_reduced<const ENERGY: bool>(
    mat: &Material,
    cd: &CentreData,
    k_hg: f64,
    u: &[[f64; 3]; 8],
    f: &mut [[f64; 3]; 8],
) -> (f64, f64, f64) {
    if cd.axis_aligned {
        return box_one_point::<ENERGY>(mat, cd, k_hg, u, f);
    }
    let d = Deformation::of::<false>(displacement_gradient::<f64, false>(
        |a, i| u[a][i],
        |a, j| cd.b[a][j],
    ));
    // (Scalar: a branch on the model costs nothing here.)
    let (p, psi) = with_law!(mat.model, L => first_piola::<L, f64, ENERGY, false>(mat, &d));
    let q = hourglass_modes::<f64, false>(|al, a| cd.gamma[al][a], |a, i| u[a][i]);
    let v = cd.volume;
    for a in 0..8 {
        for i in 0..3 {
            let mut fa = v * row_dot::<f64, false>(&p[i], cd.b[a]);
            for al in 0..4 {
                fa += k_hg * cd.gamma[al][a] * q[al][i];
            }
            f[a][i] = fa;
        }
    }
    let e_hg = if ENERGY {
        hourglass_energy(k_hg, &q)
    } else {
        0.0
    };
    (v * psi, e_hg, d.j)
}

/// [`element_forces_reduced`] on an axis-aligned box ([`CentreData::axis_aligned`]), through the
/// modes of the trilinear field (`element::hex8::tensor`, (T3)): per component i the 8 modal
/// amplitudes m of uᵢ, H_id = β_d m_{d}, qᵅᵢ = m_{hᵅ}; then P, and the forces as the nodal
/// field of the amplitudes V β_d P_id and k qᵅᵢ ([`modes_to_nodes`]). The equations of the
/// general kernel with bₐ = sₐ ⊙ β and γᵅ = hᵅ, summed in another order.
#[inline(always)]
fn box_one_point<const ENERGY: bool>(
    mat: &Material,
    cd: &CentreData,
    k_hg: f64,
    u: &[[f64; 3]; 8],
    f: &mut [[f64; 3]; 8],
) -> (f64, f64, f64) {
    let mut h = [[0.0; 3]; 3];
    let mut q = [[0.0; 3]; 4];
    for i in 0..3 {
        let mut x = [0.0; 8];
        for (pos, x_p) in x.iter_mut().enumerate() {
            *x_p = u[NODE_AT[pos]][i];
        }
        let m = node_modes(x);
        for d in 0..3 {
            h[i][d] = cd.beta[d] * m[1 << d];
        }
        for al in 0..4 {
            q[al][i] = m[HOURGLASS_AT[al]];
        }
    }
    let d = Deformation::of::<false>(h);
    let (p, psi) = with_law!(mat.model, L => first_piola::<L, f64, ENERGY, false>(mat, &d));
    let v = cd.volume;
    for i in 0..3 {
        let mut m = [0.0; 8];
        for d in 0..3 {
            m[1 << d] = v * cd.beta[d] * p[i][d];
        }
        for al in 0..4 {
            m[HOURGLASS_AT[al]] = k_hg * q[al][i];
        }
        let fi = modes_to_nodes(m);
        for p in 0..8 {
            f[NODE_AT[p]][i] = fi[p];
        }
    }
    let e_hg = if ENERGY {
        hourglass_energy(k_hg, &q)
    } else {
        0.0
    };
    (v * psi, e_hg, d.j)
}

/// The one-point data of 8 elements, one per lane (`x[..][lane]`), for
/// [`element_forces_reduced_lanes`]. Aligned to a cache line: every field is rows of 8 lanes
/// (64 bytes), so each row the kernel loads is one line.
#[derive(Debug, Clone, Copy, Default)]
#[repr(align(64))]
pub struct LaneElements {
    /// Mean gradients bₐ [1/m].
    pub b: [[[f64; 8]; 3]; 8],
    /// Hourglass shape vectors γₐᵅ.
    pub gamma: [[[f64; 8]; 8]; 4],
    /// Volumes V [m³].
    pub vol: [f64; 8],
    /// Hourglass stiffnesses k [N/m].
    pub k_hg: [f64; 8],
    /// β of an axis-aligned box ([`CentreData::beta`]) [1/m], and V β [m²].
    pub beta: [[f64; 8]; 3],
    pub vbeta: [[f64; 8]; 3],
}

impl LaneElements {
    /// Puts the element `cd` with hourglass stiffness `k_hg` into lane `l`.
    #[inline(always)]
    pub fn set(&mut self, l: usize, cd: &CentreData, k_hg: f64) {
        for a in 0..8 {
            for j in 0..3 {
                self.b[a][j][l] = cd.b[a][j];
            }
            for al in 0..4 {
                self.gamma[al][a][l] = cd.gamma[al][a];
            }
        }
        self.vol[l] = cd.volume;
        self.k_hg[l] = k_hg;
        for d in 0..3 {
            self.beta[d][l] = cd.beta[d];
            self.vbeta[d][l] = cd.volume * cd.beta[d];
        }
    }
}

/// The one-point kernel of [`element_forces_reduced`] on 8 elements at once, one per SIMD lane
/// (`u[a][i][lane]`, `f[a][i][lane]`): same equations, SVK and neo-Hookean, with
/// P = ((S + H₀S) + H₁S) + H₂S and fₐ = V P bₐ + k Σᵅ γₐᵅ qᵅ (fused when `FMA`). Returns per lane
/// (V ψ, Ψ_hg, J); the energies only if `ENERGY`.
#[inline(always)]
pub fn element_forces_reduced_lanes<const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    el: &LaneElements,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[[f64; 8]; 3]; 8],
) -> [[f64; 8]; 3] {
    let mut work = OnePointScratch::default();
    element_forces_reduced_lanes_in::<ENERGY, FMA, false, false>(mat, el, u, f, &mut work)
}

/// The per-group work arrays of the one-point lane kernel (H, P, the hourglass modes q),
/// kept by the caller across lane groups: every entry is written before it is read, and
/// fresh zeroed arrays per group cost the AVX2 build `memset` calls (its 32-byte stores
/// exceed the compiler's inline limit for 576 and 768 bytes).
#[derive(Clone)]
pub struct OnePointScratch {
    h: Mat3<F64x8>,
    p: Mat3<F64x8>,
    q: [[F64x8; 3]; 4],
}

impl OnePointScratch {
    /// Per lane, ‖F‖²_F and |q|² of the last kernel call ([`centre_norms_of`]).
    #[inline(always)]
    pub fn centre_norms(&self) -> ([f64; 8], [f64; 8]) {
        let (f2, q2) = centre_norms_of(&self.h, &self.q);
        (f2.0, q2.0)
    }
}

/// ‖F‖²_F = Σᵢⱼ(δᵢⱼ + Hᵢⱼ)² and |q|² = Σᵅ|qᵅ|² from H and the hourglass amplitudes qᵅ: what the
/// corner bound J (1 − C|q|/s)³, s = 2J/‖F‖²_F, needs besides J (`kernels::corner_bound`,
/// model §1.9). Generic, so that `kernels::flops` counts the operations the kernel runs.
#[inline(always)]
pub fn centre_norms_of<T: Real>(h: &Mat3<T>, q: &[[T; 3]; 4]) -> (T, T) {
    let mut f2 = T::splat(0.0);
    for i in 0..3 {
        for j in 0..3 {
            let fij = if i == j {
                h[i][j] + T::splat(1.0)
            } else {
                h[i][j]
            };
            f2 = f2 + fij * fij;
        }
    }
    let mut q2 = T::splat(0.0);
    for al in 0..4 {
        for i in 0..3 {
            q2 = q2 + q[al][i] * q[al][i];
        }
    }
    (f2, q2)
}

impl Default for OnePointScratch {
    fn default() -> Self {
        let z = F64x8::splat(0.0);
        OnePointScratch {
            h: [[z; 3]; 3],
            p: [[z; 3]; 3],
            q: [[z; 3]; 4],
        }
    }
}

/// [`element_forces_reduced_lanes`] with the caller's work arrays; `HALVES` forms H and the
/// hourglass modes 4 lanes at a time ([`lane_sums_by_halves`], for AVX2's 16 registers; the
/// same bits). `BOXES`: every lane holds an axis-aligned box ([`CentreData::axis_aligned`]),
/// which goes through the modes of the trilinear field ([`box_lanes`]; with `HALVES` 4 lanes
/// at a time there too).
#[inline(always)]
pub fn element_forces_reduced_lanes_in<
    const ENERGY: bool,
    const FMA: bool,
    const HALVES: bool,
    const BOXES: bool,
>(
    mat: &Material,
    el: &LaneElements,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[[f64; 8]; 3]; 8],
    work: &mut OnePointScratch,
) -> [[f64; 8]; 3] {
    with_law!(mat.model, L => match (BOXES, HALVES) {
        (true, true) => box_lanes::<L, ENERGY, FMA, 4>(mat, el, u, f, work),
        (true, false) => box_lanes::<L, ENERGY, FMA, 8>(mat, el, u, f, work),
        (false, _) => one_point_lanes::<L, ENERGY, FMA, HALVES>(mat, el, u, f, work),
    })
}

/// [`element_forces_reduced_lanes_in`] for the law `L`.
#[inline(always)]
fn one_point_lanes<L: Law, const ENERGY: bool, const FMA: bool, const HALVES: bool>(
    mat: &Material,
    el: &LaneElements,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[[f64; 8]; 3]; 8],
    work: &mut OnePointScratch,
) -> [[f64; 8]; 3] {
    let OnePointScratch { h, p, q } = work;
    let ul = |a: usize, i: usize| F64x8(u[a][i]);
    let b = |a: usize, j: usize| F64x8(el.b[a][j]);
    let gamma = |al: usize, a: usize| F64x8(el.gamma[al][a]);
    if HALVES {
        let ur = |a: usize, i: usize| &u[a][i];
        lane_sums_by_halves::<3, 3, FMA>(ur, |a, j| &el.b[a][j], h);
        lane_sums_by_halves::<4, 3, FMA>(|a, al| &el.gamma[al][a], ur, q);
    } else {
        *h = displacement_gradient::<F64x8, FMA>(ul, b);
        *q = hourglass_modes::<F64x8, FMA>(gamma, ul);
    }
    let (psi, det) = first_piola_lanes_into::<L, ENERGY, FMA>(mat, h, p);
    let (vol, k_hg) = (F64x8(el.vol), F64x8(el.k_hg));
    for a in 0..8 {
        let ba = lanes3(&el.b[a]);
        for i in 0..3 {
            let pb = row_dot::<_, FMA>(&p[i], ba);
            let mut hg = F64x8::splat(0.0);
            for al in 0..4 {
                hg = F64x8(el.gamma[al][a]).fmadd::<FMA>(q[al][i], hg);
            }
            f[a][i] = vol.fmadd::<FMA>(pb, k_hg * hg).0;
        }
    }
    if ENERGY {
        [(vol * psi).0, hourglass_energy(k_hg, q).0, det.0]
    } else {
        [[0.0; 8], [0.0; 8], det.0]
    }
}

/// [`element_forces_reduced_lanes_in`] on 8 axis-aligned boxes for the law `L`
/// (`box_one_point` lane by lane, fused when `FMA`), W lanes at
/// a time through the modal transforms (W = 4 for AVX2's 16 registers, 8 otherwise). Returns
/// per lane (V ψ, Ψ_hg, J).
#[inline(always)]
fn box_lanes<L: Law, const ENERGY: bool, const FMA: bool, const W: usize>(
    mat: &Material,
    el: &LaneElements,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[[f64; 8]; 3]; 8],
    work: &mut OnePointScratch,
) -> [[f64; 8]; 3] {
    let OnePointScratch { h, p, q } = work;
    // Plain loops: `NODE_AT.map(..)` and slice copies were left as calls (`try_map`, `memcpy`).
    for i in 0..3 {
        for part in 0..8 / W {
            let o = part * W;
            let mut x = [Lanes::<W>([0.0; W]); 8];
            for (pos, x_p) in x.iter_mut().enumerate() {
                for l in 0..W {
                    x_p.0[l] = u[NODE_AT[pos]][i][o + l];
                }
            }
            let m = node_modes(x);
            for d in 0..3 {
                for l in 0..W {
                    h[i][d].0[o + l] = el.beta[d][o + l] * m[1 << d].0[l];
                }
            }
            for al in 0..4 {
                for l in 0..W {
                    q[al][i].0[o + l] = m[HOURGLASS_AT[al]].0[l];
                }
            }
        }
    }
    let (psi, det) = first_piola_lanes_into::<L, ENERGY, FMA>(mat, h, p);
    for i in 0..3 {
        for part in 0..8 / W {
            let o = part * W;
            let mut m = [Lanes::<W>([0.0; W]); 8];
            for d in 0..3 {
                for l in 0..W {
                    m[1 << d].0[l] = el.vbeta[d][o + l] * p[i][d].0[o + l];
                }
            }
            for al in 0..4 {
                for l in 0..W {
                    m[HOURGLASS_AT[al]].0[l] = el.k_hg[o + l] * q[al][i].0[o + l];
                }
            }
            let fi = modes_to_nodes(m);
            for (pos, f_p) in fi.iter().enumerate() {
                for l in 0..W {
                    f[NODE_AT[pos]][i][o + l] = f_p.0[l];
                }
            }
        }
    }
    if ENERGY {
        let vol = F64x8(el.vol);
        [(vol * psi).0, hourglass_energy(F64x8(el.k_hg), q).0, det.0]
    } else {
        [[0.0; 8], [0.0; 8], det.0]
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::HEX_CORNERS;
    use super::*;
    use crate::material::MaterialModel;

    /// The 8-lane one-point kernel gives the scalar kernel's forces and energies on 8
    /// different distorted elements with large displacements (both models, with and without
    /// FMA: only rounding differs, 1e-12 relative).
    #[test]
    fn lane_kernel_matches_scalar_one_point_kernel() {
        let mut lanes = LaneElements::default();
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
                    ul[a][j][l] = u[a][j];
                }
            }
            lanes.set(l, &cd, 1e5 * (1.0 + l as f64));
            cds.push(cd);
            us.push(u);
        }
        for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
            let mat = Material::new(model, 5e6, 0.45, 1100.0);
            let mut fl = [[[0.0; 8]; 3]; 8];
            for fma in [false, true] {
                let [en, hg, det] = if fma {
                    element_forces_reduced_lanes::<true, true>(&mat, &lanes, &ul, &mut fl)
                } else {
                    element_forces_reduced_lanes::<true, false>(&mat, &lanes, &ul, &mut fl)
                };
                for l in 0..8 {
                    let mut f = [[0.0; 3]; 8];
                    let (e1, h1, j1) = element_forces_reduced::<true>(
                        &mat,
                        &cds[l],
                        lanes.k_hg[l],
                        &us[l],
                        &mut f,
                    );
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
}
