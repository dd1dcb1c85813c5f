//! Two run summaries (`run --summary`, a golden file's `summary`) compared key by key with the
//! default tolerances of [`super`] (the reasons are there).

use super::{Kind, Report, Row, Tol};
use serde_json::{Map, Value};

/// Summary keys that measure the machine or the outputs, not the physics: left out.
pub const TIMING_KEYS: [&str; 9] = [
    "wall_seconds",
    "step_wall_seconds",
    "element_steps_per_second",
    "ns_per_element_step",
    "stage_seconds",
    "threads",
    "recording",
    "paraview",
    "series",
];

/// The summary object of a JSON text: the text itself, or its `summary` key (a golden file).
/// A golden file of a scene that failed to set up (`setup_error`) is a summary of that error.
pub fn parse(text: &str) -> Result<Value, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| {
        format!("not JSON ({e}): compare run summaries (run --summary), golden files (tests/golden/*.json), time series (.csv) or captures (.rrd)")
    })?;
    let is_summary = |v: &Value| v.get("energies").is_some() && v.get("status").is_some();
    if let Some(s) = v.get("summary").filter(|s| is_summary(s)) {
        return Ok(s.clone());
    }
    if let Some(e) = v.get("setup_error").and_then(Value::as_str) {
        let mut m = Map::new();
        m.insert("status".into(), "set-up failed".into());
        m.insert("error".into(), e.into());
        return Ok(Value::Object(m));
    }
    if is_summary(&v) {
        return Ok(v);
    }
    Err("JSON without `status` and `energies`: not a run summary (run --summary) nor a golden file (a `summary` key)".into())
}

fn num(v: &Value, path: &[&str]) -> Option<f64> {
    path.iter().try_fold(v, |v, k| v.get(k))?.as_f64()
}

/// What a run's tolerances are made of.
struct Scales {
    /// Largest step [s].
    h: f64,
    /// The ledger's band: max relative residual × the largest energy, plus round-off [J].
    energy: f64,
    /// Max relative residual.
    residual: f64,
}

impl Scales {
    fn of(s: &Value) -> Scales {
        let e = s.get("energies");
        let terms: Vec<f64> = e
            .and_then(Value::as_object)
            .map(|m| {
                m.iter()
                    .filter(|(k, _)| *k != "relative_residual")
                    .filter_map(|(_, v)| v.as_f64())
                    .collect()
            })
            .unwrap_or_default();
        let largest_term = terms.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        // The ledger divides by the largest energy seen, which may have been before the end.
        let seen = match (
            num(s, &["energies", "residual"]),
            num(s, &["energies", "relative_residual"]),
        ) {
            (Some(r), Some(q)) if q != 0.0 && (r / q).is_finite() => (r / q).abs(),
            _ => 0.0,
        };
        let e_max = largest_term.max(seen);
        let residual = num(s, &["max_relative_residual"]).unwrap_or(0.0).abs();
        let steps = num(s, &["steps"]).unwrap_or(0.0);
        let h = num(s, &["steps_taken", "h_max"])
            .or_else(|| num(s, &["time_step"]))
            .unwrap_or(0.0);
        Scales {
            h,
            energy: residual * e_max + steps * f64::EPSILON * e_max,
            residual,
        }
    }

    fn max(a: Scales, b: Scales) -> Scales {
        Scales {
            h: a.h.max(b.h),
            energy: a.energy.max(b.energy),
            residual: a.residual.max(b.residual),
        }
    }
}

const WHY_ENERGY: &str = "max relative residual × largest energy (the ledger's error) + round-off";
const WHY_TIME: &str = "two steps (an event is seen at the first step it holds)";
const WHY_H: &str = "2 %: the margin of a cheap h_crit update";

