//! A lesson as the explorer holds it (Lesson, Step, Question), the shipped lessons, and the
//! loading of a lesson: parsed ([`super::parse`]), then checked against its scene.

use super::{parse, PlotName, RunResult};
use std::fmt;

/// The lessons shipped with the explorer (the page has no files): (name, text of
/// `lessons/NAME.md`), in their teaching order. A test checks that the folder holds these
/// files and no other.
pub const LESSONS: &[(&str, &str)] = &[
    (
        "cohesive_law",
        include_str!("../../../../lessons/cohesive_law.md"),
    ),
    ("pull_off", include_str!("../../../../lessons/pull_off.md")),
    ("peel", include_str!("../../../../lessons/peel.md")),
    ("friction", include_str!("../../../../lessons/friction.md")),
    ("rate", include_str!("../../../../lessons/rate.md")),
    (
        "stability",
        include_str!("../../../../lessons/stability.md"),
    ),
    (
        "demoulding",
        include_str!("../../../../lessons/demoulding.md"),
    ),
];

/// Why a lesson was refused: the file, the line (1-based, when the error is at one) and what is
/// wrong, with what is admissible.
#[derive(Debug, Clone, PartialEq)]
pub struct LessonError {
    pub file: String,
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for LessonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{l}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for LessonError {}

/// A question: the student predicts `result` of the step's run; the run's value is compared
/// with the prediction.
#[derive(Debug, Clone, PartialEq)]
pub struct Question {
    pub text: String,
    pub result: RunResult,
    /// The reference answer, in the result's unit (what the run gives, within `tolerance`).
    pub answer: f64,
    /// Relative tolerance of a right prediction (and of the reference answer against the run).
    pub tolerance: f64,
    /// Shown once the run has answered.
    pub explain: String,
    /// Line of `answer` in the file.
    pub line: usize,
}

impl Question {
    /// Whether `prediction` is within the tolerance of the run's `value`.
    pub fn accepts(&self, prediction: f64, value: f64) -> bool {
        (prediction - value).abs() <= self.tolerance * value.abs()
    }
}

/// One step of a lesson.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub title: String,
    /// The step's Markdown, without its `step` block.
    pub text: String,
    /// Line of the step's heading.
    pub line: usize,
    /// Scene overrides (`key.path=value`) this step adds to those of the steps before.
    pub set: Vec<String>,
    /// The line of each of them in the file.
    pub set_lines: Vec<usize>,
    /// Start a run when the step opens (a step with a question runs when the prediction is in).
    pub run: bool,
    pub plot: Option<PlotName>,
    /// The time [s] at which the 3-D view stops following the run (the run goes on), and its
    /// line in the file.
    pub time: Option<(f64, usize)>,
    /// The node the inspector opens on (an interface or contact node of the scene), and its
    /// line in the file.
    pub node: Option<(u32, usize)>,
    pub question: Option<Question>,
}

/// A parsed lesson.
#[derive(Debug, Clone, PartialEq)]
pub struct Lesson {
    /// The file's stem: the name links use (`?lesson=NAME`).
    pub name: String,
    /// The file as messages name it.
    pub file: String,
    pub title: String,
    pub summary: String,
    /// The scene file (`scenes/NAME.toml`).
    pub scene: String,
    /// The Markdown before the first step.
    pub intro: String,
    pub steps: Vec<Step>,
}

impl Lesson {
    /// The overrides in force at step `k` (0-based): those of steps 0..=k in order, an
    /// override left out when a later one sets the same key (it would replace it).
    pub fn sets_through(&self, k: usize) -> Vec<String> {
        let all: Vec<&String> = (self.steps.iter().take(k + 1))
            .flat_map(|s| s.set.iter())
            .collect();
        let key = |s: &str| s.split_once('=').map_or(s, |(k, _)| k).trim().to_string();
        (all.iter().enumerate())
            .filter(|(i, s)| !all[i + 1..].iter().any(|t| key(t) == key(s)))
            .map(|(_, s)| s.to_string())
            .collect()
    }
}

/// The scene file a lesson's `scene` names: `scenes/NAME.toml`.
pub fn scene_path(name: &str) -> String {
    format!("scenes/{name}.toml")
}

/// The text of the shipped lesson `name`, or what is admissible.
pub fn shipped(name: &str) -> Result<&'static str, String> {
    LESSONS
        .iter()
        .find(|l| l.0 == name)
        .map(|l| l.1)
        .ok_or_else(|| {
            let names: Vec<&str> = LESSONS.iter().map(|l| l.0).collect();
            format!("no lesson `{name}`: the lessons are {}", names.join(", "))
        })
}

