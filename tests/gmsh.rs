//! Gmsh meshes (physics/src/gmsh/): a box written as `.msh` and read back is `Mesh::boxed` and runs the
//! pull-off exactly as the box does; the grooved tread block of scenes/tread.toml has the analytic
//! volume and areas, and tears off; bad files are refused with the file and the item named.

#[allow(dead_code)]
#[path = "../examples/tread_block.rs"]
mod tread_block;

use decohesion::gmsh::{msh_text, parse_msh, read_msh};
use decohesion::mesh::{Mesh, HEX_CORNERS};
use decohesion::scene::{load_scene, parse_scene};
use decohesion::solver::Simulation;
use std::path::PathBuf;

/// A fresh directory for one test's files.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("decohesion-gmsh-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn volume(m: &Mesh) -> f64 {
    let cls = m.element_classes().unwrap();
    cls.class_of
        .iter()
        .map(|&c| cls.data[c as usize].volume())
        .sum()
}

fn area(m: &Mesh, set: &str) -> f64 {
    m.nodal_areas(&m.face_sets[set]).iter().map(|p| p.1).sum()
}

fn centre(m: &Mesh, nodes: &[u32]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &n in nodes {
        for (ck, xk) in c.iter_mut().zip(m.nodes[n as usize]) {
            *ck += xk / nodes.len() as f64;
        }
    }
    c
}

