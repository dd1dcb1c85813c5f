//! A run of the explorer on its own thread: set up, run through the run driver
//! ([`crate::driver`]) with the recording and ParaView files the settings ask for, report
//! progress over a channel, end with a history row (also when the thread panics).

use super::frames::{Frame, FrameSampler};
use super::history::{output_error_text, CurvePoint, RunCurve};
use super::{HistoryRow, Settings};
use crate::driver::{Driver, Plan, Progress};
use crate::record::{Cadence, ColourField, Sink};
use crate::scene::Scene;
use crate::solver::Simulation;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender, TryRecvError};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Asks the window for a repaint (from any thread); `None` without a window.
pub type Repaint = Arc<dyn Fn() + Send + Sync>;

/// What the solver thread reports.
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

/// A run on its own thread.
pub struct Job {
    pub id: u32,
    pub end_time: f64,
    pub started: Instant,
    pub cancel: Arc<AtomicBool>,
    rx: Receiver<JobMessage>,
    /// The last progress: step and sample.
    pub last: Option<(u64, CurvePoint)>,
}

impl Job {
    /// Starts run `id` of `scene` on its own thread, recorded to `sink` if any.
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
            cancel,
            rx,
            last: None,
        })
    }

    /// The next message of the solver thread, without waiting.
    pub fn try_recv(&self) -> Result<JobMessage, TryRecvError> {
        self.rx.try_recv()
    }

    /// Asks the solver to stop after its current step.
    pub fn stop(&self) {
        self.cancel.store(true, Ordering::SeqCst);
    }
}

/// The solver thread: set up, record, step until done or stopped, report.
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
    let plan = Plan {
        cadence: Cadence::PerSimSecond(settings.frames.max(1) as f64 / sim.model.end_time),
        paraview: settings.paraview.then(|| {
            let stem = settings.scene_stem();
            Path::new(&settings.output_dir).join(format!("run{id:03}_{stem}_vtk"))
        }),
        recording: sink.map(|s| (s, ColourField::Displacement)),
    };
    let driver = match Driver::open(&plan, scene, &sim, started) {
        Ok(d) => d,
        Err(e) => return HistoryRow::failed(id, settings, output_error_text(&e), started),
    };
    let mut progress = Channel {
        tx,
        repaint,
        last_report: Instant::now(),
        sample: sim.model.end_time / 300.0,
        next_sample: 0.0,
        curve: RunCurve::default(),
        frames: FrameSampler::new(&sim, settings.frames),
    };
    progress.send_frame(&sim, false);
    let done = driver.run(&mut sim, cancel, &mut progress);
    progress.send_frame(&sim, true);
    let mut row = HistoryRow::from_run(id, settings, &done, recording_target);
    progress.curve.finish(CurvePoint::of(&sim));
    row.curve = progress.curve;
    row
}

/// Progress over the job's channel: every 50 ms of wall time (the bar) and every end_time/300
/// of simulated time (the curves over time), whichever comes first; each sample is also kept
/// in the run's curve (decimated past [`super::history::CURVE_MAX_POINTS`]).
struct Channel<'a> {
    tx: &'a Sender<JobMessage>,
    repaint: Option<Repaint>,
    last_report: Instant,
    /// Simulated time between two points of the curve [s].
    sample: f64,
    next_sample: f64,
    curve: RunCurve,
    frames: FrameSampler,
}

impl Channel<'_> {
    /// Sends the frame of `s` if one is due, or if `s` is the final state.
    fn send_frame(&mut self, s: &Simulation, last: bool) {
        let frame = match last {
            false => self.frames.due(s),
            true => self.frames.last(s),
        };
        if let Some(f) = frame {
            let _ = self.tx.send(JobMessage::Frame(Box::new(f)));
        }
    }
}

impl Progress for Channel<'_> {
    fn step(&mut self, s: &Simulation) {
        self.send_frame(s, false);
        if self.last_report.elapsed() >= Duration::from_millis(50) || s.time >= self.next_sample {
            self.last_report = Instant::now();
            self.next_sample = s.time + self.sample;
            let point = CurvePoint::of(s);
            self.curve.push(point);
            let _ = self.tx.send(JobMessage::Progress {
                step: s.step_count,
                point,
            });
            if let Some(r) = &self.repaint {
                r();
            }
        }
    }
}
