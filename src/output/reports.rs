//! What each output reports when it ends and what can go wrong in it: the types of the
//! [`super::Output`] trait's results ([`super::OutputReport`], [`super::OutputError`]), kept
//! below the outputs that fill them ([`crate::record`], [`crate::vtk`]) so that `output` names
//! none of them.

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
