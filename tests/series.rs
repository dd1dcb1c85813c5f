//! `decohesion run --series FILE.csv`: the run's scalars as a CSV time series.
//! - `roller_peel` whole, a row per step: the header's units, time and step in order, the
//!   roller's force and moment there and nonzero, the last row equal to the summary to the bit,
//!   and the roller's force in the steady peel Kendall's (the check of
//!   `tests/recording_mould_loads.rs`, here on every step);
//! - a short pull-off: the reaction at the summary's peak time is the summary's peak to the
//!   bit, and the imposed motion's work integrated from the rows by the trapezoid rule is the
//!   ledger's reaction work; with `--every` the rows are the frames' steps;
//! - a run that fails (an inverted element) and one cancelled by Ctrl-C leave a complete file;
//! - a file that cannot be created is refused before the run starts.

use crate::common::cli::{decohesion, decohesion_ok, interrupt_cancelled, scratch, summary, BIN};
use decohesion::output::surface::mould::body_box;
use decohesion::scene::load_scene;
use std::path::Path;
use std::process::Command;

/// A series read back: the header's names and the rows, every value parsed.
struct Series {
    names: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Series {
    /// Reads the CSV at `path`; fails the test on a line without all the columns or a value
    /// that is not a number (NaN and ±inf are numbers here).
    fn read(path: &Path) -> Series {
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.ends_with('\n'), "the file ends with a whole line");
        let mut lines = text.lines();
        let names: Vec<String> = lines
            .next()
            .expect("a header")
            .split(',')
            .map(String::from)
            .collect();
        let rows: Vec<Vec<f64>> = lines
            .enumerate()
            .map(|(i, line)| {
                let row: Vec<f64> = (line.split(','))
                    .map(|v| {
                        v.parse()
                            .unwrap_or_else(|e| panic!("line {}: {v:?}: {e}", i + 2))
                    })
                    .collect();
                assert_eq!(row.len(), names.len(), "line {}: {line}", i + 2);
                row
            })
            .collect();
        Series { names, rows }
    }

    /// The index of the column `name`, which must be there.
    fn index(&self, name: &str) -> usize {
        (self.names.iter().position(|n| n == name))
            .unwrap_or_else(|| panic!("no column {name:?} in {:?}", self.names))
    }

    /// The column `name`.
    fn column(&self, name: &str) -> Vec<f64> {
        let k = self.index(name);
        self.rows.iter().map(|r| r[k]).collect()
    }

    /// The last row's value of `name`.
    fn last(&self, name: &str) -> f64 {
        self.rows.last().unwrap()[self.index(name)]
    }
}

/// Every column named `name [unit]` with a unit of this list.
fn check_units(s: &Series) {
    for name in &s.names {
        let unit = name
            .strip_suffix(']')
            .and_then(|n| n.rsplit_once(" ["))
            .map(|(_, u)| u);
        assert!(
            matches!(unit, Some("s" | "-" | "m" | "N" | "N m" | "J")),
            "column {name:?}: `name [unit]` with a unit of s, -, m, N, N m, J"
        );
    }
}

/// Time increases strictly and the step by one from 0 (a row per step).
fn check_every_step(s: &Series) {
    let (t, step) = (s.column("t [s]"), s.column("step [-]"));
    assert_eq!(t[0], 0.0);
    assert!(t.windows(2).all(|w| w[1] > w[0]), "time increases");
    assert!(
        step.iter().enumerate().all(|(i, &n)| n == i as f64),
        "a row per step from step 0"
    );
}

const ROLLER: &str = "scenes/roller_peel.toml";

