//! The parser of a lesson file: its front matter, its `## ` steps and their `step` blocks.

use super::{scene_path, Lesson, LessonError, PlotName, Question, RunResult, Step};
use serde::Deserialize;
use std::ops::Range;

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
    time: Option<toml::Spanned<f64>>,
    node: Option<toml::Spanned<i64>>,
    question: Option<String>,
    result: Option<toml::Spanned<String>>,
    answer: Option<toml::Spanned<f64>>,
    tolerance: Option<toml::Spanned<f64>>,
    #[serde(default)]
    explain: String,
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
            time: None,
            node: None,
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
    if let Some(t) = &raw.time {
        let v = *t.get_ref();
        if !(v.is_finite() && v >= 0.0) {
            return Err((
                at(t.span()),
                format!("time = {v}: must be a time of the run, ≥ 0 (seconds)"),
            ));
        }
        step.time = Some((v, at(t.span())));
    }
    if let Some(n) = &raw.node {
        let v = *n.get_ref();
        let node = u32::try_from(v).map_err(|_| {
            (
                at(n.span()),
                format!("node = {v}: must be a mesh node's number, 0 or more"),
            )
        })?;
        step.node = Some((node, at(n.span())));
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
