//! The explorer's run history: one row per run (finished, failed or stopped), built from the
//! run driver's result, with the run's curves over time ([`RunCurve`], decimated to a bounded
//! size) for the comparison of runs, the parameters that tell selected runs apart, and the CSV
//! export.

use super::Settings;
#[cfg(not(target_arch = "wasm32"))]
use crate::driver::Finished;
#[cfg(not(target_arch = "wasm32"))]
use crate::output::OutputError;
use crate::report::RunSummary;
#[cfg(not(target_arch = "wasm32"))]
use crate::solver::SolverError;
use crate::solver::StateCounts;
use serde::{Deserialize, Serialize};
#[cfg(not(target_arch = "wasm32"))]
use std::path::Path;
use web_time::Instant;

/// One finished (or failed, or stopped) run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct HistoryRow {
    pub id: u32,
    pub settings: Settings,
    /// "completed", "failed" or "cancelled".
    pub status: String,
    pub error: Option<String>,
    pub steps: u64,
    pub simulated_time: f64,
    pub time_full_rupture: Option<f64>,
    pub time_first_damage: Option<f64>,
    /// Largest |reaction| of the first prescribed displacement [N].
    pub peak_force: Option<f64>,
    pub damage_dissipated: f64,
    pub max_relative_residual: f64,
    pub counts: StateCounts,
    pub interface_nodes: usize,
    pub wall_seconds: f64,
    /// Where the recording went.
    pub recording: Option<String>,
    /// The ParaView index (`.pvd`) of the run's files, when written.
    #[serde(default)]
    pub paraview: Option<String>,
    /// The run's curves over time (empty for rows saved before they were kept).
    #[serde(default)]
    pub curve: RunCurve,
    /// The run's summary as `decohesion run --summary` writes it (JSON), for *save summary*;
    /// kept for the runs of this session only.
    #[serde(skip)]
    pub summary_json: Option<String>,
}

/// One sample of a run, taken by the solver thread.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CurvePoint {
    /// Simulated time [s].
    pub t: f64,
    pub counts: StateCounts,
    /// Balance residual / largest energy so far (NaN at the end sample, which has none).
    pub residual: f64,
    /// Mean damage α over the interface nodes [m] (NaN without an interface).
    pub mean_alpha: f64,
    /// Imposed displacement of the first prescribed condition [m] (NaN without one).
    pub displacement: f64,
    /// Its reaction [N] (NaN without one).
    pub reaction: f64,
    /// The magnitude of the reaction on the first prescribed displacement's faces, every
    /// component prescribed there [N] (NaN without one; a pull along a slant prescribes two).
    #[serde(default = "nan")]
    pub force: f64,
}

fn nan() -> f64 {
    f64::NAN
}

impl CurvePoint {
    /// The sample of `sim` now.
    pub fn of(sim: &crate::solver::Simulation) -> CurvePoint {
        let nodes = &sim.state.interface_nodes;
        let mean_alpha = if nodes.is_empty() {
            f64::NAN
        } else {
            nodes.iter().map(|n| n.alpha).sum::<f64>() / nodes.len() as f64
        };
        let first = sim.model.displacements.first();
        CurvePoint {
            t: sim.state.time,
            counts: sim.state_counts(),
            residual: sim.state.ledger.relative_residual(),
            mean_alpha,
            displacement: first.map_or(f64::NAN, |d| d.history.value(sim.state.time)[0]),
            reaction: sim.stats.reactions.first().copied().unwrap_or(f64::NAN),
            force: first.map_or(f64::NAN, |d| {
                let mut f = [0.0; 3];
                for (c, r) in sim.model.displacements.iter().zip(&sim.stats.reactions) {
                    if c.faces == d.faces {
                        f[c.component] += r;
                    }
                }
                (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt()
            }),
        }
    }
}

pub use crate::tunables::CURVE_MAX_POINTS;

/// A run's samples, bounded: every `stride`-th sample offered is kept; when more than
/// [`CURVE_MAX_POINTS`] are kept, every other one is dropped and the stride doubles, so a run
/// of any length keeps between half and all of the bound, evenly spread over the samples, plus
/// its last one.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RunCurve {
    pub points: Vec<CurvePoint>,
    /// Samples offered so far.
    seen: u64,
    /// Keep one sample in this many (0 = 1).
    stride: u64,
}

