//! The physics crate's integration tests as one test binary: each file of `tests/` is a module
//! here, linked once. `allocation.rs` is a binary of its own: it installs a counting global
//! allocator, which would count every other test's allocations too. A file of `tests/` that is
//! neither listed here nor in `Cargo.toml` fails [`every_test_file_is_built`].

mod common;
/// The bad-input corpus's table, shared with the root tests.
#[path = "../../tests/common/corpus.rs"]
mod corpus;
mod hertz;
#[path = "../../tests/common/listing.rs"]
mod listing;
/// The graph of the top-level modules, checked for cycles below.
#[path = "../../tests/common/modules.rs"]
mod modules;
/// Records for the validation report (`scripts/validation.sh`), shared with the root tests.
#[path = "../../tests/common/validation.rs"]
mod validation;

mod bad_input;
mod bad_input_corpus;
mod bk;
mod bulk_viscosity;
mod cohesive_law;
mod concave_corner;
mod contact_start;
mod corner_jacobian;
mod dcb;
mod delay;
mod enf;
mod extreme;
mod fbar;
mod form_turning;
mod free_vibration;
mod friction;
mod glue_torque;
mod glued_start;
mod impact;
mod indent_adhesive;
mod mass_scaling;
mod mould_bad_input;
mod mould_cache;
mod mould_indent;
mod mould_motion;
mod mould_shapes;
mod multi_constraint;
mod partial_contact;
mod peel;
mod physical;
mod properties;
mod pull_off;
mod rccm;
mod reduced;
mod roller_peel;
mod rubber;
mod rubber_runs;
mod stability;
mod step;
mod teaching_scenes;
mod tet_damping;
mod tets;
mod tread_demould;
mod wave_speed;

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

/// Edges the cycle check leaves out until they are removed: none (the last, mesh → kernels,
/// went when the nodal field, the row flags and the corner-bound constant moved into `mesh`).
const PENDING_EDGES: &[(&str, &str)] = &[];

/// The top-level modules of the physics crate use each other without a cycle: each
/// `crate::X` or `super::` path that leaves its top-level module is an edge, and the graph of
/// those edges (`tests/common/modules.rs`), but for [`PENDING_EDGES`], has none. The layers
/// are listed in `docs/src/architecture.md`.
#[test]
fn no_module_cycle() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    if let Err(e) = modules::check(dir, "lib.rs", PENDING_EDGES) {
        panic!("{e}");
    }
}
