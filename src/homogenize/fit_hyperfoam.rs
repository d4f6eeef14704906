//! Fitting an N-term hyperfoam (N = 1…3) to uniaxial compression data (seed §5.1, Table 5.1).
//!
//! **Compressibility.** All terms share one β = ν/(1 − 2ν). Then the stress-free lateral stretch
//! of a uniaxial test is exactly λₗ = λ^(−ν) (each term's lateral stress λₗ^α − J^(−αβ) vanishes
//! when λₗ = J^(−β)), so lateral-strain data fix ν by the linear least-squares fit
//! ln λₗ = −ν ln λ; without lateral data ν = β = 0 (the seed's choice: no lateral strain).
//!
//! **Axial stress.** With that λₗ the nominal stress is, compression positive (λ = 1 − ε),
//!
//! σ(ε) = −Σᵢ (2μᵢ/αᵢ)(λ^(αᵢ−1) − λ^(−αᵢν−1)),   E⁰ = dσ/dε(0) = 2(1 + ν)Σμᵢ,
//!
//! which for ν = 0 is (5.7). μ and α are fitted by Levenberg–Marquardt on σ over the data with
//! 0 < ε ≤ `strain_max`. Stability is kept by construction: every μᵢ > 0, αᵢ > 0 (the fit runs
//! in ln μ, ln α), so each term stiffens and μ₀, K₀ > 0; the result is then checked for
//! monotonic uniaxial response and Drucker stability (uniaxial, equibiaxial, hydrostatic) over
//! the fitted stretch range, with a warning wherever that fails.
//!
//! **Pinning E⁰.** When the initial modulus is known (an idealised tangent law), Σμᵢ is held at
//! E⁰/(2(1 + ν)) and only the split between terms (softmax weights) and the αᵢ are fitted: this
//! is how Table 5.1 has μ = 350 MPa = E⁰/2 for every ε₀.
//!
//! **Starting values.** For fixed α the stress is linear in μ: every combination of N distinct
//! α from a geometric grid is tried with μ from linear least squares (variable projection), and
//! the best combination with all μᵢ > 0 starts the nonlinear fit.
//!
//! **Uncertainty.** Standard errors of μᵢ, αᵢ from the covariance of the fit (delta method
//! through the parametrisation), conditional on ν; the standard error of ν from its own fit.

use super::curve::StressStrainCurve;
use super::hyperfoam::{beta_from_nu, Hyperfoam, Mode};
use crate::numerics::least_squares::{self as lsq, Problem};
use nalgebra::{DMatrix, DVector};

/// The largest N this fit handles (CalculiX reads N ≤ 3).
pub const MAX_FIT_TERMS: usize = 3;

/// Default upper end of the fitted strain range. The seed does not state its range; fitting
/// N = 1 with μ = E⁰/2 to the tangent law over 0 < ε ≤ 0.3 reproduces Table 5.1's α (18.8, 14.5,
/// 12.0, 9.1) within 2.4 % for all four ε₀, and 0.29–0.35 all stay within 2.5 %: see
/// docs/homogenize.md for the scan.
pub const DEFAULT_STRAIN_MAX: f64 = 0.3;

/// Settings of [`fit_hyperfoam`].
#[derive(Debug, Clone, Copy)]
pub struct HyperfoamFitParams {
    /// number of terms N, 1 to [`MAX_FIT_TERMS`]
    pub terms: usize,
    /// fit the data with 0 < ε ≤ this nominal compressive strain
    pub strain_max: f64,
    /// hold the initial Young's modulus E⁰ (GPa) fixed, or fit it (`None`)
    pub initial_modulus: Option<f64>,
    /// the least-squares solver's settings
    pub solver: lsq::Params,
}

impl Default for HyperfoamFitParams {
    fn default() -> Self {
        HyperfoamFitParams {
            terms: 1,
            strain_max: DEFAULT_STRAIN_MAX,
            initial_modulus: None,
            solver: lsq::Params::default(),
        }
    }
}

/// Standard errors of the fitted constants.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HyperfoamStdErrors {
    /// of μᵢ, GPa
    #[serde(rename = "mu_GPa")]
    pub mu: Vec<f64>,
    /// of αᵢ
    pub alpha: Vec<f64>,
    /// of β (common to all terms; 0 when ν was not fitted)
    pub beta: f64,
}

