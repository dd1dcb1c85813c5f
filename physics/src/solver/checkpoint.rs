//! Checkpoints: the state of a run at tₙ written to bytes and read back into a simulation of
//! the same model, so that a run continues from it as if it had never stopped (model §4.13).
//!
//! A checkpoint holds everything a step reads that the set-up did not compute from the model:
//! the run's [`State`] (U, V_{n+½}, F_int, every interface and contact node, the moulds' poses
//! and per-node geometry, the step control, the bulk viscosity's step values, the ledger's sums,
//! tₙ, n and h) and its statistics. What the set-up computes from the model (masses, element
//! classes and blocks, the stable-step operator's constants) is not written:
//! [`Simulation::restore`] writes the state into a simulation freshly set up from the same model,
//! which has them already. The fields of [`Simulation`] are listed without `..` in
//! [`Simulation::checkpoint`], so a field added to it does not compile until it is placed in the
//! state or declared the set-up's.
//!
//! The bytes: a magic line, a header (format, the model's name, sizes and fingerprint, n and
//! tₙ, the payload's length and CRC-32) with its own CRC-32, then the payload in postcard
//! (serde's compact binary format; an f64 is its 8 bytes, so a restore is exact). A file is
//! written atomically ([`write_atomically`]: a temporary file, fsync, rename, fsync of the
//! folder), so a run killed while writing leaves the previous checkpoint whole.

use super::{Simulation, State};
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The first bytes of every checkpoint.
const MAGIC: &[u8; 22] = b"decohesion checkpoint\n";
/// The layout of the payload; a checkpoint of another format is refused.
pub const CHECKPOINT_FORMAT: u32 = 5;

/// Why a checkpoint could not be written or read back.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{0} is not a decohesion checkpoint (it does not start with the checkpoint's magic line)"
    )]
    NotACheckpoint(String),
    #[error("{what} is a checkpoint of format {found}; this build reads format {CHECKPOINT_FORMAT} only (write it again with this build)")]
    Format { what: String, found: u32 },
    #[error("{what} is corrupt: {why}")]
    Corrupt { what: String, why: String },
    #[error("{what} is a checkpoint of another model: it was written by a run of '{found}' ({found_nodes} nodes, {found_elements} elements, fingerprint {found_fp:08x}), this model is '{expected}' ({nodes} nodes, {elements} elements, fingerprint {fp:08x}). The scene file, its --set overrides, its mesh or a mould's surface changed since it was written")]
    Foreign {
        what: String,
        found: String,
        found_nodes: usize,
        found_elements: usize,
        found_fp: u32,
        expected: String,
        nodes: usize,
        elements: usize,
        fp: u32,
    },
}

/// What a checkpoint says about itself, read before its payload.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckpointHeader {
    pub format: u32,
    /// The version of the physics crate that wrote it.
    pub writer: String,
    /// The model's name, node and element counts, and [`model_fingerprint`].
    pub model: String,
    pub nodes: usize,
    pub elements: usize,
    pub fingerprint: u32,
    /// Step n and time tₙ [s] of the state.
    pub step: u64,
    pub time: f64,
    pub payload_len: u64,
    pub payload_crc: u32,
}

/// The fingerprint of a model: the CRC-32 of its full `Debug` text (every value, the mesh, the
/// moulds' surfaces; floats printed so that they read back to the same bits), streamed.
pub fn model_fingerprint(model: &Model) -> u32 {
    struct Crc(crc32fast::Hasher);
    impl std::fmt::Write for Crc {
        fn write_str(&mut self, s: &str) -> std::fmt::Result {
            self.0.update(s.as_bytes());
            Ok(())
        }
    }
    let mut crc = Crc(crc32fast::Hasher::new());
    // Writing to a hasher cannot fail.
    let _ = write!(crc, "{model:?}");
    crc.0.finalize()
}

/// What a checkpoint holds (see the module docs): the run's [`State`] and its statistics,
/// borrowed when written, owned when read.
#[derive(Serialize, Deserialize)]
struct Saved<'a> {
    state: Cow<'a, State>,
    stats: Cow<'a, super::RunStats>,
}

