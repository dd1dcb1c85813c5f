//! Readers of the ParaView files, independent of the writer: quick-xml for the `.pvd` index,
//! vtkio for the `.vtu` frames.

use std::collections::BTreeMap;
use std::path::Path;
use vtkio::model::{Attribute, CellType, DataSet, Piece, UnstructuredGridPiece, Vtk};

/// The `(timestep, file)` entries of the body (part 0) in a `.pvd` collection.
pub fn read_pvd(path: &Path) -> Vec<(f64, String)> {
    read_pvd_parts(path)
        .into_iter()
        .filter(|e| e.part == 0)
        .map(|e| (e.time, e.file))
        .collect()
}

/// One `<DataSet>` of a `.pvd` collection.
pub struct PvdEntry {
    pub time: f64,
    pub part: usize,
    pub name: String,
    pub file: String,
}

/// Every entry of a `.pvd` collection, parsed as XML (an error if the file is not
/// well-formed or not a collection).
pub fn read_pvd_parts(path: &Path) -> Vec<PvdEntry> {
    use quick_xml::events::Event;
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{} unreadable: {e}", path.display()));
    let mut reader = quick_xml::Reader::from_str(&text);
    let (mut entries, mut depth, mut root) = (vec![], 0usize, None);
    loop {
        match reader.read_event() {
            Ok(Event::Start(e)) => {
                if depth == 0 {
                    root = e
                        .try_get_attribute("type")
                        .unwrap()
                        .map(|a| String::from_utf8(a.value.to_vec()).unwrap());
                }
                depth += 1;
            }
            Ok(Event::End(_)) => depth -= 1,
            Ok(Event::Empty(e)) if e.name().as_ref() == b"DataSet" => {
                let attr = |k: &str| {
                    let a = e.try_get_attribute(k).unwrap().expect(k);
                    a.unescape_value().unwrap().into_owned()
                };
                entries.push(PvdEntry {
                    time: attr("timestep").parse::<f64>().unwrap(),
                    part: attr("part").parse().unwrap(),
                    name: attr("name"),
                    file: attr("file"),
                });
            }
            Ok(Event::Eof) => break,
            Ok(_) => {}
            Err(e) => panic!("{} is not well-formed XML: {e}\n{text}", path.display()),
        }
    }
    assert_eq!(depth, 0, "{} is not closed:\n{text}", path.display());
    assert_eq!(root.as_deref(), Some("Collection"));
    entries
}

/// One frame read back: mesh and arrays by name, as f64.
pub struct Grid {
    pub points: Vec<f64>,
    pub connectivity: Vec<u64>,
    pub types: Vec<CellType>,
    pub point: BTreeMap<String, Vec<f64>>,
    pub cell: BTreeMap<String, Vec<f64>>,
}

fn arrays(attributes: Vec<Attribute>) -> BTreeMap<String, Vec<f64>> {
    attributes
        .into_iter()
        .map(|a| match a {
            Attribute::DataArray(d) => {
                let v = d.data.cast_into::<f64>().expect("numeric array");
                (d.name, v)
            }
            Attribute::Field { name, .. } => panic!("unexpected field {name}"),
        })
        .collect()
}

pub fn read_vtu(path: &Path) -> Grid {
    let vtk =
        Vtk::import(path).unwrap_or_else(|e| panic!("{} does not read: {e:?}", path.display()));
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else {
        panic!("{} is not an unstructured grid", path.display())
    };
    assert_eq!(pieces.len(), 1);
    let Piece::Inline(piece) = pieces.remove(0) else {
        panic!("inline piece expected")
    };
    let UnstructuredGridPiece {
        points,
        cells,
        data,
    } = *piece;
    let (connectivity, offsets) = cells.cell_verts.into_xml();
    // Hexahedra and tetrahedra (the body) or triangles (a mould).
    let corners = |t: &CellType| match t {
        CellType::Triangle => 3,
        CellType::Tetra => 4,
        CellType::Hexahedron => 8,
        other => panic!("unexpected VTK cell type {other:?}"),
    };
    let ends: Vec<u64> = cells
        .types
        .iter()
        .scan(0, |end, t| {
            *end += corners(t);
            Some(*end)
        })
        .collect();
    assert_eq!(offsets, ends);
    Grid {
        points: points.cast_into::<f64>().unwrap(),
        connectivity,
        types: cells.types,
        point: arrays(data.point),
        cell: arrays(data.cell),
    }
}

/// States of the points of a frame: (not interface, elastic, transition, ruptured).
pub fn state_counts(g: &Grid) -> [usize; 4] {
    let mut c = [0; 4];
    for &s in &g.point["state"] {
        c[(s + 1.0) as usize] += 1;
    }
    c
}
