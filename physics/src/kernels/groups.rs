//! The calls of the element kernels for a material's law and with or without the energy, by a
//! lane group or by one element: one monomorphised body per choice, picked per call.

use super::*;
use crate::material::Law;

/// [`element_forces_reduced_lanes_in`] with or without the energy (`HALVES`, `BOXES` as there).
/// Inlined natively, a function of its own in the web page, as [`full_group`].
#[cfg_attr(not(target_arch = "wasm32"), inline(always))]
#[cfg_attr(target_arch = "wasm32", inline(never))]
pub(super) fn reduced_group<const FMA: bool, const HALVES: bool, const BOXES: bool>(
    mat: &Material,
    lanes: &LaneElements,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[[f64; 8]; 3]; 8],
    work: &mut OnePointScratch,
    energy: bool,
) -> [[f64; 8]; 3] {
    if energy {
        element_forces_reduced_lanes_in::<true, FMA, HALVES, BOXES>(mat, lanes, ul, fl, work)
    } else {
        element_forces_reduced_lanes_in::<false, FMA, HALVES, BOXES>(mat, lanes, ul, fl, work)
    }
}

/// [`full::full_lanes`] for the material's law, with or without the energy; `DIAG` when every
/// lane's J₀ is diagonal ([`GaussData::axis_aligned`]).
#[inline(always)]
pub(super) fn full_group<const FMA: bool, const DIAG: bool, G: full::GaussLanes>(
    mat: &Material,
    g: &G,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[F64x8; 3]; 8],
    work: &mut full::FullScratch,
    energy: bool,
) -> (F64x8, F64x8) {
    with_law!(mat.model, L => full_group_law::<L, FMA, DIAG, G>(mat, g, ul, fl, work, energy))
}

/// [`full_group`] for the law `L`. Inlined into the AVX builds (their target features), a
/// function of its own in the web page, one per law and variant: the engine compiles a
/// WebAssembly function when it is first called and optimises it once it is hot, on a
/// background thread while the run goes on in the baseline code, so a function holding every
/// law (or the 4 variants inlined twice, with and without prefetching, into the chunk loop)
/// kept the run in the baseline code for longer, and a run optimises only its own law's.
#[cfg_attr(not(target_arch = "wasm32"), inline(always))]
#[cfg_attr(target_arch = "wasm32", inline(never))]
fn full_group_law<L: Law, const FMA: bool, const DIAG: bool, G: full::GaussLanes>(
    mat: &Material,
    g: &G,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[F64x8; 3]; 8],
    work: &mut full::FullScratch,
    energy: bool,
) -> (F64x8, F64x8) {
    if energy {
        full::full_lanes::<L, true, FMA, DIAG, G>(mat, g, ul, fl, work)
    } else {
        full::full_lanes::<L, false, FMA, DIAG, G>(mat, g, ul, fl, work)
    }
}

/// Element `e` through the scalar full kernel ([`element_forces`], the Gauss points in lanes),
/// its forces scattered: (strain energy if `energy`, min J).
///
/// # Safety
/// As [`scatter`]; `e` and its nodes in range.
#[inline(always)]
pub(super) unsafe fn scalar_element<const FMA: bool>(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    u: [&[f64]; 3],
    f: PlanesPtr,
    e: u32,
    energy: bool,
) -> (f64, f64) {
    let conn = mesh.elements.get_unchecked(e as usize);
    let gd: &GaussData = classes
        .data
        .get_unchecked(*classes.class_of.get_unchecked(e as usize) as usize);
    let ue: [[f64; 3]; 8] = std::array::from_fn(|a| node_of(u, conn[a]));
    let mut fe = [[0.0; 3]; 8];
    let out = scalar_forces::<FMA>(mat, gd, &ue, &mut fe, energy);
    scatter(f, conn, &fe);
    out
}

/// [`element_forces`] with or without the energy.
#[cfg(not(target_arch = "wasm32"))]
#[inline(always)]
fn scalar_forces<const FMA: bool>(
    mat: &Material,
    gd: &GaussData,
    ue: &[[f64; 3]; 8],
    fe: &mut [[f64; 3]; 8],
    energy: bool,
) -> (f64, f64) {
    if energy {
        element_forces::<true, FMA>(mat, gd, ue, fe)
    } else {
        element_forces::<false, FMA>(mat, gd, ue, fe)
    }
}

/// [`element_forces`] with or without the energy, in the web page: a function per law
/// ([`scalar_forces_law`]).
#[cfg(target_arch = "wasm32")]
#[inline(always)]
fn scalar_forces<const FMA: bool>(
    mat: &Material,
    gd: &GaussData,
    ue: &[[f64; 3]; 8],
    fe: &mut [[f64; 3]; 8],
    energy: bool,
) -> (f64, f64) {
    with_law!(mat.model, L => scalar_forces_law::<L, FMA>(mat, gd, ue, fe, energy))
}

/// [`element_forces`] for the law `L`, a function of its own in the web page, where the groups
/// of 8 take the lane kernel and this one runs only for a chunk's last elements and for mixed
/// groups: inlined there (every law, with and without the energy, at both call sites, twice
/// with the prefetching variant) it made the chunk loop one WebAssembly function that the
/// engine optimised for a long time after the run had started, the run going on meanwhile in
/// its baseline code (docs: performance log).
#[cfg(target_arch = "wasm32")]
#[inline(never)]
fn scalar_forces_law<L: crate::material::Law, const FMA: bool>(
    mat: &Material,
    gd: &GaussData,
    ue: &[[f64; 3]; 8],
    fe: &mut [[f64; 3]; 8],
    energy: bool,
) -> (f64, f64) {
    use crate::element::hex8::element_forces_law;
    if energy {
        element_forces_law::<L, true, FMA>(mat, gd, ue, fe)
    } else {
        element_forces_law::<L, false, FMA>(mat, gd, ue, fe)
    }
}
