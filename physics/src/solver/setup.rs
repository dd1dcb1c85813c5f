//! Building a simulation: lumped masses (model §1.7), the interface, contact, traction and
//! prescribed entries per boundary node, the first stable-step estimate (model §6), and the start
//! of the leapfrog at t₀ (model §4.11: V_{−½}, then the first impulses give V_{½}).

use super::bond::BondNode;
use super::boundary::{Boundary, NONE};
use super::ledger::StepSums;
use super::mass_scaling::{class_factors, MassScalingReport};
use super::stable_step::{capped_step, StepControl};
use super::stages::StepScratch;
use super::state::{ContactNode, InterfaceNode, PeakReaction, RunStats, SolverError, State};
use super::{Setup, Simulation, Workspace, ELEMENT_GRAIN, PARALLEL_MIN_ELEMENTS};
use crate::energy::Ledger;
use crate::interface::contact::ContactStatus;
use crate::kernels::AssemblyScratch;
use crate::kernels::Planes;
use crate::mesh::{dot, sub, ElementClasses, Mesh};
use crate::model::{Model, StartOffset};
use crate::mould::mould_closest_point;
use crate::mould::step::MouldStep;
use crate::team::Team;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The face set `name` of `mesh`.
fn face<'a>(mesh: &'a Mesh, name: &str) -> Result<&'a Vec<[u32; 4]>, SolverError> {
    mesh.face_sets
        .get(name)
        .ok_or_else(|| SolverError::Setup(format!("no face set named `{name}`")))
}

/// Lumped nodal masses mₐ = Σ_e ρ₀ s_e Vₐᵉ, the row sums of the consistent mass (model §1.7),
/// s_e the density factor of mass scaling (model §6.8; `factors` by hexahedron class,
/// `tet_factors` by tetrahedron, empty: 1);
/// a node of no element (zero mass) is refused.
fn lumped_masses(
    model: &Model,
    classes: &ElementClasses,
    factors: &[f64],
    tet_factors: &[f64],
) -> Result<Vec<f64>, SolverError> {
    let rho = model.material.density;
    let mut mass = vec![0.0; model.mesh.nodes.len()];
    for (e, conn) in model.mesh.elements.iter().enumerate() {
        let c = classes.class_of[e] as usize;
        let lv = classes.data[c].lumped_volumes();
        let rho_e = match factors.get(c) {
            Some(s) => rho * s,
            None => rho,
        };
        for a in 0..8 {
            mass[conn[a] as usize] += rho_e * lv[a];
        }
    }
    // A tetrahedron's share is ρV/4 at each node (model §1.13), ρ = s_e ρ₀ with mass scaling
    // (model §6.8).
    for (t, (conn, v)) in model.mesh.tets.iter().zip(&classes.tets.volume).enumerate() {
        let rho_e = match tet_factors.get(t) {
            Some(s) => rho * s,
            None => rho,
        };
        for &a in conn {
            mass[a as usize] += 0.25 * rho_e * v;
        }
    }
    if let Some(i) = mass.iter().position(|&m| !(m > 0.0)) {
        return Err(SolverError::Setup(format!(
            "node {i} belongs to no element (zero mass)"
        )));
    }
    Ok(mass)
}

/// The glued nodes of every interface, each bonded to its closest mould point y₀ at t₀
/// ([`mould_closest_point`]), with its tributary reference area W (model §2.1, §7.4).
/// The nodes of glue that forms on contact are allocated here too, not yet formed (g_N = 0;
/// their anchor is set when they form, [`Simulation::form_glue`]).
fn glued_nodes(model: &Model) -> Result<Vec<InterfaceNode>, SolverError> {
    let mesh = &model.mesh;
    let mut out = Vec::new();
    for (k, itf) in model.interfaces.iter().enumerate() {
        let formed = itf.forms_on_contact.is_none();
        let g0 = if formed { itf.law.g_n0 } else { 0.0 };
        let plane = &model.moulds[itf.plane];
        for (node, area) in mesh.nodal_areas(face(mesh, &itf.faces)?) {
            let x = mesh.nodes[node as usize];
            let (y0, n) = mould_closest_point(plane, x);
            let gap0 = dot(n, sub(x, y0));
            out.push(InterfaceNode {
                node,
                interface: k as u32,
                area,
                bonded_point: y0,
                alpha: 0.0,
                alpha_next: 0.0,
                alpha_static: 0.0,
                jump: [0.0; 3],
                gap: gap0,
                stiffness: g0,
                cohesive_traction: [0.0; 3],
                contact_impulse: [0.0; 3],
                contact: ContactStatus::Open,
                formed,
                prev_jump: [0.0; 3],
                prev_stiffness: g0,
            });
        }
    }
    Ok(out)
}

