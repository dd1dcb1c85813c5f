//! `decohesion fit`: the values of a scene's keys (a law's parameters, usually) that make a
//! run reproduce a measured curve.
//!
//! The misfit c(p) of a parameter vector is the mean square relative residual between the
//! measured curve and the run's series column at the measured x ([`problem`]). It is minimised
//! by Nelder–Mead (argmin's `NelderMead`) in the free keys' coordinates z ∈ [0, 1]
//! ([`free`]), started from the best of the start and a Halton sample of the box ([`halton`],
//! 20 points per key by default): c(p) of a dynamic run has local minima (the wave ringing of
//! the body shifts with the law's values), and a simplex started 50 % off the answer settles in
//! one; the sample puts it in the right basin. Nelder–Mead, because c(p) is not smooth: each interface node's rupture happens
//! on a step, so c(p) has small jumps that finite-difference gradients (Gauss–Newton,
//! Levenberg–Marquardt) take for slopes; the simplex needs values only, and its n + 1 first
//! vertices and the 2n runs of the uncertainty are independent and run side by side. Points
//! outside the bounds are refused without a run (an extreme barrier: their misfit is above any
//! run's), as are runs the scene refuses or that fail.
//!
//! The uncertainty of the fitted values is the linearised one: with J the Jacobian of the
//! relative residuals r(p) by central differences at the optimum (steps of 1 % of each key's
//! searched range) and s² = Σ rᵢ² / (m − n) the residual variance,
//!
//!   Cov(p) = s² (JᵀJ)⁻¹,   σ_j = √Cov_jj,
//!
//! which holds when the residuals are independent noise of one variance; a key whose column
//! of J vanishes is not identified by the curve (σ = ∞, reported as none).

pub mod free;
pub mod outputs;
pub mod problem;
pub mod scene_file;
mod search;

/// The measured curve (a module of its own: the explorer's page reads one too).
pub use crate::measured as data;

use anyhow::{bail, Context, Result};
use data::{Curve, Unit};
use free::{lookup, Free};
use problem::{find_column, Evaluation, Problem, SceneText};
use search::{bits, nelder_mead, uncertainty, Objective, Runs, HALTON_BASES, MAX_RESTARTS};
pub use search::{default_sample, halton, stall_runs};
use serde::Serialize;
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use crate::output::series::Columns;
use crate::solver::Simulation;

/// What a fit is asked.
#[derive(Debug, Clone)]
pub struct FitArgs {
    pub scene: PathBuf,
    /// The scene's text, when it is not the file's (the explorer's edited scene); `scene` still
    /// names it in messages and is where the files it names are read from.
    pub scene_text: Option<String>,
    /// `--set` overrides applied first (they set the start of a free key too).
    pub set: Vec<String>,
    pub data: PathBuf,
    /// The series column compared with the measured x, e.g. `u_z_plus_z`.
    pub x: String,
    /// The series column compared with the measured y, e.g. `F_z_plus_z`.
    pub y: String,
    /// `key=lo..hi` per free key.
    pub free: Vec<String>,
    /// Units of the measured columns when the header gives none.
    pub x_unit: Option<String>,
    pub y_unit: Option<String>,
    /// Runs at most (the sample's and the simplex's first vertices included, the uncertainty's
    /// not).
    pub max_evals: usize,
    /// Points of the Halton sample of the bounds' box run before the simplex, which starts from
    /// the best of them and the start [default: [`default_sample`]]; 0: the simplex starts from
    /// the start.
    pub sample: Option<usize>,
    /// Stop when the standard deviation of the simplex's misfits falls below this.
    pub tolerance: f64,
    /// Threads in all: runs side by side share them.
    pub threads: usize,
}

impl FitArgs {
    /// The defaults of the command line for everything but the scene, curve and keys.
    pub fn new(scene: &Path, data: &Path, x: &str, y: &str, free: &[String]) -> FitArgs {
        FitArgs {
            scene: scene.to_path_buf(),
            scene_text: None,
            set: Vec::new(),
            data: data.to_path_buf(),
            x: x.to_string(),
            y: y.to_string(),
            free: free.to_vec(),
            x_unit: None,
            y_unit: None,
            max_evals: DEFAULT_MAX_EVALS,
            sample: None,
            tolerance: DEFAULT_TOLERANCE,
            threads: 1,
        }
    }
}

