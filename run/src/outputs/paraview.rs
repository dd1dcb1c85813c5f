//! The ParaView files ([`crate::vtk::VtkWriter`]): `--vtk DIR`.

use super::{Entry, Opening};
use crate::output::{Output, OutputError};
use crate::vtk::VtkWriter;
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// The ParaView files' flag.
#[derive(clap::Args)]
struct Flags {
    /// Also write ParaView files to this directory (created if needed): a .vtu per frame
    /// and NAME.pvd indexing them by simulated time, complete even when the run fails or is
    /// cancelled. Can be combined with --save, --spawn or --connect.
    #[arg(long, value_name = "DIR", display_order = 40)]
    vtk: Option<PathBuf>,
}

/// The directory the flags name, if any.
fn dir(m: &ArgMatches) -> Option<PathBuf> {
    Flags::from_arg_matches(m).ok().and_then(|f| f.vtk)
}

/// Creates the directory and the index; a directory that cannot be written is an error that
/// says it all.
fn open(m: &ArgMatches, o: &Opening<'_>) -> Result<Box<dyn Output>, OutputError> {
    let dir = dir(m).expect("the ParaView files are asked for");
    VtkWriter::new(&dir, o.sim)
        .map(|w| Box::new(w) as Box<dyn Output>)
        .map_err(|e| OutputError::from(e).while_doing(None))
}

pub const ENTRY: Entry = Entry {
    name: "paraview",
    args: Flags::augment_args,
    asked: |m| dir(m).is_some(),
    open,
    writes_watched: None,
    null_when_absent: true,
    opened_last: false,
};
