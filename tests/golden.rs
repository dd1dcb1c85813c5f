//! Regression guard: every scene's physics, bit for bit, against `tests/golden/<scene>.json`,
//! and on regeneration, within physical tolerances.
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
//!
//! **Regeneration guards the physics.** With `UPDATE_GOLDEN=1`, each new summary is compared
//! with the committed one by `decohesion::compare` (what `decohesion compare A B` does), each
//! observable within its physical tolerance (energies within the ledger's residual band, event
//! times within two steps, …; the reasons are in `run/src/compare/mod.rs`). A file whose bits
//! changed but whose physics is within tolerance (reordered arithmetic) is rewritten; a file
//! whose physics moved is **not** rewritten and the test fails listing what moved, unless
//! `GOLDEN_PHYSICS_CHANGE="why"` acknowledges it (then it is rewritten and the table printed).
//! So `UPDATE_GOLDEN` alone cannot hide a drift of the physics.
//!
//! **Hosts the bits hold on.** The element and node kernels are built three ways and one is
//! picked at run time (`physics/src/kernels/simd.rs`): AVX-512 or AVX2, both with fused
//! multiply–adds, or portable (no FMA), unless `DECOHESION_ISA` forces one. The AVX2 and
//! AVX-512 builds do the same arithmetic and give the same bits (`physics/src/kernels/tests.rs`
//! asserts it kernel by kernel on a CPU that runs both); the portable build rounds a·b + c
//! twice and differs by round-off (that test bounds it at 1e-12 relative). The golden files
//! are generated on x86-64 and pass there with either fused build (`DECOHESION_ISA=avx2` and
//! `avx512` on a CPU that has AVX-512F): the hashes and the summaries' bits hold on x86-64
//! hosts with AVX2 + FMA or AVX-512F + FMA (Haswell / Zen and later), with the same libm (the
//! transcendental functions come from the platform's C library). They do not hold on a CPU
//! without AVX2 or FMA, nor on another architecture (aarch64: portable), nor with
//! `DECOHESION_ISA=portable`: there the summaries differ in their last bits, and every
//! observable stays within the tolerances above (docs/src/architecture.md, the bit-for-bit
//! guard) — the physics comparison is the check that holds on every host.

use decohesion::report::RunSummary;
use decohesion::scene::load_scene;
use decohesion::solver::Simulation;
use serde_json::Value;
use std::path::{Path, PathBuf};

// The summary keys that measure the machine or the outputs, not the physics: the ones
// `compare` leaves out too.
use decohesion::compare::summary::TIMING_KEYS;

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
    match Simulation::new(scene.model) {
        Err(e) => serde_json::json!({ "setup_error": e.to_string() }),
        Ok(mut sim) => {
            let outcome = sim.run(|_| true);
            record_of(&sim, &outcome)
        }
    }
}

/// The golden record of a run that ended with `sim` and `outcome`: the summary without what
/// measures the machine, and the hash of the bits of U, V and α.
pub fn record_of(sim: &Simulation, outcome: &Result<(), decohesion::solver::SolverError>) -> Value {
    let summary = RunSummary::new(sim, 0.0, outcome.as_ref().err());
    let mut v = serde_json::to_value(&summary).unwrap();
    let map = v.as_object_mut().unwrap();
    for k in TIMING_KEYS {
        map.remove(k);
    }
    let hash = hash_bits(
        sim.state
            .u
            .rows()
            .chain(sim.state.v.rows())
            .flatten()
            .chain(sim.state.interface_nodes.iter().map(|n| n.alpha)),
    );
    let mut out = serde_json::Map::new();
    out.insert("summary".into(), v);
    out.insert("final_state_hash".into(), Value::String(hash));
    Value::Object(out)
}

