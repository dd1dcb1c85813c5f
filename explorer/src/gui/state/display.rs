//! How the explorer is shown for a class: panels hidden (`hide=`, `gui --hide`), the projector
//! mode (`projector=1`, `gui --projector`: larger type, thicker plot lines) and the embeddable
//! view of the page (`embed=1`: one lesson or scene in a course page's `<iframe>`). Links keep
//! the first two; a link copied from the embedded view opens the full page.

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

pub use crate::tunables::PROJECTOR_LINE;
pub use crate::tunables::PROJECTOR_ZOOM;

/// The panels the embeddable view (`embed=1`) leaves out: the menus and tables around the
/// lesson or scene (its text, run bar, plots and 3-D view stay).
pub const EMBED_HIDDEN: [&str; 3] = ["settings", "history", "measured"];

pub use crate::tunables::EMBED_LESSON_WIDTH;
pub use crate::tunables::EMBED_VIEW_WIDTH;

/// Panels hidden, the projector mode and the embeddable view.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Display {
    pub hidden: BTreeSet<String>,
    pub projector: bool,
    pub embed: bool,
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
    /// Whether `panel` (a name of [`PANELS`]) is shown: not hidden, nor left out of the
    /// embeddable view ([`EMBED_HIDDEN`]).
    pub fn shows(&self, panel: &str) -> bool {
        let left_out = self.embed && EMBED_HIDDEN.contains(&panel);
        !(self.hidden.contains(panel) || left_out)
    }

    /// The query parameters that give this display (`&hide=…&projector=1`), empty by default.
    /// Never `embed=1`: a link copied from the embedded view opens the full page.
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
    /// Sets the panels hidden, the projector mode and the embeddable view (`hide=`,
    /// `projector=1`, `embed=1`).
    pub fn set_display(
        &mut self,
        hide: &[String],
        projector: bool,
        embed: bool,
    ) -> Result<(), String> {
        self.display = Display {
            hidden: parse_hidden(hide)?,
            projector,
            embed,
        };
        Ok(())
    }
}

/// The value of the page's `embed=` ([`Display::embed`]): `1` or `true` for the embeddable view,
/// `0` or `false` (or no `embed=`) for the full page; anything else is refused, naming the value
/// and what is admissible. The embeddable view shows one lesson or scene, so it needs `lesson=`
/// or `scene=` (`named`: whether the query has either).
pub fn parse_embed(value: Option<&str>, named: bool) -> Result<bool, String> {
    let embed = match value.map(str::trim) {
        None | Some("0") | Some("false") => false,
        Some("1") | Some("true") => true,
        Some(v) => {
            return Err(format!(
                "embed={v}: admissible 1 or true (the embeddable view: one lesson or scene, no \
                 menus), 0 or false (the full page)"
            ))
        }
    };
    if embed && !named {
        return Err(
            "embed=1 shows one lesson or scene: give lesson=NAME or scene=NAME with it".into(),
        );
    }
    Ok(embed)
}
