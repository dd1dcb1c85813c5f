//! The F-bar hexahedron (model §1.11) on 8 elements at once, one element per SIMD lane: the
//! 2×2×2 Gauss points of the full kernel ([`super::full`]) with the deformation gradient at
//! each point replaced by F̄_q = α_q F_q, α_q = (J̄/J_q)^{1/3}, J̄ = Σ_q w_q J_q / Σ_q w_q the
//! element's volume ratio. The volumetric part of the deformation is then one per element (the
//! explicit analogue of Q1–P0), so a nearly incompressible material does not lock.
//!
//! The forces are the exact gradient of Ψ = Σ_q w_q ψ(F̄_q) (w_q = w det J₀ at the point):
//! with P̄_q = P(F̄_q), s_q = α_q (P̄_q : F_q)/3, S̄ = Σ_q w_q s_q and V̄ = Σ_q w_q J_q,
//!
//!   fₐ = Σ_q w_q P̂_q ∇ₓNₐ(ξ_q),  P̂_q = α_q P̄_q + (S̄/V̄ − s_q/J_q) cof F_q,
//!
//! the effective first Piola–Kirchhoff stress of model §1.11, eq. (1.11c). Under a homogeneous
//! deformation every J_q is J̄, α_q = 1 and the bracket vanishes: the element is the full one,
//! and passes the same patch test.
//!
//! Every lane group goes through the lanes (the chunk's last, shorter group with its spare
//! lanes repeating an element whose results are dropped): there is no scalar twin whose bits
//! the lanes must match, so mixed shapes take the general path and the portable build runs the
//! same lanes without a vector unit.

// The AVX builds exist on x86_64 only (wasm32 runs the portable one).
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use super::simd::{simd_dispatch, ISA_AVX2, ISA_AVX512};
use super::{
    full::{GaussLanes, LaneGauss},
    gather_padded, keep_min_j, scatter_padded, PlanesPtr,
};
use crate::element::hex8::{
    box_factors, box_forces, box_gradient, first_piola_lanes_into, parent_forces, parent_gradient,
};
use crate::material::{
    cofactor, deformation_gradient, determinant, row_dot, with_law, F64x8, Law, Mat3, Material,
    Real,
};
use crate::mesh::{ElementClasses, Mesh};

/// The per-point work arrays of [`fbar_lanes`]: the parent derivatives (then Q), H and P̂ at the
/// 8 Gauss points, J_q and s_q; every entry written before it is read.
#[derive(Clone)]
pub(crate) struct FbarScratch {
    dq: [Mat3<F64x8>; 8],
    hq: [Mat3<F64x8>; 8],
    pq: [Mat3<F64x8>; 8],
    det: [F64x8; 8],
    s: [F64x8; 8],
}

impl Default for FbarScratch {
    fn default() -> Self {
        let z = F64x8::splat(0.0);
        FbarScratch {
            dq: [[[z; 3]; 3]; 8],
            hq: [[[z; 3]; 3]; 8],
            pq: [[[z; 3]; 3]; 8],
            det: [z; 8],
            s: [z; 8],
        }
    }
}

/// H̄ = F̄ − I = αH + (α − 1)I, the displacement gradient of F̄ = αF (model §1.11, eq. (1.11a)).
#[inline(always)]
pub(crate) fn scaled_gradient<T: Real>(h: &Mat3<T>, alpha: T) -> Mat3<T> {
    let mut out = *h;
    for (i, row) in out.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = alpha * h[i][j];
            if i == j {
                *x = *x + (alpha - T::splat(1.0));
            }
        }
    }
    out
}

/// ∛r for r ∈ [½, 2] by +, −, ×, ÷ only, so that it runs in the vector lanes: the start
/// y₀ = 1 + d/3 − d²/9 (d = r − 1, Taylor; error ≤ 0.04 on the interval), then three Halley
/// steps y ← y (y³ + 2r)/(2y³ + r), each cubing the relative error (0.04 → 10⁻⁵ → 10⁻¹⁵ →
/// rounding).
#[inline(always)]
pub(crate) fn halley_cube_root<T: Real>(r: T) -> T {
    let (one, two) = (T::splat(1.0), T::splat(2.0));
    let d = r - one;
    let mut y = one + d * T::splat(1.0 / 3.0) - d * d * T::splat(1.0 / 9.0);
    for _ in 0..3 {
        let y3 = y * y * y;
        y = y * (y3 + two * r) / (two * y3 + r);
    }
    y
}

