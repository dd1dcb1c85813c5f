//! A Rerun capture (`run --save FILE.rrd`) read back as a time series: every `Scalars` entity
//! of the recording, one column per instance (named `entity/series`, the series' name from its
//! static `SeriesLines`), on the `sim_time` timeline; plus the run's status (`run/status`).
//! The capture holds the frames only (200 by default, `--every`, `--fps`), so its comparison
//! resolves what those frames resolve; `--series` holds every step.
//!
//! Left out: `timing` (the machine's speed) and `body/colour_range` (the colour scale of the
//! chosen field).

use super::series::{Column, Quantity, Series};
use super::CompareError;
use rerun::external::re_chunk_store::external::re_chunk::Chunk;
use rerun::{ChunkStore, ChunkStoreConfig, TimelineName};
use std::collections::BTreeMap;
use std::path::Path;

/// What an entity's scalars hold.
fn quantity(entity: &str) -> Option<Quantity> {
    let top = entity.split('/').next().unwrap_or("");
    Some(match (top, entity) {
        (_, "timing" | "body/colour_range") => return None,
        (_, "balance/relative_residual") => Quantity::Residual,
        (_, "interface/count") => Quantity::Count,
        (_, "interface/alpha") => Quantity::Length,
        (_, "time_step") => Quantity::Step,
        ("energy", _) => Quantity::Energy,
        ("reaction", _) => Quantity::Force,
        ("mould_moment", _) => Quantity::Moment,
        ("imposed_displacement", _) => Quantity::Length,
        _ => Quantity::Other,
    })
}

/// The recording store of a capture (the file also holds a blueprint).
fn store(path: &Path) -> Result<ChunkStore, CompareError> {
    let format = |why: String| CompareError::Format {
        path: path.into(),
        why,
    };
    let mut file = std::fs::File::open(path).map_err(|source| CompareError::Read {
        path: path.into(),
        source,
    })?;
    let stores = ChunkStore::from_rrd_reader(&ChunkStoreConfig::DEFAULT, &mut file)
        .map_err(|e| format(format!("not a Rerun capture: {e:#}")))?;
    let mut recordings: Vec<ChunkStore> = stores
        .into_values()
        .filter(|s| s.id().is_recording())
        .collect();
    match recordings.len() {
        1 => Ok(recordings.pop().unwrap()),
        n => Err(format(format!(
            "{n} recordings in the file: a capture of one run (run --save) holds one"
        ))),
    }
}

/// The strings of one component of an entity's static chunks.
fn static_strings(chunks: &[&Chunk], component: rerun::ComponentIdentifier) -> Vec<String> {
    let mut out = Vec::new();
    for c in chunks.iter().filter(|c| c.is_static()) {
        for v in c.iter_slices::<String>(component) {
            out = v.iter().map(|s| s.as_str().to_string()).collect();
        }
    }
    out
}

/// Reads the capture at `path` as a series.
pub fn read(path: &Path) -> Result<Series, CompareError> {
    let store = store(path)?;
    let mut by_entity: BTreeMap<String, Vec<&Chunk>> = BTreeMap::new();
    for chunk in store.iter_physical_chunks() {
        by_entity
            .entry(chunk.entity_path().to_string())
            .or_default()
            .push(chunk);
    }
    let scalars = rerun::Scalars::descriptor_scalars().component;
    let names = rerun::SeriesLines::descriptor_names().component;
    let time = TimelineName::from_static_str("sim_time");
    let mut series = Series::default();
    for (entity, chunks) in &by_entity {
        let name = entity.trim_start_matches('/');
        let Some(q) = quantity(name) else { continue };
        let mut rows: BTreeMap<i64, Vec<f64>> = BTreeMap::new();
        for c in chunks.iter().filter(|c| !c.is_static()) {
            for ((t, _), v) in c
                .iter_component_indices(time, scalars)
                .zip(c.iter_slices::<f64>(scalars))
            {
                rows.insert(t.as_i64(), v.to_vec());
            }
        }
        let width = rows.values().map(Vec::len).max().unwrap_or(0);
        let labels = static_strings(chunks, names);
        for k in 0..width {
            let label = match (width, labels.get(k)) {
                (1, _) => name.to_string(),
                (_, Some(l)) => format!("{name}/{l}"),
                _ => format!("{name}/#{k}"),
            };
            let (t, v): (Vec<f64>, Vec<f64>) = (rows.iter())
                .filter_map(|(&t, v)| Some((t as f64 * 1e-9, *v.get(k)?)))
                .unzip();
            series.columns.push(Column {
                name: label,
                quantity: q,
                t,
                v,
            });
        }
    }
    if series.columns.is_empty() {
        return Err(CompareError::Format {
            path: path.into(),
            why: "no scalar series on the sim_time timeline: not a capture of decohesion run"
                .into(),
        });
    }
    series.status = status(&by_entity);
    Ok(series)
}

/// The run's outcome from `run/status` (`# Run completed` …): completed, failed or cancelled.
fn status(by_entity: &BTreeMap<String, Vec<&Chunk>>) -> Option<String> {
    let chunks = by_entity.get("/run/status")?;
    let text = rerun::TextDocument::descriptor_text().component;
    let mut out = None;
    for c in chunks {
        for v in c.iter_slices::<String>(text) {
            if let Some(s) = v.first() {
                let first = s.as_str().lines().next().unwrap_or("");
                out = Some(first.trim_start_matches("# Run ").trim().to_string());
            }
        }
    }
    out
}
