//! The transversely isotropic foam card in closed form along the turf's three
//! RVE tests, and its fit to them.
//!
//! The model (the FE's [`crate::continuum::material::transverse_foam`], axis a = the tube axis
//! z): ψ = ψ_hf(C; matrix) + Σⱼ 2μⱼ/αⱼ² (λ_a^αⱼ − 1 − αⱼ ln λ_a) + (μ_s/2)(I₅ − I₄²)/I₄, with
//! λ_a² = I₄ = a·Ca, I₅ = a·C²a, the matrix a hyperfoam with β = 0 (ν = 0, as the axial card's).
//! Nominal stresses, compression positive, in the deformations of [`crate::discrete::rve`] and
//! of the axial drive (every normal stress not driven vanishes):
//!
//! - **axial** F = diag(1, 1, λ), λ = 1 − ε: λ_x = λ_y = 1 exactly (each matrix term's lateral
//!   stress (2μ/α)(λₗ^(α−1) − λₗ^(−1)) vanishes at λₗ = 1), σ = −T_m(λ) − T_f(λ),
//!   T(λ) = Σ (2μ/α)(λ^(α−1) − λ^(−1)) over the matrix, resp. fibre, terms;
//! - **lateral** F = diag(λ, 1, λ_z), λ = 1 − ε: λ_z = 1 exactly, σ = −T_m(λ) — the matrix alone;
//! - **shear** F = [[1, 0, γ], [0, 1, 0], [0, 0, λ_z]], λ_z from P_zz = ∂ψ/∂λ_z = 0, τ = ∂ψ/∂γ.
//!   C's x–z block [[1, γ], [γ, γ² + λ_z²]] has eigenvalues c₁,₂ with c₁ + c₂ = s = 1 + γ² + λ_z²,
//!   c₁c₂ = λ_z²; with Γ_q = (c₁^q − c₂^q)/(c₁ − c₂) ([`crate::numerics::divided_power`]),
//!   ∂(c₁^p + c₂^p)/∂γ = 2pγ Γ_p and ∂/∂λ_z = 2pλ_z (Γ_p − Γ_(p−1)); the matrix's volumetric
//!   term is −(2μ/α) ln λ_z, the fibre's I₄ = γ² + λ_z², the shear term's (I₅ − I₄²)/I₄ = γ²/I₄.
//!
//! **Fit** ([`fit_transverse`]), in the order the tests separate the terms: the matrix to the
//! lateral curve (the hyperfoam fit, [`fit_hyperfoam`], β = 0); the fibre terms to the axial
//! curve minus the matrix's axial stress (the same fit: the fibre stress has the hyperfoam's
//! uniaxial form); μ_s to the shear curve by least squares — τ is linear in μ_s at fixed λ_z,
//! so μ_s and the λ_z of every point are iterated to a fixed point.

use super::curve::StressStrainCurve;
use super::fit_hyperfoam::{fit_hyperfoam, FitError, HyperfoamFitParams};
use super::hyperfoam::{Hyperfoam, HyperfoamError, HyperfoamTerm};
use crate::numerics::divided_power;

/// The transversely isotropic foam: matrix, fibre terms (held as a β = 0 hyperfoam whose
/// uniaxial stress is the fibre stress), longitudinal shear modulus.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TransverseFoam {
    /// the isotropic matrix (every β = 0)
    pub matrix: Hyperfoam,
    /// the fibre terms μⱼ, αⱼ (their β unused, 0)
    pub fibre: Hyperfoam,
    /// μ_s, GPa
    pub shear: f64,
}

/// Iterations of the shear test's λ_z bisection: halves [λ_lo, λ_hi] to round-off.
const BISECTIONS: usize = 200;
/// Fixed-point iterations of μ_s and λ_z before the fit gives up.
const SHEAR_ITERATIONS: usize = 100;
/// The fixed point is reached when μ_s changes by less than this relative amount.
const SHEAR_CONVERGED: f64 = 1e-13;

