//! Where a lesson stands in the explorer (its step, the prediction, the run's verdict) and
//! what the explorer opens with (Opening, checked before the window opens).

use super::{find, step_index, Lesson, Step};
use crate::gui::history::HistoryRow;

/// Where a lesson stands in the explorer.
#[derive(Debug, Clone)]
pub struct LessonState {
    pub lesson: Lesson,
    /// The open step (0-based).
    pub step: usize,
    /// The prediction field's text.
    pub prediction: String,
    /// The prediction as given when the step's run started.
    pub predicted: Option<f64>,
    /// The run started for the step (its id in the history).
    pub run: Option<u32>,
}

/// What a step's run answered.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// The run has not ended yet (or none was started).
    Waiting,
    /// The run gave no value of the result (it failed, or never ruptured).
    NoValue(String),
    /// The run's value, and whether the prediction (if any) was within the tolerance.
    Value { value: f64, right: Option<bool> },
}

impl LessonState {
    pub fn new(lesson: Lesson, step: usize) -> LessonState {
        LessonState {
            step: step.min(lesson.steps.len().saturating_sub(1)),
            lesson,
            prediction: String::new(),
            predicted: None,
            run: None,
        }
    }

    /// The open step.
    pub fn current(&self) -> &Step {
        &self.lesson.steps[self.step]
    }

    /// The verdict of the open step's question on the history.
    pub fn verdict(&self, history: &[HistoryRow]) -> Verdict {
        let Some(q) = &self.current().question else {
            return Verdict::Waiting;
        };
        let Some(row) = self.run.and_then(|id| history.iter().find(|r| r.id == id)) else {
            return Verdict::Waiting;
        };
        match q.result.value(row) {
            Some(value) => Verdict::Value {
                value,
                right: self.predicted.map(|p| q.accepts(p, value)),
            },
            None => Verdict::NoValue(match &row.error {
                Some(e) => format!("the run failed: {e}"),
                None => format!("the run has no {} ({})", q.result.label(), row.status),
            }),
        }
    }
}

/// What the explorer opens with besides a scene: a lesson at a step, or scene overrides (a
/// link's `set=`, `gui --set`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Opening {
    /// A shipped lesson's name, or (natively) the path of a lesson file (`….md`).
    pub lesson: Option<String>,
    /// The lesson's step, 1-based (0: the first).
    pub step: usize,
    /// Scene overrides (`key.path=value`) on the opened scene.
    pub set: Vec<String>,
    /// A measured curve (CSV file) to draw over the compared runs and fit (`gui --data`).
    pub data: Option<String>,
    /// Panels to hide (names of [`crate::gui::state::PANELS`], comma-separated lists).
    pub hide: Vec<String>,
    /// Larger type and thicker lines.
    pub projector: bool,
    /// The embeddable view (the page's `embed=1`): the lesson or scene without the menus.
    pub embed: bool,
}

/// Checks an opening before the window opens (`gui --lesson`, `--step`, `--set`): the lesson
/// loads and has the step, or the overrides load `scene` (the default scene without one).
pub fn check_opening(scene: Option<&str>, o: &Opening) -> Result<(), String> {
    crate::gui::state::parse_hidden(&o.hide)?;
    #[cfg(not(target_arch = "wasm32"))]
    if let Some(path) = &o.data {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("--data {path}: cannot read the measured curve: {e}"))?;
        crate::gui::state::Measured::parse(&text, path, None)?;
    }
    if let Some(name) = &o.lesson {
        let lesson = find(name)?;
        step_index(&lesson, o.step.max(1))?;
        if !o.set.is_empty() {
            return Err(
                "--set applies to a scene, not to a lesson (its steps set their keys)".into(),
            );
        }
        return Ok(());
    }
    if !o.set.is_empty() {
        let default = crate::gui::Settings::default().scene;
        crate::gui::settings::open_scene_with(scene.unwrap_or(&default), &o.set)?;
    }
    Ok(())
}
