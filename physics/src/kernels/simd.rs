//! The per-ISA dispatch of the SIMD kernels: one macro that builds a kernel for AVX-512, for
//! AVX2 (both with fused multiply–adds) and portably, and picks one at run time; plus the
//! AVX-512 and AVX2 gathers of the one-point kernel (the per-ISA twins, kept apart here).

/// The instruction set a kernel build is for (`ISA` of [`simd_dispatch!`]).
pub(crate) const ISA_PORTABLE: u8 = 0;
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) const ISA_AVX2: u8 = 1;
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) const ISA_AVX512: u8 = 2;

/// Defines `$name`, which runs `$imp::<FMA, ISA>` built for AVX-512 (`ISA = ISA_AVX512`) or AVX2
/// (`ISA_AVX2`) with fused multiply–adds when the CPU has them, else the portable build
/// (`FMA = false`, `ISA_PORTABLE`). `ISA` lets an implementation use that instruction set's
/// intrinsics for data movement (gathers, scatters); the arithmetic depends only on `FMA`. The
/// choice is detected once per process, so a given machine always takes the same path and
/// results stay bit-identical whatever the thread count. In tests, `$builds()` lists every build
/// this CPU runs.
macro_rules! simd_dispatch {
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $avx2:ident / $avx512:ident / $builds:ident
        => $imp:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty) => {
        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        $vis unsafe fn $name($($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            {
                if std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("fma") {
                    return $avx512($($arg),*);
                }
                if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                    return $avx2($($arg),*);
                }
            }
            $imp::<false, ISA_PORTABLE>($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $avx2($($arg: $ty),*) -> $ret {
            $imp::<true, ISA_AVX2>($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,avx2,fma")]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $avx512($($arg: $ty),*) -> $ret {
            $imp::<true, ISA_AVX512>($($arg),*)
        }

        /// Every build of the kernel this CPU runs, named: "portable" first, then "avx2" and
        /// "avx512" when the CPU has them (with FMA), for the tests that compare the builds.
        #[cfg(test)]
        #[allow(clippy::type_complexity)]
        pub(super) fn $builds() -> Vec<(&'static str, unsafe fn($($ty),*) -> $ret)> {
            let mut builds: Vec<(&'static str, unsafe fn($($ty),*) -> $ret)> =
                vec![("portable", $imp::<false, ISA_PORTABLE>)];
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("fma") {
                if std::is_x86_feature_detected!("avx2") {
                    builds.push(("avx2", $avx2));
                }
                if std::is_x86_feature_detected!("avx512f") {
                    builds.push(("avx512", $avx512));
                }
            }
            builds
        }
    };
}
pub(crate) use simd_dispatch;

/// Stages the displacements of the 8 nodes of the 8 elements `group` into lanes,
/// `out[a][j][l]` = U[conn(group[l])[a]][j], with AVX-512 gathers straight from the node array.
/// `elements` is the connectivity as i32 (8 per element), `u` the displacements as f64 (3 per
/// node); every offset must fit in an i32.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2")]
pub(crate) unsafe fn gather_lanes_avx512(
    elements: *const i32,
    group: &[u32],
    u: *const f64,
    out: &mut [[[f64; 8]; 3]; 8],
) {
    use std::arch::x86_64::*;
    let e8 = _mm256_slli_epi32::<3>(_mm256_loadu_si256(group.as_ptr() as *const __m256i));
    for (a, out_a) in out.iter_mut().enumerate() {
        let node = _mm256_i32gather_epi32::<4>(
            elements,
            _mm256_add_epi32(e8, _mm256_set1_epi32(a as i32)),
        );
        let row = _mm256_add_epi32(node, _mm256_add_epi32(node, node));
        for (j, out_aj) in out_a.iter_mut().enumerate() {
            _mm512_storeu_pd(out_aj.as_mut_ptr(), _mm512_i32gather_pd::<8>(row, u.add(j)));
        }
    }
}

/// [`gather_lanes_avx512`] with AVX2 gathers (two of 4 lanes per component).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn gather_lanes_avx2(
    elements: *const i32,
    group: &[u32],
    u: *const f64,
    out: &mut [[[f64; 8]; 3]; 8],
) {
    use std::arch::x86_64::*;
    let e8 = _mm256_slli_epi32::<3>(_mm256_loadu_si256(group.as_ptr() as *const __m256i));
    for (a, out_a) in out.iter_mut().enumerate() {
        let node = _mm256_i32gather_epi32::<4>(
            elements,
            _mm256_add_epi32(e8, _mm256_set1_epi32(a as i32)),
        );
        let row = _mm256_add_epi32(node, _mm256_add_epi32(node, node));
        let (lo, hi) = (
            _mm256_castsi256_si128(row),
            _mm256_extracti128_si256::<1>(row),
        );
        for (j, out_aj) in out_a.iter_mut().enumerate() {
            _mm256_storeu_pd(out_aj.as_mut_ptr(), _mm256_i32gather_pd::<8>(u.add(j), lo));
            _mm256_storeu_pd(
                out_aj.as_mut_ptr().add(4),
                _mm256_i32gather_pd::<8>(u.add(j), hi),
            );
        }
    }
}
