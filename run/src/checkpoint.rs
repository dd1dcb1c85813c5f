//! `run --checkpoint DIR --checkpoint-every N|Ts` and `run --resume DIR`: a checkpoint folder
//! holds `run.toml` (the scene file, its overrides and the interval, written once at the start)
//! and `state.ckpt` (the state of the run at its last checkpoint, model §4.13, replaced
//! atomically each time: [`decohesion_physics::solver::write_atomically`]). A run killed at any
//! moment leaves the last whole checkpoint; `run --resume DIR` sets the scene up again, checks
//! that it is the one that wrote the checkpoint, and continues bit for bit.

use crate::solver::{CheckpointError, CheckpointHeader, Simulation};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The state file in a checkpoint folder.
pub const STATE_FILE: &str = "state.ckpt";
/// The run's description in a checkpoint folder.
pub const RUN_FILE: &str = "run.toml";

/// How often a checkpoint is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Every {
    /// At every step n that is a multiple of N.
    Steps(u64),
    /// At the first step at or past each multiple of T of simulated time [s].
    Seconds(f64),
}

impl FromStr for Every {
    type Err = String;

    /// `N` (an integer ≥ 1: steps) or `Ts` (a positive number of seconds of simulated time,
    /// e.g. `0.01s` or `5e-3s`).
    fn from_str(s: &str) -> Result<Every, String> {
        let t = s.trim();
        let admissible = "an integer number of steps ≥ 1 (e.g. 1000) or a simulated time in seconds ending in s (e.g. 0.01s)";
        if let Some(x) = t.strip_suffix('s') {
            return match x.trim().parse::<f64>() {
                Ok(v) if v.is_finite() && v > 0.0 => Ok(Every::Seconds(v)),
                _ => Err(format!("'{s}' is not {admissible}")),
            };
        }
        match t.parse::<u64>() {
            Ok(n) if n >= 1 => Ok(Every::Steps(n)),
            _ => Err(format!("'{s}' is not {admissible}")),
        }
    }
}

impl std::fmt::Display for Every {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Every::Steps(n) => write!(f, "{n}"),
            Every::Seconds(t) => write!(f, "{t}s"),
        }
    }
}

/// What `run.toml` says: the run a checkpoint folder continues.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunRecord {
    /// The scene file (absolute path) and its `--set` overrides.
    pub scene: PathBuf,
    pub set: Vec<String>,
    /// The interval, as `--checkpoint-every` takes it.
    pub every: String,
    /// The Rerun recording's id: the resumed run's recording continues the first's.
    #[serde(default)]
    pub recording_id: Option<String>,
}

/// A recording id for a checkpointed run: the scene's name, the clock's nanoseconds and the
/// process, unique enough that two runs never share one by chance.
pub fn new_recording_id(scene: &str) -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    format!("{scene}-{nanos:x}-{:x}", std::process::id())
}

impl RunRecord {
    /// Reads `DIR/run.toml`; an error names the file and what is wrong.
    pub fn read(dir: &Path) -> anyhow::Result<RunRecord> {
        let path = dir.join(RUN_FILE);
        if !dir.is_dir() {
            anyhow::bail!(
                "--resume {}: no such folder (give the folder of --checkpoint)",
                dir.display()
            );
        }
        let text = std::fs::read_to_string(&path).map_err(|e| {
            anyhow::anyhow!(
                "--resume {}: cannot read {}: {e} (a checkpoint folder holds {RUN_FILE} and {STATE_FILE}, written by run --checkpoint)",
                dir.display(),
                path.display()
            )
        })?;
        let record: RunRecord = toml::from_str(&text)
            .map_err(|e| anyhow::anyhow!("{}: {}", path.display(), e.message()))?;
        record
            .every
            .parse::<Every>()
            .map_err(|e| anyhow::anyhow!("{}: key every: {e}", path.display()))?;
        Ok(record)
    }
}

/// Writes a run's checkpoints: when due after a step ([`Checkpointer::after_step`]) and when
/// asked ([`Checkpointer::write`], a cancelled run's last step).
#[derive(Debug)]
pub struct Checkpointer {
    dir: PathBuf,
    every: Every,
    /// With [`Every::Seconds`]: the next multiple of T [s].
    next_time: f64,
    /// The last checkpoint written by this process and how many.
    last: Option<CheckpointHeader>,
    written: u64,
    /// Wall time spent writing them.
    spent: std::time::Duration,
}

/// What the checkpoints of a run were, for its summary.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckpointReport {
    pub folder: PathBuf,
    /// Checkpoints written by this process; the step and time of the last [s]; its size
    /// [bytes]; the wall time spent writing them [s].
    pub written: u64,
    pub last_step: Option<u64>,
    pub last_time: Option<f64>,
    pub bytes: u64,
    pub seconds: f64,
}

