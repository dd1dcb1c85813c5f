//! `decohesion sweep SCENE --vary key=v1,v2,… [--vary …]`: the grid (cartesian product) of runs
//! of one scene, each through the run driver ([`crate::driver`]) with the `--set` overrides of its
//! values, so each row is what `decohesion run --set` gives for them. Written as CSV and JSON (the
//! varied values first), printed as a table, optionally recorded to Rerun with every observable
//! against every varied value ([`super::sweep_record`]).
//!
//! Runs are independent, so several run at once: `--jobs` of them (default: as many as the
//! threads of the global pool, `--threads` or the cores, and no more than the runs), each on
//! threads/jobs threads of its own (results do not depend on the thread count). On a small
//! mesh a run's step is serial anyway (below `PARALLEL_MIN_ELEMENTS`), so runs side by side
//! are the only way to use both cores; on a large one, two one-thread runs also avoid the
//! parallel sections' synchronisation (docs: performance log). A failed run (set-up refused,
//! blow-up, diagnostic) is a row with its status; Ctrl-C stops the runs in progress after their
//! current step (their rows say `cancelled`), starts no other, and writes the rows done.

use super::progress::{per_mille, sim_time, time_bar};
use super::sweep_record::log_sweep;
use crate::driver::{cancel_on_ctrl_c, Driver, Progress};
use crate::output::Cadence;
use crate::outputs::Plan;
use crate::report::RunSummary;
use crate::scene::{load_scene, Scene};
use crate::solver::Simulation;
pub use crate::vary::Vary;
use anyhow::{bail, Context, Result};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// The grid: every combination of the values, the last key varying fastest; each is the list
/// of `key=value` overrides.
pub fn grid(varies: &[Vary]) -> Vec<Vec<String>> {
    let mut out: Vec<Vec<String>> = vec![vec![]];
    for v in varies {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                v.values.iter().map(move |value| {
                    let mut p = prefix.clone();
                    p.push(format!("{}={value}", v.key));
                    p
                })
            })
            .collect();
    }
    out
}

/// The value of `key` in a combination of [`grid`].
fn value_of<'a>(combo: &'a [String], key: &str) -> &'a str {
    combo
        .iter()
        .find_map(|s| s.strip_prefix(key).and_then(|r| r.strip_prefix('=')))
        .unwrap_or("")
}

/// One run of the grid.
#[derive(Debug, Clone, Serialize)]
pub struct SweepRow {
    /// The varied values, in the order of the `--vary` flags (as given).
    pub values: Vec<String>,
    /// "completed", "failed" or "cancelled".
    pub status: String,
    pub error: Option<String>,
    /// The run's summary, as `decohesion run --summary` writes it (none when set-up failed).
    pub summary: Option<RunSummary>,
}

impl SweepRow {
    /// Largest |reaction| of the first prescribed displacement [N].
    pub fn peak_force(&self) -> Option<f64> {
        let s = self.summary.as_ref()?;
        s.peak_reactions.first().map(|p| p.force)
    }
}

/// The options of a sweep.
pub struct SweepArgs<'a> {
    pub scene: &'a Path,
    pub vary: &'a [String],
    pub set: &'a [String],
    pub out: Option<PathBuf>,
    pub save: Option<PathBuf>,
    pub jobs: Option<usize>,
    pub quiet: bool,
}

