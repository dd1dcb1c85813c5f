//! What the user is told: the blow-up diagnostic (where, with which h and h_crit, what to
//! change; model §6.7) and the regime warnings printed before a run.

use super::state::SolverError;
use super::Simulation;
use crate::kernels::corners::element_corner_jacobians;
use crate::model::Integration;
use crate::model::StartOffset;

/// What the near-incompressibility warnings say of the F-bar hexahedron (model §1.11).
const FBAR_DOES_NOT_LOCK: &str =
    "the F-bar hexahedron does not lock volumetrically (one volume ratio per element, model §1.11)";

/// What the near-incompressibility warnings say of a rubber on tetrahedra only.
const TETS_DO_NOT_LOCK: &str = "its 4-node tetrahedra take the average nodal pressure and a nodal share of the isochoric energy (model §1.13, §1.14), and do not lock volumetrically";

/// What the near-incompressibility warnings say of the physically stabilised one point.
const PHYSICAL_DOES_NOT_LOCK: &str =
    "one-point integration does not lock volumetrically, and the physical hourglass stiffness follows E and μ, not K (model §1.12)";

impl Simulation {
    /// The blow-up diagnostic: where, with which h and h_crit, and what to change.
    pub(super) fn unstable(&self, reason: String) -> SolverError {
        let factor = self.state.h / self.state.h_crit;
        let configured = self.model.scheme.time_step_factor;
        let advice = if configured >= 1.0 {
            format!("scheme.time_step_factor = {configured} is at or above the stability limit 1 (h is capped at h_crit, the limit itself, with no margin for the estimate or for stiffening between estimates): set it ≤ 0.9 (default 0.5).")
        } else if factor > 0.95 {
            format!("The time step factor {factor:.3} is at or above the stability limit 1: set scheme.time_step_factor ≤ 0.9 (default 0.5).")
        } else {
            "The step is below the estimated limit: stiffening under large strain may have lowered h_crit (lower scheme.h_crit_update_interval or scheme.time_step_factor), or the loading is too violent for the mesh (refine it or slow the load).".to_string()
        };
        SolverError::Unstable {
            step: self.state.step_count,
            time: self.state.time,
            h: self.state.h,
            h_crit: self.state.h_crit,
            factor,
            reason,
            advice,
        }
    }
    /// The inverted-element diagnostic for `element`, whose smallest J is `j`: with one-point
    /// integration, which corner (the kernel took the corners' J too,
    /// [`crate::kernels::corners`]) and the J at the centre, the rule's own point.
    pub(super) fn inverted(&self, element: usize, j: f64) -> SolverError {
        let n_hex = self.model.mesh.elements.len();
        let at = match self.model.scheme.integration {
            _ if element >= n_hex => format!(
                "in tetrahedron {} (nodes {:?}; F is constant over it)",
                element - n_hex,
                self.model.mesh.tets[element - n_hex]
            ),
            Integration::Full | Integration::Fbar => "at a Gauss point".to_string(),
            Integration::Reduced | Integration::ReducedPhysical => {
                let conn = self.model.mesh.elements[element];
                let cd = &self.work.classes.centre[self.work.classes.class_of[element] as usize];
                let ue = conn.map(|n| self.state.u.get(n as usize));
                let corners = element_corner_jacobians(cd, &ue);
                let (a, j_a) =
                    (corners.iter().copied().enumerate()).fold((0, f64::INFINITY), |m, (a, x)| {
                        if x < m.1 {
                            (a, x)
                        } else {
                            m
                        }
                    });
                let f = self
                    .model
                    .mesh
                    .centre_deformation_gradient(element, &self.state.u);
                let j_centre = nalgebra::Matrix3::from_fn(|r, c| f[r][c]).determinant();
                let remedy = match self.model.scheme.integration {
                    Integration::Reduced => {
                        "raise scheme.hourglass_coefficient, or use full integration"
                    }
                    _ => "refine the mesh there, or use full integration",
                };
                if j_a <= j_centre {
                    format!(
                        "at its corner {a}, node {}, while J = {j_centre:.3e} at the centre, the one-point rule's own point: the element hourglassed ({remedy})",
                        conn[a]
                    )
                } else {
                    "at its centre".to_string()
                }
            }
        };
        SolverError::Inverted {
            element,
            j,
            at,
            step: self.state.step_count,
            time: self.state.time,
            h: self.state.h,
            h_crit: self.state.h_crit,
        }
    }

