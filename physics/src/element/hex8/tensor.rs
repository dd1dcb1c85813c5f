//! Sum factorisation of the trilinear hexahedron at its 2×2×2 Gauss points (model §1.5):
//! the parent-frame displacement gradient at the 8 points, and its transpose, which turns the
//! 8 points' stresses into the 8 nodal forces. Both kernels of full integration (the scalar
//! one, whose lanes are the Gauss points, and the lane one, whose lanes are elements) go
//! through these two functions, so they share every operation.
//!
//! With the node signs sₐ = (sₐ^ξ, sₐ^η, sₐ^ζ) ∈ {±1}³ ([`crate::mesh::HEX_CORNERS`]),
//! ∂Nₐ/∂ξ_d = ⅛ sₐ^d (1 + sₐ^{t₁} t₁)(1 + sₐ^{t₂} t₂), t₁ < t₂ the two other directions. So
//!
//! ```text
//! 8 ∂u/∂ξ_d (t₁, t₂) = Σ_{s₁,s₂ = ±1} (1 + s₁t₁)(1 + s₂t₂) E_d(s₁, s₂)          (T1)
//! ```
//!
//! with E_d(s₁, s₂) = u(+, s₁, s₂) − u(−, s₁, s₂) the difference along the edge of direction d
//! at (s₁, s₂): 8 ∂u/∂ξ_d does not depend on ξ_d, and at the 4 points (t₁, t₂) ∈ {±g}²
//! (g = 1/√3) it is a bilinear interpolation, taken one direction at a time as
//! (a + b) + t (b − a) (the mean and the slope, one multiply–add per point). Then
//! H_q = Σ_d 8 ∂u/∂ξ_d (ξ_q) ⊗ (⅛ ∂ξ_d/∂X) (model §1.5, H = Σₐ uₐ ⊗ ∇ₓNₐ). The forces
//! fₐ = Σ_q w_q det J₀ P_q ∇ₓNₐ(ξ_q) become, with Q_q = w_q det J₀ P_q (⅛ ∂ξ/∂X)ᵀ,
//!
//! ```text
//! fₐ = Σ_d sₐ^d Σ_{t₁,t₂} (1 + sₐ^{t₁} t₁)(1 + sₐ^{t₂} t₂) (Q_{(−,t₁,t₂)} + Q_{(+,t₁,t₂)})_d   (T2)
//! ```
//!
//! the transpose of (T1), taken in the reverse order. Per element and component: 36
//! differences and 9 × 24 flops for the 72 parent derivatives, where Σₐ uₐ ⊗ ∇ₓNₐ point by point
//! took 8 × 144; the forces likewise (`kernels::flops` counts them).
//!
//! One point on an axis-aligned box: the trilinear field is Σ_M m_M Π_{d ∈ M} ξ_d / 8 over the
//! subsets M of {ξ, η, ζ}, with the modal amplitudes m_M = Σₐ (Π_{d ∈ M} sₐ^d) uₐ (T3)
//! ([`node_modes`]). There FB's uniform gradients are bₐ = sₐ ⊙ β and the hourglass vectors
//! γᵅ = hᵅ = the sign products of ξη, ηζ, ζξ, ξηζ (`mesh::CentreData::axis_aligned`), so
//! H = Σₐ uₐ ⊗ bₐ has the columns β_d m_{d}, qᵅ = m_{hᵅ}, and the forces
//! fₐ = V P bₐ + k Σᵅ γₐᵅ qᵅ are the transpose of (T3) applied to the amplitudes V β_d P_{·d} and
//! k qᵅ ([`modes_to_nodes`]).
//!
//! Full integration on an axis-aligned box: ⅛ J₀⁻¹ is one diagonal matrix (c_d) at every point
//! (`mesh::GaussData::axis_aligned`), and with e < f the two directions other than d
//!
//! ```text
//! 8 ∂u/∂ξ_d (ξ_e, ξ_f) = m_{d} + ξ_e m_{de} + ξ_f m_{df} + ξ_e ξ_f m_{def}                 (T4)
//! ```
//!
//! so H at the 4 points (±g, ±g) of direction d comes from 4 modes of (T3) ([`box_gradient`]),
//! and the forces from the transpose: the amplitudes of 1, ξ_e, ξ_f, ξ_e ξ_f in the pair sums of
//! P, summed over the directions into the modes of the nodal field, then the transpose of (T3)
//! ([`box_forces`]).

