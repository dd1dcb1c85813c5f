//! Moulds that are not planes in the Rerun capture (model §7): the indent scene's
//! sphere is logged once as a mesh at its t = 0 placement under `planes/ball`, and moved by a
//! Transform3D per frame taken from the step's own pose (`Simulation::mould_pose`). The file
//! is read back with the SDK's chunk store, as in `tests/recording.rs`; `rerun rrd verify` is
//! CI's (it runs it on every scene's capture), not this test's.

use crate::common;

use crate::common::capture::{read_capture, steps_with};
use crate::common::cli::{decohesion_ok, summary};
use decohesion::model::Shape;
use decohesion::scene::load_scene;
use decohesion::solver::Simulation;
use rerun::{Mesh3D, TimelineName, Transform3D};
use std::path::Path;

const SCENE: &str = "scenes/indent.toml";
/// A short, coarse indent: 4 × 4 × 8 cells to 20 ms (the sphere 0.15 mm down).
const OVERRIDES: [&str; 2] = ["mesh.cells=[4,4,8]", "end_time=0.02"];

/// The summary's simulated time, parsed from its text with `str::parse` (correctly rounded).
fn simulated_time(path: &Path) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    let key = "\"simulated_time\":";
    let rest =
        text[text.find(key).expect("simulated_time in the summary") + key.len()..].trim_start();
    let end = rest.find([',', '\n', '}']).unwrap();
    rest[..end].trim().parse().unwrap()
}

#[test]
fn indent_capture_draws_the_sphere_and_moves_it_with_its_pose() {
    let dir = common::cli::scratch("rec", "indent_moulds");
    let (rrd, json) = (dir.join("indent.rrd"), dir.join("indent.json"));
    let mut args = vec!["run", SCENE, "--quiet"];
    for o in &OVERRIDES {
        args.extend(["--set", o]);
    }
    args.extend(["--save", rrd.to_str().unwrap()]);
    args.extend(["--summary", json.to_str().unwrap()]);
    decohesion_ok(&args);
    let s = summary(&json);
    let t_end = simulated_time(&json);
    let steps = s["steps"].as_i64().unwrap();

    let overrides: Vec<String> = OVERRIDES.iter().map(|o| o.to_string()).collect();
    let model = load_scene(Path::new(SCENE), &overrides).unwrap().model;
    let k = model.moulds.iter().position(|p| p.name == "ball").unwrap();
    let Shape::Sphere(decohesion_physics::mould::shapes::sphere::Sphere { centre, radius }) =
        model.moulds[k].shape
    else {
        panic!("the ball is a sphere");
    };

    // The mesh: static, on the sphere at t = 0, the UV sphere's counts.
    let store = read_capture(&rrd);
    let entity = "/planes/ball";
    let positions = Mesh3D::descriptor_vertex_positions().component;
    let triangles = Mesh3D::descriptor_triangle_indices().component;
    let (mut vertices, mut faces) = (vec![], vec![]);
    for chunk in store.iter_physical_chunks() {
        if chunk.entity_path().to_string() != entity || !chunk.is_static() {
            continue;
        }
        for v in chunk.iter_slices::<[f32; 3]>(positions) {
            vertices.extend_from_slice(v);
        }
        for t in chunk.iter_slices::<[u32; 3]>(triangles) {
            faces.extend_from_slice(t);
        }
    }
    assert_eq!((vertices.len(), faces.len()), (482, 960), "{entity}");
    assert!(faces
        .iter()
        .flatten()
        .all(|&i| (i as usize) < vertices.len()));
    for x in &vertices {
        let r = (0..3)
            .map(|c| (f64::from(x[c]) - centre[c]).powi(2))
            .sum::<f64>()
            .sqrt();
        // f32 positions near |x| ≈ 0.28 m: an ulp is 3e-8 m.
        assert!((r - radius).abs() < 1e-7, "vertex {x:?} at {r} m");
    }

    // The transform: a translation at every frame; the last one the prescribed displacement
    // at the run's end, rounded to f32 (what Rerun stores) and nothing more.
    let translation = Transform3D::descriptor_translation().component;
    let frames = steps_with(&store, "/body/surface", positions);
    assert_eq!(steps_with(&store, entity, translation), frames);
    assert_eq!(*frames.last().unwrap(), steps);
    let step = TimelineName::from_static_str("step");
    let mut last = None;
    for chunk in store.iter_physical_chunks() {
        if chunk.entity_path().to_string() != entity {
            continue;
        }
        for ((t, _), v) in chunk
            .iter_component_indices(step, translation)
            .zip(chunk.iter_slices::<[f32; 3]>(translation))
        {
            if t.as_i64() == steps {
                last = Some(v[0]);
            }
        }
    }
    let d = model.moulds[k].displacement(t_end);
    assert!(d[2] < -1e-4, "the sphere went down: {d:?}");
    assert_eq!(
        last,
        Some(d.map(|c| c as f32)),
        "translation at step {steps}"
    );
    // The sphere does not turn: no rotation logged.
    let rotation = Transform3D::descriptor_mat3x3().component;
    assert!(steps_with(&store, entity, rotation).is_empty());
}

/// The accessor itself, in f64: at every step of the same short run, R = I and T is the
/// sphere's prescribed displacement at tₙ to 1e-12 relative.
#[test]
fn mould_pose_is_the_prescribed_motion() {
    let overrides: Vec<String> = OVERRIDES.iter().map(|o| o.to_string()).collect();
    let model = load_scene(Path::new(SCENE), &overrides).unwrap().model;
    let k = model.moulds.iter().position(|p| p.name == "ball").unwrap();
    let base = model.moulds.iter().position(|p| p.name == "base").unwrap();
    let mut sim = Simulation::new(model).unwrap();
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert_eq!(sim.mould_pose(k), (identity, [0.0; 3]));
    let mut steps = 0;
    while !sim.finished() {
        sim.step().unwrap();
        steps += 1;
        let (r, t) = sim.mould_pose(k);
        let d = sim.model.moulds[k].displacement(sim.state.time);
        assert_eq!(r, identity);
        let err = (0..3).map(|c| (t[c] - d[c]).abs()).fold(0.0, f64::max);
        let size = d.iter().map(|c| c.abs()).fold(0.0, f64::max);
        assert!(err <= 1e-12 * size, "step {steps}: {t:?} vs {d:?}");
        // The base plane does not move.
        assert_eq!(sim.mould_pose(base), (identity, [0.0; 3]));
    }
    assert!(steps > 10);
}
