//! The per-ISA dispatch of the SIMD kernels: one macro that builds a kernel for AVX-512, for
//! AVX2 (both with fused multiply–adds) and portably, and picks one at run time; plus the
//! AVX-512 and AVX2 node loads of the lane kernels (the per-ISA twins, kept apart here).

/// The instruction set a kernel build is for (`ISA` of [`simd_dispatch!`]).
pub(crate) const ISA_PORTABLE: u8 = 0;
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) const ISA_AVX2: u8 = 1;
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) const ISA_AVX512: u8 = 2;

/// An instruction set the kernels are built for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// No vector extension assumed, no fused multiply–add (the compiler's baseline).
    Portable,
    /// AVX2 with FMA: 256-bit vectors, 4 f64.
    Avx2,
    /// AVX-512F with FMA: 512-bit vectors, 8 f64.
    Avx512,
}

/// The environment variable that forces a kernel build: `portable`, `avx2` or `avx512`.
pub const ISA_VARIABLE: &str = "DECOHESION_ISA";

impl Isa {
    /// Its name, as [`ISA_VARIABLE`] takes it.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Portable => "portable",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }

    /// f64 lanes of one vector register.
    pub fn f64_lanes(self) -> usize {
        match self {
            Isa::Portable => 1,
            Isa::Avx2 => 4,
            Isa::Avx512 => 8,
        }
    }

    /// Whether this CPU runs it (AVX2 and AVX-512 builds also need FMA).
    pub fn supported(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            let fma = std::is_x86_feature_detected!("fma");
            match self {
                Isa::Portable => true,
                Isa::Avx2 => fma && std::is_x86_feature_detected!("avx2"),
                Isa::Avx512 => fma && std::is_x86_feature_detected!("avx512f"),
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self == Isa::Portable
        }
    }

    /// The widest build this CPU runs.
    pub fn detected() -> Isa {
        [Isa::Avx512, Isa::Avx2]
            .into_iter()
            .find(|i| i.supported())
            .unwrap_or(Isa::Portable)
    }

    /// The build named `value` of [`ISA_VARIABLE`], if this CPU runs it; else the error, naming
    /// the variable, the value and what is admissible.
    pub fn parse(value: &str) -> Result<Isa, String> {
        let isa = match value.trim().to_ascii_lowercase().as_str() {
            "portable" => Isa::Portable,
            "avx2" => Isa::Avx2,
            "avx512" => Isa::Avx512,
            _ => {
                return Err(format!(
                    "{ISA_VARIABLE} = {value:?}: unknown instruction set (admissible: portable, avx2, avx512)"
                ))
            }
        };
        if !isa.supported() {
            return Err(format!(
                "{ISA_VARIABLE} = {value:?}: this CPU does not run it (it runs {})",
                Isa::supported_names()
            ));
        }
        Ok(isa)
    }

    /// The builds this CPU runs, named, widest last.
    fn supported_names() -> String {
        let names: Vec<&str> = [Isa::Portable, Isa::Avx2, Isa::Avx512]
            .into_iter()
            .filter(|i| i.supported())
            .map(Isa::name)
            .collect();
        names.join(", ")
    }

    /// The build the kernels run: [`ISA_VARIABLE`] if set (and valid), else [`Isa::detected`].
    /// Read once per process, so a run never mixes builds and results stay bit-identical
    /// whatever the thread count. An invalid value is reported on stderr once and the detected
    /// build is used (`decohesion bench` refuses it instead, through [`Isa::from_env`]).
    pub fn chosen() -> Isa {
        static CHOSEN: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *CHOSEN.get_or_init(|| {
            Isa::from_env().unwrap_or_else(|e| {
                eprintln!("warning: {e}; the kernels use {}", Isa::detected().name());
                Isa::detected()
            })
        })
    }

    /// [`ISA_VARIABLE`] parsed ([`Isa::parse`]), or [`Isa::detected`] if it is unset.
    pub fn from_env() -> Result<Isa, String> {
        match std::env::var(ISA_VARIABLE) {
            Ok(v) => Isa::parse(&v),
            Err(std::env::VarError::NotPresent) => Ok(Isa::detected()),
            Err(e) => Err(format!("{ISA_VARIABLE}: {e}")),
        }
    }
}

