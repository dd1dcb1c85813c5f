//! Hyperelastic bulk materials (model §1.3, §1.4, §1.10).
//!
//! Each constitutive model is written once, over any [`Real`] number type, in a file of its own
//! with the bound of its tangent modulus that the stable step reads ([`Law`]): the compressible
//! laws of [`compressible`] from E and ν (`svk.rs`: S and ψ from E; `neo_hookean.rs`: P and ψ
//! from F and J) and the nearly incompressible rubbers of [`rubber`] (one file per isochoric
//! family, one kernel law for all of them); `physics/build.rs` registers the files of both.
//! [`first_piola`] picks one by a [`Law`] type ([`with_law!`] turns a [`MaterialModel`] into
//! one), and everything that evaluates a stress goes through it: the pointwise
//! [`Material::piola_energy`] (post-processing and tests) and the element kernels of
//! [`crate::element`] — full 2×2×2 integration with the 8 Gauss points in the 8 lanes of an
//! [`F64x8`], one point on one element, one point on 8 elements in lanes.
//!
//! - [`real`]: the [`Real`] trait, for `f64` and [`F64x8`];
//! - `kinematics`: H = ∂U/∂X, F, J, cof F, E, P = F·S, hourglass modes, shared by the element
//!   kernels.

pub mod compressible;
pub(crate) mod kinematics;
pub mod real;
pub mod rubber;

pub(crate) use kinematics::{
    cofactor, deformation_gradient, determinant, displacement_gradient, hourglass_energy,
    hourglass_modes, row_dot,
};
pub use real::{F64x8, Lanes, Mat3, Real};

pub use crate::tunables::RUBBER_HOURGLASS_SHEAR;
pub use compressible::svk::saint_venant_kirchhoff;
pub(crate) use compressible::with_law;
pub use compressible::{neo_hookean::neo_hookean, MaterialModel, COMPRESSIBLE_KEYS};
use kinematics::id;
pub use kinematics::Deformation;
use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

impl MaterialModel {
    /// Every model: the compressible laws in the order of their files, then the rubber
    /// families in the order of [`rubber::RUBBERS`].
    pub fn all() -> impl Iterator<Item = MaterialModel> {
        (MaterialModel::COMPRESSIBLE.iter().copied()).chain(
            rubber::RubberModel::ALL
                .iter()
                .map(|&r| MaterialModel::Rubber(r)),
        )
    }

    /// The keys of every model, in the order of [`MaterialModel::all`].
    pub fn keys() -> &'static [&'static str] {
        &MODEL_KEYS
    }

    /// The model of that key.
    pub fn from_key(key: &str) -> Option<MaterialModel> {
        MaterialModel::all().find(|m| m.key() == key)
    }

    /// A rubber family's row ([`rubber::RUBBERS`]), None for a compressible law (which takes
    /// E and ν).
    pub fn rubber_spec(self) -> Option<&'static rubber::RubberSpec> {
        match self {
            MaterialModel::Rubber(r) => Some(r.spec()),
            _ => None,
        }
    }
}

/// The keys of every model (`material.model`): the compressible laws in the order of their files,
/// then the rubber families in the order of [`rubber::RUBBERS`] (so a law's or a family's file
/// adds its key here).
pub const MODEL_KEYS: [&str; COMPRESSIBLE_KEYS.len() + rubber::RUBBERS.len()] = {
    let mut keys = [""; COMPRESSIBLE_KEYS.len() + rubber::RUBBERS.len()];
    let mut i = 0;
    while i < COMPRESSIBLE_KEYS.len() {
        keys[i] = COMPRESSIBLE_KEYS[i];
        i += 1;
    }
    while i < keys.len() {
        keys[i] = rubber::RUBBERS[i - COMPRESSIBLE_KEYS.len()].key;
        i += 1;
    }
    keys
};

/// As its key (`"mooney_rivlin"`).
impl Serialize for MaterialModel {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.key())
    }
}

