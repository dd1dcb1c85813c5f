//! Bytes through the STL reader (ASCII and binary) and, when they read, the surface's checks
//! (welding, open edges, folds): a surface or an error, never a panic.
#![no_main]

use decohesion_physics::mould::surface::{read_stl, SurfaceMesh};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok((v, t)) = read_stl(data, "fuzz.stl") {
        let _ = SurfaceMesh::new("fuzz.stl", None, 1.0, v, t, &|k| format!("facet {k}"));
    }
});
