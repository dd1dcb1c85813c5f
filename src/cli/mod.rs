//! The subcommands of the `decohesion` command, behind its argument parsing (`src/main.rs`):
//! `run` ([`run()`], through the run driver), `check`, `sweep` (a grid of runs, [`sweep()`]),
//! `tradeoff`, `bench`.
//!
//! On wasm32 (the web page) only [`Vary`] and [`PALETTE`] exist, which the explorer uses.

#[cfg(not(target_arch = "wasm32"))]
mod bench;
#[cfg(not(target_arch = "wasm32"))]
mod check;
#[cfg(not(target_arch = "wasm32"))]
mod peak;
#[cfg(not(target_arch = "wasm32"))]
mod run;
#[cfg(not(target_arch = "wasm32"))]
mod sweep;
#[cfg(not(target_arch = "wasm32"))]
mod sweep_record;
#[cfg(not(target_arch = "wasm32"))]
mod tradeoff;
mod vary;

pub use vary::{Vary, PALETTE};
#[cfg(not(target_arch = "wasm32"))]
pub use {
    bench::bench, check::check, run::run, sweep::sweep, sweep::SweepArgs, tradeoff::tradeoff,
};
