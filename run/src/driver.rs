//! The run driver: one loop for the command line (`decohesion run`, `decohesion::cli::run`) and
//! the explorer's job thread (`decohesion::gui`). It opens the outputs of a run (ParaView files,
//! the Rerun recording), steps the simulation, takes one [`Snapshot`] per output frame at the
//! cadence of its [`FrameClock`] and hands it to every output (and the state after every step
//! to the outputs that take per-step scalars: the `--series` CSV), reports progress, stops on
//! cancellation (Ctrl-C, Stop) or on an output's error, and finishes every output whatever the
//! outcome, so the recording and the ParaView index are complete; then it builds the run's
//! [`RunSummary`] with the outputs' reports. With checkpoints ([`Driver::checkpoints`]) it
//! writes one when due after a step and one at the last step of a cancelled run.

use crate::checkpoint::Checkpointer;
use crate::output::watch::Watch;
use crate::output::{Cadence, Ending, FrameClock, Output, OutputError, Snapshot};
use crate::report::RunSummary;
use crate::solver::{Simulation, SolverError};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Told of every step, on the solver thread: the command line's progress bar, the explorer's
/// channel.
pub trait Progress {
    /// After every step (and its frame, if one was due).
    fn step(&mut self, sim: &Simulation);
    /// The simulation stopped (before the outputs are finished).
    fn stopped(&mut self) {}
}

/// How a run went.
pub struct Finished {
    /// The solver's outcome (`Cancelled` also when an output stopped the run).
    pub outcome: Result<(), SolverError>,
    /// The summary, with what each output wrote.
    pub summary: RunSummary,
    /// The first error of an output: the one that stopped the run, or one of finishing.
    pub output_error: Option<OutputError>,
}

/// Runs a simulation with its outputs.
pub struct Driver {
    outputs: Vec<Box<dyn Output>>,
    clock: FrameClock,
    /// Solver-thread time spent on the outputs: snapshots, sends.
    spent: Duration,
    /// Some output shows velocities: the snapshots copy V ([`Output::velocities`]).
    velocities: bool,
    /// Some output takes the frames ([`Output::frames`]): else no snapshot is copied.
    frames: bool,
    /// When the run started (set-up included), for the summary's wall time.
    started: Instant,
    /// Writes the run's checkpoints (`run --checkpoint`).
    checkpoints: Option<Checkpointer>,
    /// The watched nodes, read into every snapshot ([`Snapshot::watched`]).
    watch: Watch,
    /// The summary's keys of the outputs not asked for, null (set by the registry).
    pub(crate) absent: std::collections::BTreeMap<String, serde_json::Value>,
}

impl Driver {
    /// A driver over outputs built by the caller; tells them of the current state and takes
    /// its frame.
    pub fn with_outputs(
        outputs: Vec<Box<dyn Output>>,
        cadence: Cadence,
        sim: &Simulation,
        started: Instant,
    ) -> Result<Driver, OutputError> {
        Driver::watching(outputs, cadence, sim, started, Watch::default())
    }

    /// [`Driver::with_outputs`] whose snapshots carry the readings of `watch`'s nodes (the
    /// registry's `Driver::open`, [`crate::outputs`]).
    pub(crate) fn watching(
        outputs: Vec<Box<dyn Output>>,
        cadence: Cadence,
        sim: &Simulation,
        started: Instant,
        watch: Watch,
    ) -> Result<Driver, OutputError> {
        let mut driver = Driver {
            watch,
            velocities: outputs.iter().any(|o| o.velocities()),
            frames: outputs.iter().any(|o| o.frames()),
            outputs,
            clock: FrameClock::new(cadence, sim.model.end_time),
            spent: Duration::ZERO,
            started,
            checkpoints: None,
            absent: Default::default(),
        };
        driver.step(sim, false)?;
        driver.frame(sim)?;
        Ok(driver)
    }

    /// Writes checkpoints with `checkpointer`: when due after each step, and at the last step of
    /// a run cancelled by Ctrl-C, Stop or an output's error (not of a failed one: its state is
    /// what failed). A checkpoint that cannot be written stops the run as an output's error
    /// does.
    pub fn checkpoints(mut self, checkpointer: Checkpointer) -> Driver {
        self.checkpoints = Some(checkpointer);
        self
    }

    /// Tells every output of the state of `sim` after a step ([`Output::step`]; `last`: the
    /// final state): every output is told, also when another fails; the first error is
    /// returned.
    fn step(&mut self, sim: &Simulation, last: bool) -> Result<(), OutputError> {
        let started = Instant::now();
        let mut told = Ok(());
        for output in self.outputs.iter_mut() {
            let r = output.step(sim, last);
            if told.is_ok() {
                told = r;
            }
        }
        self.spent += started.elapsed();
        told
    }

