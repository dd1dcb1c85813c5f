//! The Rerun stream of a recording: opening the sink (a file, a spawned viewer, a running
//! viewer), buffering the frames as columns on the logger thread ([`Columns`]) and sending
//! them (`send_columns`, one chunk per entity) every [`FLUSH_ROWS`] frames, [`FLUSH_BYTES`] or
//! at most [`FLUSH_WALL`] of wall time, and always before the stream is closed, so a live
//! viewer lags at most that much and nothing is lost when a run fails.

use super::eye::{send_blueprint, Eye};
use super::{
    default_blueprint, log_err, RecordError, Sink, APPLICATION_ID, FLUSH_BYTES, FLUSH_ROWS,
    FLUSH_WALL, RERUN_VERSION,
};
use rerun::external::arrow::array::{
    Array, ArrayRef, FixedSizeListArray, Float32Array, Float64Array, ListArray, UInt16Array,
    UInt32Array,
};
use rerun::external::arrow::buffer::OffsetBuffer;
use rerun::external::arrow::datatypes::{DataType, Field};
use rerun::{
    ComponentDescriptor, LineStrips2D, RecordingStream, RecordingStreamBuilder, Scalars,
    SerializedComponentBatch, TextDocument, TextLog, TimeColumn,
};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::tunables::RECORD_FLUSH_WALL_MIN as FLUSH_WALL_MIN;

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
/// no viewer executable, a malformed URL); `watched`: the entity paths of the watched nodes,
/// which the layout gives a tab each.
pub(super) fn open_stream(
    sink: &Sink,
    name: String,
    id: Option<&str>,
    eye: Option<&Eye>,
    watched: &[(String, String)],
) -> Result<RecordingStream, RecordError> {
    let rec = open_sink(sink, name, id)?;
    // The layout before anything else, as the builder's `with_blueprint` would send it, with
    // the 3-D view's eye ([`super::eye`]).
    let (bp, view) = default_blueprint(watched);
    send_blueprint(&rec, &bp, eye.map(|e| (view, e))).map_err(log_err("the blueprint"))?;
    Ok(rec)
}

