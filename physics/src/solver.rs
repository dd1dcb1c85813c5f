//! The CD-Lagrange time step (PHYSICS.md §4) with the RCCM interface, contact, friction,
//! prescribed displacements, the energy ledger (§5) and the stable-step estimate (§6).
//!
//! State at integer times tₙ: displacements U, damage α; at half times: velocities V. One call of
//! [`Simulation::step`] goes from tₙ to tₙ₊₁ through the numbered stages of PHYSICS.md §4.
//! Nothing is solved globally: every stage is a loop of local computations, the element loop in
//! parallel ([`Team`]: persistent threads, static shares) and deterministic whatever the thread
//! count (node-disjoint element blocks, fixed-size chunks, fixed-order reductions).

use crate::energy::{EnergySnapshot, Ledger};
use crate::kernels::{
    assemble_internal_forces, free_velocity_chunk, ElementRule, ElementSums, NodeSums,
};
use crate::law::InterfaceState;
use crate::mesh::{dot, norm, ElementClasses};
use crate::model::Model;
use crate::team::{SharedSlice, Team};
use serde::Serialize;
use std::time::{Duration, Instant};

/// Smallest element block ([`crate::mesh::Mesh::element_blocks`]), and nodes per chunk in node loops. Fixed,
/// so the reduction order never depends on the thread count.
const ELEMENT_GRAIN: usize = 256;
const NODE_GRAIN: usize = 4096;
/// Boundary nodes per chunk of the boundary loop (stages 4–8).
const BOUNDARY_GRAIN: usize = 256;
/// Below this many elements the loops run on the calling thread (a parallel section would
/// cost more than it saves).
pub const PARALLEL_MIN_ELEMENTS: usize = 2048;

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
    #[error("element {element} inverted (J = {j:.3e} ≤ 0) at step {step} (t = {time:.6e} s), h = {h:.4e} s, h_crit = {h_crit:.4e} s. The mesh is too coarse for this deformation, the load too fast, or the step too large: refine the mesh, slow the loading, lower scheme.time_step_factor, or use material.model = \"neo_hookean\" (SVK softens and collapses under strong compression)")]
    Inverted {
        element: usize,
        j: f64,
        step: u64,
        time: f64,
        h: f64,
        h_crit: f64,
    },
    #[error("cancelled at step {step} (t = {time:.6e} s)")]
    Cancelled { step: u64, time: f64 },
}

/// Contact status of a node against a plane, for output and debugging.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ContactStatus {
    /// Gap > 0, or approaching velocity ≥ 0: no impulse.
    #[default]
    Open,
    /// |r_T| ≤ μ r_N: no sliding.
    Stick,
    /// |r_T| = μ r_N opposing the sliding velocity.
    Slip,
}

/// An interface node: a node of the solid bonded to a material point of a rigid plane.
#[derive(Debug, Clone)]
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
    /// [u]ₙ₋₁ and g_N(αₙ₋₁), for the damage dissipation increment.
    prev_jump: [f64; 3],
    prev_stiffness: f64,
}

/// A node of a contact face set (no glue) against a plane.
#[derive(Debug, Clone)]
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

/// Per boundary node: which interface entries, contact entries, traction entries and prescribed
/// components act on it.
#[derive(Debug, Clone)]
struct BoundaryNode {
    node: u32,
    interfaces: std::ops::Range<u32>,
    contacts: std::ops::Range<u32>,
    tractions: std::ops::Range<u32>,
    /// Index of the prescribed-displacement condition of each component (`NONE` if free).
    prescribed: [u16; 3],
}
const NONE: u16 = u16::MAX;

/// Change of the smallest Jacobian since the last h_crit estimate that triggers a new estimate
/// before its scheduled step, once some element is compressed below [`JACOBIAN_COMPRESSED`]
/// (`next_time_step`).
const JACOBIAN_RETRIGGER: f64 = 0.02;
/// Smallest Jacobian below which strain changes re-estimate h_crit between scheduled estimates.
const JACOBIAN_COMPRESSED: f64 = 0.9;

/// Per-step values of the planes, prescribed conditions and tractions, computed once per step
/// (not per node) into buffers that are reused, so the step allocates nothing after the first.
#[derive(Debug, Clone, Default)]
struct StepScratch {
    /// Plane displacement d(tₙ₊₁) and the round-off tolerance of its gaps.
    plane_disp: Vec<[f64; 3]>,
    plane_tol: Vec<f64>,
    /// Plane velocity over the interval just taken and the next one.
    plane_v_old: Vec<[f64; 3]>,
    plane_v_new: Vec<[f64; 3]>,
    /// Prescribed velocity of each condition over the next interval, whether it jumps here,
    /// and its reaction force.
    bc_velocity: Vec<f64>,
    bc_jump: Vec<bool>,
    reactions: Vec<f64>,
    /// Amplitude of each traction at tₙ₊₁.
    amplitudes: Vec<f64>,
}

/// Wall time spent in each stage of the step (rapier-style counters).
#[derive(Debug, Clone, Default, Serialize)]
pub struct StageTimes {
    /// Stage 1: positions and damage update [s].
    pub positions: f64,
    /// Stage 3: element loop [s].
    pub internal_forces: f64,
    /// Stages 4–8 on the boundary: cohesion, prescribed displacements, contact, damage [s].
    pub interface_contact: f64,
    /// Stage 5 on all nodes: free velocity and the ledger dot products [s].
    pub free_velocity: f64,
    /// Stage 9: ledger closing and checks [s].
    pub bookkeeping: f64,
    /// Stable-step estimates [s].
    pub h_crit: f64,
}

/// Peak of the reaction force of one prescribed-displacement condition.
#[derive(Debug, Clone, Serialize)]
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
}

/// Running statistics of a simulation, kept as it steps.
#[derive(Debug, Clone, Default)]
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
    /// Number of h_crit estimates after the first (scheduled or triggered by strain).
    pub h_crit_estimates: u64,
}

/// Result of a stable-step estimate (PHYSICS.md §6).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StableStep {
    /// Upper estimate of ω_max² = λ_max(M⁻¹K) [1/s²]: Ritz value θ plus its residual bound.
    pub omega_max_sq: f64,
    /// Largest Ritz value θ alone [1/s²].
    pub ritz_value: f64,
    /// h_crit = 2/ω_max [s].
    pub h_crit: f64,
    pub iterations: usize,
}

/// A simulation in progress. Build it with [`Simulation::new`], advance it with
/// [`Simulation::step`] or [`Simulation::run`].
pub struct Simulation {
    pub model: Model,
    classes: ElementClasses,
    /// Colours → node-disjoint blocks → elements ([`crate::mesh::Mesh::element_blocks`]).
    blocks: Vec<Vec<Vec<u32>>>,
    /// The threads of the parallel loops (None: everything on the calling thread).
    team: Option<Team>,
    /// Per-block / per-chunk results of the parallel loops, reused from step to step.
    parts_elements: Vec<ElementSums>,
    parts_nodes: Vec<NodeSums>,
    parts_boundary: Vec<BoundarySums>,
    /// Reaction impulse of each prescribed condition from each boundary chunk.
    parts_reactions: Vec<f64>,
    /// Lumped nodal masses [kg] and their inverses.
    pub mass: Vec<f64>,
    inv_mass: Vec<f64>,
    /// Displacements Uₙ [m].
    pub u: Vec<[f64; 3]>,
    /// Velocities V_{n+½} [m/s].
    pub v: Vec<[f64; 3]>,
    /// Internal forces F_int(Uₙ) [N].
    pub f_int: Vec<[f64; 3]>,
    pub interface_nodes: Vec<InterfaceNode>,
    pub contact_nodes: Vec<ContactNode>,
    boundary: Vec<BoundaryNode>,
    boundary_interfaces: Vec<u32>,
    boundary_contacts: Vec<u32>,
    /// (traction index, nodal force at amplitude 1 [N]).
    boundary_tractions: Vec<(u16, [f64; 3])>,
    /// Boundary velocity before the step V_{n−½}, kept for the ledger.
    scratch_v_old: Vec<[f64; 3]>,
    scratch: StepScratch,
    /// Current time tₙ [s] and step count n.
    pub time: f64,
    pub step_count: u64,
    /// h_{n+½} = tₙ₊₁ − tₙ, the interval about to be taken [s].
    pub h: f64,
    pub h_crit: f64,
    pub ledger: Ledger,
    pub stats: RunStats,
    /// Smallest Jacobian seen at the last force evaluation.
    pub min_jacobian: f64,
    /// Ritz vector of the last stable-step estimate (warm start of the next one).
    ritz_vector: Vec<f64>,
    /// h_crit of the bulk alone (interface springs left out) at t = 0 [s], measured when a glued
    /// node's spring comes near the system's ω_max, i.e. when an interface may set the step.
    pub h_crit_bulk: Option<f64>,
    /// Smallest Jacobian when h_crit was last estimated.
    jacobian_at_estimate: f64,
    /// ½ V_{n+½}ᵀ M V_{n+½}, for the energy-growth check.
    pub kinetic_half: f64,
    /// Initial energy plus Σ|ΔW_ext|: what may have entered the system [J].
    energy_budget: f64,
    last_external_work: f64,
    /// Energy below which growth is round-off, E·V·1e-14 [J].
    energy_floor: f64,
    /// Largest |reference coordinate| of the mesh [m]: the scale of position round-off.
    coordinate_scale: f64,
}

