//! Recording a run to Rerun, live (a spawned or running viewer) or into an `.rrd` file.
//!
//! This module reads a [`Simulation`] and turns it into Rerun entities; the physics modules
//! (`mesh`, `material`, `law`, `solver`, `energy`) know nothing of it.
//!
//! # Timelines
//! `step` (sequence: the step count n) and `sim_time` (duration: tₙ in seconds).
//!
//! # Entity paths (stable; the README lists them with units)
//! | path | archetype | when |
//! |---|---|---|
//! | `scene/file`, `scene/resolved` | TextDocument | static |
//! | `body/surface` | Mesh3D: triangles static, positions and vertex colours per frame | frame |
//! | `body/legend` | TextDocument: field, colormap, range | frame |
//! | `planes/<name>` | Mesh3D quad (static) + Transform3D when the plane moves | static / frame |
//! | `interface` | AnnotationContext: 0 elastic, 1 transition, 2 ruptured, 10 open, 11 stick, 12 slip | static |
//! | `interface/nodes` | Points3D, class = state; `alpha_m`, `gap_m` per node (hover) | frame |
//! | `interface/contact_status` | Points3D, class = open / stick / slip | frame |
//! | `interface/cohesive_traction` | Arrows3D: −R_d on the solid [Pa] × arrow scale | frame |
//! | `interface/contact_pressure` | Arrows3D: R_c / h [Pa] × arrow scale | frame |
//! | `contact/nodes`, `contact/pressure` | the same for contact-only faces | frame |
//! | `energy` | Scalars [J], one named series per ledger term (PHYSICS.md §5; hourglass with one-point integration) and the residual | frame |
//! | `balance/relative_residual` | Scalars: residual / largest energy seen | frame |
//! | `reaction/<faces>_<axis>` | Scalars [N]: reaction of a prescribed displacement | frame |
//! | `imposed_displacement/<faces>_<axis>` | Scalars [m] | frame |
//! | `plots/reaction_vs_displacement` | LineStrips2D: (U [mm], F [kN], y up as −y) | frame |
//! | `interface/count` | Scalars: elastic, transition, ruptured node counts (paper fig. 6 right) | frame |
//! | `interface/alpha` | Scalars [m]: α of every node (≤ 64 nodes) or min/mean/max | frame |
//! | `time_step` | Scalars [s]: h and h_crit | frame |
//! | `timing` | Scalars [µs per step] per stage, averaged since the previous frame (`logging` = solver thread, `logger_thread` = the recorder's thread) | frame |
//! | `body/colour_range` | Scalars: min and max of the colour field so far | frame |
//! | `law/<faces>/...` | LineStrips2D: g_N(α)/g_N(0) and T(δ)/T_max against α/u_r, δ/u_r | static |
//! | `run/status`, `run/log` | TextDocument, TextLog: completed / failed / cancelled and why | end |
//!
//! # Threads
//! The solver thread only copies a [`Snapshot`] of the state (a memcpy of U and of the
//! interface state) and hands it to a logger thread over a bounded channel; the logger thread
//! builds the Rerun entities (Arrow arrays built directly from flat buffers) and the SDK's own
//! threads encode and write them, all at a lower priority than the solver. A slow sink applies
//! back-pressure once [`QUEUE_BYTES`] of frames wait, instead of dropping any.
//!
//! Frames are buffered and sent as columns (`send_columns`, one chunk per entity) every
//! [`FLUSH_ROWS`] frames, [`FLUSH_BYTES`] or at most [`FLUSH_WALL`] of wall time, and always before the
//! file is closed, so a live viewer lags at most that much and nothing is lost when a run fails.
//! The reaction–displacement curve is re-sent whole at each flush.

use crate::energy::EnergySnapshot;
use crate::law::InterfaceState;
use crate::mesh::{cross, dot, norm, sub};
use crate::model::Model;
// When frames are taken: shared with the ParaView output (crate::vtk).
use crate::output::{lower_thread_priority, FrameClock};
pub use crate::output::{Cadence, DEFAULT_FRAMES};
use crate::scene::Scene;
use crate::solver::{ContactStatus, Simulation, SolverError, StageTimes, StateCounts};
use rerun::blueprint::components::{PanelState, PlayState};
use rerun::blueprint::{
    Blueprint, BlueprintPanel, Horizontal, SelectionPanel, Spatial2DView, Spatial3DView, Tabs,
    TextDocumentView, TimePanel, TimeSeriesView, Vertical,
};
use rerun::external::arrow::array::{
    Array, FixedSizeListArray, Float32Array, Float64Array, ListArray, UInt16Array, UInt32Array,
};
use rerun::external::arrow::buffer::OffsetBuffer;
use rerun::external::arrow::datatypes::{DataType, Field};
use rerun::{
    AnnotationContext, Arrows3D, LineStrips2D, Mesh3D, Points2D, Points3D, RecordingStream,
    RecordingStreamBuilder, Rgba32, Scalars, SeriesLines, TextDocument, TextLog, TimeColumn,
    Transform3D,
};
use rerun::{ComponentDescriptor, SerializedComponentBatch};
use std::path::PathBuf;
use std::sync::mpsc::{sync_channel, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Application id of every recording.
pub const APPLICATION_ID: &str = "decohesion";
/// Buffered frames are sent at least every this many frames…
pub const FLUSH_ROWS: usize = 1000;
/// …or when they take this much memory [bytes]…
pub const FLUSH_BYTES: usize = 16 << 20;
/// …or after a tenth of the wall time the run has taken so far, between 10 ms and this (the
/// lag of a live viewer): short runs encode beside the solver rather than all at the end,
/// long runs do not make thousands of small chunks.
pub const FLUSH_WALL: Duration = Duration::from_millis(500);
const FLUSH_WALL_MIN: Duration = Duration::from_millis(10);
/// Interfaces with at most this many nodes get one α(t) series per node (paper fig. 6 left).
pub const ALPHA_PER_NODE_MAX: usize = 64;
/// Longest arrow, drawn for the peak traction T_max of the law, as a fraction of the body's
/// largest extent.
pub const ARROW_FRACTION: f64 = 0.2;
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

/// What was recorded, for the run summary.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct RecordingReport {
    /// "file", "spawn" or "connect".
    pub sink: String,
    pub path: Option<String>,
    /// Frames logged (3-D state + one row of every scalar series).
    pub frames: u64,
    /// Wall time the solver thread spent on recording: snapshots, waiting on a full queue,
    /// and waiting at the end until the file was complete [s].
    pub logging_seconds: f64,
    /// Busy time of the logger thread, which runs beside the solver [s].
    pub logger_thread_seconds: f64,
    /// Size of the file [bytes] (file sink only).
    pub bytes: Option<u64>,
}

/// Errors of the recorder (the SDK's, with what we were doing).
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("{0}")]
    Setup(String),
    #[error("logging {what}: {source}")]
    Log {
        what: String,
        #[source]
        source: rerun::RecordingStreamError,
    },
}

fn log_err(what: &str) -> impl FnOnce(rerun::RecordingStreamError) -> RecordError + '_ {
    move |source| RecordError::Log {
        what: what.to_string(),
        source,
    }
}

/// Flat values of one component over the buffered frames.
enum Flat {
    /// f32 values, `width` per instance (1, 2 or 3: scalars, 2-D or 3-D vectors).
    F32(Vec<f32>, i32),
    F64(Vec<f64>),
    U32(Vec<u32>),
    U16(Vec<u16>),
}