/// From its key, as a unit variant of an enum whose variants are [`MaterialModel::keys`] (an
/// unknown key is refused with the list of the admissible ones).
impl<'de> Deserialize<'de> for MaterialModel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Keys;
        impl Keys {
            fn model<E: serde::de::Error>(key: &str) -> Result<MaterialModel, E> {
                MaterialModel::from_key(key)
                    .ok_or_else(|| E::unknown_variant(key, MaterialModel::keys()))
            }
        }
        impl<'de> serde::de::Visitor<'de> for Keys {
            type Value = MaterialModel;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "one of {}", MaterialModel::keys().join(", "))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<MaterialModel, E> {
                Keys::model(v)
            }
            fn visit_enum<A: serde::de::EnumAccess<'de>>(
                self,
                data: A,
            ) -> Result<MaterialModel, A::Error> {
                use serde::de::VariantAccess;
                let (key, variant): (String, _) = data.variant()?;
                variant.unit_variant()?;
                Keys::model(&key)
            }
        }
        d.deserialize_enum("MaterialModel", MaterialModel::keys(), Keys)
    }
}

/// An isotropic hyperelastic material with its Lamé constants (for a rubber, those of its
/// small-strain limit).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Material {
    pub model: MaterialModel,
    /// Young's modulus E [Pa].
    pub young: f64,
    /// Poisson's ratio ν [-].
    pub poisson: f64,
    /// Reference density ρ₀ [kg/m³].
    pub density: f64,
    /// First Lamé constant λ = Eν/((1+ν)(1−2ν)) [Pa].
    pub lambda: f64,
    /// Shear modulus μ = E/(2(1+ν)) [Pa].
    pub mu: f64,
    /// The rubber's constants (model §1.10), for the rubber models only.
    pub rubber: Option<rubber::Rubber>,
}

impl Material {
    /// Derives the Lamé constants from (E, ν). Validity (E > 0, −1 < ν < ½, ρ > 0) is checked by
    /// the scene loader, which knows the keys to name.
    pub fn new(model: MaterialModel, young: f64, poisson: f64, density: f64) -> Self {
        Material {
            model,
            young,
            poisson,
            density,
            lambda: young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
            mu: young / (2.0 * (1.0 + poisson)),
            rubber: None,
        }
    }

    /// A rubber material (model §1.10) and the constants of its small-strain limit: μ = μ₀,
    /// λ = K − ⅔μ₀, E = 9Kμ₀/(3K + μ₀), ν = (3K − 2μ₀)/(2(3K + μ₀)). Validity (μ₀ > 0,
    /// K > 0, ρ > 0) is checked by the scene loader.
    pub fn rubber(r: rubber::Rubber, density: f64) -> Self {
        let model = MaterialModel::Rubber(r.iso.model());
        let (mu, k) = (r.mu0(), r.bulk);
        Material {
            model,
            young: 9.0 * k * mu / (3.0 * k + mu),
            poisson: (3.0 * k - 2.0 * mu) / (2.0 * (3.0 * k + mu)),
            density,
            lambda: k - 2.0 / 3.0 * mu,
            mu,
            rubber: Some(r),
        }
    }

    /// A material of `model` with typical constants (flop counts, tests): E = 5 MPa, ν = 0.3,
    /// ρ = 1000 kg/m³ for SVK and the compressible neo-Hookean; for a rubber, its family's
    /// material of [`rubber::examples`].
    pub fn example(model: MaterialModel) -> Self {
        rubber::examples()
            .into_iter()
            .map(|r| Material::rubber(r, 1000.0))
            .find(|m| m.model == model)
            .unwrap_or_else(|| Material::new(model, 5e6, 0.3, 1000.0))
    }

    /// The modulus M_hg of the one-point element's hourglass stiffness k = κ M_hg V Σₐ bₐ·bₐ/8
    /// (model §1.6, §1.10): λ + 2μ for SVK and the compressible neo-Hookean; for a rubber
    /// [`RUBBER_HOURGLASS_SHEAR`] μ₀, the λ + 2μ = 2μ(1 − ν)/(1 − 2ν) of a material of the
    /// same shear modulus at ν = 0.45 (the shipped scenes' SVK), so that the hourglass
    /// stiffness follows the shear modulus and not the bulk modulus, which would lock the
    /// element near incompressibility.
    pub fn hourglass_modulus(&self) -> f64 {
        match self.rubber {
            None => self.p_wave_modulus(),
            Some(r) => RUBBER_HOURGLASS_SHEAR * r.mu0(),
        }
    }

    /// P-wave (constrained) modulus M = λ + 2μ = E(1−ν)/((1+ν)(1−2ν)) [Pa].
    pub fn p_wave_modulus(&self) -> f64 {
        self.lambda + 2.0 * self.mu
    }

    /// Dilatational (P-) wave speed c_d = √(M/ρ₀) = √((λ + 2μ)/ρ₀) [m/s].
    pub fn wave_speed(&self) -> f64 {
        (self.p_wave_modulus() / self.density).sqrt()
    }

