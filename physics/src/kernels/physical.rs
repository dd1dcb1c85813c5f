//! The one-point hexahedron with physical hourglass stabilisation (model §1.12) on 8 elements
//! at once, one element per SIMD lane: the stress at the centre as in the one-point rule of
//! §1.6, and hourglass forces from an energy whose stiffness is the element's own bending and
//! warping stiffness, in the spirit of the assumed-strain elements of Belytschko & Bindeman
//! (1993) and Puso (2000): a bent plate's E′ = E/(1 − ν²) and Poisson coupling for the normal
//! strains of the bending modes (no parasitic shear, no λ), the shear modulus μ for the warping
//! modes. E = 9Kμ/(3K + μ) stays below 3μ and E′ below 4μ as K grows, so nothing locks near
//! incompressibility and no coefficient is tuned by hand.
//!
//! With qᵅ = Σₐ γₐᵅ uₐ (the hourglass amplitudes of §1.6), rᵅ = F⁻¹qᵅ (the amplitude pulled
//! back to the reference configuration: rigid rotations leave it unchanged),
//! r̂ᵅ = J₀⁻¹ rᵅ (in the parent axes) and the stiffness K̂ of the class
//! ([`physical_stiffness`]):
//!
//!   Ψ_hg = ½ r̂ · K̂ r̂,
//!   fₐ = V P(F) bₐ + Σᵅ tᵅ (γₐᵅ − bₐ · rᵅ),  tᵅ = F⁻ᵀ J₀⁻ᵀ (K̂ r̂)ᵅ,
//!
//! the exact gradient of V ψ(F) + Ψ_hg (the bₐ · rᵅ term is the derivative of F⁻¹). An affine
//! displacement has qᵅ = 0: the element passes the patch test and rigid motions are free.
//!
//! Every lane group goes through the lanes (the chunk's last, shorter group with its spare
//! lanes repeating an element whose results are dropped), and every corner's J is checked
//! exactly (hourglassing turns corners, not the centre).

// The AVX builds exist on x86_64 only (wasm32 runs the portable one).
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use super::simd::{simd_dispatch, ISA_AVX2, ISA_AVX512};
use super::{
    corners::LaneCorners, gather_padded, keep_min_j, scatter_padded, ElementSums, PlanesPtr,
};
use crate::element::hex8::first_piola_lanes_into;
use crate::material::{cofactor, with_law, F64x8, Law, Mat3, Material, Real};
use crate::mesh::{CentreData, ElementClasses, Mesh};

/// The pairs of hourglass components that are the two normal strains varying linearly along
/// one parent axis d, as (mode α, component i): along ξ, ε_yy of ξη and ε_zz of ζξ; along η,
/// ε_xx of ξη and ε_zz of ηζ; along ζ, ε_xx of ζξ and ε_yy of ηζ (model §1.12).
pub const BENDING_PAIRS: [[(usize, usize); 2]; 3] =
    [[(0, 1), (2, 2)], [(0, 0), (1, 2)], [(2, 0), (1, 1)]];

/// The stiffness of the physical hourglass energy (model §1.12) of an element of volume V and
/// half-lengths ℓ along its parent axes, for the amplitudes r̂ᵅ in parent axes: (the diagonal
/// K̂ᵅᵢ, the coupling k_c of each of the [`BENDING_PAIRS`]). For a mode hᵅ = ξ_m ξ_n
/// (α = 0, 1, 2: the planes (0, 1), (1, 2), (2, 0)) the bending components m and n get
/// E′V/192 with E′ = E/(1 − ν²), each pair of bending components varying along the same axis
/// is coupled by k_c = νE′V/192, and the warping component t (the third) gets
/// μ V (ℓ_t²/ℓ_m² + ℓ_t²/ℓ_n²)/192; for hᵅ = ξηζ (α = 3) every component gets E V/576.
/// On a box these are the energies of uᵢ = Q hᵅ(ξ) (whose amplitude is qᵅᵢ = 8Q): a pair of
/// normal strains eᵢ = Qᵢ ξ_d/ℓᵢ varying along ξ_d stores ½ V ⟨ξ_d²⟩ E′(e₁² + e₂² + 2ν e₁e₂)
/// (plane stress across d: a bent plate's energy, no parasitic shear, no λ); a warping the
/// full element's ½ μ V Q² (1/ℓ_m² + 1/ℓ_n²)/3 of its shear strains; ξηζ the energy
/// ½ E V Q² ⟨ξ_m² ξ_n²⟩/ℓᵢ² of its normal strain.
pub fn physical_stiffness(
    young: f64,
    poisson: f64,
    mu: f64,
    volume: f64,
    l: [f64; 3],
) -> ([[f64; 3]; 4], f64) {
    let plate = young / (1.0 - poisson * poisson);
    let bend = plate * volume / 192.0;
    let mut k = [[0.0; 3]; 4];
    for (al, (m, n)) in [(0usize, 1usize), (1, 2), (2, 0)].into_iter().enumerate() {
        let t = 3 - m - n;
        k[al][m] = bend;
        k[al][n] = bend;
        k[al][t] =
            mu * volume * (l[t] * l[t] / (l[m] * l[m]) + l[t] * l[t] / (l[n] * l[n])) / 192.0;
    }
    k[3] = [young * volume / 576.0; 3];
    (k, poisson * bend)
}

