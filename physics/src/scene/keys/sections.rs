//! The table of the scene format: every section, its keys and what each means
//! ([`SECTIONS`]), built from the key types and the named keys of `keys.rs`.

use super::*;

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
            KeyDoc::new(
                "mass_scaling",
                "table",
                "",
                "selective mass scaling to a target step: `[mass_scaling]`",
            )
            .default_text("no mass scaling"),
            KeyDoc::new(
                "bulk_viscosity",
                "table",
                "",
                "bulk viscosity: `[bulk_viscosity]`",
            )
            .default_text("no bulk viscosity"),
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
                "bond",
                "array of tables",
                "",
                "face sets of the body joined to each other by a cohesive law: `[[bond]]`",
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
                binary) of 8-node hexahedra with det J₀ > 0 and 4-node tetrahedra of positive \
                volume, either or both (model §1.13); its face sets are its physical groups of \
                dimension 2 (`physical_<tag>` for a group without a name), of 4-node \
                quadrangles and 3-node triangles on the boundary of the elements.",
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
            .admissible("a `.msh` 4.1 file of 8-node hexahedra and/or 4-node tetrahedra"),
            MESH_SCALE,
            KeyDoc::new(
                "face_set",
                "array of tables",
                "",
                "face sets selected by a box: `[[mesh.face_set]]`",
            )
            .default_text(NONE),
            KeyDoc::new(
                "split",
                "table",
                "",
                "the mesh cut in two along a plane of its faces: `[mesh.split]`",
            )
            .default_text("none (one piece)"),
        ],
    },
    SectionDoc {
        path: "mesh.split",
        array: false,
        presence: "optional",
        about: "The mesh cut in two along the plane X_axis = `at` (model §7.8): the nodes on \
                the plane get a copy for the elements above it (centroid beyond `at`), so the \
                two sides share no node, and the faces on the plane become the face sets \
                `split-` (the lower side's, outward normal along +axis) and `split+` (the upper \
                side's). A `[[bond]]` joins them again; without one the two sides are separate \
                bodies. Face sets of the mesh keep their faces (those above the plane take the \
                copies); `[[mesh.face_set]]` may select from `split-` and `split+`.",
        keys: &[
            KeyDoc::new("axis", "string", "", "the axis the cut plane is normal to")
                .choices(&["x", "y", "z"]),
            KeyDoc::new("at", "number", "m", "the plane's coordinate along `axis`").admissible(
                "strictly inside the mesh, on a layer of element faces (a box: origin + \
                 size·k/cells, 0 < k < cells)",
            ),
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
        keys: super::super::material_keys::MATERIAL_KEYS,
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
                "quadrature: 2×2×2 Gauss points (`full`), one point with Flanagan–Belytschko \
                 hourglass control (`reduced`; the hourglass energy is a ledger term), or 2×2×2 \
                 points with F̄ = (J̄/J)^{1/3} F (`fbar`: one volume ratio per element, no \
                 volumetric locking near ν = 0.5, model §1.11), or one point with physical \
                 hourglass stabilisation (`reduced_physical`: bending stiffness in E, warping in \
                 μ, no coefficient and no locking, model §1.12)",
            )
            .default_text("\"full\"")
            .choices(&["full", "reduced", "fbar", "reduced_physical"]),
            HOURGLASS_COEFFICIENT,
        ],
    },
    SectionDoc {
        path: "mass_scaling",
        array: false,
        presence: "optional",
        about: "Selective mass scaling (model §6.8), for quasi-static runs at laboratory speeds: \
                the elements whose stable step is below `target_step` get a larger density, so \
                that h_crit of the bulk is at least the target. The added mass, its share of the \
                total and the added mass's kinetic energy are reported by `check`, the summary, \
                the recording and the ledger. Absent: no scaling.",
        keys: &[MASS_SCALING_TARGET_STEP, MASS_SCALING_KINETIC_SHARE],
    },
    SectionDoc {
        path: "bulk_viscosity",
        array: false,
        presence: "optional",
        about: "Bulk viscosity (model §4.12): a viscous mean stress \
                q = ρ L_e ε̇ (b₁ c_d − b₂² L_e min(0, ε̇)) in each element (ε̇ its volumetric strain \
                rate, L_e its length, c_d the dilatational wave speed), which damps the ringing \
                of the highest modes and spreads compression shocks. Its work is the ledger's \
                `bulk_viscous_dissipated`, and the step is shortened by √(1 + ξ²) − ξ for the \
                damping ratio ξ it gives. Present (even empty): on, with Abaqus/Explicit's \
                defaults; absent: off.",
        keys: &[BULK_VISCOSITY_LINEAR, BULK_VISCOSITY_QUADRATIC],
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
        about: "A rigid mould of any shape: the keys below, which every shape takes, and those \
                of its shape (one table per shape below, each declared by the shape's file \
                `physics/src/mould/shapes/<shape>.rs`). `[[interface]]` and `[[contact]]` name \
                it by `plane` (or `mould`, the same key); plane and mould names share one \
                namespace. A key of another shape is refused, naming the keys the shape takes.",
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
            .choices(crate::mould::shapes::SHAPE_KEYS),
            KeyDoc::new(
                "pivot",
                XYZ,
                "m",
                "the point the angular velocity turns about at t = 0 (it moves with `velocity`)",
            )
            .default_text(
                "the shape's reference point: `point` of a half_space, `centre` of a shape \
                 about a centre, the origin for a surface",
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
        path: "bond",
        array: true,
        presence: "zero or more",
        about: "Two face sets of the body joined node to node by a cohesive law (model §7.8): \
                each node of `faces` is paired with the node of `to` at the same reference \
                position, and the pair's jump [u] = x_faces − x_to obeys the law as a glued \
                node's jump to its mould does: adhesion, unilateral contact between the two \
                sides, friction growing with damage up to `mu_inf`. The normal n is `to`'s \
                outward normal in the reference configuration (it does not turn: for interfaces \
                that rotate little, as in beam tests). The two sides usually come from \
                `[mesh.split]`. The bond's nodes may carry no other condition (interface, \
                contact, traction, prescribed displacement, another bond).",
        keys: &[
            FACES,
            KeyDoc::new("to", "string", "", "the face set `faces` is joined to").admissible(
                "a face set of the mesh with a node at the place of each node of `faces`, \
                 sharing none of them",
            ),
            INTERFACE_MU_INF,
            INITIAL_DAMAGE,
            KeyDoc::new(
                "law",
                "table",
                "",
                "the stiffness law g_N(α): the keys of `[interface.law]`, any family",
            ),
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
