//! The registry of a run's outputs: every file `run/src/outputs/<name>.rs` other than this
//! one is one output, and declares `pub const ENTRY: Entry` — its name (the run summary's key),
//! its command-line flags, whether the run's flags ask for it and how it is opened from them.
//! `build.rs` lists the files (`$OUT_DIR/outputs.rs`, [`ENTRIES`]); the command line
//! (`decohesion run`, [`OutputFlags`]), the explorer, `sweep`, `tradeoff` and the Python
//! package describe a run's outputs as a [`Plan`] (the parsed flags, the frames' cadence, the
//! watched nodes) and [`Driver::open`] (here, above the driver, which names no output) opens
//! the ones it asks for. Adding an output is adding its file, with its test: no list is edited by hand.
//!
//! The flags of every output and the ones they share (`--every`, `--fps`, `--watch`, here) are
//! one set, ordered by each flag's `display_order` (a flag without one comes last), so that
//! `decohesion run --help` and the generated CLI reference list them in a fixed order whatever
//! the order of the files.

use crate::driver::Driver;
use crate::output::watch::Watch;
use crate::output::{Cadence, Output, OutputError};
use crate::scene::Scene;
use crate::solver::Simulation;
use clap::{ArgMatches, Args, Command, FromArgMatches};
use std::collections::BTreeMap;
use std::ffi::OsString;
use std::time::Instant;

include!(concat!(env!("OUT_DIR"), "/outputs.rs"));

// A target directory shared by two clones could compile the other clone's output files when
// build.rs is not rerun: stop the build instead.
const _: () = assert!(
    decohesion_physics::interface::laws::same_str(GENERATED_IN, env!("CARGO_MANIFEST_DIR")),
    "outputs.rs was generated for another clone sharing this target directory: \
     `touch build.rs` reruns the build script"
);

/// How an output is opened from the run's flags.
pub type Open = fn(&ArgMatches, &Opening<'_>) -> Result<Box<dyn Output>, OutputError>;

/// One output of the registry.
#[derive(Clone, Copy)]
pub struct Entry {
    /// Its name: the run summary's key for its report ([`super::OutputReport::name`]).
    pub name: &'static str,
    /// Adds its flags to a command (a `#[derive(clap::Args)]` struct's `augment_args`; give
    /// each a `display_order`, or it comes after the others).
    pub args: fn(Command) -> Command,
    /// Whether the run's flags ask for it.
    pub asked: fn(&ArgMatches) -> bool,
    /// Opens it for the run `opening` describes (asked for by the flags). An error names the
    /// output and says what was being done (the command line's words).
    pub open: Open,
    /// How it writes the watched nodes (`--watch`), as the error of a `--watch` that nothing
    /// writes suggests it, e.g. "--series FILE.csv"; `None`: it does not write them.
    pub writes_watched: Option<&'static str>,
    /// The summary holds its key as null when it was not asked for (`recording`, `paraview`,
    /// as the Python package reads them); otherwise the key is absent.
    pub null_when_absent: bool,
    /// It is opened after the others (it may start a viewer, which a directory or file that
    /// cannot be written is to stop first) and comes first in the outputs (its error first
    /// when several fail).
    pub opened_last: bool,
}

/// What an output is opened with, besides its flags.
pub struct Opening<'a> {
    pub scene: &'a Scene,
    pub sim: &'a Simulation,
    /// When frames are taken (the driver's clock).
    pub cadence: Cadence,
    /// The watched nodes: the snapshots carry their readings, in this order.
    pub watch: &'a Watch,
    /// The Rerun recording's id (a checkpointed run's, so that the resumed run's recording
    /// continues it; `None`: a random one).
    pub recording_id: Option<&'a str>,
}

/// The outputs a run writes: the flags that ask for them, the cadence of the frames and the
/// watched nodes.
#[derive(Debug, Clone)]
pub struct Plan {
    /// When frames are taken (one clock for every output).
    pub cadence: Cadence,
    /// Nodes to follow (`--watch`, 0-based mesh indices): their values go into the frames'
    /// snapshots ([`Watch`]) and to the outputs that write them.
    pub watch: Vec<u32>,
    /// The Rerun recording's id ([`Opening::recording_id`]).
    pub recording_id: Option<String>,
    /// The flags, parsed against [`command`].
    flags: ArgMatches,
}

