//! `decohesion.fit(...)`: `decohesion fit` from Python ([`decohesion_run::fit`]), the GIL released
//! while the runs go; Ctrl-C (a signal handler raising) stops the fit after the run in progress
//! and the best so far is returned (`"stop": "cancelled"`).

use crate::scene::{override_specs, type_name};
use crate::to_python;
use decohesion_run::fit::outputs::write_outputs;
use decohesion_run::fit::{fit as run_fit, prepare, FitArgs, Record, Watch};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyAny, PyDict};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

/// Checks Python's signals after each run; a handler's exception (KeyboardInterrupt) stops the
/// fit.
struct Signals<'a> {
    cancel: &'a AtomicBool,
    raised: Option<PyErr>,
}

impl Watch for Signals<'_> {
    fn evaluated(&mut self, _: &Record, _: Option<&Record>) {
        if self.raised.is_some() {
            return;
        }
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            self.cancel.store(true, Ordering::SeqCst);
            self.raised = Some(e);
        }
    }
}

/// `{"key.path": (lo, hi)}` as `--free key=lo..hi` specs.
fn free_specs(free: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    let dict = free.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "free must be a dict {{\"key.path\": (lo, hi)}}, got {}",
            type_name(free)
        ))
    })?;
    let mut specs = Vec::new();
    for (key, bounds) in dict.iter() {
        let key: String = key.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "free: keys are key paths such as \"interface.law.u_r\" (str), got {}",
                type_name(&key)
            ))
        })?;
        let (lo, hi): (f64, f64) = bounds.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "free[\"{key}\"]: the bounds are a pair of numbers (lo, hi), got {}",
                type_name(&bounds)
            ))
        })?;
        specs.push(format!("{key}={lo:?}..{hi:?}"));
    }
    Ok(specs)
}

/// Fits the free keys of a scene to a measured curve; returns the report as a dict.
#[pyfunction]
#[pyo3(signature = (scene, data, x, y, free, overrides = None, x_unit = None, y_unit = None, max_evals = decohesion_run::fit::DEFAULT_MAX_EVALS as i64, sample = None, tolerance = decohesion_run::fit::DEFAULT_TOLERANCE, threads = None, out = None))]
#[allow(clippy::too_many_arguments)]
pub fn fit<'py>(
    py: Python<'py>,
    scene: PathBuf,
    data: PathBuf,
    x: String,
    y: String,
    free: &Bound<'py, PyAny>,
    overrides: Option<&Bound<'py, PyAny>>,
    x_unit: Option<String>,
    y_unit: Option<String>,
    max_evals: i64,
    sample: Option<i64>,
    tolerance: f64,
    threads: Option<i64>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let max_evals = usize::try_from(max_evals)
        .ok()
        .filter(|&n| n >= 1)
        .ok_or_else(|| PyValueError::new_err(format!("max_evals must be ≥ 1 (got {max_evals})")))?;
    let sample = match sample {
        None => None,
        Some(n) if n >= 0 => Some(n as usize),
        Some(n) => {
            return Err(PyValueError::new_err(format!(
                "sample must be ≥ 0 (got {n})"
            )))
        }
    };
    let threads = match threads {
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
        Some(n) if n >= 1 => n as usize,
        Some(n) => {
            return Err(PyValueError::new_err(format!(
                "threads must be ≥ 1 (got {n})"
            )))
        }
    };
    let args = FitArgs {
        set: override_specs(overrides)?,
        x_unit,
        y_unit,
        max_evals,
        sample,
        tolerance,
        threads,
        ..FitArgs::new(&scene, &data, &x, &y, &free_specs(free)?)
    };
    let message =
        |e: anyhow::Error| PyValueError::new_err(decohesion_run::errors::error_message(&e));
    let cancel = AtomicBool::new(false);
    let (report, raised) = py
        .detach(|| {
            let prep = prepare(&args)?;
            let mut watch = Signals {
                cancel: &cancel,
                raised: None,
            };
            let report = run_fit(&prep, &cancel, &mut watch)?;
            if let Some(dir) = &out {
                std::fs::create_dir_all(dir).map_err(|e| {
                    anyhow::anyhow!("out={}: cannot create the folder: {e}", dir.display())
                })?;
                write_outputs(dir, &args.scene, &report)?;
            }
            Ok::<_, anyhow::Error>((report, watch.raised))
        })
        .map_err(message)?;
    if let Some(e) = raised {
        // The best so far is returned; the interrupt is reported, not lost.
        let warnings = py.import("warnings")?;
        warnings.call_method1(
            "warn",
            (format!(
                "fit interrupted ({}) after {} runs: the best so far is returned",
                e, report.evaluations
            ),),
        )?;
    }
    to_python(py, &report)
}