/// Every quad of every face set points away from the centre of the hexahedron it bounds.
fn assert_outward(m: &Mesh) {
    let mut owner = std::collections::HashMap::new();
    for (q, e) in m.boundary_faces() {
        let mut k = q;
        k.sort_unstable();
        owner.insert(k, e);
    }
    for (name, quads) in &m.face_sets {
        for q in quads {
            let mut k = *q;
            k.sort_unstable();
            let e = owner[&k];
            let (cf, ce) = (centre(m, q), centre(m, &m.elements[e as usize]));
            let n = m.quad_normal(q);
            let d: f64 = (0..3).map(|i| n[i] * (cf[i] - ce[i])).sum();
            assert!(d > 0.0, "{name}: quad {q:?} points into its element");
        }
    }
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn box_round_trip_is_mesh_boxed() {
    let boxed = Mesh::boxed([0.1, -0.2, 0.0], [1.0, 2.0, 3.0], [3, 4, 5]);
    // What a Gmsh file may hold and the reader must undo: a node no element uses (first, so
    // every index shifts) and quads oriented inwards.
    let mut m = boxed.clone();
    m.nodes.insert(0, [9.0, 9.0, 9.0]);
    for conn in &mut m.elements {
        *conn = conn.map(|n| n + 1);
    }
    for quads in m.face_sets.values_mut() {
        for q in quads.iter_mut() {
            *q = [q[3] + 1, q[2] + 1, q[1] + 1, q[0] + 1];
        }
    }
    let text = msh_text(&m);
    let back = parse_msh(text.as_bytes(), "box.msh").unwrap();
    // Shortest round-trip decimals: the coordinates come back bit for bit.
    assert_eq!(back.nodes, boxed.nodes);
    assert_eq!(back.elements, boxed.elements);
    assert_eq!(
        back.face_sets.keys().collect::<Vec<_>>(),
        boxed.face_sets.keys().collect::<Vec<_>>()
    );
    assert!(rel(volume(&back), volume(&boxed)) < 1e-12);
    assert!(rel(volume(&back), 6.0) < 1e-12);
    for name in boxed.face_sets.keys() {
        assert!(
            rel(area(&back, name), area(&boxed, name)) < 1e-12,
            "{name}: {} vs {}",
            area(&back, name),
            area(&boxed, name)
        );
        // Same quads (as node sets), now outward again.
        let sorted = |m: &Mesh| {
            let mut v: Vec<[u32; 4]> = m.face_sets[name]
                .iter()
                .map(|q| {
                    let mut k = *q;
                    k.sort_unstable();
                    k
                })
                .collect();
            v.sort_unstable();
            v
        };
        assert_eq!(sorted(&back), sorted(&boxed), "{name}");
    }
    assert_outward(&back);
}

/// The pull-off scene with its box replaced by the same box read from a `.msh` file.
#[test]
fn box_from_a_file_runs_the_pull_off_as_the_box() {
    let dir = scratch("pull_off");
    let text = std::fs::read_to_string("scenes/pull_off.toml").unwrap();
    let (start, end) = (
        text.find("[mesh]").unwrap(),
        text.find("[material]").unwrap(),
    );
    let file_text = format!(
        "{}[mesh]\nfile = \"box.msh\"\n\n{}",
        &text[..start],
        &text[end..]
    );
    std::fs::write(
        dir.join("box.msh"),
        msh_text(&Mesh::boxed([0.0; 3], [1.0; 3], [7, 7, 7])),
    )
    .unwrap();
    let scene_path = dir.join("pull_off_from_file.toml");
    std::fs::write(&scene_path, &file_text).unwrap();
    let run = |scene: decohesion::scene::Scene| {
        let mut sim = Simulation::new(scene.model).unwrap();
        sim.run(|_| true).unwrap();
        sim
    };
    let a = run(load_scene("scenes/pull_off.toml".as_ref(), &[]).unwrap());
    let b = run(load_scene(&scene_path, &[]).unwrap());
    assert_eq!(b.state.interface_nodes.len(), 64);
    assert_eq!(a.state.step_count, b.state.step_count);
    // The same mesh up to the order of the nodes inside each boundary quad, which changes only
    // the summation order of the tributary areas: round-off.
    let (ta, tb) = (
        a.stats.time_full_rupture.unwrap(),
        b.stats.time_full_rupture.unwrap(),
    );
    assert_eq!(ta, tb, "full rupture at {ta} s (box) and {tb} s (file)");
    let (da, db) = (
        a.state.ledger.damage_dissipated,
        b.state.ledger.damage_dissipated,
    );
    // Measured: identical to the bit (the glued and pulled z∓ quads even come back in the box's
    // node order); 1e-12 allows the round-off a different quad order would bring.
    assert!(
        rel(db, da) < 1e-12,
        "dissipated {da} J (box), {db} J (file)"
    );
    let (pa, pb) = (a.stats.peaks[0].force, b.stats.peaks[0].force);
    assert!(rel(pb, pa) < 1e-12, "peak {pa} N (box), {pb} N (file)");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn tread_block_file_is_reproducible() {
    let committed = std::fs::read_to_string(tread_block::PATH).unwrap();
    assert!(
        committed == tread_block::text(),
        "{} differs from what `cargo run --example tread_block` writes: regenerate it",
        tread_block::PATH
    );
}

#[test]
fn tread_block_volume_areas_and_orientation() {
    let m = read_msh(tread_block::PATH.as_ref()).unwrap();
    // The generator's mesh exactly (it has no unused node), renumbered in slabs across its
    // longest side (x) as the reader does.
    let g = tread_block::mesh().with_nodes_in_slabs();
    assert_eq!((m.nodes.len(), m.elements.len()), (5328, 4260));
    assert_eq!(m.nodes, g.nodes);
    assert_eq!(m.elements, g.elements);
    // Trilinear hexahedra whose faces are planar and whose edges are straight have the exact
    // volume of the polyhedra: the block minus two trapezoidal prisms, to round-off [mm³].
    let v = volume(&m);
    assert!(rel(v, 33_120.0) < 1e-12, "volume {v} mm³");
    assert_eq!(tread_block::volume(), 33_120.0);
    let wall = (2.0f64 * 2.0 + 8.0 * 8.0).sqrt();
    for (set, exact) in [
        ("bottom", 60.0 * 30.0),
        ("top", (16.0 + 12.0 + 16.0) * 30.0),
        ("groove", 2.0 * 30.0 * (4.0 + 2.0 * wall)),
        (
            "sides",
            2.0 * 30.0 * 20.0 + 2.0 * (60.0 * 20.0 - 2.0 * 6.0 * 8.0),
        ),
    ] {
        let a = area(&m, set);
        assert!(rel(a, exact) < 1e-12, "{set}: {a} mm² vs {exact}");
    }
    assert_outward(&m);
    for q in &m.face_sets["bottom"] {
        assert_eq!(m.quad_normal(q), [0.0, 0.0, -1.0]);
    }
    // Not a box: the rib elements under the leaning groove walls have other shapes.
    assert!(m.element_classes().unwrap().data.len() > 1);
}

/// scenes/tread.toml: the rib tops pulled up tear the whole bottom off.
#[test]
fn tread_scene_tears_off() {
    let scene = load_scene("scenes/tread.toml".as_ref(), &[]).unwrap();
    let m = &scene.model;
    // scale = 0.001: the file's millimetres are metres here.
    let v = volume(&m.mesh);
    assert!(rel(v, 33_120e-9) < 1e-12, "volume {v} m³");
    let mut sim = Simulation::new(scene.model).unwrap();
    sim.run(|_| true).unwrap();
    // 31 × 16 nodes on the bottom, all ruptured, before the end.
    let n = sim.state.interface_nodes.len();
    assert_eq!(n, 496);
    assert_eq!(sim.state_counts().ruptured, n);
    let t = sim
        .stats
        .time_full_rupture
        .expect("the block must tear off");
    assert!(t < 0.75 * sim.model.end_time, "full rupture at {t} s");
    for itf in &sim.state.interface_nodes {
        assert!(itf.gap > 0.0, "node {} still on the plate", itf.node);
    }
    // Every node ruptured: the damage dissipation is G_c × 1800 mm² up to the discrete rupture
    // steps (O(h), +1.5 % measured; the same bounds as the pull-off test).
    let gc_area = sim.model.interfaces[0].law.fracture_energy() * 1.8e-3;
    let d = sim.state.ledger.damage_dissipated;
    assert!(
        d >= 0.99 * gc_area && d <= 1.08 * gc_area,
        "damage dissipation {d} J vs G_c·A {gc_area} J"
    );
    assert!(
        sim.state.ledger.max_relative_residual < 1e-3,
        "residual {}",
        sim.state.ledger.max_relative_residual
    );
}

/// A unit cube as one hexahedron, written by hand the way Gmsh writes files: sparse node tags,
/// a geometry point whose node no element uses, a named and an unnamed physical surface group,
/// the bottom quad oriented into the body. `extra` is appended to the volume's element block
/// (with the element count adjusted by `extra_count`).
fn one_hex(hex: &str, extra: &str, extra_count: usize) -> String {
    format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
         $PhysicalNames\n2\n2 7 \"floor\"\n3 1 \"body\"\n$EndPhysicalNames\n\
         $Entities\n1 0 2 1\n\
         1 5 5 5 0\n\
         1 0 0 0 1 1 0 1 7 0\n\
         2 0 0 1 1 1 1 1 8 0\n\
         1 0 0 0 1 1 1 1 1 2 1 2\n\
         $EndEntities\n\
         $Nodes\n2 9 11 100\n\
         0 1 0 1\n100\n5 5 5\n\
         3 1 0 8\n11\n13\n15\n17\n19\n21\n23\n25\n\
         0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
         $EndNodes\n\
         $Elements\n3 {} 1 {}\n\
         3 1 5 {}\n1 {hex}\n{extra}\
         2 1 3 1\n2 11 13 15 17\n\
         2 2 3 1\n3 19 21 23 25\n\
         $EndElements\n",
        3 + extra_count,
        3 + extra_count,
        1 + extra_count,
    )
}

const HEX: &str = "11 13 15 17 19 21 23 25";

#[test]
fn hand_written_file_with_sparse_tags_and_geometry_points() {
    let m = parse_msh(one_hex(HEX, "", 0).as_bytes(), "cube.msh").unwrap();
    // The unit cube's corners in the order of the file, which is Gmsh's hexahedron order.
    let corners: Vec<[f64; 3]> = HEX_CORNERS
        .iter()
        .map(|c| c.map(|x| 0.5 * (x + 1.0)))
        .collect();
    assert_eq!(m.nodes, corners, "the geometry point's node is dropped");
    assert_eq!(m.elements, [[0, 1, 2, 3, 4, 5, 6, 7]]);
    assert!(rel(volume(&m), 1.0) < 1e-15);
    assert_eq!(
        m.face_sets.keys().collect::<Vec<_>>(),
        ["floor", "physical_8"]
    );
    assert_eq!(m.quad_normal(&m.face_sets["floor"][0]), [0.0, 0.0, -1.0]);
    assert_eq!(
        m.quad_normal(&m.face_sets["physical_8"][0]),
        [0.0, 0.0, 1.0]
    );
    assert!(rel(area(&m, "floor"), 1.0) < 1e-15);
}

/// Reads `text` as `file` and returns the error message.
fn msh_error(text: &str) -> String {
    parse_msh(text.as_bytes(), "dir/bad.msh")
        .unwrap_err()
        .to_string()
}

fn assert_has(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "missing {part:?} in:\n{message}");
    }
}

