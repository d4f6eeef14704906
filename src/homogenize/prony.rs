//! Stress relaxation as a Prony series (seed (5.8); Abaqus/CalculiX `*VISCOELASTIC,
//! TIME=PRONY` data: gᵢ, kᵢ, τᵢ).
//!
//! The normalised shear and bulk relaxation moduli are
//!
//! g_R(t) = 1 − Σᵢ gᵢ(1 − e^(−t/τᵢ)),   k_R(t) = 1 − Σᵢ kᵢ(1 − e^(−t/τᵢ)).
//!
//! The seed's law μ(t) = μ₀(1 − μ̄(1 − e^(−t/τ))) relaxes shear and bulk alike, so it is the
//! one-term series g₁ = k₁ = μ̄, τ₁ = τ (seed values μ̄ = 0.4, τ = 3 s). A measured relaxation
//! curve is fitted with N terms by Levenberg–Marquardt (in gᵢ and ln τᵢ, plus the unrelaxed
//! stress when the curve is a stress rather than a normalised modulus); kᵢ = gᵢ, as in (5.8).

use super::curve::RelaxationCurve;
use crate::numerics::least_squares::{self as lsq, Problem};
use nalgebra::{DMatrix, DVector};

/// A Prony series; times in s.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Prony {
    /// shear relaxation ratios gᵢ
    pub g: Vec<f64>,
    /// bulk relaxation ratios kᵢ
    pub k: Vec<f64>,
    /// relaxation times τᵢ, s
    #[serde(rename = "tau_s")]
    pub tau: Vec<f64>,
}

/// Why a Prony series was refused or could not be fitted.
#[derive(Debug, Clone, thiserror::Error)]
pub enum PronyError {
    /// ratios or times out of range
    #[error("invalid Prony series: {0}")]
    Invalid(String),
    /// the least-squares fit failed
    #[error("Prony fit failed: {0}")]
    Fit(#[from] lsq::Error),
}

impl Prony {
    /// Build, checking equal lengths, gᵢ, kᵢ ≥ 0 with Σgᵢ < 1 and Σkᵢ < 1, τᵢ > 0.
    pub fn new(g: Vec<f64>, k: Vec<f64>, tau: Vec<f64>) -> Result<Self, PronyError> {
        let bad = |s: String| Err(PronyError::Invalid(s));
        if g.is_empty() || g.len() != k.len() || g.len() != tau.len() {
            return bad(format!(
                "g, k, tau need equal non-zero lengths ({}, {}, {})",
                g.len(),
                k.len(),
                tau.len()
            ));
        }
        if g.iter().chain(&k).chain(&tau).any(|x| !x.is_finite()) {
            return bad("a value is not finite".into());
        }
        if g.iter().chain(&k).any(|&x| x < 0.0)
            || g.iter().sum::<f64>() >= 1.0
            || k.iter().sum::<f64>() >= 1.0
        {
            return bad(format!(
                "need g, k >= 0 with sums below 1 (g = {g:?}, k = {k:?})"
            ));
        }
        if tau.iter().any(|&t| t <= 0.0) {
            return bad(format!("relaxation times must be positive (tau = {tau:?})"));
        }
        Ok(Prony { g, k, tau })
    }

    /// The seed's one-term law (5.8): g₁ = k₁ = μ̄, τ₁ = τ (s).
    pub fn from_relaxation(mu_bar: f64, tau: f64) -> Result<Self, PronyError> {
        Self::new(vec![mu_bar], vec![mu_bar], vec![tau])
    }

    /// Normalised shear relaxation modulus g_R(t).
    pub fn shear(&self, t: f64) -> f64 {
        relax(&self.g, &self.tau, t)
    }

    /// Normalised bulk relaxation modulus k_R(t).
    pub fn bulk(&self, t: f64) -> f64 {
        relax(&self.k, &self.tau, t)
    }
}

fn relax(ratios: &[f64], tau: &[f64], t: f64) -> f64 {
    1.0 + ratios
        .iter()
        .zip(tau)
        .map(|(g, tau)| g * (-t / tau).exp_m1())
        .sum::<f64>()
}

/// A fitted Prony series.
#[derive(Debug, Clone)]
pub struct PronyFit {
    /// the series (kᵢ = gᵢ)
    pub prony: Prony,
    /// standard errors of gᵢ and τᵢ (s); `None` for an exact or degenerate fit
    pub std_errors: Option<(Vec<f64>, Vec<f64>)>,
    /// the unrelaxed value σ(0) of a stress curve, GPa (1 for a normalised curve)
    pub unrelaxed: f64,
    /// ‖fit − data‖ / ‖data‖
    pub rms_rel: f64,
    /// solver diagnostics
    pub info: lsq::Info,
}

struct RelaxProblem<'a> {
    curve: &'a RelaxationCurve,
    terms: usize,
}

impl RelaxProblem<'_> {
    /// (scale, g, τ) from p = ([scale], g₁…g_N, ln τ₁…ln τ_N)
    fn unpack(&self, p: &[f64]) -> (f64, Vec<f64>, Vec<f64>) {
        let o = usize::from(!self.curve.normalised);
        let scale = if o == 1 { p[0] } else { 1.0 };
        let g = p[o..o + self.terms].to_vec();
        let tau = p[o + self.terms..].iter().map(|x| x.exp()).collect();
        (scale, g, tau)
    }
}