/// The flags shared by the outputs.
#[derive(clap::Args)]
struct Shared {
    /// Record a frame (Rerun, --vtk and --series rows) every N steps (1 = every step). Default:
    /// 200 frames over the scene's end time, plus step 0 and the last step (--series: every
    /// step).
    #[arg(long, value_name = "N", value_parser = positive_u64, conflicts_with = "fps", allow_negative_numbers = true, display_order = 50)]
    every: Option<u64>,
    /// Record F frames per second of simulated time (Rerun, --vtk and --series rows).
    #[arg(long, value_name = "F", value_parser = positive_f64, allow_negative_numbers = true, display_order = 60)]
    fps: Option<f64>,
    /// Follow these nodes over the run, e.g. --watch 0,17 (0-based mesh indices, as the summary
    /// and the ParaView files number them; each an interface or a contact node).
    ///
    /// Per interface node: its jump [u] (x, y, z, m), the glue's traction −R_d and the contact's
    /// R_c/h on the solid (x, y, z each, Pa), its damage α (m), its gap g (m), its state (0
    /// elastic, 1 transition, 2 ruptured, 3 unformed) and its contact status (0 open, 1 stick,
    /// 2 slip); per contact-only node its contact traction, gap and status. Written as columns
    /// of --series (`jump_x_node17 [m]`, …, `state_node17 [-]`, `contact_node17 [-]`; a node
    /// of several interfaces or contact faces once per mould, `…_node17_<mould>`) and to the
    /// recording under nodes/<N>/ (jump, traction, alpha, gap, status; each change of state
    /// or status named in nodes/<N>/log). Needs --series or a recording.
    #[arg(
        long,
        value_name = "NODE,...",
        value_delimiter = ',',
        value_parser = node_index,
        allow_negative_numbers = true,
        display_order = 80
    )]
    watch: Vec<u32>,
}

/// `N ≥ 1`.
fn positive_u64(s: &str) -> Result<u64, String> {
    match s.trim().parse::<i128>() {
        Ok(v) if v >= 1 => u64::try_from(v).map_err(|_| format!("{v} is too large")),
        Ok(v) => Err(format!("must be an integer ≥ 1 (got {v})")),
        Err(e) => Err(format!("not an integer: {e}")),
    }
}

/// A finite number > 0.
fn positive_f64(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        Ok(v) => Err(format!("must be a finite number > 0 (got {v})")),
        Err(e) => Err(format!("not a number: {e}")),
    }
}

/// A 0-based node index.
fn node_index(s: &str) -> Result<u32, String> {
    match s.trim().parse::<i128>() {
        Ok(v) if v >= 0 => u32::try_from(v).map_err(|_| format!("{v} is not a node index")),
        Ok(v) => Err(format!("a node index is an integer ≥ 0 (got {v})")),
        Err(e) => Err(format!("not a node index: {e}")),
    }
}

/// Adds the flags of every output and the shared ones to `cmd`, by `display_order`.
pub fn augment(mut cmd: Command) -> Command {
    // Collected on a command that numbers nothing, so that a flag without a display_order
    // keeps the default (after the others).
    let mut all = Shared::augment_args(Command::new("outputs").next_display_order(None));
    for e in ENTRIES {
        all = (e.args)(all);
    }
    let mut args: Vec<clap::Arg> = all.get_arguments().cloned().collect();
    args.sort_by_key(clap::Arg::get_display_order);
    for a in args {
        cmd = cmd.arg(a);
    }
    cmd
}

/// A command holding only the outputs' flags: what [`Plan::parse`] parses.
pub fn command() -> Command {
    augment(Command::new("run").no_binary_name(true))
}

/// The summary's keys for the outputs not asked for ([`Entry::null_when_absent`]).
pub fn absent() -> BTreeMap<String, serde_json::Value> {
    (ENTRIES.iter())
        .filter(|e| e.null_when_absent)
        .map(|e| (e.name.to_string(), serde_json::Value::Null))
        .collect()
}

impl Plan {
    /// The plan of parsed flags (the command line's, [`OutputFlags`]; or [`Plan::parse`]'s):
    /// the cadence from `--every`/`--fps`, the watched nodes from `--watch`.
    pub fn from_matches(flags: &ArgMatches) -> Plan {
        let shared = Shared::from_arg_matches(flags).unwrap_or(Shared {
            every: None,
            fps: None,
            watch: Vec::new(),
        });
        let cadence = match (shared.every, shared.fps) {
            (Some(n), _) => Cadence::EverySteps(n),
            (None, Some(f)) => Cadence::PerSimSecond(f),
            (None, None) => Cadence::Default,
        };
        Plan {
            cadence,
            watch: shared.watch,
            recording_id: None,
            flags: flags.clone(),
        }
    }

    /// The plan of these flags, as `decohesion run` takes them (e.g. `["--vtk", "out/vtk"]`):
    /// for the explorer, `sweep` and the Python package, which describe a run's outputs with
    /// the command line's words.
    pub fn parse<I, T>(flags: I) -> Result<Plan, clap::Error>
    where
        I: IntoIterator<Item = T>,
        T: Into<OsString> + Clone,
    {
        Ok(Plan::from_matches(&command().try_get_matches_from(flags)?))
    }

    /// A run without outputs, its frames at `cadence` (for the driver's clock).
    pub fn none(cadence: Cadence) -> Plan {
        let mut plan = Plan::parse(Vec::<OsString>::new())
            .expect("no flags is a valid set of the outputs' flags");
        plan.cadence = cadence;
        plan
    }

