//! Contact in the Rerun capture (model §3, §7.5): the nodes coloured open / stick / slip
//! (class ids of the annotation context), an arrow along the mould's normal at every node in
//! contact and none elsewhere, for glued and contact-only nodes; and a turning mould's logged
//! rotation against its analytic pose. The file is read back with the SDK's chunk store.

use crate::common::capture::{read_capture, rows};
use crate::common::cli::{decohesion_ok, scratch};
use crate::common::turning;
use decohesion::model::Shape;
use decohesion::record::NORMAL_FRACTION;
use decohesion::scene::load_scene;
use rerun::{Arrows3D, Points3D, TimelineName, Transform3D};
use std::path::Path;

/// Class ids of the contact statuses (the recording's annotation context).
const OPEN: u16 = 10;
const STICK: u16 = 11;
const SLIP: u16 = 12;

/// Records `scene` with `overrides` into DIR/NAME.rrd.
fn record(scene: &Path, overrides: &[&str], dir: &Path) -> std::path::PathBuf {
    let rrd = dir.join("capture.rrd");
    let mut args = vec!["run", scene.to_str().unwrap(), "--quiet"];
    for o in overrides {
        args.extend(["--set", o]);
    }
    args.extend(["--save", rrd.to_str().unwrap()]);
    decohesion_ok(&args);
    rrd
}

/// Checks one node set's arrows at every frame: `status` entity (class per node), `normal`
/// entity (arrows), `expected(step, node, x)` the mould's normal at node i, position x.
/// Returns the (stick, slip) arrows seen.
fn check_normals(
    store: &rerun::ChunkStore,
    (status, normal): (&str, &str),
    expected: &dyn Fn(i64, usize, [f32; 3]) -> [f64; 3],
    length: f64,
) -> (usize, usize) {
    let classes = rows::<u16>(store, status, Points3D::descriptor_class_ids().component);
    let points = rows::<[f32; 3]>(store, status, Points3D::descriptor_positions().component);
    let origins = rows::<[f32; 3]>(store, normal, Arrows3D::descriptor_origins().component);
    let vectors = rows::<[f32; 3]>(store, normal, Arrows3D::descriptor_vectors().component);
    let arrow_class = rows::<u16>(store, normal, Arrows3D::descriptor_class_ids().component);
    assert!(classes.len() > 3, "{status}: {} frames", classes.len());
    assert_eq!(
        classes.keys().collect::<Vec<_>>(),
        vectors.keys().collect::<Vec<_>>(),
        "{normal}: one row per frame"
    );
    let (mut stick, mut slip) = (0, 0);
    for (step, class) in &classes {
        assert_eq!(class.len(), points[step].len(), "{status} at step {step}");
        assert!(class.iter().all(|c| [OPEN, STICK, SLIP].contains(c)));
        let touching: Vec<usize> = (0..class.len()).filter(|&i| class[i] != OPEN).collect();
        let (o, v, c) = (&origins[step], &vectors[step], &arrow_class[step]);
        assert_eq!(v.len(), touching.len(), "{normal} at step {step}");
        for (a, &i) in touching.iter().enumerate() {
            assert_eq!(o[a], points[step][i], "{normal} at step {step}: origin");
            assert_eq!(c[a], class[i], "{normal} at step {step}: class");
            // The normal × NORMAL_FRACTION × extent, to f32 rounding of the positions the
            // expected normal is computed from (1e-7 of 0.1 m: 1e-6 of the normal).
            let n = expected(*step, i, points[step][i]);
            for k in 0..3 {
                let e = (f64::from(v[a][k]) - n[k] * length).abs();
                assert!(
                    e < 1e-5 * length,
                    "{normal} at step {step}, node {i}: {:?} vs {n:?}",
                    v[a]
                );
            }
        }
        stick += c.iter().filter(|&&x| x == STICK).count();
        slip += c.iter().filter(|&&x| x == SLIP).count();
    }
    (stick, slip)
}

