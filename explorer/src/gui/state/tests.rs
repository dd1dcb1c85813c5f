//! Tests of the explorer without a window: a run and its history, the interface editor,
//! queued variants compared.

use super::*;
use crate::gui::RecordChoice;
use std::time::{Duration, Instant};

/// The explorer's logic without a window: a 3³ pull-off run started, polled to its end
/// (the whole glued face, 4 × 4 nodes, torn off by t = 0.33 s, with a small balance
/// residual), its row in the history and in the CSV export; an inadmissible law blocks
/// the next run with the library's reason; the row's settings load back.
#[test]
fn runs_and_history_without_a_window() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut app = App::default();
    app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
    assert!(app.notes.is_empty(), "{:?}", app.notes);
    app.settings.cells = 3;
    app.settings.record = RecordChoice::Off;
    assert_eq!(app.blocker(), None);
    app.start();
    assert_eq!(app.status, Status::Running);
    let started = Instant::now();
    while app.poll() {
        assert!(started.elapsed() < Duration::from_secs(60), "no end");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(app.status, Status::Ended("finished".into()));
    assert_eq!(app.history.len(), 1);
    let row = app.history[0].clone();
    assert_eq!((row.interface_nodes, row.counts.ruptured), (16, 16));
    assert!(
        row.max_relative_residual < 1e-2,
        "{}",
        row.max_relative_residual
    );
    // The live curve ends at the run's end.
    assert_eq!(app.curve_run, Some(1));
    assert_eq!(
        app.curve.points.last().map(|p| p.t),
        Some(row.simulated_time)
    );

    let dir = std::env::temp_dir().join(format!("decohesion-state-{}", std::process::id()));
    let csv = dir.join("history.csv");
    app.export_csv(&csv).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 2, "{text}");
    assert!(text.lines().nth(1).unwrap().contains(",completed,"));
    // The curves: one line per kept sample, in time order, the last at the run's end with
    // its counts.
    app.settings.output_dir = dir.display().to_string();
    app.save_curves_csv();
    let text = std::fs::read_to_string(dir.join("curves.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("run,t_s,displacement_m,reaction_N,"),
        "{}",
        lines[0]
    );
    assert_eq!(lines.len(), 1 + row.curve.points.len());
    let fields = |l: &str| -> Vec<String> { l.split(',').map(str::to_string).collect() };
    let times: Vec<f64> = lines[1..]
        .iter()
        .map(|l| fields(l)[1].parse().unwrap())
        .collect();
    assert!(times.windows(2).all(|w| w[0] < w[1]));
    assert_eq!(times.last().copied(), Some(row.simulated_time));
    let last = fields(lines.last().unwrap());
    assert_eq!(last[7].parse::<usize>().unwrap(), row.counts.ruptured);
    // The pull: the imposed displacement grows from 0, the reaction is finite throughout.
    let column = |k: usize| -> Vec<f64> {
        lines[1..]
            .iter()
            .map(|l| fields(l)[k].parse().unwrap())
            .collect()
    };
    let (u, f) = (column(2), column(3));
    assert!(u.windows(2).all(|w| w[0] <= w[1]) && u[u.len() - 1] > 0.0);
    assert!(f.iter().all(|x| x.is_finite()) && f.iter().any(|&x| x != 0.0));
    std::fs::remove_dir_all(&dir).ok();

    let law = app.settings.law.clone();
    let alpha_e = app.settings.law.knots().unwrap().alpha_e;
    (app.settings.law.values.0).insert("u_r".into(), (0.5 * alpha_e).into());
    let reason = app.blocker().expect("u_r < α_e is refused");
    assert!(reason.starts_with("u_r"), "{reason}");
    app.start();
    assert!(app.job.is_none());
    assert!(matches!(&app.status, Status::Ended(s) if s.starts_with("not started: u_r")));
    app.load_row(0);
    assert_eq!(app.settings.law, law);
    assert_eq!(app.blocker(), None);
}

