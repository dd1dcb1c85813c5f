//! A measured curve: a CSV file of two columns, x and y, read with its units and checked
//! (finite numbers, enough points, x strictly increasing) before any run.
//!
//! ```text
//! # comments start with '#'
//! u [mm], F [kN]
//! 0.0, 0.0
//! 0.5, 1.92
//! ```
//!
//! The header names the columns and may give each a unit in brackets; a unit may instead be
//! given by the caller (`--x-unit`, `--y-unit`). Values are converted to the SI unit of the
//! series column they are compared with ([`Unit`]).

use anyhow::{bail, Result};
use std::path::Path;

/// A unit the measured data may be in, and its factor to the SI unit of its dimension.
#[derive(Debug, Clone, PartialEq)]
pub struct Unit {
    /// As written, e.g. `mm`.
    pub name: String,
    /// Value in SI = value × factor.
    pub factor: f64,
}

/// The units of each SI unit of the series' columns (`m`, `N`, `J`, `s`, `N m`, `-`): name and
/// factor to SI.
const UNITS: [(&str, &[(&str, f64)]); 6] = [
    (
        "m",
        &[
            ("m", 1.0),
            ("cm", 1e-2),
            ("mm", 1e-3),
            ("um", 1e-6),
            ("µm", 1e-6),
        ],
    ),
    ("N", &[("N", 1.0), ("kN", 1e3), ("mN", 1e-3), ("MN", 1e6)]),
    ("J", &[("J", 1.0), ("kJ", 1e3), ("mJ", 1e-3)]),
    ("s", &[("s", 1.0), ("ms", 1e-3), ("us", 1e-6), ("µs", 1e-6)]),
    ("N m", &[("N m", 1.0), ("N mm", 1e-3), ("kN m", 1e3)]),
    ("-", &[("-", 1.0), ("%", 1e-2)]),
];

impl Unit {
    /// The unit `name` for a quantity whose SI unit is `si` (a series column's unit); the
    /// error lists the admissible names.
    pub fn parse(name: &str, si: &str) -> Result<Unit, String> {
        let Some((_, table)) = UNITS.iter().find(|(s, _)| *s == si) else {
            return Err(format!("the column's unit [{si}] has no table of units"));
        };
        let name = name.trim();
        match table.iter().find(|(n, _)| *n == name) {
            Some(&(n, factor)) => Ok(Unit {
                name: n.to_string(),
                factor,
            }),
            None => Err(format!(
                "`{name}` is not a unit of [{si}]; admissible: {}",
                table.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
            )),
        }
    }

    /// The SI unit itself.
    pub fn si(si: &str) -> Unit {
        Unit {
            name: si.to_string(),
            factor: 1.0,
        }
    }
}

/// One column's header: its name and the unit written in brackets, if any.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    pub name: String,
    pub unit: Option<String>,
}

impl Header {
    fn parse(field: &str) -> Header {
        let field = field.trim();
        match field.split_once('[') {
            Some((name, rest)) if rest.ends_with(']') => Header {
                name: name.trim().to_string(),
                unit: Some(rest[..rest.len() - 1].trim().to_string()),
            },
            _ => Header {
                name: field.to_string(),
                unit: None,
            },
        }
    }
}

/// A measured curve as read: headers and values in the file's units, with each point's line.
#[derive(Debug, Clone)]
pub struct Curve {
    /// The file name used in messages.
    pub file: String,
    pub x_header: Header,
    pub y_header: Header,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// The line (1-based) of each point.
    pub lines: Vec<usize>,
}

/// Splits a data line at commas, semicolons or tabs (or runs of spaces when it has none).
fn fields(line: &str) -> Vec<&str> {
    if line.contains([',', ';', '\t']) {
        line.split([',', ';', '\t']).map(str::trim).collect()
    } else {
        line.split_whitespace().collect()
    }
}

