//! Bonds (model §7.8): pairs of nodes of the body at the same reference place, on either side
//! of a cut, joined by a cohesive law. Each pair takes the stages of a glued node with the
//! other node in the mould's place: the jump [u] = x_a − x_b (stage 2), the cohesive impulse
//! −h̄ W R_d on a and +h̄ W R_d on b (4), contact and friction on the relative velocity
//! w = V_a − V_b with the pair's reduced mass m* = m_a m_b/(m_a + m_b) (7: an impulse P on the
//! relative motion changes w by P/m*, V_a by P/m_a and V_b by −P/m_b), the ledger's halves on
//! both nodes and on w (9), and the damage from [u] + h w (8). The pass runs after the boundary
//! pass, pair by pair on one thread: a bond's nodes carry no other condition (refused at
//! set-up), so the two passes touch different nodes.

use super::boundary::BoundarySums;
use super::ledger::{GluePoint, InterfaceSums, StepChange};
use super::state::SolverError;
use super::Simulation;
use crate::interface::contact::{contact_impulse, ContactStatus};
use crate::kernels::internal_and_gravity_impulses;
use crate::mesh::dot;
use crate::model::Model;
use std::collections::BTreeMap;

/// A pair of bonded nodes and the state of its law (as an [`super::InterfaceNode`]'s).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct BondNode {
    /// The node of the bond's `faces` (side a) and its partner of `to` (side b).
    pub node: u32,
    pub other: u32,
    /// Index of the bond in `Model::bonds`.
    pub bond: u32,
    /// Tributary reference area W of `node` [m²].
    pub area: f64,
    /// The bond's normal at the pair, out of side b, fixed in the reference configuration.
    pub normal: [f64; 3],
    /// Damage αₙ, αₙ₊₁ (predicted by stage 8) and α_s [m].
    pub alpha: f64,
    pub alpha_next: f64,
    pub alpha_static: f64,
    /// [u]ₙ = x_a − x_b [m] and the gap gₙ = n·[u]ₙ [m].
    pub jump: [f64; 3],
    pub gap: f64,
    /// g_N(αₙ) [Pa/m] and R_d = g_N(α)[u] [Pa] (acting on a as −R_d, on b as +R_d).
    pub stiffness: f64,
    pub cohesive_traction: [f64; 3],
    /// Contact impulse per unit area on side a of the last step [Pa·s], and the status.
    pub contact_impulse: [f64; 3],
    pub contact: ContactStatus,
    /// [u]ₙ₋₁ and g_N(αₙ₋₁), for the damage dissipation increment.
    pub(crate) prev_jump: [f64; 3],
    pub(crate) prev_stiffness: f64,
}

