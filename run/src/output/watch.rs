//! Nodes followed over a run (`decohesion run --watch N1,N2,…`, and the explorer's inspected
//! node): the state of one interface or contact node at one step ([`Reading`]: the jump [u],
//! the tractions the glue and the contact exert on the solid, α, the gap, the state and the
//! contact status), and the watched nodes of a run ([`Watch`]: checked against the mesh, with
//! the names of their columns in the time series and of their Rerun entities).
//!
//! A node of the mesh (0-based, the index of the summary and the ParaView files) may have
//! several boundary entries: one per interface whose faces hold it and one per contact face
//! set. Each entry is watched: its columns and entities are named `node17`, or
//! `node17_<mould>` when the node has more than one entry.
//!
//! The state and the contact status are numbers with these codes (the recording's annotation
//! classes for the state): state 0 elastic, 1 transition, 2 ruptured, 3 unformed (glue that
//! forms on contact, not formed yet); contact 0 open, 1 stick, 2 slip.

use crate::interface::contact::ContactStatus;
use crate::law::InterfaceState;
use crate::solver::Simulation;

/// Where an entry's values are read: its index among the simulation's interface nodes
/// (`State::interface_nodes`) or contact-only nodes (`State::contact_nodes`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    Interface(usize),
    Contact(usize),
}

/// One boundary entry of a node at one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading {
    /// The jump [u]ₙ = xₙ − (y₀ + dₙ) from the bonded point y₀ of the mould moved by dₙ [m]
    /// (model §2.1); NaN for a contact-only node and for glue not formed yet.
    pub jump: [f64; 3],
    /// The glue's traction on the solid, −R_d = −g_N(αₙ)[u]ₙ [Pa]; 0 for a contact-only node.
    pub glue: [f64; 3],
    /// The contact's traction on the solid over the last step, R_c/h: the contact impulse per
    /// unit area R_c [Pa·s] over the step h [Pa] (the recording's contact arrows).
    pub contact: [f64; 3],
    /// Damage αₙ [m]; NaN for a contact-only node.
    pub alpha: f64,
    /// Normal gap gₙ to the mould [m].
    pub gap: f64,
    /// The interface state ([`crate::solver::InterfaceNode::state`]); `None` for a
    /// contact-only node.
    pub state: Option<InterfaceState>,
    /// The contact status of the last step.
    pub status: ContactStatus,
}

impl Reading {
    /// The entry `source` of `sim` at its current step.
    pub fn of(sim: &Simulation, source: Source) -> Reading {
        let per_step = |r: f64| {
            if sim.state.h > 0.0 {
                r / sim.state.h
            } else {
                0.0
            }
        };
        match source {
            Source::Interface(j) => {
                let n = &sim.state.interface_nodes[j];
                let law = &sim.model.interfaces[n.interface as usize].law;
                let state = n.state(law);
                let formed = state != InterfaceState::Unformed;
                Reading {
                    jump: if formed { n.jump } else { [f64::NAN; 3] },
                    glue: n.cohesive_traction.map(|r| -r),
                    contact: n.contact_impulse.map(per_step),
                    alpha: n.alpha,
                    gap: n.gap,
                    state: Some(state),
                    status: n.contact,
                }
            }
            Source::Contact(k) => {
                let n = &sim.state.contact_nodes[k];
                Reading {
                    jump: [f64::NAN; 3],
                    glue: [0.0; 3],
                    contact: n.contact_impulse.map(per_step),
                    alpha: f64::NAN,
                    gap: n.gap,
                    state: None,
                    status: n.contact,
                }
            }
        }
    }

    /// Every boundary entry of `sim` in the explorer's order: the interface nodes, then the
    /// contact-only nodes.
    pub fn all(sim: &Simulation) -> Vec<Reading> {
        let interface = (0..sim.state.interface_nodes.len()).map(Source::Interface);
        let contact = (0..sim.state.contact_nodes.len()).map(Source::Contact);
        interface
            .chain(contact)
            .map(|s| Reading::of(sim, s))
            .collect()
    }

    /// The state's code: 0 elastic, 1 transition, 2 ruptured, 3 unformed; NaN for a
    /// contact-only node.
    pub fn state_code(&self) -> f64 {
        match self.state {
            Some(InterfaceState::Elastic) => 0.0,
            Some(InterfaceState::Transition) => 1.0,
            Some(InterfaceState::Ruptured) => 2.0,
            Some(InterfaceState::Unformed) => 3.0,
            None => f64::NAN,
        }
    }

