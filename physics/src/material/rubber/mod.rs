//! Nearly incompressible rubber materials (model §1.10): the isochoric/volumetric split
//! ψ(F) = ψ_iso(C̄) + U(J), C̄ = J^{-2/3} C, with one file per isochoric family in `families/`
//! — [`neo_hookean`], [`mooney_rivlin`], [`yeoh`] (functions of the invariants Ī₁, Ī₂) and
//! [`ogden`] (of the principal stretches) — and the volumetric energy [`Volumetric`].
//!
//! A family is a type implementing [`Family`]: its row of [`RUBBERS`] (key, label, parameters
//! with symbol, unit and admissible range), how it is built from a scene's values, its initial
//! shear modulus μ₀, its stress and an example. `physics/build.rs` lists the files of
//! `families/` and the macro below turns the list into [`Isochoric`] (one variant per family,
//! holding its constants), [`RubberModel`] (the family without them) and [`RUBBERS`]: to add a
//! family, add `families/<key>.rs` with a type `<Key>` (CamelCase) implementing [`Family`], and
//! its test. The kernels see one law type for all of them (`material::RubberLaw`): all lanes
//! of a kernel share one material, so the `match` on the family is uniform, and the kernels are
//! not compiled once more per family. The stress is written on `f64` ([`piola_energy`]) and
//! applied lane by lane ([`Real::per_lane`]): no fused operation is written, so every build
//! gives the same bits.
//!
//! [`drucker`] checks the stability of the isochoric part over the stretches of the three
//! standard tests.

pub mod drucker;
mod eigen;

use super::real::{Mat3, Real};
use crate::interface::family::Range;
use serde::{Deserialize, Serialize};

pub use eigen::symmetric_eigen;

/// The volumetric energy U(J) (model §1.10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Volumetric {
    /// U = ½K(J − 1)², U′ = K(J − 1) (Abaqus' and LS-DYNA's default form).
    #[default]
    Quadratic,
    /// U = ½K(ln J)², U′ = K ln J / J (grows without bound as J → 0).
    Log,
}

impl Volumetric {
    /// (U(J), U′(J)) for the bulk modulus `k`.
    #[inline(always)]
    pub fn energy_slope(self, k: f64, j: f64) -> (f64, f64) {
        match self {
            Volumetric::Quadratic => {
                let d = j - 1.0;
                (0.5 * k * d * d, k * d)
            }
            Volumetric::Log => {
                let l = j.ln();
                (0.5 * k * l * l, k * l / j)
            }
        }
    }
}

/// A 3×3 matrix, rows first.
pub type Matrix = [[f64; 3]; 3];

/// The kinematics of one point that the isochoric stress reads (model §1.10): F, cof F,
/// J = det F and J^{-2/3}.
pub struct IsoPoint<'a> {
    pub f: &'a Matrix,
    pub cof: &'a Matrix,
    pub j: f64,
    pub j23: f64,
}

/// What an isochoric rubber family declares (model §1.10), one file of `families/` each.
pub trait Family: Sized + Copy {
    /// Its key (`material.model`), label, energy and parameters.
    const SPEC: RubberSpec;

    /// The family's constants from a scene's values, each checked against its range and the
    /// family's conditions (μ₀ > 0): the key, the value and what is admissible otherwise.
    fn from_values(v: &dyn RubberValues) -> Result<Self, ParamError>;

    /// The initial shear modulus μ₀ (the small-strain limit of ψ_iso) [Pa].
    fn initial_shear_modulus(&self) -> f64;

    /// Its constants as `check` prints them (`C₁₀ = 3.0000e5 Pa`).
    fn describe(&self) -> Vec<String>;

    /// (P_iso, ψ_iso) = (∂ψ_iso(C̄)/∂F, ψ_iso) at the point `x` (ψ_iso only if `ENERGY`, else
    /// 0). An invariant family calls [`invariant_stress`].
    fn piola_iso<const ENERGY: bool>(&self, x: &IsoPoint) -> (Matrix, f64);

    /// A material of the family for tests and examples, and its volumetric form (the examples
    /// take K = 50 μ₀, a filled rubber's).
    fn example() -> (Self, Volumetric);

    /// The same family with every modulus times `s` > 0: ψ_iso and P_iso times s at every F
    /// (the same stretch response, s times stiffer).
    fn scaled(&self, s: f64) -> Self;
}

