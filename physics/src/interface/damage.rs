//! The cohesive part of the interface at one node (model §2.2–§2.4, §4.5, §4.8, §5.5):
//! traction R_d = g_N(α)[u], stored energy Ψ_d = ½ W g_N(α)|[u]|², the damage update of eq. 12
//! and its dissipation increment.
//!
//! Generalised (model §2.2, §2.3): a law may load the tangential jump with
//! g_T = r g_N (r = r_T of the g_N(α) families, C_T/C_N of `rccm`) and the normal jump on opening
//! only (`rccm`: R_N = C_N β²⟨[u]_N⟩₊). With [u]_N = [u]·n, [u]_T = [u] − [u]_N n and ũ_N the
//! normal jump the law loads ([u]_N, or ⟨[u]_N⟩₊ on opening only):
//! R_d = g_N(α)(ũ_N n + r [u]_T), Ψ_d = ½ W g_N(α)(ũ_N² + r|[u]_T|²), and the damage is driven by
//! f = (⟨[u]_N⟩₊² + r|[u]_T|²)^½, so that Ψ_d = ½ W g_N(α) f² on opening and the Clausius–Duhem
//! dissipation −∂Ψ_d/∂α α̇ = −½ W g_N′(α) f² α̇ is ≥ 0 for every r > 0. With r = 1 and both
//! signs of the normal jump loaded (every g_N(α) family by default) these are the formulas of
//! paper eqs. 15–16, evaluated by the same operations.

use crate::vec3::dot;

/// Damage driving measure f = |[u]| with only the positive part of the normal jump counted:
/// a negative normal jump can only come from the velocity-level contact's position drift
/// (model §2.3, §3.8), and must not damage the glue.
#[inline]
pub fn damage_measure(jump: [f64; 3], n: [f64; 3]) -> f64 {
    weighted_damage_measure(jump, n, 1.0)
}

/// The damage measure of a law with tangential ratio r: f = (⟨[u]_N⟩₊² + r|[u]_T|²)^½ (module
/// doc). With r = 1 it is [`damage_measure`] bit for bit (1·x = x).
#[inline]
pub fn weighted_damage_measure(jump: [f64; 3], n: [f64; 3], r: f64) -> f64 {
    weighted_damage_split(jump, n, r).0
}

/// (f, r|[u]_T|²): the damage measure of [`weighted_damage_measure`], by the same operations,
/// and its shear part, so that B = r|[u]_T|²/f² is the shear share of the stored energy on
/// opening (the mode mixity of the `bk` law, model §2.11).
#[inline]
pub fn weighted_damage_split(jump: [f64; 3], n: [f64; 3], r: f64) -> (f64, f64) {
    let un = dot(jump, n);
    let t2 = dot(jump, jump) - un * un;
    let shear = r * t2.max(0.0);
    ((un.max(0.0).powi(2) + shear).sqrt(), shear)
}

/// Eq. 12 evaluated on a configuration: α' = min(u_r, max(α, f)), the largest jump ever
/// reached, capped at u_r (model §2.4, §4.8). α never decreases.
#[inline]
pub fn damage_update(alpha: f64, f: f64, u_r: f64) -> f64 {
    u_r.min(alpha.max(f))
}

/// Cohesive traction R_d = g_N(α)[u] [Pa] (model §2.2, paper eq. 16: one stiffness for
/// the normal and tangential jumps); it acts on the solid as −W R_d.
#[inline]
pub fn cohesive_traction(stiffness: f64, jump: [f64; 3]) -> [f64; 3] {
    jump.map(|c| stiffness * c)
}

/// Interface stored energy of one node, Ψ_d = ½ W g_N(α)|[u]|² [J] (model §5.5).
#[inline]
pub fn stored_energy(area: f64, stiffness: f64, jump: [f64; 3]) -> f64 {
    0.5 * area * stiffness * dot(jump, jump)
}

/// Damage dissipation of one node over a step, ΔDₙ = W ½ (g_N(αₙ₋₁) − g_N(αₙ)) [u]ₙ₋₁·[u]ₙ
/// [J] (model §5.5): with it the trapezoid work of the cohesive force is ΔΨ_d + ΔD exactly,
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

/// How a law loads the jump: the tangential ratio r = g_T/g_N and whether the normal jump is
/// loaded on opening only (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loading {
    pub ratio: f64,
    pub opening_only: bool,
    /// ΔD taken as ≥ 0 (a delayed law, see [`Loading::dissipation_increment`]).
    pub nonnegative_dissipation: bool,
}

impl Loading {
    /// One stiffness for every component, both signs of the normal jump: paper eqs. 15–16
    /// (model §2.2).
    #[inline]
    pub fn isotropic(&self) -> bool {
        self.ratio == 1.0 && !self.opening_only
    }