/// The class data of 8 lanes: bₐ, γₐᵅ, V, J₀⁻¹, K̂ᵅ and k_c (lanes innermost).
#[derive(Clone)]
pub(crate) struct PhysicalLanes {
    b: [[F64x8; 3]; 8],
    gamma: [[F64x8; 8]; 4],
    volume: F64x8,
    jinv0: Mat3<F64x8>,
    k: [[F64x8; 3]; 4],
    kc: F64x8,
}

impl Default for PhysicalLanes {
    fn default() -> Self {
        let z = F64x8::splat(0.0);
        PhysicalLanes {
            b: [[z; 3]; 8],
            gamma: [[z; 8]; 4],
            volume: z,
            jinv0: [[z; 3]; 3],
            k: [[z; 3]; 4],
            kc: z,
        }
    }
}

impl PhysicalLanes {
    /// Puts the class data `cd` into lane `l`, with the stiffness of `mat`.
    pub(crate) fn set(&mut self, l: usize, cd: &CentreData, mat: &Material) {
        for a in 0..8 {
            for j in 0..3 {
                self.b[a][j].0[l] = cd.b[a][j];
            }
        }
        for al in 0..4 {
            for a in 0..8 {
                self.gamma[al][a].0[l] = cd.gamma[al][a];
            }
        }
        self.volume.0[l] = cd.volume;
        for d in 0..3 {
            for i in 0..3 {
                self.jinv0[d][i].0[l] = cd.jinv0[d][i];
            }
        }
        let (k, kc) =
            physical_stiffness(mat.young, mat.poisson, mat.mu, cd.volume, cd.half_lengths);
        for al in 0..4 {
            for d in 0..3 {
                self.k[al][d].0[l] = k[al][d];
            }
        }
        self.kc.0[l] = kc;
    }
}

/// M v for a 3×3 `m` (rows first), or Mᵀ v when `TRANSPOSE`.
#[inline(always)]
fn mat_vec<T: Real, const TRANSPOSE: bool, const FMA: bool>(m: &Mat3<T>, v: [T; 3]) -> [T; 3] {
    std::array::from_fn(|i| {
        let e = |j: usize| if TRANSPOSE { m[j][i] } else { m[i][j] };
        e(2).fmadd::<FMA>(v[2], e(1).fmadd::<FMA>(v[1], e(0) * v[0]))
    })
}

/// H = Σₐ uₐ ⊗ bₐ and the hourglass amplitudes qᵅ = Σₐ γₐᵅ uₐ (fused when `FMA`).
#[inline(always)]
pub(crate) fn gradient_and_modes<T: Real, const FMA: bool>(
    u: impl Fn(usize, usize) -> T,
    b: impl Fn(usize, usize) -> T,
    gamma: impl Fn(usize, usize) -> T,
) -> (Mat3<T>, [[T; 3]; 4]) {
    let mut h = [[T::splat(0.0); 3]; 3];
    let mut q = [[T::splat(0.0); 3]; 4];
    for a in 0..8 {
        for i in 0..3 {
            let x = u(a, i);
            for j in 0..3 {
                h[i][j] = x.fmadd::<FMA>(b(a, j), h[i][j]);
            }
            for (al, q_al) in q.iter_mut().enumerate() {
                q_al[i] = gamma(al, a).fmadd::<FMA>(x, q_al[i]);
            }
        }
    }
    (h, q)
}

