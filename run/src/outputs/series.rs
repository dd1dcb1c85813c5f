//! The time series of the run's scalars ([`crate::output::series::SeriesWriter`]):
//! `--series FILE.csv`.

use super::{Entry, Opening};
use crate::output::series::SeriesWriter;
use crate::output::{Output, OutputError};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// The series' flag.
#[derive(clap::Args)]
struct Flags {
    /// Write the run's scalars to this CSV file, one row per step (with --every or --fps, at
    /// the frames' steps instead), streamed as the run goes: time, step, h, each prescribed
    /// condition's imposed displacement and reaction, each mould's force and moment, every
    /// energy of the ledger, the interface's state and contact counts; units in the header.
    /// Complete up to the last step when the run fails or is cancelled with Ctrl-C.
    #[arg(long, value_name = "FILE.csv", display_order = 70)]
    series: Option<PathBuf>,
}

/// The file the flags name, if any.
fn file(m: &ArgMatches) -> Option<PathBuf> {
    Flags::from_arg_matches(m).ok().and_then(|f| f.series)
}

/// Creates the file and writes its header (the watched nodes' columns included).
fn open(m: &ArgMatches, o: &Opening<'_>) -> Result<Box<dyn Output>, OutputError> {
    let path = file(m).expect("the series is asked for");
    Ok(Box::new(SeriesWriter::new(&path, o.cadence, o.sim, o.watch)?))
}

pub const ENTRY: Entry = Entry {
    name: "series",
    args: Flags::augment_args,
    asked: |m| file(m).is_some(),
    open,
    writes_watched: Some("--series FILE.csv"),
    null_when_absent: false,
    opened_last: false,
};