/// A chunk of displacements and the matching velocities (stage 1).
type PositionChunk<'a> = (&'a mut [[f64; 3]], &'a [[f64; 3]]);
/// One chunk of the node loop: (velocities, internal forces), (masses, inverse masses).
type NodeChunk<'a> = ((&'a mut [[f64; 3]], &'a [[f64; 3]]), (&'a [f64], &'a [f64]));

impl Simulation {
    /// Builds the simulation: reference gradients, colours, lumped masses, boundary bookkeeping,
    /// the first stable-step estimate, and the start of the leapfrog (V_{−½}, V_{½}).
    ///
    /// The initial velocity field is the rigid motion V₀(X) = v₀ + ω₀ × (X − X_c) of the scene's
    /// `initial_velocity` v₀ and `initial_angular_velocity` ω₀ about the centre of mass X_c.
    pub fn new(model: Model) -> Result<Simulation, SolverError> {
        let v0 = model.initial_velocity;
        let w = model.initial_angular_velocity;
        let mesh = &model.mesh;
        let n = mesh.nodes.len();
        let velocities = if w == [0.0; 3] {
            vec![v0; n]
        } else {
            let xc = mesh
                .centre_of_volume()
                .map_err(|e| SolverError::Setup(e.to_string()))?;
            mesh.nodes
                .iter()
                .map(|x| {
                    let r = crate::mesh::sub(*x, xc);
                    [
                        v0[0] + w[1] * r[2] - w[2] * r[1],
                        v0[1] + w[2] * r[0] - w[0] * r[2],
                        v0[2] + w[0] * r[1] - w[1] * r[0],
                    ]
                })
                .collect()
        };
        Self::with_initial_state(model, vec![[0.0; 3]; n], velocities)
    }

    /// As [`Simulation::new`], from given initial displacements U₀ and velocities V₀ per node
    /// (prescribed components of U₀ are overwritten by their histories at t = 0).
    pub fn with_initial_state(
        model: Model,
        u0: Vec<[f64; 3]>,
        v0: Vec<[f64; 3]>,
    ) -> Result<Simulation, SolverError> {
        if u0.len() != model.mesh.nodes.len() || v0.len() != model.mesh.nodes.len() {
            return Err(SolverError::Setup(format!(
                "initial state has {} displacements and {} velocities for {} nodes",
                u0.len(),
                v0.len(),
                model.mesh.nodes.len()
            )));
        }
        let mesh = &model.mesh;
        let classes = mesh
            .element_classes()
            .map_err(|e| SolverError::Setup(e.to_string()))?;
        let blocks = mesh.element_blocks(ELEMENT_GRAIN);
        let n_nodes = mesh.nodes.len();
        let rho = model.material.density;
        let mut mass = vec![0.0; n_nodes];
        for (e, conn) in mesh.elements.iter().enumerate() {
            let lv = classes.data[classes.class_of[e] as usize].lumped_volumes();
            for a in 0..8 {
                mass[conn[a] as usize] += rho * lv[a];
            }
        }
        if let Some(i) = mass.iter().position(|&m| !(m > 0.0)) {
            return Err(SolverError::Setup(format!(
                "node {i} belongs to no element (zero mass)"
            )));
        }
        let inv_mass = mass.iter().map(|m| 1.0 / m).collect();

        // Boundary entries, gathered per node.
        let face = |name: &str| -> Result<&Vec<[u32; 4]>, SolverError> {
            mesh.face_sets
                .get(name)
                .ok_or_else(|| SolverError::Setup(format!("no face set named `{name}`")))
        };
        let mut interface_nodes = Vec::new();
        for (k, itf) in model.interfaces.iter().enumerate() {
            let plane = &model.planes[itf.plane];
            for (node, area) in mesh.nodal_areas(face(&itf.faces)?) {
                let x = mesh.nodes[node as usize];
                let gap0 = dot(plane.normal, crate::mesh::sub(x, plane.point));
                let y0 = [
                    x[0] - gap0 * plane.normal[0],
                    x[1] - gap0 * plane.normal[1],
                    x[2] - gap0 * plane.normal[2],
                ];
                interface_nodes.push(InterfaceNode {
                    node,
                    interface: k as u32,
                    area,
                    bonded_point: y0,
                    alpha: 0.0,
                    alpha_next: 0.0,
                    jump: [0.0; 3],
                    gap: gap0,
                    stiffness: itf.law.g_n0,
                    cohesive_traction: [0.0; 3],
                    contact_impulse: [0.0; 3],
                    contact: ContactStatus::Open,
                    prev_jump: [0.0; 3],
                    prev_stiffness: itf.law.g_n0,
                });
            }
        }
        let mut contact_nodes = Vec::new();
        for c in &model.contacts {
            for (node, area) in mesh.nodal_areas(face(&c.faces)?) {
                contact_nodes.push(ContactNode {
                    node,
                    plane: c.plane as u32,
                    mu: c.mu,
                    area,
                    gap: 0.0,
                    contact_impulse: [0.0; 3],
                    contact: ContactStatus::Open,
                });
            }
        }
        let mut trac_entries: Vec<(u32, u16, [f64; 3])> = Vec::new();
        for (k, t) in model.tractions.iter().enumerate() {
            for (node, area) in mesh.nodal_areas(face(&t.faces)?) {
                trac_entries.push((node, k as u16, t.vector.map(|c| c * area)));
            }
        }
        let mut prescribed: std::collections::BTreeMap<u32, [u16; 3]> = Default::default();
        for (k, d) in model.displacements.iter().enumerate() {
            for node in mesh.face_set_nodes(face(&d.faces)?) {
                let slot = &mut prescribed.entry(node).or_insert([NONE; 3])[d.component];
                if *slot != NONE && model.displacements[*slot as usize].history != d.history {
                    return Err(SolverError::Setup(format!(
                        "node {node} has component {} prescribed twice with different histories (displacement[{}] on `{}` and displacement[{k}] on `{}`)",
                        ["x", "y", "z"][d.component],
                        *slot,
                        model.displacements[*slot as usize].faces,
                        d.faces
                    )));
                }
                if *slot == NONE {
                    *slot = k as u16;
                }
            }
        }
        let mut nodes_touched: Vec<u32> = interface_nodes
            .iter()
            .map(|i| i.node)
            .chain(contact_nodes.iter().map(|c| c.node))
            .chain(trac_entries.iter().map(|t| t.0))
            .chain(prescribed.keys().copied())
            .collect();
        nodes_touched.sort_unstable();
        nodes_touched.dedup();
        let mut by_node_i: Vec<(u32, u32)> = interface_nodes
            .iter()
            .enumerate()
            .map(|(k, i)| (i.node, k as u32))
            .collect();
        by_node_i.sort_unstable();
        let mut by_node_c: Vec<(u32, u32)> = contact_nodes
            .iter()
            .enumerate()
            .map(|(k, c)| (c.node, k as u32))
            .collect();
        by_node_c.sort_unstable();
        trac_entries.sort_by_key(|t| (t.0, t.1));
        let (mut pi, mut pc, mut pt) = (0usize, 0usize, 0usize);
        let mut boundary = Vec::with_capacity(nodes_touched.len());
        let mut boundary_interfaces = Vec::new();
        let mut boundary_contacts = Vec::new();
        let mut boundary_tractions = Vec::new();
        for &node in &nodes_touched {
            let i0 = boundary_interfaces.len() as u32;
            while pi < by_node_i.len() && by_node_i[pi].0 == node {
                boundary_interfaces.push(by_node_i[pi].1);
                pi += 1;
            }
            let c0 = boundary_contacts.len() as u32;
            while pc < by_node_c.len() && by_node_c[pc].0 == node {
                boundary_contacts.push(by_node_c[pc].1);
                pc += 1;
            }
            let t0 = boundary_tractions.len() as u32;
            while pt < trac_entries.len() && trac_entries[pt].0 == node {
                boundary_tractions.push((trac_entries[pt].1, trac_entries[pt].2));
                pt += 1;
            }
            boundary.push(BoundaryNode {
                node,
                interfaces: i0..boundary_interfaces.len() as u32,
                contacts: c0..boundary_contacts.len() as u32,
                tractions: t0..boundary_tractions.len() as u32,
                prescribed: prescribed.get(&node).copied().unwrap_or([NONE; 3]),
            });
        }

        let volume: f64 = classes
            .class_of
            .iter()
            .map(|&c| classes.data[c as usize].volume())
            .sum();
        let threads = rayon::current_num_threads();
        let team = (mesh.elements.len() >= PARALLEL_MIN_ELEMENTS && threads > 1)
            .then(|| Team::new(threads));
        let n_bc = model.displacements.len();
        let mut sim = Simulation {
            classes,
            blocks,
            team,
            parts_elements: Vec::new(),
            parts_nodes: Vec::new(),
            parts_boundary: Vec::new(),
            parts_reactions: Vec::new(),
            mass,
            inv_mass,
            u: u0,
            v: v0,
            f_int: vec![[0.0; 3]; n_nodes],
            interface_nodes,
            contact_nodes,
            scratch_v_old: vec![[0.0; 3]; boundary.len()],
            scratch: StepScratch::default(),
            boundary,
            boundary_interfaces,
            boundary_contacts,
            boundary_tractions,
            time: 0.0,
            step_count: 0,
            h: 0.0,
            h_crit: 0.0,
            ledger: Ledger::default(),
            stats: RunStats {
                peaks: model
                    .displacements
                    .iter()
                    .map(|d| PeakReaction {
                        faces: d.faces.clone(),
                        component: ["x", "y", "z"][d.component].into(),
                        force: 0.0,
                        imposed_displacement: d.history.value(0.0)[0],
                        time: 0.0,
                    })
                    .collect(),
                reactions: vec![0.0; n_bc],
                ..Default::default()
            },
            min_jacobian: 1.0,
            ritz_vector: Vec::new(),
            h_crit_bulk: None,
            jacobian_at_estimate: 1.0,
            kinetic_half: 0.0,
            energy_budget: 0.0,
            last_external_work: 0.0,
            energy_floor: model.material.young * volume * 1e-14,
            coordinate_scale: model
                .mesh
                .nodes
                .iter()
                .flatten()
                .fold(0.0f64, |a, x| a.max(x.abs())),
            model,
        };
        sim.start()?;
        Ok(sim)
    }

