//! `decohesion run`: a scene headless through the run driver ([`crate::driver`]), with a
//! progress bar over simulated time on a terminal (or a line at each tenth of the end time
//! otherwise), Ctrl-C to stop, the summary printed and written as JSON; checkpoints written
//! (`--checkpoint`) or continued from (`--resume`, [`crate::checkpoint`]).

use super::progress::{per_mille, sim_time, tenths, time_bar};
use crate::checkpoint::{new_recording_id, Checkpointer, Every, RunRecord, STATE_FILE};
use crate::driver::{cancel_on_ctrl_c, Driver, Progress};
use crate::output::OutputError;
use crate::outputs::Plan;
use crate::scene::load_scene;
use crate::solver::Simulation;
use anyhow::{bail, Context, Result};
use indicatif::ProgressBar;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

/// The checkpoints of a run.
#[derive(Debug, Clone, Default)]
pub enum Checkpoints {
    #[default]
    None,
    /// Into this folder, at this interval (default: a tenth of the end time).
    Write { dir: PathBuf, every: Option<Every> },
    /// Continue the run of this folder (its scene, from its state), writing on into it at this
    /// interval (default: its own).
    Resume { dir: PathBuf, every: Option<Every> },
}

/// Runs the scene at `path` with the `set` overrides and the outputs of `plan` (with
/// [`Checkpoints::Resume`], the folder's scene from its state: `path` and `set` are unused);
/// prints the summary and writes it to `summary_path` (also when the run fails). The error is
/// the first output's, else the solver's.
pub fn run(
    path: Option<&Path>,
    set: &[String],
    summary_path: Option<&Path>,
    quiet: bool,
    plan: &Plan,
    checkpoints: &Checkpoints,
) -> Result<()> {
    let wall = Instant::now();
    if let Some(p) = summary_path {
        check_writable(p)?;
    }
    if let Err(why) = plan.check_watch() {
        bail!(why);
    }
    let record = match checkpoints {
        Checkpoints::Resume { dir, .. } => Some(RunRecord::read(dir)?),
        _ => None,
    };
    let (path, set) = match (&record, path) {
        (Some(r), _) => (r.scene.as_path(), r.set.as_slice()),
        (None, Some(p)) => (p, set),
        (None, None) => bail!("run: give a scene file, or --resume DIR"),
    };
    let scene = load_scene(path, set).with_context(|| match checkpoints {
        Checkpoints::Resume { dir, .. } => format!(
            "--resume {}: the scene of {}",
            dir.display(),
            dir.join(crate::checkpoint::RUN_FILE).display()
        ),
        _ => String::new(),
    })?;
    let mut sim = Simulation::new(scene.model.clone())
        .with_context(|| format!("setting up {}", path.display()))?;
    // A checkpointed run's recording has an id kept in its folder, which the resumed run's
    // recording takes again.
    let mut plan = plan.clone();
    let checkpointer = match checkpoints {
        Checkpoints::None => None,
        Checkpoints::Write { dir, every } => {
            let every = every.unwrap_or(Every::Seconds(sim.model.end_time / 10.0));
            let id = plan
                .wants("recording")
                .then(|| new_recording_id(&sim.model.name));
            plan.recording_id = id.clone();
            Some(Checkpointer::create(dir, every, path, set, id, &sim)?)
        }
        Checkpoints::Resume { dir, every } => {
            let state = dir.join(STATE_FILE);
            let header = sim
                .load_checkpoint(&state)
                .with_context(|| format!("--resume {}", dir.display()))?;
            if !quiet {
                eprintln!(
                    "resuming {} from {} at step {}, t = {:.6e} s",
                    sim.model.name,
                    state.display(),
                    header.step,
                    header.time
                );
            }
            let own = record.as_ref().map(|r| r.every.parse::<Every>());
            let every = match (every, own) {
                (Some(e), _) => *e,
                (None, Some(Ok(e))) => e,
                _ => Every::Seconds(sim.model.end_time / 10.0),
            };
            if plan.wants("recording") {
                let kept = record.as_ref().and_then(|r| r.recording_id.clone());
                plan.recording_id = Some(kept.unwrap_or_else(|| new_recording_id(&sim.model.name)));
            }
            Some(Checkpointer::continuing(dir, every, &sim))
        }
    };
    let driver = Driver::open(&plan, &scene, &sim, wall).map_err(OutputError::into_anyhow)?;
    let driver = match checkpointer {
        Some(c) => driver.checkpoints(c),
        None => driver,
    };
    // Ctrl-C: stop after the current step, then write the recording, the ParaView index and
    // the summary.
    let interrupted = Arc::new(AtomicBool::new(false));
    cancel_on_ctrl_c(interrupted.clone());
    let mut progress = Terminal::new(&sim, quiet);
    let done = driver.run(&mut sim, &interrupted, &mut progress);
    println!("{}", done.summary.table());
    if let Some(c) = &done.summary.checkpoint {
        match (c.last_step, c.last_time) {
            (Some(n), Some(t)) => println!(
                "checkpoint: {} at step {n}, t = {t:.6e} s ({} written, {:.1} MB, {:.2} s in all); continue with: decohesion run --resume {}",
                c.folder.join(STATE_FILE).display(),
                c.written,
                c.bytes as f64 / 1e6,
                c.seconds,
                c.folder.display()
            ),
            _ => println!("checkpoint: none written to {} (none was due)", c.folder.display()),
        }
    }
    if let Some(p) = summary_path {
        let json = serde_json::to_string_pretty(&done.summary)?;
        std::fs::write(p, json)
            .with_context(|| format!("writing the summary to {}", p.display()))?;
    }
    if let Some(e) = done.output_error {
        return Err(e.into_anyhow());
    }
    if let Err(e) = done.outcome {
        bail!(e);
    }
    Ok(())
}

