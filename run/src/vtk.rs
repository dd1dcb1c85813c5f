//! ParaView output (`decohesion run --vtk DIR`): one VTK XML unstructured grid (`.vtu`) per
//! frame and a `.pvd` collection that indexes them by simulated time.
//!
//! Files, in DIR, with `NAME` the scene name (characters other than letters, digits, `-`, `_`
//! and `.` replaced by `_`):
//! - `NAME_000000.vtu`, `NAME_000001.vtu`, … — frame k, written in full under a hidden
//!   temporary name and then renamed, so a `.vtu` that exists is complete;
//! - `NAME_<mould>.vtu` or `NAME_<mould>_000000.vtu`, … — each mould's surface ([`moulds`]):
//!   once for a mould that does not move, at every frame for one that does;
//! - `NAME.pvd` — `<VTKFile type="Collection">` with, per frame, one
//!   `<DataSet timestep="tₙ" part="0" name="body" file="…"/>` and one per mould
//!   (`part` = 1 + its index, `name` = its name): ParaView reads each part as a block. It is a valid file at every moment of the run: each frame is added (by
//!   rewriting the closing tags) as soon as its `.vtu` is in place. A run that fails, is
//!   cancelled (Ctrl-C) or is killed leaves an index of every frame written so far.
//!
//! Every frame holds the reference mesh (points X [m], hexahedra, VTK cell type 12, whose node
//! order is the mesh's) and, all in double precision:
//!
//! | array | where | components | meaning [unit] |
//! |---|---|---|---|
//! | `displacement` | points | 3 | Uₙ [m]; ParaView's *Warp By Vector* on it shows x = X + U |
//! | `velocity` | points | 3 | V_{n+½} [m/s], the CD-Lagrange velocity of the step that follows tₙ (model §4.1: Uₙ₊₁ = Uₙ + h V_{n+½}) |
//! | `alpha` | points | 1 | damage α of an interface node [m] (eq. 12); [`NOT_INTERFACE`] elsewhere |
//! | `state` | points | 1 (Int8) | 0 elastic, 1 transition, 2 ruptured, 3 unformed (glue that forms on contact, not formed yet; [`crate::law::InterfaceState`]); [`NOT_INTERFACE`] on nodes off the interfaces |
//! | `J` | cells | 1 | J = det F at the element centre ξ = 0 ([`crate::output::fields`]) [-] |
//! | `cauchy_stress` | cells | 9 | σ = J⁻¹ F S Fᵀ at the centre, row-major σ_xx σ_xy σ_xz σ_yx … [Pa] |
//! | `von_mises` | cells | 1 | √(3/2 s:s) of that σ [Pa] |
//!
//! The centre values are what one-point integration uses and what `--colour von_mises|jacobian`
//! shows; with full integration they are the element's stress at ξ = 0, not a mean of its Gauss
//! points. A node on two interfaces shows the more damaged one.
//!
//! # Format
//! VTK XML 1.0, `header_type="UInt64"`, every array inline in VTK's base64 `binary` format
//! (a UInt64 byte count then the little-endian values, one base64 stream), uncompressed; the
//! reference mesh is encoded once and copied into every frame. Written here rather than with
//! `vtkio`'s writer, which spent much of its CPU time in quick-xml escaping the base64 text,
//! took several times this writer's CPU per frame and lengthened a run's wall time far more
//! (docs: performance log); `vtkio` reads the files back in the tests (`tests/vtk.rs`), a
//! reader independent of this writer.
//!
//! # Threads
//! The run driver ([`crate::driver`]) copies the state once per frame ([`Snapshot`]) and hands
//! it to every output; this one passes it to a writer thread over a bounded channel
//! (back-pressure, nothing dropped, [`crate::output::worker`]), which computes the element
//! fields, encodes and writes the files at a lower priority. This module uses no Rerun.

mod moulds;

pub use moulds::VTK_TRIANGLE;

