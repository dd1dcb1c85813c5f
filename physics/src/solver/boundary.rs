//! Stages 5–8 (model §4.5–§4.8) at the boundary nodes: what acts on each node (glue, contact,
//! tractions, prescribed components) and the fused pass that applies, node by node, the stage
//! functions in their order: external tractions and cohesion, the free velocity (5) completed,
//! prescribed components (6), contact (7), the node's ledger halves (summed here, closed in
//! stage 9), and the damage prediction (8). A node's stages read and write only that node, so
//! the pass runs in fixed chunks on the thread team.

use super::stages::StepScratch;
use super::state::{ContactNode, InterfaceNode};
use super::{Simulation, BOUNDARY_GRAIN};
use crate::interface::contact::{contact_impulse, JointStats};
use crate::kernels::{internal_and_gravity_impulses, Planes, PlanesPtr};
use crate::mesh::dot;
use crate::model::Model;
use crate::mould::step::{MouldStep, NodeGeometry};
use crate::mould::surface::{Faces, MAX_FACES};
use crate::team::SharedSlice;
use std::ops::Range;

mod adhesion;
mod entries;
mod joint;
mod moulds;

pub(super) use entries::{Boundary, BoundaryNode};
pub(super) use joint::check_constraint_count;

/// No prescribed condition on this component.
pub(super) const NONE: u16 = u16::MAX;

/// Contact constraints on one node kept for the ledger (a node on a cavity corner has a few):
/// as many as the joint solve takes (each of [`joint::MAX_JOINT`] entries, refused beyond at
/// setup, with up to [`MAX_FACES`] faces of a concave edge or vertex, model §7.5), so no
/// impulse that acted is left out of the ledger.
const MAX_CONSTRAINTS: usize = joint::MAX_JOINT * MAX_FACES;

/// Read-only data of the boundary pass for one step.
struct BoundaryStep<'a> {
    model: &'a Model,
    boundary: &'a Boundary,
    /// The step's surface and prescribed velocities, traction amplitudes, and V_{n+½} of the
    /// boundary nodes (stages 4 and 5).
    scratch: &'a StepScratch,
    /// The moulds' poses and per-node geometry (stages 2 and 4).
    moulds: &'a MouldStep,
    mass: &'a [f64],
    inv_mass: &'a [f64],
    f_int: &'a Planes,
    h_bar: f64,
    h_next: f64,
    /// Some mould is not a plain plane (else every node takes the plane path at once).
    general: bool,
}

/// The [`BoundaryStep`] of simulation `$sim` over h̄ = `$h_bar`, h_{n+3/2} = `$h_next`,
/// borrowing its fields one by one (the pass writes V and the interface entries meanwhile).
macro_rules! boundary_step {
    ($sim:ident, $h_bar:expr, $h_next:expr) => {
        BoundaryStep {
            model: &$sim.model,
            boundary: &$sim.state.boundary,
            scratch: &$sim.work.step,
            moulds: &$sim.state.moulds,
            mass: &$sim.setup.mass,
            inv_mass: &$sim.setup.inv_mass,
            f_int: &$sim.state.f_int,
            h_bar: $h_bar,
            h_next: $h_next,
            general: $sim.state.moulds.any_general(),
        }
    };
}

/// Sums of the boundary pass over a chunk of boundary nodes, reduced in chunk order: the
/// ledger halves (before/after) of tractions, reactions, planes, contact (normal, tangential),
/// and the node loop's corrections.
#[derive(Default, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(super) struct BoundarySums {
    pub trac_b: f64,
    pub trac_a: f64,
    pub reac_b: f64,
    pub reac_a: f64,
    pub plane_b: f64,
    pub plane_a: f64,
    pub cn_b: f64,
    pub cn_a: f64,
    pub ct_b: f64,
    pub ct_a: f64,
    pub int_a: f64,
    pub grav_a: f64,
    pub kinetic: f64,
    pub kinetic_half: f64,
    /// Stage 7's joint solves at nodes with several active constraints.
    pub joint: JointStats,
}