#[test]
fn non_hexahedral_volume_element_is_named() {
    // A tetrahedron (type 4) of negative volume beside the hexahedron.
    let text = one_hex(HEX, "", 0).replace(
        "3 1 5 1\n1 11 13 15 17 19 21 23 25\n",
        "3 1 5 1\n1 11 13 15 17 19 21 23 25\n3 1 4 1\n4 11 15 13 19\n",
    );
    let text = text.replace("$Elements\n3 3 1 3", "$Elements\n4 4 1 4");
    let e = msh_error(&text);
    assert_has(
        &e,
        &[
            "dir/bad.msh",
            "element 4 (tetrahedron) has volume -1.66666",
            "a negative one is inverted",
        ],
    );
    // The same tetrahedron the right way round: a mixed mesh of one hexahedron and one
    // tetrahedron (model §1.13), volume 1/6.
    let text = one_hex(HEX, "", 0)
        .replace(
            "3 1 5 1\n1 11 13 15 17 19 21 23 25\n",
            "3 1 5 1\n1 11 13 15 17 19 21 23 25\n3 1 4 1\n4 11 13 15 19\n",
        )
        .replace("$Elements\n3 3 1 3", "$Elements\n4 4 1 4");
    let m = parse_msh(text.as_bytes(), "dir/mixed.msh").unwrap();
    assert_eq!((m.elements.len(), m.tets.len()), (1, 1));
    assert!((m.tet_data().unwrap().volume[0] - 1.0 / 6.0).abs() < 1e-15);
    // A prism (type 6) beside it: refused, with the types that are read.
    let text = one_hex(HEX, "", 0)
        .replace(
            "3 1 5 1\n1 11 13 15 17 19 21 23 25\n",
            "3 1 5 1\n1 11 13 15 17 19 21 23 25\n3 1 6 1\n4 11 13 15 17 19 21\n",
        )
        .replace("$Elements\n3 3 1 3", "$Elements\n4 4 1 4");
    let e = msh_error(&text);
    assert_has(
        &e,
        &[
            "dir/bad.msh",
            "element 4 (type 6, 6-node prism, in volume 1)",
            "the 8-node hexahedron (type 5) and the 4-node tetrahedron (type 4)",
        ],
    );
}

