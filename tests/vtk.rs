//! ParaView output (`decohesion run --vtk DIR`) read back with `vtkio` (the `.vtu` frames) and
//! quick-xml (the `.pvd` index), readers independent of the writer, and checked against the
//! physics of the run and its JSON summary. Cases: completed pull-off runs on a 3³ cube (mid-
//! damage and torn off), an unstable run that fails, a run cancelled with Ctrl-C, a run killed
//! outright, and a directory that cannot be written.

use decohesion::scene::load_scene;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use vtkio::model::CellType;

use crate::common;
use crate::common::cli::{decohesion, decohesion_ok, summary, BIN};
use crate::common::paraview::{read_pvd, read_vtu, state_counts, Grid};
const SCENE: &str = "scenes/pull_off.toml";

fn scratch(name: &str) -> PathBuf {
    common::cli::scratch("vtk", name)
}

/// The summary's simulated time, parsed from its text with `str::parse` (correctly rounded;
/// serde_json's default float parser may be one ulp off).
fn simulated_time(dir: &Path) -> f64 {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let key = "\"simulated_time\":";
    let rest =
        text[text.find(key).expect("simulated_time in the summary") + key.len()..].trim_start();
    let end = rest.find([',', '\n', '}']).unwrap();
    rest[..end].trim().parse().unwrap()
}

fn pull_off_3(dir: &Path, end_time: &str, extra: &[&str]) -> (Output, serde_json::Value) {
    let json = dir.join("summary.json");
    let vtk = dir.join("vtk");
    let end = format!("end_time={end_time}");
    let mut args = vec![
        "run",
        SCENE,
        "--quiet",
        "--set",
        "mesh.cells=[3,3,3]",
        "--set",
        &end,
        "--vtk",
        vtk.to_str().unwrap(),
        "--summary",
        json.to_str().unwrap(),
    ];
    args.extend(extra);
    let out = decohesion(&args);
    (out, summary(&json))
}

