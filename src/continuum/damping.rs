//! Viscous contact damping (seed eq. 4.4, PHYSICS.md): a pressure c(g)·ġ opposing the rate of
//! change of the gap, with c(g) = c₀ for g ≤ η g′, falling linearly to 0 at g = g′ and 0 beyond.
//!
//! It exists only to carry a quasi-static Newton solution through jump-to-contact and jump-out
//! (where the displacement-controlled equilibrium has no nearby solution): the incremental
//! pseudo-potential ½c(gₙ)(g − gₙ)²/Δt adds c/Δt to the tangent, so each step is well posed.
//! How it enters the surface integral is in [`super::contact::Damping`]; the driver reports the
//! energy it dissipated, Σ ∫ c(gₙ)(g − gₙ)²/Δt dA over the steps, against the strain energy, so
//! a user sees that it is negligible (or not).

use serde::{Deserialize, Serialize};

/// Why contact-damping parameters are unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DampingError {
    /// c₀ is not positive and finite
    #[error("damping c0 must be positive, got {c0}")]
    Coefficient {
        /// c₀, GPa·s/nm
        c0: f64,
    },
    /// g′ does not exceed the law's equilibrium gap z₀
    #[error("damping gap g′ = {gap} nm must exceed z0 = {z0} nm")]
    Gap {
        /// g′, nm
        gap: f64,
        /// the law's z₀, nm
        z0: f64,
    },
    /// η is outside [0, 1)
    #[error("damping eta must lie in [0, 1), got {eta}")]
    Eta {
        /// η
        eta: f64,
    },
}

/// The damping coefficient c(g).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactDamping {
    /// full coefficient c₀, GPa·s/nm
    pub c0: f64,
    /// gap g′ beyond which there is no damping, nm
    pub gap: f64,
    /// fraction η of g′ up to which the damping is full, in [0, 1)
    pub eta: f64,
}

impl ContactDamping {
    /// c(g), GPa·s/nm.
    pub fn coefficient(&self, g: f64) -> f64 {
        let full = self.eta * self.gap;
        if g <= full {
            self.c0
        } else if g >= self.gap {
            0.0
        } else {
            self.c0 * (self.gap - g) / (self.gap - full)
        }
    }

    /// Check the parameters against the law's equilibrium gap z₀ (g′ must exceed it, or the
    /// damping would not act where the surfaces meet).
    pub fn validate(&self, z0: f64) -> Result<(), DampingError> {
        if !(self.c0 > 0.0 && self.c0.is_finite()) {
            return Err(DampingError::Coefficient { c0: self.c0 });
        }
        if !(self.gap > z0 && self.gap.is_finite()) {
            return Err(DampingError::Gap { gap: self.gap, z0 });
        }
        if !(self.eta >= 0.0 && self.eta < 1.0) {
            return Err(DampingError::Eta { eta: self.eta });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficient_is_full_then_linear_then_zero() {
        let d = ContactDamping {
            c0: 2.0,
            gap: 4.0,
            eta: 0.5,
        };
        assert_eq!(d.coefficient(-1.0), 2.0);
        assert_eq!(d.coefficient(2.0), 2.0);
        assert!((d.coefficient(3.0) - 1.0).abs() < 1e-15);
        assert_eq!(d.coefficient(4.0), 0.0);
        assert_eq!(d.coefficient(9.0), 0.0);
        assert!(d.validate(0.34).is_ok());
        assert!(d.validate(5.0).is_err());
        assert!(ContactDamping { eta: 1.0, ..d }.validate(0.34).is_err());
    }
}