impl Problem for RelaxProblem<'_> {
    fn parameters(&self) -> usize {
        2 * self.terms + usize::from(!self.curve.normalised)
    }
    fn residuals(&self, p: &[f64]) -> Option<DVector<f64>> {
        let (scale, g, tau) = self.unpack(p);
        if scale <= 0.0 || g.iter().any(|&x| x < 0.0) || g.iter().sum::<f64>() >= 1.0 {
            return None;
        }
        let c = self.curve;
        Some(DVector::from_iterator(
            c.time.len(),
            c.time
                .iter()
                .zip(&c.value)
                .map(|(&t, &v)| scale * relax(&g, &tau, t) - v),
        ))
    }
    fn jacobian(&self, p: &[f64]) -> DMatrix<f64> {
        let (scale, g, tau) = self.unpack(p);
        let o = usize::from(!self.curve.normalised);
        let n = self.terms;
        DMatrix::from_fn(self.curve.time.len(), self.parameters(), |k, c| {
            let t = self.curve.time[k];
            if c < o {
                relax(&g, &tau, t)
            } else if c < o + n {
                scale * (-t / tau[c - o]).exp_m1()
            } else {
                let i = c - o - n;
                // ∂/∂ln τ of g e^(−t/τ) = g (t/τ) e^(−t/τ)
                scale * g[i] * (t / tau[i]) * (-t / tau[i]).exp()
            }
        })
    }
}

/// Fit an N-term series to a relaxation curve. Start: relaxation times spread geometrically
/// over the sampled times, the total relaxation split evenly.
pub fn fit_prony(
    curve: &RelaxationCurve,
    terms: usize,
    solver: &lsq::Params,
) -> Result<PronyFit, PronyError> {
    if terms == 0 || terms > 6 {
        return Err(PronyError::Invalid(format!(
            "{terms} terms; 1 to 6 allowed"
        )));
    }
    let problem = RelaxProblem { curve, terms };
    let (first, last) = (
        curve.value[0],
        *curve.value.last().unwrap_or(&curve.value[0]),
    );
    let scale0 = if curve.normalised { 1.0 } else { first };
    let total = (1.0 - last / scale0).clamp(0.05, 0.9);
    let t_lo = curve.time.iter().copied().find(|&t| t > 0.0).unwrap_or(1.0);
    let t_hi = *curve.time.last().unwrap_or(&1.0);
    let mut p = Vec::new();
    if !curve.normalised {
        p.push(scale0);
    }
    p.extend(std::iter::repeat_n(total / terms as f64, terms));
    for i in 0..terms {
        let f = (i as f64 + 1.0) / (terms as f64 + 1.0);
        p.push((t_lo.ln() * (1.0 - f) + t_hi.ln() * f).max(f64::MIN_POSITIVE.ln()));
    }
    let (p, info) = lsq::solve(&problem, &p, solver)?;
    let (scale, g, tau) = problem.unpack(&p);
    let o = usize::from(!curve.normalised);
    let std_errors = info.std_errors().map(|se| {
        let gs = se[o..o + terms].to_vec();
        let ts = (0..terms).map(|i| tau[i] * se[o + terms + i]).collect();
        (gs, ts)
    });
    let norm = curve.value.iter().map(|x| x * x).sum::<f64>().sqrt();
    Ok(PronyFit {
        prony: Prony::new(g.clone(), g, tau)?,
        std_errors,
        unrelaxed: scale,
        rms_rel: (2.0 * info.cost).sqrt() / norm,
        info,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_law_is_one_term_with_equal_shear_and_bulk() {
        let p = Prony::from_relaxation(0.4, 3.0).unwrap();
        assert_eq!(p.shear(0.0), 1.0);
        // μ(t)/μ₀ = 1 − μ̄(1 − e^(−t/τ)) (5.8)
        let t = 2.0;
        assert!((p.shear(t) - (1.0 - 0.4 * (1.0 - (-t / 3.0f64).exp()))).abs() < 1e-15);
        assert_eq!(p.shear(t), p.bulk(t));
        assert!((p.shear(1e6) - 0.6).abs() < 1e-15);
        assert!(Prony::from_relaxation(1.0, 3.0).is_err());
        assert!(Prony::from_relaxation(0.4, 0.0).is_err());
    }

    #[test]
    fn a_sampled_seed_curve_is_recovered_from_stress() {
        let law = Prony::from_relaxation(0.4, 3.0).unwrap();
        let time: Vec<f64> = (0..40).map(|i| 0.5 * i as f64).collect();
        let value = time.iter().map(|&t| 0.02 * law.shear(t)).collect();
        let c = RelaxationCurve {
            time,
            value,
            normalised: false,
        };
        let f = fit_prony(&c, 1, &lsq::Params::default()).unwrap();
        // noise-free data: solver tolerance only
        const EXACT_TOL: f64 = 1e-7;
        assert!((f.prony.g[0] - 0.4).abs() < EXACT_TOL, "{:?}", f.prony);
        assert!((f.prony.tau[0] - 3.0).abs() < EXACT_TOL * 3.0);
        assert!((f.unrelaxed - 0.02).abs() < EXACT_TOL * 0.02);
    }

    #[test]
    fn jacobian_is_exact() {
        let time: Vec<f64> = (0..8).map(|i| i as f64).collect();
        let c = RelaxationCurve {
            time,
            value: vec![1.0; 8],
            normalised: false,
        };
        let pr = RelaxProblem {
            curve: &c,
            terms: 2,
        };
        let p = [0.9, 0.2, 0.1, 0.5, 1.5];
        let j = pr.jacobian(&p);
        let h = 1e-6;
        for col in 0..5 {
            let (mut a, mut b) = (p, p);
            a[col] += h;
            b[col] -= h;
            let fd = (pr.residuals(&a).unwrap() - pr.residuals(&b).unwrap()) / (2.0 * h);
            for r in 0..8 {
                assert!((fd[r] - j[(r, col)]).abs() < 1e-8, "{r} {col}");
            }
        }
    }
}
