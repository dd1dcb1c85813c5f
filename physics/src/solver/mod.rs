//! The CD-Lagrange time step (model §4) with the RCCM interface, contact, friction,
//! prescribed displacements, the energy ledger (model §5) and the stable-step estimate (§6).
//!
//! State at integer times tₙ: displacements U, damage α; at half times: velocities V. One call of
//! [`Simulation::step`] goes from tₙ to tₙ₊₁ through the numbered stages of model §4, each a
//! named function:
//!
//! | stage | function | file |
//! |---|---|---|
//! | 1 positions and state | [`Simulation::advance_positions`] | `stages.rs` |
//! | 2 surfaces, gaps, prescribed values | [`Simulation::surfaces_and_gaps`], [`Simulation::prescribed_motion`] | `stages.rs` |
//! | 3 internal forces | [`Simulation::internal_forces`] | `stages.rs` |
//! | model §6: next step | [`Simulation::next_time_step`] | `stable_step.rs`, `lanczos.rs`, `stiffness.rs` |
//! | 5 free velocity, all nodes | [`Simulation::free_velocity`] | `stages.rs` |
//! | 4–8 at boundary nodes | [`Simulation::boundary_pass`]: per node, tractions, cohesion (4), free velocity (5), prescribed components (6), contact (7), the ledger's halves, damage (8) | `boundary.rs` |
//! | 9 ledger | [`Simulation::ledger`] | `ledger.rs` |
//!
//! Nothing is solved globally: every stage is a loop of local computations, the element loop in
//! parallel ([`Team`]: persistent threads, static shares) and deterministic whatever the thread
//! count (node-disjoint element blocks, fixed-size chunks, fixed-order reductions). Stages 4–8
//! are one fused pass over the boundary nodes (a node's stages need only that node), which calls
//! the stage functions in order.

mod bound;
mod boundary;
mod bulk_viscosity;
mod checkpoint;
mod diagnostics;
mod lanczos;
mod ledger;
mod mass_scaling;
mod setup;
mod stable_step;
mod stages;
mod state;
mod stiffness;

pub use state::{
    ContactNode, CornerChecks, DamageClamped, InterfaceNode, PeakReaction, RunStats, SolverError,
    StableStep, StageTimes, StateCounts,
};

use crate::energy::{EnergySnapshot, Ledger};
use crate::kernels::{
    assemble_internal_forces, Assembly, ElementRule, ElementSums, NodeSums, Planes,
};
use crate::law::InterfaceState;
use crate::mesh::ElementClasses;
use crate::model::{Model, StartOffset};
use crate::team::Team;
use boundary::{Boundary, BoundarySums};
pub use checkpoint::{
    model_fingerprint, read_header, write_atomically, CheckpointError, CheckpointHeader,
    CHECKPOINT_FORMAT,
};
pub use mass_scaling::MassScalingReport;
use stable_step::StepControl;
use stages::StepScratch;
use std::sync::Arc;
// std's `Instant` on native; the browser's clock on wasm32, where std's panics.
use web_time::Instant;

/// Smallest element block ([`crate::mesh::Mesh::element_blocks`]), and nodes per chunk in node
/// loops. Fixed, so the reduction order never depends on the thread count.
const ELEMENT_GRAIN: usize = 256;
const NODE_GRAIN: usize = 4096;
/// Boundary nodes per chunk of the boundary loop (stages 4–8).
const BOUNDARY_GRAIN: usize = 256;
/// Below this many elements the loops run on the calling thread (a parallel section would
/// cost more than it saves).
pub const PARALLEL_MIN_ELEMENTS: usize = 2048;