    /// First Piola–Kirchhoff stress P(F) and energy density ψ(F) at one point, from
    /// [`first_piola`] unfused, H = F − I (post-processing and tests; the time loop uses
    /// the element kernels, which call the same formulas).
    pub fn piola_energy(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, f64) {
        let h = std::array::from_fn(|i| std::array::from_fn(|j| f[(i, j)] - id(i, j)));
        let d = Deformation::of::<false>(h);
        let (p, psi) = with_law!(self.model, L => first_piola::<L, f64, true, false>(self, &d));
        (Matrix3::from_fn(|i, j| p[i][j]), psi)
    }

    /// Cauchy stress σ = J⁻¹ F S Fᵀ = J⁻¹ P Fᵀ at one point, J = det F (model §1.2) [Pa]
    /// (post-processing only; J ≤ 0 gives a meaningless or infinite σ, not a panic).
    pub fn cauchy_stress(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        let (p, _) = self.piola_energy(f);
        p * f.transpose() / f.determinant()
    }

    /// Von Mises equivalent of the Cauchy stress at one point, [`von_mises_equivalent`] of
    /// [`Material::cauchy_stress`] [Pa] (post-processing only).
    pub fn von_mises(&self, f: &Matrix3<f64>) -> f64 {
        von_mises_equivalent(&self.cauchy_stress(f))
    }
}

/// A constitutive model as a type, so that a kernel generic over it is compiled once per law
/// as straight-line code ([`with_law!`] picks the type of a [`MaterialModel`]). What a bulk
/// material declares to the kernels and to the stable step: its stress and energy density, and
/// an upper bound of its tangent modulus. One file each: [`svk`], [`compressible`] and the
/// rubbers' [`RubberLaw`] (one law for every family of [`rubber`]).
pub trait Law {
    /// First Piola–Kirchhoff stress P and energy density ψ (ψ only if `ENERGY`, else 0) at a
    /// point deformed by `d`, over any [`Real`]; multiply–adds fused when `FMA` (`d` is formed
    /// with the same `FMA`).
    fn piola<T: Real, const ENERGY: bool, const FMA: bool>(
        mat: &Material,
        d: &Deformation<T>,
    ) -> (Mat3<T>, T);

    /// Upper bound a(F) of the pointwise tangent modulus, G : A(F) : G ≤ a(F) |G|² for every G,
    /// A = ∂P/∂F, given C = FᵀF (model §6.4); +∞ where the model declares none or F is
    /// inverted. The stable step clips it at 0 (`solver::bound`).
    fn modulus_bound(mat: &Material, f: &[[f64; 3]; 3], c: &[[f64; 3]; 3]) -> f64;

    /// [`Law::modulus_bound`] for 8 deformation gradients at once (`f[i][j][lane]`, C likewise):
    /// the same arithmetic on lanes, which the compiler vectorises. A lane with a non-positive
    /// J gives +∞ and may leave the others 0: the callers take the maximum.
    fn modulus_lanes(mat: &Material, f: &Mat3<[f64; 8]>, c: &Mat3<[f64; 8]>) -> [f64; 8];
}

/// The rubber models ([`rubber`]) as one [`Law`]: one more copy of each kernel for all of
/// them, not one per family; the family is matched at run time (all the lanes of a kernel
/// share one material, so the branch is uniform). They declare no modulus bound (+∞): every
/// estimate of their stable step is a converged Lanczos estimate (model §6.4).
pub struct RubberLaw;
impl Law for RubberLaw {
    #[inline(always)]
    fn piola<T: Real, const ENERGY: bool, const FMA: bool>(
        mat: &Material,
        d: &Deformation<T>,
    ) -> (Mat3<T>, T) {
        match &mat.rubber {
            Some(r) => rubber::rubber_piola::<T, ENERGY>(r, &d.f, d.j),
            // `Material::rubber` is the one constructor of a rubber model's material.
            None => unreachable!("a rubber model's material holds its constants"),
        }
    }

    #[inline(always)]
    fn modulus_bound(_: &Material, _: &[[f64; 3]; 3], _: &[[f64; 3]; 3]) -> f64 {
        f64::INFINITY
    }

    #[inline(always)]
    fn modulus_lanes(_: &Material, _: &Mat3<[f64; 8]>, _: &Mat3<[f64; 8]>) -> [f64; 8] {
        [f64::INFINITY; 8]
    }
}

