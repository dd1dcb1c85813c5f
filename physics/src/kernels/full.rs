//! The full-integration (2×2×2 Gauss) kernel on 8 elements at once, one element per SIMD lane
//! (model §1.5): the parent derivatives of the displacement at the 8 Gauss points by sum
//! factorisation (`element::hex8::tensor`), then for each Gauss point q in turn
//! H_q = Σₐ uₐ ⊗ ∇ₓNₐ(ξ_q), P_q = P(I + H_q) and J_q on the 8 elements; the forces
//! fₐ = Σ_q P_q (w_q det J₀ ∇ₓNₐ(ξ_q)) by the transpose, Ψ = Σ_q w_q det J₀ ψ_q, and min_q J_q
//! per element. On 8 axis-aligned boxes H and the forces go through the modes of the trilinear
//! field instead ((T4) of `element::hex8::tensor` and its transpose).
//!
//! Each lane carries out the operations of the scalar kernel
//! ([`crate::element::hex8::element_forces`], whose lanes are the Gauss points of one element) in
//! the same order: the same sum factorisation (one function for both), the same pointwise
//! stress ([`crate::element::hex8::first_piola_lanes_into`]), each row product (r₀g₀ + r₁g₁) + r₂g₂,
//! the energy point after point and min J by the same tree. So every element gets the scalar
//! kernel's bits.

use crate::element::hex8::{
    box_factors, box_forces, box_gradient, first_piola_lanes_into, parent_forces, parent_gradient,
};
use crate::material::{row_dot, F64x8, Law, Material, Real};
use crate::mesh::GaussData;

/// The reference data of the 8 elements of a lane group at the Gauss points.
pub(crate) trait GaussLanes {
    /// ⅛ ∂ξ_d/∂Xⱼ at Gauss point q, per lane [1/m] ([`GaussData::jinv`]).
    fn jinv(&self, d: usize, j: usize, q: usize) -> F64x8;
    /// ⅛ w_q det J₀ ∂ξ_d/∂Xⱼ at Gauss point q, per lane [m²] ([`GaussData::wjinv`]).
    fn wjinv(&self, d: usize, j: usize, q: usize) -> F64x8;
    /// w_q det J₀, per lane [m³].
    fn wdet(&self, q: usize) -> F64x8;
}

/// Eight elements of one class (a structured box has one): the class's data broadcast.
pub(crate) struct OneClass<'a>(pub &'a GaussData);

impl GaussLanes for OneClass<'_> {
    #[inline(always)]
    fn jinv(&self, d: usize, j: usize, q: usize) -> F64x8 {
        F64x8::splat(self.0.jinv[d][j][q])
    }
    #[inline(always)]
    fn wjinv(&self, d: usize, j: usize, q: usize) -> F64x8 {
        F64x8::splat(self.0.wjinv[d][j][q])
    }
    #[inline(always)]
    fn wdet(&self, q: usize) -> F64x8 {
        F64x8::splat(self.0.wdet[q])
    }
}

/// Eight elements of several classes: each lane's data staged (`[q][d][j]`, lanes innermost).
#[derive(Clone)]
pub(crate) struct LaneGauss {
    jinv: [[[F64x8; 3]; 3]; 8],
    wjinv: [[[F64x8; 3]; 3]; 8],
    wdet: [F64x8; 8],
}

impl Default for LaneGauss {
    fn default() -> Self {
        let z = F64x8::splat(0.0);
        LaneGauss {
            jinv: [[[z; 3]; 3]; 8],
            wjinv: [[[z; 3]; 3]; 8],
            wdet: [z; 8],
        }
    }
}

impl LaneGauss {
    /// Puts the class data `gd` into lane `l`.
    #[inline(always)]
    pub(crate) fn set(&mut self, l: usize, gd: &GaussData) {
        for q in 0..8 {
            for d in 0..3 {
                for j in 0..3 {
                    self.jinv[q][d][j].0[l] = gd.jinv[d][j][q];
                    self.wjinv[q][d][j].0[l] = gd.wjinv[d][j][q];
                }
            }
            self.wdet[q].0[l] = gd.wdet[q];
        }
    }
}

impl GaussLanes for LaneGauss {
    #[inline(always)]
    fn jinv(&self, d: usize, j: usize, q: usize) -> F64x8 {
        self.jinv[q][d][j]
    }
    #[inline(always)]
    fn wjinv(&self, d: usize, j: usize, q: usize) -> F64x8 {
        self.wjinv[q][d][j]
    }
    #[inline(always)]
    fn wdet(&self, q: usize) -> F64x8 {
        self.wdet[q]
    }
}

/// Lane-wise `f64::min` (a NaN lane of one operand gives the other's; [`F64x8::lane_min`]).
#[inline(always)]
fn min8(x: F64x8, y: F64x8) -> F64x8 {
    x.lane_min(y)
}

