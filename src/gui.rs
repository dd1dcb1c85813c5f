//! The explorer window (`decohesion gui`): pick a scene, reshape the interface law, run it on a
//! background thread, stream each run to the Rerun viewer as its own recording, keep a history.
//!
//! The UI never blocks: the solver runs on its own thread ([`Job`]) and reports over a channel;
//! Stop sets a flag the solver reads after every step. Parameters edited during a run apply to
//! the next one. The edited scene goes through the same parser and validation as a scene file
//! ([`crate::scene::parse_scene`]), so the window can run nothing the CLI would refuse.
//! The physics modules know nothing of this one.

use crate::law::{LawFamily, StiffnessLaw};
use crate::record::{find_on_path, Cadence, ColourField, Recorder, Sink, RERUN_VERSION};
use crate::report::RunSummary;
use crate::scene::{parse_scene, Scene};
use crate::solver::{Simulation, SolverError, StateCounts};
use crate::vtk::VtkWriter;
use egui_plot::{Legend, Line, Plot, VLine};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Above this many elements the window does not estimate h_crit while settings are edited
/// (set-up and Lanczos estimate: 40 ms at 20³, 130 ms at 28³ here); the run does it.
pub const CHECK_MAX_ELEMENTS: usize = 25_000;

/// Key of the persisted settings in eframe's storage.
pub const STORAGE_KEY: &str = "decohesion-explorer";

/// The law families offered by the editor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Family {
    PlateauLinear,
    Bilinear,
    Exponential,
    Table,
}

impl Family {
    const ALL: [Family; 4] = [
        Family::PlateauLinear,
        Family::Bilinear,
        Family::Exponential,
        Family::Table,
    ];
    fn key(self) -> &'static str {
        match self {
            Family::PlateauLinear => "plateau_linear",
            Family::Bilinear => "bilinear",
            Family::Exponential => "exponential",
            Family::Table => "table",
        }
    }
    fn label(self) -> &'static str {
        match self {
            Family::PlateauLinear => "plateau–linear (paper fig. 5)",
            Family::Bilinear => "bilinear (linear-softening traction)",
            Family::Exponential => "exponential",
            Family::Table => "table of points",
        }
    }
}

/// The interface law as edited (applied to every interface of the scene).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LawSettings {
    pub family: Family,
    /// g_N(0) [Pa/m].
    pub g_n0: f64,
    /// α_e [m].
    pub alpha_e: f64,
    /// u_r [m].
    pub u_r: f64,
    /// Exponent k of the exponential family.
    pub decay: f64,
    /// (α [m], g_N [Pa/m]) rows of the table family.
    pub points: Vec<[f64; 2]>,
    /// μ_inf, friction of the fully ruptured interface.
    pub mu_inf: f64,
}

impl Default for LawSettings {
    fn default() -> Self {
        LawSettings {
            family: Family::PlateauLinear,
            g_n0: 5e8,
            alpha_e: 2e-3,
            u_r: 4e-3,
            decay: 5.0,
            points: vec![[0.0, 5e8], [2e-3, 5e8], [4e-3, 0.0]],
            mu_inf: 0.5,
        }
    }
}

impl LawSettings {
    /// The law, or why it is inadmissible (the library's own checks).
    pub fn law(&self) -> Result<StiffnessLaw, String> {
        let r = match self.family {
            Family::PlateauLinear => {
                StiffnessLaw::new(LawFamily::PlateauLinear, self.g_n0, self.alpha_e, self.u_r)
            }
            Family::Bilinear => {
                StiffnessLaw::new(LawFamily::Bilinear, self.g_n0, self.alpha_e, self.u_r)
            }
            Family::Exponential => StiffnessLaw::new(
                LawFamily::Exponential { decay: self.decay },
                self.g_n0,
                self.alpha_e,
                self.u_r,
            ),
            Family::Table => StiffnessLaw::from_table(self.points.clone()),
        };
        let law = r.map_err(|e| format!("{}: {}", e.key, e.reason))?;
        if !(self.mu_inf.is_finite() && self.mu_inf >= 0.0) {
            return Err(format!("μ_inf = {}: must be finite and ≥ 0", self.mu_inf));
        }
        Ok(law)
    }

    fn to_toml(&self) -> toml::Table {
        let mut t = toml::Table::new();
        t.insert("family".into(), self.family.key().into());
        if self.family == Family::Table {
            let rows = self
                .points
                .iter()
                .map(|p| toml::Value::Array(vec![p[0].into(), p[1].into()]))
                .collect();
            t.insert("points".into(), toml::Value::Array(rows));
        } else {
            t.insert("g_n0".into(), self.g_n0.into());
            t.insert("alpha_e".into(), self.alpha_e.into());
            t.insert("u_r".into(), self.u_r.into());
            if self.family == Family::Exponential {
                t.insert("decay".into(), self.decay.into());
            }
        }
        t
    }
}

