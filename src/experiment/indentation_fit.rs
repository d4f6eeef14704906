//! Fitting the quasi-rheological constants K₁, K₂, η of seed §2.3 (eqs. 2.1–2.7, Fig 2.1b) to a
//! force-controlled indentation record.
//!
//! **What the record is in the model.** The instrument applies the force P(t) to the indenter
//! plate and measures the plate displacement h(t) (a Hysitron transducer does both). The plate
//! is held by the support springs k₁ and reaches the specimen through the load-frame spring k₂
//! (the naming of [`crate::theory::indentation_law`]); the specimen is K₁ in series with the
//! Kelvin element K₂ ∥ η. With c = 1/K₁ + 1/k₂, ω = 1 + k₁c (= k₁(1/χ + 1/K₁), seed 2.4) and
//! S = k₁ + ωK₂ the network gives
//!
//! h = (cP + δ₂)/ω,  τ dδ₂/dt = P/S − δ₂,  τ = ωη/S  (seed 2.5, its α = ω),
//!
//! and Q = P − k₁h, δ = h − Q/k₂ are the true force and depth. The *ideal machine* (k₁ = 0,
//! k₂ = ∞, the default when the record is already corrected for the instrument) gives P = Q,
//! h = δ and the standard linear solid τ = η/K₂. P(t) is taken piecewise linear through the
//! record's samples; on each interval the Kelvin extension is propagated exactly (the segment
//! solution of (2.1)–(2.3)), and so are its derivatives with respect to K₁, K₂, η (forward
//! sensitivities), which give the exact Jacobian of the residuals.
//!
//! **What is fitted.** The residuals are rᵢ = h(tᵢ) − h(t₀) + d − (hᵢ − h₀) at every sample,
//! with the specimen taken relaxed under the first sample's load (δ₂ = P₀/S; P₀ = 0 is a start
//! from rest) and d a displacement offset fitted with K₁, K₂, η (so that the noise of the first
//! sample, the zero of the record, does not bias the fit; d ≈ 0 for a clean zero). A depth
//! zeroed at a preload is thus fitted as it is. They are minimised by
//! [`crate::numerics::least_squares`]
//! (Levenberg–Marquardt, standard errors from s²(JᵀJ)⁻¹) from a few starting relaxation times,
//! keeping the best. τ and its standard error follow from (2.5) and the covariance (delta
//! method). The checks of the seed's slopes are computed on the record's (Q, δ): the initial
//! loading slope (≈ K₁, 2.7) and the hold slope (= −χ, 2.6). A fit whose covariance is singular
//! or whose standard error exceeds [`UNDETERMINED_REL_SE`] of a constant carries a warning: the
//! record does not determine that constant (e.g. stiff support springs hide the specimen).
//!
//! Units: nN, nm, s; stiffnesses nN/nm, η nN·s/nm.

use super::record::{IndentationRecord, MIN_POINTS};
use crate::numerics::least_squares::{self, Problem, Termination};
use nalgebra::{DMatrix, DVector};

/// The share of the peak load change over which the initial loading slope is measured: small,
/// because dQ/dδ falls from K₁ at t = 0⁺ towards K₁K₂/(K₁+K₂) as the dashpot yields (2.7).
pub const INITIAL_WINDOW: f64 = 0.1;

/// A record interval is part of a hold when its load rate is below this share of the largest
/// load rate in the record (load-controlled holds are flat to the controller's resolution).
pub const HOLD_RATE_SHARE: f64 = 0.01;

/// Starting relaxation times, as shares of the record's duration: the cost is not convex in τ
/// (a τ far from the truth hides the creep), so the fit starts from each and keeps the best.
const START_TAU_SHARES: [f64; 5] = [0.01, 0.03, 0.1, 0.3, 1.0];

/// A constant whose standard error exceeds this share of its value is flagged as not
/// determined by the record: its 1σ interval then includes zero (and every larger multiple).
pub const UNDETERMINED_REL_SE: f64 = 1.0;

/// The fewest samples in a slope window (a line through two points has no redundancy).
const MIN_SLOPE_POINTS: usize = 3;