/// The per-point work arrays of [`full_lanes`] (the parent derivatives, then Q, at the 8
/// Gauss points, or on boxes H and P at the 8; P and H at one), kept by the caller across lane
/// groups: every entry is written before it is read, and a fresh zeroed array per group cost
/// the AVX2 build a `memset` call per group (its ymm stores exceed the compiler's inline limit,
/// AVX-512's zmm stores do not).
#[derive(Clone)]
pub(crate) struct FullScratch {
    dq: [[[F64x8; 3]; 3]; 8],
    pq: [[[F64x8; 3]; 3]; 8],
    p: [[F64x8; 3]; 3],
    h: [[F64x8; 3]; 3],
}

impl Default for FullScratch {
    fn default() -> Self {
        let z = F64x8::splat(0.0);
        FullScratch {
            dq: [[[z; 3]; 3]; 8],
            pq: [[[z; 3]; 3]; 8],
            p: [[z; 3]; 3],
            h: [[z; 3]; 3],
        }
    }
}

/// Internal nodal forces of 8 elements, fₐ = Σ_q w_q det J₀ P(F_q) ∇ₓNₐ(ξ_q) (model §1.5),
/// element l in lane l: `u[a][i][l]` the displacement of its node a, `f[a][i].0[l]` its force.
/// By sum factorisation (`element::hex8::tensor`): the parent derivatives D_q = 8 ∂u/∂ξ (T1), then
/// per point H_q = D_q·(⅛ J₀⁻¹), P_q and Q_q = P_q·(⅛ w_q det J₀ J₀⁻ᵀ), then the forces by the
/// transpose (T2). Returns per lane (strain energy Σ_q w_q det J₀ ψ_q if `ENERGY`, else 0;
/// min_q J_q), each lane bit-identical to [`crate::element::hex8::element_forces`] on that element.
/// `DIAG`: every lane is an axis-aligned box ([`GaussData::axis_aligned`]: ⅛ J₀⁻¹ one diagonal
/// at every point), so H and the forces go through the modes of the trilinear field
/// ([`box_gradient`], [`box_forces`]), as the scalar kernel does for a box.
#[inline(always)]
pub(crate) fn full_lanes<
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
    work: &mut FullScratch,
) -> (F64x8, F64x8) {
    let zero = F64x8::splat(0.0);
    let FullScratch { dq, pq, p, h } = work;
    let mut det = [zero; 8];
    let mut energy = zero;
    // An axis-aligned box's ⅛ J₀⁻¹ and ⅛ w det J₀ J₀⁻ᵀ are one diagonal at every point
    // (`GaussData::axis_aligned`): H and the forces go through the modes of the trilinear field
    // ((T4) of `element::hex8::tensor` and its transpose), `dq` holds H and `pq` P. (No copies
    // between the arrays: each is a `memcpy` call in the AVX2 build.)
    if DIAG {
        let k = box_factors([g.jinv(0, 0, 0), g.jinv(1, 1, 0), g.jinv(2, 2, 0)]);
        box_gradient(|a, i| F64x8(u[a][i]), &k, dq);
    } else {
        parent_gradient::<F64x8, FMA>(|a, i| F64x8(u[a][i]), dq);
    }
    for q in 0..8 {
        if !DIAG {
            for (i, h_i) in h.iter_mut().enumerate() {
                for (j, h_ij) in h_i.iter_mut().enumerate() {
                    let jinv = [g.jinv(0, j, q), g.jinv(1, j, q), g.jinv(2, j, q)];
                    *h_ij = row_dot::<_, FMA>(&dq[q][i], jinv);
                }
            }
        }
        let (h_q, p_q) = if DIAG {
            (&dq[q], &mut pq[q])
        } else {
            (&*h, &mut *p)
        };
        let (psi, jq) = first_piola_lanes_into::<L, ENERGY, FMA>(mat, h_q, p_q);
        det[q] = jq;
        if ENERGY {
            energy = energy + psi * g.wdet(q);
        }
        if !DIAG {
            for (i, dq_i) in dq[q].iter_mut().enumerate() {
                for (k, dq_ik) in dq_i.iter_mut().enumerate() {
                    let w = [g.wjinv(k, 0, q), g.wjinv(k, 1, q), g.wjinv(k, 2, q)];
                    *dq_ik = row_dot::<_, FMA>(&p[i], w);
                }
            }
        }
    }
    if DIAG {
        let k = box_factors([g.wjinv(0, 0, 0), g.wjinv(1, 1, 0), g.wjinv(2, 2, 0)]);
        box_forces(|q, i, d| pq[q][i][d], &k, f);
    } else {
        parent_forces::<F64x8, FMA>(|q, i, k| dq[q][i][k], f);
    }
    let d = det;
    let min_j = min8(
        min8(min8(d[0], d[1]), min8(d[2], d[3])),
        min8(min8(d[4], d[5]), min8(d[6], d[7])),
    );
    (energy, min_j)
}
