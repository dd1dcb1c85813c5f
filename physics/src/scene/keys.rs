//! The keys of a scene file as data: for every section of the format, each key's type, unit,
//! default, admissible values and meaning ([`SECTIONS`]). The keys each mould shape takes are
//! declared by the shape's own file ([`crate::mould::shapes`]).
//!
//! `decohesion reference scenes` renders these tables, with the law families' parameters
//! ([`crate::law::families`]) for `[interface.law]`, as the scene reference. The loader reads
//! them too: the numbers with a [`KeyDoc::range`] are checked against it (`Check::admit`). The
//! scene tests compare the keys of every section
//! with the fields that the serde structs of `raw.rs` accept, the defaults with what the loader
//! takes when a key is left out, and the choices with the enums they name.
//!
//! Here the key types and the keys the loader checks by name; the table of every section is
//! `keys/sections.rs`, its tests `keys/tests.rs`.

use crate::interface::family::Range;
pub use crate::keydoc::{DefaultDoc, KeyDoc};

mod sections;
pub use sections::SECTIONS;

/// One section of a scene file: a table (`[material]`), an array of tables (`[[plane]]`), or
/// the top level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionDoc {
    /// The key path of the table (`mesh.face_set`); empty for the top level.
    pub path: &'static str,
    /// An array of tables (`[[plane]]`): zero or more in a scene.
    pub array: bool,
    /// `required`, `optional` or `zero or more`.
    pub presence: &'static str,
    /// What the section describes, a paragraph.
    pub about: &'static str,
    pub keys: &'static [KeyDoc],
}

impl SectionDoc {
    /// As a scene writes its header: `[mesh]`, `[[mesh.face_set]]`, `top level`.
    pub fn header(&self) -> String {
        match (self.path, self.array) {
            ("", _) => "top level".to_string(),
            (p, true) => format!("[[{p}]]"),
            (p, false) => format!("[{p}]"),
        }
    }

    /// The key of that name (or alias).
    pub fn key(&self, key: &str) -> Option<&'static KeyDoc> {
        self.keys
            .iter()
            .find(|k| k.key == key || k.alias == Some(key))
    }
}

const NONE: &str = "none";
const ZERO3: &str = "[0, 0, 0]";
const XYZ: &str = "[x, y, z]";
const FINITE3: &str = "3 finite numbers";
const HISTORY: &str = "≥ 1 row, t ≥ 0 strictly increasing";

/// `end_time`.
pub const END_TIME: KeyDoc =
    KeyDoc::new("end_time", "number", "s", "simulated duration").range(Range::above(0.0));

/// `mesh.size`.
pub const MESH_SIZE: KeyDoc =
    KeyDoc::new("size", XYZ, "m", "edge lengths of the box along x, y, z")
        .default_text("required for a box")
        .range(Range::above(0.0));

/// `mesh.cells`.
pub const MESH_CELLS: KeyDoc = KeyDoc::new(
    "cells",
    "[nx, ny, nz] integers",
    "–",
    "hexahedra along x, y, z",
)
.default_text("required for a box")
.range(Range::at_least(1.0))
.admissible("integers; their product at most 50 000 000 elements");

/// `mesh.scale`.
pub const MESH_SCALE: KeyDoc = KeyDoc::new(
    "scale",
    "number",
    "–",
    "metres per mesh unit, for a Gmsh file only (0.001 for a mesh drawn in millimetres)",
)
.default_number(1.0)
.range(Range::above(0.0));

/// `material.young`.
pub const YOUNG: KeyDoc =
    KeyDoc::new("young", "number", "Pa", "Young's modulus E").range(Range::above(0.0));

/// `material.poisson`.
pub const POISSON: KeyDoc = KeyDoc::new("poisson", "number", "–", "Poisson's ratio ν")
    .symbol("ν")
    .range(Range::between(-1.0, true, 0.5, true))
    .admissible("0.5 is incompressible; above 0.49 use scheme.integration = \"fbar\" or \"reduced_physical\"");

