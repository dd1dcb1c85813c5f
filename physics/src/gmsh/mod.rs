//! Gmsh meshes: reads `.msh` files of format 4.1 (ASCII or binary, parsed by the `mshio` crate)
//! holding 8-node hexahedra and 4-node tetrahedra into a [`Mesh`], and writes a [`Mesh`] as a
//! `.msh` 4.1 ASCII file.
//!
//! What is read:
//! - every element of a volume entity must be an 8-node hexahedron (Gmsh type 5) or a 4-node
//!   tetrahedron (type 4; both may mix, model §1.13); any other volume element is refused with
//!   its tag and type; a tetrahedron of zero or negative volume is refused with its tag and
//!   volume;
//! - the physical groups of dimension 2 become the face sets, named by `$PhysicalNames` or
//!   `physical_<tag>` when the group has no name; their elements must be 4-node quadrangles
//!   (type 3) that are boundary faces of the hexahedra, or 3-node triangles (type 2) that are
//!   boundary faces of the tetrahedra (stored as [a, b, c, c], see [`Mesh::face_sets`]). Each quad is re-ordered as the face of
//!   its hexahedron, counter-clockwise seen from outside (outward normal, as [`Mesh`] requires),
//!   whatever orientation the file gives it;
//! - nodes that no hexahedron uses (geometry points, construction nodes) are dropped; the others
//!   keep the order of the file and are numbered from 0;
//! - curves, points, surface elements outside physical groups and volume physical groups are
//!   ignored;
//! - every hexahedron must have det J₀ > 0 at its Gauss points (model §1.5); an inverted or
//!   degenerate one is refused with its tag.
//!
//! Node order: Gmsh's hexahedron has node 0 at (u, v, w) = (−1, −1, −1), 1 at (1, −1, −1),
//! 2 at (1, 1, −1), 3 at (−1, 1, −1), then 4–7 above them at w = 1 (Gmsh reference manual,
//! "Node ordering"), exactly [`crate::mesh::HEX_CORNERS`]: the connectivity is taken as it is
//! ([`GMSH_HEX8_ORDER`] is the identity).
//!
//! Node tags: `mshio` keeps the tags of a `$Nodes` section only when they are sparse; when they
//! are contiguous (min..=max, what Gmsh writes) the k-th node of the section in file order has the
//! tag min + k, which is how Gmsh numbers them.

mod header;
mod write;

use crate::element::{Element, Hex8, Tet4};
use crate::mesh::Mesh;
use header::{check_data_size, is_binary, physical_names, syntax_error};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
pub use write::{msh_text, write_msh};

/// Position in a Gmsh hexahedron of the node that [`Mesh`] puts at each local index: the two
/// conventions coincide (see the module docs).
pub const GMSH_HEX8_ORDER: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];

/// Gmsh element type numbers used here.
const HEX8: i32 = <Hex8 as Element>::GMSH_TYPE;
const TET4: i32 = <Tet4 as Element>::GMSH_TYPE;
const QUAD4: i32 = 3;
const TRI3: i32 = 2;

/// Why a `.msh` file could not be read. Every message starts with the file name.
#[derive(Debug, thiserror::Error)]
pub enum MshError {
    /// The file could not be read.
    #[error("{file}: cannot read the mesh file: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    /// The file is not valid MSH 4.1 (`at` is "line N" for ASCII, "byte N" for binary files).
    #[error("{file}: {at}: not a valid MSH 4.1 file: {message}")]
    Syntax {
        file: String,
        at: String,
        message: String,
    },
    /// Valid MSH, but not a mesh this program can use; `message` names the element, node or
    /// physical group.
    #[error("{file}: {message}")]
    Mesh { file: String, message: String },
}

/// How a scene's files (meshes, mould surfaces) are read: `std::fs::read` by default; the web page,
/// which has no file system, passes the files built into it.
pub type ReadFile<'a> = &'a dyn Fn(&Path) -> std::io::Result<Vec<u8>>;

/// Reads the `.msh` file at `path` (see the module docs for what is accepted).
pub fn read_msh(path: &Path) -> Result<Mesh, MshError> {
    read_msh_with(path, &|p| std::fs::read(p))
}

