//! The explorer's state and logic, without a window: settings, the edited scene and its
//! validation, runs (started on their own thread, [`Job`]), the history and its CSV export,
//! what is persisted. The views ([`super::views`]) draw it and call these methods; a test can
//! drive it without egui.

use super::history::export_csv;
use super::job::{Job, JobMessage, Repaint};
use super::{list_scenes, HistoryRow, RecordChoice, SceneEntry, Settings};
use crate::record::{find_on_path, Sink, RERUN_VERSION};
use crate::scene::{parse_scene, Scene};
use crate::solver::{Simulation, StateCounts};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::mpsc::TryRecvError;

/// Above this many elements the window does not estimate h_crit while settings are edited
/// (set-up and Lanczos estimate: 40 ms at 20³, 130 ms at 28³ here); the run does it.
pub const CHECK_MAX_ELEMENTS: usize = 25_000;

/// Progress of a run over simulated time, for the live plot: (t [s], counts, relative residual).
pub type Curve = Vec<(f64, StateCounts, f64)>;

/// Where the app is.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    Idle,
    Running,
    /// The last run ended: "finished", "failed: …", "stopped".
    Ended(String),
}

/// The explorer.
pub struct App {
    pub settings: Settings,
    pub history: Vec<HistoryRow>,
    pub scenes: Vec<SceneEntry>,
    pub job: Option<Job>,
    pub status: Status,
    pub selected: Option<usize>,
    /// Messages for the user (viewer missing, CSV written, …).
    pub notes: Vec<String>,
    /// Validation of the current settings, cached by the scene text it was computed from.
    validation: Option<(String, Result<Checked, String>)>,
    /// Asks the window for a repaint, from the solver thread.
    pub(super) repaint: Option<Repaint>,
    /// State counts and residual of the running (or last) run over time.
    pub curve: Curve,
    /// Run id of `curve`.
    pub curve_run: Option<u32>,
}

/// What the current settings give, shown before a run.
#[derive(Debug, Clone)]
pub(super) struct Checked {
    pub(super) elements: usize,
    pub(super) interface_nodes: usize,
    pub(super) h: f64,
    pub(super) h_crit: f64,
    pub(super) steps: f64,
    /// [`Simulation::advisories`] of the settings.
    pub(super) warnings: Vec<String>,
}

/// What is saved between launches.
#[derive(Serialize, Deserialize, Default)]
#[serde(default)]
pub(super) struct Persisted {
    pub(super) settings: Settings,
    pub(super) history: Vec<HistoryRow>,
}

impl Default for App {
    fn default() -> Self {
        App::new(Settings::default(), vec![])
    }
}

impl App {
    pub fn new(settings: Settings, history: Vec<HistoryRow>) -> App {
        let scenes = list_scenes(Path::new("scenes"));
        App {
            settings,
            history,
            scenes,
            job: None,
            status: Status::Idle,
            selected: None,
            notes: vec![],
            validation: None,
            repaint: None,
            curve: vec![],
            curve_run: None,
        }
    }

    /// Takes the law and run settings of a scene file.
    pub fn load_scene(&mut self, path: &str) {
        match crate::scene::load_scene(Path::new(path), &[]) {
            Ok(scene) => {
                self.settings.scene = path.to_string();
                self.settings.take_scene(&scene);
                self.validation = None;
            }
            Err(e) => self.notes.push(format!("{e}")),
        }
    }

    /// The settings of history row `i`, to run them again.
    pub fn load_row(&mut self, i: usize) {
        if let Some(row) = self.history.get(i) {
            self.settings = row.settings.clone();
            self.validation = None;
        }
    }

    /// The scene file with the edited settings applied, as TOML text.
    pub fn scene_text(&self) -> Result<String, String> {
        self.settings.scene_text()
    }

    /// The scene with the settings applied, validated as a file would be.
    pub fn scene(&self) -> Result<Scene, String> {
        self.settings.scene()
    }

