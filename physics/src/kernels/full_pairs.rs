//! The full-integration (2×2×2 Gauss) kernel of the web page ([`ISA_SIMD128`]): a lane group
//! of 8 elements as 4 pairs, each pair of elements the lanes of an [`F64x2`] (model §1.5).
//! The same sum factorisation, pointwise stress and sums as [`super::full::full_lanes`], whose
//! 8-lane values the engine kept in memory (an [`F64x8`] is four WebAssembly registers, and a
//! load or store went around nearly every f64x2 operation); a pair is one register. The
//! stress is [`first_piola`] on the pair itself, where the 8-lane kernel evaluates it lane
//! after lane on `f64`: the same formula, so the same IEEE operations in the same order.
//! Each lane gets the scalar kernel's bits ([`crate::material::element_forces`]).
//!
//! [`ISA_SIMD128`]: super::simd::ISA_SIMD128

use super::full::GaussLanes;
use crate::material::{
    box_factors, box_forces, box_gradient, first_piola, parent_forces, parent_gradient, row_dot,
    Deformation, F64x2, F64x8, Law, Mat3, Material, Real,
};

/// The per-point work arrays of [`full_pair`] (the parent derivatives, then Q, at the 8 Gauss
/// points, or on boxes H and P at the 8), kept by the caller across lane groups as
/// [`super::full::FullScratch`]: every entry is written before it is read.
#[derive(Clone)]
pub(crate) struct PairScratch {
    dq: [[[F64x2; 3]; 3]; 8],
    pq: [[[F64x2; 3]; 3]; 8],
}

impl Default for PairScratch {
    fn default() -> Self {
        let z = F64x2::splat(0.0);
        PairScratch {
            dq: [[[z; 3]; 3]; 8],
            pq: [[[z; 3]; 3]; 8],
        }
    }
}

/// [`super::full::full_lanes`] on 8 elements (element l in lane l of `u` and `f`), computed
/// as the 4 pairs of lanes (0, 1), (2, 3), (4, 5), (6, 7) by [`full_pair`]: returns per lane
/// (strain energy if `ENERGY`, else 0; min_q J_q), each lane bit-identical to
/// [`crate::material::element_forces`] on that element.
#[inline(always)]
pub(crate) fn full_pairs<
    L: Law,
    const ENERGY: bool,
    const FMA: bool,
    const DIAG: bool,
    G: GaussLanes,
>(
    mat: &Material,
    g: &G,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[F64x8; 3]; 8],
    work: &mut PairScratch,
) -> (F64x8, F64x8) {
    let mut energy = F64x8::splat(0.0);
    let mut min_j = F64x8::splat(0.0);
    for pr in 0..4 {
        let mut fp = [[F64x2::splat(0.0); 3]; 8];
        let (e, j) = full_pair::<L, ENERGY, FMA, DIAG, G>(mat, g, pr, u, &mut fp, work);
        for (fp_a, f_a) in fp.iter().zip(f.iter_mut()) {
            for (fp_ai, f_ai) in fp_a.iter().zip(f_a.iter_mut()) {
                fp_ai.put_into(f_ai, pr);
            }
        }
        e.put_into(&mut energy, pr);
        j.put_into(&mut min_j, pr);
    }
    (energy, min_j)
}

/// The pair `pr` of [`full_pairs`]: elements 2 pr and 2 pr + 1 of the group in the lanes.
/// fₐ = Σ_q w_q det J₀ P(F_q) ∇ₓNₐ(ξ_q) by sum factorisation: D_q = 8 ∂u/∂ξ (T1 of
/// `material::tensor`), H_q = D_q·(⅛ J₀⁻¹), P_q, Q_q = P_q·(⅛ w_q det J₀ J₀⁻ᵀ), the forces by
/// the transpose (T2); on boxes (`DIAG`) H and the forces through the modes of the trilinear
/// field (T4 and its transpose). Returns (Σ_q w_q det J₀ ψ_q if `ENERGY`, else 0; min_q J_q).
#[inline(always)]
fn full_pair<L: Law, const ENERGY: bool, const FMA: bool, const DIAG: bool, G: GaussLanes>(
    mat: &Material,
    g: &G,
    pr: usize,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[F64x2; 3]; 8],
    work: &mut PairScratch,
) -> (F64x2, F64x2) {
    let zero = F64x2::splat(0.0);
    let PairScratch { dq, pq } = work;
    let mut h: Mat3<F64x2> = [[zero; 3]; 3];
    let jinv = |d, j, q| F64x2::pair_of(&g.jinv(d, j, q), pr);
    let wjinv = |d, j, q| F64x2::pair_of(&g.wjinv(d, j, q), pr);
    let node = |a: usize, i: usize| F64x2::new(u[a][i][2 * pr], u[a][i][2 * pr + 1]);
    let mut det = [zero; 8];
    let mut energy = zero;
    if DIAG {
        let k = box_factors([jinv(0, 0, 0), jinv(1, 1, 0), jinv(2, 2, 0)]);
        box_gradient(node, &k, dq);
    } else {
        parent_gradient::<F64x2, FMA>(node, dq);
    }
    for q in 0..8 {
        if !DIAG {
            for (i, h_i) in h.iter_mut().enumerate() {
                for (j, h_ij) in h_i.iter_mut().enumerate() {
                    let r = [jinv(0, j, q), jinv(1, j, q), jinv(2, j, q)];
                    *h_ij = row_dot::<_, FMA>(&dq[q][i], r);
                }
            }
        }
        let d = Deformation::of::<FMA>(if DIAG { dq[q] } else { h });
        let (p_q, psi) = first_piola::<L, F64x2, ENERGY, FMA>(mat, &d);
        det[q] = d.j;
        if ENERGY {
            energy = energy + psi * F64x2::pair_of(&g.wdet(q), pr);
        }
        if DIAG {
            pq[q] = p_q;
        } else {
            for (i, dq_i) in dq[q].iter_mut().enumerate() {
                for (k, dq_ik) in dq_i.iter_mut().enumerate() {
                    let w = [wjinv(k, 0, q), wjinv(k, 1, q), wjinv(k, 2, q)];
                    *dq_ik = row_dot::<_, FMA>(&p_q[i], w);
                }
            }
        }
    }
    if DIAG {
        let k = box_factors([wjinv(0, 0, 0), wjinv(1, 1, 0), wjinv(2, 2, 0)]);
        box_forces(|q, i, d| pq[q][i][d], &k, f);
    } else {
        parent_forces::<F64x2, FMA>(|q, i, k| dq[q][i][k], f);
    }
    let d = det;
    let m = |x: F64x2, y: F64x2| x.lane_min(y);
    let min_j = m(
        m(m(d[0], d[1]), m(d[2], d[3])),
        m(m(d[4], d[5]), m(d[6], d[7])),
    );
    (energy, min_j)
}
