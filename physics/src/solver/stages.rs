//! Stages 1, 2, 3, 4's velocities and 5 of model §4 (the boundary's stages 5–8 are in
//! `boundary.rs`, the step's choice in `stable_step.rs`, the ledger's stage 9 in `ledger.rs`), and the per-step buffers they fill.

use super::state::SolverError;
use super::{ElementLoop, Simulation, NODE_GRAIN};
use crate::kernels::{free_velocity_chunk, NodeSums, CORNER_EXACT_BELOW};
use crate::team::SharedSlice;

/// One chunk of the node loop, by plane: velocities, internal forces, (masses, inverse masses).
type NodeChunk<'a> = ([&'a mut [f64]; 3], [&'a [f64]; 3], (&'a [f64], &'a [f64]));

/// Per-step values of the planes, prescribed conditions and tractions, computed once per step
/// (not per node), and the step's sums, in buffers that are reused, so the step allocates
/// nothing after the first.
#[derive(Default)]
pub(super) struct StepScratch {
    /// Plane displacement d(tₙ₊₁) and the round-off tolerance of its gaps.
    pub plane_disp: Vec<[f64; 3]>,
    pub plane_tol: Vec<f64>,
    /// Plane velocity over the interval just taken and the next one.
    pub plane_v_old: Vec<[f64; 3]>,
    pub plane_v_new: Vec<[f64; 3]>,
    /// Prescribed velocity of each condition over the next interval, whether it jumps here,
    /// and its reaction force.
    pub bc_velocity: Vec<f64>,
    pub bc_jump: Vec<bool>,
    pub reactions: Vec<f64>,
    /// Amplitude of each traction at tₙ₊₁.
    pub amplitudes: Vec<f64>,
    /// V_{n+½} of the boundary nodes (by boundary index), before stage 5, for the ledger.
    pub v_old: Vec<[f64; 3]>,
    /// V_{n+½} of both nodes of each bond pair, before stage 5, for the ledger.
    pub bond_v_old: Vec<[[f64; 3]; 2]>,
    /// The per-mould (before, after) works of the ledger's passes.
    pub mould_halves: Vec<(f64, f64)>,
}

impl Simulation {
    /// Stage 1: Uₙ₊₁ = Uₙ + h V_{n+½}, αₙ₊₁ = αₙ + h α̇_{n+½} (the αₙ₊₁ predicted by stage 8),
    /// tₙ₊₁ = tₙ + h; and F_int ← 0 for stage 3.
    pub(super) fn advance_positions(&mut self, h: f64) {
        let grain = NODE_GRAIN;
        let n = self.state.v.len();
        // Plane by plane (component slices, so the loops vectorise); the same pass zeroes
        // F_int for stage 3 (nothing reads it in between).
        let u = self.state.u.planes_mut().map(SharedSlice::new);
        let f = self.state.f_int.planes_mut().map(SharedSlice::new);
        let v = self.state.v.planes();
        // SAFETY: nodes a..b of each plane of u and f are touched by item i only.
        let chunk = |i: usize| unsafe {
            let (a, b) = (i * grain, ((i + 1) * grain).min(n));
            for c in 0..3 {
                for (ui, vi) in u[c].range(a, b).iter_mut().zip(&v[c][a..b]) {
                    *ui += h * vi;
                }
                f[c].range(a, b).fill(0.0);
            }
        };
        match &self.work.team {
            Some(team) => {
                team.map(n.div_ceil(grain), chunk);
            }
            None => (0..n.div_ceil(grain)).for_each(chunk),
        }
        for itf in self.state.interface_nodes.iter_mut() {
            itf.alpha = itf.alpha_next;
        }
        self.advance_bond_damage();
        self.state.time += h;
        self.state.step_count += 1;
    }

    /// Stage 2: the rigid surfaces at tₙ₊₁ (plane displacement d(t)), and at every interface
    /// node the jump [u] = x − y(t) and gap g = n·(x − p(t)), at every contact node the gap.
    ///
    /// A gap within the round-off of positions, |g| ≤ 16 ε (max|X| + |p(t)|), is set to 0:
    /// below that, "g ≤ 0" is not a property of the motion but of the last bit of a velocity
    /// that an impulse brought to zero (V + (−mV)/m can be one ulp off). Without it, a node
    /// held on a plane drifts by h·ulp(V), reads g = +3e-22 m, is declared open, and the next
    /// step takes it through the plane with the full free velocity (a spurious inelastic
    /// impact of h·V depth inside a persistent contact).
    pub(super) fn surfaces_and_gaps(&mut self) {
        let t = self.state.time;
        let planes = &self.model.moulds;
        let sc = &mut self.work.step;
        sc.plane_disp.clear();
        sc.plane_disp
            .extend(planes.iter().map(|p| p.displacement(t)));
        sc.plane_tol.clear();
        sc.plane_tol
            .extend(planes.iter().zip(&sc.plane_disp).map(|(p, d)| {
                let scale = (0..3).fold(self.setup.coordinate_scale, |a, c| {
                    a.max(p.point[c].abs()).max((p.point[c] + d[c]).abs())
                });
                16.0 * f64::EPSILON * scale
            }));
        let (disp, tol) = (&sc.plane_disp, &sc.plane_tol);
        let snap = |g: f64, tol: f64| if g.abs() <= tol { 0.0 } else { g };
        let nodes = &self.model.mesh.nodes;
        for itf in self.state.interface_nodes.iter_mut() {
            let k = self.model.interfaces[itf.interface as usize].plane;
            let (p, d) = (&planes[k], disp[k]);
            let i = itf.node as usize;
            let ui = self.state.u.get(i);
            let x: [f64; 3] = std::array::from_fn(|c| nodes[i][c] + ui[c]);
            itf.jump = std::array::from_fn(|c| x[c] - (itf.bonded_point[c] + d[c]));
            itf.gap = snap(
                (0..3)
                    .map(|c| p.normal[c] * (x[c] - p.point[c] - d[c]))
                    .sum(),
                tol[k],
            );
        }
        for cn in self.state.contact_nodes.iter_mut() {
            let (p, d) = (&planes[cn.plane as usize], disp[cn.plane as usize]);
            let i = cn.node as usize;
            let ui = self.state.u.get(i);
            cn.gap = snap(
                (0..3)
                    .map(|c| p.normal[c] * (nodes[i][c] + ui[c] - p.point[c] - d[c]))
                    .sum(),
                tol[cn.plane as usize],
            );
        }
        self.mould_gaps();
        self.bond_gaps();
    }

    /// Stage 3: F_int(Uₙ₊₁) = Σ_e fₑ(Uₙ₊₁) (model §4.3) and Ψₙ₊₁; an inverted element
    /// (J ≤ 0) stops the run. `zeroed`: F_int is already 0 (stage 1 clears it), else it is
    /// cleared here.
    pub(super) fn internal_forces(
        &mut self,
        energy: bool,
        zeroed: bool,
    ) -> Result<(), SolverError> {
        if !zeroed {
            // (Else F_int was zeroed by stage 1.)
            self.state.f_int.fill_zero();
        }
        let elements = ElementLoop {
            model: &self.model,
            classes: &self.work.classes,
            blocks: &self.work.blocks,
            team: self.work.team.as_ref(),
            prefetch: self.work.prefetch,
        };
        // The smallest J of the corners has one consumer in the step, the inversion check
        // (J ≤ 0), which needs its sign only. So the one-point kernel skips a lane group's exact
        // corner check where the bound J (1 − C|q|/s)³ ([`crate::kernels::corner_bound`]) of
        // each of its elements is positive (≥ CORNER_EXACT_BELOW): every corner is then
        // positive, and an inverted corner (J_a ≤ 0, so a bound ≤ 0) is checked exactly. Exact
        // everywhere at t₀. The step control reads the stress points' J (`stress_jacobian`),
        // always exact.
        let exact_below = if self.state.step_count == 0 {
            f64::INFINITY
        } else {
            CORNER_EXACT_BELOW
        };
        let asm = elements.assemble(
            &self.state.u,
            &mut self.state.f_int,
            energy,
            &mut self.work.elements,
            exact_below,
        );
        self.stats.corner_checks.groups += asm.corner_groups;
        self.stats.corner_checks.skipped += asm.corner_skipped;
        let (min_j, min_e) = (asm.min_j, asm.min_element);
        self.state.min_jacobian = min_j;
        self.state.stress_jacobian = asm.min_stress_j;
        self.state.step_control.compressed_element = asm.min_stress_element;
        if energy {
            self.state.ledger.strain = asm.strain;
            self.state.ledger.hourglass = asm.hourglass;
        }
        if !(min_j > 0.0) {
            if min_j.is_nan() {
                return Err(
                    self.unstable("non-finite displacements (NaN) in the element loop".into())
                );
            }
            return Err(self.inverted(min_e, min_j));
        }
        self.bulk_viscosity_forces();
        Ok(())
    }

    /// Stage 4, once h_{n+3/2} is fixed: the velocity of each plane over the
    /// interval just taken and the next one, the prescribed velocity of each condition over the
    /// next interval (Ū(tₙ₊₂) − Ū(tₙ₊₁))/h and whether it jumps at tₙ₊₁ (then the reaction is
    /// that jump's impulse, not a force to report), and the traction amplitudes at tₙ₊₁.
    /// `first`: the start of the run (nothing moved before t₀).
    pub(super) fn prescribed_motion(&mut self, h_next: f64, first: bool) {
        let t = self.state.time;
        let t_next = t + h_next;
        let planes = &self.model.moulds;
        let h_prev = self.state.h;
        let sc = &mut self.work.step;
        (self.state.moulds).advance(planes, t, h_next, h_prev, first || h_prev <= 0.0);
        sc.plane_v_old.clear();
        sc.plane_v_old.extend(planes.iter().map(|p| {
            if first || h_prev <= 0.0 {
                [0.0; 3]
            } else {
                let (a, b) = (p.displacement(t - h_prev), p.displacement(t));
                std::array::from_fn(|c| (b[c] - a[c]) / h_prev)
            }
        }));
        sc.plane_v_new.clear();
        sc.plane_v_new.extend(planes.iter().map(|p| {
            let (a, b) = (p.displacement(t), p.displacement(t_next));
            std::array::from_fn(|c| (b[c] - a[c]) / h_next)
        }));
        sc.bc_velocity.clear();
        sc.bc_jump.clear();
        for d in &self.model.displacements {
            let u = |t: f64| d.history.value(t)[0];
            let target = (u(t_next) - u(t)) / h_next;
            let jump = first || {
                let prev = (u(t) - u(t - h_prev)) / h_prev;
                (target - prev).abs() > 1e-9 * (target.abs() + prev.abs())
            };
            sc.bc_velocity.push(target);
            sc.bc_jump.push(jump);
        }
        sc.reactions.clear();
        sc.reactions.resize(self.model.displacements.len(), 0.0);
        sc.amplitudes.clear();
        sc.amplitudes.extend(
            self.model
                .tractions
                .iter()
                .map(|tr| tr.amplitude.value(t)[0]),
        );
    }

    /// Stage 5 on every node: V_free = V + h̄ M⁻¹(m g − F_int), with the ledger's halves
    /// b = ½V_old·P and a = ½V_free·P of the internal and gravity impulses P; keeps V_{n+½} of
    /// the boundary nodes first (their stages 5–8 follow in [`Simulation::boundary_pass`]).
    /// Returns the node loop's sums for stage 9.
    pub(super) fn free_velocity(&mut self, h_bar: f64) -> NodeSums {
        // Keep V_{n+½} of boundary nodes and bond pairs for the ledger's backward halves.
        self.keep_bond_velocities();
        let sc = &mut self.work.step;
        sc.v_old.clear();
        sc.v_old.extend(
            self.state
                .boundary
                .nodes
                .iter()
                .map(|b| self.state.v.get(b.node as usize)),
        );
        let g = self.model.gravity;
        // SAFETY: the dispatch runs the build the CPU supports; the slices have one length.
        let body = |(v, f, (m, im)): NodeChunk| -> NodeSums {
            unsafe { free_velocity_chunk(v, f, m, im, h_bar, g) }
        };
        let grain = NODE_GRAIN;
        let parts = &mut self.work.parts_nodes;
        let n = self.state.v.len();
        let v = self.state.v.planes_mut().map(SharedSlice::new);
        let (f, m, im) = (
            self.state.f_int.planes(),
            &self.setup.mass,
            &self.setup.inv_mass,
        );
        // SAFETY: nodes a..b of each plane of v are touched by item i only.
        let chunk = |i: usize| unsafe {
            let (a, b) = (i * grain, ((i + 1) * grain).min(n));
            let vc = v.each_ref().map(|p| p.range(a, b));
            body((vc, f.map(|p| &p[a..b]), (&m[a..b], &im[a..b])))
        };
        match &self.work.team {
            Some(team) => team.map_into(n.div_ceil(grain), parts, chunk),
            None => {
                parts.clear();
                parts.extend((0..n.div_ceil(grain)).map(chunk));
            }
        }
        if let Some(bv) = self.state.bulk_viscosity.as_mut() {
            bv.h_bar = h_bar;
        }
        parts.iter().fold(NodeSums::default(), |a, &b| a.add(b))
    }
}
