//! Selective mass scaling (model §6.8): the density of each element class whose stable step is
//! below the target h_t is multiplied by (h_t/h_e)², h_e = 2/√(a₀ g_e + g_hg,e) the element
//! bound of model §6.4 at rest (a₀ = max(3λ + 2μ, 2μ), the largest eigenvalue of the
//! small-strain elasticity tensor as a form on displacement gradients). Since g_e ∝ 1/ρ, the
//! scaled element's bound is exactly h_t, and Irons' bound then keeps ω_max² of the bulk below
//! (2/h_t)²: h_crit of the bulk is at least h_t. The glue's springs W g_N/m are softened by the
//! added mass but not scaled for: a target they still hold below is refused at set-up.
//! A tetrahedron is scaled the same way, element by element, with its own bound
//! h_e = 2/√(a₀ g_e), g_e = (4/ρ₀) λ_max(Σₐ ∇ₓNₐ ⊗ ∇ₓNₐ) (model §1.13, §6.8).

use super::bound::{class_bounds, tet_g};
use super::Simulation;
use crate::mesh::ElementClasses;
use crate::model::Model;
use serde::Serialize;

/// What mass scaling did (`check`, the summary, the recording).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct MassScalingReport {
    /// The target stable step h_t [s].
    pub target_step: f64,
    /// The smallest element stable step before scaling (element bound at rest) [s].
    pub smallest_element_step: f64,
    /// Elements whose density was raised, and of how many.
    pub scaled_elements: usize,
    pub elements: usize,
    /// The largest density factor (h_t/h_e)² [-].
    pub largest_factor: f64,
    /// The body's mass before scaling and the mass added [kg].
    pub mass: f64,
    pub added_mass: f64,
    /// The added mass's largest kinetic energy over the run, ½ Σ Δmₐ|Vₐ|² [J], and the largest
    /// elastic energy stored (bulk, hourglass and glue) it is compared with [J].
    pub added_kinetic_peak: f64,
    pub stored_peak: f64,
}

impl MassScalingReport {
    /// The added mass as a share of the body's mass [-].
    pub fn added_share(&self) -> f64 {
        self.added_mass / self.mass
    }

    /// The added mass's largest kinetic energy as a share of the largest elastic energy
    /// stored [-] (0 while nothing is stored).
    pub fn kinetic_share(&self) -> f64 {
        if self.stored_peak > 0.0 {
            self.added_kinetic_peak / self.stored_peak
        } else {
            0.0
        }
    }
}

/// The stable step of each element class at rest and at the unscaled density, its element
/// bound h_c = 2/√(a₀ g_c + g_hg,c) (model §6.4, [`class_bounds`]), a₀ = max(3λ + 2μ, 2μ).
fn class_steps(model: &Model, classes: &ElementClasses) -> Vec<f64> {
    let mat = &model.material;
    let full = model.scheme.integration.full_bound_at_rest();
    let kappa = model.scheme.hourglass_coefficient;
    let a0 = (3.0 * mat.lambda + 2.0 * mat.mu).max(2.0 * mat.mu);
    (class_bounds(mat, classes, full, kappa, &[]).iter())
        .map(|[g, g_hg]| 2.0 / (a0 * g + g_hg).sqrt())
        .collect()
}

/// The stable step of each tetrahedron at rest and at the unscaled density, its element bound
/// h_e = 2/√(a₀ g_e) with g_e = (4/ρ₀) λ_max(Σₐ ∇ₓNₐ ⊗ ∇ₓNₐ) ([`tet_g`], model §1.13, §6.8),
/// a₀ as for the hexahedra ([`class_steps`]). Empty without tetrahedra.
fn tet_steps(model: &Model, classes: &ElementClasses) -> Vec<f64> {
    let mat = &model.material;
    let a0 = (3.0 * mat.lambda + 2.0 * mat.mu).max(2.0 * mat.mu);
    (classes.tets.grad.iter())
        .map(|g| 2.0 / (a0 * tet_g(g, mat.density)).sqrt())
        .collect()
}

/// The length of each element class for bulk viscosity (model §4.12), L_c = c_d h_c with
/// c_d = √((λ + 2μ)/ρ₀) and h_c its stable step ([`class_steps`]): the element length of a bar,
/// and independent of the density, so of mass scaling.
pub(super) fn class_lengths(model: &Model, classes: &ElementClasses) -> Vec<f64> {
    let c = model.material.wave_speed();
    (class_steps(model, classes).iter())
        .map(|h| c * h)
        .collect()
}

/// The length of each tetrahedron for bulk viscosity (model §4.12), L_e = c_d h_e with h_e its
/// stable step at rest ([`tet_steps`]), as [`class_lengths`] for the hexahedra.
pub(super) fn tet_lengths(model: &Model, classes: &ElementClasses) -> Vec<f64> {
    let c = model.material.wave_speed();
    (tet_steps(model, classes).iter()).map(|h| c * h).collect()
}

