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

use crate::material::{
    displacement_gradient, first_piola_lanes, row_dot, F64x8, Law, Material, Real,
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

/// Internal nodal forces of 8 elements, fₐ = Σ_q w_q det J₀ P(F_q) ∇ₓNₐ(ξ_q) (PHYSICS.md §2),
/// element l in lane l: `u[a][i][l]` the displacement of its node a, `f[a][i][l]` its force.
/// Returns per lane (strain energy Σ_q w_q det J₀ ψ_q if `ENERGY`, else 0; min_q J_q), each
/// lane bit-identical to [`crate::material::element_forces`] on that element.
#[inline(always)]
pub(crate) fn full_lanes<L: Law, const ENERGY: bool, const FMA: bool, G: GaussLanes>(
    mat: &Material,
    g: &G,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[[f64; 8]; 3]; 8],
) -> (F64x8, F64x8) {
    let zero = F64x8::splat(0.0);
    let mut p = [[[zero; 3]; 3]; 8];
    let mut det = [zero; 8];
    let mut energy = zero;
    for q in 0..8 {
        let h = displacement_gradient::<F64x8, FMA>(|a, i| F64x8(u[a][i]), |a, j| g.grad(a, j, q));
        let (pq, psi, jq) = first_piola_lanes::<L, ENERGY, FMA>(mat, &h);
        p[q] = pq;
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
