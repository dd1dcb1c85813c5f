//! A sweep (`decohesion sweep --save`) as its own Rerun recording: every observable against
//! every varied value, as scalar series whose timeline is the varied value.
//!
//! Timelines are integers, so each varied key gets one whose ticks are its values in a unit of
//! 10^e, e the largest power that makes every value a whole number (`pull_speed [×1e-2]`: 0.01,
//! 0.1, 1 → 1, 10, 100); values spanning two decades or more also get `log10 <key> [×1e-d]`
//! (ticks 10^d·log₁₀ v, evenly spaced for a sweep by decades; d = 3 up to two decades, 2 up to
//! twenty, so that the span stays within the 2000 ticks the viewer plots whole); values that are not numbers
//! (`scheme.integration="full","reduced"`) are placed by their index in the `--vary` list.
//! Entity `sweep/<key>/<observable>/<others>` is logged on the timelines of `<key>` only, one
//! entity (series) per combination of the other varied keys' values. The table of runs is
//! `table`.

use super::sweep::{observable_names, observables, SweepRow, Vary};
use crate::vary::PALETTE;
use anyhow::{Context, Result};
use rerun::blueprint::components::{PanelState, PlayState};
use rerun::blueprint::{
    Blueprint, BlueprintPanel, ContainerLike, Grid, SelectionPanel, Tabs, TextDocumentView,
    TimePanel, TimeSeriesView, Vertical,
};
use rerun::{RecordingStreamBuilder, Rgba32, Scalars, SeriesLines, SeriesPoints, TextDocument};
use std::path::Path;

/// The observables drawn (columns of [`observables`]), with their view titles.
const PLOTTED: [(usize, &str); 8] = [
    (0, "peak reaction [N]"),
    (1, "dissipated by damage [J]"),
    (5, "time of full rupture [s]"),
    (6, "ruptured nodes at the end"),
    (7, "end time reached [s]"),
    (8, "max balance residual / largest energy"),
    (2, "dissipated by friction [J]"),
    (3, "external work [J]"),
];