/// α = (J̄/J)^{1/3} on the 8 lanes: by [`halley_cube_root`] when every lane's J̄/J is in [½, 2]
/// (an element whose volume ratio varies by less than a factor 2 between its points: every
/// element but a collapsing one), else by the library's `cbrt` lane by lane (not vectorised).
/// Which of the two a lane takes depends on its lane group, which the mesh fixes (not the
/// thread count).
#[inline(always)]
pub(crate) fn volume_factor(jbar: F64x8, j: F64x8) -> F64x8 {
    let r = jbar / j;
    let mut in_range = true;
    for x in r.0 {
        in_range &= (0.5..=2.0).contains(&x);
    }
    if in_range {
        halley_cube_root(r)
    } else {
        F64x8(r.0.map(f64::cbrt))
    }
}

/// At one point, from P̄ = P(αF) in `p`: s = α (P̄ : F)/3, and `p` ← αP̄ (the first part of
/// P̂, eq. (1.11c)). Returns s.
#[inline(always)]
pub(crate) fn scale_stress<T: Real, const FMA: bool>(p: &mut Mat3<T>, f: &Mat3<T>, alpha: T) -> T {
    let mut pf = T::splat(0.0);
    for i in 0..3 {
        for j in 0..3 {
            pf = p[i][j].fmadd::<FMA>(f[i][j], pf);
            p[i][j] = alpha * p[i][j];
        }
    }
    alpha * pf * T::splat(1.0 / 3.0)
}

/// At one point: `p` ← p + c cof F with c = S̄/V̄ − s/J (the second part of P̂, eq. (1.11c)).
#[inline(always)]
pub(crate) fn add_pressure_correction<T: Real, const FMA: bool>(
    p: &mut Mat3<T>,
    f: &Mat3<T>,
    c: T,
) {
    let cof = cofactor(f);
    for i in 0..3 {
        for j in 0..3 {
            p[i][j] = c.fmadd::<FMA>(cof[i][j], p[i][j]);
        }
    }
}

/// Internal nodal forces of 8 F-bar elements, element l in lane l (module doc):
/// `u[a][i][l]` the displacement of its node a, `f[a][i].0[l]` its force. Returns per lane
/// (Ψ = Σ_q w_q ψ(F̄_q) if `ENERGY`, else 0; min_q J_q). `DIAG`: every lane is an axis-aligned
/// box, H and the forces through the modes of the trilinear field as in [`super::full`].
#[inline(always)]
pub(crate) fn fbar_lanes<
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
    work: &mut FbarScratch,
) -> (F64x8, F64x8) {
    let zero = F64x8::splat(0.0);
    let FbarScratch { dq, hq, pq, det, s } = work;
    // H_q at the 8 points.
    if DIAG {
        let k = box_factors([g.jinv(0, 0, 0), g.jinv(1, 1, 0), g.jinv(2, 2, 0)]);
        box_gradient(|a, i| F64x8(u[a][i]), &k, hq);
    } else {
        parent_gradient::<F64x8, FMA>(|a, i| F64x8(u[a][i]), dq);
        for q in 0..8 {
            for i in 0..3 {
                for j in 0..3 {
                    let jinv = [g.jinv(0, j, q), g.jinv(1, j, q), g.jinv(2, j, q)];
                    hq[q][i][j] = row_dot::<_, FMA>(&dq[q][i], jinv);
                }
            }
        }
    }
    // J_q, V̄ = Σ w_q J_q and V₀ = Σ w_q.
    let (mut vbar, mut v0) = (zero, zero);
    for q in 0..8 {
        det[q] = determinant::<F64x8, FMA>(&deformation_gradient(&hq[q]));
        vbar = g.wdet(q).fmadd::<FMA>(det[q], vbar);
        v0 = v0 + g.wdet(q);
    }
    let jbar = vbar / v0;
    // P̄_q = P(α_q F_q), s_q, αP̄ and the energy.
    let mut energy = zero;
    let mut sbar = zero;
    for q in 0..8 {
        let alpha = volume_factor(jbar, det[q]);
        let hbar = scaled_gradient(&hq[q], alpha);
        let (psi, _) = first_piola_lanes_into::<L, ENERGY, FMA>(mat, &hbar, &mut pq[q]);
        if ENERGY {
            energy = psi.fmadd::<FMA>(g.wdet(q), energy);
        }
        s[q] = scale_stress::<F64x8, FMA>(&mut pq[q], &deformation_gradient(&hq[q]), alpha);
        sbar = g.wdet(q).fmadd::<FMA>(s[q], sbar);
    }
    // P̂_q = αP̄_q + (S̄/V̄ − s_q/J_q) cof F_q.
    let p_mean = sbar / vbar;
    for q in 0..8 {
        let c = p_mean - s[q] / det[q];
        add_pressure_correction::<F64x8, FMA>(&mut pq[q], &deformation_gradient(&hq[q]), c);
    }
    if DIAG {
        let k = box_factors([g.wjinv(0, 0, 0), g.wjinv(1, 1, 0), g.wjinv(2, 2, 0)]);
        box_forces(|q, i, d| pq[q][i][d], &k, f);
    } else {
        for q in 0..8 {
            for i in 0..3 {
                for k in 0..3 {
                    let w = [g.wjinv(k, 0, q), g.wjinv(k, 1, q), g.wjinv(k, 2, q)];
                    dq[q][i][k] = row_dot::<_, FMA>(&pq[q][i], w);
                }
            }
        }
        parent_forces::<F64x8, FMA>(|q, i, k| dq[q][i][k], f);
    }
    let mut min_j = det[0];
    for d in &det[1..] {
        for l in 0..8 {
            min_j.0[l] = min_j.0[l].min(d.0[l]);
        }
    }
    (energy, min_j)
}

