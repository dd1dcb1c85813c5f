//! The run's scalars as a time series: one row per recorded step of the time, the step, the
//! imposed displacements and reactions of the prescribed conditions, each mould's force and
//! moment, every energy of the ledger and the interface's state counts, then the watched nodes'
//! values (`--watch`, [`super::watch`]). Two consumers share the
//! columns ([`Columns`]) and the values of a row ([`Columns::row`]), so they agree to the bit:
//! - [`SeriesWriter`], the output of `decohesion run --series FILE.csv` fed by the run driver
//!   ([`crate::driver`]): a CSV file streamed row by row (memory stays flat), whose every line
//!   is whole even when the run fails or is cancelled;
//! - [`History`], the Python API's `Simulation.history`: the same rows in memory, by column.
//!
//! Values are written as the shortest decimal that reads back to the same f64 (Rust's `{:?}`,
//! which is `{}` with an exponent for the very small and very large), so a CSV parsed with any
//! correct float parser gives the history's values to the bit.

use super::snapshot::mould_loads;
use super::watch::Watch;
use super::{Cadence, Ending, FrameClock, Output, OutputError, OutputReport, Snapshot};
use crate::energy::EnergySnapshot;
use crate::interface::contact::ContactStatus;
use crate::solver::Simulation;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub use crate::tunables::SERIES_FLUSH_BYTES as FLUSH_BYTES;
pub use crate::tunables::SERIES_FLUSH_WALL as FLUSH_WALL;

/// The ledger's terms as columns [J]: [`EnergySnapshot::TERMS`], then `relative_residual` [-].
pub const ENERGY_COLUMNS: [&str; 15] = EnergySnapshot::TERMS;

const AXES: [&str; 3] = ["x", "y", "z"];

/// A name usable as one part of a column or entity name: `z+` → `z_plus`, `mould 2` →
/// `mould_2` (ASCII letters, digits and `_` kept, every other character replaced).
pub fn name_part(s: &str) -> String {
    let mut out = String::new();
    for ch in s.chars() {
        match ch {
            '+' => out.push_str("_plus"),
            '-' => out.push_str("_minus"),
            c if c.is_ascii_alphanumeric() || c == '_' => out.push(c),
            _ => out.push('_'),
        }
    }
    out
}

/// The name of a prescribed condition's columns (`u_<name> [m]`, `F_<name> [N]`):
/// `<faces>_<axis>`, the Rerun entity's name.
pub fn condition_name(faces: &str, component: usize) -> String {
    format!("{}_{}", name_part(faces), AXES[component.min(2)])
}

/// The columns of a series of one simulation: their names with units, e.g. `t [s]`, and which
/// hold whole numbers (the step, the counts).
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    /// `name [unit]`, in row order.
    pub names: Vec<String>,
    /// Whether the column holds whole numbers (stored as exact f64 in a row).
    pub integer: Vec<bool>,
    /// Whether the series lists each mould's friction (several moulds).
    mould_friction: bool,
    /// The watched nodes, whose columns end the row.
    watch: Watch,
}

impl Columns {
    /// The columns of `sim`'s series, in this order:
    /// - `t [s]`, `step [-]`, `h [s]` (tₙ, n, the step h_{n+½} about to be taken);
    /// - per prescribed condition `<faces>_<axis>` (the Rerun entity's name): `u_… [m]`, the
    ///   imposed displacement at tₙ, and `F_… [N]`, its reaction P/h̄ of the last step;
    /// - per mould `<name>`: `F_mould_<name>_x [N]`…, the force the body exerted on it over the
    ///   last step, and `M_mould_<name>_x [N m]`…, its moment about the mould's pivot
    ///   ([`mould_loads`]);
    /// - the ledger's terms [J] ([`ENERGY_COLUMNS`]) and `relative_residual [-]`;
    /// - with several moulds, `friction_mould_<name> [J]`, the friction dissipated on each;
    /// - `n_elastic [-]`, `n_transition [-]`, `n_ruptured [-]`, `n_unformed [-]` interface
    ///   nodes by state, and `n_open [-]`, `n_stick [-]`, `n_slip [-]` nodes by contact status
    ///   (interface and contact-only nodes).
    pub fn new(sim: &Simulation) -> Columns {
        Columns::watching(sim, &Watch::default())
    }

