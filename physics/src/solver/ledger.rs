//! Stage 9 (model §4.9): the energy ledger of model §5 closed for the step, the run statistics
//! (reactions and their peaks, first damage, full rupture), and the blow-up checks.

use super::boundary::BoundarySums;
use super::state::{SolverError, StateCounts};
use super::Simulation;
use crate::energy::Work;
use crate::interface::law::StiffnessLaw;
use crate::kernels::NodeSums;
use crate::mesh::dot;

/// What the interface nodes hold after a step: Σ Ψ_d, Σ ΔD, the most negative ΔD, the state
/// counts, the glue's total spring stiffness Σ W g_N(αₙ), and the cohesive force's step-change
/// work and the glue's torque work over the interval just taken.
pub(super) struct InterfaceSums {
    pub stored: f64,
    pub dissipated: f64,
    pub worst: f64,
    pub counts: StateCounts,
    pub springs: f64,
    pub step_change: f64,
    /// Σ W_τ, the glue's torque work on turning moulds (model §5.5,
    /// [`Loading::torque_work`]): the moulds' work.
    ///
    /// [`Loading::torque_work`]: crate::interface::damage::Loading::torque_work
    torque: f64,
    /// Glued nodes whose damage is evolving ([`damage_evolving`]).
    pub evolving: usize,
    /// Σ of what taking a delayed law's ΔD as ≥ 0 added to it ([`Loading::booked_dissipation`]).
    ///
    /// [`Loading::booked_dissipation`]: crate::interface::damage::Loading::booked_dissipation
    pub clamped: f64,
}

/// The glue's values at one point (an interface node or a bond pair) that stage 9's sums read.
pub(super) struct GluePoint<'a> {
    /// W [m²], g_N(αₙ) and g_N(αₙ₋₁) [Pa/m].
    pub area: f64,
    pub stiffness: f64,
    pub prev_stiffness: f64,
    /// [u]ₙ, [u]ₙ₋₁ [m] and R_d,ₙ [Pa].
    pub jump: &'a [f64; 3],
    pub prev_jump: &'a [f64; 3],
    pub cohesive_traction: &'a [f64; 3],
    /// αₙ and the static damage of the delayed law.
    pub alpha: f64,
    pub alpha_static: f64,
}

impl InterfaceSums {
    /// One glue point's share of the sums (model §5.4, §5.8): Ψ_d, ΔD (the most negative, and
    /// what taking a delayed law's ΔD as ≥ 0 added), W g_N(αₙ), whether its damage evolves, and
    /// at a change of step the cohesive step-change work
    /// ½([u]ₙ − [u]ₙ₋₁)·W(prev R_d,ₙ₋₁ − now R_d,ₙ), R_d,ₙ₋₁ along the glue normal `n_prev` of
    /// tₙ₋₁ (`n` the normal at tₙ).
    pub(super) fn add_glue(
        &mut self,
        law: &StiffnessLaw,
        g: &GluePoint,
        n: [f64; 3],
        n_prev: [f64; 3],
        change: Option<StepChange>,
    ) {
        self.stored += law.stored_energy(g.area, g.stiffness, *g.jump, n);
        let (dd, clamped) = law.loading().booked_dissipation(
            g.area,
            g.prev_stiffness,
            g.stiffness,
            *g.prev_jump,
            *g.jump,
            n,
        );
        self.clamped += clamped;
        self.worst = self.worst.min(dd);
        self.dissipated += dd;
        self.springs += g.area * g.stiffness;
        if let Some(w) = change {
            let r_prev = law.cohesive_traction(g.prev_stiffness, *g.prev_jump, n_prev);
            self.step_change += (0..3)
                .map(|c| {
                    let du = g.jump[c] - g.prev_jump[c];
                    0.5 * du * g.area * (w.prev * r_prev[c] - w.now * g.cohesive_traction[c])
                })
                .sum::<f64>();
        }
        self.evolving += usize::from(damage_evolving(law, g.alpha, g.alpha_static));
    }
}

/// The weights of a change of step in the interval [tₙ₋₁, tₙ] just taken (model §5.8):
/// with h₋ = h_{n−3/2}, h = h_{n−½}, h₊ = h_{n+½},
/// `prev` = (h − h₋)/(2h) = 1 − h̄ₙ₋₁/h and `now` = (h₊ − h)/(2h) = h̄ₙ/h − 1; both 0 at a
/// constant step.
#[derive(Clone, Copy)]
pub(super) struct StepChange {
    pub prev: f64,
    pub now: f64,
}