/// The node pairs of every bond, with their area and normal ([`crate::mesh::Mesh::pairs`]),
/// intact (α = 0) until [`Simulation::initial_damage`]. A bond node that carries another
/// condition (`taken`: the boundary's nodes) or is in two pairs is refused: the bond pass would
/// then write a velocity that the boundary pass writes too.
pub(super) fn bond_nodes(model: &Model, taken: &[u32]) -> Result<Vec<BondNode>, SolverError> {
    let mesh = &model.mesh;
    // Each node's partner and the bond that paired them first.
    let mut partner: BTreeMap<u32, (u32, usize)> = BTreeMap::new();
    let mut out = Vec::new();
    for (k, bond) in model.bonds.iter().enumerate() {
        let set = |name: &str| {
            mesh.face_sets.get(name).ok_or_else(|| {
                SolverError::Setup(format!("bond[{k}]: the mesh has no face set `{name}`"))
            })
        };
        let pairs = mesh
            .pairs(set(&bond.faces)?, set(&bond.to)?)
            .map_err(|e| SolverError::Setup(format!("bond[{k}]: {e}")))?;
        for p in pairs {
            for (n, o) in [(p.node, p.other), (p.other, p.node)] {
                if taken.binary_search(&n).is_ok() {
                    return Err(SolverError::Setup(format!(
                        "bond[{k}]: node {n} also carries an interface, contact, traction or \
                         prescribed displacement; a bond's nodes may carry nothing else"
                    )));
                }
                match partner.insert(n, (o, k)) {
                    Some((o2, j)) if o2 != o => {
                        return Err(SolverError::Setup(format!(
                            "bond[{k}]: node {n} is paired with node {o} here and with node \
                             {o2} by bond[{j}]; a node has one partner"
                        )))
                    }
                    _ => {}
                }
            }
            let g0 = bond.law.g_n0;
            out.push(BondNode {
                node: p.node,
                other: p.other,
                bond: k as u32,
                area: p.area,
                normal: p.normal,
                alpha: 0.0,
                alpha_next: 0.0,
                alpha_static: 0.0,
                jump: [0.0; 3],
                gap: 0.0,
                stiffness: g0,
                cohesive_traction: [0.0; 3],
                contact_impulse: [0.0; 3],
                contact: ContactStatus::Open,
                prev_jump: [0.0; 3],
                prev_stiffness: g0,
            });
        }
    }
    // A pair in several bonds (a node where two face sets meet) has its entries side by side,
    // one contact between its nodes: their normals must agree.
    out.sort_by_key(|p| (p.node.min(p.other), p.node.max(p.other), p.bond));
    for w in out.windows(2) {
        let same = (w[0].node, w[0].other) == (w[1].node, w[1].other);
        if same && (0..3).any(|c| (w[0].normal[c] - w[1].normal[c]).abs() > 1e-9) {
            return Err(SolverError::Setup(format!(
                "bond[{}] and bond[{}] join nodes {} and {} along different normals ({:?} and \
                 {:?}): bonds that share a pair must share its `to` face set's normal",
                w[0].bond, w[1].bond, w[0].node, w[0].other, w[0].normal, w[1].normal
            )));
        }
        if (w[0].node, w[0].other) == (w[1].other, w[1].node) {
            return Err(SolverError::Setup(format!(
                "bond[{}] and bond[{}] join nodes {} and {} in opposite directions: give both \
                 the same `faces` side",
                w[0].bond, w[1].bond, w[0].node, w[0].other
            )));
        }
    }
    Ok(out)
}

/// The entries of one node pair: [`BondNode`]s side by side from `start` (one per bond that
/// joins the pair).
fn pair_end(nodes: &[BondNode], start: usize) -> usize {
    let key = (nodes[start].node, nodes[start].other);
    start
        + nodes[start..]
            .iter()
            .take_while(|p| (p.node, p.other) == key)
            .count()
}

impl Simulation {
    /// Stage 1 for the bonds: αₙ₊₁ = the αₙ₊₁ stage 8 predicted.
    pub(super) fn advance_bond_damage(&mut self) {
        for p in &mut self.state.bond_nodes {
            p.alpha = p.alpha_next;
        }
    }

    /// Stage 2 for the bonds: [u]ₙ₊₁ = x_a − x_b = U_a − U_b (the two nodes start at one place)
    /// and gₙ₊₁ = n·[u]ₙ₊₁, a gap within the round-off of positions set to 0 (as on moulds).
    pub(super) fn bond_gaps(&mut self) {
        let tol = 16.0 * f64::EPSILON * self.setup.coordinate_scale;
        for p in &mut self.state.bond_nodes {
            let (ua, ub) = (
                self.state.u.get(p.node as usize),
                self.state.u.get(p.other as usize),
            );
            p.jump = std::array::from_fn(|c| ua[c] - ub[c]);
            let g = dot(p.normal, p.jump);
            p.gap = if g.abs() <= tol { 0.0 } else { g };
        }
    }