    /// [`Columns::new`] followed by the columns of the watched nodes ([`Watch::columns`]:
    /// e.g. `jump_x_node17 [m]`, `traction_glue_z_node17 [Pa]`, `alpha_node17 [m]`,
    /// `state_node17 [-]`).
    pub fn watching(sim: &Simulation, watch: &Watch) -> Columns {
        let m = &sim.model;
        let mut names: Vec<String> = vec!["t [s]".into(), "step [-]".into(), "h [s]".into()];
        let mut integer = vec![false, true, false];
        for d in &m.displacements {
            let name = condition_name(&d.faces, d.component);
            names.push(format!("u_{name} [m]"));
            names.push(format!("F_{name} [N]"));
            integer.extend([false; 2]);
        }
        for p in &m.moulds {
            let name = name_part(&p.name);
            names.extend(AXES.map(|a| format!("F_mould_{name}_{a} [N]")));
            names.extend(AXES.map(|a| format!("M_mould_{name}_{a} [N m]")));
            integer.extend([false; 6]);
        }
        names.extend(ENERGY_COLUMNS.map(|e| format!("{e} [J]")));
        names.push("relative_residual [-]".into());
        integer.extend([false; ENERGY_COLUMNS.len() + 1]);
        let mould_friction = m.moulds.len() > 1;
        if mould_friction {
            for p in &m.moulds {
                names.push(format!("friction_mould_{} [J]", name_part(&p.name)));
                integer.push(false);
            }
        }
        for c in [
            "elastic",
            "transition",
            "ruptured",
            "unformed",
            "open",
            "stick",
            "slip",
        ] {
            names.push(format!("n_{c} [-]"));
            integer.push(true);
        }
        let (watched, whole) = watch.columns();
        names.extend(watched);
        integer.extend(whole);
        Columns {
            names,
            integer,
            mould_friction,
            watch: watch.clone(),
        }
    }

    /// Number of columns.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether there are no columns (never: time, step and h are always there).
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// The values of the row of `sim` at its current step, in column order, into `out`
    /// (cleared first). Reads the state only: O(interface and contact nodes).
    pub fn row(&self, sim: &Simulation, out: &mut Vec<f64>) {
        out.clear();
        let m = &sim.model;
        out.extend([sim.state.time, sim.state.step_count as f64, sim.state.h]);
        for (k, d) in m.displacements.iter().enumerate() {
            out.push(d.history.value(sim.state.time)[0]);
            out.push(sim.stats.reactions.get(k).copied().unwrap_or(0.0));
        }
        for (f, mm) in mould_loads(sim) {
            out.extend(f);
            out.extend(mm);
        }
        let e = sim.energies();
        out.extend(e.terms());
        out.push(e.relative_residual);
        if self.mould_friction {
            out.extend(sim.mould_frictions().into_iter().map(|(_, d)| d));
        }
        let c = sim.state_counts();
        out.extend([c.elastic, c.transition, c.ruptured, c.unformed].map(|n| n as f64));
        let mut status = [0usize; 3];
        let statuses = (sim.state.interface_nodes.iter().map(|n| n.contact))
            .chain(sim.state.contact_nodes.iter().map(|n| n.contact));
        for s in statuses {
            status[match s {
                ContactStatus::Open => 0,
                ContactStatus::Stick => 1,
                ContactStatus::Slip => 2,
            }] += 1;
        }
        out.extend(status.map(|n| n as f64));
        self.watch.row(sim, out);
        debug_assert_eq!(out.len(), self.len());
    }

    /// The CSV header line: the names joined by commas, a name holding a comma or a quote
    /// quoted (RFC 4180), ended by a newline.
    pub fn header(&self) -> String {
        let mut line = String::new();
        for (i, name) in self.names.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            if name.contains([',', '"', '\n']) {
                line.push('"');
                line.push_str(&name.replace('"', "\"\""));
                line.push('"');
            } else {
                line.push_str(name);
            }
        }
        line.push('\n');
        line
    }
}

