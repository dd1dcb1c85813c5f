//! Runs with the rubber materials (model §1.10) — the pull-off cube with each family, the shipped
//! `pull_off_rubber` scene — and malformed rubber input: each error names the file, the key,
//! the value and what is admissible.

use crate::common::{self, scene_file};
use crate::validation::{record, Tol};
use decohesion_physics::material::rubber::examples;
use decohesion_physics::material::Material;
use decohesion_physics::scene::{load_scene, parse_scene};
use decohesion_physics::solver::Simulation;

/// The pull-off cube of model §9 (4³ hex8) with each rubber of [`examples`] (K/μ₀ = 50),
/// scaled to the SVK cube's shear modulus (1.72 MPa) so that the glue's 1 MPa peak is reached:
/// the glue tears off entirely, damage dissipates G_c·A within the pull-off test's band (the
/// ruptures' discrete steps, O(h)), and the ledger closes within the pull-off test's 1e-3
/// (model §5.10).
#[test]
fn the_pull_off_closes_its_ledger_with_every_rubber() {
    for r in examples() {
        let mut m = common::pull_off(4, 0.33);
        m.material = Material::rubber(r.scaled(1.72e6 / r.mu0()), 1100.0);
        let mut sim = Simulation::new(m).unwrap();
        sim.run(|_| true).unwrap();
        let model = sim.model.material.model;
        assert_eq!(
            sim.state_counts().ruptured,
            sim.state.interface_nodes.len(),
            "{model:?}: not torn off"
        );
        let gc_area = sim.model.interfaces[0].law.fracture_energy();
        let d = sim.state.ledger.damage_dissipated;
        assert!(
            d >= 0.99 * gc_area && d <= 1.08 * gc_area,
            "{model:?}: damage dissipation {d} vs G_c·A {gc_area}"
        );
        let residual = sim.state.ledger.max_relative_residual;
        record(
            "ledger_pull_off_rubber",
            &format!(
                "largest relative residual of the energy balance, {}",
                model.key()
            ),
            0.0,
            "energy balance (model §5.10)",
            residual,
            Tol::Abs(1e-3),
        );
        assert!(residual < 1e-3, "{model:?}: residual {residual}");
    }
}

/// `scenes/pull_off_rubber.toml`: every glued node ruptures, damage dissipates G_c·A within the
/// pull-off test's band, the ledger closes.
#[test]
fn pull_off_rubber_scene() {
    let scene = load_scene(&scene_file("pull_off_rubber.toml"), &[]).unwrap();
    let mut sim = Simulation::new(scene.model).unwrap();
    sim.run(|_| true).unwrap();
    crate::pull_off::assert_full_rupture_dissipation(&sim, "pull_off_rubber");
    assert!(sim.state.ledger.max_relative_residual < 1e-3);
}

/// The scene's name in messages.
const FILE: &str = "scenes/rubber.toml";

/// The glued cube of the bad-input tests with its material replaced by `material`.
fn error(material: &str) -> String {
    let text = common::GLUED_CUBE.replacen(
        "[material]\nyoung = 5.0e6\npoisson = 0.45\ndensity = 1100.0",
        material,
        1,
    );
    assert_ne!(text, common::GLUED_CUBE);
    match parse_scene(&text, FILE, &[]) {
        Ok(_) => panic!("accepted:\n{material}"),
        Err(e) => e.to_string(),
    }
}

fn assert_has(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "missing {part:?} in:\n{message}");
    }
}

const MOONEY: &str =
    "[material]\nmodel = \"mooney_rivlin\"\nc10 = 0.3e6\nc01 = 0.05e6\ndensity = 1100.0";

#[test]
fn a_valid_rubber_scene_is_valid() {
    for material in [
        format!("{MOONEY}\npoisson = 0.49"),
        "[material]\nmodel = \"ogden\"\nmu = [0.63e6, 0.0012e6, -0.01e6]\nalpha = [1.3, 5.0, -2.0]\nbulk = 1e9\nvolumetric = \"log\"\ndensity = 1000.0".into(),
        "[material]\nmodel = \"yeoh\"\nc10 = 0.5e6\nc20 = -0.01e6\npoisson = 0.499\ndensity = 1000.0".into(),
        "[material]\nmodel = \"isochoric_neo_hookean\"\nc10 = 0.5e6\nbulk = 1e8\ndensity = 1000.0".into(),
    ] {
        let text = common::GLUED_CUBE.replacen(
            "[material]\nyoung = 5.0e6\npoisson = 0.45\ndensity = 1100.0",
            &material,
            1,
        );
        let scene = parse_scene(&text, FILE, &[]).unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.model.material.rubber.is_some());
    }
}