pub use crate::tunables::FIT_MAX_EVALS as DEFAULT_MAX_EVALS;
pub use crate::tunables::FIT_TOLERANCE as DEFAULT_TOLERANCE;

/// A fit checked and ready: the problem, the start, the measured curve and its units.
#[derive(Debug, Clone)]
pub struct Prepared {
    pub problem: Problem,
    pub curve: Curve,
    pub x_unit: Unit,
    pub y_unit: Unit,
    /// Whether each unit was assumed (SI, none given).
    pub units_assumed: [bool; 2],
    /// The start of each free key, and where it came from ("scene" or "middle").
    pub start: Vec<f64>,
    pub start_from: Vec<&'static str>,
    /// The scene's name.
    pub name: String,
    pub args: FitArgs,
}

/// Checks everything before the first run: the free keys (syntax, twice, reversed bounds, a
/// value that is not a number, bounds the scene refuses, a start outside them), the curve (its
/// file, enough points, units of the right kind) and the columns (they exist in the scene's
/// series); every error names the flag, key, file or line and what is admissible.
pub fn prepare(args: &FitArgs) -> Result<Prepared> {
    if args.free.is_empty() {
        bail!("give at least one --free key=lo..hi");
    }
    if args.free.len() > HALTON_BASES.len() {
        bail!(
            "{} free keys: at most {} can be fitted at once",
            args.free.len(),
            HALTON_BASES.len()
        );
    }
    if args.max_evals == 0 {
        bail!("--max-evals 0: give at least 1");
    }
    if !(args.tolerance >= 0.0) || !args.tolerance.is_finite() {
        bail!("--tolerance {}: give a finite number ≥ 0", args.tolerance);
    }
    let free: Vec<Free> = args
        .free
        .iter()
        .map(|s| Free::parse(s))
        .collect::<Result<_>>()?;
    for (i, f) in free.iter().enumerate() {
        if free[..i].iter().any(|g| g.key == f.key) {
            bail!("--free {}: the key is free twice", f.key);
        }
    }
    let curve = Curve::read(&args.data)?;
    let n = free.len();
    curve.require_points(
        (n + 2).max(5),
        "more points than free keys for the uncertainty, and 5 to make a curve",
    )?;
    let scene = match &args.scene_text {
        Some(text) => SceneText {
            file: args.scene.display().to_string(),
            text: text.clone(),
        },
        None => SceneText::read(&args.scene)?,
    };
    let base = scene.load(&args.set)?;
    let sim = Simulation::new(base.model.clone())
        .with_context(|| format!("{}: the scene cannot be set up", args.scene.display()))?;
    let columns = Columns::new(&sim);
    drop(sim);
    let (_, x) = find_column(&columns, &args.x, "--x").map_err(anyhow::Error::msg)?;
    let (_, y) = find_column(&columns, &args.y, "--y").map_err(anyhow::Error::msg)?;
    let (x_unit, x_assumed) =
        curve.unit(&curve.x_header, args.x_unit.as_deref(), "--x-unit", &x.unit)?;
    let (y_unit, y_assumed) =
        curve.unit(&curve.y_header, args.y_unit.as_deref(), "--y-unit", &y.unit)?;
    let xs: Vec<f64> = curve.x.iter().map(|v| v * x_unit.factor).collect();
    let ys: Vec<f64> = curve.y.iter().map(|v| v * y_unit.factor).collect();
    let y_scale = ys.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    if !(y_scale > 0.0) {
        bail!(
            "{}: every measured y is 0; there is nothing to fit",
            curve.file
        );
    }
    let doc: toml::Table =
        toml::from_str(&base.resolved).context("the resolved scene does not read back as TOML")?;
    let (mut start, mut start_from) = (Vec::new(), Vec::new());
    for f in &free {
        let (value, from) = match lookup(&doc, &f.key) {
            Some(toml::Value::Float(v)) => (*v, "scene"),
            Some(toml::Value::Integer(v)) => (*v as f64, "scene"),
            Some(other) => bail!(
                "--free {}: the scene's value `{other}` is a {}, not a number; only numbers \
                 can be fitted",
                f.key,
                other.type_str()
            ),
            None => (f.middle(), "middle"),
        };
        for (which, v) in [("lower", f.lo), ("upper", f.hi)] {
            admitted_bound(&scene, args, &free, f, v).with_context(|| {
                format!(
                    "--free {}: the scene refuses the {which} bound {v:?}",
                    f.key
                )
            })?;
        }
        if !(f.lo <= value && value <= f.hi) {
            bail!(
                "--free {}={}..{}: the start, the scene's value {value:?}, lies outside the \
                 bounds; widen them or give a start inside with --set {}=VALUE",
                f.key,
                f.lo,
                f.hi,
                f.key
            );
        }
        start.push(value);
        start_from.push(from);
    }
    Ok(Prepared {
        problem: Problem {
            scene,
            set: args.set.clone(),
            free,
            x,
            y,
            xs,
            ys,
            y_scale,
        },
        curve,
        x_unit,
        y_unit,
        units_assumed: [x_assumed, y_assumed],
        start,
        start_from,
        name: base.model.name.clone(),
        args: args.clone(),
    })
}

