//! The RCCM interface stiffness law g_N(α) and everything derived from it (PHYSICS.md §3).
//!
//! Conventions: α is the damage variable in metres (the largest jump norm ever reached, capped
//! at u_r), g_N is a stiffness per unit area in Pa/m, tractions are in Pa, energies per unit area
//! in J/m². The undamaged stiffness is always written `g_n0` = g_N(0).

use serde::{Deserialize, Serialize};

/// Which family of stiffness law (PHYSICS.md §3, "Stiffness laws a user expects").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "snake_case", deny_unknown_fields)]
pub enum LawFamily {
    /// Paper fig. 5: g_N = g_N(0) on [0, α_e], then linear decrease to 0 at u_r:
    /// g_N(α) = g_N(0) (u_r − α)/(u_r − α_e).
    PlateauLinear,
    /// Linear-softening traction: g_N(α) = g_N(0) α_e (u_r − α) / (α (u_r − α_e)) past α_e,
    /// so T(δ) = g_N(δ)δ falls linearly from g_N(0)α_e to 0; G_c = ½ g_N(0) α_e u_r.
    Bilinear,
    /// Exponential decrease past α_e, cut to 0 at u_r:
    /// g_N(α) = g_N(0) exp(−k (α − α_e)/(u_r − α_e)), k = `decay` (dimensionless).
    Exponential {
        /// Decay exponent k over the softening range (dimensionless, > 0).
        decay: f64,
    },
    /// User table of (α, g_N) points, linear between points. The first point must be at α = 0,
    /// the last one at α = u_r with g_N = 0; α_e is the end of the leading plateau.
    Table {
        /// (α [m], g_N [Pa/m]) pairs.
        points: Vec<[f64; 2]>,
    },
}

/// A validated stiffness law: a non-increasing g_N on [0, u_r] with g_N(α ≥ u_r) = 0.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StiffnessLaw {
    pub family: LawFamily,
    /// Undamaged stiffness g_N(0) [Pa/m].
    pub g_n0: f64,
    /// End of the elastic range α_e [m].
    pub alpha_e: f64,
    /// Rupture opening u_r [m].
    pub u_r: f64,
}

/// Why a law is not admissible (PHYSICS.md §3, last paragraph). `key` names the offending
/// parameter so the scene loader can point at it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {reason}")]
pub struct LawError {
    pub key: &'static str,
    pub value: String,
    pub reason: String,
}

fn law_err(key: &'static str, value: impl ToString, reason: impl Into<String>) -> LawError {
    LawError {
        key,
        value: value.to_string(),
        reason: reason.into(),
    }
}

impl StiffnessLaw {
    /// Builds and checks a parametric law (plateau_linear, bilinear, exponential).
    /// For `Table`, g_n0, α_e and u_r are derived from the points and the arguments are ignored.
    pub fn new(family: LawFamily, g_n0: f64, alpha_e: f64, u_r: f64) -> Result<Self, LawError> {
        if let LawFamily::Table { points } = &family {
            return Self::from_table(points.clone());
        }
        if !(g_n0.is_finite() && g_n0 > 0.0) {
            return Err(law_err(
                "g_n0",
                g_n0,
                "g_N(0) must be finite and > 0 (Pa/m)",
            ));
        }
        if !(alpha_e.is_finite() && alpha_e >= 0.0) {
            return Err(law_err(
                "alpha_e",
                alpha_e,
                "α_e must be finite and ≥ 0 (m)",
            ));
        }
        if !(u_r.is_finite() && u_r > alpha_e) {
            return Err(law_err(
                "u_r",
                u_r,
                format!(
                    "u_r must be finite and > α_e = {alpha_e} m (rupture after the elastic range)"
                ),
            ));
        }
        match &family {
            LawFamily::Bilinear if alpha_e <= 0.0 => {
                return Err(law_err(
                    "alpha_e",
                    alpha_e,
                    "the bilinear law needs α_e > 0 (its peak traction is g_N(0)·α_e)",
                ))
            }
            LawFamily::Exponential { decay } if !(decay.is_finite() && *decay > 0.0) => {
                return Err(law_err(
                    "decay",
                    decay,
                    "the exponential decay k must be finite and > 0",
                ))
            }
            _ => {}
        }
        Ok(Self {
            family,
            g_n0,
            alpha_e,
            u_r,
        })
    }