/// The nodes of every contact face set, with their area and friction coefficient.
fn contact_nodes(model: &Model) -> Result<Vec<ContactNode>, SolverError> {
    let mut out = Vec::new();
    for c in &model.contacts {
        for (node, area) in model.mesh.nodal_areas(face(&model.mesh, &c.faces)?) {
            out.push(ContactNode {
                node,
                plane: c.plane as u32,
                mu: c.mu,
                area,
                gap: 0.0,
                contact_impulse: [0.0; 3],
                contact: ContactStatus::Open,
            });
        }
    }
    Ok(out)
}

/// (node, traction index, nodal force W t at amplitude 1 [N]) of every traction.
fn traction_entries(model: &Model) -> Result<Vec<(u32, u16, [f64; 3])>, SolverError> {
    let mut out = Vec::new();
    for (k, t) in model.tractions.iter().enumerate() {
        for (node, area) in model.mesh.nodal_areas(face(&model.mesh, &t.faces)?) {
            out.push((node, k as u16, t.vector.map(|c| c * area)));
        }
    }
    Ok(out)
}

/// The prescribed condition of each component per node; a component prescribed twice with
/// different histories is refused.
fn prescribed_components(model: &Model) -> Result<BTreeMap<u32, [u16; 3]>, SolverError> {
    let mut prescribed: BTreeMap<u32, [u16; 3]> = BTreeMap::new();
    for (k, d) in model.displacements.iter().enumerate() {
        for node in model.mesh.face_set_nodes(face(&model.mesh, &d.faces)?) {
            let slot = &mut prescribed.entry(node).or_insert([NONE; 3])[d.component];
            if *slot != NONE && model.displacements[*slot as usize].history != d.history {
                return Err(SolverError::Setup(format!(
                    "node {node} has component {} prescribed twice with different histories (displacement[{}] on `{}` and displacement[{k}] on `{}`)",
                    ["x", "y", "z"][d.component],
                    *slot,
                    model.displacements[*slot as usize].faces,
                    d.faces
                )));
            }
            if *slot == NONE {
                *slot = k as u16;
            }
        }
    }
    Ok(prescribed)
}

/// The lumped masses of a model, scaled where mass scaling asks for it (model §1.7, §6.8).
struct Masses {
    /// mₐ with the density factors s_e.
    mass: Vec<f64>,
    /// s_e per hexahedron class and per tetrahedron (empty without mass scaling).
    class_density: Vec<f64>,
    tet_density: Vec<f64>,
    /// (node, mₐ − mₐ⁰) where scaling added mass.
    added_mass: Vec<(u32, f64)>,
    mass_scaling: Option<MassScalingReport>,
}

impl Masses {
    fn of(model: &Model, classes: &ElementClasses) -> Result<Masses, SolverError> {
        let (class_density, tet_density, mut mass_scaling) = match class_factors(model, classes) {
            Some((f, r)) => (f.class, f.tet, Some(r)),
            None => (vec![], vec![], None),
        };
        let mass = lumped_masses(model, classes, &class_density, &tet_density)?;
        let added_mass = match mass_scaling.as_mut() {
            None => vec![],
            Some(report) => {
                let unscaled = lumped_masses(model, classes, &[], &[])?;
                report.mass = unscaled.iter().sum();
                report.added_mass = mass.iter().sum::<f64>() - report.mass;
                (mass.iter().zip(&unscaled).enumerate())
                    .filter(|(_, (m, m0))| m > m0)
                    .map(|(i, (m, m0))| (i as u32, m - m0))
                    .collect()
            }
        };
        Ok(Masses {
            mass,
            class_density,
            tet_density,
            added_mass,
            mass_scaling,
        })
    }
}

