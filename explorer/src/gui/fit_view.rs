//! The measured curve's section of the explorer (egui): load a CSV file (a path natively, a
//! file dropped on the window in both), its points drawn over the compared runs' reaction
//! against imposed displacement; natively, the fit of the edited law's number parameters to it
//! ([`super::state::FitPanel`]): the free parameters and their bounds, the compared columns,
//! progress and Stop, the fitted values with σ, the curves, and "use the fitted values".

use super::App;
#[cfg(target_arch = "wasm32")]
use std::sync::{Arc, Mutex};

/// Files dropped on the page, read by the browser (asynchronously): name and text, or why not.
#[cfg(target_arch = "wasm32")]
pub type Inbox = Arc<Mutex<Vec<(String, Result<String, String>)>>>;

impl App {
    /// Takes the CSV files dropped on the window: the last one read becomes the measured curve.
    pub(super) fn take_dropped_files(&mut self, ctx: &egui::Context) {
        let files = ctx.input(|i| i.raw.dropped_files.clone());
        for file in files {
            let name = file.path().display().to_string();
            #[cfg(not(target_arch = "wasm32"))]
            match file.bytes().map(String::from_utf8) {
                Ok(Ok(text)) => {
                    let path = Some(file.path().to_path_buf()).filter(|p| p.is_file());
                    self.load_measured_text(&text, &name, path)
                }
                Ok(Err(_)) => self.notes.push(format!("{name}: not a text (UTF-8) file")),
                Err(e) => self.notes.push(format!("{name}: cannot read it: {e}")),
            }
            #[cfg(target_arch = "wasm32")]
            {
                let inbox = self.dropped.clone();
                let repaint = ctx.clone();
                wasm_bindgen_futures::spawn_local(async move {
                    let text = file.bytes_async().await.and_then(|b| {
                        String::from_utf8(b).map_err(|_| "not a text (UTF-8) file".to_string())
                    });
                    if let Ok(mut q) = inbox.lock() {
                        q.push((name, text));
                    }
                    repaint.request_repaint();
                });
            }
        }
        #[cfg(target_arch = "wasm32")]
        {
            let read: Vec<_> = self
                .dropped
                .lock()
                .map(|mut q| q.drain(..).collect())
                .unwrap_or_default();
            for (name, text) in read {
                match text {
                    Ok(t) => self.load_measured_text(&t, &name, None),
                    Err(e) => self.notes.push(format!("{name}: {e}")),
                }
            }
        }
    }

