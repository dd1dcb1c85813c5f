//! A run of the explorer, reported as [`JobMessage`]s: on native on its own thread, through the
//! run driver ([`crate::driver`]) with the recording and ParaView files the settings ask for; in
//! the web page inside the frame loop ([`super::page_run`]), a slice of steps per frame. Both
//! runners take their samples with one [`Sampler`], so a message is built in one place for
//! both; the run ends with a history row (also when the native thread panics).

use super::frames::{Frame, FrameSampler};
use super::history::{CurvePoint, RunCurve};
use super::page_run::PageRun;
use super::{HistoryRow, Settings};
use crate::scene::Scene;
use crate::solver::Simulation;
use std::sync::mpsc::TryRecvError;
use std::sync::Arc;
use std::time::Duration;
use web_time::Instant;
// The thread's run: the driver, its outputs, the channel.
#[cfg(not(target_arch = "wasm32"))]
use {
    super::history::output_error_text,
    crate::driver::{Driver, Progress},
    crate::outputs::Plan,
    crate::record::{Cadence, Sink},
    std::path::Path,
    std::sync::atomic::{AtomicBool, Ordering},
    std::sync::mpsc::{channel, Receiver, Sender},
};

/// Asks the window for a repaint (from any thread); `None` without a window.
pub type Repaint = Arc<dyn Fn() + Send + Sync>;

/// What a run reports (the solver thread over its channel, the page runner from its queue).
#[derive(Debug)]
pub enum JobMessage {
    /// A sample of the run (also kept in the run's [`RunCurve`], which its row carries).
    Progress {
        step: u64,
        point: CurvePoint,
    },
    /// A frame for the 3-D view ([`super::frames`]), at the recorder's cadence.
    Frame(Box<Frame>),
    Done(Box<HistoryRow>),
}

/// When a run reports, for both runners: every 50 ms of wall time (the bar) and every
/// end_time/300 of simulated time (the curves over time), whichever comes first; each sample is
/// also kept in the run's curve (decimated past [`super::history::CURVE_MAX_POINTS`]). The 3-D
/// view's frames at the recorder's cadence ([`FrameSampler`]), the first at t = 0 and the last
/// at the end.
pub struct Sampler {
    last_report: Instant,
    /// Simulated time between two points of the curve [s].
    sample: f64,
    next_sample: f64,
    pub curve: RunCurve,
    frames: FrameSampler,
}

impl Sampler {
    /// The sampler of a run of `sim` with `frames` frames over its end time; hands `send` the
    /// frame at t = 0.
    pub fn new(sim: &Simulation, frames: u32, send: &mut dyn FnMut(JobMessage)) -> Sampler {
        let mut sampler = Sampler {
            last_report: Instant::now(),
            sample: sim.model.end_time / 300.0,
            next_sample: 0.0,
            curve: RunCurve::default(),
            frames: FrameSampler::new(sim, frames),
        };
        if let Some(f) = sampler.frames.due(sim) {
            send(JobMessage::Frame(Box::new(f)));
        }
        sampler
    }

    /// After a step of `s`: hands `send` the messages due now (none at most steps). The one
    /// place where both runners build their messages from the simulation.
    pub fn after_step(&mut self, s: &Simulation, send: &mut dyn FnMut(JobMessage)) {
        if let Some(f) = self.frames.due(s) {
            send(JobMessage::Frame(Box::new(f)));
        }
        if self.last_report.elapsed() >= Duration::from_millis(50)
            || s.state.time >= self.next_sample
        {
            self.last_report = Instant::now();
            self.next_sample = s.state.time + self.sample;
            let point = CurvePoint::of(s);
            self.curve.push(point);
            send(JobMessage::Progress {
                step: s.state.step_count,
                point,
            });
        }
    }

    /// The run's curve, ended with the last state of `s`; hands `send` the last frame.
    pub fn finish(mut self, s: &Simulation, send: &mut dyn FnMut(JobMessage)) -> RunCurve {
        if let Some(f) = self.frames.last(s) {
            send(JobMessage::Frame(Box::new(f)));
        }
        self.curve.finish(CurvePoint::of(s));
        self.curve
    }
}

/// A run in progress: on its own thread (native) or stepped by the page's frames.
pub struct Job {
    pub id: u32,
    pub end_time: f64,
    pub started: Instant,
    /// The last progress: step and sample.
    pub last: Option<(u64, CurvePoint)>,
    runner: Runner,
}

enum Runner {
    #[cfg(not(target_arch = "wasm32"))]
    Thread {
        cancel: Arc<AtomicBool>,
        rx: Receiver<JobMessage>,
    },
    Page(Box<PageRun>),
}

