//! The per-ISA dispatch of the SIMD kernels: one macro that builds a kernel for AVX-512, for
//! AVX2 (both with fused multiply–adds) and portably, and picks one at run time; plus the
//! AVX-512 and AVX2 twins of the corner bound and of the row scatter's line adds, kept apart
//! here.
//!
//! The web page (wasm32) runs the portable build, compiled with WebAssembly SIMD for the whole
//! module (`-C target-feature=+simd128`, `.cargo/config.toml`) as the ISA [`ISA_SIMD128`]: its
//! 8-lane arithmetic is f64x2 pairs (`material::real`), the full kernel puts 8 elements in
//! lanes as the AVX builds do, and simd128 has no fused multiply–add, so it gives the portable
//! build's bits (`web/test_page.py` checks the page against `DECOHESION_ISA=portable` bit for
//! bit).
//! WebAssembly has no run-time feature detection (a module with SIMD instructions does not load
//! on an engine without them), so there is no second wasm32 build to choose from.

/// The instruction set a kernel build is for (`ISA` of [`simd_dispatch!`]).
pub(crate) const ISA_PORTABLE: u8 = 0;
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) const ISA_AVX2: u8 = 1;
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) const ISA_AVX512: u8 = 2;
/// The portable build compiled for WebAssembly SIMD (the web page): the portable build's
/// arithmetic (no fused multiply–add, the same bits), [`crate::material::F64x8`]'s as f64x2
/// pairs, and, where a kernel has a choice, the 8-elements-in-lanes form that the AVX builds
/// take (the full kernel's; natively the portable build runs it one element at a time).
#[cfg_attr(
    not(all(target_arch = "wasm32", target_feature = "simd128")),
    allow(dead_code)
)]
pub(crate) const ISA_SIMD128: u8 = 3;
/// The `ISA` of the portable build on this target: [`ISA_SIMD128`] on wasm32 with simd128,
/// else [`ISA_PORTABLE`].
pub(crate) const ISA_OF_PORTABLE: u8 =
    if cfg!(all(target_arch = "wasm32", target_feature = "simd128")) {
        ISA_SIMD128
    } else {
        ISA_PORTABLE
    };

