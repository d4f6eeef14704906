//! turf: mechanics of carbon-nanotube turfs, from the tubes to a nanoindentation test.
//!
//! The chain of models (see `docs/` and the project's DESIGN):
//!
//! - [`units`]: internal units (nm, nN, s) and the quantity-string parser.
//! - [`laws`]: force–separation laws shared by every engine (LJ 9-3, 10-4, thermally shifted).
//! - [`theory`]: closed forms — Hertz, JKR, DMT, Maugis–Dugdale, Tabor, micromechanics,
//!   the quasi-rheological indentation law, thermal amplitude of tube ends.
//! - [`numerics`]: solvers shared by the engines (sparse factorisation, ...).
//! - [`halfspace`]: small-strain half-space with LJ tractions (fast adhesion curves).
//! - [`continuum`]: axisymmetric finite-deformation FE indentation.
//! - [`discrete`]: the turf as tubes.
//! - [`homogenize`]: from a stress–strain curve to a material card.
//! - [`experiment`]: measured indentation records and the fit of the seed's indentation law.
//! - [`scene`]: the scene file (TOML), its validation and the resolved plan.
//! - [`pipeline`]: a scene's stages run in order.
//! - [`interrupt`]: the SIGINT/SIGTERM request long stages poll to stop with what they have.
//! - [`report`]: CSV, JSON, plots and VTK, every file written atomically.
//! - [`bench`]: the speed–accuracy ladder and refinement sweeps of `turf bench`.
#![warn(missing_docs)]

/// The build that runs: the crate version and the hash of the source it was built from
/// (`build.rs`), e.g. `0.1.1+8c3e0d1f2a4b5c6d`. Results kept for reuse (the stage cache, a
/// sweep point's result, an ensemble's realisation) are keyed on it, so a changed engine never
/// hands over what the old one computed.
pub const BUILD: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("TURF_SOURCE_HASH"));

pub mod bench;
pub mod continuum;
pub mod discrete;
pub mod experiment;
pub mod halfspace;
pub mod homogenize;
pub mod interrupt;
pub mod laws;
pub mod numerics;
pub mod pipeline;
pub mod report;
pub mod scene;
pub mod theory;
pub mod units;
