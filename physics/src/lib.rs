//! The physics of decohesion: explicit non-smooth dynamics (CD-Lagrange scheme) of a
//! hyperelastic solid glued to rigid surfaces by the RCCM cohesive law (damageable adhesion,
//! unilateral contact, friction growing with damage). The model is stated in
//! `docs/src/model.md`; every function that implements an equation names it and cites the
//! section ("model §4.7").
//!
//! `Scene -> Model -> Simulation::step()`. This crate depends on no viewer, GUI or command-line
//! crate (rerun, egui, eframe, clap, indicatif): the compiler enforces it, since none is in its
//! `Cargo.toml`, and `.ci/run` checks its dependency tree.

// Index loops over tensor components and Gauss lanes read like the equations they implement.
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is used on purpose: it is also true for NaN, which must be caught.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod element;
pub mod energy;
/// Gmsh `.msh` 4.1 hexahedral meshes in and out.
pub mod gmsh;
/// The RCCM interface: the stiffness law and its families (one file each), cohesion, damage,
/// contact.
pub mod interface;
/// The element loop (stage 3) and the node loop (stage 5), built per instruction set.
pub mod kernels;
pub mod keydoc;
/// The stiffness law g_N(α) (`interface::law`, under the path the rest of the code uses).
pub use interface::law;
pub mod material;
pub mod mesh;
pub mod model;
/// Rigid moulds of any shape: shapes, closest-point queries, prescribed rigid motion.
pub mod mould;
/// Piecewise-linear functions of time (velocity, traction and rotation histories).
pub mod piecewise;
pub mod scene;
pub mod solver;
/// The persistent thread team of the step's parallel loops.
pub mod team;
/// The median the benchmarks report.
pub mod timing;
/// The numbers the solver chose rather than derived: meaning, unit and source of each.
pub mod tunables;
pub mod vec3;
