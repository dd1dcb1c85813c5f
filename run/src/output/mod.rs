//! What the run outputs share — the Rerun recording ([`crate::record`]) and the ParaView files
//! ([`crate::vtk`]): when a frame is due ([`Cadence`], [`FrameClock`]), the state a frame shows
//! ([`Snapshot`], copied once per frame by the run driver, [`crate::driver`]), the per-element
//! fields both show ([`fields`]), the writer threads ([`worker`]) and the interface an output
//! offers the driver ([`Output`]), and what each output reports at its end or fails with
//! ([`reports`]). Uses neither the Rerun SDK nor any file format itself (the recorder's error
//! only holds the SDK's error type), except the time series of the run's scalars ([`series`],
//! `--series FILE.csv`). The nodes a run watches (`--watch`) and what is read of one are
//! [`watch`].

pub mod fields;
#[cfg(not(target_arch = "wasm32"))]
pub mod reports;
#[cfg(not(target_arch = "wasm32"))]
pub mod series;
pub mod snapshot;
pub mod surface;
pub mod watch;
pub mod worker;

pub use snapshot::{InterfaceSnapshot, Snapshot};

use crate::solver::SolverError;
// The outputs themselves are native (the web page has none); the cadence, the snapshot and the
// per-element fields are shared.
#[cfg(not(target_arch = "wasm32"))]
use {crate::solver::Simulation, std::sync::Arc};

/// One output of a run (the Rerun recording, the ParaView files), fed by the run driver
/// ([`crate::driver::Driver`]) with one shared [`Snapshot`] per frame, at the cadence of the
/// driver's one [`FrameClock`]: every output of a run holds the same steps.
#[cfg(not(target_arch = "wasm32"))]
pub trait Output {
    /// Takes one frame. An error stops the run; the output is still finished.
    fn frame(&mut self, snapshot: &Arc<Snapshot>) -> Result<(), OutputError>;

    /// Told of the state after every step (and of step 0 when the driver opens, before its
    /// frame), whether or not a frame is due, and once more of the final state (`last`) before
    /// [`Output::finish`]; for an output of per-step scalars (the time series), which reads
    /// them from `sim` without a snapshot. An error stops the run. Default: nothing.
    fn step(&mut self, _sim: &Simulation, _last: bool) -> Result<(), OutputError> {
        Ok(())
    }

    /// Whether this output shows the velocities: only then do the snapshots copy V (half of a
    /// snapshot: 24 MB of a 10⁶-element body's 49 MB). The Rerun recording draws U alone.
    fn velocities(&self) -> bool {
        false
    }

    /// Whether this output takes the frames' snapshots: the driver copies none when no output
    /// does (the time series alone reads the state at [`Output::step`]).
    fn frames(&self) -> bool {
        true
    }

    /// Ends the output whatever the outcome of the run: `last` is the final state when it was
    /// not a frame already. When it returns, what was written is complete (a closed recording,
    /// an index of every frame).
    fn finish(
        self: Box<Self>,
        last: Option<Arc<Snapshot>>,
        end: &Ending<'_>,
    ) -> Result<OutputReport, OutputError>;
}

/// How a run ended, for the outputs' closing words.
#[derive(Debug, Clone, Copy)]
pub struct Ending<'a> {
    /// Steps taken.
    pub step: u64,
    /// Simulated time reached [s].
    pub time: f64,
    /// Why the run stopped early (a failure or a cancellation), `None` when it completed.
    pub error: Option<&'a SolverError>,
    /// Wall time inside the solver's steps so far [s] (for an output's share of it).
    pub step_seconds: f64,
}

/// What an output reports at the end, for the run summary: a value under the output's name
/// (the summary's JSON key: `recording`, `paraview`, `series`) and a line for the console's
/// table. The driver and the summary hold it without naming the output.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug, Clone)]
pub struct OutputReport {
    /// The output's name ([`crate::outputs::Entry::name`]), the summary's key.
    pub name: &'static str,
    /// What it wrote, as the summary's JSON holds it.
    pub value: serde_json::Value,
    /// The row of the console's table (`None`: no row).
    pub line: Option<String>,
}

#[cfg(not(target_arch = "wasm32"))]
impl OutputReport {
    /// The report of output `name`: `report` serialised, and `line` for the console.
    pub fn new(name: &'static str, report: &impl serde::Serialize, line: Option<String>) -> Self {
        OutputReport {
            name,
            // A report is a plain struct of numbers and strings: serialising it cannot fail.
            value: serde_json::to_value(report).unwrap_or(serde_json::Value::Null),
            line,
        }
    }
}

/// The error of one output, naming which: the output's name (`recording`, `paraview`,
/// `series`, `checkpoint`, `watch`, …), what the run was doing in the command line's words
/// (`starting the recording`, `--series`, `ParaView output`, …; `None`: the error says it all)
/// and the error itself. Shows as the error itself; [`OutputError::into_anyhow`] puts the
/// context above it.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug)]
pub struct OutputError {
    /// The output's name.
    pub output: &'static str,
    /// What the run was doing, in the command line's words.
    pub context: Option<&'static str>,
    error: anyhow::Error,
}

#[cfg(not(target_arch = "wasm32"))]
impl OutputError {
    /// `error` of output `output`, while doing `context`.
    pub fn new(
        output: &'static str,
        context: Option<&'static str>,
        error: impl Into<anyhow::Error>,
    ) -> OutputError {
        OutputError {
            output,
            context,
            error: error.into(),
        }
    }

    /// The same error while doing `context` instead (opening an output rather than running it).
    pub fn while_doing(mut self, context: Option<&'static str>) -> OutputError {
        self.context = context;
        self
    }