    /// Number of elements times steps done.
    pub fn element_steps(&self) -> u64 {
        self.model.mesh.elements.len() as u64 * self.step_count
    }

    /// t = 0: U₀ (prescribed values), α₀, first h_crit, V_{−½} = V₀ − ½h M⁻¹F₀, then the usual
    /// impulse stages give V_{½} (so K₀ = ½V_{−½}ᵀMV_{½}).
    fn start(&mut self) -> Result<(), SolverError> {
        for b in &self.boundary {
            for c in 0..3 {
                if b.prescribed[c] != NONE {
                    self.u[b.node as usize][c] = self.model.displacements[b.prescribed[c] as usize]
                        .history
                        .value(0.0)[0];
                }
            }
        }
        self.update_interface_kinematics();
        for itf in self.interface_nodes.iter_mut() {
            let spec = &self.model.interfaces[itf.interface as usize];
            let (law, n) = (&spec.law, self.model.planes[spec.plane].normal);
            // α₀ = min(u_r, max(initial damage, f₀)): eq. 12's "largest jump ever reached",
            // with the damage the interface had before the run.
            itf.alpha = law
                .u_r
                .min(damage_measure(itf.jump, n).max(spec.initial_damage));
            itf.alpha_next = itf.alpha;
            itf.stiffness = law.g_n(itf.alpha);
            itf.prev_stiffness = itf.stiffness;
            itf.prev_jump = itf.jump;
        }
        let est = self.estimate_stable_step(None);
        self.h_crit = est.h_crit;
        // When a glued node's own spring (ω_i² = W g_N/m) is near the whole system's ω_max, the
        // interface may set the step: measure the bulk alone once, for `advisories`.
        let omega_itf_sq = self
            .interface_nodes
            .iter()
            .map(|n| n.area * n.stiffness * self.inv_mass[n.node as usize])
            .fold(0.0, f64::max);
        if omega_itf_sq > 0.0 && 2.0 / omega_itf_sq.sqrt() < 1.5 * est.h_crit {
            let ritz = std::mem::take(&mut self.ritz_vector);
            self.h_crit_bulk = Some(self.stable_step_estimate(None, false).h_crit);
            self.ritz_vector = ritz;
        }
        self.stats.h_crit_initial = est.h_crit;
        self.stats.h_crit_min = est.h_crit;
        self.h = self.model.scheme.time_step_factor * est.h_crit;
        if !(self.h.is_finite() && self.h > 0.0) {
            return Err(SolverError::Setup(format!(
                "the stable time step estimate is not usable (ω_max² = {:e}); check the material and interface stiffness",
                est.omega_max_sq
            )));
        }
        self.compute_internal_forces(true, false)?;
        // V_{−½} = V₀ − ½h M⁻¹F₀ with the smooth forces (internal, gravity, tractions, glue).
        let (h, g) = (self.h, self.model.gravity);
        for i in 0..self.v.len() {
            for c in 0..3 {
                self.v[i][c] -= 0.5 * h * (g[c] - self.f_int[i][c] * self.inv_mass[i]);
            }
        }
        for bi in 0..self.boundary.len() {
            let b = self.boundary[bi].clone();
            let i = b.node as usize;
            let mut force = [0.0; 3];
            for k in b.tractions.clone() {
                let (t, fv) = self.boundary_tractions[k as usize];
                let amp = self.model.tractions[t as usize].amplitude.value(0.0)[0];
                for c in 0..3 {
                    force[c] += amp * fv[c];
                }
            }
            for k in b.interfaces.clone() {
                let itf = &self.interface_nodes[self.boundary_interfaces[k as usize] as usize];
                for c in 0..3 {
                    force[c] -= itf.area * itf.stiffness * itf.jump[c];
                }
            }
            for c in 0..3 {
                self.v[i][c] -= 0.5 * h * force[c] * self.inv_mass[i];
            }
        }
        self.impulses(h, h, true);
        self.bookkeeping(true)?;
        Ok(())
    }

    /// Threads that run the step's loops: the team's size, or 1 when the mesh is below the size
    /// where parallel sections pay off (or one thread was asked for).
    pub fn threads(&self) -> usize {
        self.team.as_ref().map_or(1, Team::size)
    }

