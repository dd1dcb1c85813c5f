//! The solver's tunables in one place: each number the code chose rather than derived, with its
//! meaning, unit and source. None of them is a physical parameter of a scene (those are scene
//! keys, `docs/src/reference/scene.md`); changing one changes how a result is computed, not
//! what is modelled. The modules that use them re-export them under their old paths.
//!
//! The sources: **round-off** (set well above the round-off of the quantity and well below
//! anything that changes a result), **measured** (chosen for speed or accuracy by measurement;
//! the measurement is in `docs/src/performance-log.md` under the heading named), **model**
//! (follows from the model statement's equations, `docs/src/model.md`), **limit** (a bound on
//! what a run may ask, refused with a message rather than exhausting memory or time), or
//! **chosen** (a design value with no measurement behind it: it sets how often something is
//! recomputed or how fine a drawing is, within the tolerances the model statement states).

// ---------------------------------------------------------------------------------------------
// Parallel loops (model §4.10). Fixed sizes, so that the reduction order, and hence every bit of
// a result, never depends on the thread count.

/// Smallest element block of the element loop ([`crate::mesh::Mesh::element_blocks`]) [elements].
/// Source: chosen; smaller grains were tried and gained nothing (measured, "Scaling").
pub const ELEMENT_GRAIN: usize = 256;

/// Nodes per chunk of the node loops (positions, free velocity) [nodes]. Source: chosen.
pub const NODE_GRAIN: usize = 4096;

/// Boundary nodes per chunk of the boundary pass (stages 5–8) [nodes]. Source: chosen.
pub const BOUNDARY_GRAIN: usize = 256;

/// Below this many elements the loops run on the calling thread: a parallel section would cost
/// more than it saves [elements]. Source: chosen.
pub const PARALLEL_MIN_ELEMENTS: usize = 2048;

/// Degrees of freedom per chunk of the stable-step estimate's streaming passes: the nodes of a
/// chunk of the step's node loops, so that a thread touches the share it has in those loops
/// [degrees of freedom]. Source: model (three per node).
pub const DOF_GRAIN: usize = 3 * NODE_GRAIN;

/// Elements per chunk of the element bound's parallel pass (model §6.6) [elements]. Source:
/// chosen.
pub const BOUND_ELEMENT_CHUNK: usize = 512;

// ---------------------------------------------------------------------------------------------
// The stable step (model §6.5, §6.6).

/// Smallest and largest change of the smallest Jacobian since the last h_crit estimate that
/// triggers a new estimate before its scheduled step, once some element is compressed below
/// [`JACOBIAN_COMPRESSED`] [1]. The threshold adapts between the two: halved after an estimate
/// that found ω_max² moved by more than [`OMEGA_MOVED`], doubled after one that found it within
/// [`OMEGA_STILL`] (a body vibrating in and out of compression, whose stiffest mode barely
/// moves, would otherwise re-estimate at every swing). Source: chosen.
pub const JACOBIAN_RETRIGGER: f64 = 0.02;
/// See [`JACOBIAN_RETRIGGER`] [1].
pub const JACOBIAN_RETRIGGER_MAX: f64 = 0.16;
/// Relative change of ω_max² that halves the Jacobian trigger [1]. Source: chosen.
pub const OMEGA_MOVED: f64 = 0.05;
/// Relative change of ω_max² within which the Jacobian trigger doubles [1]. Source: chosen.
pub const OMEGA_STILL: f64 = 0.02;

/// Smallest J where the stress is evaluated (the Gauss points, or one point's centre) below
/// which compression re-estimates h_crit between scheduled estimates [1]. Source: chosen.
pub const JACOBIAN_COMPRESSED: f64 = 0.9;

/// Change of the glue's total spring stiffness Σ W g_N(α) since the last estimate, as a
/// fraction of its value at t = 0, that re-estimates h_crit (damage and rupture soften the
/// glue, which may set the step) [1]. Source: chosen.
pub const SPRING_RETRIGGER: f64 = 0.1;

/// Largest number of Lanczos iterations of an update (warm-started) estimate [iterations].
/// Source: chosen.
pub const UPDATE_MAX_ITER: usize = 12;

/// An update estimate stops once the Ritz residual ‖r‖ is below this fraction of θ: the margin
/// θ + ‖r‖ then costs at most ½ % of h_crit [1]. Source: model (h_crit ∝ 1/√(θ + ‖r‖)).
pub const UPDATE_RESIDUAL: f64 = 1e-2;

/// Smallest margin of an update estimate, relative to θ [1]. Source: chosen.
pub const UPDATE_MARGIN: f64 = 0.03;

/// Largest Lanczos basis kept in memory by an estimate [f64 values] (64 MB): a run of more
/// iterations than fit forms its Ritz vector by a second pass that regenerates the basis.
/// Source: limit.
pub const BASIS_BUDGET: usize = 1 << 23;

/// Largest ratio h_{n+3/2}/h_{n+½} while the step grows back after a softening [1]. Source:
/// measured ("The stable step under load").
pub const GROWTH_RATIO: f64 = 1.02;

/// Relative dead band of the step's changes: h shrinks when it exceeds the target
/// factor × h_crit by more than this, and grows when the target exceeds it by more [1].
/// Source: chosen.
pub const STEP_BAND: f64 = 0.05;

/// Relative slack on the element bound (B) for the round-off of the 8×8 eigenvalues and of the
/// pass [1] (a few ulps each). Source: round-off.
pub const BOUND_ROUNDING_SLACK: f64 = 1e-9;

// ---------------------------------------------------------------------------------------------
// Contact on several faces at once (model §7.5).

