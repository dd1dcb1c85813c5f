//! What acts on each boundary node: its interface, contact and traction entries and its
//! prescribed components, as ranges into flat lists, gathered once at set-up.

use super::NONE;
use std::ops::Range;

/// Per boundary node: which interface entries, contact entries, traction entries and prescribed
/// components act on it.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(in crate::solver) struct BoundaryNode {
    pub node: u32,
    pub interfaces: Range<u32>,
    pub contacts: Range<u32>,
    pub tractions: Range<u32>,
    /// Index of the prescribed-displacement condition of each component (`NONE` if free).
    pub prescribed: [u16; 3],
}

/// The boundary nodes and, per node, ranges into the flat lists of its entries.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub(in crate::solver) struct Boundary {
    pub nodes: Vec<BoundaryNode>,
    /// Indices into `Simulation::interface_nodes`.
    pub interfaces: Vec<u32>,
    /// Indices into `Simulation::contact_nodes`.
    pub contacts: Vec<u32>,
    /// (traction index, nodal force at amplitude 1 [N]).
    pub tractions: Vec<(u16, [f64; 3])>,
    /// Interface nodes whose glue forms on contact and has not formed yet (indices into
    /// `Simulation::interface_nodes`, allocated at setup; [`Simulation::form_glue`] removes
    /// each as it forms).
    pub forming: Vec<u32>,
}

impl Boundary {
    /// Gathers the entries per node: `interfaces` and `contacts` are the nodes of
    /// `Simulation::interface_nodes` and `contact_nodes` in order, `tractions` (node, traction,
    /// nodal force), `prescribed` the prescribed condition of each component per node.
    pub fn gather(
        interfaces: impl Iterator<Item = u32>,
        contacts: impl Iterator<Item = u32>,
        mut tractions: Vec<(u32, u16, [f64; 3])>,
        prescribed: &std::collections::BTreeMap<u32, [u16; 3]>,
    ) -> Boundary {
        let by_node = |nodes: &mut dyn Iterator<Item = u32>| {
            let mut v: Vec<(u32, u32)> = nodes.enumerate().map(|(k, n)| (n, k as u32)).collect();
            v.sort_unstable();
            v
        };
        let by_node_i = by_node(&mut { interfaces });
        let by_node_c = by_node(&mut { contacts });
        tractions.sort_by_key(|t| (t.0, t.1));
        let mut touched: Vec<u32> = by_node_i
            .iter()
            .chain(&by_node_c)
            .map(|e| e.0)
            .chain(tractions.iter().map(|t| t.0))
            .chain(prescribed.keys().copied())
            .collect();
        touched.sort_unstable();
        touched.dedup();
        let mut out = Boundary::default();
        let (mut pi, mut pc, mut pt) = (0usize, 0usize, 0usize);
        // The entries of `node` from a list sorted by node, from cursor `p` on.
        fn take<T: Copy>(
            list: &[(u32, T)],
            p: &mut usize,
            node: u32,
            out: &mut Vec<T>,
        ) -> Range<u32> {
            let start = out.len() as u32;
            while *p < list.len() && list[*p].0 == node {
                out.push(list[*p].1);
                *p += 1;
            }
            start..out.len() as u32
        }
        let tr: Vec<(u32, (u16, [f64; 3]))> = tractions.iter().map(|t| (t.0, (t.1, t.2))).collect();
        for &node in &touched {
            out.nodes.push(BoundaryNode {
                node,
                interfaces: take(&by_node_i, &mut pi, node, &mut out.interfaces),
                contacts: take(&by_node_c, &mut pc, node, &mut out.contacts),
                tractions: take(&tr, &mut pt, node, &mut out.tractions),
                prescribed: prescribed.get(&node).copied().unwrap_or([NONE; 3]),
            });
        }
        out
    }
}