/// The density factors of mass scaling, s_e = max(1, (h_t/h_e)²) with h_e the element bound at
/// rest: one per hexahedron class ([`class_steps`]) and one per tetrahedron ([`tet_steps`]).
pub(super) struct DensityFactors {
    pub class: Vec<f64>,
    pub tet: Vec<f64>,
}

/// The density factor of each element class and of each tetrahedron
/// ([`DensityFactors`]), and the report's set-up part (the masses are filled in by the
/// caller). `None` without mass scaling.
pub(super) fn class_factors(
    model: &Model,
    classes: &ElementClasses,
) -> Option<(DensityFactors, MassScalingReport)> {
    let ms = model.scheme.mass_scaling?;
    let factor = |&h: &f64| (ms.target_step / h).powi(2).max(1.0);
    let steps = class_steps(model, classes);
    let factors: Vec<f64> = steps.iter().map(factor).collect();
    let t_steps = tet_steps(model, classes);
    let tet: Vec<f64> = t_steps.iter().map(factor).collect();
    let scaled_elements = (classes.class_of.iter())
        .filter(|&&c| factors[c as usize] > 1.0)
        .count()
        + tet.iter().filter(|&&s| s > 1.0).count();
    let report = MassScalingReport {
        target_step: ms.target_step,
        smallest_element_step: (steps.iter().chain(&t_steps))
            .copied()
            .fold(f64::INFINITY, f64::min),
        scaled_elements,
        elements: classes.class_of.len() + tet.len(),
        largest_factor: (factors.iter().chain(&tet)).copied().fold(1.0, f64::max),
        ..Default::default()
    };
    Some((
        DensityFactors {
            class: factors,
            tet,
        },
        report,
    ))
}

impl Simulation {
    /// At stage 9 with mass scaling: the added mass's kinetic energy ½ Σ Δmₐ|Vₐ|² at the latest
    /// half step into the ledger, and the peaks the end-of-run check compares.
    pub(super) fn added_mass_energy(&mut self) {
        let Some(report) = self.setup.mass_scaling.as_mut() else {
            return;
        };
        let v = self.state.v.planes();
        let kinetic: f64 = (self.setup.added_mass.iter())
            .map(|&(i, dm)| {
                let i = i as usize;
                0.5 * dm * (v[0][i] * v[0][i] + v[1][i] * v[1][i] + v[2][i] * v[2][i])
            })
            .sum();
        let l = &mut self.state.ledger;
        l.added_mass_kinetic = kinetic;
        report.added_kinetic_peak = report.added_kinetic_peak.max(kinetic);
        let stored = l.strain + l.hourglass + l.interface_stored;
        report.stored_peak = report.stored_peak.max(stored);
    }

    /// The target step against the glue at t₀: refused when the glue's springs alone, a glued
    /// node's W g_N(0)/m with the scaled masses, allow a stable step more than 1 % below it
    /// (mass scaling adds mass to elements, not to the glue; the element bound then cannot
    /// reach the target).
    pub(super) fn check_mass_scaling_target(&self) -> Result<(), super::SolverError> {
        let Some(r) = self.setup.mass_scaling else {
            return Ok(());
        };
        let h_glue = 2.0 / self.glue_spring_omega_sq().sqrt();
        if h_glue >= 0.99 * r.target_step {
            return Ok(());
        }
        Err(super::SolverError::Setup(format!(
            "mass_scaling.target_step = {:e} s is above what the glue allows: a glued node's spring W g_N(0) against its scaled mass m has ω² = W g_N(0)/m, a stable step of {:.4e} s, and mass scaling adds mass to elements only. Admissible: a target ≤ {:.4e} s, or a softer glue",
            r.target_step, h_glue, h_glue
        )))
    }

    /// The warning when h_crit of the scaled model at t₀ is more than 1 % below the target: the
    /// glue's springs add to the elements' stiffness at the glued nodes (model §6.8).
    pub(super) fn mass_scaling_shortfall(&self) -> Option<String> {
        let r = self.setup.mass_scaling?;
        let h0 = self.stats.h_crit_initial;
        (h0 < 0.99 * r.target_step).then(|| {
            format!(
                "mass scaling: h_crit = {h0:.4e} s at t₀ is {:.1} % below mass_scaling.target_step = {:e} s: every element's own bound reaches the target, but the glue's springs add their stiffness at the glued nodes (model §6.8). A larger target, or a softer glue, moves h_crit further.",
                100.0 * (1.0 - h0 / r.target_step),
                r.target_step
            )
        })
    }
}