use crate::law::InterfaceState;
use crate::model::Model;
use crate::output::fields::centre_fields;
use crate::output::reports::{VtkError, VtkReport};
use crate::output::worker::Worker;
use crate::output::{Ending, Output, OutputError, OutputReport, Snapshot, QUEUE_BYTES};
use crate::solver::Simulation;
use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Value of `alpha` and `state` on nodes that are not interface nodes (α ≥ 0 and states ≥ 0
/// otherwise, so ParaView's *Threshold* on `state` ≥ 0 selects the interface).
pub const NOT_INTERFACE: i8 = -1;

/// Opening and closing of the `.pvd` collection.
const PVD_HEAD: &str = "<?xml version=\"1.0\"?>\n\
<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
const PVD_TAIL: &str = "  </Collection>\n</VTKFile>\n";

/// What the writer thread reports when it ends.
struct WriterEnd {
    frames: u64,
    bytes: u64,
    busy: Duration,
}

/// Writes a running [`Simulation`] as a ParaView time series: an [`Output`] of the run driver,
/// which feeds it the frames and finishes it whatever the outcome.
pub struct VtkWriter {
    worker: Worker<Arc<Snapshot>, WriterEnd, VtkError>,
    pvd: PathBuf,
}

impl VtkWriter {
    /// Creates `dir` (and its parents) and an empty index `dir/NAME.pvd` and starts the
    /// writer thread. A directory that cannot be created or written is reported here, before
    /// the run starts, naming it.
    pub fn new(dir: &Path, sim: &Simulation) -> Result<VtkWriter, VtkError> {
        let started = Instant::now();
        let dir_err = |source| VtkError::Dir {
            dir: dir.to_path_buf(),
            source,
        };
        std::fs::create_dir_all(dir).map_err(dir_err)?;
        let stem = file_stem(&sim.model.name);
        let pvd_path = dir.join(format!("{stem}.pvd"));
        let pvd = Pvd::create(&pvd_path).map_err(dir_err)?;
        let mut series = Series::new(sim, dir.to_path_buf(), stem, pvd);
        let queue = (QUEUE_BYTES / Snapshot::bytes(sim)).clamp(2, 1024);
        let thread_error = |what: &str| VtkError::Thread(what.to_string());
        let body = move |rx: Receiver<Arc<Snapshot>>| {
            let mut busy = Duration::ZERO;
            while let Ok(frame) = rx.recv() {
                let t = Instant::now();
                series.write(&frame)?;
                busy += t.elapsed();
            }
            Ok(WriterEnd {
                frames: series.frames,
                bytes: series.written + series.pvd.len,
                busy,
            })
        };
        let mut worker = Worker::spawn("decohesion-vtk", queue, thread_error, body)?;
        worker.charge(started.elapsed());
        Ok(VtkWriter {
            worker,
            pvd: pvd_path,
        })
    }
}

impl Output for VtkWriter {
    /// Sends one frame to the writer thread. An error of the writer thread (a full disk, a
    /// removed directory) is returned by the next call.
    fn frame(&mut self, snapshot: &Arc<Snapshot>) -> Result<(), OutputError> {
        Ok(self.worker.send(snapshot.clone(), snapshot.capture_time)?)
    }

    /// The `.vtu` files carry the velocity field.
    fn velocities(&self) -> bool {
        true
    }

    /// Sends the last state (if not sent yet) and waits until every frame is written and
    /// indexed.
    fn finish(
        self: Box<Self>,
        last: Option<Arc<Snapshot>>,
        ending: &Ending<'_>,
    ) -> Result<OutputReport, OutputError> {
        let capture = last.as_ref().map_or(Duration::ZERO, |s| s.capture_time);
        let (end, solver_time) = self.worker.finish(last, capture)?;
        let report = VtkReport {
            pvd: self.pvd.display().to_string(),
            frames: end.frames,
            bytes: end.bytes,
            solver_seconds: solver_time.as_secs_f64(),
            writer_thread_seconds: end.busy.as_secs_f64(),
        };
        let line = report.line(ending.step_seconds);
        Ok(OutputReport::new("paraview", &report, Some(line)))
    }
}

/// A scene name usable as a file name stem.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.trim_matches('.').is_empty() {
        "frames".into()
    } else {
        s
    }
}