    /// Why Run is disabled, if it is.
    pub fn blocker(&mut self) -> Option<String> {
        if let Err(e) = self.settings.law.law() {
            return Some(e);
        }
        if self.settings.frames == 0 {
            return Some("frames per run must be ≥ 1".into());
        }
        self.check().err()
    }

    /// Validation and h/h_crit of the current settings, recomputed when they change.
    pub(super) fn check(&mut self) -> Result<Checked, String> {
        let text = self.scene_text()?;
        if let Some((t, r)) = &self.validation {
            if *t == text {
                return r.clone();
            }
        }
        let r = parse_scene(&text, &self.settings.edited_name(), &[])
            .map_err(|e| e.to_string())
            .and_then(|scene| {
                let m = scene.model;
                let elements = m.mesh.elements.len();
                if elements > CHECK_MAX_ELEMENTS {
                    // The Lanczos estimate would stall the window: say so, do not compute.
                    return Ok(Checked {
                        elements,
                        interface_nodes: 0,
                        h: f64::NAN,
                        h_crit: f64::NAN,
                        steps: f64::NAN,
                        warnings: Vec::new(),
                    });
                }
                let end = m.end_time;
                let sim = Simulation::new(m).map_err(|e| e.to_string())?;
                Ok(Checked {
                    elements,
                    interface_nodes: sim.interface_nodes.len(),
                    h: sim.h,
                    h_crit: sim.h_crit,
                    steps: (end / sim.h).ceil(),
                    warnings: sim.advisories(),
                })
            });
        self.validation = Some((text, r.clone()));
        r
    }

    /// Where run `id` is recorded, per the settings (a note when the viewer is missing).
    fn sink(&mut self, id: u32) -> Option<Sink> {
        let settings = &self.settings;
        let dir = PathBuf::from(&settings.output_dir);
        match settings.record {
            RecordChoice::Off => None,
            RecordChoice::File => {
                if let Err(e) = std::fs::create_dir_all(&dir) {
                    self.notes
                        .push(format!("cannot create {}: {e}", dir.display()));
                }
                let stem = settings.scene_stem();
                Some(Sink::Save(dir.join(format!("run{id:03}_{stem}.rrd"))))
            }
            RecordChoice::Viewer if find_on_path("rerun").is_some() => Some(Sink::Spawn),
            RecordChoice::Viewer => {
                let _ = std::fs::create_dir_all(&dir);
                let path = dir.join(format!("run{id:03}.rrd"));
                self.notes.push(format!(
                    "No Rerun viewer on PATH: run {id} is saved to {} instead. Install the viewer \
                     with `pip install rerun-sdk=={RERUN_VERSION}` and put its bin/ on PATH.",
                    path.display()
                ));
                Some(Sink::Save(path))
            }
        }
    }

    /// Starts a run with the current settings on a new thread.
    pub fn start(&mut self) {
        if self.job.is_some() {
            return;
        }
        if let Some(reason) = self.blocker() {
            self.status = Status::Ended(format!("not started: {reason}"));
            return;
        }
        let scene = match self.scene() {
            Ok(s) => s,
            Err(e) => {
                self.status = Status::Ended(format!("not started: {e}"));
                return;
            }
        };
        let id = self.history.iter().map(|r| r.id).max().unwrap_or(0) + 1;
        let sink = self.sink(id);
        let settings = self.settings.clone();
        match Job::start(id, scene, sink, settings, self.repaint.clone()) {
            Ok(job) => {
                self.job = Some(job);
                self.status = Status::Running;
                self.curve.clear();
                self.curve_run = Some(id);
            }
            Err(e) => self.status = Status::Ended(format!("failed: cannot start a thread: {e}")),
        }
    }

    /// Asks the running job to stop after its current step.
    pub fn stop(&mut self) {
        if let Some(j) = &self.job {
            j.stop();
        }
    }

    /// Back to the scene file's own values.
    pub fn reset(&mut self) {
        let scene = self.settings.scene.clone();
        self.load_scene(&scene);
    }

