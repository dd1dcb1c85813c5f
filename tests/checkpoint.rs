//! Checkpoints (model §4.13): every shipped scene, restored from a checkpoint, ends with its
//! golden file's summary and final state, bit for bit; `run --checkpoint`
//! killed with SIGKILL and continued with `run --resume` ends with the uninterrupted run's
//! summary; a folder or a file that is not a checkpoint of the scene is refused.

use crate::common::capture::{read_capture, scalars};
use crate::common::cli::{decohesion, decohesion_ok, scratch, summary, BIN};
use crate::golden;
use decohesion::compare::summary::TIMING_KEYS;
use decohesion::scene::load_scene;
use decohesion::solver::Simulation;
use serde_json::Value;
use std::path::Path;

/// Every shipped scene restored from a checkpoint half-way through its run (the step count of
/// its golden file, halved) runs to the end of its golden file, bit for bit: the summary
/// (statistics, peaks, ledger, counts, the error of a failing scene) and the hash of U, V and α
/// (the golden test holds the uninterrupted run to the same file). The scenes cover the glue,
/// damage with and without delay, RCCM, contact and friction, turning and triangulated moulds,
/// glue that forms, bulk viscosity, mass scaling and every integration rule.
#[test]
fn every_scene_resumes_bit_for_bit() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    for path in golden::scene_files() {
        let file = dir.join(format!("{}.json", golden::golden_name(&path)));
        let text =
            std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let expected: Value = serde_json::from_str(&text).unwrap();
        let Some(steps) = expected["summary"]["steps"].as_u64() else {
            continue; // a scene that refuses to set up has no run to resume
        };
        let name = path.display().to_string();
        let model = load_scene(&path, &[])
            .unwrap_or_else(|e| panic!("{e}"))
            .model;
        let mut first = Simulation::new(model.clone()).unwrap();
        for _ in 0..steps / 2 {
            first.step().unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        let bytes = first.checkpoint();
        drop(first);
        let mut resumed = Simulation::new(model).unwrap();
        let header = resumed.restore(&bytes, &name).unwrap();
        assert_eq!(header.step, steps / 2, "{name}");
        let outcome = resumed.run(|_| true);
        let got = golden::record_of(&resumed, &outcome);
        assert!(
            got == expected,
            "{name}: resumed at step {} of {steps}, the run ends elsewhere than its golden file:\n{}",
            steps / 2,
            serde_json::to_string_pretty(&got).unwrap()
        );
    }
}

/// The scene of the command-line tests: a peel by a turning roller (glue, damage, contact,
/// friction, a moving mould, a variable step), over twenty thousand steps.
fn roller_peel() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/roller_peel.toml")
        .display()
        .to_string()
}