#[test]
fn roller_peel_series_has_the_roller_s_load_and_ends_at_the_summary() {
    let dir = scratch("series", "roller");
    let (csv, json) = (dir.join("roller.csv"), dir.join("roller.json"));
    let (csv_s, json_s) = (csv.to_str().unwrap(), json.to_str().unwrap());
    decohesion_ok(&[
        "run",
        ROLLER,
        "--quiet",
        "--series",
        csv_s,
        "--summary",
        json_s,
    ]);
    let (s, sum) = (Series::read(&csv), summary(&json));
    check_units(&s);
    check_every_step(&s);
    assert_eq!(s.rows.len() as u64, sum["steps"].as_u64().unwrap() + 1);
    assert_eq!(s.last("t [s]"), sum["simulated_time"].as_f64().unwrap());
    assert_eq!(sum["series"]["rows"].as_u64().unwrap(), s.rows.len() as u64);
    assert_eq!(
        sum["series"]["bytes"].as_u64().unwrap(),
        std::fs::metadata(&csv).unwrap().len()
    );

    // Both moulds' force and moment, the roller's nonzero (it lifts, pulls and winds).
    for mould in ["plate", "roller"] {
        for q in ["F", "M"] {
            for axis in ["x", "y", "z"] {
                let unit = if q == "F" { "N" } else { "N m" };
                s.index(&format!("{q}_mould_{mould}_{axis} [{unit}]"));
            }
        }
    }
    for name in ["F_mould_roller_x [N]", "F_mould_roller_z [N]"] {
        assert!(s.column(name).iter().any(|&f| f != 0.0), "{name}");
    }
    assert!(s.column("M_mould_roller_y [N m]").iter().any(|&m| m != 0.0));

    // The last row is the state the summary describes: the same f64s (the JSON writes the
    // shortest decimal that reads back to the same f64, as the CSV does), so equal to the bit.
    for (key, value) in sum["energies"].as_object().unwrap() {
        let unit = if key == "relative_residual" { "-" } else { "J" };
        assert_eq!(
            s.last(&format!("{key} [{unit}]")),
            value.as_f64().unwrap(),
            "{key}"
        );
    }
    for entry in sum["mould_friction"].as_array().unwrap() {
        let name = entry[0].as_str().unwrap();
        let column = format!("friction_mould_{name} [J]");
        assert_eq!(s.last(&column), entry[1].as_f64().unwrap(), "{column}");
    }
    for state in ["elastic", "transition", "ruptured"] {
        let want = sum["final_counts"][state].as_f64().unwrap();
        assert_eq!(s.last(&format!("n_{state} [-]")), want, "{state}");
    }
    // The counts of each row add up to the interface nodes.
    let nodes = sum["interface_nodes"].as_f64().unwrap();
    let counts =
        ["elastic", "transition", "ruptured", "unformed"].map(|c| s.column(&format!("n_{c} [-]")));
    for i in 0..s.rows.len() {
        assert_eq!(counts.iter().map(|c| c[i]).sum::<f64>(), nodes, "row {i}");
    }

    // Physics: the roller's force in the steady peel (t ≥ 0.06 s) against Kendall's balance
    // at the front with the arm's stretch and the kinetic energy it carries away,
    // (F/b)(1 − cos θ) + (F/b)²/(2Et) = G_c + ρtV²(1 − cos θ), θ the angle of the mean force:
    // within 3 %, the tolerance of physics/tests/roller_peel.rs (the force drops by about
    // half each time a node pair lets go, ~20 times in the window), here over every step.
    let model = load_scene(Path::new(ROLLER), &[]).unwrap().model;
    let (gc, young, rho) = (
        model.interfaces[0].law.fracture_energy(),
        model.material.young,
        model.material.density,
    );
    let (lo, hi) = body_box(&model);
    let (b, t) = (hi[1] - lo[1], hi[2] - lo[2]);
    let roller = model.moulds.iter().find(|p| p.name == "roller").unwrap();
    let v = roller.velocity.as_ref().unwrap().value(0.1)[0];
    let time = s.column("t [s]");
    let steady: Vec<usize> = (0..time.len()).filter(|&i| time[i] >= 0.06).collect();
    assert!(steady.len() > 1000, "{} steps", steady.len());
    let f: [f64; 3] = ["x", "y", "z"].map(|a| {
        let c = s.column(&format!("F_mould_roller_{a} [N]"));
        steady.iter().map(|&i| c[i]).sum::<f64>() / steady.len() as f64
    });
    let f_abs = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    let c1 = 1.0 - f[0] / f_abs;
    let a = 1.0 / (2.0 * young * t);
    let rhs = gc + rho * t * v * v * c1;
    let kendall = b * (-c1 + (c1 * c1 + 4.0 * a * rhs).sqrt()) / (2.0 * a);
    eprintln!(
        "roller: mean F = {f:?} N over {} steps, |F| = {f_abs:.4} N, Kendall {kendall:.4} N \
         ({:+.2} %)",
        steady.len(),
        100.0 * (f_abs / kendall - 1.0)
    );
    assert!(
        (f_abs / kendall - 1.0).abs() <= 0.03,
        "{f_abs} N vs {kendall} N"
    );
}

/// The pull-off on 3³ elements to the full rupture and past it (0.2 s, about a second).
const PULL: [&str; 6] = [
    "scenes/pull_off.toml",
    "--quiet",
    "--set",
    "mesh.cells=[3,3,3]",
    "--set",
    "end_time=0.2",
];