    /// One CD-Lagrange step tₙ → tₙ₊₁ (PHYSICS.md §4, stages 1–9).
    pub fn step(&mut self) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let h = self.h;
        // 1. Uₙ₊₁ = Uₙ + h V_{n+½}; αₙ₊₁ = αₙ + h α̇_{n+½} (stored as the predicted αₙ₊₁).
        self.advance_positions(h);
        // 2. Rigid surfaces and prescribed displacements to tₙ₊₁ (evaluated from their
        //    histories where used), interface kinematics [u]ₙ₊₁, gₙ₊₁.
        self.update_interface_kinematics();
        let t1 = Instant::now();
        // 3. F_int,ₙ₊₁ from Uₙ₊₁ (parallel element loop); F_ext is applied in stage 5.
        self.compute_internal_forces(true, true)?;
        let t2 = Instant::now();
        // (§6) Re-estimate h_crit as the stiffness changes; fixes h_{n+3/2}.
        let h_next = self.next_time_step();
        let t3 = Instant::now();
        let free_velocity_before = self.stats.stage_times.free_velocity;
        // 4–8. Free velocity with cohesion, prescribed components, contact, damage rate.
        self.impulses(0.5 * (h + h_next), h_next, false);
        let t4 = Instant::now();
        // 9. Energy bookkeeping and blow-up checks.
        self.bookkeeping(false)?;
        self.h = h_next;
        let t5 = Instant::now();
        let st = &mut self.stats.stage_times;
        st.positions += (t1 - t0).as_secs_f64();
        st.internal_forces += (t2 - t1).as_secs_f64();
        st.h_crit += (t3 - t2).as_secs_f64();
        // The free-velocity loop over every node is timed on its own.
        st.interface_contact += (t4 - t3).as_secs_f64() - (st.free_velocity - free_velocity_before);
        st.bookkeeping += (t5 - t4).as_secs_f64();
        self.stats.steps_wall += t5 - t0;
        Ok(())
    }

    /// Steps until `model.end_time`, calling `on_step` after each step; `on_step` returning
    /// `false` cancels the run.
    pub fn run(&mut self, mut on_step: impl FnMut(&Simulation) -> bool) -> Result<(), SolverError> {
        while !self.finished() {
            self.step()?;
            if !on_step(self) {
                return Err(SolverError::Cancelled {
                    step: self.step_count,
                    time: self.time,
                });
            }
        }
        Ok(())
    }

    /// True once tₙ has reached the end time (to within a millionth of a step).
    pub fn finished(&self) -> bool {
        self.time >= self.model.end_time - 1e-6 * self.h
    }

    /// Stage 1, and F_int ← 0 for stage 3.
    fn advance_positions(&mut self, h: f64) {
        let grain = NODE_GRAIN;
        // The same pass zeroes F_int for stage 3 (nothing reads it in between).
        // Flat component slices, so the loop vectorises.
        let body = |((u, v), f): (PositionChunk, &mut [[f64; 3]])| {
            for (ui, vi) in u.as_flattened_mut().iter_mut().zip(v.as_flattened()) {
                *ui += h * vi;
            }
            f.as_flattened_mut().fill(0.0);
        };
        if let Some(team) = &self.team {
            let (u, f) = (
                SharedSlice::new(&mut self.u),
                SharedSlice::new(&mut self.f_int),
            );
            let v = &self.v;
            let n = v.len();
            // SAFETY: chunk i of u and f is touched by item i only.
            team.map(n.div_ceil(grain), |i| unsafe {
                let (a, b) = (i * grain, ((i + 1) * grain).min(n));
                body(((u.range(a, b), &v[a..b]), f.range(a, b)))
            });
        } else {
            self.u
                .chunks_mut(grain)
                .zip(self.v.chunks(grain))
                .zip(self.f_int.chunks_mut(grain))
                .for_each(body);
        }
        for itf in self.interface_nodes.iter_mut() {
            itf.alpha = itf.alpha_next;
        }
        self.time += h;
        self.step_count += 1;
    }

    /// Stage 2/4 kinematics: [u] = x − y(t), g = n·(x − p(t)) at every interface node, and the
    /// gap of every contact node.
    ///
    /// A gap within the round-off of positions, |g| ≤ 16 ε (max|X| + |p(t)|), is set to 0:
    /// below that, "g ≤ 0" is not a property of the motion but of the last bit of a velocity
    /// that an impulse brought to zero (V + (−mV)/m can be one ulp off). Without it, a node
    /// held on a plane drifts by h·ulp(V), reads g = +3e-22 m, is declared open, and the next
    /// step takes it through the plane with the full free velocity (a spurious inelastic
    /// impact of h·V depth inside a persistent contact).
    fn update_interface_kinematics(&mut self) {
        let t = self.time;
        let planes = &self.model.planes;
        let sc = &mut self.scratch;
        sc.plane_disp.clear();
        sc.plane_disp
            .extend(planes.iter().map(|p| p.displacement(t)));
        sc.plane_tol.clear();
        sc.plane_tol
            .extend(planes.iter().zip(&sc.plane_disp).map(|(p, d)| {
                let scale = (0..3).fold(self.coordinate_scale, |a, c| {
                    a.max(p.point[c].abs()).max((p.point[c] + d[c]).abs())
                });
                16.0 * f64::EPSILON * scale
            }));
        let (disp, tol) = (&sc.plane_disp, &sc.plane_tol);
        let snap = |g: f64, tol: f64| if g.abs() <= tol { 0.0 } else { g };
        let nodes = &self.model.mesh.nodes;
        for itf in self.interface_nodes.iter_mut() {
            let k = self.model.interfaces[itf.interface as usize].plane;
            let (p, d) = (&planes[k], disp[k]);
            let i = itf.node as usize;
            let x: [f64; 3] = std::array::from_fn(|c| nodes[i][c] + self.u[i][c]);
            itf.jump = std::array::from_fn(|c| x[c] - (itf.bonded_point[c] + d[c]));
            itf.gap = snap(
                (0..3)
                    .map(|c| p.normal[c] * (x[c] - p.point[c] - d[c]))
                    .sum(),
                tol[k],
            );
        }
        for cn in self.contact_nodes.iter_mut() {
            let (p, d) = (&planes[cn.plane as usize], disp[cn.plane as usize]);
            let i = cn.node as usize;
            cn.gap = snap(
                (0..3)
                    .map(|c| p.normal[c] * (nodes[i][c] + self.u[i][c] - p.point[c] - d[c]))
                    .sum(),
                tol[cn.plane as usize],
            );
        }
    }

    /// Stage 3: F_int(Uₙ₊₁) and Ψₙ₊₁; an inverted element stops the run. `zeroed`: F_int is
    /// already 0 (stage 1 clears it), else it is cleared here.
    fn compute_internal_forces(&mut self, energy: bool, zeroed: bool) -> Result<(), SolverError> {
        if !zeroed {
            // (Else F_int was zeroed by stage 1.)
            self.f_int.fill([0.0; 3]);
        }
        let asm = assemble_internal_forces(
            &self.model.mesh,
            &self.classes,
            &self.blocks,
            &self.model.material,
            ElementRule::of(&self.model.scheme),
            &self.u,
            &mut self.f_int,
            energy,
            self.team.as_ref(),
            &mut self.parts_elements,
        );
        let (min_j, min_e) = (asm.min_j, asm.min_element);
        self.min_jacobian = min_j;
        if energy {
            self.ledger.strain = asm.strain;
            self.ledger.hourglass = asm.hourglass;
        }
        if !(min_j > 0.0) {
            if min_j.is_nan() {
                return Err(
                    self.unstable("non-finite displacements (NaN) in the element loop".into())
                );
            }
            return Err(SolverError::Inverted {
                element: min_e,
                j: min_j,
                step: self.step_count,
                time: self.time,
                h: self.h,
                h_crit: self.h_crit,
            });
        }
        Ok(())
    }

    /// Stages 4–8 (PHYSICS.md §4). `h_bar` = (h_{n+½} + h_{n+3/2})/2 scales forces into impulses,
    /// `h_next` = h_{n+3/2} is the interval the new velocities will act over.
    fn impulses(&mut self, h_bar: f64, h_next: f64, first: bool) {
        // Keep V_{n+½} of boundary nodes for the ledger's backward halves.
        for (k, b) in self.boundary.iter().enumerate() {
            self.scratch_v_old[k] = self.v[b.node as usize];
        }
        // 5. Free velocity on every node: V_free = V + h̄ M⁻¹(m g − F_int), with the ledger's
        //    halves b = ½V_old·P and a = ½V_free·P for the internal and gravity impulses.
        let g = self.model.gravity;
        let t5 = Instant::now();
        // SAFETY: the dispatch runs the build the CPU supports; the slices have one length.
        let body = |((v, f), (m, im)): NodeChunk| -> NodeSums {
            unsafe { free_velocity_chunk(v, f, m, im, h_bar, g) }
        };
        let grain = NODE_GRAIN;
        let parts = &mut self.parts_nodes;
        if let Some(team) = &self.team {
            let v = SharedSlice::new(&mut self.v);
            let (f, m, im) = (&self.f_int, &self.mass, &self.inv_mass);
            let n = f.len();
            // SAFETY: chunk i of v is touched by item i only.
            team.map_into(n.div_ceil(grain), parts, |i| unsafe {
                let (a, b) = (i * grain, ((i + 1) * grain).min(n));
                body(((v.range(a, b), &f[a..b]), (&m[a..b], &im[a..b])))
            })
        } else {
            parts.clear();
            parts.extend(
                self.v
                    .chunks_mut(grain)
                    .zip(self.f_int.chunks(grain))
                    .zip(self.mass.chunks(grain).zip(self.inv_mass.chunks(grain)))
                    .map(body),
            );
        };
        let mut s = parts.iter().fold(NodeSums::default(), |a, &b| a.add(b));
        self.stats.stage_times.free_velocity += t5.elapsed().as_secs_f64();

        // Boundary nodes: tractions, cohesion (4–5), prescribed components (6), contact (7),
        // their ledger halves, and the damage prediction (8).
        let t = self.time;
        let t_next = t + h_next;
        let planes = &self.model.planes;
        let h_prev = self.h;
        let sc = &mut self.scratch;
        sc.plane_v_old.clear();
        sc.plane_v_old.extend(planes.iter().map(|p| {
            if first || h_prev <= 0.0 {
                [0.0; 3]
            } else {
                let (a, b) = (p.displacement(t - h_prev), p.displacement(t));
                std::array::from_fn(|c| (b[c] - a[c]) / h_prev)
            }
        }));
        sc.plane_v_new.clear();
        sc.plane_v_new.extend(planes.iter().map(|p| {
            let (a, b) = (p.displacement(t), p.displacement(t_next));
            std::array::from_fn(|c| (b[c] - a[c]) / h_next)
        }));
        // 6. Prescribed velocity over the next interval, (Ū(tₙ₊₂) − Ū(tₙ₊₁))/h, and whether it
        //    jumps here (then the reaction is that jump's impulse, not a force to report).
        sc.bc_velocity.clear();
        sc.bc_jump.clear();
        for d in &self.model.displacements {
            let u = |t: f64| d.history.value(t)[0];
            let target = (u(t_next) - u(t)) / h_next;
            let jump = first || {
                let prev = (u(t) - u(t - h_prev)) / h_prev;
                (target - prev).abs() > 1e-9 * (target.abs() + prev.abs())
            };
            sc.bc_velocity.push(target);
            sc.bc_jump.push(jump);
        }
        sc.reactions.clear();
        sc.reactions.resize(self.model.displacements.len(), 0.0);
        sc.amplitudes.clear();
        sc.amplitudes.extend(
            self.model
                .tractions
                .iter()
                .map(|tr| tr.amplitude.value(t)[0]),
        );
        let cx = BoundaryStep {
            model: &self.model,
            boundary: &self.boundary,
            boundary_interfaces: &self.boundary_interfaces,
            boundary_contacts: &self.boundary_contacts,
            boundary_tractions: &self.boundary_tractions,
            v_old: &self.scratch_v_old,
            mass: &self.mass,
            inv_mass: &self.inv_mass,
            f_int: &self.f_int,
            plane_v_old: &sc.plane_v_old,
            plane_v_new: &sc.plane_v_new,
            bc_velocity: &sc.bc_velocity,
            amplitudes: &sc.amplitudes,
            h_bar,
            h_next,
            g,
        };
        let (v_all, itfs, cns) = (
            SharedSlice::new(&mut self.v),
            SharedSlice::new(&mut self.interface_nodes),
            SharedSlice::new(&mut self.contact_nodes),
        );
        let n_b = self.boundary.len();
        let n_bc = self.model.displacements.len();
        let chunks = n_b.div_ceil(BOUNDARY_GRAIN);
        self.parts_reactions.clear();
        self.parts_reactions.resize(chunks * n_bc, 0.0);
        let reaction_parts = SharedSlice::new(&mut self.parts_reactions);
        // SAFETY: each boundary node has its own node, interface and contact entries, and the
        // chunks are disjoint ranges of boundary nodes with their own rows of reactions.
        let run = |c: usize| unsafe {
            let range = c * BOUNDARY_GRAIN..((c + 1) * BOUNDARY_GRAIN).min(n_b);
            let reactions = reaction_parts.range(c * n_bc, (c + 1) * n_bc);
            boundary_chunk(&cx, range, v_all, itfs, cns, reactions)
        };
        let parts = &mut self.parts_boundary;
        match &self.team {
            Some(team) if chunks > 1 => team.map_into(chunks, parts, run),
            _ => {
                parts.clear();
                parts.extend((0..chunks).map(run));
            }
        }
        let bs = parts.iter().fold(BoundarySums::default(), |a, &b| a.add(b));
        for (k, r) in sc.reactions.iter_mut().enumerate() {
            *r = (0..chunks).fold(0.0, |acc, c| acc + self.parts_reactions[c * n_bc + k]);
        }
        s.int_a += bs.int_a;
        s.grav_a += bs.grav_a;
        s.kinetic += bs.kinetic;
        s.kinetic_half += bs.kinetic_half;
        let (trac_b, trac_a, reac_b, reac_a, plane_b, plane_a) = (
            bs.trac_b, bs.trac_a, bs.reac_b, bs.reac_a, bs.plane_b, bs.plane_a,
        );
        let (cn_b, cn_a, ct_b, ct_a) = (bs.cn_b, bs.cn_a, bs.ct_b, bs.ct_a);
        // Reactions and their peaks (excluding steps where the prescribed velocity jumps).
        let sc = &self.scratch;
        for (k, r) in sc.reactions.iter().enumerate() {
            self.stats.reactions[k] = *r;
            let peak = &mut self.stats.peaks[k];
            // The pull-off peak: once every interface has ruptured the body is free and the
            // reaction only measures its vibration.
            let before_rupture =
                self.interface_nodes.is_empty() || self.stats.time_full_rupture.is_none();
            if before_rupture && !sc.bc_jump[k] && r.abs() > peak.force.abs() {
                peak.force = *r;
                peak.time = t;
                peak.imposed_displacement = self.model.displacements[k].history.value(t)[0];
            }
        }
        let l = &mut self.ledger;
        if first {
            l.kinetic = s.kinetic;
            l.internal_work.start(s.int_a);
            l.gravity_work.start(s.grav_a);
            l.traction_work.start(trac_a);
            l.reaction_work.start(reac_a);
            l.plane_work.start(plane_a);
            l.contact_normal_work.start(cn_a);
            l.contact_tangential_work.start(ct_a);
        } else {
            l.kinetic = s.kinetic;
            l.internal_work.push(s.int_b, s.int_a);
            l.gravity_work.push(s.grav_b, s.grav_a);
            l.traction_work.push(trac_b, trac_a);
            l.reaction_work.push(reac_b, reac_a);
            l.plane_work.push(plane_b, plane_a);
            l.contact_normal_work.push(cn_b, cn_a);
            l.contact_tangential_work.push(ct_b, ct_a);
        }
        self.kinetic_half = s.kinetic_half;
    }
}