#[test]
fn rubber_poisson_one_half() {
    let e = error(&format!("{MOONEY}\npoisson = 0.5"));
    assert_has(
        &e,
        &[
            FILE,
            "key `material.poisson` = 0.5",
            "-1 < ν < 0.5",
            "K = 2μ₀(1 + ν)/(3(1 − 2ν))",
            "`bulk` K > 0",
        ],
    );
}

#[test]
fn ogden_unstable_at_rest() {
    let e = error(
        "[material]\nmodel = \"ogden\"\nmu = [0.5e6, -0.4e6]\nalpha = [1.0, 2.0]\nbulk = 1e9\ndensity = 1000.0",
    );
    assert_has(
        &e,
        &[
            FILE,
            "key `material.mu` = [500000.0, -400000.0]",
            "μ₀ = ½Σμᵢαᵢ = -150000.0 Pa",
            "must be > 0",
            "Drucker",
        ],
    );
}

#[test]
fn non_positive_bulk_modulus() {
    let e = error(&format!("{MOONEY}\nbulk = 0.0"));
    assert_has(&e, &[FILE, "key `material.bulk` = 0.0", "> 0 Pa"]);
}

#[test]
fn key_of_another_family() {
    let e = error(&format!("{MOONEY}\nbulk = 1e8\nc20 = 1.0"));
    assert_has(
        &e,
        &[
            FILE,
            "key `material.c20` = 1.0",
            "the `mooney_rivlin` model takes `c10`, `c01`, `bulk` K [Pa] or `poisson` ν",
        ],
    );
}

#[test]
fn unknown_rubber_key() {
    let e = error(&format!("{MOONEY}\nbulk = 1e8\nc11 = 1.0"));
    assert_has(&e, &[FILE, "key `material.c11`", "unknown field", "`c10`"]);
}

#[test]
fn young_for_a_rubber_and_rubber_keys_for_svk() {
    let e = error(&format!("{MOONEY}\nbulk = 1e8\nyoung = 5e6"));
    assert_has(
        &e,
        &[
            FILE,
            "key `material.young` = 5000000.0",
            "small-strain E follows",
        ],
    );
    let e = error("[material]\nyoung = 5.0e6\npoisson = 0.45\ndensity = 1100.0\nc10 = 1e5");
    assert_has(
        &e,
        &[
            FILE,
            "key `material.c10` = 100000.0",
            "the `svk` model takes `young` E [Pa], `poisson` ν",
        ],
    );
}

#[test]
fn missing_bulk_and_both_bulk_and_poisson() {
    let e = error(MOONEY);
    assert_has(&e, &[FILE, "key `material.bulk` is missing", "`poisson` ν"]);
    let e = error(&format!("{MOONEY}\nbulk = 1e8\npoisson = 0.49"));
    assert_has(&e, &[FILE, "key `material.poisson` = 0.49", "not both"]);
}

#[test]
fn ogden_pairs() {
    let e = error(
        "[material]\nmodel = \"ogden\"\nmu = [0.5e6, 0.1e6]\nalpha = [2.0]\nbulk = 1e9\ndensity = 1000.0",
    );
    assert_has(
        &e,
        &[FILE, "key `material.alpha` = [2.0]", "as many exponents"],
    );
    let e = error(
        "[material]\nmodel = \"ogden\"\nmu = [1e5, 1e5, 1e5, 1e5]\nalpha = [2.0, 2.0, 2.0, 2.0]\nbulk = 1e9\ndensity = 1000.0",
    );
    assert_has(&e, &[FILE, "key `material.mu`", "1 to 3 numbers"]);
    let e = error(
        "[material]\nmodel = \"ogden\"\nmu = [1e5]\nalpha = [0.0]\nbulk = 1e9\ndensity = 1000.0",
    );
    assert_has(&e, &[FILE, "key `material.alpha` = [0.0]", "non-zero"]);
}

/// A set unstable only at large stretch is accepted, with a warning that names the first
/// unstable stretch and the mode (model §1.10).
#[test]
fn instability_at_large_stretch_is_a_warning() {
    let text = common::GLUED_CUBE.replacen(
        "[material]\nyoung = 5.0e6\npoisson = 0.45\ndensity = 1100.0",
        "[material]\nmodel = \"mooney_rivlin\"\nc10 = 1e6\nc01 = -0.6e6\nbulk = 1e8\ndensity = 1100.0",
        1,
    );
    let scene = parse_scene(&text, FILE, &[]).unwrap();
    let sim = Simulation::new(scene.model).unwrap();
    let warnings = sim.advisories().join("\n");
    assert_has(
        &warnings,
        &[
            "Mooney–Rivlin",
            "Drucker",
            "uniaxial compression from λ = 0.",
        ],
    );
}
