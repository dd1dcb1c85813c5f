//! The validated physical model a simulation runs on: mesh, material, rigid planes, interfaces,
//! contact faces, loads and scheme parameters. Built from a scene file by [`crate::scene`], or
//! directly in code. Every quantity is SI.
//!
//! Sign conventions (stated once, used everywhere): a rigid plane's unit normal `n` points into
//! the solid; the gap g = n·(x − p) is > 0 when open; contact impulses and cohesive tractions are
//! per unit reference area and act on the solid; α is in metres.

use crate::law::StiffnessLaw;
use crate::material::Material;
use crate::mesh::{dot, sub, Mesh};
use crate::mould::mould_closest_point;
// The model's vocabulary defined in the modules below it.
pub use crate::mould::{Mould, Projection, RigidMotion, Shape};
pub use crate::piecewise::PiecewiseLinear;
use serde::Serialize;

/// A face set glued to a rigid plane by the RCCM cohesive law (model §2).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Interface {
    /// Name of the face set of the mesh.
    pub faces: String,
    /// Index into `Model::moulds`.
    pub plane: usize,
    pub law: StiffnessLaw,
    /// Friction coefficient of the fully ruptured interface, μ_inf ≥ 0 (paper eq. 21).
    pub mu_inf: f64,
    /// Damage α₀ [m] at t = 0, ≥ 0: the run starts with α = min(u_r, max(α₀, |[u]₀|)), so
    /// α₀ ≥ u_r is an interface already ruptured (contact with friction μ_inf only). Damage that
    /// happened before the run is not counted as dissipated in its ledger. Default 0.
    pub initial_damage: f64,
    /// `Some(μ)`: glue that forms on contact (a `[[contact]]` entry with an adhesive law,
    /// model §8): no glue at t = 0, the face set is in contact with Coulomb friction μ; a
    /// node that comes into contact is glued from then on, anchored where it touched, with
    /// intact glue (α = 0), and follows this law like any glued node (rupture leaves contact
    /// with μ_inf; a ruptured node is never glued again). `None`: glued from t = 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub forms_on_contact: Option<f64>,
}

/// Two face sets of the body joined node to node by a cohesive law (model §7.8): each node of
/// `faces` is paired with the node of `to` at the same reference position; the pair's jump is
/// [u] = x_faces − x_to and its normal n the outward normal of `to` in the reference
/// configuration (it does not turn with the body).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bond {
    pub faces: String,
    pub to: String,
    pub law: StiffnessLaw,
    /// Friction coefficient of the fully ruptured bond, μ_inf ≥ 0 (paper eq. 21).
    pub mu_inf: f64,
    /// Damage α₀ [m] at t = 0, as [`Interface::initial_damage`]: ≥ u_r is a crack from the
    /// start (contact with friction μ_inf only).
    pub initial_damage: f64,
}

/// A face set in unilateral contact with Coulomb friction (constant μ) against a rigid plane,
/// without cohesion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactFaces {
    pub faces: String,
    pub plane: usize,
    /// Coulomb friction coefficient μ ≥ 0.
    pub mu: f64,
}

/// A prescribed displacement history of one component on the nodes of a face set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PrescribedDisplacement {
    pub faces: String,
    /// 0 = x, 1 = y, 2 = z.
    pub component: usize,
    /// Ū(t) [m].
    pub history: PiecewiseLinear<1>,
}

/// A dead-load surface traction on a face set, per unit reference area.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Traction {
    pub faces: String,
    /// Traction vector [Pa] at amplitude 1.
    pub vector: [f64; 3],
    /// Amplitude history (dimensionless).
    pub amplitude: PiecewiseLinear<1>,
}

/// Quadrature of the hexahedra (model §1.5, §1.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integration {
    /// 2×2×2 Gauss points: exact for the trilinear element, no spurious modes.
    #[default]
    Full,
    /// One point at the centre with Flanagan–Belytschko hourglass control (stiffness form,
    /// coefficient `hourglass_coefficient`): one stress evaluation per element instead of 8,
    /// cheaper per step (docs: performance log), its accuracy measured by `decohesion tradeoff`.
    Reduced,
    /// 2×2×2 Gauss points with F̄ = (J̄/J)^{1/3} F, J̄ the element's volume ratio (model §1.11):
    /// one volumetric deformation per element, so a nearly incompressible material does not
    /// lock.
    Fbar,
    /// One point at the centre with physical hourglass stabilisation (model §1.12): the
    /// hourglass stiffness is the element's bending stiffness in E and its warping stiffness in
    /// μ, so it neither locks near incompressibility nor needs a coefficient.
    ReducedPhysical,
}

impl Integration {
    /// Whether the element's stiffness at rest is bounded by the full element's (model §6.4):
    /// the full and F-bar elements (the same at rest, §1.11) and the physically stabilised one
    /// point (on a box its hourglass stiffness is at most the full element's, §1.12; on other
    /// shapes taken as so); not the one point with Flanagan–Belytschko control, whose κ may
    /// exceed it.
    pub fn full_bound_at_rest(self) -> bool {
        self != Integration::Reduced
    }
}

