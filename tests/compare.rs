//! `decohesion compare A B`: two results observable by observable.
//! - the pull-off at time-step factors 0.5 and 0.25: each energy is judged against the ledger's
//!   band computed here from the two summaries, and moved or not as that band says; a `--tol`
//!   override changes the verdict;
//! - a run against its golden file, a summary against itself: exit 0;
//! - a summary with one value edited: exit 1, naming that observable only;
//! - bad inputs (missing file, a scene file, two kinds, bad or unknown `--tol`): exit 2 with a
//!   message naming the file or the flag and what is admissible;
//! - time series: two runs of the pull-off, the same and at two factors; hand-made series whose
//!   step is one row apart (within the two-row window) or ten rows apart (moved);
//! - captures (`.rrd`) of the same two runs.

use crate::common::cli::{decohesion, decohesion_ok, scratch, summary};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The pull-off at a time-step factor: its summary, series and (with `rrd`) capture.
fn pull_off(dir: &Path, factor: &str, rrd: bool) -> (PathBuf, PathBuf, PathBuf) {
    let (json, csv, cap) = (
        dir.join(format!("s{factor}.json")),
        dir.join(format!("s{factor}.csv")),
        dir.join(format!("s{factor}.rrd")),
    );
    let set = format!("scheme.time_step_factor={factor}");
    let mut args = vec!["run", "scenes/pull_off.toml", "--quiet", "--set", &set];
    let paths = [json.to_str().unwrap(), csv.to_str().unwrap()];
    args.extend(["--summary", paths[0], "--series", paths[1]]);
    if rrd {
        args.extend(["--save", cap.to_str().unwrap()]);
    }
    decohesion_ok(&args);
    (json, csv, cap)
}

