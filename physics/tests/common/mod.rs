//! Models built in code for the verification tests, and the project's scene files.
#![allow(dead_code)]

use decohesion_physics::kernels::Planes;
use decohesion_physics::law::{Knots, StiffnessLaw};
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::mesh::Mesh;
use decohesion_physics::model::*;
use decohesion_physics::solver::Simulation;
use std::path::{Path, PathBuf};

/// The scene file `scenes/<name>` of the project (these tests run in `physics/`).
pub fn scene_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

/// Node indices of the face set `name`.
pub fn face_nodes(model: &Model, name: &str) -> Vec<usize> {
    model
        .mesh
        .face_set_nodes(&model.mesh.face_sets[name])
        .iter()
        .map(|&n| n as usize)
        .collect()
}

/// Centre-of-mass value Σmᵢxᵢ[c] / Σmᵢ of a nodal field's component c.
pub fn centre_of_mass(sim: &Simulation, field: &Planes, c: usize) -> f64 {
    let m: f64 = sim.setup.mass.iter().sum();
    field
        .rows()
        .zip(&sim.setup.mass)
        .map(|(x, mi)| mi * x[c])
        .sum::<f64>()
        / m
}

/// A box with no loads, no planes: the caller adds what the test needs.
/// The front of a peel or a crack along x: the largest reference x of a ruptured interface node
/// (α ≥ u_r of its interface), `from` when none is further.
pub fn ruptured_front(sim: &Simulation, from: f64) -> f64 {
    let nodes = &sim.model.mesh.nodes;
    sim.state
        .interface_nodes
        .iter()
        .filter(|itf| itf.alpha >= sim.model.interfaces[itf.interface as usize].law.u_r)
        .map(|itf| nodes[itf.node as usize][0])
        .fold(from, f64::max)
}

pub fn bare_box(size: [f64; 3], cells: [usize; 3], mat: Material, end_time: f64) -> Model {
    Model {
        name: "test".into(),
        description: String::new(),
        mesh: Mesh::boxed([0.0; 3], size, cells),
        material: mat,
        gravity: [0.0; 3],
        initial_velocity: [0.0; 3],
        initial_angular_velocity: [0.0; 3],
        moulds: vec![],
        interfaces: vec![],
        contacts: vec![],
        bonds: vec![],
        displacements: vec![],
        tractions: vec![],
        scheme: SchemeParams::default(),
        end_time,
    }
}

pub fn mould() -> Mould {
    Mould {
        name: "mould".into(),
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        velocity: None,
        ..Default::default()
    }
}

pub fn ramp(t_end: f64, u_end: f64) -> PiecewiseLinear<1> {
    PiecewiseLinear {
        points: vec![(0.0, [0.0]), (t_end, [u_end])],
    }
}

/// The reference pull-off cube of model §9 with `n` cells per side (same values as
/// scenes/pull_off.toml).
pub fn pull_off(n: usize, end_time: f64) -> Model {
    let mut m = bare_box(
        [1.0; 3],
        [n, n, n],
        Material::new(MaterialModel::Svk, 5e6, 0.45, 1100.0),
        end_time,
    );
    m.gravity = [0.0, 0.0, -9.81];
    m.moulds.push(mould());
    m.interfaces.push(Interface {
        faces: "z-".into(),
        plane: 0,
        law: pull_off_law(),
        mu_inf: 0.5,
        initial_damage: 0.0,
        forms_on_contact: None,
    });
    m.displacements.push(PrescribedDisplacement {
        faces: "z+".into(),
        component: 2,
        history: ramp(0.33, 0.33),
    });
    m
}

/// The law of the pull-off cube: plateau–linear, g_N(0) = 5e8 Pa/m, α_e = 2 mm, u_r = 4 mm.
pub fn pull_off_law() -> StiffnessLaw {
    let knots = Knots {
        g_n0: 5e8,
        alpha_e: 2e-3,
        u_r: 4e-3,
    };
    StiffnessLaw::build("plateau_linear", &knots.values()).unwrap()
}

/// A box resting on a fixed floor (the plane z = 0) through unilateral contact with Coulomb
/// friction μ on its `z-` face, no glue.
pub fn on_floor(size: [f64; 3], cells: [usize; 3], mat: Material, mu: f64, end_time: f64) -> Model {
    let mut m = bare_box(size, cells, mat, end_time);
    m.moulds.push(Mould {
        name: "floor".into(),
        ..mould()
    });
    m.contacts.push(ContactFaces {
        faces: "z-".into(),
        plane: 0,
        mu,
    });
    m
}

/// A valid scene: a 1 m cube on 2×2×2 cells, its bottom glued to the plane z = 0 (plateau–linear,
/// α_e = 0.5 mm), its top pulled up; the scene-error tests break it in one place.
pub const GLUED_CUBE: &str = r#"
end_time = 0.3

[mesh]
size = [1.0, 1.0, 1.0]
cells = [2, 2, 2]

[material]
young = 5.0e6
poisson = 0.45
density = 1100.0

[[plane]]
name = "mould"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]

[[interface]]
faces = "z-"
plane = "mould"
[interface.law]
family = "plateau_linear"
g_n0 = 2.0e9
alpha_e = 5.0e-4
u_r = 1.0e-3

[[displacement]]
faces = "z+"
component = "z"
table = [[0.0, 0.0], [0.3, 0.6]]
"#;

/// Mean of the values.
pub fn mean(v: impl IntoIterator<Item = f64>) -> f64 {
    let (s, n) = v
        .into_iter()
        .fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    s / n as f64
}

/// Least-squares slope of y against x.
pub fn slope(pts: &[(f64, f64)]) -> f64 {
    let (mx, my) = (mean(pts.iter().map(|p| p.0)), mean(pts.iter().map(|p| p.1)));
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

/// The damping ratio ξ of a damped oscillation sampled at every step, `xs`, from the
/// logarithmic decrement of its first and third positive maxima: δ = ln(x₀/x₂)/2 = 2πξ/√(1 − ξ²),
/// so ξ = δ/√(4π² + δ²). Fails when fewer than three maxima were sampled.
pub fn damping_ratio(xs: &[f64]) -> f64 {
    let peaks: Vec<f64> = (1..xs.len() - 1)
        .filter(|&i| xs[i] > xs[i - 1] && xs[i] >= xs[i + 1] && xs[i] > 0.0)
        .map(|i| xs[i])
        .collect();
    assert!(peaks.len() >= 3, "{} maxima in 4 periods", peaks.len());
    let delta = (peaks[0] / peaks[2]).ln() / 2.0;
    delta / (4.0 * std::f64::consts::PI * std::f64::consts::PI + delta * delta).sqrt()
}
