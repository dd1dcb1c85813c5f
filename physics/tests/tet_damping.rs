//! Mass scaling and bulk viscosity on tetrahedra and on meshes mixing them with hexahedra
//! (model §1.13, §4.12, §5.11, §6.8): the scaled mesh's h_crit against the target, the ledger
//! with the added mass and with the viscous work, and the viscosity's dissipation.

use crate::common::{bare_box, damping_ratio, pull_off, scene_file};
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::mesh::Mesh;
use decohesion_physics::model::BulkViscosity;
use decohesion_physics::model::{MassScaling, Model};
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;

/// The model of `scene` with the overrides `set`, its mesh replaced by `mesh(its mesh)`.
fn model(scene: &str, set: &[&str], mesh: impl Fn(&Mesh) -> Mesh) -> Model {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let scene = load_scene(&scene_file(scene), &set).unwrap_or_else(|e| panic!("{e}"));
    let mut m = (*scene.model).clone();
    m.mesh = mesh(&m.mesh);
    m
}

/// The same body with the hexahedra whose centre is above `z_cut` cut into Kuhn's 6
/// tetrahedra each ([`Mesh::kuhn_tets`]), the others kept: a mesh of both kinds sharing the
/// nodes of the cut (a quadrilateral face against two triangles). The face sets are kept as
/// they are (the tests' face sets lie in the hexahedral part).
fn tets_above(m: &Mesh, z_cut: f64) -> Mesh {
    let all = m.kuhn_tets();
    let mut out = m.clone();
    out.elements.clear();
    out.tets.clear();
    for (e, conn) in m.elements.iter().enumerate() {
        let z = conn.iter().map(|&n| m.nodes[n as usize][2]).sum::<f64>() / 8.0;
        if z < z_cut {
            out.elements.push(*conn);
        } else {
            out.tets.extend_from_slice(&all.tets[6 * e..6 * e + 6]);
        }
    }
    out
}

/// Irons' bound is a real bound on tetrahedra: each tetrahedron's density is raised to make its
/// element bound h_e = 2/√(a₀ g_e), g_e = (4/ρ) λ_max(Σₐ ∇ₓNₐ ⊗ ∇ₓNₐ) (model §1.13, §6.8) reach
/// the target, and the scaled mesh's Lanczos h_crit is then at or above the target, within the
/// estimate's tolerance (1e-6 on ω², as the hexahedral tests in `mass_scaling.rs`).
///
/// Two meshes: the impact's column (no glue) cut into 720 Kuhn tetrahedra (SVK, ν = 0) with
/// a target 3 h_crit, which scales every tetrahedron, and the Gmsh mesh of
/// `scenes/rubber_peel.toml` (a graded strip of 2045 tetrahedra, its glue left out) with a
/// target 20 % above its smallest element step, which scales some of its tetrahedra only, and
/// one of 1.5 times its unscaled h_crit: in an SVK of ν = 0.45 and in the scene's nearly incompressible rubber (average nodal pressure
/// and nodal share, model §1.13–§1.14, whose tangent the element bound with a₀ = 3λ + 2μ
/// bounds too, loosely: the nodal averages soften the volumetric modes).
#[test]
fn scaled_tetrahedra_have_h_crit_at_or_above_the_target() {
    let kuhn = |m: &Mesh| m.kuhn_tets();
    let plain = Simulation::new(model("impact.toml", &[], kuhn)).unwrap();
    let target = 3.0 * plain.state.h_crit;
    let set = format!("mass_scaling.target_step={target:e}");
    let scaled = Simulation::new(model("impact.toml", &[&set], kuhn)).unwrap();
    let r = scaled.setup.mass_scaling.expect("mass scaling is on");
    eprintln!(
        "Kuhn column: {} of {} tetrahedra scaled, largest factor {:.3}, added {:.3} of the mass; \
         h_crit {:.6e} s (plain {:.6e} s) for a target {target:.6e} s, element step {:.6e} s",
        r.scaled_elements,
        r.elements,
        r.largest_factor,
        r.added_share(),
        scaled.state.h_crit,
        plain.state.h_crit,
        r.smallest_element_step
    );
    assert_eq!(r.elements, scaled.model.mesh.tets.len());
    assert_eq!(r.scaled_elements, r.elements);
    let mass: f64 = plain.setup.mass.iter().sum();
    assert!((r.mass / mass - 1.0).abs() <= 1e-12);
    assert!(r.added_mass > 0.0 && r.added_share() <= r.largest_factor - 1.0 + 1e-12);
    assert!(
        scaled.state.h_crit >= target * (1.0 - 1e-6),
        "h_crit {:.9e} s below the target {target:.9e} s",
        scaled.state.h_crit
    );

    let gmsh = |m: &Mesh| m.clone();
    let svk = "material={model=\"svk\",young=5.0e6,poisson=0.45,density=1100.0}";
    for (name, material) in [("SVK", Some(svk)), ("rubber", None)] {
        let mut set = vec!["interface=[]", "mass_scaling.target_step=1e-12"];
        set.extend(material);
        let probe = Simulation::new(model("rubber_peel.toml", &set, gmsh)).unwrap();
        let r0 = probe.setup.mass_scaling.unwrap();
        assert_eq!(r0.scaled_elements, 0);
        // A target 20 % above the smallest element step scales a few tetrahedra only; one of
        // 1.5 times the unscaled h_crit is above what the mesh allows, so the scaled h_crit
        // against it is the bound's test.
        for target in [1.2 * r0.smallest_element_step, 1.5 * probe.state.h_crit] {
            let ms = format!("mass_scaling.target_step={target:e}");
            let mut with = set.clone();
            with[1] = &ms;
            let scaled = Simulation::new(model("rubber_peel.toml", &with, gmsh)).unwrap();
            let r = scaled.setup.mass_scaling.unwrap();
            eprintln!(
                "Gmsh strip, {name}: {} of {} tetrahedra scaled, added {:.4} of the mass; \
                 h_crit {:.6e} s (plain {:.6e} s, smallest element step {:.6e} s) for a \
                 target {target:.6e} s",
                r.scaled_elements,
                r.elements,
                r.added_share(),
                scaled.state.h_crit,
                probe.state.h_crit,
                r0.smallest_element_step
            );
            assert!(r.scaled_elements > 0 && r.added_mass > 0.0);
            if target < probe.state.h_crit {
                assert!(
                    r.scaled_elements < r.elements,
                    "{name}: {} of {} tetrahedra scaled",
                    r.scaled_elements,
                    r.elements
                );
            }
            assert!(
                scaled.state.h_crit >= target * (1.0 - 1e-6),
                "{name}: h_crit {:.9e} s below the target {target:.9e} s",
                scaled.state.h_crit
            );
        }
    }
}