/// Whether the scene admits the free key `f` at the bound `v`: with the other free keys at their
/// start, else at some corner of their bounds (a bound may be refused only together with
/// another key's value, `u_r > α_e`, and the box then holds points the runs refuse, which the fit
/// reports as failed runs). The error is the scene's with the others at their start.
fn admitted_bound(
    scene: &SceneText,
    args: &FitArgs,
    free: &[Free],
    f: &Free,
    v: f64,
) -> Result<()> {
    let this = format!("{}={v:?}", f.key);
    let mut set = args.set.clone();
    set.push(this.clone());
    let Err(first) = scene.load(&set) else {
        return Ok(());
    };
    let others: Vec<&Free> = free.iter().filter(|g| g.key != f.key).collect();
    // 2^(n−1) corners; past 6 other keys (64 loads) the start's verdict stands.
    if others.len() <= 6 {
        for mask in 0..1usize << others.len() {
            let mut set = args.set.clone();
            set.extend(others.iter().enumerate().map(|(k, g)| {
                let at = if mask >> k & 1 == 1 { g.hi } else { g.lo };
                format!("{}={at:?}", g.key)
            }));
            set.push(this.clone());
            if scene.load(&set).is_ok() {
                return Ok(());
            }
        }
    }
    Err(first.into())
}

/// One run of the fit.
#[derive(Debug, Clone, Serialize)]
pub struct Record {
    /// 1, 2, … in the order the optimiser asked for them.
    pub index: usize,
    /// The free keys' values.
    pub values: Vec<f64>,
    /// Their coordinates z, as the optimiser gave them.
    #[serde(skip)]
    pub z: Vec<f64>,
    /// The misfit c (absent when the run failed).
    pub cost: Option<f64>,
    /// "completed", "failed" or "cancelled".
    pub status: &'static str,
    pub error: Option<String>,
}

/// Told of every run as it ends (the command line's progress bar).
pub trait Watch {
    /// `record` ended; `best` is the best so far.
    fn evaluated(&mut self, record: &Record, best: Option<&Record>);
}

/// A watch that says nothing.
pub struct Silent;
impl Watch for Silent {
    fn evaluated(&mut self, _: &Record, _: Option<&Record>) {}
}

/// How the optimisation ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// The simplex's misfits agree within the tolerance.
    Converged,
    /// No run improved on the best misfit in the last [`stall_runs`] runs: the simplex has shrunk
    /// onto the best point (by 2⁻²⁰ of its size at least) without its misfits agreeing, as they
    /// need not where c(p) steps (a node's rupture moving by one time step).
    Stalled,
    /// `--max-evals` runs were made.
    MaxEvals,
    /// Ctrl-C: the best so far is kept.
    Cancelled,
}

