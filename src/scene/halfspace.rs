//! `[halfspace]`: the small-strain integral solver — an elastic half-space under a rigid
//! sphere with LJ tractions (Boussinesq kernel on an axisymmetric radial grid), giving the full
//! load–approach S-curve at any Tabor μ in milliseconds to seconds. It needs `[indenter]`
//! (sphere), a linear `[material]` and `[adhesion]`.

use super::check::Checker;
use super::quantity::Length;
use crate::laws::LjKind;
use serde::{Deserialize, Serialize};

/// `[halfspace]`: grid and approach range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Halfspace {
    /// Radial grid points, ≥ 16. Default 512.
    #[serde(default = "default_grid")]
    pub grid: usize,
    /// Radius of the modelled surface, nm. Default: chosen by the half-space solver from the
    /// contact radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extent: Option<Length>,
    /// Force–separation law, `"lj93"` or `"lj104"`. Default: `adhesion.law`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law: Option<LjKind>,
    /// Smallest rigid-body approach δ, nm (negative: clear of the surface). Default −5 z₀.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_min: Option<Length>,
    /// Largest rigid-body approach δ, nm. Required, larger than `depth_min`.
    pub depth_max: Length,
    /// Approach positions on the way in (and again on the way out), ≥ 2. Default 200.
    #[serde(default = "default_points")]
    pub points: usize,
}

fn default_grid() -> usize {
    512
}
fn default_points() -> usize {
    200
}

impl Halfspace {
    pub(crate) fn check(&mut self, c: &mut Checker, z0: Option<f64>) {
        c.count_at_least("halfspace.grid", self.grid, 16);
        c.count_at_least("halfspace.points", self.points, 2);
        c.positive_opt("halfspace.extent", self.extent);
        if let Some(z0) = z0 {
            let lo = *self.depth_min.get_or_insert(Length(-5.0 * z0));
            if self.depth_max.0 <= lo.0 {
                c.bad(
                    "halfspace.depth_max",
                    format!(
                        "{} nm is not allowed: must exceed depth_min = {} nm",
                        self.depth_max.0, lo.0
                    ),
                );
            }
        }
    }
}