/// The breathing mode of one free regular tetrahedron, x = ε (X − X_c), is an eigenmode of its
/// stiffness and of its viscous forces (∇ₓNₐ ∝ Xₐ − X_c), at the top of the element bound:
/// with Σₐ ∇ₓNₐ ⊗ ∇ₓNₐ = 4/(3h²) I (h the altitude), ω² = a₀ g_e = (3λ + 2μ)/ρ for the
/// corners (±1, ±1, ±1) of alternate parity (h = 4/√3 m). L_e = c_d h_e with h_e = 2/ω, so,
/// as for the cube (`bulk_viscosity.rs`), the mode is one damped oscillator of damping ratio
/// ξ = b₁ (λ + 2μ)/K (model §4.12): 1.615 b₁ at ν = 0.3. The logarithmic decrement of the
/// successive maxima gives it back, δ = 2πξ/√(1 − ξ²), within 1 % (the cube test's tolerance:
/// 150 steps a period leave central differences' O((ωh)²) errors and the sampled maxima at
/// 2e-4; strains of 1e-7 keep SVK linear to 1e-7). The ledger closes (1e-4, the cube's) with
/// the viscous dissipation.
#[test]
fn a_breathing_tetrahedron_decays_with_the_damping_ratio_of_the_model() {
    let (young, nu, rho): (f64, f64, f64) = (5.0e6, 0.3, 1000.0);
    let lambda = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = young / (2.0 * (1.0 + nu));
    let k = lambda + 2.0 * mu / 3.0;
    let omega = (3.0 * k / rho).sqrt();
    let b1 = 0.02;
    let xi = b1 * (lambda + 2.0 * mu) / k;
    let period = 2.0 * std::f64::consts::PI / omega;
    let mat = Material::new(MaterialModel::Svk, young, nu, rho);
    let mut m = bare_box([1.0; 3], [1, 1, 1], mat, 4.0 * period);
    m.mesh = Mesh {
        nodes: vec![
            [1.0, 1.0, 1.0],
            [-1.0, -1.0, 1.0],
            [-1.0, 1.0, -1.0],
            [1.0, -1.0, -1.0],
        ],
        elements: vec![],
        tets: vec![[0, 1, 2, 3]],
        face_sets: Default::default(),
    };
    m.scheme.time_step_factor = 0.02;
    m.scheme.h_crit_update_interval = 0;
    m.scheme.bulk_viscosity = Some(BulkViscosity {
        linear: b1,
        quadratic: 0.0,
    });
    let rate = 1e-7 * omega;
    let v0 = m.mesh.nodes.iter().map(|x| x.map(|c| rate * c)).collect();
    let mut sim = Simulation::with_initial_state(m, vec![[0.0; 3]; 4], v0).unwrap();
    assert!(
        (sim.state.h_crit * omega / 2.0 - 1.0).abs() < 1e-5,
        "h_crit {:.9e} s, 2/ω {:.9e} s",
        sim.state.h_crit,
        2.0 / omega
    );
    // Node 0 at (1, 1, 1) moves along its position in the mode.
    let mut xs = vec![];
    while !sim.finished() {
        sim.step().unwrap();
        xs.push(sim.state.u.get(0)[0]);
    }
    let measured = damping_ratio(&xs);
    eprintln!(
        "breathing tetrahedron: damping ratio {measured:.6}, model {xi:.6}, residual {:.2e}",
        sim.state.ledger.max_relative_residual
    );
    assert!(
        (measured / xi - 1.0).abs() <= 0.01,
        "damping ratio {measured:.5}, model {xi:.5} (b₁ (λ + 2μ)/K)"
    );
    assert!(sim.energies().bulk_viscous_dissipated > 0.0);
    assert!(
        sim.state.ledger.max_relative_residual <= 1e-4,
        "residual {:.2e}",
        sim.state.ledger.max_relative_residual
    );
}