/// `roller_peel` has two interfaces (the peel on the plate, the clamp on the roller): the
/// editor edits one at a time, and the other keeps its own law. Editing interface 1 (the
/// clamp) leaves the peel's law as the scene file has it, and the history row names the
/// edited interface.
#[test]
fn the_editor_edits_one_interface_at_a_time() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut app = App::default();
    app.load_scene(
        &root
            .join("../scenes/roller_peel.toml")
            .display()
            .to_string(),
    );
    assert!(app.notes.is_empty(), "{:?}", app.notes);
    assert_eq!(app.settings.interfaces, ["z- on plate", "clamp on roller"]);
    assert_eq!(app.settings.interface, 0);
    let file = app.scene().unwrap();
    let laws = |scene: &Scene| -> Vec<String> {
        (scene.model.interfaces.iter())
            .map(|i| i.law.to_string())
            .collect()
    };
    let original = laws(&file);
    // The peel law loaded by default; the clamp's once picked.
    app.edit_interface(1);
    assert_eq!(app.settings.interface, 1);
    assert_eq!(app.settings.law.law().unwrap().to_string(), original[1]);
    let u_r = app.settings.law.knots().unwrap().u_r;
    (app.settings.law.values.0).insert("u_r".into(), (2.0 * u_r).into());
    let edited = laws(&app.scene().unwrap());
    assert_eq!(edited[0], original[0], "the peel law must not change");
    assert_ne!(edited[1], original[1]);
    assert_eq!(app.settings.interface_label(), "1: clamp on roller");
    let row = HistoryRow::failed(1, &app.settings, "not run".into(), web_time::Instant::now());
    assert!(super::super::history::csv(&[row]).contains(",\"1: clamp on roller\","));
}

/// Queued variants: a key the explorer cannot vary and an inadmissible value are refused
/// naming the key, the value and what is admissible, and nothing is queued; two values of
/// u_r (given by its key path) run one after the other and are both ticked, labelled by u_r
/// alone. Each row carries its curve, ending at the run's end with its counts; once every
/// node is ruptured its mean α is u_r (eq. 12 caps α at u_r); the larger u_r dissipates
/// more (G_c grows with u_r at fixed g_N(0) and α_e).
#[test]
fn queued_variants_are_run_and_compared() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut app = App::default();
    app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
    app.settings.cells = 3;
    app.settings.record = RecordChoice::Off;
    let e = app.queue_spec("young=1e6,2e6").unwrap_err();
    assert!(
        e.contains("`young` cannot be compared")
            && e.contains("interface.law.NAME")
            && e.contains("u_r")
            && e.contains("scheme.time_step_factor"),
        "{e}"
    );
    let e = app.queue_spec("u_r=0.003,0.001").unwrap_err();
    assert!(e.starts_with("u_r = 0.001: u_r"), "{e}");
    let e = app.queue_spec("u_r=0.003,x").unwrap_err();
    assert!(e.contains("`x`: not a number"), "{e}");
    assert!(app.queue.is_empty() && app.job.is_none());

    app.queue_spec("interface.law.u_r=0.003,0.006").unwrap();
    let started = Instant::now();
    while app.poll() {
        assert!(started.elapsed() < Duration::from_secs(60), "no end");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(app.queue.is_empty());
    assert_eq!(app.history.len(), 2);
    assert_eq!(app.compare.iter().copied().collect::<Vec<_>>(), [1, 2]);
    let compared = app.compared();
    let labels: Vec<&str> = compared.iter().map(|c| c.1.as_str()).collect();
    assert_eq!(labels, ["run 1: u_r=0.003", "run 2: u_r=0.006"]);
    for (row, u_r) in app.history.iter().zip([0.003, 0.006]) {
        let last = row.curve.points.last().expect("a curve");
        assert_eq!((last.t, last.counts), (row.simulated_time, row.counts));
        assert_eq!(row.counts.ruptured, row.interface_nodes);
        assert!(
            (last.mean_alpha - u_r).abs() <= 1e-12 * u_r,
            "{}",
            last.mean_alpha
        );
        assert!(row.curve.points.len() > 100, "{}", row.curve.points.len());
    }
    assert!(app.history[1].damage_dissipated > app.history[0].damage_dissipated);
}

