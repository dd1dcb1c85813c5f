//! The public data of a simulation: its interface and contact nodes, run statistics, stage
//! timings, stable-step estimates and errors. Sign conventions (model §2.1): the rigid
//! surface's normal n points into the solid, a gap g > 0 is open, impulses and tractions are per
//! unit reference area (Pa·s, Pa), the damage α and the jump [u] are in metres.

use crate::interface::contact::ContactStatus;
use crate::interface::law::{InterfaceState, StiffnessLaw};
use serde::Serialize;
use std::time::Duration;

use super::boundary::Boundary;
use super::bulk_viscosity::BulkViscosityState;
use super::stable_step::StepControl;
use crate::energy::Ledger;
use crate::kernels::Planes;
use crate::mould::step::MouldStep;

/// What defines a run at tₙ (model §4.13): the displacements, velocities and internal forces,
/// every interface and contact node (damage, jumps, impulses, the glue formed), the moulds' poses
/// and per-node geometry (in the step's buffers), the step control, the ledger's sums, tₙ, n and
/// h. Everything else of a [`Simulation`](super::Simulation) is the model, what the set-up computes from it (masses,
/// element classes and blocks, the stable-step operator's constants), buffers that every step
/// writes before it reads them, or the statistics. A checkpoint is this state and the
/// statistics ([`Simulation::checkpoint`](super::Simulation::checkpoint)).
#[derive(Clone, Serialize, serde::Deserialize)]
pub struct State {
    /// Displacements Uₙ [m], by component ([`Planes`]: a row of elements along x loads its
    /// nodes 8 at a time, and the node loops run lane against lane).
    pub u: Planes,
    /// Velocities V_{n+½} [m/s], by component.
    pub v: Planes,
    /// Internal forces F_int(Uₙ) [N], by component ([`Planes`]: the element loop adds a row of
    /// elements' forces 8 nodes at a time).
    pub f_int: Planes,
    pub interface_nodes: Vec<InterfaceNode>,
    pub contact_nodes: Vec<ContactNode>,
    /// The node pairs of the bonds (model §7.8).
    #[serde(default)]
    pub bond_nodes: Vec<super::BondNode>,
    /// What acts on each boundary node (glue, contact, tractions, prescribed components), with
    /// the glue still to form.
    pub(super) boundary: Boundary,
    /// The moulds' poses at tₙ, tₙ₊₁, tₙ₊₂, per-node geometry against curved moulds, and
    /// their works (model §7).
    pub(super) moulds: MouldStep,
    /// Bulk viscosity's constants, forces and step values (model §4.12); None without.
    pub(super) bulk_viscosity: Option<BulkViscosityState>,
    /// Current time tₙ [s] and step count n.
    pub time: f64,
    pub step_count: u64,
    /// h_{n+½} = tₙ₊₁ − tₙ, the interval about to be taken [s].
    pub h: f64,
    pub h_crit: f64,
    pub ledger: Ledger,
    /// Smallest Jacobian seen at the last force evaluation (one point: the centre and the
    /// corners): exact when ≤ 0 (an inverted element, which stops the run) and at t₀;
    /// otherwise, with one-point integration, possibly a positive lower bound of it
    /// ([`crate::kernels::assemble_internal_forces`], [`crate::kernels::CORNER_EXACT_BELOW`]).
    pub min_jacobian: f64,
    /// Smallest J where the stress is evaluated at the last force evaluation (the Gauss points,
    /// or one point's centre: [`crate::kernels::Assembly::min_stress_j`]), always exact: the
    /// step control's compression indicator. With one point the corners' J (in
    /// `min_jacobian`) may be far lower under hourglassing while the stiffness, set by the
    /// centre's F and the constant hourglass stiffness, has not moved.
    pub stress_jacobian: f64,
    /// Ritz vector of the last stable-step estimate (warm start of the next one).
    pub(super) ritz_vector: Vec<f64>,
    /// h_crit of the bulk alone (interface springs left out) at t = 0 [s], measured when a glued
    /// node's spring comes near the system's ω_max, i.e. when an interface may set the step.
    pub h_crit_bulk: Option<f64>,
    /// [`State::stress_jacobian`] when h_crit was last estimated.
    pub(super) jacobian_at_estimate: f64,
    /// The variable step's state: the previous interval, the growth goal, the glue's stiffness.
    pub(super) step_control: StepControl,
    /// ½ V_{n+½}ᵀ M V_{n+½}, for the energy-growth check.
    pub kinetic_half: f64,
    /// Initial energy plus Σ|ΔW_ext|: what may have entered the system [J].
    pub(super) energy_budget: f64,
    pub(super) last_external_work: f64,
}