/// `run SCENE --checkpoint FOLDER --checkpoint-every 1000` with `more` arguments, started and
/// returned once its first checkpoint is written.
fn checkpointing(scene: &str, folder: &Path, more: &[&str]) -> std::process::Child {
    let child = std::process::Command::new(BIN)
        .args(["run", scene, "--quiet", "--threads", "1", "--checkpoint"])
        .arg(folder)
        .args(["--checkpoint-every", "1000"])
        .args(more)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let state = folder.join("state.ckpt");
    let start = std::time::Instant::now();
    while !state.exists() {
        assert!(
            start.elapsed().as_secs() < 120,
            "no checkpoint written in two minutes"
        );
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    child
}

/// `run --checkpoint` killed by SIGKILL right after its first checkpoint, then `run --resume`,
/// ends with the uninterrupted run's summary (without its timings and the checkpoint's report);
/// the resumed run keeps checkpointing into the folder.
#[test]
fn a_run_killed_by_sigkill_resumes_to_the_uninterrupted_summary() {
    use std::os::unix::process::ExitStatusExt;
    let dir = scratch("checkpoint", "sigkill");
    let scene = roller_peel();
    let full = dir.join("full.json");
    decohesion_ok(&[
        "run",
        &scene,
        "--quiet",
        "--summary",
        full.to_str().unwrap(),
    ]);
    let folder = dir.join("ck");
    let mut child = checkpointing(&scene, &folder, &[]);
    child.kill().unwrap(); // SIGKILL
    let status = child.wait().unwrap();
    assert_eq!(
        status.signal(),
        Some(9),
        "the run ended before it was killed ({status}): it is too short for this test"
    );
    let resumed = dir.join("resumed.json");
    let out = decohesion_ok(&[
        "run",
        "--resume",
        folder.to_str().unwrap(),
        "--quiet",
        "--summary",
        resumed.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("continue with: decohesion run --resume"),
        "{stdout}"
    );
    let (mut a, mut b) = (summary(&full), summary(&resumed));
    let report = b.as_object_mut().unwrap().remove("checkpoint").unwrap();
    assert!(report["written"].as_u64().unwrap() >= 1, "{report}");
    for k in TIMING_KEYS {
        a.as_object_mut().unwrap().remove(k);
        b.as_object_mut().unwrap().remove(k);
    }
    assert_eq!(a, b);
    std::fs::remove_dir_all(&dir).ok();
}

/// `--resume` refuses, naming the file and what is wrong, without a panic: a folder that does
/// not exist, a folder without run.toml, a run.toml with an unknown key, a state file that is
/// not a checkpoint or is cut short, and a checkpoint of another scene (the overrides changed).
#[test]
fn resume_refuses_what_is_not_a_checkpoint_of_the_scene() {
    let dir = scratch("checkpoint", "refuse");
    let folder = dir.join("ck");
    let scene = roller_peel();
    decohesion_ok(&[
        "run",
        &scene,
        "--quiet",
        "--set",
        "end_time=0.01",
        "--checkpoint",
        folder.to_str().unwrap(),
        "--checkpoint-every",
        "50",
    ]);
    let run_toml = std::fs::read_to_string(folder.join("run.toml")).unwrap();
    let good = std::fs::read(folder.join("state.ckpt")).unwrap();
    let resume = |f: &Path| decohesion(&["run", "--resume", f.to_str().unwrap(), "--quiet"]);
    let refused = |out: std::process::Output, expect: &[&str]| {
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        for e in expect {
            assert!(err.contains(e), "expected {e:?} in: {err}");
        }
    };
    refused(resume(&dir.join("nowhere")), &["nowhere", "no such folder"]);
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    refused(resume(&empty), &["run.toml", "--checkpoint"]);
    std::fs::write(folder.join("run.toml"), format!("{run_toml}colour = 3\n")).unwrap();
    refused(resume(&folder), &["run.toml", "colour"]);
    std::fs::write(folder.join("run.toml"), &run_toml).unwrap();
    std::fs::write(folder.join("state.ckpt"), b"not a checkpoint").unwrap();
    refused(
        resume(&folder),
        &["state.ckpt", "not a decohesion checkpoint"],
    );
    std::fs::write(folder.join("state.ckpt"), &good[..good.len() / 2]).unwrap();
    refused(resume(&folder), &["state.ckpt", "corrupt", "truncated"]);
    std::fs::write(folder.join("state.ckpt"), &good).unwrap();
    let other = run_toml.replace("end_time=0.01", "end_time=0.02");
    assert_ne!(other, run_toml, "run.toml holds the overrides: {run_toml}");
    std::fs::write(folder.join("run.toml"), other).unwrap();
    refused(resume(&folder), &["state.ckpt", "another model", "--set"]);
    std::fs::write(folder.join("run.toml"), &run_toml).unwrap();
    decohesion_ok(&["run", "--resume", folder.to_str().unwrap(), "--quiet"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// A checkpointed run stopped by Ctrl-C (SIGINT: a checkpoint at the step it stops at) and
/// resumed, each with `--save`: the two recordings have one recording id, so the viewer shows
/// them as one recording, and the resumed one starts at the step the first one ends at.
#[test]
fn a_resumed_recording_continues_the_first() {
    let dir = scratch("checkpoint", "recording");
    let scene = roller_peel();
    let folder = dir.join("ck");
    let (first, second) = (dir.join("first.rrd"), dir.join("second.rrd"));
    let child = checkpointing(&scene, &folder, &["--save", first.to_str().unwrap()]);
    let pid = child.id().to_string();
    let kill = std::process::Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert!(
        !out.status.success(),
        "the run ended before Ctrl-C: too short for this test"
    );
    decohesion_ok(&[
        "run",
        "--resume",
        folder.to_str().unwrap(),
        "--quiet",
        "--save",
        second.to_str().unwrap(),
    ]);
    let (a, b) = (read_capture(&first), read_capture(&second));
    assert_eq!(a.id().recording_id(), b.id().recording_id());
    let (ea, eb) = (scalars(&a, "/energy"), scalars(&b, "/energy"));
    let last_a = *ea.keys().next_back().unwrap();
    let first_b = *eb.keys().next().unwrap();
    assert_eq!(
        first_b, last_a,
        "the resumed recording starts where the first stops"
    );
    assert!(eb.keys().next_back().unwrap() > &last_a);
    std::fs::remove_dir_all(&dir).ok();
}
