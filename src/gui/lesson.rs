//! Lessons: a scene, a text and steps a class follows in the explorer (native and page). A lesson
//! is a Markdown file (`lessons/NAME.md`): TOML front matter between two `+++` lines (`title`,
//! `scene`, optional `summary`), an introduction, then one `## ` heading per step. A step's
//! text is Markdown; one fenced block with the info string `step` holds its actions in TOML:
//! `set` (scene overrides, `key.path=value` as `run --set` takes them), `run`, `plot` (the plot to
//! look at) and a question (`question`, `result`, `answer`, `tolerance`, `explain`): the student's
//! prediction is compared with the named result of the step's run. The format is documented in
//! `docs/src/guide/lessons.md`.
//!
//! [`load`] parses a lesson and checks it against its scene: every step's overrides (those of
//! the steps before it included, since they accumulate) must load the scene as `run --set`
//! would. Every error names the file, the line, the key or value and what is admissible.
//! No egui here: the panel is `lesson_view.rs`.

use super::history::HistoryRow;
use serde::Deserialize;
use std::fmt;
use std::ops::Range;

/// The lessons shipped with the explorer (the page has no files): (name, text of
/// `lessons/NAME.md`), in their teaching order. A test checks that the folder holds these
/// files and no other.
pub const LESSONS: &[(&str, &str)] = &[
    (
        "cohesive_law",
        include_str!("../../lessons/cohesive_law.md"),
    ),
    ("pull_off", include_str!("../../lessons/pull_off.md")),
    ("peel", include_str!("../../lessons/peel.md")),
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

/// A result of a run a question compares a prediction with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunResult {
    PeakForce,
    LateForce,
    Dissipated,
    FirstDamage,
    FullRupture,
    Ruptured,
}

/// Each result: (key in lesson files, its label, its unit, what it is).
pub const RESULTS: &[(RunResult, &str, &str, &str, &str)] = &[
    (
        RunResult::PeakForce,
        "peak_force",
        "peak force",
        "N",
        "the largest |reaction| of the first prescribed displacement until the glue has torn",
    ),
    (
        RunResult::LateForce,
        "late_force",
        "force over the last third",
        "N",
        "the magnitude of the reaction on the first prescribed displacement's faces (every \
         component prescribed there), averaged over time over the last third of the run",
    ),
    (
        RunResult::Dissipated,
        "dissipated_energy",
        "energy dissipated by damage",
        "J",
        "the glue's damage dissipation D at the end of the run",
    ),
    (
        RunResult::FirstDamage,
        "time_first_damage",
        "time of first damage",
        "s",
        "when the first glued node started to damage",
    ),
    (
        RunResult::FullRupture,
        "time_full_rupture",
        "time of full rupture",
        "s",
        "when the last glued node ruptured",
    ),
    (
        RunResult::Ruptured,
        "ruptured_nodes",
        "ruptured nodes",
        "",
        "the glued nodes ruptured at the end of the run",
    ),
];

impl RunResult {
    fn entry(
        self,
    ) -> &'static (
        RunResult,
        &'static str,
        &'static str,
        &'static str,
        &'static str,
    ) {
        RESULTS
            .iter()
            .find(|r| r.0 == self)
            .expect("every result is listed")
    }

    /// Its key in lesson files.
    pub fn key(self) -> &'static str {
        self.entry().1
    }

    /// What the explorer calls it.
    pub fn label(self) -> &'static str {
        self.entry().2
    }

    /// Its unit ("" for a count).
    pub fn unit(self) -> &'static str {
        self.entry().3
    }

    /// The result named `key`, or what is admissible.
    pub fn from_key(key: &str) -> Result<RunResult, String> {
        RESULTS
            .iter()
            .find(|r| r.1 == key)
            .map(|r| r.0)
            .ok_or_else(|| {
                let keys: Vec<&str> = RESULTS.iter().map(|r| r.1).collect();
                format!("unknown result `{key}`: admissible are {}", keys.join(", "))
            })
    }

    /// Its value in a finished run, if the run has one (a run that never ruptured has no time
    /// of full rupture).
    pub fn value(self, row: &HistoryRow) -> Option<f64> {
        match self {
            RunResult::PeakForce => row.peak_force,
            RunResult::LateForce => late_force(row),
            RunResult::Dissipated => Some(row.damage_dissipated),
            RunResult::FirstDamage => row.time_first_damage,
            RunResult::FullRupture => row.time_full_rupture,
            RunResult::Ruptured => Some(row.counts.ruptured as f64),
        }
        .filter(|v| v.is_finite())
    }
}