/// Read-only data of the boundary loop (stages 4–8) for one step.
struct BoundaryStep<'a> {
    model: &'a Model,
    boundary: &'a [BoundaryNode],
    boundary_interfaces: &'a [u32],
    boundary_contacts: &'a [u32],
    boundary_tractions: &'a [(u16, [f64; 3])],
    /// V_{n+½} of the boundary nodes (by boundary index).
    v_old: &'a [[f64; 3]],
    mass: &'a [f64],
    inv_mass: &'a [f64],
    f_int: &'a [[f64; 3]],
    plane_v_old: &'a [[f64; 3]],
    plane_v_new: &'a [[f64; 3]],
    bc_velocity: &'a [f64],
    amplitudes: &'a [f64],
    h_bar: f64,
    h_next: f64,
    g: [f64; 3],
}

/// Sums of the boundary loop over a chunk of boundary nodes, reduced in chunk order: the
/// ledger halves (before/after) of tractions, reactions, planes, contact (normal, tangential),
/// and the node loop's corrections.
#[derive(Default, Clone, Copy)]
struct BoundarySums {
    trac_b: f64,
    trac_a: f64,
    reac_b: f64,
    reac_a: f64,
    plane_b: f64,
    plane_a: f64,
    cn_b: f64,
    cn_a: f64,
    ct_b: f64,
    ct_a: f64,
    int_a: f64,
    grav_a: f64,
    kinetic: f64,
    kinetic_half: f64,
}

impl BoundarySums {
    fn add(mut self, o: BoundarySums) -> BoundarySums {
        self.trac_b += o.trac_b;
        self.trac_a += o.trac_a;
        self.reac_b += o.reac_b;
        self.reac_a += o.reac_a;
        self.plane_b += o.plane_b;
        self.plane_a += o.plane_a;
        self.cn_b += o.cn_b;
        self.cn_a += o.cn_a;
        self.ct_b += o.ct_b;
        self.ct_a += o.ct_a;
        self.int_a += o.int_a;
        self.grav_a += o.grav_a;
        self.kinetic += o.kinetic;
        self.kinetic_half += o.kinetic_half;
        self
    }
}

