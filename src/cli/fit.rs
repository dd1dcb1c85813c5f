//! `decohesion fit SCENE --data CURVE.csv --x COLUMN --y COLUMN --free key=lo..hi …`: the
//! values of the free keys that make the run reproduce a measured curve ([`crate::fit`]), with a
//! progress bar over the runs, Ctrl-C keeping the best so far, and the results in a folder:
//! - `fit.json`: the report (values, σ, correlations, residuals, the curves);
//! - `fit.csv`: x, the measured y, the run at the start and the fitted run, in the measured units;
//! - `evaluations.csv`: every run of the optimiser, its values and misfit;
//! - `fit.svg`: the picture;
//! - `<scene>_fitted.toml`: the scene file with the fitted values (comments kept);
//!
//! and, with `--save`, a Rerun recording of the curves and of the optimiser's path.

use crate::driver::cancel_on_ctrl_c;
use crate::fit::outputs::{table, write_outputs};
use crate::fit::{fit as run_fit, prepare, FitArgs, FitReport, Record, Stop, Watch};
use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The options of `decohesion fit` beyond the fit itself.
pub struct FitCli {
    pub args: FitArgs,
    /// Folder of the results [default: out/fit_<scene name>].
    pub out: Option<PathBuf>,
    /// A Rerun recording of the fit.
    pub save: Option<PathBuf>,
    pub quiet: bool,
}

/// The bar over the runs (a line every tenth of `--max-evals` off a terminal).
struct Bar {
    bar: ProgressBar,
    tty: bool,
    quiet: bool,
    keys: Vec<String>,
    max: usize,
}

impl Watch for Bar {
    fn evaluated(&mut self, r: &Record, best: Option<&Record>) {
        self.bar.set_position(r.index as u64);
        let best_text = best.map_or("no run completed yet".to_string(), |b| {
            let values: Vec<String> = self
                .keys
                .iter()
                .zip(&b.values)
                .map(|(k, v)| format!("{}={v:.5e}", k.rsplit('.').next().unwrap_or(k)))
                .collect();
            format!(
                "best RMS {:.3} % at {}",
                100.0 * b.cost.unwrap_or(f64::NAN).sqrt(),
                values.join(" ")
            )
        });
        self.bar.set_message(best_text.clone());
        let tenth = (self.max / 10).max(1);
        if !self.tty && !self.quiet && r.index.is_multiple_of(tenth) {
            eprintln!("  run {}: {best_text}", r.index);
        }
    }
}

/// Runs `decohesion fit`.
pub fn fit(c: FitCli) -> Result<()> {
    let prep = prepare(&c.args)?;
    let dir = c
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/fit_{}", prep.name)));
    if dir.exists() && !dir.is_dir() {
        bail!("--out {}: not a folder", dir.display());
    }
    if let Some(save) = &c.save {
        if save.extension().and_then(|e| e.to_str()) != Some("rrd") {
            bail!("--save {}: give a file name ending in .rrd", save.display());
        }
    }
    if !c.quiet {
        let free: Vec<String> = prep
            .problem
            .free
            .iter()
            .zip(&prep.start)
            .map(|(f, s)| format!("{} in [{}, {}] from {s}", f.key, f.lo, f.hi))
            .collect();
        eprintln!(
            "decohesion fit: {} ({}) to {} ({} points, {} against {}); {}; at most {} runs",
            c.args.scene.display(),
            prep.name,
            prep.curve.file,
            prep.problem.xs.len(),
            prep.problem.y.name,
            prep.problem.x.name,
            free.join(", "),
            c.args.max_evals
        );
        for (k, assumed) in prep.units_assumed.iter().enumerate() {
            if *assumed {
                let (h, col) = if k == 0 {
                    (&prep.curve.x_header, &prep.problem.x)
                } else {
                    (&prep.curve.y_header, &prep.problem.y)
                };
                eprintln!(
                    "warning: {}: column `{}` has no unit; taken in [{}] like {} (give it as \
                     `{} [unit]` in the header or with --{}-unit)",
                    prep.curve.file,
                    h.name,
                    col.unit,
                    col.name,
                    h.name,
                    if k == 0 { "x" } else { "y" }
                );
            }
        }
    }
    let tty = std::io::stderr().is_terminal() && !c.quiet;
    let bar = ProgressBar::with_draw_target(
        Some(c.args.max_evals as u64),
        if tty {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} runs  {msg}",
        )
        .expect("static template"),
    );
    let mut watch = Bar {
        bar,
        tty,
        quiet: c.quiet,
        keys: prep.problem.free.iter().map(|f| f.key.clone()).collect(),
        max: c.args.max_evals,
    };
    let interrupted = Arc::new(AtomicBool::new(false));
    cancel_on_ctrl_c(interrupted.clone());
    let report = run_fit(&prep, &interrupted, &mut watch);
    watch.bar.finish_and_clear();
    let report = report?;
    // The files first (a reader that stops early, `| head`, ends the process at the table),
    // then the table, printed also when a file could not be written.
    let written = std::fs::create_dir_all(&dir)
        .with_context(|| format!("--out {}: cannot create the folder", dir.display()))
        .and_then(|()| write_outputs(&dir, &prep.args.scene, &report))
        .and_then(|()| {
            c.save
                .as_ref()
                .map_or(Ok(()), |save| log_fit(save, &report))
        });
    print!("{}", table(&report));
    written?;
    println!("results in {}", dir.display());
    if interrupted.load(Ordering::SeqCst) || report.stop == Stop::Cancelled {
        bail!(
            "interrupted after {} runs: the best so far is written to {}",
            report.evaluations,
            dir.display()
        );
    }
    Ok(())
}