/// The `.pvd` index, valid after every [`Pvd::add`]: entries are written over the closing tags,
/// which are written again after them.
struct Pvd {
    file: File,
    path: PathBuf,
    /// Where the closing tags start.
    tail_at: u64,
    /// Current length [bytes].
    len: u64,
}

impl Pvd {
    fn create(path: &Path) -> std::io::Result<Pvd> {
        let mut file = File::create(path)?;
        file.write_all(PVD_HEAD.as_bytes())?;
        file.write_all(PVD_TAIL.as_bytes())?;
        file.flush()?;
        Ok(Pvd {
            file,
            path: path.to_path_buf(),
            tail_at: PVD_HEAD.len() as u64,
            len: (PVD_HEAD.len() + PVD_TAIL.len()) as u64,
        })
    }

    /// Indexes `file` (a name in the same directory) at simulated time `t` [s] as block
    /// `part` called `name` (XML-escaped). The time is written in Rust's shortest round-trip
    /// form: it reads back as the same f64.
    fn add(&mut self, t: f64, part: usize, name: &str, file: &str) -> std::io::Result<()> {
        let name = name
            .replace('&', "&amp;")
            .replace('"', "&quot;")
            .replace('<', "&lt;")
            .replace('>', "&gt;");
        let entry = format!(
            "    <DataSet timestep=\"{t}\" group=\"\" part=\"{part}\" name=\"{name}\" \
             file=\"{file}\"/>\n"
        );
        // The new text is longer than the tail it replaces: no truncation needed.
        self.file.seek(SeekFrom::Start(self.tail_at))?;
        self.file
            .write_all(format!("{entry}{PVD_TAIL}").as_bytes())?;
        self.file.flush()?;
        self.tail_at += entry.len() as u64;
        self.len = self.tail_at + PVD_TAIL.len() as u64;
        Ok(())
    }
}

/// Appends one `<DataArray>` in VTK's inline binary format: base64 of a UInt64 byte count
/// followed by the little-endian values, encoded as one stream (what VTK writes uncompressed).
fn data_array<T: Copy, const N: usize>(
    out: &mut String,
    bytes: &mut Vec<u8>,
    attributes: &str,
    values: &[T],
    to_le: impl Fn(T) -> [u8; N],
) {
    use base64::Engine;
    bytes.clear();
    bytes.extend_from_slice(&((N * values.len()) as u64).to_le_bytes());
    for &v in values {
        bytes.extend_from_slice(&to_le(v));
    }
    out.push_str("        <DataArray ");
    out.push_str(attributes);
    out.push_str(" format=\"binary\">");
    base64::engine::general_purpose::STANDARD.encode_string(&bytes[..], out);
    out.push_str("</DataArray>\n");
}

fn f64_array(out: &mut String, bytes: &mut Vec<u8>, attributes: &str, values: &[f64]) {
    data_array(out, bytes, attributes, values, f64::to_le_bytes);
}

/// The writer thread's side: the static mesh data and the index.
struct Series {
    /// The simulation's model, shared, not copied.
    model: Arc<Model>,
    dir: PathBuf,
    stem: String,
    pvd: Pvd,
    /// `<Points>` and `<Cells>` of the reference mesh, encoded once: the same in every frame.
    mesh_xml: String,
    /// (node, interface index) of each interface node.
    interface_nodes: Vec<(u32, u32)>,
    /// Each mould's series.
    moulds: Vec<moulds::MouldSeries>,
    /// Buffers reused from frame to frame.
    text: String,
    bytes: Vec<u8>,
    frames: u64,
    written: u64,
}

