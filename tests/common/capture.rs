//! Reading Rerun captures back with the SDK's chunk store (what the viewer loads).

use rerun::external::re_chunk_store::external::re_chunk::ChunkComponentSlicer as Slicer;
use rerun::TimelineName;
use rerun::{ChunkStore, ChunkStoreConfig};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// The recording store of a capture (the file also holds a blueprint store).
pub fn read_capture(path: &Path) -> ChunkStore {
    let mut file = std::fs::File::open(path).unwrap();
    let stores = ChunkStore::from_rrd_reader(&ChunkStoreConfig::DEFAULT, &mut file)
        .unwrap_or_else(|e| panic!("{} does not read back: {e:#}", path.display()));
    let mut recordings: Vec<ChunkStore> = stores
        .into_values()
        .filter(|s| s.id().is_recording())
        .collect();
    assert_eq!(recordings.len(), 1, "one run, one recording");
    recordings.pop().unwrap()
}

/// Every row of a Scalars entity on the `step` timeline: step → values.
pub fn scalars(store: &ChunkStore, entity: &str) -> BTreeMap<i64, Vec<f64>> {
    rows::<f64>(
        store,
        entity,
        rerun::Scalars::descriptor_scalars().component,
    )
}

/// Every row of one component of an entity on the `step` timeline: step → instances.
pub fn rows<T>(
    store: &ChunkStore,
    entity: &str,
    component: rerun::ComponentIdentifier,
) -> BTreeMap<i64, Vec<T>>
where
    T: Clone + for<'a> Slicer<Item<'a> = &'a [T]>,
{
    rows_on(store, entity, component, "step")
}

/// Every row of one component of an entity on a timeline (`step`: the step; `sim_time`: the
/// simulated time in ns): time → instances.
pub fn rows_on<T>(
    store: &ChunkStore,
    entity: &str,
    component: rerun::ComponentIdentifier,
    timeline: &'static str,
) -> BTreeMap<i64, Vec<T>>
where
    T: Clone + for<'a> Slicer<Item<'a> = &'a [T]>,
{
    let timeline = TimelineName::from_static_str(timeline);
    let mut rows = BTreeMap::new();
    for chunk in store.iter_physical_chunks() {
        if chunk.entity_path().to_string() != entity {
            continue;
        }
        for ((t, _), v) in chunk
            .iter_component_indices(timeline, component)
            .zip(chunk.iter_slices::<T>(component))
        {
            rows.insert(t.as_i64(), v.to_vec());
        }
    }
    rows
}

/// Steps at which an entity has a component.
pub fn steps_with(
    store: &ChunkStore,
    entity: &str,
    component: rerun::ComponentIdentifier,
) -> Vec<i64> {
    let timeline = TimelineName::from_static_str("step");
    let mut steps = vec![];
    for chunk in store.iter_physical_chunks() {
        if chunk.entity_path().to_string() == entity {
            steps.extend(
                chunk
                    .iter_component_indices(timeline, component)
                    .map(|(t, _)| t.as_i64()),
            );
        }
    }
    steps.sort_unstable();
    steps.dedup();
    steps
}

/// `rerun rrd verify` on a capture, with the CLI of the CI's virtual environment
/// (`DECOHESION_VENV`, default ~/.cache/decohesion-venv; `.ci/run` installs it) or on PATH.
pub fn verify(rrd: &Path) {
    let venv = std::env::var("DECOHESION_VENV").unwrap_or_else(|_| {
        format!(
            "{}/.cache/decohesion-venv",
            std::env::var("HOME").unwrap_or_default()
        )
    });
    let venv_cli = Path::new(&venv).join("bin/rerun");
    let cli = if venv_cli.exists() {
        venv_cli
    } else if let Some(p) = decohesion::record::find_on_path("rerun") {
        p
    } else {
        // CI installs the CLI before the tests (`.ci/run`): there, a missing CLI is a failure.
        assert!(
            std::env::var("CI").is_err(),
            "CI is set and no rerun CLI was found in {venv}/bin or on PATH (rerun-sdk==0.36.3)"
        );
        eprintln!("no rerun CLI (install rerun-sdk==0.36.3): `rrd verify` skipped, read back only");
        return;
    };
    let out = Command::new(&cli)
        .args(["rrd", "verify"])
        .arg(rrd)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "rerun rrd verify: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
