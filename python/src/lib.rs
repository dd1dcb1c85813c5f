//! `decohesion._native`: the Python extension module of decohesion (PyO3, abi3). The Python
//! package `decohesion` (folder `decohesion/` beside this crate) re-exports its classes and
//! documents them (`_native.pyi`).
//!
//! - [`scene::Scene`]: a scene file (or text) loaded and validated by the physics crate's
//!   parser, with `--set`-style overrides; its `check()` is `decohesion check` as a dict.
//! - [`simulation::Simulation`]: the CD-Lagrange simulation of a scene, stepped with the GIL
//!   released, its state as numpy arrays (copies), `run()` through the command line's run
//!   driver (so `save=` and `vtk=` write the command line's Rerun recording and ParaView files).
//! - [`fit::fit`]: `decohesion fit` (a scene's keys fitted to a measured curve), the report as
//!   a dict.
//! - [`errors`]: scene errors → `ValueError` (the command line's message), blow-ups →
//!   `decohesion.SolverError` carrying step, t, h, h_crit.
//!
//! No physics here: every number comes from the `decohesion-run` and `decohesion-physics` crates.

mod arrays;
mod errors;
mod fit;
mod scene;
mod simulation;

use pyo3::prelude::*;
use pyo3::types::PyAny;

/// A value serialised by serde, as the Python object `json.loads` makes of it (dicts, lists,
/// floats that read back bit for bit: serde_json writes the shortest round-trip form).
pub(crate) fn to_python<'py, T: serde::Serialize>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::Scene>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add("SolverError", m.py().get_type::<errors::SolverError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
