//! `decohesion.Simulation`: a [`decohesion_run::solver::Simulation`] driven from Python. Stepping
//! releases the GIL (`Python::detach`) and looks at Python's signals every
//! [`SIGNAL_INTERVAL`] between steps, so Ctrl-C stops a run after the current step; `run()` goes
//! through the command line's run driver ([`Driver`]), whose outputs are the command line's
//! (`save=` → the `--save` recording, `vtk=` → the `--vtk` files, `series=` → the `--series`
//! CSV), finished whatever the outcome. Every step's scalars are kept in [`History`] (the
//! `--series` columns and values): `Simulation.history`.

use crate::arrays::{array, column, vectors};
use crate::errors::{checkpoint_error, output_error, solver_error};
use crate::scene::Scene;
use crate::to_python;
use decohesion_run::driver::{Driver, Progress};
use decohesion_run::interface::contact::ContactStatus;
use decohesion_run::law::InterfaceState;
use decohesion_run::output::series::History;
use decohesion_run::output::{Cadence, OutputError};
use decohesion_run::outputs::Plan;
use decohesion_run::record::ColourField;
use decohesion_run::report::RunSummary;
use decohesion_run::scene::Scene as RustScene;
use decohesion_run::solver::{Simulation as Solver, SolverError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyAny;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Wall time between two looks at Python's signals (and progress updates) while stepping.
const SIGNAL_INTERVAL: Duration = Duration::from_millis(100);

/// The axes' names in `<faces>_<axis>` (the recording's entity names).
const AXES: [&str; 3] = ["x", "y", "z"];

/// What the outputs of a run wrote: the summary's values under their names, its table's rows.
type Outputs = (
    std::collections::BTreeMap<String, serde_json::Value>,
    Vec<(String, String)>,
);

/// A simulation of a scene (see the stub `_native.pyi` for the Python documentation).
#[pyclass(module = "decohesion")]
pub struct Simulation {
    scene: RustScene,
    sim: Solver,
    /// The blow-up that stopped the simulation for good: stepping again raises it again.
    failure: Option<SolverError>,
    /// The cancellation (KeyboardInterrupt) of the last call, until stepping resumes.
    cancelled: Option<SolverError>,
    /// Wall time of the set-up and of every step()/run() [s], for the summary.
    wall: Duration,
    /// What the outputs of the last run() wrote: the summary's values under their names and
    /// its rows of the table (`None` before a run).
    outputs: Option<Outputs>,
    /// A row of scalars per step taken, step 0 included (the `--series` rows).
    history: History,
}

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (scene, threads = None))]
    fn new(py: Python<'_>, scene: &Scene, threads: Option<i64>) -> PyResult<Simulation> {
        let started = Instant::now();
        let scene = scene.scene.clone();
        let model = scene.model.clone();
        let mut sim = py
            .detach(|| Solver::new(model))
            .map_err(|e| solver_error(py, &e, &scene.file))?;
        if let Some(n) = threads {
            if n < 1 {
                return Err(PyValueError::new_err(format!(
                    "threads must be ≥ 1 (got {n}); None uses every core above 2048 elements"
                )));
            }
            sim.use_threads(n as usize);
        }
        let mut history = History::new(&sim);
        history.push(&sim);
        Ok(Simulation {
            scene,
            sim,
            failure: None,
            cancelled: None,
            wall: started.elapsed(),
            outputs: None,
            history,
        })
    }

    /// Takes `n` steps (the GIL released); Ctrl-C stops after the current step.
    #[pyo3(signature = (n = 1))]
    fn step(&mut self, py: Python<'_>, n: i64) -> PyResult<()> {
        if n < 0 {
            return Err(PyValueError::new_err(format!(
                "n must be ≥ 0 steps (got {n})"
            )));
        }
        self.resume(py)?;
        let started = Instant::now();
        let (sim, history) = (&mut self.sim, &mut self.history);
        let stop = py.detach(|| {
            let mut watch = Watch::new(None);
            for _ in 0..n {
                let stepped = sim.step();
                // The failed state too, as the driver's last row (`--series`).
                history.push(sim);
                if let Err(e) = stepped {
                    return Err(Stop::Solver(e));
                }
                if watch.signalled(sim) {
                    return Err(Stop::Python(watch.signal.take()));
                }
            }
            Ok(())
        });
        self.wall += started.elapsed();
        match stop {
            Ok(()) => Ok(()),
            Err(Stop::Solver(e)) => Err(self.failed(py, e)),
            Err(Stop::Python(e)) => {
                self.cancelled = Some(cancelled(&self.sim));
                Err(e.unwrap_or_else(|| PyErr::fetch(py)))
            }
        }
    }

    /// Steps to `until` (default: the end time) through the command line's run driver.
    #[pyo3(signature = (until = None, progress = true, save = None, vtk = None, every = None, fps = None, colour = "displacement", series = None))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        &mut self,
        py: Python<'_>,
        until: Option<f64>,
        progress: bool,
        save: Option<PathBuf>,
        vtk: Option<PathBuf>,
        every: Option<i64>,
        fps: Option<f64>,
        colour: &str,
        series: Option<PathBuf>,
    ) -> PyResult<()> {
        let until = until.unwrap_or(self.sim.model.end_time);
        if !until.is_finite() {
            return Err(PyValueError::new_err(format!(
                "until must be a finite time in seconds (got {until})"
            )));
        }
        // The outputs in the command line's words (the registry's flags).
        let mut flags: Vec<std::ffi::OsString> = Vec::new();
        if let Some(p) = save {
            colour_field(colour)?;
            flags.extend(["--save".into(), p.into(), "--colour".into(), colour.into()]);
        }
        if let Some(d) = vtk {
            flags.extend(["--vtk".into(), d.into()]);
        }
        if let Some(f) = series {
            flags.extend(["--series".into(), f.into()]);
        }
        let mut plan = Plan::parse(flags).map_err(|e| PyValueError::new_err(e.to_string()))?;
        plan.cadence = cadence(every, fps)?;
        self.resume(py)?;
        let bar = match progress {
            true => Some(progress_bar(py, &self.sim, until)?),
            false => None,
        };
        let started = Instant::now();
        let (scene, sim, history) = (&self.scene, &mut self.sim, &mut self.history);
        let (finished, signal) = py
            .detach(|| {
                let driver = Driver::open(&plan, scene, sim, started)?;
                let cancel = AtomicBool::new(false);
                let mut watch = Watch::new(bar.as_ref());
                watch.cancel = Some(&cancel);
                watch.history = Some(history);
                let finished = driver.run_until(sim, until, &cancel, &mut watch);
                // The final state, also when the last step failed (the driver's last row).
                if let Some(h) = watch.history.take() {
                    h.push(sim);
                }
                Ok::<_, OutputError>((finished, watch.signal))
            })
            .map_err(|e| output_error(&e))?;
        self.wall += started.elapsed();
        self.outputs = Some((finished.summary.outputs, finished.summary.output_lines));
        // The solver's failure first, then the signal (KeyboardInterrupt), then an output's.
        let result = match (finished.outcome, signal, finished.output_error) {
            (Err(SolverError::Cancelled { step, time }), signal, output) => {
                self.cancelled = Some(SolverError::Cancelled { step, time });
                match (signal, output) {
                    (Some(signal), _) => Err(signal),
                    (None, Some(e)) => Err(output_error(&e)),
                    (None, None) => Ok(()),
                }
            }
            (Err(e), _, _) => Err(self.failed(py, e)),
            (Ok(()), _, Some(e)) => Err(output_error(&e)),
            (Ok(()), _, None) => Ok(()),
        };
        // The bar's last word; its own error only when the run went well.
        let closed = bar.map_or(Ok(()), |bar| {
            update_bar(py, &bar, &self.sim)?;
            bar.call_method0(py, "close").map(drop)
        });
        result.and(closed)
    }

    /// The command line's `--summary` JSON of the simulation now, as a dict.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let error = self.failure.as_ref().or(self.cancelled.as_ref());
        let mut s = RunSummary::new(&self.sim, self.wall.as_secs_f64(), error);
        if error.is_none() && !self.sim.finished() {
            s.status = "in_progress".into();
        }
        s.outputs = decohesion_run::outputs::absent();
        if let Some((outputs, lines)) = &self.outputs {
            s.outputs = outputs.clone();
            s.output_lines = lines.clone();
        }
        to_python(py, &s)
    }

    /// The scalars of every step taken, step 0 included: a dict of the `--series` column names
    /// (`"t [s]"`, …) to (rows,) arrays, float64 (int64 for the step and the counts).
    #[getter]
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let h = &self.history;
        let dict = pyo3::types::PyDict::new(py);
        for ((name, values), integer) in (h.columns.names.iter())
            .zip(&h.values)
            .zip(&h.columns.integer)
        {
            let array = match integer {
                true => column(py, values.iter().map(|&v| v as i64))?,
                false => column(py, values.iter().copied())?,
            };
            dict.set_item(name, array)?;
        }
        Ok(dict.into_any())
    }

    /// Writes the state at tₙ to the checkpoint file `path`, atomically (model §4.13).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        if let Some(e) = &self.failure {
            return Err(PyValueError::new_err(format!(
                "the simulation failed ({e}): its state is not saved"
            )));
        }
        let sim = &self.sim;
        py.detach(|| sim.save_checkpoint(&path))
            .map(|_| ())
            .map_err(checkpoint_error)
    }

    /// Continues from the checkpoint file `path`, written by `save` of a simulation of the same
    /// scene; the history restarts at the restored step.
    fn restore(&mut self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let sim = &mut self.sim;
        py.detach(|| sim.load_checkpoint(&path))
            .map_err(checkpoint_error)?;
        self.failure = None;
        self.cancelled = None;
        self.history = History::new(&self.sim);
        self.history.push(&self.sim);
        Ok(())
    }

    /// tₙ [s].
    #[getter]
    fn t(&self) -> f64 {
        self.sim.state.time
    }

    /// The step about to be taken, h_{n+½} [s].
    #[getter]
    fn h(&self) -> f64 {
        self.sim.state.h
    }

    /// The last stable-step estimate 2/ω_max [s].
    #[getter]
    fn h_crit(&self) -> f64 {
        self.sim.state.h_crit
    }

    /// Steps taken, n.
    #[getter]
    fn step_count(&self) -> u64 {
        self.sim.state.step_count
    }

    #[getter]
    fn end_time(&self) -> f64 {
        self.sim.model.end_time
    }

    /// True once tₙ has reached the end time.
    #[getter]
    fn finished(&self) -> bool {
        self.sim.finished()
    }

    #[getter]
    fn scene(&self) -> Scene {
        Scene {
            scene: self.scene.clone(),
        }
    }

    #[getter]
    fn threads(&self) -> usize {
        self.sim.threads()
    }

    /// X, (nodes, 3) float64 [m].
    #[getter]
    fn reference_coordinates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        vectors(py, self.sim.model.mesh.nodes.iter().copied())
    }

    /// The hex8 connectivity, (elements, 8) int64.
    #[getter]
    fn elements<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let e = &self.sim.model.mesh.elements;
        array(py, e.iter().flatten().map(|&n| n as i64), &[e.len(), 8])
    }

    /// Lumped nodal masses, (nodes,) float64 [kg].
    #[getter]
    fn mass<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(py, self.sim.setup.mass.iter().copied())
    }

    /// Uₙ, (nodes, 3) float64 [m].
    #[getter]
    fn displacement<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        vectors(py, self.sim.state.u.rows())
    }

    /// V_{n+½}, (nodes, 3) float64 [m/s].
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        vectors(py, self.sim.state.v.rows())
    }

    /// The interface nodes' indices into the node arrays, (m,) int64.
    #[getter]
    fn interface_nodes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(
            py,
            self.sim.state.interface_nodes.iter().map(|n| n.node as i64),
        )
    }

    /// Damage αₙ of the interface nodes, (m,) float64 [m].
    #[getter]
    fn alpha<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(py, self.sim.state.interface_nodes.iter().map(|n| n.alpha))
    }

    /// Normal gap gₙ of the interface nodes (> 0 open), (m,) float64 [m].
    #[getter]
    fn gap<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(py, self.sim.state.interface_nodes.iter().map(|n| n.gap))
    }

    /// Displacement jump [u]ₙ of the interface nodes, (m, 3) float64 [m].
    #[getter]
    fn jump<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        vectors(py, self.sim.state.interface_nodes.iter().map(|n| n.jump))
    }

    /// Cohesive traction R_d = g_N(α)[u] of the interface nodes, (m, 3) float64 [Pa].
    #[getter]
    fn cohesive_traction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        vectors(
            py,
            self.sim
                .state
                .interface_nodes
                .iter()
                .map(|n| n.cohesive_traction),
        )
    }

    /// State class of the interface nodes, (m,) int8: 0 elastic, 1 transition, 2 ruptured, 3
    /// unformed (glue that forms on contact, not formed yet).
    #[getter]
    fn interface_state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let laws = &self.sim.model.interfaces;
        column(
            py,
            self.sim.state.interface_nodes.iter().map(|n| {
                match n.state(&laws[n.interface as usize].law) {
                    InterfaceState::Elastic => 0i8,
                    InterfaceState::Transition => 1,
                    InterfaceState::Ruptured => 2,
                    InterfaceState::Unformed => 3,
                }
            }),
        )
    }

    /// Contact status of the interface nodes, (m,) int8: 0 open, 1 stick, 2 slip.
    #[getter]
    fn interface_contact<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(
            py,
            self.sim
                .state
                .interface_nodes
                .iter()
                .map(|n| status(n.contact)),
        )
    }

    /// The contact-only nodes' indices into the node arrays, (k,) int64.
    #[getter]
    fn contact_nodes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(
            py,
            self.sim.state.contact_nodes.iter().map(|n| n.node as i64),
        )
    }

    /// Normal gap of the contact-only nodes, (k,) float64 [m].
    #[getter]
    fn contact_gap<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(py, self.sim.state.contact_nodes.iter().map(|n| n.gap))
    }

    /// Contact status of the contact-only nodes, (k,) int8: 0 open, 1 stick, 2 slip.
    #[getter]
    fn contact_status<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(
            py,
            self.sim
                .state
                .contact_nodes
                .iter()
                .map(|n| status(n.contact)),
        )
    }

    /// Names `<faces>_<axis>` of the prescribed-displacement conditions.
    #[getter]
    fn prescribed(&self) -> Vec<String> {
        let m = &self.sim.model;
        m.displacements
            .iter()
            .map(|d| format!("{}_{}", d.faces, AXES[d.component.min(2)]))
            .collect()
    }

    /// Reaction force of each prescribed condition now, (p,) float64 [N].
    #[getter]
    fn reactions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        column(py, self.sim.stats.reactions.iter().copied())
    }

    /// Imposed displacement of each prescribed condition at tₙ, (p,) float64 [m].
    #[getter]
    fn imposed_displacements<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let t = self.sim.state.time;
        let m = &self.sim.model;
        column(py, m.displacements.iter().map(|d| d.history.value(t)[0]))
    }

    /// The energy ledger now, a dict of floats [J] (relative_residual: [-]).
    #[getter]
    fn energies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.sim.energies())
    }

    /// Interface nodes per state now: {"elastic": …, "transition": …, "ruptured": …}, and
    /// "unformed": … where glue that forms on contact has nodes not formed yet.
    #[getter]
    fn state_counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.sim.state_counts())
    }

    fn __repr__(&self) -> String {
        format!(
            "Simulation({:?}, step {}, t = {:.6e} s of {} s, h = {:.4e} s, h_crit = {:.4e} s)",
            self.sim.model.name,
            self.sim.state.step_count,
            self.sim.state.time,
            self.sim.model.end_time,
            self.sim.state.h,
            self.sim.state.h_crit
        )
    }
}