/// What stage 5 and stages 5–8 hand to stage 9: the sums of the ledger's halves from the
/// node loop ([`Simulation::free_velocity`]) and from the boundary and bond passes
/// ([`Simulation::boundary_pass`], [`Simulation::bond_pass`]) (model §4.9, §5).
#[derive(Clone, Copy)]
pub(super) struct StepSums {
    pub nodes: NodeSums,
    pub boundary: BoundarySums,
}

impl Simulation {
    /// Stage 9: the step's work halves into the ledger (trapezoid pairing, model §5.3), the
    /// reactions and their peaks, the interface energies, damage dissipation and the glue's
    /// torque work on turning moulds (model §5.5, booked as the moulds' work), the ledger's
    /// closing, the run statistics and the blow-up checks (non-finite values, negative damage
    /// dissipation, contact creating energy, energy growing without a source). `h_next`:
    /// h_{n+3/2}, fixed by stage 4. `first`: the start of the run, where only the forward
    /// halves exist.
    ///
    /// *Variable step* (model §5.8). The impulse form of every work, ½V_{n−½}·(Pₙ₋₁ + Pₙ)
    /// with Pₙ = h̄ₙFₙ, sums exactly to Kₙ − Kₙ₋₁ at any sequence of steps. The stored-energy
    /// identities (bulk Ψ to O(h²), cohesive Ψ_d + D exactly) hold for the plain trapezoid
    /// ½ΔU·(Fₙ₋₁ + Fₙ), ΔU = h_{n−½}V_{n−½}. The two differ only where h changes, by
    /// ½ΔU·((h̄ₙ₋₁/h_{n−½} − 1)Fₙ₋₁ + (h̄ₙ/h_{n−½} − 1)Fₙ) for each conservative force (internal
    /// and cohesive on the body, the latter on the jump [u]): the **step-change work**
    /// W_Δh that the change of step feeds into K. It enters the balance as a source,
    /// residual = W_ext + W_Δh − (ΔK + ΔΨ + ΔΨ_hg + ΔΨ_d + D + D_c + D_f), which is then exact
    /// up to the bulk's O(h²) term whatever the steps. In halves: the impulse halves b, a of
    /// F_int (at tₙ, h̄ = ½(h_{n−½} + h_{n+½})) give b(1 − h_{n−½}/h̄) and a(1 − h_{n+½}/h̄);
    /// the cohesive part uses [u]ₙ − [u]ₙ₋₁ directly ([`StepChange`]).
    pub(super) fn ledger(
        &mut self,
        h_next: f64,
        first: bool,
        sums: StepSums,
    ) -> Result<(), SolverError> {
        self.reactions_and_peaks();
        let c = &mut self.state.step_control;
        if first {
            c.h_before = self.state.h;
        }
        let (h_before, h) = (c.h_before, self.state.h);
        let change = (!first && (h_before != h || h_next != h)).then(|| StepChange {
            prev: (h - h_before) / (2.0 * h),
            now: (h_next - h) / (2.0 * h),
        });
        let itf = self.interface_sums(first, change);
        let c = &mut self.state.step_control;
        c.springs_now = itf.springs;
        c.damage_evolving = itf.evolving + usize::from(tearing(itf.counts));
        if first {
            (c.springs_initial, c.springs_at_estimate) = (itf.springs, itf.springs);
        } else {
            c.h_before = h;
        }
        let internal = (!first && h_next != h).then(|| (h_next - h) / (h_next + h));
        self.push_work(first, sums, internal, itf.step_change, itf.torque);
        self.push_mould_work(first);
        self.push_mould_friction(first);
        if itf.clamped > 0.0 {
            self.stats.damage_clamped.energy += itf.clamped;
            self.stats.damage_clamped.steps += 1;
            let worst = &mut self.stats.damage_clamped.largest_step;
            *worst = worst.max(itf.clamped);
        }
        let l = &mut self.state.ledger;
        l.interface_stored = itf.stored;
        l.damage_dissipated += itf.dissipated;
        if first {
            l.initial_kinetic = l.kinetic;
            l.initial_strain = l.strain;
            l.initial_hourglass = l.hourglass;
            l.initial_interface_stored = l.interface_stored;
            self.state.energy_budget =
                (self.state.kinetic_half + l.strain + l.hourglass + l.interface_stored).abs();
        }
        l.close_step();
        self.added_mass_energy();
        let l = &self.state.ledger;
        // The budget is compared with ½V_{n+½}ᵀMV_{n+½}, so it takes the works up to the forward
        // halves of this step's impulses: with the work up to tₙ only, a load ramped from zero
        // (no work yet at t₁, a velocity already) reads as energy created at step 1.
        let ext = l.external_work_settled();
        self.state.energy_budget += (ext - self.state.last_external_work).abs();
        self.state.last_external_work = ext;
        self.damage_times(itf.counts);
        self.blow_up_checks(itf.worst)
    }

