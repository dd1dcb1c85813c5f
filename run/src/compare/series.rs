//! Two time series compared column by column: a `run --series` CSV file or a capture's scalars
//! ([`super::rrd`]).
//!
//! Each value of A at a time t is compared with B around the same time: its distance from the
//! range B takes on [t − τ, t + τ] (linearly interpolated at the ends), τ = two rows (the
//! larger time between consecutive rows of either series: two steps for a series of every
//! step). Two runs of the same physics place an event (a rupture, a contact) up to two steps
//! apart; compared at equal times only, a step of the force would count as a difference of
//! its whole height. The largest distance over A's times is the column's difference, against
//! the column's tolerance (defaults and reasons in [`super`]).

use super::{Kind, Report, Row, Tol};

/// What a column holds, which sets its default tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// An energy of the ledger [J].
    Energy,
    /// The relative residual [-].
    Residual,
    /// A force [N]: a reaction, a mould's force.
    Force,
    /// A moment [N m].
    Moment,
    /// A length: an imposed displacement, a damage variable [m].
    Length,
    /// A count of nodes [-].
    Count,
    /// The time step [s].
    Step,
    /// Shown, not judged.
    Other,
}

/// One column: its name (without the unit), what it holds, and its samples in time order.
#[derive(Debug, Clone)]
pub struct Column {
    pub name: String,
    pub quantity: Quantity,
    pub t: Vec<f64>,
    pub v: Vec<f64>,
}

/// A time series: its columns (each with its own times; a CSV file's share them).
#[derive(Debug, Clone, Default)]
pub struct Series {
    pub columns: Vec<Column>,
    /// The run's outcome (completed, failed, cancelled), when the file says it (a capture).
    pub status: Option<String>,
}

/// The quantity of a CSV column from its name and unit.
fn quantity(name: &str, unit: &str) -> Quantity {
    match (name, unit) {
        ("relative_residual", _) => Quantity::Residual,
        ("h", _) => Quantity::Step,
        (n, "-") if n.starts_with("n_") => Quantity::Count,
        (_, "J") => Quantity::Energy,
        (_, "N") => Quantity::Force,
        (_, "N m") => Quantity::Moment,
        (_, "m") => Quantity::Length,
        _ => Quantity::Other,
    }
}

impl Series {
    /// Reads a `run --series` CSV text: a header `t [s],step [-],…` and rows of numbers.
    pub fn parse(text: &str) -> Result<Series, String> {
        let mut lines = text.lines();
        let header = header_names(lines.next().unwrap_or(""));
        if header.first().map(String::as_str) != Some("t [s]") {
            return Err("not a time series: the first line must be the header of run --series, starting `t [s],`".into());
        }
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for (i, line) in lines.enumerate().filter(|(_, l)| !l.is_empty()) {
            let row: Result<Vec<f64>, _> = line.split(',').map(str::parse::<f64>).collect();
            match row {
                Ok(r) if r.len() == header.len() => rows.push(r),
                _ => {
                    return Err(format!(
                        "line {}: {} numbers expected, one per column of the header",
                        i + 2,
                        header.len()
                    ))
                }
            }
        }
        let t: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        let columns = header
            .iter()
            .enumerate()
            .skip(1)
            .filter(|(_, h)| !h.starts_with("step "))
            .map(|(k, h)| {
                let (name, unit) = h
                    .strip_suffix(']')
                    .and_then(|n| n.rsplit_once(" ["))
                    .unwrap_or((h.as_str(), ""));
                Column {
                    name: name.to_string(),
                    quantity: quantity(name, unit),
                    t: t.clone(),
                    v: rows.iter().map(|r| r[k]).collect(),
                }
            })
            .collect();
        Ok(Series {
            columns,
            status: None,
        })
    }

    fn column(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.name == name)
    }

    /// The largest time between consecutive samples of any column [s].
    fn largest_gap(&self) -> f64 {
        let gaps = self
            .columns
            .iter()
            .flat_map(|c| c.t.windows(2).map(|w| w[1] - w[0]));
        gaps.fold(0.0, f64::max)
    }

    /// The ledger's band: the largest |relative residual| × the largest energy, plus
    /// round-off (samples × ε × the largest energy) [J].
    fn energy_band(&self) -> f64 {
        let e_max = largest(self, Quantity::Energy);
        let samples = self.columns.first().map_or(0, |c| c.t.len()) as f64;
        largest(self, Quantity::Residual) * e_max + samples * f64::EPSILON * e_max
    }
}

/// The names of a CSV header line: split at commas, a quoted name (RFC 4180, as the series
/// writes a name holding a comma or a quote) kept whole with its doubled quotes undone.
fn header_names(line: &str) -> Vec<String> {
    let (mut names, mut name, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                name.push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => names.push(std::mem::take(&mut name)),
            (c, _) => name.push(c),
        }
    }
    names.push(name);
    names
}

/// B's value at time `t`, linearly interpolated (`t` within B's times).
fn interpolate(t: &[f64], v: &[f64], x: f64) -> f64 {
    let k = t.partition_point(|&s| s <= x);
    if k == 0 {
        return v[0];
    }
    if k >= t.len() {
        return v[t.len() - 1];
    }
    let (t0, t1) = (t[k - 1], t[k]);
    let w = if t1 > t0 { (x - t0) / (t1 - t0) } else { 1.0 };
    v[k - 1] + w * (v[k] - v[k - 1])
}