/// A free key's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fitted {
    pub key: String,
    pub lo: f64,
    pub hi: f64,
    /// Searched in log p.
    pub log: bool,
    pub start: f64,
    /// "scene" (its value after `--set`) or "middle" (of the bounds; the scene has none).
    pub start_from: &'static str,
    pub value: f64,
    /// One standard deviation (linearised; none when the curve does not identify the key or
    /// the fit was cancelled).
    pub sigma: Option<f64>,
    /// Whether the value sits on a bound (within 0.1 % of the range): widen it.
    pub at_bound: bool,
}

/// A curve's agreement with the measured one.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Agreement {
    /// The misfit c.
    pub cost: f64,
    /// √c, the RMS residual relative to max |y|.
    pub rms_relative: f64,
    /// The RMS residual in the measured y's unit.
    pub rms: f64,
}

/// The curves, in the measured units, point by point.
#[derive(Debug, Clone, Serialize)]
pub struct Curves {
    pub x: Vec<f64>,
    pub measured: Vec<f64>,
    /// The run at the start (none when it failed).
    pub initial: Option<Vec<f64>>,
    pub fitted: Vec<f64>,
}

/// What a fit found: `fit.json`, the Python API's dictionary.
#[derive(Debug, Clone, Serialize)]
pub struct FitReport {
    pub scene: String,
    pub name: String,
    pub data: String,
    pub set: Vec<String>,
    /// The series columns compared, with the measured units (and whether assumed).
    pub x: ColumnReport,
    pub y: ColumnReport,
    pub points: usize,
    pub parameters: Vec<Fitted>,
    /// Correlations of the fitted values (row by row), when every σ exists.
    pub correlation: Option<Vec<Vec<f64>>>,
    pub initial: Option<Agreement>,
    pub fitted: Agreement,
    pub stop: Stop,
    pub evaluations: usize,
    pub failed_evaluations: usize,
    /// Runs made for the uncertainty (2 per free key, fewer at a bound).
    pub uncertainty_evaluations: usize,
    /// Nelder–Mead restarts from the best point after the first descent.
    pub restarts: usize,
    pub optimiser: String,
    pub tolerance: f64,
    pub max_evals: usize,
    pub wall_seconds: f64,
    pub curves: Curves,
    /// Every run of the optimiser.
    #[serde(skip)]
    pub records: Vec<Record>,
}

/// A compared column in the report.
#[derive(Debug, Clone, Serialize)]
pub struct ColumnReport {
    /// The measured column's name (from the CSV header).
    pub measured: String,
    /// The series column.
    pub column: String,
    /// The measured values' unit and whether it was assumed (none given).
    pub unit: String,
    pub unit_assumed: bool,
}