impl Simulation {
    /// Before stepping: a failed simulation raises its error again; a cancelled one goes on.
    fn resume(&mut self, py: Python<'_>) -> PyResult<()> {
        if let Some(e) = &self.failure {
            return Err(solver_error(py, e, &self.scene.file));
        }
        self.cancelled = None;
        Ok(())
    }

    /// Notes a blow-up and returns it as a Python exception.
    fn failed(&mut self, py: Python<'_>, e: SolverError) -> PyErr {
        let err = solver_error(py, &e, &self.scene.file);
        self.failure = Some(e);
        err
    }
}

/// Why stepping stopped early.
enum Stop {
    Solver(SolverError),
    /// A Python signal handler raised (KeyboardInterrupt), or the progress bar did.
    Python(Option<PyErr>),
}

/// The cancellation at the current step of `sim`.
fn cancelled(sim: &Solver) -> SolverError {
    SolverError::Cancelled {
        step: sim.state.step_count,
        time: sim.state.time,
    }
}

/// Looks at Python's signals (and updates the progress bar) every [`SIGNAL_INTERVAL`] of wall
/// time, between steps, the GIL taken for that moment only.
struct Watch<'a> {
    last: Instant,
    bar: Option<&'a Py<PyAny>>,
    /// Set when a signal handler raised, to stop the driver.
    cancel: Option<&'a AtomicBool>,
    /// The exception a signal handler (or the progress bar) raised.
    signal: Option<PyErr>,
    /// Where each step's row goes (`run()`).
    history: Option<&'a mut History>,
}