    /// Plain-words warnings about the regime of this model, for the user before the run: the
    /// parameters are admissible, but the results or the cost need reading with care.
    ///
    /// - A rubber whose constants fail Drucker's stability somewhere over the stretches
    ///   checked ([`crate::material::rubber::drucker::check`]): the first unstable stretch of
    ///   each mode.
    /// - Near incompressibility (ν ≥ 0.49): K/G = 2(1+ν)/(3(1−2ν)) and c_p/c_s =
    ///   √(2(1−ν)/(1−2ν)); with full integration the hex8 locks volumetrically.
    /// - Interfaces that set the stable step: h_crit with the glue springs W g_N(α) in K
    ///   (model §6.1) at least 1.5× below [`Simulation::h_crit_bulk`], the bulk's alone; the
    ///   run is then that many times longer.
    /// - A brittle law, (u_r − α_e)/α_e < 1 %: the softening branch is crossed within a step.
    /// - Elongated elements (aspect ratio ≥ 10): the shortest edge sets the step.
    /// - A time-step factor above 1: the step is capped at h_crit, the limit itself.
    /// - Glued nodes that start off their mould by more than the tolerance, or inside it
    ///   ([`StartOffset`]): their glue starts pre-stressed (pre-damaged beyond α_e).
    pub fn advisories(&self) -> Vec<String> {
        let m = &self.model;
        let mut out = Vec::new();
        out.extend(self.material_advisories());
        let le = m.mesh.min_edge();
        if let Some(h_bulk) = self
            .state
            .h_crit_bulk
            .filter(|&hb| hb >= 1.5 * self.stats.h_crit_initial)
        {
            let h0 = self.stats.h_crit_initial;
            let names: Vec<String> = m
                .interfaces
                .iter()
                .enumerate()
                .map(|(k, itf)| format!("interface[{k}] (g_N(0) = {:.3e} Pa/m)", itf.law.g_n0))
                .collect();
            out.push(format!(
                "the interface stiffness sets the stable step: h_crit = {h0:.3e} s with the glue springs of {}, {h_bulk:.3e} s for the bulk alone, so the run takes {:.1}× the steps. A glued node's spring against its mass has ω² = W g_N(0)/m: g_N(0) about {:.0}× smaller would no longer limit the step.",
                names.join(", "),
                h_bulk / h0,
                (h_bulk / h0).powi(2)
            ));
        }
        for (k, itf) in m.interfaces.iter().enumerate() {
            let law = &itf.law;
            if law.alpha_e > 0.0 && (law.u_r - law.alpha_e) < 0.01 * law.alpha_e {
                out.push(format!(
                    "interface[{k}] is brittle: u_r − α_e = {:.3e} m is {:.2} % of α_e; a node goes from damage onset to rupture within a step or two, the softening branch T(δ) is not resolved in time (the dissipation still is, by the ledger's ΔD).",
                    law.u_r - law.alpha_e,
                    100.0 * (law.u_r - law.alpha_e) / law.alpha_e
                ));
            }
        }
        let aspect = m.mesh.max_aspect_ratio();
        if aspect >= 10.0 {
            out.push(format!(
                "elements with aspect ratio up to {aspect:.0}: the shortest edge ({le:.3e} m) sets the stable step, h_crit = {:.3e} s.",
                self.state.h_crit
            ));
        }
        out.extend(
            self.setup
                .start_offsets
                .iter()
                .map(|o| self.start_offset_warning(o)),
        );
        out.extend(self.run_advisories());
        let factor = m.scheme.time_step_factor;
        if factor > 1.0 {
            out.push(format!(
                "scheme.time_step_factor = {factor} > 1: the step is capped at h = h_crit, since the central-difference scheme is unstable above it (model §6); at h_crit itself there is no margin for the estimate or for stiffening between estimates: ≤ 0.9 is safe."
            ));
        }
        out
    }

