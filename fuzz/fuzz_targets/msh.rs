//! Bytes through the Gmsh `.msh` reader (ASCII and binary): a mesh or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = decohesion_physics::gmsh::parse_msh(data, "fuzz.msh");
});
