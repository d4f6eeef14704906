//! Closed-form contact mechanics and turf micromechanics (seed chapters 2, 3 and §5.2).
//!
//! Entry points:
//! - [`hertz`]: elastic sphere without adhesion (seed 3.1–3.3), exact-sphere depth helper;
//! - [`jkr`]: Johnson–Kendall–Roberts (seed 3.4–3.6), pull-off −3/2 and −5/6 πγR;
//! - [`dmt`]: Derjaguin–Muller–Toporov (seed 3.7), pull-off −2πγR;
//! - [`tabor`]: Tabor's μ (seed 3.9, corrected) and Maugis' λ from a law's maximum tension;
//! - [`maugis`]: the Maugis–Dugdale transition (seed 3.10–3.11, Johnson & Greenwood 1997);
//! - [`micromech`]: bent free segments between tube–tube contacts (seed 2.8–2.14);
//! - [`indentation_law`]: the quasi-rheological machine + specimen model (seed 2.1–2.7);
//! - [`thermal`]: RMS amplitude of a free tube end (seed 5.9);
//! - [`process_zone`]: the width ℓ = E\*γ/σ_peak² of any surface law's process zone, which
//!   adhesive meshes resolve.
//!
//! Normalisation (Johnson & Greenwood 1997, seed 3.10): for a sphere of radius R on a
//! half-space of plane-strain modulus E\* with work of adhesion γ,
//! ā = a (4E\*/(3πγR²))^(1/3), P̄ = P/(πγR), δ̄ = δ (16E\*²/(9π²γ²R))^(1/3).
//! In these variables Hertz is P̄ = ā³, δ̄ = ā² (see [`Scales`]).
//!
//! Units: lengths nm, forces nN, moduli GPa, γ J/m² (= nN/nm).

pub mod dmt;
pub mod hertz;
pub mod indentation_law;
pub mod jkr;
pub mod maugis;
pub mod micromech;
pub mod process_zone;
pub mod tabor;
pub mod thermal;

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Why a closed form could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TheoryError {
    /// an input that must be positive and finite is not
    #[error("{what} must be positive and finite, got {value}")]
    NotPositive {
        /// which input
        what: &'static str,
        /// its value
        value: f64,
    },
    /// an input outside the formula's domain
    #[error("{what} = {value} is outside the domain: {allowed}")]
    OutOfDomain {
        /// which input
        what: &'static str,
        /// its value
        value: f64,
        /// what is allowed
        allowed: String,
    },
    /// an iterative solve failed
    #[error("{what} did not converge after {iterations} iterations (residual {residual:e})")]
    NoConvergence {
        /// which solve
        what: &'static str,
        /// iterations spent
        iterations: usize,
        /// last residual
        residual: f64,
    },
    /// a NaN or infinity appeared
    #[error("{what} is not finite ({value})")]
    NotFinite {
        /// which quantity
        what: &'static str,
        /// its value
        value: f64,
    },
}

/// Return `value` if it is positive and finite, else a [`TheoryError::NotPositive`].
pub fn positive(what: &'static str, value: f64) -> Result<f64, TheoryError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(TheoryError::NotPositive { what, value })
    }
}

/// How the test is driven when the contact comes apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Control {
    /// the load is prescribed (a soft machine): pull-off at the minimum of P along the curve
    Load,
    /// the depth is prescribed (a stiff machine): the contact jumps off where dδ/da = 0
    Displacement,
}

/// A sphere on a half-space: the data of every adhesive closed form.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sphere {
    /// effective radius R (seed 3.2 footnote), nm
    pub radius: f64,
    /// plane-strain modulus E\* = (Σ(1−νᵢ²)/Eᵢ)⁻¹ (seed 3.2), GPa
    pub modulus: f64,
    /// work of adhesion γ, J/m² (= nN/nm)
    pub gamma: f64,
}

impl Sphere {
    /// Check that R, E\* and γ are positive and finite.
    pub fn new(radius: f64, modulus: f64, gamma: f64) -> Result<Self, TheoryError> {
        Ok(Sphere {
            radius: positive("radius R", radius)?,
            modulus: positive("modulus E*", modulus)?,
            gamma: positive("work of adhesion γ", gamma)?,
        })
    }

    /// The scales that turn normalised quantities into physical ones.
    pub fn scales(&self) -> Scales {
        let (r, e, g) = (self.radius, self.modulus, self.gamma);
        Scales {
            length: (3.0 * PI * g * r * r / (4.0 * e)).cbrt(),
            force: PI * g * r,
            depth: (9.0 * PI * PI * g * g * r / (16.0 * e * e)).cbrt(),
        }
    }
}

/// Physical size of one unit of ā, P̄ and δ̄ (Johnson & Greenwood 1997).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// a = ā · length, nm: (3πγR²/(4E\*))^(1/3)
    pub length: f64,
    /// P = P̄ · force, nN: πγR
    pub force: f64,
    /// δ = δ̄ · depth, nm: (9π²γ²R/(16E\*²))^(1/3)
    pub depth: f64,
}

/// One point of a load–approach curve in normalised variables.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NormalizedPoint {
    /// contact radius ā
    pub a_bar: f64,
    /// load P̄ = P/(πγR), positive compressive
    pub p_bar: f64,
    /// approach δ̄, positive penetration
    pub delta_bar: f64,
}

/// The sphere models that have a closed-form or semi-analytic curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "lowercase")]
pub enum Model {
    /// no adhesion
    Hertz,
    /// the λ → ∞ limit
    Jkr,
    /// the λ → 0 limit
    Dmt,
    /// Maugis–Dugdale at transition parameter λ
    Maugis {
        /// Maugis' λ (seed 3.10)
        lambda: f64,
    },
}

impl Model {
    /// The normalised point at contact radius ā > 0.
    pub fn point(&self, a_bar: f64) -> Result<NormalizedPoint, TheoryError> {
        positive("contact radius ā", a_bar)?;
        Ok(match *self {
            Model::Hertz => hertz::normalized(a_bar),
            Model::Jkr => jkr::normalized(a_bar),
            Model::Dmt => dmt::normalized(a_bar),
            Model::Maugis { lambda } => {
                maugis::point(lambda, a_bar, &maugis::MaugisParams::default())?.into()
            }
        })
    }

    /// Normalised pull-off P̄ (negative) under the given control; Hertz has none (0).
    pub fn pull_off(&self, control: Control) -> Result<f64, TheoryError> {
        Ok(match *self {
            Model::Hertz => 0.0,
            Model::Jkr => jkr::pull_off(control),
            Model::Dmt => dmt::PULL_OFF,
            Model::Maugis { lambda } => {
                maugis::pull_off(lambda, control, &maugis::MaugisParams::default())?.p_bar
            }
        })
    }
}
