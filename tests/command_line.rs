//! The command line is consistent across its subcommands: `bench` takes the scene as its first
//! argument like every other command; `tradeoff --out` is a folder like `sweep --out`;
//! `gui --compare` takes the key paths `sweep --vary` takes and lists what is admissible when it
//! refuses one; the progress lines off a terminal follow the simulated time and end at 100 %;
//! `--quiet` is global and silences the progress of `run`, `sweep` and `tradeoff`; every
//! argument of every subcommand has a help line. (Named `command_line` rather than `cli`: the
//! helpers are `common::cli`.)

use crate::common::cli::{decohesion, decohesion_ok, scratch};
use decohesion::gui::{check_compare, App, RecordChoice, Status};
use std::time::{Duration, Instant};

const SUBCOMMANDS: [&str; 6] = ["run", "check", "gui", "sweep", "tradeoff", "bench"];

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The scene is the first argument of `bench`: a scene with a Gmsh mesh given there is refused
/// by name (so it was read, rather than the default pull-off); the hidden `--scene` still works,
/// with a deprecation warning, and cannot be combined with the positional scene.
#[test]
fn bench_takes_the_scene_positionally() {
    let out = decohesion(&["bench", "scenes/tread.toml", "--sizes=3"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("scenes/tread.toml: key `mesh.file`") && err.contains("--sizes needs a box"),
        "{err}"
    );

    let out = decohesion(&["bench", "--scene", "scenes/tread.toml", "--sizes=3"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("--scene is deprecated") && err.contains("scenes/tread.toml: key `mesh.file`"),
        "{err}"
    );

    let out = decohesion(&[
        "bench",
        "scenes/pull_off.toml",
        "--scene",
        "scenes/tread.toml",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("cannot be used with"),
        "{}",
        stderr(&out)
    );
}

/// `tradeoff --out DIR` writes `DIR/tradeoff.csv` and `DIR/tradeoff.json` (the folder is
/// created); a path that is a file is refused naming `--out`, the path and what it must be.
#[test]
fn tradeoff_out_is_a_folder() {
    let dir = scratch("command-line", "tradeoff");
    let folder = dir.join("results");
    let grid = [
        "tradeoff",
        "scenes/pull_off.toml",
        "--cells",
        "2",
        "--factors",
        "0.5",
        "--integration",
        "reduced",
        "--quiet",
        "--out",
    ];
    let mut args = grid.to_vec();
    args.push(folder.to_str().unwrap());
    let out = decohesion_ok(&args);
    let json: Vec<serde_json::Value> = serde_json::from_str(
        &std::fs::read_to_string(folder.join("tradeoff.json")).expect("tradeoff.json"),
    )
    .unwrap();
    assert_eq!(json.len(), 1);
    let csv = std::fs::read_to_string(folder.join("tradeoff.csv")).expect("tradeoff.csv");
    assert_eq!(csv.lines().count(), 2, "header + 1 row");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("tradeoff.csv"), "{stdout}");

    let file = dir.join("a_file");
    std::fs::write(&file, "").unwrap();
    let mut args = grid.to_vec();
    args.push(file.to_str().unwrap());
    let out = decohesion(&args);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains(&format!("--out {}", file.display()))
            && err.contains("cannot create the folder of tradeoff.csv and tradeoff.json"),
        "{err}"
    );
}

/// `gui --compare` takes a key path as `sweep --vary` does (the short names stay aliases), and
/// refuses an unknown key before the window opens, listing what is admissible.
#[test]
fn compare_takes_key_paths_and_lists_the_admissible_ones() {
    let scene = Some("scenes/pull_off.toml");
    for spec in [
        "interface.law.u_r=0.003,0.006",
        "u_r=0.003,0.006",
        "interface.mu_inf=0.2,0.4",
        "mesh.cells=2,3",
        "scheme.time_step_factor=0.25,0.5",
        "end_time=0.1,0.2",
    ] {
        check_compare(spec, scene).unwrap_or_else(|e| panic!("{spec}: {e}"));
        check_compare(spec, None).unwrap_or_else(|e| panic!("{spec} (no scene): {e}"));
    }

    // Refused by the command before any window: the flag, the key and the admissible list.
    let out = decohesion(&[
        "gui",
        "scenes/pull_off.toml",
        "--compare",
        "interface.law.young=1e6,2e6",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    for needle in [
        "--compare `interface.law.young` cannot be compared",
        "`plateau_linear` law",
        "interface.law.NAME",
        "g_n0, alpha_e, u_r",
        "interface.mu_inf",
        "mesh.cells",
        "scheme.time_step_factor",
        "end_time",
    ] {
        assert!(err.contains(needle), "{needle}: {err}");
    }
    let out = decohesion(&["gui", "--compare", "interface.law.u_r=0.003,abc"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("--compare interface.law.u_r = `abc`: not a number"),
        "{}",
        stderr(&out)
    );

    // The window queues the runs of a key path as of its short name.
    let mut app = App::default();
    app.load_scene("scenes/pull_off.toml");
    app.settings.cells = 2;
    app.settings.record = RecordChoice::Off;
    app.queue_spec("interface.mu_inf=0.2,0.4").unwrap();
    let started = Instant::now();
    while app.poll() {
        assert!(started.elapsed() < Duration::from_secs(120), "no end");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(matches!(app.status, Status::Ended(_)));
    assert_eq!(app.history.len(), 2);
}

/// The lines `run` prints off a terminal follow the simulated time: one per tenth of the end
/// time, increasing, the last at 100 % (the pull-off's step grows after the tear, so a bar
/// counted in estimated steps stopped short of its end).
#[test]
fn progress_lines_off_a_terminal_end_at_100_percent() {
    let out = decohesion_ok(&["run", "scenes/pull_off.toml", "--set", "mesh.cells=[3,3,3]"]);
    let err = stderr(&out);
    let percents: Vec<u64> = err
        .lines()
        .filter_map(|l| l.trim_start().split_once(" %  t = "))
        .map(|(p, _)| p.trim().parse().expect("a percentage"))
        .collect();
    assert_eq!(percents.last(), Some(&100), "{err}");
    assert!(percents.windows(2).all(|w| w[0] < w[1]), "{err}");
    assert!(percents.iter().all(|p| p % 10 == 0), "{err}");
    let last = err.lines().rfind(|l| l.contains("100 %")).unwrap();
    assert!(last.contains(" ms / 330.0 ms"), "{last}");
}

/// `--quiet` (global: before or after the subcommand) leaves stderr empty for `run`, `sweep` and
/// `tradeoff`, which otherwise print their progress there.
#[test]
fn quiet_prints_no_progress() {
    let dir = scratch("command-line", "quiet");
    let sweep_out = dir.join("sweep");
    let tradeoff_out = dir.join("tradeoff");
    let commands: [Vec<&str>; 3] = [
        vec!["run", "scenes/pull_off.toml", "--set", "mesh.cells=[2,2,2]"],
        vec![
            "sweep",
            "scenes/pull_off.toml",
            "--set",
            "mesh.cells=[2,2,2]",
            "--vary",
            "end_time=0.05,0.1",
            "--out",
            sweep_out.to_str().unwrap(),
        ],
        vec![
            "tradeoff",
            "scenes/pull_off.toml",
            "--cells",
            "2",
            "--factors",
            "0.5",
            "--integration",
            "reduced",
            "--out",
            tradeoff_out.to_str().unwrap(),
        ],
    ];
    for args in commands {
        let loud = decohesion_ok(&args);
        assert!(!stderr(&loud).is_empty(), "{}: no progress", args[0]);
        let mut after = args.clone();
        after.push("--quiet");
        let mut before = vec!["--quiet"];
        before.extend(&args);
        for quiet in [after, before] {
            let out = decohesion_ok(&quiet);
            assert_eq!(stderr(&out), "", "{}", quiet.join(" "));
            assert!(!out.stdout.is_empty(), "{}: the results", quiet.join(" "));
        }
    }
}

/// Every argument of every subcommand has a help line (`-h` puts it on the argument's line).
#[test]
fn every_argument_has_help() {
    for sub in SUBCOMMANDS {
        let out = decohesion_ok(&[sub, "-h"]);
        let text = String::from_utf8_lossy(&out.stdout);
        let mut in_list = false;
        for line in text.lines() {
            if line.ends_with(':') && !line.starts_with(' ') {
                in_list = matches!(line, "Arguments:" | "Options:" | "Global options:");
                continue;
            }
            let entry = line.trim_start();
            if !in_list || !line.starts_with("  ") || line.starts_with("        ") {
                continue;
            }
            if entry.starts_with('-') || entry.starts_with('<') || entry.starts_with('[') {
                let help = entry.split_once("  ").map_or("", |(_, h)| h.trim());
                assert!(!help.is_empty(), "decohesion {sub}: `{entry}` has no help");
            }
        }
    }
}

/// `check` on a `bk` (mixed-mode) interface gives the energy to break in each pure mode: its G_c
/// is the mode-I one, and mode II's is G_IIc × the glued area (0.1 × 0.1 m² of `mixed_mode`).
#[test]
fn check_gives_both_pure_mode_energies_of_a_mixed_mode_law() {
    let law = "interface.law={family=\"bk\", g_n0=2.5e8, alpha_e=1.0e-3, g_ic=250.0, g_iic=750.0, eta=2.0}";
    let out = decohesion_ok(&["check", "scenes/mixed_mode.toml", "--set", law]);
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.contains("to break"))
        .unwrap_or_else(|| panic!("no energy to break in:\n{text}"));
    assert!(line.contains("G_c = 2.50000e2 J/m²"), "{line}");
    assert!(line.contains("2.50000e0 J to break in mode I"), "{line}");
    assert!(
        line.contains("G_IIc = 7.50000e2 J/m² → 7.50000e0 J"),
        "{line}"
    );
}
