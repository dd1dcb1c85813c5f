//! The explorer's state and logic, without a window: settings, the edited scene and its
//! validation, runs (started on their own thread, [`Job`], or queued), the history, the runs
//! selected for comparison and its CSV export, what is persisted. The views ([`super::views`]) draw it and call these methods; a test can
//! drive it without egui.

mod compare;
mod display;
mod measured;
mod run;
mod save;
#[cfg(test)]
mod tests;

pub use compare::{check_compare, variant_key, VARIANT_KEYS};
pub use display::{
    parse_embed, parse_hidden, Display, EMBED_HIDDEN, EMBED_LESSON_WIDTH, EMBED_VIEW_WIDTH, PANELS,
    PROJECTOR_LINE, PROJECTOR_ZOOM,
};
pub use measured::Measured;
#[cfg(not(target_arch = "wasm32"))]
pub use measured::{FitOutcome, FitPanel, FreeKey};

use super::history::RunCurve;
use super::job::{Job, Repaint};
use super::{list_scenes, HistoryRow, SceneEntry, Settings};
use crate::scene::Scene;
use crate::solver::Simulation;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeSet, VecDeque};
use std::path::Path;

pub use crate::tunables::CHECK_MAX_ELEMENTS;

/// Progress of a run over simulated time, for the live plot.
pub type Curve = RunCurve;

pub use crate::tunables::FRAME_BUDGET;

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
    /// Panels hidden, the projector mode and the embeddable view ([`display`]).
    pub display: Display,
    /// A plot or the 3-D view to save as PNG once the window's screenshot comes.
    pub pending_png: Option<super::export::PendingPng>,
    /// The 3-D view's animation being captured.
    pub gif: Option<super::animation::GifCapture>,
    /// The measured curve drawn over the compared runs ([`measured`]).
    pub measured: Option<Measured>,
    /// The fit of the edited law to it (native).
    #[cfg(not(target_arch = "wasm32"))]
    pub fit: FitPanel,
    /// The path field of the measured curve (native).
    #[cfg(not(target_arch = "wasm32"))]
    pub measured_path: String,
    /// Files dropped on the page, read by the browser.
    #[cfg(target_arch = "wasm32")]
    pub(super) dropped: super::fit_view::Inbox,
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
            display: Display::default(),
            pending_png: None,
            gif: None,
            measured: None,
            #[cfg(not(target_arch = "wasm32"))]
            fit: FitPanel::default(),
            #[cfg(not(target_arch = "wasm32"))]
            measured_path: String::new(),
            #[cfg(target_arch = "wasm32")]
            dropped: Default::default(),
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
                    interface_nodes: sim.state.interface_nodes.len(),
                    h: sim.state.h,
                    h_crit: sim.state.h_crit,
                    steps: (end / sim.state.h).ceil(),
                    warnings: sim.advisories(),
                })
            });
        self.validation = Some((text, r.clone()));
        r
    }

    /// Back to the scene file's own values.
    pub fn reset(&mut self) {
        let scene = self.settings.scene.clone();
        self.load_scene(&scene);
    }

    pub(super) fn persisted(&self) -> Persisted {
        Persisted {
            settings: self.settings.clone(),
            history: self.history.clone(),
        }
    }
}