/// Fits `prep`: Nelder–Mead from its start until the tolerance, `max_evals` runs or `cancel`;
/// then the uncertainty (unless cancelled). The best run so far is kept whatever stops it. Fails
/// only when no run completed (with the first failure's reason).
pub fn fit(prep: &Prepared, cancel: &AtomicBool, watch: &mut dyn Watch) -> Result<FitReport> {
    let started = Instant::now();
    let a = &prep.args;
    let free = &prep.problem.free;
    let z0: Vec<f64> = free
        .iter()
        .zip(&prep.start)
        .map(|(f, p)| f.coordinate(*p))
        .collect();
    let obj = Objective {
        prep,
        cancel,
        threads: a.threads.max(1),
        max_evals: a.max_evals,
        state: RefCell::new(Runs {
            cache: HashMap::new(),
            records: Vec::new(),
            best: None,
            watch,
            stopped: None,
            since_best: 0,
        }),
    };
    // The start and the sample, side by side; the simplex starts from the best of them, its
    // size half the sample's spacing N^(−1/n).
    let n = free.len();
    let sample = a.sample.unwrap_or_else(|| default_sample(n));
    let mut first: Vec<Vec<f64>> = vec![z0.clone()];
    first.extend((1..=sample as u64).map(|i| halton(i, n)));
    first.truncate(a.max_evals);
    obj.run_many(&first);
    let best_first = {
        let st = obj.state.borrow();
        st.best.map(|b| st.records[b].z.clone())
    };
    let step = if sample == 0 {
        0.15
    } else {
        (0.5 * (sample as f64).powf(-1.0 / n as f64)).clamp(0.02, 0.15)
    };
    let mut from = best_first.unwrap_or_else(|| z0.clone());
    let mut restarts = 0;
    let stop = loop {
        let stop = nelder_mead(&obj, &from, step, n)?;
        if !matches!(stop, Stop::Converged | Stop::Stalled) || restarts == MAX_RESTARTS {
            break stop;
        }
        // Restarted from the best point with a simplex of the first size, Nelder–Mead leaves a
        // place where its simplex collapsed on a step of c(p) (or crawled along a valley); the
        // fit ends when a restart finds nothing better.
        let st = obj.state.borrow();
        let best = st.best.map(|b| st.records[b].z.clone());
        drop(st);
        let Some(best) = best else { break stop };
        if restarts > 0 && best == from {
            break stop;
        }
        from = best;
        restarts += 1;
    };
    let (records, best) = {
        let st = obj.state.borrow();
        (st.records.clone(), st.best)
    };
    let Some(best) = best else {
        let first = records
            .iter()
            .find_map(|r| r.error.clone())
            .unwrap_or_else(|| "cancelled before any run ended".into());
        bail!("no run of the fit completed; the first failed with: {first}");
    };
    let best_z = records[best].z.clone();
    let lookup_y = |z: &[f64]| -> Option<Vec<f64>> {
        match obj.state.borrow().cache.get(&bits(z)) {
            Some(Evaluation::Done { y, .. }) => Some(y.clone()),
            _ => None,
        }
    };
    let fitted_y = lookup_y(&best_z).expect("the best run completed and is cached");
    let initial_y = lookup_y(&z0);
    let p = &prep.problem;
    let agreement = |y: &[f64]| {
        let cost = p.misfit(y);
        Agreement {
            cost,
            rms_relative: cost.sqrt(),
            rms: cost.sqrt() * p.y_scale / prep.y_unit.factor,
        }
    };
    let (sigmas, correlation, extra) = if stop == Stop::Cancelled {
        (vec![None; free.len()], None, 0)
    } else {
        uncertainty(&obj, &best_z, &fitted_y)
    };
    let parameters = free
        .iter()
        .enumerate()
        .map(|(j, f)| {
            let value = records[best].values[j];
            Fitted {
                key: f.key.clone(),
                lo: f.lo,
                hi: f.hi,
                log: f.log,
                start: prep.start[j],
                start_from: prep.start_from[j],
                value,
                sigma: sigmas[j],
                at_bound: best_z[j] <= 1e-3 || best_z[j] >= 1.0 - 1e-3,
            }
        })
        .collect();
    let to_measured =
        |y: &[f64]| -> Vec<f64> { y.iter().map(|v| v / prep.y_unit.factor).collect() };
    let column =
        |measured: &data::Header, c: &problem::Column, u: &Unit, assumed: bool| ColumnReport {
            measured: measured.name.clone(),
            column: c.name.clone(),
            unit: u.name.clone(),
            unit_assumed: assumed,
        };
    Ok(FitReport {
        scene: a.scene.display().to_string(),
        name: prep.name.clone(),
        data: prep.curve.file.clone(),
        set: a.set.clone(),
        x: column(
            &prep.curve.x_header,
            &p.x,
            &prep.x_unit,
            prep.units_assumed[0],
        ),
        y: column(
            &prep.curve.y_header,
            &p.y,
            &prep.y_unit,
            prep.units_assumed[1],
        ),
        points: p.xs.len(),
        parameters,
        correlation,
        initial: initial_y.as_deref().map(agreement),
        fitted: agreement(&fitted_y),
        stop,
        evaluations: records.len(),
        failed_evaluations: records.iter().filter(|r| r.status == "failed").count(),
        uncertainty_evaluations: extra,
        restarts,
        optimiser: format!(
            "Nelder–Mead (argmin 0.11; α = 1, γ = 2, ρ = σ = 0.5) over z ∈ [0, 1]^{}",
            free.len()
        ),
        tolerance: a.tolerance,
        max_evals: a.max_evals,
        wall_seconds: started.elapsed().as_secs_f64(),
        curves: Curves {
            x: prep.curve.x.clone(),
            measured: prep.curve.y.clone(),
            initial: initial_y.as_deref().map(to_measured),
            fitted: to_measured(&fitted_y),
        },
        records,
    })
}