#[test]
fn pull_off_series_holds_the_peak_and_the_imposed_motion_s_work() {
    let dir = scratch("series", "pull");
    let (csv, json) = (dir.join("pull.csv"), dir.join("pull.json"));
    let mut args = vec!["run"];
    args.extend(PULL);
    args.extend(["--series", csv.to_str().unwrap()]);
    args.extend(["--summary", json.to_str().unwrap()]);
    decohesion_ok(&args);
    let (s, sum) = (Series::read(&csv), summary(&json));
    check_units(&s);
    check_every_step(&s);
    let (u, f, t) = (
        s.column("u_z_plus_z [m]"),
        s.column("F_z_plus_z [N]"),
        s.column("t [s]"),
    );

    // The summary's peak is the row at its time, to the bit (the same f64s).
    let peak = &sum["peak_reactions"][0];
    let at = peak["time"].as_f64().unwrap();
    let i = t.iter().position(|&x| x == at).expect("a row at the peak");
    assert_eq!(f[i], peak["force"].as_f64().unwrap());
    assert_eq!(u[i], peak["imposed_displacement"].as_f64().unwrap());
    assert!(f[i] > 0.0);

    // The imposed motion's work from the rows, Σ ½(Fₖ₋₁ + Fₖ)(uₖ − uₖ₋₁), is the ledger's
    // reaction work: the ledger adds ½(V_{k−½} + V_{k+½})·Pₖ with Pₖ = Fₖ h̄ₖ and
    // h̄ₖ = ½(h_{k−½} + h_{k+½}); at the constant imposed velocity V = 1 m/s of this scene,
    // V h_{k±½} = uₖ₊₁ − uₖ (or uₖ − uₖ₋₁), so both are the same sum regrouped and differ by
    // round-off only: 1e-12 of the work (some 10³ terms, each rounded to 1e-16 of itself).
    let work: f64 = (1..u.len())
        .map(|k| 0.5 * (f[k - 1] + f[k]) * (u[k] - u[k - 1]))
        .sum();
    let ledger = sum["energies"]["reaction_work"].as_f64().unwrap();
    assert_eq!(s.last("reaction_work [J]"), ledger);
    eprintln!("reaction work: trapezoid {work} J, ledger {ledger} J");
    assert!(
        (work - ledger).abs() <= 1e-12 * ledger.abs(),
        "trapezoid {work} J vs ledger {ledger} J"
    );
}

#[test]
fn with_every_the_rows_are_the_frames_steps() {
    let dir = scratch("series", "every");
    let (csv, json) = (dir.join("every.csv"), dir.join("every.json"));
    let mut args = vec!["run"];
    args.extend(PULL);
    args.extend(["--every", "7", "--series", csv.to_str().unwrap()]);
    args.extend(["--summary", json.to_str().unwrap()]);
    decohesion_ok(&args);
    let (s, sum) = (Series::read(&csv), summary(&json));
    let n = sum["steps"].as_u64().unwrap();
    let want: Vec<f64> = (0..=n)
        .filter(|k| k % 7 == 0)
        .chain((n % 7 != 0).then_some(n))
        .map(|k| k as f64)
        .collect();
    assert_eq!(s.column("step [-]"), want);
}

#[test]
fn a_failing_run_leaves_a_complete_series_to_the_failing_step() {
    let dir = scratch("series", "fail");
    let (csv, json) = (dir.join("fail.csv"), dir.join("fail.json"));
    let out = decohesion(&[
        "run",
        "scenes/pull_off.toml",
        "--quiet",
        "--set",
        // The top slammed down at 100 m/s: an element inverts within a few steps.
        "displacement.0.table=[[0.0, 0.0], [0.01, -1.0]]",
        "--set",
        "end_time=0.05",
        "--series",
        csv.to_str().unwrap(),
        "--summary",
        json.to_str().unwrap(),
    ]);
    assert!(!out.status.success(), "an inverted element fails the run");
    let sum = summary(&json);
    assert_eq!(sum["status"], "failed");
    let s = Series::read(&csv);
    let failing = sum["steps"].as_f64().unwrap();
    assert!(failing > 0.0);
    assert_eq!(
        s.last("step [-]"),
        failing,
        "the failing step is the last row"
    );
    assert_eq!(s.rows.len() as f64, failing + 1.0, "every step before it");
}

#[test]
fn ctrl_c_leaves_a_complete_series() {
    let dir = scratch("series", "sigint");
    let (csv, json) = (dir.join("sigint.csv"), dir.join("sigint.json"));
    // A long run (10³ elements to t = 10 s) interrupted once rows are in the file.
    let child = Command::new(BIN)
        .args([
            "run",
            "scenes/pull_off.toml",
            "--quiet",
            "--set",
            "mesh.cells=[10,10,10]",
            "--set",
            "end_time=10",
            "--series",
            csv.to_str().unwrap(),
            "--summary",
            json.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let header = |p: &Path| std::fs::read_to_string(p).map_or(0, |t| t.lines().count());
    let waited = std::time::Instant::now();
    while header(&csv) < 3 && waited.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let sum = interrupt_cancelled(child, &json);
    let s = Series::read(&csv);
    check_every_step(&s);
    assert_eq!(s.last("step [-]"), sum["steps"].as_f64().unwrap());
}

#[test]
fn a_series_file_that_cannot_be_created_is_refused_before_the_run() {
    let dir = scratch("series", "refused");
    let json = dir.join("refused.json");
    let out = decohesion(&[
        "run",
        "scenes/pull_off.toml",
        "--series",
        "/nonexistent-dir/x.csv",
        "--summary",
        json.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("/nonexistent-dir/x.csv") && err.contains("--series"),
        "{err}"
    );
    assert!(!json.exists(), "the run did not start");
}
