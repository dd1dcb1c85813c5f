//! `decohesion run --watch N,…`: two nodes on an edge of the pull-off's glued face followed to
//! the rupture, in the `--series` columns and the recording, checked against the law and
//! against the run's other outputs:
//! - α never decreases, stays in [0, u_r], starts at 0 and ends at u_r;
//! - the mould is the fixed plane z = 0 the nodes are bonded to, so [u]_z = g at every step;
//! - the glue's traction is −g_N(α)[u], the state's code the law's state of α;
//! - the last row says ruptured, as the summary's counts; the node ruptures no later than the
//!   summary's full rupture;
//! - the recording's `nodes/<N>/…` series are the series' rows of the frames' steps, to the bit,
//!   and its α is the node's instance of `interface/alpha`; its log names each change; the
//!   capture passes `rerun rrd verify` when the CLI is installed.
//!
//! The refusals of `--watch` (a node out of range, an inner node, no output) are cases of the
//! bad-input corpus (`tests/data/bad_input/cases.toml`).

use crate::common::capture::{read_capture, scalars, steps_with, verify};
use crate::common::cli::{decohesion_ok, scratch, summary};
use decohesion::law::InterfaceState;
use decohesion::scene::load_scene;
use decohesion::solver::Simulation;
use std::collections::BTreeMap;
use std::path::Path;

/// A `--series` file: the header's names and the rows.
fn read_series(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (names, rows)
}

#[test]
fn watched_edge_nodes_follow_the_glue_to_rupture() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene_path = root.join("scenes/pull_off.toml");
    let set = "mesh.cells=[3,3,3]".to_string();
    let model = load_scene(&scene_path, std::slice::from_ref(&set))
        .unwrap()
        .model;
    let law = model.interfaces[0].law.clone();
    let nodes = &model.mesh.nodes;
    // The corner of the glued face and the next node along its edge y = z = 0.
    let corner = nodes.iter().position(|x| *x == [0.0; 3]).unwrap();
    let edge = (nodes.iter())
        .position(|x| x[1] == 0.0 && x[2] == 0.0 && x[0] > 0.0 && x[0] < 1.0)
        .unwrap();
    let order: Vec<u32> = (Simulation::new(model.clone())
        .unwrap()
        .state
        .interface_nodes)
        .iter()
        .map(|n| n.node)
        .collect();

    let dir = scratch("watch", "pull_off");
    let (csv, rrd, json) = (dir.join("s.csv"), dir.join("r.rrd"), dir.join("s.json"));
    let watch = format!("{corner},{edge}");
    let path = |p: &Path| p.display().to_string();
    decohesion_ok(&[
        "run",
        &path(&scene_path),
        "--set",
        &set,
        "--watch",
        &watch,
        "--series",
        &path(&csv),
        "--save",
        &path(&rrd),
        "--summary",
        &path(&json),
        "--quiet",
    ]);
    let sum = summary(&json);
    assert_eq!(sum["status"], "completed");
    assert_eq!(sum["final_counts"]["ruptured"], 16, "the whole face tears");
    let full_rupture = sum["time_full_rupture"].as_f64().unwrap();

    let (names, rows) = read_series(&csv);
    let column = |name: &str| -> Vec<f64> {
        let k = (names.iter().position(|n| n == name))
            .unwrap_or_else(|| panic!("no column {name:?} in {names:?}"));
        rows.iter().map(|r| r[k]).collect()
    };
    let steps = column("step [-]");
    let times = column("t [s]");
    let store = read_capture(&rrd);
    for node in [corner, edge] {
        let c = |part: &str, unit: &str| column(&format!("{part}_node{node} [{unit}]"));
        let alpha = c("alpha", "m");
        let gap = c("gap", "m");
        let jump = ["x", "y", "z"].map(|a| c(&format!("jump_{a}"), "m"));
        let glue = ["x", "y", "z"].map(|a| c(&format!("traction_glue_{a}"), "Pa"));
        let contact = ["x", "y", "z"].map(|a| c(&format!("traction_contact_{a}"), "Pa"));
        let state = c("state", "-");
        let status = c("contact", "-");
        assert!(alpha.windows(2).all(|w| w[0] <= w[1]), "α never decreases");
        assert!(alpha.iter().all(|&a| (0.0..=law.u_r).contains(&a)));
        assert_eq!((alpha[0], *alpha.last().unwrap()), (0.0, law.u_r));
        for k in 0..rows.len() {
            assert!(
                (jump[2][k] - gap[k]).abs() <= 1e-12,
                "node {node}, step {}: [u]_z = {} against g = {}",
                steps[k],
                jump[2][k],
                gap[k]
            );
            let g_n = law.g_n(alpha[k]);
            for i in 0..3 {
                let expect = -g_n * jump[i][k];
                assert!(
                    (glue[i][k] - expect).abs() <= 1e-9 * expect.abs().max(1.0),
                    "node {node}, step {}: −R_d,{i} = {} against −g_N(α)[u] = {expect}",
                    steps[k],
                    glue[i][k]
                );
                assert!(contact[i][k].is_finite());
            }
            let code = match law.state(alpha[k]) {
                InterfaceState::Elastic => 0.0,
                InterfaceState::Transition => 1.0,
                InterfaceState::Ruptured => 2.0,
                InterfaceState::Unformed => 3.0,
            };
            assert_eq!(state[k], code, "node {node}, step {}", steps[k]);
            assert!([0.0, 1.0, 2.0].contains(&status[k]));
        }
        assert_eq!(*state.last().unwrap(), 2.0, "ruptured at the end");
        let ruptured = times[state.iter().position(|&s| s == 2.0).unwrap()];
        assert!(ruptured <= full_rupture, "{ruptured} > {full_rupture}");
        assert!(state.contains(&1.0), "through the transition");

        // The recording: its frames are rows of the series (a row every step), to the bit.
        let row_of: BTreeMap<i64, usize> = (steps.iter().enumerate())
            .map(|(k, &s)| (s as i64, k))
            .collect();
        let rec = |what: &str| scalars(&store, &format!("/nodes/{node}/{what}"));
        let rec_alpha = rec("alpha");
        assert!(rec_alpha.len() > 100, "{} frames", rec_alpha.len());
        let all_alpha = scalars(&store, "/interface/alpha");
        let instance = order.iter().position(|&n| n as usize == node).unwrap();
        let (rec_jump, rec_traction, rec_gap, rec_status) =
            (rec("jump"), rec("traction"), rec("gap"), rec("status"));
        for (step, a) in &rec_alpha {
            let k = row_of[step];
            assert_eq!(a, &vec![alpha[k]], "step {step}");
            assert_eq!(all_alpha[step][instance], alpha[k], "step {step}");
            let at = |v: &[Vec<f64>; 3]| v.iter().map(|c| c[k]).collect::<Vec<f64>>();
            assert_eq!(rec_jump[step], at(&jump));
            let mut t = at(&glue);
            t.extend(at(&contact));
            assert_eq!(rec_traction[step], t);
            assert_eq!(rec_gap[step], vec![gap[k]]);
            assert_eq!(rec_status[step], vec![state[k], status[k]]);
        }
        // The log: the first frame, the transition and the rupture at least.
        let log = steps_with(
            &store,
            &format!("/nodes/{node}/log"),
            rerun::TextLog::descriptor_text().component,
        );
        assert!(log.len() >= 3, "{log:?}");
    }
    verify(&rrd);
    std::fs::remove_dir_all(&dir).ok();
}