/// Compares two summaries.
pub fn compare(a: &Value, b: &Value) -> Report {
    let sc = Scales::max(Scales::of(a), Scales::of(b));
    let mut rows = Vec::new();
    let text = |v: &Value, k: &str| {
        v.get(k)
            .filter(|x| !x.is_null())
            .map(|x| x.as_str().map_or(x.to_string(), String::from))
    };
    for (key, tol) in [
        ("status", Tol::Exact),
        ("error", Tol::Exact),
        ("scene", Tol::Info),
    ] {
        let why = if tol == Tol::Info { "a name" } else { "equal" };
        rows.push(
            Row::text(
                key.into(),
                if tol == Tol::Info { "inputs" } else { "status" },
                text(a, key),
                text(b, key),
                tol,
            )
            .because(why),
        );
    }
    let n = |key: &str, group, tol: Tol, why: &str| {
        Row::num(
            key.into(),
            group,
            num(a, &key.split('.').collect::<Vec<_>>()),
            num(b, &key.split('.').collect::<Vec<_>>()),
            tol,
        )
        .because(why)
    };
    for key in ["nodes", "elements", "interface_nodes"] {
        rows.push(n(key, "mesh", Tol::Exact, "equal: the same mesh"));
    }
    rows.push(n("time_step_factor", "inputs", Tol::Info, "an input"));
    let steps = num(a, &["steps"])
        .unwrap_or(0.0)
        .max(num(b, &["steps"]).unwrap_or(0.0));
    rows.push(n(
        "steps",
        "steps",
        Tol::Abs(0.01 * steps + 2.0),
        "1 % + 2: the controller's decisions shift with round-off",
    ));
    for key in [
        "time_step",
        "h_crit_initial",
        "h_crit_min",
        "steps_taken.h_min",
        "steps_taken.h_max",
    ] {
        rows.push(n(key, "h", Tol::Rel(0.02), WHY_H));
    }
    for key in [
        "changes",
        "h_crit_estimates",
        "h_crit_iterations",
        "h_crit_certified",
    ] {
        rows.push(n(
            &format!("steps_taken.{key}"),
            "controller",
            Tol::Info,
            "the controller's statistics",
        ));
    }
    rows.push(n("simulated_time", "times", Tol::Abs(sc.h), "one step"));
    for key in ["time_first_damage", "time_full_rupture"] {
        rows.push(n(key, "times", Tol::Abs(2.0 * sc.h), WHY_TIME));
    }
    peaks(a, b, sc.h, &mut rows);
    for key in ["elastic", "transition", "ruptured", "unformed"] {
        let k = format!("final_counts.{key}");
        let (x, y) = (
            num(a, &["final_counts", key]),
            num(b, &["final_counts", key]),
        );
        if x.is_some() || y.is_some() || key != "unformed" {
            rows.push(
                Row::num(k, "counts", x.or(Some(0.0)), y.or(Some(0.0)), Tol::Abs(1.0))
                    .because("one node: a node near a threshold at the end"),
            );
        }
    }
    energies(a, b, sc.energy, &mut rows);
    rows.push(n(
        "max_relative_residual",
        "residual",
        Tol::Rel(0.5),
        "a factor 2: only its magnitude means something",
    ));
    rows.push(n(
        "energies.relative_residual",
        "residual",
        Tol::Abs(sc.residual),
        "within the larger max relative residual",
    ));
    rest(a, b, &mut rows);
    Report {
        kind: Kind::Summary,
        rows,
        notes: vec![],
    }
}

/// The peak reactions, matched by face set and component.
fn peaks(a: &Value, b: &Value, h: f64, rows: &mut Vec<Row>) {
    let list = |v: &Value| -> Vec<(String, Value)> {
        let arr = v
            .get("peak_reactions")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        arr.into_iter()
            .map(|p| {
                let name = format!(
                    "{} {}",
                    p["faces"].as_str().unwrap_or("?"),
                    p["component"].as_str().unwrap_or("?")
                );
                (name, p)
            })
            .collect()
    };
    let (pa, pb) = (list(a), list(b));
    let mut names: Vec<&String> = pa.iter().map(|p| &p.0).collect();
    names.extend(
        pb.iter()
            .map(|p| &p.0)
            .filter(|n| !pa.iter().any(|p| &p.0 == *n)),
    );
    let largest = (pa.iter().chain(&pb))
        .filter_map(|p| p.1["force"].as_f64())
        .fold(0.0_f64, |m, f| m.max(f.abs()));
    for name in names {
        let get = |l: &[(String, Value)], k: &str| {
            l.iter()
                .find(|p| &p.0 == name)
                .and_then(|p| p.1[k].as_f64())
        };
        rows.extend(peak_rows(name, |k| (get(&pa, k), get(&pb, k)), h, largest));
    }
}