/// The SDK's stream for a sink, without a blueprint; with `id`, the recording's id (a resumed
/// run's recording continues its first part's: the viewer shows the two files as one
/// recording), else a random one.
fn open_sink(sink: &Sink, name: String, id: Option<&str>) -> Result<RecordingStream, RecordError> {
    let mut builder = RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(name)
        .batcher_config(batcher_config());
    if let Some(id) = id {
        builder = builder.recording_id(id).send_properties(true);
    }
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

/// Flat values of one component over the buffered frames.
pub(super) enum Flat {
    F32(Vec<f32>),
    F64(Vec<f64>),
    U32(Vec<u32>),
    U16(Vec<u16>),
}

/// A value type of a column, with its place in [`Flat`].
pub(super) trait Value: Copy {
    fn empty() -> Flat;
    fn values(data: &mut Flat) -> Option<&mut Vec<Self>>;
}

macro_rules! value {
    ($t:ty, $variant:ident) => {
        impl Value for $t {
            fn empty() -> Flat {
                Flat::$variant(Vec::new())
            }
            fn values(data: &mut Flat) -> Option<&mut Vec<$t>> {
                match data {
                    Flat::$variant(v) => Some(v),
                    _ => None,
                }
            }
        }
    };
}
value!(f32, F32);
value!(f64, F64);
value!(u32, U32);
value!(u16, U16);

/// One component of one entity, over the buffered frames.
struct Column {
    path: String,
    descriptor: ComponentDescriptor,
    data: Flat,
    /// Values per instance (1, 2, 3 or 9: scalars, 2-D or 3-D vectors, 3×3 matrices; f32 only
    /// above 1).
    width: i32,
    /// Instances per frame.
    lengths: Vec<usize>,
}

impl Column {
    fn array(self) -> (String, ComponentDescriptor, Vec<usize>, ArrayRef) {
        let array: ArrayRef = match self.data {
            Flat::F32(v) if self.width == 1 => Arc::new(Float32Array::from(v)),
            Flat::F32(v) => {
                let item = Arc::new(Field::new("item", DataType::Float32, false));
                Arc::new(FixedSizeListArray::new(
                    item,
                    self.width,
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
pub(super) struct Columns {
    steps: Vec<i64>,
    times: Vec<f64>,
    columns: Vec<Column>,
    bytes: usize,
}

impl Columns {
    /// Starts a frame at step n, time tₙ [s].
    pub(super) fn begin(&mut self, step: u64, time: f64) {
        self.steps.push(step as i64);
        self.times.push(time);
    }

    /// Appends one frame's instances of a component of entity `path`, `width` values each (1
    /// for scalars, 3 for 3-D vectors).
    pub(super) fn push<T: Value>(
        &mut self,
        path: &str,
        descriptor: ComponentDescriptor,
        width: i32,
        values: &[T],
    ) {
        self.bytes += std::mem::size_of_val(values);
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
                    data: T::empty(),
                    width,
                    lengths: Vec::new(),
                });
                self.columns.len() - 1
            }
        };
        let c = &mut self.columns[i];
        if let Some(v) = T::values(&mut c.data) {
            v.extend_from_slice(values);
        }
        c.lengths.push(values.len() / width as usize);
    }

    /// One row of a Scalars entity.
    pub(super) fn scalars(&mut self, path: &str, values: &[f64]) {
        self.push(path, Scalars::descriptor_scalars(), 1, values);
    }
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

/// The logger thread's stream: the SDK's recording and the frames buffered for it.
pub(super) struct Stream {
    rec: RecordingStream,
    pub(super) columns: Columns,
    /// A viewer over the network (spawned or connected): the final flush has a time limit.
    network: bool,
    last_flush: Instant,
    started: Instant,
}

impl Stream {
    /// Opens the stream of a sink, recording `name` (see [`open_stream`]).
    pub(super) fn open(
        sink: &Sink,
        name: String,
        id: Option<&str>,
        eye: &Eye,
        watched: &[(String, String)],
    ) -> Result<Stream, RecordError> {
        Ok(Stream {
            rec: open_stream(sink, name, id, Some(eye), watched)?,
            columns: Columns::default(),
            network: !matches!(sink, Sink::Save(_)),
            last_flush: Instant::now(),
            started: Instant::now(),
        })
    }

    /// The SDK's stream, for what is logged directly (static entities, the run log).
    pub(super) fn rec(&self) -> &RecordingStream {
        &self.rec
    }

    /// Sends the buffered frames when they hold [`FLUSH_ROWS`] frames, [`FLUSH_BYTES`], or
    /// after a tenth of the wall time so far (between 10 ms and [`FLUSH_WALL`]).
    pub(super) fn flush_if_due(&mut self, curves: &[Vec<[f32; 2]>]) -> Result<(), RecordError> {
        let cols = &self.columns;
        if cols.steps.len() >= FLUSH_ROWS
            || cols.bytes >= FLUSH_BYTES
            || self.last_flush.elapsed()
                >= (self.started.elapsed() / 10).clamp(FLUSH_WALL_MIN, FLUSH_WALL)
        {
            self.flush(curves)?;
        }
        Ok(())
    }

    /// Sends the buffered frames: one chunk per entity, with the `step` and `sim_time`
    /// columns; then the reaction–displacement `curves` so far (re-sent whole), at the last
    /// buffered frame.
    fn flush(&mut self, curves: &[Vec<[f32; 2]>]) -> Result<(), RecordError> {
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
        if !curves.is_empty() {
            self.rec.set_time_sequence("step", last_step);
            self.rec.set_duration_secs("sim_time", last_time);
            self.rec
                .log("plots/reaction_vs_displacement", &strips2d_batch(curves))
                .map_err(log_err("the reaction curve"))?;
        }
        Ok(())
    }

    /// Sends the buffered frames and `curves`, logs the outcome at the last frame's time,
    /// flushes and closes the stream (dropping it writes the file's footer).
    pub(super) fn close(
        mut self,
        curves: &[Vec<[f32; 2]>],
        status: &str,
        text: &str,
        level: &str,
    ) -> Result<(), RecordError> {
        let r3 = self.flush(curves);
        let r1 = self.rec.log(
            "run/status",
            &TextDocument::from_markdown(format!("# Run {status}\n\n{text}\n")),
        );
        let r2 = self
            .rec
            .log("run/log", &TextLog::new(text.to_string()).with_level(level));
        let flushed = if self.network {
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
