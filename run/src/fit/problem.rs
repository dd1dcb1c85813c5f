//! What one evaluation of the fit is: the scene run with the free keys set to a parameter
//! vector, its series column y read at the measured x, and the misfit.
//!
//! The misfit of a parameter vector p is the mean square of the relative residuals
//!
//!   c(p) = (1/m) Σᵢ rᵢ(p)²,   rᵢ(p) = (ŷ(xᵢ; p) − yᵢ) / max_k |y_k|,
//!
//! where ŷ(x; p) is the run's y column read at the measured xᵢ by linear interpolation in its
//! x column (non-decreasing over the run: a ramp, time). Runs are independent and
//! deterministic: the same p gives the same c(p) whatever the thread count.

use super::free::Free;
use crate::output::series::Columns;
use crate::scene::{parse_scene, Scene, SceneError};
use crate::solver::Simulation;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// A scene file's text, read once for all the runs of a fit, and the file's name (in messages,
/// and the directory the files it names are read from).
#[derive(Debug, Clone)]
pub struct SceneText {
    pub file: String,
    pub text: String,
}

impl SceneText {
    /// Reads the scene file at `path` (the error is [`crate::scene::load_scene`]'s).
    pub fn read(path: &Path) -> Result<SceneText, SceneError> {
        let file = path.display().to_string();
        match std::fs::read_to_string(path) {
            Ok(text) => Ok(SceneText { file, text }),
            Err(source) => Err(SceneError::Io { file, source }),
        }
    }

    /// The scene with the `--set` overrides `set`.
    pub fn load(&self, set: &[String]) -> Result<Scene, SceneError> {
        parse_scene(&self.text, &self.file, set)
    }
}

/// A column of the run's series named by the caller.
#[derive(Debug, Clone)]
pub struct Column {
    /// As given (`F_z_plus_z`, with or without its unit).
    pub key: String,
    /// The series column's full name, `F_z_plus_z [N]`.
    pub name: String,
    /// Its SI unit, `N`.
    pub unit: String,
}

/// The series column `key` names among `columns` (with or without the bracketed unit); the
/// error lists them all.
pub fn find_column(columns: &Columns, key: &str, flag: &str) -> Result<(usize, Column), String> {
    let key = key.trim();
    for (i, name) in columns.names.iter().enumerate() {
        let (bare, unit) = name
            .split_once(" [")
            .map(|(b, u)| (b, u.trim_end_matches(']')))
            .unwrap_or((name.as_str(), "-"));
        if key == name || key == bare {
            return Ok((
                i,
                Column {
                    key: key.to_string(),
                    name: name.clone(),
                    unit: unit.to_string(),
                },
            ));
        }
    }
    Err(format!(
        "{flag} {key}: no such column in the run's time series; the columns are: {}",
        columns
            .names
            .iter()
            .map(|n| n.split_once(" [").map_or(n.as_str(), |(b, _)| b))
            .collect::<Vec<_>>()
            .join(", ")
    ))
}

/// How one evaluation ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Evaluation {
    /// The run reached the measured range: ŷ at each measured x [SI] and the misfit c(p).
    Done { y: Vec<f64>, cost: f64 },
    /// The scene refused the values, the run failed (blow-up, diagnostic) or ended before the
    /// last measured x: the reason.
    Failed(String),
    /// Cancelled (Ctrl-C) before it ended.
    Cancelled,
}

impl Evaluation {
    /// The misfit the optimiser sees: a failed run is worse than any that completed
    /// ([`FAILED_COST`]).
    pub fn cost(&self) -> f64 {
        match self {
            Evaluation::Done { cost, .. } => *cost,
            _ => FAILED_COST,
        }
    }
}

/// The misfit given to a failed run and to a point outside the bounds: far above any misfit of a
/// completed run (c = 1 is a curve off by its own magnitude), finite so that the optimiser's
/// arithmetic stays finite.
pub const FAILED_COST: f64 = 1e100;

/// The fit's problem: the scene, the free keys, the measured points in SI units.
#[derive(Debug, Clone)]
pub struct Problem {
    pub scene: SceneText,
    /// The caller's `--set` overrides, applied before the free keys.
    pub set: Vec<String>,
    pub free: Vec<Free>,
    pub x: Column,
    pub y: Column,
    /// Measured x [SI], strictly increasing.
    pub xs: Vec<f64>,
    /// Measured y [SI].
    pub ys: Vec<f64>,
    /// max |yᵢ|, the scale of the relative residuals.
    pub y_scale: f64,
}

impl Problem {
    /// The `--set` overrides of the parameter vector `p` (in the free keys' units), after the
    /// caller's: each value printed as the shortest decimal that reads back to it, with a
    /// decimal point or an exponent (so that a key that takes only integers refuses it).
    pub fn overrides(&self, p: &[f64]) -> Vec<String> {
        let mut set = self.set.clone();
        set.extend(
            self.free
                .iter()
                .zip(p)
                .map(|(f, v)| format!("{}={v:?}", f.key)),
        );
        set
    }

    /// Loads the scene with the values `p`.
    pub fn scene(&self, p: &[f64]) -> Result<Scene, String> {
        (self.scene.load(&self.overrides(p))).map_err(|e| e.to_string())
    }

