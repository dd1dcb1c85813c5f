//! `decohesion sweep` end to end: every row of a 2×2 grid is, bit for bit, the summary of a
//! single `run --set` of the same values; bad `--vary` input is refused before anything runs,
//! naming the key and the value; the Rerun capture holds each observable against the varied
//! value (read back with the SDK, and checked by `rerun rrd verify` when the CLI is installed);
//! a failed run is a row; Ctrl-C writes the rows done.

use crate::common::capture::{read_capture, verify};
use crate::common::cli::{decohesion, scratch, summary, BIN};
use serde_json::Value;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

/// The summary's physics: everything but what measures the machine (wall times, threads) or
/// names the outputs.
const PHYSICS_KEYS: [&str; 17] = [
    "scene",
    "status",
    "error",
    "nodes",
    "elements",
    "interface_nodes",
    "steps",
    "time_step",
    "h_crit_initial",
    "h_crit_min",
    "time_step_factor",
    "simulated_time",
    "peak_reactions",
    "time_first_damage",
    "time_full_rupture",
    "final_counts",
    "energies",
];

/// The physics of a summary, as JSON text (equal text = equal bits), with its residual and
/// warnings.
fn physics(v: &Value) -> String {
    let mut keys = PHYSICS_KEYS.to_vec();
    keys.extend(["max_relative_residual", "warnings"]);
    let picked: serde_json::Map<String, Value> = keys
        .iter()
        .map(|k| (k.to_string(), v.get(*k).cloned().expect(k)))
        .collect();
    Value::Object(picked).to_string()
}

/// The rows of `sweep.json` in `dir`.
fn runs(dir: &Path) -> Vec<Value> {
    let json = summary(&dir.join("sweep.json"));
    json["runs"].as_array().expect("runs").clone()
}

