//! The check that every file of a `tests/` folder is built: with `autotests = false` a test file
//! that is neither a module of `tests/main.rs` nor a `[[test]]` of `Cargo.toml` would never run.
//! Included by both crates' test binaries (`tests/main.rs`, `physics/tests/main.rs`).

/// The stems of the `tests/*.rs` files of the package at `root` that `tests/main.rs` does not
/// declare as `mod NAME;` and `Cargo.toml` does not name as a test's `path`.
pub fn unlisted_test_files(root: &str) -> Vec<String> {
    let main = std::fs::read_to_string(format!("{root}/tests/main.rs")).unwrap();
    let manifest = std::fs::read_to_string(format!("{root}/Cargo.toml")).unwrap();
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(format!("{root}/tests")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let stem = path.file_stem().unwrap().to_str().unwrap().to_string();
        let listed = stem == "main"
            || main.lines().any(|l| l.trim() == format!("mod {stem};"))
            || manifest.contains(&format!("path = \"tests/{stem}.rs\""));
        if !listed {
            missing.push(stem);
        }
    }
    missing.sort();
    missing
}