/// Reads the `.msh` file at `path` through `read` (the file system, or the files built into the
/// web page).
pub fn read_msh_with(path: &Path, read: ReadFile) -> Result<Mesh, MshError> {
    let file = path.display().to_string();
    let bytes = read(path).map_err(|source| MshError::Io {
        file: file.clone(),
        source,
    })?;
    parse_msh(&bytes, &file)
}

/// Name of a Gmsh element type for messages.
fn type_name(t: i32) -> String {
    let name = match t {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        11 => "10-node tetrahedron",
        12 => "27-node hexahedron",
        15 => "1-node point",
        17 => "20-node hexahedron",
        _ => return format!("type {t}"),
    };
    format!("type {t}, {name}")
}

/// Parses the bytes of a `.msh` file; `file` names it in messages.
pub fn parse_msh(bytes: &[u8], file: &str) -> Result<Mesh, MshError> {
    let binary = is_binary(bytes);
    check_data_size(bytes, file, binary)?;
    let msh = mshio::parse_msh_bytes(bytes).map_err(|e| syntax_error(&e, bytes, file, binary))?;
    let err = MeshErr(file);
    let names = physical_names(bytes, file, binary)?;
    let nodes = FileNodes::read(&msh, &err)?;
    let group_name = |tag: i32| {
        names
            .get(&(2, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical_{tag}"))
    };
    let el = read_elements(&msh, &nodes, &group_name, &err)?;
    let (mesh, new_index) = volume_mesh(&nodes.coords, &el.hexes, &el.tets, &err)?;
    let mesh = with_face_sets(mesh, &new_index, el.faces, &group_name, &err)?;
    // A Gmsh file numbers its nodes by geometric entity, not by position: renumber them slab by
    // slab for the element loop's caches (a no-op for a file written along its longest axis).
    Ok(mesh.with_nodes_in_slabs())
}

/// Builds the [`MshError::Mesh`] errors of one file.
struct MeshErr<'a>(&'a str);

impl MeshErr<'_> {
    fn at(&self, message: String) -> MshError {
        MshError::Mesh {
            file: self.0.to_string(),
            message,
        }
    }
}

/// The file's nodes: tag → index in file order, and coordinates.
struct FileNodes {
    index: HashMap<u64, usize>,
    coords: Vec<[f64; 3]>,
}

/// A file's msh data, as mshio reads it.
type Msh = mshio::MshFile<u64, i32, f64>;

impl FileNodes {
    fn read(msh: &Msh, err: &MeshErr) -> Result<FileNodes, MshError> {
        let mut out = FileNodes {
            index: HashMap::new(),
            coords: Vec::new(),
        };
        let Some(nodes) = &msh.data.nodes else {
            return Ok(out);
        };
        for block in &nodes.node_blocks {
            let tags: Vec<u64> = match &block.node_tags {
                Some(map) => {
                    let mut tags = vec![0u64; block.nodes.len()];
                    for (&t, &i) in map {
                        tags[i] = t;
                    }
                    if map.len() != block.nodes.len() {
                        return Err(err.at(format!(
                            "the node block of entity (dim {}, tag {}) repeats a node tag",
                            block.entity_dim, block.entity_tag
                        )));
                    }
                    tags
                }
                None => (0..block.nodes.len() as u64)
                    .map(|k| nodes.min_node_tag + out.coords.len() as u64 + k)
                    .collect(),
            };
            for (t, n) in tags.into_iter().zip(&block.nodes) {
                if out.index.insert(t, out.coords.len()).is_some() {
                    return Err(err.at(format!("node tag {t} is defined twice")));
                }
                if ![n.x, n.y, n.z].iter().all(|c| c.is_finite()) {
                    return Err(err.at(format!(
                        "node {t} has a non-finite coordinate ({}, {}, {}): every coordinate \
                         must be a finite number",
                        n.x, n.y, n.z
                    )));
                }
                out.coords.push([n.x, n.y, n.z]);
            }
        }
        Ok(out)
    }