use crate::material::Real;
use std::ops::{Add, Sub};

/// The Gauss coordinate g = 1/√3 (`mesh::gauss_points`; equal bits, tested).
pub(crate) const GAUSS: f64 = 0.577_350_269_189_625_8;

/// The node of [`crate::mesh::HEX_CORNERS`] whose signs are `b` (0 for −1, 1 for +1).
const fn node(b: [usize; 3]) -> usize {
    let face = match (b[0], b[1]) {
        (0, 0) => 0,
        (1, 0) => 1,
        (1, 1) => 2,
        _ => 3,
    };
    face + 4 * b[2]
}

/// The signs of node (or Gauss point) `a` (0 for −1, 1 for +1), the inverse of [`node`].
const fn bits(a: usize) -> [usize; 3] {
    let face = a % 4;
    let (b0, b1) = match face {
        0 => (0, 0),
        1 => (1, 0),
        2 => (1, 1),
        _ => (0, 1),
    };
    [b0, b1, a / 4]
}

/// The two directions other than d, increasing.
const OTHERS: [[usize; 2]; 3] = [[1, 2], [0, 2], [0, 1]];

/// `EDGES[d][s₁ + 2 s₂]` = (the node at −1, the node at +1) along direction d at the other two
/// signs (s₁, s₂) (0 for −1, 1 for +1).
const EDGES: [[(usize, usize); 4]; 3] = {
    let mut e = [[(0, 0); 4]; 3];
    let mut d = 0;
    while d < 3 {
        let mut k = 0;
        while k < 4 {
            let mut b = [0; 3];
            b[OTHERS[d][0]] = k % 2;
            b[OTHERS[d][1]] = k / 2;
            b[d] = 0;
            let minus = node(b);
            b[d] = 1;
            e[d][k] = (minus, node(b));
            k += 1;
        }
        d += 1;
    }
    e
};

/// `AT[d][q]` = the index p = b₁ + 2 b₂ of the other two coordinates of Gauss point q for
/// direction d (b = 0 at −g, 1 at +g): where (T1)'s 4 values go, and the edge (T2) feeds.
const AT: [[usize; 8]; 3] = {
    let mut at = [[0; 8]; 3];
    let mut d = 0;
    while d < 3 {
        let mut q = 0;
        while q < 8 {
            let b = bits(q);
            at[d][q] = b[OTHERS[d][0]] + 2 * b[OTHERS[d][1]];
            q += 1;
        }
        d += 1;
    }
    at
};

/// Whether node a's sign along d is +1.
const PLUS: [[bool; 3]; 8] = {
    let mut p = [[false; 3]; 8];
    let mut a = 0;
    while a < 8 {
        let b = bits(a);
        p[a] = [b[0] == 1, b[1] == 1, b[2] == 1];
        a += 1;
    }
    p
};

/// Σ_{s = ±1} (1 + s t) x_s at t = −g and t = +g from x₋ = `a`, x₊ = `b`: the mean and the
/// slope, (a + b) + t (b − a), one multiply–add per point (fused when `FMA`). 6 flops. The
/// same weights serve (T1) (values at the points from the edges) and its transpose (T2).
#[inline(always)]
fn along<T: Real, const FMA: bool>(a: T, b: T) -> [T; 2] {
    let (m, s) = (a + b, b - a);
    [
        s.fmadd::<FMA>(T::splat(-GAUSS), m),
        s.fmadd::<FMA>(T::splat(GAUSS), m),
    ]
}

