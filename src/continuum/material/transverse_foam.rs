//! Transversely isotropic hyperfoam: the isotropic hyperfoam
//! ([`super::hyperfoam`]) as the matrix, plus a foam of the fibre stretch along the preferred
//! direction a — the tube axis, the FE's Z axis (the indentation axis) — and a longitudinal
//! shear term:
//!
//! ψ = ψ_hf(C) + Σⱼ kⱼ (I₄^(pⱼ) − 1 − pⱼ ln I₄) + (μ_s/2)(I₅ − I₄²)/I₄,
//!
//! kⱼ = 2μⱼ/αⱼ², pⱼ = αⱼ/2, I₄ = a·Ca = λ_a² (λ_a the fibre stretch), I₅ = a·C²a. The fibre
//! term is the hyperfoam's one-stretch function 2μ/α²(λ_a^α − 1 − α ln λ_a), so along a it adds
//! the nominal stress (2μⱼ/αⱼ)(λ_a^(αⱼ−1) − λ_a^(−1)) — the axial data's own form. I₅ − I₄² =
//! |Ca|² − (a·Ca)² is the squared component of Ca normal to a: it vanishes in every stretch
//! along and across a (uniaxial, lateral) and is C_RZ² in axisymmetry, so μ_s acts in
//! longitudinal shear alone. With no fibre terms and μ_s = 0 the model is the hyperfoam.
//!
//! Initial moduli with a matrix β = 0 (ν = 0): E_T = 2μ_m (across a), E_A = 2(μ_m + Σμⱼ) (along
//! a), G_T = μ_m, G_L = μ_m + μ_s, every Poisson ratio 0; positive definite iff μ_m > 0,
//! μ_m + Σμⱼ > 0, μ_m + μ_s > 0. The fibre term is convex in λ_a for α ≥ 1 and the shear term
//! (quadratic over linear in C) convex in C for μ_s ≥ 0; not polyconvex in F. Where the fit
//! leaves the model (docs/homogenize.md) its stability is checked along the fitted paths.
//!
//! Stress and tangent in the axisymmetric Voigt order (a = e_Z, slot 1 = ZZ, slot 3 = RZ):
//! S_ZZ += 2ψ_f′(I₄) − μ_s C_RZ²/I₄², S_RZ += μ_s C_RZ/I₄, 𝔺_ZZZZ += 4ψ_f″(I₄) + 4μ_s C_RZ²/I₄³,
//! 𝔺_ZZRZ = 𝔺_RZZZ += −2μ_s C_RZ/I₄², 𝔺_RZRZ += μ_s/I₄.

use super::hyperfoam::Hyperfoam;
use super::{finite, Deformation, Evaluated, Material, MaterialError};
use serde::{Deserialize, Serialize};

/// One fibre term: the hyperfoam's one-stretch function of λ_a.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FibreTerm {
    /// μⱼ, GPa
    pub mu: f64,
    /// αⱼ, dimensionless (non-zero)
    pub alpha: f64,
}

/// The transversely isotropic foam with its axis along Z.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransverseFoam {
    /// the isotropic matrix
    pub matrix: Hyperfoam,
    /// the fibre terms along the axis
    pub fibre: Vec<FibreTerm>,
    /// μ_s, the longitudinal shear term's modulus, GPa (G_L = μ_m + μ_s)
    pub shear: f64,
}

impl TransverseFoam {
    /// The matrix's initial shear modulus μ_m = Σμᵢ, GPa.
    fn matrix_mu(&self) -> f64 {
        self.matrix.terms.iter().map(|t| t.mu).sum()
    }

    /// Initial Young's modulus along the axis E_A = E_m + 2Σμⱼ (GPa) and the matrix's Poisson
    /// ratio: the axial stiffness a flat punch or sphere meets first.
    pub fn initial_moduli(&self) -> (f64, f64) {
        let (e, nu) = self.matrix.initial_moduli();
        (e + 2.0 * self.fibre.iter().map(|f| f.mu).sum::<f64>(), nu)
    }

    /// Initial longitudinal shear modulus G_L = μ_m + μ_s, GPa.
    pub fn longitudinal_shear_modulus(&self) -> f64 {
        self.matrix_mu() + self.shear
    }

    /// The matrix valid, every fibre α ≠ 0 with finite μ, μ_s finite, and the initial moduli
    /// along the axis and in longitudinal shear positive.
    pub fn validate(&self) -> Result<(), MaterialError> {
        self.matrix.validate()?;
        for f in &self.fibre {
            if !(f.alpha.abs() > 0.0 && f.alpha.is_finite() && f.mu.is_finite()) {
                return Err(MaterialError::Invalid(format!(
                    "fibre term needs finite μ and α ≠ 0, got μ = {}, α = {}",
                    f.mu, f.alpha
                )));
            }
        }
        let (e_a, _) = self.initial_moduli();
        let g_l = self.longitudinal_shear_modulus();
        if !(e_a > 0.0 && g_l > 0.0 && self.shear.is_finite()) {
            return Err(MaterialError::Invalid(format!(
                "transversely isotropic foam needs E_A > 0 and G_L = μ_m + μ_s > 0, got E_A = \
                 {e_a} GPa, G_L = {g_l} GPa"
            )));
        }
        Ok(())
    }
}

