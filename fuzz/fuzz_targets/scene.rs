//! A scene file's text (and one `--set` override after a NUL byte) through the scene loader:
//! any input is a scene or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (text, set) = match data.iter().position(|&b| b == 0) {
        Some(k) => (&data[..k], vec![String::from_utf8_lossy(&data[k + 1..]).into_owned()]),
        None => (data, vec![]),
    };
    let Ok(text) = std::str::from_utf8(text) else {
        return;
    };
    let _ = decohesion_physics::scene::parse_scene(text, "fuzz.toml", &set);
});