/// Σ_{s₁,s₂} (1 + s₁t₁)(1 + s₂t₂) e[s₁ + 2 s₂] at the 4 points (t₁, t₂) ∈ {±g}², index
/// b₁ + 2 b₂ (T1): [`along`] t₁, then t₂. 24 flops.
#[inline(always)]
fn interpolate<T: Real, const FMA: bool>(e: [T; 4]) -> [T; 4] {
    let v0 = along::<T, FMA>(e[0], e[1]);
    let v1 = along::<T, FMA>(e[2], e[3]);
    let w0 = along::<T, FMA>(v0[0], v1[0]);
    let w1 = along::<T, FMA>(v0[1], v1[1]);
    [w0[0], w1[0], w0[1], w1[1]]
}

/// The transpose of [`interpolate`]: Σ_{t₁,t₂} (1 + s₁t₁)(1 + s₂t₂) r[b₁ + 2 b₂] for the 4
/// sign pairs (s₁, s₂), index s₁ + 2 s₂: [`along`] t₂, then t₁ (T2). 24 flops.
#[inline(always)]
fn spread<T: Real, const FMA: bool>(r: [T; 4]) -> [T; 4] {
    // v_{b₁} = the sums over t₂ for s₂ = −1, +1.
    let v0 = along::<T, FMA>(r[0], r[2]);
    let v1 = along::<T, FMA>(r[1], r[3]);
    let g0 = along::<T, FMA>(v0[0], v1[0]);
    let g1 = along::<T, FMA>(v0[1], v1[1]);
    [g0[0], g0[1], g1[0], g1[1]]
}

/// 8 ∂uᵢ/∂ξ_d at the 8 Gauss points (T1) into `out[q][i][d]`, `u(a, i)` the displacement of
/// node a: 36 edge differences, then [`interpolate`] per direction and component. 252 flops.
#[inline(always)]
pub(crate) fn parent_gradient<T: Real, const FMA: bool>(
    u: impl Fn(usize, usize) -> T,
    out: &mut [[[T; 3]; 3]; 8],
) {
    for d in 0..3 {
        for i in 0..3 {
            let edge = |k: usize| u(EDGES[d][k].1, i) - u(EDGES[d][k].0, i);
            let e = [edge(0), edge(1), edge(2), edge(3)];
            let w = interpolate::<T, FMA>(e);
            for (q, out_q) in out.iter_mut().enumerate() {
                out_q[i][d] = w[AT[d][q]];
            }
        }
    }
}

/// The sums of Q_q,id over the two points along d (−g first) at the 4 positions k of the other
/// coordinates, `q(q, i, d)` the point's Q (the first step of (T2)).
#[inline(always)]
fn pair_sums<T: Real>(q: &impl Fn(usize, usize, usize) -> T, i: usize, d: usize) -> [T; 4] {
    // Written out: a closure here was not inlined (48 calls per lane group).
    let e = &EDGES[d];
    [
        q(e[0].0, i, d) + q(e[0].1, i, d),
        q(e[1].0, i, d) + q(e[1].1, i, d),
        q(e[2].0, i, d) + q(e[2].1, i, d),
        q(e[3].0, i, d) + q(e[3].1, i, d),
    ]
}

/// The factors of an axis-aligned box's modal (T1) and (T2) for a diagonal factor c_d (⅛ ∂ξ_d/∂X_d
/// for H, ⅛ w det J₀ ∂ξ_d/∂X_d for the forces): (c_d, c_d g, c_d g²), g = 1/√3, per direction.
#[inline(always)]
pub(crate) fn box_factors<T: Real>(c: [T; 3]) -> [[T; 3]; 3] {
    let g = T::splat(GAUSS);
    let mut out = [[c[0]; 3]; 3];
    for d in 0..3 {
        let cg = c[d] * g;
        out[d] = [c[d], cg, cg * g];
    }
    out
}