    /// The file index of node `tag`, referred to by element `element`.
    fn get(&self, tag: u64, element: u64, err: &MeshErr) -> Result<usize, MshError> {
        self.index.get(&tag).copied().ok_or_else(|| {
            err.at(format!(
                "element {element} refers to node {tag}, which the $Nodes section does not define"
            ))
        })
    }
}

/// The element types a volume may hold, for messages: "8-node hexahedron (type 5){join}4-node
/// tetrahedron (type 4)".
fn volume_types(join: &str) -> String {
    format!(
        "{} (type {HEX8}){join}{} (type {TET4})",
        Hex8::NAME,
        Tet4::NAME
    )
}

/// The `N` nodes of element `tag` as file node indices, in the mesh's order (Gmsh's, for the
/// hexahedron [`GMSH_HEX8_ORDER`] and the tetrahedron alike).
fn element_nodes<const N: usize>(
    file_nodes: &[u64],
    tag: u64,
    nodes: &FileNodes,
    err: &MeshErr,
) -> Result<[usize; N], MshError> {
    let mut conn = [0usize; N];
    for (a, slot) in conn.iter_mut().enumerate() {
        *slot = nodes.get(file_nodes[a], tag, err)?;
    }
    Ok(conn)
}

/// Hexahedra and tetrahedra (file node indices, element tag), and the faces of each physical
/// surface group (quads; a triangle [a, b, c] as [a, b, c, c]).
struct Elements {
    hexes: Vec<([usize; 8], u64)>,
    tets: Vec<([usize; 4], u64)>,
    faces: BTreeMap<i32, Vec<([usize; 4], u64)>>,
}

/// The hexahedra of the volume entities and the quads of each physical surface group; any
/// other volume element, or any other element in a face set, is refused.
fn read_elements(
    msh: &Msh,
    nodes: &FileNodes,
    group_name: &dyn Fn(i32) -> String,
    err: &MeshErr,
) -> Result<Elements, MshError> {
    let mut surface_groups: HashMap<i32, Vec<i32>> = HashMap::new();
    if let Some(ent) = &msh.data.entities {
        for s in &ent.surfaces {
            surface_groups.insert(s.tag, s.physical_tags.iter().map(|t| t.abs()).collect());
        }
    }
    let mut out = Elements {
        hexes: Vec::new(),
        tets: Vec::new(),
        faces: BTreeMap::new(),
    };
    let Some(elements) = &msh.data.elements else {
        return Ok(out);
    };
    for block in &elements.element_blocks {
        let ty = block.element_type as i32;
        match block.entity_dim {
            3 => {
                for el in &block.elements {
                    let tag = el.element_tag;
                    match ty {
                        HEX8 => out
                            .hexes
                            .push((element_nodes(&el.nodes, tag, nodes, err)?, tag)),
                        TET4 => out
                            .tets
                            .push((element_nodes(&el.nodes, tag, nodes, err)?, tag)),
                        _ => {
                            return Err(err.at(format!(
                                "element {tag} ({}, in volume {}): the volume elements read \
                                 are the {}",
                                type_name(ty),
                                block.entity_tag,
                                volume_types(" and the ")
                            )))
                        }
                    }
                }
            }
            2 => {
                let Some(groups) = surface_groups.get(&block.entity_tag) else {
                    continue;
                };
                for &g in groups {
                    for el in &block.elements {
                        if ty == TRI3 {
                            let mut t = [0usize; 3];
                            for (a, slot) in t.iter_mut().enumerate() {
                                *slot = nodes.get(el.nodes[a], el.element_tag, err)?;
                            }
                            let q = [t[0], t[1], t[2], t[2]];
                            out.faces.entry(g).or_default().push((q, el.element_tag));
                            continue;
                        }
                        if ty != QUAD4 {
                            return Err(err.at(format!(
                                "element {} ({}, in surface {} of physical group \"{}\"): \
                                 only 4-node quadrangles (type 3) and 3-node triangles (type \
                                 2) are supported in face sets",
                                el.element_tag,
                                type_name(ty),
                                block.entity_tag,
                                group_name(g)
                            )));
                        }
                        let mut q = [0usize; 4];
                        for (a, slot) in q.iter_mut().enumerate() {
                            *slot = nodes.get(el.nodes[a], el.element_tag, err)?;
                        }
                        out.faces.entry(g).or_default().push((q, el.element_tag));
                    }
                }
            }
            _ => {}
        }
    }
    Ok(out)
}

