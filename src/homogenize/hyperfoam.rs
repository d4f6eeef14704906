//! The hyperfoam strain energy (Hill 1978; Storåkers 1986; the Abaqus/CalculiX `*HYPERFOAM`
//! form; seed (5.3)–(5.7) with the OCR errors corrected, see PHYSICS.md), its principal stresses
//! and tangent, and a single-point driver (uniaxial, equibiaxial, hydrostatic).
//!
//! U(λ₁, λ₂, λ₃) = Σᵢ 2μᵢ/αᵢ² [λ₁^αᵢ + λ₂^αᵢ + λ₃^αᵢ − 3 + (1/βᵢ)(J^(−αᵢβᵢ) − 1)],  J = λ₁λ₂λ₃,
//!
//! with the β → 0 limit (1/β)(J^(−αβ) − 1) → −α ln J. Written as expm1(−αβ ln J)/β the
//! volumetric term is accurate for every β, including β = 0 exactly.
//!
//! - principal nominal stress (seed 5.4) Tⱼ = ∂U/∂λⱼ = Σᵢ (2μᵢ/αᵢ)(λⱼ^(αᵢ−1) − J^(−αᵢβᵢ)/λⱼ);
//! - Kirchhoff τⱼ = λⱼTⱼ, Cauchy σⱼ = τⱼ/J;
//! - ground-state moduli (5.5) μ₀ = Σμᵢ, K₀ = Σ 2μᵢ(1/3 + βᵢ); βᵢ = νᵢ/(1 − 2νᵢ) (5.6);
//! - with β = 0 a uniaxial test has no lateral strain and T = (2μ/α)(λ^(α−1) − λ^(−1)), so the
//!   initial Young's modulus is E⁰ = Σ 2μᵢ (expand λ = 1 − ε: T ≈ −(2μ/α)(α − 1 + 1)ε).
//!
//! Stresses are in GPa when μ is (energy density aJ/nm³ = GPa). A pure kernel: the continuum FE
//! evaluates the same functions at its quadrature points.

/// One term of the series: μᵢ (GPa), αᵢ, βᵢ (dimensionless).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HyperfoamTerm {
    /// shear-like modulus μᵢ, GPa
    pub mu: f64,
    /// stretch exponent αᵢ (≠ 0)
    pub alpha: f64,
    /// compressibility βᵢ = νᵢ/(1 − 2νᵢ) (> −1/3)
    pub beta: f64,
}

impl HyperfoamTerm {
    /// The Poisson-like ratio νᵢ = βᵢ/(1 + 2βᵢ) of this term (seed 5.6).
    pub fn nu(&self) -> f64 {
        self.beta / (1.0 + 2.0 * self.beta)
    }
}

/// β from ν: β = ν/(1 − 2ν).
pub fn beta_from_nu(nu: f64) -> f64 {
    nu / (1.0 - 2.0 * nu)
}

/// A hyperfoam material: N terms (1 ≤ N ≤ [`MAX_TERMS`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Hyperfoam {
    /// the terms of the series
    pub terms: Vec<HyperfoamTerm>,
}

/// The largest N accepted (CalculiX reads N ≤ 3; Abaqus allows 6).
pub const MAX_TERMS: usize = 6;

/// Why a hyperfoam evaluation or construction failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HyperfoamError {
    /// constants outside their admissible range
    #[error("invalid hyperfoam constants: {0}")]
    InvalidConstants(String),
    /// a stretch ≤ 0 or non-finite
    #[error("stretches {0:?} are not all positive and finite")]
    BadStretch([f64; 3]),
    /// the stress-free lateral stretch could not be found
    #[error("no stress-free lateral stretch found at λ = {stretch} ({reason})")]
    NoLateralEquilibrium {
        /// the imposed stretch
        stretch: f64,
        /// what went wrong
        reason: String,
    },
}