    /// The error itself (its sources are its own).
    pub fn error(&self) -> &(dyn std::error::Error + Send + Sync + 'static) {
        self.error.as_ref()
    }

    /// The error with its context above it, as the command line reports it.
    pub fn into_anyhow(self) -> anyhow::Error {
        match self.context {
            Some(c) => self.error.context(c),
            None => self.error,
        }
    }

    /// "context: error", or the error alone without context (the explorer's history).
    pub fn with_context(&self) -> String {
        match self.context {
            Some(c) => format!("{c}: {}", self.error),
            None => self.error.to_string(),
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl std::fmt::Display for OutputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Display::fmt(&self.error, f)
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl std::error::Error for OutputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.error.source()
    }
}

pub use crate::tunables::QUEUE_BYTES;

pub use crate::tunables::DEFAULT_FRAMES;

/// When a frame is taken. Step 0 and the last step are always taken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cadence {
    /// [`DEFAULT_FRAMES`] frames over the scene's end time: one every `end_time / 200` of
    /// simulated time, whatever the step.
    Default,
    /// Every N steps (`--every N`; 1 logs every step for contact debugging).
    EverySteps(u64),
    /// F frames per second of simulated time (`--fps F`).
    PerSimSecond(f64),
}

/// Decides, step by step, whether a frame is due: the first call (step 0) always, then every N
/// steps or at the first step at or past each k·interval of simulated time; `finish` code adds
/// the last step with [`FrameClock::take`]. One clock per run, the driver's, so a Rerun capture
/// and a ParaView series of one run hold the same steps.
#[derive(Debug, Clone)]
pub struct FrameClock {
    every: Option<u64>,
    interval: Option<f64>,
    next_frame_time: f64,
    last_frame_step: Option<u64>,
    frames: u64,
}

impl FrameClock {
    /// A clock for a run that ends at `end_time` [s] (used by [`Cadence::Default`]).
    pub fn new(cadence: Cadence, end_time: f64) -> FrameClock {
        let (every, interval) = match cadence {
            Cadence::Default => (None, Some(end_time / DEFAULT_FRAMES)),
            Cadence::EverySteps(n) => (Some(n.max(1)), None),
            Cadence::PerSimSecond(f) => (None, Some(1.0 / f)),
        };
        FrameClock {
            every,
            interval,
            next_frame_time: 0.0,
            last_frame_step: None,
            frames: 0,
        }
    }

    /// Is a frame due at this step (n, tₙ)? Always when no frame was taken yet.
    pub fn due(&self, step: u64, time: f64) -> bool {
        match (self.every, self.interval) {
            _ if self.last_frame_step.is_none() => true,
            (Some(n), _) => step.is_multiple_of(n),
            (None, Some(_)) => time >= self.next_frame_time,
            (None, None) => false,
        }
    }

    /// Takes the frame of step n at tₙ unless it was taken already (a step is taken at most
    /// once): true when the caller is to write it.
    pub fn take(&mut self, step: u64, time: f64) -> bool {
        if self.last_frame_step == Some(step) {
            return false;
        }
        self.mark(step, time);
        true
    }

    /// Notes that the frame of step n at tₙ was taken.
    fn mark(&mut self, step: u64, time: f64) {
        if let Some(iv) = self.interval {
            // The next frame time after this one, on the grid k·interval. A time that passed
            // the test `time ≥ k·interval·(1 − 1e-12)` counts as k with the same tolerance
            // (otherwise a step landing one ulp below k·interval would take k again, and the
            // next step a second frame).
            let k = (time / iv * (1.0 + 1e-12)).floor() + 1.0;
            self.next_frame_time = k * iv * (1.0 - 1e-12);
        }
        self.last_frame_step = Some(step);
        self.frames += 1;
    }

    /// Frames taken so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }
}

/// Lowers the calling thread's scheduling priority (Linux nice is per thread; threads it
/// starts inherit it), so that output threads yield the CPU to the solver. Best effort: a
/// failure only means the output competes evenly.
pub fn lower_thread_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority on the calling thread (who = 0) has no memory effects.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, 0, 10);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steps a clock takes over a run of constant step h to `end`, the last one included.
    fn steps(cadence: Cadence, h: f64, end: f64) -> Vec<u64> {
        let mut c = FrameClock::new(cadence, end);
        let mut out = vec![];
        let n_end = (end / h).ceil() as u64;
        for n in 0..=n_end {
            let t = n as f64 * h;
            if c.due(n, t) && c.take(n, t) {
                out.push(n);
            }
        }
        if c.take(n_end, n_end as f64 * h) {
            out.push(n_end);
        }
        assert_eq!(c.frames(), out.len() as u64);
        out
    }

    #[test]
    fn default_is_200_frames_plus_step_zero() {
        // h = end/1000: every 5th step, k = 0..=200.
        let s = steps(Cadence::Default, 1e-3, 1.0);
        assert_eq!(s.len(), 201);
        assert_eq!(s[..3], [0, 5, 10]);
        assert_eq!(*s.last().unwrap(), 1000);
    }

    #[test]
    fn every_and_fps() {
        assert_eq!(steps(Cadence::EverySteps(4), 0.1, 1.0), vec![0, 4, 8, 10]);
        // 2.5 frames per second with h = 0.25: the first steps at or past 0.4, 0.8, 1.2, then
        // the last step (t = 1.5; 1.6 is not reached).
        assert_eq!(
            steps(Cadence::PerSimSecond(2.5), 0.25, 1.5),
            vec![0, 2, 4, 5, 6]
        );
    }
}