/// H = D·(⅛ J₀⁻¹) at the 8 Gauss points of an axis-aligned box, whose ⅛ J₀⁻¹ is one diagonal
/// (`mesh::GaussData::axis_aligned`), through the modes of the trilinear field (T3): with
/// e < f the two directions other than d,
///
/// ```text
/// 8 ∂u/∂ξ_d (ξ_e, ξ_f) = m_{d} + ξ_e m_{de} + ξ_f m_{df} + ξ_e ξ_f m_{def}                 (T4)
/// ```
///
/// so with a₀ = c m_{d}, a₁ = cg m_{de}, a₂ = cg m_{df}, a₃ = cg² m_{def} (`k[d]` from
/// [`box_factors`] of the diagonal) the 4 values at (±g, ±g) are (a₀ ± a₃) ± (a₁ ± a₂). Into
/// `out[q][i][d]`, `u(a, i)` the displacement of node a. Per component (T3)'s 24 sums, per
/// direction 4 products and 8 sums: 180 flops, where [`parent_gradient`] and the products take
/// 288.
#[inline(always)]
pub(crate) fn box_gradient<T: Real>(
    u: impl Fn(usize, usize) -> T,
    k: &[[T; 3]; 3],
    out: &mut [[[T; 3]; 3]; 8],
) {
    for i in 0..3 {
        let mut x = [T::splat(0.0); 8];
        for (p, x_p) in x.iter_mut().enumerate() {
            *x_p = u(NODE_AT[p], i);
        }
        let m = node_modes(x);
        for d in 0..3 {
            let [e, f] = OTHERS[d];
            let a0 = k[d][0] * m[1 << d];
            let a1 = k[d][1] * m[(1 << d) | (1 << e)];
            let a2 = k[d][1] * m[(1 << d) | (1 << f)];
            let a3 = k[d][2] * m[7];
            let (ap, am, bp, bm) = (a0 + a3, a0 - a3, a1 + a2, a1 - a2);
            // At b_e + 2 b_f (b = 1 at +g, as [`AT`]).
            let w = [ap - bp, am + bm, am - bm, ap + bp];
            for (q, out_q) in out.iter_mut().enumerate() {
                out_q[i][d] = w[AT[d][q]];
            }
        }
    }
}

/// The nodal forces of (T2) on an axis-aligned box from P at the 8 points (`p(q, i, d)`),
/// ⅛ w det J₀ J₀⁻ᵀ being one diagonal: the transpose of (T4). Per direction d the pair sums r
/// over the points along d ([`pair_sums`]) give the amplitudes of 1, t_e, t_f and t_e t_f,
/// M₀ = c Σ r, M₁ = cg Σ s_e r, M₂ = cg Σ s_f r, M₃ = cg² Σ s_e s_f r (`k[d]` from
/// [`box_factors`]); they are the modal amplitudes m_{d} = M₀, m_{de} = M₁(d) + M₁ or M₂ of e,
/// m_{xyz} = Σ_d M₃(d) of the nodal forces, which the transpose of (T3) ([`modes_to_nodes`])
/// turns into fₐ. Per component 3 × (4 pair sums, 8 sums, 4 products), 5 sums of amplitudes and
/// 24: 231 flops, where [`parent_forces`] and the products take 339.
#[inline(always)]
pub(crate) fn box_forces<T: Real>(
    p: impl Fn(usize, usize, usize) -> T,
    k: &[[T; 3]; 3],
    f: &mut [[T; 3]; 8],
) {
    for i in 0..3 {
        // amp[d] = (M₀, M₁, M₂, M₃) of direction d.
        let mut amp = [[T::splat(0.0); 4]; 3];
        for (d, amp_d) in amp.iter_mut().enumerate() {
            let r = pair_sums(&p, i, d);
            // r at b_e + 2 b_f: (−,−), (+,−), (−,+), (+,+).
            let (p0, p1, n0, n1) = (r[0] + r[3], r[1] + r[2], r[3] - r[0], r[1] - r[2]);
            *amp_d = [
                (p0 + p1) * k[d][0],
                (n0 + n1) * k[d][1],
                (n0 - n1) * k[d][1],
                (p0 - p1) * k[d][2],
            ];
        }
        // Mode positions: ξ 1, η 2, ζ 4. OTHERS: ξ → (η, ζ), η → (ξ, ζ), ζ → (ξ, η).
        let m = [
            T::splat(0.0),
            amp[0][0],
            amp[1][0],
            amp[0][1] + amp[1][1],
            amp[2][0],
            amp[0][2] + amp[2][1],
            amp[1][2] + amp[2][2],
            (amp[0][3] + amp[1][3]) + amp[2][3],
        ];
        let x = modes_to_nodes(m);
        for (pos, x_p) in x.iter().enumerate() {
            f[NODE_AT[pos]][i] = *x_p;
        }
    }
}

