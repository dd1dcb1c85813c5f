//! Delayed damage (model §2.9): the Allix–Ladevèze delay-effect form
//! written for α in metres. The damage no longer jumps to its rate-independent value
//! α_s = min(u_r, max over the history of f) (eq. 12) but follows it at a bounded rate,
//!
//! α̇ = (u_r/τ_c) (1 − exp(−a ⟨α_s − α⟩₊ / u_r)),   0 ≤ α̇ ≤ u_r/τ_c,
//!
//! with τ_c [s] the characteristic time and a [–] the sharpness. α̇ ≥ 0 and g_N non-increasing
//! keep the Clausius–Duhem inequality (−½ g_N′(α) f² α̇ ≥ 0); as τ_c → 0, α → α_s.

use super::law::LawError;
use serde::Serialize;

/// The parameters of `[interface.delay]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Delay {
    /// Characteristic time τ_c [s] (> 0): the damage rate never exceeds u_r/τ_c.
    pub tau_c: f64,
    /// Sharpness a [–] (> 0): the rate is (u_r/τ_c)(1 − e^{−a x/u_r}) at a lag x = α_s − α.
    pub a: f64,
}

impl Delay {
    /// Checks τ_c > 0 and a > 0 (finite); the error names the key, the value and the range.
    pub fn new(tau_c: f64, a: f64) -> Result<Self, LawError> {
        if !(tau_c.is_finite() && tau_c > 0.0) {
            return Err(LawError::new(
                "tau_c",
                tau_c,
                "τ_c must be finite and > 0 (s); leave `[interface.delay]` out for the rate-independent law",
            ));
        }
        if !(a.is_finite() && a > 0.0) {
            return Err(LawError::new("a", a, "a must be finite and > 0 (–)"));
        }
        Ok(Delay { tau_c, a })
    }

    /// α̇ = (u_r/τ_c)(1 − exp(−a⟨α_s − α⟩₊/u_r)) [m/s].
    pub fn rate(&self, alpha: f64, alpha_s: f64, u_r: f64) -> f64 {
        let x = (alpha_s - alpha).max(0.0);
        -(u_r / self.tau_c) * (-self.a * x / u_r).exp_m1()
    }

    /// α after an interval h with α_s frozen at its end value: the exact solution of the ODE.
    /// With x = α_s − α and y = a x/u_r, ẏ = −(a/τ_c)(1 − e^{−y}), i.e.
    /// d/dt ln(e^y − 1) = −a/τ_c, so
    ///
    /// y(h) = ln(1 + (e^{y₀} − 1) E) = y₀ + ln(E + (1 − E) e^{−y₀}),   E = e^{−a h/τ_c},
    ///
    /// evaluated in log space (no overflow for any a, h/τ_c). 0 ≤ y(h) ≤ y₀: α never passes α_s
    /// and never decreases, whatever h/τ_c; E → 0 (τ_c → 0) gives y = 0, α = α_s exactly.
    ///
    /// The last approach is geometric (x → E x per step): once (1 − E) x is below half an ulp of
    /// α the computed α would stall short of α_s for ever (a node at α_s = u_r would never count
    /// as ruptured). A step that makes no representable progress therefore ends at α_s: a jump
    /// of x < ulp(α)/(2(1 − E)), the size of the round-off the 1/(1 − E) steps of the exact
    /// approach would commit.
    pub fn advance(&self, alpha: f64, alpha_s: f64, u_r: f64, h: f64) -> f64 {
        let x = alpha_s - alpha;
        if x <= 0.0 {
            return alpha;
        }
        let y0 = self.a * x / u_r;
        // ln E and ln((1 − E) e^{−y₀}), then y = y₀ + logaddexp of the two.
        let p = -self.a * h / self.tau_c;
        let q = (-p.exp_m1()).ln() - y0;
        let y = y0 + p.max(q) + (-(p - q).abs()).exp().ln_1p();
        let y = y.clamp(0.0, y0);
        if y == 0.0 {
            return alpha_s;
        }
        let next = (alpha_s - u_r * y / self.a).max(alpha);
        if next == alpha {
            alpha_s
        } else {
            next
        }
    }
}
