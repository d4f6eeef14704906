//! `[compression]`: the discrete drive — a rigid platen (or, with `indenter = "sphere"`, a rigid
//! frictionless sphere of radius `sphere_radius` over the box centre) pressed onto the turf (or
//! rods) along a nominal-strain path, optionally unloaded again to measure reversibility; each step is
//! relaxed to equilibrium by FIRE or Newton.

use super::check::Checker;
use super::quantity::{Force, Length, Number};
use serde::{Deserialize, Serialize};

/// How the platen meets the tube tops.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Platen {
    /// the tops slide freely on the platen
    Frictionless,
    /// the tops move with the platen
    Bonded,
}

/// What presses on the turf.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Indenter {
    /// a flat platen over the whole box (stress–strain curve)
    Platen,
    /// a rigid frictionless sphere over the box centre (load–depth curve)
    Sphere,
}

/// Equilibrium solver of each step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DiscreteSolver {
    /// FIRE relaxation (robust through buckling and contact changes)
    Fire,
    /// Newton with line search (fast near equilibrium)
    Newton,
}

/// `[compression]`: the strain path and its solver.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Compression {
    /// `"frictionless"` or `"bonded"`. Default `"frictionless"`.
    #[serde(default = "default_platen")]
    pub platen: Platen,
    /// `"platen"` or `"sphere"`. Default `"platen"`.
    #[serde(default = "default_indenter")]
    pub indenter: Indenter,
    /// Radius of the sphere, > 0; required with `indenter = "sphere"`, not allowed otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere_radius: Option<Length>,
    /// Final nominal compressive strain, in (0, 1). Required.
    pub to: Number,
    /// Strain steps to reach `to`, ≥ 1. Default 20.
    #[serde(default = "default_steps")]
    pub steps: usize,
    /// Also unload back to zero strain, in as many steps. Default false.
    #[serde(default)]
    pub unload: bool,
    /// `"fire"` or `"newton"`. Default `"fire"`.
    #[serde(default = "default_solver")]
    pub solver: DiscreteSolver,
    /// Largest residual force on a node at equilibrium, nN. Default 1e-3 nN.
    #[serde(default = "default_tolerance")]
    pub tolerance: Force,
    /// Iterations per step before the stage gives up, ≥ 1. Default 100000.
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
}

fn default_platen() -> Platen {
    Platen::Frictionless
}
fn default_indenter() -> Indenter {
    Indenter::Platen
}
fn default_steps() -> usize {
    20
}
fn default_solver() -> DiscreteSolver {
    DiscreteSolver::Fire
}
fn default_tolerance() -> Force {
    Force(1e-3)
}
fn default_iterations() -> usize {
    100_000
}

impl Compression {
    pub(crate) fn check(&self, c: &mut Checker) {
        c.number_in("compression.to", self.to.0, 0.0, 1.0, true);
        match (self.indenter, self.sphere_radius) {
            (Indenter::Sphere, None) => c.bad(
                "compression.sphere_radius",
                "is required with indenter = \"sphere\" (a length > 0)",
            ),
            (Indenter::Sphere, r) => c.positive_opt("compression.sphere_radius", r),
            (Indenter::Platen, Some(_)) => c.unused(
                "compression.sphere_radius",
                "with indenter = \"platen\" (allowed: \"platen\", \"sphere\")",
            ),
            (Indenter::Platen, None) => {}
        }
        c.count_at_least("compression.steps", self.steps, 1);
        c.positive("compression.tolerance", self.tolerance);
        c.count_at_least("compression.max_iterations", self.max_iterations, 1);
    }
}
