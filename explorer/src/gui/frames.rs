//! Frames of a run for the explorer's 3-D view ([`super::view3d`]): what the view draws of the
//! state at one step — the deformed surface x = X + U of the body (the recorder's surface,
//! [`crate::output::surface`]), the colouring fields at its vertices, the interface nodes with
//! their state and contact status, the contact-only nodes with their contact status, and the
//! pose of each mould (its drawing, [`crate::output::surface::mould`], is in the run's
//! [`Topology`], once: a frame holds 48 bytes a mould), and what the inspected node's plots
//! read: every interface and contact node's [`Reading`] (jump, tractions, α, gap, state and
//! status), so any node can be picked during or after the run.
//!
//! Built on the solver's thread from a `&Simulation` ([`FrameSampler::due`]), so the native
//! run thread ([`super::job`]) and an in-page runner call the same function, at the steps of
//! the run driver's [`FrameClock`] (one implementation of when a frame is due). A run's frames are
//! bounded in memory: at most [`MAX_RUN_BYTES`] in all (28³ pull-off: ≈ 206 kB a frame, see
//! [`FrameBuilder::frame_bytes`]), so the cadence is the recorder's (the run's `frames` over
//! its end time) or coarser.

use crate::interface::contact::ContactStatus;
use crate::kernels::Planes;
use crate::law::InterfaceState;
use crate::model::Model;
use crate::output::fields::Scalar;
use crate::output::surface::mould::{body_box, mould_drawing, place};
use crate::output::surface::Surface;
use crate::output::watch::Reading;
use crate::output::{Cadence, FrameClock};
use crate::solver::Simulation;
use std::sync::Arc;

pub use crate::tunables::MAX_RUN_BYTES;

/// The field that colours the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Field {
    /// |U| at the node [m].
    #[default]
    Displacement,
    /// Von Mises stress of the Cauchy stress at the element centres, averaged to the nodes [Pa].
    VonMises,
    /// J = det F at the element centres, averaged to the nodes [-].
    Jacobian,
}

impl Field {
    pub const ALL: [Field; 3] = [Field::Displacement, Field::VonMises, Field::Jacobian];

    /// Name and unit.
    pub fn label(self) -> (&'static str, &'static str) {
        match self {
            Field::Displacement => ("|U|", "m"),
            Field::VonMises => ("von Mises", "Pa"),
            Field::Jacobian => ("J = det F", "-"),
        }
    }

    fn scalar(self) -> Option<Scalar> {
        match self {
            Field::Displacement => None,
            Field::VonMises => Some(Scalar::VonMises),
            Field::Jacobian => Some(Scalar::Jacobian),
        }
    }
}

/// What does not change over a run: the surface's triangles, the reference box, the moulds.
#[derive(Debug)]
pub struct Topology {
    /// Two triangles per boundary face, in surface vertex numbers.
    pub triangles: Vec<[u32; 3]>,
    /// Number of surface vertices.
    pub vertices: usize,
    /// Centre of the reference surface's bounding box [m].
    pub centre: [f32; 3],
    /// Largest side of that box [m].
    pub extent: f32,
    /// Each mould's drawing at t = 0 (a half-space as a square around the body's box).
    pub moulds: Vec<MouldTriangles>,
    /// The mesh node (0-based) of each boundary entry: the interface nodes, then the
    /// contact-only nodes (a frame's `points` then `contact_points`, and its `readings`).
    pub boundary_nodes: Vec<u32>,
    /// What each boundary entry is: "glued on `z-` to mould", "in contact with wall".
    pub boundary_labels: Vec<String>,
}