/// Builds [`Isochoric`], [`RubberModel`], their dispatch and [`RUBBERS`] from the
/// `index Type => module` lines `physics/build.rs` writes, one per file of `families/`.
macro_rules! rubber_families {
    ($($index:literal $family:ident => $module:ident,)*) => {
        /// The isochoric family and its constants.
        #[derive(Debug, Clone, Copy, PartialEq, Serialize)]
        #[serde(rename_all = "snake_case")]
        pub enum Isochoric {
            $($family($module::$family),)*
        }

        /// Which rubber family, without its constants (a scene's `material.model`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum RubberModel {
            $($family,)*
        }

        /// The rubber families' rows, in the order of their files.
        pub const RUBBERS: &[RubberSpec] = &[$(<$module::$family as Family>::SPEC,)*];

        impl RubberModel {
            /// Every family, in the order of [`RUBBERS`].
            pub const ALL: &'static [RubberModel] = &[$(RubberModel::$family,)*];

            /// Its row of [`RUBBERS`].
            pub fn spec(self) -> &'static RubberSpec {
                match self {
                    $(RubberModel::$family => &RUBBERS[$index],)*
                }
            }

            /// The family's constants from a scene's values ([`Family::from_values`]).
            pub fn from_values(self, v: &dyn RubberValues) -> Result<Isochoric, ParamError> {
                match self {
                    $(RubberModel::$family => {
                        <$module::$family as Family>::from_values(v).map(Isochoric::$family)
                    })*
                }
            }

            /// The family's example material ([`Family::example`]) with K = 50 μ₀.
            pub fn example(self) -> Rubber {
                match self {
                    $(RubberModel::$family => {
                        let (m, volumetric) = <$module::$family as Family>::example();
                        Rubber {
                            bulk: 50.0 * Family::initial_shear_modulus(&m),
                            iso: Isochoric::$family(m),
                            volumetric,
                        }
                    })*
                }
            }
        }

        impl Isochoric {
            /// Its family.
            pub fn model(&self) -> RubberModel {
                match self {
                    $(Isochoric::$family(_) => RubberModel::$family,)*
                }
            }

            /// The initial shear modulus μ₀ (the small-strain limit of the family) [Pa].
            pub fn initial_shear_modulus(&self) -> f64 {
                match self {
                    $(Isochoric::$family(m) => Family::initial_shear_modulus(m),)*
                }
            }

            /// [`Family::scaled`].
            pub fn scaled(&self, s: f64) -> Isochoric {
                match self {
                    $(Isochoric::$family(m) => Isochoric::$family(Family::scaled(m, s)),)*
                }
            }

            /// Its constants as `check` prints them.
            fn describe(&self) -> Vec<String> {
                match self {
                    $(Isochoric::$family(m) => Family::describe(m),)*
                }
            }

            /// (P_iso, ψ_iso) of the family ([`Family::piola_iso`]).
            #[inline(always)]
            fn piola_iso<const ENERGY: bool>(&self, x: &IsoPoint) -> (Matrix, f64) {
                match self {
                    $(Isochoric::$family(m) => m.piola_iso::<ENERGY>(x),)*
                }
            }
        }
    };
}

include!(concat!(env!("OUT_DIR"), "/rubber_families.rs"));

const _: () = assert!(
    crate::interface::laws::same_str(GENERATED_IN, env!("CARGO_MANIFEST_DIR")),
    "rubber_families.rs was generated for another clone sharing this target directory: \
     `touch physics/build.rs` reruns the build script"
);

impl Isochoric {
    /// The family's row of [`RUBBERS`].
    pub fn spec(&self) -> &'static RubberSpec {
        self.model().spec()
    }
}

/// A rubber material: the isochoric family, the bulk modulus K and the volumetric form.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Rubber {
    pub iso: Isochoric,
    /// Bulk modulus K [Pa].
    pub bulk: f64,
    pub volumetric: Volumetric,
}

impl Rubber {
    /// The initial shear modulus μ₀ [Pa].
    pub fn mu0(&self) -> f64 {
        self.iso.initial_shear_modulus()
    }

    /// Every modulus, K included, times `s` > 0 (the same stretch response, s times stiffer).
    pub fn scaled(&self, s: f64) -> Rubber {
        Rubber {
            iso: self.iso.scaled(s),
            bulk: s * self.bulk,
            volumetric: self.volumetric,
        }
    }
}

/// As `check` prints it: `Mooney–Rivlin: C₁₀ = 3.0000e5 Pa, C₀₁ = 5.0000e4 Pa; μ₀ = …, K = …
/// (K/μ₀ = 50), U = ½K(J − 1)²`.
impl std::fmt::Display for Rubber {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let spec = self.iso.spec();
        let values = self.iso.describe();
        let u = match self.volumetric {
            Volumetric::Quadratic => "½K(J − 1)²",
            Volumetric::Log => "½K(ln J)²",
        };
        write!(
            f,
            "{}: {}; μ₀ = {:.4e} Pa, K = {:.4e} Pa (K/μ₀ = {:.0}), U = {u}",
            spec.label,
            values.join(", "),
            self.mu0(),
            self.bulk,
            self.bulk / self.mu0()
        )
    }
}