/// A measured curve in the explorer: `data/pull_off_noisy.csv` (the shipped pull-off with
/// α_e = 2 mm and u_r = 4 mm, 2 % noise) read with its units (mm and kN, drawn in m and N);
/// a file whose x does not increase refused with its line; u_r fitted on the edited scene from
/// 5.5 mm (38 % off) with α_e at its value: within 5 % of 4 mm (the issue's round-trip
/// tolerance for two keys and a start 50 % off; one key here), the misfit below the start's,
/// and the value taken back into the law editor, and refused for another family.
#[test]
fn a_measured_curve_is_drawn_and_fitted() {
    use crate::interface::family::ParamValue;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut app = App::default();
    app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
    app.settings.record = RecordChoice::Off;
    app.load_measured_text("u [mm], F [kN]\n0, 1\n0, 2\n", "bad.csv", None);
    assert!(app.measured.is_none());
    let note = app.notes.last().cloned().unwrap_or_default();
    assert!(
        note.starts_with("bad.csv, line 3: x = 0 after x = 0"),
        "{note}"
    );

    app.load_measured(
        &root
            .join("../data/pull_off_noisy.csv")
            .display()
            .to_string(),
    );
    let m = app.measured.as_ref().expect("the shipped curve loads");
    let si = m.si.as_ref().expect("a length and a force");
    assert_eq!(si.len(), m.curve.x.len());
    assert_eq!(si[3], [m.curve.x[3] * 1e-3, m.curve.y[3] * 1e3]);
    assert_eq!(
        (app.fit.x_column.as_str(), app.fit.y_column.as_str()),
        ("u_z_plus_z", "F_z_plus_z")
    );
    assert!(app.start_fit().unwrap_err().contains("tick at least one"));

    let spec = app.settings.law.spec().unwrap();
    let u_r = spec.params.iter().find(|p| p.key == "u_r").unwrap();
    let alpha_e = spec.params.iter().find(|p| p.key == "alpha_e").unwrap();
    *app.settings.law.value_mut(alpha_e) = ParamValue::Number(2e-3);
    *app.settings.law.value_mut(u_r) = ParamValue::Number(5.5e-3);
    let free = app.fit.free.get_mut("u_r").unwrap();
    *free = FreeKey {
        on: true,
        lo: 3e-3,
        hi: 8e-3,
    };
    app.fit.max_evals = 40;
    app.start_fit().unwrap();
    assert!(app
        .start_fit()
        .unwrap_err()
        .contains("a run or a fit is going"));
    while app.poll_fit() {
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = app.fit.outcome.as_ref().unwrap();
    let report = out.report.as_ref().unwrap();
    let fitted = report.parameters[0].value;
    assert_eq!(report.parameters[0].key, "interface.0.law.u_r");
    assert!((fitted - 4e-3).abs() < 0.05 * 4e-3, "u_r = {fitted}");
    assert!(report.fitted.cost < report.initial.unwrap().cost);
    app.apply_fit().unwrap();
    assert_eq!(app.settings.law.value(u_r), ParamValue::Number(fitted));
    app.settings.law.family = "exponential".into();
    assert!(app
        .apply_fit()
        .unwrap_err()
        .contains("the editor now edits `exponential`"));
}

/// A class's display: `hide=` hides the named panels (a name that is not a panel is refused
/// with the admissible ones) and `projector=1` sets the projector mode; the copied link keeps
/// both, after the scene and its changed keys.
#[test]
fn panels_hidden_and_the_projector_mode_go_into_links() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut app = App::default();
    app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
    let opening = crate::gui::Opening {
        hide: vec!["history,law".into(), "view".into()],
        projector: true,
        ..Default::default()
    };
    app.open(&opening).unwrap();
    let names: Vec<&str> = app.display.hidden.iter().map(String::as_str).collect();
    assert_eq!(names, ["history", "law", "view"]);
    assert!(app.display.projector && app.display.shows("settings"));
    let link = app.link_query().unwrap();
    assert!(
        link.ends_with("&hide=history,law,view&projector=1"),
        "{link}"
    );
    let bad = crate::gui::Opening {
        hide: vec!["history,plots".into()],
        ..Default::default()
    };
    let e = crate::gui::check_opening(None, &bad).unwrap_err();
    assert!(
        e.contains("hide=plots: no such panel; admissible: settings, history, view, law"),
        "{e}"
    );
    assert!(app.open(&bad).is_err());
}

