//! The subcommands of the `decohesion` command, behind its argument parsing (`src/main.rs`):
//! `run` ([`run()`], through the run driver), `check`, `sweep` (a grid of runs, [`sweep()`]),
//! `tradeoff`, `bench`.

mod bench;
mod check;
mod peak;
mod run;
mod sweep;
mod sweep_record;
mod tradeoff;

pub use bench::bench;
pub use check::check;
pub use run::run;
pub use sweep::{sweep, SweepArgs, Vary};
pub use sweep_record::PALETTE;
pub use tradeoff::tradeoff;