/// Why a simulation could not be built or could not go on.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SolverError {
    #[error("cannot set up the model: {0}")]
    Setup(String),
    #[error("the run became unstable at step {step} (t = {time:.6e} s): {reason}. Current time step h = {h:.4e} s, estimated h_crit = {h_crit:.4e} s (factor {factor:.3}). {advice}")]
    Unstable {
        step: u64,
        time: f64,
        h: f64,
        h_crit: f64,
        factor: f64,
        reason: String,
        advice: String,
    },
    #[error("element {element} inverted (J = {j:.3e} ≤ 0 {at}) at step {step} (t = {time:.6e} s), h = {h:.4e} s, h_crit = {h_crit:.4e} s. The mesh is too coarse for this deformation, the load too fast, or the step too large: refine the mesh, slow the loading, lower scheme.time_step_factor, or use material.model = \"neo_hookean\" (SVK softens and collapses under strong compression)")]
    Inverted {
        element: usize,
        j: f64,
        /// Where in the element: "at a Gauss point", "at its centre", or "at its corner k
        /// (node n) …" (one-point integration checks the corners too).
        at: String,
        step: u64,
        time: f64,
        h: f64,
        h_crit: f64,
    },
    #[error("cancelled at step {step} (t = {time:.6e} s)")]
    Cancelled { step: u64, time: f64 },
}

/// An interface node: a node of the solid bonded to a material point of a rigid plane.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct InterfaceNode {
    pub node: u32,
    /// Index of the interface in `Model::interfaces`.
    pub interface: u32,
    /// Tributary reference area W [m²].
    pub area: f64,
    /// Bonded point of the plane at t = 0 (projection of the node on the plane) [m].
    pub bonded_point: [f64; 3],
    /// Damage αₙ [m].
    pub alpha: f64,
    /// αₙ₊₁, predicted by stage 8 [m].
    pub alpha_next: f64,
    /// α_s = min(u_r, max over the history of f), the target of a delayed law [m]; without a
    /// delay α is α_s and this slot is neither read nor written after t = 0.
    pub alpha_static: f64,
    /// Displacement jump [u]ₙ [m].
    pub jump: [f64; 3],
    /// Normal gap gₙ [m].
    pub gap: f64,
    /// g_N(αₙ) [Pa/m].
    pub stiffness: f64,
    /// Cohesive traction R_d = g_N(α)[u] [Pa] (acting on the solid as −R_d).
    pub cohesive_traction: [f64; 3],
    /// Contact impulse per unit area R_c of the last step [Pa·s].
    pub contact_impulse: [f64; 3],
    pub contact: ContactStatus,
    /// Whether the glue is there: true from t = 0 for an `[[interface]]`; for glue that forms
    /// on contact (`Interface::forms_on_contact`), false until the node first comes into
    /// contact, and true from then on (model §8). While false the node is a contact node
    /// (friction μ of its `[[contact]]` entry): no glue force, g_N = 0, α = 0, no damage, and
    /// its `jump` and `bonded_point` mean nothing.
    pub formed: bool,
    /// [u]ₙ₋₁ and g_N(αₙ₋₁), for the damage dissipation increment.
    pub(crate) prev_jump: [f64; 3],
    pub(crate) prev_stiffness: f64,
}

impl InterfaceNode {
    /// Its state: [`InterfaceState::Unformed`] until glue that forms on contact has formed,
    /// then fig. 6's classification of α by its law (model §2.8: elastic α ≤ α_e,
    /// transition α_e < α < u_r, ruptured α ≥ u_r).
    #[inline]
    pub fn state(&self, law: &StiffnessLaw) -> InterfaceState {
        if self.formed {
            law.state(self.alpha)
        } else {
            InterfaceState::Unformed
        }
    }
}

/// A node of a contact face set (no glue) against a plane.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ContactNode {
    pub node: u32,
    pub plane: u32,
    /// Coulomb coefficient μ.
    pub mu: f64,
    /// Tributary reference area W [m²].
    pub area: f64,
    pub gap: f64,
    pub contact_impulse: [f64; 3],
    pub contact: ContactStatus,
}