impl BoundarySums {
    pub fn add(mut self, o: BoundarySums) -> BoundarySums {
        self.trac_b += o.trac_b;
        self.trac_a += o.trac_a;
        self.reac_b += o.reac_b;
        self.reac_a += o.reac_a;
        self.plane_b += o.plane_b;
        self.plane_a += o.plane_a;
        self.cn_b += o.cn_b;
        self.cn_a += o.cn_a;
        self.ct_b += o.ct_b;
        self.ct_a += o.ct_a;
        self.int_a += o.int_a;
        self.grav_a += o.grav_a;
        self.kinetic += o.kinetic;
        self.kinetic_half += o.kinetic_half;
        self.joint = self.joint.merge(o.joint);
        self
    }
}

/// The impulses that acted on one node in this step, kept for its ledger halves: cohesion
/// (per interface entry) and contact (per constraint), each with its mould and the entry it
/// came from (interface node, or contact node when `from_interface` is false), whose geometry
/// gives the mould's velocity and normal where it acts ([`BoundaryStep::glue`],
/// [`BoundaryStep::surface`]), in the order they acted. One per chunk, [`NodeImpulses::clear`]ed
/// per node: the slots below the counts are the ones written, and zeroing the whole record per
/// node was a visible share of the boundary pass (docs: performance log).
#[derive(Default)]
struct NodeImpulses {
    cohesion: [[f64; 3]; MAX_CONSTRAINTS],
    cohesion_from: [(usize, u32); MAX_CONSTRAINTS],
    cohesions: usize,
    contact: [[f64; 3]; MAX_CONSTRAINTS],
    /// The normal each contact impulse acted along (its entry's, or a face's, model §7.5).
    contact_normal: [[f64; 3]; MAX_CONSTRAINTS],
    contact_from: [(usize, u32, bool); MAX_CONSTRAINTS],
    contacts: usize,
}

impl NodeImpulses {
    /// No impulse yet (the slots are left as they are).
    fn clear(&mut self) {
        self.cohesions = 0;
        self.contacts = 0;
    }
}