/// The boundary nodes of a model: glued interface nodes, contact nodes, their entries per node
/// with the tractions and prescribed components (one constraint count each), the bonded pairs
/// (on nodes no other condition takes), and the glue that forms on contact (model §8).
struct BoundaryEntries {
    interface_nodes: Vec<InterfaceNode>,
    contact_nodes: Vec<ContactNode>,
    bond_nodes: Vec<BondNode>,
    boundary: Boundary,
}

impl BoundaryEntries {
    fn of(model: &Model) -> Result<BoundaryEntries, SolverError> {
        let interface_nodes = glued_nodes(model)?;
        let contact_nodes = contact_nodes(model)?;
        let mut boundary = Boundary::gather(
            interface_nodes.iter().map(|i| i.node),
            contact_nodes.iter().map(|c| c.node),
            traction_entries(model)?,
            &prescribed_components(model)?,
        );
        super::boundary::check_constraint_count(&boundary.nodes)?;
        let mut taken: Vec<u32> = boundary.nodes.iter().map(|b| b.node).collect();
        taken.sort_unstable();
        let bond_nodes = super::bond::bond_nodes(model, &taken)?;
        boundary.forming = (0..interface_nodes.len() as u32)
            .filter(|&j| !interface_nodes[j as usize].formed)
            .collect();
        Ok(BoundaryEntries {
            interface_nodes,
            contact_nodes,
            bond_nodes,
            boundary,
        })
    }
}

impl State {
    /// The state before t₀'s start: U₀ and V₀ as given, the boundary entries, every sum and
    /// estimate zero (`Simulation::start` fills them).
    fn at_start(u0: Vec<[f64; 3]>, v0: Vec<[f64; 3]>, entries: BoundaryEntries) -> State {
        let n_nodes = u0.len();
        State {
            bulk_viscosity: None,
            u: Planes::from_rows(&u0),
            v: Planes::from_rows(&v0),
            f_int: Planes::zeros(n_nodes),
            interface_nodes: entries.interface_nodes,
            contact_nodes: entries.contact_nodes,
            bond_nodes: entries.bond_nodes,
            boundary: entries.boundary,
            moulds: MouldStep::default(),
            time: 0.0,
            step_count: 0,
            h: 0.0,
            h_crit: 0.0,
            ledger: Ledger::default(),
            min_jacobian: 1.0,
            stress_jacobian: 1.0,
            ritz_vector: Vec::new(),
            h_crit_bulk: None,
            jacobian_at_estimate: 1.0,
            step_control: StepControl {
                try_certify: true,
                ..Default::default()
            },
            kinetic_half: 0.0,
            energy_budget: 0.0,
            last_external_work: 0.0,
        }
    }
}

/// The statistics at t = 0: one peak-reaction record per prescribed displacement.
fn initial_stats(model: &Model) -> RunStats {
    RunStats {
        peaks: model
            .displacements
            .iter()
            .map(|d| PeakReaction {
                faces: d.faces.clone(),
                component: ["x", "y", "z"][d.component].into(),
                force: 0.0,
                imposed_displacement: d.history.value(0.0)[0],
                time: 0.0,
            })
            .collect(),
        reactions: vec![0.0; model.displacements.len()],
        ..Default::default()
    }
}

impl Simulation {
    /// Builds the simulation: reference gradients, colours, lumped masses, boundary bookkeeping,
    /// the first stable-step estimate, and the start of the leapfrog (V_{−½}, V_{½}).
    ///
    /// The initial velocity field is the rigid motion V₀(X) = v₀ + ω₀ × (X − X_c) of the scene's
    /// `initial_velocity` v₀ and `initial_angular_velocity` ω₀ about the centre of mass X_c.
    pub fn new(model: impl Into<Arc<Model>>) -> Result<Simulation, SolverError> {
        let model: Arc<Model> = model.into();
        let v0 = model.initial_velocity;
        let w = model.initial_angular_velocity;
        let mesh = &model.mesh;
        let n = mesh.nodes.len();
        let velocities = if w == [0.0; 3] {
            vec![v0; n]
        } else {
            let xc = mesh
                .centre_of_volume()
                .map_err(|e| SolverError::Setup(e.to_string()))?;
            mesh.nodes
                .iter()
                .map(|x| {
                    let r = sub(*x, xc);
                    [
                        v0[0] + w[1] * r[2] - w[2] * r[1],
                        v0[1] + w[2] * r[0] - w[0] * r[2],
                        v0[2] + w[0] * r[1] - w[1] * r[0],
                    ]
                })
                .collect()
        };
        Self::with_initial_state(model, vec![[0.0; 3]; n], velocities)
    }