/// Stages 4–8 on boundary nodes `range` (indices into `cx.boundary`): tractions, cohesion
/// P_coh = −h̄ W g_N(αₙ₊₁)[u]ₙ₊₁ (4–5), prescribed components (6), contact (7), their ledger
/// halves, and the damage prediction αₙ₊₂ (8) (PHYSICS.md §4). `v` holds the free velocities
/// on entry and V_{n+3/2} on exit; `reactions` (one entry per prescribed condition, zeroed)
/// receives this chunk's reaction forces.
///
/// # Safety
/// Chunks run concurrently must cover disjoint boundary nodes (each boundary node has its own
/// node, interface and contact entries), and the slices must outlive the call.
unsafe fn boundary_chunk(
    cx: &BoundaryStep,
    range: std::ops::Range<usize>,
    v_all: SharedSlice<[f64; 3]>,
    itfs: SharedSlice<InterfaceNode>,
    cns: SharedSlice<ContactNode>,
    reactions: &mut [f64],
) -> BoundarySums {
    let (h_bar, h_next, g) = (cx.h_bar, cx.h_next, cx.g);
    let planes = &cx.model.planes;
    let (plane_v_old, plane_v_new) = (cx.plane_v_old, cx.plane_v_new);
    let mut out = BoundarySums::default();
    for k in range {
        let b = &cx.boundary[k];
        let i = b.node as usize;
        let (m, im) = (cx.mass[i], cx.inv_mass[i]);
        let vo = cx.v_old[k];
        let v_free0 = *v_all.get(i);
        let mut v = v_free0;
        // Tractions (dead load on the reference area).
        for e in b.tractions.clone() {
            let (tk, fv) = cx.boundary_tractions[e as usize];
            let p: [f64; 3] = fv.map(|c| h_bar * cx.amplitudes[tk as usize] * c);
            // v is updated after all smooth impulses; the forward half uses the final v.
            out.trac_b += 0.5 * dot(vo, p);
            for c in 0..3 {
                v[c] += p[c] * im;
            }
        }
        // Cohesion: P_coh = −h̄ W g_N(αₙ₊₁)[u]ₙ₊₁ (stage 4–5).
        let mut coh: [[f64; 3]; 4] = [[0.0; 3]; 4];
        for (slot, e) in b.interfaces.clone().enumerate() {
            let itf = itfs.get(cx.boundary_interfaces[e as usize] as usize);
            let law = &cx.model.interfaces[itf.interface as usize].law;
            itf.stiffness = law.g_n(itf.alpha);
            itf.cohesive_traction = itf.jump.map(|c| itf.stiffness * c);
            let p = itf.cohesive_traction.map(|c| -h_bar * itf.area * c);
            if slot < 4 {
                coh[slot] = p;
            }
            for c in 0..3 {
                v[c] += p[c] * im;
            }
        }
        let v_free = v;
        // 6. Prescribed components: V_{n+3/2} = (Ū(tₙ₊₂) − Ū(tₙ₊₁))/h.
        let mut any_prescribed = false;
        for c in 0..3 {
            let bc = b.prescribed[c];
            if bc != NONE {
                any_prescribed = true;
                v[c] = cx.bc_velocity[bc as usize];
                let p = m * (v[c] - v_free[c]);
                reactions[bc as usize] += p / h_bar;
                out.reac_b += 0.5 * vo[c] * p;
            }
        }
        // 7. Contact, node by node in closed form (only on fully free nodes).
        let mut contact_p: [[f64; 3]; 4] = [[0.0; 3]; 4];
        let mut contact_plane: [usize; 4] = [usize::MAX; 4];
        let mut nc = 0;
        if !any_prescribed {
            for e in b.interfaces.clone() {
                let itf = itfs.get(cx.boundary_interfaces[e as usize] as usize);
                let spec = &cx.model.interfaces[itf.interface as usize];
                let plane = &planes[spec.plane];
                let mu = spec.law.mu(itf.alpha, spec.mu_inf);
                let (impulse, status) = contact_impulse(
                    &mut v,
                    itf.gap,
                    plane.normal,
                    plane_v_new[spec.plane],
                    mu,
                    m,
                );
                itf.contact_impulse = impulse.map(|c| c / itf.area.max(f64::MIN_POSITIVE));
                itf.contact = status;
                if nc < 4 {
                    contact_p[nc] = impulse;
                    contact_plane[nc] = spec.plane;
                    nc += 1;
                }
            }
            for e in b.contacts.clone() {
                let cn = cns.get(cx.boundary_contacts[e as usize] as usize);
                let plane = &planes[cn.plane as usize];
                let (impulse, status) = contact_impulse(
                    &mut v,
                    cn.gap,
                    plane.normal,
                    plane_v_new[cn.plane as usize],
                    cn.mu,
                    m,
                );
                cn.contact_impulse = impulse.map(|c| c / cn.area.max(f64::MIN_POSITIVE));
                cn.contact = status;
                if nc < 4 {
                    contact_p[nc] = impulse;
                    contact_plane[nc] = cn.plane as usize;
                    nc += 1;
                }
            }
        }
        *v_all.get(i) = v;
        // Ledger: forward halves with the final velocity, corrections of the node loop.
        let dv = [v[0] - v_free0[0], v[1] - v_free0[1], v[2] - v_free0[2]];
        let pint = [
            -h_bar * cx.f_int[i][0],
            -h_bar * cx.f_int[i][1],
            -h_bar * cx.f_int[i][2],
        ];
        let pg = [h_bar * m * g[0], h_bar * m * g[1], h_bar * m * g[2]];
        out.int_a += 0.5 * dot(dv, pint);
        out.grav_a += 0.5 * dot(dv, pg);
        out.kinetic += 0.5 * m * dot(vo, dv);
        out.kinetic_half += 0.5 * m * (dot(v, v) - dot(v_free0, v_free0));
        for e in b.tractions.clone() {
            let (tk, fv) = cx.boundary_tractions[e as usize];
            let p: [f64; 3] = fv.map(|c| h_bar * cx.amplitudes[tk as usize] * c);
            out.trac_a += 0.5 * dot(v, p);
        }
        for c in 0..3 {
            if b.prescribed[c] != NONE {
                out.reac_a += 0.5 * v[c] * m * (v[c] - v_free[c]);
            }
        }
        // Glue of moving planes: the plane's share ½ v_plane·P_coh of the cohesive work.
        for (slot, e) in b.interfaces.clone().enumerate().take(4) {
            let itf = &*itfs.get(cx.boundary_interfaces[e as usize] as usize);
            let k = cx.model.interfaces[itf.interface as usize].plane;
            out.plane_b += 0.5 * dot(plane_v_old[k], coh[slot]);
            out.plane_a += 0.5 * dot(plane_v_new[k], coh[slot]);
        }
        // Contact: split the work on the relative velocity (dissipation, normal and
        // tangential) and on the plane's velocity (external work).
        for j in 0..nc {
            let k = contact_plane[j];
            let n = planes[k].normal;
            let p = contact_p[j];
            let pn = dot(p, n);
            let pt = [p[0] - pn * n[0], p[1] - pn * n[1], p[2] - pn * n[2]];
            let rel_o = [
                vo[0] - plane_v_old[k][0],
                vo[1] - plane_v_old[k][1],
                vo[2] - plane_v_old[k][2],
            ];
            let rel_n = [
                v[0] - plane_v_new[k][0],
                v[1] - plane_v_new[k][1],
                v[2] - plane_v_new[k][2],
            ];
            out.cn_b += 0.5 * dot(rel_o, n) * pn;
            out.cn_a += 0.5 * dot(rel_n, n) * pn;
            out.ct_b += 0.5 * dot(rel_o, pt);
            out.ct_a += 0.5 * dot(rel_n, pt);
            out.plane_b += 0.5 * dot(plane_v_old[k], p);
            out.plane_a += 0.5 * dot(plane_v_new[k], p);
        }
        // 8. Damage rate after the dynamics: αₙ₊₂ = min(u_r, max(αₙ₊₁, fₙ₊₂)),
        //    fₙ₊₂ = |[u]ₙ₊₁ + h (V_{n+3/2} − v_plane)| (normal part counted when positive).
        for e in b.interfaces.clone() {
            let itf = itfs.get(cx.boundary_interfaces[e as usize] as usize);
            let spec = &cx.model.interfaces[itf.interface as usize];
            let vp = plane_v_new[spec.plane];
            let next: [f64; 3] = std::array::from_fn(|c| itf.jump[c] + h_next * (v[c] - vp[c]));
            let f = damage_measure(next, planes[spec.plane].normal);
            itf.alpha_next = spec.law.u_r.min(itf.alpha.max(f));
        }
    }
    out
}

/// Stage 7 for one node against one plane (PHYSICS.md §4, paper eqs. 19–20, 22): if gₙ₊₁ ≤ 0
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

/// Damage driving measure f = |[u]| with only the positive part of the normal jump counted:
/// a negative normal jump can only come from the velocity-level contact's position drift
/// (PHYSICS.md §3), and must not damage the glue.
#[inline]
pub fn damage_measure(jump: [f64; 3], n: [f64; 3]) -> f64 {
    let un = dot(jump, n);
    let t2 = dot(jump, jump) - un * un;
    (un.max(0.0).powi(2) + t2.max(0.0)).sqrt()
}

