//! The hyperelastic laws of model §1.3–§1.4 written out by hand with nalgebra, independently of
//! `decohesion::material`: the tests compare the element kernels with them.
//!
//! E = ½(FᵀF − I), C = FᵀF, J = det F,
//! Saint-Venant–Kirchhoff: S = λ tr(E) I + 2μE, ψ = ½λ(tr E)² + μ E:E;
//! neo-Hookean: S = μ(I − C⁻¹) + λ ln J C⁻¹, ψ = ½μ(tr C − 3) − μ ln J + ½λ(ln J)²;
//! P = F S; Lamé constants λ = Eν/((1+ν)(1−2ν)), μ = E/(2(1+ν)).

#![allow(dead_code)]

use decohesion::material::MaterialModel;
use nalgebra::Matrix3;

/// (λ, μ) of Young's modulus `young` and Poisson's ratio `nu`.
pub fn lame(young: f64, nu: f64) -> (f64, f64) {
    (
        young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        young / (2.0 * (1.0 + nu)),
    )
}

/// First Piola–Kirchhoff stress P = F S and energy density ψ of `model` at F, for (E, ν).
pub fn piola_energy(
    model: MaterialModel,
    young: f64,
    nu: f64,
    f: &Matrix3<f64>,
) -> (Matrix3<f64>, f64) {
    let (lambda, mu) = lame(young, nu);
    let id = Matrix3::identity();
    let c = f.transpose() * f;
    let (s, psi) = match model {
        MaterialModel::Svk => {
            let e = (c - id) / 2.0;
            let tr = e.trace();
            let s = id * (lambda * tr) + e * (2.0 * mu);
            (s, lambda / 2.0 * tr * tr + mu * e.dot(&e))
        }
        MaterialModel::NeoHookean => {
            let ln_j = f.determinant().ln();
            let c_inv = c.try_inverse().expect("F is invertible");
            let s = (id - c_inv) * mu + c_inv * (lambda * ln_j);
            let psi = mu / 2.0 * (c.trace() - 3.0) - mu * ln_j + lambda / 2.0 * ln_j * ln_j;
            (s, psi)
        }
        rubber => panic!("{rubber:?}: the (E, ν) laws only; the rubbers' own formulas are in physics/tests/rubber.rs"),
    };
    (f * s, psi)
}

/// The size of P's round-off: entries of P are sums of O(10) products of λ, μ and up to three
/// entries of F, so either side is off by ≲ 50 ε (λ + 2μ) |F|³ ≈ 1e-14 (λ + 2μ) |F|³. A formula
/// error (a wrong Lamé constant, a missing term) is O((λ + 2μ)|E|) with |E| ≥ 1e-2 here, 10¹⁰
/// times larger; the tests allow 1e-12 of this scale.
pub fn stress_scale(young: f64, nu: f64, f: &Matrix3<f64>) -> f64 {
    let (lambda, mu) = lame(young, nu);
    (lambda + 2.0 * mu) * f.abs().max().max(1.0).powi(3)
}

/// Homogeneous deformation gradients for the tests (strains of 5–40 %, J from 0.8 to 1.5,
/// rotations included), as (name, F).
pub fn deformations() -> Vec<(&'static str, Matrix3<f64>)> {
    vec![
        (
            "stretch",
            Matrix3::new(1.3, 0.0, 0.0, 0.0, 0.9, 0.0, 0.0, 0.0, 1.05),
        ),
        (
            "shear",
            Matrix3::new(1.0, 0.4, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        ),
        (
            "compression",
            Matrix3::new(0.85, 0.0, 0.0, 0.0, 0.95, 0.0, 0.0, 0.0, 1.0),
        ),
        (
            "general",
            Matrix3::new(1.1, 0.2, -0.05, 0.03, 0.95, 0.1, 0.0, -0.12, 1.2),
        ),
        (
            "rotated",
            nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0).matrix()
                * Matrix3::new(1.2, 0.1, 0.0, 0.0, 0.95, 0.05, 0.0, 0.0, 1.1),
        ),
    ]
}
