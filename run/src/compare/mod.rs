//! Two run results compared observable by observable, each against a tolerance that says what
//! "the same physics" means for it: `decohesion compare A B` and the golden files' guard
//! (`tests/golden.rs`).
//!
//! Inputs ([`load`]): two run summaries (`run --summary`, or a golden file
//! `tests/golden/*.json`, whose `summary` key holds one), two time series (`run --series`
//! CSV) or two Rerun captures (`run --save FILE.rrd`, read back with the SDK's chunk store in
//! [`rrd`]). The core (this module, [`summary`], [`series`]) reads JSON and CSV only; the
//! capture's reader is the one part that uses the Rerun SDK.
//!
//! # Default tolerances and why
//! A run is a discretisation: two runs that differ only in round-off (reordered arithmetic, a
//! kernel build with or without fused multiply–adds) or in the details of the step sequence
//! give results that differ by up to the run's own discretisation error, and the physics is
//! the same. Each default is that error, measured by the run itself where it can be:
//! - **energies** [J] (every ledger term, each mould's work and friction): absolute, the larger
//!   of the two runs' balance residual, `max_relative_residual` × the largest energy of the run
//!   (the ledger's own discretisation error: two energies closer than it are not told apart by
//!   the run that computed them), plus round-off, steps × ε × the largest energy;
//! - **event times** (first damage, full rupture, a peak's time) [s]: absolute, two steps
//!   (2 × the larger `h_max`): an event is detected at the first step it holds, so each run
//!   places it up to one step late; `simulated_time`: one step;
//! - **peak reactions** (force and the imposed displacement there): relative, 2 h_max /
//!   t_peak: a load that rises from zero to its peak over t_peak changes by about h/t_peak of
//!   the peak per step, and the peak may be taken two steps apart;
//! - **time steps** (h, h_crit initial and minimum, h_min, h_max): relative 2 %: a cheap h_crit
//!   update keeps a margin of up to 3 % in ω² (1.5 % in h) and is warm-started from the run's
//!   history, so the estimates of two physically equal runs differ by up to that much;
//! - **step count**: 1 % + 2 steps (the step controller's decisions, grow by ≤ 2 % a step,
//!   re-estimate on thresholds, shift with round-off);
//! - **final state counts** (elastic, transition, ruptured nodes): one node (a node within a
//!   step's growth of a threshold at the end changes class with the step sequence);
//! - **the residual**: `max_relative_residual` within a factor 2 (relative 50 %: only its order
//!   of magnitude is meaningful, a doubling is a change of the ledger); the final
//!   `relative_residual` within the larger max relative residual;
//! - **status, error, mesh sizes**: equal.
//!
//! Time series ([`series`]) use the same energy band, 1 % of the column's largest value for
//! reactions, moments and displacements, one node for counts, and compare each value of A with
//! B over A's time ± two rows (the event-time tolerance), so an event two steps apart is not a
//! difference of the whole jump.
//!
//! Shown but not judged (`info`): the scene's name, the time-step factor (an input), the step
//! controller's statistics, the warnings, and any key this module does not know.
//! `--tol KEY=VALUE` overrides a group or one observable ([`Tolerances`]).

#[cfg(not(target_arch = "wasm32"))]
pub mod rrd;
pub mod series;
pub mod summary;
mod table;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A tolerance: how far apart two values may be and still be the same.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tol {
    /// Equal (numbers: the same f64; text: the same string).
    Exact,
    /// |a − b| ≤ this, in the observable's unit.
    Abs(f64),
    /// |a − b| ≤ this × max(|a|, |b|) (a series: × the largest |value| of the column, or of
    /// every force or every moment column for those).
    Rel(f64),
    /// Not judged: shown only.
    Info,
}

impl Tol {
    /// The largest difference allowed between values of magnitudes `a` and `b`.
    pub fn allowed(self, a: f64, b: f64) -> f64 {
        match self {
            Tol::Exact => 0.0,
            Tol::Abs(x) => x,
            Tol::Rel(r) => r * a.abs().max(b.abs()),
            Tol::Info => f64::INFINITY,
        }
    }

