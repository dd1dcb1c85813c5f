//! The explorer window, headless (egui_kittest drives the real UI code through AccessKit):
//! an inadmissible law disables Run and says why; Run on a small scene reaches "finished" and
//! adds a history row; Stop during a run leaves a complete recording; the ParaView option writes
//! frames that read back with the run's outcome.

use crate::common::capture::{read_capture, steps_with};
use crate::common::paraview::{read_pvd, read_vtu, state_counts};
use decohesion::gui::{App, RecordChoice, Status};
use decohesion::law::{families, ParamKind};
use egui::accesskit::Role;
use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use std::time::{Duration, Instant};

fn harness(app: App) -> Harness<'static, App> {
    // The window asks for a few more frames after a load or a run (`App::settle`, so that
    // the plots' axes widen to their labels), each 100 ms apart: more than kittest's default
    // 4 steps when the machine is loaded, so `run()` may take up to 32 to settle.
    Harness::builder()
        .with_size([1500.0, 950.0])
        .with_max_steps(32)
        .build_ui_state(|ui, app: &mut App| app.ui(ui), app)
}

/// The pull-off scene at `cells`³, recorded nowhere unless the test says so.
fn small_pull_off(cells: usize) -> App {
    let mut app = App::default();
    app.load_scene("scenes/pull_off.toml");
    app.settings.cells = cells;
    app.settings.record = RecordChoice::Off;
    app
}

