//! The explorer's plots (egui_plot): the edited law's curves g_N(α), T(δ), μ(α), the
//! interface states and balance residual of the running or last run, and the runs ticked for
//! comparison overlaid (states against time, reaction against imposed displacement, mean α
//! against time), each in its run's colour.

use super::export::Export;
use super::history::CurvePoint;
use super::lesson::PlotName;
use super::view3d::Inspected;
use super::App;
use crate::figure::{Figure, Style};
use crate::output::watch::Reading;
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
    use crate::vary::PALETTE;
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

/// One plot of a row: its figure (what is drawn and exported), its title as shown (the lesson's
/// mark), its id, and marks drawn over it but not exported.
struct Panel<'a> {
    fig: Figure,
    title: egui::WidgetText,
    id: &'a str,
    marks: Box<dyn FnOnce(&mut egui_plot::PlotUi) + 'a>,
}

impl<'a> Panel<'a> {
    fn new(fig: Figure, title: impl Into<egui::WidgetText>, id: &'a str) -> Panel<'a> {
        Panel {
            fig,
            title: title.into(),
            id,
            marks: Box::new(|_| {}),
        }
    }

    fn marks(mut self, marks: impl FnOnce(&mut egui_plot::PlotUi) + 'a) -> Panel<'a> {
        self.marks = Box::new(marks);
        self
    }
}

/// A figure with its axes' labels and no series yet.
fn figure(title: &str, x_label: &str, y_label: &str) -> Figure {
    Figure {
        title: title.to_string(),
        x_label: x_label.to_string(),
        y_label: y_label.to_string(),
        traces: vec![],
    }
}

/// The colour lines take when a figure gives one series (egui_plot's first automatic colour).
const INK: [u8; 3] = [31, 119, 180];

impl App {
    /// Draws `panels` side by side, a third of the width each; a right-click on one offers its
    /// figure as PNG, SVG or CSV, carried out here.
    fn plot_row(&mut self, ui: &mut egui::Ui, mut panels: Vec<Panel<'_>>) {
        let projector = self.display.projector;
        // Three plots a row, or as many as fit at 150 points (the embedded page's narrow
        // frame), the others on the next rows.
        let avail = ui.available_width();
        let per_row = ((avail / 158.0).floor() as usize).clamp(1, 3);
        let w = (avail / per_row as f32 - 8.0).max(150.0);
        let mut asked = None;
        ui.horizontal_wrapped(|ui| {
            for (k, panel) in panels.iter_mut().enumerate() {
                let marks = std::mem::replace(&mut panel.marks, Box::new(|_| {}));
                let title = std::mem::replace(&mut panel.title, "".into());
                if let Some(e) = figure_plot(ui, title, &panel.fig, panel.id, w, projector, marks) {
                    asked = Some((k, e));
                }
            }
        });
        if let Some((k, e)) = asked {
            self.export_figure(ui.ctx(), &panels[k].fig, e);
        }
    }

    /// The law's curves, with α_e and u_r marked.
    pub(super) fn plots_ui(&mut self, ui: &mut egui::Ui) {
        let Ok(law) = self.settings.law.law() else {
            ui.label("(no plot: the law is inadmissible)");
            return;
        };
        let mu_inf = self.settings.law.mu_inf;
        let n = 300;
        let span = law.u_r * 1.15;
        let xs: Vec<f64> = (0..=n).map(|k| span * k as f64 / n as f64).collect();
        let curve = |label: &str, title: &str, x: &str, y: &str, f: &dyn Fn(f64) -> [f64; 2]| {
            let mut fig = figure(title, x, y);
            fig.trace(label, xs.iter().map(|&a| f(a)).collect(), INK, Style::Solid);
            fig
        };
        let g = curve(
            "g_N(α)",
            "stiffness g_N(α)",
            "α [mm]",
            "g_N [Pa/m]",
            &|a| [1e3 * a, law.g_n(a)],
        );
        let t = curve("T(δ)", "traction T(δ)", "δ [mm]", "T [MPa]", &|d| {
            [1e3 * d, 1e-6 * law.traction(d)]
        });
        let mu = curve("μ(α)", "friction μ(α)", "α [mm]", "μ [-]", &|a| {
            [1e3 * a, law.mu(a, mu_inf)]
        });
        let (ae, ur) = (1e3 * law.alpha_e, 1e3 * law.u_r);
        let marks = move |p: &mut egui_plot::PlotUi| {
            p.vline(VLine::new("α_e", ae));
            p.vline(VLine::new("u_r", ur));
        };
        let titles = [
            self.plot_title(PlotName::Law, "stiffness g_N(α) [Pa/m]"),
            self.plot_title(PlotName::Traction, "traction T(δ) = g_N(δ)δ [MPa]"),
            self.plot_title(
                PlotName::Friction,
                "friction μ(α) = μ_inf (1 − g_N(α)/g_N(0))",
            ),
        ];
        let [t_law, t_traction, t_mu] = titles;
        self.plot_row(
            ui,
            vec![
                Panel::new(g, t_law, "g_n").marks(marks),
                Panel::new(t, t_traction, "traction").marks(marks),
                Panel::new(mu, t_mu, "mu").marks(marks),
            ],
        );
    }

    pub(super) fn progress_plot_ui(&mut self, ui: &mut egui::Ui) {
        let Some(run) = self.curve_run else {
            ui.label("Run a scene to see its interface states over time here.");
            return;
        };
        let points = &self.curve.points;
        let pick = |f: fn(&StateCounts) -> usize| series(points, |p| [p.t, f(&p.counts) as f64]);
        let title = format!("run {run}: interface nodes by state (paper fig. 6, right)");
        let mut states = figure(&title, "t [s]", "nodes");
        states.trace("elastic", pick(|c| c.elastic), [46, 160, 67], Style::Solid);
        states.trace(
            "transition",
            pick(|c| c.transition),
            [245, 166, 35],
            Style::Solid,
        );
        states.trace("ruptured", pick(|c| c.ruptured), [208, 2, 27], Style::Solid);
        // Glue that forms on contact: its nodes not formed yet (none in other scenes).
        if points.iter().any(|p| p.counts.unformed > 0) {
            states.trace("unformed", pick(|c| c.unformed), [90, 90, 90], Style::Solid);
        }
        let t_states = self.plot_title(PlotName::States, &title);
        let title = format!("run {run}: force on the pulled faces [N]");
        let mut force = figure(&title, "t [s]", "|reaction| [N]");
        force.trace(
            "|reaction|",
            series(points, |p| [p.t, p.force]),
            INK,
            Style::Solid,
        );
        let t_force = self.plot_title(PlotName::Force, &title);
        let title = format!("run {run}: balance residual / largest energy");
        let mut residual = figure(&title, "t [s]", "residual [-]");
        let data = series(points, |p| [p.t, p.residual]);
        residual.trace("residual", data, INK, Style::Solid);
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
        let prediction = move |p: &mut egui_plot::PlotUi| {
            if let Some(f) = predicted {
                let colour = Color32::from_rgb(230, 150, 0);
                p.hline(egui_plot::HLine::new("your prediction", f).color(colour));
            }
        };
        self.plot_row(
            ui,
            vec![
                Panel::new(states, t_states, "counts"),
                Panel::new(force, t_force, "force").marks(prediction),
                Panel::new(residual, title, "residual"),
            ],
        );
    }
}

/// The x, y, z colours of a vector's components.
const AXIS_COLOURS: [[u8; 3]; 3] = [[220, 60, 60], [60, 170, 80], [60, 120, 230]];

/// The figures of the inspected node over the run: its jump [u] and gap g [mm]; the glue's
/// traction −R_d (solid) and the contact's R_c/h (dashed) on the solid [MPa]; its damage α
/// [mm]; the codes of its state (0 elastic, 1 transition, 2 ruptured, 3 unformed) and of its
/// contact status (0 open, 1 stick, 2 slip). A contact-only node has no jump, glue or α.
pub(super) fn node_figures(node: &Inspected) -> [Figure; 4] {
    let n = node.node;
    let glued = node.series.first().is_some_and(|s| s.2.state.is_some());
    let over = |f: &dyn Fn(&Reading) -> f64| -> Vec<[f64; 2]> {
        let points = node.series.iter().map(|(t, _, r)| [*t, f(r)]);
        points.filter(|p| p[1].is_finite()).collect()
    };
    let mut lengths = figure(
        &format!("node {n}: jump [u] and gap g [mm]"),
        "t [s]",
        "[mm]",
    );
    if glued {
        for (i, a) in ["x", "y", "z"].into_iter().enumerate() {
            let data = over(&|r| 1e3 * r.jump[i]);
            lengths.trace(&format!("[u]_{a}"), data, AXIS_COLOURS[i], Style::Solid);
        }
    }
    lengths.trace("g", over(&|r| 1e3 * r.gap), INK, Style::Dashed);
    let mut traction = figure(
        &format!("node {n}: traction on the solid [MPa]"),
        "t [s]",
        "[MPa]",
    );
    for (i, a) in ["x", "y", "z"].into_iter().enumerate() {
        if glued {
            let data = over(&|r| 1e-6 * r.glue[i]);
            traction.trace(
                &format!("glue −R_d,{a}"),
                data,
                AXIS_COLOURS[i],
                Style::Solid,
            );
        }
        let data = over(&|r| 1e-6 * r.contact[i]);
        let label = format!("contact R_c/h,{a}");
        traction.trace(&label, data, AXIS_COLOURS[i], Style::Dashed);
    }
    let mut alpha = figure(&format!("node {n}: damage α [mm]"), "t [s]", "α [mm]");
    if glued {
        alpha.trace("α", over(&|r| 1e3 * r.alpha), INK, Style::Solid);
    }
    let mut codes = figure(
        &format!(
            "node {n}: state (0 elastic, 1 transition, 2 ruptured, 3 unformed), contact (0 open, 1 stick, 2 slip)"
        ),
        "t [s]",
        "code",
    );
    if glued {
        codes.trace(
            "state",
            over(&Reading::state_code),
            [208, 2, 27],
            Style::Solid,
        );
    }
    codes.trace(
        "contact",
        over(&Reading::status_code),
        [30, 120, 220],
        Style::Dashed,
    );
    [lengths, traction, alpha, codes]
}

/// The inspected node's numbers at the frame shown, as one text.
pub(super) fn node_text(node: &Inspected) -> String {
    let Some((t, step, r)) = node.series.get(node.shown) else {
        return format!("node {}: no frame", node.node);
    };
    let v = |x: [f64; 3]| format!("({:.4e}, {:.4e}, {:.4e})", x[0], x[1], x[2]);
    let mut s = format!(
        "node {}, {}: at t = {t:.4e} s (step {step}), ",
        node.node, node.label
    );
    if r.state.is_some() {
        s += &format!(
            "[u] = {} m, α = {:.4e} m, state {}, glue traction −R_d = {} Pa, ",
            v(r.jump),
            r.alpha,
            r.state_name(),
            v(r.glue)
        );
    }
    s += &format!(
        "g = {:.4e} m, contact {}, contact traction R_c/h = {} Pa",
        r.gap,
        r.status_name(),
        v(r.contact)
    );
    s
}

impl App {
    /// The node picked in the 3-D view: its numbers at the slider's frame, and its plots over
    /// the run with that frame's time marked.
    pub(super) fn node_plot_ui(&mut self, ui: &mut egui::Ui) {
        let Some(node) = self.view.inspected() else {
            return;
        };
        ui.horizontal(|ui| {
            ui.strong(format!("Inspected node {}", node.node));
            if ui.button("clear").clicked() {
                self.view.selected = None;
            }
        });
        ui.label(node_text(&node));
        let now = node.series.get(node.shown).map(|s| s.0);
        let mark = move |p: &mut egui_plot::PlotUi| {
            if let Some(t) = now {
                p.vline(VLine::new("shown", t).color(Color32::from_rgb(255, 230, 0)));
            }
        };
        let [lengths, traction, alpha, codes] = node_figures(&node);
        let panel = |fig: Figure, id| {
            let title = fig.title.clone();
            Panel::new(fig, title, id).marks(mark)
        };
        self.plot_row(
            ui,
            vec![
                panel(lengths, "node_lengths"),
                panel(traction, "node_traction"),
                panel(alpha, "node_alpha"),
            ],
        );
        self.plot_row(ui, vec![panel(codes, "node_codes")]);
    }
}

/// Draws `fig` at width `w` under `title`, then `marks`; a right-click offers the figure as
/// PNG, SVG or CSV, and the choice is returned.
fn figure_plot<'a>(
    ui: &mut egui::Ui,
    title: egui::WidgetText,
    fig: &Figure,
    id: &str,
    w: f32,
    projector: bool,
    marks: Box<dyn FnOnce(&mut egui_plot::PlotUi) + 'a>,
) -> Option<Export> {
    let mut asked = None;
    ui.vertical(|ui| {
        // A long title is cut to the plot's width (whole on hover), not widening the row.
        let title = egui::Label::new(title).truncate();
        ui.allocate_ui(egui::vec2(w, 0.0), |ui| ui.add(title));
        let shown = plot_125(Plot::new(id))
            .width(w)
            .height(210.0)
            .x_axis_label(fig.x_label.clone())
            .legend(Legend::default())
            .show(ui, |p| {
                for t in &fig.traces {
                    let colour = Color32::from_rgb(t.colour[0], t.colour[1], t.colour[2]);
                    let data = t.points.clone();
                    if t.style == Style::Points {
                        p.points(Points::new(t.label.clone(), data).radius(3.0).color(colour));
                        continue;
                    }
                    let style = match t.style {
                        Style::Dashed => LineStyle::dashed_dense(),
                        Style::Dotted => LineStyle::dotted_dense(),
                        _ => LineStyle::Solid,
                    };
                    let line = Line::new(t.label.clone(), data).color(colour).style(style);
                    p.line(match projector {
                        true => line.width(super::state::PROJECTOR_LINE),
                        false => line,
                    });
                }
                marks(p);
            });
        let rect = shown.response.rect;
        shown
            .response
            .on_hover_text("right-click: save as PNG, SVG or CSV")
            .context_menu(|ui| {
                for (label, e) in [
                    ("save PNG", Export::Png(rect)),
                    ("save SVG", Export::Svg),
                    ("save CSV", Export::Csv),
                ] {
                    if ui.button(label).clicked() {
                        asked = Some(e);
                        ui.close();
                    }
                }
            });
    });
    asked
}

impl App {
    /// The runs ticked in the history, overlaid: interface states against time (ruptured
    /// solid, transition dashed, elastic dotted), reaction against imposed displacement, mean
    /// α against time; one legend entry per run (its parameters that differ between the runs),
    /// and the measured curve, if one is loaded, over the reaction.
    pub(super) fn compare_plots_ui(&mut self, ui: &mut egui::Ui) {
        let runs = self.compared();
        ui.label(format!(
            "{} runs compared (tick or untick them in the history)",
            runs.len()
        ));
        let styles = [
            (Style::Solid, (|c| c.ruptured) as fn(&StateCounts) -> usize),
            (Style::Dashed, |c| c.transition),
            (Style::Dotted, |c| c.elastic),
        ];
        let colour = |id: u32| {
            let c = run_colour(id);
            [c.r(), c.g(), c.b()]
        };
        let title = "interface nodes: ruptured solid, transition dashed, elastic dotted";
        let mut counts = figure(title, "t [s]", "nodes");
        for (row, label) in &runs {
            for (style, f) in &styles {
                let data = series(&row.curve.points, |q| [q.t, f(&q.counts) as f64]);
                counts.trace(label, data, colour(row.id), *style);
            }
        }
        let overlay = |fig: &mut Figure, f: &dyn Fn(&CurvePoint) -> [f64; 2]| {
            for (row, label) in &runs {
                fig.trace(
                    label,
                    series(&row.curve.points, f),
                    colour(row.id),
                    Style::Solid,
                );
            }
        };
        let title = "reaction [kN] against imposed displacement [mm]";
        let mut reaction = figure(title, "U [mm]", "reaction [kN]");
        overlay(&mut reaction, &|q| {
            [1e3 * q.displacement, 1e-3 * q.reaction]
        });
        if let Some(m) = &self.measured {
            if let Ok(points) = &m.si {
                let points = points.iter().map(|[x, y]| [1e3 * x, 1e-3 * y]).collect();
                let label = format!("measured ({})", m.curve.file);
                reaction.trace(&label, points, [235, 235, 235], Style::Points);
            }
        }
        let title = "mean damage α [mm] over the interface";
        let mut alpha = figure(title, "t [s]", "mean α [mm]");
        overlay(&mut alpha, &|q| [q.t, 1e3 * q.mean_alpha]);
        drop(runs);
        let panel = |fig: Figure, id| {
            let title = fig.title.clone();
            Panel::new(fig, title, id)
        };
        let panels = vec![
            panel(counts, "compare_counts"),
            panel(reaction, "compare_reaction"),
            panel(alpha, "compare_alpha"),
        ];
        self.plot_row(ui, panels);
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
