//! Malformed scenes: each error must name the file, the key path and the offending value, and say
//! what is admissible. Each case edits one line of a valid scene.

use crate::common;
use crate::common::scene_file;
use decohesion_physics::law::families;
use decohesion_physics::scene::parse_scene;
use std::sync::LazyLock;

/// The scene's name in messages: a file of `scenes/`, so that its mesh files resolve there.
static FILE: LazyLock<String> = LazyLock::new(|| scene_file("bad.toml").display().to_string());

/// A valid scene; every case below breaks it in one place.
const VALID: &str = common::GLUED_CUBE;

/// The error for `VALID` with `from` replaced by `to` (which must occur), after `overrides`.
fn error(from: &str, to: &str, overrides: &[&str]) -> String {
    assert!(VALID.contains(from), "{from:?} is not in the valid scene");
    let text = VALID.replacen(from, to, 1);
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match parse_scene(&text, &FILE, &overrides) {
        Ok(_) => panic!("accepted: {from:?} -> {to:?} with {overrides:?}"),
        Err(e) => e.to_string(),
    }
}

fn assert_has(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "missing {part:?} in:\n{message}");
    }
}

#[test]
fn the_valid_scene_is_valid() {
    parse_scene(VALID, &FILE, &[]).unwrap();
}

#[test]
fn unknown_top_level_key() {
    let e = error("end_time = 0.3", "end_time = 0.3\ncolour = \"red\"", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `colour`",
            "colour = \"red\"",
            "unknown field",
            "`end_time`",
        ],
    );
}

#[test]
fn unknown_key_in_material() {
    let e = error("density = 1100.0", "density = 1100.0\nhardness = 40", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `material.hardness`",
            "hardness = 40",
            "expected one of `model`",
        ],
    );
}

#[test]
fn negative_density() {
    let e = error("density = 1100.0", "density = -1100.0", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `material.density` = -1100.0",
            "must be > 0 kg/m³",
        ],
    );
}

#[test]
fn poisson_one_half() {
    let e = error("poisson = 0.45", "poisson = 0.5", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `material.poisson` = 0.5",
            "-1 < ν < 0.5",
            "0.5 is incompressible",
        ],
    );
}

#[test]
fn poisson_above_one_half() {
    let e = error("poisson = 0.45", "poisson = 0.7", &[]);
    assert_has(&e, &[&FILE, "key `material.poisson` = 0.7", "-1 < ν < 0.5"]);
}

#[test]
fn table_law_with_increasing_stiffness() {
    let table = "family = \"table\"\npoints = [[0.0, 1e9], [1e-4, 2e9], [1e-3, 0.0]]";
    let e = error(
        "family = \"plateau_linear\"\ng_n0 = 2.0e9\nalpha_e = 5.0e-4\nu_r = 1.0e-3",
        table,
        &[],
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].law.points`",
            "g_N = 2000000000 at α = 0.0001",
            "non-increasing",
        ],
    );
}

#[test]
fn rupture_opening_not_beyond_elastic_range() {
    let e = error("u_r = 1.0e-3", "u_r = 5.0e-4", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].law.u_r` = 0.0005",
            "> α_e = 0.0005 m",
        ],
    );
}

#[test]
fn rupture_opening_below_elastic_range_via_override() {
    let text = VALID;
    let e = parse_scene(text, &FILE, &["interface.law.u_r=2e-4".to_string()])
        .unwrap_err()
        .to_string();
    assert_has(
        &e,
        &[
            &format!("{} (after --set overrides)", *FILE),
            "key `interface[0].law.u_r` = 0.0002",
            "> α_e = 0.0005 m",
        ],
    );
}

#[test]
fn unknown_face_set_lists_the_admissible_ones() {
    let e = error("faces = \"z-\"", "faces = \"bottom\"", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].faces` = \"bottom\"",
            "admissible: `x+`, `x-`",
            "`z-`",
        ],
    );
}

#[test]
fn empty_face_set_name() {
    let e = error("faces = \"z+\"", "faces = \"\"", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `displacement[0].faces` = \"\"",
            "no face set of that name",
        ],
    );
}

#[test]
fn zero_cells() {
    let e = error("cells = [2, 2, 2]", "cells = [2, 0, 2]", &[]);
    assert_has(&e, &[&FILE, "key `mesh.cells[1]` = 0", "integer ≥ 1"]);
}

#[test]
fn zero_end_time() {
    let e = error("end_time = 0.3", "end_time = 0", &[]);
    assert_has(&e, &[&FILE, "key `end_time` = 0.0", "must be > 0 s"]);
}

#[test]
fn negative_end_time() {
    let e = error("end_time = 0.3", "end_time = -0.3", &[]);
    assert_has(&e, &[&FILE, "key `end_time` = -0.3", "must be > 0 s"]);
}

#[test]
fn unknown_plane_name_lists_the_planes() {
    let e = error("plane = \"mould\"", "plane = \"mold\"", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].plane` = \"mold\"",
            "admissible: `mould`",
        ],
    );
}