/// A homogeneous deformation mode of the single-point driver.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// λ₁ = λ imposed, λ₂ = λ₃ free with zero lateral stress
    Uniaxial,
    /// λ₁ = λ₂ = λ imposed, λ₃ free with zero stress
    Equibiaxial,
    /// λ₁ = λ₂ = λ₃ = λ
    Hydrostatic,
}

/// The state of the single-point driver at one imposed stretch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointState {
    /// principal stretches λ₁, λ₂, λ₃
    pub stretch: [f64; 3],
    /// principal nominal stresses ∂U/∂λⱼ, GPa (tension positive)
    pub nominal: [f64; 3],
    /// principal Cauchy stresses, GPa (tension positive)
    pub cauchy: [f64; 3],
    /// strain energy density, GPa (= aJ/nm³)
    pub energy: f64,
}

/// Tolerance of the lateral-equilibrium solve: the free nominal stress is driven below this
/// fraction of the stress scale Σ|2μᵢ/αᵢ| (well below the 1e-4 agreement asked of cards).
const LATERAL_TOL: f64 = 1e-14;
/// Newton iterations allowed for the lateral stretch (quadratic convergence needs ~6).
const LATERAL_MAX_ITER: usize = 100;

impl Hyperfoam {
    /// Build from arrays of μ (GPa), α and β, checking lengths and admissible values:
    /// finite numbers, αᵢ ≠ 0, βᵢ > −1/3, μᵢαᵢ ≥ 0, and a positive initial shear modulus μ₀.
    pub fn new(mu: &[f64], alpha: &[f64], beta: &[f64]) -> Result<Self, HyperfoamError> {
        let bad = |s: String| Err(HyperfoamError::InvalidConstants(s));
        if mu.is_empty() || mu.len() > MAX_TERMS {
            return bad(format!(
                "{} terms given, 1 to {MAX_TERMS} allowed",
                mu.len()
            ));
        }
        if alpha.len() != mu.len() || beta.len() != mu.len() {
            return bad(format!(
                "mu, alpha, beta must have equal lengths (got {}, {}, {})",
                mu.len(),
                alpha.len(),
                beta.len()
            ));
        }
        let terms: Vec<HyperfoamTerm> = (0..mu.len())
            .map(|i| HyperfoamTerm {
                mu: mu[i],
                alpha: alpha[i],
                beta: beta[i],
            })
            .collect();
        for (i, t) in terms.iter().enumerate() {
            if !(t.mu.is_finite() && t.alpha.is_finite() && t.beta.is_finite()) {
                return bad(format!("term {} has a non-finite constant", i + 1));
            }
            if t.alpha == 0.0 {
                return bad(format!("alpha{} = 0 (must be non-zero)", i + 1));
            }
            if t.beta <= -1.0 / 3.0 {
                return bad(format!("beta{} = {} (must exceed -1/3)", i + 1, t.beta));
            }
            if t.mu * t.alpha < 0.0 {
                return bad(format!(
                    "mu{0}*alpha{0} = {1} < 0 (each term must stiffen: mu*alpha >= 0)",
                    i + 1,
                    t.mu * t.alpha
                ));
            }
        }
        let m = Hyperfoam { terms };
        if m.initial_shear_modulus() <= 0.0 {
            return bad(format!(
                "initial shear modulus sum(mu) = {} <= 0",
                m.initial_shear_modulus()
            ));
        }
        Ok(m)
    }

    /// μ values, GPa.
    pub fn mu(&self) -> Vec<f64> {
        self.terms.iter().map(|t| t.mu).collect()
    }
    /// α values.
    pub fn alpha(&self) -> Vec<f64> {
        self.terms.iter().map(|t| t.alpha).collect()
    }
    /// β values.
    pub fn beta(&self) -> Vec<f64> {
        self.terms.iter().map(|t| t.beta).collect()
    }

    /// Initial shear modulus μ₀ = Σμᵢ, GPa (seed 5.5).
    pub fn initial_shear_modulus(&self) -> f64 {
        self.terms.iter().map(|t| t.mu).sum()
    }

