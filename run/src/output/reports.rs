//! What the Rerun recording ([`crate::record`]) and the ParaView files ([`crate::vtk`]) report
//! when they end and what can go wrong in them, as the values and errors of the
//! [`super::Output`] trait ([`super::OutputReport`], [`super::OutputError`]); kept below the
//! outputs that fill them so that the run summary ([`crate::report`]) and the Python package
//! read them without the Rerun SDK's types.

use std::path::PathBuf;

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

impl RecordingReport {
    /// The console's row: frames, target, size and the solver's time spent logging, as a share
    /// of `step_seconds`, the solver's time [s].
    pub fn line(&self, step_seconds: f64) -> String {
        let size = self
            .bytes
            .map_or(String::new(), |b| format!(", {:.1} kB", b as f64 / 1e3));
        let target = self
            .path
            .clone()
            .unwrap_or_else(|| match self.sink.as_str() {
                "spawn" => "the spawned Rerun viewer".to_string(),
                _ => "the Rerun viewer".to_string(),
            });
        format!(
            "{} frames to {target}{size}; logging {:.1} ms = {:.1} % of the solve",
            self.frames,
            1e3 * self.logging_seconds,
            100.0 * self.logging_seconds / step_seconds.max(1e-12)
        )
    }
}

/// While the run goes, the recorder's error says `recording` above it (the command line's
/// context; opening it, `starting the recording`).
impl From<RecordError> for super::OutputError {
    fn from(e: RecordError) -> super::OutputError {
        super::OutputError::new("recording", Some("recording"), e)
    }
}

/// While the run goes, the ParaView writer's error says `ParaView output` above it (opening it,
/// the error says it all).
impl From<VtkError> for super::OutputError {
    fn from(e: VtkError) -> super::OutputError {
        super::OutputError::new("paraview", Some("ParaView output"), e)
    }
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

/// What could not be written.
#[derive(Debug, thiserror::Error)]
pub enum VtkError {
    #[error("cannot write the ParaView output (--vtk) to directory {}: {source}", dir.display())]
    Dir {
        dir: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("writing {}: {source}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("the ParaView writer thread {0}")]
    Thread(String),
}

/// What was written, for the run summary.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct VtkReport {
    /// The `.pvd` index.
    pub pvd: String,
    /// Frames (`.vtu` files) written and indexed.
    pub frames: u64,
    /// Bytes of all the frames and the index.
    pub bytes: u64,
    /// Wall time the solver thread spent: copies, waiting on a full queue, final wait [s].
    pub solver_seconds: f64,
    /// Busy time of the writer thread, beside the solver [s].
    pub writer_thread_seconds: f64,
}

impl VtkReport {
    /// The console's row: frames, index, size and the solver's time spent, as a share of
    /// `step_seconds`, the solver's time [s].
    pub fn line(&self, step_seconds: f64) -> String {
        format!(
            "{} frames indexed by {}, {:.1} MB; solver thread {:.1} ms = {:.1} % of the solve",
            self.frames,
            self.pvd,
            self.bytes as f64 / 1e6,
            1e3 * self.solver_seconds,
            100.0 * self.solver_seconds / step_seconds.max(1e-12)
        )
    }
}