    /// As `--tol` takes it: `exact`, `ignore`, a number (absolute) or `N%` (relative).
    pub fn parse(value: &str) -> Option<Tol> {
        let v = value.trim();
        match v {
            "exact" => return Some(Tol::Exact),
            "ignore" => return Some(Tol::Info),
            _ => {}
        }
        let (number, rel) = match v.strip_suffix('%') {
            Some(n) => (n, true),
            None => (v, false),
        };
        let x: f64 = number.trim().parse().ok()?;
        (x.is_finite() && x >= 0.0).then_some(if rel {
            Tol::Rel(x / 100.0)
        } else {
            Tol::Abs(x)
        })
    }

    /// As the table shows it: `exact`, `1.2e-3` (absolute), `2 %` (relative), `-`.
    pub fn label(self) -> String {
        match self {
            Tol::Exact => "exact".into(),
            Tol::Abs(x) => format!("{x:.3e}"),
            Tol::Rel(r) => format!("{} %", sig(100.0 * r)),
            Tol::Info => "-".into(),
        }
    }
}

/// `x` with 3 significant digits, without trailing zeros.
fn sig(x: f64) -> String {
    let s = format!("{x:.3}");
    if x != 0.0 && x.abs() < 1e-2 {
        return format!("{x:.2e}");
    }
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// One side of a row: a number, a text, or nothing (the observable is absent, or `never`).
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    Num(f64),
    Text(String),
    Missing,
}

impl Cell {
    fn show(&self) -> String {
        match self {
            Cell::Num(x) if *x == x.trunc() && x.abs() < 1e15 => format!("{x}"),
            Cell::Num(x) => format!("{x:.6e}"),
            Cell::Text(t) => t.clone(),
            Cell::Missing => "-".into(),
        }
    }
}

/// The verdict of a row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Ok,
    Moved,
    /// Shown, not judged.
    Info,
}

impl Verdict {
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Ok => "ok",
            Verdict::Moved => "MOVED",
            Verdict::Info => "info",
        }
    }
}

/// One observable compared.
#[derive(Debug, Clone)]
pub struct Row {
    /// Its name, as `--tol` takes it: `energies.damage_dissipated`, `peak_reactions[z+ z].force`,
    /// a series column `damage_dissipated`.
    pub key: String,
    /// Its group, which `--tol` also takes: `energies`, `times`, …
    pub group: &'static str,
    /// A's and B's values (a series: each column's largest |value|).
    pub a: Cell,
    pub b: Cell,
    /// |a − b| (a series: the largest distance of A from B around the same time); NaN when
    /// the row is text or a side is missing.
    pub difference: f64,
    /// Where the difference was largest (series) [s].
    pub at: Option<f64>,
    pub tol: Tol,
    /// What a relative tolerance is relative to; `None`: the larger of |a| and |b|.
    pub scale: Option<f64>,
    /// Why this tolerance (the default's reason, or `--tol`).
    pub why: String,
    pub verdict: Verdict,
}

impl Row {
    /// A row of two numbers (or missing sides), judged at once.
    pub fn num(key: String, group: &'static str, a: Option<f64>, b: Option<f64>, tol: Tol) -> Row {
        let cell = |x: Option<f64>| x.map_or(Cell::Missing, Cell::Num);
        let difference = match (a, b) {
            (Some(x), Some(y)) => (x - y).abs(),
            _ => f64::NAN,
        };
        let mut row = Row {
            key,
            group,
            a: cell(a),
            b: cell(b),
            difference,
            at: None,
            tol,
            scale: None,
            why: String::new(),
            verdict: Verdict::Info,
        };
        row.judge();
        row
    }

    /// A row of two texts, equal or not.
    pub fn text(
        key: String,
        group: &'static str,
        a: Option<String>,
        b: Option<String>,
        tol: Tol,
    ) -> Row {
        let cell = |x: Option<String>| x.map_or(Cell::Missing, Cell::Text);
        let mut row = Row {
            key,
            group,
            a: cell(a),
            b: cell(b),
            difference: f64::NAN,
            at: None,
            tol,
            scale: None,
            why: String::new(),
            verdict: Verdict::Info,
        };
        row.judge();
        row
    }