impl Material for TransverseFoam {
    fn response(&self, d: &Deformation, history: &[f64], dt: f64) -> Evaluated {
        let mut r = self.matrix.response(d, history, dt)?;
        let (i4, crz) = (d.c()[1], d.c()[3]);
        let ln_i4 = (2.0 * d.green()[1]).ln_1p();
        for f in &self.fibre {
            let k = 2.0 * f.mu / (f.alpha * f.alpha);
            let p = 0.5 * f.alpha;
            let ip = (p * ln_i4).exp();
            r.energy += k * crate::numerics::expm1_minus_x(p * ln_i4);
            // ψ′ = kp(I₄^(p−1) − 1/I₄), ψ″ = kp((p−1)I₄^(p−2) + 1/I₄²)
            r.stress[1] += 2.0 * k * p * (p * ln_i4).exp_m1() / i4;
            r.tangent[1][1] += 4.0 * k * p * ((p - 1.0) * ip + 1.0) / (i4 * i4);
        }
        let mu_s = self.shear;
        r.energy += 0.5 * mu_s * crz * crz / i4;
        r.stress[1] -= mu_s * crz * crz / (i4 * i4);
        r.stress[3] += mu_s * crz / i4;
        r.tangent[1][1] += 4.0 * mu_s * crz * crz / (i4 * i4 * i4);
        r.tangent[1][3] -= 2.0 * mu_s * crz / (i4 * i4);
        r.tangent[3][1] -= 2.0 * mu_s * crz / (i4 * i4);
        r.tangent[3][3] += mu_s / i4;
        finite(r, d)
    }
}

#[cfg(test)]
mod tests {
    use super::super::fd;
    use super::super::hyperfoam::HyperfoamTerm;
    use super::*;

    /// As the hyperfoam's: central differences at 1e-6 in E.
    const FD_TOL: f64 = 1e-6;

    /// A soft two-term matrix (one term compressible), two fibre terms, a shear term.
    fn foam(shear: f64) -> TransverseFoam {
        TransverseFoam {
            matrix: Hyperfoam {
                terms: vec![
                    HyperfoamTerm {
                        mu: 0.01,
                        alpha: 6.0,
                        beta: 0.0,
                    },
                    HyperfoamTerm {
                        mu: 0.002,
                        alpha: -2.0,
                        beta: 0.2,
                    },
                ],
            },
            fibre: vec![
                FibreTerm {
                    mu: 0.3,
                    alpha: 12.0,
                },
                FibreTerm {
                    mu: 0.05,
                    alpha: 2.5,
                },
            ],
            shear,
        }
    }

    #[test]
    fn stress_and_tangent_match_finite_differences() {
        for m in [foam(0.004), foam(-0.005)] {
            for c in [
                [0.8, 1.1, 0.95, 0.05],
                [1.02, 0.64, 1.02, -0.12], // compressed along the axis, sheared
                [0.7, 0.7, 1.05, 0.0],
                [1.0, 1.0, 1.0, 0.0],
                [1.0, 1.09, 1.0, 0.3], // simple shear γ = 0.3 at λ_z ≈ 1
            ] {
                let (es, ed) = fd::mismatch(&m, &c, &[], 0.0);
                assert!(es < FD_TOL && ed < FD_TOL, "{c:?}: {es} {ed}");
            }
        }
    }

    /// As the hyperfoam's: ψ from E keeps its relative precision down to strains of 1e-7.
    #[test]
    fn the_energy_of_a_small_strain_keeps_its_precision() {
        for size in [1e-3, 1e-5, 1e-7] {
            let mismatch = fd::quadratic_mismatch(&foam(0.004), fd::small_strain(size));
            assert!(mismatch < 20.0 * size, "{size:e}: {mismatch:e}");
        }
    }

    #[test]
    fn without_fibre_and_shear_terms_it_is_the_hyperfoam_bit_for_bit() {
        let mut m = foam(0.0);
        m.fibre.clear();
        for c in [[0.8, 1.1, 0.95, 0.05], [1.0, 1.0, 1.0, 0.0]] {
            let a = m.response(&Deformation::from_c(c), &[], 0.0).unwrap();
            let b = m
                .matrix
                .response(&Deformation::from_c(c), &[], 0.0)
                .unwrap();
            assert_eq!(a, b);
        }
    }

    #[test]
    fn initial_tangent_has_the_transversely_isotropic_moduli() {
        let m = foam(0.004);
        let r = m
            .response(&Deformation::from_c([1.0, 1.0, 1.0, 0.0]), &[], 0.0)
            .unwrap();
        let mu0 = 0.012;
        let k0 = 2.0 * 0.01 / 3.0 + 2.0 * 0.002 * (1.0 / 3.0 + 0.2);
        let lam = k0 - 2.0 * mu0 / 3.0;
        let tol = 1e-12;
        assert!((r.tangent[0][0] - (lam + 2.0 * mu0)).abs() < tol);
        assert!((r.tangent[1][1] - (lam + 2.0 * mu0 + 2.0 * 0.35)).abs() < tol);
        assert!((r.tangent[3][3] - (mu0 + 0.004)).abs() < tol);
        assert!((r.tangent[1][3]).abs() < tol && r.stress.iter().all(|s| s.abs() < tol));
        assert!(foam(-0.02).validate().is_err() && foam(-0.01).validate().is_ok());
    }
}