impl RunCurve {
    /// Offers the next sample.
    pub fn push(&mut self, p: CurvePoint) {
        let stride = self.stride.max(1);
        if self.seen.is_multiple_of(stride) {
            self.points.push(p);
            if self.points.len() > CURVE_MAX_POINTS {
                let mut k = 0;
                self.points.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride = 2 * stride;
            }
        }
        self.seen += 1;
    }

    /// The run's last sample, kept whatever the stride (it replaces a kept sample of the same
    /// time).
    pub fn finish(&mut self, p: CurvePoint) {
        if self.points.last().is_some_and(|q| q.t == p.t) {
            self.points.pop();
        }
        self.points.push(p);
        self.seen += 1;
    }

    pub fn clear(&mut self) {
        *self = RunCurve::default();
    }
}

/// What a run was run with, as (name, value shown, value compared): scene, law family and
/// every parameter of it, μ_inf, mesh, time step, end time, material, quadrature. A points
/// table is shown by its size and compared whole.
pub fn parameters(s: &Settings) -> Vec<(String, String, String)> {
    let same = |k: &str, v: String| (k.to_string(), v.clone(), v);
    let mut out = vec![
        same("scene", s.scene_stem()),
        same("law", s.law.family.clone()),
    ];
    for (k, v) in s.law.params().0 {
        out.push(match v {
            crate::law::ParamValue::Number(x) => same(&k, format!("{x}")),
            crate::law::ParamValue::Points(p) => {
                (k, format!("{} points", p.len()), format!("{p:?}"))
            }
        });
    }
    out.extend([
        same("μ_inf", s.law.mu_inf.to_string()),
        same("cells", s.cells.to_string()),
        same("h/h_crit", s.factor.to_string()),
        same("end", format!("{} s", s.end_time)),
        same("material", s.material.clone()),
        same("integration", s.integration.clone()),
    ]);
    out
}

/// The legend label of each row: `run N` and the parameters whose values are not the same in
/// every row given.
pub fn legend_labels(rows: &[&HistoryRow]) -> Vec<String> {
    let params: Vec<_> = rows.iter().map(|r| parameters(&r.settings)).collect();
    let compared = |p: &[(String, String, String)], name: &str| {
        p.iter().find(|q| q.0 == name).map(|q| q.2.clone())
    };
    let differs = |name: &str| {
        let first = compared(&params[0], name);
        params.iter().any(|p| compared(p, name) != first)
    };
    rows.iter()
        .zip(&params)
        .map(|(r, p)| {
            let shown: Vec<String> = p
                .iter()
                .filter(|q| differs(&q.0))
                .map(|q| format!("{}={}", q.0, q.1))
                .collect();
            if shown.is_empty() {
                format!("run {}", r.id)
            } else {
                format!("run {}: {}", r.id, shown.join(", "))
            }
        })
        .collect()
}

impl HistoryRow {
    /// The row of a run that did not start (set-up failed) or whose thread panicked.
    pub fn failed(id: u32, settings: &Settings, error: String, started: Instant) -> HistoryRow {
        HistoryRow {
            id,
            settings: settings.clone(),
            status: "failed".into(),
            error: Some(error),
            steps: 0,
            simulated_time: 0.0,
            time_full_rupture: None,
            time_first_damage: None,
            peak_force: None,
            damage_dissipated: 0.0,
            max_relative_residual: 0.0,
            counts: StateCounts::default(),
            interface_nodes: 0,
            wall_seconds: started.elapsed().as_secs_f64(),
            recording: None,
            paraview: None,
            curve: RunCurve::default(),
            summary_json: None,
        }
    }