/// One component of one entity, over the buffered frames.
struct Column {
    path: String,
    descriptor: ComponentDescriptor,
    data: Flat,
    /// Instances per frame.
    lengths: Vec<usize>,
}

impl Column {
    fn array(
        self,
    ) -> (
        String,
        ComponentDescriptor,
        Vec<usize>,
        rerun::external::arrow::array::ArrayRef,
    ) {
        let array: rerun::external::arrow::array::ArrayRef = match self.data {
            Flat::F32(v, 1) => Arc::new(Float32Array::from(v)),
            Flat::F32(v, w) => {
                let item = Arc::new(Field::new("item", DataType::Float32, false));
                Arc::new(FixedSizeListArray::new(
                    item,
                    w,
                    Arc::new(Float32Array::from(v)),
                    None,
                ))
            }
            Flat::F64(v) => Arc::new(Float64Array::from(v)),
            Flat::U32(v) => Arc::new(UInt32Array::from(v)),
            Flat::U16(v) => Arc::new(UInt16Array::from(v)),
        };
        (self.path, self.descriptor, self.lengths, array)
    }
}

/// Frames buffered on the logger thread and sent as columns (`send_columns`): one chunk per
/// entity per flush instead of one row per entity per frame, which is what keeps the cost of a
/// frame to a few memcpys.
#[derive(Default)]
struct Columns {
    steps: Vec<i64>,
    times: Vec<f64>,
    columns: Vec<Column>,
    bytes: usize,
}

impl Columns {
    fn column(&mut self, path: &str, descriptor: ComponentDescriptor, empty: Flat) -> &mut Column {
        let i = match self
            .columns
            .iter()
            .position(|c| c.path == path && c.descriptor == descriptor)
        {
            Some(i) => i,
            None => {
                self.columns.push(Column {
                    path: path.to_string(),
                    descriptor,
                    data: empty,
                    lengths: Vec::new(),
                });
                self.columns.len() - 1
            }
        };
        &mut self.columns[i]
    }

    /// Appends one frame's instances of an f32 component (`width` values each).
    fn f32s(&mut self, path: &str, descriptor: ComponentDescriptor, width: i32, values: &[f32]) {
        self.bytes += 4 * values.len();
        let c = self.column(path, descriptor, Flat::F32(Vec::new(), width));
        if let Flat::F32(v, _) = &mut c.data {
            v.extend_from_slice(values);
        }
        c.lengths.push(values.len() / width as usize);
    }

    fn f64s(&mut self, path: &str, descriptor: ComponentDescriptor, values: &[f64]) {
        self.bytes += 8 * values.len();
        let c = self.column(path, descriptor, Flat::F64(Vec::new()));
        if let Flat::F64(v) = &mut c.data {
            v.extend_from_slice(values);
        }
        c.lengths.push(values.len());
    }

    /// One row of a Scalars entity.
    fn scalars(&mut self, path: &str, values: &[f64]) {
        self.f64s(path, Scalars::descriptor_scalars(), values);
    }

    fn u32s(&mut self, path: &str, descriptor: ComponentDescriptor, values: &[u32]) {
        self.bytes += 4 * values.len();
        let c = self.column(path, descriptor, Flat::U32(Vec::new()));
        if let Flat::U32(v) = &mut c.data {
            v.extend_from_slice(values);
        }
        c.lengths.push(values.len());
    }

    fn u16s(&mut self, path: &str, descriptor: ComponentDescriptor, values: &[u16]) {
        self.bytes += 2 * values.len();
        let c = self.column(path, descriptor, Flat::U16(Vec::new()));
        if let Flat::U16(v) = &mut c.data {
            v.extend_from_slice(values);
        }
        c.lengths.push(values.len());
    }
}