/// Defines `$name`, which runs `$imp::<FMA, ISA>` built for AVX-512 (`ISA = ISA_AVX512`) or AVX2
/// (`ISA_AVX2`) with fused multiply–adds, or the portable build (`FMA = false`,
/// `ISA_PORTABLE`), as [`Isa::chosen`] says (the widest the CPU runs unless [`ISA_VARIABLE`]
/// forces one). `ISA` lets an implementation use that instruction set's intrinsics for data
/// movement (gathers, scatters); the arithmetic depends only on `FMA`, so the AVX2 and AVX-512
/// builds give the same bits. The choice is made once per process, so a given machine always
/// takes the same path and results stay bit-identical whatever the thread count. In tests,
/// `$builds()` lists every build this CPU runs.
macro_rules! simd_dispatch {
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $avx2:ident / $avx512:ident / $builds:ident
        => $imp:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty) => {
        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        $vis unsafe fn $name($($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            match $crate::kernels::simd::Isa::chosen() {
                $crate::kernels::simd::Isa::Avx512 => return $avx512($($arg),*),
                $crate::kernels::simd::Isa::Avx2 => return $avx2($($arg),*),
                $crate::kernels::simd::Isa::Portable => {}
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

/// The two 128-bit rows `p0` (low half) and `p1` (high half) as one 256-bit vector.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
unsafe fn pair(p0: *const f64, p1: *const f64) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(_mm_loadu_pd(p0)), _mm_loadu_pd(p1))
}

/// Stages the displacements of the 8 nodes of the 8 elements `group` into lanes,
/// `out[a][j][l]` = U[conn(group[l])[a]][j], with 128-bit loads of each node's (x, y) and
/// (y, z) and an in-register transpose (AVX-512: 8 lanes per vector). Plain loads and
/// shuffles: the AVX-512 and AVX2 gathers they replace took a third of the one-point element
/// loop on AMD Zen 4 (microcoded there). Only data moves, so every value keeps its bits; no
/// load reaches past a node's 3 components.
///
/// # Safety
/// Every element of `group` (8 of them) and every node of theirs must be in range.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) unsafe fn load_lanes_avx512(
    elements: &[[u32; 8]],
    group: &[u32],
    u: *const f64,
    out: &mut [[[f64; 8]; 3]; 8],
) {
    let c = connectivity(elements, group);
    lanes_from_rows_avx512(|a| rows(&c, a, u), out);
}

/// [`load_lanes_avx512`] for a row along x ([`super::is_row`]): node a of lane l is node a of
/// the first element `first` plus l, so the 64 node addresses come from 8 indices (the same
/// loads, the same values).
///
/// # Safety
/// `first`'s nodes plus 0…7 must be in range.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) unsafe fn load_row_lanes_avx512(
    first: &[u32; 8],
    u: *const f64,
    out: &mut [[[f64; 8]; 3]; 8],
) {
    lanes_from_rows_avx512(|a| row_nodes(first, a, u), out);
}

/// The transposing loads of [`load_lanes_avx512`] from the node rows `p(a)` of corner a.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2")]
#[inline]
unsafe fn lanes_from_rows_avx512(
    p_of: impl Fn(usize) -> [*const f64; 8],
    out: &mut [[[f64; 8]; 3]; 8],
) {
    use std::arch::x86_64::*;
    for (a, out_a) in out.iter_mut().enumerate() {
        let p = p_of(a);
        // x y of lanes (0 2 4 6) and (1 3 5 7); y z likewise; unpacking pairs them by lane.
        let ev_xy = wide(pair(p[0], p[2]), pair(p[4], p[6]));
        let od_xy = wide(pair(p[1], p[3]), pair(p[5], p[7]));
        let ev_yz = wide(
            pair(p[0].add(1), p[2].add(1)),
            pair(p[4].add(1), p[6].add(1)),
        );
        let od_yz = wide(
            pair(p[1].add(1), p[3].add(1)),
            pair(p[5].add(1), p[7].add(1)),
        );
        _mm512_storeu_pd(out_a[0].as_mut_ptr(), _mm512_unpacklo_pd(ev_xy, od_xy));
        _mm512_storeu_pd(out_a[1].as_mut_ptr(), _mm512_unpackhi_pd(ev_xy, od_xy));
        _mm512_storeu_pd(out_a[2].as_mut_ptr(), _mm512_unpackhi_pd(ev_yz, od_yz));
    }
}

/// The 256-bit `lo` and `hi` as one 512-bit vector.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn wide(
    lo: std::arch::x86_64::__m256d,
    hi: std::arch::x86_64::__m256d,
) -> std::arch::x86_64::__m512d {
    use std::arch::x86_64::*;
    _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(lo), hi)
}

/// The rows of node `a` of the elements `c` in `u` (3 f64 per node).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn rows(c: &[&[u32; 8]; 8], a: usize, u: *const f64) -> [*const f64; 8] {
    let mut p = [u; 8];
    for l in 0..8 {
        p[l] = u.add(3 * c[l][a] as usize);
    }
    p
}

/// The rows of node `a` of the 8 elements of a row along x whose first element is `first`:
/// node a of lane l is `first[a]` + l.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn row_nodes(first: &[u32; 8], a: usize, u: *const f64) -> [*const f64; 8] {
    let base = u.add(3 * first[a] as usize);
    std::array::from_fn(|l| base.add(3 * l))
}

/// The connectivity rows of the 8 elements `group`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn connectivity<'a>(elements: &'a [[u32; 8]], group: &[u32]) -> [&'a [u32; 8]; 8] {
    let mut c = [elements.get_unchecked(0); 8];
    for l in 0..8 {
        c[l] = elements.get_unchecked(*group.get_unchecked(l) as usize);
    }
    c
}

/// [`load_lanes_avx512`] with 256-bit vectors (4 lanes each).
///
/// # Safety
/// As [`load_lanes_avx512`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn load_lanes_avx2(
    elements: &[[u32; 8]],
    group: &[u32],
    u: *const f64,
    out: &mut [[[f64; 8]; 3]; 8],
) {
    let c = connectivity(elements, group);
    lanes_from_rows_avx2(|a| rows(&c, a, u), out);
}

