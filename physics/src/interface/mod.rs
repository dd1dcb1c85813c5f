//! The RCCM interface (PHYSICS.md §3): the stiffness law g_N(α) and its families.

mod compat;
pub mod family;
pub mod law;
pub mod laws;