/// A simulation in progress. Build it with [`Simulation::new`], advance it with
/// [`Simulation::step`] or [`Simulation::run`].
pub struct Simulation {
    pub model: Arc<Model>,
    classes: ElementClasses,
    /// Colours → node-disjoint blocks → elements ([`crate::mesh::Mesh::element_blocks`]).
    blocks: Vec<Vec<Vec<u32>>>,
    /// The threads of the parallel loops (None: everything on the calling thread).
    team: Option<Team>,
    /// The element loops prefetch each lane group's nodes: the nodal fields exceed the
    /// last-level cache ([`crate::kernels::prefetch_pays`]).
    prefetch: bool,
    /// Per-block / per-chunk results of the parallel loops, reused from step to step.
    parts_elements: Vec<ElementSums>,
    parts_nodes: Vec<NodeSums>,
    parts_boundary: Vec<BoundarySums>,
    /// Reaction impulse of each prescribed condition from each boundary chunk.
    parts_reactions: Vec<f64>,
    /// Lumped nodal masses [kg] and their inverses.
    pub mass: Vec<f64>,
    inv_mass: Vec<f64>,
    /// Mass scaling (model §6.8): the density factor of each element class (empty without),
    /// the mass added at each node that has some, and what the scaling did.
    class_density: Vec<f64>,
    added_mass: Vec<(u32, f64)>,
    pub mass_scaling: Option<MassScalingReport>,
    /// Bulk viscosity's constants, forces and step values (model §4.12); None without.
    bulk_viscosity: Option<bulk_viscosity::BulkViscosityState>,
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
    /// What acts on each boundary node (glue, contact, tractions, prescribed components).
    boundary: Boundary,
    /// Per-step values and sums, in buffers reused from step to step.
    scratch: StepScratch,
    /// Current time tₙ [s] and step count n.
    pub time: f64,
    pub step_count: u64,
    /// h_{n+½} = tₙ₊₁ − tₙ, the interval about to be taken [s].
    pub h: f64,
    pub h_crit: f64,
    pub ledger: Ledger,
    pub stats: RunStats,
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
    ritz_vector: Vec<f64>,
    /// h_crit of the bulk alone (interface springs left out) at t = 0 [s], measured when a glued
    /// node's spring comes near the system's ω_max, i.e. when an interface may set the step.
    pub h_crit_bulk: Option<f64>,
    /// [`Simulation::stress_jacobian`] when h_crit was last estimated.
    jacobian_at_estimate: f64,
    /// The variable step's state: the previous interval, the growth goal, the glue's stiffness.
    step_control: StepControl,
    /// ½ V_{n+½}ᵀ M V_{n+½}, for the energy-growth check.
    pub kinetic_half: f64,
    /// Initial energy plus Σ|ΔW_ext|: what may have entered the system [J].
    energy_budget: f64,
    last_external_work: f64,
    /// Energy below which growth is round-off, E·V·1e-14 [J].
    energy_floor: f64,
    /// Largest |reference coordinate| of the mesh [m]: the scale of position round-off.
    coordinate_scale: f64,
    /// The interfaces whose glued nodes start off or inside their mould (for the warnings and
    /// the summary; empty when every glued node starts on its mould).
    pub start_offsets: Vec<StartOffset>,
    /// The model's fingerprint for checkpoints ([`checkpoint::model_fingerprint`]), computed at
    /// the first checkpoint written or read.
    fingerprint: std::sync::OnceLock<u32>,
}

