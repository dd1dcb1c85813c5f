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
//! | 2 moulds, jumps, gaps | [`Simulation::surfaces_and_gaps`] | `stages.rs` |
//! | 3 internal forces | [`Simulation::internal_forces`] | `stages.rs` |
//! | 4 the next step, the velocities over it | [`Simulation::next_step`] (model §6), [`Simulation::prescribed_motion`] | `stable_step.rs`, `lanczos.rs`, `stiffness.rs`, `stages.rs` |
//! | 5 free velocity, all nodes | [`Simulation::free_velocity`] | `stages.rs` |
//! | 5–8 at boundary nodes | [`Simulation::boundary_pass`]: per node, tractions and cohesion (5), prescribed components (6), contact (7), the ledger's halves (9), damage (8) | `boundary.rs` |
//! | 5–8 at bonded pairs | [`Simulation::bond_pass`] (model §7.8) | `bond.rs` |
//! | 9 glue that forms, ledger | [`Simulation::form_glue`] (model §8), [`Simulation::ledger`] | `boundary/adhesion.rs`, `ledger.rs` |
//!
//! Nothing is solved globally: every stage is a loop of local computations, the element loop in
//! parallel ([`Team`]: persistent threads, static shares) and deterministic whatever the thread
//! count (node-disjoint element blocks, fixed-size chunks, fixed-order reductions). Stages 5–8
//! are one fused pass over the boundary nodes (a node's stages need only that node, model
//! §4.10), which calls the stage functions in order.

mod bond;
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

pub use bond::BondNode;
pub use state::{
    ContactNode, CornerChecks, DamageClamped, InterfaceNode, PeakReaction, RunStats, SolverError,
    StableStep, StageTimes, State, StateCounts,
};

use crate::energy::EnergySnapshot;
use crate::kernels::{
    assemble_internal_forces, Assembly, AssemblyScratch, ElementRule, NodeSums, Planes,
};
use crate::law::InterfaceState;
use crate::mesh::ElementClasses;
use crate::model::{Model, StartOffset};
use crate::team::Team;
use boundary::BoundarySums;
pub use checkpoint::{
    model_fingerprint, read_header, write_atomically, CheckpointError, CheckpointHeader,
    CHECKPOINT_FORMAT,
};
use ledger::StepSums;
pub use mass_scaling::MassScalingReport;
use stages::StepScratch;
use std::sync::Arc;
// std's `Instant` on native; the browser's clock on wasm32, where std's panics.
pub use crate::tunables::PARALLEL_MIN_ELEMENTS;
use crate::tunables::{BOUNDARY_GRAIN, ELEMENT_GRAIN, NODE_GRAIN};
use web_time::Instant;

/// A simulation in progress. Build it with [`Simulation::new`], advance it with
/// [`Simulation::step`] or [`Simulation::run`].
///
/// Four parts: the model (immutable, shared), what the set-up computes from it ([`Setup`], fixed
/// for the run), the run's [`State`] at tₙ (what a checkpoint saves), the buffers the step's
/// loops reuse ([`Workspace`], written before they are read in every step), and the statistics.
pub struct Simulation {
    pub model: Arc<Model>,
    /// What the set-up computed from the model: masses, mass scaling, scales, start offsets.
    pub setup: Setup,
    /// What defines the run at tₙ (model §4.13): everything a checkpoint saves.
    pub state: State,
    /// Element classes and blocks, the thread team, the loops' per-block results.
    work: Workspace,
    pub stats: RunStats,
}