/// Steps the UI (which polls the solver thread) until the run ends or `timeout` passes.
fn wait_for_end(h: &mut Harness<'static, App>, timeout: Duration) {
    let start = Instant::now();
    while matches!(h.state().status, Status::Running) {
        assert!(
            start.elapsed() < timeout,
            "the run did not end in {timeout:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
}

fn run_disabled(h: &Harness<'static, App>) -> bool {
    h.get_by_label("Run").accesskit_node().is_disabled()
}

#[test]
fn inadmissible_law_disables_run_and_says_why() {
    let mut h = harness(small_pull_off(3));
    h.run();
    assert!(!run_disabled(&h), "the scene's own law is admissible");

    // u_r below α_e = 2 mm: rupture before the end of the elastic range.
    h.state_mut()
        .settings
        .law
        .values
        .0
        .insert("u_r".into(), 1.0e-3.into());
    h.run();
    assert!(run_disabled(&h));
    h.get_by_label_contains("Run is disabled: u_r");
    h.get_by_label_contains("inadmissible law — u_r");

    // Fixed: enabled again.
    h.state_mut()
        .settings
        .law
        .values
        .0
        .insert("u_r".into(), 4.0e-3.into());
    h.run();
    assert!(!run_disabled(&h));

    // A table that increases is refused too.
    let points = vec![[0.0, 1e8], [1e-3, 2e8], [2e-3, 0.0]];
    h.state_mut().settings.law.family = "table".into();
    h.state_mut()
        .settings
        .law
        .values
        .0
        .insert("points".into(), points.into());
    h.run();
    assert!(run_disabled(&h));
}

/// The law editor is the table of families: the picker offers every family by its label, and
/// each family, at its defaults, shows a labelled slider per number parameter, a row per point
/// of a table parameter, and what its (admissible) law gives. A family added to
/// `physics/src/interface/laws/` is listed and edited without a line of the explorer.
#[test]
fn the_law_editor_is_built_from_the_table_of_families() {
    let mut h = harness(small_pull_off(3));
    h.run();
    h.get_by_label("family").click();
    h.run();
    for f in families() {
        assert!(
            h.query_all_by_label(f.label).next().is_some(),
            "{} is not offered",
            f.label
        );
    }
    let mut others = None;
    for f in families() {
        h.state_mut().settings.law.family = f.key.into();
        h.state_mut().settings.law.values = Default::default();
        h.run();
        let shown = |text: &str| {
            (h.query_all_by_label_contains(text)).any(|n| n.accesskit_node().role() == Role::Label)
        };
        assert!(shown("peak traction"), "{}: no admissible law", f.key);
        let mut numbers = 0;
        for p in f.params {
            match p.kind {
                ParamKind::Number(_) => {
                    h.get_by_role_and_label(Role::Label, p.symbol);
                    numbers += 1;
                }
                ParamKind::Points { default } => {
                    assert!(shown(p.meaning), "{}", p.meaning);
                    assert_eq!(
                        h.query_all_by_label("−").count(),
                        default.len(),
                        "{}",
                        f.key
                    );
                    h.get_by_label("add a point");
                }
            }
        }
        // Every other slider (μ_inf, run settings) is the same whatever the family.
        let sliders = h.query_all_by_role(Role::Slider).count();
        assert_eq!(
            *others.get_or_insert(sliders - numbers),
            sliders - numbers,
            "{}",
            f.key
        );
    }
}

#[test]
fn run_reaches_finished_and_adds_a_history_row() {
    let mut h = harness(small_pull_off(3));
    h.run();
    h.get_by_label("Run").click();
    h.step();
    assert_eq!(h.state().status, Status::Running);
    wait_for_end(&mut h, Duration::from_secs(60));
    assert_eq!(h.state().status, Status::Ended("finished".into()));
    let app = h.state();
    assert_eq!(app.history.len(), 1);
    let row = &app.history[0];
    // 3×3×3 cube: the glued face has 4×4 nodes, all torn off by t = 0.33 s.
    assert_eq!(row.interface_nodes, 16);
    assert_eq!(row.counts.ruptured, 16);
    assert!(row.time_full_rupture.is_some());
    assert!(
        row.max_relative_residual < 1e-2,
        "{}",
        row.max_relative_residual
    );
    h.step();
    h.get_by_label("16/16");

    // The history exports as CSV with a header and one row.
    let dir = std::env::temp_dir().join(format!("decohesion-gui-{}", std::process::id()));
    let csv = dir.join("history.csv");
    h.state_mut().export_csv(&csv).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 2, "{text}");
    assert!(text.lines().nth(1).unwrap().contains(",completed,"));
}

#[test]
fn stop_during_a_run_leaves_a_valid_recording() {
    let dir = std::env::temp_dir().join(format!("decohesion-gui-stop-{}", std::process::id()));
    let mut app = small_pull_off(6);
    app.settings.end_time = 10.0; // far longer than the test waits
    app.settings.record = RecordChoice::File;
    app.settings.output_dir = dir.display().to_string();
    let mut h = harness(app);
    h.run();
    h.get_by_label("Run").click();
    // Wait until the solver has reported progress, then press Stop.
    let start = Instant::now();
    while h.state().job.as_ref().and_then(|j| j.last).is_none() {
        assert!(start.elapsed() < Duration::from_secs(30), "no progress");
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    h.get_by_label("Stop").click();
    wait_for_end(&mut h, Duration::from_secs(30));
    assert_eq!(h.state().status, Status::Ended("stopped".into()));
    let row = h.state().history[0].clone();
    assert_eq!(row.status, "cancelled");
    assert!(row.simulated_time < 10.0);
    let path = row.recording.expect("recorded to a file");
    let store = read_capture(std::path::Path::new(&path));
    let frames = steps_with(
        &store,
        "/body/surface",
        rerun::Mesh3D::descriptor_vertex_positions().component,
    );
    assert_eq!(frames.first(), Some(&0));
    assert_eq!(frames.last(), Some(&(row.steps as i64)), "ends at the stop");
}

/// The window stays responsive on a 56³ run (175 616 hex8): its solver thread reports
/// progress while the window draws, the 3-D view receives the run's frames, and Stop ends the
/// run at the solver's next step. The frame times and the stop latency are printed, not
/// asserted (`--nocapture`; machines differ; docs: performance log).
#[test]
fn a_56_cube_run_reports_progress_and_stops_at_the_next_step() {
    let mut app = small_pull_off(56);
    app.settings.end_time = 10.0; // far longer than the test waits
    let mut h = harness(app);
    h.run();
    h.get_by_label("Run").click();
    let start = Instant::now();
    let mut frame_ms = Vec::new();
    let mut reports = std::collections::BTreeSet::new();
    // Until the solver has reported at least five distinct steps (set-up included).
    while reports.len() < 5 {
        assert!(
            start.elapsed() < Duration::from_secs(600),
            "no progress from the 56³ run"
        );
        std::thread::sleep(Duration::from_millis(20));
        let t = Instant::now();
        h.step();
        frame_ms.push(t.elapsed().as_secs_f64() * 1e3);
        assert_eq!(h.state().status, Status::Running);
        if let Some((step, _)) = h.state().job.as_ref().and_then(|j| j.last) {
            reports.insert(step);
        }
    }
    let first_report = start.elapsed();
    assert!(
        !h.state().view.frames().is_empty(),
        "the 3-D view received the run's frames"
    );
    let seen = *reports.last().unwrap();
    let clicked = Instant::now();
    h.get_by_label("Stop").click();
    let mut frames_to_end = 0;
    while matches!(h.state().status, Status::Running) {
        assert!(clicked.elapsed() < Duration::from_secs(60), "Stop ignored");
        std::thread::sleep(Duration::from_millis(5));
        h.step();
        frames_to_end += 1;
    }
    let stop_ms = clicked.elapsed().as_secs_f64() * 1e3;
    assert_eq!(h.state().status, Status::Ended("stopped".into()));
    let row = h.state().history[0].clone();
    assert_eq!(row.status, "cancelled");
    assert!(row.steps >= seen, "{} < {seen}", row.steps);
    frame_ms.sort_by(f64::total_cmp);
    println!(
        "56³ in the window: {} frames while running, frame time median {:.1} ms, max {:.1} ms; \
         five progress reports after {:.1} s (set-up included); Stop -> ended in {stop_ms:.0} ms, \
         {frames_to_end} frames, {} steps after the last report seen",
        frame_ms.len(),
        frame_ms[frame_ms.len() / 2],
        frame_ms[frame_ms.len() - 1],
        first_report.as_secs_f64(),
        row.steps - seen
    );
}

/// Settings saved by an older version (missing fields) still load, with defaults for the rest,
/// and what is saved comes back identical.
#[test]
fn saved_settings_round_trip_and_tolerate_missing_fields() {
    use decohesion::gui::Settings;
    let old: Settings =
        serde_json::from_str(r#"{"scene": "scenes/pull_off.toml", "cells": 5}"#).unwrap();
    assert_eq!(old.cells, 5);
    assert_eq!(old.law, Settings::default().law);
    let mut s = Settings::default();
    s.law.values.0.insert("u_r".into(), 7e-3.into());
    s.record = RecordChoice::File;
    let back: Settings = serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap();
    assert_eq!(back, s);
}

/// A scene whose mesh is a Gmsh file: no cells setting (the window says why), and it runs.
#[test]
fn scene_with_a_mesh_file_runs_without_the_cells_setting() {
    let mut app = App::default();
    app.load_scene("scenes/tread.toml");
    app.settings.record = RecordChoice::Off;
    assert_eq!(app.settings.cells, 0, "0 = the mesh of the file");
    let mut h = harness(app);
    h.run();
    h.get_by_label_contains("mesh from the scene's Gmsh file");
    assert!(!run_disabled(&h));
    h.get_by_label("Run").click();
    h.step();
    wait_for_end(&mut h, Duration::from_secs(60));
    assert_eq!(h.state().status, Status::Ended("finished".into()));
    let row = &h.state().history[0];
    // The 31 × 16 bottom nodes of the tread block, all torn off.
    assert_eq!((row.interface_nodes, row.counts.ruptured), (496, 496));
}

#[test]
fn the_regime_warnings_show_before_a_run() {
    // ν = 0.499 with full integration: the window shows the locking warning of the solver
    // (`Simulation::advisories`) with its recommended hourglass coefficient, and the pull-off
    // (ν = 0.45) shows no locking warning.
    let mut app = App::default();
    app.load_scene("scenes/extreme/incompressible_beam.toml");
    app.settings.record = RecordChoice::Off;
    let mut h = harness(app);
    h.run();
    h.get_by_label_contains("locks volumetrically");
    h.get_by_label_contains("scheme.hourglass_coefficient = 2.0e-4");
    let mut h = harness(small_pull_off(4));
    h.run();
    assert!(h.query_by_label_contains("locks volumetrically").is_none());
    h.get_by_label_contains("the interface stiffness sets the stable step");
}

/// With "also write ParaView files", a run leaves a `.pvd` index in the output folder whose
/// frames go from t = 0 to the run's end time, the last one with every interface node
/// ruptured (the history row's count), and the CSV export names it.
#[test]
fn paraview_option_writes_frames_that_read_back() {
    let dir = std::env::temp_dir().join(format!("decohesion-gui-vtk-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut app = small_pull_off(3);
    app.settings.paraview = true;
    app.settings.frames = 20;
    app.settings.output_dir = dir.display().to_string();
    let mut h = harness(app);
    h.run();
    h.get_by_label_contains("also write ParaView files");
    h.get_by_label("Run").click();
    h.step();
    wait_for_end(&mut h, Duration::from_secs(60));
    assert_eq!(h.state().status, Status::Ended("finished".into()));
    let row = h.state().history[0].clone();
    let pvd = std::path::PathBuf::from(row.paraview.clone().expect("the .pvd of the run"));
    assert!(
        pvd.starts_with(&dir),
        "{} outside the output folder",
        pvd.display()
    );
    let frames = read_pvd(&pvd);
    // 20 frames over the run, plus step 0 and the last step.
    assert!((20..=22).contains(&frames.len()), "{} frames", frames.len());
    assert_eq!(frames[0].0, 0.0);
    assert!(frames.windows(2).all(|w| w[0].0 < w[1].0));
    let (t_last, file) = frames.last().unwrap();
    assert!((t_last - row.simulated_time).abs() <= 1e-12 * row.simulated_time);
    let last = read_vtu(&pvd.parent().unwrap().join(file));
    let [_, elastic, transition, ruptured] = state_counts(&last);
    assert_eq!((elastic, transition), (0, 0));
    assert_eq!(ruptured, row.counts.ruptured);
    assert_eq!(ruptured, 16);
    let csv = dir.join("history.csv");
    h.state_mut().export_csv(&csv).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.contains(&pvd.display().to_string()), "{text}");
}

/// Two runs queued from the window's "compare values of" field: both are ticked in the
/// history and overlaid in the three comparison plots, one legend entry per run and plot named
/// by the parameter that differs; unticking run 1 removes its overlays.
#[test]
fn two_runs_overlaid_in_the_comparison_plots() {
    let mut h = harness(small_pull_off(3));
    h.run();
    h.get_by_role(Role::TextInput).focus();
    h.run();
    h.get_by_role(Role::TextInput).type_text("u_r=0.003,0.006");
    h.run();
    h.get_by_label("queue runs").click();
    h.run();
    wait_for_end(&mut h, Duration::from_secs(60));
    h.run();
    let st = h.state();
    assert_eq!(
        st.history.len(),
        2,
        "{:?} {:?} {:?}",
        st.variants_text,
        st.notes,
        st.status
    );
    let legend = |h: &Harness<'static, App>, label: &str| {
        h.query_all_by_label(label)
            .filter(|n| n.accesskit_node().role() == Role::CheckBox)
            .count()
    };
    for label in ["run 1: u_r=0.003", "run 2: u_r=0.006"] {
        assert_eq!(
            legend(&h, label),
            3,
            "{label}: one entry in each of the 3 plots"
        );
    }
    for id in [1, 2] {
        let name = format!("compare run {id}");
        let tick = h.get_by_label(&name);
        assert_eq!(
            tick.accesskit_node().toggled(),
            Some(egui::accesskit::Toggled::True)
        );
    }
    h.get_by_label("compare run 1").click();
    h.run();
    assert_eq!(legend(&h, "run 1: u_r=0.003"), 0);
    assert_eq!(legend(&h, "run 2"), 3, "alone, nothing differs: `run 2`");
}

/// `hide=history,view` as a class opens the window: the runs table and the 3-D view are not
/// drawn, the rest is; the projector mode enlarges the window's type (egui's zoom).
#[test]
fn hidden_panels_are_not_drawn() {
    let mut app = small_pull_off(3);
    app.set_display(&["history,view".to_string()], true, false)
        .unwrap();
    let mut h = harness(app);
    h.run();
    assert!(h.query_by_label("Runs").is_none(), "the history is hidden");
    assert!(
        h.query_by_label("3-D view").is_none(),
        "the 3-D view is hidden"
    );
    assert!(h.query_by_label("Interface law").is_some());
    assert!(h.query_by_label("Run").is_some());
    assert_eq!(h.ctx.zoom_factor(), decohesion::gui::state::PROJECTOR_ZOOM);
}
