//! Glue that forms on contact (a `[[contact]]` entry with an adhesive law; model §8,
//! the generalisation of §2–§5, where glue exists from t = 0 only).
//!
//! Until it forms, such a node is a contact node: its interface entry is a unilateral
//! constraint with the contact's Coulomb μ (stage 7), with no glue force (g_N = 0), no damage
//! and nothing in the glue's share of the ledger (Ψ_d = ½W g_N|[u]|² = 0, ΔD = 0). A node forms
//! at the end of the step tₙ₊₁ whose contact solve closed it (status stick or slip: gₙ₊₁ ≤ 0
//! and an impulse pressing it on the mould):
//!
//! - its anchor is the material point of the mould at which the node is at tₙ₊₁,
//!   y = xₙ₊₁ (the closest point p plus the snapped penetration gₙ₊₁n, gₙ₊₁ ≤ 0 within the
//!   step's contact tolerance; p itself when gₙ₊₁ = 0), stored in the mould's frame at t₀ as
//!   glued anchors are, y₀ = R(tₙ₊₁)ᵀ(y − c(tₙ₊₁)) + c₀ (a plane: y − d(tₙ₊₁)), so that it moves
//!   and turns with the mould from then on; the glue normal is the mould's normal at p, kept in
//!   the mould's frame, N₀ = R(tₙ₊₁)ᵀn;
//! - the glue is intact: α = α_s = 0, g_N = g_N(0), [u]ₙ₊₁ = 0, so its stored energy starts at
//!   exactly 0 and the step's damage dissipation increment is 0 (the ledger closes with no
//!   term for the formation; the glue's energy afterwards is the work of its own force);
//! - from the next step on it is a glued node like any other (stage 5 cohesion, stage 7
//!   contact with μ(α), stage 8 damage, μ_inf once ruptured).
//!
//! A ruptured node is never glued again (`formed` stays true, g_N(u_r) = 0: contact with μ_inf
//! only). The damage of RCCM is irreversible: the glue's fracture energy G_c was spent tearing
//! it, and re-forming it at the next touch would create glue (and energy to dissipate) from
//! nothing; the hysteresis test checks D = G_c × the torn area on that basis.

use crate::interface::contact::ContactStatus;
use crate::mesh::sub;
use crate::mould::motion::mat_t_vec;
use crate::solver::Simulation;

impl Simulation {
    /// Forms the glue of each not-yet-glued node that this step's contact solve closed (module
    /// docs); runs after the boundary pass, before the ledger. Allocates nothing: the nodes
    /// were allocated at setup, and each leaves `boundary.forming` by a swap.
    pub(in crate::solver) fn form_glue(&mut self) {
        let mut i = 0;
        while i < self.state.boundary.forming.len() {
            let j = self.state.boundary.forming[i] as usize;
            if self.state.interface_nodes[j].contact == ContactStatus::Open {
                i += 1;
            } else {
                self.form_glue_at(j);
                self.state.boundary.forming.swap_remove(i);
            }
        }
    }

    /// Glues interface node `j` where it is at tₙ₊₁ (module docs).
    fn form_glue_at(&mut self, j: usize) {
        let itf = &self.state.interface_nodes[j];
        let spec = &self.model.interfaces[itf.interface as usize];
        let k = spec.plane;
        let g0 = spec.law.g_n(0.0);
        let i = itf.node as usize;
        let x: [f64; 3] =
            std::array::from_fn(|c| self.model.mesh.nodes[i][c] + self.state.u.get(i)[c]);
        let ms = &mut self.state.moulds;
        let bonded = if !ms.any_general() || ms.plane[k] {
            sub(x, self.work.step.plane_disp[k])
        } else {
            let mould = &self.model.moulds[k];
            let pose = ms.pose_at(k, self.state.time);
            let geo = &mut ms.interface[j];
            geo.normal0 = mat_t_vec(&pose.rotation, geo.normal);
            (geo.glue_normal, geo.anchor) = (geo.normal, x);
            pose.unplace(mould.pivot(), x)
        };
        let itf = &mut self.state.interface_nodes[j];
        itf.formed = true;
        itf.bonded_point = bonded;
        (itf.alpha, itf.alpha_next, itf.alpha_static) = (0.0, 0.0, 0.0);
        (itf.jump, itf.prev_jump) = ([0.0; 3], [0.0; 3]);
        (itf.stiffness, itf.prev_stiffness) = (g0, g0);
        itf.cohesive_traction = [0.0; 3];
    }
}
