//! A run stepped inside the frame loop, for the web page (one thread: the page's): each frame
//! [`PageRun::advance`] takes steps for a wall-time budget and returns, so the page keeps
//! drawing and Stop is seen at the next frame. It writes no recording and no file; its
//! messages are the native thread's ([`JobMessage`], built by the same [`Sampler`]), and its
//! end is the summary `decohesion run --summary` writes ([`RunSummary`]) and a history row.
//!
//! The loop is the run driver's ([`crate::driver`] on native) without outputs: a step while
//! tₙ < end − 10⁻⁶ h ([`Simulation::finished`]), the samples after each step, the cancel flag
//! after each step. It compiles on native too, where the tests check it gives the thread's
//! results bit for bit.

use super::job::{JobMessage, Sampler};
use super::{HistoryRow, Settings};
use crate::report::RunSummary;
use crate::scene::Scene;
use crate::solver::{Simulation, SolverError};
use std::collections::VecDeque;
use std::sync::mpsc::TryRecvError;
use std::time::Duration;
use web_time::Instant;

pub use crate::tunables::DRAWING_RATIO;

pub use crate::tunables::MAX_SLICE;

/// A run of the page in progress.
pub struct PageRun {
    id: u32,
    settings: Settings,
    /// `None` once the run has ended (or when its set-up failed).
    state: Option<(Simulation, Sampler)>,
    started: Instant,
    cancel: bool,
    /// Messages not read yet.
    outbox: VecDeque<JobMessage>,
    /// When the last slice of steps ended: the time since is what the page spent drawing.
    slice_end: Option<Instant>,
    /// Slices of steps taken (frames that stepped).
    pub slices: u64,
}

impl PageRun {
    /// Sets run `id` of `scene` up (mesh, masses, the Lanczos estimate of h_crit); a set-up
    /// that fails ends the run at once with a failed row.
    pub fn new(id: u32, scene: Scene, settings: Settings) -> PageRun {
        let started = Instant::now();
        let mut run = PageRun {
            id,
            settings,
            state: None,
            started,
            cancel: false,
            outbox: VecDeque::new(),
            slice_end: None,
            slices: 0,
        };
        match Simulation::new(scene.model) {
            Ok(sim) => {
                let outbox = &mut run.outbox;
                let sampler = Sampler::new(&sim, run.settings.frames, &mut |m| outbox.push_back(m));
                run.state = Some((sim, sampler));
            }
            Err(e) => {
                let row = HistoryRow::failed(id, &run.settings, e.to_string(), started);
                run.outbox.push_back(JobMessage::Done(Box::new(row)));
            }
        }
        run
    }

    /// Steps for about `budget` of wall time, or for [`DRAWING_RATIO`] times as long as the
    /// page took since the last slice (its drawing) if that is longer, at most [`MAX_SLICE`]
    /// (at least one step), then returns; ends the run when it reaches its end time, fails, or
    /// was stopped. True while it goes on.
    ///
    /// The stretch draws a new picture only when the solver has had its share since the last
    /// one: drawing takes at most 1/(1 + [`DRAWING_RATIO`]) of the page's time when it is slow
    /// (software WebGL under headless Chromium; docs: performance log), at the price of fewer
    /// pictures per second; with fast drawing a frame steps for `budget`, so the page draws at
    /// its own rate and Stop acts within a frame.
    pub fn advance(&mut self, budget: Duration) -> bool {
        let Some((sim, sampler)) = &mut self.state else {
            return false;
        };
        let slice = Instant::now();
        let budget = self.slice_end.map_or(budget, |end| {
            budget.max((slice - end).saturating_mul(DRAWING_RATIO).min(MAX_SLICE))
        });
        self.slices += 1;
        let outbox = &mut self.outbox;
        let outcome = loop {
            if sim.finished() {
                break Ok(());
            }
            if self.cancel {
                break Err(cancelled(sim));
            }
            if let Err(e) = sim.step() {
                break Err(e);
            }
            sampler.after_step(sim, &mut |m| outbox.push_back(m));
            if slice.elapsed() >= budget {
                self.slice_end = Some(Instant::now());
                return true;
            }
        };
        self.end(outcome);
        false
    }

