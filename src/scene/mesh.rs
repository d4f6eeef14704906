//! `[mesh]`: the axisymmetric FE mesh — graded triangles, small at the contact, large far away
//! (seed ch. 4). Every size defaults from the expected contact radius a (PHYSICS.md), with the
//! FE engine's own defaults ([`crate::continuum::indent::DEFAULT_BLOCK_FACTOR`] and the rest):
//! the body is 200a wide and deep (a rigid bottom at depth L adds a compliance error of about
//! 0.42·a/L, a free side at a small width a larger one of the other sign), with ~20 elements
//! across a and, with adhesion, ≥ 10 across the law's process zone ℓ = E*γ/σ_peak²
//! (`crate::theory::process_zone`; σ_peak = σ_max/b for a thermally shifted law). These derived
//! sizes are the ones the continuum stage meshes.

use super::check::Checker;
use super::quantity::{Length, Number};
use serde::{Deserialize, Serialize};

use crate::continuum::adhesion::ZONE_ELEMENTS;
use crate::continuum::indent::{
    DEFAULT_BLOCK_FACTOR, DEFAULT_ELEMENTS_PER_RADIUS, DEFAULT_GRADING,
};

/// Default width of the body in expected contact radii (PHYSICS.md: at least 10).
pub const WIDTH_PER_CONTACT_RADIUS: f64 = DEFAULT_BLOCK_FACTOR;
/// Default depth of the body in expected contact radii.
pub const DEPTH_PER_CONTACT_RADIUS: f64 = DEFAULT_BLOCK_FACTOR;
/// Default elements across the contact radius (PHYSICS.md).
pub const ELEMENTS_PER_CONTACT_RADIUS: f64 = DEFAULT_ELEMENTS_PER_RADIUS;
/// Default elements across the process zone (PHYSICS.md), the FE engine's own.
pub const ELEMENTS_PER_PROCESS_ZONE: f64 = ZONE_ELEMENTS;

/// `[mesh]`: sizes of the body and its elements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mesh {
    /// Radius of the modelled body, nm. Default 200 × the expected contact radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<Length>,
    /// Depth of the modelled body (rigid bottom), nm. Default 200 × the expected contact radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<Length>,
    /// Smallest element size, at the contact, nm. Default a/20, and with adhesion at most a
    /// tenth of the law's process zone E*γ/σ_peak² (σ_peak = σ_max/b once thermally shifted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub smallest: Option<Length>,
    /// Growth factor of element size away from the contact: the size ratio of neighbouring
    /// elements, > 1 (at most 2). Default 1.2.
    #[serde(default = "default_grading")]
    pub grading: Number,
    /// Depth of the zone of smallest elements under the surface, nm. Default half the
    /// expected contact radius. With adhesion the smallest size is set by the LJ process zone,
    /// which lies at the surface: a layer a few process zones deep resolves it, the elements
    /// growing with `grading` below (docs/validation-continuum.md, hyperfoam_indent.toml).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fine_depth: Option<Length>,
    /// Refuse a generated mesh of more elements than this (a clear stop instead of a run that
    /// exhausts memory). Default 1,000,000 (≈ 3 GB).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_elements: Option<u64>,
    /// A fine zone that follows the contact edge, remeshed as the edge moves (the element
    /// count then grows like log(a/ℓ) instead of (a/ℓ)²); needs adhesion and the Newton method.
    /// Default `false` (one mesh fine over the whole contact): validated at μ = 1, 2 and 5 only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<bool>,
}

fn default_grading() -> Number {
    Number(1.0 + DEFAULT_GRADING)
}

impl Default for Mesh {
    fn default() -> Self {
        Mesh {
            width: None,
            depth: None,
            smallest: None,
            grading: default_grading(),
            fine_depth: None,
            max_elements: None,
            adaptive: None,
        }
    }
}

impl Mesh {
    pub(crate) fn check(&self, c: &mut Checker) {
        c.positive_opt("mesh.width", self.width);
        c.positive_opt("mesh.depth", self.depth);
        c.positive_opt("mesh.smallest", self.smallest);
        c.positive_opt("mesh.fine_depth", self.fine_depth);
        if self.max_elements.is_some_and(|n| n < 100) {
            c.bad(
                "mesh.max_elements",
                "must be at least 100 (a usable mesh has hundreds of elements)".to_string(),
            );
        }
        if !(self.grading.0 > 1.0 && self.grading.0 <= 2.0) {
            c.bad(
                "mesh.grading",
                format!("{} is not allowed: must lie in (1, 2]", self.grading.0),
            );
        }
        if let (Some(s), Some(w), Some(d)) = (self.smallest, self.width, self.depth) {
            if s.0 >= w.0.min(d.0) {
                c.bad(
                    "mesh.smallest",
                    format!("{} nm is not allowed: must be smaller than the width and depth of the body", s.0),
                );
            }
        }
    }
}