impl Job {
    /// Starts run `id` of `scene` on its own thread, recorded to `sink` if any.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn start(
        id: u32,
        scene: Scene,
        sink: Option<Sink>,
        settings: Settings,
        repaint: Option<Repaint>,
    ) -> std::io::Result<Job> {
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = channel();
        let flag = cancel.clone();
        let end_time = scene.model.end_time;
        std::thread::Builder::new()
            .name(format!("decohesion-run-{id}"))
            .spawn(move || {
                let started = Instant::now();
                let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run_job(id, &scene, sink, &settings, &flag, &tx, repaint.clone())
                }));
                let row = outcome.unwrap_or_else(|panic| {
                    let msg = panic
                        .downcast_ref::<String>()
                        .cloned()
                        .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_else(|| "unknown panic".into());
                    let error = format!("panic in the solver thread: {msg}");
                    HistoryRow::failed(id, &settings, error, started)
                });
                let _ = tx.send(JobMessage::Done(Box::new(row)));
                if let Some(r) = repaint {
                    r();
                }
            })?;
        Ok(Job {
            id,
            end_time,
            started: Instant::now(),
            last: None,
            runner: Runner::Thread { cancel, rx },
        })
    }

    /// Starts run `id` of `scene` in the page: set up now, stepped by [`Job::advance`].
    pub fn in_page(id: u32, scene: Scene, settings: Settings) -> Job {
        let end_time = scene.model.end_time;
        Job {
            id,
            end_time,
            started: Instant::now(),
            last: None,
            runner: Runner::Page(Box::new(PageRun::new(id, scene, settings))),
        }
    }

    /// Steps a run in the page for about `budget` of wall time (nothing for a thread's run);
    /// true while it goes on.
    pub fn advance(&mut self, budget: Duration) -> bool {
        match &mut self.runner {
            Runner::Page(run) => run.advance(budget),
            #[cfg(not(target_arch = "wasm32"))]
            Runner::Thread { .. } => true,
        }
    }

    /// True for a run stepped by the page's frames.
    pub fn in_frames(&self) -> bool {
        matches!(self.runner, Runner::Page(_))
    }

    /// The next message of the run, without waiting.
    pub fn try_recv(&mut self) -> Result<JobMessage, TryRecvError> {
        match &mut self.runner {
            Runner::Page(run) => run.next_message(),
            #[cfg(not(target_arch = "wasm32"))]
            Runner::Thread { rx, .. } => rx.try_recv(),
        }
    }

    /// Asks the solver to stop after its current step.
    pub fn stop(&mut self) {
        match &mut self.runner {
            Runner::Page(run) => run.stop(),
            #[cfg(not(target_arch = "wasm32"))]
            Runner::Thread { cancel, .. } => cancel.store(true, Ordering::SeqCst),
        }
    }
}

/// The solver thread: set up, record, step until done or stopped, report.
#[cfg(not(target_arch = "wasm32"))]
fn run_job(
    id: u32,
    scene: &Scene,
    sink: Option<Sink>,
    settings: &Settings,
    cancel: &AtomicBool,
    tx: &Sender<JobMessage>,
    repaint: Option<Repaint>,
) -> HistoryRow {
    let started = Instant::now();
    let mut sim = match Simulation::new(scene.model.clone()) {
        Ok(s) => s,
        Err(e) => return HistoryRow::failed(id, settings, e.to_string(), started),
    };
    let recording_target = sink.as_ref().map(|s| match s {
        Sink::Save(p) => p.display().to_string(),
        Sink::Spawn => "Rerun viewer".to_string(),
        Sink::Connect(u) => u.clone().unwrap_or_else(|| "Rerun viewer".into()),
    });
    // The outputs in the command line's words (the registry's flags).
    let mut flags: Vec<std::ffi::OsString> = Vec::new();
    if settings.paraview {
        let stem = settings.scene_stem();
        let dir = Path::new(&settings.output_dir).join(format!("run{id:03}_{stem}_vtk"));
        flags.extend(["--vtk".into(), dir.into()]);
    }
    match sink {
        Some(Sink::Save(p)) => flags.extend(["--save".into(), p.into()]),
        Some(Sink::Spawn) => flags.push("--spawn".into()),
        Some(Sink::Connect(url)) => {
            flags.extend(["--connect".into(), url.unwrap_or_default().into()])
        }
        None => {}
    }
    let mut plan = match Plan::parse(flags) {
        Ok(p) => p,
        Err(e) => return HistoryRow::failed(id, settings, e.to_string(), started),
    };
    plan.cadence = Cadence::PerSimSecond(settings.frames.max(1) as f64 / sim.model.end_time);
    let driver = match Driver::open(&plan, scene, &sim, started) {
        Ok(d) => d,
        Err(e) => return HistoryRow::failed(id, settings, output_error_text(&e), started),
    };
    let mut progress = Channel {
        tx,
        repaint,
        sampler: Sampler::new(&sim, settings.frames, &mut |m| {
            let _ = tx.send(m);
        }),
    };
    let done = driver.run(&mut sim, cancel, &mut progress);
    let mut row = HistoryRow::from_run(id, settings, &done, recording_target);
    row.curve = progress.sampler.finish(&sim, &mut |m| {
        let _ = tx.send(m);
    });
    row
}

/// Progress over the job's channel, sampled by the [`Sampler`].
#[cfg(not(target_arch = "wasm32"))]
struct Channel<'a> {
    tx: &'a Sender<JobMessage>,
    repaint: Option<Repaint>,
    sampler: Sampler,
}

#[cfg(not(target_arch = "wasm32"))]
impl Progress for Channel<'_> {
    fn step(&mut self, s: &Simulation) {
        let mut sent = false;
        self.sampler.after_step(s, &mut |m| {
            let _ = self.tx.send(m);
            sent = true;
        });
        if sent {
            if let Some(r) = &self.repaint {
                r();
            }
        }
    }
}
