//! The F-bar hexahedron (model §1.11) on the problems that lock the full element: the nearly
//! incompressible cantilever of `scenes/extreme/incompressible_beam.toml` against
//! Euler–Bernoulli, and Cook's membrane, nearly incompressible and compressible, against their
//! converged references.
//!
//! All are linear static problems (small loads) solved by explicit dynamics: the load is
//! applied at t = 0 and held, and the motion about the static state is removed by kinetic
//! damping ([`relaxed`]). Each test asserts that the kinetic energy left at the last reset is
//! below 10⁻⁶ of the strain energy, so the state is static to far better than the tolerances.

use crate::common::{bare_box, face_nodes, scene_file};
use crate::validation::{record, Tol};
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::mesh::Mesh;
use decohesion_physics::model::{Integration, PiecewiseLinear, PrescribedDisplacement, Traction};
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;

/// Dynamic relaxation by kinetic damping (Cundall): steps `sim` to its end, setting every
/// velocity to zero each time the kinetic energy has passed a peak. Each reset removes the
/// energy of the motion about the static state, so the state converges to it; returns
/// `probe` at the end and the kinetic energy at the last peak over the strain energy.
pub(crate) fn relaxed(sim: &mut Simulation, probe: impl Fn(&Simulation) -> f64) -> (f64, f64) {
    let mut last = 0.0;
    let mut peak_share = f64::INFINITY;
    while !sim.finished() {
        sim.step().unwrap();
        let e = sim.energies();
        if e.kinetic < last {
            peak_share = last / e.strain;
            for p in sim.state.v.planes_mut() {
                p.fill(0.0);
            }
            last = 0.0;
        } else {
            last = e.kinetic;
        }
    }
    (probe(sim), peak_share)
}

/// The cantilever of `incompressible_beam` (0.5 m × 0.1 m × 0.1 m, 20×2×2, clamped at x = 0,
/// under its weight) with the F-bar hexahedron at ν = 0.499 (K/G = 500) and 0.4999 (K/G = 5000):
/// the static tip sag within 5 % of Euler–Bernoulli's qL⁴/(8EI) (20.2 mm), where the full element
/// sags less than half of it (`extreme::nearly_incompressible_locking_is_reported_and_measured`).
///
/// Why 5 %: the 3-D cantilever differs from Euler–Bernoulli by its shear deflection,
/// qL²/(2κGA) with κ = 5/6, +4.8 % at ν → 0.5 (Timoshenko), and the mesh — two elements
/// through the depth — is stiffer than the continuum; locking is a factor 2 or more.
#[test]
fn fbar_cantilever_does_not_lock_near_incompressibility() {
    cantilever_within_euler_bernoulli("fbar", "fbar_cantilever");
}

/// The cantilever of `incompressible_beam` with `scheme.integration = rule` at ν = 0.499 and
/// 0.4999, relaxed to its static state: no locking warning, and the tip sag within 5 % of
/// Euler–Bernoulli's qL⁴/(8EI), recorded as validation case `case`.
pub(crate) fn cantilever_within_euler_bernoulli(rule: &str, case: &str) {
    for nu in ["0.499", "0.4999"] {
        let set: Vec<String> = vec![
            format!("scheme.integration=\"{rule}\""),
            format!("material.poisson={nu}"),
            "end_time=2.0".into(),
        ];
        let path = scene_file("extreme/incompressible_beam.toml");
        let scene = load_scene(&path, &set).unwrap();
        let mut sim = Simulation::new(scene.model).unwrap();
        assert!(
            sim.advisories()
                .iter()
                .all(|w| !w.contains("locks volumetrically")),
            "{:?}",
            sim.advisories()
        );
        let tip = face_nodes(&sim.model, "x+");
        let (s, share) = relaxed(&mut sim, |s| {
            -tip.iter().map(|&i| s.state.u.get(i)[2]).sum::<f64>() / tip.len() as f64
        });
        assert!(share < 1e-6, "not relaxed: K/Ψ = {share}");
        let m = &sim.model.material;
        let (l, b) = (0.5f64, 0.1f64);
        let q = m.density * 9.81 * b * b;
        let ei = m.young * b.powi(4) / 12.0;
        let delta = q * l.powi(4) / (8.0 * ei);
        eprintln!(
            "ν = {nu}: {rule} static sag {s:.5} m = {:.4} × Euler–Bernoulli {delta:.5} m",
            s / delta
        );
        record(
            case,
            &format!("static tip sag over Euler–Bernoulli's, ν = {nu}"),
            1.0,
            "Euler–Bernoulli qL⁴/(8EI)",
            s / delta,
            Tol::Abs(0.05),
        );
        assert!(
            (s / delta - 1.0).abs() < 0.05,
            "ν = {nu}: {rule} sags {s} m, Euler–Bernoulli {delta} m"
        );
    }
}