/// The embeddable view (`embed=1`, for a course page's `<iframe>`): the menus, the history and
/// the measured-curve section are left out whatever `hide=` says, the plots stay; the copied
/// link is the full page's (no `embed=`, the lesson's step or the scene's keys and the `hide=`
/// given). A value of `embed=` other than 1/true/0/false is refused naming it, and so is
/// `embed=1` without a lesson or scene to show.
#[test]
fn the_embeddable_view_leaves_out_the_menus_and_links_to_the_full_page() {
    crate::gui::at_repository_root();
    use super::parse_embed;
    assert_eq!(parse_embed(None, false), Ok(false));
    assert_eq!(parse_embed(Some("1"), true), Ok(true));
    assert_eq!(parse_embed(Some("true"), true), Ok(true));
    assert_eq!(parse_embed(Some("0"), false), Ok(false));
    let e = parse_embed(Some("yes"), true).unwrap_err();
    assert!(e.starts_with("embed=yes: admissible 1 or true"), "{e}");
    let e = parse_embed(Some("1"), false).unwrap_err();
    assert!(e.contains("give lesson=NAME or scene=NAME"), "{e}");

    let mut app = App::default();
    let opening = crate::gui::Opening {
        lesson: Some("cohesive_law".into()),
        step: 4,
        hide: vec!["view".into()],
        embed: true,
        ..Default::default()
    };
    app.open(&opening).unwrap();
    assert!(app.display.embed);
    for panel in ["settings", "history", "measured", "view"] {
        assert!(!app.display.shows(panel), "{panel} shown");
    }
    assert!(app.display.shows("law") && app.display.shows("progress"));
    assert_eq!(
        app.link_query().unwrap(),
        "?lesson=cohesive_law&step=4&hide=view"
    );

    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut app = App::default();
    app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
    let opening = crate::gui::Opening {
        set: vec!["interface.law.u_r=0.005".into()],
        embed: true,
        ..Default::default()
    };
    app.open(&opening).unwrap();
    let link = app.link_query().unwrap();
    assert!(
        link.contains("set=interface.0.law.u_r%3D0.005") && !link.contains("embed"),
        "{link}"
    );
}