    /// The contact status's code: 0 open, 1 stick, 2 slip.
    pub fn status_code(&self) -> f64 {
        match self.status {
            ContactStatus::Open => 0.0,
            ContactStatus::Stick => 1.0,
            ContactStatus::Slip => 2.0,
        }
    }

    /// The state's name (`contact only` for a contact-only node).
    pub fn state_name(&self) -> &'static str {
        match self.state {
            Some(InterfaceState::Elastic) => "elastic",
            Some(InterfaceState::Transition) => "transition",
            Some(InterfaceState::Ruptured) => "ruptured",
            Some(InterfaceState::Unformed) => "unformed",
            None => "contact only",
        }
    }

    /// The contact status's name.
    pub fn status_name(&self) -> &'static str {
        match self.status {
            ContactStatus::Open => "open",
            ContactStatus::Stick => "stick",
            ContactStatus::Slip => "slip",
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
pub use native::*;

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use super::{Reading, Source};
    use crate::output::series::name_part;
    use crate::solver::Simulation;

    /// The entries shown at most in an error's list of admissible nodes.
    const LISTED: usize = 8;

    /// The columns of an interface entry (after `_node17`: the name part, and the unit).
    const INTERFACE_COLUMNS: [(&str, &str); 13] = [
        ("jump_x", "m"),
        ("jump_y", "m"),
        ("jump_z", "m"),
        ("traction_glue_x", "Pa"),
        ("traction_glue_y", "Pa"),
        ("traction_glue_z", "Pa"),
        ("traction_contact_x", "Pa"),
        ("traction_contact_y", "Pa"),
        ("traction_contact_z", "Pa"),
        ("alpha", "m"),
        ("gap", "m"),
        ("state", "-"),
        ("contact", "-"),
    ];

    /// The columns of a contact-only entry.
    const CONTACT_COLUMNS: [(&str, &str); 5] = [
        ("traction_contact_x", "Pa"),
        ("traction_contact_y", "Pa"),
        ("traction_contact_z", "Pa"),
        ("gap", "m"),
        ("contact", "-"),
    ];

    /// One watched boundary entry.
    #[derive(Debug, Clone, PartialEq, Eq)]
    pub struct Watched {
        /// The node (0-based mesh index).
        pub node: u32,
        pub source: Source,
        /// `node17`, or `node17_<mould>` when the node has several entries: the suffix of its
        /// columns.
        pub name: String,
        /// `nodes/17`, or `nodes/17/<mould>`: the prefix of its Rerun entities.
        pub path: String,
    }

    /// The watched entries of a run, in the order of the nodes given, each node's interface
    /// entries first.
    #[derive(Debug, Clone, Default, PartialEq, Eq)]
    pub struct Watch {
        pub entries: Vec<Watched>,
    }

    /// A node `--watch` cannot follow.
    #[derive(Debug, Clone, thiserror::Error)]
    #[error("--watch {value}: {why}")]
    pub struct WatchError {
        /// The value as given (the node indices, comma-separated).
        pub value: String,
        pub why: String,
    }

    /// A node that cannot be watched is the `watch` output's error, which says it all.
    impl From<WatchError> for crate::output::OutputError {
        fn from(e: WatchError) -> crate::output::OutputError {
            crate::output::OutputError::new("watch", None, e)
        }
    }

    impl Watch {
        /// The entries of `nodes` (a node given twice is watched once). A node out of the
        /// mesh's range, or one that is neither an interface nor a contact node, is refused
        /// with what is admissible.
        pub fn new(sim: &Simulation, nodes: &[u32]) -> Result<Watch, WatchError> {
            let value = (nodes.iter().map(u32::to_string))
                .collect::<Vec<_>>()
                .join(",");
            let refuse = |why: String| WatchError {
                value: value.clone(),
                why,
            };
            let m = &sim.model;
            let count = m.mesh.nodes.len();
            let mut entries = Vec::new();
            let mut seen = Vec::new();
            for &node in nodes {
                if seen.contains(&node) {
                    continue;
                }
                seen.push(node);
                if node as usize >= count {
                    return Err(refuse(format!(
                        "node {node} is not a node of the mesh, which has {count} nodes, 0 to \
                         {}; {}",
                        count - 1,
                        admissible(sim)
                    )));
                }
                let mut own: Vec<(Source, &str)> = Vec::new();
                for (j, n) in sim.state.interface_nodes.iter().enumerate() {
                    if n.node == node {
                        let plane = m.interfaces[n.interface as usize].plane;
                        own.push((Source::Interface(j), m.moulds[plane].name.as_str()));
                    }
                }
                for (k, n) in sim.state.contact_nodes.iter().enumerate() {
                    if n.node == node {
                        own.push((Source::Contact(k), m.moulds[n.plane as usize].name.as_str()));
                    }
                }
                if own.is_empty() {
                    return Err(refuse(format!(
                        "node {node} is neither an interface node nor a contact node; {}",
                        admissible(sim)
                    )));
                }
                let several = own.len() > 1;
                let mut names: Vec<String> = Vec::new();
                for (source, mould) in own {
                    let (mut name, mut path) = match several {
                        true => {
                            let m = name_part(mould);
                            (format!("node{node}_{m}"), format!("nodes/{node}/{m}"))
                        }
                        false => (format!("node{node}"), format!("nodes/{node}")),
                    };
                    // Two entries on one mould (two glued face sets sharing the node).
                    let again = names.iter().filter(|n| **n == name).count();
                    if again > 0 {
                        name = format!("{name}_{}", again + 1);
                        path = format!("{path}_{}", again + 1);
                    }
                    names.push(name.clone());
                    entries.push(Watched {
                        node,
                        source,
                        name,
                        path,
                    });
                }
            }
            Ok(Watch { entries })
        }

        pub fn is_empty(&self) -> bool {
            self.entries.is_empty()
        }

        /// The reading of each entry in `sim`'s current state.
        pub fn readings(&self, sim: &Simulation) -> Vec<Reading> {
            (self.entries.iter())
                .map(|w| Reading::of(sim, w.source))
                .collect()
        }

        /// The time series' columns of the entries, `name [unit]` (e.g. `jump_x_node17 [m]`),
        /// with whether each holds whole numbers: per interface entry [u] (x, y, z) [m], the
        /// glue's and the contact's tractions on the solid (x, y, z each) [Pa], α [m], g [m],
        /// the state's and the contact status's codes [-]; per contact-only entry the
        /// contact's traction, g and the contact status's code.
        pub fn columns(&self) -> (Vec<String>, Vec<bool>) {
            let (mut names, mut integer) = (Vec::new(), Vec::new());
            for w in &self.entries {
                for (part, unit) in columns_of(w.source) {
                    names.push(format!("{part}_{} [{unit}]", w.name));
                    integer.push(*unit == "-");
                }
            }
            (names, integer)
        }

        /// Appends the entries' values of `sim`'s current state to a row, in
        /// [`Watch::columns`] order. A contact-only node's state is not a column; an interface
        /// entry's codes are exact whole numbers.
        pub fn row(&self, sim: &Simulation, out: &mut Vec<f64>) {
            for w in &self.entries {
                values(&Reading::of(sim, w.source), w.source, out);
            }
        }
    }

    /// The columns of an entry of this source.
    fn columns_of(source: Source) -> &'static [(&'static str, &'static str)] {
        match source {
            Source::Interface(_) => &INTERFACE_COLUMNS,
            Source::Contact(_) => &CONTACT_COLUMNS,
        }
    }

    /// Appends the values of `r` in the order of the columns of `source`.
    fn values(r: &Reading, source: Source, out: &mut Vec<f64>) {
        match source {
            Source::Interface(_) => {
                out.extend(r.jump);
                out.extend(r.glue);
                out.extend(r.contact);
                out.extend([r.alpha, r.gap, r.state_code(), r.status_code()]);
            }
            Source::Contact(_) => {
                out.extend(r.contact);
                out.extend([r.gap, r.status_code()]);
            }
        }
    }

    /// What `--watch` admits in `sim`: how many interface and contact-only nodes there are,
    /// the first few of each.
    fn admissible(sim: &Simulation) -> String {
        let list = |what: &str, nodes: Vec<u32>| -> Option<String> {
            let mut nodes = nodes;
            nodes.sort_unstable();
            nodes.dedup();
            let shown: Vec<String> = nodes.iter().take(LISTED).map(u32::to_string).collect();
            let more = if nodes.len() > LISTED { ", …" } else { "" };
            (!nodes.is_empty()).then(|| {
                format!(
                    "the {} {what} nodes ({}{more})",
                    nodes.len(),
                    shown.join(", ")
                )
            })
        };
        let interface = list(
            "interface",
            sim.state.interface_nodes.iter().map(|n| n.node).collect(),
        );
        let contact = list(
            "contact",
            sim.state.contact_nodes.iter().map(|n| n.node).collect(),
        );
        match [interface, contact] {
            [None, None] => {
                "this scene has no interface and no contact face: nothing to watch".into()
            }
            [a, b] => format!(
                "admissible: {}",
                a.into_iter().chain(b).collect::<Vec<_>>().join(" and ")
            ),
        }
    }

    #[cfg(test)]
    mod tests {
        use super::*;
        use crate::law::InterfaceState;

        fn sim(scene: &str, set: &[&str]) -> Simulation {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(scene);
            let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
            Simulation::new(crate::scene::load_scene(&path, &set).unwrap().model).unwrap()
        }

        /// The pull-off's glued corner: one interface entry, its 13 columns named after it,
        /// and a row that reads the state (at t = 0: no jump, elastic).
        #[test]
        fn an_interface_node_has_its_columns_and_row() {
            let s = sim("scenes/pull_off.toml", &["mesh.cells=[2,2,2]"]);
            let corner = s.state.interface_nodes[0].node;
            let w = Watch::new(&s, &[corner, corner]).unwrap();
            assert_eq!(w.entries.len(), 1, "a node given twice is watched once");
            assert_eq!(w.entries[0].source, Source::Interface(0));
            assert_eq!(w.entries[0].path, format!("nodes/{corner}"));
            let (names, integer) = w.columns();
            assert_eq!(names.len(), 13);
            assert_eq!(names[0], format!("jump_x_node{corner} [m]"));
            assert_eq!(names[12], format!("contact_node{corner} [-]"));
            assert_eq!(integer.iter().filter(|i| **i).count(), 2);
            let mut row = vec![];
            w.row(&s, &mut row);
            assert_eq!(row.len(), 13);
            let r = Reading::of(&s, Source::Interface(0));
            assert_eq!(r.state, Some(InterfaceState::Elastic));
            assert_eq!(r.jump, [0.0; 3]);
            assert_eq!((row[9], row[11], row[12]), (r.alpha, 0.0, r.status_code()));
        }

        /// Out of range, a node inside the body: refused naming the flag, the value and what
        /// is admissible.
        #[test]
        fn a_node_that_cannot_be_watched_is_refused() {
            let s = sim("scenes/pull_off.toml", &["mesh.cells=[2,2,2]"]);
            let e = Watch::new(&s, &[3, 27]).unwrap_err().to_string();
            assert!(e.starts_with("--watch 3,27: node 27"), "{e}");
            assert!(e.contains("27 nodes") && e.contains("0 to 26"), "{e}");
            // The centre of the 2³ cube: 13.
            let e = Watch::new(&s, &[13]).unwrap_err().to_string();
            assert!(
                e.contains("node 13 is neither")
                    && e.contains("admissible: the 9 interface nodes (0, 1, 2, 3, 4, 5, 6, 7, …)"),
                "{e}"
            );
            assert!(!e.contains("contact nodes ("), "{e}");
        }

        /// Demoulding: a bottom edge node is glued to the floor and in contact with a wall, two
        /// entries named after their moulds; a contact-only node has 5 columns.
        #[test]
        fn a_node_with_several_entries_is_watched_on_each() {
            let s = sim("scenes/demould.toml", &["mesh.cells=[2,2,2]"]);
            let both = (s.state.interface_nodes.iter().map(|n| n.node))
                .find(|n| s.state.contact_nodes.iter().any(|c| c.node == *n))
                .expect("an edge node glued and in contact");
            let w = Watch::new(&s, &[both]).unwrap();
            assert!(w.entries.len() >= 2, "{w:?}");
            assert!(matches!(w.entries[0].source, Source::Interface(_)));
            assert_eq!(w.entries[0].name, format!("node{both}_floor"));
            assert!(w.entries[1..].iter().all(|e| e.name.contains("_wall_")));
            let only = (s.state.contact_nodes.iter().map(|c| c.node))
                .find(|n| !s.state.interface_nodes.iter().any(|i| i.node == *n))
                .unwrap();
            let w = Watch::new(&s, &[only]).unwrap();
            let (names, _) = w.columns();
            assert!(names.len() % 5 == 0 && !names.is_empty(), "{names:?}");
            let r = w.readings(&s)[0];
            assert!(r.alpha.is_nan() && r.state.is_none() && r.state_code().is_nan());
        }
    }
}