    /// As [`Simulation::new`], from given initial displacements U₀ and velocities V₀ per node
    /// (prescribed components of U₀ are overwritten by their histories at t = 0).
    pub fn with_initial_state(
        model: impl Into<Arc<Model>>,
        u0: Vec<[f64; 3]>,
        v0: Vec<[f64; 3]>,
    ) -> Result<Simulation, SolverError> {
        let model: Arc<Model> = model.into();
        let n_nodes = model.mesh.nodes.len();
        if u0.len() != n_nodes || v0.len() != n_nodes {
            return Err(SolverError::Setup(format!(
                "initial state has {} displacements and {} velocities for {} nodes",
                u0.len(),
                v0.len(),
                n_nodes
            )));
        }
        let mesh = &model.mesh;
        let classes = mesh
            .element_classes()
            .map_err(|e| SolverError::Setup(e.to_string()))?;
        let masses = Masses::of(&model, &classes)?;
        let entries = BoundaryEntries::of(&model)?;
        let volume: f64 = classes
            .class_of
            .iter()
            .map(|&c| classes.data[c as usize].volume())
            .sum::<f64>()
            + classes.tets.volume.iter().sum::<f64>();
        #[cfg(not(target_arch = "wasm32"))]
        let threads = rayon::current_num_threads();
        // wasm32-unknown-unknown has one thread: the page steps on a team of one.
        #[cfg(target_arch = "wasm32")]
        let threads = 1;
        let team = (mesh.element_count() >= PARALLEL_MIN_ELEMENTS && threads > 1)
            .then(|| Team::new(threads));
        let coordinate_scale = mesh
            .nodes
            .iter()
            .flatten()
            .fold(0.0f64, |a, x| a.max(x.abs()));
        let start_offsets = (0..model.interfaces.len())
            .filter_map(|k| StartOffset::of(&model, k))
            .filter(StartOffset::any)
            .collect();
        let mut sim = Simulation {
            setup: Setup {
                start_offsets,
                inv_mass: masses.mass.iter().map(|m| 1.0 / m).collect(),
                mass: masses.mass,
                class_density: masses.class_density,
                tet_density: masses.tet_density,
                added_mass: masses.added_mass,
                mass_scaling: masses.mass_scaling,
                energy_floor: model.material.young * volume * 1e-14,
                coordinate_scale,
                fingerprint: std::sync::OnceLock::new(),
            },
            work: Workspace {
                blocks: mesh.element_blocks(ELEMENT_GRAIN),
                prefetch: crate::kernels::prefetch_pays(mesh.nodes.len()),
                classes,
                team,
                elements: AssemblyScratch::default(),
                parts_nodes: Vec::new(),
                parts_boundary: Vec::new(),
                parts_reactions: Vec::new(),
                step: StepScratch::default(),
                cold_mould_queries: false,
            },
            state: State::at_start(u0, v0, entries),
            stats: initial_stats(&model),
            model,
        };
        sim.state.moulds = MouldStep::new(&sim.model.moulds, 0.0);
        sim.mould_geometry_at_start();
        sim.bulk_viscosity_setup();
        sim.start()?;
        Ok(sim)
    }