    /// The run's end: the summary, the row with its curve, the `Done` message.
    fn end(&mut self, outcome: Result<(), SolverError>) {
        let Some((sim, sampler)) = self.state.take() else {
            return;
        };
        let wall = self.started.elapsed().as_secs_f64();
        let summary = RunSummary::new(&sim, wall, outcome.as_ref().err());
        let error = match outcome {
            Ok(()) | Err(SolverError::Cancelled { .. }) => None,
            Err(e) => Some(e.to_string()),
        };
        #[cfg(target_arch = "wasm32")]
        super::browser::log(&format!(
            "decohesion: run {} {}: {} steps in {} frames, {:.3} s in step(), {:.3} s wall",
            self.id, summary.status, summary.steps, self.slices, summary.step_wall_seconds, wall
        ));
        let mut row = HistoryRow::from_summary(self.id, &self.settings, &summary, error, None);
        let outbox = &mut self.outbox;
        row.curve = sampler.finish(&sim, &mut |m| outbox.push_back(m));
        self.outbox.push_back(JobMessage::Done(Box::new(row)));
    }

    /// Stop: the run ends before its next step (at the next frame).
    pub fn stop(&mut self) {
        self.cancel = true;
    }

    /// The next message, without waiting; `Disconnected` once the run has ended and every
    /// message was read.
    pub fn next_message(&mut self) -> Result<JobMessage, TryRecvError> {
        match self.outbox.pop_front() {
            Some(m) => Ok(m),
            None if self.state.is_some() => Err(TryRecvError::Empty),
            None => Err(TryRecvError::Disconnected),
        }
    }
}

/// The error of a run stopped at the current step of `sim` (Stop).
fn cancelled(sim: &Simulation) -> SolverError {
    SolverError::Cancelled {
        step: sim.state.step_count,
        time: sim.state.time,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{App, RecordChoice, Status};
    use std::path::Path;
    use std::time::{Duration, Instant};

    /// The explorer with the 7³ pull-off (64 glued nodes), recording off.
    fn pull_off(in_page: bool) -> App {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut app = App::default();
        app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
        app.settings.cells = 7;
        app.settings.record = RecordChoice::Off;
        app.in_page = in_page;
        app
    }

    fn run_to_end(app: &mut App) {
        app.start();
        assert_eq!(app.status, Status::Running);
        let started = Instant::now();
        while app.poll() {
            assert!(started.elapsed() < Duration::from_secs(60), "no end");
            if !app.in_page {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    }

    /// A run stepped in frames (the page's runner) gives the thread's run bit for bit — steps,
    /// time, counts, energies, peak force, the curve — since both step the same simulation
    /// with the same loop and outputs only read it; the page's slices of 10 ms take many
    /// frames (the page keeps drawing), and the row's summary is the JSON `run --summary`
    /// writes.
    #[test]
    fn frames_give_the_threads_results() {
        let mut thread = pull_off(false);
        run_to_end(&mut thread);
        let mut page = pull_off(true);
        page.start();
        let mut frames = 0;
        while page.poll() {
            frames += 1;
        }
        assert_eq!(page.status, Status::Ended("finished".into()));
        let (a, b) = (&thread.history[0], &page.history[0]);
        assert_eq!((b.counts.ruptured, b.interface_nodes), (64, 64));
        assert_eq!(
            (a.steps, a.simulated_time, a.counts, a.time_full_rupture),
            (b.steps, b.simulated_time, b.counts, b.time_full_rupture)
        );
        assert_eq!(a.damage_dissipated.to_bits(), b.damage_dissipated.to_bits());
        assert_eq!(a.peak_force, b.peak_force);
        assert_eq!(a.max_relative_residual, b.max_relative_residual);
        assert_eq!(a.curve.points.last(), b.curve.points.last());
        assert!(frames > 1, "{frames} frames");
        let json: serde_json::Value =
            serde_json::from_str(b.summary_json.as_deref().unwrap()).unwrap();
        assert_eq!(json["status"], "completed");
        assert_eq!(json["final_counts"]["ruptured"], 64);
    }

    /// Stop in the page ends the run at the next frame, before any further step: a `stopped`
    /// status and a `cancelled` row at the step reached.
    #[test]
    fn stop_ends_a_page_run_at_the_next_frame() {
        let mut app = pull_off(true);
        app.start();
        assert!(app.poll(), "10 ms do not finish the 7³ run (~2000 steps)");
        let reached = app.job.as_ref().and_then(|j| j.last).map(|l| l.0);
        app.stop();
        assert!(!app.poll(), "ended at the next frame");
        assert_eq!(app.status, Status::Ended("stopped".into()));
        let row = &app.history[0];
        assert_eq!(row.status, "cancelled");
        assert!(
            row.steps >= reached.unwrap_or(0) && row.steps > 0,
            "{}",
            row.steps
        );
        assert!(row.counts.ruptured < 64);
    }
}
