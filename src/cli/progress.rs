//! Progress of a run measured in simulated time, for every command that shows it (`run`, the
//! runs of `sweep` and `tradeoff`): the bars' position is the per-mille of the end time reached
//! and the simulated time is shown against the end time, so a bar reaches its end exactly when
//! the run does, however the time step changes on the way (a count of steps estimated from the
//! first step does not: the pull-off's step grows once the glue has torn). Off a terminal `run`
//! prints a line at each tenth of the end time, the last one at the end.

use crate::solver::Simulation;
use indicatif::{ProgressBar, ProgressStyle};

/// The length of a run's bar: its position is in per-mille of the end time.
pub const PER_MILLE: u64 = 1000;

/// The per-mille of the end time that `sim` has reached, rounded down: [`PER_MILLE`] once the
/// run is finished ([`Simulation::finished`], the driver's own test), and never before.
pub fn per_mille(sim: &Simulation) -> u64 {
    if sim.finished() {
        return PER_MILLE;
    }
    let fraction = sim.state.time / sim.model.end_time;
    if fraction.is_nan() || fraction <= 0.0 {
        return 0;
    }
    ((fraction * PER_MILLE as f64).floor() as u64).min(PER_MILLE - 1)
}

/// `t` against the end time `end` [s], both in the unit that suits `end` (s, ms, µs, ns), e.g.
/// `12.3 ms / 330.0 ms`.
pub fn sim_time(t: f64, end: f64) -> String {
    let (scale, unit) = [(1.0, "s"), (1e-3, "ms"), (1e-6, "µs")]
        .into_iter()
        .find(|(scale, _)| end >= *scale)
        .unwrap_or((1e-9, "ns"));
    let e = end / scale;
    let decimals = if e >= 100.0 {
        1
    } else if e >= 10.0 {
        2
    } else {
        3
    };
    format!("{:.decimals$} {unit} / {e:.decimals$} {unit}", t / scale)
}

/// A bar of `PER_MILLE` positions with `template` (which should show `{percent}` and `{msg}`).
pub fn time_bar(template: &str) -> ProgressBar {
    let bar = ProgressBar::new(PER_MILLE);
    bar.set_style(ProgressStyle::with_template(template).expect("static template"));
    bar
}

/// The tenths of the end time reached, for the plain lines off a terminal: a new line is due
/// when this is above the last one printed.
pub fn tenths(sim: &Simulation) -> u64 {
    per_mille(sim) / (PER_MILLE / 10)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit follows the end time; the time and the end time share it.
    #[test]
    fn simulated_time_is_shown_against_the_end_time() {
        assert_eq!(sim_time(0.0123, 0.05), "12.30 ms / 50.00 ms");
        assert_eq!(sim_time(0.0123, 0.33), "12.3 ms / 330.0 ms");
        assert_eq!(sim_time(1.5, 12.0), "1.50 s / 12.00 s");
        assert_eq!(sim_time(2e-6, 5e-6), "2.000 µs / 5.000 µs");
    }
}
