//! The explorer's state and logic, without a window: settings, the edited scene and its
//! validation, runs (started on their own thread, [`Job`], or queued), the history, the runs
//! selected for comparison and its CSV export, what is persisted. The views ([`super::views`]) draw it and call these methods; a test can
//! drive it without egui.

use super::history::{legend_labels, RunCurve};
use super::job::{Job, JobMessage, Repaint};
#[cfg(not(target_arch = "wasm32"))]
use super::RecordChoice;
use super::{list_scenes, HistoryRow, SceneEntry, Settings};
#[cfg(not(target_arch = "wasm32"))]
use crate::record::{find_on_path, Sink, RERUN_VERSION};
use crate::scene::Scene;
use crate::solver::Simulation;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeSet, VecDeque};
use std::path::Path;
#[cfg(not(target_arch = "wasm32"))]
use std::path::PathBuf;
use std::sync::mpsc::TryRecvError;
use std::time::Duration;

/// Above this many elements the window does not estimate h_crit while settings are edited (the
/// set-up and the Lanczos estimate would hold the window for a visible time); the run does it.
pub const CHECK_MAX_ELEMENTS: usize = 25_000;

/// Progress of a run over simulated time, for the live plot.
pub type Curve = RunCurve;

/// Settings the explorer can vary over queued runs ([`App::queue_variants`]) besides the
/// number parameters of the law (`interface.law.NAME`, alias `NAME`): the key path as
/// `sweep --vary` and `--set` take it, and its short name. `mesh.cells` is the number of cells
/// along the longest side of a box mesh (the other sides scaled in proportion), as
/// `tradeoff --cells` takes it.
pub const VARIANT_KEYS: [(&str, &str); 4] = [
    ("interface.mu_inf", "mu_inf"),
    ("mesh.cells", "cells"),
    ("scheme.time_step_factor", "factor"),
    ("end_time", "end_time"),
];

/// The prefix of the law's parameters in a key path.
const LAW_PREFIX: &str = "interface.law.";

/// The number parameters of a law family (none for an unknown family).
fn number_params(spec: Option<&'static crate::law::FamilySpec>) -> Vec<&'static str> {
    spec.map_or(&[][..], |f| f.params)
        .iter()
        .filter(|p| matches!(p.kind, crate::law::ParamKind::Number(_)))
        .map(|p| p.key)
        .collect()
}

/// The short name of the compared key `key` (a key path or its short name): a number parameter
/// of the law (`params`, of the family `family`, or of any family when it is not known yet) or
/// one of [`VARIANT_KEYS`]. The error lists what is admissible.
pub fn variant_key(key: &str, family: Option<&str>, params: &[&str]) -> Result<String, String> {
    let param = key.strip_prefix(LAW_PREFIX).unwrap_or(key);
    if params.contains(&param) {
        return Ok(param.to_string());
    }
    if let Some((_, short)) = VARIANT_KEYS.iter().find(|(p, s)| key == *p || key == *s) {
        return Ok(short.to_string());
    }
    let law = match family {
        Some(f) => format!("of the `{f}` law"),
        None => "of the scene's law".to_string(),
    };
    let paths: Vec<&str> = VARIANT_KEYS.iter().map(|k| k.0).collect();
    let shorts: Vec<&str> = VARIANT_KEYS.iter().map(|k| k.1).collect();
    Err(format!(
        "`{key}` cannot be compared: admissible are {LAW_PREFIX}NAME for a number parameter \
         {law} (NAME: {}), {} (short names: NAME, {})",
        params.join(", "),
        paths.join(", "),
        shorts.join(", ")
    ))
}

/// Parses `key=v1,v2,…` of *compare values of* and `gui --compare`: the short name of the key
/// ([`variant_key`]) and the values, which must be numbers. The error names the key and the
/// value (without the flag, which the caller adds).
fn parse_compare(
    spec: &str,
    family: Option<&str>,
    params: &[&str],
) -> Result<(String, Vec<f64>), String> {
    let vary = crate::cli::Vary::parse(spec).map_err(|e| e.to_string().replace("--vary ", ""))?;
    let key = variant_key(&vary.key, family, params)?;
    let values = vary
        .values
        .iter()
        .map(|v| match v.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!("{} = `{v}`: not a number", vary.key)),
        })
        .collect::<Result<Vec<f64>, String>>()?;
    Ok((key, values))
}