    /// Initial bulk modulus K₀ = Σ 2μᵢ(1/3 + βᵢ), GPa (seed 5.5, corrected).
    pub fn initial_bulk_modulus(&self) -> f64 {
        self.terms
            .iter()
            .map(|t| 2.0 * t.mu * (1.0 / 3.0 + t.beta))
            .sum()
    }

    /// Initial Young's modulus E⁰ = 9K₀μ₀/(3K₀ + μ₀), GPa (= 2μ₀ when every β = 0).
    pub fn initial_youngs_modulus(&self) -> f64 {
        let (k, g) = (self.initial_bulk_modulus(), self.initial_shear_modulus());
        9.0 * k * g / (3.0 * k + g)
    }

    fn check(l: [f64; 3]) -> Result<(), HyperfoamError> {
        if l.iter().all(|x| x.is_finite() && *x > 0.0) {
            Ok(())
        } else {
            Err(HyperfoamError::BadStretch(l))
        }
    }

    /// Strain energy density U, GPa.
    pub fn energy(&self, l: [f64; 3]) -> Result<f64, HyperfoamError> {
        Self::check(l)?;
        let ln_j = l.iter().map(|x| x.ln()).sum::<f64>();
        Ok(self
            .terms
            .iter()
            .map(|t| {
                let (a, b) = (t.alpha, t.beta);
                let vol = if b == 0.0 {
                    -a * ln_j
                } else {
                    (-a * b * ln_j).exp_m1() / b
                };
                2.0 * t.mu / (a * a) * (l.iter().map(|x| x.powf(a)).sum::<f64>() - 3.0 + vol)
            })
            .sum())
    }

    /// Principal nominal stresses Tⱼ = ∂U/∂λⱼ, GPa (seed 5.4).
    pub fn nominal_stress(&self, l: [f64; 3]) -> Result<[f64; 3], HyperfoamError> {
        Self::check(l)?;
        let ln_j = l.iter().map(|x| x.ln()).sum::<f64>();
        let mut s = [0.0; 3];
        for t in &self.terms {
            let (a, b) = (t.alpha, t.beta);
            let jv = (-a * b * ln_j).exp();
            for (sj, &lj) in s.iter_mut().zip(&l) {
                *sj += 2.0 * t.mu / a * (lj.powf(a - 1.0) - jv / lj);
            }
        }
        Ok(s)
    }

    /// The tangent ∂Tᵢ/∂λⱼ = ∂²U/∂λᵢ∂λⱼ, GPa.
    pub fn nominal_tangent(&self, l: [f64; 3]) -> Result<[[f64; 3]; 3], HyperfoamError> {
        Self::check(l)?;
        let ln_j = l.iter().map(|x| x.ln()).sum::<f64>();
        let mut k = [[0.0; 3]; 3];
        for t in &self.terms {
            let (a, b) = (t.alpha, t.beta);
            let jv = (-a * b * ln_j).exp();
            let c = 2.0 * t.mu / a;
            for i in 0..3 {
                for j in 0..3 {
                    let mut v = a * b * jv / (l[i] * l[j]);
                    if i == j {
                        v += (a - 1.0) * l[i].powf(a - 2.0) + jv / (l[i] * l[i]);
                    }
                    k[i][j] += c * v;
                }
            }
        }
        Ok(k)
    }

    /// Principal Cauchy stresses σⱼ = λⱼTⱼ/J, GPa.
    pub fn cauchy_stress(&self, l: [f64; 3]) -> Result<[f64; 3], HyperfoamError> {
        let t = self.nominal_stress(l)?;
        let j = l[0] * l[1] * l[2];
        Ok([l[0] * t[0] / j, l[1] * t[1] / j, l[2] * t[2] / j])
    }

