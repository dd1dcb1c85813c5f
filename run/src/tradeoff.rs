//! Speed against accuracy, measured: run a grid of configurations (quadrature × mesh × time
//! step) of one scene and compare their observables with the most accurate one.
//!
//! The observables are the scene's: peak reaction of the first prescribed displacement, time of
//! first damage, time of full rupture, energy dissipated by damage, max balance residual. The
//! reference is the finest configuration of the grid (most cells, smallest h/h_crit, full
//! integration); its own errors are 0 by construction, so errors of the next-finest rows are
//! lower bounds (Richardson's caveat).

use crate::driver::{Driver, Progress};
use crate::output::Cadence;
use crate::scene::{load_scene, Scene, SceneError};
use crate::solver::Simulation;
use serde::Serialize;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// One configuration of the grid.
#[derive(Debug, Clone, Serialize)]
pub struct Config {
    /// "full", "reduced", "fbar" or "reduced_physical".
    pub integration: String,
    /// Cells along the longest side.
    pub cells: usize,
    /// h / h_crit.
    pub factor: f64,
}

/// What one configuration gave.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub config: Config,
    pub elements: usize,
    pub steps: u64,
    /// Wall time of the steps [s] (set-up excluded).
    pub wall_seconds: f64,
    pub ns_per_element_step: f64,
    /// Observables [N], [s], [s], [J], [-].
    pub peak_force: Option<f64>,
    pub time_first_damage: Option<f64>,
    pub time_full_rupture: Option<f64>,
    pub damage_dissipated: f64,
    pub max_relative_residual: f64,
    /// Relative errors against the reference (None when either side lacks the observable).
    pub error_peak_force: Option<f64>,
    pub error_first_damage: Option<f64>,
    pub error_full_rupture: Option<f64>,
    pub error_dissipated: Option<f64>,
    /// Largest of the relative errors above: the accuracy axis of the frontier.
    pub error: f64,
    /// On the Pareto front of (wall time, error).
    pub pareto: bool,
    pub reference: bool,
    /// Why the run stopped early, if it did.
    pub failure: Option<String>,
}

impl Row {
    /// A row with nothing measured yet.
    pub fn new(config: Config, elements: usize) -> Row {
        Row {
            config,
            elements,
            steps: 0,
            wall_seconds: 0.0,
            ns_per_element_step: 0.0,
            peak_force: None,
            time_first_damage: None,
            time_full_rupture: None,
            damage_dissipated: 0.0,
            max_relative_residual: 0.0,
            error_peak_force: None,
            error_first_damage: None,
            error_full_rupture: None,
            error_dissipated: None,
            error: f64::NAN,
            pareto: false,
            reference: false,
            failure: None,
        }
    }

    /// "ref", "*" (Pareto-optimal), "failed" or "".
    pub fn front_mark(&self) -> &'static str {
        if self.reference {
            "ref"
        } else if self.pareto {
            "*"
        } else if self.failure.is_some() {
            "failed"
        } else {
            ""
        }
    }
}

/// The grid of a tradeoff study.
pub fn grid(integrations: &[String], cells: &[usize], factors: &[f64]) -> Vec<Config> {
    let mut out = vec![];
    for i in integrations {
        for &n in cells {
            for &f in factors {
                out.push(Config {
                    integration: i.clone(),
                    cells: n,
                    factor: f,
                });
            }
        }
    }
    out
}

/// Refuses a scene whose mesh is a Gmsh file: `flag` (`--cells`, `--sizes`) sets the cells of a
/// box mesh, and a file's resolution is fixed.
pub fn require_box_mesh(scene: &Scene, flag: &str) -> Result<(), SceneError> {
    let doc: toml::Table = scene.resolved.parse().unwrap_or_default();
    match doc.get("mesh").and_then(|m| m.get("file")) {
        Some(file) => Err(SceneError::Invalid {
            file: scene.file.clone(),
            key: "mesh.file".into(),
            value: file.to_string(),
            reason: format!(
                "{flag} needs a box mesh (`mesh.size` and `mesh.cells`): this scene reads its \
                 mesh from a Gmsh file, whose resolution {flag} cannot change"
            ),
        }),
        None => Ok(()),
    }
}

