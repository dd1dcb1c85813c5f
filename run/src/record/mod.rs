//! Recording a run to Rerun, live (a spawned or running viewer) or into an `.rrd` file.
//!
//! This module reads a [`Simulation`] and turns it into Rerun entities; the physics modules
//! (`mesh`, `material`, `law`, `solver`, `energy`) know nothing of it.
//!
//! # Timelines
//! `step` (sequence: the step count n) and `sim_time` (duration: tₙ in seconds).
//!
//! # Entity paths (stable; the user documentation lists them with units)
//! | path | archetype | when |
//! |---|---|---|
//! | `scene/file`, `scene/resolved` | TextDocument | static |
//! | `body/surface` | Mesh3D: triangles static, positions and vertex colours per frame | frame |
//! | `body/legend` | TextDocument: field, colormap, range | frame |
//! | `planes/<name>` | each mould at t = 0, Mesh3D (static): a half-space as a square around the body's bounding box, a box, sphere, capped cylinder or triangulated surface as its mesh; Transform3D per frame when it moves (translation; its 3×3 rotation when it turns) | static / frame |
//! | `interface` | AnnotationContext: 0 elastic, 1 transition, 2 ruptured, 10 open, 11 stick, 12 slip | static |
//! | `interface/nodes` | Points3D, class = state; `alpha_m`, `gap_m` per node (hover) | frame |
//! | `interface/contact_status` | Points3D, class = open / stick / slip | frame |
//! | `interface/cohesive_traction` | Arrows3D: −R_d on the solid [Pa] × arrow scale | frame |
//! | `interface/contact_pressure` | Arrows3D: R_c / h [Pa] × arrow scale | frame |
//! | `interface/contact_normal` | Arrows3D at the nodes in contact (stick, slip): the mould's outward unit normal there × [`NORMAL_FRACTION`] of the body's extent, class = status | frame |
//! | `contact/nodes`, `contact/pressure`, `contact/normal` | the same for contact-only faces | frame |
//! | `energy` | Scalars [J], one named series per ledger term (model §5.1; hourglass with one-point integration) and the residual | frame |
//! | `energy/mould_friction` | Scalars [J]: friction dissipated on each mould (several moulds) | frame |
//! | `balance/relative_residual` | Scalars: residual / largest energy seen | frame |
//! | `reaction/<faces>_<axis>` | Scalars [N]: reaction of a prescribed displacement | frame |
//! | `reaction/mould_<name>` | Scalars [N]: force of the body on a moving mould over the last step | frame |
//! | `mould_moment/<name>` | Scalars [N·m]: its moment about a turning mould's pivot | frame |
//! | `imposed_displacement/<faces>_<axis>` | Scalars [m] | frame |
//! | `plots/reaction_vs_displacement` | LineStrips2D: (U [mm], F [kN], y up as −y) | frame |
//! | `interface/count` | Scalars: elastic, transition, ruptured node counts (paper fig. 6 right) | frame |
//! | `interface/alpha` | Scalars [m]: α of every node (≤ 64 nodes) or min/mean/max | frame |
//! | `time_step` | Scalars [s]: h and h_crit | frame |
//! | `timing` | Scalars [µs per step] per stage, averaged since the previous frame (`logging` = the solver thread's time on the outputs, `logger_thread` = the recorder's thread) | frame |
//! | `body/colour_range` | Scalars: min and max of the colour field so far | frame |
//! | `law/<faces>/...` | LineStrips2D: g_N(α)/g_N(0) and T(δ)/T_max against α/u_r, δ/u_r | static |
//! | `nodes/<N>/jump` | Scalars [m]: the jump [u] of a watched interface node (`run --watch`), x, y, z | frame |
//! | `nodes/<N>/traction` | Scalars [Pa]: on the solid, the glue's −R_d (x, y, z; interface nodes) and the contact's R_c/h (x, y, z) | frame |
//! | `nodes/<N>/alpha`, `nodes/<N>/gap` | Scalars [m]: damage α (interface nodes), gap g | frame |
//! | `nodes/<N>/status` | Scalars: the state's code (0 elastic, 1 transition, 2 ruptured, 3 unformed; interface nodes) and the contact status's (0 open, 1 stick, 2 slip) | frame |
//! | `nodes/<N>/log` | TextLog: the state and the contact status by name, at the first frame and at each change | frame |
//! | `run/status`, `run/log` | TextDocument, TextLog: completed / failed / cancelled and why | end |
//!
//! `<N>` is the node's index (0-based), or `<N>/<mould>` for each of the entries of a node
//! glued or in contact on several moulds ([`crate::output::watch`]).
//!
//! # Modules
//! [`stream`] (the Rerun stream: sink, columnar buffering, flushing), [`geometry`] (the
//! per-frame geometry: surface, colours, nodes, arrows), [`layout`] (the static layout: entity
//! names, blueprint, annotation context, law curves), [`eye`] (the 3-D view's default eye,
//! placed from the scene and sent in the blueprint), [`logger`] (the logger thread),
//! [`frontier`] (the speed–accuracy study's own recording).
//!
//! # Threads
//! The run driver ([`crate::driver`]) copies a [`Snapshot`] of the state once per frame and
//! hands it to every output; the [`Recorder`] passes it to a logger thread over a bounded
//! channel ([`crate::output::worker`]); the logger thread builds the Rerun entities (Arrow
//! arrays built directly from flat buffers) and the SDK's own threads encode and write them,
//! all at a lower priority than the solver. A slow sink applies back-pressure once
//! [`QUEUE_BYTES`] of frames wait, instead of dropping any.
//!
//! Frames are buffered and sent as columns (`send_columns`, one chunk per entity) every
//! [`FLUSH_ROWS`] frames, [`FLUSH_BYTES`] or at most [`FLUSH_WALL`] of wall time, and always before the
//! file is closed, so a live viewer lags at most that much and nothing is lost when a run fails.
//! The reaction–displacement curve is re-sent whole at each flush.