impl TransverseFoam {
    /// Initial moduli [E_A, E_T, G_L], GPa: along the axis 2(μ_m + Σμⱼ), across it 2μ_m, in
    /// longitudinal shear μ_m + μ_s.
    pub fn initial_moduli(&self) -> [f64; 3] {
        let mu_m: f64 = self.matrix.terms.iter().map(|t| t.mu).sum();
        let mu_f: f64 = self.fibre.terms.iter().map(|t| t.mu).sum();
        [2.0 * (mu_m + mu_f), 2.0 * mu_m, mu_m + self.shear]
    }

    /// Refuse a matrix with β ≠ 0 (the closed forms assume ν = 0).
    pub fn check(&self) -> Result<(), HyperfoamError> {
        if self.matrix.terms.iter().any(|t| t.beta != 0.0) {
            return Err(HyperfoamError::InvalidConstants(
                "the transversely isotropic foam's matrix needs β = 0 (ν = 0)".into(),
            ));
        }
        Ok(())
    }

    /// Axial nominal compressive stress at strain ε along the axis, GPa.
    pub fn axial_stress(&self, eps: f64) -> Result<f64, HyperfoamError> {
        let l = [1.0, 1.0, 1.0 - eps];
        Ok(-self.matrix.nominal_stress(l)?[2] - self.fibre.nominal_stress(l)?[2])
    }

    /// Lateral nominal compressive stress at strain ε across the axis, GPa.
    pub fn lateral_stress(&self, eps: f64) -> Result<f64, HyperfoamError> {
        Ok(-self.matrix.nominal_stress([1.0 - eps, 1.0, 1.0])?[0])
    }

    /// (∂ψ/∂γ, ∂ψ/∂λ_z) in the shear deformation, GPa, split as (without μ_s, per unit μ_s).
    fn shear_derivatives(&self, gamma: f64, lz: f64) -> Result<[[f64; 2]; 2], HyperfoamError> {
        let s = 1.0 + gamma * gamma + lz * lz;
        let r = (0.25 * s * s - lz * lz).max(0.0).sqrt();
        let (c1, c2) = (0.5 * s + r, lz * lz / (0.5 * s + r));
        let (mut dg, mut dl) = (0.0, 0.0);
        for t in &self.matrix.terms {
            let (k, p) = (2.0 * t.mu / (t.alpha * t.alpha), 0.5 * t.alpha);
            let gp = divided_power(c1, c2, p);
            dg += k * 2.0 * p * gamma * gp;
            dl += k * (2.0 * p * lz * (gp - divided_power(c1, c2, p - 1.0)) - t.alpha / lz);
        }
        let i4 = gamma * gamma + lz * lz;
        let la = i4.sqrt();
        // ψ_f′(I₄) = T_f(λ_a)/(2λ_a)
        let df = self.fibre.nominal_stress([1.0, 1.0, la])?[2] / (2.0 * la);
        dg += df * 2.0 * gamma;
        dl += df * 2.0 * lz;
        let unit = [gamma * lz * lz / (i4 * i4), -gamma * gamma * lz / (i4 * i4)];
        Ok([[dg, dl], unit])
    }

    /// λ_z at which P_zz = 0 in shear γ, with μ_s = `shear` (bisection: P_zz → −∞ as λ_z → 0
    /// through the matrix's −(2μ/α)/λ_z, and grows without bound for large λ_z).
    fn shear_height(&self, gamma: f64, shear: f64) -> Result<f64, HyperfoamError> {
        let pzz = |lz: f64| -> Result<f64, HyperfoamError> {
            let [[_, d], [_, u]] = self.shear_derivatives(gamma, lz)?;
            Ok(d + shear * u)
        };
        let (mut lo, mut hi) = (1e-3, 1.0);
        while pzz(hi)? < 0.0 {
            hi *= 2.0;
            if hi > 1e3 {
                return Err(HyperfoamError::InvalidConstants(format!(
                    "no stress-free height in shear γ = {gamma}: P_zz < 0 up to λ_z = 1000"
                )));
            }
        }
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if pzz(mid)? < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(0.5 * (lo + hi))
    }

