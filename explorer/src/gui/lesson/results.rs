//! What a step's question and plot name: the results of a run (and their values in a
//! history row) and the plots.

use crate::gui::history::HistoryRow;

/// A result of a run a question compares a prediction with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunResult {
    PeakForce,
    LateForce,
    Dissipated,
    FirstDamage,
    FullRupture,
    Ruptured,
}

/// Each result: (key in lesson files, its label, its unit, what it is).
pub const RESULTS: &[(RunResult, &str, &str, &str, &str)] = &[
    (
        RunResult::PeakForce,
        "peak_force",
        "peak force",
        "N",
        "the largest |reaction| of the first prescribed displacement until the glue has torn",
    ),
    (
        RunResult::LateForce,
        "late_force",
        "force over the last third",
        "N",
        "the magnitude of the reaction on the first prescribed displacement's faces (every \
         component prescribed there), averaged over time over the last third of the run",
    ),
    (
        RunResult::Dissipated,
        "dissipated_energy",
        "energy dissipated by damage",
        "J",
        "the glue's damage dissipation D at the end of the run",
    ),
    (
        RunResult::FirstDamage,
        "time_first_damage",
        "time of first damage",
        "s",
        "when the first glued node started to damage",
    ),
    (
        RunResult::FullRupture,
        "time_full_rupture",
        "time of full rupture",
        "s",
        "when the last glued node ruptured",
    ),
    (
        RunResult::Ruptured,
        "ruptured_nodes",
        "ruptured nodes",
        "",
        "the glued nodes ruptured at the end of the run",
    ),
];

impl RunResult {
    fn entry(
        self,
    ) -> &'static (
        RunResult,
        &'static str,
        &'static str,
        &'static str,
        &'static str,
    ) {
        RESULTS
            .iter()
            .find(|r| r.0 == self)
            .expect("every result is listed")
    }

    /// Its key in lesson files.
    pub fn key(self) -> &'static str {
        self.entry().1
    }

    /// What the explorer calls it.
    pub fn label(self) -> &'static str {
        self.entry().2
    }

    /// Its unit ("" for a count).
    pub fn unit(self) -> &'static str {
        self.entry().3
    }

    /// The result named `key`, or what is admissible.
    pub fn from_key(key: &str) -> Result<RunResult, String> {
        RESULTS
            .iter()
            .find(|r| r.1 == key)
            .map(|r| r.0)
            .ok_or_else(|| {
                let keys: Vec<&str> = RESULTS.iter().map(|r| r.1).collect();
                format!("unknown result `{key}`: admissible are {}", keys.join(", "))
            })
    }

    /// Its value in a finished run, if the run has one (a run that never ruptured has no time
    /// of full rupture).
    pub fn value(self, row: &HistoryRow) -> Option<f64> {
        match self {
            RunResult::PeakForce => row.peak_force.map(f64::abs),
            RunResult::LateForce => late_force(row),
            RunResult::Dissipated => Some(row.damage_dissipated),
            RunResult::FirstDamage => row.time_first_damage,
            RunResult::FullRupture => row.time_full_rupture,
            RunResult::Ruptured => Some(row.counts.ruptured as f64),
        }
        .filter(|v| v.is_finite())
    }
}

/// The time average (trapezoids over the samples, which need not be evenly spaced) of the
/// force on the pulled faces over the last third of the run.
fn late_force(row: &HistoryRow) -> Option<f64> {
    let from = row.simulated_time * 2.0 / 3.0;
    let points: Vec<[f64; 2]> = (row.curve.points.iter())
        .filter(|p| p.t >= from && p.force.is_finite())
        .map(|p| [p.t, p.force])
        .collect();
    let span = points.last()?[0] - points.first()?[0];
    if !(span > 0.0) {
        return None;
    }
    let area: f64 = (points.windows(2))
        .map(|w| 0.5 * (w[0][1] + w[1][1]) * (w[1][0] - w[0][0]))
        .sum();
    Some(area / span)
}

/// A plot a step may ask the student to look at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotName {
    Law,
    Traction,
    Friction,
    States,
    Force,
}

/// Each plot: (key in lesson files, the plot's title in the explorer).
pub const PLOTS: &[(PlotName, &str, &str)] = &[
    (PlotName::Law, "law", "stiffness g_N(α)"),
    (PlotName::Traction, "traction", "traction T(δ)"),
    (PlotName::Friction, "friction", "friction μ(α)"),
    (PlotName::States, "states", "interface nodes by state"),
    (PlotName::Force, "force", "force on the pulled faces"),
];

impl PlotName {
    /// Its key in lesson files.
    pub fn key(self) -> &'static str {
        PLOTS.iter().find(|p| p.0 == self).map_or("", |p| p.1)
    }

    /// The title of the plot in the explorer.
    pub fn title(self) -> &'static str {
        PLOTS.iter().find(|p| p.0 == self).map_or("", |p| p.2)
    }

    pub(super) fn from_key(key: &str) -> Result<PlotName, String> {
        PLOTS
            .iter()
            .find(|p| p.1 == key)
            .map(|p| p.0)
            .ok_or_else(|| {
                let keys: Vec<&str> = PLOTS.iter().map(|p| p.1).collect();
                format!("unknown plot `{key}`: admissible are {}", keys.join(", "))
            })
    }
}
