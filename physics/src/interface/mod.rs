//! The RCCM interface of model §2–§3 at one node: the stiffness law g_N(α) and its families
//! ([`law`], [`family`], one file per family in [`laws`]), the cohesive traction, its energy,
//! the damage update and its dissipation ([`damage`]), and unilateral contact with Coulomb
//! friction ([`contact`]).

pub mod contact;
pub mod damage;
pub mod delay;
pub mod family;
pub mod law;
pub mod laws;