impl Series {
    fn new(sim: &Simulation, dir: PathBuf, stem: String, pvd: Pvd) -> Series {
        let model = &sim.model;
        let mesh = &model.mesh;
        let mut mesh_xml = String::new();
        let mut bytes = Vec::new();
        mesh_xml.push_str("      <Points>\n");
        let points: Vec<f64> = mesh.nodes.iter().flatten().copied().collect();
        f64_array(
            &mut mesh_xml,
            &mut bytes,
            "type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"",
            &points,
        );
        mesh_xml.push_str("      </Points>\n      <Cells>\n");
        // Each element type's node order is VTK's for its cell type (`Element::VTK_TYPE`):
        // for the hexahedron 0–3 on ζ = −1 counter-clockwise seen from +ζ, 4–7 above; for the
        // tetrahedron a positive volume.
        let mut connectivity: Vec<i64> = Vec::new();
        let mut offsets: Vec<i64> = Vec::with_capacity(mesh.element_count());
        let mut types: Vec<u8> = Vec::with_capacity(mesh.element_count());
        for (conn, top) in mesh.cells() {
            connectivity.extend(conn.iter().map(|&n| n as i64));
            offsets.push(connectivity.len() as i64);
            types.push(top.vtk_type);
        }
        data_array(
            &mut mesh_xml,
            &mut bytes,
            "type=\"Int64\" Name=\"connectivity\"",
            &connectivity,
            i64::to_le_bytes,
        );
        data_array(
            &mut mesh_xml,
            &mut bytes,
            "type=\"Int64\" Name=\"offsets\"",
            &offsets,
            i64::to_le_bytes,
        );
        data_array(
            &mut mesh_xml,
            &mut bytes,
            "type=\"UInt8\" Name=\"types\"",
            &types,
            u8::to_le_bytes,
        );
        mesh_xml.push_str("      </Cells>\n");
        Series {
            model: model.clone(),
            dir,
            stem,
            pvd,
            mesh_xml,
            interface_nodes: sim
                .state
                .interface_nodes
                .iter()
                .map(|n| (n.node, n.interface))
                .collect(),
            moulds: moulds::MouldSeries::of(model),
            text: String::new(),
            bytes,
            frames: 0,
            written: 0,
        }
    }

    /// The `.vtu` text of one frame, in `self.text`.
    fn grid(&mut self, f: &Snapshot) {
        let m = &self.model;
        let nodes = m.mesh.nodes.len();
        let cells = m.mesh.element_count();
        let mut alpha = vec![NOT_INTERFACE as f64; nodes];
        let mut state = vec![NOT_INTERFACE; nodes];
        for (&(n, _), node) in self.interface_nodes.iter().zip(&f.interface) {
            let (n, a) = (n as usize, node.alpha);
            if a >= alpha[n] {
                alpha[n] = a;
                state[n] = match node.state {
                    InterfaceState::Elastic => 0,
                    InterfaceState::Transition => 1,
                    InterfaceState::Ruptured => 2,
                    InterfaceState::Unformed => 3,
                };
            }
        }
        let mut jac = Vec::with_capacity(cells);
        let mut sigma = Vec::with_capacity(9 * cells);
        let mut vm = Vec::with_capacity(cells);
        for e in 0..cells {
            let c = centre_fields(m, e, &f.u);
            jac.push(c.jacobian);
            for i in 0..3 {
                for j in 0..3 {
                    sigma.push(c.cauchy[(i, j)]);
                }
            }
            vm.push(c.von_mises);
        }
        let flat = |v: &[[f64; 3]]| -> Vec<f64> { v.iter().flatten().copied().collect() };
        let (out, bytes) = (&mut self.text, &mut self.bytes);
        out.clear();
        out.push_str(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
             byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n",
        );
        out.push_str(&format!(
            "    <Piece NumberOfPoints=\"{nodes}\" NumberOfCells=\"{cells}\">\n"
        ));
        out.push_str("      <PointData Vectors=\"displacement\" Scalars=\"state\">\n");
        let vector = "type=\"Float64\" NumberOfComponents=\"3\" Name=";
        f64_array(
            out,
            bytes,
            &format!("{vector}\"displacement\""),
            &flat(&f.u),
        );
        f64_array(out, bytes, &format!("{vector}\"velocity\""), &flat(&f.v));
        f64_array(out, bytes, "type=\"Float64\" Name=\"alpha\"", &alpha);
        data_array(
            out,
            bytes,
            "type=\"Int8\" Name=\"state\"",
            &state,
            i8::to_le_bytes,
        );
        out.push_str("      </PointData>\n");
        out.push_str("      <CellData Scalars=\"von_mises\" Tensors=\"cauchy_stress\">\n");
        f64_array(out, bytes, "type=\"Float64\" Name=\"J\"", &jac);
        f64_array(
            out,
            bytes,
            "type=\"Float64\" Name=\"cauchy_stress\" NumberOfComponents=\"9\"",
            &sigma,
        );
        f64_array(out, bytes, "type=\"Float64\" Name=\"von_mises\"", &vm);
        out.push_str("      </CellData>\n");
        out.push_str(&self.mesh_xml);
        out.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    }

