//! The explorer window (`decohesion gui`, and the web page: [`crate::web`]): pick a scene,
//! reshape the interface law, run it on a background thread, stream each run to the Rerun
//! viewer as its own recording, keep a history.
//!
//! The UI never blocks: the solver runs on its own thread ([`Job`]) and reports over a channel;
//! Stop sets a flag the solver reads after every step. In the web page (one thread, no files)
//! the run is stepped inside the frame loop instead, a slice of steps per frame
//! ([`page_run`]), with the same messages and no recording. Parameters edited during a run apply to
//! the next one. The edited scene goes through the same parser and validation as a scene file
//! ([`crate::scene::parse_scene`]), so the window can run nothing the CLI would refuse.
//! The physics modules know nothing of this one.
//!
//! Modules: [`state`] (the state and logic, no egui), [`settings`] (what the user sets, the
//! edited scene), [`law`] (the edited law: a family of the table and its parameter values),
//! [`history`] (history rows, CSV), [`job`] (a run: the thread, through the run driver, or
//! [`page_run`], the page's), `views`, `law_editor` and `plots` (the egui code), and here the eframe
//! application.

pub mod animation;
/// The browser's services (wasm32 only): the page's document, the console, a download.
#[cfg(target_arch = "wasm32")]
pub mod browser;
pub mod export;
mod fit_view;
pub mod frames;
pub mod history;
pub mod job;
pub mod law;
mod law_editor;
pub mod lesson;
mod lesson_view;
pub mod page_run;
mod plots;
pub mod settings;
pub mod state;
pub mod view3d;
mod views;

pub use history::HistoryRow;
pub use job::{Job, JobMessage};
pub use law::{LawSettings, DEFAULT_FAMILY};
pub use lesson::{check_opening, Opening};
pub use settings::{list_scenes, RecordChoice, SceneEntry, Settings};
pub use state::{check_compare, variant_key, App, Curve, Status, CHECK_MAX_ELEMENTS};

use state::Persisted;

/// Key of the persisted settings in eframe's storage.
pub const STORAGE_KEY: &str = "decohesion-explorer";

impl App {
    /// Restores the settings and history saved by a previous launch, then opens `scene` if
    /// given.
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
}

/// The eframe application around [`App`].
pub struct Explorer {
    pub app: App,
    run_on_start: bool,
    /// `key=v1,v2,…`: runs to queue and compare when the window opens.
    compare: Option<String>,
}

impl Explorer {
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        scene: Option<String>,
        run_on_start: bool,
        record: Option<RecordChoice>,
        compare: Option<String>,
    ) -> Explorer {
        let mut app = App::from_storage(cc.storage, scene);
        if let Some(r) = record {
            app.settings.record = r;
        }
        app.repaint = Some(views::repaint_handle(&cc.egui_ctx));
        Explorer {
            app,
            run_on_start,
            compare,
        }
    }
}

impl Explorer {
    /// Opens a lesson at a step, or the scene with overrides ([`Opening`]); a refusal is
    /// noted in the window.
    pub fn open(&mut self, opening: &Opening) {
        let _ = self.app.open(opening);
    }
}

impl eframe::App for Explorer {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        self.app.view.glow = frame.gl().is_some();
        if self.run_on_start {
            self.run_on_start = false;
            // A lesson's step runs with its question's prediction field (empty: no prediction).
            if self.app.lesson.is_some() {
                self.app.run_step();
            } else {
                self.app.start();
            }
        }
        if let Some(spec) = self.compare.take() {
            if let Err(e) = self.app.queue_spec(&spec) {
                self.app.notes.push(e);
            }
        }
        self.app.ui(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, STORAGE_KEY, &self.app.persisted());
    }
}

/// Opens the window (blocks until it is closed); `compare` (`key=v1,v2,…`) queues runs to
/// compare.
#[cfg(not(target_arch = "wasm32"))]
pub fn run_window(
    scene: Option<String>,
    run_on_start: bool,
    record: Option<RecordChoice>,
    compare: Option<String>,
    opening: Opening,
) -> Result<(), String> {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1500.0, 950.0])
            .with_title("decohesion explorer"),
        // The 3-D view draws through glow (OpenGL, WebGL2), with a depth buffer.
        renderer: eframe::Renderer::Glow,
        depth_buffer: 24,
        ..Default::default()
    };
    eframe::run_native(
        "decohesion explorer",
        options,
        Box::new(move |cc| {
            let mut explorer = Explorer::new(cc, scene, run_on_start, record, compare);
            explorer.open(&opening);
            Ok(Box::new(explorer))
        }),
    )
    .map_err(|e| format!("cannot open the window: {e}"))
}

/// For the tests: the explorer reads `scenes/` and `lessons/` relative to the working directory,
/// as `decohesion gui` does when run from the repository, but cargo runs a crate's tests in the
/// crate's folder (`explorer/`). The tests that read them call this first: it moves the whole
/// test process to the repository, once.
#[cfg(test)]
pub(crate) fn at_repository_root() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        std::env::set_current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .expect("the repository is the explorer crate's parent folder")
    });
}
