//! Patch tests (model §1.5, §1.6): a homogeneous deformation U = (F − I)X of a mesh with
//! distorted elements must give the exact stress: zero force on interior nodes, and on the
//! boundary the nodal forces of the constant first Piola stress P = F·S, P and ψ being the
//! formulas of model §1.3–§1.4 written out by hand (`by_hand`) at ν = 0.45. A rigid rotation
//! gives no force and no strain energy. Both quadratures: 2×2×2 Gauss and one point with
//! hourglass control (the hourglass shape vectors are orthogonal to affine fields, so the patch
//! test holds exactly and the hourglass energy is round-off).

use crate::by_hand::{piola_energy, stress_scale};
use crate::validation::{record, Tol};
use decohesion::kernels::{assemble_internal_forces, AssemblyScratch, ElementRule, Planes};
use decohesion::material::{Material, MaterialModel};
use decohesion::mesh::Mesh;
use decohesion::team::Team;

const RULES: [ElementRule; 2] = [ElementRule::Full, ElementRule::Reduced { kappa: 0.1 }];
use nalgebra::{Matrix3, Rotation3, Vector3};

/// A 3×3×3 box whose interior nodes are moved off the grid, so no two elements share a shape.
fn distorted_mesh() -> Mesh {
    let mut m = Mesh::boxed([0.0; 3], [1.0, 1.2, 0.9], [3, 3, 3]);
    for (i, x) in m.nodes.iter_mut().enumerate() {
        let interior = (1e-9..1.0 - 1e-9).contains(&x[0])
            && (1e-9..1.2 - 1e-9).contains(&x[1])
            && (1e-9..0.9 - 1e-9).contains(&x[2]);
        if interior {
            let s = (i as f64 * 0.7).sin();
            x[0] += 0.06 * s;
            x[1] -= 0.05 * (i as f64 * 1.3).cos();
            x[2] += 0.04 * s * s;
        }
    }
    m
}

fn forces(
    mesh: &Mesh,
    mat: &Material,
    f_def: &Matrix3<f64>,
    rule: ElementRule,
) -> (Vec<[f64; 3]>, f64) {
    let classes = mesh.element_classes().unwrap();
    // Blocks of 8 elements and two threads: the team path with several blocks per colour.
    let blocks = mesh.element_blocks(8);
    let team = Team::new(2);
    let u: Vec<[f64; 3]> = mesh
        .nodes
        .iter()
        .map(|x| {
            let d = (f_def - Matrix3::identity()) * Vector3::from(*x);
            [d[0], d[1], d[2]]
        })
        .collect();
    let mut f = Planes::zeros(u.len());
    let asm = assemble_internal_forces(
        mesh,
        &classes,
        &blocks,
        mat,
        rule,
        &Planes::from_rows(&u),
        &mut f,
        true,
        Some(&team),
        &mut AssemblyScratch::default(),
        f64::INFINITY,
        // The prefetching loop (hints only; the patch test holds for it as without).
        true,
    );
    assert!((asm.min_j - f_def.determinant()).abs() < 1e-13 * f_def.abs().max().powi(3));
    // γ·(affine field) = 0: the hourglass energy is round-off, ½k(ε|u|)² per element.
    assert!(
        asm.hourglass.abs() <= 1e-20 * mat.young,
        "{rule:?}: hourglass energy {} of a homogeneous field",
        asm.hourglass
    );
    (f.to_rows(), asm.strain)
}

