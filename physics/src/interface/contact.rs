//! Stage 7 of PHYSICS.md §4: unilateral contact with Coulomb friction at one node, in closed
//! form (the mass is lumped and the integration nodal, so each node's problem is local).
//!
//! Conventions: n is the surface's unit normal pointing into the solid, a gap g > 0 is open,
//! velocities are relative to the surface's material point, impulses are W R (N·s).

use crate::mesh::{dot, norm};
use crate::solver::ContactStatus;

/// Stage 7 for one node against one surface (PHYSICS.md §4, paper eqs. 19–20, 22): if gₙ₊₁ ≤ 0
/// and the relative free velocity approaches (v_N < 0), r_N = −m v_N/W brings v_N to 0; the
/// trial tangential impulse −m v_T/W sticks if |r_T| ≤ μ r_N, else r_T = −μ r_N v_T/|v_T|.
///
/// A node whose velocity components are partly prescribed (`free[c]` false: a symmetry edge, a
/// clamped edge) gets contact and friction on its free components only.
///
/// Let F be the span of the free axes (`free[c]`), P_F its projector, V* the velocity after
/// stage 6 (prescribed components already set), v* = V* − v_plane. The mould pushes with
/// λn + r_T (r_T ⊥ n); the Dirichlet support takes the share on the prescribed components,
/// so what moves the node is the projection on F, p = P_F(λn + r_T), with V = V* + p/m. The
/// friction is taken in F as well, r_T ∈ T_F = F ∩ n^⊥. For u ∈ F, u·n = u·n_F with
/// n_F = P_F n, so T_F = F ∩ n_F^⊥: the normal part λn_F and the tangential part r_T of p are
/// orthogonal and the problem splits as in the free case. With v_N = n·(V − v_plane):
///
/// - normal: v_N = v*_N + λ|n_F|²/m, and 0 ≤ v_N ⊥ λ ≥ 0 (eq. 19 in F) gives
///   λ = max(0, −m v*_N/|n_F|²): the free components bring the approach velocity to 0;
/// - tangential: w = the component of v* in T_F, trial r_T = −m w; it sticks if
///   |r_T| ≤ μλ (λ is the mould's normal reaction, of which the node feels λn_F), else
///   r_T = −μλ w/|w| (eq. 20 in T_F);
/// - |n_F|² ≤ 1e-12 (the normal along prescribed axes only): the free components cannot change
///   the gap, the prescribed motion alone sets it; no impulse.
///
/// With no axis prescribed (F = ℝ³, n_F = n) this is the law above (and the same operations). It is exact Coulomb
/// when the prescribed components do not slide along the mould (a symmetry plane; a clamped
/// edge moved along the normal, e.g. the peel's lifted end); when they do (a node dragged
/// along the mould by its prescribed motion), the friction of that sliding goes to the
/// support's reaction and the free components obey Coulomb on their own instead of sharing
/// one cone with it. The prescribed share of λn + r_T is not added to the reported reaction
/// (only their sum is determined on those components).
///
/// Updates `v` in place (free components only) and returns the impulse W R_c [N·s] and the
/// status.
#[inline]
pub fn contact_impulse(
    v: &mut [f64; 3],
    gap: f64,
    n: [f64; 3],
    v_plane: [f64; 3],
    mu: f64,
    m: f64,
    free: [bool; 3],
) -> ([f64; 3], ContactStatus) {
    let all_free = free == [true; 3];
    let on_f = |x: [f64; 3]| std::array::from_fn::<f64, 3, _>(|c| if free[c] { x[c] } else { 0.0 });
    let n_f = if all_free { n } else { on_f(n) };
    let nf2 = if all_free { 1.0 } else { dot(n_f, n_f) };
    if gap > 0.0 || nf2 <= 1e-12 {
        return ([0.0; 3], ContactStatus::Open);
    }
    let rel = [v[0] - v_plane[0], v[1] - v_plane[1], v[2] - v_plane[2]];
    let vn = dot(rel, n);
    if vn >= 0.0 {
        return ([0.0; 3], ContactStatus::Open);
    }
    // Impulses (W R) rather than per-area values: W cancels (PHYSICS.md §4 step 7).
    // λ: the normal reaction; w: the relative velocity in the tangent space (T_F).
    let (lambda, w) = if all_free {
        let vt = [rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]];
        (-m * vn, vt)
    } else {
        let rf = on_f(rel);
        let s = dot(rf, n_f) / nf2;
        let w = [rf[0] - s * n_f[0], rf[1] - s * n_f[1], rf[2] - s * n_f[2]];
        (-m * vn / nf2, w)
    };
    let w_norm = norm(w);
    let (pt, status) = if m * w_norm <= mu * lambda {
        (w.map(|c| -m * c), ContactStatus::Stick)
    } else {
        let k = mu * lambda / w_norm;
        (w.map(|c| -k * c), ContactStatus::Slip)
    };
    let p = [
        lambda * n_f[0] + pt[0],
        lambda * n_f[1] + pt[1],
        lambda * n_f[2] + pt[2],
    ];
    for c in 0..3 {
        v[c] += p[c] / m;
    }
    (p, status)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random number in [−1, 1).
    fn rnd(k: &mut u64) -> f64 {
        *k = k
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*k >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn unit(x: [f64; 3]) -> [f64; 3] {
        let l = norm(x);
        x.map(|c| c / l)
    }

    /// With every component free, the law of PHYSICS.md §4 step 7 written out by hand.
    #[test]
    fn all_free_is_the_free_law() {
        let mut k = 7;
        for _ in 0..200 {
            let n = unit([rnd(&mut k), rnd(&mut k), rnd(&mut k)]);
            let v0 = [rnd(&mut k), rnd(&mut k), rnd(&mut k)];
            let vp = [0.1 * rnd(&mut k), 0.0, 0.2];
            let mu = 0.5 * (1.0 + rnd(&mut k));
            let (mut a, mut b) = (v0, v0);
            // PHYSICS.md §4 step 7: r_N = −m v_N, trial −m v_T, Coulomb.
            let rel = [a[0] - vp[0], a[1] - vp[1], a[2] - vp[2]];
            let vn = dot(rel, n);
            let vt = [rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]];
            let pn = (-2.0 * vn).max(0.0);
            let scale = if 2.0 * norm(vt) <= mu * pn {
                2.0
            } else {
                mu * pn / norm(vt)
            };
            let pa: [f64; 3] = std::array::from_fn(|c| pn * n[c] - scale * vt[c]);
            let (pb, _) = contact_impulse(&mut b, 0.0, n, vp, mu, 2.0, [true; 3]);
            for c in 0..3 {
                assert!(
                    (pa[c] - pb[c]).abs() <= 1e-14 * (1.0 + norm(pa)),
                    "{pa:?} {pb:?}"
                );
                a[c] += pa[c] / 2.0;
                assert!((a[c] - b[c]).abs() <= 1e-14 * (1.0 + norm(a)));
            }
        }
    }

    /// Frictionless, one or two components prescribed, a tilted normal: the velocity after the
    /// impulse is Moreau's, the point of {V ∈ V* + F : n·(V − v_plane) ≥ 0} nearest to V*
    /// (Gauss's least constraint with a lumped mass). Checked against 2000 random feasible
    /// points of that set, none nearer; and the prescribed components are untouched.
    #[test]
    fn frictionless_is_the_least_constraint_velocity_on_the_free_components() {
        let mut k = 11;
        for free in [
            [true, true, false],
            [false, true, true],
            [true, false, false],
        ] {
            for _ in 0..50 {
                let n = unit([rnd(&mut k), rnd(&mut k), 1.0 + rnd(&mut k).abs()]);
                let v0 = [rnd(&mut k), rnd(&mut k), -1.0 + 0.5 * rnd(&mut k)];
                let vp = [0.0, 0.1, 0.0];
                let mut v = v0;
                let (p, _) = contact_impulse(&mut v, -1e-9, n, vp, 0.0, 3.0, free);
                let rel = |x: [f64; 3]| dot([x[0] - vp[0], x[1] - vp[1], x[2] - vp[2]], n);
                for c in 0..3 {
                    if !free[c] {
                        assert_eq!((v[c], p[c]), (v0[c], 0.0));
                    }
                }
                let dist = |x: [f64; 3]| norm([x[0] - v0[0], x[1] - v0[1], x[2] - v0[2]]);
                if rel(v0) >= 0.0 {
                    assert_eq!(v, v0);
                    continue;
                }
                assert!(rel(v).abs() <= 1e-12, "approach velocity left: {}", rel(v));
                for _ in 0..2000 {
                    let d: [f64; 3] =
                        std::array::from_fn(|c| if free[c] { 3.0 * rnd(&mut k) } else { 0.0 });
                    let x = [v0[0] + d[0], v0[1] + d[1], v0[2] + d[2]];
                    if rel(x) >= 0.0 {
                        assert!(dist(x) >= dist(v) - 1e-12);
                    }
                }
            }
        }
    }

    /// A symmetry edge (x prescribed) on a plane z = 0 sliding along y with x held: stick when
    /// μ allows it (no free relative velocity left), else slip on the cone |r_T| = μλ against
    /// the free sliding velocity; the normal along a prescribed axis gives no impulse.
    #[test]
    fn friction_in_the_free_tangent_plane() {
        let n = [0.0, 0.0, 1.0];
        let free = [false, true, true];
        let mut v = [0.3, 0.2, -1.0];
        let (p, s) = contact_impulse(&mut v, 0.0, n, [0.0; 3], 0.5, 1.0, free);
        assert_eq!((s, v), (ContactStatus::Stick, [0.3, 0.0, 0.0]));
        assert_eq!(p, [0.0, -0.2, 1.0]);
        let mut v = [0.3, 0.8, -1.0];
        let (p, s) = contact_impulse(&mut v, 0.0, n, [0.0; 3], 0.5, 1.0, free);
        assert_eq!(s, ContactStatus::Slip);
        assert_eq!(p, [0.0, -0.5, 1.0]);
        assert!((v[1] - 0.3).abs() < 1e-15 && v[2] == 0.0);
        let mut v = [0.3, 0.8, -1.0];
        let (p, s) = contact_impulse(&mut v, 0.0, n, [0.0; 3], 0.5, 1.0, [true, true, false]);
        assert_eq!((p, s, v), ([0.0; 3], ContactStatus::Open, [0.3, 0.8, -1.0]));
    }
}