/// Parameters of the CD-Lagrange scheme. Every field has its meaning, unit and range here;
/// `Default` gives the values used when a scene does not set them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SchemeParams {
    /// Time step as a fraction of the estimated critical step h_crit = 2/ω_max, in (0, 2).
    /// Default 0.5. Above 1 the scheme is unstable (and the run stops with a diagnostic).
    pub time_step_factor: f64,
    /// Re-estimate h_crit every this many steps (large strains stiffen or soften the body);
    /// 0 = only at the start. Default 500.
    pub h_crit_update_interval: usize,
    /// Relative tolerance on ω_max² of the Lanczos estimate (model §6.2). Default 1e-6.
    pub h_crit_tolerance: f64,
    /// The run is declared unstable when the mechanical energy exceeds this factor times the
    /// energy that entered the system (initial energy plus |external work|). Default 10.
    pub energy_growth_limit: f64,
    /// Quadrature of the elements. Default full (2×2×2).
    pub integration: Integration,
    /// κ of the hourglass stiffness k = κ (λ + 2μ) V Σₐ bₐ·bₐ / 8 (reduced integration only),
    /// in [0, 1]. Default 0.05; 0 leaves the hourglass modes free.
    pub hourglass_coefficient: f64,
    /// Mass scaling (model §6.8): the elements whose stable step is below a target get the
    /// density that brings it up to the target. Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass_scaling: Option<MassScaling>,
    /// Bulk viscosity (model §4.12): a viscous mean stress in each element. Default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bulk_viscosity: Option<BulkViscosity>,
}

/// Bulk viscosity (model §4.12): the viscous mean stress q = ρ L_e ε̇ (b₁ c_d − b₂² L_e min(0, ε̇))
/// of each element, ε̇ its volumetric strain rate, L_e its length, c_d the dilatational wave
/// speed: the linear term damps the ringing of the highest modes (a damping ratio b₁ in a bar's
/// highest mode), the quadratic one spreads compression shocks over a few elements. Its work is
/// a dissipation of the ledger.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BulkViscosity {
    /// b₁ [-], ≥ 0 (Abaqus/Explicit's default 0.06).
    pub linear: f64,
    /// b₂ [-], ≥ 0 (Abaqus/Explicit's default 1.2).
    pub quadratic: f64,
}

impl BulkViscosity {
    /// b₁ and b₂ when a scene's `[bulk_viscosity]` leaves them out: Abaqus/Explicit's.
    pub const DEFAULT_LINEAR: f64 = 0.06;
    pub const DEFAULT_QUADRATIC: f64 = 1.2;
}

/// Selective mass scaling of the elements below a target stable step (model §6.8): an element
/// of stable step h_e < h_t (its element bound at rest, model §6.4) has its density multiplied
/// by (h_t/h_e)², so that the bound of every element, and with it h_crit of the bulk, is at
/// least h_t. Quasi-static runs take fewer steps at the price of added inertia, whose kinetic
/// energy the ledger reports.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MassScaling {
    /// The target stable step h_t [s], > 0.
    pub target_step: f64,
    /// A warning is given when the added mass's largest kinetic energy exceeds this share of the
    /// largest elastic energy stored (bulk, hourglass and glue) [-], in (0, 1].
    pub kinetic_share: f64,
}

impl MassScaling {
    /// [`MassScaling::kinetic_share`] when a scene leaves it out.
    pub const DEFAULT_KINETIC_SHARE: f64 = 0.05;
}

impl Default for SchemeParams {
    fn default() -> Self {
        SchemeParams {
            time_step_factor: 0.5,
            h_crit_update_interval: 500,
            h_crit_tolerance: 1e-6,
            energy_growth_limit: 10.0,
            integration: Integration::Full,
            hourglass_coefficient: 0.05,
            mass_scaling: None,
            bulk_viscosity: None,
        }
    }
}

/// Everything a [`crate::solver::Simulation`] needs.
#[derive(Debug, Clone)]
pub struct Model {
    pub name: String,
    pub description: String,
    pub mesh: Mesh,
    pub material: Material,
    /// Body force per unit mass [m/s²].
    pub gravity: [f64; 3],
    /// Uniform initial velocity [m/s].
    pub initial_velocity: [f64; 3],
    /// Initial angular velocity ω₀ [rad/s] about the centre of mass X_c: the initial velocity
    /// field is V₀(X) = v₀ + ω₀ × (X − X_c), a rigid motion.
    pub initial_angular_velocity: [f64; 3],
    pub moulds: Vec<Mould>,
    pub interfaces: Vec<Interface>,
    pub contacts: Vec<ContactFaces>,
    /// Face sets of the body joined to each other (model §7.8).
    pub bonds: Vec<Bond>,
    pub displacements: Vec<PrescribedDisplacement>,
    pub tractions: Vec<Traction>,
    pub scheme: SchemeParams,
    /// Simulated duration [s].
    pub end_time: f64,
}