/// The nodal forces fₐᵢ = Σ_d sₐ^d Σ_q 8 ∂Nₐ/∂ξ_d (ξ_q) / sₐ^d · Q_q,id of (T2) into `f`,
/// `q(q, i, d)` the point's Q: the two points along d summed (−g first, [`pair_sums`]),
/// [`spread`], then per node (sₐ^ξ G_ξ ± G_η) ± G_ζ. 300 flops. Writes every entry of `f` once
/// and builds no zeroed temporary: the lane kernel's 1.5 kB arrays cost a `memset` and a
/// `memcpy` call per lane group when they were.
#[inline(always)]
pub(crate) fn parent_forces<T: Real, const FMA: bool>(
    q: impl Fn(usize, usize, usize) -> T,
    f: &mut [[T; 3]; 8],
) {
    for i in 0..3 {
        let g = [
            spread::<T, FMA>(pair_sums(&q, i, 0)),
            spread::<T, FMA>(pair_sums(&q, i, 1)),
            spread::<T, FMA>(pair_sums(&q, i, 2)),
        ];
        for (a, f_a) in f.iter_mut().enumerate() {
            f_a[i] = node_force(a, &g);
        }
    }
}

/// Node a's share of (T2) from the spread sums `g[d]` of a component: (sₐ^ξ G_ξ ± G_η) ± G_ζ.
/// A function, not closures inside [`parent_forces`]: those were not inlined once the lane
/// kernel had two variants (8 calls per lane group).
#[inline(always)]
fn node_force<T: Real>(a: usize, g: &[[T; 4]; 3]) -> T {
    let b = bits(a);
    let at = [
        g[0][b[OTHERS[0][0]] + 2 * b[OTHERS[0][1]]],
        g[1][b[OTHERS[1][0]] + 2 * b[OTHERS[1][1]]],
        g[2][b[OTHERS[2][0]] + 2 * b[OTHERS[2][1]]],
    ];
    // No negation: a sign change would give NaNs of both signs (an inverted element), and
    // which one a sum of two returns depends on the operand order the compiler picks, so the
    // AVX2 and AVX-512 builds would differ in their bits. Start from the first + sign: two
    // sums or differences per node, three for the node of signs (−, −, −).
    let plus = PLUS[a];
    match plus {
        [true, _, _] => {
            let s = if plus[1] {
                at[0] + at[1]
            } else {
                at[0] - at[1]
            };
            if plus[2] {
                s + at[2]
            } else {
                s - at[2]
            }
        }
        [false, true, _] => {
            let s = at[1] - at[0];
            if plus[2] {
                s + at[2]
            } else {
                s - at[2]
            }
        }
        [false, false, true] => (at[2] - at[0]) - at[1],
        [false, false, false] => ((T::splat(0.0) - at[0]) - at[1]) - at[2],
    }
}

/// The node at each modal position p = b_ξ + 2 b_η + 4 b_ζ (b = 0 for the sign −1, 1 for +1):
/// the order [`node_modes`] reads and [`modes_to_nodes`] writes.
pub(crate) const NODE_AT: [usize; 8] = {
    let mut n = [0; 8];
    let mut p = 0;
    while p < 8 {
        n[p] = node([p & 1, (p >> 1) & 1, p >> 2]);
        p += 1;
    }
    n
};

/// The modal position of the hourglass base vectors hᵅ of [`crate::mesh::hourglass_vectors`]
/// (ξη, ηζ, ζξ, ξηζ), and that of the linear mode along d is 2^d.
pub(crate) const HOURGLASS_AT: [usize; 4] = [0b011, 0b110, 0b101, 0b111];

