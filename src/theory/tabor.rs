//! Tabor's parameter μ and Maugis' λ: which adhesion model applies.
//!
//! - Tabor (seed 3.9, corrected — the seed prints E\* where E\*² belongs, PHYSICS.md):
//!   μ = (Rγ²/(E\*² z₀³))^(1/3), dimensionless. DMT holds for μ ≲ 0.1, JKR for μ ≳ 5.
//! - Maugis (seed 3.10): λ = σ₀ (9R/(2πγE\*²))^(1/3), with σ₀ the Dugdale stress. Here σ₀ is
//!   always taken from the force law actually used, σ₀ = −min p ([`SurfaceLaw::max_tension`]),
//!   so λ/μ = (σ₀z₀/γ)(9/(2π))^(1/3) depends only on the law's shape: 1.1573 for LJ 9-3
//!   (σ₀ = 16γ/(9√3 z₀)), about 1.65 for LJ 10-4 ([`lambda_per_mu`]).
//!
//! Units: R, z₀ in nm; E\*, σ₀ in GPa; γ in J/m².

use super::{positive, Sphere, TheoryError};
use crate::laws::{LennardJones, LjKind, SurfaceLaw};
use std::f64::consts::PI;

/// Tabor's μ = (Rγ²/(E\*² z₀³))^(1/3).
pub fn tabor_mu(s: &Sphere, z0: f64) -> Result<f64, TheoryError> {
    let z0 = positive("equilibrium separation z₀", z0)?;
    Ok(mu_of(s, z0))
}

/// Tabor's μ of inputs the caller has validated (R, E\*, γ, z₀ positive and finite).
pub fn mu_of(s: &Sphere, z0: f64) -> f64 {
    (s.radius * s.gamma * s.gamma / (s.modulus * s.modulus * z0.powi(3))).cbrt()
}

/// Maugis' λ = σ₀ (9R/(2πγE\*²))^(1/3) for a Dugdale stress σ₀ (GPa).
pub fn maugis_lambda(s: &Sphere, sigma0: f64) -> Result<f64, TheoryError> {
    let sigma0 = positive("Dugdale stress σ₀", sigma0)?;
    Ok(sigma0 * (9.0 * s.radius / (2.0 * PI * s.gamma * s.modulus * s.modulus)).cbrt())
}

/// Maugis' λ with σ₀ the maximum tension of `law` (its γ replaces the sphere's).
pub fn lambda_from_law(s: &Sphere, law: &SurfaceLaw) -> Result<f64, TheoryError> {
    let s = Sphere::new(s.radius, s.modulus, law.gamma())?;
    maugis_lambda(&s, law.max_tension())
}

/// The ratio λ/μ of a Lennard-Jones law: (σ₀z₀/γ)(9/(2π))^(1/3).
pub fn lambda_per_mu(kind: LjKind) -> f64 {
    let unit = LennardJones::new(kind, 1.0, 1.0);
    unit.max_tension() * (9.0 / (2.0 * PI)).cbrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambda_is_1_16_mu_for_lj93() {
        let r = lambda_per_mu(LjKind::Lj93);
        let closed = 16.0 / (9.0 * 3f64.sqrt()) * (9.0 / (2.0 * PI)).cbrt();
        assert!((r - closed).abs() < 1e-12);
        assert!((r - 1.16).abs() < 0.005, "{r}");
        let s = Sphere::new(1800.0, 1.0, 0.46).unwrap();
        let law = SurfaceLaw::from(LennardJones::new(LjKind::Lj93, 0.46, 0.34));
        let (mu, lambda) = (
            tabor_mu(&s, 0.34).unwrap(),
            lambda_from_law(&s, &law).unwrap(),
        );
        assert!((lambda / mu - r).abs() < 1e-12);
    }

    #[test]
    fn mu_is_dimensionless() {
        // scaling every length by c and every stress by 1/c leaves μ alone only if μ is built
        // as (Rγ²/(E*²z₀³))^(1/3): γ ~ stress·length is invariant, R/z₀³ ~ 1/c², E*² ~ 1/c²
        let c = 7.0;
        let s1 = Sphere::new(100.0, 2.0, 0.3).unwrap();
        let s2 = Sphere::new(100.0 * c, 2.0 / c, 0.3).unwrap();
        let (m1, m2) = (tabor_mu(&s1, 0.5).unwrap(), tabor_mu(&s2, 0.5 * c).unwrap());
        assert!((m1 - m2).abs() < 1e-12 * m1);
    }
}
