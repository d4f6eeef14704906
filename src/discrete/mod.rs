//! The discrete turf (seed chapter 2.4): tubes as elastica chains, van der Waals contacts,
//! broadphase, generation, drives, analysis.

pub mod broadphase;
pub mod energy;
pub mod turf;
pub mod vdw;
pub mod vdw_term;