/// The element's forces from H, P(F), J and the amplitudes qᵅ (module doc, model §1.12):
/// F⁻¹ = (cof F)ᵀ/J, per mode rᵅ = F⁻¹qᵅ and r̂ᵅ = J₀⁻¹rᵅ; s = K̂ r̂ (the diagonal `k` and the
/// coupling `kc` of the [`BENDING_PAIRS`]); per mode tᵅ = F⁻ᵀ J₀⁻ᵀ sᵅ and cₐᵅ = γₐᵅ − bₐ · rᵅ;
/// then fₐ = V P bₐ + Σᵅ tᵅ cₐᵅ into `f`. Returns Ψ_hg = ½ Σᵅ sᵅ · r̂ᵅ if `ENERGY`, else 0.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn stabilised_forces<T: Real, const ENERGY: bool, const FMA: bool>(
    b: impl Fn(usize, usize) -> T,
    gamma: impl Fn(usize, usize) -> T,
    volume: T,
    jinv0: &Mat3<T>,
    k: &[[T; 3]; 4],
    kc: T,
    h: &Mat3<T>,
    q: &[[T; 3]; 4],
    p: &Mat3<T>,
    det: T,
    f: &mut [[T; 3]; 8],
) -> T {
    let (zero, one) = (T::splat(0.0), T::splat(1.0));
    let mut fm = *h;
    for (i, row) in fm.iter_mut().enumerate() {
        row[i] = row[i] + one;
    }
    let cof = cofactor(&fm);
    let inv_j = one / det;
    let finv: Mat3<T> = std::array::from_fn(|i| std::array::from_fn(|j| cof[j][i] * inv_j));
    let r: [[T; 3]; 4] = std::array::from_fn(|al| mat_vec::<_, false, FMA>(&finv, q[al]));
    let rh: [[T; 3]; 4] = std::array::from_fn(|al| mat_vec::<_, false, FMA>(jinv0, r[al]));
    let mut s: [[T; 3]; 4] =
        std::array::from_fn(|al| std::array::from_fn(|d| k[al][d] * rh[al][d]));
    for [(a0, i0), (a1, i1)] in BENDING_PAIRS {
        s[a0][i0] = kc.fmadd::<FMA>(rh[a1][i1], s[a0][i0]);
        s[a1][i1] = kc.fmadd::<FMA>(rh[a0][i0], s[a1][i1]);
    }
    let mut hourglass = zero;
    let mut t = [[zero; 3]; 4];
    let mut c = [[zero; 4]; 8];
    for al in 0..4 {
        if ENERGY {
            let e = s[al][2].fmadd::<FMA>(
                rh[al][2],
                s[al][1].fmadd::<FMA>(rh[al][1], s[al][0] * rh[al][0]),
            );
            hourglass = e.fmadd::<FMA>(T::splat(0.5), hourglass);
        }
        t[al] = mat_vec::<_, true, FMA>(&finv, mat_vec::<_, true, FMA>(jinv0, s[al]));
        let ra = r[al];
        for (a, c_a) in c.iter_mut().enumerate() {
            let br = b(a, 2).fmadd::<FMA>(ra[2], b(a, 1).fmadd::<FMA>(ra[1], b(a, 0) * ra[0]));
            c_a[al] = gamma(al, a) - br;
        }
    }
    let vp: Mat3<T> = std::array::from_fn(|i| std::array::from_fn(|j| volume * p[i][j]));
    for (a, f_a) in f.iter_mut().enumerate() {
        let stress = mat_vec::<_, false, FMA>(&vp, [b(a, 0), b(a, 1), b(a, 2)]);
        for i in 0..3 {
            let mut x = stress[i];
            for al in 0..4 {
                x = t[al][i].fmadd::<FMA>(c[a][al], x);
            }
            f_a[i] = x;
        }
    }
    hourglass
}

/// Internal nodal forces of 8 one-point elements with physical hourglass stabilisation
/// (module doc; model §1.12), element l in lane l: `u[a][i][l]` the displacement of its node a,
/// `f[a][i].0[l]` its force. Returns per lane [V ψ(F), Ψ_hg, J at the centre], the energies
/// only if `ENERGY`.
#[inline(always)]
pub(crate) fn physical_lanes<L: Law, const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    g: &PhysicalLanes,
    u: &[[[f64; 8]; 3]; 8],
    f: &mut [[F64x8; 3]; 8],
) -> [F64x8; 3] {
    let zero = F64x8::splat(0.0);
    let (h, q) = gradient_and_modes::<F64x8, FMA>(
        |a, i| F64x8(u[a][i]),
        |a, j| g.b[a][j],
        |al, a| g.gamma[al][a],
    );
    let mut p = [[zero; 3]; 3];
    let (psi, det) = first_piola_lanes_into::<L, ENERGY, FMA>(mat, &h, &mut p);
    let hourglass = stabilised_forces::<F64x8, ENERGY, FMA>(
        |a, j| g.b[a][j],
        |al, a| g.gamma[al][a],
        g.volume,
        &g.jinv0,
        &g.k,
        g.kc,
        &h,
        &q,
        &p,
        det,
        f,
    );
    let strain = if ENERGY { g.volume * psi } else { zero };
    [strain, hourglass, det]
}