    /// Builds a `table` law and checks it: first α = 0, α strictly increasing, g_N finite,
    /// g_N(0) > 0, g_N non-increasing (Clausius–Duhem, paper eqs. 13–16), last g_N = 0.
    pub fn from_table(points: Vec<[f64; 2]>) -> Result<Self, LawError> {
        if points.len() < 2 {
            return Err(law_err(
                "points",
                points.len(),
                "a table law needs at least 2 points: (0, g_N(0)) and (u_r, 0)",
            ));
        }
        for (i, p) in points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(law_err(
                    "points",
                    format!("{p:?} (point {i})"),
                    "values must be finite",
                ));
            }
        }
        if points[0][0] != 0.0 {
            return Err(law_err(
                "points",
                points[0][0],
                "the first point must be at α = 0",
            ));
        }
        let g_n0 = points[0][1];
        if g_n0 <= 0.0 {
            return Err(law_err(
                "points",
                g_n0,
                "g_N(0) (second value of the first point) must be > 0",
            ));
        }
        for i in 1..points.len() {
            let (a, b) = (points[i - 1], points[i]);
            if b[0] <= a[0] {
                return Err(law_err(
                    "points",
                    format!("α = {} after α = {} (point {i})", b[0], a[0]),
                    "α must be strictly increasing",
                ));
            }
            if b[1] > a[1] {
                return Err(law_err(
                    "points",
                    format!("g_N = {} at α = {} after g_N = {} at α = {} (point {i})", b[1], b[0], a[1], a[0]),
                    "g_N must be non-increasing (a stiffness that grows with damage violates Clausius–Duhem)",
                ));
            }
        }
        let last = points[points.len() - 1];
        if last[1] != 0.0 {
            return Err(law_err(
                "points",
                last[1],
                format!(
                    "the last point (α = u_r = {}) must have g_N = 0 (rupture)",
                    last[0]
                ),
            ));
        }
        let u_r = last[0];
        let alpha_e = points
            .iter()
            .take_while(|p| p[1] == g_n0)
            .last()
            .map(|p| p[0])
            .unwrap_or(0.0);
        if u_r <= alpha_e {
            return Err(law_err("points", u_r, "u_r must exceed α_e"));
        }
        Ok(Self {
            family: LawFamily::Table { points },
            g_n0,
            alpha_e,
            u_r,
        })
    }

    /// Interface stiffness g_N(α) [Pa/m] (PHYSICS.md §3): g_N(0) on [0, α_e], 0 for α ≥ u_r,
    /// non-increasing in between according to the family.
    #[inline]
    pub fn g_n(&self, alpha: f64) -> f64 {
        if alpha <= self.alpha_e {
            return self.g_n0;
        }
        if alpha >= self.u_r {
            return 0.0;
        }
        let span = self.u_r - self.alpha_e;
        match &self.family {
            LawFamily::PlateauLinear => self.g_n0 * (self.u_r - alpha) / span,
            LawFamily::Bilinear => self.g_n0 * self.alpha_e * (self.u_r - alpha) / (alpha * span),
            LawFamily::Exponential { decay } => {
                self.g_n0 * (-decay * (alpha - self.alpha_e) / span).exp()
            }
            LawFamily::Table { points } => {
                let i = points.partition_point(|p| p[0] <= alpha).max(1);
                let (a, b) = (points[i - 1], points[i.min(points.len() - 1)]);
                if b[0] == a[0] {
                    return b[1];
                }
                a[1] + (b[1] - a[1]) * (alpha - a[0]) / (b[0] - a[0])
            }
        }
    }

    /// Friction coefficient grown by damage, paper eq. 21: μ(α) = μ_inf (1 − g_N(α)/g_N(0)).
    #[inline]
    pub fn mu(&self, alpha: f64, mu_inf: f64) -> f64 {
        mu_inf * (1.0 - self.g_n(alpha) / self.g_n0)
    }

    /// Traction under monotonic opening, T(δ) = g_N(δ) δ [Pa] (PHYSICS.md §3).
    #[inline]
    pub fn traction(&self, delta: f64) -> f64 {
        self.g_n(delta) * delta
    }

    /// Fracture energy G_c = ∫₀^{u_r} g_N(δ) δ dδ [J/m²], in closed form for each family
    /// (PHYSICS.md §3; the bilinear value is ½ g_N(0) α_e u_r).
    pub fn fracture_energy(&self) -> f64 {
        let (g0, ae, ur) = (self.g_n0, self.alpha_e, self.u_r);
        let plateau = 0.5 * g0 * ae * ae;
        match &self.family {
            LawFamily::PlateauLinear => {
                plateau
                    + g0 / (ur - ae)
                        * (ur * (ur * ur - ae * ae) / 2.0 - (ur * ur * ur - ae * ae * ae) / 3.0)
            }
            LawFamily::Bilinear => 0.5 * g0 * ae * ur,
            LawFamily::Exponential { decay } => {
                let (k, l) = (*decay, ur - ae);
                let e = (-k).exp();
                plateau + g0 * (ae * l * (1.0 - e) / k + l * l * (1.0 - e * (1.0 + k)) / (k * k))
            }
            LawFamily::Table { points } => points
                .windows(2)
                .map(|w| {
                    // g linear on [x0, x1]: g = c0 + c1 x, ∫ (c0 + c1 x) x dx.
                    let ([x0, g0], [x1, g1]) = (w[0], w[1]);
                    let c1 = (g1 - g0) / (x1 - x0);
                    let c0 = g0 - c1 * x0;
                    let prim = |x: f64| c0 * x * x / 2.0 + c1 * x * x * x / 3.0;
                    prim(x1) - prim(x0)
                })
                .sum(),
        }
    }

    /// Peak of T(δ) over [0, u_r] and where it is reached: (T_max [Pa], δ [m]). Evaluated on the
    /// breakpoints and a fine sampling (relative accuracy ~1e-8 for the smooth families).
    pub fn peak_traction(&self) -> (f64, f64) {
        let mut best = (self.traction(self.alpha_e), self.alpha_e);
        let mut consider = |d: f64| {
            let t = self.traction(d);
            if t > best.0 {
                best = (t, d);
            }
        };
        let n = 20_000;
        for i in 0..=n {
            consider(self.u_r * i as f64 / n as f64 * (1.0 - 1e-15));
        }
        if let LawFamily::Table { points } = &self.family {
            for p in points {
                consider(p[0] * (1.0 - 1e-15));
            }
        }
        // Plateau–linear: interior maximum at δ = u_r/2 when u_r > 2 α_e.
        if matches!(self.family, LawFamily::PlateauLinear) && self.u_r > 2.0 * self.alpha_e {
            consider(self.u_r / 2.0);
        }
        best
    }

    /// Elastic / transition / ruptured classification of a node, paper fig. 6 (PHYSICS.md §3).
    #[inline]
    pub fn state(&self, alpha: f64) -> InterfaceState {
        if alpha <= self.alpha_e {
            InterfaceState::Elastic
        } else if alpha < self.u_r {
            InterfaceState::Transition
        } else {
            InterfaceState::Ruptured
        }
    }
}

