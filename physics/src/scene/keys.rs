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

use crate::interface::family::Range;

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
    /// < 0.5 (0.5 is incompressible; use 0.49 at most)`.
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
    .admissible("0.5 is incompressible; use 0.49 at most");

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

/// The sections of a scene file, in the order of the format.
pub const SECTIONS: &[SectionDoc] = &[
    SectionDoc {
        path: "",
        array: false,
        presence: "required",
        about: "All quantities are SI. Unknown keys are errors (a misspelt key is never silently \
                ignored), and so are numbers that are not finite (`inf`, `nan`) anywhere in the \
                file; integers are accepted where a real number is expected. A plane's or \
                mould's normal points into the solid; the interface damage α is in metres.",
        keys: &[
            KeyDoc::new(
                "name",
                "string",
                "",
                "name of the run (its outputs are named after it)",
            )
            .default_text("the file's stem"),
            KeyDoc::new("description", "string", "", "free text").default_text("\"\""),
            END_TIME,
            KeyDoc::new("gravity", XYZ, "m/s²", "body force per unit mass")
                .default_text(ZERO3)
                .admissible(FINITE3),
            KeyDoc::new(
                "initial_velocity",
                XYZ,
                "m/s",
                "uniform initial velocity v₀",
            )
            .default_text(ZERO3)
            .admissible(FINITE3),
            KeyDoc::new(
                "initial_angular_velocity",
                XYZ,
                "rad/s",
                "ω₀ of a rigid initial spin about the centre of mass: V₀(X) = v₀ + ω₀ × (X − X_c)",
            )
            .default_text(ZERO3)
            .admissible(FINITE3),
            KeyDoc::new("mesh", "table", "", "the body: `[mesh]`"),
            KeyDoc::new("material", "table", "", "the body's material: `[material]`"),
            KeyDoc::new(
                "scheme",
                "table",
                "",
                "the time-stepping scheme: `[scheme]`",
            )
            .default_text("every key at its default"),
            KeyDoc::new("plane", "array of tables", "", "rigid planes: `[[plane]]`")
                .default_text(NONE),
            KeyDoc::new(
                "mould",
                "array of tables",
                "",
                "rigid moulds of any shape: `[[mould]]`",
            )
            .default_text(NONE),
            KeyDoc::new(
                "interface",
                "array of tables",
                "",
                "face sets glued to a plane or mould: `[[interface]]`",
            )
            .default_text(NONE),
            KeyDoc::new(
                "contact",
                "array of tables",
                "",
                "face sets in contact with a plane or mould, or glued on contact: `[[contact]]`",
            )
            .default_text(NONE),
            KeyDoc::new(
                "displacement",
                "array of tables",
                "",
                "prescribed displacements: `[[displacement]]`",
            )
            .default_text(NONE),
            KeyDoc::new(
                "traction",
                "array of tables",
                "",
                "dead loads on face sets: `[[traction]]`",
            )
            .default_text(NONE),
        ],
    },
    SectionDoc {
        path: "mesh",
        array: false,
        presence: "required",
        about: "The body, in one of two forms: a box (`size` and `cells`, optional `origin`) or \
                a Gmsh file (`file`, optional `scale`); keys of both forms, or `scale` with a \
                box, are refused. A box is a structured block [origin, origin + size] of \
                hexahedra whose face sets are `x-`, `x+`, `y-`, `y+`, `z-`, `z+` (the faces at \
                the low / high end of each axis). A Gmsh file is a `.msh` 4.1 mesh (ASCII or \
                binary) of 8-node hexahedra with det J₀ > 0; its face sets are its physical \
                groups of dimension 2 (`physical_<tag>` for a group without a name), of 4-node \
                quadrangles on the boundary of the hexahedra.",
        keys: &[
            KeyDoc::new("origin", XYZ, "m", "lowest corner of a box")
                .default_text(ZERO3)
                .admissible("a box only"),
            MESH_SIZE,
            MESH_CELLS,
            KeyDoc::new(
                "file",
                "string",
                "",
                "path of a Gmsh `.msh` 4.1 file, relative to the scene file's directory",
            )
            .default_text("required for a Gmsh mesh")
            .admissible("a `.msh` 4.1 file of 8-node hexahedra"),
            MESH_SCALE,
            KeyDoc::new(
                "face_set",
                "array of tables",
                "",
                "face sets selected by a box: `[[mesh.face_set]]`",
            )
            .default_text(NONE),
        ],
    },
    SectionDoc {
        path: "mesh.face_set",
        array: true,
        presence: "zero or more",
        about: "The faces of the face set `of` whose centre (the mean of their four nodes) lies \
                in the box `min` ≤ x ≤ `max` (each component, bounds included) become the face \
                set `name`, usable wherever a face set is named (either mesh form).",
        keys: &[
            KeyDoc::new("name", "string", "", "name of the new face set")
                .admissible("not the name of a face set yet"),
            KeyDoc::new("of", "string", "", "the face set to select from").admissible(
                "a face set of the mesh, or one selected by an earlier `[[mesh.face_set]]`",
            ),
            KeyDoc::new("min", XYZ, "m", "low corner of the box")
                .admissible("`min` ≤ `max` in each component"),
            KeyDoc::new("max", XYZ, "m", "high corner of the box")
                .admissible("at least one face's centre in the box"),
        ],
    },
    SectionDoc {
        path: "material",
        array: false,
        presence: "required",
        about: "The body's isotropic hyperelastic material: Saint-Venant–Kirchhoff or the \
                compressible neo-Hookean from E and ν, or a nearly incompressible rubber \
                (model §1.10) from its family's parameters and its bulk modulus K (`bulk`, or \
                `poisson` ν through the initial shear modulus μ₀). Each rubber is checked for \
                Drucker stability over stretches 0.1 to 10 in uniaxial, equibiaxial and planar \
                tension: an unstable set at rest (μ₀ ≤ 0) is refused, an instability further out \
                is a warning that names the first unstable stretch and the mode.",
        keys: super::material_keys::MATERIAL_KEYS,
    },
    SectionDoc {
        path: "scheme",
        array: false,
        presence: "optional",
        about: "The CD-Lagrange scheme's parameters; a key left out takes its default.",
        keys: &[
            TIME_STEP_FACTOR,
            H_CRIT_UPDATE_INTERVAL,
            H_CRIT_TOLERANCE,
            ENERGY_GROWTH_LIMIT,
            KeyDoc::new(
                "integration",
                "string",
                "",
                "quadrature: 2×2×2 Gauss points (`full`), or one point with Flanagan–Belytschko \
                 hourglass control (`reduced`; the hourglass energy is a ledger term)",
            )
            .default_text("\"full\"")
            .choices(&["full", "reduced"]),
            HOURGLASS_COEFFICIENT,
        ],
    },
    SectionDoc {
        path: "plane",
        array: true,
        presence: "zero or more",
        about: "A rigid plane: points x with n·(x − p(t)) > 0 are on the solid's side. \
                `[[interface]]` and `[[contact]]` name it by `plane`; plane and mould names \
                share one namespace.",
        keys: &[
            KeyDoc::new(
                "name",
                "string",
                "",
                "referred to by interfaces and contacts",
            )
            .admissible("unique among planes and moulds"),
            KeyDoc::new("point", XYZ, "m", "a point of the plane at t = 0").admissible(FINITE3),
            KeyDoc::new(
                "normal",
                XYZ,
                "–",
                "normal into the solid; normalised on load",
            )
            .admissible("not all zero"),
            KeyDoc::new(
                "velocity",
                "rows [t, vx, vy, vz]",
                "s, m/s",
                "velocity history, linear between rows, constant before the first and after the \
                 last row",
            )
            .default_text("none (fixed)")
            .admissible(HISTORY),
        ],
    },
    SectionDoc {
        path: "mould",
        array: true,
        presence: "zero or more",
        about: "A rigid mould of any shape (the shapes and their keys are listed below). \
                `[[interface]]` and `[[contact]]` name it by `plane` (or `mould`, the same key); \
                plane and mould names share one namespace. A key of another shape is refused, \
                naming the keys the shape takes.",
        keys: &[
            KeyDoc::new(
                "name",
                "string",
                "",
                "referred to by interfaces and contacts",
            )
            .admissible("unique among planes and moulds"),
            KeyDoc::new(
                "shape",
                "string",
                "",
                "the mould's shape (table of shapes below)",
            )
            .choices(&["half_space", "box", "sphere", "cylinder", "surface"]),
            KeyDoc::new(
                "point",
                XYZ,
                "m",
                "a point of a `half_space`'s plane at t = 0",
            )
            .default_text("required for `half_space`"),
            KeyDoc::new(
                "normal",
                XYZ,
                "–",
                "normal of a `half_space`, into the solid; normalised on load",
            )
            .default_text("required for `half_space`")
            .admissible("not all zero"),
            KeyDoc::new("centre", XYZ, "m", "centre at t = 0")
                .default_text("required for `box`, `sphere`, `cylinder`"),
            MOULD_SIZE,
            MOULD_RADIUS,
            KeyDoc::new("axis", XYZ, "–", "axis of a `cylinder`; normalised on load")
                .default_text("required for `cylinder`")
                .admissible("not all zero"),
            MOULD_LENGTH,
            KeyDoc::new(
                "file",
                "string",
                "",
                "a `surface`'s triangles: an STL (ASCII or binary) or a Gmsh `.msh`, relative to \
                 the scene file's directory",
            )
            .default_text("required for `surface`")
            .admissible(
                "triangles counter-clockwise seen from the solid (out of the mould), \
                 consistent, not degenerate",
            ),
            KeyDoc::new(
                "group",
                "string",
                "",
                "the 2-D physical group (triangles or quadrangles) of a `.msh` `surface`",
            )
            .default_text("required for a `.msh` file; refused for an STL")
            .admissible("a 2-D physical group of the file"),
            MOULD_SCALE,
            KeyDoc::new(
                "pivot",
                XYZ,
                "m",
                "the point the angular velocity turns about at t = 0 (it moves with `velocity`)",
            )
            .default_text(
                "`point` (half_space), `centre` (box, sphere, cylinder), the origin (surface)",
            ),
            KeyDoc::new(
                "velocity",
                "rows [t, vx, vy, vz]",
                "s, m/s",
                "velocity history of the pivot, piecewise linear",
            )
            .default_text("none (fixed)")
            .admissible(HISTORY),
            KeyDoc::new(
                "angular_velocity",
                "rows [t, ωx, ωy, ωz]",
                "s, rad/s",
                "angular velocity history about the pivot, piecewise linear",
            )
            .default_text("none (no rotation)")
            .admissible("as `velocity`; not every row zero"),
        ],
    },
    SectionDoc {
        path: "interface",
        array: true,
        presence: "zero or more",
        about: "A face set glued to a plane or mould by a cohesive law (PHYSICS.md §3): \
                damageable adhesion, unilateral contact, friction growing with damage up to \
                `mu_inf` once ruptured. A glued face's outward normal must point into the mould, \
                and its nodes must not start inside it. A face set meets a given plane through \
                at most one `[[interface]]` or `[[contact]]` (an interface already gives contact \
                and friction after rupture).",
        keys: &[
            FACES,
            ON,
            INTERFACE_MU_INF,
            INITIAL_DAMAGE,
            KeyDoc::new(
                "law",
                "table",
                "",
                "the stiffness law g_N(α): `[interface.law]`",
            ),
            KeyDoc::new("delay", "table", "", "delayed damage: `[interface.delay]`")
                .default_text("none (rate-independent)"),
        ],
    },
    SectionDoc {
        path: "interface.law",
        array: false,
        presence: "required",
        about: "g_N(α) is the normal stiffness per unit area as a function of the damage α; it is \
                non-increasing, equal to g_N(0) up to α_e and 0 from u_r on (`rccm`: C_N β², which \
                only tends to 0; its u_r marks the ruptured state). `family` names the law; the \
                other keys are the family's parameters (tables below), and a key that the family \
                does not take is refused. `[contact.law]` takes the same keys.",
        keys: &[KeyDoc::new("family", "string", "", "the law family")
            .admissible("the key of a family below")],
    },
    SectionDoc {
        path: "interface.delay",
        array: false,
        presence: "optional",
        about: "Delayed damage on a g_N(α) family (a family with its own rate effect refuses \
                it): α̇ = (u_r/τ_c)(1 − exp(−a⟨α_s − α⟩₊/u_r)), α_s the rate-independent damage \
                of eq. 12. `[contact.delay]` takes the same keys.",
        keys: &[TAU_C, DELAY_A],
    },
    SectionDoc {
        path: "contact",
        array: true,
        presence: "zero or more",
        about: "Unilateral contact with Coulomb friction against a plane or mould, without \
                cohesion; or, with a `[contact.law]` table, glue that forms on contact: no glue \
                at t = 0, a node that comes into contact is glued there with intact glue, and \
                from then on behaves as a glued node of an `[[interface]]` with that law; a torn \
                node is never glued again. No node of the face set may start inside the mould.",
        keys: &[
            FACES,
            ON,
            CONTACT_MU,
            KeyDoc::new(
                "law",
                "table",
                "",
                "glue that forms on contact: the keys of `[interface.law]`, any family",
            )
            .default_text("none (contact only)"),
            CONTACT_MU_INF,
            KeyDoc::new(
                "delay",
                "table",
                "",
                "delayed damage of the glue: the keys of `[interface.delay]`; only with \
                 `[contact.law]`",
            )
            .default_text("none (rate-independent)"),
        ],
    },
    SectionDoc {
        path: "displacement",
        array: true,
        presence: "zero or more",
        about: "A prescribed displacement of one component on the nodes of a face set, as a \
                table U(t) or a constant speed (exactly one of `table` and `speed`).",
        keys: &[
            FACES,
            KeyDoc::new(
                "component",
                "string",
                "",
                "the displacement component prescribed",
            )
            .choices(&["x", "y", "z"]),
            KeyDoc::new(
                "table",
                "rows [t, U]",
                "s, m",
                "U(t), linear between rows, constant outside",
            )
            .default_text("`table` or `speed`")
            .admissible(HISTORY),
            KeyDoc::new(
                "speed",
                "number",
                "m/s",
                "a constant pull speed v: U = U(t_r) + v (t − t_r) after the ramp (one scalar, so \
                 `decohesion sweep --vary displacement.speed=…` sweeps it)",
            )
            .default_text("`table` or `speed`"),
            RAMP,
            RAMP_STEPS,
        ],
    },
    SectionDoc {
        path: "traction",
        array: true,
        presence: "zero or more",
        about: "A dead load per unit reference area on a face set: `vector` × amplitude(t).",
        keys: &[
            FACES,
            KeyDoc::new("vector", XYZ, "Pa", "the traction at amplitude 1").admissible(FINITE3),
            KeyDoc::new(
                "amplitude",
                "rows [t, factor]",
                "s, –",
                "amplitude history, linear between rows, constant outside",
            )
            .default_text("constant 1")
            .admissible(HISTORY),
        ],
    },
];