impl BoundaryStep<'_> {
    /// The glue normal of interface node `j` on mould `k` and the mould's velocity at its
    /// anchor over the intervals before and after tₙ₊₁: a plain plane's normal and velocities,
    /// or on a curved mould the normal at the anchor turned with it and the anchor's velocity
    /// ([`crate::mould::step`]).
    #[inline]
    fn glue(&self, j: usize, k: usize) -> ([f64; 3], [[f64; 3]; 2]) {
        let ms = &self.moulds;
        if !self.general || ms.plane[k] {
            let sc = self.scratch;
            (
                self.model.moulds[k].normal,
                [sc.plane_v_old[k], sc.plane_v_new[k]],
            )
        } else {
            let g = &ms.interface[j];
            let v = [ms.velocity_old(k, g.anchor), ms.velocity_new(k, g.anchor)];
            (g.glue_normal, v)
        }
    }

    /// The contact normal of a node on mould `k` and the mould's velocity at the contact point
    /// before and after tₙ₊₁ (`geo`: the node's geometry on a curved mould).
    #[inline]
    fn surface(&self, k: usize, geo: Option<&NodeGeometry>) -> ([f64; 3], [[f64; 3]; 2]) {
        let ms = &self.moulds;
        match geo {
            Some(g) if self.general && !ms.plane[k] => {
                let v = [ms.velocity_old(k, g.point), ms.velocity_new(k, g.point)];
                (g.normal, v)
            }
            _ => {
                let sc = self.scratch;
                (
                    self.model.moulds[k].normal,
                    [sc.plane_v_old[k], sc.plane_v_new[k]],
                )
            }
        }
    }

    /// [`BoundaryStep::surface`] for the entry `from` (interface node, or contact node when
    /// the flag is false) on mould `k`.
    #[inline]
    fn surface_of(&self, k: usize, from: (u32, bool)) -> ([f64; 3], [[f64; 3]; 2]) {
        let ms = &self.moulds;
        let geo = match from {
            (j, true) => ms.interface.get(j as usize),
            (j, false) => ms.contact.get(j as usize),
        };
        self.surface(k, geo)
    }

    /// The faces of a concave edge or vertex the entry `from` (interface node, or contact node
    /// when the flag is false) is behind on mould `k` (model §7.5; none on a plain plane or
    /// another shape).
    #[inline]
    fn faces_of(&self, k: usize, from: (u32, bool)) -> Faces {
        let ms = &self.moulds;
        if !self.general || ms.plane[k] {
            return Faces::default();
        }
        let geo = match from {
            (j, true) => ms.interface.get(j as usize),
            (j, false) => ms.contact.get(j as usize),
        };
        geo.map_or_else(Faces::default, |g| g.faces)
    }

    /// External traction impulse of entry `e` over the step, P = h̄ a(tₙ₊₁) W t (a dead load on
    /// the reference area W; `fv` = W t is stored per entry) [N·s].
    #[inline]
    fn traction_impulse(&self, e: u32) -> [f64; 3] {
        let (tk, fv) = self.boundary.tractions[e as usize];
        fv.map(|c| self.h_bar * self.scratch.amplitudes[tk as usize] * c)
    }

    /// External tractions on node `b` (part of F_ext in stage 5): V += M⁻¹P, and their
    /// backward ledger halves ½V_{n+½}·P.
    fn tractions(&self, b: &BoundaryNode, vo: [f64; 3], v: &mut [f64; 3], out: &mut BoundarySums) {
        let im = self.inv_mass[b.node as usize];
        for e in b.tractions.clone() {
            let p = self.traction_impulse(e);
            // v is updated after all smooth impulses; the forward half uses the final v.
            out.trac_b += 0.5 * dot(vo, p);
            for c in 0..3 {
                v[c] += p[c] * im;
            }
        }
    }

    /// Stage 5's cohesion on node `b`: g_N(αₙ₊₁), R_d = g_N(αₙ₊₁)[u]ₙ₊₁ and the
    /// cohesive impulse P_coh = −h̄ W R_d added to the velocity.
    ///
    /// # Safety
    /// No other thread may touch the interface entries of `b`.
    unsafe fn cohesion(
        &self,
        b: &BoundaryNode,
        itfs: SharedSlice<InterfaceNode>,
        v: &mut [f64; 3],
        impulses: &mut NodeImpulses,
    ) {
        let im = self.inv_mass[b.node as usize];
        for e in b.interfaces.clone() {
            let j = self.boundary.interfaces[e as usize] as usize;
            let itf = itfs.get(j);
            if !itf.formed {
                continue; // glue that forms on contact, not formed yet: no force
            }
            let spec = &self.model.interfaces[itf.interface as usize];
            let n = self.glue(j, spec.plane).0;
            let law = &spec.law;
            itf.stiffness = law.g_n(itf.alpha);
            itf.cohesive_traction = law.cohesive_traction(itf.stiffness, itf.jump, n);
            let p = itf.cohesive_traction.map(|c| -self.h_bar * itf.area * c);
            let slot = impulses.cohesions;
            if slot < MAX_CONSTRAINTS {
                impulses.cohesion[slot] = p;
                impulses.cohesion_from[slot] = (spec.plane, j as u32);
                impulses.cohesions = slot + 1;
            }
            for c in 0..3 {
                v[c] += p[c] * im;
            }
        }
    }

    /// Stage 6 on node `b`: V_{n+3/2} = (Ū(tₙ₊₂) − Ū(tₙ₊₁))/h on the prescribed components; the
    /// reaction is what it took, M(V − V_free)/h̄. Returns which components are free.
    fn prescribed(
        &self,
        b: &BoundaryNode,
        vo: [f64; 3],
        v: &mut [f64; 3],
        reactions: &mut [f64],
        out: &mut BoundarySums,
    ) -> [bool; 3] {
        let m = self.mass[b.node as usize];
        let v_free = *v;
        for c in 0..3 {
            let bc = b.prescribed[c];
            if bc != NONE {
                v[c] = self.scratch.bc_velocity[bc as usize];
                let p = m * (v[c] - v_free[c]);
                reactions[bc as usize] += p / self.h_bar;
                out.reac_b += 0.5 * vo[c] * p;
            }
        }
        b.prescribed.map(|bc| bc == NONE)
    }

    /// Stage 7 on node `b`: each glued entry (μ(αₙ₊₁) of its law) and each contact entry
    /// against its mould, on the node's `free` components. The candidates are the entries with
    /// gₙ₊₁ ≤ 0 and those closed at the previous step, held while their gap is open:
    /// v_N ≥ −g⁺/h_{n+3/2} ([`held_reach`], one definition for both paths). A node with at most
    /// one candidate gets the one-surface closed form ([`contact_impulse`]); a node with several
    /// gets them solved together ([`BoundaryStep::contact_together`], a held entry's surface
    /// velocity shifted by −(g⁺/h_{n+3/2}) n, [`joint::Entry::constraint`]). An entry behind
    /// the faces of a concave edge or vertex of a triangulated mould gives one candidate per
    /// face (model §7.5).
    ///
    /// [`held_reach`]: crate::interface::contact::held_reach
    ///
    /// # Safety
    /// No other thread may touch the interface and contact entries of `b`.
    #[allow(clippy::too_many_arguments)]
    unsafe fn contact(
        &self,
        b: &BoundaryNode,
        itfs: SharedSlice<InterfaceNode>,
        cns: SharedSlice<ContactNode>,
        v: &mut [f64; 3],
        free: [bool; 3],
        impulses: &mut NodeImpulses,
        sums: &mut BoundarySums,
    ) {
        if self.several_active(b, itfs, cns) {
            return self.contact_together(b, itfs, cns, v, free, impulses, sums);
        }
        let m = self.mass[b.node as usize];
        for e in self.entries(b, itfs, cns) {
            let (n, vm) = self.surface_of(e.plane, e.from);
            let held = e.held.then_some(self.h_next);
            let (impulse, status) = contact_impulse(v, e.gap, n, vm[1], e.mu, m, free, held);
            let k = impulses.contacts;
            if k < MAX_CONSTRAINTS {
                impulses.contact[k] = impulse;
                impulses.contact_normal[k] = n;
                impulses.contact_from[k] = (e.plane, e.from.0, e.from.1);
                impulses.contacts += 1;
            }
            let per_area = impulse.map(|c| c / e.area.max(f64::MIN_POSITIVE));
            joint::put(itfs, cns, e.from, per_area, status);
        }
    }

    /// The node's forward ledger halves with its final velocity V_{n+3/2} (model §5.3), and
    /// the corrections of the all-node loop's sums (which used the free velocity).
    #[allow(clippy::too_many_arguments)]
    fn ledger_halves(
        &self,
        b: &BoundaryNode,
        vo: [f64; 3],
        v_free0: [f64; 3],
        v_free: [f64; 3],
        v: [f64; 3],
        impulses: &NodeImpulses,
        out: &mut BoundarySums,
    ) {
        let (h_bar, g) = (self.h_bar, self.model.gravity);
        let i = b.node as usize;
        let m = self.mass[i];
        let dv = [v[0] - v_free0[0], v[1] - v_free0[1], v[2] - v_free0[2]];
        let (pint, pg) = internal_and_gravity_impulses(h_bar, self.f_int.get(i), m, g);
        out.int_a += 0.5 * dot(dv, pint);
        out.grav_a += 0.5 * dot(dv, pg);
        out.kinetic += 0.5 * m * dot(vo, dv);
        out.kinetic_half += 0.5 * m * (dot(v, v) - dot(v_free0, v_free0));
        for e in b.tractions.clone() {
            out.trac_a += 0.5 * dot(v, self.traction_impulse(e));
        }
        for c in 0..3 {
            if b.prescribed[c] != NONE {
                out.reac_a += 0.5 * v[c] * m * (v[c] - v_free[c]);
            }
        }
        // Glue of moving moulds: the mould's share ½ v_mould·P_coh of the cohesive work, with
        // the mould's velocity at the anchor.
        for slot in 0..impulses.cohesions {
            let (k, j) = impulses.cohesion_from[slot];
            let [v_old, v_new] = self.glue(j as usize, k).1;
            out.plane_b += 0.5 * dot(v_old, impulses.cohesion[slot]);
            out.plane_a += 0.5 * dot(v_new, impulses.cohesion[slot]);
        }
        // Contact: split the work on the relative velocity (dissipation, normal and
        // tangential) and on the mould's velocity at the contact point (external work).
        for c in 0..impulses.contacts {
            let (k, j, from_interface) = impulses.contact_from[c];
            let [v_old, v_new] = self.surface_of(k, (j, from_interface)).1;
            let n = impulses.contact_normal[c];
            let p = impulses.contact[c];
            let pn = dot(p, n);
            let pt = [p[0] - pn * n[0], p[1] - pn * n[1], p[2] - pn * n[2]];
            let rel_o = [vo[0] - v_old[0], vo[1] - v_old[1], vo[2] - v_old[2]];
            let rel_n = [v[0] - v_new[0], v[1] - v_new[1], v[2] - v_new[2]];
            out.cn_b += 0.5 * dot(rel_o, n) * pn;
            out.cn_a += 0.5 * dot(rel_n, n) * pn;
            out.ct_b += 0.5 * dot(rel_o, pt);
            out.ct_a += 0.5 * dot(rel_n, pt);
            out.plane_b += 0.5 * dot(v_old, p);
            out.plane_a += 0.5 * dot(v_new, p);
        }
    }

    /// Stage 8 on node `b`: αₙ₊₂ = min(u_r, max(αₙ₊₁, fₙ₊₂)) with
    /// fₙ₊₂ = |[u]ₙ₊₁ + h (V_{n+3/2} − v_plane)| (normal part counted when positive): eq. 12
    /// evaluated exactly on the next configuration.
    ///
    /// # Safety
    /// No other thread may touch the interface entries of `b`.
    unsafe fn damage(&self, b: &BoundaryNode, itfs: SharedSlice<InterfaceNode>, v: [f64; 3]) {
        let ms = &self.moulds;
        for e in b.interfaces.clone() {
            let j = self.boundary.interfaces[e as usize] as usize;
            let itf = itfs.get(j);
            if !itf.formed {
                continue; // no glue yet: α stays 0
            }
            let spec = &self.model.interfaces[itf.interface as usize];
            let k = spec.plane;
            // On a curved mould the anchor's velocity and its normal at tₙ₊₂ (R(tₙ₊₂)N₀).
            let (vp, n) = if !self.general || ms.plane[k] {
                (self.scratch.plane_v_new[k], self.model.moulds[k].normal)
            } else {
                let g = &ms.interface[j];
                (
                    ms.velocity_new(k, g.anchor),
                    ms.glue_normal_next(k, g.normal0),
                )
            };
            let next: [f64; 3] =
                std::array::from_fn(|c| itf.jump[c] + self.h_next * (v[c] - vp[c]));
            itf.alpha_next =
                (spec.law).next_damage(itf.alpha, &mut itf.alpha_static, next, n, self.h_next);
        }
    }
}

