//! The full-integration (2×2×2 Gauss) kernel on 8 elements at once, one element per SIMD lane
//! (PHYSICS.md §2): for each Gauss point q in turn, H_q = Σₐ uₐ ⊗ ∇ₓNₐ(ξ_q), P_q = P(I + H_q)
//! and J_q on the 8 elements; then fₐ = Σ_q P_q (w_q det J₀ ∇ₓNₐ(ξ_q)), Ψ = Σ_q w_q det J₀ ψ_q,
//! and min_q J_q per element.
//!
//! Each lane carries out the operations of the scalar kernel
//! ([`crate::material::element_forces`], whose lanes are the Gauss points of one element) in
//! the same order: H accumulated node after node, the same pointwise stress
//! ([`first_piola_lanes`]), each row product (r₀g₀ + r₁g₁) + r₂g₂, the Gauss points summed
//! pairwise ((q₀ + q₁) + (q₂ + q₃)) + ((q₄ + q₅) + (q₆ + q₇)), the energy point after point and
//! min J by the same tree. So every element gets the scalar kernel's bits, and the golden runs
//! do not move.

use super::simd::ISA_AVX2;
use crate::material::{
    displacement_gradient, first_piola_lanes_into, row_dot, F64x8, Law, Material, Real,
};
use crate::mesh::GaussData;

/// The reference data of the 8 elements of a lane group at the Gauss points.
pub(crate) trait GaussLanes {
    /// ∂Nₐ/∂Xⱼ at Gauss point q, per lane [1/m].
    fn grad(&self, a: usize, j: usize, q: usize) -> F64x8;
    /// w_q det J₀ ∂Nₐ/∂Xⱼ at Gauss point q, per lane [m²].
    fn wgrad(&self, a: usize, j: usize, q: usize) -> F64x8;
    /// w_q det J₀, per lane [m³].
    fn wdet(&self, q: usize) -> F64x8;
}

/// Eight elements of one class (a structured box has one): the class's data broadcast.
pub(crate) struct OneClass<'a>(pub &'a GaussData);

impl GaussLanes for OneClass<'_> {
    #[inline(always)]
    fn grad(&self, a: usize, j: usize, q: usize) -> F64x8 {
        F64x8::splat(self.0.grad[a][j][q])
    }
    #[inline(always)]
    fn wgrad(&self, a: usize, j: usize, q: usize) -> F64x8 {
        F64x8::splat(self.0.wgrad[a][j][q])
    }
    #[inline(always)]
    fn wdet(&self, q: usize) -> F64x8 {
        F64x8::splat(self.0.wdet[q])
    }
}

/// Eight elements of several classes: each lane's data staged (`[q][a][j]`, lanes innermost).
#[derive(Clone)]
pub(crate) struct LaneGauss {
    grad: [[[F64x8; 3]; 8]; 8],
    wgrad: [[[F64x8; 3]; 8]; 8],
    wdet: [F64x8; 8],
}

impl Default for LaneGauss {
    fn default() -> Self {
        let z = F64x8::splat(0.0);
        LaneGauss {
            grad: [[[z; 3]; 8]; 8],
            wgrad: [[[z; 3]; 8]; 8],
            wdet: [z; 8],
        }
    }
}

impl LaneGauss {
    /// Puts the class data `gd` into lane `l`.
    #[inline(always)]
    pub(crate) fn set(&mut self, l: usize, gd: &GaussData) {
        for q in 0..8 {
            for a in 0..8 {
                for j in 0..3 {
                    self.grad[q][a][j].0[l] = gd.grad[a][j][q];
                    self.wgrad[q][a][j].0[l] = gd.wgrad[a][j][q];
                }
            }
            self.wdet[q].0[l] = gd.wdet[q];
        }
    }
}

impl GaussLanes for LaneGauss {
    #[inline(always)]
    fn grad(&self, a: usize, j: usize, q: usize) -> F64x8 {
        self.grad[q][a][j]
    }
    #[inline(always)]
    fn wgrad(&self, a: usize, j: usize, q: usize) -> F64x8 {
        self.wgrad[q][a][j]
    }
    #[inline(always)]
    fn wdet(&self, q: usize) -> F64x8 {
        self.wdet[q]
    }
}

/// Lane-wise `f64::min` (a NaN lane of one operand gives the other's).
#[inline(always)]
fn min8(x: F64x8, y: F64x8) -> F64x8 {
    let mut r = x.0;
    for l in 0..8 {
        r[l] = r[l].min(y.0[l]);
    }
    F64x8(r)
}

