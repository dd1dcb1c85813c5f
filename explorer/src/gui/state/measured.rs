//! A measured curve in the explorer ([`crate::measured`]: a CSV file of x and y with their
//! units), drawn over the compared runs' reaction against imposed displacement; natively, the
//! edited law's number parameters fitted to it: `decohesion fit`'s search ([`crate::fit`]) on
//! the edited scene, run on a thread, its best values taken back into the editor.

use super::App;
use crate::measured::Curve;
use std::path::PathBuf;
#[cfg(not(target_arch = "wasm32"))]
use {
    crate::fit::{FitArgs, FitReport, Record, Watch},
    crate::interface::family::{ParamKind, ParamValue},
    std::collections::BTreeMap,
    std::sync::atomic::{AtomicBool, Ordering},
    std::sync::{Arc, Mutex},
    std::thread::JoinHandle,
};

/// A loaded measured curve.
#[derive(Debug, Clone)]
pub struct Measured {
    pub curve: Curve,
    /// The file it was read from; `None` for a file dropped on the page (which has no files: it
    /// cannot be fitted there).
    pub path: Option<PathBuf>,
    /// The points in SI units, x [m] and y [N], for the reaction plot; or why they cannot be
    /// drawn there (the columns are not a length and a force).
    pub si: Result<Vec<[f64; 2]>, String>,
}

impl Measured {
    /// The curve of the CSV text `text` of the file named `file` (refused with the file and
    /// line, as `decohesion fit` refuses it).
    pub fn parse(text: &str, file: &str, path: Option<PathBuf>) -> Result<Measured, String> {
        let curve = Curve::parse(text, file).map_err(|e| e.to_string())?;
        curve
            .require_points(2, "to draw a curve")
            .map_err(|e| e.to_string())?;
        let units = || -> anyhow::Result<Vec<[f64; 2]>> {
            let (x, _) = curve.unit(&curve.x_header, None, "", "m")?;
            let (y, _) = curve.unit(&curve.y_header, None, "", "N")?;
            Ok((curve.x.iter().zip(&curve.y))
                .map(|(a, b)| [a * x.factor, b * y.factor])
                .collect())
        };
        let si = units().map_err(|e| {
            format!("not drawn over the reaction against displacement (a length and a force): {e}")
        });
        Ok(Measured { curve, path, si })
    }
}

impl App {
    /// Loads the measured curve of the CSV text `text` (a file dropped on the window, or read
    /// from `path`); a refused file leaves the current curve and says why in the notes.
    pub fn load_measured_text(&mut self, text: &str, file: &str, path: Option<PathBuf>) {
        match Measured::parse(text, file, path) {
            Ok(m) => {
                self.measured = Some(m);
                #[cfg(not(target_arch = "wasm32"))]
                self.fit_defaults();
            }
            Err(e) => self.notes.push(e),
        }
    }

    /// Reads and loads the measured curve at `path` ([`App::load_measured_text`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn load_measured(&mut self, path: &str) {
        match std::fs::read_to_string(path) {
            Ok(text) => {
                self.measured_path = path.to_string();
                self.load_measured_text(&text, path, Some(PathBuf::from(path)))
            }
            Err(e) => self
                .notes
                .push(format!("{path}: cannot read the measured curve: {e}")),
        }
    }
}

/// A number parameter of the edited law, free or not in the fit, and its bounds.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeKey {
    pub on: bool,
    pub lo: f64,
    pub hi: f64,
}

/// What a running fit has done: runs ended and the best misfit so far.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug, Clone, Copy, Default)]
pub struct FitProgress {
    pub runs: usize,
    pub best: Option<f64>,
}

/// A fit running on its thread.
#[cfg(not(target_arch = "wasm32"))]
pub struct FitJob {
    cancel: Arc<AtomicBool>,
    pub progress: Arc<Mutex<FitProgress>>,
    handle: JoinHandle<Result<FitReport, String>>,
    /// The family and interface fitted: the values go back only to the same law.
    family: String,
    interface: usize,
}

/// A fit's end: its report or why it failed, and the law it fitted.
#[cfg(not(target_arch = "wasm32"))]
pub struct FitOutcome {
    pub report: Result<FitReport, String>,
    pub family: String,
    pub interface: usize,
}

/// The fit's settings and its job (native: the page has no threads and no files).
#[cfg(not(target_arch = "wasm32"))]
pub struct FitPanel {
    /// By parameter key of the edited family.
    pub free: BTreeMap<String, FreeKey>,
    /// The series columns compared with the measured x and y (`u_z_plus_z`, `F_z_plus_z`).
    pub x_column: String,
    pub y_column: String,
    pub max_evals: usize,
    pub job: Option<FitJob>,
    pub outcome: Option<FitOutcome>,
}

#[cfg(not(target_arch = "wasm32"))]
impl Default for FitPanel {
    fn default() -> Self {
        FitPanel {
            free: BTreeMap::new(),
            x_column: String::new(),
            y_column: String::new(),
            max_evals: 200,
            job: None,
            outcome: None,
        }
    }
}

/// Tells the window of each run of the fit.
#[cfg(not(target_arch = "wasm32"))]
struct Progress {
    shared: Arc<Mutex<FitProgress>>,
    repaint: Option<super::Repaint>,
}