    /// Runs the scene with the values `p` on `threads` threads at most and compares it with the
    /// measured points; stops early when `cancel` is set.
    pub fn evaluate(&self, p: &[f64], threads: usize, cancel: &AtomicBool) -> Evaluation {
        match self.run_curve(p, threads, cancel) {
            Ok(Some((xs, ys))) => match interpolate(&xs, &ys, &self.xs, &self.x.name) {
                Ok(y) => {
                    let cost = self.misfit(&y);
                    Evaluation::Done { y, cost }
                }
                Err(e) => Evaluation::Failed(e),
            },
            Ok(None) => Evaluation::Cancelled,
            Err(e) => Evaluation::Failed(e),
        }
    }

    /// c = (1/m) Σ ((ŷᵢ − yᵢ)/y_scale)².
    pub fn misfit(&self, y: &[f64]) -> f64 {
        let m = self.ys.len() as f64;
        y.iter()
            .zip(&self.ys)
            .map(|(a, b)| ((a - b) / self.y_scale).powi(2))
            .sum::<f64>()
            / m
    }

    /// The relative residuals rᵢ of a completed evaluation's ŷ.
    pub fn residuals(&self, y: &[f64]) -> Vec<f64> {
        y.iter()
            .zip(&self.ys)
            .map(|(a, b)| (a - b) / self.y_scale)
            .collect()
    }

    /// The run's (x, y) columns at every step, or `None` when cancelled. The run stops once its
    /// x passes the last measured x (the rest cannot change the misfit) or at its end time.
    fn run_curve(
        &self,
        p: &[f64],
        threads: usize,
        cancel: &AtomicBool,
    ) -> Result<Option<RunCurve>, String> {
        let scene = self.scene(p)?;
        let mut sim = Simulation::new(scene.model.clone()).map_err(|e| e.to_string())?;
        if sim.threads() > threads {
            sim.use_threads(threads);
        }
        let columns = Columns::new(&sim);
        let (xi, _) = find_column(&columns, &self.x.key, "--x")?;
        let (yi, _) = find_column(&columns, &self.y.key, "--y")?;
        let last = *self.xs.last().expect("a curve has points");
        let (mut xs, mut ys, mut row) = (Vec::new(), Vec::new(), Vec::new());
        loop {
            columns.row(&sim, &mut row);
            xs.push(row[xi]);
            ys.push(row[yi]);
            if row[xi] > last || sim.finished() {
                return Ok(Some((xs, ys)));
            }
            if cancel.load(Ordering::SeqCst) {
                return Ok(None);
            }
            sim.step().map_err(|e| e.to_string())?;
        }
    }
}

/// A run's (x, y) columns at every step.
type RunCurve = (Vec<f64>, Vec<f64>);

/// ŷ at each of `at` (increasing) by linear interpolation in the run's curve (`xs`
/// non-decreasing up to the last point needed; where xs is flat, the latest y is taken).
/// Refused: x decreasing in the run, or a measured x beyond the run's last x.
pub fn interpolate(xs: &[f64], ys: &[f64], at: &[f64], x_name: &str) -> Result<Vec<f64>, String> {
    let mut out = Vec::with_capacity(at.len());
    let mut k = 0;
    for &x in at {
        if x < xs[0] {
            return Err(format!(
                "the measured x = {x:e} lies before the run's first {x_name} = {:e}",
                xs[0]
            ));
        }
        // The last k with xs[k] <= x.
        while k + 1 < xs.len() && xs[k + 1] <= x {
            if xs[k + 1] < xs[k] {
                return Err(format!(
                    "the run's {x_name} decreases (from {:e} to {:e} at row {}): the measured \
                     curve can only be read against a column that does not decrease, such as \
                     the imposed displacement of a ramp or t",
                    xs[k],
                    xs[k + 1],
                    k + 1
                ));
            }
            k += 1;
        }
        if k + 1 == xs.len() {
            if x > xs[k] {
                return Err(format!(
                    "the measured x = {x:e} lies beyond the run's last {x_name} = {:e}: \
                     lengthen end_time or the loading",
                    xs[k]
                ));
            }
            out.push(ys[k]);
        } else {
            let (x0, x1) = (xs[k], xs[k + 1]);
            let s = if x1 > x0 { (x - x0) / (x1 - x0) } else { 1.0 };
            out.push(ys[k] + s * (ys[k + 1] - ys[k]));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::interpolate;

    #[test]
    fn interpolates_linearly_and_refuses_what_cannot_be_read() {
        let xs = [0.0, 1.0, 1.0, 3.0];
        let ys = [0.0, 2.0, 4.0, 8.0];
        let y = interpolate(&xs, &ys, &[0.0, 0.5, 1.0, 2.0, 3.0], "u").unwrap();
        assert_eq!(y, [0.0, 1.0, 4.0, 6.0, 8.0]);
        let e = interpolate(&xs, &ys, &[3.5], "u").unwrap_err();
        assert!(e.contains("beyond the run's last u"), "{e}");
        let e = interpolate(&[0.0, 2.0, 1.0, 3.0], &ys, &[2.5], "u").unwrap_err();
        assert!(e.contains("decreases"), "{e}");
    }
}