impl Curve {
    /// Reads the CSV file at `path` ([`Curve::parse`]).
    pub fn read(path: &Path) -> Result<Curve> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| anyhow::anyhow!("{file}: cannot read the measured curve: {e}"))?;
        Curve::parse(&text, &file)
    }

    /// Parses the text of a measured curve: comment lines (`#`) and blank lines are skipped;
    /// the first other line is the header of two columns, every later one two numbers. Refused
    /// with the file and line: a header missing or of another number of columns, a value that
    /// is not a finite number, x not strictly increasing (the curve is compared point by point
    /// at its x), fewer than `min_points` points.
    pub fn parse(text: &str, file: &str) -> Result<Curve> {
        let mut header: Option<(Header, Header)> = None;
        let (mut x, mut y, mut lines) = (Vec::new(), Vec::new(), Vec::new());
        for (i, raw) in text.lines().enumerate() {
            let n = i + 1;
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let f = fields(line);
            if f.len() != 2 {
                bail!(
                    "{file}, line {n}: `{line}` has {} column{}; expected 2 (x and y), \
                     separated by a comma",
                    f.len(),
                    if f.len() == 1 { "" } else { "s" }
                );
            }
            let Some(_) = &header else {
                if f.iter().all(|s| s.parse::<f64>().is_ok()) {
                    bail!(
                        "{file}, line {n}: `{line}` is data, but the first line must be a header \
                         naming the two columns with their units, e.g. `u [mm], F [N]`"
                    );
                }
                header = Some((Header::parse(f[0]), Header::parse(f[1])));
                continue;
            };
            let mut v = [0.0; 2];
            for (k, s) in f.iter().enumerate() {
                v[k] = match s.parse::<f64>() {
                    Ok(v) if v.is_finite() => v,
                    Ok(_) => {
                        bail!("{file}, line {n}: `{s}` is not a finite number; every value must be")
                    }
                    Err(_) => bail!("{file}, line {n}: `{s}` is not a number"),
                };
            }
            if let Some(&last) = x.last() {
                if !(v[0] > last) {
                    bail!(
                        "{file}, line {n}: x = {} after x = {last} (line {}): x must increase \
                         strictly (the run's curve is read at each measured x)",
                        v[0],
                        lines.last().copied().unwrap_or(0)
                    );
                }
            }
            x.push(v[0]);
            y.push(v[1]);
            lines.push(n);
        }
        let Some((x_header, y_header)) = header else {
            bail!("{file}: no header and no data (only comments or blank lines)");
        };
        Ok(Curve {
            file: file.to_string(),
            x_header,
            y_header,
            x,
            y,
            lines,
        })
    }

    /// Refuses a curve of fewer than `min` points, saying why `min` points are needed.
    pub fn require_points(&self, min: usize, why: &str) -> Result<()> {
        if self.x.len() < min {
            bail!(
                "{}: {} data point{}; at least {min} are needed ({why})",
                self.file,
                self.x.len(),
                if self.x.len() == 1 { "" } else { "s" }
            );
        }
        Ok(())
    }

    /// The unit of one column: the header's, else `flag`, else the SI unit `si` (and whether it
    /// was assumed). Both given and different: refused.
    pub fn unit(
        &self,
        header: &Header,
        flag: Option<&str>,
        flag_name: &str,
        si: &str,
    ) -> Result<(Unit, bool)> {
        let named = match (&header.unit, flag) {
            (Some(h), Some(f)) if h.trim() != f.trim() => bail!(
                "{}: the header gives `{}` the unit [{h}] and {flag_name} says `{f}`; give one",
                self.file,
                header.name
            ),
            (Some(h), _) => Some(h.as_str()),
            (None, Some(f)) => Some(f),
            (None, None) => None,
        };
        match named {
            Some(u) => Unit::parse(u, si)
                .map(|u| (u, false))
                .map_err(|e| anyhow::anyhow!("{}: column `{}`: {e}", self.file, header.name)),
            None => Ok((Unit::si(si), true)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_header_units_and_points() {
        let c = Curve::parse("# a\nu [mm], F [kN]\n0, 0\n1.5; 2\n3\t4\n", "c.csv").unwrap();
        assert_eq!(c.x_header.name, "u");
        assert_eq!(c.x_header.unit.as_deref(), Some("mm"));
        assert_eq!(c.y_header.unit.as_deref(), Some("kN"));
        assert_eq!(c.x, [0.0, 1.5, 3.0]);
        assert_eq!(c.y, [0.0, 2.0, 4.0]);
        assert_eq!(c.lines, [3, 4, 5]);
        let (u, assumed) = c.unit(&c.x_header, None, "--x-unit", "m").unwrap();
        assert_eq!((u.factor, assumed), (1e-3, false));
    }

    #[test]
    fn refuses_with_file_and_line() {
        let cases = [
            ("0,0\n1,1\n", "line 1: `0,0` is data"),
            ("u,F\n0,0\n0,1\n", "line 3: x = 0 after x = 0 (line 2)"),
            ("u,F\n0,NaN\n", "line 2: `NaN` is not a finite number"),
            ("u,F\n0,abc\n", "line 2: `abc` is not a number"),
            ("u,F,G\n", "line 1: `u,F,G` has 3 columns"),
            ("# only\n", "no header and no data"),
        ];
        for (text, want) in cases {
            let e = Curve::parse(text, "m.csv").unwrap_err().to_string();
            assert!(e.starts_with("m.csv"), "{e}");
            assert!(e.contains(want), "{text:?}: {e}");
        }
        let c = Curve::parse("u [kN],F\n0,0\n", "m.csv").unwrap();
        let e = c.unit(&c.x_header, None, "--x-unit", "m").unwrap_err();
        assert!(e.to_string().contains("admissible: m, cm, mm"), "{e}");
        let e = c
            .unit(&c.x_header, Some("mm"), "--x-unit", "m")
            .unwrap_err();
        assert!(e.to_string().contains("--x-unit says `mm`"), "{e}");
        let e = c.require_points(5, "two free keys").unwrap_err();
        assert!(e.to_string().contains("1 data point; at least 5"), "{e}");
    }
}