/// The time average (trapezoids over the samples, which need not be evenly spaced) of the
/// force on the pulled faces over the last third of the run.
fn late_force(row: &HistoryRow) -> Option<f64> {
    let from = row.simulated_time * 2.0 / 3.0;
    let points: Vec<[f64; 2]> = (row.curve.points.iter())
        .filter(|p| p.t >= from && p.force.is_finite())
        .map(|p| [p.t, p.force])
        .collect();
    let span = points.last()?[0] - points.first()?[0];
    if !(span > 0.0) {
        return None;
    }
    let area: f64 = (points.windows(2))
        .map(|w| 0.5 * (w[0][1] + w[1][1]) * (w[1][0] - w[0][0]))
        .sum();
    Some(area / span)
}

/// A plot a step may ask the student to look at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotName {
    Law,
    Traction,
    Friction,
    States,
    Force,
}

/// Each plot: (key in lesson files, the plot's title in the explorer).
pub const PLOTS: &[(PlotName, &str, &str)] = &[
    (PlotName::Law, "law", "stiffness g_N(α)"),
    (PlotName::Traction, "traction", "traction T(δ)"),
    (PlotName::Friction, "friction", "friction μ(α)"),
    (PlotName::States, "states", "interface nodes by state"),
    (PlotName::Force, "force", "force on the pulled faces"),
];