/// The section at that key path (`mesh.face_set`; `""` for the top level).
pub fn section(path: &str) -> Option<&'static SectionDoc> {
    SECTIONS.iter().find(|s| s.path == path)
}

#[cfg(test)]
mod tests {
    //! The table against the loader: the keys against the serde structs' fields, the choices
    //! against the enums, the defaults against what a scene that leaves the keys out gets.

    use super::super::raw::{
        Axis, RawContact, RawDelay, RawDisplacement, RawFaceSet, RawInterface, RawLaw, RawMaterial,
        RawMesh, RawMould, RawPlane, RawScene, RawScheme, RawTraction,
    };
    use super::*;
    use crate::law::Delay;
    use crate::material::MaterialModel;
    use crate::model::{Integration, SchemeParams};
    use crate::scene::parse_scene;
    use serde::de::{self, DeserializeOwned, Visitor};
    use std::fmt;

    /// The error that ends an introspection.
    #[derive(Debug)]
    struct Stop;

    impl fmt::Display for Stop {
        fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("introspection")
        }
    }

    impl std::error::Error for Stop {}

    impl de::Error for Stop {
        fn custom<T: fmt::Display>(_: T) -> Self {
            Stop
        }
    }

    /// A deserializer that only records the names a derived `Deserialize` asks for: a struct's
    /// fields (with their aliases) or an enum's variants (as renamed).
    struct Names<'a>(&'a mut Option<&'static [&'static str]>);

    impl<'de> de::Deserializer<'de> for Names<'_> {
        type Error = Stop;

        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Stop> {
            Err(Stop)
        }

        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Stop> {
            *self.0 = Some(fields);
            Err(Stop)
        }

        fn deserialize_enum<V: Visitor<'de>>(
            self,
            _: &'static str,
            variants: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Stop> {
            *self.0 = Some(variants);
            Err(Stop)
        }

        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
            option unit unit_struct newtype_struct seq tuple tuple_struct map identifier
            ignored_any
        }
    }

    /// The field names (aliases included) or variant names that `T` deserializes; `None` for
    /// a type that asks for neither (a struct with a flattened field asks for a map).
    fn names<T: DeserializeOwned>() -> Option<Vec<&'static str>> {
        let mut seen = None;
        let _ = T::deserialize(Names(&mut seen));
        seen.map(|names| {
            let mut names = names.to_vec();
            names.sort_unstable();
            names
        })
    }

    /// The keys of a section, aliases included, sorted.
    fn documented(path: &str) -> Vec<&'static str> {
        let section = section(path).unwrap_or_else(|| panic!("no section `{path}`"));
        let mut keys: Vec<&str> = (section.keys.iter())
            .flat_map(|k| std::iter::once(k.key).chain(k.alias))
            .collect();
        keys.sort_unstable();
        keys
    }

    /// Every key the loader accepts has its row, and every row is a key the loader accepts: a
    /// field added to a struct of `raw.rs` without its row here fails.
    #[test]
    fn every_section_documents_exactly_the_keys_the_loader_accepts() {
        let structs: Vec<(&str, Option<Vec<&str>>)> = vec![
            ("", names::<RawScene>()),
            ("mesh", names::<RawMesh>()),
            ("mesh.face_set", names::<RawFaceSet>()),
            ("material", names::<RawMaterial>()),
            ("scheme", names::<RawScheme>()),
            ("plane", names::<RawPlane>()),
            ("mould", names::<RawMould>()),
            ("interface", names::<RawInterface>()),
            ("interface.delay", names::<RawDelay>()),
            ("contact", names::<RawContact>()),
            ("displacement", names::<RawDisplacement>()),
            ("traction", names::<RawTraction>()),
        ];
        for (path, fields) in &structs {
            let fields = fields
                .as_ref()
                .unwrap_or_else(|| panic!("the struct of `{path}` lists no fields"));
            assert_eq!(
                &documented(path),
                fields,
                "section `{path}`: the table of keys (physics/src/scene/keys.rs) and the serde \
                 struct (raw.rs) differ"
            );
        }
        // `[interface.law]` flattens the family's parameters (documented by the families):
        // serde asks for a map; its one fixed key is `family`.
        assert_eq!(names::<RawLaw>(), None);
        assert_eq!(documented("interface.law"), ["family"]);
        let law: RawLaw = super::super::raw::from_toml("family = \"rccm\"", "t.toml").unwrap();
        assert_eq!((law.family.as_str(), law.params.len()), ("rccm", 0));
        // No section without its struct.
        for s in SECTIONS {
            assert!(
                s.path == "interface.law" || structs.iter().any(|(p, _)| *p == s.path),
                "section `{}` has no serde struct in this test",
                s.path
            );
        }
        // A key of kind table names a section of that path.
        for s in SECTIONS {
            for k in s.keys.iter().filter(|k| k.kind.contains("table")) {
                let path = if s.path.is_empty() {
                    k.key.to_string()
                } else {
                    format!("{}.{}", s.path, k.key)
                };
                let shared = matches!(path.as_str(), "contact.law" | "contact.delay");
                assert!(
                    shared || section(&path).is_some(),
                    "`{path}` is a table without a section"
                );
            }
        }
    }

    #[test]
    fn choices_are_the_variants_of_the_enums() {
        let key = |path: &str, key: &str| section(path).unwrap().key(key).unwrap().choices;
        let sorted = |c: &[&'static str]| {
            let mut c = c.to_vec();
            c.sort_unstable();
            Some(c)
        };
        assert_eq!(sorted(key("material", "model")), names::<MaterialModel>());
        assert_eq!(
            sorted(key("material", "volumetric")),
            names::<crate::material::rubber::Volumetric>()
        );
        assert_eq!(sorted(key("scheme", "integration")), names::<Integration>());
        assert_eq!(sorted(key("displacement", "component")), names::<Axis>());
        let shapes: Vec<&str> = MOULD_SHAPES.iter().map(|s| s.shape).collect();
        assert_eq!(key("mould", "shape"), shapes);
    }

    /// The keys of `[[mould]]` are the common ones and those of the shapes, each documented.
    #[test]
    fn mould_shapes_take_documented_keys() {
        let mut keys: Vec<&str> = MOULD_COMMON.to_vec();
        for shape in MOULD_SHAPES {
            assert!(!shape.description.is_empty());
            for k in shape.keys {
                if !keys.contains(k) {
                    keys.push(k);
                }
            }
        }
        keys.sort_unstable();
        assert_eq!(keys, documented("mould"));
    }

    /// What a scene that leaves the optional keys out gets is what the table says.
    #[test]
    fn defaults_are_what_the_loader_takes() {
        let text = r#"
            end_time = 1.0
            [mesh]
            size = [1.0, 1.0, 1.0]
            cells = [1, 1, 1]
            [material]
            young = 1e6
            poisson = 0.3
            density = 1000.0
            [[plane]]
            name = "p"
            point = [0.0, 0.0, 0.0]
            normal = [0.0, 0.0, 1.0]
            [[interface]]
            faces = "z-"
            plane = "p"
            [interface.law]
            family = "plateau_linear"
            g_n0 = 1e9
            alpha_e = 1e-4
            u_r = 1e-3
            [[contact]]
            faces = "x-"
            plane = "p"
        "#;
        let model = parse_scene(text, "t.toml", &[]).unwrap().model;
        let number = |path: &str, key: &str| match section(path).unwrap().key(key).unwrap().default
        {
            DefaultDoc::Number(x) => x,
            other => panic!("`{path}.{key}` has no number default: {other:?}"),
        };
        let d = SchemeParams::default();
        assert_eq!(model.scheme, d);
        let scheme = [
            ("time_step_factor", d.time_step_factor),
            ("h_crit_update_interval", d.h_crit_update_interval as f64),
            ("h_crit_tolerance", d.h_crit_tolerance),
            ("energy_growth_limit", d.energy_growth_limit),
            ("hourglass_coefficient", d.hourglass_coefficient),
        ];
        for (key, value) in scheme {
            assert_eq!(number("scheme", key), value, "scheme.{key}");
        }
        assert_eq!(
            section("scheme")
                .unwrap()
                .key("integration")
                .unwrap()
                .default,
            DefaultDoc::Text("\"full\"")
        );
        assert_eq!(d.integration, Integration::Full);
        assert_eq!(
            section("material").unwrap().key("model").unwrap().default,
            DefaultDoc::Text("\"svk\"")
        );
        assert_eq!(model.material.model, MaterialModel::Svk);
        let itf = &model.interfaces[0];
        assert_eq!(number("interface", "mu_inf"), itf.mu_inf);
        assert_eq!(number("interface", "initial_damage"), itf.initial_damage);
        assert_eq!(number("contact", "mu"), model.contacts[0].mu);
        assert_eq!((model.name.as_str(), model.gravity), ("t", [0.0; 3]));
        assert_eq!(model.initial_velocity, [0.0; 3]);
        assert_eq!(model.initial_angular_velocity, [0.0; 3]);
    }

    /// `Delay::new` checks `[interface.delay]`; its ranges are the table's.
    #[test]
    fn delay_ranges_are_the_tables() {
        for x in [-1.0, 0.0, 1e-12, 1.0, f64::INFINITY, f64::NAN] {
            assert_eq!(Delay::new(x, 1.0).is_ok(), TAU_C.admits(x), "tau_c = {x}");
            assert_eq!(Delay::new(1.0, x).is_ok(), DELAY_A.admits(x), "a = {x}");
        }
    }

    /// Every row says what it is; a number default is admissible; keys are unique.
    #[test]
    fn every_row_is_complete_and_consistent() {
        for s in SECTIONS {
            assert!(!s.about.is_empty() && !s.presence.is_empty(), "{}", s.path);
            for (i, k) in s.keys.iter().enumerate() {
                let at = format!("{}.{}", s.path, k.key);
                assert!(!k.kind.is_empty() && !k.description.is_empty(), "{at}");
                assert!(
                    s.keys[..i]
                        .iter()
                        .all(|o| o.key != k.key && Some(o.key) != k.alias),
                    "{at} twice"
                );
                if k.range.is_some() || k.kind == "number" {
                    assert!(
                        !k.unit.is_empty(),
                        "{at}: a number needs a unit (– if none)"
                    );
                }
                if let Some(r) = k.range {
                    assert!(r.min <= r.max, "{at}: empty range");
                }
                match k.default {
                    DefaultDoc::Number(x) => assert!(k.admits(x), "{at}: default {x} refused"),
                    DefaultDoc::Text(t) => assert!(!t.is_empty(), "{at}"),
                    DefaultDoc::Required => {}
                }
                if !k.choices.is_empty() {
                    assert_eq!(k.kind, "string", "{at}");
                }
            }
        }
        assert_eq!(
            MESH_CELLS.admissible,
            "integers; their product at most 50 000 000 elements"
        );
        assert_eq!(super::super::mesh::MAX_ELEMENTS, 50_000_000);
    }

    #[test]
    fn messages_say_the_range_and_the_unit() {
        assert_eq!(END_TIME.must(), "must be > 0 s");
        assert_eq!(
            POISSON.must(),
            "must satisfy -1 < ν < 0.5 (0.5 is incompressible; use 0.49 at most)"
        );
        assert_eq!(H_CRIT_TOLERANCE.must(), "must be in (0, 0.01]");
        assert_eq!(INTERFACE_MU_INF.must(), "must be ≥ 0");
    }
}