/// Where each run goes in Rerun.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RecordChoice {
    /// Stream to the Rerun viewer (started if none listens on 127.0.0.1:9876).
    Viewer,
    /// Save each run to `out/gui/<n>_<scene>.rrd`.
    File,
    /// No recording.
    Off,
}

/// Everything the user sets, persisted between launches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Scene file.
    pub scene: String,
    pub law: LawSettings,
    /// Cells along the longest side of the box mesh; 0 when the scene reads its mesh from a
    /// Gmsh file (`mesh.file`), whose resolution the window cannot change.
    pub cells: usize,
    /// h / h_crit.
    pub factor: f64,
    /// Simulated time [s].
    pub end_time: f64,
    /// Frames per run logged to Rerun.
    pub frames: u32,
    /// "svk" or "neo_hookean".
    pub material: String,
    /// "full" (2×2×2) or "reduced" (one point + hourglass control).
    pub integration: String,
    /// κ of the hourglass control (reduced integration).
    pub hourglass: f64,
    pub record: RecordChoice,
    /// Also write ParaView files (`.vtu` per frame and a `.pvd` index, as `run --vtk`) to
    /// `<output_dir>/runNNN_<scene>_vtk/`.
    pub paraview: bool,
    /// Folder of saved recordings, ParaView files and CSV exports.
    pub output_dir: String,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            scene: "scenes/pull_off.toml".into(),
            law: LawSettings::default(),
            cells: 7,
            factor: 0.5,
            end_time: 0.33,
            frames: 200,
            material: "svk".into(),
            integration: "full".into(),
            hourglass: 0.05,
            record: RecordChoice::Viewer,
            paraview: false,
            output_dir: "out/gui".into(),
        }
    }
}

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

/// A scene offered by the picker.
#[derive(Debug, Clone)]
pub struct SceneEntry {
    pub path: String,
    pub description: String,
}

/// Lists `dir/*.toml` with their descriptions (unreadable files are listed with the error).
pub fn list_scenes(dir: &Path) -> Vec<SceneEntry> {
    let mut out = vec![];
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    let mut paths: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    for p in paths {
        let description = match crate::scene::load_scene(&p, &[]) {
            Ok(s) => s.model.description,
            Err(e) => format!("(does not load: {e})"),
        };
        out.push(SceneEntry {
            path: p.display().to_string(),
            description,
        });
    }
    out
}

/// What the solver thread reports.
#[derive(Debug)]
pub enum JobMessage {
    Progress {
        step: u64,
        time: f64,
        counts: StateCounts,
        relative_residual: f64,
    },
    Done(Box<HistoryRow>),
}

/// A run on its own thread.
pub struct Job {
    pub id: u32,
    pub end_time: f64,
    pub started: Instant,
    pub cancel: Arc<AtomicBool>,
    rx: Receiver<JobMessage>,
    pub last: Option<(u64, f64, StateCounts, f64)>,
}

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
    /// A repaint handle for the solver thread.
    ctx: Option<egui::Context>,
    /// State counts and residual of the running (or last) run over time.
    pub curve: Curve,
    /// Run id of `curve`.
    pub curve_run: Option<u32>,
}

/// What the current settings give, shown before a run.
#[derive(Debug, Clone)]
struct Checked {
    elements: usize,
    interface_nodes: usize,
    h: f64,
    h_crit: f64,
    steps: f64,
    /// [`Simulation::advisories`] of the settings.
    warnings: Vec<String>,
}