/// Relative tolerance of the joint solve: the sweeps stop when no impulse changed the velocity
/// by more than `JOINT_TOLERANCE · s` (|Δpᵢ|/m ≤ ε s), with s = maxᵢ |V_free − v_surface,i|
/// the node's velocity scale [1]. Source: round-off.
pub const JOINT_TOLERANCE: f64 = 1e-12;

/// Sweeps after which the joint solve stops unconverged (the run warns with the count)
/// [sweeps]. Source: limit (the roadmap's "Moulds and contact" says where it is reached).
pub const JOINT_MAX_SWEEPS: u32 = 200;

/// The most constraint entries one node may have (the solver refuses more at set-up), and the
/// most constraints the exact frictionless projection enumerates (a node behind the faces of a
/// concave corner of a triangulated mould can have more, model §7.5: the sweeps take them)
/// [constraints]. Source: limit.
pub const JOINT_MAX_CONSTRAINTS: usize = 8;

// ---------------------------------------------------------------------------------------------
// Triangulated moulds (model §7.3).

/// The most triangles a node's list of nearby triangles holds
/// ([`crate::mould::SurfaceMesh::project_near`]) [triangles]. Source: chosen.
pub const NEAR_CAPACITY: usize = 16;

/// ρ/(longest edge of the node's closest triangle): the list reaches about ρ around the node's
/// foot point on the surface [1]. Source: chosen.
pub const NEAR_REACH: f64 = 0.5;

/// ε/(the largest coordinate of the node and the surface): the margin of the list's bounds and
/// of a tie [1]. Source: round-off.
pub const NEAR_TOLERANCE: f64 = 1e-9;

/// A triangulated mould with at most this many triangles is queried with parry's full query
/// (its BVH is a few leaves; the lists cost more there) [triangles]. Source: measured
/// ("Closest points on a triangulated mould").
pub const SMALL_SURFACE: usize = 2 * NEAR_CAPACITY;

/// Two vertices of a mould's surface closer than this fraction of its bounding-box diagonal are
/// one vertex (welded): the same corner written twice by a program that rounds differently, or
/// an STL whose facets repeat their corners in single precision [1]. Source: round-off (single
/// precision's 6e-8, with room).
pub const WELD_TOLERANCE: f64 = 1e-6;

/// Two triangles that share an edge are folded onto each other when their unit normals satisfy
/// n₁·n₂ ≤ −1 + `FOLD_TOLERANCE` (they face opposite ways to within 0.08°): the edge's
/// pseudo-normal n₁ + n₂ is then zero or nearly so, and the gap measured along it undefined [1].
/// Source: round-off.
pub const FOLD_TOLERANCE: f64 = 1e-6;

/// Rings (pole to pole) and meridians of a sphere mould's drawing (2 + 15 × 32 = 482 vertices,
/// 960 triangles; each pole is a vertex, so the point of a sphere pressed along its axis is
/// exact). The drawing only: contact uses the exact sphere. Source: chosen for the picture.
pub const SPHERE_RINGS: usize = 16;
/// See [`SPHERE_RINGS`].
pub const SPHERE_MERIDIANS: usize = 32;

/// Segments around a cylinder mould's drawing (contact uses the exact cylinder). Source:
/// chosen for the picture.
pub const CYLINDER_SEGMENTS: usize = 48;

// ---------------------------------------------------------------------------------------------
// Materials and elements (model §1).

/// A rubber's hourglass modulus in units of its initial shear modulus μ₀
/// ([`crate::material::Material::hourglass_modulus`]): the λ + 2μ = 2μ(1 − ν)/(1 − 2ν) of a
/// material of ν = 0.45, so that near incompressibility the one-point element's hourglass
/// stiffness stays at the shear modulus's scale rather than the bulk modulus's [1]. Source:
/// model (model §1.6, §1.10), with ν = 0.45 chosen.
pub const RUBBER_HOURGLASS_SHEAR: f64 = 11.0;

/// The element's share α of the rubbers' isochoric energy on tetrahedra (model §1.14): the
/// rest is taken at the nodes' averaged F, which removes the linear tetrahedron's bending
/// stiffening; the element's share keeps the nodal averaging's spurious modes (a displacement
/// field whose nodal averages vanish) stiff [1]. Source: measured on the nearly incompressible
/// cantilever ("Tetrahedra that do not stiffen").
pub const TET_ELEMENT_SHARE: f64 = 0.3;

/// The largest stretch of the Drucker stability check of a rubber (and its inverse the
/// smallest) [1]. Source: issue 39 (stretches 0.1–10).
pub const DRUCKER_STRETCH_MAX: f64 = 10.0;
/// Samples of the Drucker check between λ = 1 and [`DRUCKER_STRETCH_MAX`] (and its inverse),
/// evenly in ln λ [samples]. Source: chosen (a step of 0.5 % in ln λ).
pub const DRUCKER_SAMPLES: usize = 500;
/// The Drucker check's central-difference step in logarithmic strain [1]. Source: round-off
/// (its truncation error h² and round-off ε/h balance near 1e-5).
pub const DRUCKER_STEP: f64 = 1e-4;

/// The most Jacobi sweeps of the 3×3 symmetric eigen-solve of the Ogden stress [sweeps] (it
/// converges quadratically: a 3×3 matrix takes a handful). Source: limit.
pub const EIGEN_MAX_SWEEPS: usize = 24;

// ---------------------------------------------------------------------------------------------
// Scenes.

/// Largest mesh a scene may ask for [elements]. Source: limit.
pub const MAX_ELEMENTS: u128 = 50_000_000;
