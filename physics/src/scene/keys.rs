//! The keys of a scene file as data: for every section of the format, each key's type, unit,
//! default, admissible values and meaning ([`SECTIONS`]), and the keys each mould shape takes
//! ([`MOULD_SHAPES`]).
//!
//! `decohesion reference scenes` renders these tables, with the law families' parameters
//! ([`crate::law::families`]) for `[interface.law]`, as the scene reference. The loader reads
//! them too: the numbers with a [`KeyDoc::range`] are checked against it (`Check::admit`), and
//! the mould shapes' keys are [`MOULD_SHAPES`]. The scene tests compare the keys of every section
//! with the fields that the serde structs of `raw.rs` accept, the defaults with what the loader
//! takes when a key is left out, and the choices with the enums they name.
//!
//! Here the key types and the keys the loader checks by name; the table of every section is
//! `keys/sections.rs`, its tests `keys/tests.rs`.

use crate::interface::family::Range;

mod sections;
pub use sections::SECTIONS;

/// What the loader takes when a scene leaves a key out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DefaultDoc {
    /// The scene must give the key.
    Required,
    /// This number.
    Number(f64),
    /// What the loader does, in words (`the file's stem`, `[0, 0, 0]`, `required for a box`).
    Text(&'static str),
}

/// One key of a section of a scene file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyDoc {
    /// The key in its section (`end_time`).
    pub key: &'static str,
    /// Another name the loader accepts for it (`mould` for `plane`), if any.
    pub alias: Option<&'static str>,
    /// The TOML type (`number`, `integer`, `string`, `[x, y, z]`, `rows [t, U]`, `table`).
    pub kind: &'static str,
    /// SI unit; `–` for a dimensionless number, empty for a key that is not a quantity.
    pub unit: &'static str,
    /// The quantity's symbol (`ν`), if a range between two numbers reads better as an
    /// inequality (`-1 < ν < 0.5`); empty otherwise.
    pub symbol: &'static str,
    pub default: DefaultDoc,
    /// Admissible values of the number (each component of an array): the loader refuses any
    /// other (`Check::admit`). `None`: any finite number, or not a number.
    pub range: Option<Range>,
    /// The admissible strings of a key that names one of a few choices (`svk`, `neo_hookean`).
    pub choices: &'static [&'static str],
    /// Further conditions, in words (appended to the range in messages and in the reference).
    pub admissible: &'static str,
    /// What the key is.
    pub description: &'static str,
}

impl KeyDoc {
    /// A required key of that type, unit and meaning, any value of the type admissible.
    pub const fn new(
        key: &'static str,
        kind: &'static str,
        unit: &'static str,
        description: &'static str,
    ) -> Self {
        KeyDoc {
            key,
            alias: None,
            kind,
            unit,
            symbol: "",
            default: DefaultDoc::Required,
            range: None,
            choices: &[],
            admissible: "",
            description,
        }
    }

    /// With another accepted name.
    pub const fn alias(self, alias: &'static str) -> Self {
        KeyDoc {
            alias: Some(alias),
            ..self
        }
    }

    /// With the quantity's symbol, for its range as an inequality.
    pub const fn symbol(self, symbol: &'static str) -> Self {
        KeyDoc { symbol, ..self }
    }

    /// Optional: `x` when left out.
    pub const fn default_number(self, x: f64) -> Self {
        KeyDoc {
            default: DefaultDoc::Number(x),
            ..self
        }
    }

    /// Optional, or required in some cases only: what happens when it is left out, in words.
    pub const fn default_text(self, text: &'static str) -> Self {
        KeyDoc {
            default: DefaultDoc::Text(text),
            ..self
        }
    }

    /// Each number in `range`.
    pub const fn range(self, range: Range) -> Self {
        KeyDoc {
            range: Some(range),
            ..self
        }
    }