    /// (ũ_N, [u]_T): the normal jump the law loads and the tangential jump.
    #[inline]
    fn split(&self, jump: [f64; 3], n: [f64; 3]) -> (f64, [f64; 3]) {
        let un = dot(jump, n);
        let ut = std::array::from_fn(|c| jump[c] - un * n[c]);
        (if self.opening_only { un.max(0.0) } else { un }, ut)
    }

    /// R_d = g_N(α)(ũ_N n + r [u]_T) [Pa].
    #[inline]
    pub fn traction(&self, stiffness: f64, jump: [f64; 3], n: [f64; 3]) -> [f64; 3] {
        if self.isotropic() {
            return cohesive_traction(stiffness, jump);
        }
        let (un, ut) = self.split(jump, n);
        std::array::from_fn(|c| stiffness * (un * n[c] + self.ratio * ut[c]))
    }

    /// ũ_N ũ'_N + r [u]_T·[u]'_T: the product the energies are made of.
    #[inline]
    fn product(&self, a: [f64; 3], b: [f64; 3], n: [f64; 3]) -> f64 {
        let ((an, at), (bn, bt)) = (self.split(a, n), self.split(b, n));
        an * bn + self.ratio * dot(at, bt)
    }

    /// Ψ_d = ½ W g_N(α)(ũ_N² + r|[u]_T|²) [J].
    #[inline]
    pub fn stored_energy(&self, area: f64, stiffness: f64, jump: [f64; 3], n: [f64; 3]) -> f64 {
        if self.isotropic() {
            return stored_energy(area, stiffness, jump);
        }
        0.5 * area * stiffness * self.product(jump, jump, n)
    }

    /// ΔDₙ = W ½ (g_N(αₙ₋₁) − g_N(αₙ))(ũ_N,ₙ₋₁ ũ_N,ₙ + r [u]_T,ₙ₋₁·[u]_T,ₙ) [J]: the trapezoid
    /// work of the traction minus ΔΨ_d, exactly, on each component (for a normal jump loaded on
    /// opening only, up to the step where it changes sign); ≥ 0 while g_N does not increase and
    /// the loaded jump turns by less than 90° in a step (always, for the normal part on opening
    /// only).
    ///
    /// A delayed α still grows after the jump has turned back: at a step where the loaded jump
    /// reverses the form is < 0 by O(Δg_N |[u]||Δ[u]|), a first-order error of the time
    /// discretisation (the continuous −½ g_N′ f² α̇ is ≥ 0). With `nonnegative_dissipation` it is
    /// taken as 0 there, and the difference shows in the balance residual.
    #[inline]
    pub fn dissipation_increment(
        &self,
        area: f64,
        stiffness_before: f64,
        stiffness: f64,
        jump_before: [f64; 3],
        jump: [f64; 3],
        n: [f64; 3],
    ) -> f64 {
        self.booked_dissipation(area, stiffness_before, stiffness, jump_before, jump, n)
            .0
    }

    /// The glue's torque work over a step on a turning mould (model §5.5), the part of the
    /// trapezoid work of the traction that ΔΨ_d + ΔD leave out when the glue normal turns from
    /// nₙ₋₁ to nₙ:
    /// W_τ,ₙ = W ½ g_N(αₙ₋₁)(Pₙ(nₙ) − Pₙ(nₙ₋₁)), Pₙ(n) = ũ_N,ₙ₋₁ ũ_N,ₙ + r [u]_T,ₙ₋₁·[u]_T,ₙ
    /// with the jumps split on n [J]; the work the mould does on the glue through the couple
    /// W R_d × [u] of the glue's two forces. 0 for isotropic glue (Pₙ = [u]ₙ₋₁·[u]ₙ whatever
    /// n), which is not evaluated.
    #[inline]
    pub fn torque_work(
        &self,
        area: f64,
        stiffness_before: f64,
        jumps: [[f64; 3]; 2],
        normals: [[f64; 3]; 2],
    ) -> f64 {
        if self.isotropic() {
            return 0.0;
        }
        let [before, now] = jumps;
        let turned = self.product(before, now, normals[1]) - self.product(before, now, normals[0]);
        0.5 * area * stiffness_before * turned
    }

    /// [`Loading::dissipation_increment`] and what taking it as ≥ 0 added to the exact form:
    /// (ΔD booked, ΔD booked − ΔD exact), the second 0 but where a delayed law's ΔD < 0 was
    /// taken as 0 (what the ledger reports as clamped).
    #[inline]
    pub fn booked_dissipation(
        &self,
        area: f64,
        stiffness_before: f64,
        stiffness: f64,
        jump_before: [f64; 3],
        jump: [f64; 3],
        n: [f64; 3],
    ) -> (f64, f64) {
        let dd = if self.isotropic() {
            dissipation_increment(area, stiffness_before, stiffness, jump_before, jump)
        } else {
            0.5 * area * (stiffness_before - stiffness) * self.product(jump_before, jump, n)
        };
        if self.nonnegative_dissipation && dd < 0.0 {
            (0.0, -dd)
        } else {
            (dd, 0.0)
        }
    }
}
