//! Malformed `[[mould]]` sections (model §7.1) — each error names the file, the key and the value
//! and says what is admissible. Each case adds one mould to a valid scene.

use crate::common;
use crate::common::scene_file;
use decohesion_physics::scene::parse_scene;

/// The scene's name in messages: a file of `scenes/`, so that mould files resolve there.
fn file() -> String {
    scene_file("bad.toml").display().to_string()
}

/// The error of the glued cube with `mould` added (and its interface on `plane`).
fn error(mould: &str, plane: &str) -> String {
    let text = common::GLUED_CUBE.replacen("plane = \"mould\"", &format!("plane = \"{plane}\""), 1)
        + "\n[[mould]]\n"
        + mould;
    match parse_scene(&text, &file(), &[]) {
        Ok(_) => panic!("accepted:\n{mould}"),
        Err(e) => e.to_string(),
    }
}

fn assert_has(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "missing {part:?} in:\n{message}");
    }
}

#[test]
fn a_valid_sphere_mould_is_valid() {
    let text = common::GLUED_CUBE.to_string()
        + "\n[[mould]]\nname = \"ball\"\nshape = \"sphere\"\ncentre = [0.5, 0.5, 2.0]\nradius = 0.5\nangular_velocity = [[0.0, 0.0, 0.0, 1.0]]\n";
    let scene = parse_scene(&text, &file(), &[]).unwrap();
    assert_eq!(scene.model.planes[1].pivot(), [0.5, 0.5, 2.0]);
}

#[test]
fn unknown_shape_lists_the_shapes() {
    let e = error("name = \"m\"\nshape = \"cone\"\n", "mould");
    assert_has(
        &e,
        &[
            &file(),
            "key `mould[0].shape` = \"cone\"",
            "half_space, box, sphere, cylinder, surface",
        ],
    );
}

#[test]
fn a_key_of_another_shape_is_refused() {
    let e = error("name = \"m\"\nshape = \"sphere\"\ncentre = [0.0, 0.0, 0.0]\nradius = 1.0\nnormal = [0.0, 0.0, 1.0]\n", "mould");
    assert_has(
        &e,
        &[
            "key `mould[0].normal` = [0.0, 0.0, 1.0]",
            "a sphere mould takes centre, radius",
        ],
    );
}

#[test]
fn missing_and_bad_lengths() {
    let e = error(
        "name = \"m\"\nshape = \"sphere\"\ncentre = [0.0, 0.0, 0.0]\n",
        "mould",
    );
    assert_has(
        &e,
        &[
            "key `mould[0].radius` is missing",
            "a sphere mould needs centre, radius",
        ],
    );
    let e = error(
        "name = \"m\"\nshape = \"sphere\"\ncentre = [0.0, 0.0, 0.0]\nradius = -1.0\n",
        "mould",
    );
    assert_has(&e, &["key `mould[0].radius` = -1.0", "must be > 0 m"]);
}

#[test]
fn zero_axis_and_zero_rotation_are_refused() {
    let e = error("name = \"m\"\nshape = \"cylinder\"\ncentre = [0.0, 0.0, 0.0]\naxis = [0.0, 0.0, 0.0]\nradius = 1.0\nlength = 1.0\n", "mould");
    assert_has(
        &e,
        &["key `mould[0].axis` = [0.0, 0.0, 0.0]", "non-zero vector"],
    );
    let e = error("name = \"m\"\nshape = \"sphere\"\ncentre = [0.5, 0.5, 3.0]\nradius = 1.0\nangular_velocity = [[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]\n", "mould");
    assert_has(&e, &["key `mould[0].angular_velocity`", "no rotation axis"]);
}

#[test]
fn a_pivot_that_is_not_a_point() {
    let e = error("name = \"m\"\nshape = \"sphere\"\ncentre = [0.5, 0.5, 3.0]\nradius = 1.0\npivot = [1.0, 2.0]\n", "mould");
    assert_has(&e, &["key `mould[0].pivot`", "length 3"]);
}

#[test]
fn surfaces_from_bad_files() {
    // Not an STL (a text file that is not `solid … facet`, nor a binary STL's length).
    let e = error(
        "name = \"m\"\nshape = \"surface\"\nfile = \"README.md\"\n",
        "mould",
    );
    assert_has(
        &e,
        &["key `mould[0].file` = \"README.md\"", ": not an STL file"],
    );
    // A Gmsh file without the named group: the groups it has are listed.
    let e = error(
        "name = \"m\"\nshape = \"surface\"\nfile = \"meshes/tread_block.msh\"\ngroup = \"ribs\"\n",
        "mould",
    );
    assert_has(
        &e,
        &[
            "key `mould[0].file` = \"meshes/tread_block.msh\"",
            "no 2-D physical group named \"ribs\"",
            "the file has:",
        ],
    );
    let e = error(
        "name = \"m\"\nshape = \"surface\"\nfile = \"meshes/tread_block.msh\"\n",
        "mould",
    );
    assert_has(&e, &["key `mould[0].group` is missing"]);
}

/// A glued face inside a sphere mould at t = 0 by 0.1 m (the sphere's top at z = 0.1 above the
/// glued face at z = 0), far beyond the tolerance: refused, with the depth.
#[test]
fn a_mould_intersecting_the_glued_face_is_refused() {
    let e = error(
        "name = \"ball\"\nshape = \"sphere\"\ncentre = [0.5, 0.5, -0.4]\nradius = 0.5\n",
        "ball",
    );
    assert_has(
        &e,
        &[
            "key `interface[0].faces` = \"z-\"",
            "start inside mould `ball` by up to 1.0000e-1 m",
        ],
    );
}

#[test]
fn plane_and_mould_names_are_one_namespace() {
    let e = error(
        "name = \"mould\"\nshape = \"sphere\"\ncentre = [0.5, 0.5, 3.0]\nradius = 1.0\n",
        "mould",
    );
    assert_has(
        &e,
        &[
            "key `mould[0].name` = \"mould\"",
            "must be unique (`plane[0]` has it already)",
        ],
    );
}