    /// The reaction of each prescribed condition and its peak (excluding steps where the
    /// prescribed velocity jumps, and after full rupture, when the body is free and the
    /// reaction only measures its vibration).
    fn reactions_and_peaks(&mut self) {
        let t = self.state.time;
        let sc = &self.work.step;
        for (k, r) in sc.reactions.iter().enumerate() {
            self.stats.reactions[k] = *r;
            let peak = &mut self.stats.peaks[k];
            let before_rupture =
                self.state.interface_nodes.is_empty() || self.stats.time_full_rupture.is_none();
            if before_rupture && !sc.bc_jump[k] && r.abs() > peak.force.abs() {
                peak.force = *r;
                peak.time = t;
                peak.imposed_displacement = self.model.displacements[k].history.value(t)[0];
            }
        }
    }

    /// Kₙ and each force's half contributions of this step (backward ½V_{n−½}·P, forward
    /// ½V_{n+½}·P) from the node loop and the boundary pass, into the ledger; the step-change
    /// work: `cohesive` for the interval just taken, and, with
    /// `internal` = ρ = (h_{n+½} − h_{n−½})/(h_{n+½} + h_{n−½}), the internal force's halves
    /// ρb and −ρa ([`Simulation::ledger`]); and the glue's torque work W_τ of the interval just
    /// taken, `torque`, to the moulds' work (model §5.5, §5.7).
    fn push_work(
        &mut self,
        first: bool,
        sums: StepSums,
        internal: Option<f64>,
        cohesive: f64,
        torque: f64,
    ) {
        let (mut s, bs) = (sums.nodes, sums.boundary);
        s.int_a += bs.int_a;
        // The viscous part of F_int is not conservative: its halves go to its own work
        // (model §5.11), not to the internal work or the step-change work.
        let (bv_b, bv_a) = self.bulk_viscosity_halves();
        s.int_b -= bv_b;
        s.int_a -= bv_a;
        s.grav_a += bs.grav_a;
        s.kinetic += bs.kinetic;
        s.kinetic_half += bs.kinetic_half;
        // W_τ belongs to the interval just taken: it joins the moulds' backward half. It is 0
        // but for anisotropic glue on a turning mould, and is then left out, so that every
        // other run keeps its arithmetic.
        let plane_b = if torque != 0.0 {
            bs.plane_b + torque
        } else {
            bs.plane_b
        };
        let l = &mut self.state.ledger;
        l.kinetic = s.kinetic;
        let works: [(&mut Work, f64, f64); 8] = [
            (&mut l.bulk_viscous_work, bv_b, bv_a),
            (&mut l.internal_work, s.int_b, s.int_a),
            (&mut l.gravity_work, s.grav_b, s.grav_a),
            (&mut l.traction_work, bs.trac_b, bs.trac_a),
            (&mut l.reaction_work, bs.reac_b, bs.reac_a),
            (&mut l.plane_work, plane_b, bs.plane_a),
            (&mut l.contact_normal_work, bs.cn_b, bs.cn_a),
            (&mut l.contact_tangential_work, bs.ct_b, bs.ct_a),
        ];
        let (rb, ra) = internal.map_or((0.0, 0.0), |rho| (rho * s.int_b, -rho * s.int_a));
        for (work, b, a) in works {
            if first {
                work.start(a);
            } else {
                work.push(b, a);
            }
        }
        if first {
            l.step_change_work.start(0.0);
        } else {
            l.step_change_work.push(rb + cohesive, ra);
        }
        self.state.kinetic_half = s.kinetic_half;
    }