/// The 8 modal amplitudes of a nodal field of the trilinear hexahedron,
///
/// ```text
/// m_M = Σₐ (Π_{d ∈ M} sₐ^d) xₐ      for each subset M of {ξ, η, ζ}, at position Σ_{d ∈ M} 2^d   (T3)
/// ```
///
/// with `x[p]` the value at node [`NODE_AT`]`[p]`: an unnormalised fast Walsh–Hadamard
/// transform, one stage per direction of 4 sums and 4 differences (24 flops). On an
/// axis-aligned box ∇ₓNₐ = sₐ ⊙ β and γᵅ = hᵅ ([`crate::mesh::CentreData::axis_aligned`]), so
/// H = Σₐ uₐ ⊗ bₐ has the columns β_d m_{d} and the hourglass amplitudes qᵅ = m_{hᵅ}
/// ([`HOURGLASS_AT`]): 24 sums instead of 8 × 3 multiply–adds for a column of H and 8 for
/// each qᵅ.
#[inline(always)]
pub(crate) fn node_modes<T: Copy + Add<Output = T> + Sub<Output = T>>(mut x: [T; 8]) -> [T; 8] {
    for s in [1, 2, 4] {
        for p in 0..8 {
            if p & s == 0 {
                let (lo, hi) = (x[p], x[p | s]);
                x[p] = lo + hi;
                x[p | s] = hi - lo;
            }
        }
    }
    x
}

