//! Run summaries (table and JSON) and derived quantities of a model. No physics here: this
//! reads a [`Simulation`] and formats it.

use crate::energy::EnergySnapshot;
use crate::solver::{PeakReaction, Simulation, StageTimes, StateCounts};
use serde::Serialize;

/// The run's steps: h's range and changes, and the cost of the h_crit estimates.
#[derive(Debug, Clone, Serialize, Default)]
pub struct StepHistory {
    /// Smallest and largest step [s].
    pub h_min: f64,
    pub h_max: f64,
    /// Steps after which h changed.
    pub changes: u64,
    /// Estimates of h_crit after the first, and their Lanczos iterations in all.
    pub h_crit_estimates: u64,
    pub h_crit_iterations: u64,
    /// Of those, the cheap updates that the element bound certified (the step below 2/ω_b);
    /// the others were converged.
    pub h_crit_certified: u64,
    /// Estimates meant to converge (the first among them) that stopped on the Lanczos
    /// iteration cap; the step then rests on the element bound where it is the larger ω².
    /// Absent when 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub h_crit_unconverged: u64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

/// What a run produced, as printed at the end and written by `--summary`.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    pub scene: String,
    /// "completed", "failed" or "cancelled".
    pub status: String,
    /// The error message when the run did not complete.
    pub error: Option<String>,
    pub nodes: usize,
    pub elements: usize,
    pub interface_nodes: usize,
    /// Threads that ran the step's loops (1 below the size where they run in parallel).
    pub threads: usize,
    pub steps: u64,
    /// Last time step h [s].
    pub time_step: f64,
    pub h_crit_initial: f64,
    pub h_crit_min: f64,
    pub time_step_factor: f64,
    /// How the step moved: smallest and largest h, the number of changes, and the h_crit
    /// estimates after the first with their Lanczos iterations (about one force evaluation
    /// each).
    pub steps_taken: StepHistory,
    /// Simulated time reached [s].
    pub simulated_time: f64,
    /// Wall time of the whole run, set-up included [s].
    pub wall_seconds: f64,
    /// Wall time inside `step()` only [s].
    pub step_wall_seconds: f64,
    pub element_steps_per_second: f64,
    pub ns_per_element_step: f64,
    pub peak_reactions: Vec<PeakReaction>,
    pub time_first_damage: Option<f64>,
    pub time_full_rupture: Option<f64>,
    pub final_counts: StateCounts,
    pub energies: EnergySnapshot,
    pub max_relative_residual: f64,
    pub stage_seconds: StageTimes,
    /// What each output of the run wrote, under its name ([`crate::output::OutputReport`]):
    /// `recording` (Rerun) and `paraview` (`--vtk`), null without them, `series` (`--series`),
    /// absent without it (the run driver's summary; empty here); an output of the registry
    /// ([`crate::outputs`]) adds its own.
    #[cfg(not(target_arch = "wasm32"))]
    #[serde(flatten)]
    pub outputs: std::collections::BTreeMap<String, serde_json::Value>,
    /// The outputs' rows of the console's table, as (name, text), in the outputs' order.
    #[cfg(not(target_arch = "wasm32"))]
    #[serde(skip)]
    pub output_lines: Vec<(String, String)>,
    /// [`Simulation::advisories`]: warnings about the regime of the model.
    pub warnings: Vec<String>,
    /// The checkpoints written (`run --checkpoint`, `--resume`); absent without them.
    #[cfg(not(target_arch = "wasm32"))]
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkpoint: Option<crate::checkpoint::CheckpointReport>,
    /// Interfaces whose glued nodes start off their mould beyond the tolerance, or inside it:
    /// per interface the count and the largest offset ([`crate::model::StartOffset`]; also a
    /// warning). Absent when every glued node starts on its mould.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub glued_start_offsets: Vec<crate::model::StartOffset>,
    /// Each mould's work since t₀ [J] (force · velocity of the mould at the points it acts on,
    /// moments included; their sum is `energies.plane_work`), as (name, work). Listed when a
    /// scene has a mould that is not a plain fixed-orientation plane (model §7.6).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub mould_work: Vec<(String, f64)>,
    /// The friction dissipated on each mould since t₀ [J] (their sum is
    /// `energies.friction_dissipated`, to round-off), as (name, dissipation); listed with
    /// `mould_work`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub mould_friction: Vec<(String, f64)>,
    /// Delayed laws: the negative ΔD the ledger took as 0 ([`crate::solver::DamageClamped`]);
    /// absent when nothing was.
    #[serde(default, skip_serializing_if = "crate::solver::DamageClamped::is_none")]
    pub damage_clamped: crate::solver::DamageClamped,
    /// Stage 7's joint solves at nodes with several active constraints: how many, their sweeps,
    /// those that fell back to the frictionless projection (`friction_dropped`) and those that
    /// did not converge even so (`capped`). Absent when there were none.
    #[serde(skip_serializing_if = "crate::interface::contact::JointStats::is_empty")]
    pub joint_contact: crate::interface::contact::JointStats,
    /// What mass scaling did (model §6.8): the target step, the elements scaled, the mass
    /// added, and the added mass's largest kinetic energy against the largest elastic energy
    /// stored. Absent without mass scaling.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass_scaling: Option<crate::solver::MassScalingReport>,
}

