//! A micromechanical model of the turf (seed §2.4, eqs. 2.8–2.14): the nominally vertical tubes
//! are n free segments of length l, each bent to a mean curvature κ, joined by n straight contact
//! patches of length a held by tube–tube adhesion.
//!
//! - strain energy (2.8): U = ½ n l K κ²
//! - total energy (2.9): E = ½ n l K κ² − ½ n a γ_L
//! - kinematics at constant structure (2.10–2.12): δκ = κ f(θ) δε, with the printed
//!   f(θ) = (φθ + sin θ)/(φ cos θ − sin θ), φ = a/l
//! - stress (2.13): σ = ∂E/∂ε = n l K κ² f(θ); threshold (2.14): σ₀ = n l K κ₀² f(θ)
//!
//! The printed f(θ) does not follow from the constant-length circular arc the text describes:
//! with θ = κl/2 and chord b = l sin θ/θ, (2.10) gives f = (φθ + sin θ)/(sin θ − θ cos θ) — the
//! printed numerator, another denominator — and the discrete rod follows that form
//! (docs/discrete-compression.md). Both are offered ([`ShapeFactor`]); the printed one stays the
//! default of `turf theory micromech` because it is the seed's equation.
//!
//! Symbols: K = Y·I the tube's bending stiffness (nN·nm²); γ_L the contact energy per unit
//! length of tube–tube contact (nN = nJ/m; the seed calls it γ); θ the angle of the segment
//! geometry of the seed's Fig 2.3 (lost from the text); ε the nominal compressive strain.
//! The seed counts n per unit mass, making E an energy per mass; here n is counted **per unit
//! volume** (1/nm³) so that E is an energy density (aJ/nm³ = GPa) and σ a stress in GPa —
//! divide by the turf's density for the seed's per-mass form. The printed f(θ) is positive only
//! for tan θ < φ, the arc's for 0 < θ < 4.4934 (tan θ = θ); outside, an error is returned.

use super::{positive, TheoryError};

/// The free segments and contacts of the idealised turf.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Segments {
    /// n: free segments (= contact patches) per unit volume, 1/nm³
    pub number_density: f64,
    /// l: free segment length, nm
    pub free_length: f64,
    /// a: contact patch length, nm
    pub contact_length: f64,
    /// K = Y·I: bending stiffness, nN·nm²
    pub bending_stiffness: f64,
    /// γ_L: contact energy per unit length, nN
    pub line_energy: f64,
}

impl Segments {
    /// φ = a/l.
    pub fn phi(&self) -> f64 {
        self.contact_length / self.free_length
    }

    /// Energy density E (2.9) at mean curvature κ (1/nm), GPa (= aJ/nm³).
    pub fn energy_density(&self, kappa: f64) -> f64 {
        let n = self.number_density;
        0.5 * n * self.free_length * self.bending_stiffness * kappa * kappa
            - 0.5 * n * self.contact_length * self.line_energy
    }

    /// Stress (2.13), GPa, compressive positive, at curvature κ (1/nm) and angle θ (rad), with
    /// the shape factor `shape`.
    pub fn stress(&self, kappa: f64, theta: f64, shape: ShapeFactor) -> Result<f64, TheoryError> {
        positive("segment density n", self.number_density)?;
        positive("free length l", self.free_length)?;
        positive("bending stiffness K", self.bending_stiffness)?;
        let f = shape.value(theta, self.phi())?;
        Ok(self.number_density * self.free_length * self.bending_stiffness * kappa * kappa * f)
    }

    /// Threshold stress σ₀ (2.14) at the initial curvature κ₀, GPa.
    pub fn threshold_stress(
        &self,
        kappa0: f64,
        theta: f64,
        shape: ShapeFactor,
    ) -> Result<f64, TheoryError> {
        self.stress(kappa0, theta, shape)
    }
}

/// The arc's f(θ) is positive below the first positive root of tan θ = θ.
const ARC_THETA_MAX: f64 = 4.493_409_457_909_064;

/// Which f(θ) of (2.11) relates the curvature to the strain at constant structure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeFactor {
    /// f(θ) = (φθ + sin θ)/(φ cos θ − sin θ), as printed (seed 2.12), for 0 ≤ θ with tan θ < φ
    Printed,
    /// f(θ) = (φθ + sin θ)/(sin θ − θ cos θ), the constant-length circular arc of half-angle θ
    /// with (2.10), for 0 < θ < 4.4934
    Arc,
}

impl ShapeFactor {
    /// f(θ) at φ = a/l.
    pub fn value(self, theta: f64, phi: f64) -> Result<f64, TheoryError> {
        positive("φ = a/l", phi)?;
        let (den, allowed) = match self {
            ShapeFactor::Printed => (
                phi * theta.cos() - theta.sin(),
                format!("0 ≤ θ < atan(φ) = {} rad, where f(θ) > 0", phi.atan()),
            ),
            ShapeFactor::Arc => (
                theta.sin() - theta * theta.cos(),
                format!("0 < θ < {ARC_THETA_MAX} rad (tan θ = θ), where f(θ) > 0"),
            ),
        };
        if !(theta.is_finite() && theta >= 0.0) || den <= 0.0 {
            return Err(TheoryError::OutOfDomain {
                what: "segment angle θ",
                value: theta,
                allowed,
            });
        }
        Ok((phi * theta + theta.sin()) / den)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segs() -> Segments {
        Segments {
            number_density: 1e-6,
            free_length: 500.0,
            contact_length: 200.0,
            bending_stiffness: 2.21e7,
            line_energy: 1.0,
        }
    }

    #[test]
    fn stress_is_the_strain_derivative_of_the_energy() {
        // at constant structure dκ/dε = κ f(θ) (2.11): κ(ε) = κ₀ exp(f ε); σ = dE/dε by FD
        let s = segs();
        let (k0, theta) = (1e-3, 0.2);
        for shape in [ShapeFactor::Printed, ShapeFactor::Arc] {
            let f = shape.value(theta, s.phi()).unwrap();
            let kappa = |eps: f64| k0 * (f * eps).exp();
            let e = 1e-6;
            let fd = (s.energy_density(kappa(e)) - s.energy_density(kappa(-e))) / (2.0 * e);
            let sigma = s.stress(k0, theta, shape).unwrap();
            // central difference: relative truncation ~(f e)² ~ 1e-12
            assert!((fd - sigma).abs() < 1e-8 * sigma, "{shape:?}: {fd} {sigma}");
        }
    }

    #[test]
    fn shape_factor_domain_and_limits() {
        let printed = |t, p| ShapeFactor::Printed.value(t, p);
        assert_eq!(printed(0.0, 0.4).unwrap(), 0.0);
        assert!(printed(0.5, 0.4).is_err()); // tan 0.5 > 0.4
        assert!(printed(0.3, 0.4).unwrap() > 0.0);
        assert!(printed(0.1, 0.0).is_err());
        let arc = |t, p| ShapeFactor::Arc.value(t, p);
        assert!(arc(0.0, 0.4).is_err()); // a straight segment cannot shorten at constant length
        assert!(arc(ARC_THETA_MAX + 1e-9, 0.4).is_err());
        // small θ: sin θ − θ cos θ ≈ θ³/3, so f ≈ 3(1 + φ)/θ² (relative error O(θ²))
        let (t, p) = (1e-3, 0.4);
        let small = 3.0 * (1.0 + p) / (t * t);
        assert!((arc(t, p).unwrap() / small - 1.0).abs() < 1e-6);
    }
}