/// Largest distance between a glued node and its mould at t = 0 that is taken as "on the
/// mould": 1e-3 of the law's elastic range α_e (of u_r if α_e = 0), and never below the
/// round-off of positions, 16ε·(largest |coordinate|) (the gap snap of stage 2).
///
/// Why 1e-3 α_e: a node that starts at a distance δ from its anchor starts with the jump
/// [u]₀ = δn, so its glue is pre-stressed by g_N(0)δ and, for δ > α_e, pre-damaged (α₀ = δ,
/// eq. 12). At δ ≤ 1e-3 α_e the pre-stress is ≤ 0.1 % of the elastic peak traction
/// g_N(0)α_e, its stored energy ½g_N(0)δ² ≤ 1e-6 of the elastic energy at α_e, and the node is
/// a thousand times inside the elastic range: nothing a result could show. A mesh written with
/// six significant digits on a body a thousand α_e across passes it.
pub fn start_offset_tolerance(law: &StiffnessLaw, coordinate_scale: f64) -> f64 {
    let range = if law.alpha_e > 0.0 {
        law.alpha_e
    } else {
        law.u_r
    };
    (1e-3 * range).max(16.0 * f64::EPSILON * coordinate_scale)
}

/// How far the glued nodes of one interface start from their mould (reference positions):
/// the signed gap g₀ = n·(X − p) of [`mould_closest_point`], off the mould (g₀ > 0) or inside
/// it (g₀ < 0). Nodes off by more than the [`start_offset_tolerance`] start pre-stressed (and
/// pre-damaged beyond α_e); nodes inside start pushed out by their glue. A scene refuses a
/// start inside beyond the tolerance; the rest is a warning ([`crate::solver::Simulation::advisories`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StartOffset {
    /// Index of the interface, its face set and its mould.
    pub interface: usize,
    pub faces: String,
    pub mould: String,
    /// Glued nodes farther than the tolerance off the mould, and the largest such g₀ [m].
    pub off_nodes: usize,
    pub largest_off: f64,
    /// Glued nodes inside the mould by more than the round-off of positions, and the deepest
    /// such −g₀ [m].
    pub inside_nodes: usize,
    pub deepest: f64,
    /// Of those, the nodes inside by more than the tolerance (a scene refuses them).
    pub deep_nodes: usize,
    /// [`start_offset_tolerance`] of the interface's law [m].
    pub tolerance: f64,
}

impl StartOffset {
    /// The start offsets of interface `k` of `model` (`None` when its face set is unknown).
    pub fn of(model: &Model, k: usize) -> Option<StartOffset> {
        let (mesh, itf) = (&model.mesh, &model.interfaces[k]);
        if itf.forms_on_contact.is_some() {
            return None; // no glue at t = 0: the contact entry's start check applies
        }
        let plane = &model.moulds[itf.plane];
        let scale =
            (mesh.nodes.iter().flatten().chain(&plane.point)).fold(0.0f64, |a, x| a.max(x.abs()));
        let round_off = 16.0 * f64::EPSILON * scale;
        let mut out = StartOffset {
            interface: k,
            faces: itf.faces.clone(),
            mould: plane.name.clone(),
            off_nodes: 0,
            largest_off: 0.0,
            inside_nodes: 0,
            deepest: 0.0,
            deep_nodes: 0,
            tolerance: start_offset_tolerance(&itf.law, scale),
        };
        for node in mesh.face_set_nodes(mesh.face_sets.get(&itf.faces)?) {
            let x = mesh.nodes[node as usize];
            let (p, n) = mould_closest_point(plane, x);
            let g0 = dot(n, sub(x, p));
            if g0 > out.tolerance {
                out.off_nodes += 1;
                out.largest_off = out.largest_off.max(g0);
            } else if -g0 > round_off {
                out.inside_nodes += 1;
                out.deepest = out.deepest.max(-g0);
                out.deep_nodes += usize::from(-g0 > out.tolerance);
            }
        }
        Some(out)
    }

    /// True when some glued node starts off or inside its mould (worth a warning).
    pub fn any(&self) -> bool {
        self.off_nodes + self.inside_nodes > 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_linear_integral_is_exact() {
        let v = PiecewiseLinear::<1> {
            points: vec![(0.0, [0.0]), (1.0, [2.0]), (3.0, [2.0])],
        };
        assert_eq!(v.value(0.5), [1.0]);
        assert_eq!(v.integral(1.0), [1.0]);
        assert_eq!(v.integral(2.0), [3.0]);
        assert_eq!(v.integral(5.0), [9.0]);
        let late = PiecewiseLinear::<1> {
            points: vec![(1.0, [1.0]), (2.0, [3.0])],
        };
        assert_eq!(late.integral(1.0), [1.0]);
        assert_eq!(late.integral(2.0), [3.0]);
    }
}
