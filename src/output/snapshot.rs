//! The state of a simulation at one output frame, copied once on the solver thread by the run
//! driver and shared (`Arc`) by every output's writer thread.

use crate::energy::EnergySnapshot;
use crate::solver::{ContactStatus, Simulation, StageTimes, StateCounts};
use std::time::Duration;
use web_time::Instant;

/// The state of a simulation at one step: what the Rerun recording and the ParaView files
/// show of it.
#[derive(Debug, Clone)]
pub struct Snapshot {
    pub step: u64,
    /// tₙ [s].
    pub time: f64,
    pub h: f64,
    pub h_crit: f64,
    /// Uₙ of every node [m].
    pub u: Vec<[f64; 3]>,
    /// V_{n+½} of every node [m/s] (PHYSICS.md §4: Uₙ₊₁ = Uₙ + h V_{n+½}).
    pub v: Vec<[f64; 3]>,
    /// One entry per interface node, in `Simulation::interface_nodes` order.
    pub interface: Vec<InterfaceSnapshot>,
    /// Contact status and impulse per unit area [Pa·s] of the contact-only nodes.
    pub contact: Vec<(ContactStatus, [f64; 3])>,
    /// The pose of each mould at tₙ, in `model.planes` order: (R, T) with x = R x₀ + T for a
    /// point x₀ of the mould at t = 0 ([`Simulation::mould_pose`]).
    pub moulds: Vec<([[f64; 3]; 3], [f64; 3])>,
    pub energies: EnergySnapshot,
    /// Reaction of each prescribed-displacement condition [N].
    pub reactions: Vec<f64>,
    pub counts: StateCounts,
    pub stages: StageTimes,
    /// Solver-thread time spent on the outputs before this frame [s] (the `logging` stage of
    /// the recording's timing series).
    pub output_seconds: f64,
    /// Solver-thread time this copy took.
    pub capture_time: Duration,
}

/// One interface node in a [`Snapshot`].
#[derive(Debug, Clone, Copy)]
pub struct InterfaceSnapshot {
    /// α [m].
    pub alpha: f64,
    /// Normal gap [m].
    pub gap: f64,
    pub contact: ContactStatus,
    /// R_d = g_N(α)[u] [Pa].
    pub cohesive_traction: [f64; 3],
    /// R_c per unit area of the last step [Pa·s].
    pub contact_impulse: [f64; 3],
}

impl Snapshot {
    /// Copies what a frame shows (O(nodes) memcpys); `output_time` is the solver-thread time
    /// spent on the outputs so far.
    pub fn capture(sim: &Simulation, output_time: Duration) -> Snapshot {
        let started = Instant::now();
        let mut s = Snapshot {
            step: sim.step_count,
            time: sim.time,
            h: sim.h,
            h_crit: sim.h_crit,
            u: sim.u.clone(),
            v: sim.v.clone(),
            interface: sim
                .interface_nodes
                .iter()
                .map(|n| InterfaceSnapshot {
                    alpha: n.alpha,
                    gap: n.gap,
                    contact: n.contact,
                    cohesive_traction: n.cohesive_traction,
                    contact_impulse: n.contact_impulse,
                })
                .collect(),
            contact: sim
                .contact_nodes
                .iter()
                .map(|n| (n.contact, n.contact_impulse))
                .collect(),
            moulds: (0..sim.model.planes.len())
                .map(|k| sim.mould_pose(k))
                .collect(),
            energies: sim.energies(),
            reactions: sim.stats.reactions.clone(),
            counts: sim.state_counts(),
            stages: sim.stats.stage_times.clone(),
            output_seconds: output_time.as_secs_f64(),
            capture_time: Duration::ZERO,
        };
        s.capture_time = started.elapsed();
        s
    }

    /// Memory of a snapshot of `sim` [bytes], roughly: for the sizes of the writer queues.
    pub fn bytes(sim: &Simulation) -> usize {
        48 * sim.u.len() + 96 * (sim.interface_nodes.len() + sim.contact_nodes.len()) + 512
    }
}
