//! Glued nodes that start off their mould (model §7.7): the warning reaches `check`, the
//! run's summary (its `warnings` and the `glued_start_offsets` field with the count and the
//! largest offset) and the recording's run log.

use crate::common::capture::read_capture;
use crate::common::cli::{decohesion, scratch, summary};

#[test]
fn a_start_off_the_mould_is_reported_in_check_summary_and_recording() {
    let dir = scratch("offset", "pull_off");
    let (json, rrd) = (dir.join("s.json"), dir.join("s.rrd"));
    // The mould 1 mm below the cube's glued bottom (tolerance 1e-3 α_e = 2 µm).
    let set = [
        "--set",
        "plane.0.point=[0.0, 0.0, -0.001]",
        "--set",
        "end_time=0.01",
    ];
    let out = decohesion(&[&["check", "scenes/pull_off.toml"][..], &set].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("64 start off it by up to δ = 1.000e-3 m"),
        "check does not warn:\n{text}"
    );
    assert!(text.contains("h never exceeds h_crit"), "{text}");
    let args = [
        &[
            "run",
            "scenes/pull_off.toml",
            "--quiet",
            "--summary",
            json.to_str().unwrap(),
        ][..],
        &["--save", rrd.to_str().unwrap()],
        &set,
    ]
    .concat();
    let out = decohesion(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = summary(&json);
    let o = &s["glued_start_offsets"][0];
    assert_eq!(o["off_nodes"], 64);
    assert_eq!(o["mould"], "mould");
    assert!((o["largest_off"].as_f64().unwrap() - 1e-3).abs() < 1e-12);
    assert!(s["warnings"]
        .to_string()
        .contains("do not start on mould `mould`"));
    // The recording's run log holds the same text.
    let store = read_capture(&rrd);
    let text_component = rerun::TextLog::descriptor_text().component;
    let mut logged = Vec::new();
    for chunk in store.iter_physical_chunks() {
        if chunk.entity_path().to_string() == "/run/log" {
            for v in chunk.iter_slices::<String>(text_component) {
                logged.extend(v.iter().map(|t| t.to_string()));
            }
        }
    }
    assert!(
        logged
            .iter()
            .any(|t| t.contains("64 start off it by up to δ = 1.000e-3 m")),
        "{logged:?}"
    );
    // Without the offset: no field.
    let plain = dir.join("plain.json");
    let out = decohesion(&[
        "run",
        "scenes/pull_off.toml",
        "--quiet",
        "--set",
        "end_time=0.01",
        "--summary",
        plain.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(summary(&plain).get("glued_start_offsets").is_none());
}