/// What the set-up computes from the model alone, fixed for the run.
pub struct Setup {
    /// Lumped nodal masses [kg] and their inverses.
    pub mass: Vec<f64>,
    inv_mass: Vec<f64>,
    /// Mass scaling (model §6.8): the density factor of each hexahedron class and of each
    /// tetrahedron (empty without), the mass added at each node that has some, and what the
    /// scaling did.
    class_density: Vec<f64>,
    tet_density: Vec<f64>,
    added_mass: Vec<(u32, f64)>,
    pub mass_scaling: Option<MassScalingReport>,
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

/// The element classes and blocks the loops walk, the threads that run them, and the loops'
/// per-block results, reused from step to step (none of it is state: a restored simulation
/// builds its own).
struct Workspace {
    classes: ElementClasses,
    /// Colours → node-disjoint blocks → elements ([`crate::mesh::Mesh::element_blocks`]).
    blocks: Vec<Vec<Vec<u32>>>,
    /// The threads of the parallel loops (None: everything on the calling thread).
    team: Option<Team>,
    /// The element loops prefetch each lane group's nodes: the nodal fields exceed the
    /// last-level cache ([`crate::kernels::prefetch_pays`]).
    prefetch: bool,
    /// Per-block / per-chunk results of the parallel loops.
    /// The element loop's buffers (its per-block results, the tetrahedra's points and nodal
    /// fields).
    elements: AssemblyScratch,
    parts_nodes: Vec<NodeSums>,
    parts_boundary: Vec<BoundarySums>,
    /// Reaction impulse of each prescribed condition from each boundary chunk.
    parts_reactions: Vec<f64>,
    /// The values stages hand to later stages of the same step (surface and prescribed
    /// velocities, traction amplitudes, V_{n+½} of the boundary nodes, the reactions).
    step: StepScratch,
    /// Query triangulated moulds cold (the full BVH query at every step, the lists of nearby
    /// triangles unused): only for measuring what the lists save
    /// (`physics/examples/mould_cache.rs`); off in runs.
    cold_mould_queries: bool,
}

impl Simulation {
    /// One CD-Lagrange step tₙ → tₙ₊₁ (model §4.1–§4.9), written with the index of
    /// the step just completed as n − 1: on entry Uₙ, αₙ, V_{n+½}; on exit Uₙ₊₁, αₙ₊₁, V_{n+3/2}.
    pub fn step(&mut self) -> Result<(), SolverError> {
        let t0 = Instant::now();
        let h = self.state.h;
        // 1. Uₙ₊₁ = Uₙ + h V_{n+½}; αₙ₊₁ = αₙ + h α̇_{n+½} (model §4.1).
        self.advance_positions(h);
        // 2. Moulds at tₙ₊₁: jumps [u]ₙ₊₁ and gaps gₙ₊₁ (§4.2).
        self.surfaces_and_gaps();
        let t1 = Instant::now();
        // 3. F_int,ₙ₊₁ from Uₙ₊₁ (parallel element loop); an inverted element stops the run (§4.3).
        self.internal_forces(true, true)?;
        let t2 = Instant::now();
        // 4. The next step h_{n+3/2} (§6.5, §6.6), then the mould and prescribed velocities
        //    over it (§4.4).
        let h_next = self.next_step();
        let t3 = Instant::now();
        self.prescribed_motion(h_next, false);
        let h_bar = 0.5 * (h + h_next);
        // 5. Free velocity on every node: internal forces and gravity (§4.5).
        let nodes = self.free_velocity(h_bar);
        let t4 = Instant::now();
        // 5–8 at the boundary nodes, one fused pass: tractions and cohesion (5), prescribed
        //    components (6), contact and friction (7), damage for the next step (8) (§4.10).
        let boundary = self.boundary_pass(h_bar, h_next);
        // 5–8 at the bonded node pairs (§7.8).
        let boundary = self.bond_pass(h_bar, h_next, boundary);
        let t5 = Instant::now();
        // 9. Glue that forms on contact (§8), then the ledger and checks (§4.9, §5).
        self.form_glue();
        self.ledger(h_next, false, StepSums { nodes, boundary })?;
        self.count_step_change(h, h_next);
        self.state.h = h_next;
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
                    step: self.state.step_count,
                    time: self.state.time,
                });
            }
        }
        Ok(())
    }

    /// True once tₙ has reached the end time (to within a millionth of a step).
    pub fn finished(&self) -> bool {
        self.state.time >= self.model.end_time - 1e-6 * self.state.h
    }

    /// Threads that run the step's loops: the team's size, or 1 when the mesh is below the size
    /// where parallel sections pay off (or one thread was asked for).
    pub fn threads(&self) -> usize {
        self.work.team.as_ref().map_or(1, Team::size)
    }

    /// Runs the step's loops on a team of `threads` threads from now on (1: on the calling
    /// thread), whatever the mesh size. Results do not depend on it.
    pub fn use_threads(&mut self, threads: usize) {
        self.work.team = (threads > 1).then(|| Team::new(threads));
    }

    /// Number of elements times steps done.
    pub fn element_steps(&self) -> u64 {
        self.model.mesh.element_count() as u64 * self.state.step_count
    }

    /// Number of distinct element shapes (each has its own precomputed Gauss data).
    pub fn element_class_count(&self) -> usize {
        self.work.classes.data.len()
    }

    /// Whether every element shape is an axis-aligned box (J₀ diagonal,
    /// [`crate::mesh::GaussData::axis_aligned`], [`crate::mesh::CentreData::axis_aligned`]):
    /// the full-integration kernel then forms H and Q with one product per entry
    /// ([`crate::kernels::flops::full`]), the one-point kernel goes through the modes of the
    /// trilinear field ([`crate::kernels::flops::one_point`]).
    pub fn axis_aligned(&self) -> bool {
        self.work.classes.data.iter().all(|gd| gd.axis_aligned)
            && self.work.classes.centre.iter().all(|cd| cd.axis_aligned)
    }

    /// Interface state counts now (paper fig. 6, right).
    pub fn state_counts(&self) -> StateCounts {
        let mut c = StateCounts::default();
        for itf in &self.state.interface_nodes {
            c.add(itf.state(&self.model.interfaces[itf.interface as usize].law));
        }
        c
    }

    /// The ledger's values now.
    pub fn energies(&self) -> EnergySnapshot {
        self.state.ledger.snapshot()
    }

    /// The pose of mould `k` (index into `model.moulds`) at the current time tₙ, as the affine
    /// map (R, T) that takes a point x₀ of the mould at t = 0 to its place now, x = R x₀ + T:
    /// R the rotation the step composed ([`crate::mould::step::MouldStep`]: R(tₙ), exactly
    /// the pose stage 2 used at tₙ), T = d + (c₀ − R c₀) with c₀ the pivot at t = 0 and
    /// d = c(tₙ) − c₀ = ∫₀ᵗ v dτ the prescribed translation (taken from the motion itself, not
    /// as a difference of positions, so T = d to the bit when R = I). A plain plane: R = I,
    /// T = its displacement. Read-only (for the outputs); the step does not use it.
    pub fn mould_pose(&self, k: usize) -> ([[f64; 3]; 3], [f64; 3]) {
        use crate::mould::motion::{mat_vec, IDENTITY};
        let m = &self.model.moulds[k];
        let ms = &self.state.moulds;
        if ms.plane.get(k).copied().unwrap_or(true) {
            return (IDENTITY, m.displacement(self.state.time));
        }
        let pose = ms.pose_at(k, self.state.time);
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
        scratch: &mut AssemblyScratch,
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
            scratch,
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
