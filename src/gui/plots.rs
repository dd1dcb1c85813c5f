//! The explorer's plots (egui_plot): the edited law's curves g_N(α), T(δ), μ(α), the
//! interface states and balance residual of the running or last run, and the runs ticked for
//! comparison overlaid (states against time, reaction against imposed displacement, mean α
//! against time), each in its run's colour.

use super::history::CurvePoint;
use super::lesson::PlotName;
use super::App;
use crate::solver::StateCounts;
use egui::Color32;
use egui_plot::{uniform_grid_spacer, GridInput, Legend, Line, LineStyle, Plot, Points, VLine};

/// The smallest of 1, 2, 5 × 10^k that is ≥ `x` (> 0).
fn step_125(x: f64) -> f64 {
    let decade = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= x * (1.0 - 1e-12))
        .unwrap_or(10.0 * decade)
}

/// Grid lines at 1-2-5 steps: egui_plot's default spacer steps by powers of ten only, so a
/// 210-pixel plot spanning ±800 had lines every 100 (too close for labels) or 1000 (only "0"
/// labelled). Each coarser step is the next 1-2-5 value ≥ 4× the finer one (a multiple of it).
pub(super) fn plot_125(plot: Plot<'_>) -> Plot<'_> {
    let spacer = || {
        uniform_grid_spacer(|input: GridInput| {
            let fine = step_125(input.base_step_size.abs().max(f64::MIN_POSITIVE));
            let mid = step_125(4.0 * fine);
            [fine, mid, step_125(4.0 * mid)]
        })
    };
    plot.x_grid_spacer(spacer())
        .y_grid_spacer(spacer())
        .x_axis_formatter(|mark, _| tick_label(mark.value, mark.step_size))
        .y_axis_formatter(|mark, _| tick_label(mark.value, mark.step_size))
}

/// A tick's label with as many decimals as its step needs (egui_plot's default rounds the
/// decimals of log10(step), so a 0.05 step printed 0.05 as "0.1"), in e-notation for steps
/// ≥ 10⁵ or < 10⁻⁴ (4e8 Pa/m rather than 400000000); trailing zeros dropped, so a mark
/// labelled with a finer step than its neighbour's still reads alike ("0.1" beside "0.05").
fn tick_label(value: f64, step: f64) -> String {
    if value == 0.0 {
        return "0".to_string();
    }
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if !(1e-4..1e5).contains(&step) {
        let digits = (value.abs().log10().floor() - step.log10().floor()).max(0.0) as usize;
        let text = format!("{value:.digits$e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        return format!("{}e{exponent}", trim(mantissa.to_string()));
    }
    let decimals = (-step.log10() - 1e-9).ceil().max(0.0) as usize;
    trim(format!("{value:.decimals$}"))
}

/// The colour of run `id` (the same in every plot and in the history).
pub(super) fn run_colour(id: u32) -> Color32 {
    use crate::cli::PALETTE;
    let [r, g, b] = PALETTE[(id.max(1) as usize - 1) % PALETTE.len()];
    Color32::from_rgb(r, g, b)
}

/// The finite (x, y) of a run's samples.
fn series(points: &[CurvePoint], f: impl Fn(&CurvePoint) -> [f64; 2]) -> Vec<[f64; 2]> {
    points
        .iter()
        .map(f)
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect()
}

impl App {
    /// The law's curves, with α_e and u_r marked.
    pub(super) fn plots_ui(&mut self, ui: &mut egui::Ui) {
        let projector = self.display.projector;
        let Ok(law) = self.settings.law.law() else {
            ui.label("(no plot: the law is inadmissible)");
            return;
        };
        let mu_inf = self.settings.law.mu_inf;
        let n = 300;
        let span = law.u_r * 1.15;
        let xs: Vec<f64> = (0..=n).map(|k| span * k as f64 / n as f64).collect();
        let g: Vec<[f64; 2]> = xs.iter().map(|&a| [1e3 * a, law.g_n(a)]).collect();
        let t: Vec<[f64; 2]> = xs
            .iter()
            .map(|&d| [1e3 * d, 1e-6 * law.traction(d)])
            .collect();
        let mu: Vec<[f64; 2]> = xs.iter().map(|&a| [1e3 * a, law.mu(a, mu_inf)]).collect();
        let (ae, ur) = (1e3 * law.alpha_e, 1e3 * law.u_r);
        let marks = |p: &mut egui_plot::PlotUi| {
            p.vline(VLine::new("α_e", ae));
            p.vline(VLine::new("u_r", ur));
        };
        let w = (ui.available_width() / 3.0 - 8.0).max(150.0);
        let titles = [
            self.plot_title(PlotName::Law, "stiffness g_N(α) [Pa/m]"),
            self.plot_title(PlotName::Traction, "traction T(δ) = g_N(δ)δ [MPa]"),
            self.plot_title(
                PlotName::Friction,
                "friction μ(α) = μ_inf (1 − g_N(α)/g_N(0))",
            ),
        ];
        let [t_law, t_traction, t_mu] = titles;
        ui.horizontal(|ui| {
            titled_plot(ui, t_law, "g_n", "α [mm]", w, |p| {
                line(p, projector, Line::new("g_N(α)", g));
                marks(p);
            });
            titled_plot(ui, t_traction, "traction", "δ [mm]", w, |p| {
                line(p, projector, Line::new("T(δ)", t));
                marks(p);
            });
            titled_plot(ui, t_mu, "mu", "α [mm]", w, |p| {
                line(p, projector, Line::new("μ(α)", mu));
                marks(p);
            });
        });
    }

    pub(super) fn progress_plot_ui(&mut self, ui: &mut egui::Ui) {
        let projector = self.display.projector;
        let Some(run) = self.curve_run else {
            ui.label("Run a scene to see its interface states over time here.");
            return;
        };
        let points = &self.curve.points;
        let pick = |f: fn(&StateCounts) -> usize| series(points, |p| [p.t, f(&p.counts) as f64]);
        let residual = series(points, |p| [p.t, p.residual]);
        // Glue that forms on contact: its nodes not formed yet (none in other scenes).
        let unformed = points.iter().any(|p| p.counts.unformed > 0);
        let force = series(points, |p| [p.t, p.force]);
        // The open question's prediction, drawn over the force when it is a force.
        let predicted = self.lesson.as_ref().and_then(|s| {
            let q = s.current().question.as_ref()?;
            let force = matches!(
                q.result,
                super::lesson::RunResult::LateForce | super::lesson::RunResult::PeakForce
            );
            (force && s.run == Some(run))
                .then_some(s.predicted)
                .flatten()
        });
        let w = (ui.available_width() / 3.0 - 8.0).max(150.0);
        let colour = |c: [u8; 3]| egui::Color32::from_rgb(c[0], c[1], c[2]);
        let t_states = self.plot_title(
            PlotName::States,
            &format!("run {run}: interface nodes by state (paper fig. 6, right)"),
        );
        let t_force = self.plot_title(
            PlotName::Force,
            &format!("run {run}: force on the pulled faces [N]"),
        );
        ui.horizontal(|ui| {
            titled_plot(ui, t_states, "counts", "t [s]", w, |p| {
                line(
                    p,
                    projector,
                    Line::new("elastic", pick(|c| c.elastic)).color(colour([46, 160, 67])),
                );
                line(
                    p,
                    projector,
                    Line::new("transition", pick(|c| c.transition)).color(colour([245, 166, 35])),
                );
                line(
                    p,
                    projector,
                    Line::new("ruptured", pick(|c| c.ruptured)).color(colour([208, 2, 27])),
                );
                if unformed {
                    line(
                        p,
                        projector,
                        Line::new("unformed", pick(|c| c.unformed)).color(colour([90, 90, 90])),
                    );
                }
            });
            titled_plot(ui, t_force, "force", "t [s]", w, |p| {
                line(p, projector, Line::new("|reaction|", force));
                if let Some(f) = predicted {
                    p.hline(
                        egui_plot::HLine::new("your prediction", f).color(colour([230, 150, 0])),
                    );
                }
            });
            titled_plot(
                ui,
                format!("run {run}: balance residual / largest energy"),
                "residual",
                "t [s]",
                w,
                |p| line(p, projector, Line::new("residual", residual)),
            );
        });
    }
}

/// Adds `l` to the plot, thicker in the projector mode ([`super::state::Display`]).
fn line<'a>(p: &mut egui_plot::PlotUi<'a>, projector: bool, l: Line<'a>) {
    p.line(match projector {
        true => l.width(super::state::PROJECTOR_LINE),
        false => l,
    });
}

/// A plot of width `w` under its title, with a legend.
fn titled_plot<'a>(
    ui: &mut egui::Ui,
    title: impl Into<egui::WidgetText>,
    id: &str,
    x_label: &str,
    w: f32,
    add: impl FnOnce(&mut egui_plot::PlotUi<'a>) + 'a,
) {
    ui.vertical(|ui| {
        // A long title is cut to the plot's width (whole on hover), not widening the row.
        let title = egui::Label::new(title).truncate();
        ui.allocate_ui(egui::vec2(w, 0.0), |ui| ui.add(title));
        plot_125(Plot::new(id))
            .width(w)
            .height(210.0)
            .x_axis_label(x_label.to_string())
            .legend(Legend::default())
            .show(ui, add);
    });
}

impl App {
    /// The runs ticked in the history, overlaid: interface states against time (ruptured
    /// solid, transition dashed, elastic dotted), reaction against imposed displacement, mean
    /// α against time; one legend entry per run (its parameters that differ between the runs).
    pub(super) fn compare_plots_ui(&mut self, ui: &mut egui::Ui) {
        let projector = self.display.projector;
        let runs = self.compared();
        let measured = self.measured.as_ref().map(|m| m.si.clone());
        let measured_name = self
            .measured
            .as_ref()
            .map_or(String::new(), |m| m.curve.file.clone());
        ui.label(format!(
            "{} runs compared (tick or untick them in the history)",
            runs.len()
        ));
        let w = (ui.available_width() / 3.0 - 8.0).max(150.0);
        let styles = [
            (
                LineStyle::Solid,
                (|c| c.ruptured) as fn(&StateCounts) -> usize,
            ),
            (LineStyle::dashed_dense(), |c| c.transition),
            (LineStyle::dotted_dense(), |c| c.elastic),
        ];
        ui.horizontal(|ui| {
            titled_plot(
                ui,
                "interface nodes: ruptured solid, transition dashed, elastic dotted",
                "compare_counts",
                "t [s]",
                w,
                |p| {
                    for (row, label) in &runs {
                        for (style, f) in &styles {
                            let data = series(&row.curve.points, |q| [q.t, f(&q.counts) as f64]);
                            line(
                                p,
                                projector,
                                Line::new(label.clone(), data)
                                    .color(run_colour(row.id))
                                    .style(*style),
                            );
                        }
                    }
                },
            );
            let overlay = |p: &mut egui_plot::PlotUi, f: &dyn Fn(&CurvePoint) -> [f64; 2]| {
                for (row, label) in &runs {
                    let data = series(&row.curve.points, f);
                    line(
                        p,
                        projector,
                        Line::new(label.clone(), data).color(run_colour(row.id)),
                    );
                }
            };
            titled_plot(
                ui,
                "reaction [kN] against imposed displacement [mm]",
                "compare_reaction",
                "U [mm]",
                w,
                |p| {
                    overlay(p, &|q| [1e3 * q.displacement, 1e-3 * q.reaction]);
                    if let Some(Ok(points)) = &measured {
                        let points: Vec<[f64; 2]> =
                            points.iter().map(|[x, y]| [1e3 * x, 1e-3 * y]).collect();
                        p.points(
                            Points::new(format!("measured ({})", measured_name), points)
                                .radius(3.0)
                                .color(Color32::from_gray(235)),
                        );
                    }
                },
            );
            titled_plot(
                ui,
                "mean damage α [mm] over the interface",
                "compare_alpha",
                "t [s]",
                w,
                |p| overlay(p, &|q| [q.t, 1e3 * q.mean_alpha]),
            );
        });
    }
}

#[cfg(test)]
mod tests {
    use super::{step_125, tick_label};

    #[test]
    fn tick_labels_carry_the_decimals_of_their_step() {
        assert_eq!(tick_label(0.05, 0.05), "0.05");
        assert_eq!(tick_label(0.2, 0.1), "0.2");
        assert_eq!(tick_label(-500.0, 100.0), "-500");
        assert_eq!(tick_label(4e8, 1e8), "4e8");
        assert_eq!(tick_label(1.5e8, 5e7), "1.5e8");
        assert_eq!(tick_label(2e-5, 1e-5), "2e-5");
        assert_eq!(tick_label(0.1, 0.05), "0.1");
        assert_eq!(tick_label(1e8, 5e7), "1e8");
    }

    #[test]
    fn grid_steps_are_one_two_five_times_a_power_of_ten() {
        for (x, step) in [
            (0.3, 0.5),
            (1.0, 1.0),
            (1.7, 2.0),
            (101.0, 200.0),
            (6e-4, 1e-3),
        ] {
            let got = step_125(x);
            assert!((got - step).abs() <= 1e-12 * step, "{x}: {got} != {step}");
        }
    }
}