/// H = Σₐ uₐ ⊗ gₐ of 8 elements at one point into `h`, `u[a][i][l]` and `g(a, j)` per lane,
/// as [`displacement_gradient`] on [`F64x8`] (each Hᵢⱼ accumulated node after node, fused
/// when `FMA`: the same bits) but 4 lanes at a time: the nine sums of 4 lanes fill nine of
/// AVX2's 16 registers, where the nine sums of 8 lanes (18 registers) spilled to the stack
/// and each fused multiply–add waited on a store and a reload.
#[inline(always)]
pub(crate) fn gradient_by_halves<const FMA: bool>(
    u: &[[[f64; 8]; 3]; 8],
    g: impl Fn(usize, usize) -> F64x8,
    h: &mut [[F64x8; 3]; 3],
) {
    for half in [0, 4] {
        let mut acc = [[[0.0f64; 4]; 3]; 3];
        for a in 0..8 {
            for (i, acc_i) in acc.iter_mut().enumerate() {
                for (j, acc_ij) in acc_i.iter_mut().enumerate() {
                    let gj = g(a, j);
                    for (l, s) in acc_ij.iter_mut().enumerate() {
                        *s = u[a][i][half + l].fmadd::<FMA>(gj.0[half + l], *s);
                    }
                }
            }
        }
        for i in 0..3 {
            for j in 0..3 {
                for l in 0..4 {
                    h[i][j].0[half + l] = acc[i][j][l];
                }
            }
        }
    }
}

/// The per-point work arrays of [`full_lanes`] (P and J at the 8 Gauss points, H at one),
/// kept by the caller across lane groups: every entry is written before it is read, and a
/// fresh zeroed array per group cost the AVX2 build a 4.6 kB `memset` call per group (its
/// ymm stores exceed the compiler's inline limit, AVX-512's zmm stores do not).
#[derive(Clone)]
pub(crate) struct FullScratch {
    p: [[[F64x8; 3]; 3]; 8],
    h: [[F64x8; 3]; 3],
}

impl Default for FullScratch {
    fn default() -> Self {
        let z = F64x8::splat(0.0);
        FullScratch {
            p: [[[z; 3]; 3]; 8],
            h: [[z; 3]; 3],
        }
    }
}

/// Internal nodal forces of 8 elements, fₐ = Σ_q w_q det J₀ P(F_q) ∇ₓNₐ(ξ_q) (PHYSICS.md §2),
/// element l in lane l: `u[a][i][l]` the displacement of its node a, `f[a][i][l]` its force.
/// Returns per lane (strain energy Σ_q w_q det J₀ ψ_q if `ENERGY`, else 0; min_q J_q), each
/// lane bit-identical to [`crate::material::element_forces`] on that element. The AVX2 build
/// (`ISA`) computes H 4 lanes at a time ([`gradient_by_halves`], for its 16 registers).
#[inline(always)]
pub(crate) fn full_lanes<
    L: Law,
    const ENERGY: bool,
    const FMA: bool,
    const ISA: u8,
    G: GaussLanes,
>(
    mat: &Material,
    g: &G,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[[f64; 8]; 3]; 8],
    work: &mut FullScratch,
) -> (F64x8, F64x8) {
    let zero = F64x8::splat(0.0);
    let FullScratch { p, h } = work;
    let mut det = [zero; 8];
    let mut energy = zero;
    for q in 0..8 {
        if ISA == ISA_AVX2 {
            gradient_by_halves::<FMA>(u, |a, j| g.grad(a, j, q), h);
        } else {
            *h = displacement_gradient::<F64x8, FMA>(|a, i| F64x8(u[a][i]), |a, j| g.grad(a, j, q));
        }
        let (psi, jq) = first_piola_lanes_into::<L, ENERGY, FMA>(mat, h, &mut p[q]);
        det[q] = jq;
        if ENERGY {
            energy = energy + psi * g.wdet(q);
        }
    }
    for a in 0..8 {
        for i in 0..3 {
            let mut acc = [zero; 8];
            for q in 0..8 {
                let w = [g.wgrad(a, 0, q), g.wgrad(a, 1, q), g.wgrad(a, 2, q)];
                acc[q] = row_dot::<_, FMA>(&p[q][i], w);
            }
            f[a][i] = (((acc[0] + acc[1]) + (acc[2] + acc[3]))
                + ((acc[4] + acc[5]) + (acc[6] + acc[7])))
                .0;
        }
    }
    let d = det;
    let min_j = min8(
        min8(min8(d[0], d[1]), min8(d[2], d[3])),
        min8(min8(d[4], d[5]), min8(d[6], d[7])),
    );
    (energy, min_j)
}