/// The largest distance of A's values from B's range over each A time ± `tau`, and where
/// (A's times outside B's time range are skipped).
fn tube_distance(a: &Column, b: &Column, tau: f64) -> (f64, Option<f64>) {
    let (Some(&b0), Some(&b1)) = (b.t.first(), b.t.last()) else {
        return (f64::NAN, None);
    };
    let mut worst = (0.0, None);
    for (&t, &x) in a.t.iter().zip(&a.v) {
        if t < b0 - tau || t > b1 + tau {
            continue;
        }
        let (lo, hi) = ((t - tau).max(b0), (t + tau).min(b1));
        let (i, j) = (
            b.t.partition_point(|&s| s < lo),
            b.t.partition_point(|&s| s <= hi),
        );
        let ends = [interpolate(&b.t, &b.v, lo), interpolate(&b.t, &b.v, hi)];
        let inside = b.v[i..j].iter().chain(&ends);
        let (min, max) = inside.fold((f64::INFINITY, f64::NEG_INFINITY), |(m, n), &y| {
            (m.min(y), n.max(y))
        });
        let d = if x.is_nan() || min.is_nan() {
            f64::INFINITY
        } else {
            (min - x).max(x - max).max(0.0)
        };
        if d > worst.0 {
            worst = (d, Some(t));
        }
    }
    worst
}

/// The largest |value| of the columns holding `q`.
fn largest(s: &Series, q: Quantity) -> f64 {
    let vals = s
        .columns
        .iter()
        .filter(|c| c.quantity == q)
        .flat_map(|c| c.v.iter());
    vals.fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// The default tolerance of a column, and why.
fn default_tol(q: Quantity, band: f64, residual: f64) -> (Tol, &'static str, &'static str) {
    match q {
        Quantity::Energy => (
            Tol::Abs(band),
            "energies",
            "max relative residual × largest energy (the ledger's error) + round-off",
        ),
        Quantity::Residual => (
            Tol::Abs(residual),
            "residual",
            "within the larger max relative residual",
        ),
        Quantity::Force => (
            Tol::Rel(0.01),
            "reactions",
            "1 % of the largest force, over ± two rows",
        ),
        Quantity::Moment => (
            Tol::Rel(0.01),
            "reactions",
            "1 % of the largest moment, over ± two rows",
        ),
        Quantity::Length => (
            Tol::Rel(0.01),
            "displacements",
            "1 % of the largest value, over ± two rows",
        ),
        Quantity::Count => (Tol::Abs(1.0), "counts", "one node, over ± two rows"),
        Quantity::Step => (
            Tol::Rel(0.02),
            "h",
            "2 %: the margin of a cheap h_crit update",
        ),
        Quantity::Other => (Tol::Info, "other", "not a physical observable"),
    }
}

/// Compares two series: a row per column of A found in B (the others are noted), plus the
/// time each ends at.
pub fn compare(a: &Series, b: &Series, kind: Kind) -> Report {
    let tau = 2.0 * a.largest_gap().max(b.largest_gap());
    let band = a.energy_band().max(b.energy_band());
    let residual = largest(a, Quantity::Residual).max(largest(b, Quantity::Residual));
    let end = |s: &Series| {
        s.columns
            .iter()
            .filter_map(|c| c.t.last().copied())
            .fold(f64::NAN, f64::max)
    };
    let mut rows = vec![Row::num(
        "end_time".into(),
        "times",
        Some(end(a)),
        Some(end(b)),
        Tol::Abs(tau),
    )
    .because("two rows: the last step lands within a step of the end")];
    if a.status.is_some() || b.status.is_some() {
        rows.insert(
            0,
            Row::text(
                "status".into(),
                "status",
                a.status.clone(),
                b.status.clone(),
                Tol::Exact,
            )
            .because("equal"),
        );
    }
    let mut notes = vec![format!(
        "each value of A is compared with B over A's time ± {tau:.4e} s (two rows)"
    )];
    let mut only = Vec::new();
    for ca in &a.columns {
        let Some(cb) = b.column(&ca.name) else {
            only.push(format!("{} (A)", ca.name));
            continue;
        };
        let scale = |c: &Column| c.v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let (tol, group, why) = default_tol(ca.quantity, band, residual);
        let (d, at) = tube_distance(ca, cb, tau);
        let mut row = Row::num(
            ca.name.clone(),
            group,
            Some(scale(ca)),
            Some(scale(cb)),
            tol,
        )
        .because(why);
        row.difference = d;
        row.at = at;
        // A force or moment is judged against the largest of its kind: a component that is
        // round-off (a mould's tangential force in a pull-off) is not its own scale.
        if matches!(ca.quantity, Quantity::Force | Quantity::Moment) {
            row.scale = Some(largest(a, ca.quantity).max(largest(b, ca.quantity)));
        }
        row.judge();
        rows.push(row);
    }
    only.extend(
        b.columns
            .iter()
            .filter(|c| a.column(&c.name).is_none())
            .map(|c| format!("{} (B)", c.name)),
    );
    if !only.is_empty() {
        notes.push(format!(
            "in one file only, not compared: {}",
            only.join(", ")
        ));
    }
    Report { kind, rows, notes }
}
