//! A [`Mesh`] written as a `.msh` 4.1 ASCII file.

use super::{GMSH_HEX8_ORDER, HEX8, QUAD4};
use crate::mesh::Mesh;
use std::io::Write;

/// Writes `mesh` as a `.msh` 4.1 ASCII file: one volume entity (physical group "body") holding
/// every node and hexahedron, and one surface entity per face set, in a physical group of the
/// same name, with its quads as stored (outward). Node and element tags start at 1; numbers are
/// written in their shortest round-trip form, so reading the file back gives the same mesh.
pub fn write_msh(mesh: &Mesh, out: &mut impl Write) -> std::io::Result<()> {
    let sets: Vec<(&String, &Vec<[u32; 4]>)> = mesh.face_sets.iter().collect();
    let bbox = |nodes: &mut dyn Iterator<Item = u32>| {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut nodes = nodes.peekable();
        if nodes.peek().is_none() {
            (lo, hi) = ([0.0; 3], [0.0; 3]);
        }
        for n in nodes {
            let x = mesh.nodes[n as usize];
            for c in 0..3 {
                lo[c] = lo[c].min(x[c]);
                hi[c] = hi[c].max(x[c]);
            }
        }
        format!(
            "{:?} {:?} {:?} {:?} {:?} {:?}",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        )
    };
    writeln!(out, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
    writeln!(out, "$PhysicalNames\n{}", sets.len() + 1)?;
    for (k, (name, _)) in sets.iter().enumerate() {
        writeln!(out, "2 {} \"{}\"", k + 1, name)?;
    }
    writeln!(out, "3 1 \"body\"\n$EndPhysicalNames")?;
    writeln!(out, "$Entities\n0 0 {} 1", sets.len())?;
    for (k, (_, quads)) in sets.iter().enumerate() {
        let b = bbox(&mut quads.iter().flatten().copied());
        writeln!(out, "{} {b} 1 {} 0", k + 1, k + 1)?;
    }
    let b = bbox(&mut (0..mesh.nodes.len() as u32));
    let surfaces: Vec<String> = (1..=sets.len()).map(|s| s.to_string()).collect();
    writeln!(
        out,
        "1 {b} 1 1 {} {}\n$EndEntities",
        sets.len(),
        surfaces.join(" ")
    )?;
    let n = mesh.nodes.len();
    writeln!(out, "$Nodes\n1 {n} 1 {n}\n3 1 0 {n}")?;
    for i in 1..=n {
        writeln!(out, "{i}")?;
    }
    for x in &mesh.nodes {
        writeln!(out, "{:?} {:?} {:?}", x[0], x[1], x[2])?;
    }
    writeln!(out, "$EndNodes")?;
    let quads: usize = sets.iter().map(|s| s.1.len()).sum();
    let total = mesh.elements.len() + quads;
    writeln!(out, "$Elements\n{} {total} 1 {total}", sets.len() + 1)?;
    writeln!(out, "3 1 {HEX8} {}", mesh.elements.len())?;
    let mut tag = 0;
    for conn in &mesh.elements {
        tag += 1;
        let ids: Vec<String> = (0..8)
            .map(|a| (conn[GMSH_HEX8_ORDER[a]] + 1).to_string())
            .collect();
        writeln!(out, "{tag} {}", ids.join(" "))?;
    }
    for (k, (_, set)) in sets.iter().enumerate() {
        writeln!(out, "2 {} {QUAD4} {}", k + 1, set.len())?;
        for q in set.iter() {
            tag += 1;
            writeln!(
                out,
                "{tag} {} {} {} {}",
                q[0] + 1,
                q[1] + 1,
                q[2] + 1,
                q[3] + 1
            )?;
        }
    }
    writeln!(out, "$EndElements")
}

/// [`write_msh`] into a string.
pub fn msh_text(mesh: &Mesh) -> String {
    let mut buf = Vec::new();
    write_msh(mesh, &mut buf).expect("writing to memory cannot fail");
    String::from_utf8(buf).expect("the writer emits UTF-8")
}