#[test]
fn zero_plane_normal() {
    let e = error("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 0.0]", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `plane[0].normal` = [0.0, 0.0, 0.0]",
            "non-zero vector",
        ],
    );
}

#[test]
fn displacement_times_not_increasing() {
    let e = error(
        "table = [[0.0, 0.0], [0.3, 0.6]]",
        "table = [[0.0, 0.0], [0.3, 0.6], [0.2, 0.7]]",
        &[],
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `displacement[0].table[2][0]` = 0.2",
            "strictly increasing",
            "t = 0.3",
        ],
    );
}

#[test]
fn wrong_toml_type() {
    let e = error("cells = [2, 2, 2]", "cells = \"seven\"", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `mesh.cells`",
            "line 6",
            "\"seven\"",
            "invalid type: string",
        ],
    );
}

#[test]
fn toml_syntax_error() {
    let e = error("young = 5.0e6", "young = 5.0e6 Pa", &[]);
    assert_has(
        &e,
        &[&FILE, "TOML parse error at line 9", "young = 5.0e6 Pa"],
    );
}

#[test]
fn non_finite_number() {
    let e = error("g_n0 = 2.0e9", "g_n0 = nan", &[]);
    assert_has(&e, &[&FILE, "key `interface[0].law.g_n0` = NaN", "finite"]);
}

#[test]
fn law_key_of_another_family() {
    let e = error(
        "u_r = 1.0e-3",
        "u_r = 1.0e-3\npoints = [[0.0, 1.0], [1.0, 0.0]]",
        &[],
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].law.points` = [[0.0, 1.0], [1.0, 0.0]]",
            "not a parameter of the `plateau_linear` law",
        ],
    );
}

/// The message lists every family of the table (`bilinear`, …, `table`), so it needs no edit
/// when a family is added.
#[test]
fn unknown_law_family_lists_the_table() {
    let e = error("family = \"plateau_linear\"", "family = \"trilinear\"", &[]);
    let keys: Vec<String> = families().iter().map(|f| format!("`{}`", f.key)).collect();
    let admissible = format!(
        "no law family of that name; admissible: {}",
        keys.join(", ")
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].law.family` = \"trilinear\"",
            &admissible,
            "`plateau_linear`",
            "`table`",
        ],
    );
}

#[test]
fn law_parameter_of_the_wrong_type() {
    let e = error("g_n0 = 2.0e9", "g_n0 = \"stiff\"", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].law.g_n0` = \"stiff\"",
            "must be a number (Pa/m)",
        ],
    );
}

#[test]
fn bilinear_law_without_elastic_range() {
    let e = error(
        "family = \"plateau_linear\"\ng_n0 = 2.0e9\nalpha_e = 5.0e-4",
        "family = \"bilinear\"\ng_n0 = 2.0e9\nalpha_e = 0.0",
        &[],
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].law.alpha_e` = 0",
            "α_e must be finite and > 0 (m)",
            "the bilinear law",
        ],
    );
}

