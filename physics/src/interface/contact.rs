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
/// Updates `v` in place and returns the impulse W R_c [N·s] and the status.
#[inline]
pub fn contact_impulse(
    v: &mut [f64; 3],
    gap: f64,
    n: [f64; 3],
    v_plane: [f64; 3],
    mu: f64,
    m: f64,
) -> ([f64; 3], ContactStatus) {
    if gap > 0.0 {
        return ([0.0; 3], ContactStatus::Open);
    }
    let rel = [v[0] - v_plane[0], v[1] - v_plane[1], v[2] - v_plane[2]];
    let vn = dot(rel, n);
    if vn >= 0.0 {
        return ([0.0; 3], ContactStatus::Open);
    }
    // Impulses (W R) rather than per-area values: W cancels (PHYSICS.md §4 step 7).
    let pn = -m * vn;
    let vt = [rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]];
    let vt_norm = norm(vt);
    let (pt, status) = if m * vt_norm <= mu * pn {
        (vt.map(|c| -m * c), ContactStatus::Stick)
    } else {
        let s = mu * pn / vt_norm;
        (vt.map(|c| -s * c), ContactStatus::Slip)
    };
    let p = [pn * n[0] + pt[0], pn * n[1] + pt[1], pn * n[2] + pt[2]];
    for c in 0..3 {
        v[c] += p[c] / m;
    }
    (p, status)
}
