//! A comparison as a table for the terminal and as JSON (`decohesion compare --json`).

use super::{Cell, Report, Row, Tol, Verdict};
use serde_json::{json, Value};

/// A cell of at most `n` characters (cut with `…`).
fn cut(s: String, n: usize) -> String {
    if s.chars().count() <= n {
        return s;
    }
    let mut t: String = s.chars().take(n - 1).collect();
    t.push('…');
    t
}

fn difference(r: &Row) -> String {
    match (&r.a, &r.b) {
        (Cell::Text(_), _) | (_, Cell::Text(_)) if r.a != r.b => "differs".into(),
        _ if r.a == r.b && r.difference.is_nan() => "".into(),
        (Cell::Missing, _) | (_, Cell::Missing) if r.a != r.b => "one side only".into(),
        _ if r.difference.is_nan() => "NaN".into(),
        _ => match r.at {
            Some(t) if r.difference > 0.0 => format!("{:.3e} at t = {t:.4e} s", r.difference),
            _ => format!("{:.3e}", r.difference),
        },
    }
}

fn tolerance(r: &Row) -> String {
    let magnitude = |c: &Cell| match c {
        Cell::Num(x) => x.abs(),
        _ => 0.0,
    };
    match r.tol {
        Tol::Rel(_) => format!(
            "{} = {:.3e}",
            r.tol.label(),
            r.tol.allowed(magnitude(&r.a), magnitude(&r.b))
        ),
        t => t.label(),
    }
}

impl Report {
    /// The table: a line per observable (observable, A, B, difference, tolerance, verdict),
    /// then the notes, then what moved with the reason of its tolerance.
    pub fn table(&self) -> String {
        let series = self.kind != super::Kind::Summary;
        let (ha, hb) = if series {
            ("max |A|", "max |B|")
        } else {
            ("A", "B")
        };
        let lines: Vec<[String; 6]> = self
            .rows
            .iter()
            .map(|r| {
                [
                    r.key.clone(),
                    cut(r.a.show(), 24),
                    cut(r.b.show(), 24),
                    difference(r),
                    tolerance(r),
                    r.verdict.label().to_string(),
                ]
            })
            .collect();
        let head = ["observable", ha, hb, "difference", "tolerance", ""].map(String::from);
        let mut width = [0; 6];
        for l in lines.iter().chain([&head]) {
            for (w, c) in width.iter_mut().zip(l) {
                *w = (*w).max(c.chars().count());
            }
        }
        let mut s = format!("A and B: {}\n", self.kind.name());
        for l in [&head].into_iter().chain(&lines) {
            let mut line = String::new();
            for (k, (c, w)) in l.iter().zip(width).enumerate() {
                let pad = w - c.chars().count();
                match k {
                    0 => line.push_str(&format!("  {c}{}", " ".repeat(pad))),
                    _ => line.push_str(&format!("  {}{c}", " ".repeat(pad))),
                }
            }
            s.push_str(line.trim_end());
            s.push('\n');
        }
        for n in &self.notes {
            s.push_str(&format!("note: {n}\n"));
        }
        let moved: Vec<&Row> = self.moved().collect();
        let judged = self
            .rows
            .iter()
            .filter(|r| r.verdict != Verdict::Info)
            .count();
        match moved.len() {
            0 => s.push_str(&format!(
                "{judged} observables compared, all within tolerance\n"
            )),
            k => {
                s.push_str(&format!(
                    "{k} of {judged} observables moved beyond their tolerance:\n"
                ));
                for r in moved {
                    s.push_str(&format!(
                        "  {}: {} → {} (tolerance {}: {})\n",
                        r.key,
                        r.a.show(),
                        r.b.show(),
                        tolerance(r),
                        r.why
                    ));
                }
            }
        }
        s
    }

    /// The comparison as JSON: the kind, whether something moved, the notes, and per row the
    /// key, group, values, difference (null when there is none), the tolerance (kind, value,
    /// allowed difference, reason) and the verdict.
    pub fn json(&self) -> Value {
        let cell = |c: &Cell| match c {
            Cell::Num(x) => json!(x),
            Cell::Text(t) => json!(t),
            Cell::Missing => Value::Null,
        };
        let rows: Vec<Value> = self
            .rows
            .iter()
            .map(|r| {
                let (kind, value) = match r.tol {
                    Tol::Exact => ("exact", Value::Null),
                    Tol::Abs(x) => ("absolute", json!(x)),
                    Tol::Rel(x) => ("relative", json!(x)),
                    Tol::Info => ("not judged", Value::Null),
                };
                let mag = |c: &Cell| if let Cell::Num(x) = c { x.abs() } else { 0.0 };
                let allowed = r.allowed(mag(&r.a), mag(&r.b));
                json!({
                    "key": r.key, "group": r.group, "a": cell(&r.a), "b": cell(&r.b),
                    "difference": if r.difference.is_finite() { json!(r.difference) } else { Value::Null },
                    "at_time": r.at,
                    "tolerance": {"kind": kind, "value": value,
                        "allowed": if allowed.is_finite() { json!(allowed) } else { Value::Null }, "why": r.why},
                    "verdict": match r.verdict { Verdict::Ok => "ok", Verdict::Moved => "moved", Verdict::Info => "info" },
                })
            })
            .collect();
        json!({
            "kind": self.kind.name(),
            "moved": self.moved().map(|r| r.key.clone()).collect::<Vec<_>>(),
            "notes": self.notes,
            "rows": rows,
        })
    }
}