    /// t = 0: U₀ (prescribed values), [u]₀, g₀, α₀, the first h_crit and h, F₀; then
    /// V_{−½} = V₀ − ½h M⁻¹F₀ and the first step's stages 4 (velocities), 5–8 and 9 give V_{½}
    /// (so K₀ = ½V_{−½}ᵀMV_{½}).
    fn start(&mut self) -> Result<(), SolverError> {
        for b in &self.state.boundary.nodes {
            for c in 0..3 {
                if b.prescribed[c] != NONE {
                    let mut x = self.state.u.get(b.node as usize);
                    x[c] = self.model.displacements[b.prescribed[c] as usize]
                        .history
                        .value(0.0)[0];
                    self.state.u.set(b.node as usize, x);
                }
            }
        }
        self.surfaces_and_gaps();
        self.initial_damage();
        self.bond_initial_damage();
        self.first_time_step()?;
        self.check_mass_scaling_target()?;
        self.internal_forces(true, false)?;
        let h = self.state.h;
        self.half_step_back(h);
        let nodes = self.free_velocity(h);
        let boundary = self.boundary_pass(h, h);
        let boundary = self.bond_pass(h, h, boundary);
        self.form_glue();
        self.ledger(h, true, StepSums { nodes, boundary })
    }

    /// α₀ = min(u_r, max(initial damage, f₀)): eq. 12's "largest jump ever reached", with the
    /// damage the interface had before the run.
    fn initial_damage(&mut self) {
        for j in 0..self.state.interface_nodes.len() {
            let n = self.glue_normal(j);
            let itf = &mut self.state.interface_nodes[j];
            if !itf.formed {
                continue; // α = 0 and g_N = 0 until the glue forms
            }
            let spec = &self.model.interfaces[itf.interface as usize];
            let law = &spec.law;
            itf.alpha = law.initial_damage(spec.initial_damage, itf.jump, n);
            (itf.alpha_next, itf.alpha_static) = (itf.alpha, itf.alpha);
            itf.stiffness = law.g_n(itf.alpha);
            itf.prev_stiffness = itf.stiffness;
            itf.prev_jump = itf.jump;
        }
    }

    /// The first h_crit estimate and h = min(factor, 1) × h_crit (model §6.6,
    /// [`capped_step`]); when a glued node's
    /// own spring (ω_i² = W g_N/m) is near the whole system's ω_max, the interface may set the
    /// step: the bulk alone is then measured once, for [`Simulation::advisories`].
    fn first_time_step(&mut self) -> Result<(), SolverError> {
        let est = self.estimate_stable_step(None);
        self.state.h_crit = est.h_crit;
        let omega_itf_sq = self.glue_spring_omega_sq();
        if omega_itf_sq > 0.0 && 2.0 / omega_itf_sq.sqrt() < 1.5 * est.h_crit {
            let ritz = std::mem::take(&mut self.state.ritz_vector);
            self.state.h_crit_bulk = Some(self.stable_step_estimate(None, false).h_crit);
            self.state.ritz_vector = ritz;
        }
        self.stats.h_crit_initial = est.h_crit;
        self.stats.h_crit_min = est.h_crit;
        self.state.h = capped_step(self.model.scheme.time_step_factor, est.h_crit);
        if let Some(bv) = self.model.scheme.bulk_viscosity {
            // The viscosity's damping ratio at rest, b₁ (λ + 2μ)/K (model §4.12).
            let xi = bv.linear * super::bulk_viscosity::mode_ratio(&self.model.material);
            self.state.h *= super::bulk_viscosity::damped_step_factor(xi);
        }
        if !(self.state.h.is_finite() && self.state.h > 0.0) {
            return Err(SolverError::Setup(format!(
                "the stable time step estimate is not usable (ω_max² = {:e}); check the material and interface stiffness",
                est.omega_max_sq
            )));
        }
        Ok(())
    }

    /// The largest ω² = W k/m of a glued node's spring alone against its mass [1/s²] (0
    /// without glue).
    pub(super) fn glue_spring_omega_sq(&self) -> f64 {
        (self.state.interface_nodes.iter())
            .map(|n| n.area * n.stiffness * self.setup.inv_mass[n.node as usize])
            .fold(0.0, f64::max)
    }

    /// V_{−½} = V₀ − ½h M⁻¹F₀ with the smooth forces (internal, gravity, tractions, glue):
    /// stage 5's smooth impulses taken for half a step backwards, h̄ = −½h.
    fn half_step_back(&mut self, h: f64) {
        self.prescribed_motion(h, true);
        self.free_velocity(-0.5 * h);
        self.smooth_impulses(-0.5 * h);
    }
}
