//! decohesion: explicit non-smooth dynamics (CD-Lagrange scheme) of a hyperelastic solid glued
//! to rigid surfaces by the RCCM cohesive law (damageable adhesion, unilateral contact, friction
//! growing with damage). The model is stated in `docs/src/model.md`; every
//! function that implements an equation names it and cites the section ("model §4.7").
//!
//! The physics is the crate `decohesion_physics` (folder `physics/`), re-exported here: it knows
//! nothing of the command line or of any viewer, by its dependencies; `record` (Rerun) and `vtk` (ParaView files) read them
//! and are read by none of them.

// Index loops over tensor components and Gauss lanes read like the equations they implement.
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is used on purpose: it is also true for NaN, which must be caught.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// The physics crate's modules, under the names the command line, the outputs and the tests use.
pub use decohesion_physics::{
    energy, gmsh, interface, kernels, law, material, mesh, model, scene, solver, team,
};

/// Checkpoints of a run (`run --checkpoint`, `run --resume`): the folder, the interval, the
/// writes.
#[cfg(not(target_arch = "wasm32"))]
pub mod checkpoint;
/// The `decohesion` subcommands behind the command line's parsing (run, check, tradeoff, bench);
/// on wasm32 only what the explorer shares with it (the `--vary` parser, the series colours).
pub mod cli;
/// `decohesion compare`: two results observable by observable, each within a physical tolerance.
pub mod compare;
/// The run driver: the outputs of a run, its loop, cancellation, progress, the summary.
#[cfg(not(target_arch = "wasm32"))]
pub mod driver;
/// A plot as data, drawn as SVG or written as CSV (the fit's picture, the explorer's figures).
pub mod figure;
/// `decohesion fit`: the values of a scene's keys that make a run reproduce a measured curve
/// (Nelder–Mead over the runs, the linearised uncertainty, the fitted scene file).
#[cfg(not(target_arch = "wasm32"))]
pub mod fit;
/// The explorer (egui): reads scenes, runs simulations on a thread or, in the web page, inside
/// the frame loop; not used by the physics. Left out without the `gui` feature (the Python
/// package).
#[cfg(feature = "gui")]
pub mod gui;
/// A measured curve (CSV with units) read and checked: what `fit` fits and the explorer overlays.
pub mod measured;
/// What the outputs share: frame cadence, snapshot, per-element fields, writer threads, and the
/// time series of the scalars (on wasm32 without the outputs themselves: the explorer's view
/// may read the fields).
pub mod output;
/// Rerun recording (live or `.rrd`): reads a simulation, is not read by the physics.
#[cfg(not(target_arch = "wasm32"))]
pub mod outputs;
#[cfg(not(target_arch = "wasm32"))]
pub mod record;
pub mod report;
/// Speed against accuracy: a grid of configurations of one scene compared with the finest.
#[cfg(not(target_arch = "wasm32"))]
pub mod tradeoff;
/// The front ends' tunables (the outputs, the recording, the fit, the explorer), each with its
/// meaning, unit and source.
pub mod tunables;
/// ParaView output (`.vtu` frames and a `.pvd` index): reads a simulation, uses no Rerun.
#[cfg(not(target_arch = "wasm32"))]
pub mod vtk;
/// The web page's entry point (wasm32): the explorer in a canvas, every scene of `scenes/`
/// built in, runs stepped inside the frame loop.
#[cfg(all(target_arch = "wasm32", feature = "gui"))]
pub mod web;

// Native-only (threads, files, Rerun, ParaView, the command line): on wasm32-unknown-unknown the
// modules marked so above are left out, not stubbed; the page offers no recording and no files.
