//! The free keys of a fit, `--free key=lo..hi`: a scene key (the `--set` syntax), its bounds,
//! and the coordinate the optimiser moves in.
//!
//! The optimiser works in z ∈ [0, 1] per key: p = lo + z (hi − lo), or, for bounds of one sign
//! spanning a decade or more, p = lo (hi/lo)^z, so that a key known to an order of magnitude
//! (a stiffness, a rate) is searched evenly in its logarithm.

use anyhow::{bail, Result};

/// One free key.
#[derive(Debug, Clone, PartialEq)]
pub struct Free {
    /// The key path, as for `--set` (`interface.law.u_r`).
    pub key: String,
    pub lo: f64,
    pub hi: f64,
    /// Searched in log(p) (bounds of one sign, hi/lo ≥ 10).
    pub log: bool,
}

impl Free {
    /// Parses `key=lo..hi`; the error names the flag's text and what is expected.
    pub fn parse(spec: &str) -> Result<Free> {
        let expected = "expected `key=lo..hi`, e.g. --free interface.law.u_r=1e-3..1e-2";
        let Some((key, range)) = spec.split_once('=') else {
            bail!("--free {spec}: no `=`; {expected}");
        };
        let key = key.trim();
        if key.is_empty() || key.split('.').any(|s| s.trim().is_empty()) {
            bail!("--free {spec}: the key is empty or has an empty segment; {expected}");
        }
        let Some((lo, hi)) = range.split_once("..") else {
            bail!("--free {spec}: no `..` between the bounds; {expected}");
        };
        let bound = |s: &str, which: &str| -> Result<f64> {
            match s.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => bail!(
                    "--free {spec}: the {which} bound `{}` is not a finite number; {expected}",
                    s.trim()
                ),
            }
        };
        let (lo, hi) = (bound(lo, "lower")?, bound(hi, "upper")?);
        if !(lo < hi) {
            bail!("--free {spec}: the bounds are reversed or equal ({lo} ≥ {hi}); give lo < hi");
        }
        let log = (lo > 0.0 && hi / lo >= 10.0) || (hi < 0.0 && lo / hi >= 10.0);
        Ok(Free {
            key: key.to_string(),
            lo,
            hi,
            log,
        })
    }

    /// The value at the coordinate z (z = 0 → lo, z = 1 → hi).
    pub fn value(&self, z: f64) -> f64 {
        if self.log {
            self.lo * (self.hi / self.lo).powf(z)
        } else {
            self.lo + z * (self.hi - self.lo)
        }
    }

    /// The coordinate of the value p.
    pub fn coordinate(&self, p: f64) -> f64 {
        if self.log {
            (p / self.lo).ln() / (self.hi / self.lo).ln()
        } else {
            (p - self.lo) / (self.hi - self.lo)
        }
    }

    /// The middle of the bounds (in the searched coordinate), the start when the scene has no
    /// value for the key.
    pub fn middle(&self) -> f64 {
        self.value(0.5)
    }
}

/// The value of `key` (the `--set` path) in a resolved scene document: `None` when absent
/// (the key takes its default). A one-element array of tables may be passed over, as `--set`
/// allows (`interface.law.u_r` for the one `[[interface]]`).
pub fn lookup<'a>(doc: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
    let segs: Vec<&str> = key.split('.').map(str::trim).collect();
    let mut value: Option<&toml::Value> = None;
    let mut table = doc;
    let mut i = 0;
    while i < segs.len() {
        let v = table.get(segs[i])?;
        i += 1;
        let v = match v {
            toml::Value::Array(items) => match segs.get(i).and_then(|s| s.parse::<usize>().ok()) {
                Some(n) => {
                    i += 1;
                    items.get(n)?
                }
                None if items.len() == 1 && i < segs.len() => &items[0],
                None => v,
            },
            _ => v,
        };
        value = Some(v);
        if i < segs.len() {
            table = v.as_table()?;
        }
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_bounds_and_maps_both_ways() {
        let f = Free::parse("interface.law.u_r=1e-3..4e-3").unwrap();
        assert_eq!((f.lo, f.hi, f.log), (1e-3, 4e-3, false));
        assert!((f.value(f.coordinate(2.5e-3)) - 2.5e-3).abs() < 1e-18);
        let g = Free::parse("interface.law.g_n0 = 1e7 .. 1e10").unwrap();
        assert!(g.log);
        assert!((g.middle() / 10f64.powf(8.5) - 1.0).abs() < 1e-12);
        assert!((g.coordinate(1e8) - 1.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn refuses_malformed_specs() {
        for (spec, want) in [
            ("u_r", "no `=`"),
            ("u_r=1", "no `..`"),
            ("u_r=2..1", "reversed or equal"),
            ("u_r=a..1", "lower bound `a` is not a finite number"),
            ("u_r=0..inf", "upper bound `inf`"),
            (".u_r=0..1", "empty segment"),
        ] {
            let e = Free::parse(spec).unwrap_err().to_string();
            assert!(e.contains(want), "{spec}: {e}");
        }
    }

    #[test]
    fn looks_up_through_a_single_table_array() {
        let doc: toml::Table =
            toml::from_str("[[interface]]\nfaces='z-'\n[interface.law]\nu_r = 4e-3\n").unwrap();
        assert_eq!(
            lookup(&doc, "interface.law.u_r").and_then(|v| v.as_float()),
            Some(4e-3)
        );
        assert_eq!(
            lookup(&doc, "interface.0.law.u_r").and_then(|v| v.as_float()),
            Some(4e-3)
        );
        assert!(lookup(&doc, "interface.law.alpha_e").is_none());
    }
}
