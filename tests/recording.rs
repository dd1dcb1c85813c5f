//! Rerun captures as test artefacts: the command line records the pull-off scene to an `.rrd`
//! file, and the file is read back with the SDK's chunk store (what the viewer loads).
//! Cases: a completed run, an unstable run that fails mid-way, a run cancelled with Ctrl-C
//! (SIGINT), and the errors of bad recording flags.

use crate::common;

use crate::common::capture::{read_capture, scalars, steps_with};
use std::path::PathBuf;
use std::process::Command;

use crate::common::cli::{decohesion, interrupt_cancelled, summary, BIN};

fn scratch(name: &str) -> PathBuf {
    common::cli::scratch("rec", name)
}

fn positions() -> rerun::ComponentIdentifier {
    rerun::Mesh3D::descriptor_vertex_positions().component
}

#[test]
fn pull_off_capture_holds_every_frame_and_matches_the_summary() {
    let dir = scratch("pull_off");
    let rrd = dir.join("pull_off.rrd");
    let json = dir.join("pull_off.json");
    let out = decohesion(&[
        "run",
        "scenes/pull_off.toml",
        "--quiet",
        "--save",
        rrd.to_str().unwrap(),
        "--summary",
        json.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = summary(&json);
    let store = read_capture(&rrd);

    let entities: Vec<String> = store
        .all_entities_sorted()
        .iter()
        .map(|e| e.to_string())
        .collect();
    for expect in [
        "/scene/file",
        "/scene/resolved",
        "/body/surface",
        "/body/legend",
        "/planes/mould",
        "/interface",
        "/interface/nodes",
        "/interface/contact_status",
        "/interface/cohesive_traction",
        "/interface/contact_pressure",
        "/interface/alpha",
        "/interface/count",
        "/energy",
        "/balance/relative_residual",
        "/reaction/z_plus_z",
        "/imposed_displacement/z_plus_z",
        "/plots/reaction_vs_displacement",
        "/time_step",
        "/timing",
        "/body/colour_range",
        "/law/z_minus/g_n",
        "/law/z_minus/traction",
        "/run/status",
    ] {
        assert!(
            entities.iter().any(|e| e == expect),
            "{expect} missing: {entities:?}"
        );
    }

    // Frames: step 0, then the first step at or past each k·end_time/200, k = 1..200; the
    // last one is the final step. 201 frames, each with positions and a row of every series.
    let steps = s["steps"].as_i64().unwrap();
    let frames = steps_with(&store, "/body/surface", positions());
    assert_eq!(frames.len(), 201, "frames at steps {frames:?}");
    assert_eq!(frames[0], 0);
    assert_eq!(*frames.last().unwrap(), steps);
    assert_eq!(s["recording"]["frames"].as_u64().unwrap(), 201);
    // Counts: [elastic, transition, ruptured] at every frame.
    let counts = scalars(&store, "/interface/count");
    assert_eq!(
        counts.keys().copied().collect::<Vec<_>>(),
        frames,
        "scalars at every frame"
    );

    // Last ruptured count = all 8×8 interface nodes; the counts always sum to 64.
    let n_iface = s["interface_nodes"].as_u64().unwrap() as f64;
    assert_eq!(n_iface, 64.0);
    assert_eq!(counts.values().last().unwrap()[2], n_iface);
    for (k, c) in &counts {
        assert_eq!(c.iter().sum::<f64>(), n_iface, "step {k}");
    }
    // The paper's fig. 6 (right): all elastic at first, all ruptured at the end.
    assert_eq!(counts[&0], vec![n_iface, 0.0, 0.0]);

    // The final dissipated energy in the file is the summary's, to the last bit
    // (energy instance 4 = damage_dissipated).
    let energy = scalars(&store, "/energy");
    assert_eq!(energy.values().last().unwrap().len(), 13);
    let dissipated: Vec<f64> = energy.values().map(|v| v[4]).collect();
    let expect = s["energies"]["damage_dissipated"].as_f64().unwrap();
    assert_eq!(*dissipated.last().unwrap(), expect);
    // And it never decreases (ΔD ≥ 0, model §5.5).
    assert!(dissipated.windows(2).all(|w| w[1] >= w[0]));

    // α(t) of every node (64 ≤ 64): at the end all beyond u_r.
    let alpha = scalars(&store, "/interface/alpha");
    let a_end = alpha.values().last().unwrap();
    assert_eq!(a_end.len(), 64);
    assert!(a_end.iter().all(|&a| a >= 4.0e-3), "{a_end:?}");

    // The recorder's own cost is reported.
    let logging = s["recording"]["logging_seconds"].as_f64().unwrap();
    assert!(logging > 0.0);
    assert!(s["recording"]["bytes"].as_u64().unwrap() > 10_000);
}

#[test]
fn unstable_run_still_leaves_a_readable_capture_ending_at_the_failing_step() {
    let dir = scratch("unstable");
    let rrd = dir.join("unstable.rrd");
    let json = dir.join("unstable.json");
    let out = decohesion(&[
        "run",
        "scenes/pull_off.toml",
        "--quiet",
        "--set",
        // The top slammed down at 100 m/s: an element inverts within a few steps (a factor
        // above 1 no longer fails: h is capped at h_crit).
        "displacement.0.table=[[0.0, 0.0], [0.01, -1.0]]",
        "--set",
        "end_time=0.05",
        "--every",
        "5",
        "--save",
        rrd.to_str().unwrap(),
        "--summary",
        json.to_str().unwrap(),
    ]);
    assert!(
        !out.status.success(),
        "an inverted element must fail the run"
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("h_crit"), "{stderr}");
    let s = summary(&json);
    assert_eq!(s["status"], "failed");
    let failing_step = s["steps"].as_i64().unwrap();
    assert!(failing_step > 0 && failing_step < 150);

    let store = read_capture(&rrd);
    let frames = steps_with(&store, "/body/surface", positions());
    // Every 5th step, then the failing step itself.
    let expect: Vec<i64> = (0..=failing_step)
        .filter(|k| k % 5 == 0)
        .chain((failing_step % 5 != 0).then_some(failing_step))
        .collect();
    assert_eq!(frames, expect);
    let energy = scalars(&store, "/energy");
    assert_eq!(*energy.keys().last().unwrap(), failing_step);
    // The failure is in the file.
    let status_component = rerun::TextDocument::descriptor_text().component;
    assert_eq!(
        steps_with(&store, "/run/status", status_component),
        vec![failing_step]
    );
}

#[test]
fn ctrl_c_finishes_the_capture() {
    let dir = scratch("sigint");
    let rrd = dir.join("sigint.rrd");
    let json = dir.join("sigint.json");
    // A long run (14³ elements to t = 10 s, ~30 s alone) interrupted after 3 s.
    let child = Command::new(BIN)
        .args([
            "run",
            "scenes/pull_off.toml",
            "--quiet",
            "--set",
            "mesh.cells=[14,14,14]",
            "--set",
            "end_time=10",
            "--save",
            rrd.to_str().unwrap(),
            "--summary",
            json.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs(3));
    let s = interrupt_cancelled(child, &json);
    let steps = s["steps"].as_i64().unwrap();
    let store = read_capture(&rrd);
    let frames = steps_with(&store, "/body/surface", positions());
    assert_eq!(frames.first(), Some(&0));
    assert_eq!(frames.last(), Some(&steps), "the last step is in the file");
    assert_eq!(
        frames.len() as u64,
        s["recording"]["frames"].as_u64().unwrap()
    );
}

#[test]
fn bad_recording_flags_are_refused_with_the_admissible_values() {
    for (args, expect) in [
        (vec!["--every", "0"], "0"),
        (vec!["--fps", "-3"], "> 0"),
        (vec!["--fps", "nan"], "> 0"),
        (
            vec!["--colour", "rainbow"],
            "displacement, von_mises, jacobian",
        ),
        (vec!["--every", "3", "--fps", "10"], "cannot be used with"),
        (vec!["--save", "a.rrd", "--spawn"], "cannot be used with"),
    ] {
        let mut all = vec!["run", "scenes/pull_off.toml"];
        all.extend(args.iter().copied());
        let out = decohesion(&all);
        assert!(!out.status.success(), "{args:?} accepted");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(expect), "{args:?}: {err}");
    }
    // A file that cannot be created: named, and nothing else happens.
    let out = decohesion(&[
        "run",
        "scenes/pull_off.toml",
        "--save",
        "/nonexistent-dir/x.rrd",
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("/nonexistent-dir/x.rrd"), "{err}");
}

#[test]
fn spawn_without_a_viewer_says_how_to_install_it() {
    let empty = scratch("nopath");
    let out = Command::new(BIN)
        .args(["run", "scenes/pull_off.toml", "--spawn"])
        .env("PATH", &empty)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("pip install rerun-sdk==0.36.3"), "{err}");
}

/// `--threads` beyond the machine's cores runs (results do not depend on the thread count) but
/// warns that the spinning threads then slow every step; `--threads 0` is refused; the summary
/// says how many threads ran the step.
#[test]
fn more_threads_than_cores_warns_and_zero_is_refused() {
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let many = (cores + 1).to_string();
    let out = decohesion(&["--threads", &many, "check", "scenes/pull_off.toml"]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("--threads {many} is more than the {cores} cores")),
        "{err}"
    );
    let fits = cores.to_string();
    let out = decohesion(&["--threads", &fits, "check", "scenes/pull_off.toml"]);
    assert!(out.status.success());
    assert!(!String::from_utf8_lossy(&out.stderr).contains("warning: --threads"));
    let out = decohesion(&["--threads", "0", "check", "scenes/pull_off.toml"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--threads must be ≥ 1"));
    // The summary reports the threads that ran the step: 1 below the parallel size (7³ = 343
    // elements), the team's size above it (14³ = 2744).
    let dir = scratch("threads");
    for (cells, expect) in [(7, 1), (14, 2)] {
        let json = dir.join(format!("{cells}.json"));
        let mesh = format!("mesh.cells=[{cells},{cells},{cells}]");
        let out = decohesion(&[
            "--threads",
            "2",
            "run",
            "scenes/pull_off.toml",
            "--quiet",
            "--set",
            &mesh,
            "--set",
            "end_time=0.005",
            "--summary",
            json.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(summary(&json)["threads"], expect, "{cells}³");
    }
}