/// The testing machine: support springs k₁ and load-frame spring k₂.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Machine {
    /// k₁, nN/nm (≥ 0; 0: no support springs, the applied force reaches the specimen)
    #[serde(rename = "k1_nN_per_nm")]
    pub k1: f64,
    /// k₂, nN/nm (> 0), or `None` (absent in JSON) for a rigid load frame
    #[serde(rename = "k2_nN_per_nm", skip_serializing_if = "Option::is_none")]
    pub k2: Option<f64>,
}

impl Machine {
    /// The ideal machine: k₁ = 0, k₂ = ∞, so the record holds the specimen's Q and δ.
    pub const IDEAL: Machine = Machine { k1: 0.0, k2: None };

    /// The load-frame compliance 1/k₂, nm/nN.
    pub fn frame_compliance(&self) -> f64 {
        self.k2.map_or(0.0, |k| 1.0 / k)
    }

    /// χ = (1/k₁ + 1/k₂)⁻¹, nN/nm: the magnitude of dQ/dδ during a hold (seed 2.6).
    pub fn chi(&self) -> f64 {
        self.k1 / (1.0 + self.k1 * self.frame_compliance())
    }

    /// The true force and depth (Q, δ) on the specimen for applied force `p` and plate
    /// displacement `h`: Q = P − k₁h, δ = h − Q/k₂ (machine equilibrium, no specimen model).
    pub fn specimen_state(&self, p: f64, h: f64) -> (f64, f64) {
        let q = p - self.k1 * h;
        (q, h - q * self.frame_compliance())
    }

    fn check(&self) -> Result<(), FitError> {
        let k2_ok = self.k2.is_none_or(|k| k.is_finite() && k > 0.0);
        if !(self.k1.is_finite() && self.k1 >= 0.0 && k2_ok) {
            return Err(FitError::Machine {
                k1: self.k1,
                k2: self.k2,
            });
        }
        Ok(())
    }
}

/// The specimen's quasi-rheological constants (seed Fig 2.1b).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Specimen {
    /// K₁, the instantaneous spring, nN/nm
    #[serde(rename = "K1_nN_per_nm")]
    pub k1: f64,
    /// K₂, the Kelvin element's spring, nN/nm
    #[serde(rename = "K2_nN_per_nm")]
    pub k2: f64,
    /// η, the Kelvin element's dashpot, nN·s/nm
    #[serde(rename = "eta_nN_s_per_nm")]
    pub eta: f64,
}

impl Specimen {
    fn from_slice(p: &[f64]) -> Specimen {
        Specimen {
            k1: p[0],
            k2: p[1],
            eta: p[2],
        }
    }
}

/// The network constants c, ω, S, τ and their derivatives by (K₁, K₂, η).
struct Network {
    c: f64,
    omega: f64,
    s: f64,
    tau: f64,
    dc: [f64; 3],
    domega: [f64; 3],
    ds: [f64; 3],
    dtau: [f64; 3],
}

fn network(m: &Machine, sp: &Specimen) -> Network {
    let a = m.k1;
    let c = 1.0 / sp.k1 + m.frame_compliance();
    let dc = [-1.0 / (sp.k1 * sp.k1), 0.0, 0.0];
    let omega = 1.0 + a * c;
    let domega = dc.map(|d| a * d);
    let s = a + omega * sp.k2;
    let ds = [sp.k2 * domega[0], omega, 0.0];
    let tau = omega * sp.eta / s;
    let deta = [0.0, 0.0, 1.0];
    let dtau =
        std::array::from_fn(|k| (sp.eta * domega[k] + omega * deta[k]) / s - tau * ds[k] / s);
    Network {
        c,
        omega,
        s,
        tau,
        dc,
        domega,
        ds,
        dtau,
    }
}

/// Relaxation time τ = ωη/S (seed 2.5), s, and its gradient by (K₁, K₂, η).
pub fn relaxation_time(m: &Machine, sp: &Specimen) -> (f64, [f64; 3]) {
    let n = network(m, sp);
    (n.tau, n.dtau)
}