#[cfg(not(target_arch = "wasm32"))]
impl Watch for Progress {
    fn evaluated(&mut self, _: &Record, best: Option<&Record>) {
        if let Ok(mut p) = self.shared.lock() {
            p.runs += 1;
            p.best = best.and_then(|b| b.cost);
        }
        if let Some(r) = &self.repaint {
            r();
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl App {
    /// The fit's defaults for the edited law and scene: every number parameter listed (not
    /// free) between half and twice its value, the columns of the scene's first prescribed
    /// displacement (its imposed displacement and reaction), kept where already set.
    pub fn fit_defaults(&mut self) {
        let Some(spec) = self.settings.law.spec() else {
            return;
        };
        let mut free = BTreeMap::new();
        for p in spec.params {
            if !matches!(p.kind, ParamKind::Number(_)) {
                continue;
            }
            let ParamValue::Number(v) = self.settings.law.value(p) else {
                continue;
            };
            let kept = self.fit.free.get(p.key).copied();
            let (lo, hi) = if v > 0.0 {
                (0.5 * v, 2.0 * v)
            } else {
                (0.0, 1.0)
            };
            free.insert(
                p.key.to_string(),
                kept.unwrap_or(FreeKey { on: false, lo, hi }),
            );
        }
        self.fit.free = free;
        if self.fit.x_column.is_empty() || self.fit.y_column.is_empty() {
            if let Some(d) = (self.settings.scene().ok()).and_then(|s| {
                let d = s.model.displacements.first()?;
                Some(crate::output::series::condition_name(&d.faces, d.component))
            }) {
                self.fit.x_column = format!("u_{d}");
                self.fit.y_column = format!("F_{d}");
            }
        }
    }

    /// Starts fitting the ticked parameters of the edited law to the measured curve, on the
    /// edited scene; refused (with why) without a curve read from a file, a free key, or while
    /// a run or a fit is going.
    pub fn start_fit(&mut self) -> Result<(), String> {
        if self.fit.job.is_some() || self.job.is_some() {
            return Err("a run or a fit is going: wait for it or stop it".into());
        }
        let Some(path) = self.measured.as_ref().and_then(|m| m.path.clone()) else {
            return Err("load a measured curve from a file first".into());
        };
        let k = self.settings.interface;
        let free: Vec<String> = (self.fit.free.iter())
            .filter(|(_, f)| f.on)
            .map(|(key, f)| format!("interface.{k}.law.{key}={:?}..{:?}", f.lo, f.hi))
            .collect();
        if free.is_empty() {
            return Err("tick at least one parameter to fit".into());
        }
        let text = self.settings.scene_text()?;
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let args = FitArgs {
            scene_text: Some(text),
            max_evals: self.fit.max_evals.max(1),
            threads,
            ..FitArgs::new(
                std::path::Path::new(&self.settings.scene),
                &path,
                &self.fit.x_column,
                &self.fit.y_column,
                &free,
            )
        };
        let cancel = Arc::new(AtomicBool::new(false));
        let progress = Arc::new(Mutex::new(FitProgress::default()));
        let mut watch = Progress {
            shared: progress.clone(),
            repaint: self.repaint.clone(),
        };
        let stop = cancel.clone();
        let handle = std::thread::spawn(move || {
            let prep = crate::fit::prepare(&args).map_err(|e| format!("{e:#}"))?;
            crate::fit::fit(&prep, &stop, &mut watch).map_err(|e| format!("{e:#}"))
        });
        self.fit.outcome = None;
        self.fit.job = Some(FitJob {
            cancel,
            progress,
            handle,
            family: self.settings.law.family.clone(),
            interface: k,
        });
        Ok(())
    }

    /// Asks the running fit to stop; it keeps its best values so far.
    pub fn stop_fit(&mut self) {
        if let Some(j) = &self.fit.job {
            j.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Takes the fit's end when its thread has finished; whether a fit is still running.
    pub fn poll_fit(&mut self) -> bool {
        let finished = self.fit.job.as_ref().map(|j| j.handle.is_finished());
        match finished {
            None => false,
            Some(false) => true,
            Some(true) => {
                let job = self.fit.job.take().expect("checked above");
                let report = job
                    .handle
                    .join()
                    .unwrap_or_else(|_| Err("the fit's thread panicked".into()));
                self.fit.outcome = Some(FitOutcome {
                    report,
                    family: job.family,
                    interface: job.interface,
                });
                false
            }
        }
    }

    /// Puts the fitted values into the law editor; refused when the editor now edits another
    /// family or interface than the one fitted.
    pub fn apply_fit(&mut self) -> Result<(), String> {
        let Some(out) = &self.fit.outcome else {
            return Err("no fit has ended".into());
        };
        let report = out.report.as_ref().map_err(|e| e.clone())?;
        if out.family != self.settings.law.family || out.interface != self.settings.interface {
            return Err(format!(
                "the fit was of the `{}` law of interface {}; the editor now edits `{}` of \
                 interface {}",
                out.family, out.interface, self.settings.law.family, self.settings.interface
            ));
        }
        let spec = self
            .settings
            .law
            .spec()
            .ok_or("the edited family is unknown")?;
        for f in &report.parameters {
            let key = f.key.rsplit('.').next().unwrap_or(&f.key);
            if let Some(p) = spec.params.iter().find(|p| p.key == key) {
                *self.settings.law.value_mut(p) = ParamValue::Number(f.value);
            }
        }
        Ok(())
    }
}