/// The scene files of `scenes/` and `scenes/extreme/`, sorted.
pub fn scene_files() -> Vec<PathBuf> {
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
pub fn golden_name(path: &Path) -> String {
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

/// The environment variable that acknowledges a change of physics on regeneration: its value
/// says why (`scripts/golden.sh` passes it through).
const ACKNOWLEDGE: &str = "GOLDEN_PHYSICS_CHANGE";

/// Regenerates one golden file: written when it is new, when its physics is within tolerance
/// of the committed one (only bits changed), or when `why` acknowledges a change; otherwise
/// left as it is and the observables that moved returned.
fn regenerate(name: &str, file: &Path, text: &str, why: Option<&str>) -> Result<(), String> {
    use decohesion::compare::summary;
    let Ok(golden) = std::fs::read_to_string(file) else {
        std::fs::write(file, text).unwrap();
        return Ok(());
    };
    if golden == text {
        return Ok(());
    }
    let (old, new) = (summary::parse(&golden), summary::parse(text));
    let report = summary::compare(&old.unwrap(), &new.unwrap());
    let moved: Vec<String> = report
        .moved()
        .map(|r| format!("{}: {} → {} ({})", r.key, r.a_text(), r.b_text(), r.why))
        .collect();
    if moved.is_empty() {
        println!("{name}: bits changed, physics within tolerance");
    } else if let Some(why) = why {
        println!(
            "{name}: physics changed ({ACKNOWLEDGE}: {why}):\n{}",
            report.table()
        );
    } else {
        return Err(format!("{name}:\n  {}", moved.join("\n  ")));
    }
    std::fs::write(file, text).unwrap();
    Ok(())
}

#[test]
fn every_scene_matches_its_golden_file_bit_for_bit() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let update = std::env::var_os("UPDATE_GOLDEN").is_some();
    let why = std::env::var(ACKNOWLEDGE)
        .ok()
        .filter(|w| !w.trim().is_empty());
    if update {
        std::fs::create_dir_all(&dir).unwrap();
    }
    let files = scene_files();
    assert!(files.len() >= 20, "scenes found: {files:?}");
    let mut failures = Vec::new();
    let mut drifted = Vec::new();
    for path in &files {
        let name = golden_name(path);
        let text = serde_json::to_string_pretty(&record(path)).unwrap() + "\n";
        let file = dir.join(format!("{name}.json"));
        if update {
            if let Err(moved) = regenerate(&name, &file, &text, why.as_deref()) {
                drifted.push(moved);
            }
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
        drifted.is_empty(),
        "the physics moved beyond its tolerance (these files were not rewritten; if the change \
         is meant, say why: {ACKNOWLEDGE}=\"why\" scripts/golden.sh; compare one file with \
         decohesion compare):\n{}",
        drifted.join("\n")
    );
    assert!(
        failures.is_empty(),
        "runs differ from tests/golden (regenerate with scripts/golden.sh only for a physics change, and say why):\n{}",
        failures.join("\n")
    );
}

/// The guard of [`regenerate`] on a committed file and a new text, without a run: a change of
/// the last bits is rewritten; a damage dissipation moved by 10 % (far beyond the ledger's
/// band) is refused, named, and the file left as it was; acknowledged, it is rewritten.
#[test]
fn regeneration_refuses_a_drift_of_physics_unless_acknowledged() {
    let dir = crate::common::cli::scratch("golden", "guard");
    let new = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/pull_off.json"),
    )
    .unwrap();
    let edited = |f: &dyn Fn(&mut Value)| {
        let mut v: Value = serde_json::from_str(&new).unwrap();
        f(&mut v["summary"]);
        serde_json::to_string_pretty(&v).unwrap() + "\n"
    };
    let scale = |key: &'static str, by: f64| {
        move |s: &mut Value| {
            let x = s["energies"][key].as_f64().unwrap();
            s["energies"][key] = (x * by).into();
        }
    };
    let file = dir.join("pull_off.json");

    let bits = edited(&scale("damage_dissipated", 1.0 + 1e-12));
    std::fs::write(&file, &bits).unwrap();
    regenerate("pull_off", &file, &new, None).expect("only bits changed");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), new);

    let drift = edited(&scale("damage_dissipated", 1.1));
    std::fs::write(&file, &drift).unwrap();
    let moved = regenerate("pull_off", &file, &new, None).unwrap_err();
    assert!(moved.contains("energies.damage_dissipated"), "{moved}");
    assert!(!moved.contains("energies.kinetic"), "{moved}");
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        drift,
        "not rewritten"
    );

    regenerate("pull_off", &file, &new, Some("a test")).expect("acknowledged");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), new);
}