    /// The snapshot of `sim` if its step was not taken yet and some output takes frames, with
    /// the watched nodes' readings.
    fn snapshot(&mut self, sim: &Simulation) -> Option<Arc<Snapshot>> {
        (self.clock.take(sim.state.step_count, sim.state.time) && self.frames).then(|| {
            let mut s = Snapshot::capture(sim, self.spent, self.velocities);
            s.watched = self.watch.readings(sim);
            Arc::new(s)
        })
    }

    /// Hands the state of `sim` to every output as one frame (once per step at most): every
    /// output gets it, also when another fails; the first error is returned.
    fn frame(&mut self, sim: &Simulation) -> Result<(), OutputError> {
        let started = Instant::now();
        let Some(snapshot) = self.snapshot(sim) else {
            return Ok(());
        };
        let mut sent = Ok(());
        for output in self.outputs.iter_mut() {
            let r = output.frame(&snapshot);
            if sent.is_ok() {
                sent = r;
            }
        }
        self.spent += started.elapsed();
        sent
    }

    /// Steps `sim` to its end time, or until `cancel` is set or an output fails; then
    /// finishes every output with the last state and builds the summary.
    pub fn run(
        self,
        sim: &mut Simulation,
        cancel: &AtomicBool,
        progress: &mut dyn Progress,
    ) -> Finished {
        let end = sim.model.end_time;
        self.run_until(sim, end, cancel, progress)
    }

    /// [`Driver::run`] to the time `until` [s] instead of the end time: steps while
    /// tₙ < `until` − 10⁻⁶ hₙ (the test of [`Simulation::finished`], which it is for
    /// `until` = end time), so the last step is the first at or past `until`. The Python
    /// API's `run(until=…)`; `until` may lie past the end time.
    pub fn run_until(
        mut self,
        sim: &mut Simulation,
        until: f64,
        cancel: &AtomicBool,
        progress: &mut dyn Progress,
    ) -> Finished {
        let mut output_error = None;
        let outcome = loop {
            if sim.state.time >= until - 1e-6 * sim.state.h {
                break Ok(());
            }
            if let Err(e) = sim.step() {
                break Err(e);
            }
            let s = &*sim;
            if let Err(e) = self.step(s, false) {
                output_error = Some(e);
                break Err(cancelled(s));
            }
            if self.clock.due(s.state.step_count, s.state.time) {
                if let Err(e) = self.frame(s) {
                    output_error = Some(e);
                    break Err(cancelled(s));
                }
            }
            if let Some(c) = &mut self.checkpoints {
                if let Err(e) = c.after_step(s) {
                    output_error = Some(checkpoint_error(e));
                    break Err(cancelled(s));
                }
            }
            progress.step(s);
            if cancel.load(Ordering::SeqCst) {
                break Err(cancelled(s));
            }
        };
        progress.stopped();
        if let (Err(SolverError::Cancelled { .. }), Some(c)) = (&outcome, &mut self.checkpoints) {
            if let Err(e) = c.write(sim) {
                output_error.get_or_insert(checkpoint_error(e));
            }
        }
        if let Err(e) = self.step(sim, true) {
            output_error.get_or_insert(e);
        }
        let last = self.snapshot(sim);
        let end = Ending {
            step: sim.state.step_count,
            time: sim.state.time,
            error: outcome.as_ref().err(),
            step_seconds: sim.stats.steps_wall.as_secs_f64(),
        };
        let mut reports = Vec::new();
        for output in self.outputs {
            match output.finish(last.clone(), &end) {
                Ok(r) => reports.push(r),
                Err(e) => {
                    output_error.get_or_insert(e);
                }
            }
        }
        let wall = self.started.elapsed().as_secs_f64();
        let mut summary = RunSummary::new(sim, wall, outcome.as_ref().err());
        summary.checkpoint = self.checkpoints.as_ref().map(Checkpointer::report);
        summary.outputs = std::mem::take(&mut self.absent);
        for r in reports {
            summary.add_output(r);
        }
        Finished {
            outcome,
            summary,
            output_error,
        }
    }
}

/// A checkpoint that cannot be written, as an output's error ("checkpoint: …").
fn checkpoint_error(e: decohesion_physics::solver::CheckpointError) -> OutputError {
    OutputError::new("checkpoint", Some("checkpoint"), e)
}