/// A mould's drawing at t = 0: triangles of vertices [m], in its frame at t = 0.
#[derive(Debug)]
pub struct MouldTriangles {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

impl MouldTriangles {
    /// The corners of every triangle placed by `pose`, x = R x₀ + T, in triangle order.
    pub fn placed(&self, pose: &Pose) -> impl Iterator<Item = [f32; 3]> + '_ {
        let pose = (pose.0.map(|r| r.map(f64::from)), pose.1.map(f64::from));
        self.triangles
            .iter()
            .flatten()
            .map(move |&v| f32x3(place(&pose, self.vertices[v as usize])))
    }
}

/// A mould's pose at a frame, (R, T) with x = R x₀ + T.
pub type Pose = ([[f32; 3]; 3], [f32; 3]);

/// The state of a run at one step, as the 3-D view draws it.
#[derive(Debug, Clone)]
pub struct Frame {
    pub topology: Arc<Topology>,
    pub step: u64,
    /// tₙ [s].
    pub time: f64,
    /// x = X + Uₙ of each surface vertex [m].
    pub positions: Vec<[f32; 3]>,
    /// Each [`Field`] (in [`Field::ALL`] order) at each surface vertex.
    pub fields: [Vec<f32>; 3],
    /// x = X + Uₙ of each interface node [m].
    pub points: Vec<[f32; 3]>,
    /// State of the law at αₙ and contact status of each interface node.
    pub states: Vec<(InterfaceState, ContactStatus)>,
    /// x = X + Uₙ of each contact-only node [m].
    pub contact_points: Vec<[f32; 3]>,
    /// Contact status of each contact-only node.
    pub contact_states: Vec<ContactStatus>,
    /// Pose of each mould at tₙ (`Simulation::mould_pose`).
    pub mould_poses: Vec<Pose>,
    /// Each boundary entry's state ([`Reading::all`]: the interface nodes, then the
    /// contact-only nodes).
    pub readings: Vec<Reading>,
}

impl Frame {
    pub fn field(&self, f: Field) -> &[f32] {
        &self.fields[f as usize]
    }
}

/// Builds the frames of one simulation.
pub struct FrameBuilder {
    surface: Surface,
    topology: Arc<Topology>,
}

fn f32x3(x: [f64; 3]) -> [f32; 3] {
    x.map(|c| c as f32)
}

/// x = X + U of node `n` [m].
fn position(m: &Model, u: &Planes, n: u32) -> [f32; 3] {
    let (x, u) = (m.mesh.nodes[n as usize], u.get(n as usize));
    f32x3([x[0] + u[0], x[1] + u[1], x[2] + u[2]])
}

impl FrameBuilder {
    pub fn new(sim: &Simulation) -> FrameBuilder {
        let m = &sim.model;
        let surface = Surface::extract(m);
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &n in &surface.nodes {
            let x = m.mesh.nodes[n as usize];
            lo = [0, 1, 2].map(|i| lo[i].min(x[i]));
            hi = [0, 1, 2].map(|i| hi[i].max(x[i]));
        }
        let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let extent = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
        let body = body_box(m);
        let moulds = m
            .moulds
            .iter()
            .map(|p| {
                let d = mould_drawing(p, body);
                MouldTriangles {
                    vertices: d.vertices,
                    triangles: d.triangles,
                }
            })
            .collect();
        let plane = |k: usize| &m.moulds[k].name;
        let boundary_labels = (sim.state.interface_nodes.iter())
            .map(|n| {
                let itf = &m.interfaces[n.interface as usize];
                format!("glued on `{}` to {}", itf.faces, plane(itf.plane))
            })
            .chain(
                (sim.state.contact_nodes.iter())
                    .map(|n| format!("in contact with {}", plane(n.plane as usize))),
            )
            .collect();
        let topology = Arc::new(Topology {
            triangles: surface.triangles.clone(),
            vertices: surface.nodes.len(),
            centre: f32x3(centre),
            extent: extent as f32,
            moulds,
            boundary_nodes: (sim.state.interface_nodes.iter().map(|n| n.node))
                .chain(sim.state.contact_nodes.iter().map(|n| n.node))
                .collect(),
            boundary_labels,
        });
        FrameBuilder { surface, topology }
    }

