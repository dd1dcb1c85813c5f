//! Malformed `[[mould]]` sections (model §7.1) — each error names the file, the key and the value
//! and says what is admissible. Each case adds one mould to a valid scene.

use crate::common;
use crate::common::scene_file;
use crate::corpus;
use decohesion_physics::mould::open_surface_warnings;
use decohesion_physics::mould::surface::{read_stl, WELD_TOLERANCE};
use decohesion_physics::mould::SurfaceMesh;
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
    assert_eq!(scene.model.moulds[1].pivot(), [0.5, 0.5, 2.0]);
}

#[test]
fn unknown_shape_lists_the_shapes() {
    let e = error("name = \"m\"\nshape = \"cone\"\n", "mould");
    assert_has(
        &e,
        &[
            &file(),
            "key `mould[0].shape` = \"cone\"",
            "box, cylinder, half_space, sphere, surface",
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

/// An STL file of the bad-input corpus (`tests/data/bad_input/`), read and checked.
fn stl(file: &str) -> Result<SurfaceMesh, String> {
    let bytes = std::fs::read(corpus::dir().join(file)).unwrap();
    let (v, t) = read_stl(&bytes, file).map_err(|e| e.to_string())?;
    SurfaceMesh::new(file, None, 1.0, v, t, &|k| format!("facet {k}")).map_err(|e| e.to_string())
}

/// The unit cube's 12 outward triangles, three vertices of their own each, vertex j of
/// triangle k moved along x by `shift(3k + j)`.
fn cube_soup(shift: &dyn Fn(usize) -> f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let corner = |i: usize| [(i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2) as f64];
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut vertices = Vec::new();
    for [a, b, c, d] in quads {
        for tri in [[a, b, c], [a, c, d]] {
            for i in tri {
                let mut x = corner(i);
                x[0] += shift(vertices.len());
                vertices.push(x);
            }
        }
    }
    let triangles = (0..12u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
    (vertices, triangles)
}

/// Corners written twice a little apart are one vertex within the weld tolerance
/// (10⁻⁶ × the diagonal √3 here), and stay apart beyond it.
#[test]
fn vertices_within_the_weld_tolerance_are_welded() {
    let diagonal = 3f64.sqrt();
    let near = |i: usize| 0.9 * WELD_TOLERANCE * diagonal * (i % 5) as f64 / 5.0;
    let (v, t) = cube_soup(&near);
    let s = SurfaceMesh::new("cube", None, 1.0, v, t, &|k| format!("triangle {k}")).unwrap();
    assert_eq!((s.open_edges, s.mesh.vertices().len()), (0, 8));
    // Inside the closed cube, 0.2 below its top face: the gap is −0.2 along the top's normal.
    let p = s.project([0.5, 0.5, 0.8]);
    assert_eq!(p.normal, [0.0, 0.0, 1.0]);
    let far = |i: usize| 1e-4 * (i % 5) as f64;
    let (v, t) = cube_soup(&far);
    let s = SurfaceMesh::new("cube", None, 1.0, v, t, &|k| format!("triangle {k}")).unwrap();
    assert!(s.open_edges > 0, "{} open edges", s.open_edges);
    // The corpus's box whose facets repeat their corners 1e-12 apart, as two writers would.
    let s = stl("valid/box_jittered.stl").unwrap();
    assert_eq!((s.open_edges, s.mesh.vertices().len()), (0, 8));
}

/// A surface with a rim is accepted, its open edges counted, and the warning names them.
#[test]
fn open_edges_are_counted_and_reported() {
    assert_eq!(stl("valid/box.stl").unwrap().open_edges, 0);
    assert_eq!(stl("valid/box_open.stl").unwrap().open_edges, 4);
    let corpus = crate::corpus::corpus();
    let text = corpus.template.stl.replace("{file}", "valid/box_open.stl");
    let file = corpus::dir().join("stl_scene.toml").display().to_string();
    let scene = parse_scene(&text, &file, &[]).unwrap();
    let warnings = open_surface_warnings(&scene.model.moulds);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_has(
        &warnings[0],
        &["mould `wall`", "valid/box_open.stl", "is open (4 edges"],
    );
}

/// Two triangles folded onto each other across their edge: the edge's pseudo-normal n₁ + n₂
/// is zero and the gap NaN; refused, naming both. So is a vertex where two triangles meet
/// tip to tip facing opposite ways (its pseudo-normal is zero, no edge shared).
#[test]
fn folded_surfaces_are_refused_naming_the_triangles() {
    for file in ["stl/folded_pair.stl", "stl/folded_sheet.stl"] {
        let e = stl(file).unwrap_err();
        assert_has(
            &e,
            &[
                file,
                "facet 0 and facet 1 share an edge and face opposite ways",
                "folds back",
            ],
        );
    }
    let e = stl("stl/bowtie_vertex.stl").unwrap_err();
    assert_has(
        &e,
        &["the normals of the triangles around a vertex cancel (facet 0, facet 1)"],
    );
}

/// A NaN or an infinite coordinate is refused with the facet and the vertex, not taken for a
/// degenerate triangle.
#[test]
fn non_finite_coordinates_are_refused_naming_the_facet() {
    let e = stl("stl/ascii_nan_vertex.stl").unwrap_err();
    assert_has(&e, &["facet 0 has a non-finite coordinate at its vertex 0"]);
    let e = stl("stl/binary_inf_vertex.stl").unwrap_err();
    assert_has(&e, &["facet 5 has a non-finite coordinate at its vertex 0"]);
}