/// Refuses, before the run, a summary path that cannot be written: a directory, or a file in
/// a folder that is missing or not writable (a probe file is created there and removed). The
/// summary itself is written after the run, as it holds the run's results.
fn check_writable(p: &Path) -> Result<()> {
    let refuse = |why: String| {
        anyhow::anyhow!(
            "cannot write the summary (--summary) to {}: {why}",
            p.display()
        )
    };
    if p.is_dir() {
        return Err(refuse("it is a directory".into()));
    }
    let name = p.file_name().ok_or_else(|| refuse("no file name".into()))?;
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(refuse(format!("{} is not a directory", dir.display())));
    }
    let probe = dir.join(format!(
        ".{}.probe-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| refuse(format!("{e}")))?;
    std::fs::remove_file(&probe).ok();
    Ok(())
}

/// Progress on stderr over simulated time ([`super::progress`]): a bar on a terminal, else a
/// line at each tenth of the end time, the last at the end (nothing with `--quiet`).
struct Terminal {
    bar: Option<ProgressBar>,
    quiet: bool,
    end_time: f64,
    /// Tenths of the end time already printed off a terminal.
    printed: u64,
}

impl Terminal {
    /// Prints the run's size and advisories and starts the bar.
    fn new(sim: &Simulation, quiet: bool) -> Terminal {
        let end_time = sim.model.end_time;
        let expected = ((end_time - sim.state.time).max(0.0) / sim.state.h).ceil() as u64;
        let tty = std::io::stderr().is_terminal() && !quiet;
        let bar = tty.then(|| {
            time_bar("{spinner} [{elapsed_precise}] {bar:40} {percent:>3} %  {msg}  ETA {eta}")
        });
        if !quiet {
            eprintln!(
                "{}: {} elements, h = {:.4e} s (h_crit {:.4e} s), ~{} steps to t = {} s",
                sim.model.name,
                sim.model.mesh.element_count(),
                sim.state.h,
                sim.state.h_crit,
                expected,
                end_time
            );
            let surfaces = decohesion_physics::mould::open_surface_warnings(&sim.model.moulds);
            for w in sim.advisories().into_iter().chain(surfaces) {
                eprintln!("warning: {w}");
            }
        }
        Terminal {
            bar,
            quiet,
            end_time,
            printed: 0,
        }
    }
}

impl Progress for Terminal {
    fn step(&mut self, s: &Simulation) {
        if let Some(pb) = &self.bar {
            if s.state.step_count.is_multiple_of(16) || s.finished() {
                pb.set_position(per_mille(s));
                let c = s.state_counts();
                pb.set_message(format!(
                    "t = {}, step {}, ruptured {}/{}",
                    sim_time(s.state.time, self.end_time),
                    s.state.step_count,
                    c.ruptured,
                    s.state.interface_nodes.len()
                ));
            }
        } else if !self.quiet && tenths(s) > self.printed {
            self.printed = tenths(s);
            let c = s.state_counts();
            eprintln!(
                "  {:>3} %  t = {}  step {}  ruptured {}/{}  residual {:.2e}",
                10 * self.printed,
                sim_time(s.state.time, self.end_time),
                s.state.step_count,
                c.ruptured,
                s.state.interface_nodes.len(),
                s.state.ledger.relative_residual()
            );
        }
    }

    fn stopped(&mut self) {
        if let Some(pb) = self.bar.take() {
            pb.finish_and_clear();
        }
    }
}