/// The plate displacement h at each sample for the applied force `load` (piecewise linear in
/// `time`), the specimen relaxed under the first load, and ∂h/∂(K₁, K₂, η) at each sample
/// (as many samples as the shorter of `time` and `load`).
pub fn plate_displacement(
    time: &[f64],
    load: &[f64],
    m: &Machine,
    sp: &Specimen,
) -> (Vec<f64>, Vec<[f64; 3]>) {
    let n = network(m, sp);
    let out = |p: f64, d2: f64, dd2: &[f64; 3]| {
        let h = (n.c * p + d2) / n.omega;
        let dh =
            std::array::from_fn(|k| (n.dc[k] * p + dd2[k]) / n.omega - h * n.domega[k] / n.omega);
        (h, dh)
    };
    let p0 = load.first().copied().unwrap_or(0.0);
    let mut d2 = p0 / n.s;
    let mut dd2: [f64; 3] = n.ds.map(|d| -p0 * d / (n.s * n.s));
    let (h0, dh0) = out(p0, d2, &dd2);
    let (mut h, mut dh) = (vec![h0], vec![dh0]);
    for j in 0..time.len().min(load.len()).saturating_sub(1) {
        let x = (time[j + 1] - time[j]) / n.tau;
        let e = (-x).exp();
        let one_minus_e = -(-x).exp_m1();
        let phi = one_minus_e / x;
        let dp = load[j + 1] - load[j];
        // δ₂ at the interval's end: δ₂e + A/S, A = ΔP(1 − φ) + Pⱼ(1 − e), φ = (1 − e)/x
        let a = dp * (1.0 - phi) + load[j] * one_minus_e;
        let da_dtau = -(dp * (phi - e) + load[j] * e * x) / n.tau;
        let de_dtau = e * x / n.tau;
        dd2 = std::array::from_fn(|k| {
            dd2[k] * e + (d2 * de_dtau + da_dtau / n.s) * n.dtau[k] - a * n.ds[k] / (n.s * n.s)
        });
        d2 = d2 * e + a / n.s;
        let (hj, dhj) = out(load[j + 1], d2, &dd2);
        h.push(hj);
        dh.push(dhj);
    }
    (h, dh)
}

/// Why a fit failed.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// the machine springs are not usable
    #[error("machine springs k1 = {k1} nN/nm (must be >= 0), k2 = {k2:?} nN/nm (must be > 0) are not valid")]
    Machine {
        /// k₁ given
        k1: f64,
        /// k₂ given
        k2: Option<f64>,
    },
    /// the record breaks an invariant of [`IndentationRecord`]
    #[error("invalid record: {0}")]
    InvalidRecord(&'static str),
    /// no start converged
    #[error("the fit of K1, K2, eta did not converge from any of {starts} starts: {last}")]
    NoConvergence {
        /// starts tried
        starts: usize,
        /// the last solver error
        last: least_squares::Error,
    },
}

/// A measured slope dQ/dδ next to the value the model predicts for it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SlopeCheck {
    /// slope of the record's (δ, Q) by least squares over the window, nN/nm
    #[serde(rename = "measured_nN_per_nm")]
    pub measured: f64,
    /// the same slope on the fitted model's curve, nN/nm
    #[serde(rename = "fitted_curve_nN_per_nm")]
    pub fitted_curve: f64,
    /// the seed's value: K₁ (2.7) for the initial slope, −χ (2.6) for the hold slope, nN/nm
    #[serde(rename = "seed_value_nN_per_nm")]
    pub seed_value: f64,
    /// first sample of the window (0-based)
    pub first_sample: usize,
    /// samples in the window
    pub samples: usize,
}

/// The result of [`fit`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct IndentationFit {
    /// the machine assumed
    pub machine: Machine,
    /// χ of the machine, nN/nm
    #[serde(rename = "chi_nN_per_nm")]
    pub chi: f64,
    /// the fitted constants
    pub specimen: Specimen,
    /// their standard errors (same units), when the covariance exists
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std_errors: Option<Specimen>,
    /// the fitted displacement offset d (the record's zero against the model's), nm
    pub offset_nm: f64,
    /// its standard error, nm
    #[serde(skip_serializing_if = "Option::is_none")]
    pub offset_std_error_nm: Option<f64>,
    /// τ (2.5), s
    pub tau_s: f64,
    /// its standard error, s
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tau_std_error_s: Option<f64>,
    /// root-mean-square displacement residual, nm
    pub rms_residual_nm: f64,
    /// coefficient of determination of the displacement changes
    pub r_squared: f64,
    /// the initial loading slope against K₁ (2.7), when the record starts with loading
    #[serde(skip_serializing_if = "Option::is_none")]
    pub initial_slope: Option<SlopeCheck>,
    /// the hold slope against −χ (2.6), when the record has a hold
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hold_slope: Option<SlopeCheck>,
    /// the fitted plate displacement at every sample, on the record's zero, nm
    #[serde(skip)]
    pub fitted_displacement: Vec<f64>,
    /// samples fitted
    pub samples: usize,
    /// starts tried and converged
    pub starts: usize,
    /// starts that converged
    pub converged_starts: usize,
    /// iterations of the best start
    pub iterations: usize,
    /// residual evaluations over all starts
    pub evaluations: usize,
    /// why the best start stopped
    pub termination: Termination,
    /// what the record does not determine (empty for a well-posed fit)
    pub warnings: Vec<String>,
}