#[test]
fn exponential_decay_not_positive() {
    let e = error(
        "family = \"plateau_linear\"",
        "family = \"exponential\"\ndecay = -2.0",
        &[],
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].law.decay` = -2",
            "k must be finite and > 0",
        ],
    );
}

#[test]
fn duplicate_plane_name() {
    let second =
        "[[plane]]\nname = \"mould\"\npoint = [0, 0, 1]\nnormal = [0, 0, -1]\n\n[[interface]]";
    let e = error("[[interface]]", second, &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `plane[1].name` = \"mould\"",
            "unique",
            "`plane[0]`",
        ],
    );
}

#[test]
fn interface_and_contact_on_the_same_faces_and_plane() {
    let contact = "[[contact]]\nfaces = \"z-\"\nplane = \"mould\"\n\n[[displacement]]";
    let e = error("[[displacement]]", contact, &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `contact[0].faces` = \"z-\"",
            "already attached to plane `mould` by `interface[0]`",
        ],
    );
}

#[test]
fn ambiguous_override() {
    let second =
        "[[plane]]\nname = \"lid\"\npoint = [0, 0, 1]\nnormal = [0, 0, -1]\n\n[[interface]]";
    let text = VALID.replacen("[[interface]]", second, 1);
    let e = parse_scene(&text, &FILE, &["plane.normal=[0,1,0]".to_string()])
        .unwrap_err()
        .to_string();
    assert_has(
        &e,
        &[
            &FILE,
            "--set `plane.normal=[0,1,0]`",
            "2 elements",
            "`plane.0.normal`",
        ],
    );
}

proptest::proptest! {
    /// No input makes the loader panic: arbitrary edits of the valid scene, arbitrary overrides.
    #[test]
    fn never_panics(
        at in 0..VALID.len(),
        cut in 0usize..40,
        insert in "[\\[\\]=\".,a-z0-9_ \\n+-]{0,30}",
        set in proptest::collection::vec("[a-z_.0-9]{0,20}=?[\\[\\]0-9.,\"a-z-]{0,12}", 0..3),
    ) {
        let (start, end) = (at, (at + cut).min(VALID.len()));
        if VALID.is_char_boundary(start) && VALID.is_char_boundary(end) {
            let text = format!("{}{insert}{}", &VALID[..start], &VALID[end..]);
            let _ = parse_scene(&text, &FILE, &set);
        }
    }
}

#[test]
fn unknown_integration_rule() {
    let e = error(
        "end_time = 0.3",
        "end_time = 0.3\n[scheme]\nintegration = \"half\"",
        &[],
    );
    assert_has(
        &e,
        &[&FILE, "scheme.integration", "half", "`full`", "`reduced`"],
    );
}

#[test]
fn hourglass_coefficient_above_one() {
    let e = error(
        "end_time = 0.3",
        "end_time = 0.3\n[scheme]\nintegration = \"reduced\"\nhourglass_coefficient = 2.0",
        &[],
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `scheme.hourglass_coefficient` = 2",
            "must be in [0, 1]",
        ],
    );
}

#[test]
fn negative_initial_damage() {
    let e = error(
        "plane = \"mould\"\n[interface.law]",
        "plane = \"mould\"\ninitial_damage = -1e-4\n[interface.law]",
        &[],
    );
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].initial_damage` = -0.0001",
            "must be ≥ 0 m",
            "≥ u_r means ruptured from the start",
        ],
    );
    let e = error(
        "g_n0 = 2.0e9",
        "g_n0 = 2.0e9",
        &["interface.initial_damage=inf"],
    );
    assert_has(&e, &["key `interface[0].initial_damage` = inf", "finite"]);
}

/// The box of `VALID`, and a Gmsh mesh file instead (the tread block, relative to `scenes/`).
const BOX: &str = "[mesh]\nsize = [1.0, 1.0, 1.0]\ncells = [2, 2, 2]";
const MESH_FILE: &str = "[mesh]\nfile = \"meshes/tread_block.msh\"\nscale = 0.001";

#[test]
fn mesh_file_and_box_keys_exclude_each_other() {
    let e = error(BOX, &format!("{MESH_FILE}\ncells = [2, 2, 2]"), &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `mesh.cells` = [2, 2, 2]",
            "`mesh.file` is given",
            "either a Gmsh file",
        ],
    );
}

#[test]
fn box_without_cells() {
    let e = error("cells = [2, 2, 2]", "", &[]);
    assert_has(
        &e,
        &[&FILE, "key `mesh.cells` is missing", "a box mesh needs"],
    );
}

#[test]
fn missing_mesh_file() {
    let e = error(BOX, "[mesh]\nfile = \"meshes/nowhere.msh\"", &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `mesh.file` = \"meshes/nowhere.msh\"",
            "scenes/meshes/nowhere.msh: cannot read the mesh file",
        ],
    );
}

#[test]
fn unknown_physical_group() {
    // The tread block's face sets are its physical groups; `z-` is a box's.
    let e = error(BOX, MESH_FILE, &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `interface[0].faces` = \"z-\"",
            "admissible: `bottom`, `groove`, `sides`, `top`",
        ],
    );
}

#[test]
fn mesh_scale_not_positive() {
    let e = error(BOX, &MESH_FILE.replace("0.001", "-1.0"), &[]);
    assert_has(&e, &[&FILE, "key `mesh.scale` = -1.0", "must be > 0"]);
}

#[test]
fn mesh_scale_with_a_box() {
    let e = error(BOX, &format!("{BOX}\nscale = 0.001"), &[]);
    assert_has(
        &e,
        &[
            &FILE,
            "key `mesh.scale` = 0.001",
            "applies to a `mesh.file` only",
        ],
    );
}
