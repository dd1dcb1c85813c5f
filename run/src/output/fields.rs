//! Per-element fields at the element centre ξ = 0, computed from the displacement U: the
//! deformation gradient F, the volume ratio J = det F, the Cauchy stress σ = J⁻¹ F S Fᵀ and its
//! von Mises equivalent √(3/2 s:s) (model §1.2; the material's own
//! [`Material::cauchy_stress`](crate::material::Material::cauchy_stress) and
//! [`von_mises_equivalent`]). The one place the outputs compute them: the ParaView cells
//! ([`crate::vtk`]) and the colours of the recorded surface ([`crate::record`]).
//!
//! The centre values are what one-point integration uses; with full integration they are the
//! element's state at ξ = 0, not a mean of its Gauss points.

use crate::kernels::NodalField;
use crate::material::von_mises_equivalent;
use crate::model::Model;
use nalgebra::Matrix3;

/// F at the centre of element `e` ([`crate::mesh::Mesh::centre_deformation_gradient`]).
pub fn centre_gradient<U: NodalField + ?Sized>(model: &Model, e: usize, u: &U) -> Matrix3<f64> {
    let f = model.mesh.centre_deformation_gradient(e, u);
    Matrix3::from_fn(|i, j| f[i][j])
}

/// The fields of one element at its centre.
#[derive(Debug, Clone, Copy)]
pub struct CentreFields {
    /// J = det F [-].
    pub jacobian: f64,
    /// σ [Pa].
    pub cauchy: Matrix3<f64>,
    /// √(3/2 s:s) of σ [Pa].
    pub von_mises: f64,
}

/// J, σ and the von Mises stress of element `e` at its centre.
pub fn centre_fields(model: &Model, e: usize, u: &[[f64; 3]]) -> CentreFields {
    let f = centre_gradient(model, e, u);
    let cauchy = model.material.cauchy_stress(&f);
    CentreFields {
        jacobian: f.determinant(),
        cauchy,
        von_mises: von_mises_equivalent(&cauchy),
    }
}

/// A scalar element field, computed alone (J needs no stress).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scalar {
    /// J = det F [-].
    Jacobian,
    /// Von Mises stress of σ [Pa].
    VonMises,
}

/// One scalar field of element `e` at its centre: the same value as [`centre_fields`] gives.
pub fn centre_scalar<U: NodalField + ?Sized>(model: &Model, e: usize, u: &U, field: Scalar) -> f64 {
    let f = centre_gradient(model, e, u);
    match field {
        Scalar::Jacobian => f.determinant(),
        Scalar::VonMises => von_mises_equivalent(&model.material.cauchy_stress(&f)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A uniform stretch x = λ X (U = (λ − 1) X) gives F = λ I: J = λ³, and a hydrostatic σ
    /// (isotropic material), in tension, whose von Mises stress is 0 to the round-off of σ's
    /// deviator.
    #[test]
    fn uniform_stretch_is_hydrostatic() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/pull_off.toml");
        let m = crate::scene::load_scene(&path, &["mesh.cells=[2,2,2]".into()])
            .unwrap()
            .model;
        let lambda = 1.1;
        let u: Vec<[f64; 3]> = m
            .mesh
            .nodes
            .iter()
            .map(|x| x.map(|c| (lambda - 1.0) * c))
            .collect();
        for e in 0..m.mesh.elements.len() {
            let c = centre_fields(&m, e, &u);
            assert!((c.jacobian - lambda.powi(3)).abs() <= 8.0 * f64::EPSILON);
            let p = c.cauchy.trace() / 3.0;
            assert!(p > 0.0, "stretched: tension");
            assert!(c.von_mises <= 1e-9 * p, "{} vs p = {p}", c.von_mises);
            // The scalar alone is the same value, to the bit.
            let alone = |f| centre_scalar(&m, e, &u[..], f).to_bits();
            assert_eq!(alone(Scalar::Jacobian), c.jacobian.to_bits());
            assert_eq!(alone(Scalar::VonMises), c.von_mises.to_bits());
        }
    }
}