    /// α₀ = min(u_r, max(α₀ of the bond, f([u]₀))) on every pair, as on glued nodes.
    pub(super) fn bond_initial_damage(&mut self) {
        for p in &mut self.state.bond_nodes {
            let bond = &self.model.bonds[p.bond as usize];
            p.alpha = bond
                .law
                .initial_damage(bond.initial_damage, p.jump, p.normal);
            (p.alpha_next, p.alpha_static) = (p.alpha, p.alpha);
            p.stiffness = bond.law.g_n(p.alpha);
            p.prev_stiffness = p.stiffness;
            p.prev_jump = p.jump;
        }
    }

    /// V_{n+½} of both nodes of every pair, before stage 5 changes them (the ledger's
    /// backward halves).
    pub(super) fn keep_bond_velocities(&mut self) {
        let sc = &mut self.work.step;
        sc.bond_v_old.clear();
        sc.bond_v_old.extend(self.state.bond_nodes.iter().map(|p| {
            [
                self.state.v.get(p.node as usize),
                self.state.v.get(p.other as usize),
            ]
        }));
    }

    /// Stages 5, 7, 9 (the nodes' shares) and 8 on every node pair, after stage 5's free
    /// velocity (see the module docs); returns the boundary's sums `sums` with the pairs' ledger
    /// halves added. A
    /// pair in several bonds takes each bond's cohesion, then one contact with their total
    /// area W = Σ Wᵢ and the area-weighted μ = Σ Wᵢ μᵢ(αᵢ)/W, shared as one impulse per area.
    pub(super) fn bond_pass(
        &mut self,
        h_bar: f64,
        h_next: f64,
        mut sums: BoundarySums,
    ) -> BoundarySums {
        let n = self.state.bond_nodes.len();
        let mut start = 0;
        while start < n {
            let end = pair_end(&self.state.bond_nodes, start);
            self.bond_pair(start..end, h_bar, h_next, &mut sums);
            start = end;
        }
        sums
    }

    /// [`Simulation::bond_pass`] on the entries `range` of one node pair.
    fn bond_pair(
        &mut self,
        range: std::ops::Range<usize>,
        h_bar: f64,
        h_next: f64,
        sums: &mut super::boundary::BoundarySums,
    ) {
        let entries = &mut self.state.bond_nodes[range.clone()];
        let (a, b) = (entries[0].node as usize, entries[0].other as usize);
        let (ma, mb) = (self.setup.mass[a], self.setup.mass[b]);
        let free0 = [self.state.v.get(a), self.state.v.get(b)];
        let mut v = free0;
        let (mut area, mut mu_area, mut held) = (0.0, 0.0, false);
        for p in entries.iter_mut() {
            let bond = &self.model.bonds[p.bond as usize];
            // 5. Cohesion: −h̄ W R_d on a, +h̄ W R_d on b.
            p.stiffness = bond.law.g_n(p.alpha);
            p.cohesive_traction = bond.law.cohesive_traction(p.stiffness, p.jump, p.normal);
            let pc = p.cohesive_traction.map(|c| h_bar * p.area * c);
            for c in 0..3 {
                v[0][c] -= pc[c] / ma;
                v[1][c] += pc[c] / mb;
            }
            area += p.area;
            mu_area += p.area * bond.law.mu(p.alpha, bond.mu_inf);
            held |= p.contact != ContactStatus::Open;
        }
        // 7. Contact on the relative motion with the reduced mass.
        let (n, gap) = (entries[0].normal, entries[0].gap);
        let m_star = ma * mb / (ma + mb);
        let mut w: [f64; 3] = std::array::from_fn(|c| v[0][c] - v[1][c]);
        let mu = mu_area / area;
        let held = held.then_some(h_next);
        let (imp, status) = contact_impulse(&mut w, gap, n, [0.0; 3], mu, m_star, [true; 3], held);
        for c in 0..3 {
            v[0][c] += imp[c] / ma;
            v[1][c] -= imp[c] / mb;
        }
        self.state.v.set(a, v[0]);
        self.state.v.set(b, v[1]);
        // 9. The nodes' forward halves and corrections (as a boundary node's), and the
        // contact's work on the relative velocity.
        let vo = self.work.step.bond_v_old[range.start];
        for (s, (i, m)) in [(a, ma), (b, mb)].into_iter().enumerate() {
            let dv: [f64; 3] = std::array::from_fn(|c| v[s][c] - free0[s][c]);
            let f = self.state.f_int.get(i);
            let (pint, pg) = internal_and_gravity_impulses(h_bar, f, m, self.model.gravity);
            sums.int_a += 0.5 * dot(dv, pint);
            sums.grav_a += 0.5 * dot(dv, pg);
            sums.kinetic += 0.5 * m * dot(vo[s], dv);
            sums.kinetic_half += 0.5 * m * (dot(v[s], v[s]) - dot(free0[s], free0[s]));
        }
        let pn = dot(imp, n);
        let pt: [f64; 3] = std::array::from_fn(|c| imp[c] - pn * n[c]);
        let rel_o: [f64; 3] = std::array::from_fn(|c| vo[0][c] - vo[1][c]);
        let rel_n: [f64; 3] = std::array::from_fn(|c| v[0][c] - v[1][c]);
        sums.cn_b += 0.5 * dot(rel_o, n) * pn;
        sums.cn_a += 0.5 * dot(rel_n, n) * pn;
        sums.ct_b += 0.5 * dot(rel_o, pt);
        sums.ct_a += 0.5 * dot(rel_n, pt);
        // 8. Damage from the jump at tₙ₊₂, [u]ₙ₊₁ + h (V_a − V_b).
        for p in entries.iter_mut() {
            let law = &self.model.bonds[p.bond as usize].law;
            (p.contact, p.contact_impulse) = (status, imp.map(|c| c / area));
            let next: [f64; 3] = std::array::from_fn(|c| p.jump[c] + h_next * rel_n[c]);
            p.alpha_next = law.next_damage(p.alpha, &mut p.alpha_static, next, n, h_next);
        }
    }