impl PlotName {
    /// Its key in lesson files.
    pub fn key(self) -> &'static str {
        PLOTS.iter().find(|p| p.0 == self).map_or("", |p| p.1)
    }

    /// The title of the plot in the explorer.
    pub fn title(self) -> &'static str {
        PLOTS.iter().find(|p| p.0 == self).map_or("", |p| p.2)
    }

    fn from_key(key: &str) -> Result<PlotName, String> {
        PLOTS
            .iter()
            .find(|p| p.1 == key)
            .map(|p| p.0)
            .ok_or_else(|| {
                let keys: Vec<&str> = PLOTS.iter().map(|p| p.1).collect();
                format!("unknown plot `{key}`: admissible are {}", keys.join(", "))
            })
    }
}

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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Front {
    title: String,
    scene: String,
    #[serde(default)]
    summary: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStep {
    #[serde(default)]
    set: Vec<toml::Spanned<String>>,
    #[serde(default)]
    run: bool,
    plot: Option<toml::Spanned<String>>,
    question: Option<String>,
    result: Option<toml::Spanned<String>>,
    answer: Option<toml::Spanned<f64>>,
    tolerance: Option<toml::Spanned<f64>>,
    #[serde(default)]
    explain: String,
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

/// Line (1-based) of byte `offset` of `text`.
fn line_of(text: &str, offset: usize) -> usize {
    1 + text[..offset.min(text.len())].matches('\n').count()
}

/// Parses a lesson (front matter, steps and their blocks) without loading its scene.
pub fn parse(text: &str, file: &str) -> Result<Lesson, LessonError> {
    let err = |line: Option<usize>, message: String| LessonError {
        file: file.to_string(),
        line,
        message,
    };
    let lines: Vec<&str> = text.lines().collect();
    if lines.first().map(|l| l.trim_end()) != Some("+++") {
        return Err(err(
            Some(1),
            "a lesson starts with its front matter: a line `+++`, the TOML keys title, scene \
             (and summary), and a closing `+++`"
                .into(),
        ));
    }
    let close = (lines.iter().skip(1).position(|l| l.trim_end() == "+++"))
        .map(|i| i + 1)
        .ok_or_else(|| err(Some(1), "the front matter has no closing `+++` line".into()))?;
    let front_text = lines[1..close].join("\n");
    let front: Front = toml::from_str(&front_text).map_err(|e| {
        let line = e.span().map(|s| 1 + line_of(&front_text, s.start));
        err(line, format!("front matter: {}", e.message()))
    })?;
    let name = std::path::Path::new(file)
        .file_stem()
        .map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned());
    let mut lesson = Lesson {
        name,
        file: file.to_string(),
        title: front.title,
        summary: front.summary,
        scene: scene_path(&front.scene),
        intro: String::new(),
        steps: vec![],
    };
    // Sections: the introduction, then one per `## ` heading (outside fenced blocks).
    let mut sections: Vec<(usize, String, Vec<usize>)> = vec![(close + 1, String::new(), vec![])];
    let mut fenced = false;
    for (i, line) in lines.iter().enumerate().skip(close + 1) {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if !fenced && line.starts_with("## ") {
            sections.push((i, line[3..].trim().to_string(), vec![]));
        } else {
            sections.last_mut().expect("one section").2.push(i);
        }
    }
    if fenced {
        return Err(err(None, "a fenced block (```) is not closed".into()));
    }
    for (k, (heading, title, body)) in sections.into_iter().enumerate() {
        let (md, block) = split_block(&lines, &body).map_err(|(l, m)| err(Some(l + 1), m))?;
        if k == 0 {
            if let Some((l, _)) = block {
                return Err(err(
                    Some(l + 1),
                    "a `step` block before the first step: put it under a `## ` heading".into(),
                ));
            }
            lesson.intro = md;
            continue;
        }
        let mut step = Step {
            title,
            text: md,
            line: heading + 1,
            set: vec![],
            set_lines: vec![],
            run: false,
            plot: None,
            question: None,
        };
        if let Some((start, block)) = block {
            read_block(&mut step, &block, start + 2)
                .map_err(|(l, m)| err(Some(l), format!("step {} (“{}”): {m}", k, step.title)))?;
        }
        lesson.steps.push(step);
    }
    if lesson.steps.is_empty() {
        return Err(err(
            None,
            "the lesson has no step: each step starts with a `## ` heading".into(),
        ));
    }
    Ok(lesson)
}

/// A section's lines split into its Markdown and its `step` block (the line of its opening
/// fence, 0-based, and its text); at most one block per section.
type Split = (String, Option<(usize, String)>);

fn split_block(lines: &[&str], body: &[usize]) -> Result<Split, (usize, String)> {
    let mut md: Vec<&str> = vec![];
    let mut block: Option<(usize, Vec<&str>)> = None;
    let mut in_step = false;
    let mut in_other = false;
    for &i in body {
        let line = lines[i];
        let fence = line.trim_start().starts_with("```");
        if in_step {
            if fence {
                in_step = false;
            } else if let Some(b) = &mut block {
                b.1.push(line);
            }
            continue;
        }
        if fence && !in_other && line.trim_start().trim_start_matches('`').trim() == "step" {
            if block.is_some() {
                return Err((i, "a second `step` block: a step has at most one".into()));
            }
            block = Some((i, vec![]));
            in_step = true;
            continue;
        }
        if fence {
            in_other = !in_other;
        }
        md.push(line);
    }
    let text = md.join("\n").trim().to_string();
    Ok((text, block.map(|(i, b)| (i, b.join("\n")))))
}

/// Reads a step's block (its first line is line `first` of the file) into `step`; the error is
/// (the file's line, the reason).
fn read_block(step: &mut Step, block: &str, first: usize) -> Result<(), (usize, String)> {
    let at = |span: Range<usize>| first + line_of(block, span.start) - 1;
    let raw: RawStep = toml::from_str(block).map_err(|e| {
        let line = e.span().map_or(first, &at);
        (line, e.message().trim().to_string())
    })?;
    for s in &raw.set {
        let spec = s.get_ref();
        if !spec.contains('=') {
            return Err((
                at(s.span()),
                format!("set `{spec}`: expected `key.path=value`, as `run --set` takes it"),
            ));
        }
        step.set.push(spec.clone());
        step.set_lines.push(at(s.span()));
    }
    step.run = raw.run;
    if let Some(p) = &raw.plot {
        step.plot = Some(PlotName::from_key(p.get_ref()).map_err(|m| (at(p.span()), m))?);
    }
    let keys = [
        raw.result.as_ref().map(|r| r.span()),
        raw.answer.as_ref().map(|r| r.span()),
        raw.tolerance.as_ref().map(|r| r.span()),
    ];
    match (raw.question, raw.result, raw.answer, raw.tolerance) {
        (None, None, None, None) => {}
        (Some(text), Some(result), Some(answer), Some(tolerance)) => {
            let r = RunResult::from_key(result.get_ref()).map_err(|m| (at(result.span()), m))?;
            let a = *answer.get_ref();
            if !a.is_finite() {
                return Err((
                    at(answer.span()),
                    format!("answer = {a}: must be a finite number"),
                ));
            }
            let tol = *tolerance.get_ref();
            if !(tol > 0.0 && tol < 1.0) {
                return Err((
                    at(tolerance.span()),
                    format!(
                        "tolerance = {tol}: must be a relative tolerance in (0, 1), e.g. 0.05 \
                         for 5 %"
                    ),
                ));
            }
            step.question = Some(Question {
                text,
                result: r,
                answer: a,
                tolerance: tol,
                explain: raw.explain,
                line: at(answer.span()),
            });
        }
        _ => {
            let line = keys.into_iter().flatten().next().map_or(first, at);
            return Err((
                line,
                "a question needs all of question, result, answer and tolerance".into(),
            ));
        }
    }
    Ok(())
}

/// Checks a parsed lesson against its scene: the scene exists, and at every step the overrides
/// so far load it (as `run --set` would); the error names the line of the step's `set`.
pub fn check(lesson: &Lesson) -> Result<(), LessonError> {
    let err = |line: Option<usize>, message: String| LessonError {
        file: lesson.file.clone(),
        line,
        message,
    };
    super::settings::read_scene(&lesson.scene).map_err(|e| {
        let scenes: Vec<String> = super::list_scenes(std::path::Path::new("scenes"))
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
        if step.set.is_empty() && k > 0 {
            continue;
        }
        if let Err(e) = super::settings::open_scene_with(&lesson.scene, &lesson.sets_through(k)) {
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
                    super::settings::open_scene_with(&lesson.scene, &set).is_err()
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

/// `text` as it may stand in a URL's query (RFC 3986: letters, digits and `-._~` as they are,
/// every other byte percent-encoded).
pub fn url_encode(text: &str) -> String {
    let mut out = String::new();
    for b in text.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// The query of a link that opens `scene` (`scenes/NAME.toml`: `NAME`) with the overrides
/// `set` (and starts the run with `run`).
pub fn scene_query(scene: &str, set: &[String], run: bool) -> String {
    let name = scene
        .strip_prefix("scenes/")
        .and_then(|s| s.strip_suffix(".toml"))
        .unwrap_or(scene);
    let mut q = format!("?scene={}", url_encode(name));
    for s in set {
        q.push_str("&set=");
        q.push_str(&url_encode(s));
    }
    if run {
        q.push_str("&run=1");
    }
    q
}

/// The query of a link to step `k` (0-based) of lesson `name`.
pub fn lesson_query(name: &str, k: usize) -> String {
    format!("?lesson={}&step={}", url_encode(name), k + 1)
}

/// The overrides that turn the document `base` into `edited` (both TOML texts): one
/// `key.path=value` per value that differs, arrays of tables of the same length entered by
/// index, any other array (and a table or array of another length) given whole. Keys that
/// `edited` lacks are not listed (an override cannot remove a key).
pub fn changed_keys(base: &str, edited: &str) -> Result<Vec<String>, String> {
    let base: toml::Table = base.parse().map_err(|e| format!("{e}"))?;
    let edited: toml::Table = edited.parse().map_err(|e| format!("{e}"))?;
    let mut out = vec![];
    diff_tables(&base, &edited, "", &mut out);
    out.sort();
    Ok(out)
}

fn diff_tables(base: &toml::Table, edited: &toml::Table, prefix: &str, out: &mut Vec<String>) {
    for (key, value) in edited {
        let path = format!("{prefix}{key}");
        diff_values(base.get(key), value, &path, out);
    }
}

fn diff_values(
    base: Option<&toml::Value>,
    edited: &toml::Value,
    path: &str,
    out: &mut Vec<String>,
) {
    use toml::Value;
    match (base, edited) {
        (Some(b), e) if b == e => {}
        (Some(Value::Table(b)), Value::Table(e)) => diff_tables(b, e, &format!("{path}."), out),
        (Some(Value::Array(b)), Value::Array(e))
            if b.len() == e.len() && b.iter().chain(e).all(Value::is_table) =>
        {
            for (i, (bi, ei)) in b.iter().zip(e).enumerate() {
                diff_values(Some(bi), ei, &format!("{path}.{i}"), out);
            }
        }
        (_, e) => out.push(format!("{path}={}", inline(e))),
    }
}

/// A TOML value on one line (tables inline).
fn inline(v: &toml::Value) -> String {
    match v {
        toml::Value::Table(t) => {
            let items: Vec<String> = t
                .iter()
                .map(|(k, v)| format!("{k} = {}", inline(v)))
                .collect();
            format!("{{ {} }}", items.join(", "))
        }
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(inline).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

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

/// Checks an opening before the window opens (`gui --lesson`, `--step`, `--set`): the lesson
/// loads and has the step, or the overrides load `scene` (the default scene without one).
pub fn check_opening(scene: Option<&str>, o: &Opening) -> Result<(), String> {
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
        let default = super::Settings::default().scene;
        super::settings::open_scene_with(scene.unwrap_or(&default), &o.set)?;
    }
    Ok(())
}

impl super::App {
    /// Opens what `o` asks for; the error says why not (also noted for the window).
    pub fn open(&mut self, o: &Opening) -> Result<(), String> {
        let r = match &o.lesson {
            Some(name) => find(name).and_then(|l| {
                let k = step_index(&l, o.step.max(1))?;
                self.open_lesson(l, k);
                Ok(())
            }),
            None if !o.set.is_empty() => self.apply_set(&self.settings.scene.clone(), &o.set),
            None => Ok(()),
        };
        if let Err(e) = &r {
            self.notes.push(e.clone());
        }
        r
    }

    /// The settings of `scene` with the overrides `set`.
    pub fn apply_set(&mut self, scene: &str, set: &[String]) -> Result<(), String> {
        let s = super::settings::open_scene_with(scene, set)?;
        self.settings.scene = scene.to_string();
        self.settings.set = set.to_vec();
        self.settings.take_scene(&s);
        self.validation = None;
        Ok(())
    }

    /// Opens `lesson` at step `k` (0-based).
    pub fn open_lesson(&mut self, lesson: Lesson, k: usize) {
        self.lesson = Some(LessonState::new(lesson, 0));
        self.go_to_step(k);
    }

    /// Closes the lesson; the settings stay.
    pub fn close_lesson(&mut self) {
        self.lesson = None;
    }

    /// Opens step `k` of the lesson: the scene with the overrides of the steps up to it; its run
    /// starts if it has one and no question (a question's run starts with the prediction).
    pub fn go_to_step(&mut self, k: usize) {
        let Some(state) = &mut self.lesson else {
            return;
        };
        state.step = k.min(state.lesson.steps.len() - 1);
        state.prediction.clear();
        state.predicted = None;
        state.run = None;
        let (scene, set) = (
            state.lesson.scene.clone(),
            state.lesson.sets_through(state.step),
        );
        let auto = state.current().run && state.current().question.is_none();
        if let Err(e) = self.apply_set(&scene, &set) {
            self.notes.push(e);
            return;
        }
        if auto {
            self.run_step();
        }
    }

    /// Starts the open step's run, with the prediction field's value if it reads as a number.
    pub fn run_step(&mut self) {
        self.start();
        let id = self.job.as_ref().and(self.curve_run);
        if let Some(state) = &mut self.lesson {
            state.predicted = state
                .prediction
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|p| p.is_finite());
            state.run = id;
        }
    }

    /// The settings as the scene file gives them (no overrides, no edits).
    fn file_settings(&self) -> Result<super::Settings, String> {
        let mut base = self.settings.clone();
        base.set.clear();
        base.take_scene(&super::settings::open_scene(&base.scene)?);
        Ok(base)
    }

    /// Every key the settings change in the scene file, as overrides (`key.path=value`).
    pub fn changed_keys(&self) -> Result<Vec<String>, String> {
        changed_keys(
            &self.file_settings()?.scene_text()?,
            &self.settings.scene_text()?,
        )
    }

    /// The query of a link to what the explorer shows: the lesson's step while its settings are
    /// the step's, else the scene and every changed key.
    pub fn link_query(&self) -> Result<String, String> {
        if let Some(state) = &self.lesson {
            let mut step = self.settings.clone();
            step.set = state.lesson.sets_through(state.step);
            if let Ok(s) = super::settings::open_scene_with(&state.lesson.scene, &step.set) {
                step.take_scene(&s);
                if step.scene_text() == self.settings.scene_text() {
                    return Ok(lesson_query(&state.lesson.name, state.step));
                }
            }
        }
        Ok(scene_query(
            &self.settings.scene,
            &self.changed_keys()?,
            false,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"+++
title = "A test"
scene = "pull_off"
summary = "one step"
+++
Intro **text**.

## First step

Read this.

```step
set = ["mesh.cells=[2,2,2]", "end_time=0.2"]
run = true
plot = "traction"
```

## Second step

```step
question = "How much?"
result = "dissipated_energy"
answer = 2000.0
tolerance = 0.1
explain = "G_c times the area."
```
"#;

    fn err(text: &str) -> LessonError {
        load(text, "lessons/bad.md").unwrap_err()
    }

    /// A lesson with two steps: the front matter, the introduction, each step's text without
    /// its block, the overrides accumulated, the question.
    #[test]
    fn a_lesson_parses() {
        let l = load(GOOD, "lessons/good.md").unwrap();
        assert_eq!((l.name.as_str(), l.title.as_str()), ("good", "A test"));
        assert_eq!(l.scene, "scenes/pull_off.toml");
        assert_eq!(l.intro, "Intro **text**.");
        assert_eq!(l.steps.len(), 2);
        assert_eq!(l.steps[0].text, "Read this.");
        assert_eq!(l.steps[0].line, 8);
        assert!(l.steps[0].run);
        assert_eq!(l.steps[0].plot, Some(PlotName::Traction));
        assert_eq!(l.sets_through(1), ["mesh.cells=[2,2,2]", "end_time=0.2"]);
        let mut later = l.clone();
        later.steps[1].set = vec!["end_time=0.3".into()];
        assert_eq!(
            later.sets_through(1),
            ["mesh.cells=[2,2,2]", "end_time=0.3"]
        );
        let q = l.steps[1].question.as_ref().unwrap();
        assert_eq!(
            (q.result, q.answer, q.tolerance),
            (RunResult::Dissipated, 2000.0, 0.1)
        );
        assert_eq!(q.line, 23);
        assert!(q.accepts(2150.0, 2000.0) && !q.accepts(2250.0, 2000.0));
    }

    /// Each kind of error names the file, the line, the key or value and what is admissible.
    #[test]
    fn errors_name_the_file_the_line_and_what_is_admissible() {
        let e = err(&GOOD.replace("scene = \"pull_off\"", "scene = \"pul_off\""));
        let m = e.to_string();
        assert!(m.starts_with("lessons/bad.md: scene = \"pul_off\""), "{m}");
        assert!(m.contains("admissible are") && m.contains("peel"), "{m}");

        let e = err(&GOOD.replace("summary =", "sumary ="));
        assert_eq!(e.line, Some(4), "{e}");
        assert!(
            e.message.contains("unknown field `sumary`") && e.message.contains("`summary`"),
            "{e}"
        );

        let e = err(&GOOD.replace("run = true", "runs = true"));
        assert_eq!(e.line, Some(14), "{e}");
        assert!(
            e.message.contains("unknown field `runs`") && e.message.contains("`run`"),
            "{e}"
        );

        let e = err(&GOOD.replace("end_time=0.2", "end_time=-1"));
        let m = e.to_string();
        assert!(m.starts_with("lessons/bad.md:13: step 1"), "{m}");
        assert!(m.contains("end_time") && m.contains("-1"), "{m}");

        let e = err(&GOOD.replace("end_time=0.2", "interface.law.u_rr=0.2"));
        assert!(e.to_string().contains("u_rr"), "{e}");

        let e = err(&GOOD.replace("\"end_time=0.2\"", "\"end_time\""));
        assert_eq!(e.line, Some(13), "{e}");
        assert!(
            e.message
                .contains("set `end_time`: expected `key.path=value`"),
            "{e}"
        );

        let e = err(&GOOD.replace("dissipated_energy", "dissipation"));
        assert_eq!(e.line, Some(22), "{e}");
        assert!(
            e.message.contains("unknown result `dissipation`") && e.message.contains("peak_force"),
            "{e}"
        );

        let e = err(&GOOD.replace("\"traction\"", "\"tractions\""));
        assert_eq!(e.line, Some(15), "{e}");
        assert!(
            e.message.contains("unknown plot `tractions`") && e.message.contains("law"),
            "{e}"
        );

        let e = err(&GOOD.replace("tolerance = 0.1", "tolerance = 5"));
        assert_eq!(e.line, Some(24), "{e}");
        assert!(e.message.contains("tolerance = 5"), "{e}");

        let e = err(&GOOD.replace("answer = 2000.0\n", ""));
        assert!(
            e.message
                .contains("needs all of question, result, answer and tolerance"),
            "{e}"
        );

        let e = err(&GOOD.replace("## Second step", "Second step"));
        assert!(e.message.contains("second `step` block"), "{e}");

        let e = err(&GOOD.replacen("+++\n", "", 1));
        assert_eq!(e.line, Some(1), "{e}");
        let e = err(GOOD.split("## First").next().unwrap());
        assert!(e.message.contains("no step"), "{e}");

        let l = load(GOOD, "lessons/good.md").unwrap();
        let e = step_index(&l, 3).unwrap_err();
        assert!(e.contains("no step 3") && e.contains("steps 1 to 2"), "{e}");
        assert_eq!(step_index(&l, 2), Ok(1));
    }

    /// Every shipped lesson loads, and `lessons/` holds exactly the shipped ones.
    #[test]
    fn the_shipped_lessons_load_and_are_the_folder_s() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons");
        let mut files: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .filter_map(|e| {
                e.file_name()
                    .to_str()?
                    .strip_suffix(".md")
                    .map(str::to_string)
            })
            .collect();
        files.sort();
        let mut names: Vec<String> = LESSONS.iter().map(|l| l.0.to_string()).collect();
        names.sort();
        assert_eq!(files, names);
        for (name, text) in LESSONS {
            let l = load(text, &format!("lessons/{name}.md")).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(l.name, *name);
            assert_eq!(
                std::fs::read_to_string(dir.join(format!("{name}.md"))).unwrap(),
                *text
            );
        }
    }

    /// Links: a scene with overrides, percent-encoded; the overrides between two documents.
    #[test]
    fn links_and_changed_keys() {
        let q = scene_query(
            "scenes/peel.toml",
            &["interface.law.u_r=0.004".into()],
            true,
        );
        assert_eq!(q, "?scene=peel&set=interface.law.u_r%3D0.004&run=1");
        assert_eq!(lesson_query("peel", 1), "?lesson=peel&step=2");
        let base = "end_time = 1.0\n[a]\nb = 2\n[[d]]\nx = 1\n[[d]]\nx = 2\n";
        let edited = "end_time = 2.0\n[a]\nb = 2\nc = [1, 2]\n[[d]]\nx = 1\n[[d]]\nx = 3\n";
        assert_eq!(
            changed_keys(base, edited).unwrap(),
            ["a.c=[1, 2]", "d.1.x=3", "end_time=2.0"]
        );
        let grown = format!("{base}[[d]]\nx = 4\n");
        assert_eq!(
            changed_keys(base, &grown).unwrap(),
            ["d=[{ x = 1 }, { x = 2 }, { x = 4 }]"]
        );
    }
}