/// The mesh of the hexahedra and tetrahedra, with only the nodes they use (in file order),
/// each element checked for inversion (det J₀ > 0 at every Gauss point of a hexahedron, a
/// positive volume for a tetrahedron); and the file-to-mesh node index.
fn volume_mesh(
    coords: &[[f64; 3]],
    hexes: &[([usize; 8], u64)],
    tets: &[([usize; 4], u64)],
    err: &MeshErr,
) -> Result<(Mesh, Vec<u32>), MshError> {
    if hexes.is_empty() && tets.is_empty() {
        return Err(err.at(format!(
            "no {} in the file: the body must be meshed with hexahedra or tetrahedra",
            volume_types(" or ")
        )));
    }
    let mut new_index = vec![u32::MAX; coords.len()];
    let used = (hexes.iter().flat_map(|h| h.0.iter())).chain(tets.iter().flat_map(|t| t.0.iter()));
    for &n in used {
        new_index[n] = 0;
    }
    let mut nodes = Vec::new();
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = nodes.len() as u32;
            nodes.push(coords[i]);
        }
    }
    let elements: Vec<[u32; 8]> = hexes
        .iter()
        .map(|(conn, _)| conn.map(|n| new_index[n]))
        .collect();
    for (e, (_, tag)) in hexes.iter().enumerate() {
        let x = elements[e].map(|n| nodes[n as usize]);
        if let Err(det) = Hex8::reference(&x) {
            return Err(err.at(format!(
                "element {tag} (hexahedron) is inverted or degenerate: det J₀ = {det:e} at a \
                 Gauss point; Gmsh orders its nodes 0–3 counter-clockwise on one face seen from \
                 the opposite face 4–7 (node 4 above 0)"
            )));
        }
    }
    let tets: Vec<[u32; 4]> = (tets.iter())
        .map(|(conn, tag)| {
            let t = conn.map(|n| new_index[n]);
            let (det, _) = crate::element::tet4::tet_gradients(&t.map(|n| nodes[n as usize]));
            if det > 0.0 {
                Ok(t)
            } else {
                Err(err.at(format!(
                    "element {tag} (tetrahedron) has volume {:e} m³: a tetrahedron must have \
                     a positive volume det[X₁ − X₀, X₂ − X₀, X₃ − X₀]/6 (Gmsh's node order); \
                     a zero volume is a degenerate element, a negative one is inverted",
                    det / 6.0
                )))
            }
        })
        .collect::<Result<_, _>>()?;
    let mesh = Mesh {
        nodes,
        elements,
        tets,
        face_sets: BTreeMap::new(),
    };
    Ok((mesh, new_index))
}

/// Face sets from the physical surface groups: each quad becomes the outward face of its
/// hexahedron; a quad off the boundary, or two groups of one name, are refused.
fn with_face_sets(
    mut mesh: Mesh,
    new_index: &[u32],
    group_quads: BTreeMap<i32, Vec<([usize; 4], u64)>>,
    group_name: &dyn Fn(i32) -> String,
    err: &MeshErr,
) -> Result<Mesh, MshError> {
    let mut boundary: HashMap<[u32; 4], [u32; 4]> = HashMap::new();
    for (quad, _) in mesh.boundary_faces() {
        boundary.insert(face_key(quad), quad);
    }
    let mut seen_names: BTreeMap<String, i32> = BTreeMap::new();
    for (g, quads) in group_quads {
        let name = group_name(g);
        if let Some(other) = seen_names.insert(name.clone(), g) {
            return Err(err.at(format!(
                "physical groups {other} and {g} of dimension 2 are both named \"{name}\": face \
                 set names must be unique"
            )));
        }
        let mut set = Vec::with_capacity(quads.len());
        let mut in_set = std::collections::HashSet::new();
        for (q, tag) in quads {
            let key = face_key(q.map(|n| new_index[n]));
            let outward = boundary.get(&key).ok_or_else(|| {
                err.at(format!(
                    "element {tag} (a {} of physical group \"{name}\") is not a face on the \
                     boundary of the body: face sets must lie on its surface, a quadrangle on a \
                     hexahedron, a triangle on a tetrahedron",
                    if q[2] == q[3] {
                        "triangle"
                    } else {
                        "quadrangle"
                    }
                ))
            })?;
            if in_set.insert(key) {
                set.push(*outward);
            }
        }
        mesh.face_sets.insert(name, set);
    }
    Ok(mesh)
}

