//! A decohesion run and its outputs, for the command line, the explorer and the Python package:
//! the run driver (one loop: frames, cancellation, progress, the summary), the outputs it opens
//! (the Rerun recording, ParaView files, the time series), checkpoints, the comparison of two
//! results, the speed–accuracy grid and the fit of a law to a measured curve.
//!
//! It reads the physics crate (`decohesion_physics`, re-exported here under the paths the front
//! ends use) and is read by none of it; it has no GUI and no command line (its outputs declare
//! their flags with clap, which the command line adds to `run`).

// Index loops over tensor components and Gauss lanes read like the equations they implement.
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is used on purpose: it is also true for NaN, which must be caught.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// The physics crate's modules, under the names the outputs and the front ends use.
pub use decohesion_physics::{
    element, energy, gmsh, interface, kernels, law, material, mesh, model, scene, solver, team,
};

/// Checkpoints of a run (`run --checkpoint`, `run --resume`): the folder, the interval, the
/// writes.
#[cfg(not(target_arch = "wasm32"))]
pub mod checkpoint;
/// Two results observable by observable, each within a physical tolerance (`decohesion
/// compare`, the golden files' guard).
pub mod compare;
/// The run driver: the outputs of a run, its loop, cancellation, progress, the summary.
#[cfg(not(target_arch = "wasm32"))]
pub mod driver;
/// An error's text as the command line and Python print it.
pub mod errors;
/// A plot as data, drawn as SVG or written as CSV (the fit's picture, the explorer's figures).
pub mod figure;
/// The fit: the values of a scene's keys that make a run reproduce a measured curve
/// (Nelder–Mead over the runs, the linearised uncertainty, the fitted scene file).
#[cfg(not(target_arch = "wasm32"))]
pub mod fit;
/// A measured curve (CSV with units) read and checked: what `fit` fits and the explorer overlays.
pub mod measured;
/// What the outputs share: frame cadence, snapshot, per-element fields, writer threads, and the
/// time series of the scalars (on wasm32 without the outputs themselves: the explorer's view
/// may read the fields).
pub mod output;
/// The registry of a run's outputs: one file per output, its flags, and `Driver::open`.
#[cfg(not(target_arch = "wasm32"))]
pub mod outputs;
/// Rerun recording (live or `.rrd`): reads a simulation, is not read by the physics.
#[cfg(not(target_arch = "wasm32"))]
pub mod record;
/// The run summary: the table, the JSON and the outputs' reports.
pub mod report;
/// Speed against accuracy: a grid of configurations of one scene compared with the finest.
#[cfg(not(target_arch = "wasm32"))]
pub mod tradeoff;
/// The front ends' tunables (the outputs, the recording, the fit, the explorer), each with its
/// meaning, unit and source.
pub mod tunables;
/// The `--vary key=v1,v2,…` parser of `sweep` and of the explorer's *compare values of*, and the
/// colours of series.
pub mod vary;
/// ParaView output (`.vtu` frames and a `.pvd` index): reads a simulation, uses no Rerun.
#[cfg(not(target_arch = "wasm32"))]
pub mod vtk;

// Native-only (threads, files, Rerun, ParaView): on wasm32-unknown-unknown the modules marked so
// above are left out, not stubbed; the page offers no recording and no files.