/// Figures for slides, as a right-click on a plot asks: SVG and CSV written at once into the
/// output folder; PNG when the window's screenshot comes (put here as the window would), cropped
/// to the plot's rectangle and readable as a PNG of its size.
#[test]
fn figures_are_saved_as_svg_csv_and_png() {
    use crate::figure::{Figure, Style};
    use crate::gui::export::Export;
    let dir = std::env::temp_dir().join(format!("decohesion-figures-{}", std::process::id()));
    let mut app = App::default();
    app.settings.output_dir = dir.display().to_string();
    let mut fig = Figure {
        title: "run 1: force on the pulled faces [N]".into(),
        x_label: "t [s]".into(),
        y_label: "|reaction| [N]".into(),
        traces: vec![],
    };
    fig.trace(
        "|reaction|",
        vec![[0.0, 0.0], [0.1, 5.0]],
        [31, 119, 180],
        Style::Solid,
    );
    let ctx = egui::Context::default();
    app.export_figure(&ctx, &fig, Export::Svg);
    app.export_figure(&ctx, &fig, Export::Csv);
    let stem = dir.join("run_1_force_on_the_pulled_faces_N");
    let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
    assert_eq!(svg.matches("<polyline").count(), 1);
    let csv = std::fs::read_to_string(stem.with_extension("csv")).unwrap();
    assert_eq!(csv.lines().nth(3), Some("|reaction|,0.1,5.0"));

    let rect = egui::Rect::from_min_size(egui::pos2(1.0, 1.0), egui::vec2(2.0, 1.0));
    app.export_figure(&ctx, &fig, Export::Png(rect));
    app.take_screenshot(&ctx);
    assert!(
        app.pending_png.is_some(),
        "nothing saved before the screenshot"
    );
    let shot = egui::ColorImage::new([4, 3], vec![egui::Color32::RED; 12]);
    let slot = app.pending_png.as_ref().unwrap().image.clone();
    *slot.lock().unwrap() = Some(std::sync::Arc::new(shot));
    app.take_screenshot(&ctx);
    assert!(app.pending_png.is_none());
    let png = std::fs::read(stem.with_extension("png")).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (2, 1));
    assert_eq!(&buf[..4], &[255, 0, 0, 255]);
    std::fs::remove_dir_all(&dir).ok();
}

/// The 3-D view's animation: after a 3³ pull-off, "save GIF" shows 60 of the run's frames one
/// after the other (the first and the last included), takes each one's screenshot (put here as
/// the window would) cropped to the view, and writes a GIF of 60 frames of the view's size.
#[test]
fn the_3d_view_is_saved_as_a_gif() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("decohesion-gif-{}", std::process::id()));
    let mut app = App::default();
    app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
    app.settings.cells = 3;
    app.settings.record = RecordChoice::Off;
    app.settings.output_dir = dir.display().to_string();
    app.start();
    while app.poll() {
        std::thread::sleep(Duration::from_millis(10));
    }
    let frames = app.view.frames().len();
    assert!(frames > 60, "{frames} frames");
    app.view.rect = Some(egui::Rect::from_min_size(
        egui::pos2(0.0, 0.0),
        egui::vec2(8.0, 6.0),
    ));
    let ctx = egui::Context::default();
    app.start_gif();
    let mut shown = vec![];
    while app.gif.is_some() {
        app.gif_step(&ctx);
        let Some(g) = &app.gif else { break };
        shown.push(app.view.shown.unwrap());
        let shot = egui::ColorImage::new([10, 10], vec![egui::Color32::GRAY; 100]);
        let slot = g.slot.clone().expect("a screenshot is asked for");
        *slot.lock().unwrap() = Some(std::sync::Arc::new(shot));
    }
    assert_eq!(shown.len(), crate::gui::animation::GIF_FRAMES);
    assert_eq!((shown[0], shown[59]), (0, frames - 1));
    let name = dir.join("pull_off_3d_view.gif");
    let bytes =
        std::fs::read(&name).unwrap_or_else(|e| panic!("{}: {e}; {:?}", name.display(), app.notes));
    let mut decoder = gif::DecodeOptions::new()
        .read_info(std::io::Cursor::new(bytes))
        .unwrap();
    let mut count = 0;
    while let Some(f) = decoder.read_next_frame().unwrap() {
        assert_eq!((f.width, f.height), (8, 6));
        count += 1;
    }
    assert_eq!(count, 60);
    std::fs::remove_dir_all(&dir).ok();
}