impl Checkpointer {
    /// Checkpoints of the run of `scene` with `set` into `dir` (created if needed), every
    /// `every`: `run.toml` is written now, so a folder that cannot be written is refused before
    /// the run.
    pub fn create(
        dir: &Path,
        every: Every,
        scene: &Path,
        set: &[String],
        recording_id: Option<String>,
        sim: &Simulation,
    ) -> anyhow::Result<Checkpointer> {
        std::fs::create_dir_all(dir).map_err(|e| {
            anyhow::anyhow!(
                "--checkpoint {}: cannot create the folder: {e}",
                dir.display()
            )
        })?;
        let scene = std::path::absolute(scene).unwrap_or_else(|_| scene.to_path_buf());
        let record = RunRecord {
            scene,
            set: set.to_vec(),
            every: every.to_string(),
            recording_id,
        };
        let text = format!(
            "# The run this checkpoint folder continues (decohesion run --resume {}).\n{}",
            dir.display(),
            toml::to_string(&record)?
        );
        decohesion_physics::solver::write_atomically(&dir.join(RUN_FILE), text.as_bytes())
            .map_err(|e| anyhow::anyhow!("--checkpoint: {e}"))?;
        Ok(Checkpointer::continuing(dir, every, sim))
    }

    /// Checkpoints into `dir`, whose `run.toml` is written already (a resumed run), from the
    /// state of `sim` on.
    pub fn continuing(dir: &Path, every: Every, sim: &Simulation) -> Checkpointer {
        let mut c = Checkpointer {
            dir: dir.to_path_buf(),
            every,
            next_time: 0.0,
            last: None,
            written: 0,
            spent: std::time::Duration::ZERO,
        };
        c.advance(sim.state.time);
        c
    }

    /// The next multiple of T past `time` (a time within 1e-12 relative of a multiple counts
    /// as it, as the frame clock does).
    fn advance(&mut self, time: f64) {
        if let Every::Seconds(t) = self.every {
            let k = (time / t * (1.0 + 1e-12)).floor() + 1.0;
            self.next_time = k * t * (1.0 - 1e-12);
        }
    }

    /// Writes a checkpoint of `sim` if one is due at its step.
    pub fn after_step(&mut self, sim: &Simulation) -> Result<(), CheckpointError> {
        let due = match self.every {
            Every::Steps(n) => sim.state.step_count.is_multiple_of(n),
            Every::Seconds(_) => sim.state.time >= self.next_time,
        };
        if due {
            self.write(sim)?;
        }
        Ok(())
    }

    /// Writes a checkpoint of `sim` now (once per step).
    pub fn write(&mut self, sim: &Simulation) -> Result<(), CheckpointError> {
        if self
            .last
            .as_ref()
            .is_some_and(|h| h.step == sim.state.step_count)
        {
            return Ok(());
        }
        let started = std::time::Instant::now();
        let header = sim.save_checkpoint(&self.dir.join(STATE_FILE))?;
        self.spent += started.elapsed();
        self.advance(sim.state.time);
        self.last = Some(header);
        self.written += 1;
        Ok(())
    }

    /// What was written.
    pub fn report(&self) -> CheckpointReport {
        let bytes = std::fs::metadata(self.dir.join(STATE_FILE)).map_or(0, |m| m.len());
        CheckpointReport {
            folder: self.dir.clone(),
            written: self.written,
            last_step: self.last.as_ref().map(|h| h.step),
            last_time: self.last.as_ref().map(|h| h.time),
            bytes,
            seconds: self.spent.as_secs_f64(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--checkpoint-every` reads steps and seconds and refuses the rest, saying what it takes.
    #[test]
    fn intervals_parse_or_are_refused_with_what_is_admissible() {
        assert_eq!("1000".parse(), Ok(Every::Steps(1000)));
        assert_eq!("0.01s".parse(), Ok(Every::Seconds(0.01)));
        assert_eq!(" 5e-3s".parse(), Ok(Every::Seconds(5e-3)));
        for bad in [
            "0", "-3", "1.5", "s", "0s", "-1s", "nans", "infs", "10min", "",
        ] {
            let e = bad.parse::<Every>().unwrap_err();
            assert!(
                e.contains(&format!("'{bad}'")) && e.contains("0.01s"),
                "{bad}: {e}"
            );
        }
        for every in [Every::Steps(7), Every::Seconds(0.25)] {
            assert_eq!(every.to_string().parse(), Ok(every));
        }
    }
}
