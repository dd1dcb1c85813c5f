//! `decohesion tradeoff`: a grid of quadratures × meshes × time steps of one scene, compared
//! with the finest run ([`crate::tradeoff`]), printed, written as CSV and JSON, and optionally
//! recorded ([`crate::record::log_frontier`]).

use crate::record::Sink;
use crate::scene::load_scene;
use anyhow::{bail, Context, Result};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Validates every configuration, then runs them with a progress bar and writes the results.
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
    let bar = indicatif::ProgressBar::new(configs.len() as u64);
    if std::io::stderr().is_terminal() {
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} runs  {msg}",
            )
            .expect("static template"),
        );
    } else {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let mut rows = vec![];
    for c in &configs {
        bar.set_message(format!("{} {}³ ×{}", c.integration, c.cells, c.factor));
        rows.push(run_one(path, c, set)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    compare(&mut rows);
    println!(
        "decohesion tradeoff: {} ({}), {} threads; reference = the finest full-integration run; error = largest relative error of peak force, first damage, full rupture, dissipation",
        path.display(),
        base.model.name,
        rayon::current_num_threads()
    );
    print!("{}", crate::tradeoff::table(&rows));
    let prefix = out.unwrap_or_else(|| PathBuf::from(format!("out/tradeoff_{}", base.model.name)));
    if let Some(dir) = prefix.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
    }
    let csv_path = prefix.with_extension("csv");
    let json_path = prefix.with_extension("json");
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
