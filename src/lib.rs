//! decohesion: explicit non-smooth dynamics (CD-Lagrange scheme) of a hyperelastic solid glued
//! to rigid surfaces by the RCCM cohesive law (damageable adhesion, unilateral contact, friction
//! growing with damage). See `PHYSICS.md` of the project for the model; every function that
//! implements an equation names it.
//!
//! Usable as a library: `Scene -> Model -> Simulation::step()`. The physics modules know nothing
//! of the command line or of any viewer; `record` (Rerun) and `vtk` (ParaView files) read them
//! and are read by none of them.

// Index loops over tensor components and Gauss lanes read like the equations they implement.
#![allow(clippy::needless_range_loop)]
// `!(x > 0.0)` is used on purpose: it is also true for NaN, which must be caught.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod energy;
/// Gmsh `.msh` 4.1 hexahedral meshes in and out.
pub mod gmsh;
/// The explorer window (egui): reads scenes, runs simulations on a thread; not used by the physics.
pub mod gui;
pub mod law;
pub mod material;
pub mod mesh;
pub mod model;
/// What the outputs share: frame cadence, writer-thread priority.
pub mod output;
/// Rerun recording (live or `.rrd`): reads a simulation, is not read by the physics.
pub mod record;
pub mod report;
pub mod scene;
pub mod solver;
/// The persistent thread team of the step's parallel loops.
pub mod team;
/// Speed against accuracy: a grid of configurations of one scene compared with the finest.
pub mod tradeoff;
/// ParaView output (`.vtu` frames and a `.pvd` index): reads a simulation, uses no Rerun.
pub mod vtk;
