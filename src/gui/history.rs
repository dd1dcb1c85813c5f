//! The explorer's run history: one row per run (finished, failed or stopped), built from the
//! run driver's result, and its CSV export.

use super::Settings;
use crate::driver::Finished;
use crate::output::OutputError;
use crate::solver::{SolverError, StateCounts};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

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
        }
    }

    /// The row of a run that went through the driver. The error is the first output's, else
    /// the solver's (none for a run stopped by the user); a run that completed with an output
    /// error counts as failed.
    pub fn from_run(
        id: u32,
        settings: &Settings,
        done: &Finished,
        recording: Option<String>,
    ) -> HistoryRow {
        let summary = &done.summary;
        let error = match (&done.outcome, &done.output_error) {
            (_, Some(e)) => Some(output_error_text(e)),
            (Err(SolverError::Cancelled { .. }), None) => None,
            (Err(e), None) => Some(e.to_string()),
            (Ok(()), None) => None,
        };
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
            paraview: summary.paraview.as_ref().map(|p| p.pvd.clone()),
        }
    }
}

/// An output's error as the history shows it, naming the output.
pub fn output_error_text(e: &OutputError) -> String {
    match e {
        OutputError::Recording(e) => format!("recording: {e}"),
        OutputError::Paraview(e) => format!("ParaView files: {e}"),
    }
}

/// The history as CSV: a header, then one line per run.
pub fn csv(rows: &[HistoryRow]) -> String {
    let mut s = String::from(
        "id,scene,family,g_n0_Pa_per_m,alpha_e_m,u_r_m,mu_inf,cells,time_step_factor,end_time_s,material,integration,\
         status,steps,simulated_time_s,time_first_damage_s,time_full_rupture_s,peak_force_N,\
         damage_dissipated_J,max_relative_residual,elastic,transition,ruptured,wall_s,recording,paraview,error\n",
    );
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
    let quote = |v: &str| format!("\"{}\"", v.replace('"', "\"\""));
    for r in rows {
        let st = &r.settings;
        let knots = st.law.knots();
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:e},{},{},{},{:e},{:e},{},{},{},{:.3},{},{},{}\n",
            r.id,
            quote(&st.scene),
            st.law.family,
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
            r.wall_seconds,
            quote(r.recording.as_deref().unwrap_or("")),
            quote(r.paraview.as_deref().unwrap_or("")),
            quote(r.error.as_deref().unwrap_or("")),
        ));
    }
    s
}

/// Writes the history as CSV to `path` (its folder created if needed).
pub fn export_csv(rows: &[HistoryRow], path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, csv(rows)).map_err(|e| format!("{}: {e}", path.display()))
}