    /// A's value as the table shows it.
    pub fn a_text(&self) -> String {
        self.a.show()
    }

    /// B's value as the table shows it.
    pub fn b_text(&self) -> String {
        self.b.show()
    }

    /// With the reason of its tolerance.
    pub fn because(mut self, why: impl Into<String>) -> Row {
        self.why = why.into();
        self
    }

    /// The largest difference its tolerance allows between values of magnitudes `a`, `b`.
    pub fn allowed(&self, a: f64, b: f64) -> f64 {
        match (self.tol, self.scale) {
            (Tol::Rel(r), Some(s)) => r * s,
            (tol, _) => tol.allowed(a, b),
        }
    }

    /// Sets the verdict from the values and the tolerance.
    pub(crate) fn judge(&mut self) {
        self.verdict = match (&self.a, &self.b, self.tol) {
            (_, _, Tol::Info) => Verdict::Info,
            (Cell::Missing, Cell::Missing, _) => Verdict::Ok,
            (Cell::Num(x), Cell::Num(y), _) => {
                // A NaN difference is the same only for the same bits (or two NaNs).
                let same = self.difference.is_nan()
                    && (x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()));
                let within = self.difference <= self.allowed(*x, *y);
                if same || within {
                    Verdict::Ok
                } else {
                    Verdict::Moved
                }
            }
            (a, b, _) if a == b => Verdict::Ok,
            _ => Verdict::Moved,
        };
    }
}

/// What was compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Summary,
    Series,
    Capture,
}

impl Kind {
    /// One of this kind, in words.
    pub fn one(self) -> &'static str {
        match self {
            Kind::Summary => "a run summary",
            Kind::Series => "a time series",
            Kind::Capture => "a capture",
        }
    }

    /// Two of this kind, in words (the table's title).
    pub fn name(self) -> &'static str {
        match self {
            Kind::Summary => "two run summaries (JSON)",
            Kind::Series => "two time series (CSV)",
            Kind::Capture => "two Rerun captures (.rrd)",
        }
    }
}

/// A comparison: every observable's row, in order.
#[derive(Debug, Clone)]
pub struct Report {
    pub kind: Kind,
    pub rows: Vec<Row>,
    /// Notes on the comparison as a whole (the time window of a series, columns in one file
    /// only).
    pub notes: Vec<String>,
}

impl Report {
    /// The rows whose observable moved beyond its tolerance.
    pub fn moved(&self) -> impl Iterator<Item = &Row> {
        self.rows.iter().filter(|r| r.verdict == Verdict::Moved)
    }

    /// Applies the `--tol` overrides: a row whose key, else whose group, is named gets that
    /// tolerance and is judged again.
    pub fn apply(&mut self, tols: &Tolerances) -> Result<(), CompareError> {
        let groups: Vec<&str> = self.rows.iter().map(|r| r.group).collect();
        for key in tols.0.keys() {
            if !self.rows.iter().any(|r| &r.key == key) && !groups.contains(&key.as_str()) {
                return Err(CompareError::UnknownKey {
                    key: key.clone(),
                    admissible: admissible(&self.rows),
                });
            }
        }
        for row in &mut self.rows {
            let tol = tols.0.get(&row.key).or_else(|| tols.0.get(row.group));
            if let Some(&(tol, ref spec)) = tol {
                row.tol = tol;
                row.why = format!("--tol {spec}");
                row.judge();
            }
        }
        Ok(())
    }
}

/// The groups, then the observables, that `--tol` takes for these rows.
fn admissible(rows: &[Row]) -> String {
    let mut groups: Vec<&str> = rows.iter().map(|r| r.group).collect();
    groups.sort_unstable();
    groups.dedup();
    let keys: Vec<&str> = rows.iter().map(|r| r.key.as_str()).collect();
    format!(
        "a group ({}) or an observable ({})",
        groups.join(", "),
        keys.join(", ")
    )
}