/// [`physical_lanes`] for the material's law, with or without the energies.
#[inline(always)]
fn physical_group<const FMA: bool>(
    mat: &Material,
    g: &PhysicalLanes,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[F64x8; 3]; 8],
    energy: bool,
) -> [F64x8; 3] {
    with_law!(mat.model, L => physical_group_law::<L, FMA>(mat, g, ul, fl, energy))
}

/// [`physical_group`] for the law `L`: inlined natively, a function per law in the web page,
/// which then optimises only its run's law (as `groups::full_group_law`).
#[cfg_attr(not(target_arch = "wasm32"), inline(always))]
#[cfg_attr(target_arch = "wasm32", inline(never))]
fn physical_group_law<L: Law, const FMA: bool>(
    mat: &Material,
    g: &PhysicalLanes,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[F64x8; 3]; 8],
    energy: bool,
) -> [F64x8; 3] {
    if energy {
        physical_lanes::<L, true, FMA>(mat, g, ul, fl)
    } else {
        physical_lanes::<L, false, FMA>(mat, g, ul, fl)
    }
}

simd_dispatch! {
    /// One chunk of a colour with the physically stabilised one-point hexahedron: groups of 8
    /// elements through [`physical_lanes`], the last shorter group with its spare lanes
    /// repeating its last element (their results dropped); the forces scattered element after
    /// element in chunk order. The corners' J of every element exactly.
    pub(crate) fn chunk_forces_physical / chunk_forces_physical_avx2 / chunk_forces_physical_avx512
        / chunk_forces_physical_builds
        => chunk_forces_physical_impl(
            mesh: &Mesh,
            classes: &ElementClasses,
            mat: &Material,
            u: [&[f64]; 3],
            f: PlanesPtr,
            chunk: &[u32],
            energy: bool
        ) -> ElementSums
}

#[inline(always)]
unsafe fn chunk_forces_physical_impl<const FMA: bool, const ISA: u8>(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    u: [&[f64]; 3],
    f: PlanesPtr,
    chunk: &[u32],
    energy: bool,
) -> ElementSums {
    let mut sums = ElementSums {
        strain: 0.0,
        hourglass: 0.0,
        min_j: f64::INFINITY,
        min_element: 0,
        skipped: 0,
        min_stress_j: f64::INFINITY,
        min_stress_element: 0,
    };
    let mut ul = super::gather::NodeLanes::zeros();
    let mut fl = [[F64x8([0.0; 8]); 3]; 8];
    let mut lanes = PhysicalLanes::default();
    let mut corner_lanes = LaneCorners::default();
    let mut staged = [u32::MAX; 8];
    for group in chunk.chunks(8) {
        let n = group.len();
        for l in 0..8 {
            let e = *group.get_unchecked(l.min(n - 1));
            let c = *classes.class_of.get_unchecked(e as usize);
            if c != staged[l] {
                staged[l] = c;
                let cd = classes.centre.get_unchecked(c as usize);
                lanes.set(l, cd, mat);
                corner_lanes.set(l, cd);
            }
        }
        let row = gather_padded(mesh, classes, u, group, &mut ul.0);
        let [strain, hourglass, det] = physical_group::<FMA>(mat, &lanes, &ul.0, &mut fl, energy);
        let corner = corner_lanes.min_jacobian::<FMA>(&ul.0);
        for (l, &e) in group.iter().enumerate() {
            sums.strain += strain.0[l];
            sums.hourglass += hourglass.0[l];
            // The corners' J, or the centre's where it is smaller or NaN.
            let j = if corner[l] < det.0[l] {
                corner[l]
            } else {
                det.0[l]
            };
            keep_min_j(j, e, &mut sums.min_j, &mut sums.min_element);
            keep_min_j(
                det.0[l],
                e,
                &mut sums.min_stress_j,
                &mut sums.min_stress_element,
            );
        }
        scatter_padded::<ISA>(f, mesh, group, row, &fl);
    }
    sums
}

#[cfg(test)]
mod tests;
