//! Stage 2 against moulds that are not plain planes (issue 13, [`crate::mould`]): each glued
//! node's anchor, jump and glue normal, each node's closest mould point, normal and gap. Plain
//! planes keep stage 2 of `stages.rs` untouched (the same arithmetic as before moulds existed).

use super::super::Simulation;
use crate::mesh::{dot, sub};
use crate::mould::step::NodeGeometry;

impl Simulation {
    /// At t₀: the per-node geometry of glued and contact nodes on curved moulds (empty when
    /// every mould is a plain plane): the glue normal N₀ at each anchor y₀ (the closest mould
    /// point to the node at t₀, already in `bonded_point`).
    pub(in crate::solver) fn mould_geometry_at_start(&mut self) {
        let ms = &mut self.scratch.moulds;
        if !ms.any_general() {
            return;
        }
        let planes = &self.model.planes;
        ms.interface = (self.interface_nodes.iter())
            .map(|itf| {
                let k = self.model.interfaces[itf.interface as usize].plane;
                let n0 = planes[k].project0(itf.bonded_point).normal;
                NodeGeometry {
                    normal0: n0,
                    glue_normal: n0,
                    anchor: itf.bonded_point,
                    ..Default::default()
                }
            })
            .collect();
        ms.contact = vec![NodeGeometry::default(); self.contact_nodes.len()];
    }

    /// Stage 2 on curved moulds at tₙ₊₁ (module docs of [`crate::mould`]): for a glued node, the
    /// anchor y(t) = c + R(y₀ − c₀) (a material point of the mould), [u] = x − y(t) and the glue
    /// normal R N₀; for every node on such a mould, the closest point p, the outward normal n
    /// there and the gap g = n·(x − p) (snapped to 0 within the round-off of positions, as for
    /// planes).
    pub(in crate::solver) fn mould_gaps(&mut self) {
        if !self.scratch.moulds.any_general() {
            return;
        }
        let nodes = &self.model.mesh.nodes;
        let (planes, u) = (&self.model.planes, &self.u);
        let sc = &mut self.scratch;
        let (ms, tol) = (&mut sc.moulds, &sc.plane_tol);
        let snap = |g: f64, tol: f64| if g.abs() <= tol { 0.0 } else { g };
        let place = |i: usize| -> [f64; 3] { std::array::from_fn(|c| nodes[i][c] + u[i][c]) };
        for (j, itf) in self.interface_nodes.iter_mut().enumerate() {
            let k = self.model.interfaces[itf.interface as usize].plane;
            if ms.plane[k] {
                continue;
            }
            let (m, x) = (&planes[k], place(itf.node as usize));
            let pose = ms.cur[k];
            let mut geo = ms.interface[j];
            geo.anchor = pose.place(m.pivot(), itf.bonded_point);
            geo.glue_normal = crate::mould::motion::mat_vec(&pose.rotation, geo.normal0);
            itf.jump = sub(x, geo.anchor);
            let pr = ms.project(m, k, x);
            (geo.point, geo.normal) = (pr.point, pr.normal);
            itf.gap = snap(dot(pr.normal, sub(x, pr.point)), tol[k]);
            ms.interface[j] = geo;
        }
        for (j, cn) in self.contact_nodes.iter_mut().enumerate() {
            let k = cn.plane as usize;
            if ms.plane[k] {
                continue;
            }
            let x = place(cn.node as usize);
            let pr = ms.project(&planes[k], k, x);
            (ms.contact[j].point, ms.contact[j].normal) = (pr.point, pr.normal);
            cn.gap = snap(dot(pr.normal, sub(x, pr.point)), tol[k]);
        }
    }

    /// The glue normal of interface node `j` at tₙ₊₁: its plane's normal, or on a curved mould
    /// the mould's normal at the anchor turned with the mould (R N₀).
    #[inline]
    pub(in crate::solver) fn glue_normal(&self, j: usize) -> [f64; 3] {
        let k = self.model.interfaces[self.interface_nodes[j].interface as usize].plane;
        if self.scratch.moulds.plane[k] {
            self.model.planes[k].normal
        } else {
            self.scratch.moulds.interface[j].glue_normal
        }
    }
}