/// The `--tol KEY=VALUE` overrides, by key: (tolerance, the flag's text).
#[derive(Debug, Clone, Default)]
pub struct Tolerances(BTreeMap<String, (Tol, String)>);

impl Tolerances {
    /// Parses each `KEY=VALUE`; VALUE is `exact`, `ignore`, a number ≥ 0 (absolute, in the
    /// observable's unit) or `N%` (relative to the larger magnitude). The keys are checked
    /// against the rows later ([`Report::apply`]).
    pub fn parse(specs: &[String]) -> Result<Tolerances, CompareError> {
        let mut map = BTreeMap::new();
        for spec in specs {
            let bad = |why: &str| CompareError::BadTol {
                spec: spec.clone(),
                why: why.into(),
            };
            let (key, value) = spec
                .split_once('=')
                .ok_or_else(|| bad("expected KEY=VALUE"))?;
            let tol = Tol::parse(value).ok_or_else(|| {
                bad("the value must be `exact`, `ignore`, a number ≥ 0 (absolute, in the observable's unit) or N% (relative)")
            })?;
            map.insert(key.trim().to_string(), (tol, spec.clone()));
        }
        Ok(Tolerances(map))
    }
}

/// A file that cannot be compared, or a bad `--tol`: exit status 2 of `decohesion compare`.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    #[error("{}: cannot read it: {source}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: {why}", path.display())]
    Format { path: PathBuf, why: String },
    #[error("{} and {} are not of one kind ({} against {}): compare two summaries (run --summary, or tests/golden/*.json), two time series (run --series) or two captures (run --save)", a.display(), b.display(), ka.one(), kb.one())]
    Mismatch {
        a: PathBuf,
        ka: Kind,
        b: PathBuf,
        kb: Kind,
    },
    #[error("--tol {spec}: {why}")]
    BadTol { spec: String, why: String },
    #[error("--tol {key}: no such observable or group here; admissible: {admissible}")]
    UnknownKey { key: String, admissible: String },
}

/// A result read from a file.
pub enum Input {
    /// A run summary's JSON object.
    Summary(serde_json::Value),
    /// A time series: a CSV file or a capture's scalars.
    Series(series::Series, Kind),
}

impl Input {
    fn kind(&self) -> Kind {
        match self {
            Input::Summary(_) => Kind::Summary,
            Input::Series(_, k) => *k,
        }
    }
}

/// Reads a result: `.rrd` a capture, `.csv` a series, anything else JSON (a summary, or a
/// golden file's `summary`).
pub fn load(path: &Path) -> Result<Input, CompareError> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if ext.eq_ignore_ascii_case("rrd") {
        #[cfg(not(target_arch = "wasm32"))]
        return rrd::read(path).map(|s| Input::Series(s, Kind::Capture));
    }
    let text = std::fs::read_to_string(path).map_err(|source| CompareError::Read {
        path: path.into(),
        source,
    })?;
    let format = |why: String| CompareError::Format {
        path: path.into(),
        why,
    };
    if ext.eq_ignore_ascii_case("csv") {
        return series::Series::parse(&text)
            .map(|s| Input::Series(s, Kind::Series))
            .map_err(format);
    }
    summary::parse(&text).map(Input::Summary).map_err(format)
}

/// Compares the results in files `a` and `b` with the default tolerances, then `tols`.
pub fn compare_files(a: &Path, b: &Path, tols: &Tolerances) -> Result<Report, CompareError> {
    let (ia, ib) = (load(a)?, load(b)?);
    let mut report = match (&ia, &ib) {
        (Input::Summary(x), Input::Summary(y)) => summary::compare(x, y),
        (Input::Series(x, k), Input::Series(y, l)) if k == l => series::compare(x, y, *k),
        _ => {
            return Err(CompareError::Mismatch {
                a: a.into(),
                ka: ia.kind(),
                b: b.into(),
                kb: ib.kind(),
            })
        }
    };
    report.apply(tols)?;
    Ok(report)
}
