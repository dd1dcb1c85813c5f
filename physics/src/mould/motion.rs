//! Prescribed rigid motion of a mould: a translation-velocity history v(t) and an
//! angular-velocity history ω(t) about a pivot c, both piecewise linear in t.
//!
//! A material point of the mould at X (its position at t = 0) is at
//!
//! x(t) = c(t) + R(t)(X − c₀),  c(t) = c₀ + ∫₀ᵗ v dτ,
//!
//! with c₀ the pivot at t = 0 (the pivot moves with the translation). The translation is the
//! exact integral of the piecewise-linear v. The rotation is integrated over the steps of the
//! run, exactly for an ω that is constant over each step: over [tₙ, tₙ₊₁] the step's ω is its
//! mean ω̄ = (Ω(tₙ₊₁) − Ω(tₙ))/h with Ω(t) = ∫₀ᵗ ω dτ (exact for the piecewise-linear table),
//! and
//!
//! R(tₙ₊₁) = exp([Ω(tₙ₊₁) − Ω(tₙ)]×) R(tₙ)
//!
//! with the exponential map of so(3) in Rodrigues' form, exp([φ]×) = I + (sin θ/θ)[φ]× +
//! ((1 − cos θ)/θ²)[φ]×², θ = |φ| — a rotation to round-off whatever the step, composed per
//! step (not an Euler sum R + hωR, which is no rotation). A fixed axis gives R(t) = exp([Ω(t)]×)
//! whatever the steps.

use crate::piecewise::PiecewiseLinear;

/// A 3×3 matrix, rows.
pub type Mat3 = [[f64; 3]; 3];

/// The identity.
pub const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// y = A x.
#[inline]
pub fn mat_vec(a: &Mat3, x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2])
}

/// y = Aᵀ x.
#[inline]
pub fn mat_t_vec(a: &Mat3, x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[0][i] * x[0] + a[1][i] * x[1] + a[2][i] * x[2])
}

/// A B.
pub fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
    })
}

/// A Bᵀ.
pub fn mat_mul_t(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[j][0] + a[i][1] * b[j][1] + a[i][2] * b[j][2])
    })
}

/// The rotation exp([φ]×) by the rotation vector φ (Rodrigues):
/// R = I + a[φ]× + b[φ]×², a = sin θ/θ, b = (1 − cos θ)/θ², θ = |φ|; for θ < 1e-4 the series
/// a = 1 − θ²/6 + θ⁴/120, b = ½ − θ²/24 + θ⁴/720 (their next terms are below 1e-24).
pub fn rodrigues(phi: [f64; 3]) -> Mat3 {
    let t2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2];
    let (a, b) = if t2 < 1e-8 {
        (
            1.0 - t2 / 6.0 + t2 * t2 / 120.0,
            0.5 - t2 / 24.0 + t2 * t2 / 720.0,
        )
    } else {
        let t = t2.sqrt();
        (t.sin() / t, (1.0 - t.cos()) / t2)
    };
    let [x, y, z] = phi;
    // [φ]× and [φ]×² = φφᵀ − θ² I.
    let k: Mat3 = [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]];
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let id = if i == j { 1.0 } else { 0.0 };
            id + a * k[i][j] + b * (phi[i] * phi[j] - id * t2)
        })
    })
}

/// The prescribed motion of a mould (see the module docs).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct RigidMotion {
    /// Translation velocity history v(t) [m/s] of the pivot; `None`: no translation.
    pub velocity: Option<PiecewiseLinear<3>>,
    /// Angular velocity history ω(t) [rad/s]; `None`: no rotation.
    pub angular_velocity: Option<PiecewiseLinear<3>>,
    /// The pivot c₀ at t = 0 [m].
    pub pivot: [f64; 3],
}

/// The pose of a mould at one time: x = centre + R (X − c₀).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pose {
    pub time: f64,
    pub rotation: Mat3,
    /// c(t) = c₀ + ∫v [m].
    pub centre: [f64; 3],
}

impl RigidMotion {
    /// c(t) − c₀ = ∫₀ᵗ v dτ (exact).
    pub fn translation(&self, t: f64) -> [f64; 3] {
        self.velocity.as_ref().map_or([0.0; 3], |v| v.integral(t))
    }

    /// The pose at t = 0 (R = I, centre c₀) — or at `t` for a mould that does not turn.
    pub fn start(&self, t: f64) -> Pose {
        let d = self.translation(t);
        Pose {
            time: t,
            rotation: IDENTITY,
            centre: std::array::from_fn(|c| self.pivot[c] + d[c]),
        }
    }