    /// The bonds' share of stage 9's interface sums: Ψ_d, ΔD, the state counts, Σ W g_N, and
    /// at a change of step the cohesive step-change work ½([u]ₙ − [u]ₙ₋₁)·W(prev R_d,ₙ₋₁ − now
    /// R_d,ₙ) (model §5.8); moves [u]ₙ, g_N(αₙ) into the "previous" slots.
    pub(super) fn bond_sums(&mut self, change: Option<StepChange>, out: &mut InterfaceSums) {
        for p in &mut self.state.bond_nodes {
            let law = &self.model.bonds[p.bond as usize].law;
            let glue = GluePoint {
                area: p.area,
                stiffness: p.stiffness,
                prev_stiffness: p.prev_stiffness,
                jump: &p.jump,
                prev_jump: &p.prev_jump,
                cohesive_traction: &p.cohesive_traction,
                alpha: p.alpha,
                alpha_static: p.alpha_static,
            };
            out.add_glue(law, &glue, p.normal, p.normal, change);
            p.prev_stiffness = p.stiffness;
            p.prev_jump = p.jump;
            out.counts.add(law.state(p.alpha));
        }
    }

    /// The bonds' springs for the stable-step operator, as diagonal springs 2 W g_N(α) on every
    /// free component of both nodes: the pair's spring W g_N [[1, −1], [−1, 1]] is below
    /// 2 W g_N [[1, 0], [0, 1]] (their difference W g_N [[1, 1], [1, 1]] is positive
    /// semi-definite), so the estimate of ω_max is an upper bound of the pair's, equal to it for
    /// equal masses (the opposing mode, ω² = 2 W g_N/m).
    pub(super) fn bond_springs(&self, mask: &[bool], springs: &mut Vec<(usize, f64)>) {
        for p in &self.state.bond_nodes {
            let ks = 2.0
                * p.area
                * self.model.bonds[p.bond as usize]
                    .law
                    .spring_stiffness(p.alpha);
            for i in [p.node as usize, p.other as usize] {
                springs.extend((3 * i..3 * i + 3).filter(|&k| !mask[k]).map(|k| (k, ks)));
            }
        }
    }
}
