//! The lesson panel (egui): pick a lesson, read its step (the Markdown drawn with labels:
//! headings, paragraphs, lists, bold, italics, code), Back / Next, the prediction field and
//! the run's answer; *copy link*. The logic is in [`super::lesson`].

use super::lesson::{find, PlotName, Verdict, LESSONS};
use super::App;
use egui::text::LayoutJob;
use egui::{Color32, FontId, RichText, TextFormat};

/// Where a link's query is appended natively (the page uses its own address): the site as
/// `python3 -m http.server … 8000` serves it (docs/src/guide/web-page.md).
pub const LOCAL_SITE: &str = "http://127.0.0.1:8000/";

/// Draws Markdown: `#` headings, paragraphs, `- ` list items, `**bold**`, `*italics*`,
/// `` `code` `` and `[text](address)` (its text); fenced blocks as code.
pub(super) fn markdown(ui: &mut egui::Ui, text: &str) {
    let mut paragraph = String::new();
    let mut code = false;
    let flush = |ui: &mut egui::Ui, p: &mut String| {
        if !p.trim().is_empty() {
            ui.label(inline(ui, p.trim(), 14.0));
        }
        p.clear();
    };
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            flush(ui, &mut paragraph);
            code = !code;
            continue;
        }
        if code {
            ui.label(RichText::new(line).monospace());
            continue;
        }
        let t = line.trim();
        if t.is_empty() {
            flush(ui, &mut paragraph);
        } else if let Some(h) = t.strip_prefix('#') {
            flush(ui, &mut paragraph);
            let level = 1 + h.chars().take_while(|&c| c == '#').count();
            let size = if level <= 2 { 20.0 } else { 16.0 };
            ui.label(inline(ui, h.trim_start_matches('#').trim(), size));
        } else if let Some(item) = t.strip_prefix("- ").or_else(|| t.strip_prefix("* ")) {
            flush(ui, &mut paragraph);
            paragraph.push_str("•  ");
            paragraph.push_str(item);
        } else {
            if !paragraph.is_empty() {
                paragraph.push(' ');
            }
            paragraph.push_str(t);
        }
    }
    flush(ui, &mut paragraph);
}

/// A line of Markdown with its inline marks, at `size` points.
fn inline(ui: &egui::Ui, text: &str, size: f32) -> LayoutJob {
    let normal = ui.visuals().text_color();
    let strong = ui.visuals().strong_text_color();
    let mut job = LayoutJob::default();
    job.wrap.max_width = ui.available_width();
    let (mut bold, mut italic, mut code) = (false, false, false);
    let mut run = String::new();
    let push = |job: &mut LayoutJob, run: &mut String, bold: bool, italic: bool, code: bool| {
        if run.is_empty() {
            return;
        }
        let format = TextFormat {
            font_id: if code {
                FontId::monospace(size - 1.0)
            } else {
                FontId::proportional(size)
            },
            color: if bold { strong } else { normal },
            italics: italic,
            background: if code {
                ui.visuals().code_bg_color
            } else {
                Color32::TRANSPARENT
            },
            ..Default::default()
        };
        job.append(run, 0.0, format);
        run.clear();
    };
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '`' {
            push(&mut job, &mut run, bold, italic, code);
            code = !code;
        } else if code {
            run.push(c);
        } else if c == '*' && chars.get(i + 1) == Some(&'*') {
            push(&mut job, &mut run, bold, italic, code);
            bold = !bold;
            i += 1;
        } else if c == '*' || (c == '_' && (i == 0 || !chars[i - 1].is_alphanumeric())) {
            push(&mut job, &mut run, bold, italic, code);
            italic = !italic;
        } else if c == '[' {
            // [text](address): the text only.
            let rest: String = chars[i..].iter().collect();
            if let Some((label, after)) = rest[1..].split_once("](") {
                if let Some(end) = after.find(')') {
                    run.push_str(label);
                    i += 1 + label.chars().count() + 2 + after[..end].chars().count() + 1;
                    continue;
                }
            }
            run.push(c);
        } else {
            run.push(c);
        }
        i += 1;
    }
    push(&mut job, &mut run, bold, italic, code);
    job
}

impl App {
    /// The lesson picker (in the scene section).
    pub(super) fn lesson_picker_ui(&mut self, ui: &mut egui::Ui) {
        let current = self.lesson.as_ref().map(|l| l.lesson.name.clone());
        let mut pick = None;
        egui::ComboBox::from_label("lesson")
            .selected_text(current.clone().unwrap_or_else(|| "(none)".into()))
            .show_ui(ui, |ui| {
                if ui.selectable_label(current.is_none(), "(none)").clicked() {
                    pick = Some(None);
                }
                for (name, _) in LESSONS {
                    if ui
                        .selectable_label(current.as_deref() == Some(name), *name)
                        .clicked()
                    {
                        pick = Some(Some(name.to_string()));
                    }
                }
            });
        match pick {
            Some(None) => self.close_lesson(),
            Some(Some(name)) => match find(&name) {
                Ok(l) => self.open_lesson(l, 0),
                Err(e) => self.notes.push(e),
            },
            None => {}
        }
    }