#[test]
fn pull_off_frames_read_back_with_the_run_physics() {
    // 0.08 s: 12 elastic and 4 transition nodes (the corners of the glued face start tearing
    // first); 0.33 s: the cube torn off, 16 ruptured.
    for end_time in ["0.08", "0.33"] {
        let dir = scratch(&format!("pull_off_{end_time}"));
        let (out, s) = pull_off_3(&dir, end_time, &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let model = load_scene(
            Path::new(SCENE),
            &["mesh.cells=[3,3,3]".into(), format!("end_time={end_time}")],
        )
        .unwrap()
        .model;
        let mesh = &model.mesh;

        // The index: step 0 first, times strictly increasing, the last one the run's end
        // (bit for bit: times are written in round-trip form), one entry per frame reported.
        let entries = read_pvd(&dir.join("vtk/pull_off.pvd"));
        let times: Vec<f64> = entries.iter().map(|e| e.0).collect();
        assert_eq!(times[0], 0.0);
        assert!(times.windows(2).all(|w| w[1] > w[0]), "{times:?}");
        assert_eq!(*times.last().unwrap(), simulated_time(&dir));
        assert_eq!(
            entries.len() as u64,
            s["paraview"]["frames"].as_u64().unwrap()
        );
        // Default cadence: step 0, then the first step at or past each k·end_time/200 (the
        // 200th is the last step). With fewer than 200 steps (0.08 s: 147) that is every step.
        let steps = s["steps"].as_u64().unwrap();
        let expect = if steps < 200 { steps + 1 } else { 201 };
        assert_eq!(entries.len() as u64, expect, "{steps} steps");

        let frames: Vec<Grid> = entries
            .iter()
            .map(|(_, f)| read_vtu(&dir.join("vtk").join(f)))
            .collect();
        let nodes = s["nodes"].as_u64().unwrap() as usize;
        let cells = s["elements"].as_u64().unwrap() as usize;
        let iface = s["interface_nodes"].as_u64().unwrap() as usize;
        assert_eq!((nodes, cells, iface), (64, 27, 16));
        let flat_nodes: Vec<f64> = mesh.nodes.iter().flatten().copied().collect();
        let flat_conn: Vec<u64> = mesh.elements.iter().flatten().map(|&n| n as u64).collect();
        for g in &frames {
            // The reference mesh, hexahedra (VTK type 12) in the mesh's node order.
            assert_eq!(g.points, flat_nodes);
            assert_eq!(g.connectivity, flat_conn);
            assert!(g.types.iter().all(|&t| t == CellType::Hexahedron));
            assert_eq!(g.point["displacement"].len(), 3 * nodes);
            assert_eq!(g.point["velocity"].len(), 3 * nodes);
            assert_eq!(g.cell["cauchy_stress"].len(), 9 * cells);
            assert_eq!(g.cell["von_mises"].len(), cells);
            // No element inverted; α ≥ 0 exactly on the interface nodes.
            assert!(g.cell["J"].iter().all(|&j| j > 0.0), "{:?}", g.cell["J"]);
            let c = state_counts(g);
            assert_eq!(c[0], nodes - iface);
            let alpha_off = g.point["alpha"].iter().filter(|&&a| a == -1.0).count();
            assert_eq!(alpha_off, nodes - iface);
        }

        // Step 0: the undeformed body: U = 0, F = I so J = 1 and σ = 0 (to round-off: J is a
        // determinant of an exact identity here), every interface node elastic.
        let g0 = &frames[0];
        assert!(g0.point["displacement"].iter().all(|&u| u == 0.0));
        assert!(g0.cell["J"]
            .iter()
            .all(|&j| (j - 1.0).abs() <= 4.0 * f64::EPSILON));
        assert!(g0.cell["von_mises"].iter().all(|&v| v == 0.0));
        assert_eq!(state_counts(g0), [nodes - iface, iface, 0, 0]);

        // Last frame: interface states = the summary's final counts.
        let last = frames.last().unwrap();
        let fc = &s["final_counts"];
        let count = |k: &str| fc[k].as_u64().unwrap() as usize;
        assert_eq!(
            state_counts(last)[1..],
            [count("elastic"), count("transition"), count("ruptured")]
        );
        // The prescribed face moves with the table: U_z = Ū(t) at the last time, to the
        // round-off of summing one increment Ū(tₙ₊₁) − Ū(tₙ) per step (a few ulps each), and its
        // velocity V_{n+½} = (Ū(tₙ + h) − Ū(tₙ))/h (model §4.6).
        let t = *times.last().unwrap();
        let h = s["time_step"].as_f64().unwrap();
        let bc = &model.displacements[0];
        assert_eq!((bc.faces.as_str(), bc.component), ("z+", 2));
        let u_bar = bc.history.value(t)[0];
        let v_bar = (bc.history.value(t + h)[0] - u_bar) / h;
        let tol = 4.0 * f64::EPSILON * steps as f64 * u_bar;
        let top = mesh.face_set_nodes(&mesh.face_sets["z+"]);
        assert_eq!(top.len(), 16);
        let mut err: f64 = 0.0;
        for &n in &top {
            let n = n as usize;
            err = err.max((last.point["displacement"][3 * n + 2] - u_bar).abs());
            let v = last.point["velocity"][3 * n + 2];
            assert!((v - v_bar).abs() <= 1e-9, "V_z {v} vs {v_bar}");
        }
        assert!(err <= tol, "|U_z − Ū| = {err:e} > {tol:e} (Ū = {u_bar})");
        println!("end {end_time}: Ū = {u_bar}, max |U_z − Ū| = {err:e} (tol {tol:e}), V̄ = {v_bar}, {} frames", frames.len());
        // Von Mises of the stored tensor is the stored von Mises (σ symmetric, 9 components).
        for (k, &vm) in last.cell["von_mises"].iter().enumerate() {
            let sg = &last.cell["cauchy_stress"][9 * k..9 * k + 9];
            let p = (sg[0] + sg[4] + sg[8]) / 3.0;
            let d = [
                sg[0] - p,
                sg[1],
                sg[2],
                sg[3],
                sg[4] - p,
                sg[5],
                sg[6],
                sg[7],
                sg[8] - p,
            ];
            let expect = (1.5 * d.iter().map(|x| x * x).sum::<f64>()).sqrt();
            assert!((vm - expect).abs() <= 1e-9 * expect.max(1.0));
            assert!((sg[1] - sg[3]).abs() <= 1e-9 * vm.max(1.0), "σ_xy ≠ σ_yx");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// Every entry of an index names a complete frame (read back) and the index ends at `last`.
fn index_is_complete(dir: &Path, last: f64) -> usize {
    let entries = read_pvd(&dir.join("pull_off.pvd"));
    assert!(entries.windows(2).all(|w| w[1].0 > w[0].0));
    assert_eq!(entries.last().unwrap().0, last);
    for (_, f) in &entries {
        let g = read_vtu(&dir.join(f));
        assert_eq!(g.types.len(), g.cell["J"].len());
    }
    entries.len()
}

#[test]
fn unstable_run_still_leaves_an_index_ending_at_the_failing_step() {
    let dir = scratch("unstable");
    let (out, s) = pull_off_3(
        &dir,
        "0.05",
        // The top slammed down at 100 m/s: an element inverts within a few steps (a factor
        // above 1 no longer fails: h is capped at h_crit).
        &[
            "--set",
            "displacement.0.table=[[0.0, 0.0], [0.01, -1.0]]",
            "--every",
            "5",
        ],
    );
    assert!(
        !out.status.success(),
        "an inverted element must fail the run"
    );
    assert_eq!(s["status"], "failed");
    let failing = s["steps"].as_u64().unwrap();
    assert!(failing > 0 && failing < 150, "{failing}");
    let n = index_is_complete(&dir.join("vtk"), simulated_time(&dir));
    // Every 5th step, then the failing step itself.
    let expect = failing / 5 + 1 + u64::from(failing % 5 != 0);
    assert_eq!(n as u64, expect);
    assert_eq!(s["paraview"]["frames"].as_u64().unwrap(), expect);
}

/// A long run (7³ cube to t = 100 s) stopped with `signal` once its ParaView index lists 3
/// frames (the file is polled; a run that never writes them fails after a minute).
fn interrupted(name: &str, signal: &str) -> (PathBuf, std::process::Output) {
    let dir = scratch(name);
    let child = Command::new(BIN)
        .args([
            "run",
            SCENE,
            "--quiet",
            "--set",
            "end_time=100",
            "--every",
            "300",
            "--vtk",
            dir.join("vtk").to_str().unwrap(),
            "--summary",
            dir.join("summary.json").to_str().unwrap(),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pvd = dir.join("vtk/pull_off.pvd");
    let started = std::time::Instant::now();
    while std::fs::read_to_string(&pvd).map_or(0, |t| t.matches("part=\"0\"").count()) < 3 {
        assert!(
            started.elapsed() < std::time::Duration::from_secs(60),
            "3 frames never written to {}",
            pvd.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert!(!out.status.success(), "an interrupted run is not a success");
    (dir, out)
}

#[test]
fn ctrl_c_finishes_the_index_with_the_last_step() {
    let (dir, out) = interrupted("sigint", "-INT");
    let s = summary(&dir.join("summary.json"));
    assert_eq!(
        s["status"],
        "cancelled",
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let n = index_is_complete(&dir.join("vtk"), simulated_time(&dir));
    assert_eq!(n as u64, s["paraview"]["frames"].as_u64().unwrap());
    assert!(n >= 3, "{n} frames, 3 were listed before the signal");
}

#[test]
fn a_killed_run_leaves_a_valid_index_of_the_frames_written() {
    // SIGKILL: no handler runs; the index written frame by frame is still complete.
    let (dir, _) = interrupted("sigkill", "-KILL");
    let entries = read_pvd(&dir.join("vtk/pull_off.pvd"));
    assert!(
        entries.len() >= 3,
        "{} frames, 3 were listed before the signal",
        entries.len()
    );
    index_is_complete(&dir.join("vtk"), entries.last().unwrap().0);
}

#[test]
fn an_unwritable_summary_is_named_before_the_run() {
    let dir = scratch("unwritable_summary");
    let file = dir.join("plain");
    std::fs::write(&file, "not a directory").unwrap();
    for (target, why) in [
        (file.join("summary.json"), "is not a directory"),
        (dir.clone(), "it is a directory"),
    ] {
        let out = decohesion(&["run", SCENE, "--summary", target.to_str().unwrap()]);
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("cannot write the summary (--summary) to")
                && err.contains(target.to_str().unwrap())
                && err.contains(why),
            "{err}"
        );
        // Refused before the run: no summary table was printed.
        assert!(
            out.stdout.is_empty(),
            "{}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
}

#[test]
fn an_unwritable_directory_is_named_before_the_run() {
    let dir = scratch("unwritable");
    let file = dir.join("plain");
    std::fs::write(&file, "not a directory").unwrap();
    let target = file.join("vtk");
    let out = decohesion(&["run", SCENE, "--vtk", target.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cannot write the ParaView output (--vtk) to directory")
            && err.contains(target.to_str().unwrap()),
        "{err}"
    );
    // Nothing ran: no summary table.
    assert!(!String::from_utf8_lossy(&out.stdout).contains("status"));
}

/// A tetrahedral mesh (the `rubber_peel` strip from Gmsh) in ParaView: every cell a
/// tetrahedron (VTK type 10) in the mesh's node order, four nodes each, one cell per element of
/// the summary, and no inverted element in the frame (J > 0).
#[test]
fn tetrahedra_read_back_as_vtk_tetra() {
    let scene = "scenes/rubber_peel.toml";
    let dir = scratch("tetrahedra");
    let (json, vtk) = (dir.join("summary.json"), dir.join("vtk"));
    decohesion_ok(&[
        "run",
        scene,
        "--quiet",
        "--set",
        "end_time=2e-6",
        "--vtk",
        vtk.to_str().unwrap(),
        "--summary",
        json.to_str().unwrap(),
    ]);
    let s = summary(&json);
    let model = load_scene(Path::new(scene), &["end_time=2e-6".into()])
        .unwrap()
        .model;
    let mesh = &model.mesh;
    assert!(mesh.elements.is_empty() && !mesh.tets.is_empty());
    let entries = read_pvd(&vtk.join("rubber_peel.pvd"));
    let g = read_vtu(&vtk.join(&entries.last().unwrap().1));
    let flat_conn: Vec<u64> = mesh.tets.iter().flatten().map(|&n| n as u64).collect();
    assert_eq!(g.connectivity, flat_conn);
    assert_eq!(g.types.len(), s["elements"].as_u64().unwrap() as usize);
    assert!(g.types.iter().all(|&t| t == CellType::Tetra));
    assert!(g.cell["J"].iter().all(|&j| j > 0.0));
}