    /// The measured curve's section.
    pub(super) fn measured_ui(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Measured curve (CSV) and fit")
            .id_salt("measured")
            .default_open(self.measured.is_some())
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    #[cfg(not(target_arch = "wasm32"))]
                    {
                        ui.add(
                            egui::TextEdit::singleline(&mut self.measured_path)
                                .hint_text("data/pull_off_noisy.csv")
                                .desired_width(240.0),
                        );
                        if ui.button("load").clicked() {
                            let path = self.measured_path.clone();
                            self.load_measured(&path);
                        }
                    }
                    ui.label("or drop a CSV file on the window");
                    if self.measured.is_some() && ui.button("clear").clicked() {
                        self.measured = None;
                    }
                });
                let Some(m) = &self.measured else {
                    ui.label(
                        egui::RichText::new(
                            "Two columns with their units in the header, e.g. `u [mm], F [kN]` \
                             (as `decohesion fit` reads them); drawn over the reaction of the \
                             runs ticked for comparison.",
                        )
                        .small(),
                    );
                    return;
                };
                let c = &m.curve;
                let unit = |h: &crate::measured::Header| {
                    h.unit
                        .clone()
                        .map_or("no unit: SI".into(), |u| format!("[{u}]"))
                };
                ui.label(format!(
                    "{}: {} points, x `{}` {}, y `{}` {}",
                    c.file,
                    c.x.len(),
                    c.x_header.name,
                    unit(&c.x_header),
                    c.y_header.name,
                    unit(&c.y_header)
                ));
                if let Err(e) = &m.si {
                    ui.label(egui::RichText::new(e).small());
                }
                #[cfg(not(target_arch = "wasm32"))]
                self.fit_ui(ui);
            });
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl App {
    /// The fit's settings, progress and result.
    fn fit_ui(&mut self, ui: &mut egui::Ui) {
        if self.poll_fit() {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        }
        let Some(spec) = self.settings.law.spec() else {
            return;
        };
        let numbers = spec
            .params
            .iter()
            .filter(|p| matches!(p.kind, crate::interface::family::ParamKind::Number(_)));
        let keys: std::collections::BTreeSet<&str> = numbers.map(|p| p.key).collect();
        if !keys
            .iter()
            .copied()
            .eq(self.fit.free.keys().map(String::as_str))
        {
            self.fit_defaults();
        }
        ui.label(format!(
            "Fit the `{}` law of interface {} (tick the free parameters; bounds in the \
             parameter's unit):",
            spec.key, self.settings.interface
        ));
        let idle = self.fit.job.is_none();
        egui::Grid::new("fit_free").num_columns(4).show(ui, |ui| {
            for p in spec.params {
                let Some(f) = self.fit.free.get_mut(p.key) else {
                    continue;
                };
                ui.add_enabled(idle, egui::Checkbox::new(&mut f.on, p.symbol))
                    .on_hover_text(p.meaning);
                ui.label(format!("[{}]", p.unit));
                for v in [&mut f.lo, &mut f.hi] {
                    let speed = (0.01 * v.abs()).max(1e-12);
                    ui.add_enabled(
                        idle && f.on,
                        egui::DragValue::new(v)
                            .speed(speed)
                            .custom_formatter(|x, _| format!("{x:.4e}")),
                    );
                }
                ui.end_row();
            }
        });
        ui.horizontal(|ui| {
            ui.label("x column");
            ui.add(egui::TextEdit::singleline(&mut self.fit.x_column).desired_width(110.0));
            ui.label("y column");
            ui.add(egui::TextEdit::singleline(&mut self.fit.y_column).desired_width(110.0));
            ui.label("runs at most");
            ui.add(egui::DragValue::new(&mut self.fit.max_evals).range(1..=100_000));
        });
        ui.horizontal(|ui| {
            if idle {
                if ui.button("fit").clicked() {
                    if let Err(e) = self.start_fit() {
                        self.notes.push(e);
                    }
                }
            } else if ui.button("stop (keeps the best so far)").clicked() {
                self.stop_fit();
            }
            if let Some(job) = &self.fit.job {
                let p = job.progress.lock().map(|p| *p).unwrap_or_default();
                ui.label(match p.best {
                    Some(c) => format!(
                        "{} runs, best RMS residual {:.3} % of the largest |y|",
                        p.runs,
                        100.0 * c.sqrt()
                    ),
                    None => format!("{} runs", p.runs),
                });
            }
        });
        self.fit_outcome_ui(ui);
    }

    /// The last fit's values, agreement and curves.
    fn fit_outcome_ui(&mut self, ui: &mut egui::Ui) {
        let Some(out) = &self.fit.outcome else {
            return;
        };
        let report = match &out.report {
            Ok(r) => r,
            Err(e) => {
                ui.colored_label(egui::Color32::from_rgb(200, 40, 40), e);
                return;
            }
        };
        egui::Grid::new("fit_values").num_columns(4).show(ui, |ui| {
            for h in ["key", "start", "fitted", "σ"] {
                ui.strong(h);
            }
            ui.end_row();
            for f in &report.parameters {
                ui.label(&f.key);
                ui.label(format!("{:.4e}", f.start));
                let mark = if f.at_bound {
                    " (at a bound: widen it)"
                } else {
                    ""
                };
                ui.label(format!("{:.4e}{mark}", f.value));
                ui.label(f.sigma.map_or("—".into(), |s| format!("{s:.2e}")));
                ui.end_row();
            }
        });
        let before = report
            .initial
            .map_or("—".into(), |a| format!("{:.3} %", 100.0 * a.rms_relative));
        ui.label(format!(
            "RMS residual {before} → {:.3} % of the largest |y| ({} runs, stop: {:?})",
            100.0 * report.fitted.rms_relative,
            report.evaluations,
            report.stop
        ));
        let c = &report.curves;
        let pts =
            |y: &[f64]| -> Vec<[f64; 2]> { c.x.iter().zip(y).map(|(a, b)| [*a, *b]).collect() };
        let (measured, fitted) = (pts(&c.measured), pts(&c.fitted));
        let initial = c.initial.as_deref().map(pts);
        let x_label = format!("{} [{}]", report.x.measured, report.x.unit);
        let y_label = format!("{} [{}]", report.y.measured, report.y.unit);
        egui_plot::Plot::new("fit_curves")
            .height(200.0)
            .x_axis_label(x_label)
            .y_axis_label(y_label)
            .legend(egui_plot::Legend::default())
            .show(ui, |p| {
                p.points(egui_plot::Points::new("measured", measured).radius(2.5));
                if let Some(i) = initial {
                    p.line(
                        egui_plot::Line::new("start", i)
                            .style(egui_plot::LineStyle::dashed_dense()),
                    );
                }
                p.line(egui_plot::Line::new("fitted", fitted));
            });
        if ui.button("use the fitted values").clicked() {
            if let Err(e) = self.apply_fit() {
                self.notes.push(e);
            }
        }
    }
}
