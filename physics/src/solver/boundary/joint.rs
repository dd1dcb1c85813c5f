//! Stage 7 at a node with several active constraints (model §3.7): a node in a cavity corner,
//! touching two moulds, or glued to one mould and in contact with another gets one local problem
//! over all its active constraints, solved together by [`contact_impulses`] (projected Gauss–Seidel
//! on accumulated impulses, to the stated tolerance), instead of constraint after constraint. A
//! node with at most one active constraint never comes here: it keeps the one-surface closed form
//! of [`BoundaryStep::contact`] (and so its arithmetic, bit for bit).

use super::{BoundaryNode, BoundaryStep, BoundarySums, NodeImpulses, MAX_CONSTRAINTS};
use crate::interface::contact::ContactStatus;
use crate::interface::contact::{contact_impulses, held_reach, Constraint};
use crate::mould::surface::MAX_FACES;
use crate::solver::state::{ContactNode, InterfaceNode};
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
    /// The faces of a triangulated mould the node is behind at a concave edge or vertex
    /// (model §7.5; 0, or 2 to [`MAX_FACES`]): its constraints instead of the one of its gap.
    pub faces: u8,
}

impl Entry {
    /// How far the entry may approach its mould over the next step, h = `h_next`, beyond
    /// v_N = 0 ([`held_reach`]: g⁺/h when held from the previous step, 0 for a first contact
    /// at gₙ₊₁ ≤ 0); `None`: not a candidate of stage 7.
    pub(super) fn reach(&self, h_next: f64) -> Option<f64> {
        held_reach(self.gap, self.held.then_some(h_next))
    }

    /// How many constraints the entry gives stage 7: its faces at a concave edge or vertex
    /// (each behind its plane: a candidate with reach 0), else one when it is a candidate
    /// ([`Entry::reach`]), else none.
    pub(super) fn candidates(&self, h_next: f64) -> usize {
        match self.faces {
            0 => usize::from(self.reach(h_next).is_some()),
            f => f as usize,
        }
    }