    /// The entries the flags ask for.
    pub fn asked(&self) -> impl Iterator<Item = &'static Entry> + '_ {
        ENTRIES.iter().filter(|e| (e.asked)(&self.flags))
    }

    /// Whether the flags ask for the output named `name`.
    pub fn wants(&self, name: &str) -> bool {
        self.asked().any(|e| e.name == name)
    }

    /// Refuses watched nodes that no asked output writes, saying which would.
    pub fn check_watch(&self) -> Result<(), String> {
        if self.watch.is_empty() || self.asked().any(|e| e.writes_watched.is_some()) {
            return Ok(());
        }
        let nodes: Vec<String> = self.watch.iter().map(u32::to_string).collect();
        let mut ways: Vec<&str> = ENTRIES.iter().filter_map(|e| e.writes_watched).collect();
        ways.sort_by_key(|w| !w.starts_with("--"));
        Err(format!(
            "--watch {}: nothing to write the watched nodes to; add {}",
            nodes.join(","),
            ways.join(" or ")
        ))
    }

    /// Opens the outputs the flags ask for (those [`Entry::opened_last`] after the others, but
    /// first in the list).
    pub fn open(
        &self,
        scene: &Scene,
        sim: &Simulation,
        watch: &Watch,
    ) -> Result<Vec<Box<dyn Output>>, OutputError> {
        let opening = Opening {
            scene,
            sim,
            cadence: self.cadence,
            watch,
            recording_id: self.recording_id.as_deref(),
        };
        let asked: Vec<&Entry> = self.asked().collect();
        let mut rest = Vec::new();
        for e in asked.iter().filter(|e| !e.opened_last) {
            rest.push((e.open)(&self.flags, &opening)?);
        }
        let mut outputs = Vec::new();
        for e in asked.iter().filter(|e| e.opened_last) {
            outputs.push((e.open)(&self.flags, &opening)?);
        }
        outputs.extend(rest);
        Ok(outputs)
    }
}

impl Driver {
    /// Opens the outputs `plan` asks for ([`Plan::open`]) for a simulation that is set up,
    /// and takes the frame of the current state (step 0). The watched nodes first, then the
    /// outputs: a node that cannot be watched, a directory or a file that cannot be written is
    /// refused before a viewer starts or a capture file is created. `started` is when the run
    /// started. The summary holds null under the names of the outputs not asked for that
    /// [`Entry::null_when_absent`].
    pub fn open(
        plan: &Plan,
        scene: &Scene,
        sim: &Simulation,
        started: Instant,
    ) -> Result<Driver, OutputError> {
        let watch = Watch::new(sim, &plan.watch)?;
        let outputs = plan.open(scene, sim, &watch)?;
        let mut driver = Driver::watching(outputs, plan.cadence, sim, started, watch)?;
        driver.absent = absent();
        Ok(driver)
    }
}

/// The outputs' flags on the command line (`decohesion run`): `#[command(flatten)]` them;
/// [`OutputFlags::plan`] is the run's [`Plan`].
#[derive(Debug, Clone)]
pub struct OutputFlags(ArgMatches);

impl OutputFlags {
    /// The outputs these flags ask for.
    pub fn plan(&self) -> Plan {
        Plan::from_matches(&self.0)
    }
}

impl FromArgMatches for OutputFlags {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        Ok(OutputFlags(matches.clone()))
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        self.0 = matches.clone();
        Ok(())
    }
}

impl Args for OutputFlags {
    fn augment_args(cmd: Command) -> Command {
        augment(cmd)
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        augment(cmd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The flags keep the order of `decohesion run --help` before the registry (the generated
    /// CLI reference checks the text).
    #[test]
    fn flags_in_display_order() {
        let cmd = command();
        let names: Vec<&str> = cmd.get_arguments().filter_map(|a| a.get_long()).collect();
        let known = [
            "save", "spawn", "connect", "vtk", "every", "fps", "series", "watch", "colour",
        ];
        assert_eq!(names[..known.len()], known);
    }

    /// A plan of flags: its cadence and outputs; a flag of no output is refused.
    #[test]
    fn plans_from_flags() {
        let plan = Plan::parse(["--every", "7", "--vtk", "out", "--watch", "3,4"]).unwrap();
        assert_eq!(plan.cadence, Cadence::EverySteps(7));
        assert_eq!(plan.watch, vec![3, 4]);
        assert!(plan.wants("paraview") && !plan.wants("recording") && !plan.wants("series"));
        assert!(plan
            .check_watch()
            .unwrap_err()
            .contains("--series FILE.csv"));
        assert!(Plan::none(Cadence::Default).asked().next().is_none());
        assert!(Plan::parse(["--no-such-output"]).is_err());
        assert!(
            Plan::parse(["--save", "a.rrd", "--spawn"]).is_err(),
            "one sink"
        );
    }
}