    /// The pose at `t` from the pose `from` at an earlier (or equal) time: the rotation of the
    /// step composed exactly, R(t) = exp([Ω(t) − Ω(t_from)]×) R(t_from) (module docs).
    pub fn advance(&self, from: &Pose, t: f64) -> Pose {
        let (v, w) = (self.velocity.as_ref(), self.angular_velocity.as_ref());
        RigidMotion::advance_histories(v, w, self.pivot, from, t)
    }

    /// [`RigidMotion::advance`] from the histories themselves (borrowed: the time step does
    /// not copy them).
    pub fn advance_histories(
        velocity: Option<&PiecewiseLinear<3>>,
        angular_velocity: Option<&PiecewiseLinear<3>>,
        pivot: [f64; 3],
        from: &Pose,
        t: f64,
    ) -> Pose {
        let rotation = match angular_velocity {
            None => IDENTITY,
            Some(w) => {
                let (a, b) = (w.integral(from.time), w.integral(t));
                let phi = std::array::from_fn(|c| b[c] - a[c]);
                mat_mul(&rodrigues(phi), &from.rotation)
            }
        };
        let d = velocity.map_or([0.0; 3], |v| v.integral(t));
        Pose {
            time: t,
            rotation,
            centre: std::array::from_fn(|c| pivot[c] + d[c]),
        }
    }
}

impl Pose {
    /// Where the material point X (position at t = 0) is: c + R(X − c₀).
    #[inline]
    pub fn place(&self, pivot: [f64; 3], x0: [f64; 3]) -> [f64; 3] {
        let r = mat_vec(&self.rotation, std::array::from_fn(|c| x0[c] - pivot[c]));
        std::array::from_fn(|c| self.centre[c] + r[c])
    }

    /// The reference position X of the point x: c₀ + Rᵀ(x − c).
    #[inline]
    pub fn unplace(&self, pivot: [f64; 3], x: [f64; 3]) -> [f64; 3] {
        let r = mat_t_vec(
            &self.rotation,
            std::array::from_fn(|c| x[c] - self.centre[c]),
        );
        std::array::from_fn(|c| pivot[c] + r[c])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn orthonormality_error(r: &Mat3) -> f64 {
        let p = mat_mul_t(r, r);
        (0..9).fold(0.0f64, |m, k| {
            let (i, j) = (k / 3, k % 3);
            m.max((p[i][j] - IDENTITY[i][j]).abs())
        })
    }

    /// Rodrigues against the closed form about z (cos, sin), and orthonormal to round-off for
    /// large and tiny angles (the series branch).
    #[test]
    fn rodrigues_is_a_rotation() {
        for theta in [1e-9, 1e-5, 0.3, 2.0, 3.1] {
            let r = rodrigues([0.0, 0.0, theta]);
            assert!((r[0][0] - theta.cos()).abs() < 1e-15);
            assert!((r[1][0] - theta.sin()).abs() < 1e-15);
            let q = rodrigues([theta * 0.6, -theta * 0.48, theta * 0.64]);
            // Each entry of R Rᵀ sums three products of entries ≤ 1, each a few ulps off: ~8ε.
            assert!(orthonormality_error(&q) < 8.0 * f64::EPSILON, "{theta}");
        }
    }

    /// A fixed axis: composing many steps equals the one rotation by the total angle (to
    /// round-off ~ steps × ε), whatever the (uneven) steps; a changing axis stays a rotation.
    #[test]
    fn per_step_composition_is_exact_about_a_fixed_axis() {
        let axis = [0.6, 0.0, 0.8];
        let w = PiecewiseLinear::<3> {
            points: vec![(0.0, [0.0; 3]), (1.0, axis.map(|c| 2.0 * c))],
        };
        let m = RigidMotion {
            velocity: None,
            angular_velocity: Some(w.clone()),
            pivot: [0.0; 3],
        };
        let mut pose = m.start(0.0);
        let mut t = 0.0;
        for k in 0..1000 {
            t += 1e-3 * (0.5 + (k % 3) as f64 * 0.5);
            pose = m.advance(&pose, t.min(1.5));
        }
        let exact = rodrigues(w.integral(t.min(1.5)));
        for i in 0..3 {
            for j in 0..3 {
                assert!((pose.rotation[i][j] - exact[i][j]).abs() < 1e-13);
            }
        }
        assert!(orthonormality_error(&pose.rotation) < 1e-13);
    }
}