pub mod eye;
mod frontier;
mod geometry;
mod layout;
mod logger;
mod stream;

pub use crate::output::{Cadence, InterfaceSnapshot, Snapshot, DEFAULT_FRAMES, QUEUE_BYTES};
pub use frontier::log_frontier;
pub use layout::{default_blueprint, recording_name};
pub use stream::find_on_path;

use crate::model::Model;
use crate::output::reports::{RecordError, RecordingReport};
use crate::output::watch::Watch;
use crate::output::worker::Worker;
use crate::output::{Ending, Output, OutputError, OutputReport};
use crate::scene::Scene;
use crate::solver::{Simulation, SolverError};
use logger::LoggerEnd;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Application id of every recording.
pub const APPLICATION_ID: &str = "decohesion";
pub use crate::tunables::ALPHA_PER_NODE_MAX;
pub use crate::tunables::ARROW_FRACTION;
pub use crate::tunables::NORMAL_FRACTION;
pub use crate::tunables::RECORD_FLUSH_BYTES as FLUSH_BYTES;
pub use crate::tunables::RECORD_FLUSH_ROWS as FLUSH_ROWS;
pub use crate::tunables::RECORD_FLUSH_WALL as FLUSH_WALL;
/// Version of the Rerun viewer that reads our files (same as the SDK).
pub const RERUN_VERSION: &str = "0.36.3";

/// Where the recording goes.
#[derive(Debug, Clone)]
pub enum Sink {
    /// An `.rrd` file.
    Save(PathBuf),
    /// A Rerun viewer started from PATH, listening on 127.0.0.1 only.
    Spawn,
    /// A running viewer at this URL (default `rerun+http://127.0.0.1:9876/proxy`).
    Connect(Option<String>),
}

/// The field that colours the body surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColourField {
    /// |U| [m], nodal.
    #[default]
    Displacement,
    /// Von Mises stress of the Cauchy stress at element centres, averaged to the nodes [Pa].
    VonMises,
    /// J = det F at element centres, averaged to the nodes [-].
    Jacobian,
}

impl std::str::FromStr for ColourField {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "displacement" => Ok(ColourField::Displacement),
            "von_mises" => Ok(ColourField::VonMises),
            "jacobian" => Ok(ColourField::Jacobian),
            _ => Err(format!(
                "unknown colour field `{s}`; admissible: displacement, von_mises, jacobian"
            )),
        }
    }
}

impl ColourField {
    fn label(self) -> (&'static str, &'static str) {
        match self {
            ColourField::Displacement => ("displacement magnitude |U|", "m"),
            ColourField::VonMises => ("von Mises stress (Cauchy)", "Pa"),
            ColourField::Jacobian => ("volume ratio J = det F", "-"),
        }
    }
}

fn log_err(what: &str) -> impl FnOnce(rerun::RecordingStreamError) -> RecordError + '_ {
    move |source| RecordError::Log {
        what: what.to_string(),
        source,
    }
}

/// What the solver side sends to the logger thread.
enum Msg {
    Frame(Arc<Snapshot>),
    Finish {
        snapshot: Option<Arc<Snapshot>>,
        status: &'static str,
        text: String,
        level: &'static str,
    },
}

/// Records a running [`Simulation`] to Rerun: an [`Output`] of the run driver, which feeds it
/// the frames and finishes it whatever the outcome; the recording is then complete.
pub struct Recorder {
    worker: Worker<Msg, LoggerEnd, RecordError>,
    sink: Sink,
    frames: u64,
}

/// Frames that may wait for the logger thread: [`QUEUE_BYTES`] worth of snapshots, at least
/// one. (At least 4 held four whole frames of a 10⁶-element body, whose snapshot alone exceeds
/// the budget; the logger takes a small share of such a run, so one waiting frame keeps up;
/// docs: performance log.)
/// Counted with V, as the frames carry it when the run also writes ParaView files.
fn queue_frames(sim: &Simulation) -> usize {
    (QUEUE_BYTES / Snapshot::bytes(sim)).clamp(1, 4096)
}