/// The integer timeline of the measured x: ticks of 10^e of its unit, e the smallest power that
/// keeps the span within 2000 ticks (what the viewer plots whole).
fn x_ticks(x: &[f64]) -> (i32, Vec<i64>) {
    let span = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let e = if span > 0.0 {
        (span / 2000.0).log10().ceil() as i32
    } else {
        0
    };
    let unit = 10f64.powi(e);
    (e, x.iter().map(|v| (v / unit).round() as i64).collect())
}

/// Records the fit to `path`: the measured, start and fitted curves against the measured x, and
/// the misfit and values of every run against the run's number.
fn log_fit(path: &Path, r: &FitReport) -> Result<()> {
    use rerun::{RecordingStreamBuilder, Rgba32, Scalars, SeriesLines, SeriesPoints, TextDocument};
    let rec = RecordingStreamBuilder::new(crate::record::APPLICATION_ID)
        .recording_name(format!("fit · {}", r.name))
        .save(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    let (e, ticks) = x_ticks(&r.curves.x);
    let name = format!("{} [×1e{e} {}]", r.x.measured, r.x.unit);
    let timeline = rerun::TimelineName::try_new(&name)
        .map_err(|e| anyhow::anyhow!("timeline `{name}`: {e:?}"))?;
    let mut curves: Vec<(&str, &[f64], [u8; 3], bool)> =
        vec![("measured", &r.curves.measured, [34, 34, 34], true)];
    if let Some(i) = &r.curves.initial {
        curves.push(("start", i, [136, 136, 136], false));
    }
    curves.push(("fitted", &r.curves.fitted, [214, 39, 40], false));
    for (name, y, [cr, cg, cb], points) in curves {
        let entity = format!("fit/curve/{name}");
        let colour = Rgba32::from_rgb(cr, cg, cb);
        if points {
            rec.log_static(
                entity.as_str(),
                &SeriesPoints::new()
                    .with_names([name])
                    .with_colors([colour])
                    .with_marker_sizes([3.0]),
            )?;
        } else {
            rec.log_static(
                entity.as_str(),
                &SeriesLines::new().with_names([name]).with_colors([colour]),
            )?;
        }
        for (t, v) in ticks.iter().zip(y) {
            rec.set_time_sequence(timeline, *t);
            rec.log(entity.as_str(), &Scalars::single(*v))?;
        }
    }
    rec.reset_time();
    for record in &r.records {
        rec.set_time_sequence("run", record.index as i64);
        if let Some(c) = record.cost {
            rec.log("fit/runs/misfit", &Scalars::single(c))?;
        }
        for (p, v) in r.parameters.iter().zip(&record.values) {
            rec.log(format!("fit/runs/{}", p.key).as_str(), &Scalars::single(*v))?;
        }
    }
    rec.reset_time();
    rec.log_static(
        "fit/report",
        &TextDocument::from_markdown(format!("```\n{}```\n", table(r))),
    )?;
    rec.flush_blocking().context("flushing the recording")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::x_ticks;

    #[test]
    fn x_timeline_stays_within_2000_ticks() {
        let (e, t) = x_ticks(&[0.0, 0.001, 0.33]);
        assert_eq!(e, -3);
        assert_eq!(t, [0, 1, 330]);
        let (e, t) = x_ticks(&[0.0, 5.0, 12.0]);
        assert_eq!(e, -2);
        assert_eq!(t, [0, 500, 1200]);
    }
}
