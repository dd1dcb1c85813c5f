//! The energy ledger of model §5 with its exact discrete definitions.
//!
//! Every force k works by the trapezoid rule on integer-time displacements; in impulse form
//! (Pᵏₙ = h̄ₙ Fᵏₙ, the velocity jump M(V_{n+½} − V_{n−½}) = Σₖ Pᵏₙ) the work over [tₙ₋₁, tₙ] is
//! ½ V_{n−½}·(Pᵏₙ₋₁ + Pᵏₙ), which sums exactly to Kₙ − Kₙ₋₁ with Kₙ = ½ V_{n−½}ᵀ M V_{n+½}.
//! At step n the impulse Pₙ contributes a "backward half" bₙ = ½V_{n−½}·Pₙ to the interval that
//! ends at tₙ and a "forward half" aₙ = ½V_{n+½}·Pₙ to the next one: [`Work`] keeps the two.

use serde::Serialize;

/// Cumulative trapezoid work of one force, from its per-step half contributions.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct Work {
    /// Work up to the current integer time tₙ [J].
    pub value: f64,
    /// value + aₙ: the part of the next interval's work already known.
    settled: f64,
}

impl Work {
    /// Adds the step-n halves: value ← settled + bₙ (work up to tₙ), then settled += bₙ + aₙ.
    #[inline]
    pub fn push(&mut self, b: f64, a: f64) {
        self.value = self.settled + b;
        self.settled += b + a;
    }
    /// The work up to tₙ plus the forward half aₙ = ½V_{n+½}·Pₙ: what the force has put in by
    /// the time V_{n+½} is known (it pairs with ½V_{n+½}ᵀMV_{n+½}, not with Kₙ).
    #[inline]
    pub fn settled(&self) -> f64 {
        self.settled
    }
    /// The first step (n = 0): no work before t₀, only the forward half a₀ is kept.
    #[inline]
    pub fn start(&mut self, a: f64) {
        self.value = 0.0;
        self.settled = a;
    }
}

/// The ledger at the current integer time (all in joules). "Dissipated" quantities and works are
/// cumulative since t₀; stored energies are current values.
#[derive(Debug, Clone, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct Ledger {
    /// Kₙ = ½ V_{n−½}ᵀ M V_{n+½} (the leapfrog invariant's kinetic part).
    pub kinetic: f64,
    /// Bulk strain energy Ψₙ = Σ_e Σ_q w det J₀ ψ(Eₙ).
    pub strain: f64,
    /// Hourglass energy Ψ_hg,ₙ = Σ_e ½ k Σᵅ |qᵅ|² of one-point integration (0 with full
    /// integration): stored, like the strain energy.
    pub hourglass: f64,
    pub initial_hourglass: f64,
    /// Interface stored energy Σ W ½ g_N(αₙ)|[u]ₙ|².
    pub interface_stored: f64,
    /// Σ ΔDₙ, ΔDₙ = Σ W ½ (g_N(αₙ₋₁) − g_N(αₙ)) [u]ₙ₋₁·[u]ₙ ≥ 0.
    pub damage_dissipated: f64,
    /// Minus the trapezoid work of normal contact impulses on the relative displacement.
    pub contact_normal_dissipated: f64,
    /// Minus the trapezoid work of tangential contact impulses on the relative displacement.
    pub friction_dissipated: f64,
    /// Work of gravity.
    pub gravity_work: Work,
    /// Work of surface tractions.
    pub traction_work: Work,
    /// Work of the reactions of prescribed displacements.
    pub reaction_work: Work,
    /// Work of moving rigid planes (through contact and through the glue, with the glue's
    /// torque work on turning moulds, model §5.5).
    pub plane_work: Work,
    /// Trapezoid work of the internal forces (diagnostic: −Wint − ΔΨ is the O(h²) bulk term).
    pub internal_work: Work,
    /// Step-change work W_Δh: what a change of the time step feeds into the kinetic energy
    /// through the conservative forces (internal, cohesive), the difference between their
    /// impulse-form and plain trapezoid works (0 at a constant step; model §5.8,
    /// `solver/ledger.rs`). A source in the balance.
    pub step_change_work: Work,
    /// Trapezoid work of the bulk viscosity's impulses (model §5.11), ≤ 0.
    pub bulk_viscous_work: Work,
    /// Minus that work: the energy bulk viscosity dissipated (0 without it).
    pub bulk_viscous_dissipated: f64,
    /// Contact work on relative displacement, normal and tangential (negated into dissipations).
    pub contact_normal_work: Work,
    pub contact_tangential_work: Work,
    /// Values at t₀, subtracted in the balance.
    pub initial_kinetic: f64,
    pub initial_strain: f64,
    pub initial_interface_stored: f64,
    /// ½ Σ Δmₐ |Vₐ|² at the latest half step: the kinetic energy of the mass that mass
    /// scaling added (model §6.8), a part of `kinetic`, not a term of the balance; 0 without.
    pub added_mass_kinetic: f64,
    /// Largest magnitude of any ledger term seen so far (the residual's scale).
    pub max_energy_seen: f64,
    /// Largest |relative residual| seen so far.
    pub max_relative_residual: f64,
}