    /// Nominal shear stress τ = P_xz (GPa) at shear γ, with the stress-free height λ_z.
    pub fn shear_stress(&self, gamma: f64) -> Result<(f64, f64), HyperfoamError> {
        self.check()?;
        let lz = self.shear_height(gamma, self.shear)?;
        let [[d, _], [u, _]] = self.shear_derivatives(gamma, lz)?;
        Ok((d + self.shear * u, lz))
    }
}

/// The card's file beside `material.json`.
pub const CARD_JSON: &str = "material_transverse.json";

/// Settings of [`fit_transverse`].
#[derive(Debug, Clone, Copy)]
pub struct TransverseFitParams {
    /// matrix terms (fitted to the lateral curve)
    pub matrix_terms: usize,
    /// fibre terms (fitted to the axial curve less the matrix)
    pub fibre_terms: usize,
    /// fit the data with 0 < ε ≤ this strain (each curve)
    pub strain_max: f64,
}

/// The fitted card and how well it fits each curve.
#[derive(Debug, Clone)]
pub struct TransverseFit {
    /// the card
    pub material: TransverseFoam,
    /// ‖σ_card − σ_data‖/‖σ_data‖ over the fitted points: axial, lateral, shear
    pub rms_rel: [f64; 3],
    /// what the fits warned of
    pub warnings: Vec<String>,
}

impl TransverseFit {
    /// The card as `material_transverse.json`: the model, its axis, the constants (GPa), the
    /// initial moduli, the fit's quality and warnings, and the three curves' `sources`
    /// (axial, lateral, shear).
    pub fn card_json(&self, sources: &[String; 3]) -> serde_json::Value {
        let m = &self.material;
        let terms = |h: &Hyperfoam| {
            h.terms
                .iter()
                .map(|t| serde_json::json!({"mu_GPa": t.mu, "alpha": t.alpha}))
                .collect::<Vec<_>>()
        };
        let [e_a, e_t, g_l] = m.initial_moduli();
        serde_json::json!({
            "model": "transverse_foam",
            "axis": "tube axis z (the FE's Z, the indentation axis)",
            "energy": "hyperfoam(matrix, beta = 0) + sum 2mu/alpha^2 (l_a^alpha - 1 - alpha ln l_a) \
                       + (mu_s/2)(I5 - I4^2)/I4",
            "matrix": terms(&m.matrix),
            "fibre": terms(&m.fibre),
            "shear_mu_GPa": m.shear,
            "initial_moduli_GPa": {"axial": e_a, "transverse": e_t, "longitudinal_shear": g_l},
            "fit_rms_rel": {"axial": self.rms_rel[0], "lateral": self.rms_rel[1],
                            "shear": self.rms_rel[2]},
            "warnings": self.warnings,
            "sources": {"axial": sources[0], "lateral": sources[1], "shear": sources[2]},
            "inp": "none: no CalculiX or Abaqus keyword has this energy (docs/homogenize.md)",
        })
    }
}

/// Why a `material_transverse.json` card is malformed; the message names the file and the field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CardJsonError {
    /// a number field is missing or not a number
    #[error("{src}: {key} is missing or not a number")]
    Number {
        /// the card's name
        src: String,
        /// the field
        key: String,
    },
    /// a list of terms is missing or not a list
    #[error("{src}: {key} is missing or not a list of terms")]
    Terms {
        /// the card's name
        src: String,
        /// the field
        key: String,
    },
}