    pub fn topology(&self) -> &Arc<Topology> {
        &self.topology
    }

    /// The frame of `sim`'s current state.
    pub fn frame(&self, sim: &Simulation) -> Frame {
        let m = &sim.model;
        let u = &sim.state.u;
        let field = |f: Field| -> Vec<f32> {
            let v = self.surface.values(m, u, f.scalar());
            v.into_iter().map(|x| x as f32).collect()
        };
        Frame {
            topology: self.topology.clone(),
            step: sim.state.step_count,
            time: sim.state.time,
            positions: self
                .surface
                .nodes
                .iter()
                .map(|&n| position(m, u, n))
                .collect(),
            fields: Field::ALL.map(field),
            points: sim
                .state
                .interface_nodes
                .iter()
                .map(|n| position(m, u, n.node))
                .collect(),
            states: sim
                .state
                .interface_nodes
                .iter()
                .map(|n| {
                    let law = &m.interfaces[n.interface as usize].law;
                    (n.state(law), n.contact)
                })
                .collect(),
            contact_points: sim
                .state
                .contact_nodes
                .iter()
                .map(|n| position(m, u, n.node))
                .collect(),
            contact_states: sim.state.contact_nodes.iter().map(|n| n.contact).collect(),
            mould_poses: (0..m.moulds.len())
                .map(|k| {
                    let (r, t) = sim.mould_pose(k);
                    (r.map(f32x3), f32x3(t))
                })
                .collect(),
            readings: Reading::all(sim),
        }
    }

    /// Memory of one frame of `sim` [bytes]: 24 a surface vertex (position, three fields),
    /// 14 an interface node, 13 a contact-only node, a [`Reading`] of each, 48 a mould's pose,
    /// and the vectors' headers (the moulds' triangles are the topology's, shared by every
    /// frame).
    pub fn frame_bytes(&self, sim: &Simulation) -> usize {
        let reading = std::mem::size_of::<Reading>();
        24 * self.topology.vertices
            + (14 + reading) * sim.state.interface_nodes.len()
            + (13 + reading) * sim.state.contact_nodes.len()
            + std::mem::size_of::<Pose>() * self.topology.moulds.len()
            + std::mem::size_of::<Frame>()
    }
}

/// When a frame is due: the run driver's [`FrameClock`] at `frames` frames over the end time
/// (the recorder's cadence, [`Cadence::PerSimSecond`], so that the 3-D view and a recording of
/// the run hold the same steps), or fewer if that many frames would take more than
/// [`MAX_RUN_BYTES`]; the first at t = 0 and the last at the end of the run
/// ([`FrameSampler::last`]).
pub struct FrameSampler {
    builder: FrameBuilder,
    /// Simulated time between two frames [s].
    pub interval: f64,
    clock: FrameClock,
}

impl FrameSampler {
    /// About `frames` frames over the run of `sim` (at least one).
    pub fn new(sim: &Simulation, frames: u32) -> FrameSampler {
        let builder = FrameBuilder::new(sim);
        // t = 0, `most` intervals and possibly the final state.
        let most = (MAX_RUN_BYTES / builder.frame_bytes(sim)).max(3) - 2;
        let frames = (frames.max(1) as usize).min(most);
        let end_time = sim.model.end_time;
        let cadence = Cadence::PerSimSecond(frames as f64 / end_time);
        FrameSampler {
            builder,
            interval: end_time / frames as f64,
            clock: FrameClock::new(cadence, end_time),
        }
    }

    /// The frame of `sim` if one is due at its step.
    pub fn due(&mut self, sim: &Simulation) -> Option<Frame> {
        let (n, t) = (sim.state.step_count, sim.state.time);
        (self.clock.due(n, t) && self.clock.take(n, t)).then(|| self.builder.frame(sim))
    }