/// `material.density`.
pub const DENSITY: KeyDoc =
    KeyDoc::new("density", "number", "kg/m³", "reference density ρ₀").range(Range::above(0.0));

/// `scheme.time_step_factor`.
pub const TIME_STEP_FACTOR: KeyDoc = KeyDoc::new(
    "time_step_factor",
    "number",
    "–",
    "time step h as a fraction of the critical step h_crit = 2/ω_max (Lanczos estimate); h never \
     exceeds h_crit: above 1 the step is h_crit itself, with no margin (a warning says so; ≤ 0.9 \
     is safe)",
)
.default_number(0.5)
.range(Range::between(0.0, true, 2.0, true));

/// `scheme.h_crit_update_interval`.
pub const H_CRIT_UPDATE_INTERVAL: KeyDoc = KeyDoc::new(
    "h_crit_update_interval",
    "integer",
    "steps",
    "re-estimate h_crit every this many steps, and, once some element is compressed below \
     J = 0.9, at once whenever the smallest Jacobian has moved by more than 0.02 since the last \
     estimate; 0: only at the start",
)
.default_number(500.0)
.range(Range::at_least(0.0));

/// `scheme.h_crit_tolerance`.
pub const H_CRIT_TOLERANCE: KeyDoc = KeyDoc::new(
    "h_crit_tolerance",
    "number",
    "–",
    "relative tolerance on ω_max² of the Lanczos estimate of h_crit",
)
.default_number(1e-6)
.range(Range::between(0.0, true, 1e-2, false));

/// `scheme.energy_growth_limit`.
pub const ENERGY_GROWTH_LIMIT: KeyDoc = KeyDoc::new(
    "energy_growth_limit",
    "number",
    "–",
    "the run is declared unstable when the mechanical energy exceeds this factor times the \
     energy that entered the system",
)
.default_number(10.0)
.range(Range::above(1.0));

/// `scheme.hourglass_coefficient`.
pub const HOURGLASS_COEFFICIENT: KeyDoc = KeyDoc::new(
    "hourglass_coefficient",
    "number",
    "–",
    "κ of the hourglass stiffness k = κ (λ + 2μ) V Σₐ bₐ·bₐ / 8 (reduced integration only; 0 \
     leaves the hourglass modes free)",
)
.default_number(0.05)
.range(Range::between(0.0, false, 1.0, false))
.admissible("typical 0.03–0.1");

/// `mass_scaling.target_step`.
pub const MASS_SCALING_TARGET_STEP: KeyDoc = KeyDoc::new(
    "target_step",
    "number",
    "s",
    "the target stable step h_t: every element whose stable step (its element bound at rest, \
     model §6.4) is below h_t gets the density that brings it to h_t, ρ (h_t/h_e)²",
)
.symbol("h_t")
.range(Range::above(0.0))
.admissible(
    "at most the h_crit the glue's springs allow with the scaled masses (`check` prints both)",
);

/// `mass_scaling.kinetic_share`.
pub const MASS_SCALING_KINETIC_SHARE: KeyDoc = KeyDoc::new(
    "kinetic_share",
    "number",
    "–",
    "a warning is given when the added mass's largest kinetic energy exceeds this share of the \
     largest elastic energy stored (bulk, hourglass and glue)",
)
.default_number(crate::model::MassScaling::DEFAULT_KINETIC_SHARE)
.range(Range::between(0.0, true, 1.0, false));

/// `bulk_viscosity.linear`.
pub const BULK_VISCOSITY_LINEAR: KeyDoc = KeyDoc::new(
    "linear",
    "number",
    "–",
    "b₁ of the linear term ρ L_e b₁ c_d ε̇ of the viscous mean stress: the damping ratio it gives \
     a bar's highest mode",
)
.symbol("b₁")
.default_number(crate::model::BulkViscosity::DEFAULT_LINEAR)
.range(Range::between(0.0, false, 1.0, true))
.admissible("Abaqus/Explicit's default 0.06");

