//! `table` (model §2.6): a user table of (α, g_N) points, g_N linear between them. The first
//! point is at α = 0 (its g_N is g_N(0)), the last one at α = u_r with g_N = 0; α_e is the end of
//! the leading plateau.

use crate::interface::family::{Family, Knots, Param, ParamKind, ParamValues, R_T};
use crate::interface::law::{LawError, StiffnessLaw};

/// A piecewise-linear g_N through the user's points.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// (α [m], g_N [Pa/m]) pairs, α strictly increasing.
    pub points: Vec<[f64; 2]>,
}

/// The points; the editor starts from the paper's plateau–linear law.
const POINTS: Param = Param {
    key: "points",
    symbol: "(α, g_N)",
    unit: "m, Pa/m",
    meaning: "rows [α, g_N]: first α = 0, last g_N = 0 at α = u_r",
    note: "≥ 2 rows; first α = 0 with g_N > 0; α strictly increasing; g_N non-increasing; last g_N = 0 (its α is u_r)",
    optional: false,
    kind: ParamKind::Points {
        default: &[[0.0, 5e8], [2e-3, 5e8], [4e-3, 0.0]],
    },
};

impl Family for Table {
    const KEY: &'static str = "table";
    const LABEL: &'static str = "table of points";
    const DESCRIPTION: &'static str = "g_N linear between the user's points (α, g_N): the first at α = 0 (its g_N is g_N(0)), the last at α = u_r with g_N = 0; α_e is the end of the leading plateau.";
    const PARAMS: &'static [Param] = &[POINTS, R_T];

    /// Checks the table: ≥ 2 points, finite, first α = 0, g_N(0) > 0, α strictly increasing,
    /// g_N non-increasing (Clausius–Duhem, paper eqs. 13–16), last g_N = 0.
    fn build(values: &ParamValues) -> Result<(Self, Knots), LawError> {
        let points = values.points(POINTS.key)?.to_vec();
        let err = |value: String, reason: &str| Err(LawError::new(POINTS.key, value, reason));
        if points.len() < 2 {
            return err(
                points.len().to_string(),
                "a table law needs at least 2 points: (0, g_N(0)) and (u_r, 0)",
            );
        }
        if let Some((i, p)) =
            (points.iter().enumerate()).find(|(_, p)| !(p[0].is_finite() && p[1].is_finite()))
        {
            return err(format!("{p:?} (point {i})"), "values must be finite");
        }
        if points[0][0] != 0.0 {
            return err(points[0][0].to_string(), "the first point must be at α = 0");
        }
        let g_n0 = points[0][1];
        if g_n0 <= 0.0 {
            return err(
                g_n0.to_string(),
                "g_N(0) (second value of the first point) must be > 0",
            );
        }
        for i in 1..points.len() {
            let (a, b) = (points[i - 1], points[i]);
            if b[0] <= a[0] {
                return err(
                    format!("α = {} after α = {} (point {i})", b[0], a[0]),
                    "α must be strictly increasing",
                );
            }
            if b[1] > a[1] {
                return err(
                    format!("g_N = {} at α = {} after g_N = {} at α = {} (point {i})", b[1], b[0], a[1], a[0]),
                    "g_N must be non-increasing (a stiffness that grows with damage violates Clausius–Duhem)",
                );
            }
        }
        let last = points[points.len() - 1];
        if last[1] != 0.0 {
            return err(
                last[1].to_string(),
                &format!(
                    "the last point (α = u_r = {}) must have g_N = 0 (rupture)",
                    last[0]
                ),
            );
        }
        let u_r = last[0];
        let alpha_e = points
            .iter()
            .take_while(|p| p[1] == g_n0)
            .last()
            .map_or(0.0, |p| p[0]);
        if u_r <= alpha_e {
            return err(u_r.to_string(), "u_r must exceed α_e");
        }
        let knots = Knots { g_n0, alpha_e, u_r };
        Ok((Table { points }, knots))
    }

    fn values(&self, _law: &StiffnessLaw) -> ParamValues {
        ParamValues::default().with(POINTS.key, self.points.clone())
    }

    /// Linear between the two points around α.
    #[inline]
    fn softening(&self, _law: &StiffnessLaw, alpha: f64) -> f64 {
        let points = &self.points;
        let i = points.partition_point(|p| p[0] <= alpha).max(1);
        let (a, b) = (points[i - 1], points[i.min(points.len() - 1)]);
        if b[0] == a[0] {
            return b[1];
        }
        a[1] + (b[1] - a[1]) * (alpha - a[0]) / (b[0] - a[0])
    }

    /// G_c = Σ over the segments of ∫ (c₀ + c₁x) x dx, g linear on each.
    fn fracture_energy(&self, _law: &StiffnessLaw) -> f64 {
        self.points
            .windows(2)
            .map(|w| {
                let ([x0, g0], [x1, g1]) = (w[0], w[1]);
                let c1 = (g1 - g0) / (x1 - x0);
                let c0 = g0 - c1 * x0;
                let prim = |x: f64| c0 * x * x / 2.0 + c1 * x * x * x / 3.0;
                prim(x1) - prim(x0)
            })
            .sum()
    }

    /// T(δ) is piecewise quadratic with kinks at the points: each is a candidate (just below,
    /// on the branch that reaches it).
    fn peak_candidates(&self, _law: &StiffnessLaw, consider: &mut dyn FnMut(f64)) {
        for p in &self.points {
            consider(p[0] * (1.0 - 1e-15));
        }
    }
}