/// A fitted hyperfoam and how well it fits.
#[derive(Debug, Clone)]
pub struct HyperfoamFit {
    /// the material
    pub material: Hyperfoam,
    /// ν = β/(1 + 2β), common to all terms
    pub nu: f64,
    /// standard errors; `None` when the covariance does not exist (exact or degenerate fit)
    pub std_errors: Option<HyperfoamStdErrors>,
    /// number of data points fitted
    pub points: usize,
    /// upper end of the fitted strain range
    pub strain_max: f64,
    /// ‖σ_fit − σ_data‖ / ‖σ_data‖ over the fitted points
    pub rms_rel: f64,
    /// max |σ_fit − σ_data| / max σ_data over the fitted points
    pub max_rel: f64,
    /// stability and fit-quality warnings (empty when all checks pass), including why fewer
    /// terms than requested were kept
    pub warnings: Vec<String>,
    /// the number of terms asked for; `material.terms.len()` is the number used
    pub terms_requested: usize,
    /// solver diagnostics
    pub info: lsq::Info,
}

/// Why a hyperfoam fit failed.
#[derive(Debug, Clone, thiserror::Error)]
pub enum FitError {
    /// inconsistent settings or too little data
    #[error("hyperfoam fit: {0}")]
    Invalid(String),
    /// the least-squares solver failed
    #[error("hyperfoam fit failed: {0}")]
    Solver(#[from] lsq::Error),
}

/// σ(ε) of one term with unit μ and its derivative in α (common ν): returns (b, ∂b/∂α) with
/// σ = Σ μᵢ b(αᵢ).
fn basis(eps: f64, alpha: f64, nu: f64) -> (f64, f64) {
    let l = 1.0 - eps;
    let ln_l = l.ln();
    let (p, q) = (l.powf(alpha - 1.0), l.powf(-alpha * nu - 1.0));
    let b = -2.0 / alpha * (p - q);
    let db = 2.0 / (alpha * alpha) * (p - q) - 2.0 / alpha * (ln_l * p + nu * ln_l * q);
    (b, db)
}

/// How the parameter vector p maps to θ = (μ₁…μ_N, α₁…α_N).
#[derive(Debug, Clone, Copy)]
struct Layout {
    terms: usize,
    /// Σμ held at this value (GPa)
    mu_sum: Option<f64>,
}

impl Layout {
    fn len(&self) -> usize {
        match self.mu_sum {
            None => 2 * self.terms,
            Some(_) => 2 * self.terms - 1,
        }
    }
    /// θ and G = ∂θ/∂p.
    fn unpack(&self, p: &[f64]) -> (Vec<f64>, Vec<f64>, DMatrix<f64>) {
        let n = self.terms;
        let mut g = DMatrix::zeros(2 * n, self.len());
        let off = self.len() - n; // α block starts here in p
        let alpha: Vec<f64> = (0..n).map(|i| p[off + i].exp()).collect();
        for i in 0..n {
            g[(n + i, off + i)] = alpha[i];
        }
        let mu = match self.mu_sum {
            None => {
                let mu: Vec<f64> = (0..n).map(|i| p[i].exp()).collect();
                for i in 0..n {
                    g[(i, i)] = mu[i];
                }
                mu
            }
            Some(total) => {
                // softmax over (s₁…s_{N−1}, 0)
                let s: Vec<f64> = (0..n).map(|i| if i + 1 < n { p[i] } else { 0.0 }).collect();
                let smax = s.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                let e: Vec<f64> = s.iter().map(|x| (x - smax).exp()).collect();
                let z: f64 = e.iter().sum();
                let w: Vec<f64> = e.iter().map(|x| x / z).collect();
                for i in 0..n {
                    for j in 0..n - 1 {
                        let kron = if i == j { 1.0 } else { 0.0 };
                        g[(i, j)] = total * w[i] * (kron - w[j]);
                    }
                }
                w.iter().map(|wi| total * wi).collect()
            }
        };
        (mu, alpha, g)
    }
    /// p from θ (inverse of `unpack`).
    fn pack(&self, mu: &[f64], alpha: &[f64]) -> Vec<f64> {
        let n = self.terms;
        let mut p = match self.mu_sum {
            None => mu.iter().map(|m| m.ln()).collect::<Vec<_>>(),
            Some(_) => (0..n - 1).map(|i| (mu[i] / mu[n - 1]).ln()).collect(),
        };
        p.extend(alpha.iter().map(|a| a.ln()));
        p
    }
}

struct UniaxialProblem<'a> {
    strain: &'a [f64],
    stress: &'a [f64],
    nu: f64,
    layout: Layout,
}

impl UniaxialProblem<'_> {
    /// residuals and ∂r/∂θ
    fn eval(&self, mu: &[f64], alpha: &[f64], with_jac: bool) -> (DVector<f64>, DMatrix<f64>) {
        let (m, n) = (self.strain.len(), self.layout.terms);
        let mut r = DVector::zeros(m);
        let mut jt = DMatrix::zeros(if with_jac { m } else { 0 }, 2 * n);
        for (k, (&e, &s)) in self.strain.iter().zip(self.stress).enumerate() {
            let mut model = 0.0;
            for i in 0..n {
                let (b, db) = basis(e, alpha[i], self.nu);
                model += mu[i] * b;
                if with_jac {
                    jt[(k, i)] = b;
                    jt[(k, n + i)] = mu[i] * db;
                }
            }
            r[k] = model - s;
        }
        (r, jt)
    }
}