/// `bulk_viscosity.quadratic`.
pub const BULK_VISCOSITY_QUADRATIC: KeyDoc = KeyDoc::new(
    "quadratic",
    "number",
    "–",
    "b₂ of the quadratic term −ρ (b₂ L_e)² ε̇ min(0, ε̇) of the viscous mean stress (in \
     compression only: it spreads a shock over a few elements)",
)
.symbol("b₂")
.default_number(crate::model::BulkViscosity::DEFAULT_QUADRATIC)
.range(Range::between(0.0, false, 5.0, true))
.admissible("Abaqus/Explicit's default 1.2");

/// `interface.mu_inf`.
pub const INTERFACE_MU_INF: KeyDoc = KeyDoc::new(
    "mu_inf",
    "number",
    "–",
    "friction coefficient of the ruptured interface: μ(α) = μ_inf (1 − g_N(α)/g_N(0)) (paper \
     eq. 21)",
)
.default_number(0.0)
.range(Range::at_least(0.0));

/// `interface.initial_damage`.
pub const INITIAL_DAMAGE: KeyDoc = KeyDoc::new(
    "initial_damage",
    "number",
    "m",
    "damage α₀ at t = 0: the run starts from α = min(u_r, α₀), on the damaged branch g_N(α₀) \
     with μ(α₀); ≥ u_r is an interface ruptured from the start (contact with friction `mu_inf` \
     only). Damage done before the run is not in its ledger",
)
.default_number(0.0)
.range(Range::at_least(0.0))
.admissible("≥ u_r means ruptured from the start");

/// `contact.mu`.
pub const CONTACT_MU: KeyDoc = KeyDoc::new(
    "mu",
    "number",
    "–",
    "Coulomb friction coefficient (with a `law`: before the glue forms)",
)
.default_number(0.0)
.range(Range::at_least(0.0));

/// `contact.mu_inf`.
pub const CONTACT_MU_INF: KeyDoc = KeyDoc::new(
    "mu_inf",
    "number",
    "–",
    "friction coefficient of the torn glue (paper eq. 21); only with `[contact.law]`",
)
.default_number(0.0)
.range(Range::at_least(0.0));

/// `displacement.ramp`.
pub const RAMP: KeyDoc = KeyDoc::new(
    "ramp",
    "number",
    "s",
    "with `speed` only: the speed is reached over t_r = `ramp` in `ramp_steps` equal increments \
     (speed v k/n on the k-th of n intervals)",
)
.default_number(0.0)
.range(Range::at_least(0.0));

/// `displacement.ramp_steps`.
pub const RAMP_STEPS: KeyDoc = KeyDoc::new(
    "ramp_steps",
    "integer",
    "–",
    "with `speed` only: the number n of equal speed increments of the ramp",
)
.default_number(4.0)
.range(Range::at_least(1.0));

/// `interface.delay.tau_c` (checked by [`crate::law::Delay::new`]).
pub const TAU_C: KeyDoc = KeyDoc::new(
    "tau_c",
    "number",
    "s",
    "characteristic time: the damage rate never exceeds u_r/τ_c",
)
.range(Range::above(0.0));

/// `interface.delay.a` (checked by [`crate::law::Delay::new`]).
pub const DELAY_A: KeyDoc = KeyDoc::new(
    "a",
    "number",
    "–",
    "sharpness: the rate at a lag x is (u_r/τ_c)(1 − e^{−a x/u_r})",
)
.range(Range::above(0.0));

/// `faces` of the sections that act on a face set.
const FACES: KeyDoc = KeyDoc::new("faces", "string", "", "the face set it acts on")
    .admissible("a face set of the mesh");

/// `plane` (alias `mould`) of `[[interface]]` and `[[contact]]`.
const ON: KeyDoc = KeyDoc::new(
    "plane",
    "string",
    "",
    "the plane or mould the faces meet, by its `name`",
)
.alias("mould")
.admissible("the `name` of a `[[plane]]` or of a `[[mould]]`");

/// The section at that key path (`mesh.face_set`; `""` for the top level).
pub fn section(path: &str) -> Option<&'static SectionDoc> {
    SECTIONS.iter().find(|s| s.path == path)
}

#[cfg(test)]
mod tests;