/// [`load_row_lanes_avx512`] with 256-bit vectors.
///
/// # Safety
/// As [`load_row_lanes_avx512`], on a CPU with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn load_row_lanes_avx2(
    first: &[u32; 8],
    u: *const f64,
    out: &mut [[[f64; 8]; 3]; 8],
) {
    lanes_from_rows_avx2(|a| row_nodes(first, a, u), out);
}

/// The transposing loads of [`load_lanes_avx2`] from the node rows `p(a)` of corner a.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn lanes_from_rows_avx2(
    p_of: impl Fn(usize) -> [*const f64; 8],
    out: &mut [[[f64; 8]; 3]; 8],
) {
    use std::arch::x86_64::*;
    for (a, out_a) in out.iter_mut().enumerate() {
        let p = p_of(a);
        for h in [0, 4] {
            let ev_xy = pair(p[h], p[h + 2]);
            let od_xy = pair(p[h + 1], p[h + 3]);
            let ev_yz = pair(p[h].add(1), p[h + 2].add(1));
            let od_yz = pair(p[h + 1].add(1), p[h + 3].add(1));
            _mm256_storeu_pd(
                out_a[0].as_mut_ptr().add(h),
                _mm256_unpacklo_pd(ev_xy, od_xy),
            );
            _mm256_storeu_pd(
                out_a[1].as_mut_ptr().add(h),
                _mm256_unpackhi_pd(ev_xy, od_xy),
            );
            _mm256_storeu_pd(
                out_a[2].as_mut_ptr().add(h),
                _mm256_unpackhi_pd(ev_yz, od_yz),
            );
        }
    }
}

/// The corner bound J (1 − C|q|/s)³, s = 2J/‖F‖²_F, of 8 lanes in whole vectors
/// ([`super::corner_bound::corner_lower_bound`], the same IEEE operations lane by lane, so the
/// same bits; −∞ unless J > 0 and 1 − C|q|/s > 0). The per-lane form was compiled to a mix of
/// scalar, 128- and 256-bit divisions and square roots.
///
/// # Safety
/// The CPU must have AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
pub(crate) unsafe fn corner_bound_avx512(
    c: &[f64; 8],
    j: &[f64; 8],
    f_norm2: &[f64; 8],
    q_norm2: &[f64; 8],
) -> [f64; 8] {
    use std::arch::x86_64::*;
    let jv = _mm512_loadu_pd(j.as_ptr());
    let s = _mm512_div_pd(
        _mm512_mul_pd(_mm512_set1_pd(2.0), jv),
        _mm512_loadu_pd(f_norm2.as_ptr()),
    );
    let cq = _mm512_mul_pd(
        _mm512_loadu_pd(c.as_ptr()),
        _mm512_sqrt_pd(_mm512_loadu_pd(q_norm2.as_ptr())),
    );
    let r = _mm512_sub_pd(_mm512_set1_pd(1.0), _mm512_div_pd(cq, s));
    let v = _mm512_mul_pd(_mm512_mul_pd(_mm512_mul_pd(jv, r), r), r);
    let zero = _mm512_setzero_pd();
    let ok = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(jv, zero) & _mm512_cmp_pd_mask::<_CMP_GT_OQ>(r, zero);
    let mut b = [0.0; 8];
    _mm512_storeu_pd(
        b.as_mut_ptr(),
        _mm512_mask_blend_pd(ok, _mm512_set1_pd(f64::NEG_INFINITY), v),
    );
    b
}

/// [`corner_bound_avx512`] with 256-bit vectors (4 lanes each).
///
/// # Safety
/// The CPU must have AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn corner_bound_avx2(
    c: &[f64; 8],
    j: &[f64; 8],
    f_norm2: &[f64; 8],
    q_norm2: &[f64; 8],
) -> [f64; 8] {
    use std::arch::x86_64::*;
    let mut b = [0.0; 8];
    for h in [0, 4] {
        let jv = _mm256_loadu_pd(j.as_ptr().add(h));
        let s = _mm256_div_pd(
            _mm256_mul_pd(_mm256_set1_pd(2.0), jv),
            _mm256_loadu_pd(f_norm2.as_ptr().add(h)),
        );
        let cq = _mm256_mul_pd(
            _mm256_loadu_pd(c.as_ptr().add(h)),
            _mm256_sqrt_pd(_mm256_loadu_pd(q_norm2.as_ptr().add(h))),
        );
        let r = _mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_div_pd(cq, s));
        let v = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(jv, r), r), r);
        let zero = _mm256_setzero_pd();
        let ok = _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_GT_OQ>(jv, zero),
            _mm256_cmp_pd::<_CMP_GT_OQ>(r, zero),
        );
        _mm256_storeu_pd(
            b.as_mut_ptr().add(h),
            _mm256_blendv_pd(_mm256_set1_pd(f64::NEG_INFINITY), v, ok),
        );
    }
    b
}