/// Appends one CSV line of `values`: the whole numbers of the `integer` columns as integers
/// (`{}` of an integral f64: `64`), every other value with `{:?}`, the shortest decimal that
/// reads back to the same f64 (as `{}`), in scientific notation below 1e-5 and from 1e16 on
/// in magnitude (`{}` would write 5e-324 with 323 zeros); NaN and ±inf as `NaN`, `inf`, `-inf`.
fn push_line(line: &mut String, values: &[f64], integer: &[bool]) {
    use std::fmt::Write as _;
    for (i, (v, int)) in values.iter().zip(integer).enumerate() {
        if i > 0 {
            line.push(',');
        }
        let _ = match int {
            true => write!(line, "{v}"),
            false => write!(line, "{v:?}"),
        };
    }
    line.push('\n');
}

/// The rows of a series in memory, by column (the Python API's `Simulation.history`): one row
/// per step pushed, a step pushed twice kept once.
#[derive(Debug, Clone)]
pub struct History {
    pub columns: Columns,
    /// One vector per column, all of the same length (the rows).
    pub values: Vec<Vec<f64>>,
    last_step: Option<u64>,
    row: Vec<f64>,
}

impl History {
    /// An empty history of `sim`'s columns.
    pub fn new(sim: &Simulation) -> History {
        let columns = Columns::new(sim);
        History {
            values: vec![Vec::new(); columns.len()],
            columns,
            last_step: None,
            row: Vec::new(),
        }
    }

    /// Appends the row of `sim` now, unless its step is the last row's.
    pub fn push(&mut self, sim: &Simulation) {
        if self.last_step == Some(sim.state.step_count) {
            return;
        }
        self.last_step = Some(sim.state.step_count);
        self.columns.row(sim, &mut self.row);
        for (column, v) in self.values.iter_mut().zip(&self.row) {
            column.push(*v);
        }
    }

    /// Rows so far.
    pub fn rows(&self) -> usize {
        self.values.first().map_or(0, Vec::len)
    }
}

/// What the series wrote, for the run summary.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct SeriesReport {
    pub path: String,
    /// Rows written (the header not counted).
    pub rows: u64,
    pub columns: usize,
    /// Size of the file [bytes].
    pub bytes: u64,
    /// Solver-thread time spent building and writing the rows [s].
    pub seconds: f64,
}

/// The error of the series file, naming it.
#[derive(Debug, thiserror::Error)]
#[error("the series {}: {what}: {source}", path.display())]
pub struct SeriesError {
    pub path: PathBuf,
    /// What was being done: "cannot create", "cannot write".
    pub what: &'static str,
    #[source]
    pub source: std::io::Error,
}

/// While the run goes, the series' error says `--series` above it (the command line's context).
impl From<SeriesError> for OutputError {
    fn from(e: SeriesError) -> OutputError {
        OutputError::new("series", Some("--series"), e)
    }
}

/// `--series FILE.csv`: an [`Output`] of the run driver that writes one CSV row per recorded
/// step on the solver thread (a row is a few hundred bytes: no writer thread is needed). Rows
/// are kept as whole lines and written by [`FLUSH_BYTES`] or every [`FLUSH_WALL`], and all at
/// the end whatever the outcome (and on drop), so the file never ends in a partial line unless
/// the process is killed during a write.
pub struct SeriesWriter {
    file: File,
    path: PathBuf,
    columns: Columns,
    clock: FrameClock,
    /// Whole lines not yet written.
    pending: String,
    row: Vec<f64>,
    rows: u64,
    bytes: u64,
    last_write: Instant,
    spent: Duration,
}

impl SeriesWriter {
    /// Creates (or truncates) the file at `path` and writes the header, with the columns of the
    /// `watch`ed nodes. Rows are taken at every
    /// step with [`Cadence::Default`] (no `--every`/`--fps`), else at `cadence`, the frames'
    /// clock (the same steps as the recording). The caller then feeds it steps
    /// ([`Output::step`]). A file that cannot be created is an error naming it.
    pub fn new(
        path: &Path,
        cadence: Cadence,
        sim: &Simulation,
        watch: &Watch,
    ) -> Result<SeriesWriter, SeriesError> {
        let started = Instant::now();
        let error = |what| {
            move |source| SeriesError {
                path: path.to_path_buf(),
                what,
                source,
            }
        };
        let mut file = File::create(path).map_err(error("cannot create the file"))?;
        let columns = Columns::watching(sim, watch);
        let header = columns.header();
        file.write_all(header.as_bytes())
            .map_err(error("cannot write the header"))?;
        let cadence = match cadence {
            Cadence::Default => Cadence::EverySteps(1),
            c => c,
        };
        Ok(SeriesWriter {
            file,
            path: path.to_path_buf(),
            columns,
            clock: FrameClock::new(cadence, sim.model.end_time),
            pending: String::with_capacity(FLUSH_BYTES + 4096),
            row: Vec::new(),
            rows: 0,
            bytes: header.len() as u64,
            last_write: Instant::now(),
            spent: started.elapsed(),
        })
    }