/// Validates the grid (every value alone, then every combination, through the scene's own
/// checks), runs it, writes the rows.
pub fn sweep(a: SweepArgs<'_>) -> Result<()> {
    let varies: Vec<Vary> = a
        .vary
        .iter()
        .map(|s| Vary::parse(s))
        .collect::<Result<_>>()?;
    if varies.is_empty() {
        bail!("give at least one --vary key=v1,v2,…");
    }
    for (i, v) in varies.iter().enumerate() {
        if varies[..i].iter().any(|w| w.key == v.key) {
            bail!("--vary {}: the key is varied twice", v.key);
        }
        for value in &v.values {
            let mut set = a.set.to_vec();
            set.push(format!("{}={value}", v.key));
            load_scene(a.scene, &set)
                .with_context(|| format!("--vary {}: the value `{value}`", v.key))?;
        }
    }
    let base = load_scene(a.scene, a.set)?;
    let combos = grid(&varies);
    for c in &combos {
        let set: Vec<String> = a.set.iter().chain(c).cloned().collect();
        load_scene(a.scene, &set).with_context(|| format!("the combination {}", c.join(" ")))?;
    }
    let total = rayon::current_num_threads().max(1);
    let jobs = a.jobs.unwrap_or(total).clamp(1, combos.len());
    let threads = (total / jobs).max(1);
    if !a.quiet {
        eprintln!(
            "decohesion sweep: {} ({}), {} runs, {jobs} at a time on {threads} thread{} each",
            a.scene.display(),
            base.model.name,
            combos.len(),
            if threads == 1 { "" } else { "s" }
        );
    }
    let interrupted = Arc::new(AtomicBool::new(false));
    cancel_on_ctrl_c(interrupted.clone());
    let runner = Runner {
        scene: a.scene,
        set: a.set,
        threads,
        cancel: &interrupted,
        bars: Bars::new(combos.len(), a.quiet),
    };
    let rows = runner.run_all(&combos, &varies, jobs);
    let done = rows.len();
    write_outputs(&a, &base, &varies, &rows)?;
    if interrupted.load(Ordering::SeqCst) {
        bail!(
            "interrupted: {done} of {} runs written ({} not started)",
            combos.len(),
            combos.len() - done
        );
    }
    Ok(())
}

/// Runs the combinations.
struct Runner<'a> {
    scene: &'a Path,
    set: &'a [String],
    threads: usize,
    cancel: &'a AtomicBool,
    bars: Bars,
}

impl Runner<'_> {
    /// Runs every combination on `jobs` threads (each taking the next one not started) until
    /// done or cancelled; returns the rows of the runs that started, in grid order.
    fn run_all(&self, combos: &[Vec<String>], varies: &[Vary], jobs: usize) -> Vec<SweepRow> {
        let next = AtomicUsize::new(0);
        let rows: Mutex<Vec<Option<SweepRow>>> = Mutex::new(vec![None; combos.len()]);
        std::thread::scope(|s| {
            for _ in 0..jobs {
                s.spawn(|| loop {
                    if self.cancel.load(Ordering::SeqCst) {
                        return;
                    }
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    let Some(combo) = combos.get(i) else {
                        return;
                    };
                    let values: Vec<String> = varies
                        .iter()
                        .map(|v| value_of(combo, &v.key).to_string())
                        .collect();
                    let row = self.run_one(combo, values);
                    self.bars.finished(&row, combo);
                    rows.lock().expect("no panic holds the rows")[i] = Some(row);
                });
            }
        });
        self.bars.overall.finish_and_clear();
        let rows = rows.into_inner().expect("no panic holds the rows");
        rows.into_iter().flatten().collect()
    }

    /// One run, as `decohesion run --set` does it (without outputs).
    fn run_one(&self, combo: &[String], values: Vec<String>) -> SweepRow {
        let started = Instant::now();
        let set: Vec<String> = self.set.iter().chain(combo).cloned().collect();
        let failed = |error: String| SweepRow {
            values: values.clone(),
            status: "failed".into(),
            error: Some(error),
            summary: None,
        };
        let scene: Scene = match load_scene(self.scene, &set) {
            Ok(s) => s,
            Err(e) => return failed(e.to_string()),
        };
        let mut sim = match Simulation::new(scene.model.clone()) {
            Ok(s) => s,
            Err(e) => return failed(e.to_string()),
        };
        // The run's share of the threads, never more than the simulation takes by itself (one
        // below the mesh size where the step's parallel sections pay off).
        if sim.threads() > self.threads {
            sim.use_threads(self.threads);
        }
        let plan = Plan::none(Cadence::Default);
        let driver = match Driver::open(&plan, &scene, &sim, started) {
            Ok(d) => d,
            Err(e) => return failed(e.to_string()),
        };
        let mut bar = self.bars.run_bar(&sim, combo);
        let done = driver.run(&mut sim, self.cancel, &mut bar);
        SweepRow {
            values,
            status: done.summary.status.clone(),
            error: done.summary.error.clone(),
            summary: Some(done.summary),
        }
    }
}

/// The progress bars: one for the grid, one per run in progress (hidden off a terminal, where
/// a line per finished run is printed instead).
struct Bars {
    multi: MultiProgress,
    overall: ProgressBar,
    quiet: bool,
    tty: bool,
}