    /// The lesson panel: the step's text, Back / Next, the question and its answer.
    pub(super) fn lesson_ui(&mut self, ui: &mut egui::Ui) {
        let Some(state) = &self.lesson else {
            return;
        };
        let (k, n) = (state.step, state.lesson.steps.len());
        let step = state.current().clone();
        let lesson = state.lesson.clone();
        ui.horizontal(|ui| {
            ui.heading(&lesson.title);
            if ui.small_button("close").clicked() {
                self.close_lesson();
            }
        });
        if self.lesson.is_none() {
            return;
        }
        let mut go = None;
        ui.horizontal(|ui| {
            if ui
                .add_enabled(k > 0, egui::Button::new("<< Back"))
                .clicked()
            {
                go = Some(k - 1);
            }
            ui.label(format!("step {} of {n}", k + 1));
            if ui
                .add_enabled(k + 1 < n, egui::Button::new("Next >>"))
                .clicked()
            {
                go = Some(k + 1);
            }
        });
        if let Some(k) = go {
            self.go_to_step(k);
            return;
        }
        ui.separator();
        if k == 0 && !lesson.intro.is_empty() {
            markdown(ui, &lesson.intro);
            ui.separator();
        }
        ui.label(RichText::new(&step.title).size(18.0).strong());
        markdown(ui, &step.text);
        if !step.set.is_empty() {
            ui.label(RichText::new(format!("This step sets: {}", step.set.join(", "))).small());
        }
        if let Some(p) = step.plot {
            ui.label(
                RichText::new(format!("Look at the plot “{}”.", p.title()))
                    .color(HIGHLIGHT)
                    .strong(),
            );
        }
        let running = self.job.is_some();
        match &step.question {
            Some(q) => {
                ui.separator();
                markdown(ui, &format!("**Question.** {}", q.text));
                let unit = q.result.unit();
                let mut start = false;
                if let Some(state) = &mut self.lesson {
                    ui.horizontal(|ui| {
                        let label = ui.label("your prediction");
                        ui.add(
                            egui::TextEdit::singleline(&mut state.prediction).desired_width(90.0),
                        )
                        .labelled_by(label.id);
                        ui.label(unit);
                        let ok = state
                            .prediction
                            .trim()
                            .parse::<f64>()
                            .is_ok_and(f64::is_finite);
                        start = ui
                            .add_enabled(ok && !running, egui::Button::new("Run and compare"))
                            .on_disabled_hover_text(
                                "write a number first (a run must not be going on)",
                            )
                            .clicked();
                    });
                }
                if start {
                    self.run_step();
                }
                let verdict = self.lesson.as_ref().map(|s| s.verdict(&self.history));
                match verdict {
                    Some(Verdict::Value { value, right }) => {
                        let label = q.result.label();
                        ui.label(format!("The run gives {label} = {value:.4} {unit}."));
                        match right {
                            Some(true) => ui.label(
                                RichText::new(format!(
                                    "Your prediction is within {:.0} % of it: right.",
                                    100.0 * q.tolerance
                                ))
                                .color(Color32::from_rgb(46, 160, 67)),
                            ),
                            Some(false) => ui.label(
                                RichText::new(format!(
                                    "Your prediction is more than {:.0} % away from it.",
                                    100.0 * q.tolerance
                                ))
                                .color(Color32::from_rgb(208, 2, 27)),
                            ),
                            None => ui.label(""),
                        };
                        if !q.explain.is_empty() {
                            markdown(ui, &q.explain);
                        }
                    }
                    Some(Verdict::NoValue(why)) => {
                        ui.label(RichText::new(why).color(Color32::from_rgb(208, 2, 27)));
                    }
                    _ if running => {
                        ui.label("running…");
                    }
                    _ => {}
                }
            }
            None if step.run && !running && ui.button("Run this step again").clicked() => {
                self.run_step();
            }
            None => {}
        }
    }

    /// *copy link*: the link to what the explorer shows, copied and shown.
    pub(super) fn link_ui(&mut self, ui: &mut egui::Ui) {
        if ui
            .button("copy link")
            .on_hover_text(
                "a link that opens this lesson step, or this scene with every changed key",
            )
            .clicked()
        {
            match self.link_query() {
                Ok(q) => {
                    let url = format!("{}{q}", site_base());
                    ui.ctx().copy_text(url.clone());
                    self.notes.push(format!("link copied: {url}"));
                    #[cfg(not(target_arch = "wasm32"))]
                    println!("{url}");
                }
                Err(e) => self.notes.push(format!("no link: {e}")),
            }
        }
    }

    /// *full page*, in the embeddable view: the full page of what the frame shows (the link of
    /// *copy link*), opened in a new tab.
    pub(super) fn full_page_ui(&mut self, ui: &mut egui::Ui) {
        if ui
            .button("full page ↗")
            .on_hover_text("open this lesson step or scene in the full explorer, in a new tab")
            .clicked()
        {
            match self.link_query() {
                Ok(q) => ui
                    .ctx()
                    .open_url(egui::OpenUrl::new_tab(format!("{}{q}", site_base()))),
                Err(e) => self.notes.push(format!("no link: {e}")),
            }
        }
    }

    /// The title of plot `p`, marked when the open step points at it.
    pub(super) fn plot_title(&self, p: PlotName, title: &str) -> egui::WidgetText {
        let marked = (self.lesson.as_ref()).is_some_and(|s| s.current().plot == Some(p));
        if marked {
            RichText::new(format!("» {title}"))
                .color(HIGHLIGHT)
                .strong()
                .into()
        } else {
            title.into()
        }
    }
}

/// The colour of what a step points at.
const HIGHLIGHT: Color32 = Color32::from_rgb(230, 150, 0);

/// The address links start with: the page's own (without its query), natively [`LOCAL_SITE`].
fn site_base() -> String {
    #[cfg(target_arch = "wasm32")]
    if let Some(w) = web_sys::window() {
        let l = w.location();
        if let (Ok(o), Ok(p)) = (l.origin(), l.pathname()) {
            return format!("{o}{p}");
        }
    }
    LOCAL_SITE.to_string()
}