/// A sweep of the 2³ pull-off with `extra` arguments into `dir`, which must succeed; its rows.
fn sweep_small(dir: &Path, extra: &[&str]) -> Vec<Value> {
    let mut args = vec![
        "sweep",
        "scenes/pull_off.toml",
        "--set",
        "mesh.cells=[2,2,2]",
    ];
    args.extend(["--quiet", "--out", dir.to_str().unwrap()]);
    args.extend(extra);
    let out = decohesion(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    runs(dir)
}

/// 2×2 grid (u_r × time-step factor) on the 2³ pull-off cube: each row's summary, timings
/// removed, is the JSON text `run --set` writes for the same values; the CSV has the varied
/// values first, in grid order; the capture plots the dissipation of each row at its u_r.
#[test]
fn each_row_is_the_run_of_its_values() {
    let dir = scratch("sweep", "grid");
    let rrd = dir.join("sweep.rrd");
    let rows = sweep_small(
        &dir,
        &[
            "--vary",
            "interface.law.u_r=0.003,0.004",
            "--vary",
            "scheme.time_step_factor=0.5,0.3",
            "--save",
            rrd.to_str().unwrap(),
        ],
    );
    assert_eq!(rows.len(), 4);
    let csv = std::fs::read_to_string(dir.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("\"interface.law.u_r\",\"scheme.time_step_factor\",status,"));
    let grid = [
        ("0.003", "0.5"),
        ("0.003", "0.3"),
        ("0.004", "0.5"),
        ("0.004", "0.3"),
    ];
    for (i, (u_r, factor)) in grid.iter().enumerate() {
        let row = &rows[i];
        assert_eq!(row["values"], serde_json::json!([u_r, factor]));
        assert_eq!(row["status"], "completed");
        assert!(lines[i + 1].starts_with(&format!("\"{u_r}\",\"{factor}\",completed,")));
        let single = dir.join(format!("run{i}.json"));
        let out = decohesion(&[
            "run",
            "scenes/pull_off.toml",
            "--set",
            "mesh.cells=[2,2,2]",
            "--set",
            &format!("interface.law.u_r={u_r}"),
            "--set",
            &format!("scheme.time_step_factor={factor}"),
            "--quiet",
            "--summary",
            single.to_str().unwrap(),
        ]);
        assert!(out.status.success());
        let (a, b) = (physics(&row["summary"]), physics(&summary(&single)));
        assert_eq!(a, b, "row {i} differs from its run");
    }
    // The capture: damage dissipation against u_r [×1e-3], one series per factor.
    let store = read_capture(&rrd);
    let timeline = rerun::TimelineName::try_new("interface.law.u_r [×1e-3]").unwrap();
    let component = rerun::Scalars::descriptor_scalars().component;
    for (k, factor) in ["0_5", "0_3"].iter().enumerate() {
        let entity = format!(
            "/sweep/interface_law_u_r/damage_dissipated_J/scheme_time_step_factor_{factor}"
        );
        let mut points = vec![];
        for chunk in store.iter_physical_chunks() {
            if chunk.entity_path().to_string() == entity {
                for ((t, _), v) in chunk
                    .iter_component_indices(timeline, component)
                    .zip(chunk.iter_slices::<f64>(component))
                {
                    points.push((t.as_i64(), v[0]));
                }
            }
        }
        points.sort_by_key(|p| p.0);
        let expect: Vec<(i64, f64)> = [(3, k), (4, 2 + k)]
            .iter()
            .map(|&(t, i)| {
                let d = rows[i]["summary"]["energies"]["damage_dissipated"].as_f64();
                (t, d.unwrap())
            })
            .collect();
        // The row's value is read back from JSON text, which serde_json (without its
        // `float_roundtrip` parser) may return 1 ulp off; the capture holds the exact f64.
        let ulps = |a: f64, b: f64| (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
        assert!(
            points.len() == expect.len()
                && points
                    .iter()
                    .zip(&expect)
                    .all(|(p, e)| p.0 == e.0 && ulps(p.1, e.1) <= 1),
            "{entity}: {points:?} against the rows' {expect:?}"
        );
    }
    verify(&rrd);
}

/// Unknown key, non-number, empty list, empty value, a combination the scene refuses: each
/// error names the key and the value, and nothing is written.
#[test]
fn bad_vary_input_names_the_key_and_value() {
    let dir = scratch("sweep", "bad");
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["interface.law.foo=1,2"],
            &[
                "--vary interface.law.foo",
                "the value `1`",
                "not a parameter",
            ],
        ),
        (
            &["interface.law.u_r=0.004,abc"],
            &["--vary interface.law.u_r", "`abc`", "number"],
        ),
        (
            &["interface.law.u_r="],
            &["--vary interface.law.u_r", "empty"],
        ),
        (
            &["interface.law.u_r=0.004,,0.005"],
            &["--vary interface.law.u_r", "value 2"],
        ),
        (&["end_time"], &["--vary `end_time`", "no `=`"]),
        (
            &[
                "interface.law.alpha_e=0.001,0.003",
                "interface.law.u_r=0.0025,0.004",
            ],
            &[
                "interface.law.alpha_e=0.003 interface.law.u_r=0.0025",
                "u_r must be",
            ],
        ),
    ];
    for (varies, needles) in cases {
        let mut args = vec![
            "sweep",
            "scenes/pull_off.toml",
            "--out",
            dir.to_str().unwrap(),
        ];
        for v in varies {
            args.extend(["--vary", v]);
        }
        let out = decohesion(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{varies:?} accepted");
        for n in needles {
            assert!(err.contains(n), "{varies:?}: `{n}` not in {err}");
        }
        assert!(!dir.join("sweep.csv").exists(), "{varies:?}: nothing runs");
    }
}

/// A run that fails (the top slammed down at 100 m/s: an element inverts within a few steps)
/// is a failed row with its error, the other completes, the sweep succeeds.
#[test]
fn a_failed_run_is_a_row() {
    let dir = scratch("sweep", "failed");
    let slam = "displacement.table=[[0,0],[0.33,0.33]],[[0,0],[0.01,-1]]";
    let rows = sweep_small(&dir, &["--set", "end_time=0.05", "--vary", slam]);
    assert_eq!(rows[0]["status"], "completed");
    assert_eq!(rows[1]["status"], "failed");
    assert!(rows[1]["error"]
        .as_str()
        .is_some_and(|e| e.contains("inverted")));
    let csv = std::fs::read_to_string(dir.join("sweep.csv")).unwrap();
    assert!(csv.lines().nth(2).unwrap().contains(",failed,"));
}

/// Ctrl-C after the first of eight runs: the run in progress stops (a `cancelled` row), no
/// other starts, the rows done are written, the exit status says it was interrupted.
#[test]
fn ctrl_c_writes_the_rows_done() {
    let dir = scratch("sweep", "ctrl_c");
    let mut child = Command::new(BIN)
        .args([
            "sweep",
            "scenes/pull_off.toml",
            "--set",
            "mesh.cells=[3,3,3]",
            "--set",
            "end_time=4",
            "--jobs",
            "1",
            "--vary",
            "interface.law.u_r=0.003,0.004,0.005,0.006,0.007,0.008,0.009,0.010",
            "--out",
            dir.to_str().unwrap(),
        ])
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while !line.contains("run 1/8") {
        line.clear();
        assert!(stderr.read_line(&mut line).unwrap() > 0, "no run finished");
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    let status = child.wait().unwrap();
    assert!(!status.success());
    assert!(rest.contains("interrupted"), "{rest}");
    let rows = runs(&dir);
    assert!((1..8).contains(&rows.len()), "{} rows", rows.len());
    assert_eq!(rows[0]["status"], "completed");
    for r in &rows {
        assert!(
            r["status"] == "completed" || r["status"] == "cancelled",
            "{r}"
        );
    }
}