/// First Piola–Kirchhoff stress P and energy density ψ (ψ only if `ENERGY`, else 0) of the law
/// `L` at a point deformed by `d` (model §1.3, §1.4, §1.10): [`Law::piola`]. The one place every
/// evaluation of a stress goes through.
#[inline(always)]
pub fn first_piola<L: Law, T: Real, const ENERGY: bool, const FMA: bool>(
    mat: &Material,
    d: &Deformation<T>,
) -> (Mat3<T>, T) {
    L::piola::<T, ENERGY, FMA>(mat, d)
}

/// Gershgorin's bound of the largest eigenvalue of a symmetric 3×3 matrix: the largest row sum
/// of |entries|.
#[inline(always)]
pub(crate) fn gershgorin(c: &[[f64; 3]; 3]) -> f64 {
    let row = |r: &[f64; 3]| r[0].abs() + r[1].abs() + r[2].abs();
    row(&c[0]).max(row(&c[1])).max(row(&c[2]))
}

/// [`gershgorin`] of lane q of a lane matrix `m[r][s][q]`.
#[inline(always)]
pub(crate) fn gershgorin_lane(m: &Mat3<[f64; 8]>, q: usize) -> f64 {
    gershgorin(&[
        [m[0][0][q], m[0][1][q], m[0][2][q]],
        [m[1][0][q], m[1][1][q], m[1][2][q]],
        [m[2][0][q], m[2][1][q], m[2][2][q]],
    ])
}

/// Von Mises equivalent stress σ_vm = √(3/2 s:s), s = σ − ⅓ tr σ I the deviator of σ [Pa].
pub fn von_mises_equivalent(sigma: &Matrix3<f64>) -> f64 {
    let dev = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
    (1.5 * dev.component_mul(&dev).sum()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Von Mises: zero under a pure dilatation, √3 μ γ in small simple shear (to O(γ²)).
    #[test]
    fn von_mises_of_dilatation_and_shear() {
        let mat = Material::new(MaterialModel::Svk, 5e6, 0.45, 1100.0);
        assert!(mat.von_mises(&(Matrix3::identity() * 1.01)) < 1e-6 * mat.mu);
        let gamma = 1e-5;
        let mut f = Matrix3::identity();
        f[(0, 1)] = gamma;
        let expect = 3f64.sqrt() * mat.mu * gamma;
        assert!((mat.von_mises(&f) - expect).abs() < 1e-4 * expect);
    }

    /// The laws on [`F64x8`] lanes are the laws on `f64` lane by lane, to the bit (the same IEEE
    /// operations in the same order on each lane), with and without fused multiply–adds: what
    /// lets a kernel pick either form.
    #[test]
    fn laws_on_lanes_are_the_laws_per_lane() {
        fn check<L: Law, const FMA: bool>(mat: &Material) {
            let h_of = |l: usize| -> Mat3<f64> {
                let t = l as f64 + 1.0;
                std::array::from_fn(|i| {
                    std::array::from_fn(|j| 0.1 * (t * (i + 3 * j + 1) as f64).sin())
                })
            };
            let lanes = Deformation::of::<FMA>(std::array::from_fn(|i| {
                std::array::from_fn(|j| F64x8(std::array::from_fn(|l| h_of(l)[i][j])))
            }));
            let (p8, psi8) = first_piola::<L, F64x8, true, FMA>(mat, &lanes);
            for l in 0..8 {
                let d = Deformation::of::<FMA>(h_of(l));
                let (p, psi) = first_piola::<L, f64, true, FMA>(mat, &d);
                assert_eq!(
                    psi8.0[l].to_bits(),
                    psi.to_bits(),
                    "{:?} lane {l}",
                    mat.model
                );
                for i in 0..3 {
                    for j in 0..3 {
                        assert_eq!(p8[i][j].0[l].to_bits(), p[i][j].to_bits());
                    }
                }
            }
        }
        let mut materials: Vec<Material> = [MaterialModel::Svk, MaterialModel::NeoHookean]
            .map(|model| Material::new(model, 5e6, 0.45, 1100.0))
            .to_vec();
        materials.extend(
            rubber::examples()
                .into_iter()
                .map(|r| Material::rubber(r, 1100.0)),
        );
        for mat in materials {
            with_law!(mat.model, L => {
                check::<L, false>(&mat);
                check::<L, true>(&mat);
            });
        }
    }
}