    /// The material's advisories: a rubber's constants that fail Drucker's stability check, and
    /// near incompressibility with what the chosen quadrature does about it.
    fn material_advisories(&self) -> Vec<String> {
        let m = &self.model;
        let mat = &m.material;
        let mut out = Vec::new();
        if let Some(r) = &mat.rubber {
            let unstable = crate::material::rubber::drucker::check(r);
            if !unstable.is_empty() {
                let at: Vec<String> = unstable.iter().map(|i| i.to_string()).collect();
                out.push(format!(
                    "material: the {} constants are not Drucker-stable over the stretches checked (0.1 to 10 in uniaxial, equibiaxial and planar tension): first unstable stretch in {}. Beyond it the stress falls as the stretch grows; keep the deformation below it or refit the constants.",
                    r.iso.spec().label,
                    at.join(", ")
                ));
            }
        }
        let nu = mat.poisson;
        // A mesh of tetrahedra only: the hexahedron's quadrature does not apply.
        let tets_only = m.mesh.elements.is_empty() && !m.mesh.tets.is_empty();
        if nu >= 0.49 && mat.rubber.is_some() {
            let k_over_g = 2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu));
            let cp_over_cs = (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)).sqrt();
            let quadrature = match m.scheme.integration {
                _ if tets_only => TETS_DO_NOT_LOCK,
                Integration::Full => "with full 2×2×2 integration the hex8 locks volumetrically: it is far too stiff in bending and in any deformation that keeps the volume; use scheme.integration = \"fbar\" (model §1.11), \"reduced_physical\" (model §1.12) or \"reduced\" (a rubber's hourglass stiffness follows its shear modulus, model §1.10)",
                Integration::Reduced => "one-point integration does not lock volumetrically, and a rubber's hourglass stiffness κ·11μ₀ follows its shear modulus (model §1.10)",
                Integration::Fbar => FBAR_DOES_NOT_LOCK,
                Integration::ReducedPhysical => PHYSICAL_DOES_NOT_LOCK,
            };
            out.push(format!(
                "the rubber is nearly incompressible (K/μ₀ = {k_over_g:.0}, small-strain ν = {nu:.4}): {quadrature}. The stable step follows the pressure wave, c_p = {cp_over_cs:.1} c_s."
            ));
        } else if nu >= 0.49 {
            let k_over_g = 2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu));
            let cp_over_cs = (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)).sqrt();
            // The hourglass stiffness κ(λ+2μ) grows with λ: scaled to the default's share of the
            // shear modulus, κ = 0.05·2μ/(λ+2μ).
            let kappa_shear = 0.05 * 2.0 * mat.mu / (mat.lambda + 2.0 * mat.mu);
            let kappa = m.scheme.hourglass_coefficient;
            let quadrature = match m.scheme.integration {
                _ if tets_only => "the 4-node tetrahedra of a material other than a rubber lock volumetrically (the average nodal pressure is the rubbers', model §1.13): use a rubber material (material.model = \"isochoric_neo_hookean\", \"mooney_rivlin\", \"yeoh\" or \"ogden\"), or hexahedra".to_string(),
                Integration::Full => format!(
                    "with full 2×2×2 integration the hex8 locks volumetrically: it is far too stiff in bending and in any deformation that keeps the volume; use scheme.integration = \"fbar\" (model §1.11), \"reduced_physical\" (model §1.12), or \"reduced\" with scheme.hourglass_coefficient = {kappa_shear:.1e} (the hourglass stiffness κ(λ+2μ) grows with λ and locks as well at the default κ = 0.05)"
                ),
                Integration::Reduced if kappa > 2.0 * kappa_shear => format!(
                    "one-point integration does not lock volumetrically, but its hourglass stiffness κ(λ+2μ) grows with λ: at κ = {kappa} it stiffens bending as locking would; scheme.hourglass_coefficient = {kappa_shear:.1e} scales it to the shear modulus"
                ),
                Integration::Reduced => format!(
                    "one-point integration with κ = {kappa} does not lock"
                ),
                Integration::Fbar => FBAR_DOES_NOT_LOCK.to_string(),
                Integration::ReducedPhysical => PHYSICAL_DOES_NOT_LOCK.to_string(),
            };
            out.push(format!(
                "material.poisson = {nu} is nearly incompressible (K/G = {k_over_g:.0}): {quadrature}. The stable step follows the pressure wave, c_p = {cp_over_cs:.1} c_s, so shear motion costs {cp_over_cs:.1}× more steps than at ν = 0."
            ));
        }
        out
    }

    /// What the run met: joint contact solves that fell back, h_crit estimates on the iteration
    /// cap, clamped delayed-damage dissipation, mass scaling short of its target or whose added
    /// mass carried too much kinetic energy.
    fn run_advisories(&self) -> Vec<String> {
        let m = &self.model;
        let mut out = Vec::new();
        let joint = &self.stats.joint_contact;
        if joint.capped + joint.friction_dropped > 0 {
            out.push(format!(
                "contact: of {} joint solves at nodes with several active constraints, {} did not converge with friction in {} sweeps (tolerance {:.0e} of the node's velocity) and took the frictionless projection for that step, and {} did not converge even so (last change {:.1e}, approach velocity left up to {:.1e} of the node's velocity): projected Gauss–Seidel contracts slowly for a node barely slipping on two surfaces, or between nearly opposite normals (a narrow slot).",
                joint.nodes,
                joint.friction_dropped,
                crate::interface::contact::JOINT_MAX_SWEEPS,
                crate::interface::contact::JOINT_TOLERANCE,
                joint.capped,
                joint.worst_change,
                joint.worst_approach.max(0.0)
            ));
        }
        let unconverged = self.stats.h_crit_unconverged;
        if unconverged > 0 {
            out.push(format!(
                "stable step: {unconverged} h_crit estimate(s) stopped on the Lanczos iteration cap before meeting scheme.h_crit_tolerance = {:e}; each took the proven element bound (model §6.4) where it gave the smaller step (a material without a pointwise bound, a rubber, has none: its estimate stood). A looser tolerance, or a mesh with fewer degrees of freedom per estimate, avoids it.",
                m.scheme.h_crit_tolerance
            ));
        }
        let clamped = &self.stats.damage_clamped;
        if !clamped.is_none() {
            out.push(format!(
                "delayed damage: at {} steps a negative damage dissipation ΔD (the loaded jump reversing while α still grows, a first-order error of the time step, model §5.5) was taken as 0: {:.3e} J in all ({:.2e} of the damage dissipated), at most {:.3e} J in one step; the balance residual carries it. A smaller scheme.time_step_factor shrinks it.",
                clamped.steps,
                clamped.energy,
                clamped.energy / self.state.ledger.damage_dissipated.max(f64::MIN_POSITIVE),
                clamped.largest_step
            ));
        }
        out.extend(self.mass_scaling_shortfall());
        // The added kinetic energy against the stored energy, over the steps run: before the
        // first step (the warnings printed before a run) both are the start's, nothing stored.
        if let (Some(r), Some(ms)) = (self.setup.mass_scaling, m.scheme.mass_scaling) {
            if self.state.step_count > 0 && r.kinetic_share() > ms.kinetic_share {
                out.push(format!(
                    "mass scaling: the added mass's kinetic energy reached {:.3e} J, {:.1} % of the largest elastic energy stored ({:.3e} J), above mass_scaling.kinetic_share = {}: the added inertia ({:.1} % more mass on {} of {} elements) is no longer negligible, so the run is not quasi-static. A smaller target_step or a slower loading brings it down (model §6.8).",
                    r.added_kinetic_peak,
                    100.0 * r.kinetic_share(),
                    r.stored_peak,
                    ms.kinetic_share,
                    100.0 * r.added_share(),
                    r.scaled_elements,
                    r.elements
                ));
            }
        }
        out
    }
}

