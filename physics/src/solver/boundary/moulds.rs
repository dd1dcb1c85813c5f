//! Stage 2 against moulds that are not plain planes (model §7.4, §7.5; [`crate::mould`]): each
//! glued node's anchor, jump and glue normal, each node's closest mould point, normal and gap.
//! Plain planes keep stage 2 of `stages.rs` untouched (the same arithmetic as before moulds
//! existed).

use super::super::Simulation;
use crate::mesh::{dot, sub};
use crate::mould::step::{MouldStep, NodeGeometry};
use crate::mould::surface::NearLists;
use crate::mould::Shape;

impl Simulation {
    /// At t₀: the per-node geometry of glued and contact nodes on curved moulds (empty when
    /// every mould is a plain plane): the glue normal N₀ at each anchor y₀ (the closest mould
    /// point to the node at t₀, already in `bonded_point`).
    pub(in crate::solver) fn mould_geometry_at_start(&mut self) {
        let ms = &mut self.state.moulds;
        if !ms.any_general() {
            return;
        }
        let planes = &self.model.moulds;
        ms.interface = (self.state.interface_nodes.iter())
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
        ms.contact = vec![NodeGeometry::default(); self.state.contact_nodes.len()];
        // The lists of nearby triangles, allocated once, when some mould is triangulated.
        if planes.iter().any(|m| matches!(m.shape, Shape::Surface(_))) {
            ms.near_interface = NearLists::new(ms.interface.len());
            ms.near_contact = NearLists::new(ms.contact.len());
        }
    }

    /// Stage 2 on curved moulds at tₙ₊₁ (module docs of [`crate::mould`]): for a glued node, the
    /// anchor y(t) = c + R(y₀ − c₀) (a material point of the mould), [u] = x − y(t) and the glue
    /// normal R N₀; for every node on such a mould, the closest point p, the outward normal n
    /// there and the gap g = n·(x − p) (snapped to 0 within the round-off of positions, as for
    /// planes); on a triangulated mould, the faces a node inside the mould is behind at a
    /// concave edge or vertex (model §7.5), its constraints in stage 7.
    pub(in crate::solver) fn mould_gaps(&mut self) {
        if !self.state.moulds.any_general() {
            return;
        }
        let (nodes, t) = (&self.model.mesh.nodes, self.state.time);
        let (planes, u) = (&self.model.moulds, &self.state.u);
        let sc = &mut self.work.step;
        let (ms, tol, cold) = (
            &mut self.state.moulds,
            &sc.plane_tol,
            self.work.cold_mould_queries,
        );
        let snap = |g: f64, tol: f64| if g.abs() <= tol { 0.0 } else { g };
        let place = |i: usize| -> [f64; 3] {
            let ui = u.get(i);
            std::array::from_fn(|c| nodes[i][c] + ui[c])
        };
        for (j, itf) in self.state.interface_nodes.iter_mut().enumerate() {
            let k = self.model.interfaces[itf.interface as usize].plane;
            if ms.plane[k] {
                continue;
            }
            let (m, x) = (&planes[k], place(itf.node as usize));
            let pose = ms.pose_at(k, t);
            let mut geo = ms.interface[j];
            geo.anchor = pose.place(m.pivot(), itf.bonded_point);
            geo.glue_normal = crate::mould::motion::mat_vec(&pose.rotation, geo.normal0);
            itf.jump = sub(x, geo.anchor);
            let near = (&mut ms.near_interface, j);
            let (pr, faces) = MouldStep::project(m, &pose, x, &mut geo.feature, near, cold, tol[k]);
            (geo.point, geo.normal, geo.faces) = (pr.point, pr.normal, faces);
            itf.gap = snap(dot(pr.normal, sub(x, pr.point)), tol[k]);
            ms.interface[j] = geo;
        }
        for (j, cn) in self.state.contact_nodes.iter_mut().enumerate() {
            let k = cn.plane as usize;
            if ms.plane[k] {
                continue;
            }
            let x = place(cn.node as usize);
            let pose = ms.pose_at(k, t);
            let (geo, near) = (&mut ms.contact[j], (&mut ms.near_contact, j));
            let (pr, faces) =
                MouldStep::project(&planes[k], &pose, x, &mut geo.feature, near, cold, tol[k]);
            (geo.point, geo.normal, geo.faces) = (pr.point, pr.normal, faces);
            cn.gap = snap(dot(pr.normal, sub(x, pr.point)), tol[k]);
        }
    }

