//! The decohesion explorer: the law editor, the plots, the 3-D view, the lessons and the fit, in a
//! native window (egui, eframe) or in the web page (`web`, wasm32, runs stepped inside the frame
//! loop). The command line opens it (`decohesion gui`, the root crate's `gui` feature).
//!
//! It reads the physics crate and the run crate (re-exported here under the paths the explorer
//! uses: `crate::solver`, `crate::driver`, …); neither of them knows it.

// Index loops over tensor components and Gauss lanes read like the equations they implement.
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is used on purpose: it is also true for NaN, which must be caught.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub use decohesion_physics::{
    element, energy, gmsh, interface, kernels, law, material, mesh, model, scene, solver, team,
};
#[cfg(not(target_arch = "wasm32"))]
pub use decohesion_run::{checkpoint, driver, fit, outputs, record, tradeoff, vtk};
pub use decohesion_run::{compare, errors, figure, measured, output, report, tunables, vary};

/// The explorer (egui): reads scenes, runs simulations on a thread or, in the web page, inside
/// the frame loop; not used by the physics.
pub mod gui;
/// The web page's entry point (wasm32): the explorer in a canvas, every scene of `scenes/`
/// built in, runs stepped inside the frame loop.
#[cfg(target_arch = "wasm32")]
pub mod web;
