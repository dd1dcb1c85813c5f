//! Writes `scenes/meshes/tread_block.msh`, the mesh of `scenes/tread.toml`, as Gmsh would (MSH
//! 4.1 ASCII, hexahedra, named physical surface groups), since no `gmsh` binary is needed to
//! reproduce it:
//!
//! ```sh
//! cargo run --release --example tread_block
//! ```
//!
//! A rubber tread block 60 × 30 × 20 mm (x × y × z, lengths in millimetres: the scene reads it
//! with `scale = 0.001`) with two grooves across its top, along y: trapezoidal, 8 mm wide at the
//! top, 4 mm at their floor, 8 mm deep, centred at x = 20 and 40 mm. Hexahedra of 2 mm below the
//! groove floor (z < 12 mm); above it the x-lines of the grid lean with the groove walls, so the
//! rib elements are trapezoids (the mesh is not a box: its elements have several shapes).
//! Physical groups: `bottom` (z = 0), `top` (the rib tops, z = 20 mm), `groove` (walls and
//! floors), `sides` (x = 0, x = 60, y = 0, y = 30 mm). Volume: 60·30·20 − 2·30·(8 + 4)/2·8
//! = 33 120 mm³. `tests/gmsh.rs` checks that this program reproduces the committed file. The
//! dimensions are in `examples/shared/tread_geometry.rs`, shared with `examples/ribbed_mould.rs`.

use decohesion::gmsh::write_msh;
use decohesion::mesh::Mesh;
use std::collections::BTreeMap;

#[allow(dead_code)]
#[path = "shared/tread_geometry.rs"]
mod tread_geometry;
pub use tread_geometry::{GROOVE_CENTRES, GROOVE_DEPTH, GROOVE_FLOOR, GROOVE_TOP, SIZE};

/// Element size below the groove floor [mm].
const CELL: f64 = 2.0;

/// Where the file goes, relative to the crate root.
pub const PATH: &str = "scenes/meshes/tread_block.msh";

/// Analytic volume of the block minus its grooves [mm³].
pub fn volume() -> f64 {
    SIZE[0] * SIZE[1] * SIZE[2]
        - GROOVE_CENTRES.len() as f64 * SIZE[1] * 0.5 * (GROOVE_TOP + GROOVE_FLOOR) * GROOVE_DEPTH
}

/// Maps a floor-level x to the top-level x: piecewise linear, taking each groove floor
/// [c − f/2, c + f/2] onto its top [c − t/2, c + t/2] and the ribs between onto the ribs.
fn top_x(x: f64) -> f64 {
    let mut floor = vec![0.0];
    let mut top = vec![0.0];
    for c in GROOVE_CENTRES {
        floor.extend([c - 0.5 * GROOVE_FLOOR, c + 0.5 * GROOVE_FLOOR]);
        top.extend([c - 0.5 * GROOVE_TOP, c + 0.5 * GROOVE_TOP]);
    }
    floor.push(SIZE[0]);
    top.push(SIZE[0]);
    let i = (1..floor.len())
        .find(|&i| x <= floor[i])
        .unwrap_or(floor.len() - 1);
    let s = (x - floor[i - 1]) / (floor[i] - floor[i - 1]);
    top[i - 1] + s * (top[i] - top[i - 1])
}

/// The tread block mesh (no unused node), face sets outward.
pub fn mesh() -> Mesh {
    let n = SIZE.map(|s| (s / CELL).round() as usize);
    let floor_z = SIZE[2] - GROOVE_DEPTH;
    let x_at = |i: usize, z: f64| {
        let x = SIZE[0] * i as f64 / n[0] as f64;
        if z <= floor_z {
            x
        } else {
            let s = (z - floor_z) / GROOVE_DEPTH;
            x + s * (top_x(x) - x)
        }
    };
    let in_groove = |i: usize, k: usize| {
        // Cell (i, k) is void when it lies above the floor between the groove walls.
        let xc = SIZE[0] * (i as f64 + 0.5) / n[0] as f64;
        let zc = SIZE[2] * (k as f64 + 0.5) / n[2] as f64;
        zc > floor_z
            && GROOVE_CENTRES
                .iter()
                .any(|c| (xc - c).abs() < 0.5 * GROOVE_FLOOR)
    };
    let grid = |i: usize, j: usize, k: usize| i + (n[0] + 1) * (j + (n[1] + 1) * k);
    let mut elements = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                if !in_groove(i, k) {
                    elements.push([
                        grid(i, j, k),
                        grid(i + 1, j, k),
                        grid(i + 1, j + 1, k),
                        grid(i, j + 1, k),
                        grid(i, j, k + 1),
                        grid(i + 1, j, k + 1),
                        grid(i + 1, j + 1, k + 1),
                        grid(i, j + 1, k + 1),
                    ]);
                }
            }
        }
    }
    // Number the used grid points in grid order.
    let mut index = vec![u32::MAX; (n[0] + 1) * (n[1] + 1) * (n[2] + 1)];
    for conn in &elements {
        for &g in conn {
            index[g] = 0;
        }
    }
    let mut nodes = Vec::new();
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let g = grid(i, j, k);
                if index[g] == 0 {
                    index[g] = nodes.len() as u32;
                    let z = SIZE[2] * k as f64 / n[2] as f64;
                    nodes.push([x_at(i, z), SIZE[1] * j as f64 / n[1] as f64, z]);
                }
            }
        }
    }
    let mut mesh = Mesh {
        nodes,
        elements: elements.iter().map(|conn| conn.map(|g| index[g])).collect(),
        tets: Vec::new(),
        face_sets: BTreeMap::new(),
    };
    // Classify the boundary faces by where they lie.
    let on = |q: &[u32; 4], axis: usize, value: f64| {
        q.iter()
            .all(|&v| (mesh.nodes[v as usize][axis] - value).abs() < 1e-9)
    };
    let mut sets: BTreeMap<String, Vec<[u32; 4]>> = BTreeMap::new();
    for (q, _) in mesh.boundary_faces() {
        let name = if on(&q, 2, 0.0) {
            "bottom"
        } else if on(&q, 2, SIZE[2]) {
            "top"
        } else if on(&q, 0, 0.0) || on(&q, 0, SIZE[0]) || on(&q, 1, 0.0) || on(&q, 1, SIZE[1]) {
            "sides"
        } else {
            "groove"
        };
        sets.entry(name.into()).or_default().push(q);
    }
    mesh.face_sets = sets;
    mesh
}

/// The file's text.
pub fn text() -> String {
    let mut buf = Vec::new();
    write_msh(&mesh(), &mut buf).expect("writing to memory");
    String::from_utf8(buf).expect("UTF-8")
}

fn main() -> std::io::Result<()> {
    let m = mesh();
    std::fs::create_dir_all("scenes/meshes")?;
    std::fs::write(PATH, text())?;
    println!(
        "{PATH}: {} nodes, {} hexahedra, face sets {}",
        m.nodes.len(),
        m.elements.len(),
        m.face_sets
            .iter()
            .map(|(k, v)| format!("{k} ({} quads)", v.len()))
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}