/// K from Poisson's ratio and the initial shear modulus, K = 2μ₀(1 + ν)/(3(1 − 2ν)) (the
/// small-strain relation; infinite at ν = ½).
pub fn bulk_from_poisson(mu0: f64, nu: f64) -> f64 {
    2.0 * mu0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))
}

/// One parameter of a rubber family as scene files and the reference see it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RubberParam {
    /// Key in `[material]` (`c10`).
    pub key: &'static str,
    /// Symbol in messages (`C₁₀`).
    pub symbol: &'static str,
    pub unit: &'static str,
    pub meaning: &'static str,
    /// Admissible values (each entry of a list).
    pub range: Range,
    /// A list of 1 to 3 numbers (Ogden's μᵢ, αᵢ) rather than one.
    pub list: bool,
    /// A scene may leave it out; it is then 0.
    pub optional: bool,
}

/// What a rubber family declares: its key (`material.model`), label and parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RubberSpec {
    pub key: &'static str,
    pub label: &'static str,
    /// ψ_iso and μ₀, in words and symbols.
    pub energy: &'static str,
    pub params: &'static [RubberParam],
}

/// The row of [`RUBBERS`] of that key.
pub fn rubber_spec(key: &str) -> Option<&'static RubberSpec> {
    RUBBERS.iter().find(|s| s.key == key)
}

/// The parameter of that key in the first family that declares it (a key that several
/// families take is of the same kind, number or list, in each: tested).
pub fn rubber_param(key: &str) -> Option<&'static RubberParam> {
    RUBBERS.iter().flat_map(|s| s.params).find(|p| p.key == key)
}

/// Every key of a family's parameters, each once, in the order of [`RUBBERS`].
pub fn rubber_param_keys() -> impl Iterator<Item = &'static str> {
    let all = || RUBBERS.iter().flat_map(|s| s.params);
    all()
        .enumerate()
        .filter(move |&(i, p)| all().position(|q| q.key == p.key) == Some(i))
        .map(|(_, p)| p.key)
}

/// Why a family's values are not admissible: the key, the value as shown, what is admissible.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError {
    pub key: &'static str,
    pub value: String,
    pub reason: String,
}

/// The numbers a scene gave for a family's parameters, by key (lists as given).
pub trait RubberValues {
    /// The number at `key` (None when absent).
    fn number(&self, key: &str) -> Option<f64>;
    /// The list at `key` (None when absent).
    fn list(&self, key: &str) -> Option<Vec<f64>>;
}

/// `x` at `p` checked against its range (0 when absent and optional).
pub(crate) fn admit(p: &RubberParam, x: Option<f64>, family: &str) -> Result<f64, ParamError> {
    match x {
        None if p.optional => Ok(0.0),
        None => Err(ParamError {
            key: p.key,
            value: "(missing)".into(),
            reason: format!("the `{family}` model takes {} [{}]", p.symbol, p.unit),
        }),
        Some(x) if !p.range.contains(x) => Err(ParamError {
            key: p.key,
            value: format!("{x:?}"),
            reason: format!("{} must be finite and {} ({})", p.symbol, p.range, p.unit),
        }),
        Some(x) => Ok(x),
    }
}

/// Any finite number.
pub(crate) const FINITE: Range = Range::between(f64::NEG_INFINITY, true, f64::INFINITY, true);

/// First Piola–Kirchhoff stress P and energy density ψ (ψ only if `ENERGY`, else 0) of a
/// rubber material over any [`Real`] (model §1.10): [`piola_energy`] lane by lane
/// ([`Real::per_lane`]), F and J = det F the kernel's.
#[inline(always)]
pub fn rubber_piola<T: Real, const ENERGY: bool>(r: &Rubber, f: &Mat3<T>, j: T) -> (Mat3<T>, T) {
    let x: [T; 10] = [
        f[0][0], f[0][1], f[0][2], f[1][0], f[1][1], f[1][2], f[2][0], f[2][1], f[2][2], j,
    ];
    let y = T::per_lane(x, |x| {
        let f = [[x[0], x[1], x[2]], [x[3], x[4], x[5]], [x[6], x[7], x[8]]];
        let (p, psi) = piola_energy::<ENERGY>(r, &f, x[9]);
        [
            p[0][0], p[0][1], p[0][2], p[1][0], p[1][1], p[1][2], p[2][0], p[2][1], p[2][2], psi,
        ]
    });
    (
        [[y[0], y[1], y[2]], [y[3], y[4], y[5]], [y[6], y[7], y[8]]],
        y[9],
    )
}