/// Wall time spent in each stage of the step (rapier-style counters).
#[derive(Debug, Clone, Default, Serialize, serde::Deserialize)]
pub struct StageTimes {
    /// Stage 1: positions and damage update [s].
    pub positions: f64,
    /// Stage 3: element loop [s].
    pub internal_forces: f64,
    /// Stages 5–8 on the boundary nodes and the bonded pairs: tractions, cohesion,
    /// prescribed displacements, contact, damage [s].
    pub interface_contact: f64,
    /// Stage 4's velocities and stage 5 on all nodes: free velocity and the ledger dot
    /// products [s].
    pub free_velocity: f64,
    /// Stage 9: glue that forms, ledger closing and checks [s].
    pub bookkeeping: f64,
    /// Stage 4's step: stable-step estimates [s].
    pub h_crit: f64,
}

/// Peak of the reaction force of one prescribed-displacement condition.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct PeakReaction {
    pub faces: String,
    pub component: String,
    /// Largest |reaction| (signed) along the prescribed component, excluding steps where the
    /// prescribed velocity jumps (their impulse is the jump itself) [N].
    pub force: f64,
    /// Imposed displacement at that step [m].
    pub imposed_displacement: f64,
    /// Time of the peak [s].
    pub time: f64,
}

/// Counts of interface nodes per state (paper fig. 6, right).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, serde::Deserialize)]
pub struct StateCounts {
    pub elastic: usize,
    pub transition: usize,
    pub ruptured: usize,
    /// Nodes of glue that forms on contact not formed yet ([`InterfaceState::Unformed`]);
    /// left out of the JSON when 0, so that scenes without such glue write what they wrote.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub unformed: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// Running statistics of a simulation, kept as it steps.
#[derive(Debug, Clone, Default, Serialize, serde::Deserialize)]
pub struct RunStats {
    pub h_crit_initial: f64,
    pub h_crit_min: f64,
    pub time_first_damage: Option<f64>,
    pub time_full_rupture: Option<f64>,
    pub peaks: Vec<PeakReaction>,
    /// Current reaction force of each prescribed condition [N].
    pub reactions: Vec<f64>,
    pub stage_times: StageTimes,
    pub steps_wall: Duration,
    /// Number of h_crit estimates after the first (scheduled, or triggered by strain or by the
    /// glue's softening), and their Lanczos iterations in all (about one force evaluation each).
    pub h_crit_estimates: u64,
    pub h_crit_estimate_iterations: u64,
    /// Estimates that the element bound certified (the step below 2/ω_b, `solver/bound.rs`)
    /// instead of converging them.
    pub h_crit_certified: u64,
    /// Smallest and largest step taken [s], and the number of steps whose successor differs.
    pub h_min: f64,
    pub h_max: f64,
    pub step_changes: u64,
    /// Stage 7's joint solves at nodes with several active constraints, over the run.
    pub joint_contact: crate::interface::contact::JointStats,
    /// One-point integration: lane groups of the steps' element loops, and those whose exact
    /// corner check the bound skipped (stage 3 only, not the stable-step estimates).
    pub corner_checks: CornerChecks,
    /// Delayed laws: the negative ΔD taken as 0 (model §5.5), over the run.
    pub damage_clamped: DamageClamped,
    /// h_crit estimates meant to converge that stopped on the Lanczos iteration cap instead;
    /// each took the proven element bound where it was the larger ω² (model §6.4).
    pub h_crit_unconverged: u64,
}

/// What the ledger added to the damage dissipation by taking a delayed law's negative ΔD as 0
/// (model §5.5: at a step where the loaded jump reverses, a first-order error of the time
/// discretisation): the sum over the run [J], the steps where it happened and the largest sum
/// of one step [J]. All 0 without a delayed law. The balance residual carries the same amount.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct DamageClamped {
    pub energy: f64,
    pub steps: u64,
    pub largest_step: f64,
}

impl DamageClamped {
    /// Nothing was clamped.
    pub fn is_none(&self) -> bool {
        self.steps == 0
    }
}

/// Lane groups of 8 elements through the one-point kernel, and those that skipped the exact
/// corner check because the bound showed it could not change what the step uses
/// (`kernels::corner_bound`).
#[derive(Debug, Clone, Copy, Default, Serialize, serde::Deserialize)]
pub struct CornerChecks {
    pub groups: u64,
    pub skipped: u64,
}

/// Result of a stable-step estimate (model §6.2).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StableStep {
    /// Upper estimate of ω_max² = λ_max(M⁻¹K) [1/s²]: Ritz value θ plus its residual bound.
    pub omega_max_sq: f64,
    /// Largest Ritz value θ alone [1/s²].
    pub ritz_value: f64,
    /// h_crit = 2/ω_max [s].
    pub h_crit: f64,
    pub iterations: usize,
    /// The Lanczos run stopped on its convergence test, not on its iteration cap.
    pub converged: bool,
}