impl Problem for UniaxialProblem<'_> {
    fn parameters(&self) -> usize {
        self.layout.len()
    }
    fn residuals(&self, p: &[f64]) -> Option<DVector<f64>> {
        let (mu, alpha, _) = self.layout.unpack(p);
        let total: f64 = mu.iter().sum();
        let admissible = alpha
            .iter()
            .all(|a| (ALPHA_RANGE.0..=ALPHA_RANGE.1).contains(a))
            && mu.iter().all(|&m| m >= MU_SHARE_MIN * total);
        admissible.then(|| self.eval(&mu, &alpha, false).0)
    }
    fn jacobian(&self, p: &[f64]) -> DMatrix<f64> {
        let (mu, alpha, g) = self.layout.unpack(p);
        self.eval(&mu, &alpha, true).1 * g
    }
}

/// The α grid of the start search: geometric, 0.5 to ~60.
fn alpha_grid() -> Vec<f64> {
    (0..20).map(|k| 0.5 * 1.29f64.powi(k)).collect()
}

/// All N-subsets of the grid, descending α within each.
fn combinations(grid: &[f64], n: usize) -> Vec<Vec<f64>> {
    if n == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for (i, &a) in grid.iter().enumerate().rev() {
        for mut rest in combinations(&grid[..i], n - 1) {
            rest.insert(0, a);
            out.push(rest);
        }
    }
    out
}

/// Admissible α during the fit: beyond these a term is numerically a step function or a
/// constant, and the fit would run away (α → ∞ with μ → 0) instead of converging.
const ALPHA_RANGE: (f64, f64) = (1e-2, 1e3);
/// Smallest share of Σμ a term may take during the fit (a vanishing term is degenerate).
const MU_SHARE_MIN: f64 = 1e-8;

/// Share of Σμ below which a fitted term counts as negligible (a candidate for dropping): the
/// quickstart's degenerate two-term card had 1e-3.
const NEGLIGIBLE_SHARE: f64 = 1e-2;

/// A degenerate N-term fit is replaced by the (N−1)-term fit unless it lowers the relative RMS
/// misfit by more than this fraction (a small term that does real work is kept).
const REDUNDANT_GAIN: f64 = 0.05;

/// Relative RMS misfit below which two fits count as equal whatever their ratio: round-off and
/// solver tolerance (exact data fit to ~1e-16).
const RMS_ROUNDOFF: f64 = 1e-9;

/// Relative distance from an end of [`ALPHA_RANGE`] within which α counts as pinned there.
const AT_BOUND: f64 = 1e-2;

/// Share of Σμ given to the new term of a nested start.
const NESTED_SHARE: f64 = 1e-3;

/// Smallest share of the mean μ a start term gets when the linear optimum is not positive.
const START_MU_FLOOR: f64 = 1e-3;

/// μ for fixed α by linear least squares (Σμ pinned when asked, then only approximately when a
/// term had to be clamped); `None` when Σμ ≤ 0.
fn linear_mu(
    strain: &[f64],
    stress: &[f64],
    alpha: &[f64],
    nu: f64,
    mu_sum: Option<f64>,
) -> Option<(Vec<f64>, f64)> {
    let (m, n) = (strain.len(), alpha.len());
    let b = DMatrix::from_fn(m, n, |k, i| basis(strain[k], alpha[i], nu).0);
    let y = DVector::from_column_slice(stress);
    let mu: Vec<f64> = match mu_sum {
        None => {
            let sol = b.clone().svd(true, true).solve(&y, 1e-14).ok()?;
            sol.iter().copied().collect()
        }
        Some(total) => {
            // μ_N = total − Σ_{i<N} μᵢ: y − total·b_N = Σ_{i<N} μᵢ (bᵢ − b_N)
            let last = b.column(n - 1).into_owned();
            let rhs = &y - &last * total;
            if n == 1 {
                vec![total]
            } else {
                let a = DMatrix::from_fn(m, n - 1, |k, i| b[(k, i)] - last[k]);
                let sol = a.svd(true, true).solve(&rhs, 1e-14).ok()?;
                let mut v: Vec<f64> = sol.iter().copied().collect();
                v.push(total - v.iter().sum::<f64>());
                v
            }
        }
    };
    // A negative μᵢ is clamped to a small positive share (the nonlinear fit then decides):
    // a start must exist even when the unconstrained optimum leaves the admissible set.
    let total: f64 = mu.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let floor = START_MU_FLOOR * total / n as f64;
    let mut mu: Vec<f64> = mu.iter().map(|&x| x.max(floor)).collect();
    if let Some(total) = mu_sum {
        let sum: f64 = mu.iter().sum();
        mu.iter_mut().for_each(|x| *x *= total / sum);
    }
    let r = b * DVector::from_column_slice(&mu) - y;
    Some((mu, r.norm_squared()))
}

