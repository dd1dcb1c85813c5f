//! The number type of the constitutive and kinematic formulas: [`Real`], implemented for `f64`
//! (one point) and for [`F64x8`] (8 SIMD lanes: the 8 Gauss points of an element, or 8
//! elements). A formula written once over `T: Real` is the same IEEE operations, in the same
//! order, on every lane; everything is `#[inline(always)]`, so the lane loops vectorise.

use std::ops::{Add, Div, Mul, Sub};

/// What the formulas need from a number: +, −, ×, ÷, ln, a constant, and a multiply–add that is
/// fused when `FMA` (one rounding; the choice is fixed per CPU, see `kernels::simd`).
pub trait Real:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// The constant `v` (on every lane).
    fn splat(v: f64) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// `self`·b + c, fused (one rounding) when `FMA`, else a product then a sum.
    fn fmadd<const FMA: bool>(self, b: Self, c: Self) -> Self;
    /// `f` applied to each lane: the N inputs of a lane in, its M outputs out. For what has no
    /// lane-wise form written here (cube roots, powers, eigenvalues: the rubber materials,
    /// `material::rubber`); on [`F64x8`] it is `f` lane after lane, so every lane has the bits
    /// of `f` on `f64`.
    fn per_lane<const N: usize, const M: usize>(
        x: [Self; N],
        f: impl Fn([f64; N]) -> [f64; M],
    ) -> [Self; M];
}

impl Real for f64 {
    #[inline(always)]
    fn splat(v: f64) -> f64 {
        v
    }
    #[inline(always)]
    fn ln(self) -> f64 {
        f64::ln(self)
    }
    #[inline(always)]
    fn fmadd<const FMA: bool>(self, b: f64, c: f64) -> f64 {
        if FMA {
            self.mul_add(b, c)
        } else {
            self * b + c
        }
    }
    #[inline(always)]
    fn per_lane<const N: usize, const M: usize>(
        x: [f64; N],
        f: impl Fn([f64; N]) -> [f64; M],
    ) -> [f64; M] {
        f(x)
    }
}

/// Eight f64 lanes, operated on lane by lane (`.0[l]` is lane l); aligned as one AVX-512
/// register.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct F64x8(pub [f64; 8]);

impl F64x8 {
    /// Lane-wise `f64::min`: the smaller of the two lanes, a NaN lane passed over for the
    /// other's (of two zeros, either; in the web page `self`'s). In the page (wasm32 with
    /// simd128) as f64x2 comparisons and selects: `f64::min` is a call to `fmin` there.
    #[inline(always)]
    pub fn lane_min(self, o: F64x8) -> F64x8 {
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        {
            use core::arch::wasm32::{f64x2_lt, f64x2_ne, v128_bitselect};
            wasm_pairs(self, o, |x, y| {
                // y < x ? y : x, then y where x is NaN.
                let r = v128_bitselect(y, x, f64x2_lt(y, x));
                v128_bitselect(y, r, f64x2_ne(x, x))
            })
        }
        #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
        {
            let mut r = self.0;
            for l in 0..8 {
                r[l] = r[l].min(o.0[l]);
            }
            F64x8(r)
        }
    }

    /// The smallest lane, by `f64::min` (a NaN lane is passed over unless all are NaN; the
    /// result does not depend on the order), taken pairwise so that it vectorises.
    #[inline(always)]
    pub fn min_lane(self) -> f64 {
        let d = self.0;
        (d[0].min(d[1]).min(d[2].min(d[3]))).min(d[4].min(d[5]).min(d[6].min(d[7])))
    }
}

/// W f64 lanes without [`F64x8`]'s alignment: a slice of an [`F64x8`]'s lanes (the one-point
/// box kernel runs 4 at a time on AVX2, whose 16 registers hold 4 × 8 modal amplitudes of 4
/// lanes but not of 8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lanes<const W: usize>(pub [f64; W]);