/// Parses the lesson text of `file` and checks it against its scene ([`check`]).
pub fn load(text: &str, file: &str) -> Result<Lesson, LessonError> {
    let lesson = parse(text, file)?;
    check(&lesson)?;
    Ok(lesson)
}

/// Checks a parsed lesson against its scene: the scene exists, and at every step the overrides
/// so far load it (as `run --set` would); the error names the line of the step's `set`.
pub fn check(lesson: &Lesson) -> Result<(), LessonError> {
    let err = |line: Option<usize>, message: String| LessonError {
        file: lesson.file.clone(),
        line,
        message,
    };
    crate::gui::settings::read_scene(&lesson.scene).map_err(|e| {
        let scenes: Vec<String> = crate::gui::list_scenes(std::path::Path::new("scenes"))
            .iter()
            .filter_map(|s| {
                let p = s.path.strip_prefix("scenes/")?.strip_suffix(".toml")?;
                Some(p.to_string())
            })
            .collect();
        err(
            None,
            format!(
                "scene = {:?}: no such scene ({e}); admissible are {}",
                lesson
                    .scene
                    .trim_start_matches("scenes/")
                    .trim_end_matches(".toml"),
                scenes.join(", ")
            ),
        )
    })?;
    for (k, step) in lesson.steps.iter().enumerate() {
        if step.set.is_empty() && k > 0 && step.time.is_none() && step.node.is_none() {
            continue;
        }
        let opened = crate::gui::settings::open_scene_with(&lesson.scene, &lesson.sets_through(k));
        if let Ok(scene) = &opened {
            check_hold(step, &scene.model).map_err(|(line, m)| {
                err(
                    Some(line),
                    format!("step {} (“{}”), {m}", k + 1, step.title),
                )
            })?;
        }
        if let Err(e) = opened {
            // The line of the first override of the step that the scene refuses.
            let before = if k == 0 {
                vec![]
            } else {
                lesson.sets_through(k - 1)
            };
            let line = (0..step.set.len())
                .find(|&j| {
                    let mut set = before.clone();
                    set.extend_from_slice(&step.set[..=j]);
                    crate::gui::settings::open_scene_with(&lesson.scene, &set).is_err()
                })
                .map_or(step.line, |j| step.set_lines[j]);
            return Err(err(
                Some(line),
                format!("step {} (“{}”), its `set`: {e}", k + 1, step.title),
            ));
        }
    }
    Ok(())
}

/// A step's `time` within the run of its scene (0 to the end time) and its `node` on one of
/// the scene's interface or contact faces; the error is (the file's line, the reason).
fn check_hold(step: &Step, model: &crate::model::Model) -> Result<(), (usize, String)> {
    if let Some((t, line)) = step.time {
        if t > model.end_time {
            return Err((
                line,
                format!(
                    "its `time` = {t} s: after the run's end, {} s; admissible is 0 to {} s",
                    model.end_time, model.end_time
                ),
            ));
        }
    }
    if let Some((node, line)) = step.node {
        let faces = (model.interfaces.iter().map(|i| &i.faces))
            .chain(model.contacts.iter().map(|c| &c.faces));
        let mut nodes: Vec<u32> = faces
            .filter_map(|f| model.mesh.face_sets.get(f))
            .flatten()
            .flatten()
            .copied()
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        if nodes.binary_search(&node).is_err() {
            let range = match (nodes.first(), nodes.last()) {
                (Some(a), Some(b)) => format!(
                    "admissible are the {} nodes of the interface and contact faces ({a} to {b})",
                    nodes.len()
                ),
                _ => "the scene has no interface or contact face to inspect".to_string(),
            };
            return Err((
                line,
                format!("its `node` = {node}: not a node of an interface or contact face; {range}"),
            ));
        }
    }
    Ok(())
}

/// The step `n` of a link (1-based) as an index, or what is admissible.
pub fn step_index(lesson: &Lesson, n: usize) -> Result<usize, String> {
    if (1..=lesson.steps.len()).contains(&n) {
        Ok(n - 1)
    } else {
        Err(format!(
            "{}: no step {n}: the lesson has steps 1 to {}",
            lesson.file,
            lesson.steps.len()
        ))
    }
}

/// The lesson `name` (a shipped one) or, natively, the lesson file at `name` (a path ending in
/// `.md`), loaded and checked.
pub fn find(name: &str) -> Result<Lesson, String> {
    #[cfg(not(target_arch = "wasm32"))]
    if name.ends_with(".md") {
        let text = std::fs::read_to_string(name)
            .map_err(|e| format!("{name}: cannot read the lesson: {e}"))?;
        return load(&text, name).map_err(|e| e.to_string());
    }
    let text = shipped(name)?;
    load(text, &format!("lessons/{name}.md")).map_err(|e| e.to_string())
}
