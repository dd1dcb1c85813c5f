//! decohesion: explicit non-smooth dynamics (CD-Lagrange scheme) of a hyperelastic solid glued
//! to rigid surfaces by the RCCM cohesive law (damageable adhesion, unilateral contact, friction
//! growing with damage). The model is stated in `docs/src/model.md`; every
//! function that implements an equation names it and cites the section ("model §4.7").
//!
//! This crate is the command line ([`cli`]). The physics is the crate `decohesion_physics`
//! (folder `physics/`), the run driver and its outputs the crate `decohesion_run` (folder `run/`),
//! the explorer and the web page the crate `decohesion_explorer` (folder `explorer/`, feature
//! `gui`); they are re-exported here under the paths the command line and the tests use. The
//! physics knows nothing of the command line or of any viewer, by its dependencies; the run crate
//! knows no GUI and no command line.

// Index loops over tensor components and Gauss lanes read like the equations they implement.
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is used on purpose: it is also true for NaN, which must be caught.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// The physics crate's modules, under the names the command line, the outputs and the tests use.
pub use decohesion_physics::{
    element, energy, gmsh, interface, kernels, law, material, mesh, model, scene, solver, team,
};
// The run crate's modules, likewise.
#[cfg(not(target_arch = "wasm32"))]
pub use decohesion_run::{checkpoint, driver, fit, outputs, record, tradeoff, vtk};
pub use decohesion_run::{compare, errors, figure, measured, output, report, tunables, vary};

/// The `decohesion` subcommands behind the command line's parsing (run, check, tradeoff, bench,
/// sweep, compare, fit, reference).
pub mod cli;
/// The explorer (egui, the crate `decohesion_explorer`, folder `explorer/`), which `decohesion
/// gui` opens. Left out without the `gui` feature.
#[cfg(feature = "gui")]
pub use decohesion_explorer::gui;
