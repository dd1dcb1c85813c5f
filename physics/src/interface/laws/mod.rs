//! The law families, one file each (model §2.6).
//!
//! `physics/build.rs` lists the files of this folder and writes the `mod` lines and one
//! `families!` line per family; the macro below turns that list into [`LawKind`] (one variant per
//! family, holding its data: g_N is one `match` away, inlined, no indirection) and [`FAMILIES`]
//! (the table). To add a family, add `<key>.rs` here with a type `<Key>` (CamelCase) that
//! implements [`Family`](super::family::Family), and its test.

use super::family::{DamageStep, Family, FamilySpec, ParamValues};
use super::law::StiffnessLaw;

/// Builds [`LawKind`], its dispatch and [`FAMILIES`] from `index Type => module` lines.
macro_rules! families {
    ($($index:literal $family:ident => $module:ident,)*) => {
        /// Which family a law is, with the family's own data (model §2.6).
        #[derive(Debug, Clone, PartialEq)]
        pub enum LawKind {
            $($family($module::$family),)*
        }

        $(impl From<$module::$family> for LawKind {
            fn from(law: $module::$family) -> Self {
                LawKind::$family(law)
            }
        })*

        impl LawKind {
            /// The family's row of [`FAMILIES`].
            pub fn spec(&self) -> &'static FamilySpec {
                match self {
                    $(LawKind::$family(_) => &FAMILIES[$index],)*
                }
            }

            /// [`Family::softening`] of the family.
            #[inline]
            pub(crate) fn softening(&self, law: &StiffnessLaw, alpha: f64) -> f64 {
                match self {
                    $(LawKind::$family(f) => f.softening(law, alpha),)*
                }
            }

            /// [`Family::values`] of the family.
            pub(crate) fn values(&self, law: &StiffnessLaw) -> ParamValues {
                match self {
                    $(LawKind::$family(f) => f.values(law),)*
                }
            }

            /// [`Family::fracture_energy`] of the family.
            pub(crate) fn fracture_energy(&self, law: &StiffnessLaw) -> f64 {
                match self {
                    $(LawKind::$family(f) => f.fracture_energy(law),)*
                }
            }

            /// [`Family::next_damage`] of the family.
            #[inline]
            pub(crate) fn next_damage(&self, law: &StiffnessLaw, s: DamageStep, a_s: &mut f64) -> f64 {
                match self {
                    $(LawKind::$family(k) => k.next_damage(law, s, a_s),)*
                }
            }

            /// [`Family::damage_opening`] of the family.
            #[inline]
            pub(crate) fn damage_opening(&self, law: &StiffnessLaw, f: f64, shear: f64) -> f64 {
                match self {
                    $(LawKind::$family(k) => k.damage_opening(law, f, shear),)*
                }
            }

            /// [`Family::refuses_delay`] of the family.
            pub(crate) fn refuses_delay(&self) -> Option<&'static str> {
                match self {
                    $(LawKind::$family(f) => f.refuses_delay(),)*
                }
            }

            /// [`Family::peak_candidates`] of the family.
            pub(crate) fn peak_candidates(&self, law: &StiffnessLaw, consider: &mut dyn FnMut(f64)) {
                match self {
                    $(LawKind::$family(f) => f.peak_candidates(law, consider),)*
                }
            }
        }

        /// The table of law families, in the order of their keys (= file names).
        pub static FAMILIES: &[FamilySpec] = &[$(FamilySpec::of::<$module::$family>(),)*];

        /// The files the table was generated from (`plateau_linear.rs`, …), for the test that
        /// none of the folder's files is left out.
        pub const FILES: &[&str] = &[$(concat!(stringify!($module), ".rs"),)*];
    };
}

include!(concat!(env!("OUT_DIR"), "/law_families.rs"));

/// Byte-wise equality of two strings, at compile time (the generated registries' check that
/// they were generated for this clone, here and in the root crate's outputs).
pub const fn same_str(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

const _: () = assert!(
    same_str(GENERATED_IN, env!("CARGO_MANIFEST_DIR")),
    "law_families.rs was generated for another clone sharing this target directory: \
     `touch physics/build.rs` reruns the build script"
);