    /// Reads the job's messages; returns true while a run is going on.
    pub fn poll(&mut self) -> bool {
        let Some(job) = &mut self.job else {
            return false;
        };
        loop {
            match job.try_recv() {
                Ok(JobMessage::Progress {
                    step,
                    time,
                    counts,
                    relative_residual,
                }) => {
                    job.last = Some((step, time, counts, relative_residual));
                    self.curve.push((time, counts, relative_residual));
                }
                Ok(JobMessage::Done(row)) => {
                    self.curve.push((row.simulated_time, row.counts, f64::NAN));
                    self.status = Status::Ended(match row.status.as_str() {
                        "completed" => "finished".to_string(),
                        "cancelled" => "stopped".to_string(),
                        _ => format!("failed: {}", row.error.clone().unwrap_or_default()),
                    });
                    if let Some(pvd) = &row.paraview {
                        self.notes.push(format!(
                            "run {}: ParaView files indexed by {pvd} (open it in ParaView)",
                            row.id
                        ));
                    }
                    self.history.push(*row);
                    self.job = None;
                    return false;
                }
                Err(TryRecvError::Empty) => return true,
                Err(TryRecvError::Disconnected) => {
                    self.status =
                        Status::Ended("failed: the solver thread ended without a word".into());
                    self.job = None;
                    return false;
                }
            }
        }
    }

    /// Writes the history as CSV.
    pub fn export_csv(&mut self, path: &Path) -> Result<(), String> {
        export_csv(&self.history, path)
    }

    pub(super) fn persisted(&self) -> Persisted {
        Persisted {
            settings: self.settings.clone(),
            history: self.history.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    /// The explorer's logic without a window: a 3³ pull-off run started, polled to its end
    /// (the whole glued face, 4 × 4 nodes, torn off by t = 0.33 s, with a small balance
    /// residual), its row in the history and in the CSV export; an inadmissible law blocks
    /// the next run with the library's reason; the row's settings load back.
    #[test]
    fn runs_and_history_without_a_window() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut app = App::default();
        app.load_scene(&root.join("scenes/pull_off.toml").display().to_string());
        assert!(app.notes.is_empty(), "{:?}", app.notes);
        app.settings.cells = 3;
        app.settings.record = RecordChoice::Off;
        assert_eq!(app.blocker(), None);
        app.start();
        assert_eq!(app.status, Status::Running);
        let started = Instant::now();
        while app.poll() {
            assert!(started.elapsed() < Duration::from_secs(60), "no end");
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(app.status, Status::Ended("finished".into()));
        assert_eq!(app.history.len(), 1);
        let row = &app.history[0];
        assert_eq!((row.interface_nodes, row.counts.ruptured), (16, 16));
        assert!(
            row.max_relative_residual < 1e-2,
            "{}",
            row.max_relative_residual
        );
        // The live curve ends at the run's end.
        assert_eq!(app.curve_run, Some(1));
        assert_eq!(app.curve.last().map(|p| p.0), Some(row.simulated_time));

        let dir = std::env::temp_dir().join(format!("decohesion-state-{}", std::process::id()));
        let csv = dir.join("history.csv");
        app.export_csv(&csv).unwrap();
        let text = std::fs::read_to_string(&csv).unwrap();
        assert_eq!(text.lines().count(), 2, "{text}");
        assert!(text.lines().nth(1).unwrap().contains(",completed,"));
        std::fs::remove_dir_all(&dir).ok();

        let law = app.settings.law.clone();
        let alpha_e = app.settings.law.knots().unwrap().alpha_e;
        (app.settings.law.values.0).insert("u_r".into(), (0.5 * alpha_e).into());
        let reason = app.blocker().expect("u_r < α_e is refused");
        assert!(reason.starts_with("u_r"), "{reason}");
        app.start();
        assert!(app.job.is_none());
        assert!(matches!(&app.status, Status::Ended(s) if s.starts_with("not started: u_r")));
        app.load_row(0);
        assert_eq!(app.settings.law, law);
        assert_eq!(app.blocker(), None);
    }
}