/// A plain copy of the ledger's values, for summaries and plots.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct EnergySnapshot {
    pub kinetic: f64,
    pub strain: f64,
    /// Hourglass energy (one-point integration; 0 with full integration).
    pub hourglass: f64,
    pub interface_stored: f64,
    pub damage_dissipated: f64,
    pub contact_normal_dissipated: f64,
    pub friction_dissipated: f64,
    pub external_work: f64,
    pub gravity_work: f64,
    pub traction_work: f64,
    pub reaction_work: f64,
    pub plane_work: f64,
    pub internal_work: f64,
    /// Step-change work W_Δh (0 at a constant step), a source in the balance.
    pub step_change_work: f64,
    /// external work + step-change work − (ΔK + ΔΨ + ΔΨ_d + D_damage + D_contact + D_friction
    /// + D_bulk viscosity).
    pub residual: f64,
    /// residual / largest energy seen.
    pub relative_residual: f64,
    /// The added mass's kinetic energy (mass scaling, model §6.8), a part of `kinetic`; absent
    /// without mass scaling.
    #[serde(skip_serializing_if = "is_zero")]
    pub added_mass_kinetic: f64,
    /// The energy bulk viscosity dissipated (model §5.11), a term of the balance; absent
    /// without bulk viscosity.
    #[serde(skip_serializing_if = "is_zero")]
    pub bulk_viscous_dissipated: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl EnergySnapshot {
    /// The names of the ledger's terms [J] (the fields of this struct, as the summary's
    /// `energies` keys), in the order of [`EnergySnapshot::terms`]; `relative_residual` [-] is
    /// not among them.
    pub const TERMS: [&'static str; 15] = [
        "kinetic",
        "strain",
        "hourglass",
        "interface_stored",
        "damage_dissipated",
        "contact_normal_dissipated",
        "friction_dissipated",
        "external_work",
        "gravity_work",
        "traction_work",
        "reaction_work",
        "plane_work",
        "internal_work",
        "step_change_work",
        "residual",
    ];

    /// The ledger's terms [J] in the order of [`EnergySnapshot::TERMS`].
    pub fn terms(&self) -> [f64; 15] {
        [
            self.kinetic,
            self.strain,
            self.hourglass,
            self.interface_stored,
            self.damage_dissipated,
            self.contact_normal_dissipated,
            self.friction_dissipated,
            self.external_work,
            self.gravity_work,
            self.traction_work,
            self.reaction_work,
            self.plane_work,
            self.internal_work,
            self.step_change_work,
            self.residual,
        ]
    }
}

impl Ledger {
    /// Total external work: gravity, tractions, reactions of prescribed displacements, moving planes.
    pub fn external_work(&self) -> f64 {
        self.gravity_work.value
            + self.traction_work.value
            + self.reaction_work.value
            + self.plane_work.value
    }

    /// External work including the forward halves of the last impulses ([`Work::settled`]):
    /// the energy that may be in the half-step kinetic energy ½V_{n+½}ᵀMV_{n+½}.
    pub fn external_work_settled(&self) -> f64 {
        self.gravity_work.settled()
            + self.traction_work.settled()
            + self.reaction_work.settled()
            + self.plane_work.settled()
    }

    /// Balance residual = W_ext + W_Δh − (ΔK + ΔΨ + ΔΨ_hg + ΔΨ_d + D_damage + D_normal + D_friction
    /// + D_bv) (model §5.1, §5.11).
    pub fn residual(&self) -> f64 {
        self.external_work() + self.step_change_work.value
            - ((self.kinetic - self.initial_kinetic)
                + (self.strain - self.initial_strain)
                + (self.hourglass - self.initial_hourglass)
                + (self.interface_stored - self.initial_interface_stored)
                + self.damage_dissipated
                + self.contact_normal_dissipated
                + self.friction_dissipated
                + self.bulk_viscous_dissipated)
    }

    /// Updates the dissipations from the contact works, the scale and the max relative residual;
    /// called once per step after every term is in.
    pub fn close_step(&mut self) {
        self.contact_normal_dissipated = 0.0 - self.contact_normal_work.value;
        self.friction_dissipated = 0.0 - self.contact_tangential_work.value;
        self.bulk_viscous_dissipated = 0.0 - self.bulk_viscous_work.value;
        let terms = [
            self.kinetic,
            self.strain,
            self.hourglass,
            self.interface_stored,
            self.damage_dissipated,
            self.contact_normal_dissipated,
            self.friction_dissipated,
            self.bulk_viscous_dissipated,
            self.gravity_work.value,
            self.traction_work.value,
            self.reaction_work.value,
            self.plane_work.value,
        ];
        for t in terms {
            self.max_energy_seen = self.max_energy_seen.max(t.abs());
        }
        let rel = self.relative_residual();
        if rel.abs() > self.max_relative_residual.abs() || rel.is_nan() {
            self.max_relative_residual = rel.abs();
        }
    }

    /// Residual divided by the largest energy seen (0 while nothing has happened).
    pub fn relative_residual(&self) -> f64 {
        if self.max_energy_seen > 0.0 {
            self.residual() / self.max_energy_seen
        } else {
            0.0
        }
    }

    pub fn snapshot(&self) -> EnergySnapshot {
        EnergySnapshot {
            kinetic: self.kinetic,
            strain: self.strain,
            hourglass: self.hourglass,
            interface_stored: self.interface_stored,
            damage_dissipated: self.damage_dissipated,
            contact_normal_dissipated: self.contact_normal_dissipated,
            friction_dissipated: self.friction_dissipated,
            external_work: self.external_work(),
            gravity_work: self.gravity_work.value,
            traction_work: self.traction_work.value,
            reaction_work: self.reaction_work.value,
            plane_work: self.plane_work.value,
            internal_work: self.internal_work.value,
            step_change_work: self.step_change_work.value,
            residual: self.residual(),
            relative_residual: self.relative_residual(),
            added_mass_kinetic: self.added_mass_kinetic,
            bulk_viscous_dissipated: self.bulk_viscous_dissipated,
        }
    }
}