/// [`fbar_lanes`] for the material's law, with or without the energy.
#[inline(always)]
fn fbar_group<const FMA: bool, const DIAG: bool>(
    mat: &Material,
    g: &LaneGauss,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[F64x8; 3]; 8],
    work: &mut FbarScratch,
    energy: bool,
) -> (F64x8, F64x8) {
    with_law!(mat.model, L => fbar_group_law::<L, FMA, DIAG>(mat, g, ul, fl, work, energy))
}

/// [`fbar_group`] for the law `L`: inlined natively, a function per law and variant in the web
/// page, which then optimises only its run's law (as `groups::full_group_law`).
#[cfg_attr(not(target_arch = "wasm32"), inline(always))]
#[cfg_attr(target_arch = "wasm32", inline(never))]
fn fbar_group_law<L: Law, const FMA: bool, const DIAG: bool>(
    mat: &Material,
    g: &LaneGauss,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[F64x8; 3]; 8],
    work: &mut FbarScratch,
    energy: bool,
) -> (F64x8, F64x8) {
    if energy {
        fbar_lanes::<L, true, FMA, DIAG, LaneGauss>(mat, g, ul, fl, work)
    } else {
        fbar_lanes::<L, false, FMA, DIAG, LaneGauss>(mat, g, ul, fl, work)
    }
}

simd_dispatch! {
    /// One chunk of a colour with the F-bar hexahedron: groups of 8 elements through
    /// [`fbar_lanes`], the last shorter group with its spare lanes repeating its last element
    /// (their results dropped); the forces scattered element after element in chunk order.
    /// Returns (strain energy if `energy`, min J at the Gauss points, its element).
    pub(crate) fn chunk_forces_fbar / chunk_forces_fbar_avx2 / chunk_forces_fbar_avx512
        / chunk_forces_fbar_builds
        => chunk_forces_fbar_impl(
            mesh: &Mesh,
            classes: &ElementClasses,
            mat: &Material,
            u: [&[f64]; 3],
            f: PlanesPtr,
            chunk: &[u32],
            energy: bool
        ) -> (f64, f64, usize)
}

#[inline(always)]
unsafe fn chunk_forces_fbar_impl<const FMA: bool, const ISA: u8>(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    u: [&[f64]; 3],
    f: PlanesPtr,
    chunk: &[u32],
    energy: bool,
) -> (f64, f64, usize) {
    let mut e_sum = 0.0;
    let mut min_j = f64::INFINITY;
    let mut min_e = 0usize;
    let mut ul = super::gather::NodeLanes::zeros();
    let mut fl = [[F64x8([0.0; 8]); 3]; 8];
    let mut lanes = LaneGauss::default();
    let mut staged = [u32::MAX; 8];
    let mut work = FbarScratch::default();
    for group in chunk.chunks(8) {
        let n = group.len();
        let mut boxes = 0;
        for l in 0..8 {
            let e = *group.get_unchecked(l.min(n - 1));
            let c = *classes.class_of.get_unchecked(e as usize);
            if c != staged[l] {
                staged[l] = c;
                lanes.set(l, classes.data.get_unchecked(c as usize));
            }
            boxes += classes.data.get_unchecked(c as usize).axis_aligned as usize;
        }
        let row = gather_padded(mesh, classes, u, group, &mut ul.0);
        let (en, det) = if boxes == 8 {
            fbar_group::<FMA, true>(mat, &lanes, &ul.0, &mut fl, &mut work, energy)
        } else {
            fbar_group::<FMA, false>(mat, &lanes, &ul.0, &mut fl, &mut work, energy)
        };
        for (l, &e) in group.iter().enumerate() {
            e_sum += en.0[l];
            keep_min_j(det.0[l], e, &mut min_j, &mut min_e);
        }
        scatter_padded::<ISA>(f, mesh, group, row, &fl);
    }
    (e_sum, min_j, min_e)
}

#[cfg(test)]
pub(super) mod tests;