impl Simulation {
    /// The warning for glued nodes that start off or inside their mould: how many, how far, and
    /// what it does to the glue (pre-stress g_N(0)δ, pre-damage α₀ = δ beyond α_e, eq. 12).
    fn start_offset_warning(&self, o: &StartOffset) -> String {
        let law = &self.model.interfaces[o.interface].law;
        let mut parts = Vec::new();
        if o.off_nodes > 0 {
            let damage = if o.largest_off > law.alpha_e {
                format!(
                    " and pre-damaged (α₀ = δ > α_e = {:.3e} m: {:?})",
                    law.alpha_e,
                    law.state(o.largest_off.min(law.u_r))
                )
            } else {
                String::new()
            };
            parts.push(format!(
                "{} start off it by up to δ = {:.3e} m: their glue starts stretched, pre-stressed by up to g_N(0)δ = {:.3e} Pa{damage}",
                o.off_nodes,
                o.largest_off,
                law.g_n0 * o.largest_off
            ));
        }
        if o.inside_nodes > 0 {
            parts.push(format!(
                "{} start inside it by up to {:.3e} m, pushed out by their glue",
                o.inside_nodes, o.deepest
            ));
        }
        format!(
            "interface[{}]: glued nodes of `{}` do not start on mould `{}` (tolerance {:.3e} m): {}. Move the face set onto the mould, or the mould onto it, if that is not meant.",
            o.interface,
            o.faces,
            o.mould,
            o.tolerance,
            parts.join("; ")
        )
    }
}