impl Simulation {
    /// The state at tₙ as the bytes of a checkpoint (module docs): restored by
    /// [`Simulation::restore`] into a simulation of the same model, the run goes on bit for bit
    /// as if it had not stopped.
    pub fn checkpoint(&self) -> Vec<u8> {
        // Every field, named: a new one must be placed here (written) or in the list of what
        // the set-up computes (not written).
        // Every part, named: a new one must be placed here, as state (written) or not.
        let Simulation {
            model,
            // Computed by the set-up from the model alone, and the loops' buffers.
            setup: _,
            work: _,
            // The state, and the statistics.
            state,
            stats,
        } = self;
        let saved = Saved {
            state: Cow::Borrowed(state),
            stats: Cow::Borrowed(stats),
        };
        // Serialising plain data into a vector cannot fail.
        let payload = postcard::to_stdvec(&saved).expect("a checkpoint's state serialises");
        let header = CheckpointHeader {
            format: CHECKPOINT_FORMAT,
            writer: env!("CARGO_PKG_VERSION").into(),
            model: model.name.clone(),
            nodes: model.mesh.nodes.len(),
            elements: model.mesh.element_count(),
            fingerprint: self.fingerprint(),
            step: state.step_count,
            time: state.time,
            payload_len: payload.len() as u64,
            payload_crc: crc32fast::hash(&payload),
        };
        let head = postcard::to_stdvec(&header).expect("a checkpoint's header serialises");
        let mut out = Vec::with_capacity(MAGIC.len() + 8 + head.len() + payload.len());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(head.len() as u32).to_le_bytes());
        out.extend_from_slice(&crc32fast::hash(&head).to_le_bytes());
        out.extend_from_slice(&head);
        out.extend_from_slice(&payload);
        out
    }

    /// The model's [`model_fingerprint`], computed once.
    pub fn fingerprint(&self) -> u32 {
        *self
            .setup
            .fingerprint
            .get_or_init(|| model_fingerprint(&self.model))
    }

    /// Continues from the checkpoint `bytes` (of [`Simulation::checkpoint`]; `what` names them
    /// in errors, e.g. the file): refused, with the simulation left as it was, when they are not
    /// a checkpoint, are of another format, are corrupt (a checksum or a size differs) or were
    /// written by a run of another model (its fingerprint differs).
    pub fn restore(
        &mut self,
        bytes: &[u8],
        what: &str,
    ) -> Result<CheckpointHeader, CheckpointError> {
        let header = read_header(bytes, what)?;
        if header.fingerprint != self.fingerprint()
            || header.nodes != self.model.mesh.nodes.len()
            || header.elements != self.model.mesh.element_count()
        {
            return Err(CheckpointError::Foreign {
                what: what.into(),
                found: header.model.clone(),
                found_nodes: header.nodes,
                found_elements: header.elements,
                found_fp: header.fingerprint,
                expected: self.model.name.clone(),
                nodes: self.model.mesh.nodes.len(),
                elements: self.model.mesh.element_count(),
                fp: self.fingerprint(),
            });
        }
        let corrupt = |why: String| CheckpointError::Corrupt {
            what: what.into(),
            why,
        };
        let payload = &bytes[bytes.len() - header.payload_len as usize..];
        let Saved { state, stats } = postcard::from_bytes(payload)
            .map_err(|e| corrupt(format!("its state does not read back ({e})")))?;
        let sizes = [
            (state.u.len(), self.state.u.len(), "U"),
            (state.v.len(), self.state.v.len(), "V"),
            (state.f_int.len(), self.state.f_int.len(), "F_int"),
            (
                state.interface_nodes.len(),
                self.state.interface_nodes.len(),
                "interface nodes",
            ),
            (
                state.contact_nodes.len(),
                self.state.contact_nodes.len(),
                "contact nodes",
            ),
            (
                state.boundary.nodes.len(),
                self.state.boundary.nodes.len(),
                "boundary nodes",
            ),
        ];
        if let Some((found, expected, name)) = sizes.iter().find(|s| s.0 != s.1) {
            return Err(corrupt(format!(
                "it has {found} {name} where the model has {expected}"
            )));
        }
        let mut state = state.into_owned();
        // The stable-step operator's constants and buffers are this simulation's own.
        let control = &mut self.state.step_control;
        state.step_control.estimates = std::mem::take(&mut control.estimates);
        state.step_control.bound = std::mem::take(&mut control.bound);
        self.state = state;
        self.stats = stats.into_owned();
        Ok(header)
    }

    /// Writes [`Simulation::checkpoint`] to `path` atomically ([`write_atomically`]).
    pub fn save_checkpoint(&self, path: &Path) -> Result<CheckpointHeader, CheckpointError> {
        let bytes = self.checkpoint();
        write_atomically(path, &bytes)?;
        read_header(&bytes, &path.display().to_string())
    }

    /// Reads the checkpoint file at `path` and continues from it ([`Simulation::restore`]).
    pub fn load_checkpoint(&mut self, path: &Path) -> Result<CheckpointHeader, CheckpointError> {
        let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io {
            path: path.into(),
            source,
        })?;
        self.restore(&bytes, &path.display().to_string())
    }
}

