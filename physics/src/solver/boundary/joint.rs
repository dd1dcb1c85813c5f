//! Stage 7 at a node with several active constraints (PHYSICS.md §8, "several active
//! constraints at one node"): a node in a cavity corner, touching two moulds, or glued to one
//! mould and in contact with another gets one local problem over all its active constraints,
//! solved together by [`contact_impulses`] (projected Gauss–Seidel on accumulated impulses, to
//! the stated tolerance), instead of constraint after constraint. A node with at most one
//! active constraint never comes here: it keeps the one-surface closed form of
//! [`BoundaryStep::contact`] (and so its arithmetic, bit for bit).

use super::{BoundaryNode, BoundaryStep, BoundarySums, NodeImpulses, MAX_CONSTRAINTS};
use crate::interface::contact::{contact_impulses, Constraint};
use crate::solver::state::{ContactNode, ContactStatus, InterfaceNode};
use crate::team::SharedSlice;

/// Most constraint entries (glued and contact) one node may have; setup refuses more
/// ([`check_constraint_count`]).
pub(in crate::solver) const MAX_JOINT: usize = crate::interface::contact::JOINT_MAX_CONSTRAINTS;

/// Refuses a node with more than [`MAX_JOINT`] constraint entries (a node can only be on so
/// many moulds at once; more means the scene attaches one face set many times).
pub(in crate::solver) fn check_constraint_count(
    nodes: &[BoundaryNode],
) -> Result<(), crate::solver::SolverError> {
    match nodes
        .iter()
        .find(|b| b.interfaces.len() + b.contacts.len() > MAX_JOINT)
    {
        Some(b) => Err(crate::solver::SolverError::Setup(format!(
            "node {} has {} glued and contact entries: at most {MAX_JOINT} constraints per node are solved together",
            b.node,
            b.interfaces.len() + b.contacts.len()
        ))),
        None => Ok(()),
    }
}

/// One constraint entry of a node: its gap gₙ₊₁, its mould, where it comes from (interface
/// node, or contact node when the flag is false), μ (μ(αₙ₊₁) when glued) and its area W.
#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub gap: f64,
    pub plane: usize,
    pub from: (u32, bool),
    pub mu: f64,
    pub area: f64,
    /// Closed (stick or slip) at the previous step.
    pub held: bool,
}

impl BoundaryStep<'_> {
    /// The constraint entries of node `b`, glued ones first, in the order of `b`'s ranges.
    ///
    /// # Safety
    /// No other thread may write the interface and contact entries of `b`.
    pub(super) unsafe fn entries<'s>(
        &'s self,
        b: &'s BoundaryNode,
        itfs: SharedSlice<InterfaceNode>,
        cns: SharedSlice<ContactNode>,
    ) -> impl Iterator<Item = Entry> + 's {
        let glued = b.interfaces.clone().map(move |e| {
            let j = self.boundary.interfaces[e as usize] as usize;
            let itf = itfs.get(j);
            let spec = &self.model.interfaces[itf.interface as usize];
            Entry {
                gap: itf.gap,
                plane: spec.plane,
                from: (j as u32, true),
                // Before glue that forms on contact has formed: its contact entry's μ.
                mu: match (itf.formed, spec.forms_on_contact) {
                    (false, Some(mu)) => mu,
                    _ => spec.law.mu(itf.alpha, spec.mu_inf),
                },
                area: itf.area,
                held: itf.contact != ContactStatus::Open,
            }
        });
        let contact = b.contacts.clone().map(move |e| {
            let j = self.boundary.contacts[e as usize] as usize;
            let cn = cns.get(j);
            Entry {
                gap: cn.gap,
                plane: cn.plane as usize,
                from: (j as u32, false),
                mu: cn.mu,
                area: cn.area,
                held: cn.contact != ContactStatus::Open,
            }
        });
        glued.chain(contact)
    }

    /// Whether node `b` has two or more active constraints (gₙ₊₁ ≤ 0).
    ///
    /// # Safety
    /// As [`BoundaryStep::entries`].
    pub(super) unsafe fn several_active(
        &self,
        b: &BoundaryNode,
        itfs: SharedSlice<InterfaceNode>,
        cns: SharedSlice<ContactNode>,
    ) -> bool {
        b.interfaces.len() + b.contacts.len() > 1
            && self.entries(b, itfs, cns).filter(|e| e.gap <= 0.0).count() > 1
    }

    /// Stage 7 on node `b` with its active constraints together ([`contact_impulses`] on the
    /// `free` components): each entry gets its impulse per area W R_c/W and status (open ones
    /// zero), the ledger its impulses, `sums` the solve's counts.
    ///
    /// # Safety
    /// No other thread may touch the interface and contact entries of `b`.
    #[allow(clippy::too_many_arguments)]
    pub(super) unsafe fn contact_together(
        &self,
        b: &BoundaryNode,
        itfs: SharedSlice<InterfaceNode>,
        cns: SharedSlice<ContactNode>,
        v: &mut [f64; 3],
        free: [bool; 3],
        impulses: &mut NodeImpulses,
        sums: &mut BoundarySums,
    ) {
        let m = self.mass[b.node as usize];
        let none = Constraint {
            normal: [0.0; 3],
            v_surface: [0.0; 3],
            mu: 0.0,
        };
        let (mut active, mut cs, mut k) = ([None; MAX_JOINT], [none; MAX_JOINT], 0);
        for e in self.entries(b, itfs, cns) {
            if e.gap > 0.0 {
                put(itfs, cns, e.from, [0.0; 3], ContactStatus::Open);
                continue;
            }
            let (n, vm) = self.surface_of(e.plane, e.from);
            (active[k], cs[k]) = (
                Some(e),
                Constraint {
                    normal: n,
                    v_surface: vm[1],
                    mu: e.mu,
                },
            );
            k += 1;
        }
        let (mut p, mut st) = ([[0.0; 3]; MAX_JOINT], [ContactStatus::Open; MAX_JOINT]);
        let solve = contact_impulses(v, &cs[..k], m, free, &mut p[..k], &mut st[..k]);
        for (i, e) in active[..k].iter().flatten().enumerate() {
            let per_area = p[i].map(|c| c / e.area.max(f64::MIN_POSITIVE));
            put(itfs, cns, e.from, per_area, st[i]);
            let c = impulses.contacts;
            if c < MAX_CONSTRAINTS {
                impulses.contact[c] = p[i];
                impulses.contact_from[c] = (e.plane, e.from.0, e.from.1);
                impulses.contacts += 1;
            }
        }
        let j = &mut sums.joint;
        j.nodes += 1;
        j.sweeps += u64::from(solve.sweeps);
        j.friction_dropped += u64::from(solve.friction_dropped);
        if !solve.converged {
            j.capped += 1;
            j.worst_change = j.worst_change.max(solve.change);
            j.worst_approach = j.worst_approach.max(solve.approach);
        }
    }
}

/// Writes the contact impulse per area and the status of entry `from`.
///
/// # Safety
/// No other thread may touch that entry.
pub(super) unsafe fn put(
    itfs: SharedSlice<InterfaceNode>,
    cns: SharedSlice<ContactNode>,
    from: (u32, bool),
    impulse_per_area: [f64; 3],
    status: ContactStatus,
) {
    match from {
        (j, true) => {
            let itf = itfs.get(j as usize);
            (itf.contact_impulse, itf.contact) = (impulse_per_area, status);
        }
        (j, false) => {
            let cn = cns.get(j as usize);
            (cn.contact_impulse, cn.contact) = (impulse_per_area, status);
        }
    }
}
