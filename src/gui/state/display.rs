//! How the explorer is shown for a class: panels hidden (`hide=`, `gui --hide`) and the projector
//! mode (`projector=1`, `gui --projector`: larger type, thicker plot lines). Links keep both.

use super::App;
use std::collections::BTreeSet;

/// The panels that can be hidden, with what each is.
pub const PANELS: [(&str, &str); 6] = [
    (
        "settings",
        "the left panel: scene, law editor, run settings",
    ),
    ("history", "the table of runs at the bottom"),
    ("view", "the 3-D view on the right"),
    ("law", "the plots of g_N(α), T(δ) and μ(α)"),
    (
        "progress",
        "the plots of the run: node states, force, balance residual",
    ),
    ("measured", "the measured curve and fit section"),
];

/// The zoom of the projector mode (egui's points per pixel, × the system's).
pub const PROJECTOR_ZOOM: f32 = 1.5;
/// The width of plot lines in the projector mode [points] (egui_plot's default is 1.5).
pub const PROJECTOR_LINE: f32 = 3.5;

/// Panels hidden and the projector mode.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Display {
    pub hidden: BTreeSet<String>,
    pub projector: bool,
}

/// The panels named in `specs` (each a comma-separated list); an unknown name is refused with
/// the admissible ones.
pub fn parse_hidden(specs: &[String]) -> Result<BTreeSet<String>, String> {
    let mut out = BTreeSet::new();
    for name in specs.iter().flat_map(|s| s.split(',')).map(str::trim) {
        if name.is_empty() {
            continue;
        }
        if !PANELS.iter().any(|(p, _)| *p == name) {
            return Err(format!(
                "hide={name}: no such panel; admissible: {}",
                PANELS.map(|(p, _)| p).join(", ")
            ));
        }
        out.insert(name.to_string());
    }
    Ok(out)
}

impl Display {
    /// Whether `panel` (a name of [`PANELS`]) is shown.
    pub fn shows(&self, panel: &str) -> bool {
        !self.hidden.contains(panel)
    }

    /// The query parameters that give this display (`&hide=…&projector=1`), empty by default.
    pub fn query(&self) -> String {
        let mut q = String::new();
        if !self.hidden.is_empty() {
            let names: Vec<&str> = self.hidden.iter().map(String::as_str).collect();
            q.push_str("&hide=");
            q.push_str(&names.join(","));
        }
        if self.projector {
            q.push_str("&projector=1");
        }
        q
    }
}

impl App {
    /// Sets the panels hidden and the projector mode (`hide=`, `projector=1`).
    pub fn set_display(&mut self, hide: &[String], projector: bool) -> Result<(), String> {
        self.display = Display {
            hidden: parse_hidden(hide)?,
            projector,
        };
        Ok(())
    }
}