/// The error of a run stopped at the current step of `sim` (Ctrl-C, Stop, an output's error).
fn cancelled(sim: &Simulation) -> SolverError {
    SolverError::Cancelled {
        step: sim.state.step_count,
        time: sim.state.time,
    }
}

/// Sets `flag` on Ctrl-C (SIGINT): the run stops after the current step and its outputs and
/// summary are written. A second Ctrl-C leaves at once (a recording then lacks its footer; the
/// ParaView index holds the frames written so far).
pub fn cancel_on_ctrl_c(flag: Arc<AtomicBool>) {
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::reports::{VtkError, VtkReport};
    use crate::output::OutputReport;
    use std::sync::Mutex;

    /// What a probe output saw: the steps of its frames (the last one included) and, once
    /// finished, (step of the last snapshot if any, the end's step, whether it had an error).
    #[derive(Default)]
    struct Seen {
        frames: Vec<u64>,
        finished: Vec<(Option<u64>, u64, bool)>,
        /// (nodes in U, nodes in V) of each frame.
        sizes: Vec<(usize, usize)>,
    }

    /// An output that notes what it is given, and fails at step `fail_at`.
    struct Probe {
        seen: Arc<Mutex<Seen>>,
        fail_at: Option<u64>,
        velocities: bool,
    }

    impl Output for Probe {
        fn frame(&mut self, s: &Arc<Snapshot>) -> Result<(), OutputError> {
            let mut seen = self.seen.lock().unwrap();
            seen.frames.push(s.step);
            seen.sizes.push((s.u.len(), s.v.len()));
            drop(seen);
            if self.fail_at == Some(s.step) {
                return Err(VtkError::Thread("disk full".into()).into());
            }
            Ok(())
        }

        fn velocities(&self) -> bool {
            self.velocities
        }

        fn finish(
            self: Box<Self>,
            last: Option<Arc<Snapshot>>,
            end: &Ending<'_>,
        ) -> Result<OutputReport, OutputError> {
            let mut seen = self.seen.lock().unwrap();
            let last = last.map(|s| s.step);
            seen.frames.extend(last);
            seen.finished.push((last, end.step, end.error.is_some()));
            Ok(OutputReport::new("paraview", &VtkReport::default(), None))
        }
    }

    /// Counts the steps and sets the cancel flag at step `stop_at`.
    struct Counter {
        steps: u64,
        stop_at: u64,
        cancel: Arc<AtomicBool>,
    }

    impl Progress for Counter {
        fn step(&mut self, sim: &Simulation) {
            self.steps += 1;
            if sim.state.step_count == self.stop_at {
                self.cancel.store(true, Ordering::SeqCst);
            }
        }
    }

    /// The 2³ pull-off cube to `end_time`, and two probes (the first failing at `fail_at`; the
    /// second showing velocities when `velocities`).
    fn run_with(
        end_time: f64,
        stop_at: u64,
        fail_at: Option<u64>,
        velocities: bool,
    ) -> (Finished, [Seen; 2], u64) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/pull_off.toml");
        let set = ["mesh.cells=[2,2,2]".into(), format!("end_time={end_time}")];
        let scene = crate::scene::load_scene(&path, &set).unwrap();
        let mut sim = Simulation::new(scene.model).unwrap();
        let seen = [(); 2].map(|_| Arc::new(Mutex::new(Seen::default())));
        let outputs: Vec<Box<dyn Output>> = vec![
            Box::new(Probe {
                seen: seen[0].clone(),
                fail_at,
                velocities: false,
            }),
            Box::new(Probe {
                seen: seen[1].clone(),
                fail_at: None,
                velocities,
            }),
        ];
        let driver =
            Driver::with_outputs(outputs, Cadence::EverySteps(4), &sim, Instant::now()).unwrap();
        let cancel = Arc::new(AtomicBool::new(false));
        let mut counter = Counter {
            steps: 0,
            stop_at,
            cancel: cancel.clone(),
        };
        let done = driver.run(&mut sim, &cancel, &mut counter);
        let seen = seen.map(|s| std::mem::take(&mut *s.lock().unwrap()));
        (done, seen, counter.steps)
    }

    /// [`run_with`] with outputs that draw no velocities.
    fn run(end_time: f64, stop_at: u64, fail_at: Option<u64>) -> (Finished, [Seen; 2], u64) {
        run_with(end_time, stop_at, fail_at, false)
    }

    /// The snapshots copy V only when some output shows it (the ParaView files), and then
    /// every output gets the same frame with U and V of every node.
    #[test]
    fn snapshots_copy_velocities_only_for_an_output_that_shows_them() {
        for velocities in [false, true] {
            let (done, seen, _) = run_with(0.01, u64::MAX, None, velocities);
            assert!(done.outcome.is_ok());
            let nodes = 27; // the 2³ cube
            for s in &seen {
                assert!(!s.sizes.is_empty());
                for &(u, v) in &s.sizes {
                    assert_eq!(u, nodes);
                    assert_eq!(
                        v,
                        if velocities { nodes } else { 0 },
                        "velocities: {velocities}"
                    );
                }
            }
        }
    }

    /// A completed run: step 0, every 4th step and the last step, once each, to every output;
    /// each output finished once; the summary completed.
    #[test]
    fn a_completed_run_feeds_every_output_the_same_frames() {
        let (done, seen, steps) = run(0.02, u64::MAX, None);
        assert!(done.outcome.is_ok());
        assert!(done.output_error.is_none());
        assert_eq!(done.summary.status, "completed");
        let n = done.summary.steps;
        assert!(n > 8, "{n} steps");
        assert_eq!(steps, n, "progress after every step");
        let off_grid = n % 4 != 0;
        let expect: Vec<u64> = (0..=n)
            .filter(|k| k % 4 == 0)
            .chain(off_grid.then_some(n))
            .collect();
        for s in &seen {
            assert_eq!(s.frames, expect);
            assert_eq!(s.finished, vec![(off_grid.then_some(n), n, false)]);
        }
        assert!(
            done.summary.outputs["paraview"].is_object(),
            "the reports reach the summary"
        );
    }

    /// Cancelled at step 6: frames 0 and 4, then step 6 as the last one; the outputs are told.
    #[test]
    fn a_cancelled_run_finishes_every_output_with_the_last_step() {
        let (done, seen, _) = run(1.0, 6, None);
        assert!(matches!(
            done.outcome,
            Err(SolverError::Cancelled { step: 6, .. })
        ));
        assert_eq!(done.summary.status, "cancelled");
        for s in &seen {
            assert_eq!(s.frames, vec![0, 4, 6]);
            assert_eq!(s.finished, vec![(Some(6), 6, true)]);
        }
    }

    /// An output failing at step 8 stops the run there; the other output still got that
    /// frame; both are finished; the error is reported.
    #[test]
    fn an_output_error_stops_the_run_and_is_reported() {
        let (done, seen, _) = run(1.0, u64::MAX, Some(8));
        assert!(matches!(
            done.outcome,
            Err(SolverError::Cancelled { step: 8, .. })
        ));
        let err = done.output_error.expect("the output's error");
        assert!(err.to_string().contains("disk full"), "{err}");
        for s in &seen {
            assert_eq!(s.frames, vec![0, 4, 8]);
            assert_eq!(s.finished, vec![(None, 8, true)]);
        }
    }
    /// `run_until` stops at the first step at or past `until` (stepping one by one tells which),
    /// as a completed run, the outputs' last frame at that step; a second call goes on from
    /// there to the end time.
    #[test]
    fn run_until_stops_at_the_first_step_at_or_past_until() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/pull_off.toml");
        let set = ["mesh.cells=[2,2,2]".into(), "end_time=0.02".into()];
        let model = crate::scene::load_scene(&path, &set).unwrap().model;
        let until = 0.0071;
        let mut by_steps = Simulation::new(model.clone()).unwrap();
        while by_steps.state.time < until - 1e-6 * by_steps.state.h {
            by_steps.step().unwrap();
        }
        let mut sim = Simulation::new(model).unwrap();
        let seen = Arc::new(Mutex::new(Seen::default()));
        let probe = Probe {
            seen: seen.clone(),
            fail_at: None,
            velocities: false,
        };
        let driver = Driver::with_outputs(
            vec![Box::new(probe)],
            Cadence::EverySteps(1000),
            &sim,
            Instant::now(),
        )
        .unwrap();
        let cancel = AtomicBool::new(false);
        let mut counter = Counter {
            steps: 0,
            stop_at: u64::MAX,
            cancel: Arc::new(AtomicBool::new(false)),
        };
        let done = driver.run_until(&mut sim, until, &cancel, &mut counter);
        assert!(done.outcome.is_ok());
        assert_eq!(done.summary.status, "completed");
        let n = by_steps.state.step_count;
        assert!(n > 5 && sim.state.step_count == n && sim.state.time == by_steps.state.time);
        assert_eq!(seen.lock().unwrap().frames, vec![0, n]);
        let driver = Driver::with_outputs(vec![], Cadence::Default, &sim, Instant::now()).unwrap();
        let done = driver.run(&mut sim, &cancel, &mut counter);
        assert!(done.outcome.is_ok() && sim.finished() && sim.state.step_count > n);
    }
}
