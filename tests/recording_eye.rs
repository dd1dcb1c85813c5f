//! The 3-D view's default eye in the capture: the blueprint store of
//! the `.rrd` carries an `EyeControls3D` under the 3-D view's path, looking at the centre of
//! the body's bounding box at t = 0, from where the whole body box — and the half-space
//! moulds' squares drawn around it — are inside the view's frustum.

use crate::common;

use crate::common::cli::decohesion_ok;
use decohesion::output::surface::mould::{body_box, mould_drawing};
use decohesion::scene::load_scene;
use rerun::external::re_sdk_types::blueprint::archetypes::{EyeControls3D, ViewBlueprint};
use rerun::{ChunkStore, ChunkStoreConfig};
use std::path::Path;

/// The viewer's vertical field of view (rerun 0.36 `re_view_spatial`'s `Eye::DEFAULT_FOV_Y`,
/// which the blueprint does not set).
const FOV_Y_DEG: f64 = 55.0;
/// Width / height of the 3-D view: in the default layout it is the left half of the window,
/// 780 × 880 px in the 1560 × 960 screenshots (0.89); 0.75 leaves room for a narrower window.
const ASPECT: f64 = 0.75;

/// What the blueprint says of the 3-D view's eye: position, look target, up.
struct EyeRead {
    position: [f64; 3],
    target: [f64; 3],
    up: [f64; 3],
}

/// Reads the eye of the 3-D view from the capture's blueprint store: the one `EyeControls3D`
/// entity, under a view whose `ViewBlueprint` class is "3D".
fn read_eye(rrd: &Path) -> EyeRead {
    let mut file = std::fs::File::open(rrd).unwrap();
    let stores = ChunkStore::from_rrd_reader(&ChunkStoreConfig::DEFAULT, &mut file).unwrap();
    let blueprints: Vec<&ChunkStore> = stores.values().filter(|s| s.id().is_blueprint()).collect();
    assert_eq!(blueprints.len(), 1, "one blueprint in {}", rrd.display());
    let store = blueprints[0];
    let one = |component| -> Option<(String, [f64; 3])> {
        store.iter_physical_chunks().find_map(|chunk| {
            let path = chunk.entity_path().to_string();
            let v = chunk
                .iter_slices::<[f32; 3]>(component)
                .next()?
                .first()?
                .map(f64::from);
            Some((path, v))
        })
    };
    let (path, position) = one(EyeControls3D::descriptor_position().component).expect("an eye");
    let (p2, target) = one(EyeControls3D::descriptor_look_target().component).expect("a target");
    let (p3, up) = one(EyeControls3D::descriptor_eye_up().component).expect("an up");
    assert!(path == p2 && path == p3, "{path} {p2} {p3}");
    let view = path
        .strip_suffix("/EyeControls3D")
        .unwrap_or_else(|| panic!("the eye is a view property: {path}"));
    assert!(view.starts_with("/view/"), "{view}");
    // That view is the 3-D one.
    let class = ViewBlueprint::descriptor_class_identifier().component;
    let classes: Vec<String> = store
        .iter_physical_chunks()
        .filter(|c| c.entity_path().to_string() == view)
        .flat_map(|c| c.iter_slices::<String>(class).flatten().collect::<Vec<_>>())
        .map(|s| s.to_string())
        .collect();
    assert_eq!(classes, ["3D"], "{view}");
    EyeRead {
        position,
        target,
        up,
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i] - b[i])
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| a[i] * b[i]).sum()
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    a.map(|c| c / n)
}

/// Is x inside the frustum of a perspective eye at `e.position` looking at `e.target`, up
/// `e.up`, vertical field of view [`FOV_Y_DEG`], width / height [`ASPECT`]? Its view-space
/// coordinates (right, up, forward) must satisfy |right| ≤ forward · a tan(fov/2), |up| ≤
/// forward · tan(fov/2), forward > 0.
fn in_frustum(e: &EyeRead, x: [f64; 3]) -> bool {
    let f = unit(sub(e.target, e.position));
    let r = unit(cross(f, e.up));
    let u = cross(r, f);
    let v = sub(x, e.position);
    let (x_r, x_u, x_f) = (dot(v, r), dot(v, u), dot(v, f));
    let t = (0.5 * FOV_Y_DEG.to_radians()).tan();
    x_f > 0.0 && x_r.abs() <= x_f * ASPECT * t && x_u.abs() <= x_f * t
}

fn corners((lo, hi): ([f64; 3], [f64; 3])) -> Vec<[f64; 3]> {
    (0..8)
        .map(|c| std::array::from_fn(|i| if c >> i & 1 == 0 { lo[i] } else { hi[i] }))
        .collect()
}

/// Runs `scene` for a few steps with a capture (the eye is placed at t = 0) and checks it.
fn check_scene(scene: &str, end_time: &str) {
    let path = format!("scenes/{scene}.toml");
    let dir = common::cli::scratch("rec", &format!("eye_{scene}"));
    let rrd = dir.join(format!("{scene}.rrd"));
    let end = format!("end_time={end_time}");
    decohesion_ok(&[
        "run",
        &path,
        "--quiet",
        "--set",
        &end,
        "--save",
        rrd.to_str().unwrap(),
    ]);
    let eye = read_eye(&rrd);
    let model = load_scene(Path::new(&path), &[end]).unwrap().model;
    // The body's box from the mesh's reference nodes (what U = 0 at t = 0 places).
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for x in &model.mesh.nodes {
        for i in 0..3 {
            lo[i] = lo[i].min(x[i]);
            hi[i] = hi[i].max(x[i]);
        }
    }
    let centre: [f64; 3] = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
    // The target: the body's centre, to the f32 the blueprint stores (ulp 6e-8 relative).
    let err = dot(sub(eye.target, centre), sub(eye.target, centre)).sqrt();
    assert!(
        err <= 1e-6 * dot(centre, centre).sqrt(),
        "{scene}: target {:?} vs body centre {centre:?}",
        eye.target
    );
    assert_eq!(eye.up, [0.0, 0.0, 1.0], "{scene}: z up");
    // The whole body box is seen, and so is each half-space's square drawn around it.
    for x in corners((lo, hi)) {
        assert!(
            in_frustum(&eye, x),
            "{scene}: body corner {x:?} outside the view"
        );
    }
    for p in &model.moulds {
        if p.shape.is_half_space() {
            for x in mould_drawing(p, body_box(&model)).vertices {
                assert!(
                    in_frustum(&eye, x),
                    "{scene}: {} corner {x:?} unseen",
                    p.name
                );
            }
        }
    }
    // Not from too far either: the body's box takes at least a fifth of the view's height
    // (its centre's distance d, the box's diagonal D: D/d ≥ 0.4 tan(fov/2)).
    let d = dot(sub(centre, eye.position), sub(centre, eye.position)).sqrt();
    let diag = dot(sub(hi, lo), sub(hi, lo)).sqrt();
    let t = (0.5 * FOV_Y_DEG.to_radians()).tan();
    assert!(
        diag / d >= 0.4 * t,
        "{scene}: body {diag} m seen from {d} m"
    );
}

#[test]
fn demould_opens_with_the_block_and_its_cavity_in_view() {
    check_scene("demould", "1e-4");
}

#[test]
fn tread_demould_opens_with_the_tread_and_ribs_in_view() {
    check_scene("tread_demould", "1e-5");
}

#[test]
fn roller_peel_opens_with_the_strip_and_roller_in_view() {
    check_scene("roller_peel", "1e-4");
}