    /// Each mould's work (model §5.7, §7.6), with the trapezoid pairing of the other works: the
    /// halves b = ½v_m,old·P and a = ½v_m,new·P of every impulse P the mould gives a node —
    /// the glue's −h̄W R_d at the anchor and the contact's W R_c at the contact point — with
    /// v_m the mould's velocity at that point over the interval before and after tₙ₊₁
    /// ([`crate::mould::step`]): force · velocity at the contact points, so the moment about
    /// the pivot times ω is included; and the glue's torque work W_τ on the mould over the
    /// interval just taken (model §5.5), with the backward half. Their sum is `plane_work` (to
    /// round-off: the contact impulse is read back per unit area). With one mould there is
    /// nothing to split and `plane_work` is its work (the pass is skipped).
    fn push_mould_work(&mut self, first: bool) {
        let n = self.model.moulds.len();
        if n < 2 {
            return;
        }
        let mut halves = self.mould_halves(n);
        for j in 0..self.state.interface_nodes.len() {
            let itf = &self.state.interface_nodes[j];
            let k = self.model.interfaces[itf.interface as usize].plane;
            let h_bar = self.state.moulds.h_bar;
            let coh = itf.cohesive_traction.map(|c| -h_bar * itf.area * c);
            let con = itf.contact_impulse.map(|c| c * itf.area);
            let (anchor, point) = self.mould_points(k, Some(j), None);
            let (a, b) = (
                self.mould_velocities(k, anchor),
                self.mould_velocities(k, point),
            );
            halves[k].0 += 0.5 * (dot(a[0], coh) + dot(b[0], con));
            halves[k].1 += 0.5 * (dot(a[1], coh) + dot(b[1], con));
        }
        for j in 0..self.state.contact_nodes.len() {
            let cn = &self.state.contact_nodes[j];
            let k = cn.plane as usize;
            let con = cn.contact_impulse.map(|c| c * cn.area);
            let (_, point) = self.mould_points(k, None, Some(j));
            let v = self.mould_velocities(k, point);
            halves[k].0 += 0.5 * dot(v[0], con);
            halves[k].1 += 0.5 * dot(v[1], con);
        }
        for (half, &torque) in halves.iter_mut().zip(&self.state.moulds.torque) {
            if torque != 0.0 {
                half.0 += torque;
            }
        }
        push_halves(&mut self.state.moulds.work, &halves, first);
        self.work.step.mould_halves = halves;
    }

    /// The per-mould (before, after) work array, zeroed for `n` moulds: taken out of the
    /// step's scratch (give it back after use), so that no step allocates.
    fn mould_halves(&mut self, n: usize) -> Vec<(f64, f64)> {
        let mut halves = std::mem::take(&mut self.work.step.mould_halves);
        halves.clear();
        halves.resize(n, (0.0, 0.0));
        halves
    }

    /// Each mould's friction work, with the trapezoid pairing of `contact_tangential_work`:
    /// the halves b = ½(V_{n+½} − v_m,old)·P_T and a = ½(V_{n+3/2} − v_m,new)·P_T of the
    /// tangential part P_T = P − (P·n)n of every contact impulse P that mould gives a node
    /// (glued entries with μ(α), contact entries with μ), v_m the mould's velocity at the
    /// contact point and n its normal there: the same terms as the boundary pass's `ct_b`,
    /// `ct_a`, sorted by mould, so their sum is the total friction work to round-off (the
    /// contact impulse is read back per unit area). With one mould the total is its friction
    /// and the pass is skipped ([`Simulation::mould_frictions`]).
    fn push_mould_friction(&mut self, first: bool) {
        let n_moulds = self.model.moulds.len();
        if n_moulds < 2 {
            return;
        }
        let mut halves = self.mould_halves(n_moulds);
        for (b, node) in self.state.boundary.nodes.iter().enumerate() {
            let (vo, v) = (
                self.work.step.v_old[b],
                self.state.v.get(node.node as usize),
            );
            let mut add = |k: usize, p: [f64; 3], geo: Option<usize>, interface: bool| {
                let (n, vm) = self.contact_frame(k, geo, interface);
                let pn = dot(p, n);
                let pt: [f64; 3] = std::array::from_fn(|c| p[c] - pn * n[c]);
                let rel =
                    |w: [f64; 3], m: [f64; 3]| -> [f64; 3] { std::array::from_fn(|c| w[c] - m[c]) };
                halves[k].0 += 0.5 * dot(rel(vo, vm[0]), pt);
                halves[k].1 += 0.5 * dot(rel(v, vm[1]), pt);
            };
            for e in node.interfaces.clone() {
                let j = self.state.boundary.interfaces[e as usize] as usize;
                let itf = &self.state.interface_nodes[j];
                let k = self.model.interfaces[itf.interface as usize].plane;
                add(k, itf.contact_impulse.map(|c| c * itf.area), Some(j), true);
            }
            for e in node.contacts.clone() {
                let j = self.state.boundary.contacts[e as usize] as usize;
                let cn = &self.state.contact_nodes[j];
                let p = cn.contact_impulse.map(|c| c * cn.area);
                add(cn.plane as usize, p, Some(j), false);
            }
        }
        push_halves(&mut self.state.moulds.friction, &halves, first);
        self.work.step.mould_halves = halves;
    }

