//! Thermal vibration of a free tube end (seed eq. 5.9, after Treacy, Ebbesen & Gibson, Nature
//! 381, 678, 1996): a hollow cylinder of length l, radii r_o > r_i, Young's modulus Y, clamped at
//! one end, has an RMS transverse tip amplitude
//!
//! u = (0.4243 l³ kT / (Y (r_o⁴ − r_i⁴)))^(1/2).
//!
//! Origin of 0.4243: by equipartition each bending mode n holds ½kT, so the tip variance is
//! kT Σₙ φₙ(l)²/(m ωₙ²) = kT·(static tip compliance) = kT l³/(3YI), with I = π(r_o⁴ − r_i⁴)/4
//! the axial second moment of area; hence u² = (4/(3π)) l³kT/(Y(r_o⁴ − r_i⁴)) and
//! 4/(3π) = 0.42441. Treacy et al. sum the modes as Σ βₙ⁻⁴ with βₙ the clamped–free
//! eigenvalues, 16/π·Σβₙ⁻⁴ = 0.4243 (rounded; the first mode alone gives 0.4178). The seed's
//! constant is kept.
//!
//! Units: lengths nm, Y in GPa, T in K, kT in aJ; u in nm.

use super::{positive, TheoryError};
use crate::units::BOLTZMANN_AJ_PER_K;

/// The seed's (Treacy et al.'s) mode-sum constant of eq. 5.9.
pub const MODE_SUM: f64 = 0.4243;

/// A hollow tube clamped at one end.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cantilever {
    /// free length l, nm
    pub length: f64,
    /// outer radius r_o, nm
    pub r_outer: f64,
    /// inner radius r_i (0 ≤ r_i < r_o), nm
    pub r_inner: f64,
    /// Young's modulus Y of the tube wall, GPa
    pub youngs: f64,
}

impl Cantilever {
    /// The seed's tube: l = 7 µm, r_o = 20 nm, r_i = 17.3 nm, Y = 0.4 TPa (seed §2.4, §5.2).
    pub fn seed() -> Self {
        Cantilever {
            length: 7000.0,
            r_outer: 20.0,
            r_inner: 17.3,
            youngs: 400.0,
        }
    }

    fn check(&self) -> Result<(), TheoryError> {
        positive("tube length l", self.length)?;
        positive("outer radius r_o", self.r_outer)?;
        positive("Young's modulus Y", self.youngs)?;
        if !(self.r_inner.is_finite() && self.r_inner >= 0.0 && self.r_inner < self.r_outer) {
            return Err(TheoryError::OutOfDomain {
                what: "inner radius r_i",
                value: self.r_inner,
                allowed: format!("0 ≤ r_i < r_o = {} nm", self.r_outer),
            });
        }
        Ok(())
    }

    /// Bending stiffness Y·I with I = π(r_o⁴ − r_i⁴)/4, nN·nm².
    pub fn bending_stiffness(&self) -> f64 {
        self.youngs * std::f64::consts::FRAC_PI_4 * (self.r_outer.powi(4) - self.r_inner.powi(4))
    }

    /// RMS tip amplitude u at temperature T (K), nm (seed 5.9).
    pub fn rms_tip_amplitude(&self, temperature: f64) -> Result<f64, TheoryError> {
        self.check()?;
        let kt = BOLTZMANN_AJ_PER_K * positive("temperature T", temperature)?;
        let r4 = self.r_outer.powi(4) - self.r_inner.powi(4);
        let u = (MODE_SUM * self.length.powi(3) * kt / (self.youngs * r4)).sqrt();
        if !u.is_finite() {
            return Err(TheoryError::NotFinite {
                what: "RMS tip amplitude u = (0.4243 l³ kT/(Y(r_o⁴ − r_i⁴)))^(1/2): the inputs \
                       overflow double precision, so u",
                value: u,
            });
        }
        Ok(u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_amplitude_beyond_double_precision_is_an_error() {
        let c = Cantilever {
            length: 1e300,
            ..Cantilever::seed()
        };
        let e = c.rms_tip_amplitude(300.0).unwrap_err();
        assert!(matches!(e, TheoryError::NotFinite { .. }), "{e}");
    }

    #[test]
    fn mode_sum_is_equipartition_on_the_static_compliance() {
        // u² = kT/k_tip with k_tip = 3YI/l³: the full mode sum is 4/(3π)
        let full = 4.0 / (3.0 * std::f64::consts::PI);
        assert!((MODE_SUM - full).abs() < 2e-4, "{full}");
        let c = Cantilever::seed();
        let kt = BOLTZMANN_AJ_PER_K * 300.0;
        let u_static = (kt * c.length.powi(3) / (3.0 * c.bending_stiffness())).sqrt();
        let u = c.rms_tip_amplitude(300.0).unwrap();
        // 0.4243 vs 4/(3π) = 0.424413: 2.7e-4 relative in u², 1.3e-4 in u
        assert!((u / u_static - 1.0).abs() < 2e-4);
    }

    #[test]
    fn bad_tubes_are_refused() {
        let mut c = Cantilever::seed();
        c.r_inner = 25.0;
        assert!(c.rms_tip_amplitude(300.0).is_err());
        assert!(Cantilever::seed().rms_tip_amplitude(-1.0).is_err());
    }
}
