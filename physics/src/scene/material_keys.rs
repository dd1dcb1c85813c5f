//! The keys of `[material]` (a part of the table of keys, [`super::keys`]): the model, (E, ν)
//! for Saint-Venant–Kirchhoff and the compressible neo-Hookean, the rubber families' parameters
//! (model §1.10; each family's own keys are in [`crate::material::rubber::RUBBERS`]) and the
//! density.

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
         ψ = ψ_iso(C̄) + U(J) (`isochoric_neo_hookean`, `mooney_rivlin`, `ogden`, `yeoh`; the \
         keys of each in the table below)",
    )
    .default_text("\"svk\"")
    .choices(&[
        "svk",
        "neo_hookean",
        "isochoric_neo_hookean",
        "mooney_rivlin",
        "ogden",
        "yeoh",
    ]),
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
    KeyDoc::new(
        "c10",
        "number",
        "Pa",
        "C₁₀, coefficient of (Ī₁ − 3) (isochoric_neo_hookean, mooney_rivlin, yeoh)",
    )
    .default_text("required for those models")
    .admissible("> 0 for isochoric_neo_hookean and yeoh; C₁₀ + C₀₁ > 0 for mooney_rivlin"),
    KeyDoc::new(
        "c01",
        "number",
        "Pa",
        "C₀₁, coefficient of (Ī₂ − 3) (mooney_rivlin)",
    )
    .default_text("required for mooney_rivlin"),
    KeyDoc::new(
        "c20",
        "number",
        "Pa",
        "C₂₀, coefficient of (Ī₁ − 3)² (yeoh)",
    )
    .default_number(0.0),
    KeyDoc::new(
        "c30",
        "number",
        "Pa",
        "C₃₀, coefficient of (Ī₁ − 3)³ (yeoh)",
    )
    .default_number(0.0),
    KeyDoc::new(
        "mu",
        "[μ₁, …] 1 to 3 numbers",
        "Pa",
        "Ogden's moduli μᵢ (ogden)",
    )
    .default_text("required for ogden")
    .admissible("μ₀ = ½Σμᵢαᵢ > 0"),
    KeyDoc::new(
        "alpha",
        "[α₁, …] 1 to 3 numbers",
        "–",
        "Ogden's exponents αᵢ, as many as μᵢ (ogden)",
    )
    .default_text("required for ogden")
    .admissible("non-zero"),
];
