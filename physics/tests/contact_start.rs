//! A contact face set that starts inside its mould is refused at load (model §7.7; a
//! glued one already was, `glued_start.rs`): contact acts on velocities, so such a node would
//! stay inside for the whole run. The tolerance is 1e-6 of the body's size, 1 µm on this 1 m
//! cube: 0.1 mm inside is refused with the face set, the mould, the node count and the depth;
//! 0.1 µm inside, on the mould, or off it load.

use crate::common;
use crate::common::scene_file;
use decohesion_physics::scene::parse_scene;

/// A 1 m cube resting on the plane z = `z0` by contact on its `z-` face (9 nodes), another
/// plane far off as a second mould.
fn scene(z0: &str) -> String {
    // The glued cube's mesh and material (common::GLUED_CUBE), with contact instead of glue.
    let head = &common::GLUED_CUBE[..common::GLUED_CUBE.find("[[plane]]").unwrap()];
    format!(
        r#"{head}
[[plane]]
name = "floor"
point = [0.0, 0.0, {z0}]
normal = [0.0, 0.0, 1.0]

[[plane]]
name = "wall"
point = [-1.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]

[[contact]]
faces = "x-"
plane = "wall"
mu = 0.2

[[contact]]
faces = "z-"
plane = "floor"
mu = 0.2
"#
    )
}

#[test]
fn a_contact_face_set_inside_its_mould_is_refused() {
    let file = scene_file("on_floor.toml").display().to_string();
    let e = parse_scene(&scene("1.0e-4"), &file, &[])
        .unwrap_err()
        .to_string();
    for part in [
        file.as_str(),
        "contact[1].faces",
        "\"z-\"",
        "9 of its nodes start inside mould `floor` by up to 1.0000e-4 m",
        "beyond the tolerance 1.0000e-6 m",
        "would never push them out",
    ] {
        assert!(e.contains(part), "missing {part:?} in:\n{e}");
    }
    // Within the tolerance, on the mould, or off it: loads.
    for z0 in ["1.0e-7", "0.0", "-1.0e-3"] {
        assert!(parse_scene(&scene(z0), &file, &[]).is_ok(), "z0 = {z0}");
    }
}