#[test]
fn triangle_in_a_face_set_is_named() {
    let text = one_hex(HEX, "", 0).replace("2 2 3 1\n3 19 21 23 25\n", "2 2 2 1\n3 19 21 23\n");
    let e = msh_error(&text);
    assert_has(
        &e,
        &[
            "dir/bad.msh",
            "element 3 (a triangle of physical group \"physical_8\")",
            "not a face on the boundary of the body",
        ],
    );
}

#[test]
fn inverted_hexahedron_is_named() {
    // Bottom and top swapped: a mirror image, det J₀ < 0.
    let e = msh_error(&one_hex("19 21 23 25 11 13 15 17", "", 0));
    assert_has(&e, &["dir/bad.msh", "element 1", "inverted", "det J₀ = -"]);
}

#[test]
fn quad_off_the_boundary_is_named() {
    // A diagonal section of the cube is not one of its faces.
    let text = one_hex(HEX, "", 0).replace("3 19 21 23 25", "3 11 13 23 25");
    let e = msh_error(&text);
    assert_has(
        &e,
        &[
            "dir/bad.msh",
            "element 3",
            "physical group \"physical_8\"",
            "not a face on the boundary",
        ],
    );
}

#[test]
fn undefined_node_is_named() {
    let e = msh_error(&one_hex("11 13 15 17 19 21 23 27", "", 0));
    assert_has(&e, &["dir/bad.msh", "element 1", "node 27"]);
}

#[test]
fn syntax_error_gives_the_line() {
    // A word in the second coordinate line of the hexahedron's nodes.
    let text = one_hex(HEX, "", 0).replace("1 0 0\n1 1 0\n", "1 zero 0\n1 1 0\n");
    let line = 1 + text.lines().position(|l| l == "1 zero 0").unwrap();
    let e = msh_error(&text);
    assert_has(
        &e,
        &[
            &format!("dir/bad.msh: line {line}: not a valid MSH 4.1 file"),
            "node",
        ],
    );
}