impl Simulation {
    /// Stage 9: interface energies, damage dissipation, ledger closing, statistics, and the
    /// blow-up checks (non-finite values, negative damage dissipation, energy growing without
    /// a source).
    fn bookkeeping(&mut self, first: bool) -> Result<(), SolverError> {
        let mut stored = 0.0;
        let mut dissipated = 0.0;
        let mut worst = 0.0f64;
        let mut counts = StateCounts::default();
        for itf in self.interface_nodes.iter_mut() {
            let law = &self.model.interfaces[itf.interface as usize].law;
            stored += 0.5 * itf.area * itf.stiffness * dot(itf.jump, itf.jump);
            // ΔDₙ = W ½ (g_N(αₙ₋₁) − g_N(αₙ)) [u]ₙ₋₁·[u]ₙ (PHYSICS.md §5).
            let dd = 0.5
                * itf.area
                * (itf.prev_stiffness - itf.stiffness)
                * dot(itf.prev_jump, itf.jump);
            worst = worst.min(dd);
            dissipated += dd;
            itf.prev_stiffness = itf.stiffness;
            itf.prev_jump = itf.jump;
            match law.state(itf.alpha) {
                InterfaceState::Elastic => counts.elastic += 1,
                InterfaceState::Transition => counts.transition += 1,
                InterfaceState::Ruptured => counts.ruptured += 1,
            }
        }
        let l = &mut self.ledger;
        l.interface_stored = stored;
        l.damage_dissipated += dissipated;
        if first {
            l.initial_kinetic = l.kinetic;
            l.initial_strain = l.strain;
            l.initial_hourglass = l.hourglass;
            l.initial_interface_stored = l.interface_stored;
            self.energy_budget =
                (self.kinetic_half + l.strain + l.hourglass + l.interface_stored).abs();
        }
        l.close_step();
        // The budget is compared with ½V_{n+½}ᵀMV_{n+½}, so it takes the works up to the forward
        // halves of this step's impulses: with the work up to tₙ only, a load ramped from zero
        // (no work yet at t₁, a velocity already) reads as energy created at step 1.
        let ext = l.external_work_settled();
        self.energy_budget += (ext - self.last_external_work).abs();
        self.last_external_work = ext;

        if counts.elastic < self.interface_nodes.len() && self.stats.time_first_damage.is_none() {
            self.stats.time_first_damage = Some(self.time);
        }
        if counts.ruptured == self.interface_nodes.len()
            && !self.interface_nodes.is_empty()
            && self.stats.time_full_rupture.is_none()
        {
            self.stats.time_full_rupture = Some(self.time);
        }

        let l = &self.ledger;
        let mech = self.kinetic_half + l.strain + l.hourglass + l.interface_stored;
        if !(mech.is_finite() && l.residual().is_finite()) {
            return Err(
                self.unstable("non-finite energy (NaN or infinity in velocities or forces)".into())
            );
        }
        if worst < -1e-9 * l.max_energy_seen.max(self.energy_floor) {
            return Err(self.unstable(format!(
                "negative damage dissipation increment ({worst:.3e} J): the jump turned by more than 90° in one step"
            )));
        }
        // Contact dissipation is not ≥ 0 step by step with the trapezoid pairing (PHYSICS.md §5),
        // but it must be cumulatively, to the ledger's own accuracy: 1e-3 of the largest energy.
        let contact = l.contact_normal_dissipated + l.friction_dissipated;
        if contact < -1e-3 * l.max_energy_seen.max(self.energy_floor) {
            return Err(self.unstable(format!(
                "the cumulative contact dissipation is negative ({contact:.3e} J, beyond 1e-3 of the largest energy {:.3e} J): contact is creating energy",
                l.max_energy_seen
            )));
        }
        let limit = self.model.scheme.energy_growth_limit * self.energy_budget + self.energy_floor;
        if mech > limit {
            return Err(self.unstable(format!(
                "the mechanical energy ({mech:.4e} J) grew past {}× the energy supplied ({:.4e} J) with no source",
                self.model.scheme.energy_growth_limit, self.energy_budget
            )));
        }
        Ok(())
    }

    /// The blow-up diagnostic: where, with which h and h_crit, and what to change.
    fn unstable(&self, reason: String) -> SolverError {
        let factor = self.h / self.h_crit;
        let configured = self.model.scheme.time_step_factor;
        let advice = if configured >= 1.0 {
            format!("scheme.time_step_factor = {configured} is at or above the stability limit 1: set it ≤ 0.9 (default 0.5).")
        } else if factor > 0.95 {
            format!("The time step factor {factor:.3} is at or above the stability limit 1: set scheme.time_step_factor ≤ 0.9 (default 0.5).")
        } else {
            "The step is below the estimated limit: stiffening under large strain may have lowered h_crit (lower scheme.h_crit_update_interval or scheme.time_step_factor), or the loading is too violent for the mesh (refine it or slow the load).".to_string()
        };
        SolverError::Unstable {
            step: self.step_count,
            time: self.time,
            h: self.h,
            h_crit: self.h_crit,
            factor,
            reason,
            advice,
        }
    }

    /// Re-estimates h_crit every `h_crit_update_interval` steps and returns h_{n+3/2}.
    /// The step only ever decreases: when stiffening makes the current step exceed
    /// factor × h_crit by more than 5 %, h becomes 0.95 × factor × h_crit (the margins avoid a
    /// change for estimate noise and at every estimate). A change of step breaks the exact trapezoid pairing of the ledger for that one
    /// step (the work pairs velocities of two different intervals); growing h after a softening
    /// would buy little speed for that cost, so it is not done.
    ///
    /// Between those, under strong compression (smallest Jacobian below [`JACOBIAN_COMPRESSED`])
    /// a change of the smallest Jacobian by [`JACOBIAN_RETRIGGER`] since the last estimate
    /// re-estimates at once: a violent impact stiffens a neo-Hookean body within a few steps,
    /// long before the next scheduled estimate, and the stiffest mode moves with the compression
    /// wave. Moderate strains (the pull-off's J stays above 0.9) keep the schedule alone: each
    /// estimate costs ~100 force evaluations.
    fn next_time_step(&mut self) -> f64 {
        let every = self.model.scheme.h_crit_update_interval as u64;
        if every == 0 {
            return self.h;
        }
        let strained = self.min_jacobian < JACOBIAN_COMPRESSED
            && (self.min_jacobian - self.jacobian_at_estimate).abs() > JACOBIAN_RETRIGGER;
        if !(self.step_count.is_multiple_of(every) || strained) {
            return self.h;
        }
        let warm = std::mem::take(&mut self.ritz_vector);
        let est = self.estimate_stable_step(Some(warm));
        self.jacobian_at_estimate = self.min_jacobian;
        self.stats.h_crit_estimates += 1;
        self.h_crit = est.h_crit;
        self.stats.h_crit_min = self.stats.h_crit_min.min(est.h_crit);
        let target = self.model.scheme.time_step_factor * est.h_crit;
        if self.h > 1.05 * target {
            0.95 * target
        } else {
            self.h
        }
    }

    /// Prescribed degrees of freedom (node·3 + component), true where prescribed.
    fn prescribed_mask(&self) -> Vec<bool> {
        let mut mask = vec![false; 3 * self.u.len()];
        for b in &self.boundary {
            for c in 0..3 {
                if b.prescribed[c] != NONE {
                    mask[3 * b.node as usize + c] = true;
                }
            }
        }
        mask
    }

    /// ω_max² of M⁻¹K at the current state by Lanczos on M^{-½}KM^{-½} (PHYSICS.md §6), K·x
    /// matrix-free as the directional derivative of F_int (forward difference, relative step
    /// 1e-6 of the smallest edge) plus the interface springs W g_N(α) of glued nodes;
    /// prescribed components are removed. Lanczos Ritz values approach λ_max from below, so
    /// the estimate is θ + ‖r‖ with ‖r‖ = β_j|s_j| the Ritz residual: an eigenvalue lies within
    /// ‖r‖ of θ, which bounds λ_max once θ has converged to the top of the spectrum.
    pub fn estimate_stable_step(&mut self, warm: Option<Vec<f64>>) -> StableStep {
        self.stable_step_estimate(warm, true)
    }

    /// [`Simulation::estimate_stable_step`], with the interface springs in K or without them
    /// (`springs = false`: the bulk alone).
    fn stable_step_estimate(&mut self, warm: Option<Vec<f64>>, springs: bool) -> StableStep {
        let n = 3 * self.u.len();
        let mask = self.prescribed_mask();
        let sqrt_inv_m: Vec<f64> = (0..n).map(|k| self.inv_mass[k / 3].sqrt()).collect();
        let mut f0 = vec![[0.0; 3]; self.u.len()];
        let mut parts = Vec::new();
        assemble_internal_forces(
            &self.model.mesh,
            &self.classes,
            &self.blocks,
            &self.model.material,
            ElementRule::of(&self.model.scheme),
            &self.u,
            &mut f0,
            false,
            self.team.as_ref(),
            &mut parts,
        );
        let springs: Vec<(usize, f64)> = self
            .interface_nodes
            .iter()
            .filter(|_| springs)
            .map(|itf| {
                let law = &self.model.interfaces[itf.interface as usize].law;
                (itf.node as usize, itf.area * law.g_n(itf.alpha))
            })
            .collect();
        let eps_len = 1e-6 * self.model.mesh.min_edge();
        let mut up = self.u.clone();
        let mut fp = vec![[0.0; 3]; self.u.len()];
        // y = M^{-½} K M^{-½} q.
        let mut apply = |q: &[f64], y: &mut [f64]| {
            let mut xmax = 0.0f64;
            for k in 0..n {
                if !mask[k] {
                    xmax = xmax.max((q[k] * sqrt_inv_m[k]).abs());
                }
            }
            if xmax == 0.0 {
                y.fill(0.0);
                return;
            }
            let eps = eps_len / xmax;
            for i in 0..self.u.len() {
                for c in 0..3 {
                    let k = 3 * i + c;
                    let x = if mask[k] { 0.0 } else { q[k] * sqrt_inv_m[k] };
                    up[i][c] = self.u[i][c] + eps * x;
                }
            }
            fp.fill([0.0; 3]);
            assemble_internal_forces(
                &self.model.mesh,
                &self.classes,
                &self.blocks,
                &self.model.material,
                ElementRule::of(&self.model.scheme),
                &up,
                &mut fp,
                false,
                self.team.as_ref(),
                &mut parts,
            );
            for i in 0..self.u.len() {
                for c in 0..3 {
                    let k = 3 * i + c;
                    y[k] = if mask[k] {
                        0.0
                    } else {
                        (fp[i][c] - f0[i][c]) / eps
                    };
                }
            }
            for &(i, ks) in &springs {
                for c in 0..3 {
                    let k = 3 * i + c;
                    if !mask[k] {
                        y[k] += ks * q[k] * sqrt_inv_m[k];
                    }
                }
            }
            for k in 0..n {
                y[k] *= sqrt_inv_m[k];
            }
        };
        // Start vector: the previous Ritz vector (warm start) plus a deterministic pseudo-random
        // vector so that every mode is represented.
        let mut start: Vec<f64> = (0..n)
            .map(|k| if mask[k] { 0.0 } else { splitmix(k as u64) })
            .collect();
        if let Some(w) = warm.filter(|w| w.len() == n) {
            let nw = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            let ns = start.iter().map(|x| x * x).sum::<f64>().sqrt();
            if nw > 0.0 {
                for k in 0..n {
                    start[k] = w[k] / nw + 1e-3 * start[k] / ns;
                }
            }
        }
        let tol = self.model.scheme.h_crit_tolerance;
        let max_iter = 300.min(n);
        let (alphas, betas, theta, resid, s) = lanczos(&mut apply, &start, max_iter, tol, None);
        // Second pass: regenerate the same Lanczos vectors to form the Ritz vector y = Σ sⱼqⱼ.
        let mut ritz = vec![0.0; n];
        if n > 0 {
            lanczos(&mut apply, &start, alphas.len(), 0.0, Some((&s, &mut ritz)));
        }
        drop(betas);
        self.ritz_vector = ritz;
        let omega_sq = theta + resid;
        StableStep {
            omega_max_sq: omega_sq,
            ritz_value: theta,
            h_crit: 2.0 / omega_sq.sqrt(),
            iterations: alphas.len(),
        }
    }

