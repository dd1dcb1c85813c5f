//! The compressible bulk laws (model §1.3, §1.4), one file each, taking Young's modulus E and
//! Poisson's ratio ν: `svk.rs` (Saint-Venant–Kirchhoff), `neo_hookean.rs` (the compressible
//! neo-Hookean). A file `<name>.rs` declares a type `<Name>` implementing [`Law`] (its stress
//! and energy over f64 or lanes, its modulus bound for the stable step) and [`Compressible`]
//! (its label); `physics/build.rs` registers every file of this folder, which makes `<name>`
//! the scene key of `material.model`, a variant of [`MaterialModel`] and an arm of
//! [`with_law!`](crate::material::with_law). The nearly incompressible rubbers are
//! [`crate::material::rubber`]'s families.

use super::Law;

/// What a compressible law declares besides its [`Law`]. Its key is its file's name; its
/// parameters are `young` E, `poisson` ν and `density` ρ₀, whose Lamé constants
/// [`crate::material::Material::new`] derives.
pub trait Compressible: Law {
    /// Its name in the explorer and the docs ("Saint-Venant–Kirchhoff").
    const LABEL: &'static str;
}

/// Builds [`MaterialModel`] (the compressible laws, then `Rubber`), the keys and labels of the
/// compressible laws and `with_law!` from the `index Type => module "key"` lines that
/// `physics/build.rs` writes, one per file of this folder (after a `$` for the nested macro).
macro_rules! compressible_laws {
    ($d:tt; $($index:literal $law:ident => $module:ident $key:literal,)*) => {
        /// Constitutive model: a compressible law of [`crate::material::compressible`] (one per
        /// file, from E and ν) or a rubber family of [`crate::material::rubber`].
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum MaterialModel {
            $(
                #[doc = concat!("The law of `material/compressible/", $key, ".rs`.")]
                $law,
            )*
            /// A rubber with the isochoric/volumetric split, of one of the families of
            /// [`crate::material::rubber`].
            Rubber(crate::material::rubber::RubberModel),
        }

        /// The compressible laws' keys, in the order of their files.
        pub const COMPRESSIBLE_KEYS: &[&str] = &[$($key,)*];

        impl MaterialModel {
            /// The compressible laws, in the order of their files.
            pub const COMPRESSIBLE: &'static [MaterialModel] = &[$(MaterialModel::$law,)*];

            /// The key of the model in scene files: a compressible law's file name (`svk`), a
            /// rubber family's key (`mooney_rivlin`).
            pub fn key(self) -> &'static str {
                match self {
                    $(MaterialModel::$law => $key,)*
                    MaterialModel::Rubber(r) => r.spec().key,
                }
            }

            /// Its label ("Saint-Venant–Kirchhoff", "Mooney–Rivlin").
            pub fn label(self) -> &'static str {
                match self {
                    $(MaterialModel::$law => <$module::$law as Compressible>::LABEL,)*
                    MaterialModel::Rubber(r) => r.spec().label,
                }
            }
        }

        /// `with_law!(model, L => expr)` evaluates `expr` with the type `L` standing for the
        /// [`Law`] of `model` (a [`MaterialModel`]): the one place where a model value becomes a
        /// type.
        macro_rules! with_law {
            ($d model:expr, $d law:ident => $d body:expr) => {
                match $d model {
                    $(
                        $crate::material::MaterialModel::$law => {
                            type $d law = $crate::material::compressible::$module::$law;
                            $d body
                        }
                    )*
                    $crate::material::MaterialModel::Rubber(_) => {
                        type $d law = $crate::material::RubberLaw;
                        $d body
                    }
                }
            };
        }
        pub(crate) use with_law;
    };
}

include!(concat!(env!("OUT_DIR"), "/compressible_laws.rs"));

const _: () = assert!(
    crate::interface::laws::same_str(GENERATED_IN, env!("CARGO_MANIFEST_DIR")),
    "compressible_laws.rs was generated for another clone sharing this target directory: \
     `touch physics/build.rs` reruns the build script"
);
