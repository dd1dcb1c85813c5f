//! A mesh cut in two along a plane of its faces (model §7.8): the nodes on the plane X_a = c
//! that belong to elements on the upper side (centroid X_a > c) get copies, which those
//! elements take in place of the originals, so the two sides share no node. The faces on the
//! plane become two face sets: `split-`, the lower side's faces (outward normal +e_a), and
//! `split+`, the upper side's (outward normal −e_a), which a `[[bond]]` joins again node by
//! node.

use super::{Mesh, Topology};
use std::collections::{BTreeMap, BTreeSet};

/// The face sets a split adds, lower side first.
pub const SPLIT_FACE_SETS: [&str; 2] = ["split-", "split+"];

impl Mesh {
    /// Cuts the mesh along X_`axis` = `at` (see the module docs) and returns the number of
    /// nodes copied. The plane must lie strictly inside the mesh's extent along the axis and be
    /// covered by element faces on both sides; existing face sets keep their faces, a face on
    /// the upper side (centroid above the plane) taking the copies. Names the cause otherwise.
    pub fn split(&mut self, axis: usize, at: f64) -> Result<usize, String> {
        let (lo, hi) = self
            .nodes
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x[axis]), b.max(x[axis]))
            });
        let scale = self
            .nodes
            .iter()
            .flatten()
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let tol = 1e-9 * scale.max(hi - lo);
        if !(at > lo + tol && at < hi - tol) {
            return Err(format!(
                "the plane lies outside the mesh or on its boundary: the mesh spans {lo} to {hi} \
                 along this axis, and the cut must be strictly inside"
            ));
        }
        let on = |n: u32| (self.nodes[n as usize][axis] - at).abs() <= tol;
        let centre = |conn: &[u32]| {
            conn.iter()
                .map(|&n| self.nodes[n as usize][axis])
                .sum::<f64>()
                / conn.len() as f64
        };
        // The faces on the plane, each seen from its own element (outward), per side.
        let mut lower = vec![];
        let mut upper = vec![];
        let mut cut: BTreeSet<u32> = BTreeSet::new();
        let mut side = |conn: &[u32], faces: &mut dyn Iterator<Item = [u32; 4]>| {
            let up = centre(conn) > at;
            for quad in faces {
                if quad.iter().all(|&n| on(n)) {
                    if up {
                        upper.push(quad);
                    } else {
                        lower.push(quad);
                    }
                }
            }
            if up {
                cut.extend(conn.iter().filter(|&&n| on(n)));
            }
        };
        for (conn, top) in self.cells() {
            side(conn, &mut top.faces.iter().map(|f| Topology::face(conn, f)));
        }
        if lower.is_empty() || upper.is_empty() {
            return Err(format!(
                "no element face lies on the plane at {at} ({} faces below it, {} above): the \
                 cut must follow a layer of element faces (for a box, origin + size·k/cells)",
                lower.len(),
                upper.len()
            ));
        }
        // The copies follow the nodes, in the order of their originals.
        let first = self.nodes.len() as u32;
        let copies: BTreeMap<u32, u32> = (cut.iter().enumerate())
            .map(|(i, &n)| (n, first + i as u32))
            .collect();
        let moved: Vec<[f64; 3]> = cut.iter().map(|&n| self.nodes[n as usize]).collect();
        self.nodes.extend(moved);
        let take = |n: &mut u32| {
            if let Some(&c) = copies.get(n) {
                *n = c;
            }
        };
        let above = |nodes: &[[f64; 3]], conn: &[u32]| {
            conn.iter().map(|&n| nodes[n as usize][axis]).sum::<f64>() / conn.len() as f64 > at
        };
        for conn in &mut self.elements {
            if above(&self.nodes, conn) {
                conn.iter_mut().for_each(take);
            }
        }
        for conn in &mut self.tets {
            if above(&self.nodes, conn) {
                conn.iter_mut().for_each(take);
            }
        }
        for quads in self.face_sets.values_mut() {
            for q in quads.iter_mut() {
                if above(&self.nodes, q) {
                    q.iter_mut().for_each(take);
                }
            }
        }
        for q in &mut upper {
            q.iter_mut().for_each(take);
        }
        for (name, quads) in SPLIT_FACE_SETS.iter().zip([lower, upper]) {
            if self.face_sets.contains_key(*name) {
                return Err(format!(
                    "the mesh has a face set `{name}` already: a split names its two sides \
                     `split-` and `split+`"
                ));
            }
            self.face_sets.insert(name.to_string(), quads);
        }
        Ok(copies.len())
    }
}

/// A node of one face set and the node of another at the same reference position, joined by a
/// bond (model §7.8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodePair {
    /// The node of the bond's `faces`.
    pub node: u32,
    /// The node of its `to` at the same place.
    pub other: u32,
    /// Tributary reference area W of `node` on `faces` [m²].
    pub area: f64,
    /// Unit normal of `to` at `other` (area-weighted over its quads), pointing out of the `to`
    /// side: the bond's n.
    pub normal: [f64; 3],
}

