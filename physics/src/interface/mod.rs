//! The interface of PHYSICS.md §3 at one node: the cohesive traction and its energy, the damage
//! update and its dissipation ([`damage`]), and unilateral contact with Coulomb friction
//! ([`contact`]). The stiffness laws g_N(α) are in [`crate::law`].

pub mod contact;
pub mod damage;
