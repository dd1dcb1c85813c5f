//! The state of a simulation at one output frame, copied once on the solver thread by the run
//! driver and shared (`Arc`) by every output's writer thread.

use crate::energy::EnergySnapshot;
use crate::interface::contact::ContactStatus;
use crate::law::InterfaceState;
use crate::output::watch::Reading;
use crate::solver::{Simulation, StageTimes, StateCounts};
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
    /// V_{n+½} of every node [m/s] (model §4.1: Uₙ₊₁ = Uₙ + h V_{n+½}); empty when no
    /// output of the run shows velocities ([`crate::output::Output::velocities`]).
    pub v: Vec<[f64; 3]>,
    /// One entry per interface node, in `Simulation::interface_nodes` order.
    pub interface: Vec<InterfaceSnapshot>,
    /// Contact status and impulse per unit area [Pa·s] of the contact-only nodes.
    pub contact: Vec<(ContactStatus, [f64; 3])>,
    /// The pose of each mould at tₙ, in `model.moulds` order: (R, T) with x = R x₀ + T for a
    /// point x₀ of the mould at t = 0 ([`Simulation::mould_pose`]).
    pub moulds: Vec<([[f64; 3]; 3], [f64; 3])>,
    /// The force F [N] and the moment M about its pivot at tₙ [N·m] that the body exerted on
    /// each mould over the last step, in `model.moulds` order ([`mould_loads`]).
    pub mould_loads: Vec<([f64; 3], [f64; 3])>,
    /// The friction dissipated on each mould since t₀ [J], in `model.moulds` order
    /// ([`Simulation::mould_frictions`]: with one mould, `friction_dissipated` itself).
    pub mould_friction: Vec<f64>,
    pub energies: EnergySnapshot,
    /// Reaction of each prescribed-displacement condition [N].
    pub reactions: Vec<f64>,
    pub counts: StateCounts,
    /// The watched nodes' entries (`run --watch`), in the order of the run's
    /// `output::watch::Watch`; set by the run driver, empty otherwise.
    pub watched: Vec<Reading>,
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
    /// Its state ([`crate::solver::InterfaceNode::state`]: unformed until glue that forms on
    /// contact has formed, then elastic / transition / ruptured by α).
    pub state: InterfaceState,
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
    /// spent on the outputs so far; `velocities`: copy V too (else `v` is empty).
    pub fn capture(sim: &Simulation, output_time: Duration, velocities: bool) -> Snapshot {
        let started = Instant::now();
        let mut s = Snapshot {
            step: sim.state.step_count,
            time: sim.state.time,
            h: sim.state.h,
            h_crit: sim.state.h_crit,
            u: sim.state.u.to_rows(),
            v: if velocities {
                sim.state.v.to_rows()
            } else {
                Vec::new()
            },
            interface: sim
                .state
                .interface_nodes
                .iter()
                .map(|n| InterfaceSnapshot {
                    alpha: n.alpha,
                    state: n.state(&sim.model.interfaces[n.interface as usize].law),
                    gap: n.gap,
                    contact: n.contact,
                    cohesive_traction: n.cohesive_traction,
                    contact_impulse: n.contact_impulse,
                })
                .collect(),
            contact: sim
                .state
                .contact_nodes
                .iter()
                .map(|n| (n.contact, n.contact_impulse))
                .collect(),
            moulds: (0..sim.model.moulds.len())
                .map(|k| sim.mould_pose(k))
                .collect(),
            mould_loads: mould_loads(sim),
            mould_friction: sim.mould_frictions().into_iter().map(|m| m.1).collect(),
            energies: sim.energies(),
            reactions: sim.stats.reactions.clone(),
            counts: sim.state_counts(),
            watched: Vec::new(),
            stages: sim.stats.stage_times.clone(),
            output_seconds: output_time.as_secs_f64(),
            capture_time: Duration::ZERO,
        };
        s.capture_time = started.elapsed();
        s
    }

    /// Memory of a snapshot of `sim` [bytes], roughly, counting V (its largest size, whatever
    /// the outputs of the run): for the sizes of the writer queues, which the frames of one run
    /// share.
    pub fn bytes(sim: &Simulation) -> usize {
        48 * sim.state.u.len()
            + 96 * (sim.state.interface_nodes.len() + sim.state.contact_nodes.len())
            + 512
    }
}

/// The force F [N] and moment M about its pivot c = R c₀ + T at tₙ [N·m] that the body exerted
/// on each mould over the last step of length h, from the impulses that mould gave the
/// body's nodes: the glue's −h̄ W R_d at a glued node's anchor x − [u] (the force on the
/// mould is W R_d) and the contact's W R_c at the node (the force on the mould is −W R_c/h),
/// F = Σ f, M = Σ (p − c) × f. Anisotropic glue's force acts on the mould at the node x
/// instead, which adds the couple [u] × W R_d that does the glue's torque work (model §5.5,
/// §7.6; for isotropic glue R_d is along [u] and the couple is 0, not evaluated). The same sums
/// as the ledger's per-mould work (force · velocity at these points, couple times ω) and as
/// the roller-peel test's load; zero before the first step.
pub fn mould_loads(sim: &Simulation) -> Vec<([f64; 3], [f64; 3])> {
    let n = sim.model.moulds.len();
    let mut loads = vec![([0.0; 3], [0.0; 3]); n];
    if n == 0 || sim.state.step_count == 0 || sim.state.h <= 0.0 {
        return loads;
    }
    let pivots: Vec<[f64; 3]> = (0..n)
        .map(|k| {
            let (r, t) = sim.mould_pose(k);
            let c0 = sim.model.moulds[k].pivot();
            std::array::from_fn(|i| r[i][0] * c0[0] + r[i][1] * c0[1] + r[i][2] * c0[2] + t[i])
        })
        .collect();
    let x = |node: u32| -> [f64; 3] {
        let (x0, u) = (
            sim.model.mesh.nodes[node as usize],
            sim.state.u.get(node as usize),
        );
        std::array::from_fn(|i| x0[i] + u[i])
    };
    let mut add = |k: usize, p: [f64; 3], f: [f64; 3]| {
        let (force, moment) = &mut loads[k];
        let d: [f64; 3] = std::array::from_fn(|i| p[i] - pivots[k][i]);
        let m = [
            d[1] * f[2] - d[2] * f[1],
            d[2] * f[0] - d[0] * f[2],
            d[0] * f[1] - d[1] * f[0],
        ];
        for i in 0..3 {
            force[i] += f[i];
            moment[i] += m[i];
        }
    };
    for itf in &sim.state.interface_nodes {
        let k = sim.model.interfaces[itf.interface as usize].plane;
        let xn = x(itf.node);
        let law = &sim.model.interfaces[itf.interface as usize].law;
        let glue_at = if law.loading().isotropic() {
            std::array::from_fn(|i| xn[i] - itf.jump[i]) // the anchor
        } else {
            xn
        };
        add(k, glue_at, itf.cohesive_traction.map(|r| r * itf.area));
        add(
            k,
            xn,
            itf.contact_impulse.map(|r| -r * itf.area / sim.state.h),
        );
    }
    for cn in &sim.state.contact_nodes {
        let f = cn.contact_impulse.map(|r| -r * cn.area / sim.state.h);
        add(cn.plane as usize, x(cn.node), f);
    }
    loads
}
