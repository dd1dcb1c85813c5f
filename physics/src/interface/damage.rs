//! The cohesive part of the interface at one node (PHYSICS.md §3, §4 stages 4 and 8, §5):
//! traction R_d = g_N(α)[u], stored energy Ψ_d = ½ W g_N(α)|[u]|², the damage update of eq. 12
//! and its dissipation increment.

use crate::mesh::dot;

/// Damage driving measure f = |[u]| with only the positive part of the normal jump counted:
/// a negative normal jump can only come from the velocity-level contact's position drift
/// (PHYSICS.md §3), and must not damage the glue.
#[inline]
pub fn damage_measure(jump: [f64; 3], n: [f64; 3]) -> f64 {
    let un = dot(jump, n);
    let t2 = dot(jump, jump) - un * un;
    (un.max(0.0).powi(2) + t2.max(0.0)).sqrt()
}

/// Eq. 12 evaluated on a configuration: α' = min(u_r, max(α, f)), the largest jump ever
/// reached, capped at u_r (PHYSICS.md §4 stage 8). α never decreases.
#[inline]
pub fn damage_update(alpha: f64, f: f64, u_r: f64) -> f64 {
    u_r.min(alpha.max(f))
}

/// Cohesive traction R_d = g_N(α)[u] [Pa] (PHYSICS.md §3, paper eq. 16: one stiffness for
/// the normal and tangential jumps); it acts on the solid as −W R_d.
#[inline]
pub fn cohesive_traction(stiffness: f64, jump: [f64; 3]) -> [f64; 3] {
    jump.map(|c| stiffness * c)
}

/// Interface stored energy of one node, Ψ_d = ½ W g_N(α)|[u]|² [J] (PHYSICS.md §5).
#[inline]
pub fn stored_energy(area: f64, stiffness: f64, jump: [f64; 3]) -> f64 {
    0.5 * area * stiffness * dot(jump, jump)
}

/// Damage dissipation of one node over a step, ΔDₙ = W ½ (g_N(αₙ₋₁) − g_N(αₙ)) [u]ₙ₋₁·[u]ₙ
/// [J] (PHYSICS.md §5): with it the trapezoid work of the cohesive force is ΔΨ_d + ΔD exactly,
/// and ΔD ≥ 0 while g_N is non-increasing and the jump turns by less than 90° in a step.
#[inline]
pub fn dissipation_increment(
    area: f64,
    stiffness_before: f64,
    stiffness: f64,
    jump_before: [f64; 3],
    jump: [f64; 3],
) -> f64 {
    0.5 * area * (stiffness_before - stiffness) * dot(jump_before, jump)
}