/// P = ∂ψ/∂F and ψ of the split ψ = ψ_iso(C̄) + U(J) at one point (model §1.10):
///
/// - invariant families (ψ_iso(Ī₁, Ī₂), ψ₁ = ∂ψ_iso/∂Ī₁, ψ₂ = ∂ψ_iso/∂Ī₂, Ī₁ = J^{-2/3} I₁,
///   Ī₂ = J^{-4/3} I₂, I₂ = ½(I₁² − tr C²)):
///   P_iso = 2ψ₁ J^{-2/3}(F − ⅓I₁F⁻ᵀ) + 2ψ₂ J^{-4/3}(I₁F − FC − ⅔I₂F⁻ᵀ);
/// - Ogden ([`ogden::Ogden::stress`]), from the principal stretches;
/// - P = P_iso + U′(J) cof F, ψ = ψ_iso + U(J), F⁻ᵀ = cof F / J.
///
/// J ≤ 0 (an inverted element) gives NaN or infinities: the caller checks J.
///
/// Never inlined: one out-of-line copy serves every kernel, ISA and lane (the kernels call it
/// lane by lane), where inlining it would compile the eigen solve and the powers into each
/// of them.
#[inline(never)]
pub fn piola_energy<const ENERGY: bool>(
    r: &Rubber,
    f: &[[f64; 3]; 3],
    j: f64,
) -> ([[f64; 3]; 3], f64) {
    let (mut p, psi_iso, cof) = isochoric_piola_energy::<ENERGY>(r, f, j);
    let (u, du) = r.volumetric.energy_slope(r.bulk, j);
    for i in 0..3 {
        for k in 0..3 {
            p[i][k] += du * cof[i][k];
        }
    }
    (p, if ENERGY { psi_iso + u } else { 0.0 })
}

/// The isochoric part of [`piola_energy`]: P_iso = ∂ψ_iso(C̄)/∂F and ψ_iso (ψ_iso only if
/// `ENERGY`, else 0), with cof F, J = det F given. The average-nodal-pressure tetrahedron
/// (model §1.13) adds its own volumetric part to it.
#[inline(always)]
pub fn isochoric_piola_energy<const ENERGY: bool>(
    r: &Rubber,
    f: &[[f64; 3]; 3],
    j: f64,
) -> ([[f64; 3]; 3], f64, [[f64; 3]; 3]) {
    let cof = super::kinematics::cofactor(f);
    let j13 = j.cbrt();
    let j23 = 1.0 / (j13 * j13);
    let x = IsoPoint {
        f,
        cof: &cof,
        j,
        j23,
    };
    let (p, psi_iso) = r.iso.piola_iso::<ENERGY>(&x);
    (p, psi_iso, cof)
}

/// The isochoric P of an invariant family, `psi(Ī₁, Ī₂)` = (ψ_iso, ψ₁, ψ₂) (formula of
/// [`piola_energy`]); returns (P_iso, ψ_iso).
#[inline(always)]
pub fn invariant_stress<const ENERGY: bool>(
    x: &IsoPoint,
    psi: impl Fn(f64, f64) -> (f64, f64, f64),
) -> (Matrix, f64) {
    let &IsoPoint { f, cof, j, j23 } = x;
    let c = right_cauchy_green(f);
    let i1 = c[0][0] + c[1][1] + c[2][2];
    let mut cc = 0.0;
    for row in &c {
        for x in row {
            cc += x * x;
        }
    }
    let i2 = 0.5 * (i1 * i1 - cc);
    let (w, w1, w2) = psi(j23 * i1, j23 * j23 * i2);
    let a = 2.0 * w1 * j23;
    let b = 2.0 * w2 * j23 * j23;
    let mut p = [[0.0; 3]; 3];
    for i in 0..3 {
        for k in 0..3 {
            let finv_t = cof[i][k] / j;
            let fc = f[i][0] * c[0][k] + f[i][1] * c[1][k] + f[i][2] * c[2][k];
            p[i][k] = a * (f[i][k] - i1 / 3.0 * finv_t)
                + b * (i1 * f[i][k] - fc - 2.0 / 3.0 * i2 * finv_t);
        }
    }
    (p, if ENERGY { w } else { 0.0 })
}

/// C = FᵀF.
#[inline(always)]
pub(crate) fn right_cauchy_green(f: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| {
        std::array::from_fn(|k| f[0][i] * f[0][k] + f[1][i] * f[1][k] + f[2][i] * f[2][k])
    })
}

/// One material of each family ([`RubberModel::example`]), with both volumetric forms among
/// them (tests and examples): K/μ₀ = 50, a filled rubber's.
pub fn examples() -> Vec<Rubber> {
    RubberModel::ALL.iter().map(|m| m.example()).collect()
}