/// The pull-off cube cut into 162 tetrahedra with every tetrahedron's density raised (a target
/// of 4 h_crit): the added mass is part of M, so the ledger closes to the scheme's O(h²) as
/// without scaling (model §5.10): halving the step divides the largest relative residual by
/// about 4 (3 to 5 allowed, as the hexahedral test in `mass_scaling.rs`). The added mass's
/// kinetic energy reported, ½ Σ Δmₐ|Vₐ|², is recomputed from the masses of the scaled and the
/// unscaled set-ups (Δmₐ their difference) and the half-step velocities, to round-off (1e-12
/// of the half-step kinetic energy).
#[test]
fn the_ledger_closes_on_scaled_tetrahedra() {
    let cube = |end: f64| {
        let mut m = pull_off(3, end);
        m.mesh = m.mesh.kuhn_tets();
        m
    };
    let plain = Simulation::new(cube(0.33)).unwrap();
    let target = 4.0 * plain.state.h_crit;
    let mut residuals = vec![];
    for factor in [0.5, 0.25] {
        let mut m = cube(0.33);
        m.scheme.time_step_factor = factor;
        m.scheme.mass_scaling = Some(MassScaling {
            target_step: target,
            kinetic_share: 0.05,
        });
        let mut sim = Simulation::new(m).unwrap();
        let r = sim.setup.mass_scaling.unwrap();
        assert_eq!(r.scaled_elements, r.elements);
        let added: Vec<f64> = (sim.setup.mass.iter().zip(&plain.setup.mass))
            .map(|(m, m0)| m - m0)
            .collect();
        let mut worst = 0.0f64;
        while !sim.finished() {
            sim.step().unwrap();
            let expected: f64 = (0..added.len())
                .map(|i| {
                    let v = sim.state.v.get(i);
                    0.5 * added[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                })
                .sum();
            let got = sim.state.ledger.added_mass_kinetic;
            worst =
                worst.max((got - expected).abs() / sim.state.kinetic_half.max(f64::MIN_POSITIVE));
        }
        eprintln!(
            "tetrahedral pull-off, factor {factor}: residual {:.3e}, {} steps, K_add peak {:.3e} J, \
             K_add error {worst:.1e}",
            sim.state.ledger.max_relative_residual,
            sim.state.step_count,
            sim.setup.mass_scaling.unwrap().added_kinetic_peak
        );
        assert!(worst <= 1e-12, "K_add against ½ Σ Δm |V|²: {worst:.2e}");
        assert!(sim.energies().added_mass_kinetic > 0.0);
        residuals.push(sim.state.ledger.max_relative_residual);
    }
    let order = residuals[0] / residuals[1];
    assert!(
        (3.0..=5.0).contains(&order),
        "residuals {residuals:?}: halving h divided it by {order:.2}"
    );
}

/// The impact's column (scenes/impact.toml, to 70 ms: the landing at 63.9 ms and the
/// compression wave's round trip of 1.9 ms) cut into tetrahedra, with Abaqus/Explicit's bulk
/// viscosity (b₁ = 0.06, b₂ = 1.2): the viscous stress dissipates (D_bv > 0) and the ledger closes to the hexahedral
/// impact's bound (5e-5, `bulk_viscosity.rs`): the viscous impulses are booked by the same
/// trapezoid as every other force (model §5.11). With b₁ = b₂ = 0 the viscous stress is zero:
/// no dissipation, and the run is the run without `[bulk_viscosity]` to the last bit (the
/// forces add zeros, and the step's cap √(1 + ξ²) − ξ is 1).
#[test]
fn tet_bulk_viscosity_dissipates_and_the_ledger_closes() {
    let kuhn = |m: &Mesh| m.kuhn_tets();
    let run = |set: &[&str]| {
        let mut all = vec!["end_time=0.07"];
        all.extend_from_slice(set);
        let mut sim = Simulation::new(model("impact.toml", &all, kuhn)).unwrap();
        sim.run(|_| true).unwrap();
        sim
    };
    let viscous = run(&["bulk_viscosity.linear=0.06"]);
    let e = viscous.energies();
    eprintln!(
        "tetrahedral impact with bulk viscosity: D_bv = {:.4e} J of E_k at landing ~{:.4e} J, \
         residual {:.3e}, {} steps",
        e.bulk_viscous_dissipated,
        0.5 * viscous.setup.mass.iter().sum::<f64>() * 0.626f64.powi(2),
        viscous.state.ledger.max_relative_residual,
        viscous.state.step_count
    );
    assert!(e.bulk_viscous_dissipated > 0.0);
    assert!(
        viscous.state.ledger.max_relative_residual <= 5e-5,
        "max relative residual {:.3e}",
        viscous.state.ledger.max_relative_residual
    );
    let off = run(&["bulk_viscosity.linear=0.0", "bulk_viscosity.quadratic=0.0"]);
    let plain = run(&[]);
    assert_eq!(off.energies().bulk_viscous_dissipated, 0.0);
    assert_eq!(off.state.step_count, plain.state.step_count);
    assert_eq!(off.state.u.to_rows(), plain.state.u.to_rows());
    assert_eq!(off.state.v.to_rows(), plain.state.v.to_rows());
}

/// A mesh of both kinds runs with both features: the impact's column with its upper half cut
/// into tetrahedra (60 hexahedra, 360 tetrahedra), bulk viscosity on and a target step of
/// 2 h_crit. Both kinds are scaled (the report counts 420 elements, all below the target), the
/// scaled h_crit is at or above the target (Irons' bound over elements of both kinds, within
/// the estimate's 1e-6), the viscous stress dissipates, and the ledger closes to the impact's
/// bound (5e-5).
#[test]
fn a_mixed_mesh_runs_with_mass_scaling_and_bulk_viscosity() {
    let mixed = |m: &Mesh| tets_above(m, 0.17);
    let set = ["end_time=0.07"];
    let plain = Simulation::new(model("impact.toml", &set, mixed)).unwrap();
    assert!(!plain.model.mesh.elements.is_empty() && !plain.model.mesh.tets.is_empty());
    let target = 2.0 * plain.state.h_crit;
    let ms = format!("mass_scaling.target_step={target:e}");
    let mut sim = Simulation::new(model(
        "impact.toml",
        &[set[0], &ms, "bulk_viscosity.linear=0.06"],
        mixed,
    ))
    .unwrap();
    let r = sim.setup.mass_scaling.unwrap();
    let mesh = &sim.model.mesh;
    assert_eq!(r.elements, mesh.elements.len() + mesh.tets.len());
    assert_eq!(r.scaled_elements, r.elements);
    assert!(
        sim.state.h_crit >= target * (1.0 - 1e-6),
        "h_crit {:.9e} s below the target {target:.9e} s",
        sim.state.h_crit
    );
    sim.run(|_| true).unwrap();
    let e = sim.energies();
    eprintln!(
        "mixed impact: {} hexahedra, {} tetrahedra, h_crit {:.4e} s for a target {target:.4e} s, \
         D_bv = {:.4e} J, residual {:.3e}, {} steps",
        sim.model.mesh.elements.len(),
        sim.model.mesh.tets.len(),
        sim.stats.h_crit_initial,
        e.bulk_viscous_dissipated,
        sim.state.ledger.max_relative_residual,
        sim.state.step_count
    );
    assert!(e.bulk_viscous_dissipated > 0.0);
    assert!(
        sim.state.ledger.max_relative_residual <= 5e-5,
        "max relative residual {:.3e}",
        sim.state.ledger.max_relative_residual
    );
}