/// The patch test under the homogeneous deformation `f_def` (the validation report's `case`).
fn check_patch(case: &str, f_def: Matrix3<f64>) {
    let mesh = distorted_mesh();
    let volume = 1.0 * 1.2 * 0.9;
    for (model, rule) in [MaterialModel::Svk, MaterialModel::NeoHookean]
        .into_iter()
        .flat_map(|m| RULES.map(|r| (m, r)))
    {
        let mat = Material::new(model, 5e6, 0.45, 1100.0);
        let (f, psi) = forces(&mesh, &mat, &f_def, rule);
        let (p, psi_exact) = piola_energy(model, 5e6, 0.45, &f_def);
        // Round-off of P (see `stress_scale`), over 27 elements and ~64 nodes: 1e-12 of the
        // scale leaves a margin of ~10³; a formula error is 10¹⁰ times larger.
        let scale = stress_scale(5e6, 0.45, &f_def);
        let source = "patch test (exact for the trilinear element; P, ψ by hand)";
        record(
            case,
            &format!("strain energy, {model:?}, {rule:?} [J]"),
            psi_exact * volume,
            source,
            psi,
            Tol::Abs(1e-12 * scale * volume),
        );
        // Energy: ψ × volume.
        assert!(
            (psi - psi_exact * volume).abs() <= 1e-12 * scale * volume,
            "{model:?} {rule:?}: energy {psi} vs ψ V = {}",
            psi_exact * volume
        );
        // Interior nodes: Σ over the surrounding elements cancels exactly for a constant P,
        // up to the round-off of ~8 forces of size |P|·area.
        let on_boundary = |x: &[f64; 3]| {
            x[0].abs() < 1e-12
                || (x[0] - 1.0).abs() < 1e-12
                || x[1].abs() < 1e-12
                || (x[1] - 1.2).abs() < 1e-12
                || x[2].abs() < 1e-12
                || (x[2] - 0.9).abs() < 1e-12
        };
        let interior_max = (mesh.nodes.iter().zip(&f))
            .filter(|(x, _)| !on_boundary(x))
            .flat_map(|(_, fi)| fi.iter().map(|c| c.abs()))
            .fold(0.0f64, f64::max);
        record(
            case,
            &format!("largest interior nodal force, {model:?}, {rule:?} [N]"),
            0.0,
            source,
            interior_max,
            Tol::Abs(1e-12 * scale),
        );
        for (i, x) in mesh.nodes.iter().enumerate() {
            if !on_boundary(x) {
                for c in 0..3 {
                    assert!(
                        f[i][c].abs() <= 1e-12 * scale,
                        "{model:?} {rule:?}: interior node {i} force {:?}",
                        f[i]
                    );
                }
            }
        }
        // Virtual work of every homogeneous δu = G X: Σ_a f_a·(G X_a) = V P:G, i.e.
        // Σ_a f_a ⊗ X_a = V P, the whole tensor.
        let mut vp = Matrix3::zeros();
        for (x, fa) in mesh.nodes.iter().zip(&f) {
            vp += Vector3::from(*fa) * Vector3::from(*x).transpose();
        }
        record(
            case,
            &format!("largest |V⁻¹ Σ f ⊗ X − P|, {model:?}, {rule:?} [Pa]"),
            0.0,
            source,
            (vp / volume - p).abs().max(),
            Tol::Abs(1e-12 * scale),
        );
        assert!(
            (vp / volume - p).abs().max() <= 1e-12 * scale,
            "{model:?} {rule:?}: V⁻¹ Σ f ⊗ X = {} vs P by hand {p}",
            vp / volume
        );
    }
}

#[test]
fn homogeneous_stretch() {
    check_patch(
        "patch_stretch",
        Matrix3::new(1.3, 0.0, 0.0, 0.0, 0.9, 0.0, 0.0, 0.0, 1.05),
    );
}

#[test]
fn homogeneous_shear() {
    check_patch(
        "patch_shear",
        Matrix3::new(1.0, 0.4, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
    );
}

#[test]
fn homogeneous_compression_and_shear() {
    check_patch(
        "patch_compression_shear",
        Matrix3::new(0.85, 0.1, 0.0, -0.05, 0.95, 0.2, 0.0, 0.0, 0.9),
    );
}

#[test]
fn large_rotation_gives_no_stress() {
    let r = Rotation3::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::new(1.0, 2.0, -0.5)),
        1.7,
    );
    let mesh = distorted_mesh();
    for (model, rule) in [MaterialModel::Svk, MaterialModel::NeoHookean]
        .into_iter()
        .flat_map(|m| RULES.map(|r| (m, r)))
    {
        let mat = Material::new(model, 5e6, 0.45, 1100.0);
        let (f, psi) = forces(&mesh, &mat, r.matrix(), rule);
        // Objectivity: E = 0 up to round-off, so |f| ≲ 1e-15·E·area; ψ is a cancellation of
        // O(1) terms (tr C − 3 for neo-Hookean): a few ulps times E·V, hence 1e-13·E·V.
        let fmax = f.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let source = "analytic (objectivity: no stress under a rigid rotation)";
        record(
            "patch_rotation",
            &format!("largest nodal force, {model:?}, {rule:?} [N]"),
            0.0,
            source,
            fmax,
            Tol::Abs(1e-8 * mat.young * 0.1),
        );
        record(
            "patch_rotation",
            &format!("strain energy, {model:?}, {rule:?} [J]"),
            0.0,
            source,
            psi,
            Tol::Abs(1e-13 * mat.young * 1.08),
        );
        assert!(
            fmax <= 1e-8 * mat.young * 0.1,
            "{model:?} {rule:?}: max force {fmax}"
        );
        assert!(
            psi.abs() <= 1e-13 * mat.young * 1.08,
            "{model:?} {rule:?}: energy {psi}"
        );
    }
}