impl Bars {
    fn new(runs: usize, quiet: bool) -> Bars {
        let tty = std::io::stderr().is_terminal() && !quiet;
        let multi = MultiProgress::with_draw_target(if tty {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        });
        let overall = multi.add(ProgressBar::new(runs as u64));
        overall.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} runs  ETA {eta}",
            )
            .expect("static template"),
        );
        Bars {
            multi,
            overall,
            quiet,
            tty,
        }
    }

    /// The bar of one run, over its simulated time ([`super::progress`]).
    fn run_bar(&self, sim: &Simulation, combo: &[String]) -> RunBar {
        let bar = self
            .multi
            .add(time_bar("  {bar:30} {percent:>3} %  {prefix}  {msg}"));
        bar.set_prefix(combo.join(" "));
        RunBar {
            bar,
            end_time: sim.model.end_time,
        }
    }

    /// A run ended: the overall bar moves, a line off a terminal.
    fn finished(&self, row: &SweepRow, combo: &[String]) {
        self.overall.inc(1);
        if !self.tty && !self.quiet {
            let pos = self.overall.position();
            let len = self.overall.length().unwrap_or(0);
            eprintln!(
                "  run {pos}/{len}: {}  {}{}",
                combo.join(" "),
                row.status,
                row.error
                    .as_ref()
                    .map_or(String::new(), |e| format!(": {e}"))
            );
        }
    }
}

/// The bar of one run in progress.
struct RunBar {
    bar: ProgressBar,
    end_time: f64,
}

impl Progress for RunBar {
    fn step(&mut self, s: &Simulation) {
        if s.state.step_count.is_multiple_of(64) || s.finished() {
            self.bar.set_position(per_mille(s));
            self.bar
                .set_message(format!("t = {}", sim_time(s.state.time, self.end_time)));
        }
    }

