//! The subcommands of the `decohesion` command, behind its argument parsing (`src/main.rs`):
//! `run` ([`run()`], through the run driver), `check`, `sweep` (a grid of runs, [`sweep()`]),
//! `tradeoff`, `bench`, `compare` (two results, [`compare()`]), `fit` (a law fitted to a measured curve, [`fit()`]), `reference` (the reference pages generated from the code,
//! [`reference`]).
//!
//! [`Vary`] and [`PALETTE`] are the run crate's (the explorer uses them too).

#[cfg(not(target_arch = "wasm32"))]
mod bench;
#[cfg(not(target_arch = "wasm32"))]
mod check;
#[cfg(not(target_arch = "wasm32"))]
pub mod compare;
#[cfg(not(target_arch = "wasm32"))]
mod fit;
#[cfg(not(target_arch = "wasm32"))]
mod peak;
#[cfg(not(target_arch = "wasm32"))]
mod progress;
#[cfg(not(target_arch = "wasm32"))]
pub mod reference;
#[cfg(not(target_arch = "wasm32"))]
mod run;
#[cfg(not(target_arch = "wasm32"))]
mod sweep;
#[cfg(not(target_arch = "wasm32"))]
mod sweep_record;
#[cfg(not(target_arch = "wasm32"))]
mod tradeoff;

pub use decohesion_run::vary::{Vary, PALETTE};
#[cfg(not(target_arch = "wasm32"))]
pub use {
    bench::bench, check::check, compare::compare, fit::fit, fit::FitCli, run::run,
    run::Checkpoints, sweep::sweep, sweep::SweepArgs, tradeoff::tradeoff,
};

pub use crate::errors::{causes_once, error_message};
