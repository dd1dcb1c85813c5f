//! A speed–accuracy study (`decohesion tradeoff --save/--spawn`) as its own recording.

use super::stream::open_stream;
use super::{log_err, RecordError, Sink, APPLICATION_ID};
use crate::tradeoff::{table, Row};
use rerun::blueprint::{Blueprint, Horizontal, Spatial2DView, TextDocumentView};
use rerun::{LineStrips2D, Points2D, RecordingStreamBuilder, Rgba32, TextDocument};

/// Logs a speed–accuracy study as its own recording: every configuration as a point of
/// (log₁₀ wall time [s], log₁₀ error) (2-D views point y down, so y = −log₁₀ error puts large
/// errors up), the Pareto front as a line, and the table as text.
pub fn log_frontier(sink: Sink, scene: &str, rows: &[Row]) -> Result<(), RecordError> {
    let name = format!("tradeoff · {scene}");
    let bp = Blueprint::new(Horizontal::new([
        Spatial2DView::new("error vs wall time (log₁₀, ×100)")
            .with_origin("/tradeoff")
            .into(),
        TextDocumentView::new("table").with_origin("/table").into(),
    ]));
    let builder = RecordingStreamBuilder::new(APPLICATION_ID)
        .recording_name(name)
        .with_blueprint(bp);
    let rec = match &sink {
        Sink::Save(path) => builder.save(path).map_err(|e| {
            RecordError::Setup(format!(
                "cannot write the recording {}: {e}",
                path.display()
            ))
        })?,
        other => open_stream(other, format!("tradeoff · {scene}"), None, None, &[])?,
    };
    let floor = 1e-6;
    let point = |r: &Row| {
        [
            (100.0 * r.wall_seconds.max(1e-6).log10()) as f32,
            (-100.0 * r.error.max(floor).log10()) as f32,
        ]
    };
    let ok: Vec<&Row> = rows
        .iter()
        .filter(|r| r.failure.is_none() && r.error.is_finite())
        .collect();
    let colour = |r: &Row| {
        if r.config.integration == "full" {
            Rgba32::from_rgb(30, 120, 220)
        } else {
            Rgba32::from_rgb(245, 166, 35)
        }
    };
    rec.log_static(
        "tradeoff/runs",
        &Points2D::new(ok.iter().map(|r| point(r)))
            .with_colors(ok.iter().map(|r| colour(r)))
            .with_radii([3.0f32])
            .with_labels(ok.iter().map(|r| {
                format!(
                    "{} {}³ ×{}: {:.3} s, error {:.2e}{}",
                    r.config.integration,
                    r.config.cells,
                    r.config.factor,
                    r.wall_seconds,
                    r.error,
                    if r.pareto { " (Pareto)" } else { "" }
                )
            })),
    )
    .map_err(log_err("the tradeoff points"))?;
    let mut front: Vec<&&Row> = ok.iter().filter(|r| r.pareto).collect();
    front.sort_by(|a, b| a.wall_seconds.total_cmp(&b.wall_seconds));
    rec.log_static(
        "tradeoff/pareto_front",
        &LineStrips2D::new([front.iter().map(|r| point(r)).collect::<Vec<_>>()])
            .with_colors([Rgba32::from_rgb(46, 160, 67)])
            .with_labels(["Pareto front"]),
    )
    .map_err(log_err("the Pareto front"))?;
    let table = format!("```text\n{}```\n", table(rows));
    rec.log_static("table", &TextDocument::from_markdown(table))
        .map_err(log_err("the tradeoff table"))?;
    rec.flush_blocking()
        .map_err(|e| RecordError::Setup(format!("flushing the recording: {e}")))?;
    Ok(())
}
