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

/// `impl $op for F64x8` and for [`Lanes`], lane by lane.
macro_rules! lanewise {
    ($($trait:ident :: $method:ident),*) => {$(
        impl $trait for F64x8 {
            type Output = F64x8;
            #[inline(always)]
            fn $method(self, o: F64x8) -> F64x8 {
                let mut r = self.0;
                for l in 0..8 {
                    r[l] = $trait::$method(r[l], o.0[l]);
                }
                F64x8(r)
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
lanewise!(Add::add, Sub::sub, Mul::mul, Div::div);

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
