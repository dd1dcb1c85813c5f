//! `decohesion tradeoff`: a grid of quadratures × meshes × time steps of one scene, compared
//! with the finest run ([`crate::tradeoff`]), printed, written as CSV and JSON into the `--out`
//! folder (`tradeoff.csv`, `tradeoff.json`), and optionally recorded
//! ([`crate::record::log_frontier`]).

use super::progress::{per_mille, sim_time, time_bar};
use crate::record::Sink;
use crate::scene::load_scene;
use anyhow::{bail, Context, Result};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// The files the results are written to, in the `--out` folder.
pub const CSV_FILE: &str = "tradeoff.csv";
pub const JSON_FILE: &str = "tradeoff.json";

/// Validates every configuration, then runs them with progress (a bar for the grid and one for
/// the run in progress on a terminal, a line per finished run otherwise, nothing with
/// `quiet`) and writes the results into the folder `out`.
#[allow(clippy::too_many_arguments)]
pub fn tradeoff(
    path: &Path,
    cells: &[usize],
    factors: &[f64],
    integrations: &[String],
    set: &[String],
    out: Option<PathBuf>,
    save: Option<PathBuf>,
    spawn: bool,
    quiet: bool,
) -> Result<()> {
    use crate::tradeoff::{compare, csv, grid, run as run_one};
    if cells.is_empty() || factors.is_empty() || integrations.is_empty() {
        bail!("--cells, --factors and --integration each need at least one value");
    }
    // Validate the scene and every configuration before running anything.
    let base = load_scene(path, set)?;
    crate::tradeoff::require_box_mesh(&base, "--cells")?;
    let configs = grid(integrations, cells, factors);
    for c in &configs {
        let o = crate::tradeoff::overrides(path, c, set)?;
        load_scene(path, &o).with_context(|| {
            format!("configuration {} {}³ ×{}", c.integration, c.cells, c.factor)
        })?;
    }
    let tty = std::io::stderr().is_terminal() && !quiet;
    let multi = MultiProgress::with_draw_target(if tty {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    });
    let overall = multi.add(ProgressBar::new(configs.len() as u64));
    overall.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} runs  ETA {eta}",
        )
        .expect("static template"),
    );
    let mut rows = vec![];
    for (k, c) in configs.iter().enumerate() {
        let name = format!("{} {}³ ×{}", c.integration, c.cells, c.factor);
        let bar = multi.add(time_bar("  {bar:30} {percent:>3} %  {prefix}  {msg}"));
        bar.set_prefix(name.clone());
        let mut on_step = |s: &crate::solver::Simulation| {
            if s.state.step_count.is_multiple_of(64) || s.finished() {
                bar.set_position(per_mille(s));
                bar.set_message(format!("t = {}", sim_time(s.state.time, s.model.end_time)));
            }
        };
        let row = run_one(path, c, set, &mut on_step)?;
        bar.finish_and_clear();
        overall.inc(1);
        if !tty && !quiet {
            eprintln!(
                "  run {}/{}: {name}  {}",
                k + 1,
                configs.len(),
                row.failure
                    .as_ref()
                    .map_or("completed".to_string(), |e| format!("failed: {e}"))
            );
        }
        rows.push(row);
    }
    overall.finish_and_clear();
    compare(&mut rows);
    println!(
        "decohesion tradeoff: {} ({}), {} threads; reference = the finest full-integration run; error = largest relative error of peak force, first damage, full rupture, dissipation",
        path.display(),
        base.model.name,
        rayon::current_num_threads()
    );
    print!("{}", crate::tradeoff::table(&rows));
    let dir = out.unwrap_or_else(|| PathBuf::from(format!("out/tradeoff_{}", base.model.name)));
    std::fs::create_dir_all(&dir).with_context(|| {
        format!(
            "--out {}: cannot create the folder of {CSV_FILE} and {JSON_FILE}",
            dir.display()
        )
    })?;
    let (csv_path, json_path) = (dir.join(CSV_FILE), dir.join(JSON_FILE));
    std::fs::write(&csv_path, csv(&rows))
        .with_context(|| format!("writing {}", csv_path.display()))?;
    std::fs::write(&json_path, serde_json::to_string_pretty(&rows)?)
        .with_context(|| format!("writing {}", json_path.display()))?;
    println!("wrote {} and {}", csv_path.display(), json_path.display());
    let sinks = save
        .map(Sink::Save)
        .into_iter()
        .chain(spawn.then_some(Sink::Spawn));
    for sink in sinks {
        crate::record::log_frontier(sink, &base.model.name, &rows)
            .context("recording the frontier")?;
    }
    Ok(())
}