/// The nodes of a face, sorted, whatever its orientation; a triangle [a, b, c, c] as its 3
/// nodes sorted and the last repeated.
fn face_key(q: [u32; 4]) -> [u32; 4] {
    let mut key = q;
    key.sort_unstable();
    if q[2] == q[3] {
        let mut t = [q[0], q[1], q[2]];
        t.sort_unstable();
        key = [t[0], t[1], t[2], t[2]];
    }
    key
}

/// A surface group read from a `.msh` file: the nodes, the triangles, each triangle's element tag.
pub type SurfaceGroup = (Vec<[f64; 3]>, Vec<[u32; 3]>, Vec<u64>);

/// A triangulated surface (a rigid mould, [`crate::mould::surface`]): the elements of the 2-D
/// physical group named `group` (or `physical_<tag>`) of the `.msh` file `bytes`, 3-node
/// triangles as they are and 4-node quadrangles split along their 0–2 diagonal (both halves keep
/// the quadrangle's orientation). Returns the file's nodes, the triangles (node indices) and the
/// element tag of each triangle. A missing group lists the groups there are; any other element
/// type in the group is refused with its tag.
pub fn read_surface_group(bytes: &[u8], file: &str, group: &str) -> Result<SurfaceGroup, MshError> {
    let binary = is_binary(bytes);
    let msh = mshio::parse_msh_bytes(bytes).map_err(|e| syntax_error(&e, bytes, file, binary))?;
    let err = MeshErr(file);
    let names = physical_names(bytes, file, binary)?;
    let nodes = FileNodes::read(&msh, &err)?;
    let name_of = |tag: i32| {
        names
            .get(&(2, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical_{tag}"))
    };
    let mut entities: Vec<i32> = Vec::new();
    let mut all: Vec<String> = Vec::new();
    for s in msh.data.entities.iter().flat_map(|e| &e.surfaces) {
        for t in s.physical_tags.iter().map(|t| t.abs()) {
            all.push(format!("\"{}\"", name_of(t)));
            if name_of(t) == group {
                entities.push(s.tag);
            }
        }
    }
    if entities.is_empty() {
        all.sort();
        all.dedup();
        return Err(err.at(format!(
            "no 2-D physical group named \"{group}\"; the file has: {}",
            if all.is_empty() {
                "none".to_string()
            } else {
                all.join(", ")
            }
        )));
    }
    let (mut tris, mut tags) = (Vec::new(), Vec::new());
    let blocks = msh.data.elements.iter().flat_map(|e| &e.element_blocks);
    for block in blocks.filter(|b| b.entity_dim == 2 && entities.contains(&b.entity_tag)) {
        let ty = block.element_type as i32;
        for el in &block.elements {
            let n = match ty {
                2 => 3,
                QUAD4 => 4,
                _ => {
                    return Err(err.at(format!(
                        "element {} ({}, in physical group \"{group}\"): a mould surface takes 3-node triangles (type 2) or 4-node quadrangles (type 3)",
                        el.element_tag,
                        type_name(ty)
                    )))
                }
            };
            let mut v = [0u32; 4];
            for a in 0..n {
                v[a] = nodes.get(el.nodes[a], el.element_tag, &err)? as u32;
            }
            tris.push([v[0], v[1], v[2]]);
            tags.push(el.element_tag);
            if n == 4 {
                tris.push([v[0], v[2], v[3]]);
                tags.push(el.element_tag);
            }
        }
    }
    Ok((nodes.coords, tris, tags))
}
