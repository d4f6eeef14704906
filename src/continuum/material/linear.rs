//! Linear elasticity: St Venant–Kirchhoff at finite deformation, Hooke under small kinematics.
//!
//! ψ = (λ/2)(tr E)² + μ E:E with E = (C − I)/2, so S = λ tr(E) I + 2μE and
//! 𝔺 = λ I⊗I + 2μ 𝕀. With the small-strain kinematics of [`crate::continuum::element`]
//! (C = I + 2ε) this is exactly Hooke's law σ = λ tr(ε) I + 2με.
//! Lamé constants from Young's modulus E and Poisson's ratio ν:
//! λ = Eν/((1+ν)(1−2ν)), μ = E/(2(1+ν)).
//!
//! St Venant–Kirchhoff has a limit point in compression: the uniaxial nominal stress
//! Eλ(λ² − 1)/2 is most compressive at λ² = 1/3 and returns to zero as λ → 0, so a crushed
//! element is a spurious stress-free equilibrium (a large first Newton step into contact can
//! land there: a Hertz run in 5 increments carried 27 % too little load). A point with a
//! principal value of C below [`SVK_MIN_STRETCH_SQUARED`] is therefore an error
//! ([`MaterialError::OutOfRange`]): the line search backs off, or the increment is cut back.
//! Under small kinematics the same bound is a strain of −1/3, far outside linear elasticity.

use super::{
    add_scaled, contract, finite, outer, sym_product, Deformation, Evaluated, Material,
    MaterialError, Response, Voigt, IDENTITY,
};
use serde::{Deserialize, Serialize};

/// Isotropic linear elasticity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinearElastic {
    /// Young's modulus E, GPa
    pub youngs: f64,
    /// Poisson's ratio ν, in (−1, 0.5)
    pub poisson: f64,
}

impl LinearElastic {
    /// Lamé constants (λ, μ), GPa.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.youngs, self.poisson);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }

    /// Check E > 0 and −1 < ν < 0.5.
    pub fn validate(&self) -> Result<(), MaterialError> {
        if !(self.youngs > 0.0 && self.youngs.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "Young's modulus must be positive, got {} GPa",
                self.youngs
            )));
        }
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(MaterialError::Invalid(format!(
                "Poisson's ratio must lie in (-1, 0.5), got {}",
                self.poisson
            )));
        }
        Ok(())
    }
}

/// The smallest principal value of C (stretch²) accepted: SVK's uniaxial limit point 1/3.
pub const SVK_MIN_STRETCH_SQUARED: f64 = 1.0 / 3.0;

/// The smallest principal value of C (in-plane block and hoop).
fn min_principal(c: &Voigt) -> f64 {
    let (m, d) = (0.5 * (c[0] + c[1]), 0.5 * (c[0] - c[1]));
    (m - d.hypot(c[3])).min(c[2])
}

impl Material for LinearElastic {
    fn response(&self, d: &Deformation, _history: &[f64], _dt: f64) -> Evaluated {
        d.ln_jacobian()?;
        let c_min = min_principal(d.c());
        if !(c_min >= SVK_MIN_STRETCH_SQUARED) {
            return Err(MaterialError::OutOfRange(format!(
                "St Venant–Kirchhoff compressed past its limit point (principal stretch² {c_min:.4} < 1/3)"
            )));
        }
        let (lam, mu) = self.lame();
        let e = d.green();
        let tr = e[0] + e[1] + e[2];
        let energy = 0.5 * lam * tr * tr + mu * contract(e, e);
        let mut stress = [0.0; 4];
        for i in 0..4 {
            stress[i] = lam * tr * IDENTITY[i] + 2.0 * mu * e[i];
        }
        let mut tangent = outer(&IDENTITY, &IDENTITY);
        tangent.iter_mut().flatten().for_each(|v| *v *= lam);
        add_scaled(&mut tangent, 2.0 * mu, &sym_product(&IDENTITY, &IDENTITY));
        finite(
            Response {
                energy,
                stress,
                tangent,
            },
            d,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::fd;
    use super::*;

    const FD_TOL: f64 = 1e-7; // central differences with step 1e-6 on a quadratic energy: round-off only

    #[test]
    fn stress_and_tangent_are_derivatives_of_the_energy() {
        let m = LinearElastic {
            youngs: 2.0,
            poisson: 0.3,
        };
        let (es, ed) = fd::mismatch(&m, &[1.2, 0.8, 1.1, 0.15], &[], 0.0);
        assert!(es < FD_TOL && ed < FD_TOL, "{es} {ed}");
    }

    #[test]
    fn uniaxial_small_strain_gives_youngs_modulus() {
        // σ_zz/ε_zz = E when the lateral strains are −νε (Hooke)
        let m = LinearElastic {
            youngs: 3.0,
            poisson: 0.25,
        };
        let eps = 1e-3;
        let lat = -0.25 * eps;
        let r = m
            .response(
                &Deformation::from_c([1.0 + 2.0 * lat, 1.0 + 2.0 * eps, 1.0 + 2.0 * lat, 0.0]),
                &[],
                0.0,
            )
            .unwrap();
        assert!((r.stress[1] - 3.0 * eps).abs() < 1e-14);
        assert!(r.stress[0].abs() < 1e-14 && r.stress[2].abs() < 1e-14);
    }

    #[test]
    fn inverted_point_is_an_error() {
        let m = LinearElastic {
            youngs: 1.0,
            poisson: 0.0,
        };
        assert!(matches!(
            m.response(&Deformation::from_c([1.0, 1.0, -1.0, 0.0]), &[], 0.0),
            Err(MaterialError::NonPositiveJ { .. })
        ));
        assert!(LinearElastic {
            youngs: 1.0,
            poisson: 0.5
        }
        .validate()
        .is_err());
    }

    #[test]
    fn compression_past_the_limit_point_is_an_error() {
        let m = LinearElastic {
            youngs: 1.0,
            poisson: 0.3,
        };
        // uniaxial: the nominal stress λS is most compressive at λ² = 1/3
        let nominal = |l2: f64| {
            l2.sqrt()
                * m.response(&Deformation::from_c([1.0, l2, 1.0, 0.0]), &[], 0.0)
                    .unwrap()
                    .stress[1]
        };
        assert!(nominal(0.34) < nominal(0.36) && nominal(0.34) < nominal(0.5));
        // a sheared point whose smallest principal value is below 1/3 (eigenvalues 1 ± 0.7)
        assert!(matches!(
            m.response(&Deformation::from_c([1.0, 1.0, 1.0, 0.7]), &[], 0.0),
            Err(MaterialError::OutOfRange(_))
        ));
        assert!(m
            .response(&Deformation::from_c([1.0, 1.0, 1.0, 0.6]), &[], 0.0)
            .is_ok());
    }
}