struct DisplacementFit<'a> {
    record: &'a IndentationRecord,
    machine: Machine,
}

impl Problem for DisplacementFit<'_> {
    fn parameters(&self) -> usize {
        4
    }
    fn residuals(&self, p: &[f64]) -> Option<DVector<f64>> {
        if p[..3].iter().any(|&x| !(x.is_finite() && x > 0.0)) || !p[3].is_finite() {
            return None;
        }
        let r = self.record;
        let (h, _) = plate_displacement(&r.time, &r.load, &self.machine, &Specimen::from_slice(p));
        Some(DVector::from_iterator(
            h.len(),
            (0..h.len()).map(|i| (h[i] - h[0]) + p[3] - (r.displacement[i] - r.displacement[0])),
        ))
    }
    fn jacobian(&self, p: &[f64]) -> DMatrix<f64> {
        let r = self.record;
        let (_, dh) = plate_displacement(&r.time, &r.load, &self.machine, &Specimen::from_slice(p));
        DMatrix::from_fn(dh.len(), 4, |i, k| match k {
            3 => 1.0,
            _ => dh[i][k] - dh[0][k],
        })
    }
}

/// Least-squares slope of y on x.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// The samples of the initial loading window: from the first up to the first whose load
/// change reaches [`INITIAL_WINDOW`] of the peak change.
fn initial_window(load: &[f64]) -> Option<std::ops::Range<usize>> {
    let peak = load.iter().map(|p| p - load[0]).fold(0.0, f64::max);
    if peak <= 0.0 {
        return None;
    }
    let end = load
        .iter()
        .position(|p| p - load[0] >= INITIAL_WINDOW * peak)?
        + 1;
    (end >= MIN_SLOPE_POINTS).then_some(0..end)
}

/// The samples of the longest hold (load rate below [`HOLD_RATE_SHARE`] of the largest).
fn hold_window(time: &[f64], load: &[f64]) -> Option<std::ops::Range<usize>> {
    let rates: Vec<f64> = (0..time.len() - 1)
        .map(|j| ((load[j + 1] - load[j]) / (time[j + 1] - time[j])).abs())
        .collect();
    let max = rates.iter().copied().fold(0.0, f64::max);
    let mut best = 0..0;
    let mut start = None;
    for (j, &r) in rates
        .iter()
        .chain(std::iter::once(&f64::INFINITY))
        .enumerate()
    {
        match (r <= HOLD_RATE_SHARE * max, start) {
            (true, None) => start = Some(j),
            (false, Some(s)) => {
                if j - s > best.len() {
                    best = s..j + 1; // intervals s..j cover samples s..=j
                }
                start = None;
            }
            _ => {}
        }
    }
    (best.len() >= MIN_SLOPE_POINTS).then_some(best)
}

fn slope_check(
    window: std::ops::Range<usize>,
    record: &IndentationRecord,
    fitted: &[f64],
    machine: &Machine,
    seed_value: f64,
) -> SlopeCheck {
    let on = |h: &[f64]| {
        let (q, d): (Vec<f64>, Vec<f64>) = window
            .clone()
            .map(|i| machine.specimen_state(record.load[i], h[i]))
            .unzip();
        slope(&d, &q)
    };
    SlopeCheck {
        measured: on(&record.displacement),
        fitted_curve: on(fitted),
        seed_value,
        first_sample: window.start,
        samples: window.len(),
    }
}