impl<'a> Watch<'a> {
    fn new(bar: Option<&'a Py<PyAny>>) -> Watch<'a> {
        Watch {
            last: Instant::now(),
            bar,
            cancel: None,
            signal: None,
            history: None,
        }
    }

    /// True when a signal handler (or the bar) raised: the error is kept in `signal` and the
    /// driver, if any, told to stop.
    fn signalled(&mut self, sim: &Solver) -> bool {
        if self.signal.is_some() {
            return true;
        }
        if self.last.elapsed() < SIGNAL_INTERVAL {
            return false;
        }
        self.last = Instant::now();
        let result = Python::attach(|py| {
            py.check_signals()?;
            match self.bar {
                Some(bar) => update_bar(py, bar, sim),
                None => Ok(()),
            }
        });
        match result {
            Ok(()) => false,
            Err(e) => {
                if let Some(c) = self.cancel {
                    c.store(true, Ordering::SeqCst);
                }
                self.signal = Some(e);
                true
            }
        }
    }
}

impl Progress for Watch<'_> {
    fn step(&mut self, sim: &Solver) {
        if let Some(h) = self.history.as_deref_mut() {
            h.push(sim);
        }
        self.signalled(sim);
    }
}

/// A progress bar from `decohesion._progress.bar` (tqdm if installed, else a plain line) from
/// the current time to `until`.
fn progress_bar(py: Python<'_>, sim: &Solver, until: f64) -> PyResult<Py<PyAny>> {
    let bar = py.import("decohesion._progress")?.call_method1(
        "bar",
        (sim.model.name.as_str(), sim.state.time, until, sim.state.h),
    )?;
    Ok(bar.unbind())
}