/// Checks `gui --compare key=v1,v2,…` before the window opens: the syntax, the key (against
/// the law of `scene`, or of any family when no scene is given: the window then checks it
/// against the law it opens with) and that the values are numbers. The window checks each
/// value against the scene when it queues the runs.
pub fn check_compare(spec: &str, scene: Option<&str>) -> Result<(), String> {
    match scene {
        Some(path) => {
            let mut settings = Settings::default();
            settings.take_scene(&super::settings::open_scene(path)?);
            let params = number_params(settings.law.spec());
            parse_compare(spec, Some(&settings.law.family), &params)?;
        }
        None => {
            let mut params: Vec<&str> = crate::law::families()
                .iter()
                .flat_map(|f| number_params(Some(f)))
                .collect();
            params.sort_unstable();
            params.dedup();
            parse_compare(spec, None, &params)?;
        }
    }
    Ok(())
}

/// Wall time a run in the page steps per frame before the frame is drawn: the page stays
/// responsive (≥ ~40 frames per second with the drawing) and Stop acts at the next frame.
pub const FRAME_BUDGET: Duration = Duration::from_millis(10);

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
    pub(super) validation: Option<(String, Result<Checked, String>)>,
    /// Asks the window for a repaint, from the solver thread.
    pub(super) repaint: Option<Repaint>,
    /// State counts and residual of the running (or last) run over time.
    pub curve: Curve,
    /// Run id of `curve`.
    pub curve_run: Option<u32>,
    /// Ids of the history rows whose curves are overlaid (the "compare" checkboxes).
    pub compare: BTreeSet<u32>,
    /// Settings of runs waiting to start, each once the previous run ends; they are compared.
    pub queue: VecDeque<Settings>,
    /// The running job came from the queue.
    queued_run: bool,
    /// The `key=v1,v2,…` field of the runs to queue.
    pub variants_text: String,
    /// Frames still to draw after a run ended (the plots size their axes from the previous
    /// frame's labels, so the first frame with the final curves is not the last one drawn).
    pub(super) settle: u8,
    /// The 3-D view and the frames of the running (or last) run.
    pub view: super::view3d::View3d,
    /// Runs are stepped inside the frame loop ([`Job::in_page`], [`FRAME_BUDGET`] per frame)
    /// instead of on a thread: always in the web page, which has one thread and no files (no
    /// recording, no ParaView files); on native for the tests.
    pub in_page: bool,
    /// The open lesson, if any ([`super::lesson`]).
    pub lesson: Option<super::lesson::LessonState>,
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
            curve: RunCurve::default(),
            curve_run: None,
            compare: BTreeSet::new(),
            queue: VecDeque::new(),
            queued_run: false,
            variants_text: String::new(),
            settle: 0,
            view: Default::default(),
            in_page: cfg!(target_arch = "wasm32"),
            lesson: None,
        }
    }

    /// Takes the law and run settings of a scene file.
    pub fn load_scene(&mut self, path: &str) {
        match super::settings::open_scene(path) {
            Ok(scene) => {
                self.settings.scene = path.to_string();
                self.settings.set.clear();
                self.settings.take_scene(&scene);
                self.validation = None;
            }
            Err(e) => self.notes.push(e),
        }
    }

    /// Edits the law of `[[interface]]` `k` of the scene from now on, loaded from the scene
    /// file (the edits of the previous one are dropped).
    pub fn edit_interface(&mut self, k: usize) {
        match super::settings::open_scene_with(&self.settings.scene, &self.settings.set) {
            Ok(scene) => {
                self.settings.take_interface(&scene, k);
                self.validation = None;
            }
            Err(e) => self.notes.push(e),
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
        let r = super::settings::parse_text(&text, &self.settings.edited_name())
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
    #[cfg(not(target_arch = "wasm32"))]
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
        match self.launch(id, scene) {
            Ok(job) => {
                self.job = Some(job);
                self.status = Status::Running;
                self.curve.clear();
                self.view.clear();
                self.curve_run = Some(id);
                if std::mem::take(&mut self.queued_run) {
                    self.compare.insert(id);
                }
            }
            Err(e) => self.status = Status::Ended(format!("failed: cannot start a thread: {e}")),
        }
    }

    /// Starts run `id`: in the frame loop ([`App::in_page`]) or on its own thread, recorded
    /// and written as the settings ask.
    fn launch(&mut self, id: u32, scene: Scene) -> std::io::Result<Job> {
        let settings = self.settings.clone();
        #[cfg(not(target_arch = "wasm32"))]
        if !self.in_page {
            let sink = self.sink(id);
            return Job::start(id, scene, sink, settings, self.repaint.clone());
        }
        Ok(Job::in_page(id, scene, settings))
    }

    /// Asks the running job to stop after its current step.
    pub fn stop(&mut self) {
        if let Some(j) = &mut self.job {
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
        if job.in_frames() && job.advance(FRAME_BUDGET) {
            // The next slice of steps at the next frame, drawn at once.
            if let Some(r) = &self.repaint {
                r();
            }
        }
        loop {
            match job.try_recv() {
                Ok(JobMessage::Progress { step, point }) => {
                    job.last = Some((step, point));
                    self.curve.push(point);
                }
                Ok(JobMessage::Frame(f)) => self.view.push(*f),
                Ok(JobMessage::Done(row)) => {
                    self.curve = row.curve.clone();
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
                    self.settle = 3;
                    return self.start_queued();
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

    /// Ticks or unticks history run `id` for comparison.
    pub fn toggle_compare(&mut self, id: u32) {
        if !self.compare.remove(&id) {
            self.compare.insert(id);
        }
    }

    /// The history rows ticked for comparison (in run order) with their legend labels: `run N`
    /// and the parameters that differ between them.
    pub fn compared(&self) -> Vec<(&HistoryRow, String)> {
        let rows: Vec<&HistoryRow> = self
            .history
            .iter()
            .filter(|r| self.compare.contains(&r.id))
            .collect();
        let labels = legend_labels(&rows);
        rows.into_iter().zip(labels).collect()
    }

    /// Queues one run per value of `key` (a number parameter of the edited law or one of
    /// [`VARIANT_KEYS`], as a key path or its short name: [`variant_key`]), the other settings
    /// as they are now; the runs start one after the other and are ticked for comparison.
    /// Nothing is queued if a value is refused.
    pub fn queue_variants(&mut self, key: &str, values: &[f64]) -> Result<(), String> {
        let params = number_params(self.settings.law.spec());
        let short = variant_key(key, Some(&self.settings.law.family), &params)?;
        let mut variants = vec![];
        for &v in values {
            let mut s = self.settings.clone();
            match short.as_str() {
                "mu_inf" => s.law.mu_inf = v,
                "cells" if v >= 1.0 && v.fract() == 0.0 && s.cells > 0 => s.cells = v as usize,
                "factor" => s.factor = v,
                "end_time" => s.end_time = v,
                "cells" => {
                    return Err(format!(
                        "{key} = {v}: must be a whole number ≥ 1 (cells along the longest side), \
                         on a scene with a box mesh"
                    ))
                }
                param => {
                    s.law.values.0.insert(param.to_string(), v.into());
                }
            }
            s.law.law().map_err(|e| format!("{key} = {v}: {e}"))?;
            s.scene().map_err(|e| format!("{key} = {v}: {e}"))?;
            variants.push(s);
        }
        self.queue.extend(variants);
        if self.job.is_none() {
            self.start_queued();
        }
        Ok(())
    }

    /// [`App::queue_variants`] from `key=v1,v2,…` (as `decohesion sweep --vary` takes it, the
    /// key a path or its short name); the error names the key and the value.
    pub fn queue_spec(&mut self, spec: &str) -> Result<(), String> {
        if spec.trim().is_empty() {
            return Err("write key=v1,v2,… first, e.g. interface.law.u_r=0.003,0.004,0.006".into());
        }
        let params = number_params(self.settings.law.spec());
        let (_, values) = parse_compare(spec, Some(&self.settings.law.family), &params)?;
        let key = spec.split_once('=').map_or(spec, |(k, _)| k).trim();
        self.queue_variants(key, &values)
    }

    /// Starts the next queued run, if any; true if one started.
    fn start_queued(&mut self) -> bool {
        while let Some(s) = self.queue.pop_front() {
            self.settings = s;
            self.validation = None;
            self.queued_run = true;
            self.start();
            self.queued_run = false;
            if self.job.is_some() {
                return true;
            }
        }
        false
    }

    /// Writes the history as CSV.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn export_csv(&mut self, path: &Path) -> Result<(), String> {
        super::history::export_csv(&self.history, path)
    }

    /// Saves `text` as the file `name`: into the output folder on native, as a download in the
    /// page; notes where it went or why not.
    pub fn save_file(&mut self, name: &str, text: &str) {
        #[cfg(not(target_arch = "wasm32"))]
        let saved = {
            let path = Path::new(&self.settings.output_dir).join(name);
            std::fs::create_dir_all(&self.settings.output_dir)
                .and_then(|()| std::fs::write(&path, text))
                .map(|()| format!("{name} written to {}", path.display()))
                .map_err(|e| format!("{}: {e}", path.display()))
        };
        #[cfg(target_arch = "wasm32")]
        let saved = super::browser::download(name, text).map(|()| format!("{name} downloaded"));
        match saved {
            Ok(note) => self.notes.push(note),
            Err(e) => self.notes.push(format!("cannot save {name}: {e}")),
        }
    }

    /// Saves the history as CSV (`history.csv`, [`super::history::csv`]).
    pub fn save_history_csv(&mut self) {
        let text = super::history::csv(&self.history);
        self.save_file("history.csv", &text);
    }

    /// Saves the curves of the runs as CSV (`curves.csv`, [`super::history::curves_csv`]): the
    /// force–displacement curve and the node counts over time of every run in the history.
    pub fn save_curves_csv(&mut self) {
        let text = super::history::curves_csv(&self.history);
        self.save_file("curves.csv", &text);
    }

    /// Saves the summary of history row `i` as JSON (`runNNN_<scene>_summary.json`, what
    /// `decohesion run --summary` writes), if the run is of this session.
    pub fn save_summary(&mut self, i: usize) {
        let Some(row) = self.history.get(i) else {
            return;
        };
        let name = format!(
            "run{:03}_{}_summary.json",
            row.id,
            row.settings.scene_stem()
        );
        match row.summary_json.clone() {
            Some(json) => self.save_file(&name, &json),
            None => self.notes.push(format!(
                "run {}: its summary is kept for the runs of this session only",
                row.id
            )),
        }
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
        let row = app.history[0].clone();
        assert_eq!((row.interface_nodes, row.counts.ruptured), (16, 16));
        assert!(
            row.max_relative_residual < 1e-2,
            "{}",
            row.max_relative_residual
        );
        // The live curve ends at the run's end.
        assert_eq!(app.curve_run, Some(1));
        assert_eq!(
            app.curve.points.last().map(|p| p.t),
            Some(row.simulated_time)
        );

        let dir = std::env::temp_dir().join(format!("decohesion-state-{}", std::process::id()));
        let csv = dir.join("history.csv");
        app.export_csv(&csv).unwrap();
        let text = std::fs::read_to_string(&csv).unwrap();
        assert_eq!(text.lines().count(), 2, "{text}");
        assert!(text.lines().nth(1).unwrap().contains(",completed,"));
        // The curves: one line per kept sample, in time order, the last at the run's end with
        // its counts.
        app.settings.output_dir = dir.display().to_string();
        app.save_curves_csv();
        let text = std::fs::read_to_string(dir.join("curves.csv")).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines[0].starts_with("run,t_s,displacement_m,reaction_N,"),
            "{}",
            lines[0]
        );
        assert_eq!(lines.len(), 1 + row.curve.points.len());
        let fields = |l: &str| -> Vec<String> { l.split(',').map(str::to_string).collect() };
        let times: Vec<f64> = lines[1..]
            .iter()
            .map(|l| fields(l)[1].parse().unwrap())
            .collect();
        assert!(times.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(times.last().copied(), Some(row.simulated_time));
        let last = fields(lines.last().unwrap());
        assert_eq!(last[7].parse::<usize>().unwrap(), row.counts.ruptured);
        // The pull: the imposed displacement grows from 0, the reaction is finite throughout.
        let column = |k: usize| -> Vec<f64> {
            lines[1..]
                .iter()
                .map(|l| fields(l)[k].parse().unwrap())
                .collect()
        };
        let (u, f) = (column(2), column(3));
        assert!(u.windows(2).all(|w| w[0] <= w[1]) && u[u.len() - 1] > 0.0);
        assert!(f.iter().all(|x| x.is_finite()) && f.iter().any(|&x| x != 0.0));
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

    /// `roller_peel` has two interfaces (the peel on the plate, the clamp on the roller): the
    /// editor edits one at a time, and the other keeps its own law. Editing interface 1 (the
    /// clamp) leaves the peel's law as the scene file has it, and the history row names the
    /// edited interface.
    #[test]
    fn the_editor_edits_one_interface_at_a_time() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut app = App::default();
        app.load_scene(&root.join("scenes/roller_peel.toml").display().to_string());
        assert!(app.notes.is_empty(), "{:?}", app.notes);
        assert_eq!(app.settings.interfaces, ["z- on plate", "clamp on roller"]);
        assert_eq!(app.settings.interface, 0);
        let file = app.scene().unwrap();
        let laws = |scene: &Scene| -> Vec<String> {
            (scene.model.interfaces.iter())
                .map(|i| i.law.to_string())
                .collect()
        };
        let original = laws(&file);
        // The peel law loaded by default; the clamp's once picked.
        app.edit_interface(1);
        assert_eq!(app.settings.interface, 1);
        assert_eq!(app.settings.law.law().unwrap().to_string(), original[1]);
        let u_r = app.settings.law.knots().unwrap().u_r;
        (app.settings.law.values.0).insert("u_r".into(), (2.0 * u_r).into());
        let edited = laws(&app.scene().unwrap());
        assert_eq!(edited[0], original[0], "the peel law must not change");
        assert_ne!(edited[1], original[1]);
        assert_eq!(app.settings.interface_label(), "1: clamp on roller");
        let row = HistoryRow::failed(1, &app.settings, "not run".into(), web_time::Instant::now());
        assert!(super::super::history::csv(&[row]).contains(",\"1: clamp on roller\","));
    }

    /// Queued variants: a key the explorer cannot vary and an inadmissible value are refused
    /// naming the key, the value and what is admissible, and nothing is queued; two values of
    /// u_r (given by its key path) run one after the other and are both ticked, labelled by u_r
    /// alone. Each row carries its curve, ending at the run's end with its counts; once every
    /// node is ruptured its mean α is u_r (eq. 12 caps α at u_r); the larger u_r dissipates
    /// more (G_c grows with u_r at fixed g_N(0) and α_e).
    #[test]
    fn queued_variants_are_run_and_compared() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut app = App::default();
        app.load_scene(&root.join("scenes/pull_off.toml").display().to_string());
        app.settings.cells = 3;
        app.settings.record = RecordChoice::Off;
        let e = app.queue_spec("young=1e6,2e6").unwrap_err();
        assert!(
            e.contains("`young` cannot be compared")
                && e.contains("interface.law.NAME")
                && e.contains("u_r")
                && e.contains("scheme.time_step_factor"),
            "{e}"
        );
        let e = app.queue_spec("u_r=0.003,0.001").unwrap_err();
        assert!(e.starts_with("u_r = 0.001: u_r"), "{e}");
        let e = app.queue_spec("u_r=0.003,x").unwrap_err();
        assert!(e.contains("`x`: not a number"), "{e}");
        assert!(app.queue.is_empty() && app.job.is_none());

        app.queue_spec("interface.law.u_r=0.003,0.006").unwrap();
        let started = Instant::now();
        while app.poll() {
            assert!(started.elapsed() < Duration::from_secs(60), "no end");
            std::thread::sleep(Duration::from_millis(10));
        }
        assert!(app.queue.is_empty());
        assert_eq!(app.history.len(), 2);
        assert_eq!(app.compare.iter().copied().collect::<Vec<_>>(), [1, 2]);
        let compared = app.compared();
        let labels: Vec<&str> = compared.iter().map(|c| c.1.as_str()).collect();
        assert_eq!(labels, ["run 1: u_r=0.003", "run 2: u_r=0.006"]);
        for (row, u_r) in app.history.iter().zip([0.003, 0.006]) {
            let last = row.curve.points.last().expect("a curve");
            assert_eq!((last.t, last.counts), (row.simulated_time, row.counts));
            assert_eq!(row.counts.ruptured, row.interface_nodes);
            assert!(
                (last.mean_alpha - u_r).abs() <= 1e-12 * u_r,
                "{}",
                last.mean_alpha
            );
            assert!(row.curve.points.len() > 100, "{}", row.curve.points.len());
        }
        assert!(app.history[1].damage_dissipated > app.history[0].damage_dissipated);
    }
}
