//! The subcommands of the `decohesion` command, behind its argument parsing (`src/main.rs`):
//! `run` ([`run()`], through the run driver), `check`, `tradeoff`, `bench`.

mod bench;
mod check;
mod run;
mod tradeoff;

pub use bench::bench;
pub use check::check;
pub use run::run;
pub use tradeoff::tradeoff;
