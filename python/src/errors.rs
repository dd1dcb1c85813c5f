//! Rust errors as Python exceptions, with the command line's messages.
//!
//! | Rust | Python |
//! |---|---|
//! | `SceneError::Io` (the file cannot be read) | `FileNotFoundError`, `PermissionError`, `IsADirectoryError` or `OSError` |
//! | any other `SceneError` (syntax, unknown or missing key, inadmissible value, bad override) | `ValueError` |
//! | `SolverError::Setup` | `ValueError` ("setting up FILE: …") |
//! | `SolverError::Unstable`, `SolverError::Inverted` | [`SolverError`] with `step`, `t`, `h`, `h_crit` |
//! | an output's error (recording, ParaView files) | `OSError` ("recording: …", "ParaView output: …") |
//! | `CheckpointError::Io` (`save`, `restore`) | `FileNotFoundError`, `PermissionError`, `IsADirectoryError` or `OSError` |
//! | any other `CheckpointError` (not a checkpoint, corrupt, another format or model) | `ValueError` |

use decohesion_run::output::OutputError;
use decohesion_run::scene::SceneError;
use decohesion_run::solver::{CheckpointError, SolverError as RustSolverError};
use pyo3::exceptions::{
    PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError, PyRuntimeError,
    PyValueError,
};
use pyo3::prelude::*;
use std::io::ErrorKind;

pyo3::create_exception!(
    decohesion,
    SolverError,
    PyRuntimeError,
    "The simulation could not go on (a blow-up: the energy grew, or an element inverted).\n\n\
     Attributes: step (int), t (float, s), h (float, s), h_crit (float, s), kind ('unstable' or \
     'inverted'), element (int or None: the inverted element). The message is the command \
     line's, with what to change."
);

/// A scene that could not be loaded: `ValueError`, or an `OSError` for a file that could not
/// be read; the message is the command line's (`error: …` without `error: `).
pub fn scene_error(e: SceneError) -> PyErr {
    let message = with_sources(&e);
    match e {
        SceneError::Io { source, .. } => io_error(&source, message),
        _ => PyValueError::new_err(message),
    }
}

/// The `OSError` subclass of an I/O error's kind, with `message`.
fn io_error(source: &std::io::Error, message: String) -> PyErr {
    match source.kind() {
        ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
        ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
        ErrorKind::IsADirectory => PyIsADirectoryError::new_err(message),
        _ => PyOSError::new_err(message),
    }
}

/// A checkpoint that could not be written or read: an `OSError` of the file's kind, or a
/// `ValueError` for one that is not a checkpoint, is corrupt, or is of another format or
/// model.
pub fn checkpoint_error(e: CheckpointError) -> PyErr {
    let message = with_sources(&e);
    match e {
        CheckpointError::Io { source, .. } => io_error(&source, message),
        _ => PyValueError::new_err(message),
    }
}

/// `e` and its sources as the command line prints an error (`decohesion_run::errors::causes_once`):
/// `e: source: …`, a source that the text already ends with left out.
fn with_sources(e: &(dyn std::error::Error + 'static)) -> String {
    decohesion_run::errors::causes_once(std::iter::successors(Some(e), |e| e.source()))
}

/// A solver error as a Python exception: the set-up's as `ValueError` (named after `file`),
/// a blow-up as [`SolverError`] with its fields, a cancellation as `KeyboardInterrupt`.
pub fn solver_error(py: Python<'_>, e: &RustSolverError, file: &str) -> PyErr {
    let (step, time, h, h_crit, kind, element) = match e {
        RustSolverError::Setup(_) => {
            return PyValueError::new_err(format!("setting up {file}: {e}"));
        }
        RustSolverError::Cancelled { .. } => {
            return pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string());
        }
        RustSolverError::Unstable {
            step,
            time,
            h,
            h_crit,
            ..
        } => (*step, *time, *h, *h_crit, "unstable", None),
        RustSolverError::Inverted {
            element,
            step,
            time,
            h,
            h_crit,
            ..
        } => (*step, *time, *h, *h_crit, "inverted", Some(*element)),
    };
    let err = SolverError::new_err(e.to_string());
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("step", step)?;
        value.setattr("t", time)?;
        value.setattr("h", h)?;
        value.setattr("h_crit", h_crit)?;
        value.setattr("kind", kind)?;
        value.setattr("element", element)
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// An output's error as `OSError` with the command line's words: what the run was doing
/// ("starting the recording: …", "recording: …", "ParaView output: …", "--series: …",
/// "checkpoint: …"; nothing when the error says it all), then the error with its sources.
pub fn output_error(e: &OutputError) -> PyErr {
    let prefix = e.context.map_or(String::new(), |c| format!("{c}: "));
    let message = with_sources(e.error());
    PyOSError::new_err(format!("{prefix}{message}"))
}