/// State of an interface node as the paper's figure 6 plots it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InterfaceState {
    /// α ≤ α_e: undamaged stiffness.
    Elastic,
    /// α_e < α < u_r: softening.
    Transition,
    /// α ≥ u_r: no cohesion left, unilateral contact with friction μ_inf.
    Ruptured,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut s = f(a) + f(b);
        for i in 1..n {
            s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    #[test]
    fn closed_form_fracture_energy_matches_quadrature() {
        let laws = [
            StiffnessLaw::new(LawFamily::PlateauLinear, 2e9, 5e-4, 1e-3).unwrap(),
            StiffnessLaw::new(LawFamily::Bilinear, 2e9, 5e-4, 3e-3).unwrap(),
            StiffnessLaw::new(LawFamily::Exponential { decay: 4.0 }, 2e9, 5e-4, 3e-3).unwrap(),
            StiffnessLaw::from_table(vec![[0.0, 1e9], [1e-4, 1e9], [5e-4, 4e8], [2e-3, 0.0]])
                .unwrap(),
        ];
        for law in &laws {
            // Integrate piecewise so the kink at α_e (and table points) falls on a node.
            let mut cuts = vec![0.0, law.alpha_e, law.u_r];
            if let LawFamily::Table { points } = &law.family {
                cuts.extend(points.iter().map(|p| p[0]));
            }
            cuts.sort_by(f64::total_cmp);
            cuts.dedup();
            let num: f64 = cuts
                .windows(2)
                .map(|w| {
                    simpson(
                        |d| law.traction(d.min(w[1] * (1.0 - 1e-14))),
                        w[0],
                        w[1],
                        2000,
                    )
                })
                .sum();
            let exact = law.fracture_energy();
            // Simpson on smooth pieces with 2000 panels: error ≪ 1e-9 relative.
            assert!(
                (num - exact).abs() <= 1e-8 * exact,
                "{law:?}: {num} vs {exact}"
            );
        }
    }

    #[test]
    fn inadmissible_laws_are_refused_with_the_reason() {
        let e = StiffnessLaw::new(LawFamily::PlateauLinear, 1e9, 1e-3, 1e-3).unwrap_err();
        assert_eq!(e.key, "u_r");
        let e = StiffnessLaw::new(LawFamily::PlateauLinear, -1.0, 1e-4, 1e-3).unwrap_err();
        assert_eq!(e.key, "g_n0");
        let e = StiffnessLaw::from_table(vec![[0.0, 1.0], [1.0, 2.0], [2.0, 0.0]]).unwrap_err();
        assert!(e.reason.contains("non-increasing"), "{e}");
        let e = StiffnessLaw::from_table(vec![[0.0, 1.0], [1.0, 0.5]]).unwrap_err();
        assert!(e.reason.contains("g_N = 0"), "{e}");
    }

    #[test]
    fn bilinear_traction_is_linear_softening() {
        let law = StiffnessLaw::new(LawFamily::Bilinear, 2e9, 5e-4, 3e-3).unwrap();
        // T(δ) falls linearly from g0 α_e at α_e to 0 at u_r.
        let t = |d: f64| law.traction(d);
        let mid = 0.5 * (5e-4 + 3e-3);
        assert!((t(mid) - 0.5 * 2e9 * 5e-4).abs() < 1e-6 * 1e6);
        assert_eq!(law.peak_traction().0, 2e9 * 5e-4);
    }
}
