//! The results of a fit as files and as a table: what `decohesion fit` writes into its folder and
//! prints, and what the Python API's `fit(out=…)` writes.

use super::scene_file::fitted_scene;
use super::FitReport;
use crate::figure::{Figure, Style};
use anyhow::{Context, Result};
use std::fmt::Write as _;
use std::path::Path;

/// The fitted values and the agreement, as printed.
pub fn table(r: &FitReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<28} {:>13} {:>13} {:>11} {:>8}",
        "key", "start", "fitted", "σ", "σ/value"
    );
    for p in &r.parameters {
        let sigma = p.sigma.map_or("—".into(), |v| format!("{v:.3e}"));
        let rel = p.sigma.map_or("—".into(), |v| {
            format!("{:.2} %", 100.0 * v / p.value.abs())
        });
        let _ = writeln!(
            s,
            "{:<28} {:>13.5e} {:>13.5e} {sigma:>11} {rel:>8}{}",
            p.key,
            p.start,
            p.value,
            if p.at_bound {
                "  at a bound: widen it"
            } else {
                ""
            }
        );
    }
    let unit = &r.y.unit;
    if let Some(i) = &r.initial {
        let _ = writeln!(
            s,
            "RMS residual: {:.4e} {unit} ({:.3} % of max |y|) at the start, ",
            i.rms,
            100.0 * i.rms_relative
        );
    }
    let _ = writeln!(
        s,
        "RMS residual: {:.4e} {unit} ({:.3} % of max |y|) fitted; {} runs ({} failed) + {} for σ, {:?}, {:.1} s",
        r.fitted.rms,
        100.0 * r.fitted.rms_relative,
        r.evaluations,
        r.failed_evaluations,
        r.uncertainty_evaluations,
        r.stop,
        r.wall_seconds
    );
    s
}

/// Writes the results into `dir` (which must exist): `fit.json`, `fit.csv`, `evaluations.csv`,
/// `fit.svg` and `<scene>_fitted.toml`.
pub fn write_outputs(dir: &Path, scene: &Path, r: &FitReport) -> Result<()> {
    let write = |name: &str, text: &str| -> Result<()> {
        let path = dir.join(name);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
    };
    write("fit.json", &serde_json::to_string_pretty(r)?)?;
    let mut csv = format!(
        "{} [{}],{} [{}],initial [{}],fitted [{}]\n",
        r.x.measured, r.x.unit, r.y.measured, r.y.unit, r.y.unit, r.y.unit
    );
    for i in 0..r.curves.x.len() {
        let initial = r
            .curves
            .initial
            .as_ref()
            .map_or(String::new(), |v| format!("{:?}", v[i]));
        let _ = writeln!(
            csv,
            "{:?},{:?},{initial},{:?}",
            r.curves.x[i], r.curves.measured[i], r.curves.fitted[i]
        );
    }
    write("fit.csv", &csv)?;
    let mut ev = String::from("run,");
    for p in &r.parameters {
        let _ = write!(ev, "{},", p.key);
    }
    ev.push_str("cost,status,error\n");
    for rec in &r.records {
        let _ = write!(ev, "{},", rec.index);
        for v in &rec.values {
            let _ = write!(ev, "{v:?},");
        }
        let _ = writeln!(
            ev,
            "{},{},\"{}\"",
            rec.cost.map_or(String::new(), |c| format!("{c:?}")),
            rec.status,
            rec.error.as_deref().unwrap_or("").replace('"', "'")
        );
    }
    write("evaluations.csv", &ev)?;
    let title = format!(
        "{} fitted to {} (RMS {:.2} % of max |y|)",
        r.name,
        Path::new(&r.data)
            .file_name()
            .map_or(r.data.clone(), |f| f.to_string_lossy().into_owned()),
        100.0 * r.fitted.rms_relative
    );
    let mut figure = Figure {
        title,
        x_label: format!("{} [{}]", r.x.measured, r.x.unit),
        y_label: format!("{} [{}]", r.y.measured, r.y.unit),
        traces: vec![],
    };
    let c = &r.curves;
    let along = |y: &[f64]| -> Vec<[f64; 2]> { c.x.iter().zip(y).map(|(a, b)| [*a, *b]).collect() };
    figure.trace("measured", along(&c.measured), [0x22; 3], Style::Points);
    if let Some(i) = &c.initial {
        figure.trace("start", along(i), [0x88; 3], Style::Dashed);
    }
    figure.trace("fitted", along(&c.fitted), [0xd6, 0x27, 0x28], Style::Solid);
    write("fit.svg", &figure.svg())?;
    let text = std::fs::read_to_string(scene)
        .with_context(|| format!("cannot read {}", scene.display()))?;
    let mut values: Vec<(String, toml_edit::Value, Option<String>)> = Vec::new();
    for spec in &r.set {
        if let Some((k, v)) = spec.split_once('=') {
            let value: toml_edit::Value = v
                .trim()
                .parse()
                .unwrap_or_else(|_| toml_edit::Value::from(v.trim()));
            values.push((k.trim().to_string(), value, Some("--set".into())));
        }
    }
    for p in &r.parameters {
        let note = match p.sigma {
            Some(s) => format!("fitted: σ = {s:.3e}"),
            None => "fitted".to_string(),
        };
        values.push((p.key.clone(), toml_edit::Value::from(p.value), Some(note)));
    }
    let header = format!(
        "Fitted by `decohesion fit` to {} ({} against {}): RMS residual {:.3} % of max |y|.",
        r.data,
        r.y.column,
        r.x.column,
        100.0 * r.fitted.rms_relative
    );
    let fitted = fitted_scene(&text, &header, &values)
        .with_context(|| format!("writing the fitted values into {}", scene.display()))?;
    let stem = scene
        .file_stem()
        .map_or("scene".to_string(), |s| s.to_string_lossy().into_owned());
    write(&format!("{stem}_fitted.toml"), &fitted)?;
    Ok(())
}
