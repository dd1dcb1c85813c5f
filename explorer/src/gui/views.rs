//! The explorer's views (egui): the settings panel (scene, run settings), the run bar, the
//! history table; the law editor is in [`super::law_editor`], the plots in [`super::plots`].
//! They draw the state of [`App`] and call its methods ([`super::state`]).

use super::job::Repaint;
use super::{App, RecordChoice, Status};
use crate::law::Knots;
use crate::solver::StateCounts;
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

/// The columns of the history table.
const HISTORY_COLUMNS: [&str; 16] = [
    "compare",
    "#",
    "scene",
    "law",
    "g_N(0) Pa/m",
    "α_e m",
    "u_r m",
    "μ_inf",
    "cells",
    "status",
    "rupture s",
    "peak N",
    "dissipated J",
    "residual",
    "ruptured",
    "wall s",
];

/// A repaint request for the window of `ctx`, callable from the solver thread.
pub(super) fn repaint_handle(ctx: &egui::Context) -> Repaint {
    let ctx = ctx.clone();
    Arc::new(move || ctx.request_repaint())
}

impl App {
    /// The whole window.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        if self.repaint.is_none() {
            self.repaint = Some(repaint_handle(ui.ctx()));
        }
        self.take_dropped_files(ui.ctx());
        self.take_screenshot(ui.ctx());
        let running = self.poll();
        if running || self.settle > 0 {
            self.settle = self.settle.saturating_sub(1);
            ui.ctx().request_repaint_after(Duration::from_millis(100));
        }
        if self.display.projector && ui.ctx().zoom_factor() != super::state::PROJECTOR_ZOOM {
            ui.ctx().set_zoom_factor(super::state::PROJECTOR_ZOOM);
        }
        // In the order of PANELS.
        let [settings, history, view, law, progress, measured] =
            super::state::PANELS.map(|(p, _)| self.display.shows(p));
        // The embeddable view shares the frame's width, whatever its size.
        let width = ui.available_width();
        let (lesson_width, view_width) = if self.display.embed {
            (
                width * super::state::EMBED_LESSON_WIDTH,
                width * super::state::EMBED_VIEW_WIDTH,
            )
        } else {
            (380.0, 470.0)
        };
        // Embedded, a panel keeps its share of the frame's width, set again every frame (the
        // first frames of the page may come before the canvas has its size), whatever its
        // widest line.
        let embed = self.display.embed;
        let at_most = move |p: egui::Panel, w: f32| if embed { p.exact_size(w) } else { p };
        if self.lesson.is_some() {
            at_most(egui::Panel::left("lesson"), lesson_width)
                .resizable(true)
                .default_size(lesson_width)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| self.lesson_ui(ui));
                });
        }
        if settings {
            egui::Panel::left("settings")
                .resizable(true)
                .default_size(430.0)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| self.settings_ui(ui));
                });
        }
        if history {
            egui::Panel::bottom("history")
                .resizable(true)
                .default_size(230.0)
                .show(ui, |ui| self.history_ui(ui));
        }
        if view {
            let panel = at_most(egui::Panel::right("view3d"), view_width)
                .resizable(true)
                .default_size(view_width)
                .show(ui, |ui| self.view.ui(ui));
            self.view.panel = Some(panel.response.rect);
            if std::mem::take(&mut self.view.png_requested) {
                if let Some(rect) = self.view.rect {
                    let name = format!("{}_3d_view", self.settings.scene_stem());
                    self.request_png(ui.ctx(), &name, rect);
                }
            }
            if std::mem::take(&mut self.view.gif_requested) {
                self.start_gif();
            }
            self.gif_step(ui.ctx());
        }
        egui::CentralPanel::default().show(ui, |ui| {
            // Embedded in a narrow frame, what is wider than the plots' share scrolls rather
            // than covering the 3-D view.
            let scroll = if self.display.embed {
                egui::ScrollArea::both()
            } else {
                egui::ScrollArea::vertical()
            };
            scroll.show(ui, |ui| {
                self.run_ui(ui);
                if measured {
                    ui.separator();
                    self.measured_ui(ui);
                }
                if !self.compare.is_empty() || self.measured.is_some() {
                    ui.separator();
                    self.compare_plots_ui(ui);
                }
                if law {
                    ui.separator();
                    self.plots_ui(ui);
                }
                if progress {
                    ui.separator();
                    self.progress_plot_ui(ui);
                }
                if self.view.selected.is_some() {
                    ui.separator();
                    self.node_plot_ui(ui);
                }
            });
        });
    }

    /// The left panel: scene, interface law, run settings.
    fn settings_ui(&mut self, ui: &mut egui::Ui) {
        self.scene_ui(ui);
        ui.separator();
        self.law_ui(ui);
        ui.separator();
        self.run_settings_ui(ui);
    }

    /// The scene picker.
    fn scene_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Scene");
        let current = self.settings.scene.clone();
        egui::ComboBox::from_label("scene file")
            .selected_text(&current)
            .width(300.0)
            .show_ui(ui, |ui| {
                for s in self.scenes.clone() {
                    if ui
                        .selectable_label(s.path == current, &s.path)
                        .on_hover_text(&s.description)
                        .clicked()
                    {
                        self.load_scene(&s.path);
                    }
                }
            });
        if let Some(s) = self.scenes.iter().find(|s| s.path == current) {
            ui.label(egui::RichText::new(&s.description).small());
        }
        if !self.settings.set.is_empty() {
            ui.label(
                egui::RichText::new(format!("with --set {}", self.settings.set.join(" --set ")))
                    .small(),
            );
        }
        ui.horizontal(|ui| {
            self.lesson_picker_ui(ui);
            self.link_ui(ui);
        });
    }

    /// Mesh, time step, end time, frames, material, integration, outputs; what they give.
    fn run_settings_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Run settings");
        let s = &mut self.settings;
        if s.cells == 0 {
            ui.label("mesh from the scene's Gmsh file (cells per side: box meshes only)");
        } else {
            // A scene finer than the slider's range (the peel's 100 cells) keeps its own.
            let most = s.cells.max(40);
            ui.add(egui::Slider::new(&mut s.cells, 1..=most).text("cells per side"));
        }
        ui.add(egui::Slider::new(&mut s.factor, 0.05..=1.0).text("time-step factor h/h_crit"));
        ui.add(
            egui::Slider::new(&mut s.end_time, 1e-4..=10.0)
                .logarithmic(true)
                .text("end time")
                .suffix(" s"),
        );
        if !self.in_page {
            ui.add(
                egui::Slider::new(&mut s.frames, 1..=2000)
                    .logarithmic(true)
                    .text("frames per run (Rerun)"),
            );
        }
        // The models that take the scene's parameters: E and ν (SVK, neo-Hookean) swap; a
        // rubber's constants belong to its family (the table of rubber families), so a rubber
        // scene lists its own model only.
        use crate::material::MaterialModel;
        let current = MaterialModel::from_key(&s.material);
        let rubber = current.and_then(MaterialModel::rubber_spec);
        egui::ComboBox::from_label("material")
            .selected_text(s.material.as_str())
            .show_ui(ui, |ui| {
                for model in MaterialModel::all() {
                    let label = format!("{} ({})", model.key(), model.label());
                    let takes_scene = match rubber {
                        None => model.rubber_spec().is_none(),
                        Some(_) => Some(model) == current,
                    };
                    if takes_scene {
                        ui.selectable_value(&mut s.material, model.key().to_string(), label);
                    }
                }
            });
        // Wrapped: four choices do not widen the panel.
        ui.horizontal_wrapped(|ui| {
            ui.label("integration");
            ui.radio_value(&mut s.integration, "full".to_string(), "2×2×2");
            ui.radio_value(
                &mut s.integration,
                "reduced".to_string(),
                "one point + hourglass",
            );
            ui.radio_value(&mut s.integration, "fbar".to_string(), "F-bar (no locking)");
            ui.radio_value(
                &mut s.integration,
                "reduced_physical".to_string(),
                "one point, physical hourglass",
            );
        });
        if s.integration == "reduced" {
            ui.add(egui::Slider::new(&mut s.hourglass, 0.0..=0.3).text("hourglass κ"));
        }
        // The page has no Rerun and no files: it offers neither.
        if !self.in_page {
            ui.horizontal(|ui| {
                ui.label("record to");
                ui.radio_value(&mut s.record, RecordChoice::Viewer, "Rerun viewer");
                ui.radio_value(&mut s.record, RecordChoice::File, ".rrd files");
                ui.radio_value(&mut s.record, RecordChoice::Off, "off");
            });
            ui.checkbox(
                &mut s.paraview,
                "also write ParaView files (.vtu per frame + .pvd, in the output folder)",
            );
        }
        match self.check() {
            Ok(c) if c.h.is_finite() => {
                ui.label(format!(
                    "{} hex8, {} interface nodes; h = {:.4e} s, h_crit = {:.4e} s (Lanczos); ≈ {} steps",
                    c.elements, c.interface_nodes, c.h, c.h_crit, c.steps
                ));
                for w in &c.warnings {
                    ui.colored_label(
                        egui::Color32::from_rgb(230, 150, 20),
                        format!("warning: {w}"),
                    );
                }
            }
            Ok(c) => {
                ui.label(format!(
                    "{} hex8 (h_crit is estimated when the run starts)",
                    c.elements
                ));
            }
            Err(e) => {
                ui.colored_label(egui::Color32::from_rgb(220, 50, 50), e);
            }
        }
    }

    fn run_ui(&mut self, ui: &mut egui::Ui) {
        let blocker = self.blocker();
        let running = self.job.is_some();
        // Wrapped in a narrow frame (the embeddable page).
        ui.horizontal_wrapped(|ui| {
            let run = ui.add_enabled(!running && blocker.is_none(), egui::Button::new("Run"));
            if run.clicked() {
                self.start();
            }
            if ui.add_enabled(running, egui::Button::new("Stop")).clicked() {
                self.stop();
            }
            if ui
                .add_enabled(!running, egui::Button::new("Reset"))
                .on_hover_text("back to the scene file's values")
                .clicked()
            {
                self.reset();
            }
            let status = match &self.status {
                Status::Idle => "ready".to_string(),
                Status::Running => "running".to_string(),
                Status::Ended(s) => s.clone(),
            };
            ui.label(format!("status: {status}"));
            if self.display.embed {
                // Embedded, the scene section (and its link button) is left out.
                self.link_ui(ui);
                self.full_page_ui(ui);
            }
        });
        self.variants_ui(ui);
        if let Some(b) = &blocker {
            ui.colored_label(
                egui::Color32::from_rgb(220, 50, 50),
                format!("Run is disabled: {b}"),
            );
        }
        if let Some(job) = &self.job {
            let (step, time, counts, residual) = job
                .last
                .map_or((0, 0.0, StateCounts::default(), 0.0), |(s, p)| {
                    (s, p.t, p.counts, p.residual)
                });
            let frac = (time / job.end_time).clamp(0.0, 1.0);
            let wall = job.started.elapsed().as_secs_f64();
            let rate = step as f64 / wall.max(1e-9);
            let eta = if frac > 0.0 {
                wall * (1.0 - frac) / frac
            } else {
                f64::NAN
            };
            ui.add(
                egui::ProgressBar::new(frac as f32)
                    .show_percentage()
                    .text(format!(
                        "run {}: t = {time:.4} s of {:.4} s, {rate:.0} steps/s, ETA {eta:.1} s",
                        job.id, job.end_time
                    )),
            );
            let unformed = match counts.unformed {
                0 => String::new(),
                n => format!(", {n} unformed"),
            };
            ui.label(format!(
                "interface nodes: {} elastic, {} transition, {} ruptured{unformed}; balance residual {residual:.2e}",
                counts.elastic, counts.transition, counts.ruptured
            ));
        }
        for n in &self.notes {
            ui.colored_label(egui::Color32::from_rgb(230, 160, 40), n);
        }
    }

    /// Runs of several values of one parameter, queued and compared.
    fn variants_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.label("compare values of");
            ui.add(
                egui::TextEdit::singleline(&mut self.variants_text)
                    .hint_text("interface.law.u_r=0.003,0.004,0.006")
                    .desired_width(260.0),
            )
            .on_hover_text(format!(
                "key=v1,v2,…, the key as `sweep --vary` takes it: interface.law.NAME for a \
                 number parameter of the law, or one of {} (short names: NAME, {}); one run per \
                 value, the others as set, overlaid below",
                super::state::VARIANT_KEYS.map(|k| k.0).join(", "),
                super::state::VARIANT_KEYS.map(|k| k.1).join(", ")
            ));
            if ui.button("queue runs").clicked() {
                let spec = self.variants_text.clone();
                if let Err(e) = self.queue_spec(&spec) {
                    self.notes.push(e);
                }
            }
            if !self.queue.is_empty() {
                ui.label(format!("{} queued", self.queue.len()));
            }
        });
    }

    fn history_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.heading("Runs");
            let sel = self.selected.filter(|&i| i < self.history.len());
            if ui
                .add_enabled(
                    sel.is_some() && self.job.is_none(),
                    egui::Button::new("load these parameters"),
                )
                .clicked()
            {
                if let Some(i) = sel {
                    self.load_row(i);
                }
            }
            if ui
                .add_enabled(!self.history.is_empty(), egui::Button::new("export CSV"))
                .clicked()
            {
                self.save_history_csv();
            }
            if ui
                .add_enabled(
                    !self.history.is_empty(),
                    egui::Button::new("export curves (CSV)"),
                )
                .on_hover_text(
                    "every run's samples over time: displacement, reaction, mean damage, node \
                     counts (curves.csv)",
                )
                .clicked()
            {
                self.save_curves_csv();
            }
            let summary = sel.is_some_and(|i| self.history[i].summary_json.is_some());
            if ui
                .add_enabled(summary, egui::Button::new("save summary (JSON)"))
                .on_hover_text(
                    "the selected run's summary, as `decohesion run --summary` writes it",
                )
                .clicked()
            {
                if let Some(i) = sel {
                    self.save_summary(i);
                }
            }
        });
        egui::ScrollArea::both().show(ui, |ui| {
            egui::Grid::new("history_grid")
                .striped(true)
                .num_columns(HISTORY_COLUMNS.len())
                .show(ui, |ui| {
                    for h in HISTORY_COLUMNS {
                        ui.strong(h);
                    }
                    ui.end_row();
                    let opt = |v: Option<f64>, p: usize| {
                        v.map_or("—".to_string(), |v| format!("{v:.p$e}"))
                    };
                    let mut toggled = None;
                    for (i, r) in self.history.iter().enumerate().rev() {
                        let st = &r.settings;
                        let mut ticked = self.compare.contains(&r.id);
                        let tick = ui.checkbox(&mut ticked, "");
                        let name = format!("compare run {}", r.id);
                        tick.widget_info(|| {
                            egui::WidgetInfo::selected(
                                egui::accesskit::Role::CheckBox,
                                true,
                                ticked,
                                &name,
                            )
                        });
                        if tick.on_hover_text(&name).changed() {
                            toggled = Some(r.id);
                        }
                        let id = egui::RichText::new(format!("{}", r.id));
                        let id = if ticked {
                            id.color(super::plots::run_colour(r.id)).strong()
                        } else {
                            id
                        };
                        if ui.selectable_label(self.selected == Some(i), id).clicked() {
                            self.selected = Some(i);
                        }
                        ui.label(
                            Path::new(&st.scene)
                                .file_stem()
                                .map(|s| s.to_string_lossy().to_string())
                                .unwrap_or_default(),
                        );
                        let law = st.law.law();
                        let on = st.interface_label();
                        let family = match on.is_empty() || st.interfaces.len() < 2 {
                            true => st.law.family.clone(),
                            false => format!("{} (interface {on})", st.law.family),
                        };
                        ui.label(family).on_hover_text(match &law {
                            Ok(l) => l.to_string(),
                            Err(e) => e.clone(),
                        });
                        let k = law.ok().map(|l| l.knots());
                        let knots: [fn(Knots) -> f64; 3] = [|k| k.g_n0, |k| k.alpha_e, |k| k.u_r];
                        for x in knots {
                            ui.label(opt(k.map(x), 2));
                        }
                        ui.label(format!("{}", st.law.mu_inf));
                        ui.label(match st.cells {
                            0 => "file".to_string(),
                            n => n.to_string(),
                        });
                        let status = ui.label(&r.status);
                        if let Some(e) = &r.error {
                            status.on_hover_text(e);
                        }
                        ui.label(opt(r.time_full_rupture, 4));
                        ui.label(opt(r.peak_force, 3));
                        ui.label(format!("{:.4e}", r.damage_dissipated));
                        ui.label(format!("{:.2e}", r.max_relative_residual));
                        ui.label(format!("{}/{}", r.counts.ruptured, r.interface_nodes));
                        ui.label(format!("{:.2}", r.wall_seconds));
                        ui.end_row();
                    }
                    if let Some(id) = toggled {
                        self.toggle_compare(id);
                    }
                });
        });
    }
}