/// The rows of one peak reaction (`get(key)`: A's and B's values). A peak of a component
/// that carries round-off only (below 1e-9 of the largest peak) has no meaningful time or
/// displacement: those are shown, not judged, and its force is judged against the largest.
fn peak_rows(
    name: &str,
    get: impl Fn(&str) -> (Option<f64>, Option<f64>),
    h: f64,
    largest: f64,
) -> Vec<Row> {
    let (fa, fb) = get("force");
    let round_off = fa.unwrap_or(0.0).abs().max(fb.unwrap_or(0.0).abs()) <= 1e-9 * largest;
    let t_peak = get("time").0.or(get("time").1).unwrap_or(0.0);
    let rel = if t_peak > 0.0 {
        (2.0 * h / t_peak).min(1.0)
    } else {
        0.0
    };
    let why = "2 h / t_peak: a rise from zero over t_peak, taken two steps apart";
    let mut rows = Vec::new();
    for (k, group, tol) in [
        ("force", "peaks", Tol::Rel(rel)),
        ("imposed_displacement", "peaks", Tol::Rel(rel)),
        ("time", "times", Tol::Abs(2.0 * h)),
    ] {
        let (why, tol) = match (k, round_off) {
            ("force", true) => ("round-off: 2 h / t_peak of the largest peak", tol),
            (_, true) => ("the peak of a round-off force", Tol::Info),
            ("time", false) => (WHY_TIME, tol),
            _ => (why, tol),
        };
        let (x, y) = get(k);
        let mut row =
            Row::num(format!("peak_reactions[{name}].{k}"), group, x, y, tol).because(why);
        if k == "force" && round_off {
            row.scale = Some(largest);
            row.judge();
        }
        rows.push(row);
    }
    rows
}

/// The names of `a`, then those of `b` not in `a`.
fn union(mut a: Vec<String>, b: Vec<String>) -> Vec<String> {
    for n in b {
        if !a.contains(&n) {
            a.push(n);
        }
    }
    a
}

/// Every energy of the ledger, each mould's work and friction, the clamped ΔD.
fn energies(a: &Value, b: &Value, band: f64, rows: &mut Vec<Row>) {
    let keys = |v: &Value| -> Vec<String> {
        v.get("energies")
            .and_then(Value::as_object)
            .map(|m| m.keys().cloned().collect())
            .unwrap_or_default()
    };
    let names = union(keys(a), keys(b));
    for k in names.iter().filter(|k| *k != "relative_residual") {
        rows.push(
            Row::num(
                format!("energies.{k}"),
                "energies",
                num(a, &["energies", k]),
                num(b, &["energies", k]),
                Tol::Abs(band),
            )
            .because(WHY_ENERGY),
        );
    }
    for list in ["mould_work", "mould_friction"] {
        let pairs = |v: &Value| -> Vec<(String, f64)> {
            (v.get(list)
                .and_then(Value::as_array)
                .cloned()
                .unwrap_or_default()
                .iter())
            .filter_map(|p| Some((p[0].as_str()?.to_string(), p[1].as_f64()?)))
            .collect()
        };
        let (pa, pb) = (pairs(a), pairs(b));
        let names = union(
            pa.iter().map(|p| p.0.clone()).collect(),
            pb.iter().map(|p| p.0.clone()).collect(),
        );
        for name in names {
            let get = |l: &[(String, f64)]| l.iter().find(|p| p.0 == name).map(|p| p.1);
            rows.push(
                Row::num(
                    format!("{list}[{name}]"),
                    "energies",
                    get(&pa),
                    get(&pb),
                    Tol::Abs(band),
                )
                .because(WHY_ENERGY),
            );
        }
    }
    for k in ["energy", "largest_step"] {
        let (x, y) = (
            num(a, &["damage_clamped", k]),
            num(b, &["damage_clamped", k]),
        );
        if x.is_some() || y.is_some() {
            rows.push(
                Row::num(
                    format!("damage_clamped.{k}"),
                    "energies",
                    x.or(Some(0.0)),
                    y.or(Some(0.0)),
                    Tol::Abs(band),
                )
                .because(WHY_ENERGY),
            );
        }
    }
}

/// Keys compared above, or left out.
const KNOWN: [&str; 23] = [
    "status",
    "error",
    "scene",
    "nodes",
    "elements",
    "interface_nodes",
    "time_step_factor",
    "steps",
    "time_step",
    "h_crit_initial",
    "h_crit_min",
    "steps_taken",
    "simulated_time",
    "time_first_damage",
    "time_full_rupture",
    "peak_reactions",
    "final_counts",
    "energies",
    "max_relative_residual",
    "mould_work",
    "mould_friction",
    "damage_clamped",
    "warnings",
];

/// The warnings, and every key this module does not know: shown, not judged.
fn rest(a: &Value, b: &Value, rows: &mut Vec<Row>) {
    let mut keys: Vec<String> = vec!["warnings".into()];
    for v in [a, b] {
        for k in v
            .as_object()
            .map(|m| m.keys().cloned().collect::<Vec<_>>())
            .unwrap_or_default()
        {
            if !KNOWN.contains(&k.as_str())
                && !TIMING_KEYS.contains(&k.as_str())
                && !keys.contains(&k)
            {
                keys.push(k);
            }
        }
    }
    for k in keys {
        let show = |v: &Value| v.get(&k).map(|x| x.to_string());
        rows.push(
            Row::text(k.clone(), "other", show(a), show(b), Tol::Info)
                .because("not a physical observable"),
        );
    }
}
