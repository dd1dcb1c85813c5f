//! The keys of `[material]` (a part of the table of keys, [`super::keys`]) that every model
//! shares: the model, (E, ν) for Saint-Venant–Kirchhoff and the compressible neo-Hookean, a
//! rubber's bulk modulus and volumetric form, and the density. The rubber families' own
//! parameters (model §1.10) are their rows of [`crate::material::rubber::RUBBERS`].

use super::keys::{KeyDoc, DENSITY, POISSON, YOUNG};
use crate::interface::family::Range;

/// `material.bulk`.
pub const BULK: KeyDoc = KeyDoc::new(
    "bulk",
    "number",
    "Pa",
    "bulk modulus K of a rubber's volumetric energy U(J)",
)
.default_text("a rubber model takes `bulk` or `poisson`")
.range(Range::above(0.0));

/// The rows of `[material]`.
pub const MATERIAL_KEYS: &[KeyDoc] = &[
    KeyDoc::new(
        "model",
        "string",
        "",
        "constitutive model: Saint-Venant–Kirchhoff (`svk`), compressible neo-Hookean \
         (`neo_hookean`), or a nearly incompressible rubber with the isochoric/volumetric split \
         ψ = ψ_iso(C̄) + U(J) (each family's keys in the tables below)",
    )
    .default_text("\"svk\"")
    .choices(&crate::material::MODEL_KEYS),
    KeyDoc {
        default: super::keys::DefaultDoc::Text(
            "required for `svk` and `neo_hookean`; refused for a rubber",
        ),
        ..YOUNG
    },
    KeyDoc {
        default: super::keys::DefaultDoc::Text(
            "required for `svk` and `neo_hookean`; for a rubber, `bulk` or `poisson` \
             (K = 2μ₀(1 + ν)/(3(1 − 2ν)), μ₀ the initial shear modulus)",
        ),
        ..POISSON
    },
    DENSITY,
    BULK,
    KeyDoc::new(
        "volumetric",
        "string",
        "",
        "a rubber's volumetric energy: ½K(J − 1)² (`quadratic`) or ½K(ln J)² (`log`)",
    )
    .default_text("\"quadratic\"")
    .choices(&["quadratic", "log"]),
];
