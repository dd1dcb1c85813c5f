//! The law editor (egui), drawn from the table of families: the family picker lists
//! [`families`] by label (in the table's order, that of the keys), and each parameter the edited
//! family declares ([`Param`]) gets its widget — a number a slider over its typical span (linear
//! or logarithmic) with its symbol, unit and a button back to its default, its meaning and
//! admissible range written below (and on hover); a table of points a grid of rows. Below: μ_inf, and what
//! the law gives or why it is inadmissible.

use super::{App, LawSettings};
use crate::law::{families, NumberParam, Param, ParamKind, ParamValue, StiffnessLaw};
use egui_plot::{Legend, Line, Plot};

const RED: egui::Color32 = egui::Color32::from_rgb(220, 50, 50);

impl App {
    /// With several `[[interface]]`s, which one the editor edits (named by face set and
    /// mould): picking one loads its law from the scene file; the others run with their own.
    fn interface_picker(&mut self, ui: &mut egui::Ui) {
        if self.settings.interfaces.len() < 2 {
            return;
        }
        let mut picked = None;
        egui::ComboBox::from_label("edited interface")
            .selected_text(self.settings.interface_label())
            .show_ui(ui, |ui| {
                for (k, label) in self.settings.interfaces.iter().enumerate() {
                    let text = format!("{k}: {label}");
                    if ui
                        .selectable_label(k == self.settings.interface, text)
                        .clicked()
                    {
                        picked = Some(k);
                    }
                }
            })
            .response
            .on_hover_text(
                "the law below is this interface's; the other interfaces keep the scene's own laws",
            );
        if let Some(k) = picked {
            self.edit_interface(k);
        }
    }

    /// The law editor: family, its parameters, μ_inf, and what the law gives.
    pub(super) fn law_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Interface law");
        self.interface_picker(ui);
        let law = &mut self.settings.law;
        family_picker(ui, law);
        if let Some(spec) = law.spec() {
            let mut meanings = vec![];
            egui::Grid::new("law_params")
                .num_columns(3)
                .spacing([8.0, 4.0])
                .show(ui, |ui| {
                    for p in spec.params {
                        if let ParamKind::Number(n) = p.kind {
                            number_row(ui, law, p, n);
                            meanings.push(format!("{}: {}, {}", p.symbol, p.meaning, n.range));
                        }
                    }
                });
            if !meanings.is_empty() {
                ui.label(egui::RichText::new(meanings.join(";  ")).small().weak());
            }
            for p in spec.params {
                if let ParamKind::Points { .. } = p.kind {
                    points_editor(ui, law, p);
                }
            }
        }
        ui.add(egui::Slider::new(&mut law.mu_inf, 0.0..=2.0).text("μ_inf"))
            .on_hover_text("friction coefficient of the fully ruptured interface (≥ 0)");
        delay_ui(ui, law);
        match law.law() {
            Ok(l) => {
                let (t_max, at) = l.peak_traction();
                ui.label(format!(
                    "peak traction {t_max:.4e} Pa at δ = {at:.3e} m;  G_c = {:.4e} J/m²",
                    l.fracture_energy()
                ));
                if has_rate_effect(&l) {
                    rate_plot(ui, &l, &mut law.delay.plot_rate);
                }
            }
            Err(e) => {
                ui.colored_label(RED, format!("inadmissible law — {e}"));
            }
        }
    }
}

/// The family combo box: one entry per row of the table, by label.
fn family_picker(ui: &mut egui::Ui, law: &mut LawSettings) {
    let selected = law.spec().map_or(law.family.as_str(), |s| s.label);
    egui::ComboBox::from_label("family")
        .selected_text(selected)
        .width(260.0)
        .show_ui(ui, |ui| {
            for f in families() {
                ui.selectable_value(&mut law.family, f.key.to_string(), f.label)
                    .on_hover_text(format!("`{}`: takes {}", f.key, f.takes()));
            }
        });
}

/// ` Pa/m`, or nothing for a dimensionless parameter (`–`).
fn unit_suffix(unit: &str) -> String {
    match unit {
        "" | "–" | "-" => String::new(),
        unit => format!(" {unit}"),
    }
}

/// What a parameter is and what it admits, for hover texts.
fn describe(p: &Param, admissible: &str) -> String {
    let mut s = format!(
        "{} `{}`: {}; admissible {admissible}",
        p.symbol, p.key, p.meaning
    );
    if !p.note.is_empty() {
        s.push_str(&format!(" ({})", p.note));
    }
    if p.optional {
        s.push_str("; a scene may leave it out");
    }
    s
}

/// One grid row: symbol, slider with its unit, a button back to the default.
fn number_row(ui: &mut egui::Ui, law: &mut LawSettings, p: &Param, n: NumberParam) {
    let hover = describe(p, &format!("{} ({})", n.range, p.unit));
    ui.label(p.symbol).on_hover_text(&hover);
    let ParamValue::Number(x) = law.value_mut(p) else {
        unreachable!("value_mut gives a value of the parameter's kind")
    };
    let [lo, hi] = n.typical;
    let mut slider = egui::Slider::new(x, lo..=hi)
        .logarithmic(n.logarithmic)
        .clamping(egui::SliderClamping::Never)
        .suffix(unit_suffix(p.unit));
    if n.logarithmic {
        // Values over decades read best as 5.000e8.
        slider = slider.custom_formatter(|v, _| format!("{v:.3e}"));
    }
    ui.add(slider).on_hover_text(&hover);
    let default = format!("{}{}", n.default, unit_suffix(p.unit));
    if ui
        .add_enabled(*x != n.default, egui::Button::new("default").small())
        .on_hover_text(format!("back to the default, {default}"))
        .clicked()
    {
        *x = n.default;
    }
    ui.end_row();
}