#[derive(Serialize, Deserialize, Default)]
#[serde(default)]
struct Persisted {
    settings: Settings,
    history: Vec<HistoryRow>,
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
            ctx: None,
            curve: vec![],
            curve_run: None,
        }
    }

    /// Restores the settings and history saved by a previous launch.
    pub fn from_storage(storage: Option<&dyn eframe::Storage>, scene: Option<String>) -> App {
        let p: Persisted = storage
            .and_then(|s| eframe::get_value(s, STORAGE_KEY))
            .unwrap_or_default();
        let mut app = App::new(p.settings, p.history);
        if let Some(scene) = scene {
            app.load_scene(&scene);
        }
        app
    }

    /// Takes the law and run settings of a scene file.
    pub fn load_scene(&mut self, path: &str) {
        match crate::scene::load_scene(Path::new(path), &[]) {
            Ok(scene) => {
                self.settings.scene = path.to_string();
                let m = &scene.model;
                if let Some(itf) = m.interfaces.first() {
                    let l = &itf.law;
                    self.settings.law.mu_inf = itf.mu_inf;
                    self.settings.law.g_n0 = l.g_n0;
                    self.settings.law.alpha_e = l.alpha_e;
                    self.settings.law.u_r = l.u_r;
                    match &l.family {
                        LawFamily::PlateauLinear => {
                            self.settings.law.family = Family::PlateauLinear
                        }
                        LawFamily::Bilinear => self.settings.law.family = Family::Bilinear,
                        LawFamily::Exponential { decay } => {
                            self.settings.law.family = Family::Exponential;
                            self.settings.law.decay = *decay;
                        }
                        LawFamily::Table { points } => {
                            self.settings.law.family = Family::Table;
                            self.settings.law.points = points.clone();
                        }
                    }
                }
                self.settings.cells = scene_cells(&scene).unwrap_or(0);
                self.settings.factor = m.scheme.time_step_factor;
                self.settings.integration = match m.scheme.integration {
                    crate::model::Integration::Full => "full".into(),
                    crate::model::Integration::Reduced => "reduced".into(),
                };
                self.settings.hourglass = m.scheme.hourglass_coefficient;
                self.settings.end_time = m.end_time;
                self.settings.material = match m.material.model {
                    crate::material::MaterialModel::Svk => "svk".into(),
                    crate::material::MaterialModel::NeoHookean => "neo_hookean".into(),
                };
                self.validation = None;
            }
            Err(e) => self.notes.push(format!("{e}")),
        }
    }

    /// The scene file with the edited settings applied, as TOML text.
    pub fn scene_text(&self) -> Result<String, String> {
        let text = std::fs::read_to_string(&self.settings.scene)
            .map_err(|e| format!("cannot read {}: {e}", self.settings.scene))?;
        let mut doc: toml::Table = text
            .parse()
            .map_err(|e| format!("{}: {e}", self.settings.scene))?;
        let s = &self.settings;
        if let Some(toml::Value::Array(itfs)) = doc.get_mut("interface") {
            for itf in itfs.iter_mut() {
                if let toml::Value::Table(t) = itf {
                    t.insert("law".into(), toml::Value::Table(s.law.to_toml()));
                    t.insert("mu_inf".into(), s.law.mu_inf.into());
                }
            }
        }
        if let Some(toml::Value::Table(mesh)) = doc.get_mut("mesh") {
            if let Some(toml::Value::Array(cells)) = mesh.get("cells").cloned() {
                let c: Vec<f64> = cells
                    .iter()
                    .filter_map(|v| v.as_integer())
                    .map(|v| v as f64)
                    .collect();
                let max = c.iter().cloned().fold(1.0, f64::max);
                let scaled: Vec<toml::Value> = c
                    .iter()
                    .map(|&v| {
                        let n = s.cells.max(1) as f64;
                        toml::Value::Integer(((v * n / max).round() as i64).max(1))
                    })
                    .collect();
                mesh.insert("cells".into(), toml::Value::Array(scaled));
            }
        }
        if let Some(toml::Value::Table(mat)) = doc.get_mut("material") {
            mat.insert("model".into(), s.material.clone().into());
        }
        let scheme = doc
            .entry("scheme")
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let toml::Value::Table(t) = scheme {
            t.insert("time_step_factor".into(), s.factor.into());
            t.insert("integration".into(), s.integration.clone().into());
            t.insert("hourglass_coefficient".into(), s.hourglass.into());
        }
        doc.insert("end_time".into(), s.end_time.into());
        toml::to_string(&doc).map_err(|e| e.to_string())
    }

    /// The scene with the settings applied, validated as a file would be.
    pub fn scene(&self) -> Result<Scene, String> {
        let text = self.scene_text()?;
        parse_scene(&text, &format!("{} (edited)", self.settings.scene), &[])
            .map_err(|e| e.to_string())
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
    fn check(&mut self) -> Result<Checked, String> {
        let text = self.scene_text()?;
        if let Some((t, r)) = &self.validation {
            if *t == text {
                return r.clone();
            }
        }
        let r = parse_scene(&text, &format!("{} (edited)", self.settings.scene), &[])
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
        let settings = self.settings.clone();
        let sink = match settings.record {
            RecordChoice::Off => None,
            RecordChoice::File => {
                let dir = PathBuf::from(&settings.output_dir);
                if let Err(e) = std::fs::create_dir_all(&dir) {
                    self.notes
                        .push(format!("cannot create {}: {e}", dir.display()));
                }
                let stem = Path::new(&settings.scene)
                    .file_stem()
                    .map(|s| s.to_string_lossy().to_string())
                    .unwrap_or_else(|| "run".into());
                Some(Sink::Save(dir.join(format!("run{id:03}_{stem}.rrd"))))
            }
            RecordChoice::Viewer => {
                if find_on_path("rerun").is_some() {
                    Some(Sink::Spawn)
                } else {
                    let dir = PathBuf::from(&settings.output_dir);
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
        };
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = channel();
        let flag = cancel.clone();
        let ctx = self.ctx.clone();
        let end_time = scene.model.end_time;
        let thread_settings = settings.clone();
        let spawned = std::thread::Builder::new()
            .name(format!("decohesion-run-{id}"))
            .spawn(move || {
                let started = Instant::now();
                let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run_job(id, &scene, sink, &thread_settings, &flag, &tx, ctx.as_ref())
                }));
                let row = match outcome {
                    Ok(row) => row,
                    Err(panic) => {
                        let msg = panic
                            .downcast_ref::<String>()
                            .cloned()
                            .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                            .unwrap_or_else(|| "unknown panic".into());
                        failed_row(
                            id,
                            &thread_settings,
                            format!("panic in the solver thread: {msg}"),
                            started,
                        )
                    }
                };
                let _ = tx.send(JobMessage::Done(Box::new(row)));
                if let Some(c) = ctx {
                    c.request_repaint();
                }
            });
        match spawned {
            Ok(_) => {
                self.job = Some(Job {
                    id,
                    end_time,
                    started: Instant::now(),
                    cancel,
                    rx,
                    last: None,
                });
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
            j.cancel.store(true, Ordering::SeqCst);
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
            match job.rx.try_recv() {
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
        let mut s = String::from(
            "id,scene,family,g_n0_Pa_per_m,alpha_e_m,u_r_m,mu_inf,cells,time_step_factor,end_time_s,material,integration,\
             status,steps,simulated_time_s,time_first_damage_s,time_full_rupture_s,peak_force_N,\
             damage_dissipated_J,max_relative_residual,elastic,transition,ruptured,wall_s,recording,paraview,error\n",
        );
        let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
        let quote = |v: &str| format!("\"{}\"", v.replace('"', "\"\""));
        for r in &self.history {
            let st = &r.settings;
            s.push_str(&format!(
                "{},{},{},{:e},{:e},{:e},{},{},{},{},{},{},{},{},{:e},{},{},{},{:e},{:e},{},{},{},{:.3},{},{},{}\n",
                r.id,
                quote(&st.scene),
                st.law.family.key(),
                st.law.g_n0,
                st.law.alpha_e,
                st.law.u_r,
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
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        std::fs::write(path, s).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The whole window.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        if self.ctx.is_none() {
            self.ctx = Some(ui.ctx().clone());
        }
        let running = self.poll();
        if running {
            ui.ctx().request_repaint_after(Duration::from_millis(100));
        }
        egui::Panel::left("settings")
            .resizable(true)
            .default_size(430.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.settings_ui(ui));
            });
        egui::Panel::bottom("history")
            .resizable(true)
            .default_size(230.0)
            .show(ui, |ui| self.history_ui(ui));
        egui::CentralPanel::default().show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                self.run_ui(ui);
                ui.separator();
                self.plots_ui(ui);
                ui.separator();
                self.progress_plot_ui(ui);
            });
        });
    }

    fn settings_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Scene");
        let current = self.settings.scene.clone();
        egui::ComboBox::from_label("scene file")
            .selected_text(&current)
            .width(300.0)
            .show_ui(ui, |ui| {
                for s in self.scenes.clone() {
                    if ui
                        .selectable_label(s.path == current, &s.path)
                        .on_hover_text(&s.description)
                        .clicked()
                    {
                        self.load_scene(&s.path);
                    }
                }
            });
        if let Some(s) = self.scenes.iter().find(|s| s.path == current) {
            ui.label(egui::RichText::new(&s.description).small());
        }
        ui.separator();

        ui.heading("Interface law");
        let law = &mut self.settings.law;
        egui::ComboBox::from_label("family")
            .selected_text(law.family.label())
            .show_ui(ui, |ui| {
                for f in Family::ALL {
                    ui.selectable_value(&mut law.family, f, f.label());
                }
            });
        if law.family == Family::Table {
            ui.label("points (α [m], g_N [Pa/m]); the last g_N must be 0, its α is u_r");
            let mut remove = None;
            egui::Grid::new("points").striped(true).show(ui, |ui| {
                for (i, p) in law.points.iter_mut().enumerate() {
                    ui.add(egui::DragValue::new(&mut p[0]).speed(1e-5).suffix(" m"));
                    ui.add(egui::DragValue::new(&mut p[1]).speed(1e6).suffix(" Pa/m"));
                    if ui
                        .small_button("−")
                        .on_hover_text("remove this point")
                        .clicked()
                    {
                        remove = Some(i);
                    }
                    ui.end_row();
                }
            });
            if let Some(i) = remove {
                if law.points.len() > 2 {
                    law.points.remove(i);
                }
            }
            if ui.button("add a point").clicked() {
                let last = *law.points.last().unwrap_or(&[0.0, 0.0]);
                law.points.push([last[0] * 1.25 + 1e-4, 0.0]);
            }
        } else {
            ui.add(
                egui::Slider::new(&mut law.g_n0, 1e5..=1e12)
                    .logarithmic(true)
                    .text("g_N(0)")
                    .suffix(" Pa/m"),
            );
            ui.add(
                egui::Slider::new(&mut law.alpha_e, 0.0..=0.05)
                    .logarithmic(true)
                    .smallest_positive(1e-6)
                    .text("α_e")
                    .suffix(" m"),
            );
            ui.add(
                egui::Slider::new(&mut law.u_r, 1e-6..=0.1)
                    .logarithmic(true)
                    .text("u_r")
                    .suffix(" m"),
            );
            if law.family == Family::Exponential {
                ui.add(egui::Slider::new(&mut law.decay, 0.1..=50.0).text("decay k"));
            }
        }
        ui.add(egui::Slider::new(&mut law.mu_inf, 0.0..=2.0).text("μ_inf"));
        match law.law() {
            Ok(l) => {
                let (t_max, at) = l.peak_traction();
                ui.label(format!(
                    "peak traction {t_max:.4e} Pa at δ = {at:.3e} m;  G_c = {:.4e} J/m²",
                    l.fracture_energy()
                ));
            }
            Err(e) => {
                ui.colored_label(
                    egui::Color32::from_rgb(220, 50, 50),
                    format!("inadmissible law — {e}"),
                );
            }
        }
        ui.separator();

        ui.heading("Run settings");
        let s = &mut self.settings;
        if s.cells == 0 {
            ui.label("mesh from the scene's Gmsh file (cells per side: box meshes only)");
        } else {
            ui.add(egui::Slider::new(&mut s.cells, 1..=40).text("cells per side"));
        }
        ui.add(egui::Slider::new(&mut s.factor, 0.05..=1.0).text("time-step factor h/h_crit"));
        ui.add(
            egui::Slider::new(&mut s.end_time, 1e-4..=10.0)
                .logarithmic(true)
                .text("end time")
                .suffix(" s"),
        );
        ui.add(
            egui::Slider::new(&mut s.frames, 1..=2000)
                .logarithmic(true)
                .text("frames per run (Rerun)"),
        );
        egui::ComboBox::from_label("material")
            .selected_text(s.material.as_str())
            .show_ui(ui, |ui| {
                ui.selectable_value(
                    &mut s.material,
                    "svk".to_string(),
                    "svk (Saint-Venant–Kirchhoff)",
                );
                ui.selectable_value(&mut s.material, "neo_hookean".to_string(), "neo_hookean");
            });
        ui.horizontal(|ui| {
            ui.label("integration");
            ui.radio_value(&mut s.integration, "full".to_string(), "2×2×2");
            ui.radio_value(
                &mut s.integration,
                "reduced".to_string(),
                "one point + hourglass",
            );
        });
        if s.integration == "reduced" {
            ui.add(egui::Slider::new(&mut s.hourglass, 0.0..=0.3).text("hourglass κ"));
        }
        ui.horizontal(|ui| {
            ui.label("record to");
            ui.radio_value(&mut s.record, RecordChoice::Viewer, "Rerun viewer");
            ui.radio_value(&mut s.record, RecordChoice::File, ".rrd files");
            ui.radio_value(&mut s.record, RecordChoice::Off, "off");
        });
        ui.checkbox(
            &mut s.paraview,
            "also write ParaView files (.vtu per frame + .pvd, in the output folder)",
        );
        match self.check() {
            Ok(c) if c.h.is_finite() => {
                ui.label(format!(
                    "{} hex8, {} interface nodes; h = {:.4e} s, h_crit = {:.4e} s (Lanczos); ≈ {} steps",
                    c.elements, c.interface_nodes, c.h, c.h_crit, c.steps
                ));
                for w in &c.warnings {
                    ui.colored_label(
                        egui::Color32::from_rgb(230, 150, 20),
                        format!("warning: {w}"),
                    );
                }
            }
            Ok(c) => {
                ui.label(format!(
                    "{} hex8 (h_crit is estimated when the run starts)",
                    c.elements
                ));
            }
            Err(e) => {
                ui.colored_label(egui::Color32::from_rgb(220, 50, 50), e);
            }
        }
    }

    fn run_ui(&mut self, ui: &mut egui::Ui) {
        let blocker = self.blocker();
        let running = self.job.is_some();
        ui.horizontal(|ui| {
            let run = ui.add_enabled(!running && blocker.is_none(), egui::Button::new("Run"));
            if run.clicked() {
                self.start();
            }
            if ui.add_enabled(running, egui::Button::new("Stop")).clicked() {
                self.stop();
            }
            if ui
                .add_enabled(!running, egui::Button::new("Reset"))
                .on_hover_text("back to the scene file's values")
                .clicked()
            {
                self.reset();
            }
            let status = match &self.status {
                Status::Idle => "ready".to_string(),
                Status::Running => "running".to_string(),
                Status::Ended(s) => s.clone(),
            };
            ui.label(format!("status: {status}"));
        });
        if let Some(b) = &blocker {
            ui.colored_label(
                egui::Color32::from_rgb(220, 50, 50),
                format!("Run is disabled: {b}"),
            );
        }
        if let Some(job) = &self.job {
            let (step, time, counts, residual) =
                job.last.unwrap_or((0, 0.0, StateCounts::default(), 0.0));
            let frac = (time / job.end_time).clamp(0.0, 1.0);
            let wall = job.started.elapsed().as_secs_f64();
            let rate = step as f64 / wall.max(1e-9);
            let eta = if frac > 0.0 {
                wall * (1.0 - frac) / frac
            } else {
                f64::NAN
            };
            ui.add(
                egui::ProgressBar::new(frac as f32)
                    .show_percentage()
                    .text(format!(
                        "run {}: t = {time:.4} s of {:.4} s, {rate:.0} steps/s, ETA {eta:.1} s",
                        job.id, job.end_time
                    )),
            );
            ui.label(format!(
                "interface nodes: {} elastic, {} transition, {} ruptured; balance residual {residual:.2e}",
                counts.elastic, counts.transition, counts.ruptured
            ));
        }
        for n in &self.notes {
            ui.colored_label(egui::Color32::from_rgb(230, 160, 40), n);
        }
    }

    fn plots_ui(&mut self, ui: &mut egui::Ui) {
        let Ok(law) = self.settings.law.law() else {
            ui.label("(no plot: the law is inadmissible)");
            return;
        };
        let mu_inf = self.settings.law.mu_inf;
        let n = 300;
        let span = law.u_r * 1.15;
        let xs: Vec<f64> = (0..=n).map(|k| span * k as f64 / n as f64).collect();
        let g: Vec<[f64; 2]> = xs.iter().map(|&a| [1e3 * a, law.g_n(a)]).collect();
        let t: Vec<[f64; 2]> = xs
            .iter()
            .map(|&d| [1e3 * d, 1e-6 * law.traction(d)])
            .collect();
        let mu: Vec<[f64; 2]> = xs.iter().map(|&a| [1e3 * a, law.mu(a, mu_inf)]).collect();
        let (ae, ur) = (1e3 * law.alpha_e, 1e3 * law.u_r);
        let marks = |p: &mut egui_plot::PlotUi| {
            p.vline(VLine::new("α_e", ae));
            p.vline(VLine::new("u_r", ur));
        };
        let w = (ui.available_width() / 3.0 - 8.0).max(150.0);
        ui.horizontal(|ui| {
            titled_plot(ui, "stiffness g_N(α) [Pa/m]", "g_n", "α [mm]", w, |p| {
                p.line(Line::new("g_N(α)", g));
                marks(p);
            });
            titled_plot(
                ui,
                "traction T(δ) = g_N(δ)δ [MPa]",
                "traction",
                "δ [mm]",
                w,
                |p| {
                    p.line(Line::new("T(δ)", t));
                    marks(p);
                },
            );
            titled_plot(
                ui,
                "friction μ(α) = μ_inf (1 − g_N(α)/g_N(0))",
                "mu",
                "α [mm]",
                w,
                |p| {
                    p.line(Line::new("μ(α)", mu));
                    marks(p);
                },
            );
        });
    }

    /// Interface node counts over simulated time for the running or last run (paper fig. 6,
    /// right), and the balance residual.
    fn progress_plot_ui(&mut self, ui: &mut egui::Ui) {
        let Some(run) = self.curve_run else {
            ui.label("Run a scene to see its interface states over time here.");
            return;
        };
        let pick = |f: fn(&StateCounts) -> usize| -> Vec<[f64; 2]> {
            self.curve
                .iter()
                .map(|(t, c, _)| [*t, f(c) as f64])
                .collect()
        };
        let residual: Vec<[f64; 2]> = self
            .curve
            .iter()
            .filter(|p| p.2.is_finite())
            .map(|(t, _, r)| [*t, *r])
            .collect();
        let w = (ui.available_width() / 2.0 - 8.0).max(200.0);
        let colour = |c: [u8; 3]| egui::Color32::from_rgb(c[0], c[1], c[2]);
        ui.horizontal(|ui| {
            titled_plot(
                ui,
                &format!("run {run}: interface nodes by state (paper fig. 6, right)"),
                "counts",
                "t [s]",
                w,
                |p| {
                    p.line(Line::new("elastic", pick(|c| c.elastic)).color(colour([46, 160, 67])));
                    p.line(
                        Line::new("transition", pick(|c| c.transition))
                            .color(colour([245, 166, 35])),
                    );
                    p.line(Line::new("ruptured", pick(|c| c.ruptured)).color(colour([208, 2, 27])));
                },
            );
            titled_plot(
                ui,
                &format!("run {run}: balance residual / largest energy"),
                "residual",
                "t [s]",
                w,
                |p| p.line(Line::new("residual", residual)),
            );
        });
    }

    fn history_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.heading("Runs");
            let sel = self.selected.filter(|&i| i < self.history.len());
            if ui
                .add_enabled(
                    sel.is_some() && self.job.is_none(),
                    egui::Button::new("load these parameters"),
                )
                .clicked()
            {
                if let Some(i) = sel {
                    self.settings = self.history[i].settings.clone();
                    self.validation = None;
                }
            }
            if ui
                .add_enabled(!self.history.is_empty(), egui::Button::new("export CSV"))
                .clicked()
            {
                let path = Path::new(&self.settings.output_dir).join("history.csv");
                match self.export_csv(&path) {
                    Ok(()) => self
                        .notes
                        .push(format!("history written to {}", path.display())),
                    Err(e) => self.notes.push(format!("export failed: {e}")),
                }
            }
        });
        egui::ScrollArea::both().show(ui, |ui| {
            egui::Grid::new("history_grid")
                .striped(true)
                .num_columns(13)
                .show(ui, |ui| {
                    for h in [
                        "#",
                        "scene",
                        "law",
                        "g_N(0) Pa/m",
                        "α_e m",
                        "u_r m",
                        "μ_inf",
                        "cells",
                        "status",
                        "rupture s",
                        "peak N",
                        "dissipated J",
                        "residual",
                        "ruptured",
                        "wall s",
                    ] {
                        ui.strong(h);
                    }
                    ui.end_row();
                    let opt = |v: Option<f64>, p: usize| {
                        v.map_or("—".to_string(), |v| format!("{v:.p$e}"))
                    };
                    for (i, r) in self.history.iter().enumerate().rev() {
                        let st = &r.settings;
                        if ui
                            .selectable_label(self.selected == Some(i), format!("{}", r.id))
                            .clicked()
                        {
                            self.selected = Some(i);
                        }
                        ui.label(
                            Path::new(&st.scene)
                                .file_stem()
                                .map(|s| s.to_string_lossy().to_string())
                                .unwrap_or_default(),
                        );
                        ui.label(st.law.family.key());
                        ui.label(format!("{:.2e}", st.law.g_n0));
                        ui.label(format!("{:.2e}", st.law.alpha_e));
                        ui.label(format!("{:.2e}", st.law.u_r));
                        ui.label(format!("{}", st.law.mu_inf));
                        ui.label(match st.cells {
                            0 => "file".to_string(),
                            n => n.to_string(),
                        });
                        let status = ui.label(&r.status);
                        if let Some(e) = &r.error {
                            status.on_hover_text(e);
                        }
                        ui.label(opt(r.time_full_rupture, 4));
                        ui.label(opt(r.peak_force, 3));
                        ui.label(format!("{:.4e}", r.damage_dissipated));
                        ui.label(format!("{:.2e}", r.max_relative_residual));
                        ui.label(format!("{}/{}", r.counts.ruptured, r.interface_nodes));
                        ui.label(format!("{:.2}", r.wall_seconds));
                        ui.end_row();
                    }
                });
        });
    }

    fn persisted(&self) -> Persisted {
        Persisted {
            settings: self.settings.clone(),
            history: self.history.clone(),
        }
    }
}