/// Viridis, 9 samples (matplotlib), interpolated linearly.
fn viridis(t: f64) -> [u8; 3] {
    const C: [[f64; 3]; 9] = [
        [68.0, 1.0, 84.0],
        [71.0, 44.0, 122.0],
        [59.0, 81.0, 139.0],
        [44.0, 113.0, 142.0],
        [33.0, 144.0, 141.0],
        [39.0, 173.0, 129.0],
        [92.0, 200.0, 99.0],
        [170.0, 220.0, 50.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * 8.0;
    let i = (x.floor() as usize).min(7);
    let f = x - i as f64;
    let c = |k: usize| (C[i][k] * (1.0 - f) + C[i + 1][k] * f).round() as u8;
    [c(0), c(1), c(2)]
}

/// A name usable as one entity path part: `z+` → `z_plus`.
fn path_part(s: &str) -> String {
    let mut out = String::new();
    for ch in s.chars() {
        match ch {
            '+' => out.push_str("_plus"),
            '-' => out.push_str("_minus"),
            c if c.is_ascii_alphanumeric() || c == '_' => out.push(c),
            _ => out.push('_'),
        }
    }
    out
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The ledger terms logged as the instances of `energy` [J], in this order.
const ENERGY_TERMS: [&str; 13] = [
    "kinetic",
    "strain",
    "hourglass",
    "interface_stored",
    "damage_dissipated",
    "contact_normal_dissipated",
    "friction_dissipated",
    "external_work",
    "gravity_work",
    "traction_work",
    "reaction_work",
    "plane_work",
    "residual",
];

/// Stages logged as the instances of `timing` [µs per step], in this order.
const STAGES: [&str; 8] = [
    "positions",
    "internal_forces",
    "interface_contact",
    "free_velocity",
    "bookkeeping",
    "h_crit",
    "logging",
    "logger_thread",
];

/// The recording name: scene name and the parameters a reader compares runs by.
pub fn recording_name(sim: &Simulation) -> String {
    let m = &sim.model;
    let mut name = format!(
        "{} · {} hex8 · {:?} E={:.3e} Pa ν={}",
        m.name,
        m.mesh.elements.len(),
        m.material.model,
        m.material.young,
        m.material.poisson
    );
    for itf in &m.interfaces {
        let fam = match &itf.law.family {
            crate::law::LawFamily::PlateauLinear => "plateau_linear".to_string(),
            crate::law::LawFamily::Bilinear => "bilinear".to_string(),
            crate::law::LawFamily::Exponential { decay } => format!("exponential({decay})"),
            crate::law::LawFamily::Table { .. } => "table".to_string(),
        };
        name.push_str(&format!(
            " · {fam} g_N0={:.3e} α_e={:.3e} u_r={:.3e} μ_inf={}",
            itf.law.g_n0, itf.law.alpha_e, itf.law.u_r, itf.mu_inf
        ));
    }
    name.push_str(&format!(" · h={}·h_crit", m.scheme.time_step_factor));
    name
}

/// The SDK batches logged rows into chunks on its own thread. Its default for files (a tick of
/// 200 ms) leaves a short run's whole encoding to the final flush, on the solver's clock; a
/// 20 ms tick spreads it over the run, beside the solver.
fn batcher_config() -> rerun::log::ChunkBatcherConfig {
    rerun::log::ChunkBatcherConfig {
        flush_tick: Duration::from_millis(20),
        ..rerun::log::ChunkBatcherConfig::DEFAULT
    }
}

/// Opens the Rerun stream for a sink (errors are the user's: a file that cannot be written,
/// no viewer executable, a malformed URL).
fn open_stream(sink: &Sink, name: String) -> Result<RecordingStream, RecordError> {
    let builder = RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(name)
        .with_blueprint(default_blueprint())
        .batcher_config(batcher_config());
    match sink {
        Sink::Save(path) => builder.save(path).map_err(|e| {
            RecordError::Setup(format!(
                "cannot write the recording {}: {e}",
                path.display()
            ))
        }),
        Sink::Spawn => {
            if find_on_path("rerun").is_none() {
                return Err(RecordError::Setup(format!(
                    "--spawn needs the Rerun viewer executable `rerun` on PATH, and it is not there. \
                     Install the same version as this build: `pip install rerun-sdk=={RERUN_VERSION}` \
                     (in a virtual environment whose bin/ is on PATH), or record to a file with \
                     --save FILE.rrd and open it later with `rerun FILE.rrd`"
                )));
            }
            let opts = rerun::SpawnOptions {
                // The viewer's gRPC server would listen on 0.0.0.0 by default.
                extra_args: vec!["--bind".into(), "127.0.0.1".into()],
                ..Default::default()
            };
            builder
                .spawn_opts(&opts)
                .map_err(|e| RecordError::Setup(format!("could not start the Rerun viewer: {e}")))
        }
        Sink::Connect(url) => {
            let url = url
                .clone()
                .unwrap_or_else(|| "rerun+http://127.0.0.1:9876/proxy".to_string());
            builder.connect_grpc_opts(url.clone()).map_err(|e| {
                RecordError::Setup(format!(
                    "cannot connect to a Rerun viewer at {url}: {e} \
                     (expected a URL like rerun+http://127.0.0.1:9876/proxy)"
                ))
            })
        }
    }
}

/// Is an executable called `name` on PATH?
pub fn find_on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// The default layout: 3-D view on the left; energies and state counts on the right, with
/// reactions, α(t), the law, the time step, timings and the scene text in tabs below.
pub fn default_blueprint() -> Blueprint {
    Blueprint::new(Horizontal::new([
        Spatial3DView::new("body and interface")
            .with_origin("/")
            .with_contents(["/body/**", "/planes/**", "/interface/**", "/contact/**"])
            .into(),
        Vertical::new([
            TimeSeriesView::new("energy [J]")
                .with_origin("/energy")
                .into(),
            TimeSeriesView::new("interface nodes: elastic / transition / ruptured")
                .with_origin("/interface/count")
                .into(),
            Tabs::new([
                TimeSeriesView::new("reaction [N]")
                    .with_origin("/reaction")
                    .into(),
                TimeSeriesView::new("imposed displacement [m]")
                    .with_origin("/imposed_displacement")
                    .into(),
                TimeSeriesView::new("balance residual / largest energy")
                    .with_origin("/balance")
                    .into(),
                Spatial2DView::new("reaction vs displacement (mm, kN)")
                    .with_origin("/plots")
                    .into(),
                TimeSeriesView::new("damage α [m]")
                    .with_origin("/interface/alpha")
                    .into(),
                Spatial2DView::new("stiffness law")
                    .with_origin("/law")
                    .into(),
                TimeSeriesView::new("time step [s]")
                    .with_origin("/time_step")
                    .into(),
                TimeSeriesView::new("wall time per step [µs]")
                    .with_origin("/timing")
                    .into(),
                TextDocumentView::new("scene").with_origin("/scene").into(),
                TextDocumentView::new("run").with_origin("/run").into(),
            ])
            .into(),
        ])
        .into(),
    ]))
    // Follow the run as it arrives (live), i.e. open a file at its last frame.
    .with_time_panel(
        TimePanel::new()
            .with_timeline("sim_time")
            .with_play_state(PlayState::Following)
            .with_state(PanelState::Collapsed),
    )
    .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
    .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
}

/// The state of a simulation at one step, copied on the solver thread for the logger thread.
#[derive(Debug, Clone)]
pub struct Snapshot {
    pub step: u64,
    /// tₙ [s].
    pub time: f64,
    pub h: f64,
    pub h_crit: f64,
    /// Uₙ of every node [m].
    pub u: Vec<[f64; 3]>,
    pub interface: Vec<InterfaceSnapshot>,
    /// Contact status and impulse per unit area [Pa·s] of the contact-only nodes.
    pub contact: Vec<(ContactStatus, [f64; 3])>,
    pub energies: EnergySnapshot,
    /// Reaction of each prescribed-displacement condition [N].
    pub reactions: Vec<f64>,
    pub counts: StateCounts,
    pub stages: StageTimes,
    /// Solver-thread time spent on recording so far [s].
    pub solver_logging: f64,
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
    /// Copies what a frame shows (O(nodes) memcpy).
    pub fn capture(sim: &Simulation, solver_logging: Duration) -> Snapshot {
        Snapshot {
            step: sim.step_count,
            time: sim.time,
            h: sim.h,
            h_crit: sim.h_crit,
            u: sim.u.clone(),
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
            energies: sim.energies(),
            reactions: sim.stats.reactions.clone(),
            counts: sim.state_counts(),
            stages: sim.stats.stage_times.clone(),
            solver_logging: solver_logging.as_secs_f64(),
        }
    }
}

enum Msg {
    Frame(Box<Snapshot>),
    Finish {
        snapshot: Option<Box<Snapshot>>,
        status: &'static str,
        text: String,
        level: &'static str,
    },
}

/// What the logger thread reports when it ends.
struct LoggerEnd {
    busy: Duration,
}

/// Records a running [`Simulation`]: decides when a frame is due, copies a [`Snapshot`] and
/// sends it to the logger thread. Build it once the simulation is set up, call
/// [`Recorder::on_step`] after every step and [`Recorder::finish`] at the end, whatever the
/// outcome: the recording is then complete.
pub struct Recorder {
    tx: Option<SyncSender<Msg>>,
    thread: Option<JoinHandle<Result<LoggerEnd, RecordError>>>,
    sink: Sink,
    clock: FrameClock,
    /// Solver-thread time spent recording (snapshots, waiting on a full queue, final wait).
    solver_time: Duration,
}

/// Memory that frames waiting for the logger thread may take before the solver waits
/// (back-pressure) [bytes].
pub const QUEUE_BYTES: usize = 64 << 20;

/// Frames that may wait for the logger thread: [`QUEUE_BYTES`] worth of snapshots, at least 4.
fn queue_frames(sim: &Simulation) -> usize {
    let bytes = 24 * sim.u.len() + 96 * (sim.interface_nodes.len() + sim.contact_nodes.len()) + 512;
    (QUEUE_BYTES / bytes).clamp(4, 4096)
}

impl Recorder {
    /// Starts the logger thread, which opens the sink and logs everything static (scene text,
    /// annotation context, surface topology, planes, law curves, series styles; the blueprint
    /// goes with the stream) while the solver starts. A sink that cannot be opened (a file that
    /// cannot be written, no viewer executable, a malformed URL) is reported by the first
    /// [`Recorder::frame`] at the latest. Logs the current state as the first frame.
    pub fn new(
        sink: Sink,
        scene: &Scene,
        sim: &Simulation,
        cadence: Cadence,
        colour: ColourField,
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
        let m = &sim.model;
        let statics = Statics {
            model: m.clone(),
            file: scene.file.clone(),
            text: scene.text.clone(),
            resolved: scene.resolved.clone(),
            h: sim.h,
            h_crit: sim.h_crit,
            interface_nodes: sim
                .interface_nodes
                .iter()
                .map(|n| (n.node, n.interface))
                .collect(),
            contact_nodes: sim.contact_nodes.iter().map(|n| n.node).collect(),
            advisories: sim.advisories(),
        };
        let name = recording_name(sim);
        let thread_sink = sink.clone();
        let (tx, rx) = sync_channel::<Msg>(queue_frames(sim));
        let thread = std::thread::Builder::new()
            .name("decohesion-recorder".into())
            .spawn(move || -> Result<LoggerEnd, RecordError> {
                let started = Instant::now();
                // The recording must not slow the solve: this thread, and the SDK's batcher and
                // writer threads that it starts (they inherit it), yield the CPU to the solver.
                lower_thread_priority();
                // An error here ends the thread; the solver sees it at its next frame.
                let rec = open_stream(&thread_sink, name)?;
                let flush_network = !matches!(thread_sink, Sink::Save(_));
                let mut logger = Logger::new(rec, statics, colour)?;
                let mut busy = started.elapsed();
                while let Ok(msg) = rx.recv() {
                    let t = Instant::now();
                    match msg {
                        Msg::Frame(s) => logger.frame(&s, busy)?,
                        Msg::Finish {
                            snapshot,
                            status,
                            text,
                            level,
                        } => {
                            if let Some(s) = snapshot {
                                logger.frame(&s, busy)?;
                            }
                            logger.finish(status, &text, level, flush_network)?;
                            busy += t.elapsed();
                            break;
                        }
                    }
                    busy += t.elapsed();
                }
                Ok(LoggerEnd { busy })
            })
            .map_err(|e| RecordError::Setup(format!("cannot start the recorder thread: {e}")))?;
        let mut recorder = Recorder {
            tx: Some(tx),
            thread: Some(thread),
            sink,
            clock: FrameClock::new(cadence, m.end_time),
            solver_time: started.elapsed(),
        };
        // The state before the first step.
        recorder.frame(sim)?;
        Ok(recorder)
    }

    /// Called after every step: sends a frame when the cadence asks for one.
    pub fn on_step(&mut self, sim: &Simulation) -> Result<(), RecordError> {
        if self.clock.due(sim.step_count, sim.time) {
            self.frame(sim)?;
        }
        Ok(())
    }

    /// Sends the state of `sim` as one frame (once per step at most).
    pub fn frame(&mut self, sim: &Simulation) -> Result<(), RecordError> {
        let started = Instant::now();
        if !self.clock.take(sim.step_count, sim.time) {
            return Ok(());
        }
        let snap = Box::new(Snapshot::capture(sim, self.solver_time));
        let sent = self.tx.as_ref().map(|tx| tx.send(Msg::Frame(snap)));
        self.solver_time += started.elapsed();
        match sent {
            Some(Ok(())) => Ok(()),
            // The logger thread stopped: its error says why.
            _ => Err(self
                .join()
                .err()
                .unwrap_or_else(|| RecordError::Setup("the recorder thread stopped early".into()))),
        }
    }

    fn join(&mut self) -> Result<LoggerEnd, RecordError> {
        self.tx = None;
        match self.thread.take() {
            Some(t) => t
                .join()
                .unwrap_or_else(|_| Err(RecordError::Setup("the recorder thread panicked".into()))),
            None => Err(RecordError::Setup(
                "the recorder thread already ended".into(),
            )),
        }
    }

    /// Sends the last state (if not sent yet) and the outcome, waits until everything is
    /// written and the sink closed: the file is complete and readable whatever `outcome` was.
    pub fn finish(
        mut self,
        sim: &Simulation,
        outcome: Option<&SolverError>,
    ) -> Result<RecordingReport, RecordError> {
        let started = Instant::now();
        let snapshot = self
            .clock
            .take(sim.step_count, sim.time)
            .then(|| Box::new(Snapshot::capture(sim, self.solver_time)));
        let (status, text, level) = match outcome {
            None => (
                "completed",
                format!(
                    "Run completed: {} steps to t = {:.6} s.",
                    sim.step_count, sim.time
                ),
                "INFO",
            ),
            Some(e @ SolverError::Cancelled { .. }) => ("cancelled", e.to_string(), "WARN"),
            Some(e) => ("failed", e.to_string(), "ERROR"),
        };
        if let Some(tx) = &self.tx {
            // A closed channel means the thread ended with an error, reported by join().
            let _ = tx.send(Msg::Finish {
                snapshot,
                status,
                text,
                level,
            });
        }
        let end = self.join();
        self.solver_time += started.elapsed();
        let end = end?;
        let (sink, path, bytes) = match &self.sink {
            Sink::Save(p) => (
                "file",
                Some(p.display().to_string()),
                std::fs::metadata(p).ok().map(|m| m.len()),
            ),
            Sink::Spawn => ("spawn", None, None),
            Sink::Connect(_) => ("connect", None, None),
        };
        Ok(RecordingReport {
            sink: sink.into(),
            path,
            frames: self.clock.frames(),
            logging_seconds: self.solver_time.as_secs_f64(),
            logger_thread_seconds: end.busy.as_secs_f64(),
            bytes,
        })
    }

    /// Frames sent so far.
    pub fn frames(&self) -> u64 {
        self.clock.frames()
    }

    /// Solver-thread time spent recording so far.
    pub fn logging_time(&self) -> Duration {
        self.solver_time
    }
}

/// What the logger thread needs to know of the run, owned.
struct Statics {
    model: Model,
    file: String,
    text: String,
    resolved: String,
    h: f64,
    h_crit: f64,
    /// (node, interface index) of each interface node.
    interface_nodes: Vec<(u32, u32)>,
    contact_nodes: Vec<u32>,
    /// [`Simulation::advisories`]: warnings about the regime of the model.
    advisories: Vec<String>,
}

/// Line strips of (x, y) points as one `LineStrips2D::strips` batch, built straight into Arrow.
fn strips2d_batch(strips: &[Vec<[f32; 2]>]) -> SerializedComponentBatch {
    let flat: Vec<f32> = strips.iter().flatten().flatten().copied().collect();
    let point = Arc::new(Field::new("item", DataType::Float32, false));
    let points = FixedSizeListArray::new(point, 2, Arc::new(Float32Array::from(flat)), None);
    let item = Arc::new(Field::new("item", points.data_type().clone(), false));
    let offsets = OffsetBuffer::from_lengths(strips.iter().map(|s| s.len()));
    SerializedComponentBatch {
        descriptor: LineStrips2D::descriptor_strips(),
        array: Arc::new(ListArray::new(item, offsets, Arc::new(points), None)),
    }
}

fn rgba(c: [u8; 3]) -> u32 {
    u32::from_be_bytes([c[0], c[1], c[2], 255])
}

/// The logger thread's side: owns the stream and turns snapshots into entities.
struct Logger {
    rec: RecordingStream,
    st: Statics,
    colour: ColourField,
    last_flush: Instant,
    started: Instant,
    /// Global node index of each surface vertex.
    surface_nodes: Vec<u32>,
    /// Elements around each surface vertex (CSR: offsets, indices into `surface_elements`).
    vertex_elements: (Vec<u32>, Vec<u32>),
    /// Surface elements, where element fields are evaluated.
    surface_elements: Vec<u32>,
    colour_range: (f64, f64),
    /// Arrow length per pascal [m/Pa].
    arrow_scale: f64,
    point_radius: f32,
    alpha_per_node: bool,
    moving_planes: Vec<usize>,
    columns: Columns,
    reaction_curves: Vec<Vec<[f32; 2]>>,
    last: Option<(u64, StageTimes, f64, Duration)>,
}

impl Logger {
    fn new(rec: RecordingStream, st: Statics, colour: ColourField) -> Result<Logger, RecordError> {
        let m = &st.model;
        // Surface: vertices are the nodes of boundary faces, renumbered.
        let faces = m.mesh.boundary_faces();
        let mut index_of = vec![u32::MAX; m.mesh.nodes.len()];
        let mut surface_nodes = Vec::new();
        let mut triangles = Vec::with_capacity(2 * faces.len());
        let mut surface_elements: Vec<u32> = faces.iter().map(|f| f.1).collect();
        surface_elements.sort_unstable();
        surface_elements.dedup();
        for (q, _) in &faces {
            let v = q.map(|n| {
                if index_of[n as usize] == u32::MAX {
                    index_of[n as usize] = surface_nodes.len() as u32;
                    surface_nodes.push(n);
                }
                index_of[n as usize]
            });
            triangles.push([v[0], v[1], v[2]]);
            triangles.push([v[0], v[2], v[3]]);
        }
        // Elements around each surface vertex (only surface elements touch the surface).
        let mut offsets = vec![0u32; surface_nodes.len() + 1];
        for &e in &surface_elements {
            for &n in &m.mesh.elements[e as usize] {
                let v = index_of[n as usize];
                if v != u32::MAX {
                    offsets[v as usize + 1] += 1;
                }
            }
        }
        for i in 1..offsets.len() {
            offsets[i] += offsets[i - 1];
        }
        let mut fill = offsets.clone();
        let mut adjacent = vec![0u32; *offsets.last().unwrap_or(&0) as usize];
        for (k, &e) in surface_elements.iter().enumerate() {
            for &n in &m.mesh.elements[e as usize] {
                let v = index_of[n as usize];
                if v != u32::MAX {
                    adjacent[fill[v as usize] as usize] = k as u32;
                    fill[v as usize] += 1;
                }
            }
        }

        // Scales: body extent, arrows, point radii.
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for x in &m.mesh.nodes {
            for i in 0..3 {
                lo[i] = lo[i].min(x[i]);
                hi[i] = hi[i].max(x[i]);
            }
        }
        let extent = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
        let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let t_max = m
            .interfaces
            .iter()
            .map(|i| i.law.peak_traction().0)
            .fold(0.0, f64::max);
        // No glue: contact pressures are scaled by the stiffness E.
        let t_ref = if t_max > 0.0 { t_max } else { m.material.young };
        let arrow_scale = ARROW_FRACTION * extent / t_ref;
        let point_radius = (0.15 * m.mesh.min_edge()) as f32;
        let moving_planes = m
            .planes
            .iter()
            .enumerate()
            .filter(|p| p.1.velocity.is_some())
            .map(|p| p.0)
            .collect();
        let alpha_per_node = st.interface_nodes.len() <= ALPHA_PER_NODE_MAX;
        let reaction_curves = vec![Vec::new(); m.displacements.len()];
        let mut me = Logger {
            rec,
            st,
            colour,
            last_flush: Instant::now(),
            started: Instant::now(),
            surface_nodes,
            vertex_elements: (offsets, adjacent),
            surface_elements,
            colour_range: (f64::INFINITY, f64::NEG_INFINITY),
            arrow_scale,
            point_radius,
            alpha_per_node,
            moving_planes,
            columns: Columns::default(),
            reaction_curves,
            last: None,
        };
        me.log_static(&triangles, extent, centre)?;
        Ok(me)
    }

    fn log_static(
        &mut self,
        triangles: &[[u32; 3]],
        extent: f64,
        centre: [f64; 3],
    ) -> Result<(), RecordError> {
        let rec = &self.rec;
        let st = &self.st;
        let m = &st.model;
        rec.log_static(
            "scene/file",
            &TextDocument::from_markdown(format!(
                "# {}\n\n{}\n\nFile `{}`:\n\n```toml\n{}\n```\n",
                m.name, m.description, st.file, st.text
            )),
        )
        .map_err(log_err("the scene text"))?;
        rec.log_static(
            "scene/resolved",
            &TextDocument::from_markdown(format!(
                "# Resolved parameters (after --set overrides)\n\n```toml\n{}\n```\n\n\
                 h = {:.5e} s = {} × h_crit, h_crit = {:.5e} s (Lanczos, PHYSICS.md §6); \
                 {} nodes, {} hex8 elements, {} interface nodes.\n",
                st.resolved,
                st.h,
                m.scheme.time_step_factor,
                st.h_crit,
                m.mesh.nodes.len(),
                m.mesh.elements.len(),
                st.interface_nodes.len()
            )),
        )
        .map_err(log_err("the resolved parameters"))?;
        rec.set_time_sequence("step", 0);
        rec.set_duration_secs("sim_time", 0.0);
        for text in &st.advisories {
            rec.log("run/log", &TextLog::new(text.clone()).with_level("WARN"))
                .map_err(log_err("a warning"))?;
        }

        // Class ids for interface and contact nodes, for the whole subtree.
        let classes = AnnotationContext::new([
            (0, "elastic", Rgba32::from_rgb(46, 160, 67)),
            (1, "transition", Rgba32::from_rgb(245, 166, 35)),
            (2, "ruptured", Rgba32::from_rgb(208, 2, 27)),
            (10, "open", Rgba32::from_rgb(160, 160, 160)),
            (11, "stick", Rgba32::from_rgb(30, 120, 220)),
            (12, "slip", Rgba32::from_rgb(200, 60, 200)),
        ]);
        rec.log_static("interface", &classes)
            .map_err(log_err("the annotation context"))?;
        if !st.contact_nodes.is_empty() {
            rec.log_static("contact", &classes)
                .map_err(log_err("the annotation context"))?;
        }

        // Styles that do not change: radii, arrow colours, curve labels.
        let r = self.point_radius;
        let styles: [(&str, &dyn rerun::AsComponents); 7] = [
            (
                "interface/nodes",
                &Points3D::update_fields().with_radii([r]),
            ),
            (
                "interface/contact_status",
                &Points3D::update_fields().with_radii([0.5 * r]),
            ),
            ("contact/nodes", &Points3D::update_fields().with_radii([r])),
            (
                "interface/cohesive_traction",
                &Arrows3D::update_fields().with_colors([Rgba32::from_rgb(245, 166, 35)]),
            ),
            (
                "interface/contact_pressure",
                &Arrows3D::update_fields().with_colors([Rgba32::from_rgb(30, 120, 220)]),
            ),
            (
                "contact/pressure",
                &Arrows3D::update_fields().with_colors([Rgba32::from_rgb(30, 120, 220)]),
            ),
            (
                "plots/reaction_vs_displacement",
                &LineStrips2D::update_fields().with_labels(
                    m.displacements
                        .iter()
                        .map(|d| format!("{} {}", d.faces, AXES[d.component.min(2)])),
                ),
            ),
        ];
        for (path, style) in styles {
            let used = if path.starts_with("contact/") {
                !st.contact_nodes.is_empty()
            } else if path.starts_with("plots/") {
                !m.displacements.is_empty()
            } else if path.starts_with("interface/") {
                !st.interface_nodes.is_empty()
            } else {
                true
            };
            if used {
                rec.log_static(path, style).map_err(log_err("a style"))?;
            }
        }

        // Surface topology once; positions and colours per frame.
        rec.log_static(
            "body/surface",
            &Mesh3D::update_fields().with_triangle_indices(triangles.iter().copied()),
        )
        .map_err(log_err("the surface topology"))?;

        // Planes: a square of 1.6 × the body extent centred under the body's centre.
        for p in &m.planes {
            let n = p.normal;
            let a = if n[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let t1 = normalise(cross(n, a));
            let t2 = cross(n, t1);
            let d = dot(sub(centre, p.point), n);
            let c = [0, 1, 2].map(|i| centre[i] - d * n[i]);
            let s = 0.8 * extent;
            let corner =
                |a: f64, b: f64| [0, 1, 2].map(|i| (c[i] + s * (a * t1[i] + b * t2[i])) as f32);
            let verts = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            rec.log_static(
                format!("planes/{}", path_part(&p.name)),
                &Mesh3D::new(verts)
                    .with_triangle_indices([[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]])
                    .with_albedo_factor(Rgba32::from_unmultiplied_rgba(150, 155, 165, 160)),
            )
            .map_err(log_err("a plane"))?;
        }

        // Stiffness laws, normalised: x = α/u_r ∈ [0, 1] → 0..100, y = value/peak → 0..−100
        // (2-D views point y down).
        for itf in &m.interfaces {
            let law = &itf.law;
            let base = format!("law/{}", path_part(&itf.faces));
            let n = 200;
            let (t_max, at) = law.peak_traction();
            let g: Vec<[f32; 2]> = (0..=n)
                .map(|k| {
                    let a = law.u_r * k as f64 / n as f64;
                    [
                        (100.0 * a / law.u_r) as f32,
                        (-100.0 * law.g_n(a) / law.g_n0) as f32,
                    ]
                })
                .collect();
            let t: Vec<[f32; 2]> = (0..=n)
                .map(|k| {
                    let d = law.u_r * k as f64 / n as f64;
                    [
                        (100.0 * d / law.u_r) as f32,
                        (-100.0 * law.traction(d) / t_max) as f32,
                    ]
                })
                .collect();
            rec.log_static(
                format!("{base}/g_n"),
                &LineStrips2D::new([g])
                    .with_colors([Rgba32::from_rgb(30, 120, 220)])
                    .with_labels([format!("g_N(α)/g_N(0), g_N(0) = {:.3e} Pa/m", law.g_n0)]),
            )
            .map_err(log_err("the law curve"))?;
            rec.log_static(
                format!("{base}/traction"),
                &LineStrips2D::new([t])
                    .with_colors([Rgba32::from_rgb(208, 2, 27)])
                    .with_labels([format!(
                        "T(δ)/T_max, T_max = {t_max:.3e} Pa at δ = {at:.3e} m; G_c = {:.3e} J/m²",
                        law.fracture_energy()
                    )]),
            )
            .map_err(log_err("the law curve"))?;
            rec.log_static(
                format!("{base}/axes"),
                &LineStrips2D::new([
                    vec![[0.0f32, 0.0], [105.0, 0.0]],
                    vec![[0.0f32, 0.0], [0.0, -105.0]],
                ])
                .with_colors([Rgba32::from_rgb(120, 120, 120)])
                .with_labels(["α/u_r, δ/u_r →", "↑ normalised value"]),
            )
            .map_err(log_err("the law axes"))?;
            rec.log_static(
                format!("{base}/marks"),
                &Points2D::new([
                    [(100.0 * law.alpha_e / law.u_r) as f32, 0.0],
                    [100.0f32, 0.0],
                ])
                .with_radii([1.5f32])
                .with_labels([
                    format!("α_e = {:.3e} m", law.alpha_e),
                    format!("u_r = {:.3e} m", law.u_r),
                ]),
            )
            .map_err(log_err("the law marks"))?;
        }

        // Scalar series: one entity per quantity, one named instance per series.
        let mut styles: Vec<(String, SeriesLines)> = vec![
            ("energy".into(), SeriesLines::new().with_names(ENERGY_TERMS)),
            (
                "interface/count".into(),
                SeriesLines::new()
                    .with_names(["elastic", "transition", "ruptured"])
                    .with_colors([
                        Rgba32::from_rgb(46, 160, 67),
                        Rgba32::from_rgb(245, 166, 35),
                        Rgba32::from_rgb(208, 2, 27),
                    ]),
            ),
            (
                "time_step".into(),
                SeriesLines::new().with_names(["h", "h_crit"]),
            ),
            ("timing".into(), SeriesLines::new().with_names(STAGES)),
            (
                "body/colour_range".into(),
                SeriesLines::new().with_names(["min", "max"]),
            ),
        ];
        if !st.interface_nodes.is_empty() {
            let names: Vec<String> = if self.alpha_per_node {
                st.interface_nodes
                    .iter()
                    .map(|n| format!("node {}", n.0))
                    .collect()
            } else {
                vec!["min".into(), "mean".into(), "max".into()]
            };
            styles.push((
                "interface/alpha".into(),
                SeriesLines::new().with_names(names),
            ));
        }
        for (path, style) in styles {
            rec.log_static(path, &style)
                .map_err(log_err("a series style"))?;
        }

        let (field, unit) = self.colour.label();
        rec.log_static(
            "body/legend",
            &TextDocument::from_markdown(format!(
                "Surface coloured by **{field}** [{unit}], viridis colormap (dark purple = min, \
                 yellow = max) over the range seen so far in the run (see `body/colour_range`).\n\n\
                 Arrows: {:.3e} m per Pa (the law's peak traction, or E without glue, draws \
                 {ARROW_FRACTION} × the body extent {extent:.3e} m). Cohesive arrows show −R_d = −g_N(α)[u] \
                 on the solid; contact arrows show R_c/h.\n\nInterface nodes: green elastic, \
                 orange transition, red ruptured; contact status: grey open, blue stick, \
                 magenta slip.",
                self.arrow_scale
            )),
        )
        .map_err(log_err("the legend"))?;
        Ok(())
    }

    /// Buffers one snapshot as a frame at its step and time; sends the buffer when it holds
    /// [`FLUSH_ROWS`] frames, [`FLUSH_BYTES`] or [`FLUSH_WALL`] of wall time. `busy` is the
    /// logger thread's time so far, for the timing series.
    fn frame(&mut self, s: &Snapshot, busy: Duration) -> Result<(), RecordError> {
        let m = &self.st.model;
        let position = |n: u32| {
            let x = m.mesh.nodes[n as usize];
            let u = s.u[n as usize];
            [
                (x[0] + u[0]) as f32,
                (x[1] + u[1]) as f32,
                (x[2] + u[2]) as f32,
            ]
        };
        let cols = &mut self.columns;
        cols.steps.push(s.step as i64);
        cols.times.push(s.time);

        // Body surface: positions and colours (the topology is static).
        let flat: Vec<f32> = self
            .surface_nodes
            .iter()
            .flat_map(|&n| position(n))
            .collect();
        cols.f32s(
            "body/surface",
            Mesh3D::descriptor_vertex_positions(),
            3,
            &flat,
        );
        let values: Vec<f64> = match self.colour {
            ColourField::Displacement => self
                .surface_nodes
                .iter()
                .map(|&n| norm(s.u[n as usize]))
                .collect(),
            ColourField::VonMises | ColourField::Jacobian => {
                let per_element: Vec<f64> = self
                    .surface_elements
                    .iter()
                    .map(|&e| {
                        let f = m.mesh.centre_deformation_gradient(e as usize, &s.u);
                        let f = nalgebra::Matrix3::from_fn(|i, j| f[i][j]);
                        if self.colour == ColourField::Jacobian {
                            f.determinant()
                        } else {
                            m.material.von_mises(&f)
                        }
                    })
                    .collect();
                let (offsets, adjacent) = &self.vertex_elements;
                (0..self.surface_nodes.len())
                    .map(|v| {
                        let r = offsets[v] as usize..offsets[v + 1] as usize;
                        let k = r.len().max(1) as f64;
                        adjacent[r]
                            .iter()
                            .map(|&i| per_element[i as usize])
                            .sum::<f64>()
                            / k
                    })
                    .collect()
            }
        };
        for &v in &values {
            if v.is_finite() {
                self.colour_range.0 = self.colour_range.0.min(v);
                self.colour_range.1 = self.colour_range.1.max(v);
            }
        }
        let (lo, hi) = self.colour_range;
        let span = if hi > lo { hi - lo } else { 1.0 };
        let colours: Vec<u32> = values
            .iter()
            .map(|&v| rgba(viridis((v - lo) / span)))
            .collect();
        cols.u32s("body/surface", Mesh3D::descriptor_vertex_colors(), &colours);

        for &p in &self.moving_planes {
            let plane = &m.planes[p];
            let d = plane.displacement(s.time);
            cols.f32s(
                &format!("planes/{}", path_part(&plane.name)),
                Transform3D::descriptor_translation(),
                3,
                &[d[0] as f32, d[1] as f32, d[2] as f32],
            );
        }

        let contact_class = |c: ContactStatus| match c {
            ContactStatus::Open => 10u16,
            ContactStatus::Stick => 11,
            ContactStatus::Slip => 12,
        };
        let h = s.h.max(f64::MIN_POSITIVE);
        let scale = self.arrow_scale;
        if !s.interface.is_empty() {
            let nodes = &self.st.interface_nodes;
            let pts: Vec<f32> = nodes.iter().flat_map(|&(n, _)| position(n)).collect();
            let state: Vec<u16> = nodes
                .iter()
                .zip(&s.interface)
                .map(
                    |(&(_, itf), snap)| match m.interfaces[itf as usize].law.state(snap.alpha) {
                        InterfaceState::Elastic => 0,
                        InterfaceState::Transition => 1,
                        InterfaceState::Ruptured => 2,
                    },
                )
                .collect();
            let contact: Vec<u16> = s
                .interface
                .iter()
                .map(|n| contact_class(n.contact))
                .collect();
            let alpha: Vec<f64> = s.interface.iter().map(|n| n.alpha).collect();
            let gap: Vec<f64> = s.interface.iter().map(|n| n.gap).collect();
            // −R_d on the solid, and R_c/h, both in Pa, times the arrow scale.
            let cohesive: Vec<f32> = s
                .interface
                .iter()
                .flat_map(|n| n.cohesive_traction.map(|t| (-t * scale) as f32))
                .collect();
            let pressure: Vec<f32> = s
                .interface
                .iter()
                .flat_map(|n| n.contact_impulse.map(|r| (r / h * scale) as f32))
                .collect();
            cols.f32s("interface/nodes", Points3D::descriptor_positions(), 3, &pts);
            cols.u16s("interface/nodes", Points3D::descriptor_class_ids(), &state);
            cols.f64s(
                "interface/nodes",
                ComponentDescriptor::partial("alpha_m"),
                &alpha,
            );
            cols.f64s(
                "interface/nodes",
                ComponentDescriptor::partial("gap_m"),
                &gap,
            );
            cols.f32s(
                "interface/contact_status",
                Points3D::descriptor_positions(),
                3,
                &pts,
            );
            cols.u16s(
                "interface/contact_status",
                Points3D::descriptor_class_ids(),
                &contact,
            );
            for (path, vectors) in [
                ("interface/cohesive_traction", &cohesive),
                ("interface/contact_pressure", &pressure),
            ] {
                cols.f32s(path, Arrows3D::descriptor_vectors(), 3, vectors);
                cols.f32s(path, Arrows3D::descriptor_origins(), 3, &pts);
            }
        }
        if !s.contact.is_empty() {
            let pts: Vec<f32> = self
                .st
                .contact_nodes
                .iter()
                .flat_map(|&n| position(n))
                .collect();
            let class: Vec<u16> = s.contact.iter().map(|c| contact_class(c.0)).collect();
            let pressure: Vec<f32> = s
                .contact
                .iter()
                .flat_map(|c| c.1.map(|r| (r / h * scale) as f32))
                .collect();
            cols.f32s("contact/nodes", Points3D::descriptor_positions(), 3, &pts);
            cols.u16s("contact/nodes", Points3D::descriptor_class_ids(), &class);
            cols.f32s(
                "contact/pressure",
                Arrows3D::descriptor_vectors(),
                3,
                &pressure,
            );
            cols.f32s("contact/pressure", Arrows3D::descriptor_origins(), 3, &pts);
        }

        // Reaction against imposed displacement (mm, kN; y up drawn as −y), sent at flushes.
        for (k, d) in m.displacements.iter().enumerate() {
            let u = d.history.value(s.time)[0];
            let f = s.reactions.get(k).copied().unwrap_or(0.0);
            self.reaction_curves[k].push([(1e3 * u) as f32, (-1e-3 * f) as f32]);
        }

        // One row of every scalar series.
        let e = &s.energies;
        cols.scalars(
            "energy",
            &[
                e.kinetic,
                e.strain,
                e.hourglass,
                e.interface_stored,
                e.damage_dissipated,
                e.contact_normal_dissipated,
                e.friction_dissipated,
                e.external_work,
                e.gravity_work,
                e.traction_work,
                e.reaction_work,
                e.plane_work,
                e.residual,
            ],
        );
        cols.scalars("balance/relative_residual", &[e.relative_residual]);
        for (k, d) in m.displacements.iter().enumerate() {
            let name = format!("{}_{}", path_part(&d.faces), AXES[d.component.min(2)]);
            cols.scalars(
                &format!("reaction/{name}"),
                &[s.reactions.get(k).copied().unwrap_or(0.0)],
            );
            cols.scalars(
                &format!("imposed_displacement/{name}"),
                &[d.history.value(s.time)[0]],
            );
        }
        let c = s.counts;
        cols.scalars(
            "interface/count",
            &[c.elastic as f64, c.transition as f64, c.ruptured as f64],
        );
        if !s.interface.is_empty() {
            if self.alpha_per_node {
                let alpha: Vec<f64> = s.interface.iter().map(|n| n.alpha).collect();
                cols.scalars("interface/alpha", &alpha);
            } else {
                let (mut mn, mut mx, mut sum) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
                for n in &s.interface {
                    mn = mn.min(n.alpha);
                    mx = mx.max(n.alpha);
                    sum += n.alpha;
                }
                cols.scalars("interface/alpha", &[mn, sum / s.interface.len() as f64, mx]);
            }
        }
        cols.scalars("time_step", &[s.h, s.h_crit]);
        // Wall time per step of each stage since the previous frame [µs].
        let (step0, stages0, solver0, busy0) =
            self.last
                .take()
                .unwrap_or((0, StageTimes::default(), 0.0, Duration::ZERO));
        let steps = (s.step.saturating_sub(step0)).max(1) as f64;
        let per_step = |now: f64, before: f64| 1e6 * (now - before) / steps;
        let st = &s.stages;
        cols.scalars(
            "timing",
            &[
                per_step(st.positions, stages0.positions),
                per_step(st.internal_forces, stages0.internal_forces),
                per_step(st.interface_contact, stages0.interface_contact),
                per_step(st.free_velocity, stages0.free_velocity),
                per_step(st.bookkeeping, stages0.bookkeeping),
                per_step(st.h_crit, stages0.h_crit),
                per_step(s.solver_logging, solver0),
                per_step(busy.as_secs_f64(), busy0.as_secs_f64()),
            ],
        );
        self.last = Some((s.step, s.stages.clone(), s.solver_logging, busy));
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        cols.scalars("body/colour_range", &[finite(lo), finite(hi)]);

        if cols.steps.len() >= FLUSH_ROWS
            || cols.bytes >= FLUSH_BYTES
            || self.last_flush.elapsed()
                >= (self.started.elapsed() / 10).clamp(FLUSH_WALL_MIN, FLUSH_WALL)
        {
            self.flush()?;
        }
        Ok(())
    }

    /// Sends the buffered frames: one chunk per entity, with the `step` and `sim_time`
    /// columns; then the reaction curve so far, at the last buffered frame.
    fn flush(&mut self) -> Result<(), RecordError> {
        self.last_flush = Instant::now();
        let cols = std::mem::take(&mut self.columns);
        let n = cols.steps.len();
        if n == 0 {
            return Ok(());
        }
        let (last_step, last_time) = (cols.steps[n - 1], cols.times[n - 1]);
        let index = [
            TimeColumn::new_sequence("step", cols.steps.iter().copied()),
            TimeColumn::new_duration_secs("sim_time", cols.times.iter().copied()),
        ];
        let mut by_entity: Vec<(String, Vec<rerun::SerializedComponentColumn>)> = Vec::new();
        for c in cols.columns {
            debug_assert_eq!(c.lengths.len(), n, "{} misses frames", c.path);
            let (path, descriptor, lengths, array) = c.array();
            let column = SerializedComponentBatch { descriptor, array }
                .partitioned(lengths)
                .map_err(|e| RecordError::Setup(format!("serialising {path}: {e}")))?;
            match by_entity.iter_mut().find(|e| e.0 == path) {
                Some(e) => e.1.push(column),
                None => by_entity.push((path, vec![column])),
            }
        }
        for (path, columns) in by_entity {
            self.rec
                .send_columns(path.as_str(), index.clone(), columns)
                .map_err(log_err(&path))?;
        }
        if !self.reaction_curves.is_empty() {
            self.rec.set_time_sequence("step", last_step);
            self.rec.set_duration_secs("sim_time", last_time);
            self.rec
                .log(
                    "plots/reaction_vs_displacement",
                    &strips2d_batch(&self.reaction_curves),
                )
                .map_err(log_err("the reaction curve"))?;
        }
        Ok(())
    }

    /// Logs the outcome at the last frame's time, sends the buffered scalars, flushes and
    /// closes the stream (dropping it writes the file's footer).
    fn finish(
        mut self,
        status: &str,
        text: &str,
        level: &str,
        network: bool,
    ) -> Result<(), RecordError> {
        let r3 = self.flush();
        let r1 = self.rec.log(
            "run/status",
            &TextDocument::from_markdown(format!("# Run {status}\n\n{text}\n")),
        );
        let r2 = self
            .rec
            .log("run/log", &TextLog::new(text.to_string()).with_level(level));
        let flushed = if network {
            // A viewer that went away must not hang the end of the run.
            self.rec.flush_with_timeout(Duration::from_secs(10))
        } else {
            self.rec.flush_blocking()
        };
        drop(self);
        r1.map_err(log_err("the run status"))?;
        r2.map_err(log_err("the run log"))?;
        r3?;
        flushed.map_err(|e| RecordError::Setup(format!("flushing the recording: {e}")))?;
        Ok(())
    }
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

/// Logs a speed–accuracy study as its own recording: every configuration as a point of
/// (log₁₀ wall time [s], log₁₀ error) (2-D views point y down, so y = −log₁₀ error puts large
/// errors up), the Pareto front as a line, and the table as text.
pub fn log_frontier(
    sink: Sink,
    scene: &str,
    rows: &[crate::tradeoff::Row],
) -> Result<(), RecordError> {
    let name = format!("tradeoff · {scene}");
    let bp = Blueprint::new(Horizontal::new([
        Spatial2DView::new("error vs wall time (log₁₀, ×100)")
            .with_origin("/tradeoff")
            .into(),
        TextDocumentView::new("table").with_origin("/table").into(),
    ]));
    let builder = RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(name)
        .with_blueprint(bp);
    let rec = match &sink {
        Sink::Save(path) => builder.save(path).map_err(|e| {
            RecordError::Setup(format!(
                "cannot write the recording {}: {e}",
                path.display()
            ))
        })?,
        other => open_stream(other, format!("tradeoff · {scene}"))?,
    };
    let floor = 1e-6;
    let point = |r: &crate::tradeoff::Row| {
        [
            (100.0 * r.wall_seconds.max(1e-6).log10()) as f32,
            (-100.0 * r.error.max(floor).log10()) as f32,
        ]
    };
    let ok: Vec<&crate::tradeoff::Row> = rows
        .iter()
        .filter(|r| r.failure.is_none() && r.error.is_finite())
        .collect();
    let colour = |r: &crate::tradeoff::Row| {
        if r.config.integration == "full" {
            Rgba32::from_rgb(30, 120, 220)
        } else {
            Rgba32::from_rgb(245, 166, 35)
        }
    };
    rec.log_static(
        "tradeoff/runs",
        &Points2D::new(ok.iter().map(|r| point(r)))
            .with_colors(ok.iter().map(|r| colour(r)))
            .with_radii([3.0f32])
            .with_labels(ok.iter().map(|r| {
                format!(
                    "{} {}³ ×{}: {:.3} s, error {:.2e}{}",
                    r.config.integration,
                    r.config.cells,
                    r.config.factor,
                    r.wall_seconds,
                    r.error,
                    if r.pareto { " (Pareto)" } else { "" }
                )
            })),
    )
    .map_err(log_err("the tradeoff points"))?;
    let mut front: Vec<&&crate::tradeoff::Row> = ok.iter().filter(|r| r.pareto).collect();
    front.sort_by(|a, b| a.wall_seconds.total_cmp(&b.wall_seconds));
    rec.log_static(
        "tradeoff/pareto_front",
        &LineStrips2D::new([front.iter().map(|r| point(r)).collect::<Vec<_>>()])
            .with_colors([Rgba32::from_rgb(46, 160, 67)])
            .with_labels(["Pareto front"]),
    )
    .map_err(log_err("the Pareto front"))?;
    let table = format!("```text\n{}```\n", crate::tradeoff::table(rows));
    rec.log_static("table", &TextDocument::from_markdown(table))
        .map_err(log_err("the tradeoff table"))?;
    rec.flush_blocking()
        .map_err(|e| RecordError::Setup(format!("flushing the recording: {e}")))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_clamps() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        assert_eq!(viridis(0.5), [33, 144, 141]);
    }

    #[test]
    fn path_parts_are_plain() {
        assert_eq!(path_part("z+"), "z_plus");
        assert_eq!(path_part("x-"), "x_minus");
        assert_eq!(path_part("mould 2"), "mould_2");
    }
}