impl Simulation {
    /// One CD-Lagrange step tₙ → tₙ₊₁ (model §4.1–§4.9), written with the index of
    /// the step just completed as n − 1: on entry Uₙ, αₙ, V_{n+½}; on exit Uₙ₊₁, αₙ₊₁, V_{n+3/2}.
    pub fn step(&mut self) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let h = self.h;
        // 1. Uₙ₊₁ = Uₙ + h V_{n+½}; αₙ₊₁ = αₙ + h α̇_{n+½}.
        self.advance_positions(h);
        // 2. Rigid surfaces to tₙ₊₁: jumps [u]ₙ₊₁ and gaps gₙ₊₁.
        self.surfaces_and_gaps();
        let t1 = Instant::now();
        // 3. F_int,ₙ₊₁ from Uₙ₊₁ (parallel element loop); an inverted element stops the run.
        self.internal_forces(true, true)?;
        let t2 = Instant::now();
        // §6 (model §6.5, §6.6). Re-estimate h_crit as the stiffness changes; fixes h_{n+3/2}.
        let h_next = self.next_time_step();
        let h_next = self.damped_step(h_next);
        let t3 = Instant::now();
        // 2. Surface and prescribed velocities over the interval about to be taken.
        self.prescribed_motion(h_next, false);
        let h_bar = 0.5 * (h + h_next);
        // 5. Free velocity on every node (internal forces and gravity).
        self.free_velocity(h_bar);
        let t4 = Instant::now();
        // 4–8. Boundary nodes: tractions, cohesion, prescribed components, contact, damage.
        self.boundary_pass(h_bar, h_next);
        let t5 = Instant::now();
        // 9. Energy ledger and blow-up checks.
        self.step_control.h_next = h_next;
        self.ledger(false)?;
        self.count_step_change(h, h_next);
        self.h = h_next;
        let t6 = Instant::now();
        let st = &mut self.stats.stage_times;
        st.positions += (t1 - t0).as_secs_f64();
        st.internal_forces += (t2 - t1).as_secs_f64();
        st.h_crit += (t3 - t2).as_secs_f64();
        st.free_velocity += (t4 - t3).as_secs_f64();
        st.interface_contact += (t5 - t4).as_secs_f64();
        st.bookkeeping += (t6 - t5).as_secs_f64();
        self.stats.steps_wall += t6 - t0;
        Ok(())
    }

    /// The run's smallest and largest step and its count of step changes.
    fn count_step_change(&mut self, h: f64, h_next: f64) {
        let st = &mut self.stats;
        if st.h_max == 0.0 {
            (st.h_min, st.h_max) = (h, h);
        }
        st.h_min = st.h_min.min(h_next);
        st.h_max = st.h_max.max(h_next);
        if h_next != h {
            st.step_changes += 1;
        }
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

    /// Threads that run the step's loops: the team's size, or 1 when the mesh is below the size
    /// where parallel sections pay off (or one thread was asked for).
    pub fn threads(&self) -> usize {
        self.team.as_ref().map_or(1, Team::size)
    }

    /// Runs the step's loops on a team of `threads` threads from now on (1: on the calling
    /// thread), whatever the mesh size. Results do not depend on it.
    pub fn use_threads(&mut self, threads: usize) {
        self.team = (threads > 1).then(|| Team::new(threads));
    }

    /// Number of elements times steps done.
    pub fn element_steps(&self) -> u64 {
        self.model.mesh.elements.len() as u64 * self.step_count
    }

    /// Number of distinct element shapes (each has its own precomputed Gauss data).
    pub fn element_class_count(&self) -> usize {
        self.classes.data.len()
    }

    /// Whether every element shape is an axis-aligned box (J₀ diagonal,
    /// [`crate::mesh::GaussData::axis_aligned`], [`crate::mesh::CentreData::axis_aligned`]):
    /// the full-integration kernel then forms H and Q with one product per entry
    /// ([`crate::kernels::flops::full`]), the one-point kernel goes through the modes of the
    /// trilinear field ([`crate::kernels::flops::one_point`]).
    pub fn axis_aligned(&self) -> bool {
        self.classes.data.iter().all(|gd| gd.axis_aligned)
            && self.classes.centre.iter().all(|cd| cd.axis_aligned)
    }

    /// Interface state counts now (paper fig. 6, right).
    pub fn state_counts(&self) -> StateCounts {
        let mut c = StateCounts::default();
        for itf in &self.interface_nodes {
            c.add(itf.state(&self.model.interfaces[itf.interface as usize].law));
        }
        c
    }

    /// The ledger's values now.
    pub fn energies(&self) -> EnergySnapshot {
        self.ledger.snapshot()
    }

    /// The pose of mould `k` (index into `model.planes`) at the current time tₙ, as the affine
    /// map (R, T) that takes a point x₀ of the mould at t = 0 to its place now, x = R x₀ + T:
    /// R the rotation the step composed ([`crate::mould::step::MouldStep`]: R(tₙ), exactly
    /// the pose stage 2 used at tₙ), T = d + (c₀ − R c₀) with c₀ the pivot at t = 0 and
    /// d = c(tₙ) − c₀ = ∫₀ᵗ v dτ the prescribed translation (taken from the motion itself, not
    /// as a difference of positions, so T = d to the bit when R = I). A plain plane: R = I,
    /// T = its displacement. Read-only (for the outputs); the step does not use it.
    pub fn mould_pose(&self, k: usize) -> ([[f64; 3]; 3], [f64; 3]) {
        use crate::mould::motion::{mat_vec, IDENTITY};
        let m = &self.model.planes[k];
        let ms = &self.scratch.moulds;
        if ms.plane.get(k).copied().unwrap_or(true) {
            return (IDENTITY, m.displacement(self.time));
        }
        let pose = ms.pose_at(k, self.time);
        let (c0, d) = (m.pivot(), m.displacement(pose.time));
        let rc0 = mat_vec(&pose.rotation, c0);
        (
            pose.rotation,
            std::array::from_fn(|i| d[i] + (c0[i] - rc0[i])),
        )
    }
}

/// The element loop of stage 3 over one simulation's mesh, material, rule and team: all that
/// F_int(U) = Σ_e fₑ(U) needs besides U (model §1.5). Borrowed field by field, so the step
/// can write F_int while it holds it.
struct ElementLoop<'a> {
    model: &'a Model,
    classes: &'a ElementClasses,
    blocks: &'a [Vec<Vec<u32>>],
    team: Option<&'a Team>,
    /// Prefetch each lane group's nodes ([`crate::kernels::prefetch_pays`]).
    prefetch: bool,
}

impl ElementLoop<'_> {
    /// F_int(`u`) added into `f` (zeroed by the caller), with Ψ and Ψ_hg if `energy`.
    fn assemble(
        &self,
        u: &Planes,
        f: &mut Planes,
        energy: bool,
        parts: &mut Vec<ElementSums>,
        exact_below: f64,
    ) -> Assembly {
        assemble_internal_forces(
            &self.model.mesh,
            self.classes,
            self.blocks,
            &self.model.material,
            ElementRule::of(&self.model.scheme),
            u,
            f,
            energy,
            self.team,
            parts,
            exact_below,
            self.prefetch,
        )
    }
}

impl StateCounts {
    /// Counts one more node in `state`.
    pub fn add(&mut self, state: InterfaceState) {
        match state {
            InterfaceState::Elastic => self.elastic += 1,
            InterfaceState::Transition => self.transition += 1,
            InterfaceState::Ruptured => self.ruptured += 1,
            InterfaceState::Unformed => self.unformed += 1,
        }
    }
}