/// A short, coarse indent (4 × 4 × 8 cells to 20 ms, the sphere 0.15 mm down): the pad's
/// glued base is pressed onto its plane (normal +z) and the sphere presses the top. Glued and contact-only nodes in contact get arrows along
/// their mould's normal — +z on the base, (x − c(t))/|x − c(t)| on the sphere of centre c(t)
/// at the frame (its logged translation) — and open nodes none.
#[test]
fn contact_nodes_carry_their_status_and_the_moulds_normal() {
    let scene = Path::new("scenes/indent.toml");
    let overrides = ["mesh.cells=[4,4,8]", "end_time=0.02"];
    let dir = scratch("rec", "contact_normals");
    let store = read_capture(&record(scene, &overrides, &dir));
    let set: Vec<String> = overrides.iter().map(|o| o.to_string()).collect();
    let model = load_scene(scene, &set).unwrap().model;
    let Shape::Sphere(decohesion_physics::mould::shapes::sphere::Sphere { centre, .. }) =
        model.moulds[1].shape
    else {
        panic!("the indent's second mould is the ball");
    };
    let length = NORMAL_FRACTION * 0.08; // the pad's largest side
    let base = |_: i64, _: usize, _: [f32; 3]| [0.0, 0.0, 1.0];
    let (stick, slip) = check_normals(
        &store,
        ("/interface/contact_status", "/interface/contact_normal"),
        &base,
        length,
    );
    assert!(stick + slip > 0, "no glued node in contact");
    let moved = rows::<[f32; 3]>(
        &store,
        "/planes/ball",
        Transform3D::descriptor_translation().component,
    );
    let ball = |step: i64, _: usize, x: [f32; 3]| {
        let d: [f64; 3] =
            std::array::from_fn(|k| f64::from(x[k]) - centre[k] - f64::from(moved[&step][0][k]));
        let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d.map(|c| c / r)
    };
    let (stick, slip) = check_normals(&store, ("/contact/nodes", "/contact/normal"), &ball, length);
    assert!(stick + slip > 0, "no node in contact with the sphere");
}

/// A box mould turning at a constant ω = (3, 4, 12) rad/s about a pivot off its centre while
/// its pivot moves at a constant v, above the indent's pad (never touching it): its logged
/// Transform3D at every frame is the analytic pose x = R(t)(x₀ − c₀) + c₀ + v t with
/// R(t) = exp([ω t]×), to f32 rounding.
#[test]
fn a_turning_moulds_transform_is_its_analytic_pose() {
    let dir = scratch("rec", "turning");
    let scene = turning::scene(&dir);
    let (omega, v, pivot) = (turning::OMEGA, turning::VELOCITY, turning::PIVOT);
    let store = read_capture(&record(&scene, &turning::OVERRIDES, &dir));
    let entity = "/planes/paddle";
    let matrices = rows::<[f32; 9]>(&store, entity, Transform3D::descriptor_mat3x3().component);
    let translations = rows::<[f32; 3]>(
        &store,
        entity,
        Transform3D::descriptor_translation().component,
    );
    // The frame times, on the sim_time timeline [ns].
    let step = TimelineName::from_static_str("step");
    let sim_time = TimelineName::from_static_str("sim_time");
    let mut times = std::collections::BTreeMap::new();
    for chunk in store.iter_physical_chunks() {
        if chunk.entity_path().to_string() != entity || chunk.is_static() {
            continue;
        }
        let component = Transform3D::descriptor_mat3x3().component;
        for ((n, _), (t, _)) in chunk
            .iter_component_indices(step, component)
            .zip(chunk.iter_component_indices(sim_time, component))
        {
            times.insert(n.as_i64(), t.as_i64() as f64 * 1e-9);
        }
    }
    assert!(matrices.len() > 10, "{} frames", matrices.len());
    let mut turned = 0.0f64;
    for (n, m) in &matrices {
        let t = times[n];
        let r = turning::rotation(omega.map(|w| w * t));
        // Rerun's Mat3x3 is column-major: m[3 j + i] = R_ij. The sim_time column holds t to
        // the nanosecond: |ω| × 0.5 ns = 7e-9 of angle; f32 rounding of entries ≤ 1: 6e-8.
        for i in 0..3 {
            for j in 0..3 {
                let e = (f64::from(m[0][3 * j + i]) - r[i][j]).abs();
                assert!(e < 2e-7, "step {n}, t = {t}: R[{i}][{j}] off by {e}");
            }
        }
        // T = c₀ + v t − R c₀.
        let rc0: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| r[i][j] * pivot[j]).sum());
        for i in 0..3 {
            let want = pivot[i] + v[i] * t - rc0[i];
            let e = (f64::from(translations[n][0][i]) - want).abs();
            assert!(e < 2e-7, "step {n}, t = {t}: T[{i}] off by {e} m");
        }
        turned = turned.max(13.0 * t);
    }
    // Over 0.05 s it turns 0.65 rad: far from the identity.
    assert!(turned > 0.6, "turned {turned} rad");
}