/// The rows of a table parameter, one editable row each, with their units; rows can be
/// removed (down to two) and added.
fn points_editor(ui: &mut egui::Ui, law: &mut LawSettings, p: &Param) {
    ui.label(format!("{} [{}]", p.symbol, p.unit))
        .on_hover_text(describe(p, "as the family checks it"));
    ui.label(egui::RichText::new(p.meaning).small());
    let units: Vec<String> = p.unit.split(',').map(|u| unit_suffix(u.trim())).collect();
    let unit = |i: usize| units.get(i).cloned().unwrap_or_default();
    let ParamValue::Points(points) = law.value_mut(p) else {
        unreachable!("value_mut gives a value of the parameter's kind")
    };
    // Dragging moves a value by 1/1000 of its column's largest.
    let speed = |c: usize| points.iter().map(|r| r[c].abs()).fold(1e-9, f64::max) * 1e-3;
    let speeds = [speed(0), speed(1)];
    let mut remove = None;
    egui::Grid::new(("points", p.key))
        .striped(true)
        .show(ui, |ui| {
            for (i, row) in points.iter_mut().enumerate() {
                for (c, x) in row.iter_mut().enumerate() {
                    ui.add(egui::DragValue::new(x).speed(speeds[c]).suffix(unit(c)));
                }
                if ui
                    .small_button("−")
                    .on_hover_text("remove this point")
                    .clicked()
                {
                    remove = Some(i);
                }
                ui.end_row();
            }
        });
    if let Some(i) = remove {
        if points.len() > 2 {
            points.remove(i);
        }
    }
    if ui.button("add a point").clicked() {
        let last = *points.last().unwrap_or(&[0.0, 0.0]);
        points.push([last[0] * 1.25 + 1e-4, 0.0]);
    }
}

/// `[interface.delay]`: on/off, τ_c and a on logarithmic sliders (any admissible value may be
/// typed; an inadmissible one makes the law red with the library's reason).
fn delay_ui(ui: &mut egui::Ui, law: &mut LawSettings) {
    let d = &mut law.delay;
    ui.checkbox(&mut d.on, "delayed damage  [interface.delay]")
        .on_hover_text(
            "α̇ = (u_r/τ_c)(1 − exp(−a⟨α_s − α⟩₊/u_r)): the damage follows its rate-independent \
             value α_s at a rate ≤ u_r/τ_c (not for `rccm`, whose rate effect is b)",
        );
    if !d.on {
        return;
    }
    ui.horizontal(|ui| {
        ui.label("τ_c");
        ui.add(log_slider(&mut d.tau_c, 1e-6..=10.0, " s"))
            .on_hover_text("characteristic time τ_c `tau_c`: the damage rate never exceeds u_r/τ_c; admissible > 0 (s)");
        ui.label("a");
        ui.add(log_slider(&mut d.a, 0.01..=100.0, ""))
            .on_hover_text("sharpness a `a`: rate (u_r/τ_c)(1 − e^{−a x/u_r}) at a lag x; admissible > 0 (–)");
    });
}

/// A logarithmic slider with a suffix, values shown as 1.000e-2.
fn log_slider<'a>(
    x: &'a mut f64,
    range: std::ops::RangeInclusive<f64>,
    suffix: &str,
) -> egui::Slider<'a> {
    egui::Slider::new(x, range)
        .logarithmic(true)
        .clamping(egui::SliderClamping::Never)
        .suffix(suffix)
        .custom_formatter(|v, _| format!("{v:.3e}"))
}

/// A law whose damage depends on the opening rate: a delay, or `rccm` with b > 0.
fn has_rate_effect(law: &StiffnessLaw) -> bool {
    law.delay().is_some() || law.values().number("b").is_ok_and(|b| b > 0.0)
}

/// T(δ) under normal opening at the chosen rate (the law's own update, as a glued node opened
/// at that rate would follow it) against the rate-independent T(δ), over [0, 3 u_r].
fn rate_plot(ui: &mut egui::Ui, law: &StiffnessLaw, rate: &mut f64) {
    ui.horizontal(|ui| {
        ui.label("opening rate");
        ui.add(log_slider(rate, 1e-4..=100.0, " m/s"))
            .on_hover_text("the constant opening rate of the T(δ) curve below");
    });
    if !(rate.is_finite() && *rate > 0.0) {
        ui.colored_label(
            RED,
            format!("opening rate = {rate}: must be finite and > 0 (m/s)"),
        );
        return;
    }
    let span = 3.0 * law.u_r;
    let at_rate: Vec<[f64; 2]> = (law.traction_at_rate(*rate, span, 600).into_iter())
        .map(|[d, t]| [1e3 * d, 1e-6 * t])
        .collect();
    let fixed: Vec<[f64; 2]> = (0..=600)
        .map(|k| span * k as f64 / 600.0)
        .map(|d| [1e3 * d, 1e-6 * law.traction(d)])
        .collect();
    ui.label(format!(
        "T(δ) [MPa] against δ [mm], opened at {rate:.3e} m/s"
    ));
    super::plots::plot_125(Plot::new("law_at_rate"))
        .height(160.0)
        .legend(Legend::default())
        .x_axis_label("δ [mm]")
        .show(ui, |p| {
            p.line(Line::new("rate-independent", fixed));
            p.line(Line::new(format!("at {rate:.2e} m/s"), at_rate));
        });
}