    /// The row of a run that went through the driver. The error is the first output's, else
    /// the solver's (none for a run stopped by the user); a run that completed with an output
    /// error counts as failed.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn from_run(
        id: u32,
        settings: &Settings,
        done: &Finished,
        recording: Option<String>,
    ) -> HistoryRow {
        let error = match (&done.outcome, &done.output_error) {
            (_, Some(e)) => Some(output_error_text(e)),
            (Err(SolverError::Cancelled { .. }), None) => None,
            (Err(e), None) => Some(e.to_string()),
            (Ok(()), None) => None,
        };
        HistoryRow::from_summary(id, settings, &done.summary, error, recording)
    }

    /// The row of a run that ended with `summary` (the thread's, through the driver, or the
    /// page's); `error` is what the row shows, `None` for a run completed or stopped by the
    /// user. A completed run with an error (an output's) counts as failed.
    pub fn from_summary(
        id: u32,
        settings: &Settings,
        summary: &RunSummary,
        error: Option<String>,
        recording: Option<String>,
    ) -> HistoryRow {
        HistoryRow {
            id,
            settings: settings.clone(),
            status: if error.is_some() && summary.status == "completed" {
                "failed".into()
            } else {
                summary.status.clone()
            },
            error,
            steps: summary.steps,
            simulated_time: summary.simulated_time,
            time_full_rupture: summary.time_full_rupture,
            time_first_damage: summary.time_first_damage,
            peak_force: summary.peak_reactions.first().map(|p| p.force),
            damage_dissipated: summary.energies.damage_dissipated,
            max_relative_residual: summary.max_relative_residual,
            counts: summary.final_counts,
            interface_nodes: summary.interface_nodes,
            wall_seconds: summary.wall_seconds,
            recording,
            #[cfg(not(target_arch = "wasm32"))]
            paraview: (summary.outputs.get("paraview"))
                .and_then(|p| p.get("pvd")?.as_str().map(str::to_string)),
            #[cfg(target_arch = "wasm32")]
            paraview: None,
            curve: RunCurve::default(),
            summary_json: serde_json::to_string_pretty(summary).ok(),
        }
    }
}

/// An output's error as the history shows it: what the run was doing, in the command line's
/// words ("starting the recording", "ParaView output", …), then the error.
#[cfg(not(target_arch = "wasm32"))]
pub fn output_error_text(e: &OutputError) -> String {
    e.with_context()
}

/// The history as CSV: a header, then one line per run.
pub fn csv(rows: &[HistoryRow]) -> String {
    let mut s = String::from(
        "id,scene,family,interface,g_n0_Pa_per_m,alpha_e_m,u_r_m,mu_inf,cells,time_step_factor,end_time_s,material,integration,\
         status,steps,simulated_time_s,time_first_damage_s,time_full_rupture_s,peak_force_N,\
         damage_dissipated_J,max_relative_residual,elastic,transition,ruptured,unformed,wall_s,recording,paraview,error\n",
    );
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
    let quote = |v: &str| format!("\"{}\"", v.replace('"', "\"\""));
    for r in rows {
        let st = &r.settings;
        let knots = st.law.knots();
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:e},{},{},{},{:e},{:e},{},{},{},{},{:.3},{},{},{}\n",
            r.id,
            quote(&st.scene),
            st.law.family,
            quote(&st.interface_label()),
            opt(knots.map(|k| k.g_n0)),
            opt(knots.map(|k| k.alpha_e)),
            opt(knots.map(|k| k.u_r)),
            st.law.mu_inf,
            st.cells,
            st.factor,
            st.end_time,
            st.material,
            st.integration,
            r.status,
            r.steps,
            r.simulated_time,
            opt(r.time_first_damage),
            opt(r.time_full_rupture),
            opt(r.peak_force),
            r.damage_dissipated,
            r.max_relative_residual,
            r.counts.elastic,
            r.counts.transition,
            r.counts.ruptured,
            r.counts.unformed,
            r.wall_seconds,
            quote(r.recording.as_deref().unwrap_or("")),
            quote(r.paraview.as_deref().unwrap_or("")),
            quote(r.error.as_deref().unwrap_or("")),
        ));
    }
    s
}