/// The header of the checkpoint `bytes`, its checksums and sizes checked (`what` names them).
pub fn read_header(bytes: &[u8], what: &str) -> Result<CheckpointHeader, CheckpointError> {
    let corrupt = |why: &str| CheckpointError::Corrupt {
        what: what.into(),
        why: why.into(),
    };
    let Some(rest) = bytes.strip_prefix(MAGIC.as_slice()) else {
        return Err(CheckpointError::NotACheckpoint(what.into()));
    };
    if rest.len() < 8 {
        return Err(corrupt("it ends inside its header (truncated)"));
    }
    let head_len = u32::from_le_bytes(rest[..4].try_into().unwrap()) as usize;
    let head_crc = u32::from_le_bytes(rest[4..8].try_into().unwrap());
    let rest = &rest[8..];
    if rest.len() < head_len {
        return Err(corrupt("it ends inside its header (truncated)"));
    }
    let head = &rest[..head_len];
    if crc32fast::hash(head) != head_crc {
        return Err(corrupt("its header's checksum differs"));
    }
    let header: CheckpointHeader =
        postcard::from_bytes(head).map_err(|_| corrupt("its header does not read back"))?;
    if header.format != CHECKPOINT_FORMAT {
        return Err(CheckpointError::Format {
            what: what.into(),
            found: header.format,
        });
    }
    let payload = &rest[head_len..];
    if payload.len() as u64 != header.payload_len {
        return Err(corrupt(&format!(
            "its state has {} bytes where its header says {} (truncated or extended)",
            payload.len(),
            header.payload_len
        )));
    }
    if crc32fast::hash(payload) != header.payload_crc {
        return Err(corrupt("its state's checksum differs"));
    }
    Ok(header)
}

/// Writes `bytes` to `path` so that the file is either its old content or the new one, whole,
/// whenever the process or the machine stops: a temporary file beside it, written and synced,
/// renamed over `path`, then the folder synced.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), CheckpointError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| CheckpointError::Io { path, source }
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    // The file is closed at the end of the block, before the rename.
    {
        let mut file = std::fs::File::create(&tmp).map_err(io(&tmp))?;
        let written = file.write_all(bytes).and_then(|_| file.sync_all());
        if let Err(e) = written {
            let _ = std::fs::remove_file(&tmp);
            return Err(io(&tmp)(e));
        }
    }
    std::fs::rename(&tmp, path).map_err(io(path))?;
    #[cfg(unix)]
    if let Some(dir) = path.parent() {
        let dir = if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        };
        // The rename reaches the disk with the folder's entry; a folder that cannot be opened
        // for syncing (some file systems) leaves the rename to the system.
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