    /// Query triangulated moulds cold (the full BVH query at every step) instead of from each
    /// node's list of nearby triangles: the same results (see
    /// [`crate::mould::SurfaceMesh::project_near`]), slower; for measuring the lists only.
    pub fn set_mould_queries_cold(&mut self, cold: bool) {
        self.work.cold_mould_queries = cold;
    }

    /// What the lists of nearby triangles did since the start (interface nodes, contact nodes).
    pub fn mould_near_stats(&self) -> [crate::mould::surface::NearStats; 2] {
        let ms = &self.state.moulds;
        [ms.near_interface.stats, ms.near_contact.stats]
    }

    /// The glue normal of interface node `j` at tₙ₊₁: its plane's normal, or on a curved mould
    /// the mould's normal at the anchor turned with the mould (R N₀).
    #[inline]
    pub(in crate::solver) fn glue_normal(&self, j: usize) -> [f64; 3] {
        let k = self.model.interfaces[self.state.interface_nodes[j].interface as usize].plane;
        if self.state.moulds.plane[k] {
            self.model.moulds[k].normal
        } else {
            self.state.moulds.interface[j].glue_normal
        }
    }

    /// The glue normal of interface node `j` at tₙ, R(tₙ)N₀, where its glue has a torque
    /// (model §5.5): anisotropic glue ([`Loading::isotropic`] false), formed, on a mould that
    /// is not a plain plane. `None` elsewhere: isotropic glue has none, a plain plane does not
    /// turn.
    ///
    /// [`Loading::isotropic`]: crate::interface::damage::Loading::isotropic
    #[inline]
    pub(in crate::solver) fn glue_normal_before(&self, j: usize) -> Option<[f64; 3]> {
        let itf = &self.state.interface_nodes[j];
        let spec = &self.model.interfaces[itf.interface as usize];
        let ms = &self.state.moulds;
        if ms.plane[spec.plane] || spec.law.loading().isotropic() || !itf.formed {
            return None;
        }
        Some(ms.glue_normal_prev(spec.plane, ms.interface[j].normal0))
    }

    /// The anchor of interface node `itf` and the contact point of it or of contact node `cn`
    /// on mould `k` at tₙ₊₁ (any point of a plain plane: its velocity is the same everywhere).
    pub(in crate::solver) fn mould_points(
        &self,
        k: usize,
        itf: Option<usize>,
        cn: Option<usize>,
    ) -> ([f64; 3], [f64; 3]) {
        let ms = &self.state.moulds;
        if ms.plane[k] {
            return ([0.0; 3], [0.0; 3]);
        }
        match (itf, cn) {
            (Some(j), _) => (ms.interface[j].anchor, ms.interface[j].point),
            (_, Some(j)) => ([0.0; 3], ms.contact[j].point),
            _ => ([0.0; 3], [0.0; 3]),
        }
    }

    /// The velocity of mould `k` at the point p over the intervals before and after tₙ₊₁.
    pub(in crate::solver) fn mould_velocities(&self, k: usize, p: [f64; 3]) -> [[f64; 3]; 2] {
        let sc = &self.work.step;
        if self.state.moulds.plane[k] {
            [sc.plane_v_old[k], sc.plane_v_new[k]]
        } else {
            let ms = &self.state.moulds;
            [ms.velocity_old(k, p), ms.velocity_new(k, p)]
        }
    }

    /// Each mould's name and its work since t₀ [J] (force · velocity at the points it acts
    /// on, moments included): with one mould, the ledger's `plane_work`.
    pub fn mould_works(&self) -> Vec<(String, f64)> {
        let planes = &self.model.moulds;
        if planes.len() == 1 {
            return vec![(planes[0].name.clone(), self.state.ledger.plane_work.value)];
        }
        let works = &self.state.moulds.work;
        (planes.iter().zip(works))
            .map(|(p, w)| (p.name.clone(), w.value))
            .collect()
    }
}