    /// Number of distinct element shapes (each has its own precomputed Gauss data).
    pub fn element_class_count(&self) -> usize {
        self.classes.data.len()
    }

    /// Interface state counts now.
    pub fn state_counts(&self) -> StateCounts {
        let mut c = StateCounts::default();
        for itf in &self.interface_nodes {
            match self.model.interfaces[itf.interface as usize]
                .law
                .state(itf.alpha)
            {
                InterfaceState::Elastic => c.elastic += 1,
                InterfaceState::Transition => c.transition += 1,
                InterfaceState::Ruptured => c.ruptured += 1,
            }
        }
        c
    }

    /// The ledger's values now.
    pub fn energies(&self) -> EnergySnapshot {
        self.ledger.snapshot()
    }

    /// Plain-words warnings about the regime of this model, for the user before the run: the
    /// parameters are admissible, but the results or the cost need reading with care.
    ///
    /// - Near incompressibility (ν ≥ 0.49): K/G = 2(1+ν)/(3(1−2ν)) and c_p/c_s =
    ///   √(2(1−ν)/(1−2ν)); with full integration the hex8 locks volumetrically.
    /// - Interfaces that set the stable step: h_crit with the glue springs W g_N(α) in K
    ///   (PHYSICS.md §6) at least 1.5× below [`Simulation::h_crit_bulk`], the bulk's alone; the
    ///   run is then that many times longer.
    /// - A brittle law, (u_r − α_e)/α_e < 1 %: the softening branch is crossed within a step.
    /// - Elongated elements (aspect ratio ≥ 10): the shortest edge sets the step.
    /// - A time-step factor above 1: unstable by design (PHYSICS.md §6).
    pub fn advisories(&self) -> Vec<String> {
        let m = &self.model;
        let mat = &m.material;
        let mut out = Vec::new();
        let nu = mat.poisson;
        if nu >= 0.49 {
            let k_over_g = 2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu));
            let cp_over_cs = (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)).sqrt();
            // The hourglass stiffness κ(λ+2μ) grows with λ: scaled to the default's share of the
            // shear modulus, κ = 0.05·2μ/(λ+2μ).
            let kappa_shear = 0.05 * 2.0 * mat.mu / (mat.lambda + 2.0 * mat.mu);
            let kappa = m.scheme.hourglass_coefficient;
            let quadrature = match m.scheme.integration {
                crate::model::Integration::Full => format!(
                    "with full 2×2×2 integration the hex8 locks volumetrically: it is far too stiff in bending and in any deformation that keeps the volume; use scheme.integration = \"reduced\" with scheme.hourglass_coefficient = {kappa_shear:.1e} (the hourglass stiffness κ(λ+2μ) grows with λ and locks as well at the default κ = 0.05)"
                ),
                crate::model::Integration::Reduced if kappa > 2.0 * kappa_shear => format!(
                    "one-point integration does not lock volumetrically, but its hourglass stiffness κ(λ+2μ) grows with λ: at κ = {kappa} it stiffens bending as locking would; scheme.hourglass_coefficient = {kappa_shear:.1e} scales it to the shear modulus"
                ),
                crate::model::Integration::Reduced => format!(
                    "one-point integration with κ = {kappa} does not lock"
                ),
            };
            out.push(format!(
                "material.poisson = {nu} is nearly incompressible (K/G = {k_over_g:.0}): {quadrature}. The stable step follows the pressure wave, c_p = {cp_over_cs:.1} c_s, so shear motion costs {cp_over_cs:.1}× more steps than at ν = 0."
            ));
        }
        let le = m.mesh.min_edge();
        if let Some(h_bulk) = self
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
                self.h_crit
            ));
        }
        let factor = m.scheme.time_step_factor;
        if factor > 1.0 {
            out.push(format!(
                "scheme.time_step_factor = {factor} > 1: the central-difference scheme is unstable above h_crit (PHYSICS.md §6); the run will stop when its energy grows, with a diagnostic."
            ));
        }
        out
    }
}

/// A deterministic pseudo-random number in [−1, 1) (splitmix64 of the index).
fn splitmix(k: u64) -> f64 {
    let mut z = k.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

type LanczosOut = (Vec<f64>, Vec<f64>, f64, f64, Vec<f64>);

/// Lanczos tridiagonalisation of a symmetric operator from `start`, without
/// reorthogonalisation (extreme Ritz values still converge). Stops when the largest Ritz value
/// changes by less than `tol` (relative) over 5 iterations, or after `max_iter`. Returns
/// (α, β, θ_max, Ritz residual β_j|s_j|, eigenvector s of T). With `accumulate = (s, y)`,
/// runs exactly `max_iter` iterations and accumulates y = Σ sⱼ qⱼ instead.
fn lanczos(
    apply: &mut dyn FnMut(&[f64], &mut [f64]),
    start: &[f64],
    max_iter: usize,
    tol: f64,
    mut accumulate: Option<(&[f64], &mut [f64])>,
) -> LanczosOut {
    let n = start.len();
    let nrm = start.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut q: Vec<f64> = start
        .iter()
        .map(|x| x / nrm.max(f64::MIN_POSITIVE))
        .collect();
    let mut q_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut beta_prev = 0.0;
    let mut last_theta = f64::NAN;
    let mut result = (0.0, 0.0, vec![1.0]);
    for j in 0..max_iter {
        if let Some((s, y)) = accumulate.as_mut() {
            for k in 0..n {
                y[k] += s[j] * q[k];
            }
        }
        apply(&q, &mut w);
        let a: f64 = w.iter().zip(&q).map(|(x, y)| x * y).sum();
        for k in 0..n {
            w[k] -= a * q[k] + beta_prev * q_prev[k];
        }
        let b = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        alphas.push(a);
        betas.push(b);
        let done = j + 1 == max_iter || b <= 1e-14 * a.abs();
        if accumulate.is_none() && ((j + 1) % 5 == 0 || done) {
            let m = alphas.len();
            let t = nalgebra::DMatrix::from_fn(m, m, |r, c| {
                if r == c {
                    alphas[r]
                } else if r + 1 == c {
                    betas[r]
                } else if c + 1 == r {
                    betas[c]
                } else {
                    0.0
                }
            });
            let eig = nalgebra::SymmetricEigen::new(t);
            let (imax, theta) =
                eig.eigenvalues
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::NEG_INFINITY),
                        |acc, (i, &v)| if v > acc.1 { (i, v) } else { acc },
                    );
            let s: Vec<f64> = eig.eigenvectors.column(imax).iter().copied().collect();
            let resid = (b * s[m - 1]).abs();
            result = (theta, resid, s);
            if (theta - last_theta).abs() <= tol * theta.abs() || done {
                break;
            }
            last_theta = theta;
        }
        if b <= 1e-14 * a.abs() {
            break;
        }
        for k in 0..n {
            q_prev[k] = q[k];
            q[k] = w[k] / b;
        }
        beta_prev = b;
    }
    (alphas, betas, result.0, result.1, result.2)
}