/// `impl $op for F64x8` and for [`Lanes`], lane by lane; on F64x8 in the web page (wasm32 with
/// simd128) as four f64x2 operations (`$wasm`, [`wasm_pairs`]).
macro_rules! lanewise {
    ($($trait:ident :: $method:ident / $wasm:ident),*) => {$(
        impl $trait for F64x8 {
            type Output = F64x8;
            #[inline(always)]
            fn $method(self, o: F64x8) -> F64x8 {
                #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
                {
                    wasm_pairs(self, o, |x, y| core::arch::wasm32::$wasm(x, y))
                }
                #[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
                {
                    let mut r = self.0;
                    for l in 0..8 {
                        r[l] = $trait::$method(r[l], o.0[l]);
                    }
                    F64x8(r)
                }
            }
        }
        impl<const W: usize> $trait for Lanes<W> {
            type Output = Lanes<W>;
            #[inline(always)]
            fn $method(self, o: Lanes<W>) -> Lanes<W> {
                let mut r = self.0;
                for l in 0..W {
                    r[l] = $trait::$method(r[l], o.0[l]);
                }
                Lanes(r)
            }
        }
    )*};
}
lanewise!(
    Add::add / f64x2_add,
    Sub::sub / f64x2_sub,
    Mul::mul / f64x2_mul,
    Div::div / f64x2_div
);

/// `op` on the lane pairs (0, 1), (2, 3), (4, 5), (6, 7) of `a` and `b` as WebAssembly f64x2
/// vectors. The f64x2 sum, difference, product and quotient are the IEEE operations of each
/// lane, rounded as the scalar ones (no fused multiply–add in simd128), so the bits are those
/// of the lane loop; written with the intrinsics because LLVM's cost model for wasm32 left a
/// good part of the lane loops scalar.
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
#[inline(always)]
fn wasm_pairs(
    a: F64x8,
    b: F64x8,
    op: impl Fn(core::arch::wasm32::v128, core::arch::wasm32::v128) -> core::arch::wasm32::v128,
) -> F64x8 {
    use core::arch::wasm32::v128;
    // SAFETY: [f64; 8] and [v128; 4] are both 64 bytes of plain data, every bit pattern
    // valid for each.
    let (x, y) = unsafe {
        (
            core::mem::transmute::<[f64; 8], [v128; 4]>(a.0),
            core::mem::transmute::<[f64; 8], [v128; 4]>(b.0),
        )
    };
    let r = [
        op(x[0], y[0]),
        op(x[1], y[1]),
        op(x[2], y[2]),
        op(x[3], y[3]),
    ];
    // SAFETY: as above.
    F64x8(unsafe { core::mem::transmute::<[v128; 4], [f64; 8]>(r) })
}

impl Real for F64x8 {
    #[inline(always)]
    fn splat(v: f64) -> F64x8 {
        F64x8([v; 8])
    }
    #[inline(always)]
    fn ln(self) -> F64x8 {
        let mut r = self.0;
        for l in 0..8 {
            r[l] = r[l].ln();
        }
        F64x8(r)
    }
    #[inline(always)]
    fn fmadd<const FMA: bool>(self, b: F64x8, c: F64x8) -> F64x8 {
        #[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
        if !FMA {
            return self * b + c;
        }
        let mut r = c.0;
        for l in 0..8 {
            r[l] = self.0[l].fmadd::<FMA>(b.0[l], r[l]);
        }
        F64x8(r)
    }
    #[inline(always)]
    fn per_lane<const N: usize, const M: usize>(
        x: [F64x8; N],
        f: impl Fn([f64; N]) -> [f64; M],
    ) -> [F64x8; M] {
        let mut out = [F64x8([0.0; 8]); M];
        for l in 0..8 {
            let y = f(std::array::from_fn(|k| x[k].0[l]));
            for (o, y) in out.iter_mut().zip(y) {
                o.0[l] = y;
            }
        }
        out
    }
}

/// A 3×3 tensor, `t[i][j]` its component (i, j).
pub type Mat3<T> = [[T; 3]; 3];