/// Inspecting a node: after a 3³ pull-off, a click where the 3-D view draws the glued corner
/// (0, 0, 0) selects it, and its plots and numbers are the run's: each frame's reading is the
/// state of the same scene stepped alone to that frame's step, to the bit; α rises to u_r, the
/// node ends ruptured; the numbers at the slider's frame are that frame's. A click far from
/// every node clears the selection.
#[test]
fn a_node_clicked_in_the_3d_view_shows_its_run() {
    use crate::output::watch::{Reading, Source};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut app = App::default();
    app.load_scene(&root.join("../scenes/pull_off.toml").display().to_string());
    app.settings.cells = 3;
    app.settings.record = RecordChoice::Off;
    app.start();
    while app.poll() {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(app.status, Status::Ended("finished".into()));
    let model = app.scene().unwrap().model;
    let corner = model
        .mesh
        .nodes
        .iter()
        .position(|x| *x == [0.0; 3])
        .unwrap() as u32;
    let rect = egui::Rect::from_min_size(egui::pos2(10.0, 20.0), egui::vec2(400.0, 300.0));
    let i = app.view.index().unwrap();
    let f = &app.view.frames()[i];
    let k = (f.topology.boundary_nodes.iter())
        .position(|&n| n == corner)
        .unwrap();
    let (at, _) = app.view.project(rect, i, f.points[k]).unwrap();
    assert!(rect.contains(at), "{at:?}");
    app.view.pick(rect, at);
    assert_eq!(app.view.selected, Some(k));
    let node = app.view.inspected().unwrap();
    assert_eq!(node.node, corner);
    assert!(node.label.contains("z-"), "{}", node.label);
    assert_eq!(node.series.len(), app.view.frames().len());
    let mut sim = Simulation::new(model.clone()).unwrap();
    for &(t, step, r) in &node.series {
        while sim.state.step_count < step {
            sim.step().unwrap();
        }
        assert_eq!((sim.state.step_count, sim.state.time), (step, t));
        assert_eq!(r, Reading::of(&sim, Source::Interface(k)), "step {step}");
    }
    let law = &model.interfaces[0].law;
    let last = node.series.last().unwrap().2;
    assert_eq!((last.alpha, last.state_name()), (law.u_r, "ruptured"));
    // The numbers shown are the slider's frame's.
    app.view.shown = Some(3);
    let node = app.view.inspected().unwrap();
    let (t, _, r) = node.series[3];
    let text = super::super::plots::node_text(&node);
    assert!(text.contains(&format!("t = {t:.4e} s")), "{text}");
    assert!(text.contains(&format!("α = {:.4e} m", r.alpha)), "{text}");
    let figures = super::super::plots::node_figures(&node);
    assert_eq!(figures[2].traces[0].points.len(), node.series.len());
    app.view.pick(rect, rect.max + egui::vec2(100.0, 100.0));
    assert_eq!(app.view.selected, None);
}

/// A lesson step's `time` and `node`: its run shows the frame nearest that time (the view stops
/// following the newest there) with that node inspected.
#[test]
fn a_lesson_step_holds_a_time_and_a_node() {
    crate::gui::at_repository_root();
    let text = r#"+++
title = "Hold"
scene = "pull_off"
+++
## The corner at 0.08 s

```step
set = ["mesh.cells=[3,3,3]"]
run = true
time = 0.08
node = 3
```
"#;
    let lesson = crate::gui::lesson::load(text, "lessons/hold.md").unwrap();
    let mut app = App::default();
    app.settings.record = RecordChoice::Off;
    app.open_lesson(lesson, 0);
    while app.poll() {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(app.status, Status::Ended("finished".into()));
    let frames = app.view.frames();
    let i = app.view.index().unwrap();
    assert!(i + 1 < frames.len(), "the view follows the newest frame");
    let nearest = (0..frames.len())
        .min_by(|&a, &b| {
            let d = |k: usize| (frames[k].time - 0.08).abs();
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    assert_eq!(i, nearest, "t = {} s", frames[i].time);
    let node = app.view.inspected().unwrap();
    assert_eq!(node.node, 3);
    assert_eq!(node.shown, i);
    // Leaving the lesson lets the view follow the next run again.
    app.close_lesson();
    app.start();
    while app.poll() {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(app.view.index(), Some(app.view.frames().len() - 1));
}