    /// The frame of the final state, unless it was given already.
    pub fn last(&mut self, sim: &Simulation) -> Option<Frame> {
        let (n, t) = (sim.state.step_count, sim.state.time);
        self.clock.take(n, t).then(|| self.builder.frame(sim))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pull_off(cells: usize, set: &[&str]) -> Simulation {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/pull_off.toml");
        let mut o = vec![format!("mesh.cells=[{cells},{cells},{cells}]")];
        o.extend(set.iter().map(|s| s.to_string()));
        Simulation::new(crate::scene::load_scene(&path, &o).unwrap().model).unwrap()
    }

    /// Some steps into the pull-off (the top moving, the body deformed): the frame's surface is
    /// the nodes on the faces of the box, X + U of each (the nodes found from their reference
    /// coordinates, not from the mesh's faces), its counts those of an n³ box.
    #[test]
    fn frame_is_the_deformed_box_surface() {
        let n = 4;
        let mut sim = pull_off(n, &[]);
        for _ in 0..200 {
            sim.step().unwrap();
        }
        let f = FrameBuilder::new(&sim).frame(&sim);
        let m = &sim.model;
        let (lo, hi) = (0..3).fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), i| {
            let c = m.mesh.nodes.iter().map(|x| x[i]);
            let (a, b) = c.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
            let (mut lo, mut hi) = (lo, hi);
            (lo[i], hi[i]) = (a, b);
            (lo, hi)
        });
        let on_face = |x: &[f64; 3]| (0..3).any(|i| x[i] == lo[i] || x[i] == hi[i]);
        let key = |p: [f32; 3]| p.map(f32::to_bits);
        let mut expected: Vec<_> = (0..m.mesh.nodes.len())
            .filter(|&k| on_face(&m.mesh.nodes[k]))
            .map(|k| key([0, 1, 2].map(|i| (m.mesh.nodes[k][i] + sim.state.u.get(k)[i]) as f32)))
            .collect();
        let mut got: Vec<_> = f.positions.iter().map(|&p| key(p)).collect();
        expected.sort_unstable();
        got.sort_unstable();
        assert_eq!(got, expected);
        assert!(
            sim.state.u.rows().any(|u| u[2] > 1e-4),
            "the body has moved"
        );
        assert_eq!(f.positions.len(), (n + 1).pow(3) - (n - 1).pow(3));
        assert_eq!(f.topology.triangles.len(), 2 * 6 * n * n);
        assert!(f.fields.iter().all(|v| v.len() == f.positions.len()));
        // The glued bottom face: (n + 1)² interface nodes.
        assert_eq!(
            (f.points.len(), f.states.len()),
            ((n + 1) * (n + 1), (n + 1) * (n + 1))
        );
        assert_eq!(f.mould_poses.len(), m.moulds.len());
        assert_eq!(f.topology.moulds.len(), m.moulds.len());
        // |U| at the vertices: the largest is the largest |U| on the surface.
        let max_u = |v: &[f32]| v.iter().fold(0.0f32, |a, &b| a.max(b));
        let surface_max = (0..m.mesh.nodes.len())
            .filter(|&k| on_face(&m.mesh.nodes[k]))
            .map(|k| crate::mesh::norm(sim.state.u.get(k)) as f32)
            .fold(0.0f32, f32::max);
        assert_eq!(max_u(f.field(Field::Displacement)), surface_max);
    }

    /// At t = 0 nothing is deformed: J = 1 and the von Mises stress 0 at every vertex, to the
    /// round-off of F = I.
    #[test]
    fn undeformed_fields() {
        let sim = pull_off(3, &[]);
        let f = FrameBuilder::new(&sim).frame(&sim);
        assert!(f.field(Field::Jacobian).iter().all(|&j| j == 1.0));
        assert!(f.field(Field::VonMises).iter().all(|&s| s == 0.0));
        assert!(f.field(Field::Displacement).iter().all(|&u| u == 0.0));
    }

    /// The 3-D view's frames are at the steps of the run driver's frames at the recorder's
    /// cadence (as the explorer's job sets it): a recording of the run and the view hold the
    /// same steps, step 0 and the last included.
    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn frames_at_the_steps_of_the_drivers_frames() {
        use crate::driver::{Driver, Progress};
        use crate::output::{Ending, Output, OutputError, OutputReport, Snapshot};
        use std::sync::{atomic::AtomicBool, Mutex};
        /// Notes the steps of the driver's frames.
        struct Steps(Arc<Mutex<Vec<u64>>>);
        impl Output for Steps {
            fn frame(&mut self, s: &Arc<Snapshot>) -> Result<(), OutputError> {
                self.0.lock().unwrap().push(s.step);
                Ok(())
            }
            fn finish(
                self: Box<Self>,
                last: Option<Arc<Snapshot>>,
                _end: &Ending<'_>,
            ) -> Result<OutputReport, OutputError> {
                self.0.lock().unwrap().extend(last.map(|s| s.step));
                Ok(OutputReport::new("steps", &(), None))
            }
        }
        /// The view's sampler, fed after every step.
        struct View(FrameSampler, Vec<u64>);
        impl Progress for View {
            fn step(&mut self, sim: &Simulation) {
                self.1.extend(self.0.due(sim).map(|f| f.step));
            }
        }
        let frames = 10;
        let mut sim = pull_off(2, &["end_time=0.02"]);
        let cadence = Cadence::PerSimSecond(frames as f64 / sim.model.end_time);
        let steps = Arc::new(Mutex::new(vec![]));
        let out: Vec<Box<dyn Output>> = vec![Box::new(Steps(steps.clone()))];
        let started = std::time::Instant::now();
        let driver = Driver::with_outputs(out, cadence, &sim, started).unwrap();
        let mut sampler = FrameSampler::new(&sim, frames);
        let first = sampler.due(&sim).map(|f| f.step);
        let mut view = View(sampler, first.into_iter().collect());
        let done = driver.run(&mut sim, &AtomicBool::new(false), &mut view);
        assert!(done.outcome.is_ok());
        view.1.extend(view.0.last(&sim).map(|f| f.step));
        let steps = steps.lock().unwrap().clone();
        assert!(steps.len() >= 11, "{steps:?}");
        assert_eq!(view.1, steps);
    }

    /// The recorder's cadence over a whole run: t = 0, then every end_time/frames, then the
    /// end; and a cadence that would exceed [`MAX_RUN_BYTES`] is made coarser.
    #[test]
    fn sampler_cadence_and_memory_cap() {
        let mut sim = pull_off(2, &["end_time=0.02"]);
        let mut s = FrameSampler::new(&sim, 10);
        let mut times = vec![];
        times.extend(s.due(&sim).map(|f| f.time));
        while sim.state.time < sim.model.end_time - 1e-6 * sim.state.h {
            sim.step().unwrap();
            times.extend(s.due(&sim).map(|f| f.time));
        }
        times.extend(s.last(&sim).map(|f| f.time));
        assert!(s.last(&sim).is_none(), "the last frame is given once");
        assert!((11..=12).contains(&times.len()), "{times:?}");
        assert_eq!(times[0], 0.0);
        for w in times.windows(2) {
            // One frame per interval, within a step of its multiple of the interval.
            assert!(w[1] - w[0] <= s.interval + sim.state.h, "{times:?}");
        }
        let big = FrameSampler::new(&sim, u32::MAX);
        // t = 0, one a full interval, the final state.
        let frames = (sim.model.end_time / big.interval).round() as usize + 2;
        let bytes = FrameBuilder::new(&sim).frame_bytes(&sim);
        assert!(
            frames * bytes <= MAX_RUN_BYTES,
            "{frames} frames of {bytes} bytes"
        );
    }
}