/// Starting constants from the record: K₁ from the initial slope (or the secant to the peak),
/// K₂ from the creep seen at the end of the longest hold (else 10 K₁, the seed's K₂ ≫ K₁),
/// η from a starting relaxation time `tau`; no offset.
fn start(record: &IndentationRecord, machine: &Machine, tau: f64) -> [f64; 4] {
    let (p, h) = (&record.load, &record.displacement);
    let (q0, d0) = machine.specimen_state(p[0], h[0]);
    let state = |i: usize| {
        let (q, d) = machine.specimen_state(p[i], h[i]);
        (q - q0, d - d0)
    };
    let peak = (0..p.len())
        .max_by(|&a, &b| (p[a] - p[0]).total_cmp(&(p[b] - p[0])))
        .unwrap_or(0);
    let secant = {
        let (q, d) = state(peak);
        q / d
    };
    let k1 = initial_window(p)
        .map(|w| {
            let (q, d): (Vec<f64>, Vec<f64>) = w.map(state).unzip();
            slope(&d, &q)
        })
        .filter(|k| k.is_finite() && *k > 0.0)
        .or(Some(secant).filter(|k| k.is_finite() && *k > 0.0))
        .unwrap_or(1.0);
    let k2 = hold_window(&record.time, p)
        .map(|w| {
            let (q, d) = state(w.end - 1);
            q / (d - q / k1)
        })
        .filter(|k| k.is_finite() && *k > 0.0)
        .unwrap_or(10.0 * k1);
    let guess = Specimen { k1, k2, eta: 1.0 };
    let n = network(machine, &guess);
    [k1, k2, tau * n.s / n.omega, 0.0]
}

/// The record's invariants, for records not built by [`super::record::parse_record`] (which
/// refuses the same with the line and column).
fn check_record(r: &IndentationRecord) -> Result<(), FitError> {
    let reason = if r.load.len() != r.time.len() || r.displacement.len() != r.time.len() {
        "columns of different lengths"
    } else if r.time.len() < MIN_POINTS {
        "fewer samples than record::MIN_POINTS"
    } else if [&r.time, &r.load, &r.displacement]
        .iter()
        .any(|c| c.iter().any(|x| !x.is_finite()))
    {
        "a non-finite value"
    } else if r.time.windows(2).any(|w| w[1] <= w[0]) {
        "time not strictly increasing"
    } else if [&r.load, &r.displacement]
        .iter()
        .any(|c| c.iter().all(|&x| x == c[0]))
    {
        "a load or a displacement that never changes"
    } else {
        return Ok(());
    };
    Err(FitError::InvalidRecord(reason))
}