    fn stopped(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// Writes `sweep.csv` and `sweep.json` to the output folder, prints the table, records.
fn write_outputs(
    a: &SweepArgs<'_>,
    base: &Scene,
    varies: &[Vary],
    rows: &[SweepRow],
) -> Result<()> {
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/sweep_{}", base.model.name)));
    std::fs::create_dir_all(&dir).with_context(|| {
        format!(
            "--out {}: cannot create the folder of sweep.csv and sweep.json",
            dir.display()
        )
    })?;
    let (csv_path, json_path) = (dir.join("sweep.csv"), dir.join("sweep.json"));
    std::fs::write(&csv_path, csv(varies, rows))
        .with_context(|| format!("writing {}", csv_path.display()))?;
    let json = serde_json::json!({
        "scene": a.scene.display().to_string(),
        "set": a.set,
        "vary": varies,
        "runs": rows,
    });
    std::fs::write(&json_path, serde_json::to_string_pretty(&json)?)
        .with_context(|| format!("writing {}", json_path.display()))?;
    print!("{}", table(varies, rows));
    println!("wrote {} and {}", csv_path.display(), json_path.display());
    if let Some(path) = &a.save {
        log_sweep(path, &base.model.name, varies, rows)
            .with_context(|| format!("recording the sweep to {}", path.display()))?;
        println!("recorded {}", path.display());
    }
    let failed = rows.iter().filter(|r| r.status == "failed").count();
    if failed > 0 {
        println!(
            "{failed} of {} runs failed (their rows say why)",
            rows.len()
        );
    }
    Ok(())
}

/// The observables of a row: (CSV column, table header, value). Also what the recording plots.
pub fn observables(row: &SweepRow) -> Vec<(&'static str, &'static str, Option<f64>)> {
    let s = row.summary.as_ref();
    let e = s.map(|s| &s.energies);
    vec![
        ("peak_force_N", "peak N", row.peak_force()),
        (
            "damage_dissipated_J",
            "dissipated J",
            e.map(|e| e.damage_dissipated),
        ),
        (
            "friction_dissipated_J",
            "friction J",
            e.map(|e| e.friction_dissipated),
        ),
        ("external_work_J", "ext. work J", e.map(|e| e.external_work)),
        (
            "time_first_damage_s",
            "damage s",
            s.and_then(|s| s.time_first_damage),
        ),
        (
            "time_full_rupture_s",
            "rupture s",
            s.and_then(|s| s.time_full_rupture),
        ),
        (
            "ruptured",
            "ruptured",
            s.map(|s| s.final_counts.ruptured as f64),
        ),
        ("end_time_s", "end s", s.map(|s| s.simulated_time)),
        (
            "max_relative_residual",
            "residual",
            s.map(|s| s.max_relative_residual),
        ),
        ("steps", "steps", s.map(|s| s.steps as f64)),
        ("wall_s", "wall s", s.map(|s| s.wall_seconds)),
    ]
}

/// The (CSV column, table header) of each observable, in [`observables`] order.
pub fn observable_names() -> Vec<(&'static str, &'static str)> {
    let blank = SweepRow {
        values: vec![],
        status: String::new(),
        error: None,
        summary: None,
    };
    observables(&blank).iter().map(|o| (o.0, o.1)).collect()
}

/// The rows as CSV: the varied keys, then the status, the observables, the error.
pub fn csv(varies: &[Vary], rows: &[SweepRow]) -> String {
    let quote = |v: &str| format!("\"{}\"", v.replace('"', "\"\""));
    let mut head: Vec<String> = varies.iter().map(|v| quote(&v.key)).collect();
    head.push("status".into());
    head.extend(observable_names().iter().map(|o| o.0.to_string()));
    head.push("error".into());
    let mut s = head.join(",") + "\n";
    for r in rows {
        let mut cells: Vec<String> = r.values.iter().map(|v| quote(v)).collect();
        cells.push(r.status.clone());
        cells.extend(
            observables(r)
                .iter()
                .map(|o| o.2.map_or(String::new(), |v| format!("{v:e}"))),
        );
        cells.push(quote(r.error.as_deref().unwrap_or("")));
        s.push_str(&(cells.join(",") + "\n"));
    }
    s
}

/// The rows as a fixed-width table (the observables most sweeps are about).
pub fn table(varies: &[Vary], rows: &[SweepRow]) -> String {
    let shown = [0, 1, 5, 6, 8, 10];
    let width = |k: usize| {
        rows.iter()
            .map(|r| r.values[k].len())
            .chain([varies[k].key.len()])
            .max()
            .unwrap_or(8)
    };
    let widths: Vec<usize> = (0..varies.len()).map(width).collect();
    let mut s = String::new();
    for (v, w) in varies.iter().zip(&widths) {
        s.push_str(&format!("{:>w$} ", v.key));
    }
    let heads = observable_names();
    s.push_str(&format!("{:>10}", "status"));
    for k in shown {
        s.push_str(&format!(" {:>12}", heads[k].1));
    }
    s.push('\n');
    for r in rows {
        for (v, w) in r.values.iter().zip(&widths) {
            s.push_str(&format!("{v:>w$} "));
        }
        s.push_str(&format!("{:>10}", r.status));
        let obs = observables(r);
        for k in shown {
            let cell = obs[k].2.map_or("—".to_string(), |v| format!("{v:.4e}"));
            s.push_str(&format!(" {cell:>12}"));
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values split on top-level commas only; the grid is the cartesian product, last key
    /// fastest; bad specs name the key.
    #[test]
    fn parse_and_grid() {
        let v = Vary::parse("mesh.cells=[2,2,2], [3,3,3]").unwrap();
        assert_eq!(v.values, ["[2,2,2]", "[3,3,3]"]);
        let s = Vary::parse("scheme.integration=\"full\",'reduced'").unwrap();
        assert_eq!(s.values, ["\"full\"", "'reduced'"]);
        let g = grid(&[
            Vary::parse("a=1,2").unwrap(),
            Vary::parse("b=x,y,z").unwrap(),
        ]);
        assert_eq!(g.len(), 6);
        assert_eq!(g[0], ["a=1", "b=x"]);
        assert_eq!(g[1], ["a=1", "b=y"]);
        assert_eq!(g[5], ["a=2", "b=z"]);
        assert_eq!(value_of(&g[4], "b"), "y");
        for (spec, needle) in [
            ("u_r", "no `=`"),
            ("u_r=", "--vary u_r: the list of values is empty"),
            ("u_r=1,,2", "--vary u_r: value 2"),
            ("=1,2", "the key is empty"),
        ] {
            let e = Vary::parse(spec).unwrap_err().to_string();
            assert!(e.contains(needle), "{spec}: {e}");
        }
    }
}
