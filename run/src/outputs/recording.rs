//! The Rerun recording ([`crate::record::Recorder`]): `--save FILE.rrd`, `--spawn` or
//! `--connect [URL]` (one sink), the surface coloured by `--colour`.

use super::{Entry, Opening};
use crate::output::{Output, OutputError};
use crate::record::{ColourField, Recorder, Sink};
use clap::{ArgMatches, Args, FromArgMatches};
use std::path::PathBuf;

/// The recording's flags.
#[derive(clap::Args)]
struct Flags {
    /// Record to this .rrd file (open it with `rerun FILE.rrd`). Complete even when the run
    /// fails or is cancelled with Ctrl-C.
    #[arg(long, value_name = "FILE.rrd", group = "sink", display_order = 10)]
    save: Option<PathBuf>,
    /// Start the Rerun viewer (`rerun` from PATH, listening on 127.0.0.1) and stream to it.
    #[arg(long, group = "sink", display_order = 20)]
    spawn: bool,
    /// Stream to a running Rerun viewer [default: rerun+http://127.0.0.1:9876/proxy].
    #[arg(long, value_name = "URL", num_args = 0..=1, default_missing_value = "", group = "sink", display_order = 30)]
    connect: Option<String>,
    /// Field that colours the surface: displacement (|U|, m), von_mises (Pa), jacobian (J).
    #[arg(
        long,
        value_name = "FIELD",
        default_value = "displacement",
        display_order = 90
    )]
    colour: ColourField,
}

impl Flags {
    /// The sink the flags name, if any.
    fn sink(&self) -> Option<Sink> {
        if let Some(p) = &self.save {
            Some(Sink::Save(p.clone()))
        } else if self.spawn {
            Some(Sink::Spawn)
        } else {
            self.connect
                .as_ref()
                .map(|u| Sink::Connect((!u.is_empty()).then(|| u.clone())))
        }
    }
}

/// The flags of `m`, or none when they are not there (a plan of no flags).
fn flags(m: &ArgMatches) -> Option<Flags> {
    Flags::from_arg_matches(m).ok()
}

/// Opens the recorder; its error says `starting the recording`.
fn open(m: &ArgMatches, o: &Opening<'_>) -> Result<Box<dyn Output>, OutputError> {
    let f = flags(m).expect("the recording is asked for");
    let sink = f.sink().expect("the recording is asked for");
    let id = o.recording_id.map(str::to_string);
    Recorder::new(sink, o.scene, o.sim, f.colour, id, o.watch)
        .map(|r| Box::new(r) as Box<dyn Output>)
        .map_err(|e| OutputError::from(e).while_doing(Some("starting the recording")))
}

pub const ENTRY: Entry = Entry {
    name: "recording",
    args: Flags::augment_args,
    asked: |m| flags(m).and_then(|f| f.sink()).is_some(),
    open,
    writes_watched: Some("a recording (--save FILE.rrd, --spawn or --connect)"),
    null_when_absent: true,
    opened_last: true,
};