/// ν from lateral data: least squares of ln(1 + εₗ) = −ν ln(1 − ε) through the origin; returns
/// (ν, its standard error).
fn fit_nu(strain: &[f64], lateral: &[f64]) -> Result<(f64, f64), FitError> {
    let x: Vec<f64> = strain.iter().map(|e| (1.0 - e).ln()).collect();
    let y: Vec<f64> = lateral.iter().map(|l| (1.0 + l).ln()).collect();
    let sxx: f64 = x.iter().map(|v| v * v).sum();
    let nu = -x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>() / sxx;
    let m = x.len();
    let ssr: f64 = x.iter().zip(&y).map(|(a, b)| (b + nu * a).powi(2)).sum();
    let se = if m > 1 {
        (ssr / (m - 1) as f64 / sxx).sqrt()
    } else {
        0.0
    };
    if !(nu > -1.0 && nu < 0.5) {
        return Err(FitError::Invalid(format!(
            "lateral strain gives nu = {nu:.4}, outside the admissible (-1, 0.5)"
        )));
    }
    Ok((nu, se))
}

/// Fit an N-term hyperfoam to a compressive curve (lateral strain, if present, fixes β).
pub fn fit_hyperfoam(
    curve: &StressStrainCurve,
    params: &HyperfoamFitParams,
) -> Result<HyperfoamFit, FitError> {
    let n = params.terms;
    let FitData {
        strain,
        stress,
        nu,
        nu_se,
        layout,
    } = fit_data(curve, params)?;
    let mu_sum = layout.mu_sum;
    let problem = UniaxialProblem {
        strain: &strain,
        stress: &stress,
        nu,
        layout,
    };
    // Nested start: the (N−1)-term fit plus a small new term at each grid α, so that adding a
    // term never starts worse than the fit with one term fewer.
    let fewer = if n > 1 {
        Some(fit_hyperfoam(
            curve,
            &HyperfoamFitParams {
                terms: n - 1,
                ..*params
            },
        )?)
    } else {
        None
    };
    let (mu0, alpha0) = start(&problem, fewer.as_ref())?;
    let (p, info) = match lsq::solve(&problem, &layout.pack(&mu0, &alpha0), &params.solver) {
        Ok(x) => x,
        Err(lsq::Error::NoConvergence { iterations, .. }) if fewer.is_some() => {
            // degenerate valleys (two terms merging) converge slowly: keep the converged
            // (N−1)-term fit and say so
            let why = format!(
                "the {n}-term fit did not converge in {iterations} iterations (the data do not support {n} terms)"
            );
            return Ok(with_fewer_terms(fewer.expect("checked"), n, why));
        }
        Err(e) => return Err(e.into()),
    };
    let (mu, alpha, g) = layout.unpack(&p);
    let beta = beta_from_nu(nu);
    let material = Hyperfoam::new(&mu, &alpha, &vec![beta; n])
        .map_err(|e| FitError::Invalid(e.to_string()))?;
    let std_errors = std_errors(&info, &g, n, nu, nu_se);
    let (r, _) = problem.eval(&mu, &alpha, false);
    let norm = stress.iter().map(|x| x * x).sum::<f64>().sqrt();
    let peak = stress.iter().cloned().fold(0.0, f64::max);
    let rms_rel = r.norm() / norm;
    if let Some(why) = redundancy(&mu, &alpha) {
        let no_better =
            |f: &HyperfoamFit| f.rms_rel <= rms_rel * (1.0 + REDUNDANT_GAIN) + RMS_ROUNDOFF;
        if let Some(f) = fewer.filter(no_better) {
            let why = format!(
                "the {n}-term fit is degenerate ({why}) and fits no better: relative RMS misfit \
                 {:.2} % with {n} terms, {:.2} % with {}",
                100.0 * rms_rel,
                100.0 * f.rms_rel,
                f.material.terms.len()
            );
            return Ok(with_fewer_terms(f, n, why));
        }
    }
    let mut warnings = stability_warnings(&material, params.strain_max);
    warnings.extend(bound_warnings(&alpha));
    if mu_sum.is_none() {
        warnings.extend(unresolved_e0(&material, &strain, &stress));
    }
    Ok(HyperfoamFit {
        material,
        nu,
        std_errors,
        points: strain.len(),
        strain_max: params.strain_max,
        rms_rel,
        max_rel: r.amax() / peak,
        warnings,
        terms_requested: n,
        info,
    })
}