/// `compare` with its exit status, standard output and error.
fn compare(args: &[&str]) -> (i32, String, String) {
    let mut all = vec!["compare"];
    all.extend(args);
    let out = decohesion(&all);
    (
        out.status.code().expect("an exit status"),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `compare --json`: the exit status and the rows by key.
fn compare_json(a: &Path, b: &Path, tol: &[&str]) -> (i32, Vec<Value>) {
    let mut args = vec![a.to_str().unwrap(), b.to_str().unwrap(), "--json"];
    for t in tol {
        args.extend(["--tol", t]);
    }
    let (code, out, err) = compare(&args);
    assert!(code == 0 || code == 1, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    (code, v["rows"].as_array().unwrap().clone())
}

fn row<'a>(rows: &'a [Value], key: &str) -> &'a Value {
    (rows.iter().find(|r| r["key"] == key)).unwrap_or_else(|| panic!("no row {key}"))
}

/// The ledger's band of a summary: max relative residual × the largest energy seen
/// (residual / relative residual at the end).
fn band(s: &Value) -> f64 {
    let e = &s["energies"];
    let seen = (e["residual"].as_f64().unwrap() / e["relative_residual"].as_f64().unwrap()).abs();
    s["max_relative_residual"].as_f64().unwrap() * seen
}

#[test]
fn two_time_steps_energies_within_the_ledgers_band_or_moved() {
    let dir = scratch("compare", "factors");
    let (a, _, _) = pull_off(&dir, "0.5", false);
    let (b, _, _) = pull_off(&dir, "0.25", false);
    let (sa, sb) = (summary(&a), summary(&b));
    let band = band(&sa).max(band(&sb));
    let (code, rows) = compare_json(&a, &b, &[]);
    let mut moved = 0;
    for key in [
        "damage_dissipated",
        "kinetic",
        "strain",
        "external_work",
        "residual",
    ] {
        let r = row(&rows, &format!("energies.{key}"));
        let d =
            (sa["energies"][key].as_f64().unwrap() - sb["energies"][key].as_f64().unwrap()).abs();
        let allowed = r["tolerance"]["allowed"].as_f64().unwrap();
        // The band, plus a round-off term far below it.
        assert!(
            (allowed - band).abs() <= 1e-6 * band,
            "{key}: {allowed} vs {band}"
        );
        let verdict = if d <= allowed { "ok" } else { "moved" };
        assert_eq!(r["verdict"], verdict, "{key}: |ΔE| = {d}, band {band}");
        moved += (verdict == "moved") as usize;
    }
    assert!(
        moved > 0,
        "halving h moves some energy beyond the band of these runs"
    );
    assert_eq!(code, 1, "something moved, exit 1");
    // D differs by a few per cent between the factors: 5 % accepts it, 0.1 % does not.
    let d = "energies.damage_dissipated";
    let (_, rows) = compare_json(&a, &b, &[&format!("{d}=5%")]);
    assert_eq!(row(&rows, d)["verdict"], "ok");
    assert_eq!(row(&rows, d)["tolerance"]["kind"], "relative");
    let (_, rows) = compare_json(&a, &b, &[&format!("{d}=0.1%")]);
    assert_eq!(row(&rows, d)["verdict"], "moved");
}

#[test]
fn a_run_matches_its_golden_file_and_itself() {
    let dir = scratch("compare", "same");
    let (a, _, _) = pull_off(&dir, "0.5", false);
    let golden = "tests/golden/pull_off.json";
    let (code, out, err) = compare(&[golden, a.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("all within tolerance"), "{out}");
    assert!(!out.contains("MOVED"), "{out}");
    let (code, out, _) = compare(&[a.to_str().unwrap(), a.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}");
}

#[test]
fn an_edited_summary_fails_naming_the_observable() {
    let dir = scratch("compare", "edited");
    let golden = "tests/golden/pull_off.json";
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(golden).unwrap()).unwrap();
    let s = &mut v["summary"];
    let h = s["steps_taken"]["h_max"].as_f64().unwrap();
    let t = s["time_full_rupture"].as_f64().unwrap();
    s["time_full_rupture"] = (t + 10.0 * h).into();
    let edited = dir.join("edited.json");
    std::fs::write(&edited, serde_json::to_string(&v).unwrap()).unwrap();
    let (code, out, _) = compare(&[golden, edited.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("1 of "), "one observable moved: {out}");
    let moved: Vec<&str> = out.lines().filter(|l| l.ends_with("MOVED")).collect();
    assert_eq!(moved.len(), 1, "{out}");
    assert!(
        moved[0].trim_start().starts_with("time_full_rupture "),
        "{out}"
    );
    // Two steps are the default tolerance: one step later is the same physics.
    s_edit(&mut v, t + h);
    std::fs::write(&edited, serde_json::to_string(&v).unwrap()).unwrap();
    let (code, out, _) = compare(&[golden, edited.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}");
}

fn s_edit(v: &mut Value, t: f64) {
    v["summary"]["time_full_rupture"] = t.into();
}

#[test]
fn bad_inputs_exit_2_naming_the_file_or_the_flag() {
    let dir = scratch("compare", "bad");
    let golden = "tests/golden/pull_off.json";
    let csv = dir.join("a.csv");
    std::fs::write(&csv, "t [s],step [-],h [s]\n0.0,0,0.1\n").unwrap();
    let csv = csv.to_str().unwrap();
    for (args, expect) in [
        (
            vec![golden, "/no/such/file.json"],
            vec!["/no/such/file.json", "cannot read"],
        ),
        (
            vec!["scenes/pull_off.toml", golden],
            vec!["scenes/pull_off.toml", "not JSON"],
        ),
        (vec![golden, "Cargo.toml"], vec!["Cargo.toml", "not JSON"]),
        (
            vec![golden, csv],
            vec!["not of one kind", "a run summary against a time series"],
        ),
        (
            vec![golden, golden, "--tol", "energies=abc"],
            vec!["--tol energies=abc", "N%"],
        ),
        (
            vec![golden, golden, "--tol", "energies"],
            vec!["--tol energies", "KEY=VALUE"],
        ),
        (
            vec![golden, golden, "--tol", "energies=-1"],
            vec!["--tol energies=-1", "≥ 0"],
        ),
        (
            vec![golden, golden, "--tol", "nonsense=1"],
            vec![
                "--tol nonsense",
                "admissible",
                "energies",
                "time_full_rupture",
            ],
        ),
    ] {
        let (code, out, err) = compare(&args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        for e in expect {
            assert!(err.contains(e), "{args:?}: {err:?} should contain {e:?}");
        }
    }
    let json = dir.join("other.json");
    std::fs::write(&json, "{\"steps\": 3}").unwrap();
    let (code, _, err) = compare(&[golden, json.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("other.json") && err.contains("not a run summary"),
        "{err}"
    );
}

#[test]
fn series_of_two_runs_compared_column_by_column() {
    let dir = scratch("compare", "series");
    let (_, a, _) = pull_off(&dir, "0.5", false);
    let again = dir.join("again");
    std::fs::create_dir_all(&again).unwrap();
    let (_, a2, _) = pull_off(&again, "0.5", false);
    let (_, b, _) = pull_off(&dir, "0.25", false);
    let (code, rows) = compare_json(&a, &a2, &[]);
    assert_eq!(code, 0);
    for r in &rows {
        assert!(r["difference"].as_f64().is_none_or(|d| d == 0.0), "{r}");
    }
    let (code, rows) = compare_json(&a, &b, &[]);
    assert_eq!(code, 1);
    assert_eq!(row(&rows, "damage_dissipated")["verdict"], "moved");
    assert_eq!(row(&rows, "damage_dissipated")["group"], "energies");
    assert_eq!(
        row(&rows, "u_z_plus_z")["verdict"],
        "ok",
        "the imposed motion is the same"
    );
}

/// A series of 40 rows 0.1 s apart whose force steps from 0 to 1000 N at row `at` (its column
/// named with a comma and a quote, quoted as the series writes such a name).
fn step_series(path: &Path, at: usize) {
    let mut s = String::from(
        "t [s],step [-],h [s],\"F_mould_a,\"\"b\"\"_z [N]\",kinetic [J],relative_residual [-]\n",
    );
    for k in 0..40 {
        let f = if k >= at { 1000.0 } else { 0.0 };
        s.push_str(&format!("{},{k},0.1,{f},1.0,0.0\n", k as f64 * 0.1));
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn a_step_one_row_apart_is_the_same_ten_rows_apart_it_moved() {
    let dir = scratch("compare", "step");
    let (a, near, far) = (dir.join("a.csv"), dir.join("near.csv"), dir.join("far.csv"));
    step_series(&a, 20);
    step_series(&near, 21);
    step_series(&far, 30);
    let (code, rows) = compare_json(&a, &near, &[]);
    assert_eq!(code, 0, "{rows:?}");
    let (code, rows) = compare_json(&a, &far, &[]);
    assert_eq!(code, 1);
    let r = row(&rows, "F_mould_a,\"b\"_z");
    assert_eq!(r["verdict"], "moved");
    assert_eq!(r["difference"].as_f64(), Some(1000.0));
}

#[test]
fn captures_of_two_runs_compared_as_series() {
    let dir = scratch("compare", "rrd");
    let (_, csv, a) = pull_off(&dir, "0.5", true);
    let again = dir.join("again");
    std::fs::create_dir_all(&again).unwrap();
    let (_, _, a2) = pull_off(&again, "0.5", true);
    let (_, _, b) = pull_off(&dir, "0.25", true);
    let (code, rows) = compare_json(&a, &a2, &[]);
    assert_eq!(code, 0);
    assert_eq!(row(&rows, "status")["a"], "completed");
    assert!(rows.len() > 10, "the capture's series: {rows:?}");
    let (code, rows) = compare_json(&a, &b, &[]);
    assert_eq!(code, 1);
    assert_eq!(row(&rows, "energy/damage_dissipated")["verdict"], "moved");
    let (code, _, err) = compare(&[a.to_str().unwrap(), csv.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("a capture against a time series"), "{err}");
}
