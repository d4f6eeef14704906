//! `[halfspace]`: the small-strain integral solver — an elastic half-space under a rigid
//! sphere with LJ tractions (exact Boussinesq ring kernel on an axisymmetric radial grid), giving
//! the full load–approach S-curve and the pull-off at any Tabor μ in milliseconds to seconds
//! (engine: [`crate::halfspace`]). It needs `[indenter]` (sphere), a linear `[material]` and
//! `[adhesion]`. The grid is designed by the solver from μ (uniform over the contact region
//! with `cells_per_zone` cells per LJ process zone, graded outside).

use super::check::Checker;
use crate::laws::LjKind;
use serde::{Deserialize, Serialize};

/// `[halfspace]`: law and resolution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Halfspace {
    /// Force–separation law, `"lj93"` or `"lj104"`. Default: `adhesion.law`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law: Option<LjKind>,
    /// Grid cells per LJ process zone over the contact region, a whole number ≥ 4 (and within
    /// the memory ceiling, `scene::resources`). Default 12 (pull-off
    /// converged to ≤ 0.06 % for μ ≤ 2, docs/validation-halfspace.md).
    #[serde(default = "default_cells")]
    pub cells_per_zone: f64,
    /// Also compute the pull-off on three refined grids and report the Richardson error
    /// estimate. Default true.
    #[serde(default = "default_refinement")]
    pub refinement: bool,
}

fn default_cells() -> f64 {
    12.0
}
fn default_refinement() -> bool {
    true
}

/// Smallest useful resolution: below it the contact edge is not resolved at all.
const MIN_CELLS_PER_ZONE: f64 = 4.0;

impl Halfspace {
    pub(crate) fn check(&mut self, c: &mut Checker) {
        c.number_in(
            "halfspace.cells_per_zone",
            self.cells_per_zone,
            MIN_CELLS_PER_ZONE,
            f64::INFINITY,
            false,
        );
        if self.cells_per_zone.is_finite() && self.cells_per_zone.fract() != 0.0 {
            c.bad(
                "halfspace.cells_per_zone",
                format!(
                    "{} is not allowed: a count of grid cells must be a whole number, e.g. {}",
                    self.cells_per_zone,
                    self.cells_per_zone.round().max(MIN_CELLS_PER_ZONE)
                ),
            );
        }
    }
}