    /// The entry as a constraint of the joint solve, n·(V − v_surface) ≥ 0, on the mould of
    /// normal `n` whose point moves at `v_mould` over the next step, with the entry's `reach`
    /// ([`Entry::reach`]): n·(V − v_mould) ≥ −reach is the same inequality with the surface's
    /// velocity shifted along its normal, v_surface = v_mould − reach·n (n unit). The shift is
    /// normal, so the tangential relative velocity, and with it friction, is unchanged. At
    /// reach 0 the constraint is eq. 19's, v_mould itself (the same bits as before the rule).
    pub(super) fn constraint(&self, n: [f64; 3], v_mould: [f64; 3], reach: f64) -> Constraint {
        let v_surface = if reach > 0.0 {
            std::array::from_fn(|c| v_mould[c] - reach * n[c])
        } else {
            v_mould
        };
        Constraint {
            normal: n,
            v_surface,
            mu: self.mu,
        }
    }
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
                faces: self.faces_of(spec.plane, (j as u32, true)).len,
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
                faces: self.faces_of(cn.plane as usize, (j as u32, false)).len,
            }
        });
        glued.chain(contact)
    }

    /// Whether node `b` has two or more candidate constraints ([`Entry::candidates`]: gₙ₊₁ ≤ 0,
    /// held from the previous step, or the faces of a concave edge or vertex).
    ///
    /// # Safety
    /// As [`BoundaryStep::entries`].
    pub(super) unsafe fn several_active(
        &self,
        b: &BoundaryNode,
        itfs: SharedSlice<InterfaceNode>,
        cns: SharedSlice<ContactNode>,
    ) -> bool {
        let entries = b.interfaces.len() + b.contacts.len();
        (entries > 1 || (entries == 1 && self.general))
            && (self.entries(b, itfs, cns))
                .map(|e| e.candidates(self.h_next))
                .sum::<usize>()
                > 1
    }

    /// Stage 7 on node `b` with its active constraints together ([`contact_impulses`] on the
    /// `free` components): each entry gets its impulse per area W R_c/W and status (open ones
    /// zero), the ledger its impulses, `sums` the solve's counts.
    ///
    /// An entry behind faces of a triangulated mould at a concave edge or vertex gives one
    /// constraint per face, n_T·(V − v̄(p)) ≥ 0 (model §7.5), else its one constraint
    /// ([`Entry::constraint`]). **Identical constraints** (the same normal and surface velocity,
    /// bit for bit: two entries of one node on one mould, e.g. two face sets glued to it) are
    /// one constraint of the solve, with μ̄ = Σᵢ Wᵢμᵢ / Σᵢ Wᵢ over its entries (model §3.7): its
    /// impulse p = λ n_F + r_T is shared as pᵢ = (Wᵢ/ΣW) λ n_F + (Wᵢμᵢ/ΣWμ) r_T (by area when
    /// every μᵢ is 0), so each share is in its own cone, |rᵢ| ≤ μᵢλᵢ, and their sum is p. Solved
    /// as two, the first would take the whole impulse with its own μ.
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
        const RAW: usize = MAX_JOINT * MAX_FACES;
        let m = self.mass[b.node as usize];
        let none = Constraint {
            normal: [0.0; 3],
            v_surface: [0.0; 3],
            mu: 0.0,
        };
        // The entries' constraints (`of`: the entry each comes from, an index into `active`).
        let (mut active, mut n_active) = ([None; MAX_JOINT], 0);
        let (mut raw, mut of, mut k_raw) = ([none; RAW], [0usize; RAW], 0);
        for e in self.entries(b, itfs, cns) {
            let Some(reach) = e.reach(self.h_next) else {
                put(itfs, cns, e.from, [0.0; 3], ContactStatus::Open);
                continue;
            };
            let (n, vm) = self.surface_of(e.plane, e.from);
            if e.faces == 0 {
                (raw[k_raw], of[k_raw]) = (e.constraint(n, vm[1], reach), n_active);
                k_raw += 1;
            } else {
                let faces = self.faces_of(e.plane, e.from);
                for nf in &faces.normal[..faces.len as usize] {
                    (raw[k_raw], of[k_raw]) = (e.constraint(*nf, vm[1], 0.0), n_active);
                    k_raw += 1;
                }
            }
            active[n_active] = Some(e);
            n_active += 1;
        }
        // One constraint of the solve per distinct constraint (`group`), with the areas W and
        // the sums of Wμ of the entries that share it.
        let (mut cs, mut group, mut k) = ([none; RAW], [0usize; RAW], 0);
        let (mut shared, mut w, mut wmu) = ([0u8; RAW], [0.0; RAW], [0.0; RAW]);
        for i in 0..k_raw {
            let (c, e) = (raw[i], active[of[i]].expect("an active entry"));
            let bits = |c: &Constraint| (c.normal.map(f64::to_bits), c.v_surface.map(f64::to_bits));
            let u = match (0..k).find(|&u| bits(&cs[u]) == bits(&c)) {
                Some(u) => u,
                None => {
                    (cs[k], shared[k], w[k], wmu[k]) = (c, 0, 0.0, 0.0);
                    k += 1;
                    k - 1
                }
            };
            group[i] = u;
            shared[u] += 1;
            w[u] += e.area;
            wmu[u] += e.area * c.mu;
        }
        for u in (0..k).filter(|&u| shared[u] > 1) {
            cs[u].mu = wmu[u] / w[u];
        }
        let (mut p, mut st) = ([[0.0; 3]; RAW], [ContactStatus::Open; RAW]);
        let solve = contact_impulses(v, &cs[..k], m, free, &mut p[..k], &mut st[..k]);
        // Each constraint's share, booked in the ledger and summed per entry.
        let (mut sum, mut status, mut parts) = (
            [[0.0; 3]; MAX_JOINT],
            [ContactStatus::Open; MAX_JOINT],
            [0u8; MAX_JOINT],
        );
        for i in 0..k_raw {
            let (u, a) = (group[i], of[i]);
            let e = active[a].expect("an active entry");
            let pi = if shared[u] == 1 {
                p[u]
            } else {
                let by_area = e.area / w[u];
                let by_mu = match wmu[u] > 0.0 {
                    true => e.area * raw[i].mu / wmu[u],
                    false => by_area,
                };
                share(p[u], cs[u].normal, free, by_area, by_mu)
            };
            let before = sum[a];
            sum[a] = match parts[a] {
                0 => pi,
                _ => std::array::from_fn(|c| before[c] + pi[c]),
            };
            parts[a] += 1;
            status[a] = stronger(status[a], st[u]);
            let c = impulses.contacts;
            if c < MAX_CONSTRAINTS {
                impulses.contact[c] = pi;
                impulses.contact_normal[c] = raw[i].normal;
                impulses.contact_from[c] = (e.plane, e.from.0, e.from.1);
                impulses.contacts += 1;
            }
        }
        for (a, e) in active[..n_active].iter().flatten().enumerate() {
            let per_area = sum[a].map(|c| c / e.area.max(f64::MIN_POSITIVE));
            put(itfs, cns, e.from, per_area, status[a]);
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

/// The share of an impulse p = λ n_F + r_T of one constraint of normal `n` (n_F its part on the
/// `free` components, r_T ⊥ n, so λ = p·n/|n_F|²) that an entry takes: `normal` of λ n_F and
/// `tangential` of r_T ([`BoundaryStep::contact_together`]).
fn share(p: [f64; 3], n: [f64; 3], free: [bool; 3], normal: f64, tangential: f64) -> [f64; 3] {
    let n_f: [f64; 3] = std::array::from_fn(|c| if free[c] { n[c] } else { 0.0 });
    let nf2: f64 = n_f.iter().map(|c| c * c).sum();
    let lambda = if nf2 > 1e-12 {
        p.iter().zip(&n).map(|(a, b)| a * b).sum::<f64>() / nf2
    } else {
        0.0
    };
    std::array::from_fn(|c| {
        let q = lambda * n_f[c];
        normal * q + tangential * (p[c] - q)
    })
}

/// The status of an entry with several constraints: slipping on any, else sticking on any,
/// else open.
fn stronger(a: ContactStatus, b: ContactStatus) -> ContactStatus {
    use ContactStatus::{Open, Slip, Stick};
    match (a, b) {
        (Slip, _) | (_, Slip) => Slip,
        (Stick, _) | (_, Stick) => Stick,
        _ => Open,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interface::contact::contact_impulses;

    fn entry(gap: f64, held: bool) -> Entry {
        Entry {
            gap,
            plane: 0,
            from: (0, false),
            mu: 0.0,
            area: 1.0,
            held,
            faces: 0,
        }
    }

    /// The candidates of stage 7 and their constraints: an entry with gₙ₊₁ ≤ 0 is one with its
    /// mould's velocity (the same bits); an open entry closed at the previous step is one with
    /// the surface's velocity moved by −(g/h) n; an open entry not closed before is none.
    #[test]
    fn a_held_entry_with_an_open_gap_is_a_candidate_shifted_along_its_normal() {
        let (n, vm, h, g) = ([0.6, 0.0, 0.8], [0.1, -0.3, 0.25], 1e-3, 4e-6);
        for held in [false, true] {
            for gap in [0.0, -2e-6] {
                let e = entry(gap, held);
                assert_eq!(e.reach(h), Some(0.0));
                let c = e.constraint(n, vm, 0.0);
                assert_eq!(c.v_surface.map(f64::to_bits), vm.map(f64::to_bits));
                assert_eq!(c.normal, n);
            }
        }
        assert_eq!(entry(g, false).reach(h), None);
        let e = entry(g, true);
        assert_eq!(e.reach(h), Some(g / h));
        let c = e.constraint(n, vm, g / h);
        for k in 0..3 {
            assert_eq!(c.v_surface[k], vm[k] - g / h * n[k]);
        }
    }

    /// A node in a corner, pressed on a wall (x = 0, active) and held on a floor (z = 0) whose
    /// gap has drifted open by g: solved together, the node approaching the floor faster than
    /// g/h arrives on it at the next position, n·V = −g/h, and no further, while the wall stops
    /// it; approaching slower, the floor takes no impulse and the node closes part of the gap.
    /// Before the held rule the joint solve left the floor out (g > 0) and the node went
    /// through it by h·29 m/s.
    #[test]
    fn a_corner_node_held_on_a_drifted_floor_closes_the_gap_and_no_more() {
        let (m, h, g) = (2.0, 1e-3, 4e-6);
        let (floor, wall) = ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let held = |gap: f64, n: [f64; 3]| {
            let e = entry(gap, true);
            e.constraint(
                n,
                [0.0; 3],
                e.reach(h).expect("a held entry is a candidate"),
            )
        };
        let cs = [held(g, floor), held(0.0, wall)];
        let (mut p, mut st) = ([[0.0; 3]; 2], [ContactStatus::Open; 2]);
        let mut v = [-1.0, 0.2, -29.0];
        let solve = contact_impulses(&mut v, &cs, m, [true; 3], &mut p, &mut st);
        assert!(solve.converged);
        assert!(
            (v[2] + g / h).abs() <= 1e-12 * 29.0,
            "n·V {} against −g/h",
            v[2]
        );
        assert!(v[0].abs() <= 1e-12 * 29.0, "wall: {}", v[0]);
        assert_eq!(v[1], 0.2, "frictionless: the tangential velocity stays");
        assert!(p[0][2] > 0.0 && p[1][0] > 0.0, "{p:?}");
        let mut v = [-1.0, 0.2, -0.5 * g / h];
        contact_impulses(&mut v, &cs, m, [true; 3], &mut p, &mut st);
        assert_eq!(
            p[0], [0.0; 3],
            "approaching slower than g/h: no floor impulse"
        );
        assert_eq!(st[0], ContactStatus::Open);
        assert_eq!(v[2], -0.5 * g / h);
    }
}
