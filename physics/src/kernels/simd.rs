//! The per-ISA dispatch of the SIMD kernels: one macro that builds a kernel for AVX-512, for
//! AVX2 (both with fused multiply–adds) and portably, and picks one at run time; plus the
//! AVX-512 and AVX2 gathers of the one-point kernel (the per-ISA twins, kept apart here).

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
