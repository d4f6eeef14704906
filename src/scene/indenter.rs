//! `[indenter]`: the rigid indenter — a sphere, or a Berkovich pyramid with a spherical tip
//! (seed §2.3: a 1.8 µm tip, spherical up to about 100 nm depth).
//!
//! The blunt Berkovich is a sphere of radius R blended tangentially into the cone of the same
//! projected area (half-angle θ = 70.3°); the sphere meets the cone at depth
//! h_t = R(1 − sin θ), which is the default `tip_depth` (105 nm for R = 1.8 µm).
//!
//! `tangential = "stick"` holds the surface where it first touched the indenter instead of
//! letting it slide (`crate::continuum::contact::Stick`).

use super::check::Checker;
use super::compression::Tangential;
use super::quantity::Length;
use serde::{Deserialize, Serialize};

/// Half-angle of the cone with the area function of a Berkovich pyramid, degrees.
pub const BERKOVICH_EQUIVALENT_CONE_DEG: f64 = 70.3;

/// Indenter shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Shape {
    /// a rigid sphere of radius `radius`
    Sphere,
    /// a Berkovich pyramid (as its equivalent cone) with a spherical tip of radius `radius`
    BerkovichBlunt,
}

/// `[indenter]`: a rigid indenter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Indenter {
    /// `"sphere"` or `"berkovich-blunt"`. Default `"sphere"`.
    #[serde(default = "default_shape")]
    pub shape: Shape,
    /// Radius of the sphere or of the spherical tip, nm (a length). Required.
    pub radius: Length,
    /// Depth at which the spherical tip meets the cone, nm (only for `"berkovich-blunt"`).
    /// Default R(1 − sin 70.3°), where the sphere and the equivalent cone are tangent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip_depth: Option<Length>,
    /// `"frictionless"` (the surface slides freely) or `"stick"` (the surface is held where
    /// it first touched, as `compression.sphere_tangential = "stick"` holds the tubes' tips).
    /// Default `"frictionless"`.
    #[serde(default, skip_serializing_if = "is_frictionless")]
    pub tangential: Tangential,
}

fn is_frictionless(t: &Tangential) -> bool {
    *t == Tangential::Frictionless
}

fn default_shape() -> Shape {
    Shape::Sphere
}

impl Indenter {
    pub(crate) fn check(&mut self, c: &mut Checker) {
        c.positive("indenter.radius", self.radius);
        match self.shape {
            Shape::Sphere => {
                if self.tip_depth.is_some() {
                    c.unused("indenter.tip_depth", "with shape = \"sphere\"");
                }
            }
            Shape::BerkovichBlunt => {
                let r = self.radius.0;
                let tangent = r * (1.0 - BERKOVICH_EQUIVALENT_CONE_DEG.to_radians().sin());
                let h = *self.tip_depth.get_or_insert(Length(tangent));
                if h.0 <= 0.0 || h.0 >= r {
                    c.bad(
                        "indenter.tip_depth",
                        format!(
                            "{} nm is not allowed: must lie in (0, radius = {r} nm)",
                            h.0
                        ),
                    );
                }
            }
        }
    }
}