/// The runs' curves as CSV, one line per kept sample of every run ([`RunCurve`]), in the
/// units of the header: the run's id (the `id` of [`csv`]), simulated time, the imposed
/// displacement of the first prescribed condition and its reaction (the force curve), mean
/// damage α, the node counts by state and the balance residual. Empty fields where a value is
/// NaN (no prescribed condition, no interface, the end sample's residual).
pub fn curves_csv(rows: &[HistoryRow]) -> String {
    let mut s = String::from(
        "run,t_s,displacement_m,reaction_N,mean_alpha_m,elastic,transition,ruptured,unformed,\
         relative_residual\n",
    );
    let num = |v: f64| {
        if v.is_nan() {
            String::new()
        } else {
            format!("{v:e}")
        }
    };
    for r in rows {
        for p in &r.curve.points {
            s.push_str(&format!(
                "{},{:e},{},{},{},{},{},{},{},{}\n",
                r.id,
                p.t,
                num(p.displacement),
                num(p.reaction),
                num(p.mean_alpha),
                p.counts.elastic,
                p.counts.transition,
                p.counts.ruptured,
                p.counts.unformed,
                num(p.residual),
            ));
        }
    }
    s
}

/// Writes the history as CSV to `path` (its folder created if needed).
#[cfg(not(target_arch = "wasm32"))]
pub fn export_csv(rows: &[HistoryRow], path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, csv(rows)).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(t: f64) -> CurvePoint {
        CurvePoint {
            t,
            counts: StateCounts::default(),
            residual: 0.0,
            mean_alpha: 0.0,
            displacement: t,
            reaction: 0.0,
            force: 0.0,
        }
    }

    /// 100 000 samples keep between half and all of the bound, evenly spaced (one sample in a
    /// power of two), from the first, plus the last; a short run keeps every sample.
    #[test]
    fn curves_are_bounded_and_evenly_decimated() {
        let mut c = RunCurve::default();
        for k in 0..100_000 {
            c.push(point(k as f64));
        }
        c.finish(point(100_000.0));
        let n = c.points.len() - 1;
        assert!(
            (CURVE_MAX_POINTS / 2..=CURVE_MAX_POINTS).contains(&n),
            "{n}"
        );
        let step = c.points[1].t - c.points[0].t;
        assert_eq!(c.points[0].t, 0.0);
        assert!(step.log2().fract() == 0.0, "stride {step}");
        for w in c.points[..n].windows(2) {
            assert_eq!(w[1].t - w[0].t, step);
        }
        assert_eq!(c.points[n].t, 100_000.0);
        let mut short = RunCurve::default();
        for k in 0..10 {
            short.push(point(k as f64));
        }
        short.finish(point(9.0));
        assert_eq!(
            short.points.len(),
            10,
            "the end sample replaces the same time"
        );
    }

    fn row(id: u32, settings: Settings) -> HistoryRow {
        HistoryRow::failed(id, &settings, String::new(), Instant::now())
    }

    /// The legend names the parameters that differ between the rows compared, and only them.
    #[test]
    fn legend_shows_what_differs() {
        let base = Settings::default();
        let mut other = base.clone();
        other.factor = 0.25;
        other.law.values.0.insert("u_r".into(), 0.006.into());
        let rows = [row(1, base.clone()), row(2, other), row(3, base)];
        let refs: Vec<&HistoryRow> = rows.iter().collect();
        let labels = legend_labels(&refs);
        assert!(labels[1].starts_with("run 2: "), "{}", labels[1]);
        assert!(labels[1].contains("u_r=0.006"), "{}", labels[1]);
        assert!(labels[1].contains("h/h_crit=0.25"), "{}", labels[1]);
        assert!(labels[0].contains("h/h_crit=0.5"), "{}", labels[0]);
        assert!(!labels[0].contains("scene"), "{}", labels[0]);
        assert_eq!(legend_labels(&[&rows[0], &rows[2]]), ["run 1", "run 3"]);
    }
}
