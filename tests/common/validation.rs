//! Records for the validation report (`scripts/validation.sh` → `docs/src/validation.md`),
//! shared by both crates' test binaries (`physics/tests/main.rs` includes this file by path).
//!
//! A test that compares a result with an independent reference (analytic, published, another
//! implementation) calls [`record`] right where it asserts, with the same value and the same
//! tolerance, and [`curve`] where a curve is compared. With `DECOHESION_VALIDATION_DIR` set,
//! [`record`] appends one JSON line to `$DECOHESION_VALIDATION_DIR/cases.jsonl` (one `write` on a
//! file opened with `O_APPEND`, so the parallel tests of a binary never interleave) and
//! [`curve`] writes `$DECOHESION_VALIDATION_DIR/curves/<case>--<name>.json`; unset, both do
//! nothing. The JSON is written by hand (the physics crate's tests have no `serde_json`): f64
//! as `{:?}` (shortest round-trip), non-finite values as `NaN`/`Infinity`, which Python's `json`
//! reads.
#![allow(dead_code)]

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

/// The environment variable naming the output directory.
pub const DIR_VARIABLE: &str = "DECOHESION_VALIDATION_DIR";

/// A curve keeps at most this many points (evenly strided, the last one kept).
const MAX_POINTS: usize = 4000;

/// The tolerance a test asserts.
#[derive(Clone, Copy, Debug)]
pub enum Tol {
    /// |ours − reference| ≤ tol·|reference|.
    Rel(f64),
    /// |ours − reference| ≤ tol.
    Abs(f64),
    /// lo ≤ ours ≤ hi (an admissible band; either end may be infinite).
    Between(f64, f64),
}

impl Tol {
    fn kind(self) -> &'static str {
        match self {
            Tol::Rel(_) => "relative",
            Tol::Abs(_) => "absolute",
            Tol::Between(..) => "interval",
        }
    }

    fn value(self) -> String {
        match self {
            Tol::Rel(t) | Tol::Abs(t) => number(t),
            Tol::Between(lo, hi) => format!("[{}, {}]", number(lo), number(hi)),
        }
    }

    /// Whether `ours` passes against `reference`.
    pub fn passes(self, reference: f64, ours: f64) -> bool {
        if !ours.is_finite() {
            return false;
        }
        match self {
            Tol::Rel(t) => (ours - reference).abs() <= t * reference.abs(),
            Tol::Abs(t) => (ours - reference).abs() <= t,
            Tol::Between(lo, hi) => lo <= ours && ours <= hi,
        }
    }

    /// The error shown in the report: relative for `Rel` (and for `Between` when the reference
    /// is not 0), absolute otherwise.
    fn error(self, reference: f64, ours: f64) -> f64 {
        match self {
            Tol::Abs(_) => ours - reference,
            _ if reference != 0.0 => ours / reference - 1.0,
            _ => ours - reference,
        }
    }
}

fn dir() -> Option<PathBuf> {
    std::env::var_os(DIR_VARIABLE)
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
}

/// A JSON number: the shortest round-trip form; NaN and ±∞ as Python's `json` writes them.
fn number(x: f64) -> String {
    if x.is_nan() {
        "NaN".into()
    } else if x.is_infinite() {
        if x > 0.0 { "Infinity" } else { "-Infinity" }.into()
    } else {
        format!("{x:?}")
    }
}

/// A JSON string.
fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn numbers(xs: impl Iterator<Item = f64>) -> String {
    let items: Vec<String> = xs.map(number).collect();
    format!("[{}]", items.join(","))
}

/// Records one compared quantity of `case`: `ours` against `reference` (from `source`, e.g.
/// "Kendall 1975", "analytic"), within `tol`, the tolerance the test asserts. Returns whether
/// it passes; the test's own assertion stays. The calling file and line and the running test's
/// name are recorded with it.
#[track_caller]
pub fn record(
    case: &str,
    quantity: &str,
    reference: f64,
    source: &str,
    ours: f64,
    tol: Tol,
) -> bool {
    let pass = tol.passes(reference, ours);
    let Some(dir) = dir() else {
        return pass;
    };
    let at = std::panic::Location::caller();
    let thread = std::thread::current();
    let line = format!(
        "{{\"case\": {}, \"quantity\": {}, \"reference\": {}, \"source\": {}, \"ours\": {}, \
         \"tolerance_kind\": {}, \"tolerance\": {}, \"error\": {}, \"pass\": {pass}, \
         \"test\": {}, \"at\": {}}}\n",
        string(case),
        string(quantity),
        number(reference),
        string(source),
        number(ours),
        string(tol.kind()),
        tol.value(),
        number(tol.error(reference, ours)),
        string(thread.name().unwrap_or("")),
        string(&format!("{}:{}", at.file(), at.line())),
    );
    std::fs::create_dir_all(&dir).expect("the validation directory");
    let mut file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(dir.join("cases.jsonl"))
        .expect("cases.jsonl");
    // One write of the whole line (O_APPEND: atomic with respect to the other tests' lines).
    file.write_all(line.as_bytes()).expect("cases.jsonl");
    pass
}

/// Records a curve of `case`: ours and the reference (NaN where it has none) at the abscissae
/// `xs`, with the axes' labels. At most [`MAX_POINTS`] points are kept (evenly strided).
pub fn curve(
    case: &str,
    name: &str,
    xs: &[f64],
    ours: &[f64],
    reference: &[f64],
    x_label: &str,
    y_label: &str,
) {
    let Some(dir) = dir() else {
        return;
    };
    assert!(
        xs.len() == ours.len() && xs.len() == reference.len(),
        "curve {case}/{name}: {} x, {} ours, {} reference",
        xs.len(),
        ours.len(),
        reference.len()
    );
    let stride = xs.len().div_ceil(MAX_POINTS).max(1);
    let keep: Vec<usize> = (0..xs.len())
        .filter(|&i| i % stride == 0 || i + 1 == xs.len())
        .collect();
    let pick = |v: &[f64]| numbers(keep.iter().map(|&i| v[i]));
    let text = format!(
        "{{\"case\": {}, \"name\": {}, \"x_label\": {}, \"y_label\": {}, \"x\": {}, \
         \"ours\": {}, \"reference\": {}}}\n",
        string(case),
        string(name),
        string(x_label),
        string(y_label),
        pick(xs),
        pick(ours),
        pick(reference),
    );
    let slug = |s: &str| -> String {
        s.chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect()
    };
    let curves = dir.join("curves");
    std::fs::create_dir_all(&curves).expect("the validation curves directory");
    std::fs::write(
        curves.join(format!("{}--{}.json", slug(case), slug(name))),
        text,
    )
    .expect("curve file");
}