/// Fit K₁, K₂, η to `record` measured through `machine`.
pub fn fit(record: &IndentationRecord, machine: &Machine) -> Result<IndentationFit, FitError> {
    machine.check()?;
    check_record(record)?;
    let problem = DisplacementFit {
        record,
        machine: *machine,
    };
    let duration = record.time[record.time.len() - 1] - record.time[0];
    let params = least_squares::Params::default();
    let mut best: Option<(Vec<f64>, least_squares::Info)> = None;
    let mut last_error = None;
    let mut evaluations = 0;
    let mut converged = 0;
    for share in START_TAU_SHARES {
        match least_squares::solve(&problem, &start(record, machine, share * duration), &params) {
            Ok((p, info)) => {
                converged += 1;
                evaluations += info.evaluations;
                if best.as_ref().is_none_or(|(_, b)| info.cost < b.cost) {
                    best = Some((p, info));
                }
            }
            Err(e) => last_error = Some(e),
        }
    }
    let Some((p, info)) = best else {
        return Err(FitError::NoConvergence {
            starts: START_TAU_SHARES.len(),
            last: last_error.expect("every start failed, so one error was kept"),
        });
    };
    let specimen = Specimen::from_slice(&p);
    let (h, _) = plate_displacement(&record.time, &record.load, machine, &specimen);
    let y0 = record.displacement[0];
    let fitted: Vec<f64> = h.iter().map(|x| x - h[0] + y0 + p[3]).collect();
    let m = record.time.len();
    let rms = (2.0 * info.cost / m as f64).sqrt();
    let mean = record.displacement.iter().sum::<f64>() / m as f64;
    let ss_tot: f64 = record.displacement.iter().map(|y| (y - mean).powi(2)).sum();
    let (tau, dtau) = relaxation_time(machine, &specimen);
    let std_errors = info.std_errors();
    let tau_se = info.covariance.as_ref().map(|c| {
        let g = DVector::from_column_slice(&[dtau[0], dtau[1], dtau[2], 0.0]);
        (g.transpose() * c * &g)[(0, 0)].max(0.0).sqrt()
    });
    let warnings = match &std_errors {
        None => vec![
            "no standard errors: JᵀJ is singular at the optimum, so the record does not \
             determine all of K1, K2, eta"
                .to_string(),
        ],
        Some(se) => ["K1", "K2", "eta"]
            .iter()
            .zip(&p)
            .zip(se)
            .filter(|((_, v), se)| **se > UNDETERMINED_REL_SE * v.abs())
            .map(|((name, v), se)| {
                format!(
                    "{name} = {v:.4e} ± {se:.2e} is not determined by this record (standard \
                     error above {:.0} % of the value)",
                    100.0 * UNDETERMINED_REL_SE
                )
            })
            .collect(),
    };
    Ok(IndentationFit {
        machine: *machine,
        chi: machine.chi(),
        specimen,
        std_errors: std_errors.as_ref().map(|s| Specimen::from_slice(s)),
        offset_nm: p[3],
        offset_std_error_nm: std_errors.as_ref().map(|s| s[3]),
        tau_s: tau,
        tau_std_error_s: tau_se,
        rms_residual_nm: rms,
        r_squared: 1.0 - 2.0 * info.cost / ss_tot,
        initial_slope: initial_window(&record.load)
            .map(|w| slope_check(w, record, &fitted, machine, specimen.k1)),
        hold_slope: hold_window(&record.time, &record.load)
            .map(|w| slope_check(w, record, &fitted, machine, 0.0 - machine.chi())),
        fitted_displacement: fitted,
        samples: m,
        starts: START_TAU_SHARES.len(),
        converged_starts: converged,
        iterations: info.iterations,
        evaluations,
        termination: info.termination,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::theory::indentation_law::{Rheology, Segment};

    /// Round-off allowance of the forward model against the theory module: both evaluate the
    /// same exact segment solution, by different algebra, on forces of 1e4 nN.
    const FORWARD_TOL: f64 = 1e-10;
    /// Central differences with a relative step 1e-6 are accurate to ~1e-9 relative here
    /// (truncation ~h², round-off ~1e-16/h).
    const FD_TOL: f64 = 1e-7;

    const MACHINE: Machine = Machine {
        k1: 200.0,
        k2: Some(5e4),
    };
    const SPECIMEN: Specimen = Specimen {
        k1: 30.0,
        k2: 600.0,
        eta: 900.0,
    };

    fn schedule() -> [Segment; 3] {
        Segment::load_hold_unload(1e4, 5.0, 10.0, 5.0)
    }

    fn rheology(m: &Machine, s: &Specimen) -> Rheology {
        Rheology {
            machine_k1: m.k1,
            machine_k2: m.k2.unwrap(),
            specimen_k1: s.k1,
            specimen_k2: s.k2,
            viscosity: s.eta,
        }
    }

    #[test]
    fn plate_displacement_matches_the_theory_module() {
        let r = rheology(&MACHINE, &SPECIMEN);
        let samples = r.simulate(&schedule(), 40).unwrap();
        let t: Vec<f64> = samples.iter().map(|s| s.t).collect();
        let p: Vec<f64> = samples.iter().map(|s| s.p).collect();
        let (h, _) = plate_displacement(&t, &p, &MACHINE, &SPECIMEN);
        let scale = samples.iter().map(|s| s.h.abs()).fold(0.0, f64::max);
        for (s, h) in samples.iter().zip(&h) {
            assert!((s.h - h).abs() < FORWARD_TOL * scale, "{} vs {h}", s.h);
        }
        assert!((relaxation_time(&MACHINE, &SPECIMEN).0 - r.tau()).abs() < 1e-14 * r.tau());
        assert!((MACHINE.chi() - r.chi()).abs() < 1e-14 * r.chi());
    }

    #[test]
    fn ideal_machine_creep_is_the_standard_linear_solid() {
        // a step to P then a hold: h = P/K₁ + P/K₂ (1 − e^{−t K₂/η}) after the step
        let p = 5e3;
        let t: Vec<f64> = (0..60).map(|i| i as f64 * 0.1).collect();
        let load: Vec<f64> = t.iter().map(|&t| if t > 0.0 { p } else { 0.0 }).collect();
        let (h, _) = plate_displacement(&t, &load, &Machine::IDEAL, &SPECIMEN);
        // the first interval ramps (piecewise-linear P): compare from its end on, where
        // the ramp's exact Kelvin extension is the initial condition
        let tau = SPECIMEN.eta / SPECIMEN.k2;
        let (x, dt) = (0.1 / tau, 0.1);
        let d2_1 = p / SPECIMEN.k2 * (1.0 - (1.0 - (-x).exp()) / x);
        for i in 1..t.len() {
            let s = t[i] - dt;
            let d2 = p / SPECIMEN.k2 + (d2_1 - p / SPECIMEN.k2) * (-s / tau).exp();
            let expect = p / SPECIMEN.k1 + d2;
            assert!(
                (h[i] - expect).abs() < 1e-12 * expect,
                "{i}: {} vs {expect}",
                h[i]
            );
        }
    }

    #[test]
    fn jacobian_is_the_derivative_of_the_displacement() {
        let r = rheology(&MACHINE, &SPECIMEN);
        let samples = r.simulate(&schedule(), 25).unwrap();
        let t: Vec<f64> = samples.iter().map(|s| s.t).collect();
        // a preload, so the relaxed initial state is exercised too
        let p: Vec<f64> = samples.iter().map(|s| s.p + 500.0).collect();
        for machine in [MACHINE, Machine::IDEAL] {
            let (_, dh) = plate_displacement(&t, &p, &machine, &SPECIMEN);
            let base = [SPECIMEN.k1, SPECIMEN.k2, SPECIMEN.eta];
            for k in 0..3 {
                let step = 1e-6 * base[k];
                let at = |sign: f64| {
                    let mut q = base;
                    q[k] += sign * step;
                    plate_displacement(&t, &p, &machine, &Specimen::from_slice(&q)).0
                };
                let (hp, hm) = (at(1.0), at(-1.0));
                let scale = dh.iter().map(|d| d[k].abs()).fold(0.0, f64::max);
                for i in 0..t.len() {
                    let fd = (hp[i] - hm[i]) / (2.0 * step);
                    assert!(
                        (fd - dh[i][k]).abs() < FD_TOL * scale,
                        "param {k}, sample {i}: {fd} vs {}",
                        dh[i][k]
                    );
                }
            }
            let (_, dtau) = relaxation_time(&machine, &SPECIMEN);
            for k in 0..3 {
                let mut q = [SPECIMEN.k1, SPECIMEN.k2, SPECIMEN.eta];
                let step = 1e-6 * q[k];
                q[k] += step;
                let up = relaxation_time(&machine, &Specimen::from_slice(&q)).0;
                q[k] -= 2.0 * step;
                let down = relaxation_time(&machine, &Specimen::from_slice(&q)).0;
                let fd = (up - down) / (2.0 * step);
                assert!(
                    (fd - dtau[k]).abs() < FD_TOL * dtau[k].abs().max(1e-30),
                    "{k}"
                );
            }
        }
    }

    #[test]
    fn a_record_built_by_hand_is_checked_not_trusted() {
        let t: Vec<f64> = (0..12).map(f64::from).collect();
        let mut r = IndentationRecord {
            time: t.clone(),
            load: t.clone(),
            displacement: t[..11].to_vec(),
            format: super::super::record::Format::Csv,
            columns: Default::default(),
        };
        assert!(matches!(
            fit(&r, &Machine::IDEAL),
            Err(FitError::InvalidRecord(_))
        ));
        r.displacement = t.clone();
        r.time[5] = r.time[4];
        assert!(matches!(
            fit(&r, &Machine::IDEAL),
            Err(FitError::InvalidRecord(_))
        ));
        r.time = vec![];
        assert!(matches!(
            fit(&r, &Machine::IDEAL),
            Err(FitError::InvalidRecord(_))
        ));
    }

    #[test]
    fn a_bad_machine_is_refused() {
        let bad = Machine { k1: -1.0, k2: None };
        assert!(matches!(bad.check(), Err(FitError::Machine { .. })));
        let bad = Machine {
            k1: 1.0,
            k2: Some(0.0),
        };
        assert!(matches!(bad.check(), Err(FitError::Machine { .. })));
    }
}