#[test]
fn only_volume_elements_of_type_5_make_a_body() {
    let e = msh_error("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    assert_has(&e, &["dir/bad.msh", "no 8-node hexahedron (type 5)"]);
}

/// Through a scene: the scene file, the key and the mesh file with its element.
#[test]
fn scene_names_the_scene_key_and_mesh_file() {
    let dir = scratch("scene_errors");
    let text = one_hex(HEX, "", 0).replace(
        "3 1 5 1\n1 11 13 15 17 19 21 23 25\n",
        "3 1 5 1\n1 11 13 15 17 19 21 23 25\n3 1 4 1\n4 11 15 13 19\n",
    );
    let text = text.replace("$Elements\n3 3 1 3", "$Elements\n4 4 1 4");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/tet.msh"), text).unwrap();
    let scene = "end_time = 1.0\n[mesh]\nfile = \"meshes/tet.msh\"\n\
                 [material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n";
    let file = dir.join("s.toml").display().to_string();
    let e = parse_scene(scene, &file, &[]).unwrap_err().to_string();
    let msh = dir.join("meshes/tet.msh").display().to_string();
    assert_has(
        &e,
        &[
            &format!("{file}: key `mesh.file` = \"meshes/tet.msh\": {msh}: element 4"),
            "(tetrahedron) has volume -1.66666",
        ],
    );
    std::fs::remove_dir_all(dir).ok();
}

/// The same unit cube as a binary MSH 4.1 file (little-endian, 8-byte size_t), as Gmsh writes
/// with `Mesh.Binary = 1`: `mshio` reads it, the physical names stay ASCII.
#[test]
fn binary_file() {
    let mut b: Vec<u8> = Vec::new();
    let size = |b: &mut Vec<u8>, v: &[u64]| v.iter().for_each(|x| b.extend(x.to_le_bytes()));
    let int = |b: &mut Vec<u8>, v: &[i32]| v.iter().for_each(|x| b.extend(x.to_le_bytes()));
    let real = |b: &mut Vec<u8>, v: &[f64]| v.iter().for_each(|x| b.extend(x.to_le_bytes()));
    b.extend(b"$MeshFormat\n4.1 1 8\n");
    int(&mut b, &[1]);
    b.extend(b"\n$EndMeshFormat\n$PhysicalNames\n1\n2 7 \"floor\"\n$EndPhysicalNames\n");
    b.extend(b"$Entities\n");
    size(&mut b, &[0, 0, 1, 1]);
    // Surface 1 in physical group 7, no bounding curve; volume 1 bounded by surface 1.
    int(&mut b, &[1]);
    real(&mut b, &[0.0, 0.0, 0.0, 1.0, 1.0, 0.0]);
    size(&mut b, &[1]);
    int(&mut b, &[7]);
    size(&mut b, &[0]);
    int(&mut b, &[1]);
    real(&mut b, &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    size(&mut b, &[0, 1]);
    int(&mut b, &[1]);
    b.extend(b"\n$EndEntities\n$Nodes\n");
    size(&mut b, &[1, 8, 1, 8]);
    int(&mut b, &[3, 1, 0]);
    size(&mut b, &[8, 1, 2, 3, 4, 5, 6, 7, 8]);
    for c in HEX_CORNERS {
        real(&mut b, &c.map(|x| 0.5 * (x + 1.0)));
    }
    b.extend(b"\n$EndNodes\n$Elements\n");
    size(&mut b, &[2, 2, 1, 2]);
    int(&mut b, &[3, 1, 5]);
    size(&mut b, &[1, 1, 1, 2, 3, 4, 5, 6, 7, 8]);
    int(&mut b, &[2, 1, 3]);
    size(&mut b, &[1, 2, 1, 2, 3, 4]);
    b.extend(b"\n$EndElements\n");
    let bin = parse_msh(&b, "cube_binary.msh").unwrap();
    let ascii = parse_msh(one_hex(HEX, "", 0).as_bytes(), "cube.msh").unwrap();
    assert_eq!(bin.nodes, ascii.nodes);
    assert_eq!(bin.elements, ascii.elements);
    assert_eq!(bin.face_sets["floor"], ascii.face_sets["floor"]);
    // A broken binary file is located by its byte offset.
    let e = parse_msh(&b[..b.len() - 40], "cube_binary.msh")
        .unwrap_err()
        .to_string();
    assert_has(&e, &["cube_binary.msh: byte ", "not a valid MSH 4.1 file"]);
}