/// The card of a `material_transverse.json` text ([`TransverseFit::card_json`]); `Ok(None)`
/// when the text is another card (not JSON, e.g. a `.inp`, or no `"model":
/// "transverse_foam"`: [`super::read_card`] reads those); an error naming `src` and the field
/// when it is this card but malformed.
pub fn parse_card_json(text: &str, src: &str) -> Result<Option<TransverseFoam>, CardJsonError> {
    let Ok(v) = serde_json::from_str::<serde_json::Value>(text) else {
        return Ok(None);
    };
    if v.get("model").and_then(|m| m.as_str()) != Some("transverse_foam") {
        return Ok(None);
    }
    let number = |x: &serde_json::Value, key: &str| {
        x.get(key)
            .and_then(serde_json::Value::as_f64)
            .ok_or_else(|| CardJsonError::Number {
                src: src.to_string(),
                key: key.to_string(),
            })
    };
    let terms = |key: &str| -> Result<Hyperfoam, CardJsonError> {
        let list = v
            .get(key)
            .and_then(serde_json::Value::as_array)
            .ok_or_else(|| CardJsonError::Terms {
                src: src.to_string(),
                key: key.to_string(),
            })?;
        let terms = list
            .iter()
            .map(|t| {
                Ok(HyperfoamTerm {
                    mu: number(t, "mu_GPa")?,
                    alpha: number(t, "alpha")?,
                    beta: 0.0,
                })
            })
            .collect::<Result<Vec<_>, CardJsonError>>()?;
        Ok(Hyperfoam { terms })
    };
    let card = TransverseFoam {
        matrix: terms("matrix")?,
        fibre: terms("fibre")?,
        shear: number(&v, "shear_mu_GPa")?,
    };
    Ok(Some(card))
}

fn fitted<'a>(
    curve: &'a StressStrainCurve,
    strain_max: f64,
) -> impl Iterator<Item = (f64, f64)> + 'a {
    curve
        .strain
        .iter()
        .zip(&curve.stress)
        .filter(move |(e, _)| **e > 0.0 && **e <= strain_max)
        .map(|(e, s)| (*e, *s))
}

fn rms_rel(
    curve: &StressStrainCurve,
    strain_max: f64,
    model: &dyn Fn(f64) -> Result<f64, HyperfoamError>,
) -> Result<f64, HyperfoamError> {
    let (mut num, mut den) = (0.0, 0.0);
    for (e, s) in fitted(curve, strain_max) {
        num += (model(e)? - s).powi(2);
        den += s * s;
    }
    Ok((num / den).sqrt())
}

