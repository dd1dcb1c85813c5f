//! [`F64x2`]: two f64 lanes, the web page's vector (a WebAssembly `v128` as f64x2 when built for
//! wasm32 with simd128; elsewhere two `f64`s, so the tests run the page's kernels natively).
//! The page's full kernel runs a lane group of 8 elements as 4 pairs (`kernels::full_pairs`):
//! a pair is one register, where an [`F64x8`] is four, which the engine kept in memory around
//! nearly every operation. Each lane carries out the IEEE operations of the `f64` formulas in
//! the same order (no fused multiply–add in simd128), so the bits are those of the scalar
//! kernel.

use super::real::{F64x8, Real};
use std::ops::{Add, Div, Mul, Sub};

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
use core::arch::wasm32::{
    f64x2, f64x2_add, f64x2_div, f64x2_extract_lane, f64x2_lt, f64x2_mul, f64x2_ne, f64x2_splat,
    f64x2_sub, v128, v128_bitselect,
};

/// Two f64 lanes (lane 0, lane 1).
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
#[derive(Debug, Clone, Copy)]
pub struct F64x2(v128);

/// Two f64 lanes (lane 0, lane 1).
#[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
#[derive(Debug, Clone, Copy)]
pub struct F64x2([f64; 2]);

impl F64x2 {
    /// The lanes (a, b).
    #[inline(always)]
    pub fn new(a: f64, b: f64) -> F64x2 {
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        {
            F64x2(f64x2(a, b))
        }
        #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
        {
            F64x2([a, b])
        }
    }

    /// The two lanes as numbers.
    #[inline(always)]
    pub fn lanes(self) -> [f64; 2] {
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        {
            [
                f64x2_extract_lane::<0>(self.0),
                f64x2_extract_lane::<1>(self.0),
            ]
        }
        #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
        {
            self.0
        }
    }

    /// Lanes 2p and 2p + 1 of `x` (p < 4).
    #[inline(always)]
    pub fn pair_of(x: &F64x8, p: usize) -> F64x2 {
        F64x2::new(x.0[2 * p], x.0[2 * p + 1])
    }

    /// Writes the two lanes into lanes 2p and 2p + 1 of `x` (p < 4).
    #[inline(always)]
    pub fn put_into(self, x: &mut F64x8, p: usize) {
        let [a, b] = self.lanes();
        x.0[2 * p] = a;
        x.0[2 * p + 1] = b;
    }

    /// Lane-wise `f64::min`, as [`F64x8::lane_min`] (a NaN lane of one operand gives the
    /// other's; of two zeros, either: in the page `self`'s).
    #[inline(always)]
    pub fn lane_min(self, o: F64x2) -> F64x2 {
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        {
            // o < self ? o : self, then o where self is NaN.
            let r = v128_bitselect(o.0, self.0, f64x2_lt(o.0, self.0));
            F64x2(v128_bitselect(o.0, r, f64x2_ne(self.0, self.0)))
        }
        #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
        {
            F64x2([self.0[0].min(o.0[0]), self.0[1].min(o.0[1])])
        }
    }
}

/// `impl $op for F64x2`: the f64x2 operation in the page, lane by lane elsewhere.
macro_rules! pairwise {
    ($($trait:ident :: $method:ident / $wasm:ident),*) => {$(
        impl $trait for F64x2 {
            type Output = F64x2;
            #[inline(always)]
            fn $method(self, o: F64x2) -> F64x2 {
                #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                {
                    F64x2($wasm(self.0, o.0))
                }
                #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
                {
                    F64x2([
                        $trait::$method(self.0[0], o.0[0]),
                        $trait::$method(self.0[1], o.0[1]),
                    ])
                }
            }
        }
    )*};
}
pairwise!(
    Add::add / f64x2_add,
    Sub::sub / f64x2_sub,
    Mul::mul / f64x2_mul,
    Div::div / f64x2_div
);

impl Real for F64x2 {
    #[inline(always)]
    fn splat(v: f64) -> F64x2 {
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        {
            F64x2(f64x2_splat(v))
        }
        #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
        {
            F64x2([v; 2])
        }
    }
    #[inline(always)]
    fn ln(self) -> F64x2 {
        let [a, b] = self.lanes();
        F64x2::new(a.ln(), b.ln())
    }
    #[inline(always)]
    fn fmadd<const FMA: bool>(self, b: F64x2, c: F64x2) -> F64x2 {
        if FMA {
            let ([x0, x1], [b0, b1], [c0, c1]) = (self.lanes(), b.lanes(), c.lanes());
            F64x2::new(x0.mul_add(b0, c0), x1.mul_add(b1, c1))
        } else {
            self * b + c
        }
    }
    #[inline(always)]
    fn per_lane<const N: usize, const M: usize>(
        x: [F64x2; N],
        f: impl Fn([f64; N]) -> [f64; M],
    ) -> [F64x2; M] {
        let y0 = f(std::array::from_fn(|k| x[k].lanes()[0]));
        let y1 = f(std::array::from_fn(|k| x[k].lanes()[1]));
        std::array::from_fn(|m| F64x2::new(y0[m], y1[m]))
    }
}
