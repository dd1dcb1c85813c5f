//! The lane groups' calls of the element kernels for a material's law and with or without the
//! energy: one monomorphised body per choice, picked per group.

use super::*;

/// [`element_forces_reduced_lanes_in`] with or without the energy (`HALVES`, `BOXES` as there).
#[inline(always)]
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
/// lane's J₀ is diagonal ([`GaussData::axis_aligned`]). Inlined into the AVX builds (their
/// target features), a function of its own in the web page: the engine compiles a WebAssembly
/// function when it is first called and optimises it once it is hot, so the 4 variants inlined
/// twice (with and without prefetching) into one function made the page compile 8 kernels to
/// run one.
#[cfg_attr(not(target_arch = "wasm32"), inline(always))]
#[cfg_attr(target_arch = "wasm32", inline(never))]
pub(super) fn full_group<const FMA: bool, const DIAG: bool, G: full::GaussLanes>(
    mat: &Material,
    g: &G,
    ul: &[[[f64; 8]; 3]; 8],
    fl: &mut [[F64x8; 3]; 8],
    work: &mut full::FullScratch,
    energy: bool,
) -> (F64x8, F64x8) {
    with_law!(mat.model, L => if energy {
        full::full_lanes::<L, true, FMA, DIAG, G>(mat, g, ul, fl, work)
    } else {
        full::full_lanes::<L, false, FMA, DIAG, G>(mat, g, ul, fl, work)
    })
}