    /// One of these strings.
    pub const fn choices(self, choices: &'static [&'static str]) -> Self {
        KeyDoc { choices, ..self }
    }

    /// With further conditions, in words.
    pub const fn admissible(self, admissible: &'static str) -> Self {
        KeyDoc { admissible, ..self }
    }

    /// `x` is admissible: finite and in [`KeyDoc::range`] if there is one.
    pub fn admits(&self, x: f64) -> bool {
        self.range.map_or(x.is_finite(), |r| r.contains(x))
    }

    /// The range as the reference and the messages write it: `> 0`, `in (0, 0.01]`, or with a
    /// symbol and two finite ends `-1 < ν < 0.5`.
    pub fn range_text(&self) -> Option<String> {
        let r = self.range?;
        if self.symbol.is_empty() || !(r.min.is_finite() && r.max.is_finite()) {
            return Some(r.to_string());
        }
        let sign = |open: bool| if open { "<" } else { "≤" };
        Some(format!(
            "{} {} {} {} {}",
            r.min,
            sign(r.min_open),
            self.symbol,
            sign(r.max_open),
            r.max
        ))
    }

    /// What a message says of a number outside the range: `must be > 0 s`, `must satisfy -1 < ν
    /// < 0.5 (0.5 is incompressible; above 0.49 use scheme.integration = "fbar" or
    /// "reduced_physical")`.
    pub fn must(&self) -> String {
        let mut text = match (self.range_text(), self.symbol.is_empty()) {
            (Some(r), false) if r.contains(self.symbol) => format!("must satisfy {r}"),
            (Some(r), _) => format!("must be {r}"),
            (None, _) => "must be finite".to_string(),
        };
        if !matches!(self.unit, "" | "–") {
            text.push(' ');
            text.push_str(self.unit);
        }
        if !self.admissible.is_empty() {
            text.push_str(&format!(" ({})", self.admissible));
        }
        text
    }
}

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

/// A mould shape and the keys it takes besides [`MOULD_COMMON`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeDoc {
    /// The value of `shape`.
    pub shape: &'static str,
    /// The keys this shape takes: every one is required, except `group` (a `.msh` file only)
    /// and `scale` (1 by default).
    pub keys: &'static [&'static str],
    pub description: &'static str,
}

/// The keys of `[[mould]]` that every shape takes.
pub const MOULD_COMMON: &[&str] = &["name", "shape", "pivot", "velocity", "angular_velocity"];

/// The mould shapes ([`crate::mould::Shape`]) and the keys of `[[mould]]` each one takes; the
/// loader refuses a key of another shape (`scene/mesh.rs`).
pub const MOULD_SHAPES: &[ShapeDoc] = &[
    ShapeDoc {
        shape: "half_space",
        keys: &["point", "normal"],
        description: "the half-space on the mould's side of the plane through `point` with \
                      normal `normal` (into the solid)",
    },
    ShapeDoc {
        shape: "box",
        keys: &["centre", "size"],
        description: "an axis-aligned box (at t = 0) of full edge lengths `size` about `centre`",
    },
    ShapeDoc {
        shape: "sphere",
        keys: &["centre", "radius"],
        description: "a ball of `radius` about `centre`",
    },
    ShapeDoc {
        shape: "cylinder",
        keys: &["centre", "axis", "radius", "length"],
        description: "a capped cylinder of `radius` and `length` along `axis` about `centre`",
    },
    ShapeDoc {
        shape: "surface",
        keys: &["file", "group", "scale"],
        description: "a triangulated surface read from `file` (STL, or a Gmsh `.msh` 2-D physical \
                      group `group`), times `scale`",
    },
];

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

/// `mould.size`.
pub const MOULD_SIZE: KeyDoc = KeyDoc::new(
    "size",
    XYZ,
    "m",
    "full edge lengths of a `box`, axis-aligned at t = 0",
)
.default_text("required for `box`")
.range(Range::above(0.0));

/// `mould.radius`.
pub const MOULD_RADIUS: KeyDoc = KeyDoc::new(
    "radius",
    "number",
    "m",
    "radius of a `sphere` or `cylinder`",
)
.default_text("required for `sphere`, `cylinder`")
.range(Range::above(0.0));

/// `mould.length`.
pub const MOULD_LENGTH: KeyDoc =
    KeyDoc::new("length", "number", "m", "length of a `cylinder` (capped)")
        .default_text("required for `cylinder`")
        .range(Range::above(0.0));

/// `mould.scale`.
pub const MOULD_SCALE: KeyDoc = KeyDoc::new(
    "scale",
    "number",
    "–",
    "metres per file unit of a `surface`",
)
.default_number(1.0)
.range(Range::above(0.0));

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