impl RunSummary {
    /// Adds what an output wrote: its value under its name, its row of the table.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn add_output(&mut self, report: crate::output::OutputReport) {
        if let Some(line) = report.line {
            self.output_lines.push((report.name.to_string(), line));
        }
        self.outputs.insert(report.name.to_string(), report.value);
    }

    /// Collects the summary of `sim` after a run that took `wall_seconds` in all.
    pub fn new(
        sim: &Simulation,
        wall_seconds: f64,
        error: Option<&crate::solver::SolverError>,
    ) -> Self {
        let step_wall = sim.stats.steps_wall.as_secs_f64();
        let el_steps = sim.element_steps() as f64;
        let status = match error {
            None => "completed",
            Some(crate::solver::SolverError::Cancelled { .. }) => "cancelled",
            Some(_) => "failed",
        };
        let moulds_listed = !sim.model.moulds.iter().all(|p| p.is_plane());
        RunSummary {
            scene: sim.model.name.clone(),
            status: status.into(),
            error: error.map(|e| e.to_string()),
            nodes: sim.model.mesh.nodes.len(),
            elements: sim.model.mesh.element_count(),
            interface_nodes: sim.state.interface_nodes.len(),
            threads: sim.threads(),
            steps: sim.state.step_count,
            time_step: sim.state.h,
            h_crit_initial: sim.stats.h_crit_initial,
            h_crit_min: sim.stats.h_crit_min,
            time_step_factor: sim.model.scheme.time_step_factor,
            steps_taken: StepHistory {
                h_min: sim.stats.h_min,
                h_max: sim.stats.h_max,
                changes: sim.stats.step_changes,
                h_crit_estimates: sim.stats.h_crit_estimates,
                h_crit_iterations: sim.stats.h_crit_estimate_iterations,
                h_crit_certified: sim.stats.h_crit_certified,
                h_crit_unconverged: sim.stats.h_crit_unconverged,
            },
            simulated_time: sim.state.time,
            wall_seconds,
            step_wall_seconds: step_wall,
            element_steps_per_second: if step_wall > 0.0 {
                el_steps / step_wall
            } else {
                0.0
            },
            ns_per_element_step: if el_steps > 0.0 {
                step_wall * 1e9 / el_steps
            } else {
                0.0
            },
            peak_reactions: sim.stats.peaks.clone(),
            time_first_damage: sim.stats.time_first_damage,
            time_full_rupture: sim.stats.time_full_rupture,
            final_counts: sim.state_counts(),
            energies: sim.energies(),
            max_relative_residual: sim.state.ledger.max_relative_residual,
            stage_seconds: sim.stats.stage_times.clone(),
            #[cfg(not(target_arch = "wasm32"))]
            outputs: Default::default(),
            #[cfg(not(target_arch = "wasm32"))]
            output_lines: Vec::new(),
            warnings: sim.advisories(),
            #[cfg(not(target_arch = "wasm32"))]
            checkpoint: None,
            glued_start_offsets: sim.setup.start_offsets.clone(),
            mould_work: if moulds_listed {
                sim.mould_works()
            } else {
                vec![]
            },
            mould_friction: if moulds_listed {
                sim.mould_frictions()
            } else {
                vec![]
            },
            damage_clamped: sim.stats.damage_clamped,
            joint_contact: sim.stats.joint_contact,
            mass_scaling: sim.setup.mass_scaling,
        }
    }

    /// A short human-readable table.
    pub fn table(&self) -> String {
        let opt = |t: Option<f64>| t.map_or("never".to_string(), |t| format!("{t:.5} s"));
        let mut s = String::new();
        let mut row = |k: &str, v: String| s.push_str(&format!("  {k:<28} {v}\n"));
        row("scene", self.scene.clone());
        row("status", self.status.clone());
        row(
            "mesh",
            format!(
                "{} nodes, {} hex8, {} interface nodes",
                self.nodes, self.elements, self.interface_nodes
            ),
        );
        row(
            "steps",
            format!("{} to t = {:.5} s", self.steps, self.simulated_time),
        );
        row(
            "time step",
            format!(
                "h = {:.4e} s (factor {} × h_crit; h_crit {:.4e} s initial, {:.4e} s min)",
                self.time_step, self.time_step_factor, self.h_crit_initial, self.h_crit_min
            ),
        );
        let st = &self.steps_taken;
        row(
            "step changes",
            format!(
                "{} (h from {:.4e} to {:.4e} s), {} h_crit estimates ({} certified by the element bound, {} Lanczos iterations)",
                st.changes,
                st.h_min,
                st.h_max,
                st.h_crit_estimates,
                st.h_crit_certified,
                st.h_crit_iterations
            ),
        );
        row(
            "speed",
            format!(
                "{:.1} ns/element-step, {:.3e} element-steps/s, {} thread{}, {:.3} s wall",
                self.ns_per_element_step,
                self.element_steps_per_second,
                self.threads,
                if self.threads == 1 { "" } else { "s" },
                self.wall_seconds
            ),
        );
        for p in &self.peak_reactions {
            row(
                &format!("peak reaction {} {}", p.faces, p.component),
                format!(
                    "{:.5e} N at U = {:.5e} m (t = {:.5} s)",
                    p.force, p.imposed_displacement, p.time
                ),
            );
        }
        row("first damage", opt(self.time_first_damage));
        row("full rupture", opt(self.time_full_rupture));
        let c = &self.final_counts;
        row(
            "interface nodes",
            match c.unformed {
                0 => format!(
                    "{} elastic, {} transition, {} ruptured",
                    c.elastic, c.transition, c.ruptured
                ),
                n => format!(
                    "{} elastic, {} transition, {} ruptured, {n} unformed (glue not formed yet)",
                    c.elastic, c.transition, c.ruptured
                ),
            },
        );
        let e = &self.energies;
        row(
            "kinetic / strain",
            format!("{:.6e} J / {:.6e} J", e.kinetic, e.strain),
        );
        if e.hourglass != 0.0 {
            row("hourglass (one-point)", format!("{:.6e} J", e.hourglass));
        }
        row("interface stored", format!("{:.6e} J", e.interface_stored));
        if let Some(m) = &self.mass_scaling {
            row(
                "mass scaling (§6.8)",
                format!(
                    "{:.2} % mass added on {} of {} elements (target h_t = {:.4e} s, density × {:.3} at most); its kinetic energy {:.3e} J at most, {:.2} % of the largest stored {:.3e} J",
                    100.0 * m.added_share(),
                    m.scaled_elements,
                    m.elements,
                    m.target_step,
                    m.largest_factor,
                    m.added_kinetic_peak,
                    100.0 * m.kinetic_share(),
                    m.stored_peak
                ),
            );
        }
        row(
            "dissipated",
            format!(
                "damage {:.6e} J, contact {:.6e} J, friction {:.6e} J",
                e.damage_dissipated, e.contact_normal_dissipated, e.friction_dissipated
            ),
        );
        if e.bulk_viscous_dissipated != 0.0 {
            row(
                "bulk viscosity (§4.12)",
                format!("{:.6e} J dissipated", e.bulk_viscous_dissipated),
            );
        }
        row("external work", format!("{:.6e} J", e.external_work));
        for (name, w) in &self.mould_work {
            row(&format!("  work of mould `{name}`"), format!("{w:.6e} J"));
        }
        for (name, d) in &self.mould_friction {
            row(
                &format!("  friction on mould `{name}`"),
                format!("{d:.6e} J"),
            );
        }
        row(
            "balance residual",
            format!(
                "{:.3e} J now, max relative {:.3e}",
                e.residual, self.max_relative_residual
            ),
        );
        #[cfg(not(target_arch = "wasm32"))]
        for (name, line) in &self.output_lines {
            row(name, line.clone());
        }
        for w in &self.warnings {
            row("warning", w.clone());
        }
        if let Some(err) = &self.error {
            row("error", err.clone());
        }
        s
    }
}

/// Rough memory of the solver state per element [bytes]: nodal arrays, connectivity, colours,
/// element classes, boundary entries (what the time loop touches; not the allocator's view).
pub fn state_bytes(sim: &Simulation) -> usize {
    let m = &sim.model.mesh;
    let nodes = m.nodes.len();
    // X, U, V, F_int (3 f64 each), mass and inverse mass.
    let nodal = nodes * (4 * 24 + 2 * 8);
    let elements = m.elements.len() * (32 + 4 + 4);
    let classes = sim.element_class_count() * std::mem::size_of::<crate::mesh::GaussData>();
    let iface =
        sim.state.interface_nodes.len() * std::mem::size_of::<crate::solver::InterfaceNode>();
    nodal + elements + classes + iface
}