    /// The tangent ∂σᵢ/∂(ln λⱼ) of the principal Cauchy stresses with respect to the principal
    /// log strains, GPa: from ∂τᵢ/∂ln λⱼ = Σ 2μ(δᵢⱼλᵢ^α + βJ^(−αβ)) and σ = τ/J.
    pub fn log_strain_tangent(&self, l: [f64; 3]) -> Result<[[f64; 3]; 3], HyperfoamError> {
        Self::check(l)?;
        let ln_j = l.iter().map(|x| x.ln()).sum::<f64>();
        let j = ln_j.exp();
        let mut d = [[0.0; 3]; 3];
        let mut tau = [0.0; 3];
        for t in &self.terms {
            let (a, b) = (t.alpha, t.beta);
            let jv = (-a * b * ln_j).exp();
            for p in 0..3 {
                tau[p] += 2.0 * t.mu / a * (l[p].powf(a) - jv);
                for (q, dpq) in d[p].iter_mut().enumerate() {
                    let diag = if p == q { l[p].powf(a) } else { 0.0 };
                    *dpq += 2.0 * t.mu * (diag + b * jv);
                }
            }
        }
        for (row, tp) in d.iter_mut().zip(tau) {
            for v in row.iter_mut() {
                *v = (*v - tp) / j;
            }
        }
        Ok(d)
    }

    /// Drucker stability in principal axes: the symmetric part of ∂σᵢ/∂(ln λⱼ) is positive
    /// definite (dσ : dε > 0 for every principal log-strain increment), the check Abaqus makes
    /// for its hyperfoam fits.
    pub fn drucker_stable(&self, l: [f64; 3]) -> Result<bool, HyperfoamError> {
        let t = self.log_strain_tangent(l)?;
        let sym = nalgebra::Matrix3::from_fn(|p, q| 0.5 * (t[p][q] + t[q][p]));
        Ok(sym.cholesky().is_some())
    }

    /// The single-point driver: impose `stretch` in `mode` and solve for the free stretches
    /// (zero nominal stress in the free directions), by Newton's method on the exact tangent
    /// with a bracketing safeguard.
    pub fn drive(&self, mode: Mode, stretch: f64) -> Result<PointState, HyperfoamError> {
        Self::check([stretch; 3])?;
        let l = match mode {
            Mode::Hydrostatic => [stretch; 3],
            Mode::Uniaxial => {
                let t = self.free_stretch(stretch, |s, f| [s, f, f], &[1, 2], 1)?;
                [stretch, t, t]
            }
            Mode::Equibiaxial => {
                let t = self.free_stretch(stretch, |s, f| [s, s, f], &[2], 2)?;
                [stretch, stretch, t]
            }
        };
        Ok(PointState {
            stretch: l,
            nominal: self.nominal_stress(l)?,
            cauchy: self.cauchy_stress(l)?,
            energy: self.energy(l)?,
        })
    }

