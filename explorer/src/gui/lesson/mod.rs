//! Lessons: a scene, a text and steps a class follows in the explorer (native and page). A lesson
//! is a Markdown file (`lessons/NAME.md`): TOML front matter between two `+++` lines (`title`,
//! `scene`, optional `summary`), an introduction, then one `## ` heading per step. A step's
//! text is Markdown; one fenced block with the info string `step` holds its actions in TOML:
//! `set` (scene overrides, `key.path=value` as `run --set` takes them), `run`, `plot` (the plot to
//! look at), `time` (where the 3-D view stops), `node` (the node inspected) and a question (`question`, `result`, `answer`, `tolerance`, `explain`): the student's
//! prediction is compared with the named result of the step's run. The format is documented in
//! `docs/src/guide/lessons.md`.
//!
//! [`load`] parses a lesson and checks it against its scene: every step's overrides (those of
//! the steps before it included, since they accumulate) must load the scene as `run --set`
//! would. Every error names the file, the line, the key or value and what is admissible.
//! No egui here: the panel is `lesson_view.rs`.

mod app;
mod format;
mod link;
mod parser;
mod progress;
mod results;
#[cfg(test)]
mod tests;

pub use format::{
    check, find, load, scene_path, shipped, step_index, Lesson, LessonError, Question, Step,
    LESSONS,
};
pub use link::{changed_keys, lesson_query, scene_query, url_encode};
pub use parser::parse;
pub use progress::{check_opening, LessonState, Opening, Verdict};
pub use results::{PlotName, RunResult, PLOTS, RESULTS};
