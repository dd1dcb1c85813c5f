//! The web page's entry point (wasm32-unknown-unknown, built by `scripts/build_site.sh`): the
//! explorer ([`crate::gui`]) in the canvas `#explorer` through eframe's web runner (glow on
//! WebGL2), every scene of `scenes/` built in, each run stepped inside the frame loop
//! ([`crate::gui::page_run`]) on the page's one thread.
//!
//! URL parameters: `scene=NAME` opens `scenes/NAME.toml` with the file's values, each
//! `set=key.path=value` overrides one of them (as `run --set`); `run=1` starts a run at once;
//! `lesson=NAME&step=N` opens a lesson at its step N (1-based); `hide=…` and `projector=1` set
//! the display; `embed=1` (with `lesson=` or `scene=`) is the embeddable view for a course
//! page's `<iframe>`: the lesson or scene, its run bar, plots and 3-D view sized to the frame,
//! without the menus, the history and the link to the book. A value the page cannot take
//! (`step=`, `embed=`) stops it with `failed: …` naming the parameter, the value and what is
//! admissible. The page reports in the DOM, for scripts (the browser test, `web/test_page.py`):
//! `#status` holds the explorer's status (`ready`, `running`, `finished`, `stopped`, `failed: …`),
//! `#result` the summary JSON of the last run (what `decohesion run --summary` writes), also
//! logged to the console; the title follows the status.

use crate::gui::browser::{document, js_text, log};
use crate::gui::{Explorer, Opening, RecordChoice, Status};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// Starts the explorer in the page (called by wasm-bindgen's loader when the module loads).
#[wasm_bindgen(start)]
pub fn start() {
    wasm_bindgen_futures::spawn_local(async {
        if let Err(e) = run().await {
            let text = format!("the explorer could not start: {e}");
            web_sys::console::error_1(&text.clone().into());
            set_text("status", &format!("failed: {text}"));
        }
    });
}

async fn run() -> Result<(), String> {
    let document = document()?;
    let canvas = document
        .get_element_by_id("explorer")
        .ok_or("the page has no canvas #explorer")?
        .dyn_into::<web_sys::HtmlCanvasElement>()
        .map_err(|_| "#explorer is not a canvas")?;
    let (scene, run_on_start, opening) = url_parameters()?;
    eframe::WebRunner::new()
        .start(
            canvas,
            eframe::WebOptions::default(),
            Box::new(move |cc| {
                let mut explorer =
                    Explorer::new(cc, scene, run_on_start, Some(RecordChoice::Off), None);
                explorer.open(&opening);
                Ok(Box::new(PageExplorer {
                    explorer,
                    reported: None,
                    layout: String::new(),
                }))
            }),
        )
        .await
        .map_err(js_text)
}

/// `scene=NAME` as `scenes/NAME.toml` (a path is taken as it is), `run=1`, and the lesson
/// (`lesson=NAME`, `step=N`) or the overrides (`set=key.path=value`, repeated), the panels hidden
/// (`hide=history,law`), the projector mode (`projector=1`) and the embeddable view (`embed=1`)
/// of the page's URL.
fn url_parameters() -> Result<(Option<String>, bool, Opening), String> {
    let window = web_sys::window().ok_or("no window")?;
    let search = window.location().search().map_err(js_text)?;
    let params = web_sys::UrlSearchParams::new_with_str(&search).map_err(js_text)?;
    let scene = params.get("scene").map(|s| {
        if s.ends_with(".toml") {
            s
        } else {
            format!("scenes/{s}.toml")
        }
    });
    let run = params.get("run").is_some_and(|v| v == "1" || v == "true");
    let embed = crate::gui::state::parse_embed(
        params.get("embed").as_deref(),
        scene.is_some() || params.get("lesson").is_some(),
    )?;
    if embed {
        // The link to the book is the full page's.
        if let Some(book) = window.document().and_then(|d| d.get_element_by_id("book")) {
            book.remove();
        }
    }
    let opening = Opening {
        lesson: params.get("lesson"),
        step: params.get("step").map_or(Ok(1), |s| {
            s.trim()
                .parse::<usize>()
                .map_err(|_| format!("step={s}: not a step number (1, 2, …)"))
        })?,
        set: params
            .get_all("set")
            .iter()
            .filter_map(|v| v.as_string())
            .collect(),
        data: None,
        hide: params
            .get_all("hide")
            .iter()
            .filter_map(|v| v.as_string())
            .collect(),
        projector: params
            .get("projector")
            .is_some_and(|v| v == "1" || v == "true"),
        embed,
    };
    Ok((scene, run, opening))
}

/// The explorer, with its status, last result and layout written into the DOM.
struct PageExplorer {
    explorer: Explorer,
    /// (status, runs in the history) last written.
    reported: Option<(String, usize)>,
    /// The layout last written to `#layout`.
    layout: String,
}

impl eframe::App for PageExplorer {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let frame_rect = ui.max_rect();
        eframe::App::ui(&mut self.explorer, ui, frame);
        let app = &self.explorer.app;
        // For scripts (`web/test_page.py` checks the embeddable view's share of a small
        // frame): the rectangles [x, y, width, height] in points of the page, the 3-D view's
        // panel and its picture (null when not drawn).
        let rect = |r: Option<egui::Rect>| {
            r.map_or("null".to_string(), |r| {
                format!("{:?}", [r.min.x, r.min.y, r.width(), r.height()])
            })
        };
        let layout = format!(
            "{{\"page\": {}, \"view3d_panel\": {}, \"view3d\": {}}}",
            rect(Some(frame_rect)),
            rect(app.view.panel),
            rect(app.view.rect)
        );
        if layout != self.layout {
            set_text("layout", &layout);
            self.layout = layout;
        }
        let status = match &app.status {
            Status::Idle => "ready".to_string(),
            Status::Running => "running".to_string(),
            Status::Ended(s) => s.clone(),
        };
        let now = (status, app.history.len());
        if self.reported.as_ref() == Some(&now) {
            return;
        }
        if let Some(json) = app.history.last().and_then(|r| r.summary_json.as_deref()) {
            set_text("result", json);
            log(&format!("decohesion summary: {json}"));
        }
        set_text("status", &now.0);
        if let Ok(d) = document() {
            d.set_title(&format!("decohesion explorer — {}", now.0));
        }
        self.reported = Some(now);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::App::save(&mut self.explorer, storage);
    }
}

/// Sets the text of the element `#id`, if the page has it.
fn set_text(id: &str, text: &str) {
    if let Some(e) = document().ok().and_then(|d| d.get_element_by_id(id)) {
        e.set_text_content(Some(text));
    }
}