/// The points a fit uses and what it holds fixed.
struct FitData {
    strain: Vec<f64>,
    stress: Vec<f64>,
    /// Poisson's ratio from the lateral strain (0 without it) and its standard error
    nu: f64,
    nu_se: f64,
    layout: Layout,
}

/// Check `params` against `curve` and take the points with 0 < strain ≤ `strain_max`, ν from
/// the lateral strain if the curve has it, Σμ from a pinned initial modulus.
fn fit_data(curve: &StressStrainCurve, params: &HyperfoamFitParams) -> Result<FitData, FitError> {
    let n = params.terms;
    if n == 0 || n > MAX_FIT_TERMS {
        return Err(FitError::Invalid(format!(
            "terms = {n}; 1 to {MAX_FIT_TERMS} allowed"
        )));
    }
    if !(params.strain_max > 0.0 && params.strain_max < 1.0) {
        return Err(FitError::Invalid(format!(
            "strain_max = {} must lie in (0, 1)",
            params.strain_max
        )));
    }
    let keep: Vec<usize> = (0..curve.strain.len())
        .filter(|&i| curve.strain[i] > 0.0 && curve.strain[i] <= params.strain_max)
        .collect();
    let strain: Vec<f64> = keep.iter().map(|&i| curve.strain[i]).collect();
    let stress: Vec<f64> = keep.iter().map(|&i| curve.stress[i]).collect();
    let layout = Layout {
        terms: n,
        mu_sum: None,
    };
    if strain.len() < layout.len() + 2 {
        return Err(FitError::Invalid(format!(
            "{} points with 0 < strain <= {} cannot fit {} terms (need at least {})",
            strain.len(),
            params.strain_max,
            n,
            layout.len() + 2
        )));
    }
    let (nu, nu_se) = match &curve.lateral_strain {
        Some(lat) => {
            let l: Vec<f64> = keep.iter().map(|&i| lat[i]).collect();
            fit_nu(&strain, &l)?
        }
        None => (0.0, 0.0),
    };
    let mu_sum = match params.initial_modulus {
        Some(e0) if e0 > 0.0 && e0.is_finite() => Some(e0 / (2.0 * (1.0 + nu))),
        Some(e0) => {
            return Err(FitError::Invalid(format!(
                "initial modulus {e0} GPa must be positive"
            )))
        }
        None => None,
    };
    Ok(FitData {
        strain,
        stress,
        nu,
        nu_se,
        layout: Layout { terms: n, mu_sum },
    })
}

/// The least-squares start (μ, α): the best of the variable-projection grid (μ linear for
/// each α combination) and the nested starts from the fit with one term fewer.
fn start(
    problem: &UniaxialProblem,
    fewer: Option<&HyperfoamFit>,
) -> Result<(Vec<f64>, Vec<f64>), FitError> {
    let n = problem.layout.terms;
    // variable-projection start
    let mut best: Option<(Vec<f64>, Vec<f64>, f64)> = None;
    for alpha in combinations(&alpha_grid(), n) {
        if let Some((mu, cost)) = linear_mu(
            problem.strain,
            problem.stress,
            &alpha,
            problem.nu,
            problem.layout.mu_sum,
        ) {
            if best.as_ref().is_none_or(|b| cost < b.2) {
                best = Some((mu, alpha, cost));
            }
        }
    }
    // (a fit with one term fewer that dropped a degenerate term of its own has too few terms
    // to nest: the grid start stands alone)
    if let Some(f) = fewer.filter(|f| f.material.terms.len() + 1 == n) {
        let (mu_prev, alpha_prev) = (f.material.mu(), f.material.alpha());
        let total: f64 = mu_prev.iter().sum();
        for &a in &alpha_grid() {
            let mut mu: Vec<f64> = mu_prev.iter().map(|m| m * (1.0 - NESTED_SHARE)).collect();
            mu.push(NESTED_SHARE * total);
            let mut alpha = alpha_prev.clone();
            alpha.push(a);
            if let Some(r) = problem.residuals(&problem.layout.pack(&mu, &alpha)) {
                let cost = r.norm_squared();
                if best.as_ref().is_none_or(|b| cost < b.2) {
                    best = Some((mu, alpha, cost));
                }
            }
        }
    }
    let (mu, alpha, _) = best.ok_or_else(|| {
        FitError::Invalid(format!(
            "no combination of {n} positive terms describes the data (is the curve compressive and stiffening?)"
        ))
    })?;
    Ok((mu, alpha))
}