    /// Writes the pending lines to the file.
    fn write_pending(&mut self) -> Result<(), SeriesError> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let written = self.file.write_all(self.pending.as_bytes());
        self.bytes += self.pending.len() as u64;
        self.pending.clear();
        self.last_write = Instant::now();
        written.map_err(|source| SeriesError {
            path: self.path.clone(),
            what: "cannot write",
            source,
        })
    }

    /// Adds the row of `sim` (unless its step has one) and writes when due.
    fn add(&mut self, sim: &Simulation, force: bool) -> Result<(), SeriesError> {
        let due = force || self.clock.due(sim.state.step_count, sim.state.time);
        if !(due && self.clock.take(sim.state.step_count, sim.state.time)) {
            return Ok(());
        }
        self.columns.row(sim, &mut self.row);
        push_line(&mut self.pending, &self.row, &self.columns.integer);
        self.rows += 1;
        if self.pending.len() >= FLUSH_BYTES || self.last_write.elapsed() >= FLUSH_WALL {
            self.write_pending()?;
        }
        Ok(())
    }
}

impl Output for SeriesWriter {
    /// The series takes its rows from [`Output::step`], not from the frames.
    fn frame(&mut self, _snapshot: &Arc<Snapshot>) -> Result<(), OutputError> {
        Ok(())
    }

    fn frames(&self) -> bool {
        false
    }

    /// A row of this step when one is due; the final state's row (`last`) always, unless its
    /// step has one.
    fn step(&mut self, sim: &Simulation, last: bool) -> Result<(), OutputError> {
        let started = Instant::now();
        let r = self.add(sim, last);
        self.spent += started.elapsed();
        Ok(r?)
    }

    /// Writes what is pending and syncs nothing more: the file is complete.
    fn finish(
        mut self: Box<Self>,
        _last: Option<Arc<Snapshot>>,
        _end: &Ending<'_>,
    ) -> Result<OutputReport, OutputError> {
        let started = Instant::now();
        self.write_pending()?;
        self.file.flush().map_err(|source| SeriesError {
            path: self.path.clone(),
            what: "cannot write",
            source,
        })?;
        self.spent += started.elapsed();
        let report = SeriesReport {
            path: self.path.display().to_string(),
            rows: self.rows,
            columns: self.columns.len(),
            bytes: self.bytes,
            seconds: self.spent.as_secs_f64(),
        };
        Ok(OutputReport::new("series", &report, None))
    }
}

impl Drop for SeriesWriter {
    /// A writer dropped without [`Output::finish`] (a panic unwinding) still writes its whole
    /// lines, best effort.
    fn drop(&mut self) {
        let _ = self.write_pending();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_round_trip_every_f64() {
        let values = [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            1e-300,
            f64::MAX,
            5e-324,
            -2.5e17,
        ];
        let mut line = String::new();
        push_line(&mut line, &values, &[false; 9]);
        assert!(line.ends_with('\n'));
        let back: Vec<f64> = (line.trim_end().split(','))
            .map(|s| s.parse().unwrap())
            .collect();
        assert_eq!(back.len(), values.len());
        for (a, b) in back.iter().zip(values) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }

    #[test]
    fn names_with_commas_or_quotes_are_quoted() {
        let c = Columns {
            names: vec!["t [s]".into(), "F_a,b [N]".into(), "q\"x".into()],
            integer: vec![false; 3],
            mould_friction: false,
            watch: Watch::default(),
        };
        assert_eq!(c.header(), "t [s],\"F_a,b [N]\",\"q\"\"x\"\n");
        assert_eq!(name_part("z+"), "z_plus");
        assert_eq!(name_part("mould 2"), "mould_2");
    }
}
