//! A glued face set and its mould at t = 0 (model §7.7): a face set that
//! looks away from its mould is refused (it could never tear), glued nodes that start inside
//! the mould beyond the tolerance are refused, and glued nodes that start off it (or inside
//! within the tolerance) load with a warning that says how many and how far, and what that does
//! to the glue — which the run then shows (pre-damage).

use crate::common;
use crate::common::scene_file;
use decohesion_physics::scene::parse_scene;
use decohesion_physics::solver::Simulation;
use std::sync::LazyLock;

static FILE: LazyLock<String> = LazyLock::new(|| scene_file("glued.toml").display().to_string());

/// The glued cube of the scene-error tests (α_e = 0.5 mm, so the tolerance is 1e-3 α_e =
/// 0.5 µm).
const VALID: &str = common::GLUED_CUBE;

fn load(from: &str, to: &str) -> Result<decohesion_physics::scene::Scene, String> {
    assert!(VALID.contains(from), "{from:?} is not in the scene");
    parse_scene(&VALID.replacen(from, to, 1), &FILE, &[]).map_err(|e| e.to_string())
}

fn assert_has(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "missing {part:?} in:\n{message}");
    }
}

/// The scene as given loads with no warning about the glue's start.
#[test]
fn a_face_set_on_its_mould_loads_without_warning() {
    let scene = load("", "").unwrap();
    let sim = Simulation::new(scene.model).unwrap();
    assert!(sim.setup.start_offsets.is_empty());
    assert!(!sim
        .advisories()
        .iter()
        .any(|w| w.contains("do not start on mould")));
}

/// The mould normal flipped (pointing out of the solid, the same way as the glued face's
/// outward normal): refused with the face set, the mould and both normals.
#[test]
fn a_glued_face_set_looking_away_from_its_mould_is_refused() {
    let e = load("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, -2.0]").unwrap_err();
    assert_has(
        &e,
        &[
            FILE.as_str(),
            "interface[0].faces",
            "\"z-\"",
            "4 of its 4 faces look away from mould `mould`",
            "outward normal [0.0000, 0.0000, -1.0000]",
            "mould normal [0.0000, 0.0000, -1.0000]",
        ],
    );
    // The top face glued to a plane above the cube: right with the normal pointing down into
    // the solid, refused with it pointing up.
    let top = |normal: &str| {
        VALID
            .replace("point = [0.0, 0.0, 0.0]", "point = [0.0, 0.0, 1.0]")
            .replace("normal = [0.0, 0.0, 1.0]", normal)
            .replace("faces = \"z-\"", "faces = \"z+\"")
    };
    assert!(parse_scene(&top("normal = [0.0, 0.0, -1.0]"), &FILE, &[]).is_ok());
    let e = parse_scene(&top("normal = [0.0, 0.0, 1.0]"), &FILE, &[])
        .unwrap_err()
        .to_string();
    assert_has(&e, &["\"z+\"", "outward normal [0.0000, 0.0000, 1.0000]"]);
}

/// The mould 0.1 mm above the glued face (200 tolerances): the 9 glued nodes start inside it,
/// refused with the file, the mould, the node count and the depth.
#[test]
fn glued_nodes_inside_the_mould_beyond_the_tolerance_are_refused() {
    let e = load("point = [0.0, 0.0, 0.0]", "point = [0.0, 0.0, 1.0e-4]").unwrap_err();
    assert_has(
        &e,
        &[
            FILE.as_str(),
            "interface[0].faces",
            "9 glued nodes start inside mould `mould` by up to 1.0000e-4 m",
            "tolerance 5.0000e-7 m",
        ],
    );
}

/// Inside by 0.1 µm (within the 0.5 µm tolerance): loads, with a warning that counts them.
#[test]
fn glued_nodes_inside_within_the_tolerance_load_with_a_warning() {
    let scene = load("point = [0.0, 0.0, 0.0]", "point = [0.0, 0.0, 1.0e-7]").unwrap();
    let sim = Simulation::new(scene.model).unwrap();
    let o = &sim.setup.start_offsets[0];
    assert_eq!((o.off_nodes, o.inside_nodes, o.deep_nodes), (0, 9, 0));
    assert!((o.deepest - 1e-7).abs() < 1e-15);
    let w = sim.advisories().join("\n");
    assert_has(
        &w,
        &[
            "glued nodes of `z-` do not start on mould `mould`",
            "9 start inside it by up to 1.000e-7 m",
        ],
    );
}

/// The mould 0.7 mm below the glued face: between α_e = 0.5 mm and u_r = 1 mm, so the glue
/// starts pre-damaged. The warning says so with the count and the offset, and the run agrees:
/// every glued node is in transition at t = 0, its α₀ the offset (eq. 12), and its glue pulls
/// with g_N(α₀)·δ.
#[test]
fn glued_nodes_off_the_mould_load_with_a_warning_that_the_run_confirms() {
    let scene = load("point = [0.0, 0.0, 0.0]", "point = [0.0, 0.0, -7.0e-4]").unwrap();
    let sim = Simulation::new(scene.model).unwrap();
    let o = &sim.setup.start_offsets[0];
    assert_eq!((o.off_nodes, o.inside_nodes), (9, 0));
    assert!((o.largest_off - 7e-4).abs() < 1e-15);
    let w = sim.advisories().join("\n");
    assert_has(
        &w,
        &[
            "interface[0]: glued nodes of `z-` do not start on mould `mould` (tolerance 5.000e-7 m)",
            "9 start off it by up to δ = 7.000e-4 m",
            "pre-stressed by up to g_N(0)δ = 1.400e6 Pa",
            "pre-damaged (α₀ = δ > α_e = 5.000e-4 m: Transition)",
        ],
    );
    let counts = sim.state_counts();
    assert_eq!((counts.elastic, counts.transition), (0, 9));
    for itf in &sim.state.interface_nodes {
        assert!((itf.alpha - 7e-4).abs() < 1e-15, "α₀ = {}", itf.alpha);
    }
}