impl Recorder {
    /// Starts the logger thread, which opens the sink and logs everything static (scene text,
    /// annotation context, surface topology, planes, law curves, series styles; the blueprint
    /// goes with the stream) while the solver starts. A file that cannot be written is reported
    /// here; a sink that cannot be opened otherwise (no viewer executable, a malformed URL) by
    /// the first frames at the latest.
    pub fn new(
        sink: Sink,
        scene: &Scene,
        sim: &Simulation,
        colour: ColourField,
        id: Option<String>,
        watch: &Watch,
    ) -> Result<Recorder, RecordError> {
        let started = Instant::now();
        if let Sink::Save(path) = &sink {
            // Fail now, not a few steps into the run, when the file cannot be written.
            std::fs::File::create(path).map_err(|e| {
                RecordError::Setup(format!(
                    "cannot write the recording {}: {e}",
                    path.display()
                ))
            })?;
        }
        let statics = Statics {
            model: sim.model.clone(),
            file: scene.file.clone(),
            text: scene.text.clone(),
            resolved: scene.resolved.clone(),
            h: sim.state.h,
            h_crit: sim.state.h_crit,
            interface_nodes: sim
                .state
                .interface_nodes
                .iter()
                .map(|n| (n.node, n.interface))
                .collect(),
            contact_nodes: sim
                .state
                .contact_nodes
                .iter()
                .map(|n| (n.node, n.plane))
                .collect(),
            advisories: sim.advisories(),
            watch: watch.clone(),
        };
        let name = recording_name(sim);
        let thread_sink = sink.clone();
        let thread_error = |what: &str| RecordError::Setup(format!("the recorder thread {what}"));
        let mut worker = Worker::spawn(
            "decohesion-recorder",
            queue_frames(sim),
            thread_error,
            move |rx| logger::run(rx, thread_sink, name, id, statics, colour),
        )?;
        worker.charge(started.elapsed());
        Ok(Recorder {
            worker,
            sink,
            frames: 0,
        })
    }
}

impl Output for Recorder {
    /// Sends one frame to the logger thread; when that thread has stopped, its error.
    fn frame(&mut self, snapshot: &Arc<Snapshot>) -> Result<(), OutputError> {
        self.frames += 1;
        let frame = Msg::Frame(snapshot.clone());
        Ok(self.worker.send(frame, snapshot.capture_time)?)
    }

    /// Sends the last state (if not sent yet) and the outcome, waits until everything is
    /// written and the sink closed: the file is complete and readable whatever the outcome.
    fn finish(
        self: Box<Self>,
        last: Option<Arc<Snapshot>>,
        end: &Ending<'_>,
    ) -> Result<OutputReport, OutputError> {
        let Recorder {
            worker,
            sink,
            mut frames,
        } = *self;
        let capture = last.as_ref().map_or(Duration::ZERO, |s| s.capture_time);
        frames += u64::from(last.is_some());
        let (status, text, level) = match end.error {
            None => (
                "completed",
                format!(
                    "Run completed: {} steps to t = {:.6} s.",
                    end.step, end.time
                ),
                "INFO",
            ),
            Some(e @ SolverError::Cancelled { .. }) => ("cancelled", e.to_string(), "WARN"),
            Some(e) => ("failed", e.to_string(), "ERROR"),
        };
        let finish = Msg::Finish {
            snapshot: last,
            status,
            text,
            level,
        };
        let (logged, solver_time) = worker.finish(Some(finish), capture)?;
        let (sink, path, bytes) = match &sink {
            Sink::Save(p) => (
                "file",
                Some(p.display().to_string()),
                std::fs::metadata(p).ok().map(|m| m.len()),
            ),
            Sink::Spawn => ("spawn", None, None),
            Sink::Connect(_) => ("connect", None, None),
        };
        let report = RecordingReport {
            sink: sink.into(),
            path,
            frames,
            logging_seconds: solver_time.as_secs_f64(),
            logger_thread_seconds: logged.busy.as_secs_f64(),
            bytes,
        };
        let line = report.line(end.step_seconds);
        Ok(OutputReport::new("recording", &report, Some(line)))
    }
}

/// What the logger thread needs to know of the run, owned.
struct Statics {
    /// The simulation's model, shared, not copied (58 MB at 10⁶ elements).
    model: Arc<Model>,
    file: String,
    text: String,
    resolved: String,
    h: f64,
    h_crit: f64,
    /// (node, interface index) of each interface node.
    interface_nodes: Vec<(u32, u32)>,
    /// (node, mould index) of each contact-only node.
    contact_nodes: Vec<(u32, u32)>,
    /// [`Simulation::advisories`]: warnings about the regime of the model.
    advisories: Vec<String>,
    /// The watched nodes (`run --watch`): a snapshot's `watched` readings, in this order.
    watch: Watch,
}