/// Cook's membrane: the trapezoid (0, 0), (48, 44), (48, 60), (0, 44), clamped on x = 0, a shear
/// load of total `load` per unit thickness spread over the edge x = 48; one element through a
/// slab of thickness `thickness`, in plane strain (z held on every node) or plane stress (z
/// free); `n`×`n` elements.
fn cook(
    n: usize,
    mat: Material,
    load: f64,
    thickness: f64,
    plane_strain: bool,
    rule: Integration,
) -> Simulation {
    let mut m = bare_box([1.0, 1.0, thickness], [n, n, 1], mat, 1e30);
    let map = |x: [f64; 3]| {
        let (xi, eta) = (x[0], x[1]);
        [48.0 * xi, 44.0 * xi + eta * (44.0 - 28.0 * xi), x[2]]
    };
    m.mesh = Mesh {
        nodes: m.mesh.nodes.iter().map(|&x| map(x)).collect(),
        ..m.mesh
    };
    let held = |faces: &str, component: usize| PrescribedDisplacement {
        faces: faces.into(),
        component,
        history: PiecewiseLinear {
            points: vec![(0.0, [0.0])],
        },
    };
    m.displacements = vec![held("x-", 0), held("x-", 1)];
    if plane_strain {
        m.displacements.extend([held("z-", 2), held("z+", 2)]);
    } else {
        // One node held in z against the rigid drift (the load has no z part).
        m.displacements.push(held("x-", 2));
    }
    m.tractions = vec![Traction {
        faces: "x+".into(),
        vector: [0.0, load / 16.0, 0.0],
        amplitude: PiecewiseLinear {
            points: vec![(0.0, [1.0])],
        },
    }];
    m.scheme.integration = rule;
    Simulation::new(m).unwrap()
}

/// The vertical displacement of the middle (48, 52) of Cook's loaded edge per unit load,
/// relaxed to the static state over `steps` steps: (value, K/Ψ at the last kinetic peak).
fn cook_mid_edge(mut sim: Simulation, load: f64, steps: usize) -> (f64, f64) {
    let probe: Vec<usize> = (0..sim.model.mesh.nodes.len())
        .filter(|&i| {
            let x = sim.model.mesh.nodes[i];
            (x[0] - 48.0).abs() < 1e-9 && (x[1] - 52.0).abs() < 1e-9
        })
        .collect();
    assert_eq!(probe.len(), 2);
    let end = sim.state.h * steps as f64;
    std::sync::Arc::make_mut(&mut sim.model).end_time = end;
    relaxed(&mut sim, |s| {
        probe.iter().map(|&i| s.state.u.get(i)[1]).sum::<f64>() / probe.len() as f64 / load
    })
}

/// Nearly incompressible Cook's membrane (λ = 7500, μ = 0.375, so ν = 0.49998) in plane strain
/// with the F-bar hexahedron on 16×16 elements: the vertical displacement of the middle
/// (48, 52) of the loaded edge within 2 % of 16.4326, the Richardson-extrapolated reference of
/// Krysl's FinEALE (linear elasticity). The full element on the same mesh gives 4.8, 29 % of it.
///
/// The load is 10⁻³ of the reference's so the large-strain material answers linearly (the edge
/// moves 0.016 over a height of 16: the nonlinear terms are ~10⁻³ of the answer), and the
/// displacement is divided by it. 2 %: the mesh's own error, −1.5 % measured at 16×16 (−4.6 %
/// at 8×8, −0.5 % at 32×32, converging to the reference).
#[test]
fn cook_membrane_nearly_incompressible() {
    let (lambda, mu) = (7500.0f64, 0.375f64);
    let young = mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu);
    let poisson = lambda / (2.0 * (lambda + mu));
    let mat = Material::new(MaterialModel::NeoHookean, young, poisson, 1.0);
    let load = 1e-3;
    let sim = cook(16, mat, load, 2.0, true, Integration::Fbar);
    let (v, share) = cook_mid_edge(sim, load, 300_000);
    assert!(share < 1e-6, "not relaxed: K/Ψ = {share}");
    eprintln!("Cook, ν = {poisson:.5}, 16×16 F-bar: v = {v:.4} vs 16.4326");
    record(
        "cook_membrane",
        "vertical displacement of (48, 52), ν = 0.49998, plane strain, 16×16 F-bar",
        16.4326,
        "Krysl, FinEALE (Richardson-extrapolated)",
        v,
        Tol::Rel(0.02),
    );
    assert!((v / 16.4326 - 1.0).abs() < 0.02, "v = {v}");
}

/// Compressible Cook's membrane (E = 1, ν = 1/3) in plane stress (a slab of thickness 1, z free)
/// with the F-bar hexahedron on 32×32 elements: the vertical displacement of (48, 52) within
/// 2 % of 23.96, the converged value of the literature (Cook; Simo & Rifai 1990). The 2-D
/// bilinear quadrilateral on the same meshes gives 23.43 at 16×16 and 23.82 at 32×32; F-bar
/// measured −1.6 % at 16×16, −0.5 % at 32×32. Small load as above.
#[test]
fn cook_membrane_compressible() {
    let mat = Material::new(MaterialModel::NeoHookean, 1.0, 1.0 / 3.0, 1.0);
    let load = 1e-3;
    let sim = cook(32, mat, load, 1.0, false, Integration::Fbar);
    let (v, share) = cook_mid_edge(sim, load, 30_000);
    assert!(share < 1e-6, "not relaxed: K/Ψ = {share}");
    eprintln!("Cook, ν = 1/3, plane stress, 32×32 F-bar: v = {v:.4} vs 23.96");
    record(
        "cook_membrane",
        "vertical displacement of (48, 52), ν = 1/3, plane stress, 32×32 F-bar",
        23.96,
        "Cook; Simo & Rifai 1990",
        v,
        Tol::Rel(0.02),
    );
    assert!((v / 23.96 - 1.0).abs() < 0.02, "v = {v}");
}