/// The `--set` overrides that turn the scene into configuration `c` (cells scaled so the
/// longest side has `c.cells`). A scene with a mesh file is refused ([`require_box_mesh`]).
pub fn overrides(scene: &Path, c: &Config, extra: &[String]) -> Result<Vec<String>, SceneError> {
    let base = load_scene(scene, extra)?;
    require_box_mesh(&base, "--cells")?;
    let doc: toml::Table = base.resolved.parse().unwrap_or_default();
    let cells: Vec<f64> = doc
        .get("mesh")
        .and_then(|m| m.get("cells"))
        .and_then(|c| c.as_array())
        .map(|a| {
            a.iter()
                .filter_map(|v| v.as_integer())
                .map(|v| v as f64)
                .collect()
        })
        .unwrap_or_else(|| vec![1.0; 3]);
    let max = cells.iter().cloned().fold(1.0, f64::max);
    let scaled: Vec<String> = cells
        .iter()
        .map(|&v| {
            ((v * c.cells as f64 / max).round() as i64)
                .max(1)
                .to_string()
        })
        .collect();
    let mut set = extra.to_vec();
    set.push(format!("mesh.cells=[{}]", scaled.join(",")));
    set.push(format!("scheme.time_step_factor={}", c.factor));
    set.push(format!("scheme.integration=\"{}\"", c.integration));
    Ok(set)
}

/// `on_step` as the run driver's progress.
struct OnStep<'a>(&'a mut dyn FnMut(&Simulation));

impl Progress for OnStep<'_> {
    fn step(&mut self, sim: &Simulation) {
        (self.0)(sim)
    }
}

/// Runs one configuration through the run driver without outputs, calling
/// `on_step` after every step (progress).
pub fn run(
    scene: &Path,
    c: &Config,
    extra: &[String],
    on_step: &mut dyn FnMut(&Simulation),
) -> Result<Row, SceneError> {
    let set = overrides(scene, c, extra)?;
    let s = load_scene(scene, &set)?;
    let elements = s.model.mesh.elements.len();
    let mut row = Row::new(c.clone(), elements);
    let mut sim = match Simulation::new(s.model) {
        Ok(sim) => sim,
        Err(e) => {
            row.failure = Some(e.to_string());
            return Ok(row);
        }
    };
    let t = Instant::now();
    let outcome = match Driver::with_outputs(vec![], Cadence::Default, &sim, t) {
        Ok(driver) => {
            let never = AtomicBool::new(false);
            driver.run(&mut sim, &never, &mut OnStep(on_step)).outcome
        }
        // No output: nothing can fail here.
        Err(e) => {
            row.failure = Some(e.to_string());
            return Ok(row);
        }
    };
    row.wall_seconds = t.elapsed().as_secs_f64();
    row.steps = sim.state.step_count;
    row.ns_per_element_step =
        1e9 * row.wall_seconds / (sim.state.step_count.max(1) as f64 * elements as f64);
    row.peak_force = sim.stats.peaks.first().map(|p| p.force);
    row.time_first_damage = sim.stats.time_first_damage;
    row.time_full_rupture = sim.stats.time_full_rupture;
    row.damage_dissipated = sim.state.ledger.damage_dissipated;
    row.max_relative_residual = sim.state.ledger.max_relative_residual;
    row.failure = outcome.err().map(|e| e.to_string());
    Ok(row)
}

fn rel(x: Option<f64>, r: Option<f64>) -> Option<f64> {
    match (x, r) {
        (Some(x), Some(r)) if r != 0.0 => Some(((x - r) / r).abs()),
        _ => None,
    }
}

