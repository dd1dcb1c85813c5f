//! The moulds in the ParaView output: each mould its own series of `.vtu` files, indexed in
//! the `.pvd` as its own part (`part` = 1 + the mould's index, `name` = the mould's name; the
//! body is part 0), so ParaView shows each as a block that moves and turns with the run.
//!
//! A mould's file holds its drawing ([`mould_drawing`]: a half-space as a square around the
//! body's bounding box, another shape as its triangles) as VTK triangles (cell type 5), its
//! points placed by the frame's pose, x = R x₀ + T (`Simulation::mould_pose`), in double
//! precision, and the point array `normal` (R N₀, the mould's outward unit normal carried by
//! the pose). A mould that does not move is written once (`NAME_<mould>.vtu`) and every frame
//! indexes that file; a moving one is written at every frame (`NAME_<mould>_<frame>.vtu`).

use super::{data_array, f64_array, VtkError};
use crate::model::Model;
use crate::output::surface::mould::{body_box, mould_drawing, MouldMesh, MouldPose};
use std::path::Path;

/// VTK cell type of the 3-node triangle (`VTK_TRIANGLE`).
pub const VTK_TRIANGLE: u8 = 5;

/// One mould's series.
pub(super) struct MouldSeries {
    /// Index in `Model::moulds`.
    pub(super) index: usize,
    /// The mould's name, and as a file name part.
    pub(super) name: String,
    file_part: String,
    mesh: MouldMesh,
    moves: bool,
    /// `<Cells>` of the drawing, encoded once.
    cells_xml: String,
    /// The file of a mould that does not move, once written.
    written: Option<String>,
}

impl MouldSeries {
    /// The series of every mould of the model.
    pub(super) fn of(m: &Model) -> Vec<MouldSeries> {
        let body = body_box(m);
        let mut bytes = Vec::new();
        m.moulds
            .iter()
            .enumerate()
            .map(|(index, p)| {
                let mesh = mould_drawing(p, body);
                let mut cells_xml = String::from("      <Cells>\n");
                let connectivity: Vec<i64> =
                    mesh.triangles.iter().flatten().map(|&v| v as i64).collect();
                let offsets: Vec<i64> = (1..=mesh.triangles.len() as i64).map(|k| 3 * k).collect();
                for (name, values) in [("connectivity", &connectivity), ("offsets", &offsets)] {
                    let attributes = format!("type=\"Int64\" Name=\"{name}\"");
                    data_array(
                        &mut cells_xml,
                        &mut bytes,
                        &attributes,
                        values,
                        i64::to_le_bytes,
                    );
                }
                let types = vec![VTK_TRIANGLE; mesh.triangles.len()];
                let attributes = "type=\"UInt8\" Name=\"types\"";
                data_array(
                    &mut cells_xml,
                    &mut bytes,
                    attributes,
                    &types,
                    u8::to_le_bytes,
                );
                cells_xml.push_str("      </Cells>\n");
                MouldSeries {
                    index,
                    name: p.name.clone(),
                    file_part: super::file_stem(&p.name),
                    mesh,
                    moves: p.velocity.is_some() || p.angular_velocity.is_some(),
                    cells_xml,
                    written: None,
                }
            })
            .collect()
    }

    /// The file of frame `frame` at `pose`, written unless it is a fixed mould's file already
    /// written; returns its name and the bytes written.
    pub(super) fn write(
        &mut self,
        dir: &Path,
        stem: &str,
        frame: u64,
        pose: &MouldPose,
        bytes: &mut Vec<u8>,
    ) -> Result<(String, u64), VtkError> {
        if let Some(name) = &self.written {
            return Ok((name.clone(), 0));
        }
        let name = if self.moves {
            format!("{stem}_{}_{frame:06}.vtu", self.file_part)
        } else {
            format!("{stem}_{}.vtu", self.file_part)
        };
        let text = self.grid(pose, bytes);
        super::write_in_place(dir, &name, &text)?;
        if !self.moves {
            self.written = Some(name.clone());
        }
        Ok((name, text.len() as u64))
    }

    /// The `.vtu` text of the drawing at `pose`.
    fn grid(&self, pose: &MouldPose, bytes: &mut Vec<u8>) -> String {
        use crate::output::surface::mould::place;
        let r = &pose.0;
        let points: Vec<f64> = self
            .mesh
            .vertices
            .iter()
            .flat_map(|&x| place(pose, x))
            .collect();
        let normals: Vec<f64> = self
            .mesh
            .normals
            .iter()
            .flat_map(|n| {
                std::array::from_fn::<f64, 3, _>(|i| {
                    r[i][0] * n[0] + r[i][1] * n[1] + r[i][2] * n[2]
                })
            })
            .collect();
        let mut out = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
             byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n",
        );
        out.push_str(&format!(
            "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
            self.mesh.vertices.len(),
            self.mesh.triangles.len()
        ));
        out.push_str("      <PointData Normals=\"normal\">\n");
        let vector = "type=\"Float64\" NumberOfComponents=\"3\" Name=";
        f64_array(&mut out, bytes, &format!("{vector}\"normal\""), &normals);
        out.push_str("      </PointData>\n      <Points>\n");
        f64_array(&mut out, bytes, &format!("{vector}\"Points\""), &points);
        out.push_str("      </Points>\n");
        out.push_str(&self.cells_xml);
        out.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
        out
    }
}
