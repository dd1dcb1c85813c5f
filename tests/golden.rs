//! Regression guard: every scene's physics, bit for bit, against `tests/golden/<scene>.json`.
//!
//! The files are written by `scripts/golden.sh` (this test with `UPDATE_GOLDEN=1`) from the code,
//! never by hand. What is compared: the run summary (steps, h, h_crit, peak reactions, times of
//! first damage and rupture, counts, every energy of the ledger, the residual, the warnings, the
//! status and error of a run that stops) with the timings and the thread count removed, plus a
//! hash of the bits of the final displacements, velocities and damage. A change of physics
//! regenerates the files in the same commit and says why.
//!
//! The comparison is on the JSON text: serde_json prints an f64 with the shortest digits that
//! read back to the same bits, so equal text is equal bits (parsing back could be 1 ulp off).

use decohesion::report::RunSummary;
use decohesion::scene::load_scene;
use decohesion::solver::Simulation;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Summary keys that measure the machine, not the physics.
const TIMING_KEYS: [&str; 8] = [
    "wall_seconds",
    "step_wall_seconds",
    "element_steps_per_second",
    "ns_per_element_step",
    "stage_seconds",
    "threads",
    "recording",
    "paraview",
];

/// FNV-1a over the bits of a sequence of f64.
fn hash_bits(values: impl Iterator<Item = f64>) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for x in values {
        for b in x.to_bits().to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// The golden record of one scene file: its run to the end (or to its failure).
fn record(path: &Path) -> Value {
    let scene = load_scene(path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut out = serde_json::Map::new();
    match Simulation::new(scene.model) {
        Err(e) => {
            out.insert("setup_error".into(), Value::String(e.to_string()));
        }
        Ok(mut sim) => {
            let outcome = sim.run(|_| true);
            let summary = RunSummary::new(&sim, 0.0, outcome.as_ref().err());
            let mut v = serde_json::to_value(&summary).unwrap();
            let map = v.as_object_mut().unwrap();
            for k in TIMING_KEYS {
                map.remove(k);
            }
            out.insert("summary".into(), v);
            out.insert(
                "final_state_hash".into(),
                Value::String(hash_bits(
                    sim.u
                        .rows()
                        .chain(sim.v.rows())
                        .flatten()
                        .chain(sim.interface_nodes.iter().map(|n| n.alpha)),
                )),
            );
        }
    }
    Value::Object(out)
}

fn scene_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["scenes", "scenes/extreme"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = entry.unwrap().path();
            if p.extension().is_some_and(|e| e == "toml") {
                files.push(p);
            }
        }
    }
    files.sort();
    files
}

/// `scenes/extreme/brittle.toml` → `extreme_brittle`.
fn golden_name(path: &Path) -> String {
    let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
    match path.parent().and_then(|p| p.file_name()) {
        Some(d) if d == "extreme" => format!("extreme_{stem}"),
        _ => stem,
    }
}

/// Keys (dotted paths) whose values differ between two JSON documents.
fn differing(a: &Value, b: &Value, at: String, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for k in x.keys().chain(y.keys().filter(|k| !x.contains_key(*k))) {
                let (va, vb) = (
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                );
                differing(va, vb, format!("{at}.{k}"), out);
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (va, vb)) in x.iter().zip(y).enumerate() {
                differing(va, vb, format!("{at}[{i}]"), out);
            }
        }
        _ if a != b => out.push(format!("{at}: golden {a} now {b}")),
        _ => {}
    }
}

#[test]
fn every_scene_matches_its_golden_file_bit_for_bit() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let update = std::env::var_os("UPDATE_GOLDEN").is_some();
    if update {
        std::fs::create_dir_all(&dir).unwrap();
    }
    let files = scene_files();
    assert!(files.len() >= 20, "scenes found: {files:?}");
    let mut failures = Vec::new();
    for path in &files {
        let name = golden_name(path);
        let text = serde_json::to_string_pretty(&record(path)).unwrap() + "\n";
        let file = dir.join(format!("{name}.json"));
        if update {
            std::fs::write(&file, &text).unwrap();
            continue;
        }
        let golden = std::fs::read_to_string(&file).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; generate it with scripts/golden.sh",
                file.display()
            )
        });
        if golden != text {
            let mut keys = Vec::new();
            differing(
                &serde_json::from_str(&golden).unwrap(),
                &serde_json::from_str(&text).unwrap(),
                String::new(),
                &mut keys,
            );
            if keys.is_empty() {
                keys.push("the texts differ in the last digit of a number".into());
            }
            failures.push(format!("{name}:\n  {}", keys.join("\n  ")));
        }
    }
    assert!(
        failures.is_empty(),
        "runs differ from tests/golden (regenerate with scripts/golden.sh only for a physics change, and say why):\n{}",
        failures.join("\n")
    );
}
