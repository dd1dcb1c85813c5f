//! Writes `scenes/meshes/ribbed_mould.stl`, the mould of `scenes/tread_demould.toml`: the steel
//! surface that formed the tread block of `examples/tread_block.rs`, as an ASCII STL:
//!
//! ```sh
//! cargo run --release --example ribbed_mould
//! ```
//!
//! Lengths in millimetres (the scene reads it with `scale = 0.001`). The surface is the block's
//! moulded profile (`top_profile` of `examples/shared/tread_geometry.rs`, shared with the block's
//! generator): the rib tops of the tread (z = 20 mm) and, at each groove, the mould's rib that
//! filled it (its walls and its flat end on the groove floor, z = 12 mm), extruded along y and
//! extended `MARGIN` beyond the block's 60 × 30 mm footprint on every side. An open surface: each
//! segment of the profile is a strip of two triangles across y (18 triangles, 20 vertices),
//! ordered so that the normal (b − a) × (c − a) points out of the mould, into the rubber (down
//! on the tops and floors, away from the rib on its walls), as the mould loader requires.
//! `tests/ribbed_mould.rs` checks that this program reproduces the committed file and that the
//! block's moulded nodes lie on this surface.

#[allow(dead_code)]
#[path = "shared/tread_geometry.rs"]
mod tread_geometry;

use std::fmt::Write;
use tread_geometry::{top_profile, SIZE};

/// How far the surface extends beyond the block's footprint, in x and y [mm].
pub const MARGIN: f64 = 4.0;

/// Where the file goes, relative to the crate root.
pub const PATH: &str = "scenes/meshes/ribbed_mould.stl";

/// The triangles [mm], each oriented with its normal out of the mould (module docs).
pub fn triangles() -> Vec<[[f64; 3]; 3]> {
    let profile = top_profile(-MARGIN, SIZE[0] + MARGIN);
    let (y0, y1) = (-MARGIN, SIZE[1] + MARGIN);
    let mut out = Vec::new();
    for s in profile.windows(2) {
        let ([xa, za], [xb, zb]) = (s[0], s[1]);
        // The strip's corners: a, b at y0 and c, d at y1 (a → b along the profile, +x).
        let (a, b, c, d) = ([xa, y0, za], [xb, y0, zb], [xb, y1, zb], [xa, y1, za]);
        // (c − a) × (b − a) = ŷ × (b − a) for the profile direction: −z on a top or floor
        // (the profile runs +x), −x on a wall going down, +x on a wall coming up.
        out.push([a, c, b]);
        out.push([a, d, c]);
    }
    out
}

fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// The file's text: each facet with its unit normal, coordinates in shortest round-trip form.
pub fn text() -> String {
    let mut s = String::from("solid ribbed_mould\n");
    for [a, b, c] in triangles() {
        let n = cross(
            std::array::from_fn(|k| b[k] - a[k]),
            std::array::from_fn(|k| c[k] - a[k]),
        );
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = n.map(|x| x / l + 0.0);
        writeln!(s, "  facet normal {} {} {}", n[0], n[1], n[2]).unwrap();
        s.push_str("    outer loop\n");
        for v in [a, b, c] {
            writeln!(s, "      vertex {} {} {}", v[0], v[1], v[2]).unwrap();
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid ribbed_mould\n");
    s
}

fn main() -> std::io::Result<()> {
    std::fs::create_dir_all("scenes/meshes")?;
    std::fs::write(PATH, text())?;
    println!("{PATH}: {} triangles", triangles().len());
    Ok(())
}