/// Fit the card to the axial, lateral and shear curves (strain ε or γ, nominal stress GPa).
pub fn fit_transverse(
    axial: &StressStrainCurve,
    lateral: &StressStrainCurve,
    shear: &StressStrainCurve,
    params: &TransverseFitParams,
) -> Result<TransverseFit, FitError> {
    let hf = |terms| HyperfoamFitParams {
        terms,
        strain_max: params.strain_max,
        ..HyperfoamFitParams::default()
    };
    let no_lateral = |c: &StressStrainCurve| StressStrainCurve {
        lateral_strain: None,
        ..c.clone()
    };
    let matrix_fit = fit_hyperfoam(&no_lateral(lateral), &hf(params.matrix_terms))?;
    let matrix = matrix_fit.material.clone();
    let invalid = |e: HyperfoamError| FitError::Invalid(e.to_string());
    let residual: Vec<f64> = axial
        .strain
        .iter()
        .zip(&axial.stress)
        .map(|(&e, &s)| Ok(s + matrix.nominal_stress([1.0, 1.0, 1.0 - e])?[2]))
        .collect::<Result<_, HyperfoamError>>()
        .map_err(invalid)?;
    let fibre_curve =
        StressStrainCurve::new(axial.strain.clone(), residual, None, "axial − matrix")
            .map_err(|e| FitError::Invalid(e.to_string()))?;
    let fibre_fit = fit_hyperfoam(&fibre_curve, &hf(params.fibre_terms))?;
    let fibre = Hyperfoam {
        terms: fibre_fit
            .material
            .terms
            .iter()
            .map(|t| HyperfoamTerm { beta: 0.0, ..*t })
            .collect(),
    };
    let mut card = TransverseFoam {
        matrix,
        fibre,
        shear: 0.0,
    };
    let points: Vec<(f64, f64)> = fitted(shear, params.strain_max).collect();
    if points.is_empty() {
        return Err(FitError::Invalid(format!(
            "the shear curve has no point with 0 < γ ≤ {}",
            params.strain_max
        )));
    }
    let mut converged = false;
    for _ in 0..SHEAR_ITERATIONS {
        let (mut num, mut den) = (0.0, 0.0);
        for &(g, tau) in &points {
            let lz = card.shear_height(g, card.shear).map_err(invalid)?;
            let [[d, _], [u, _]] = card.shear_derivatives(g, lz).map_err(invalid)?;
            num += u * (tau - d);
            den += u * u;
        }
        let next = num / den;
        let done = (next - card.shear).abs() <= SHEAR_CONVERGED * next.abs().max(1e-300);
        card.shear = next;
        if done {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(FitError::Invalid(format!(
            "μ_s and the shear heights did not reach a fixed point in {SHEAR_ITERATIONS} \
             iterations (last μ_s = {} GPa)",
            card.shear
        )));
    }
    let rms = [
        rms_rel(axial, params.strain_max, &|e| card.axial_stress(e)).map_err(invalid)?,
        rms_rel(lateral, params.strain_max, &|e| card.lateral_stress(e)).map_err(invalid)?,
        rms_rel(shear, params.strain_max, &|g| Ok(card.shear_stress(g)?.0)).map_err(invalid)?,
    ];
    let mut warnings: Vec<String> = matrix_fit
        .warnings
        .iter()
        .map(|w| format!("matrix (lateral curve): {w}"))
        .chain(
            fibre_fit
                .warnings
                .iter()
                .map(|w| format!("fibre (axial curve less the matrix): {w}")),
        )
        .collect();
    let g_l: f64 = card.matrix.terms.iter().map(|t| t.mu).sum::<f64>() + card.shear;
    if g_l.is_nan() || g_l <= 0.0 {
        warnings.push(format!(
            "the longitudinal shear modulus μ_m + μ_s = {g_l} GPa is not positive: unstable"
        ));
    }
    Ok(TransverseFit {
        material: card,
        rms_rel: rms,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn card() -> TransverseFoam {
        let term = |mu, alpha| HyperfoamTerm {
            mu,
            alpha,
            beta: 0.0,
        };
        TransverseFoam {
            matrix: Hyperfoam {
                terms: vec![term(3e-5, 0.5)],
            },
            fibre: Hyperfoam {
                terms: vec![term(7e-3, 5.8), term(1e-3, 2.0)],
            },
            shear: 4.2e-3,
        }
    }

    #[test]
    fn the_card_file_reads_back_and_other_cards_are_left_to_the_isotropic_reader() {
        let m = card();
        let fit = TransverseFit {
            material: m.clone(),
            rms_rel: [0.1, 0.2, 0.03],
            warnings: Vec::new(),
        };
        let sources = [
            "a.csv".to_string(),
            "l.csv".to_string(),
            "s.csv".to_string(),
        ];
        let text = fit.card_json(&sources).to_string();
        assert_eq!(parse_card_json(&text, "t.json").unwrap(), Some(m));
        assert_eq!(
            parse_card_json("*MATERIAL, NAME=TURF", "m.inp").unwrap(),
            None
        );
        assert_eq!(
            parse_card_json("{\"format\": \"turf-material-card\"}", "m.json").unwrap(),
            None
        );
        let broken = text.replace("shear_mu_GPa", "shear");
        let e = parse_card_json(&broken, "t.json").unwrap_err().to_string();
        assert!(e.contains("t.json") && e.contains("shear_mu_GPa"), "{e}");
    }
}
