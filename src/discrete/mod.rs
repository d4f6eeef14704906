//! The discrete turf (seed chapter 2.4): tubes as elastica chains, van der Waals contacts,
//! broadphase, generation, drives, analysis.

pub mod broadphase;
pub mod constraints;
pub mod energy;
pub mod rod;
pub mod rod_kernels;
pub mod rod_problems;
pub mod solve;
pub mod solve_fire;
pub mod solve_newton;
pub mod turf;
pub mod vdw;
pub mod vdw_term;
