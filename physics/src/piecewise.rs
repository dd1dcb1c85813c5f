//! Piecewise-linear functions of time: the histories of prescribed velocities, tractions and
//! mould motions.

use serde::Serialize;

/// A piecewise-linear function of time with N components, constant beyond its end points.
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseLinear<const N: usize> {
    /// (t [s], value) pairs with strictly increasing t.
    pub points: Vec<(f64, [f64; N])>,
}

/// Serialised as rows `[t, v_0, …, v_{N-1}]`, the form scene files use.
impl<const N: usize> Serialize for PiecewiseLinear<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let rows: Vec<Vec<f64>> = self
            .points
            .iter()
            .map(|(t, v)| std::iter::once(*t).chain(v.iter().copied()).collect())
            .collect();
        rows.serialize(s)
    }
}

impl<const N: usize> PiecewiseLinear<N> {
    /// Value at time t (linear interpolation, constant extrapolation).
    pub fn value(&self, t: f64) -> [f64; N] {
        let p = &self.points;
        if t <= p[0].0 {
            return p[0].1;
        }
        let last = p[p.len() - 1];
        if t >= last.0 {
            return last.1;
        }
        let i = p.partition_point(|q| q.0 <= t);
        let (a, b) = (p[i - 1], p[i]);
        let s = (t - a.0) / (b.0 - a.0);
        std::array::from_fn(|c| a.1[c] + s * (b.1[c] - a.1[c]))
    }

    /// Exact integral ∫₀ᵗ value dτ (trapezoid on each linear piece; the value before the first
    /// point is the first value). Used to turn a velocity history into a displacement.
    pub fn integral(&self, t: f64) -> [f64; N] {
        let p = &self.points;
        let mut acc = [0.0; N];
        let add = |t0: f64, t1: f64, acc: &mut [f64; N]| {
            if t1 > t0 {
                let (v0, v1) = (self.value(t0), self.value(t1));
                for c in 0..N {
                    acc[c] += 0.5 * (v0[c] + v1[c]) * (t1 - t0);
                }
            }
        };
        let mut prev = 0.0f64;
        for q in p.iter() {
            if q.0 >= t {
                break;
            }
            if q.0 > prev {
                add(prev, q.0, &mut acc);
                prev = q.0;
            }
        }
        add(prev, t, &mut acc);
        acc
    }

    /// A constant function.
    pub fn constant(v: [f64; N]) -> Self {
        PiecewiseLinear {
            points: vec![(0.0, v)],
        }
    }
}