/// A plot of width `w` under its title, with a legend.
fn titled_plot<'a>(
    ui: &mut egui::Ui,
    title: &str,
    id: &str,
    x_label: &str,
    w: f32,
    add: impl FnOnce(&mut egui_plot::PlotUi<'a>) + 'a,
) {
    ui.vertical(|ui| {
        ui.label(title);
        Plot::new(id)
            .width(w)
            .height(210.0)
            .x_axis_label(x_label.to_string())
            .legend(Legend::default())
            .show(ui, add);
    });
}

/// Cells along the longest side of a scene's box mesh (`None` for a mesh file).
fn scene_cells(scene: &Scene) -> Option<usize> {
    let doc: toml::Table = scene.resolved.parse().ok()?;
    let cells = doc.get("mesh")?.get("cells")?.as_array()?;
    cells
        .iter()
        .filter_map(|v| v.as_integer())
        .max()
        .map(|v| v as usize)
}

fn failed_row(id: u32, settings: &Settings, error: String, started: Instant) -> HistoryRow {
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

/// The solver thread: set up, record, step until done or stopped, report.
fn run_job(
    id: u32,
    scene: &Scene,
    sink: Option<Sink>,
    settings: &Settings,
    cancel: &AtomicBool,
    tx: &std::sync::mpsc::Sender<JobMessage>,
    ctx: Option<&egui::Context>,
) -> HistoryRow {
    let started = Instant::now();
    let mut sim = match Simulation::new(scene.model.clone()) {
        Ok(s) => s,
        Err(e) => return failed_row(id, settings, e.to_string(), started),
    };
    let recording_target = sink.as_ref().map(|s| match s {
        Sink::Save(p) => p.display().to_string(),
        Sink::Spawn => "Rerun viewer".to_string(),
        Sink::Connect(u) => u.clone().unwrap_or_else(|| "Rerun viewer".into()),
    });
    let cadence = Cadence::PerSimSecond(settings.frames.max(1) as f64 / sim.model.end_time);
    let mut recorder =
        match sink.map(|s| Recorder::new(s, scene, &sim, cadence, ColourField::Displacement)) {
            Some(Ok(r)) => Some(r),
            Some(Err(e)) => return failed_row(id, settings, format!("recording: {e}"), started),
            None => None,
        };
    let mut paraview = if settings.paraview {
        let stem = Path::new(&settings.scene)
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_else(|| "run".into());
        let dir = Path::new(&settings.output_dir).join(format!("run{id:03}_{stem}_vtk"));
        match VtkWriter::new(&dir, &sim, cadence) {
            Ok(w) => Some(w),
            Err(e) => return failed_row(id, settings, format!("ParaView files: {e}"), started),
        }
    } else {
        None
    };
    let mut record_error = None;
    let mut paraview_error = None;
    let mut last_report = Instant::now();
    // Progress goes out every 50 ms of wall time (the bar) and every end_time/300 of simulated
    // time (the curve of states over time), whichever comes first.
    let sample = sim.model.end_time / 300.0;
    let mut next_sample = 0.0;
    let outcome = sim.run(|s| {
        if let Some(r) = recorder.as_mut() {
            if let Err(e) = r.on_step(s) {
                record_error = Some(e.to_string());
                return false;
            }
        }
        if let Some(w) = paraview.as_mut() {
            if let Err(e) = w.on_step(s) {
                paraview_error = Some(e.to_string());
                return false;
            }
        }
        if last_report.elapsed() >= Duration::from_millis(50) || s.time >= next_sample {
            last_report = Instant::now();
            next_sample = s.time + sample;
            let _ = tx.send(JobMessage::Progress {
                step: s.step_count,
                time: s.time,
                counts: s.state_counts(),
                relative_residual: s.ledger.relative_residual(),
            });
            if let Some(c) = ctx {
                c.request_repaint();
            }
        }
        !cancel.load(Ordering::SeqCst)
    });
    if let Some(r) = recorder {
        if let Err(e) = r.finish(&sim, outcome.as_ref().err()) {
            record_error.get_or_insert(e.to_string());
        }
    }
    // The last frame and the index are written whatever the outcome (also after Stop).
    let paraview_index = match paraview.map(|w| w.finish(&sim)) {
        Some(Ok(report)) => Some(report.pvd),
        Some(Err(e)) => {
            paraview_error.get_or_insert(e.to_string());
            None
        }
        None => None,
    };
    let summary = RunSummary::new(
        &sim,
        started.elapsed().as_secs_f64(),
        outcome.as_ref().err(),
    );
    let error = match (&outcome, record_error, paraview_error) {
        (_, Some(e), _) => Some(format!("recording: {e}")),
        (_, None, Some(e)) => Some(format!("ParaView files: {e}")),
        (Err(SolverError::Cancelled { .. }), None, None) => None,
        (Err(e), None, None) => Some(e.to_string()),
        (Ok(()), None, None) => None,
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
        recording: recording_target,
        paraview: paraview_index,
    }
}

/// The eframe application around [`App`].
pub struct Explorer {
    pub app: App,
    run_on_start: bool,
}

impl Explorer {
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        scene: Option<String>,
        run_on_start: bool,
        record: Option<RecordChoice>,
    ) -> Explorer {
        let mut app = App::from_storage(cc.storage, scene);
        if let Some(r) = record {
            app.settings.record = r;
        }
        app.ctx = Some(cc.egui_ctx.clone());
        Explorer { app, run_on_start }
    }
}

impl eframe::App for Explorer {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        if self.run_on_start {
            self.run_on_start = false;
            self.app.start();
        }
        self.app.ui(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, STORAGE_KEY, &self.app.persisted());
    }
}

/// Opens the window (blocks until it is closed).
pub fn run_window(
    scene: Option<String>,
    run_on_start: bool,
    record: Option<RecordChoice>,
) -> Result<(), String> {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1500.0, 950.0])
            .with_title("decohesion explorer"),
        ..Default::default()
    };
    eframe::run_native(
        "decohesion explorer",
        options,
        Box::new(move |cc| Ok(Box::new(Explorer::new(cc, scene, run_on_start, record)))),
    )
    .map_err(|e| format!("cannot open the window: {e}"))
}