    /// Writes frame k and its moulds' files (each under a hidden name, renamed into place),
    /// then indexes them.
    fn write(&mut self, f: &Snapshot) -> Result<(), VtkError> {
        let name = format!("{}_{:06}.vtu", self.stem, self.frames);
        self.grid(f);
        write_in_place(&self.dir, &name, &self.text)?;
        self.written += self.text.len() as u64;
        let mut entries = vec![(0, "body".to_string(), name)];
        for m in &mut self.moulds {
            let pose = &f.moulds[m.index];
            let (file, bytes) =
                m.write(&self.dir, &self.stem, self.frames, pose, &mut self.bytes)?;
            self.written += bytes;
            entries.push((1 + m.index, m.name.clone(), file));
        }
        let pvd = &mut self.pvd;
        for (part, name, file) in entries {
            pvd.add(f.time, part, &name, &file)
                .map_err(|source| VtkError::Write {
                    path: pvd.path.clone(),
                    source,
                })?;
        }
        self.frames += 1;
        Ok(())
    }
}

/// Writes `text` to `dir/name` under a hidden temporary name, then renames it into place: a
/// file that exists is complete.
fn write_in_place(dir: &Path, name: &str, text: &str) -> Result<(), VtkError> {
    let path = dir.join(name);
    let part = dir.join(format!(".{name}.part"));
    let err = |p: &Path, source| VtkError::Write {
        path: p.to_path_buf(),
        source,
    };
    std::fs::write(&part, text.as_bytes()).map_err(|e| err(&part, e))?;
    std::fs::rename(&part, &path).map_err(|e| err(&path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stems_are_plain_file_names() {
        assert_eq!(file_stem("pull_off"), "pull_off");
        assert_eq!(file_stem("a b/c"), "a_b_c");
        assert_eq!(file_stem(".."), "frames");
    }

    #[test]
    fn the_index_is_complete_after_every_entry() {
        let dir = std::env::temp_dir().join(format!("decohesion-pvd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.pvd");
        let mut pvd = Pvd::create(&path).unwrap();
        let read = || std::fs::read_to_string(&path).unwrap();
        assert_eq!(read(), format!("{PVD_HEAD}{PVD_TAIL}"));
        pvd.add(0.0, 0, "body", "x_000000.vtu").unwrap();
        pvd.add(0.1 + 0.2, 1, "a \"mould\"", "x_000001.vtu")
            .unwrap();
        let text = read();
        assert!(text.ends_with(PVD_TAIL), "{text}");
        assert_eq!(text.matches("<DataSet ").count(), 2);
        // The time reads back as the same f64.
        assert!(text.contains("timestep=\"0.30000000000000004\""), "{text}");
        assert!(
            text.contains("part=\"1\" name=\"a &quot;mould&quot;\""),
            "{text}"
        );
        assert_eq!(pvd.len, text.len() as u64);
        std::fs::remove_dir_all(&dir).ok();
    }
}