/// Picks the reference (most cells, then smallest factor, full before reduced, among runs
/// that completed), fills the errors and marks the Pareto front of (wall time, error).
pub fn compare(rows: &mut [Row]) {
    let reference = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.failure.is_none())
        .max_by(|(_, a), (_, b)| {
            (
                a.config.cells,
                -a.config.factor,
                a.config.integration == "full",
            )
                .partial_cmp(&(
                    b.config.cells,
                    -b.config.factor,
                    b.config.integration == "full",
                ))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .map(|(i, _)| i);
    let Some(ri) = reference else {
        return;
    };
    let r = rows[ri].clone();
    for row in rows.iter_mut() {
        row.reference = false;
        row.error_peak_force = rel(row.peak_force, r.peak_force);
        row.error_first_damage = rel(row.time_first_damage, r.time_first_damage);
        row.error_full_rupture = rel(row.time_full_rupture, r.time_full_rupture);
        row.error_dissipated = rel(Some(row.damage_dissipated), Some(r.damage_dissipated));
        let errs = [
            row.error_peak_force,
            row.error_first_damage,
            row.error_full_rupture,
            row.error_dissipated,
        ];
        row.error = if row.failure.is_some() {
            f64::INFINITY
        } else {
            errs.iter().flatten().cloned().fold(0.0, f64::max)
        };
    }
    rows[ri].reference = true;
    for i in 0..rows.len() {
        let (w, e) = (rows[i].wall_seconds, rows[i].error);
        rows[i].pareto = rows[i].failure.is_none()
            && !rows.iter().enumerate().any(|(j, o)| {
                j != i
                    && o.failure.is_none()
                    && o.wall_seconds <= w
                    && o.error <= e
                    && (o.wall_seconds < w || o.error < e)
            });
    }
}

/// Observed orders of the dissipation error in the time step (`by_factor`) or in the element
/// size: within each group of completed rows of one quadrature that differ only in that
/// parameter, the finest row is the local reference, eᵢ = |Dᵢ − D_ref|/D_ref, and between
/// successive rows p = ln(eᵢ/eᵢ₊₁)/ln(sᵢ/sᵢ₊₁), s = h/h_crit or 1/cells. Needs three rows per
/// group. Returns (label, order) pairs.
pub fn orders(rows: &[Row], by_factor: bool) -> Vec<(String, f64)> {
    let mut groups: std::collections::BTreeMap<(String, String), Vec<&Row>> = Default::default();
    for r in rows.iter().filter(|r| r.failure.is_none()) {
        let other = if by_factor {
            format!("{}³", r.config.cells)
        } else {
            format!("h/h_crit {}", r.config.factor)
        };
        groups
            .entry((r.config.integration.clone(), other))
            .or_default()
            .push(r);
    }
    let size = |r: &Row| {
        if by_factor {
            r.config.factor
        } else {
            1.0 / r.config.cells as f64
        }
    };
    let mut out = vec![];
    for ((rule, other), mut g) in groups {
        if g.len() < 3 {
            continue;
        }
        g.sort_by(|a, b| size(b).total_cmp(&size(a)));
        let d_ref = g[g.len() - 1].damage_dissipated;
        let e: Vec<f64> = g
            .iter()
            .map(|r| ((r.damage_dissipated - d_ref) / d_ref).abs())
            .collect();
        for i in 0..g.len() - 2 {
            if e[i] > 0.0 && e[i + 1] > 0.0 {
                let label = if by_factor {
                    format!(
                        "{rule} {other}: h/h_crit {} → {}",
                        g[i].config.factor,
                        g[i + 1].config.factor
                    )
                } else {
                    format!(
                        "{rule} {other}: {}³ → {}³",
                        g[i].config.cells,
                        g[i + 1].config.cells
                    )
                };
                out.push((
                    label,
                    (e[i] / e[i + 1]).ln() / (size(g[i]) / size(g[i + 1])).ln(),
                ));
            }
        }
    }
    out
}

/// The rows as a fixed-width text table (`*` Pareto-optimal, `ref` the reference), followed by
/// the observed orders in the time step and in the mesh size.
pub fn table(rows: &[Row]) -> String {
    let mut s = format!(
        "{:>8} {:>5} {:>6} {:>8} {:>7} {:>9} {:>8} {:>11} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}  front\n",
        "rule",
        "cells",
        "h/hc",
        "elements",
        "steps",
        "wall s",
        "ns/el-st",
        "peak N",
        "t_damage",
        "t_rupture",
        "D J",
        "residual",
        "err D",
        "error"
    );
    let o = |v: Option<f64>, p: usize| v.map_or("—".to_string(), |v| format!("{v:.p$e}"));
    for r in rows {
        s.push_str(&format!(
            "{:>8} {:>5} {:>6} {:>8} {:>7} {:>9.3} {:>8.1} {:>11} {:>10} {:>10} {:>10.4e} {:>10.2e} {:>9} {:>9.2e}  {}\n",
            r.config.integration,
            r.config.cells,
            r.config.factor,
            r.elements,
            r.steps,
            r.wall_seconds,
            r.ns_per_element_step,
            o(r.peak_force, 4),
            o(r.time_first_damage, 4),
            o(r.time_full_rupture, 4),
            r.damage_dissipated,
            r.max_relative_residual,
            o(r.error_dissipated, 2),
            r.error,
            r.front_mark()
        ));
    }
    for (name, by) in [("time step", true), ("mesh size", false)] {
        let ord = orders(rows, by);
        if !ord.is_empty() {
            s.push_str(&format!(
                "observed order of the dissipation error in {name} (local reference: the finest run of each series):\n"
            ));
            for (label, p) in ord {
                s.push_str(&format!("  {label}: {p:.2}\n"));
            }
        }
    }
    s
}

/// The rows as CSV.
pub fn csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "integration,cells,factor,elements,steps,wall_s,ns_per_element_step,peak_force_N,\
         time_first_damage_s,time_full_rupture_s,damage_dissipated_J,max_relative_residual,\
         error_peak_force,error_first_damage,error_full_rupture,error_dissipated,error,pareto,\
         reference,failure\n",
    );
    let o = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
    for r in rows {
        s.push_str(&format!(
            "{},{},{},{},{},{:.6},{:.2},{},{},{},{:e},{:e},{},{},{},{},{:e},{},{},\"{}\"\n",
            r.config.integration,
            r.config.cells,
            r.config.factor,
            r.elements,
            r.steps,
            r.wall_seconds,
            r.ns_per_element_step,
            o(r.peak_force),
            o(r.time_first_damage),
            o(r.time_full_rupture),
            r.damage_dissipated,
            r.max_relative_residual,
            o(r.error_peak_force),
            o(r.error_first_damage),
            o(r.error_full_rupture),
            o(r.error_dissipated),
            r.error,
            r.pareto,
            r.reference,
            r.failure.clone().unwrap_or_default().replace('"', "'"),
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(i: &str, cells: usize, factor: f64, wall: f64, d: f64) -> Row {
        let config = Config {
            integration: i.into(),
            cells,
            factor,
        };
        Row {
            steps: 1,
            wall_seconds: wall,
            damage_dissipated: d,
            ..Row::new(config, cells * cells * cells)
        }
    }

    /// Reference = finest full row; a row slower and less accurate than another is not on
    /// the front; a second-order sequence gives order 2.
    #[test]
    fn reference_pareto_and_orders() {
        // D(h) = 100 + 1000 h²: errors vs the reference at h = 0.125.
        let d = |f: f64| 100.0 + 1000.0 * f * f;
        let mut rows = vec![
            row("full", 8, 0.5, 1.0, d(0.5)),
            row("full", 8, 0.25, 2.0, d(0.25)),
            row("full", 8, 0.125, 4.0, d(0.125)),
            row("reduced", 8, 0.5, 3.0, d(0.5) * 1.5),
        ];
        compare(&mut rows);
        assert!(rows[2].reference && rows[2].error == 0.0);
        assert!(rows[0].pareto && rows[1].pareto && rows[2].pareto);
        assert!(!rows[3].pareto, "slower and worse than row 0");
        // Local reference D(0.125): e(0.5) ∝ 0.25 − 0.015625, e(0.25) ∝ 0.0625 − 0.015625.
        let o = orders(&rows, true);
        assert_eq!(o.len(), 1, "{o:?}");
        let expect: f64 = ((0.25 - 0.015625) / (0.0625 - 0.015625_f64)).ln() / 2f64.ln();
        assert!((o[0].1 - expect).abs() < 1e-12);
    }
}
