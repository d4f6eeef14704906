//! The discrete turf (seed chapter 2.4): tubes as elastica chains, van der Waals contacts,
//! broadphase, generation, drives.
//!
//! Entry points: [`turf::generate_turf`] (a turf from `[turf]`), [`model::TurfSystem`] (its
//! energy and clamps), [`model::relax`] (contacts form, E = U − Γ), [`drive::compress`] (the
//! platen drive; [`checkpoint`] saves it after every step for `--resume`), [`rve::drive_rve`]
//! (lateral compression and longitudinal shear of the periodic volume). The curve a drive
//! records is analysed (σ₀, tangent law, hysteresis) by
//! [`crate::homogenize::curve_analysis`].

pub mod broadphase;
pub mod checkpoint;
pub mod constraints;
pub mod drive;
pub mod energy;
pub mod explicit_rods;
pub mod model;
pub mod platen;
#[cfg(feature = "rapier")]
pub mod rapier_packing;
pub mod rod;
pub mod rod_kernels;
pub mod rod_problems;
pub mod rve;
pub mod solve;
pub mod solve_fire;
pub mod solve_newton;
pub mod sphere_adhesion;
pub mod sphere_stick;
pub mod structure;
pub mod turf;
pub mod vdw;
pub mod vdw_table;
pub mod vdw_term;