/// The transpose of (T3): the nodal values xₐ = Σ_M (Π_{d ∈ M} sₐ^d) m_M of the modal
/// amplitudes `m` (position as in [`node_modes`]; the result's position p is node
/// [`NODE_AT`]`[p]`), 24 flops. The box kernel's forces fₐ = V P bₐ + k Σᵅ γₐᵅ qᵅ are this
/// field with m_{d} = V β_d P_{·d}, m_{hᵅ} = k qᵅ and m_∅ = 0.
#[inline(always)]
pub(crate) fn modes_to_nodes<T: Copy + Add<Output = T> + Sub<Output = T>>(mut m: [T; 8]) -> [T; 8] {
    for s in [1, 2, 4] {
        for p in 0..8 {
            if p & s == 0 {
                let (lo, hi) = (m[p], m[p | s]);
                m[p] = lo - hi;
                m[p | s] = lo + hi;
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::super::reference::{gauss_points, shape_derivatives, HEX_CORNERS};
    use super::*;

    #[test]
    fn gauss_coordinate_is_the_mesh_one() {
        assert_eq!(GAUSS.to_bits(), (1.0 / 3f64.sqrt()).to_bits());
        assert_eq!(gauss_points()[6][0].to_bits(), GAUSS.to_bits());
    }

    #[test]
    fn tables_follow_the_node_order() {
        for a in 0..8 {
            assert_eq!(node(bits(a)), a);
            for d in 0..3 {
                assert_eq!(PLUS[a][d], HEX_CORNERS[a][d] > 0.0);
            }
        }
        for d in 0..3 {
            for (minus, plus) in EDGES[d] {
                for c in 0..3 {
                    let (m, p) = (HEX_CORNERS[minus][c], HEX_CORNERS[plus][c]);
                    if c == d {
                        assert_eq!((m, p), (-1.0, 1.0));
                    } else {
                        assert_eq!(m, p);
                    }
                }
            }
        }
    }

    /// (T1) and (T2) against Σₐ uₐ 8 ∂Nₐ/∂ξ_d (ξ_q) and Σ_q Σ_d 8 ∂Nₐ/∂ξ_d (ξ_q) Q_q,d with the
    /// shape derivatives themselves, on arbitrary data: equal to round-off (a few ulp of the
    /// sums' magnitude, ≤ 1e-14 relative here).
    #[test]
    fn sum_factorisation_equals_the_shape_derivatives() {
        let u: [[f64; 3]; 8] =
            std::array::from_fn(|a| std::array::from_fn(|i| ((7 * a + 3 * i) % 11) as f64 - 4.3));
        let mut out = [[[0.0; 3]; 3]; 8];
        parent_gradient::<f64, true>(|a, i| u[a][i], &mut out);
        let xq = gauss_points();
        for q in 0..8 {
            let dn = shape_derivatives(xq[q]);
            for i in 0..3 {
                for d in 0..3 {
                    let direct: f64 = (0..8).map(|a| 8.0 * u[a][i] * dn[a][d]).sum();
                    assert!((out[q][i][d] - direct).abs() < 1e-13, "{q} {i} {d}");
                }
            }
        }
        let qv = |q: usize, i: usize, d: usize| ((5 * q + 3 * i + d) % 13) as f64 * 0.37 - 2.0;
        let mut f = [[0.0; 3]; 8];
        parent_forces::<f64, true>(qv, &mut f);
        for (a, f_a) in f.iter().enumerate() {
            for (i, f_ai) in f_a.iter().enumerate() {
                let direct: f64 = (0..8)
                    .map(|q| {
                        let dn = shape_derivatives(xq[q]);
                        (0..3).map(|d| 8.0 * dn[a][d] * qv(q, i, d)).sum::<f64>()
                    })
                    .sum();
                assert!((f_ai - direct).abs() < 1e-13, "{a} {i}");
            }
        }
        // An axis-aligned box through the modes ((T4) and its transpose), with diagonal factors:
        // the general functions with the factors applied point by point, to round-off.
        let c = [0.37, 1.9, 5.3];
        let k = box_factors(c);
        let mut boxed = [[[0.0; 3]; 3]; 8];
        box_gradient(|a, i| u[a][i], &k, &mut boxed);
        for q in 0..8 {
            for i in 0..3 {
                for d in 0..3 {
                    let want = out[q][i][d] * c[d];
                    assert!((boxed[q][i][d] - want).abs() < 1e-13, "{q} {i} {d}");
                }
            }
        }
        let mut fb = [[0.0; 3]; 8];
        box_forces(qv, &k, &mut fb);
        let mut fq = [[0.0; 3]; 8];
        parent_forces::<f64, true>(|q, i, d| qv(q, i, d) * c[d], &mut fq);
        for a in 0..8 {
            for i in 0..3 {
                assert!((fb[a][i] - fq[a][i]).abs() < 1e-13, "{a} {i}");
            }
        }
    }

    /// (T3) and its transpose against the sign products of [`HEX_CORNERS`] term by term, the
    /// linear modes at 2^d, and the hourglass modes at [`HOURGLASS_AT`] against
    /// `mesh::hourglass_vectors` (integer data: every sum exact, so the equality is exact).
    #[test]
    fn modes_are_the_sign_products_and_their_transpose() {
        let x: [f64; 8] = std::array::from_fn(|a| ((5 * a + 3) % 11) as f64 - 4.0);
        let sign = |a: usize, mask: usize| -> f64 {
            (0..3)
                .filter(|d| mask >> d & 1 == 1)
                .map(|d| HEX_CORNERS[a][d])
                .product()
        };
        let m = node_modes(std::array::from_fn(|p| x[NODE_AT[p]]));
        for (mask, m_mask) in m.iter().enumerate() {
            let direct: f64 = (0..8).map(|a| sign(a, mask) * x[a]).sum();
            assert_eq!(*m_mask, direct, "mode {mask:03b}");
        }
        let h = crate::mesh::hourglass_vectors();
        for (al, &at) in HOURGLASS_AT.iter().enumerate() {
            assert_eq!(
                h[al],
                std::array::from_fn(|a| sign(a, at)),
                "hourglass {al}"
            );
        }
        for d in 0..3 {
            assert_eq!(
                std::array::from_fn::<f64, 8, _>(|a| sign(a, 1 << d)),
                std::array::from_fn(|a| HEX_CORNERS[a][d])
            );
        }
        let back = modes_to_nodes(m);
        for (p, v) in back.iter().enumerate() {
            let a = NODE_AT[p];
            let direct: f64 = (0..8).map(|mask| sign(a, mask) * m[mask]).sum();
            assert_eq!(*v, direct, "node {a}");
            // The transform squared is 8 times the identity.
            assert_eq!(*v, 8.0 * x[a], "node {a}");
        }
    }
}