/// A name usable as one entity path part.
fn part(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// The timelines of one varied key: (name, tick of each value).
pub fn timelines(v: &Vary) -> Vec<(String, Vec<i64>)> {
    let nums: Option<Vec<f64>> = v
        .values
        .iter()
        .map(|s| s.parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect();
    let Some(nums) = nums else {
        let ticks = (0..v.values.len() as i64).collect();
        return vec![(format!("{} [index]", v.key), ticks)];
    };
    let whole = |e: i32| {
        let unit = 10f64.powi(e);
        nums.iter().all(|&x| {
            let n = (x / unit).round();
            n.abs() < 9e15 && (x == 0.0 || (n != 0.0 && (n * unit - x).abs() <= 1e-9 * x.abs()))
        })
    };
    let e = (-18..=18).rev().find(|&e| whole(e)).unwrap_or(-18);
    let unit = 10f64.powi(e);
    let name = if e == 0 {
        v.key.clone()
    } else {
        format!("{} [×1e{e}]", v.key)
    };
    let mut out = vec![(
        name,
        nums.iter().map(|x| (x / unit).round() as i64).collect(),
    )];
    let (lo, hi) = nums
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    if lo > 0.0 && hi / lo >= 100.0 {
        let d = log_digits((hi / lo).log10());
        let scale = 10f64.powi(d);
        let ticks = nums
            .iter()
            .map(|x| (scale * x.log10()).round() as i64)
            .collect();
        out.push((format!("log10 {} [×1e-{d}]", v.key), ticks));
    }
    out
}

use crate::tunables::SWEEP_WHOLE_SPAN as WHOLE_SPAN;

/// Decimals of log₁₀ kept on a log timeline spanning `decades`: 3 (ticks 1000·log₁₀ v) while
/// the span fits [`WHOLE_SPAN`] (up to 2 decades), then 2, 1, 0.
fn log_digits(decades: f64) -> i32 {
    (0..=3)
        .rev()
        .find(|&d| 10f64.powi(d) * decades <= WHOLE_SPAN)
        .unwrap_or(0)
}

/// The label of the series of a row for key `k`: the other keys' values.
fn others(varies: &[Vary], row: &SweepRow, k: usize) -> String {
    let parts: Vec<String> = varies
        .iter()
        .zip(&row.values)
        .enumerate()
        .filter(|(i, _)| *i != k)
        .map(|(_, (v, value))| format!("{}={value}", v.key))
        .collect();
    if parts.is_empty() {
        "runs".into()
    } else {
        parts.join(" ")
    }
}

/// The viewer's layout: per varied key a grid of the observables (tabs when several keys;
/// the plots show the timeline picked in the time panel, initially the first key's), the
/// table of runs below.
fn blueprint(varies: &[Vary], first_timeline: &str) -> Blueprint {
    let grid = |v: &Vary| -> ContainerLike {
        Grid::new(PLOTTED.iter().map(|(k, title)| {
            let obs = observables_names()[*k];
            TimeSeriesView::new(format!("{title} vs {}", v.key))
                .with_origin(format!("/sweep/{}/{obs}", part(&v.key)))
                .into()
        }))
        .with_grid_columns(4)
        .with_name(format!("against {}", v.key))
        .into()
    };
    let plots: ContainerLike = if varies.len() == 1 {
        grid(&varies[0])
    } else {
        Tabs::new(varies.iter().map(grid)).into()
    };
    Blueprint::new(
        Vertical::new([
            plots,
            TextDocumentView::new("runs").with_origin("/table").into(),
        ])
        .with_row_shares([3.0, 1.0]),
    )
    .with_time_panel(
        TimePanel::new()
            .with_timeline(first_timeline)
            // At the last value, not playing from the first: the plots then show every run.
            .with_play_state(PlayState::Following)
            .with_state(PanelState::Collapsed),
    )
    .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
    .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
}

/// The CSV names of the observables, in [`observables`] order.
fn observables_names() -> Vec<&'static str> {
    observable_names().iter().map(|o| o.0).collect()
}

/// The rows as a Markdown table: the varied values, the status, every observable.
fn markdown(varies: &[Vary], rows: &[SweepRow]) -> String {
    let mut head: Vec<String> = varies.iter().map(|v| format!("`{}`", v.key)).collect();
    head.push("status".into());
    head.extend(observables_names().iter().map(|n| n.to_string()));
    let mut s = format!("| {} |\n|{}\n", head.join(" | "), "---|".repeat(head.len()));
    for r in rows {
        let mut cells: Vec<String> = r.values.iter().map(|v| format!("`{v}`")).collect();
        cells.push(r.status.clone());
        cells.extend(
            observables(r)
                .iter()
                .map(|o| o.2.map_or("—".into(), |v| format!("{v:.4e}"))),
        );
        s.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    s
}

/// Writes the recording of a sweep to `path`.
pub fn log_sweep(path: &Path, scene: &str, varies: &[Vary], rows: &[SweepRow]) -> Result<()> {
    let axes: Vec<Vec<(String, Vec<i64>)>> = varies.iter().map(timelines).collect();
    let first = axes[0].last().map(|a| a.0.clone()).unwrap_or_default();
    let rec = RecordingStreamBuilder::new(crate::record::APPLICATION_ID)
        .recording_name(format!("sweep · {scene}"))
        .with_blueprint(blueprint(varies, &first))
        .save(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    let names = observables_names();
    // Per key, the labels of its series in order of appearance (their colours).
    let mut series: Vec<Vec<String>> = vec![vec![]; varies.len()];
    for (k, labels) in series.iter_mut().enumerate() {
        for r in rows {
            let l = others(varies, r, k);
            if !labels.contains(&l) {
                labels.push(l);
            }
        }
    }
    let mut styled = std::collections::BTreeSet::new();
    for row in rows.iter().filter(|r| r.summary.is_some()) {
        let obs = observables(row);
        for (k, v) in varies.iter().enumerate() {
            let i = v
                .values
                .iter()
                .position(|x| *x == row.values[k])
                .unwrap_or(0);
            let label = others(varies, row, k);
            let n = series[k].iter().position(|l| *l == label).unwrap_or(0);
            let [r, g, b] = PALETTE[n % PALETTE.len()];
            let colour = Rgba32::from_rgb(r, g, b);
            rec.reset_time();
            for (name, ticks) in &axes[k] {
                let timeline = rerun::TimelineName::try_new(name)
                    .map_err(|e| anyhow::anyhow!("timeline `{name}`: {e:?}"))?;
                rec.set_time_sequence(timeline, ticks[i]);
            }
            for (o, _) in PLOTTED {
                let Some(value) = obs[o].2 else { continue };
                let entity = format!("sweep/{}/{}/{}", part(&v.key), names[o], part(&label));
                if styled.insert(entity.clone()) {
                    rec.log_static(
                        entity.as_str(),
                        &SeriesLines::new()
                            .with_names([label.as_str()])
                            .with_colors([colour]),
                    )?;
                    rec.log_static(
                        entity.as_str(),
                        &SeriesPoints::new()
                            .with_names([label.as_str()])
                            .with_colors([colour])
                            .with_marker_sizes([4.0]),
                    )?;
                }
                rec.log(entity.as_str(), &Scalars::single(value))?;
            }
        }
    }
    rec.reset_time();
    rec.log_static(
        "table",
        &TextDocument::from_markdown(markdown(varies, rows)),
    )?;
    rec.flush_blocking().context("flushing the recording")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decades get a unit that makes them whole and a log timeline; names are placed by index.
    #[test]
    fn timelines_of_values() {
        let v = Vary::parse("speed=0.01,0.1,1").unwrap();
        let t = timelines(&v);
        assert_eq!(t[0], ("speed [×1e-2]".to_string(), vec![1, 10, 100]));
        assert_eq!(
            t[1],
            ("log10 speed [×1e-3]".to_string(), vec![-2000, -1000, 0])
        );
        // Three decades and more: 100·log₁₀ v, a span the viewer still plots whole.
        let t = timelines(&Vary::parse("speed=0.001,0.01,0.1,1").unwrap());
        assert_eq!(
            t[1],
            ("log10 speed [×1e-2]".to_string(), vec![-300, -200, -100, 0])
        );
        let t = timelines(&Vary::parse("tau=1e-15,1e-2").unwrap());
        assert_eq!(t[1], ("log10 tau [×1e-2]".to_string(), vec![-1500, -200]));
        assert_eq!(log_digits(2.0), 3);
        assert_eq!(log_digits(20.0), 2);
        assert_eq!(log_digits(200.0), 1);
        let v = Vary::parse("g=5e8,1e9").unwrap();
        assert_eq!(timelines(&v), vec![("g [×1e8]".to_string(), vec![5, 10])]);
        let v = Vary::parse("n=0,3,-2").unwrap();
        assert_eq!(timelines(&v), vec![("n".to_string(), vec![0, 3, -2])]);
        let v = Vary::parse("rule=full,reduced").unwrap();
        assert_eq!(
            timelines(&v),
            vec![("rule [index]".to_string(), vec![0, 1])]
        );
    }
}