    /// The normal of mould `k` at the contact point of interface entry (`interface`) or contact
    /// entry `j` and the mould's velocity there before and after tₙ₊₁: a plain plane's normal
    /// and velocities, or the entry's closest point on a curved mould.
    fn contact_frame(
        &self,
        k: usize,
        j: Option<usize>,
        interface: bool,
    ) -> ([f64; 3], [[f64; 3]; 2]) {
        let ms = &self.state.moulds;
        if ms.plane[k] {
            return (
                self.model.moulds[k].normal,
                self.mould_velocities(k, [0.0; 3]),
            );
        }
        let (itf, cn) = if interface { (j, None) } else { (None, j) };
        let (_, point) = self.mould_points(k, itf, cn);
        let geo = if interface {
            &ms.interface
        } else {
            &ms.contact
        };
        let n = j.and_then(|j| geo.get(j)).map_or([0.0; 3], |g| g.normal);
        (n, self.mould_velocities(k, point))
    }

    /// Each mould's name and the friction dissipated on it since t₀ [J] (minus its friction
    /// work, [`Simulation::push_mould_friction`]): with one mould, the ledger's
    /// `friction_dissipated` itself; with several, their sum is it to round-off.
    pub fn mould_frictions(&self) -> Vec<(String, f64)> {
        let planes = &self.model.moulds;
        if planes.len() == 1 {
            return vec![(
                planes[0].name.clone(),
                self.state.ledger.friction_dissipated,
            )];
        }
        let works = &self.state.moulds.friction;
        (planes.iter().zip(works))
            .map(|(p, w)| (p.name.clone(), 0.0 - w.value))
            .collect()
    }

    /// Σ Ψ_d = Σ W ½ g_N(αₙ)|[u]ₙ|² and Σ ΔDₙ over the interface nodes (model §5.5), their
    /// states, Σ W g_N(αₙ), where the step changed (`change`) the cohesive step-change
    /// work ½([u]ₙ − [u]ₙ₋₁)·W(prev R_d,ₙ₋₁ − now R_d,ₙ) (the force on the body is −W R_d;
    /// R_d,ₙ₋₁ on the glue normal nₙ₋₁), and after the start (`first` false) the glue's torque
    /// work W_τ,ₙ = Σ W ½ g_N(αₙ₋₁)(Pₙ(nₙ) − Pₙ(nₙ₋₁)) where the glue has one (model §5.5,
    /// [`Simulation::glue_normal_before`]), in total and per mould; moves [u]ₙ, g_N(αₙ) into
    /// the "previous" slots for the next ΔD.
    fn interface_sums(&mut self, first: bool, change: Option<StepChange>) -> InterfaceSums {
        let mut out = InterfaceSums {
            stored: 0.0,
            dissipated: 0.0,
            worst: 0.0,
            counts: StateCounts::default(),
            springs: 0.0,
            step_change: 0.0,
            torque: 0.0,
            evolving: 0,
            clamped: 0.0,
        };
        self.state.moulds.torque.fill(0.0);
        for j in 0..self.state.interface_nodes.len() {
            let n = self.glue_normal(j);
            let n_before = if first {
                None
            } else {
                self.glue_normal_before(j)
            };
            let itf = &mut self.state.interface_nodes[j];
            let spec = &self.model.interfaces[itf.interface as usize];
            let law = &spec.law;
            let glue = GluePoint {
                area: itf.area,
                stiffness: itf.stiffness,
                prev_stiffness: itf.prev_stiffness,
                jump: &itf.jump,
                prev_jump: &itf.prev_jump,
                cohesive_traction: &itf.cohesive_traction,
                alpha: itf.alpha,
                alpha_static: itf.alpha_static,
            };
            out.add_glue(law, &glue, n, n_before.unwrap_or(n), change);
            if let Some(n_prev) = n_before {
                let torque = law.loading().torque_work(
                    itf.area,
                    itf.prev_stiffness,
                    [itf.prev_jump, itf.jump],
                    [n_prev, n],
                );
                out.torque += torque;
                self.state.moulds.torque[spec.plane] += torque;
            }
            itf.prev_stiffness = itf.stiffness;
            itf.prev_jump = itf.jump;
            out.counts.add(itf.state(law));
        }
        self.bond_sums(change, &mut out);
        out
    }

