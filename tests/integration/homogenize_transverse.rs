//! The transversely isotropic foam card (issue 19, item 3): the FE material point
//! (`continuum::material::transverse_foam`, written in C) against the card's closed forms in
//! the turf's three tests (`homogenize::transverse_foam`, written in principal stretches and
//! the shear test's F), and the fit recovering a card from the curves it generates.

use turf::continuum::material::hyperfoam as fe;
use turf::continuum::material::transverse_foam::{FibreTerm, TransverseFoam as FeFoam};
use turf::continuum::material::{Deformation, Material};
use turf::homogenize::curve::StressStrainCurve;
use turf::homogenize::hyperfoam::{Hyperfoam, HyperfoamTerm};
use turf::homogenize::transverse_foam::{fit_transverse, TransverseFitParams, TransverseFoam};

/// Closed-form agreement of the issue; both sides are exact, so only round-off (1e-13 of the
/// stress scale) and the shear test's bisection for λ_z (to round-off) remain.
const CLOSED_FORM_TOL: f64 = 1e-6;

/// A card shaped like the quickstart turf's: a soft matrix, a stiff fibre, a shear term.
fn card() -> TransverseFoam {
    let term = |mu, alpha| HyperfoamTerm {
        mu,
        alpha,
        beta: 0.0,
    };
    TransverseFoam {
        matrix: Hyperfoam {
            terms: vec![term(2e-4, 4.0), term(5e-5, 9.0)],
        },
        fibre: Hyperfoam {
            terms: vec![term(8e-3, 6.5)],
        },
        shear: 3e-3,
    }
}

/// The FE material of the same card.
fn fe_of(c: &TransverseFoam) -> FeFoam {
    FeFoam {
        matrix: fe::Hyperfoam {
            terms: c
                .matrix
                .terms
                .iter()
                .map(|t| fe::HyperfoamTerm {
                    mu: t.mu,
                    alpha: t.alpha,
                    beta: t.beta,
                })
                .collect(),
        },
        fibre: c
            .fibre
            .terms
            .iter()
            .map(|t| FibreTerm {
                mu: t.mu,
                alpha: t.alpha,
            })
            .collect(),
        shear: c.shear,
    }
}

fn close(a: f64, b: f64, scale: f64, what: &str) {
    assert!(
        (a - b).abs() <= CLOSED_FORM_TOL * scale,
        "{what}: FE {a:e}, closed form {b:e}"
    );
}

#[test]
fn the_fe_material_point_matches_the_closed_forms_of_the_three_tests() {
    let c = card();
    let m = fe_of(&c);
    for eps in [0.01, 0.1, 0.2, 0.3] {
        let l = 1.0 - eps;
        // axial: F = diag(1, 1, λ) in (R, Z, θ) = (x, z, y), P_ZZ = λ S_ZZ
        let r = m
            .response(&Deformation::from_c([1.0, l * l, 1.0, 0.0]), &[], 0.0)
            .unwrap();
        let sigma = c.axial_stress(eps).unwrap();
        close(-l * r.stress[1], sigma, sigma, "axial");
        close(r.stress[0], 0.0, sigma, "axial: lateral stress");
        // lateral: F = diag(λ, λ_z = 1, 1), P_RR = λ S_RR, no stress along the axis
        let r = m
            .response(&Deformation::from_c([l * l, 1.0, 1.0, 0.0]), &[], 0.0)
            .unwrap();
        let sigma = c.lateral_stress(eps).unwrap();
        close(-l * r.stress[0], sigma, sigma, "lateral");
        close(r.stress[1], 0.0, sigma, "lateral: axial stress");
        // shear: F = [[1, γ], [0, λ_z]] in (x, z), C = [1, γ² + λ_z², 1, γ];
        // P_xz = F_xx S_xz + F_xz S_zz and P_zz = λ_z S_zz = 0
        let g = eps;
        let (tau, lz) = c.shear_stress(g).unwrap();
        let r = m
            .response(
                &Deformation::from_c([1.0, g * g + lz * lz, 1.0, g]),
                &[],
                0.0,
            )
            .unwrap();
        close(r.stress[3] + g * r.stress[1], tau, tau, "shear");
        close(lz * r.stress[1], 0.0, tau, "shear: axial stress");
        assert!(lz < 1.0, "sheared fibres shorten the turf: λ_z = {lz}");
    }
}

#[test]
fn the_fit_recovers_the_card_that_made_the_curves() {
    let truth = TransverseFoam {
        matrix: Hyperfoam {
            terms: vec![HyperfoamTerm {
                mu: 2e-4,
                alpha: 4.0,
                beta: 0.0,
            }],
        },
        fibre: Hyperfoam {
            terms: vec![HyperfoamTerm {
                mu: 8e-3,
                alpha: 6.5,
                beta: 0.0,
            }],
        },
        shear: 3e-3,
    };
    let strain: Vec<f64> = (0..=30).map(|k| 0.01 * k as f64).collect();
    let curve = |f: &dyn Fn(f64) -> f64| {
        StressStrainCurve::new(
            strain.clone(),
            strain.iter().map(|&e| f(e)).collect(),
            None,
            "synthetic",
        )
        .unwrap()
    };
    let axial = curve(&|e| truth.axial_stress(e).unwrap());
    let lateral = curve(&|e| truth.lateral_stress(e).unwrap());
    let shear = curve(&|g| truth.shear_stress(g).unwrap().0);
    let fit = fit_transverse(
        &axial,
        &lateral,
        &shear,
        &TransverseFitParams {
            matrix_terms: 1,
            fibre_terms: 1,
            strain_max: 0.3,
        },
    )
    .unwrap();
    eprintln!("{:?} rms {:?}", fit.material, fit.rms_rel);
    let m = &fit.material;
    // exact data: the fits reach the least-squares solver's tolerance
    let tol = 1e-6;
    assert!((m.matrix.terms[0].mu / 2e-4 - 1.0).abs() < tol);
    assert!((m.matrix.terms[0].alpha / 4.0 - 1.0).abs() < tol);
    assert!((m.fibre.terms[0].mu / 8e-3 - 1.0).abs() < tol);
    assert!((m.fibre.terms[0].alpha / 6.5 - 1.0).abs() < tol);
    assert!((m.shear / 3e-3 - 1.0).abs() < tol, "μ_s = {}", m.shear);
    assert!(fit.rms_rel.iter().all(|r| *r < tol), "{:?}", fit.rms_rel);
}