/// Stages 5–8 on boundary nodes `range` (indices into `cx.boundary.nodes`), node by node in the
/// order of model §4.10. `v_all` holds the free velocities of stage 5's node loop on entry
/// and V_{n+3/2} on exit; `reactions` (one entry per prescribed condition, zeroed) receives
/// this chunk's reaction forces.
///
/// # Safety
/// Chunks run concurrently must cover disjoint boundary nodes (each boundary node has its own
/// node, interface and contact entries), and the slices must outlive the call.
unsafe fn boundary_chunk(
    cx: &BoundaryStep,
    range: Range<usize>,
    v_all: PlanesPtr,
    itfs: SharedSlice<InterfaceNode>,
    cns: SharedSlice<ContactNode>,
    reactions: &mut [f64],
) -> BoundarySums {
    let mut out = BoundarySums::default();
    let mut impulses = NodeImpulses::default();
    for k in range {
        let b = &cx.boundary.nodes[k];
        let vo = cx.scratch.v_old[k];
        let v_free0 = v_all.get(b.node as usize);
        let mut v = v_free0;
        impulses.clear();
        // 5 (F_ext): surface tractions.
        cx.tractions(b, vo, &mut v, &mut out);
        // 5. Cohesion: P_coh = −h̄ W g_N(αₙ₊₁)[u]ₙ₊₁.
        cx.cohesion(b, itfs, &mut v, &mut impulses);
        let v_free = v;
        // 6. Prescribed components.
        let free = cx.prescribed(b, vo, &mut v, reactions, &mut out);
        // 7. Contact and friction, on the free components.
        if free != [false; 3] {
            cx.contact(b, itfs, cns, &mut v, free, &mut impulses, &mut out);
        }
        v_all.set(b.node as usize, v);
        // 9 (this node's share): forward halves of the ledger.
        cx.ledger_halves(b, vo, v_free0, v_free, v, &impulses, &mut out);
        // 8. Damage rate after the dynamics.
        cx.damage(b, itfs, v);
    }
    out
}