impl Mesh {
    /// Pairs each node of face set `faces` with the node of `to` at the same reference position
    /// (within 1e-9 of the mesh's size), with its area on `faces` and the normal of `to` there
    /// ([`NodePair`]). Refused, naming the node and its position, when a node has no partner or
    /// is its own (the two sets share a node: nothing to separate).
    pub fn pairs(&self, faces: &[[u32; 4]], to: &[[u32; 4]]) -> Result<Vec<NodePair>, String> {
        let scale = self
            .nodes
            .iter()
            .flatten()
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let tol = 1e-9 * scale.max(f64::MIN_POSITIVE);
        let key = |x: [f64; 3]| x.map(|c| (c / tol).round() as i64);
        let mut normals: BTreeMap<u32, [f64; 3]> = BTreeMap::new();
        for q in to {
            let x = q.map(|n| self.nodes[n as usize]);
            let c = super::cross(super::sub(x[2], x[0]), super::sub(x[3], x[1]));
            let mut distinct = q.to_vec();
            distinct.dedup();
            for n in distinct {
                let acc = normals.entry(n).or_insert([0.0; 3]);
                (0..3).for_each(|k| acc[k] += c[k]);
            }
        }
        let mut at: BTreeMap<[i64; 3], u32> = BTreeMap::new();
        for &n in normals.keys() {
            at.insert(key(self.nodes[n as usize]), n);
        }
        let mut out = vec![];
        for (node, area) in self.nodal_areas(faces) {
            let x = self.nodes[node as usize];
            // The position rounded either way at a cell boundary: look at the neighbours too.
            let k = key(x);
            let near = (0..27).find_map(|i| {
                let d = [i % 3, (i / 3) % 3, i / 9].map(|v| v as i64 - 1);
                at.get(&[k[0] + d[0], k[1] + d[1], k[2] + d[2]]).copied()
            });
            let Some(other) =
                near.filter(|&o| (0..3).all(|c| (self.nodes[o as usize][c] - x[c]).abs() <= tol))
            else {
                return Err(format!(
                    "node {node} at {x:?} has no node of the other face set at its place"
                ));
            };
            if other == node {
                return Err(format!(
                    "node {node} at {x:?} is in both face sets: a bond joins two sides that                      share no node (cut the mesh first, `[mesh.split]`)"
                ));
            }
            let c = normals[&other];
            let l = super::norm(c);
            out.push(NodePair {
                node,
                other,
                area,
                normal: c.map(|v| v / l),
            });
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_split_box_is_two_boxes_sharing_positions_not_nodes() {
        let mut m = Mesh::boxed([0.0; 3], [4.0, 1.0, 2.0], [4, 1, 2]);
        let before = m.nodes.len();
        let copied = m.split(2, 1.0).unwrap();
        assert_eq!(copied, 5 * 2);
        assert_eq!(m.nodes.len(), before + copied);
        let (lo, up) = (&m.face_sets["split-"], &m.face_sets["split+"]);
        assert_eq!((lo.len(), up.len()), (4, 4));
        for q in lo {
            assert!((m.quad_normal(q)[2] - 1.0).abs() < 1e-12);
        }
        for q in up {
            assert!((m.quad_normal(q)[2] + 1.0).abs() < 1e-12);
        }
        // No node is shared across the cut; each side's plane nodes sit where the other's do.
        let lower_nodes = m.face_set_nodes(lo);
        let upper_nodes = m.face_set_nodes(up);
        assert!(lower_nodes.iter().all(|n| !upper_nodes.contains(n)));
        for (a, b) in lower_nodes.iter().zip(&upper_nodes) {
            assert_eq!(m.nodes[*a as usize], m.nodes[*b as usize]);
        }
        for conn in &m.elements {
            let up = conn.iter().any(|&n| m.nodes[n as usize][2] > 1.5);
            let wrong = if up { &lower_nodes } else { &upper_nodes };
            assert!(conn.iter().all(|n| !wrong.contains(n)));
        }
        // The end faces of the upper half took the copies.
        let x_minus = m.face_set_nodes(&m.face_sets["x-"]);
        assert!(upper_nodes.iter().any(|n| x_minus.contains(n)));
        assert!(lower_nodes.iter().any(|n| x_minus.contains(n)));
        // Paired back node to node, with the lower side's normal +z and the upper's areas.
        let pairs = m.pairs(up, lo).unwrap();
        assert_eq!(pairs.len(), 10);
        let total: f64 = pairs.iter().map(|p| p.area).sum();
        assert!((total - 4.0).abs() < 1e-12);
        for p in &pairs {
            assert_eq!(m.nodes[p.node as usize], m.nodes[p.other as usize]);
            assert!((p.normal[2] - 1.0).abs() < 1e-12);
        }
        assert!(m.pairs(up, up).unwrap_err().contains("in both face sets"));
        assert!(m
            .pairs(up, &m.face_sets["z-"])
            .unwrap_err()
            .contains("no node"));
    }

    #[test]
    fn a_cut_off_the_face_layers_or_outside_is_refused() {
        let mut m = Mesh::boxed([0.0; 3], [4.0, 1.0, 2.0], [4, 1, 2]);
        assert!(m.split(2, 0.5).unwrap_err().contains("no element face"));
        assert!(m.split(2, 2.0).unwrap_err().contains("strictly inside"));
        assert!(m.split(0, -1.0).unwrap_err().contains("strictly inside"));
    }
}