    /// Times of first damage and of full rupture (paper fig. 6).
    fn damage_times(&mut self, counts: StateCounts) {
        let n = self.state.interface_nodes.len();
        if counts.transition + counts.ruptured > 0 && self.stats.time_first_damage.is_none() {
            self.stats.time_first_damage = Some(self.state.time);
        }
        if counts.ruptured == n && n > 0 && self.stats.time_full_rupture.is_none() {
            self.stats.time_full_rupture = Some(self.state.time);
        }
    }

    /// The ledger's blow-up checks (model §5.9): non-finite energy, a negative damage
    /// dissipation increment `worst`, a negative cumulative contact dissipation, mechanical
    /// energy grown past `energy_growth_limit` × what was supplied.
    fn blow_up_checks(&self, worst: f64) -> Result<(), SolverError> {
        let l = &self.state.ledger;
        let mech = self.state.kinetic_half + l.strain + l.hourglass + l.interface_stored;
        if !(mech.is_finite() && l.residual().is_finite()) {
            return Err(
                self.unstable("non-finite energy (NaN or infinity in velocities or forces)".into())
            );
        }
        if worst < -1e-9 * l.max_energy_seen.max(self.setup.energy_floor) {
            return Err(self.unstable(format!(
                "negative damage dissipation increment ({worst:.3e} J): the jump turned by more than 90° in one step"
            )));
        }
        // Contact dissipation is not ≥ 0 step by step with the trapezoid pairing (model §5.6),
        // but it must be cumulatively, to the ledger's own accuracy: 1e-3 of the largest energy.
        let contact = l.contact_normal_dissipated + l.friction_dissipated;
        if contact < -1e-3 * l.max_energy_seen.max(self.setup.energy_floor) {
            return Err(self.unstable(format!(
                "the cumulative contact dissipation is negative ({contact:.3e} J, beyond 1e-3 of the largest energy {:.3e} J): contact is creating energy",
                l.max_energy_seen
            )));
        }
        let limit = self.model.scheme.energy_growth_limit * self.state.energy_budget
            + self.setup.energy_floor;
        if mech > limit {
            return Err(self.unstable(format!(
                "the mechanical energy ({mech:.4e} J) grew past {}× the energy supplied ({:.4e} J) with no source",
                self.model.scheme.energy_growth_limit, self.state.energy_budget
            )));
        }
        Ok(())
    }
}

/// Whether the glue is tearing: some node has left the elastic range and some has not yet
/// ruptured. Between the two the front moves from node to node, and a node still elastic
/// next to a torn one is about to soften within a few steps (in the 7³ pull-off a moment came
/// shortly before the full rupture with no node in transition: a gate on transition alone let
/// h grow there and D rose; docs: performance log).
/// Unformed nodes (glue that forms on contact, not formed yet) count as not torn, as sound
/// glue does.
fn tearing(counts: StateCounts) -> bool {
    let n = counts.elastic + counts.transition + counts.ruptured + counts.unformed;
    counts.transition + counts.ruptured > 0 && counts.ruptured < n
}

/// Whether a glued node's damage is evolving, the state in which the step is held
/// ([`super::stable_step::StepControl::damage_evolving`]): softening, α_e < α < u_r (fig. 6's
/// transition, the same classification for every family: for `rccm` α_e = u₀ and u_r =
/// u₀/√β_min), or, with a delayed law, α still behind its rate-independent target α_s (the
/// damage keeps growing while α ≤ α_e or after the jump has turned back).
fn damage_evolving(law: &crate::interface::law::StiffnessLaw, alpha: f64, alpha_s: f64) -> bool {
    law.state(alpha) == crate::interface::law::InterfaceState::Transition
        || (law.delay().is_some() && alpha < alpha_s)
}

/// Trapezoid pairing of per-mould works: at the start only the forward halves `a`, then each
/// step's ½(b + a) pairs (model §7.6, per mould).
fn push_halves(works: &mut [Work], halves: &[(f64, f64)], first: bool) {
    for (w, &(b, a)) in works.iter_mut().zip(halves) {
        if first {
            w.start(a);
        } else {
            w.push(b, a);
        }
    }
}
