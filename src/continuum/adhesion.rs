//! Adhesive contact in the FE (seed §4.2, §5.2): the Lennard-Jones law of [`crate::laws`]
//! (9-3, 10-4, or thermally shifted) between the indenter and the specimen's surface, in place
//! of the repulsive penalty, with optional contact damping ([`super::damping`]).
//!
//! **Mesh sizes.** The contact radius used to size the block is the largest of the Hertz
//! estimate at the deepest point, JKR's radius at the Hertz load there (adhesion enlarges the
//! contact) and 2√(Rz₀) (the attractive ring around a DMT-like contact, where the gap is a few
//! z₀). The smallest element resolves the law's process zone ℓ = E\*γ/σ_peak²
//! ([`crate::theory::process_zone`], PHYSICS.md; for a shifted law σ_peak is σ_max/b) with
//! [`ZONE_ELEMENTS`] elements, unless the contact radius asks for finer ones.

use super::contact::SurfaceArea;
use super::damping::{ContactDamping, DampingError};
use super::indenter::Indenter;
use crate::laws::SurfaceLaw;
use crate::theory::{hertz, jkr, process_zone, tabor, Sphere, TheoryError};
use serde::{Deserialize, Serialize};

/// Why adhesion parameters are unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AdhesionError {
    /// the law's γ or z₀ is not positive and finite
    #[error("adhesion needs γ > 0 and z0 > 0, got γ = {gamma} J/m², z0 = {z0} nm")]
    Law {
        /// γ, J/m²
        gamma: f64,
        /// z₀, nm
        z0: f64,
    },
    /// the contact damping is unusable
    #[error(transparent)]
    Damping(#[from] DampingError),
}

/// Elements across the process zone E\*γ/σ_peak² (PHYSICS.md: ≥ 10).
pub const ZONE_ELEMENTS: f64 = 10.0;

/// The adhesive interaction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AdhesionParams {
    /// the force–separation law
    pub law: SurfaceLaw,
    /// contact damping, if any
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<ContactDamping>,
    /// the area element under finite kinematics ([`SurfaceArea`]; reference by default)
    #[serde(default)]
    pub area: SurfaceArea,
}

impl AdhesionParams {
    /// Check the law's constants and the damping.
    pub fn validate(&self) -> Result<(), AdhesionError> {
        let (g, z0) = (self.law.gamma(), self.law.z0());
        if !(g > 0.0 && g.is_finite() && z0 > 0.0 && z0.is_finite()) {
            return Err(AdhesionError::Law { gamma: g, z0 });
        }
        match &self.damping {
            Some(d) => Ok(d.validate(z0)?),
            None => Ok(()),
        }
    }

    /// The process zone ℓ = E\*γ/σ_peak² of the law, nm ([`crate::theory::process_zone`]).
    pub fn process_zone(&self, e_star: f64) -> Result<f64, TheoryError> {
        process_zone::process_zone(&self.law, e_star)
    }

    /// Tabor's μ of the law against a sphere of `radius` (nm) on modulus `e_star` (GPa)
    /// ([`crate::theory::tabor`]).
    pub fn tabor(&self, radius: f64, e_star: f64) -> Result<f64, TheoryError> {
        tabor::tabor_mu(&self.sphere(radius, e_star)?, self.law.z0())
    }

    /// The sphere of the theory module: `radius`, `e_star` and the law's γ.
    fn sphere(&self, radius: f64, e_star: f64) -> Result<Sphere, TheoryError> {
        Sphere::new(radius, e_star, self.law.gamma())
    }
}

/// The contact radius that sizes the mesh (see the module doc), nm.
pub fn sizing_radius(
    indenter: &Indenter,
    e_star: f64,
    adhesion: Option<&AdhesionParams>,
    max_depth: f64,
) -> f64 {
    let hertz = indenter.contact_radius_estimate(max_depth);
    let Some(a) = adhesion else {
        return hertz;
    };
    let r = indenter.radius();
    let p_hertz = hertz::load_from_depth(max_depth.max(0.0), r, e_star);
    let jkr = a
        .sphere(r, e_star)
        .and_then(|s| jkr::contact_radius(&s, p_hertz))
        .unwrap_or(0.0);
    hertz.max(jkr).max(2.0 * (r * a.law.z0()).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::{LennardJones, LjKind};

    #[test]
    fn tabor_and_process_zone_agree_with_the_scaled_units() {
        // E*z₀²/γ = √(Rz₀) μ^(−3/2)
        let a = AdhesionParams {
            law: LennardJones::new(LjKind::Lj93, 0.03, 0.5).into(),
            damping: None,
            area: Default::default(),
        };
        let (r, e) = (800.0, 1.3);
        let mu = a.tabor(r, e).unwrap();
        let ell = a.process_zone(e).unwrap();
        // σ_max = 16γ/(9√3 z₀) for 9-3: ℓ = (9√3/16)² E*z₀²/γ
        let shape = (9.0 * 3f64.sqrt() / 16.0).powi(2);
        let scaled = (r * 0.5f64).sqrt() * mu.powf(-1.5);
        assert!((ell - shape * scaled).abs() < 1e-9 * ell);
    }
}