impl Simulation {
    /// Stages 5–8 at every boundary node (model §4.5–§4.8), in fixed chunks on the thread team.
    /// `h_bar` = (h_{n+½} + h_{n+3/2})/2 scales forces into impulses, `h_next` = h_{n+3/2} is
    /// the interval the new velocities act over. Needs [`Simulation::prescribed_motion`] and
    /// [`Simulation::free_velocity`] of this step; returns the chunks' sums for stage 9 and
    /// leaves the reactions in the step's scratch.
    pub(super) fn boundary_pass(&mut self, h_bar: f64, h_next: f64) -> BoundarySums {
        self.state.moulds.h_bar = h_bar;
        let cx = boundary_step!(self, h_bar, h_next);
        let (v_all, itfs, cns) = (
            self.state.v.ptr(),
            SharedSlice::new(&mut self.state.interface_nodes),
            SharedSlice::new(&mut self.state.contact_nodes),
        );
        let n_b = self.state.boundary.nodes.len();
        let n_bc = self.model.displacements.len();
        let chunks = n_b.div_ceil(BOUNDARY_GRAIN);
        self.work.parts_reactions.clear();
        self.work.parts_reactions.resize(chunks * n_bc, 0.0);
        let reaction_parts = SharedSlice::new(&mut self.work.parts_reactions);
        // SAFETY: each boundary node has its own node, interface and contact entries, and the
        // chunks are disjoint ranges of boundary nodes with their own rows of reactions.
        let run = |c: usize| unsafe {
            let range = c * BOUNDARY_GRAIN..((c + 1) * BOUNDARY_GRAIN).min(n_b);
            let reactions = reaction_parts.range(c * n_bc, (c + 1) * n_bc);
            boundary_chunk(&cx, range, v_all, itfs, cns, reactions)
        };
        let parts = &mut self.work.parts_boundary;
        match &self.work.team {
            Some(team) if chunks > 1 => team.map_into(chunks, parts, run),
            _ => {
                parts.clear();
                parts.extend((0..chunks).map(run));
            }
        }
        let sums = parts.iter().fold(BoundarySums::default(), |a, &b| a.add(b));
        self.stats.joint_contact = self.stats.joint_contact.merge(sums.joint);
        for (k, r) in self.work.step.reactions.iter_mut().enumerate() {
            *r = (0..chunks).fold(0.0, |acc, c| acc + self.work.parts_reactions[c * n_bc + k]);
        }
        sums
    }
}

impl Simulation {
    /// The smooth impulses of stage 5 alone at every boundary node (tractions and cohesion,
    /// no constraint), over h̄ = `h_bar`: how [`Simulation::start`] takes V₀ back to V_{−½}
    /// with the same formulas as a step.
    pub(super) fn smooth_impulses(&mut self, h_bar: f64) {
        let cx = boundary_step!(self, h_bar, h_bar);
        let itfs = SharedSlice::new(&mut self.state.interface_nodes);
        let (mut sums, mut impulses) = (BoundarySums::default(), NodeImpulses::default());
        for (k, b) in self.state.boundary.nodes.iter().enumerate() {
            let mut v = self.state.v.get(b.node as usize);
            cx.tractions(b, cx.scratch.v_old[k], &mut v, &mut sums);
            impulses.clear();
            // SAFETY: one thread, one node at a time.
            unsafe { cx.cohesion(b, itfs, &mut v, &mut impulses) };
            self.state.v.set(b.node as usize, v);
        }
    }
}
