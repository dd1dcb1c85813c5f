//! The tests of the whole program, as one test binary: each file of `tests/` is a module here, so
//! the Rerun SDK, egui and the command line are linked once rather than once per file.
//! `gui_view.rs` (a real window under Xvfb, which sets the process's `DISPLAY`) is a binary of
//! its own. A file of `tests/` that is neither listed here nor in `Cargo.toml` fails
//! [`every_test_file_is_built`].

// The two example generators (tread_block, ribbed_mould), modules of this binary through
// gmsh.rs and ribbed_mould.rs, each include the dimensions they share as a module of their own,
// as they do when built as examples.
#![allow(clippy::duplicate_mod)]

mod by_hand;
mod common;
/// The bad-input corpus's table, shared with the physics tests.
#[path = "common/corpus.rs"]
mod corpus;
#[path = "common/listing.rs"]
mod listing;
/// The graph of the top-level modules, checked for cycles below.
#[path = "common/modules.rs"]
mod modules;
/// Records for the validation report (`scripts/validation.sh`); the physics tests include the same file.
#[path = "common/validation.rs"]
mod validation;

mod bad_input_cli;
mod checkpoint;
mod command_line;
mod compare;
mod fit;
mod gmsh;
mod golden;
mod gui;
mod lessons;
mod material;
mod patch;
mod recording;
mod recording_contact;
mod recording_eye;
mod recording_mould_loads;
mod recording_moulds;
mod reference;
mod ribbed_mould;
mod series;
mod start_offset;
mod sweep;
mod tradeoff;
mod vtk;
mod vtk_moulds;
mod watch;

/// Every `tests/*.rs` is a module of this binary or a test binary of its own in `Cargo.toml`.
#[test]
fn every_test_file_is_built() {
    let missing = listing::unlisted_test_files(env!("CARGO_MANIFEST_DIR"));
    assert!(
        missing.is_empty(),
        "tests/{{{}}}.rs: add `mod NAME;` to tests/main.rs (or a [[test]] to Cargo.toml)",
        missing.join(",")
    );
}

/// The top-level modules of this crate's sources, the run crate's (`run/`) and the explorer's
/// (`explorer/`) use each other without a cycle: each `crate::X` or `super::` path that leaves
/// its top-level module is an edge, and the graph of those edges (`tests/common/modules.rs`) has
/// none. The layers are listed in `docs/src/architecture.md`.
#[test]
fn no_module_cycle() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (crate_dir, root) in [
        (dir.to_path_buf(), "lib.rs"),
        (dir.to_path_buf(), "main.rs"),
        (dir.join("run"), "lib.rs"),
        (dir.join("explorer"), "lib.rs"),
    ] {
        if let Err(e) = modules::check(&crate_dir, root, &[]) {
            panic!("{}: {e}", crate_dir.display());
        }
    }
}