/// Standard errors of μ, α and β from the least-squares covariance (`g` = ∂θ/∂p), if finite.
fn std_errors(
    info: &lsq::Info,
    g: &DMatrix<f64>,
    n: usize,
    nu: f64,
    nu_se: f64,
) -> Option<HyperfoamStdErrors> {
    info.covariance.as_ref().and_then(|cov| {
        let ct = g * cov * g.transpose();
        let se = |k: usize| ct[(k, k)].max(0.0).sqrt();
        let e = HyperfoamStdErrors {
            mu: (0..n).map(se).collect(),
            alpha: (0..n).map(|i| se(n + i)).collect(),
            beta: nu_se / (1.0 - 2.0 * nu).powi(2),
        };
        let finite =
            e.mu.iter()
                .chain(&e.alpha)
                .chain([&e.beta])
                .all(|x| x.is_finite());
        finite.then_some(e)
    })
}

/// A warning when the first point lies far below the fitted initial modulus's line.
fn unresolved_e0(material: &Hyperfoam, strain: &[f64], stress: &[f64]) -> Option<String> {
    let (&e1, &s1) = (strain.first()?, stress.first()?);
    // the fitted initial modulus is seen by the data only if the first point still lies
    // near its line: a point far below E⁰ε₁ is past the knee, and E⁰ is an extrapolation
    let e0 = material.initial_youngs_modulus();
    (s1 < UNRESOLVED_E0 * e0 * e1).then(|| {
        format!(
            "the first point (strain {e1:.4}, stress {:.4} MPa) is {:.0} % of the fitted \
             initial modulus's line E0*strain (E0 = {:.3} MPa): the curve is past its knee \
             there, so E0 is an extrapolation the data do not resolve — sample small \
             strains more finely (more compression.steps) or pin E0",
            s1 * 1e3,
            100.0 * s1 / (e0 * e1),
            e0 * 1e3
        )
    })
}

/// Why fitted terms are redundant: a term with less than [`NEGLIGIBLE_SHARE`] of Σμ, or two
/// terms whose α differ by less than [`DEGENERATE_ALPHA`] (relative); `None` when every term is
/// distinct and carries weight.
fn redundancy(mu: &[f64], alpha: &[f64]) -> Option<String> {
    let total: f64 = mu.iter().sum();
    let mut why = Vec::new();
    for (i, m) in mu.iter().enumerate() {
        if *m < NEGLIGIBLE_SHARE * total {
            why.push(format!(
                "term {} carries {:.1e} of sum(mu)",
                i + 1,
                m / total
            ));
        }
    }
    for i in 0..alpha.len() {
        for j in i + 1..alpha.len() {
            if (alpha[i] / alpha[j] - 1.0).abs() < DEGENERATE_ALPHA {
                why.push(format!(
                    "terms {} and {} have equal alpha within {} % ({:.4}, {:.4})",
                    i + 1,
                    j + 1,
                    100.0 * DEGENERATE_ALPHA,
                    alpha[i],
                    alpha[j]
                ));
            }
        }
    }
    (mu.len() > 1 && !why.is_empty()).then(|| why.join("; "))
}

/// The fit with fewer terms, returned for a request of `requested` terms, saying why.
fn with_fewer_terms(mut fit: HyperfoamFit, requested: usize, why: String) -> HyperfoamFit {
    let used = fit.material.terms.len();
    fit.warnings.insert(
        0,
        format!("{requested} terms requested, {used} used: {why}"),
    );
    fit.terms_requested = requested;
    fit
}

/// A warning for each α at an end of [`ALPHA_RANGE`] (within [`AT_BOUND`]): the iteration
/// stopped against the bound, so the card's shape is the bound's, not the data's.
fn bound_warnings(alpha: &[f64]) -> Vec<String> {
    let (lo, hi) = ALPHA_RANGE;
    alpha
        .iter()
        .enumerate()
        .filter(|(_, &a)| a < lo * (1.0 + AT_BOUND) || a > hi / (1.0 + AT_BOUND))
        .map(|(i, a)| {
            format!(
                "alpha{} = {a:.4} sits at the bound of its admissible range [{lo}, {hi}]: the \
                 hyperfoam cannot follow this curve's shape (compare fit_rms_rel and the plot)",
                i + 1
            )
        })
        .collect()
}

/// Fraction of the initial modulus's line E⁰ε₁ below which the first fitted point counts as
/// past the knee (E⁰ not resolved by the data): at ½ the secant modulus has already halved.
const UNRESOLVED_E0: f64 = 0.5;

/// Relative difference below which two fitted α count as one term (degenerate fit).
const DEGENERATE_ALPHA: f64 = 1e-2;

/// Stretch samples of the stability check over the fitted range.
const STABILITY_SAMPLES: usize = 50;

