//! `decohesion tradeoff` end to end on a small grid: the reference row is the finest, its
//! error is 0, every row's error is the largest of its observables' relative errors, the CSV
//! and JSON (`tradeoff.csv` and `tradeoff.json` in the `--out` folder) agree, and a
//! configuration the scene refuses is reported before anything runs.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_decohesion");

#[test]
fn small_grid_marks_reference_and_front() {
    let dir = std::env::temp_dir()
        .join(format!("decohesion-tradeoff-{}", std::process::id()))
        .join("grid");
    let out = Command::new(BIN)
        .args([
            "tradeoff",
            "scenes/pull_off.toml",
            "--cells",
            "3,4",
            "--factors",
            "0.5,0.25",
            "--integration",
            "full,reduced",
            "--out",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(dir.join("tradeoff.json")).unwrap()).unwrap();
    assert_eq!(rows.len(), 8);
    let refs: Vec<&serde_json::Value> = rows.iter().filter(|r| r["reference"] == true).collect();
    assert_eq!(refs.len(), 1);
    let r = refs[0];
    assert_eq!(r["config"]["cells"], 4);
    assert_eq!(r["config"]["factor"], 0.25);
    assert_eq!(r["config"]["integration"], "full");
    assert_eq!(r["error"], 0.0);
    assert_eq!(
        r["pareto"], true,
        "the reference is never dominated in accuracy"
    );
    for row in &rows {
        let errs: Vec<f64> = [
            "error_peak_force",
            "error_first_damage",
            "error_full_rupture",
            "error_dissipated",
        ]
        .iter()
        .filter_map(|k| row[k].as_f64())
        .collect();
        let max = errs.iter().cloned().fold(0.0, f64::max);
        assert_eq!(row["error"].as_f64().unwrap(), max);
        // Dissipation error is measured against the reference's dissipation.
        let d = row["damage_dissipated"].as_f64().unwrap();
        let d_ref = r["damage_dissipated"].as_f64().unwrap();
        let e = row["error_dissipated"].as_f64().unwrap();
        assert!((e - ((d - d_ref) / d_ref).abs()).abs() < 1e-12);
    }
    let csv = std::fs::read_to_string(dir.join("tradeoff.csv")).unwrap();
    assert_eq!(csv.lines().count(), 9, "header + 8 rows");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("ref"), "{stdout}");
}

#[test]
fn an_inadmissible_configuration_is_refused_before_running() {
    let out = Command::new(BIN)
        .args([
            "tradeoff",
            "scenes/pull_off.toml",
            "--cells",
            "3",
            "--factors",
            "0.5,2.5",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("scheme.time_step_factor") && err.contains("2.5") && err.contains("(0, 2)"),
        "{err}"
    );
}

/// `--cells` (tradeoff) and `--sizes` (bench) set a box's cells: a Gmsh mesh file is refused.
#[test]
fn a_mesh_file_is_refused_by_cells_and_sizes() {
    for args in [
        ["tradeoff", "scenes/tread.toml", "--cells", "3"],
        ["bench", "scenes/tread.toml", "--sizes=3", "--repeats=1"],
    ] {
        let out = Command::new(BIN).args(args).output().unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        let flag = if args[0] == "bench" {
            "--sizes"
        } else {
            "--cells"
        };
        assert!(
            err.contains("scenes/tread.toml: key `mesh.file`")
                && err.contains(&format!("{flag} needs a box mesh")),
            "{err}"
        );
    }
}