/// An instruction set the kernels are built for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// No vector extension assumed, no fused multiply–add (the compiler's baseline: SSE2 on
    /// x86-64, simd128 in the web page).
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
///
/// Each build is the function `run` of a module of its own (`$name` for the portable build,
/// `$avx2`, `$avx512`): rustc splits a crate into codegen units by module, so the builds of a
/// kernel, each a large function once its inlined body is in, are optimised by LLVM in parallel
/// rather than one after another in one unit.
macro_rules! simd_dispatch {
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $avx2:ident / $avx512:ident / $builds:ident
        => $imp:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty $(, const by $flag:ident)?) => {
        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        $vis unsafe fn $name($($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            match $crate::kernels::simd::Isa::chosen() {
                $crate::kernels::simd::Isa::Avx512 => return $avx512::run($($arg),*),
                $crate::kernels::simd::Isa::Avx2 => return $avx2::run($($arg),*),
                $crate::kernels::simd::Isa::Portable => {}
            }
            $name::run($($arg),*)
        }

        /// The portable build of the function of the same name.
        mod $name {
            #[allow(unused_imports)]
            use super::*;
            #[allow(clippy::too_many_arguments)]
            pub(super) unsafe fn run($($arg: $ty),*) -> $ret {
                simd_dispatch!(
                    @call $imp, false, { $crate::kernels::simd::ISA_OF_PORTABLE }, [$($flag)?],
                    ($($arg),*)
                )
            }
        }

        /// The AVX2 build.
        #[cfg(target_arch = "x86_64")]
        mod $avx2 {
            #[allow(unused_imports)]
            use super::*;
            #[target_feature(enable = "avx2,fma")]
            #[allow(clippy::too_many_arguments)]
            pub(super) unsafe fn run($($arg: $ty),*) -> $ret {
                simd_dispatch!(@call $imp, true, ISA_AVX2, [$($flag)?], ($($arg),*))
            }
        }

        /// The AVX-512 build.
        #[cfg(target_arch = "x86_64")]
        mod $avx512 {
            #[allow(unused_imports)]
            use super::*;
            #[target_feature(enable = "avx512f,avx2,fma")]
            #[allow(clippy::too_many_arguments)]
            pub(super) unsafe fn run($($arg: $ty),*) -> $ret {
                simd_dispatch!(@call $imp, true, ISA_AVX512, [$($flag)?], ($($arg),*))
            }
        }

        /// Every build of the kernel this CPU runs, named: "portable" first, then "avx2" and
        /// "avx512" when the CPU has them (with FMA), for the tests that compare the builds.
        #[cfg(test)]
        #[allow(clippy::type_complexity)]
        pub(super) fn $builds() -> Vec<(&'static str, unsafe fn($($ty),*) -> $ret)> {
            let mut builds: Vec<(&'static str, unsafe fn($($ty),*) -> $ret)> =
                vec![("portable", $name::run)];
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("fma") {
                if std::is_x86_feature_detected!("avx2") {
                    builds.push(("avx2", $avx2::run));
                }
                if std::is_x86_feature_detected!("avx512f") {
                    builds.push(("avx512", $avx512::run));
                }
            }
            builds
        }
    };
    // The build's call: `imp::<FMA, ISA>`, or, with `const by flag`, `imp::<FMA, ISA, B>` with
    // B the runtime argument `flag` made a constant (a body compiled once per value). The flag
    // is `prefetch`, false in the web page (`prefetch_pays`): there one body, without the
    // hints, so that the engine optimises one copy of the loop, not two.
    (@call $imp:ident, $fma:expr, $isa:expr, [], ($($arg:ident),*)) => {
        $imp::<$fma, $isa>($($arg),*)
    };
    (@call $imp:ident, $fma:expr, $isa:expr, [$flag:ident], ($($arg:ident),*)) => {
        if $flag && !cfg!(target_arch = "wasm32") {
            $imp::<$fma, $isa, true>($($arg),*)
        } else {
            $imp::<$fma, $isa, false>($($arg),*)
        }
    };
}
pub(crate) use simd_dispatch;

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

/// [`super::add_line`] with one 512-bit vector: nodes 0–7 of the line get
/// (F + [0, f₁[0], …, f₁[6]]) + f₀ (f₁ moved up one lane by `valignq`), node 8 gets F + f₁[7].
///
/// # Safety
/// The CPU must have AVX-512F; `line` points to 9 numbers no other thread touches meanwhile.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
pub(crate) unsafe fn add_line_avx512(line: *mut f64, f0: &[f64; 8], f1: &[f64; 8]) {
    use std::arch::x86_64::*;
    let f1v = _mm512_castpd_si512(_mm512_loadu_pd(f1.as_ptr()));
    let up = _mm512_castsi512_pd(_mm512_alignr_epi64::<7>(f1v, _mm512_setzero_si512()));
    let x = _mm512_add_pd(_mm512_loadu_pd(line), up);
    _mm512_storeu_pd(line, _mm512_add_pd(x, _mm512_loadu_pd(f0.as_ptr())));
    *line.add(8) += f1[7];
}

/// [`add_line_avx512`] with two 256-bit vectors: f₁ moved up one lane across them by a
/// permute and a blend (low half) and a cross-half permute and a shuffle (high half).
///
/// # Safety
/// The CPU must have AVX2; `line` points to 9 numbers no other thread touches meanwhile.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn add_line_avx2(line: *mut f64, f0: &[f64; 8], f1: &[f64; 8]) {
    use std::arch::x86_64::*;
    let (lo, hi) = (
        _mm256_loadu_pd(f1.as_ptr()),
        _mm256_loadu_pd(f1.as_ptr().add(4)),
    );
    // [0, f₁0, f₁1, f₁2]: lanes (0 0 1 2), then lane 0 from zero.
    let up_lo = _mm256_blend_pd::<0b0001>(_mm256_permute4x64_pd::<0x90>(lo), _mm256_setzero_pd());
    // [f₁3, f₁4, f₁5, f₁6]: (f₁2 f₁3 f₁4 f₁5) from the two halves, then lanes 1, 0, 3, 2 of
    // it and of `hi` alternately.
    let up_hi = _mm256_shuffle_pd::<0b0101>(_mm256_permute2f128_pd::<0x21>(lo, hi), hi);
    let x_lo = _mm256_add_pd(_mm256_loadu_pd(line), up_lo);
    let x_hi = _mm256_add_pd(_mm256_loadu_pd(line.add(4)), up_hi);
    _mm256_storeu_pd(line, _mm256_add_pd(x_lo, _mm256_loadu_pd(f0.as_ptr())));
    _mm256_storeu_pd(
        line.add(4),
        _mm256_add_pd(x_hi, _mm256_loadu_pd(f0.as_ptr().add(4))),
    );
    *line.add(8) += f1[7];
}