    /// Solve T_row(layout(s, f)) = 0 for the free stretch f, where `free` lists the directions
    /// set to f (so dT/df sums those tangent columns).
    fn free_stretch(
        &self,
        s: f64,
        layout: impl Fn(f64, f64) -> [f64; 3],
        free: &[usize],
        row: usize,
    ) -> Result<f64, HyperfoamError> {
        let scale: f64 = self
            .terms
            .iter()
            .map(|t| (2.0 * t.mu / t.alpha).abs())
            .sum();
        let fail = |reason: String| HyperfoamError::NoLateralEquilibrium { stretch: s, reason };
        let residual = |f: f64| -> Result<(f64, f64), HyperfoamError> {
            let l = layout(s, f);
            let t = self.nominal_stress(l)?[row];
            let k = self.nominal_tangent(l)?;
            Ok((t, free.iter().map(|&c| k[row][c]).sum()))
        };
        // Bracket: T_row increases with f for stable constants; expand until the sign changes.
        let (mut lo, mut hi) = (1.0f64.min(s), 1.0f64.max(s));
        let mut expand = 0;
        while residual(lo)?.0 > 0.0 {
            lo *= 0.5;
            expand += 1;
            if expand > 200 {
                return Err(fail("no lower bracket".into()));
            }
        }
        while residual(hi)?.0 < 0.0 {
            hi *= 2.0;
            expand += 1;
            if expand > 200 {
                return Err(fail("no upper bracket".into()));
            }
        }
        let mut f = if (lo..=hi).contains(&1.0) {
            1.0
        } else {
            0.5 * (lo + hi)
        };
        for _ in 0..LATERAL_MAX_ITER {
            let (t, dt) = residual(f)?;
            if t.abs() <= LATERAL_TOL * scale {
                return Ok(f);
            }
            if t > 0.0 {
                hi = f;
            } else {
                lo = f;
            }
            let newton = f - t / dt;
            f = if dt > 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= f64::EPSILON * hi {
                return Ok(f);
            }
        }
        Err(fail(format!(
            "no convergence in {LATERAL_MAX_ITER} iterations"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_term() -> Hyperfoam {
        Hyperfoam::new(&[0.3, 0.05], &[12.0, 2.0], &[0.25, 0.1]).unwrap()
    }

    /// Central differences with h = 1e-6 on O(1) stretches: truncation ~1e-12·U''' and
    /// rounding ~1e-16/1e-6, so 1e-7 relative is a safe bound.
    const FD_TOL: f64 = 1e-7;
    const H: f64 = 1e-6;

    #[test]
    fn stress_is_the_gradient_of_the_energy() {
        let m = two_term();
        let l = [0.7, 1.1, 0.95];
        let t = m.nominal_stress(l).unwrap();
        for j in 0..3 {
            let (mut a, mut b) = (l, l);
            a[j] += H;
            b[j] -= H;
            let fd = (m.energy(a).unwrap() - m.energy(b).unwrap()) / (2.0 * H);
            assert!(
                (fd - t[j]).abs() < FD_TOL * t[j].abs().max(1e-3),
                "{j}: {fd} {}",
                t[j]
            );
        }
    }

    #[test]
    fn tangent_is_the_gradient_of_the_stress() {
        let m = two_term();
        let l = [0.7, 1.1, 0.95];
        let k = m.nominal_tangent(l).unwrap();
        for j in 0..3 {
            let (mut a, mut b) = (l, l);
            a[j] += H;
            b[j] -= H;
            let (ta, tb) = (m.nominal_stress(a).unwrap(), m.nominal_stress(b).unwrap());
            for i in 0..3 {
                let fd = (ta[i] - tb[i]) / (2.0 * H);
                assert!(
                    (fd - k[i][j]).abs() < FD_TOL * k[i][j].abs().max(1e-2),
                    "{i}{j}"
                );
            }
        }
    }

    #[test]
    fn beta_zero_is_the_limit_of_small_beta() {
        let l = [0.8, 1.05, 0.9];
        let m0 = Hyperfoam::new(&[0.35], &[18.8], &[0.0]).unwrap();
        let m1 = Hyperfoam::new(&[0.35], &[18.8], &[1e-9]).unwrap();
        // the β-term differs from its limit by O(αβ (ln J)²) ~ 1e-9
        const LIMIT_TOL: f64 = 1e-8;
        assert!((m0.energy(l).unwrap() - m1.energy(l).unwrap()).abs() < LIMIT_TOL);
        let (a, b) = (m0.nominal_stress(l).unwrap(), m1.nominal_stress(l).unwrap());
        assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < LIMIT_TOL));
    }

    #[test]
    fn ground_state_is_stress_free_with_the_stated_moduli() {
        let m = two_term();
        assert!(m
            .nominal_stress([1.0; 3])
            .unwrap()
            .iter()
            .all(|s| s.abs() < 1e-15));
        assert!(m.energy([1.0; 3]).unwrap().abs() < 1e-15);
        // small hydrostatic strain: p = K₀ ΔV/V
        let e = 1e-6;
        let s = m.cauchy_stress([1.0 + e; 3]).unwrap()[0];
        const SMALL_STRAIN_TOL: f64 = 1e-5; // O(e) nonlinearity
        assert!((s / (3.0 * e) / m.initial_bulk_modulus() - 1.0).abs() < SMALL_STRAIN_TOL);
        // uniaxial: E⁰ = 9Kμ/(3K+μ)
        let u = m.drive(Mode::Uniaxial, 1.0 - e).unwrap();
        assert!((-u.nominal[0] / e / m.initial_youngs_modulus() - 1.0).abs() < SMALL_STRAIN_TOL);
    }

    #[test]
    fn uniaxial_driver_is_lateral_stress_free_and_matches_the_closed_form() {
        // common β: lateral stretch λ^(−ν) and T = Σ(2μ/α)(λ^(α−1) − λ^(−αν−1)) exactly
        let m = Hyperfoam::new(&[0.3, 0.05], &[12.0, 2.0], &[0.25, 0.25]).unwrap();
        let nu = m.terms[0].nu();
        for lam in [0.5, 0.8, 0.99, 1.2] {
            let p = m.drive(Mode::Uniaxial, lam).unwrap();
            assert!(p.nominal[1].abs() < 1e-13 && p.nominal[2].abs() < 1e-13);
            const CLOSED_TOL: f64 = 1e-12; // Newton converged to 1e-14 of the stress scale
            assert!((p.stretch[1] - lam.powf(-nu)).abs() < CLOSED_TOL);
            let t: f64 = m
                .terms
                .iter()
                .map(|t| {
                    2.0 * t.mu / t.alpha * (lam.powf(t.alpha - 1.0) - lam.powf(-t.alpha * nu - 1.0))
                })
                .sum();
            assert!((p.nominal[0] - t).abs() < CLOSED_TOL * t.abs().max(1.0));
        }
    }

    #[test]
    fn equibiaxial_and_hydrostatic_drivers() {
        let m = two_term();
        let p = m.drive(Mode::Equibiaxial, 0.8).unwrap();
        assert!(p.nominal[2].abs() < 1e-13 && p.stretch[2] > 1.0);
        let h = m.drive(Mode::Hydrostatic, 0.9).unwrap();
        assert!(h.cauchy[0] < 0.0 && (h.cauchy[0] - h.cauchy[2]).abs() < 1e-15);
    }

    #[test]
    fn seed_card_is_stable_and_bad_constants_are_refused() {
        let m = Hyperfoam::new(&[0.35], &[18.8], &[0.0]).unwrap();
        for lam in [0.5, 0.7, 0.9, 1.0] {
            assert!(m.drucker_stable([lam, 1.0, 1.0]).unwrap());
        }
        assert!(Hyperfoam::new(&[0.35], &[0.0], &[0.0]).is_err());
        assert!(Hyperfoam::new(&[0.35], &[2.0], &[-0.4]).is_err());
        assert!(Hyperfoam::new(&[-0.35], &[2.0], &[0.0]).is_err());
        assert!(Hyperfoam::new(&[0.35, 0.1], &[2.0], &[0.0]).is_err());
        assert!(m.energy([0.0, 1.0, 1.0]).is_err());
    }

    #[test]
    fn log_strain_tangent_is_the_derivative_of_the_cauchy_stress() {
        let m = two_term();
        let l = [0.7, 1.1, 0.95];
        let d = m.log_strain_tangent(l).unwrap();
        for j in 0..3 {
            let (mut a, mut b) = (l, l);
            a[j] *= H.exp();
            b[j] *= (-H).exp();
            let (sa, sb) = (m.cauchy_stress(a).unwrap(), m.cauchy_stress(b).unwrap());
            for i in 0..3 {
                let fd = (sa[i] - sb[i]) / (2.0 * H);
                assert!(
                    (fd - d[i][j]).abs() < FD_TOL * d[i][j].abs().max(1e-2),
                    "{i}{j}"
                );
            }
        }
    }

    #[test]
    fn an_unstable_card_is_detected() {
        // A term with μ, α < 0 softens under compression; with a weak stabilising term the
        // hydrostatic tangent turns negative at large compression.
        let m = Hyperfoam::new(&[0.5, -0.45], &[2.0, -1.0], &[0.0, 0.0]).unwrap();
        assert!(m.drucker_stable([1.0; 3]).unwrap());
        assert!(!m.drucker_stable([0.2; 3]).unwrap());
    }
}
