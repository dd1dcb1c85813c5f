//! Helpers of the tests of the whole program: running the command line ([`cli`]), reading a
//! Rerun capture back ([`capture`]) and ParaView files ([`paraview`]), a turning mould and its
//! analytic pose ([`turning`]). The models built in code
//! are the physics tests' (`physics/tests/common/mod.rs`).
#![allow(dead_code)]

pub mod capture;
pub mod cli;
pub mod paraview;
pub mod turning;