/// Tells the bar where the simulation is: t, steps, ruptured and interface nodes.
fn update_bar(py: Python<'_>, bar: &Py<PyAny>, sim: &Solver) -> PyResult<()> {
    let ruptured = sim.state_counts().ruptured;
    bar.call_method1(
        py,
        "update",
        (
            sim.state.time,
            sim.state.step_count,
            ruptured,
            sim.state.interface_nodes.len(),
        ),
    )?;
    Ok(())
}

/// The recording's cadence from `every` (steps) or `fps` (frames per simulated second).
fn cadence(every: Option<i64>, fps: Option<f64>) -> PyResult<Cadence> {
    match (every, fps) {
        (Some(_), Some(_)) => Err(PyValueError::new_err(
            "give every= (steps) or fps= (frames per simulated second), not both",
        )),
        (Some(n), None) if n >= 1 => Ok(Cadence::EverySteps(n as u64)),
        (Some(n), None) => Err(PyValueError::new_err(format!(
            "every must be ≥ 1 step (got {n})"
        ))),
        (None, Some(f)) if f.is_finite() && f > 0.0 => Ok(Cadence::PerSimSecond(f)),
        (None, Some(f)) => Err(PyValueError::new_err(format!(
            "fps must be a finite number > 0 (got {f})"
        ))),
        (None, None) => Ok(Cadence::Default),
    }
}

/// The surface colour field by its command-line name.
fn colour_field(name: &str) -> PyResult<ColourField> {
    name.parse()
        .map_err(|e: String| PyValueError::new_err(format!("colour = {name:?}: {e}")))
}

/// A contact status as its int8 code.
fn status(s: ContactStatus) -> i8 {
    match s {
        ContactStatus::Open => 0,
        ContactStatus::Stick => 1,
        ContactStatus::Slip => 2,
    }
}