/// Check monotonic uniaxial response and Drucker stability (uniaxial, equibiaxial,
/// hydrostatic) for compressive stretches 1 − strain_max ≤ λ < 1; one warning per failed check
/// naming the first failing stretch.
pub fn stability_warnings(m: &Hyperfoam, strain_max: f64) -> Vec<String> {
    let mut w = Vec::new();
    let lambdas: Vec<f64> = (1..=STABILITY_SAMPLES)
        .map(|k| 1.0 - strain_max * k as f64 / STABILITY_SAMPLES as f64)
        .collect();
    let mut prev = 0.0;
    for &l in &lambdas {
        match m.drive(Mode::Uniaxial, l) {
            Ok(s) if -s.nominal[0] > prev => prev = -s.nominal[0],
            Ok(_) => {
                w.push(format!(
                    "uniaxial compressive stress stops increasing at strain {:.4} (inside the fitted range)",
                    1.0 - l
                ));
                break;
            }
            Err(e) => {
                w.push(format!(
                    "uniaxial driver failed at strain {:.4}: {e}",
                    1.0 - l
                ));
                break;
            }
        }
    }
    for mode in [Mode::Uniaxial, Mode::Equibiaxial, Mode::Hydrostatic] {
        let bad = lambdas.iter().find(|&&l| {
            m.drive(mode, l)
                .and_then(|s| m.drucker_stable(s.stretch))
                .map_or(true, |ok| !ok)
        });
        if let Some(l) = bad {
            w.push(format!(
                "not Drucker-stable in {mode:?} compression at stretch {l:.4}"
            ));
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_matches_the_driver_and_its_alpha_derivative() {
        let m = Hyperfoam::new(&[1.0], &[7.0], &[beta_from_nu(0.2)]).unwrap();
        for eps in [0.05, 0.3, 0.6] {
            let s = m.drive(Mode::Uniaxial, 1.0 - eps).unwrap();
            let (b, db) = basis(eps, 7.0, 0.2);
            // driver solved to 1e-14 of the stress scale
            assert!((b + s.nominal[0]).abs() < 1e-12 * b.abs().max(1.0), "{eps}");
            let h = 1e-6;
            let fd = (basis(eps, 7.0 + h, 0.2).0 - basis(eps, 7.0 - h, 0.2).0) / (2.0 * h);
            assert!((fd - db).abs() < 1e-7 * db.abs().max(1.0));
        }
    }

    #[test]
    fn layout_jacobian_is_exact() {
        for mu_sum in [None, Some(0.4)] {
            let lay = Layout { terms: 3, mu_sum };
            let p: Vec<f64> = (0..lay.len()).map(|i| 0.3 * i as f64 - 0.5).collect();
            let (_, _, g) = lay.unpack(&p);
            let h = 1e-6;
            for c in 0..lay.len() {
                let (mut a, mut b) = (p.clone(), p.clone());
                a[c] += h;
                b[c] -= h;
                let (ma, aa, _) = lay.unpack(&a);
                let (mb, ab, _) = lay.unpack(&b);
                let ta: Vec<f64> = ma.into_iter().chain(aa).collect();
                let tb: Vec<f64> = mb.into_iter().chain(ab).collect();
                for r in 0..6 {
                    let fd = (ta[r] - tb[r]) / (2.0 * h);
                    assert!((fd - g[(r, c)]).abs() < 1e-8, "{mu_sum:?} {r} {c}");
                }
            }
            let (mu, al, _) = lay.unpack(&p);
            let back = lay.pack(&mu, &al);
            assert!(back.iter().zip(&p).all(|(x, y)| (x - y).abs() < 1e-12));
        }
    }

    #[test]
    fn too_few_points_in_range_and_bad_settings_are_refused() {
        let strain: Vec<f64> = (0..10).map(|i| i as f64 * 0.05).collect();
        let stress = strain.iter().map(|e| 0.1 * e).collect();
        let c = StressStrainCurve::new(strain, stress, None, "t").unwrap();
        let p = HyperfoamFitParams {
            terms: 3,
            strain_max: 0.1,
            ..Default::default()
        };
        assert!(matches!(fit_hyperfoam(&c, &p), Err(FitError::Invalid(_))));
        let p = HyperfoamFitParams {
            terms: 4,
            ..Default::default()
        };
        assert!(fit_hyperfoam(&c, &p).is_err());
        let p = HyperfoamFitParams {
            strain_max: 1.5,
            ..Default::default()
        };
        assert!(fit_hyperfoam(&c, &p).is_err());
    }

    #[test]
    fn a_curve_already_past_its_knee_warns_that_e0_is_not_resolved() {
        let past = |s: &HyperfoamFit| s.warnings.iter().any(|w| w.contains("past its knee"));
        // the discrete plateau of 9 × 7 µm tubes (docs/chain.md): 0.32 MPa at the first point
        // ε = 0.03, rising to 0.49 MPa at 0.3
        let strain: Vec<f64> = (0..=10).map(|i| 0.03 * i as f64).collect();
        let stress: Vec<f64> = strain
            .iter()
            .map(|&e| {
                if e > 0.0 {
                    3.2e-4 + 6e-4 * (e - 0.03)
                } else {
                    0.0
                }
            })
            .collect();
        let c = StressStrainCurve::new(strain.clone(), stress, None, "plateau").unwrap();
        let fit = fit_hyperfoam(&c, &HyperfoamFitParams::default()).unwrap();
        assert!(past(&fit), "{:?}", fit.warnings);
        // the seed's tangent law (5.1) sampled at the same strains is resolved from ε = 0.03:
        // σ(0.03)/(E⁰·0.03) = 0.82 for ε₀ = 0.1
        let (e0, einf, eps0) = (0.7, 0.07, 0.1);
        let law: Vec<f64> = strain
            .iter()
            .map(|&e| einf * e + (e0 - einf) * eps0 * (1.0 - (-e / eps0).exp()))
            .collect();
        let c = StressStrainCurve::new(strain, law, None, "law").unwrap();
        let fit = fit_hyperfoam(&c, &HyperfoamFitParams::default()).unwrap();
        assert!(!past(&fit), "{:?}", fit.warnings);
    }

    /// The curve of a hyperfoam under uniaxial compression at ε = 0.01 … 0.30.
    fn sampled(m: &Hyperfoam) -> StressStrainCurve {
        let strain: Vec<f64> = (1..=30).map(|i| 0.01 * i as f64).collect();
        let stress = strain
            .iter()
            .map(|&e| -m.drive(Mode::Uniaxial, 1.0 - e).unwrap().nominal[0])
            .collect();
        StressStrainCurve::new(strain, stress, None, "sampled").unwrap()
    }

    #[test]
    fn a_degenerate_two_term_fit_is_reported_as_the_one_term_card_it_is() {
        // one-term data: a second term can only duplicate the first or vanish
        let c = sampled(&Hyperfoam::new(&[0.01], &[8.4], &[0.0]).unwrap());
        let p = HyperfoamFitParams {
            terms: 2,
            ..Default::default()
        };
        let fit = fit_hyperfoam(&c, &p).unwrap();
        assert_eq!(fit.terms_requested, 2);
        assert_eq!(fit.material.terms.len(), 1);
        assert!(
            fit.warnings[0].starts_with("2 terms requested, 1 used"),
            "{:?}",
            fit.warnings
        );
        // the one-term fit of exact one-term data: solver tolerance
        assert!(fit.rms_rel < 1e-6, "{}", fit.rms_rel);
        assert!((fit.material.terms[0].alpha / 8.4 - 1.0).abs() < 1e-6);
    }

    /// Three terms asked of one-term data: the two-term fit it nests on has itself dropped to
    /// one term, so there is nothing to nest — the fit starts from the grid, and returns the
    /// card the data support with the reason, rather than index past its terms.
    #[test]
    fn three_terms_on_one_term_data_nest_on_no_degenerate_fit() {
        let c = sampled(&Hyperfoam::new(&[0.01], &[8.4], &[0.0]).unwrap());
        let p = HyperfoamFitParams {
            terms: 3,
            ..Default::default()
        };
        let fit = fit_hyperfoam(&c, &p).unwrap();
        assert_eq!(fit.terms_requested, 3);
        assert!(fit.material.terms.len() < 3, "{:?}", fit.material);
        assert!(
            fit.warnings[0].starts_with("3 terms requested"),
            "{:?}",
            fit.warnings
        );
        assert!(fit.rms_rel < 1e-6, "{}", fit.rms_rel);
    }

    #[test]
    fn two_distinct_terms_that_the_data_need_are_kept() {
        let c = sampled(&Hyperfoam::new(&[0.008, 0.002], &[2.0, 25.0], &[0.0, 0.0]).unwrap());
        let p = HyperfoamFitParams {
            terms: 2,
            ..Default::default()
        };
        let fit = fit_hyperfoam(&c, &p).unwrap();
        assert_eq!(fit.material.terms.len(), 2, "{:?}", fit.warnings);
        assert!(fit.warnings.iter().all(|w| !w.contains("requested")));
        assert!(fit.rms_rel < 1e-6, "{}", fit.rms_rel);
    }

    #[test]
    fn redundancy_names_equal_alphas_and_negligible_terms() {
        assert!(redundancy(&[1.0, 1.0], &[8.0, 20.0]).is_none());
        assert!(redundancy(&[1.0], &[8.0]).is_none());
        let w = redundancy(&[1.0, 1e-3], &[8.41, 8.41]).unwrap();
        assert!(
            w.contains("term 2 carries 1.0e-3") && w.contains("equal alpha"),
            "{w}"
        );
        assert!(bound_warnings(&[0.01, 5.0])[0].starts_with("alpha1 = 0.0100 sits at the bound"));
        assert!(bound_warnings(&[5.0]).is_empty());
    }
}
