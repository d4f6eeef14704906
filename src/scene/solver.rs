//! `[solver]`: the continuum stage's nonlinear solver — Newton with increment cut-backs, or
//! Riks arc-length to follow the S-curve through jump-in and pull-off (seed ch. 4) — and its
//! kinematics (finite deformation or small strain, so the seed's claim about large rotations
//! near the contact edge can be tested rather than assumed, PHYSICS.md).

use super::check::Checker;
use super::quantity::Number;
use serde::{Deserialize, Serialize};

/// Nonlinear solution method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// load stepping with Newton iterations (with contact damping to pass instabilities)
    Newton,
    /// arc-length continuation (follows unstable branches)
    Riks,
}

/// Strain measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kinematics {
    /// total Lagrangian, finite deformation
    Finite,
    /// small strain, the undeformed geometry
    Small,
}

/// `[solver]`: method, kinematics, tolerances and increments.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// `"newton"` or `"riks"`. Default `"newton"`.
    #[serde(default = "default_method")]
    pub method: Method,
    /// `"finite"` or `"small"`. Default `"finite"`.
    #[serde(default = "default_kinematics")]
    pub kinematics: Kinematics,
    /// Relative residual tolerance, in (0, 1). Default 1e-8.
    #[serde(default = "default_tolerance")]
    pub tolerance: Number,
    /// Newton iterations per increment before a cut-back, ≥ 1. Default 25.
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
    /// Increments per schedule segment, ≥ 1. Default 100.
    #[serde(default = "default_increments")]
    pub increments: usize,
    /// Halvings of a failing increment before the stage gives up. Default 10.
    #[serde(default = "default_cutbacks")]
    pub max_cutbacks: usize,
    /// With `"riks"`: corrector iterations each arc-length step aims at (the step grows when
    /// fewer were needed, shrinks when more), ≥ 1. Default 5.
    #[serde(default = "default_target_iterations")]
    pub target_iterations: usize,
    /// With `"newton"`: an increment failing at its smallest size snaps (the drive, or the
    /// load, held and the state descended to the next minimum, `turf::continuum::snap`)
    /// instead of stopping the run; not where the material lost ellipticity, nor retracting
    /// under load control (the pull-off). Default true.
    #[serde(default = "default_snap")]
    pub snap: bool,
}

fn default_method() -> Method {
    Method::Newton
}
fn default_kinematics() -> Kinematics {
    Kinematics::Finite
}
fn default_tolerance() -> Number {
    Number(1e-8)
}
fn default_iterations() -> usize {
    25
}
fn default_increments() -> usize {
    100
}
fn default_cutbacks() -> usize {
    10
}
fn default_target_iterations() -> usize {
    5
}
fn default_snap() -> bool {
    true
}

impl Default for Solver {
    fn default() -> Self {
        Solver {
            method: default_method(),
            kinematics: default_kinematics(),
            tolerance: default_tolerance(),
            max_iterations: default_iterations(),
            increments: default_increments(),
            max_cutbacks: default_cutbacks(),
            target_iterations: default_target_iterations(),
            snap: default_snap(),
        }
    }
}

impl Solver {
    pub(crate) fn check(&self, c: &mut Checker) {
        c.number_in("solver.tolerance", self.tolerance.0, 0.0, 1.0, true);
        c.count_at_least("solver.max_iterations", self.max_iterations, 1);
        c.count_at_least("solver.increments", self.increments, 1);
        c.count_at_least("solver.target_iterations", self.target_iterations, 1);
    }
}
