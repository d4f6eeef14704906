//! Nonlinear least squares by Levenberg–Marquardt, with the parameter covariance.
//!
//! Minimises the cost C(p) = ½‖r(p)‖² over p ∈ ℝⁿ for a residual vector r ∈ ℝᵐ (m ≥ n) with
//! an exact Jacobian J = ∂r/∂p. Each step solves the damped normal equations
//!
//! (JᵀJ + λ·diag(JᵀJ)) δ = −Jᵀr
//!
//! (Marquardt's scaling, so the step is invariant under rescaling of the parameters) and updates
//! λ by Nielsen's rule from the gain ratio ρ = (actual decrease)/(decrease predicted by the
//! linear model). Convergence follows MINPACK's scale-free tests: the cosine between r and any
//! column of J (gradient test), the scaled step size, or the relative decrease of the cost.
//!
//! A problem may declare a parameter vector infeasible (outside the model's domain, e.g. a
//! negative length scale): such a trial step is treated as a failed step and the damping grows.
//!
//! At the optimum the covariance of the estimate is Σ = s²(JᵀJ)⁻¹ with s² = 2C/(m − n), the
//! residual variance; its diagonal gives the standard errors (Gauss–Markov, for independent
//! equal-variance errors — the usual nonlinear-regression reading, e.g. Seber & Wild 1989 §2.1).

use nalgebra::{DMatrix, DVector};

/// A least-squares problem: residuals and their exact Jacobian.
pub trait Problem {
    /// Number of parameters n.
    fn parameters(&self) -> usize;
    /// Residuals r(p) (length m), or `None` when `p` lies outside the model's domain.
    fn residuals(&self, p: &[f64]) -> Option<DVector<f64>>;
    /// The Jacobian ∂rᵢ/∂pⱼ (m × n) at a feasible `p`.
    fn jacobian(&self, p: &[f64]) -> DMatrix<f64>;
}

/// Settings of [`solve`].
#[derive(Debug, Clone, Copy)]
pub struct Params {
    /// iteration limit (Jacobian evaluations)
    pub max_iterations: usize,
    /// gradient test: stop when max_j |Jⱼ·r| / (‖Jⱼ‖‖r‖) ≤ this
    pub gradient_tol: f64,
    /// step test: stop when ‖D δ‖ ≤ this · (‖D p‖ + this), D the column norms of J
    pub step_tol: f64,
    /// cost test: stop when the actual and the predicted relative decrease are both ≤ this
    pub cost_tol: f64,
    /// initial damping λ (relative to diag JᵀJ)
    pub initial_damping: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            max_iterations: 500,
            gradient_tol: 1e-10,
            step_tol: 1e-12,
            cost_tol: 1e-14,
            initial_damping: 1e-3,
        }
    }
}

/// Why the iteration stopped successfully.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// the residual is orthogonal to the columns of J (gradient test)
    Gradient,
    /// the scaled step became negligible
    Step,
    /// the cost stopped decreasing
    Cost,
    /// the residual vanished (an exact fit)
    ZeroResidual,
}

/// Diagnostics of a converged fit.
#[derive(Debug, Clone)]
pub struct Info {
    /// accepted plus rejected iterations
    pub iterations: usize,
    /// residual evaluations
    pub evaluations: usize,
    /// final cost ½‖r‖²
    pub cost: f64,
    /// cost history, one entry per accepted step (starting with the initial cost)
    pub cost_history: Vec<f64>,
    /// why it stopped
    pub termination: Termination,
    /// covariance s²(JᵀJ)⁻¹ of the parameters; `None` when m = n or JᵀJ is singular
    pub covariance: Option<DMatrix<f64>>,
}

impl Info {
    /// Standard errors √Σⱼⱼ of the parameters, when the covariance exists.
    pub fn std_errors(&self) -> Option<Vec<f64>> {
        self.covariance
            .as_ref()
            .map(|c| (0..c.nrows()).map(|j| c[(j, j)].max(0.0).sqrt()).collect())
    }
}

/// Why a fit failed.
#[derive(Debug, Clone, thiserror::Error)]
pub enum Error {
    /// fewer residuals than parameters
    #[error("{residuals} data points cannot determine {parameters} parameters")]
    Underdetermined {
        /// m
        residuals: usize,
        /// n
        parameters: usize,
    },
    /// the starting point is infeasible or gives non-finite residuals
    #[error("the starting parameters {start:?} are outside the model's domain")]
    BadStart {
        /// the starting vector
        start: Vec<f64>,
    },
    /// the Jacobian has a non-finite entry
    #[error("non-finite Jacobian at parameters {at:?}")]
    NonFiniteJacobian {
        /// where
        at: Vec<f64>,
    },
    /// the iteration limit was reached
    #[error(
        "no convergence in {iterations} iterations (cost {cost:e}, gradient cosine {gradient:e})"
    )]
    NoConvergence {
        /// iterations done
        iterations: usize,
        /// cost reached
        cost: f64,
        /// gradient test value reached
        gradient: f64,
        /// the best parameters found
        best: Vec<f64>,
    },
}

fn finite(r: &DVector<f64>) -> bool {
    r.iter().all(|x| x.is_finite())
}

/// Minimise ½‖r(p)‖² from `start`. Returns the optimum and its diagnostics.
pub fn solve<P: Problem>(
    problem: &P,
    start: &[f64],
    params: &Params,
) -> Result<(Vec<f64>, Info), Error> {
    let n = problem.parameters();
    let (mut p, mut r) = start_point(problem, start)?;
    let m = r.len();
    let mut evaluations = 1;
    let mut cost = 0.5 * r.norm_squared();
    let mut history = vec![cost];
    let mut lambda = params.initial_damping;
    let mut nu = 2.0;
    let mut gradient_test = f64::INFINITY;
    let mut iterations = 0;
    let mut j = problem.jacobian(p.as_slice());
    let termination = loop {
        if iterations >= params.max_iterations {
            return Err(Error::NoConvergence {
                iterations,
                cost,
                gradient: gradient_test,
                best: p.as_slice().to_vec(),
            });
        }
        if j.iter().any(|x| !x.is_finite()) {
            return Err(Error::NonFiniteJacobian {
                at: p.as_slice().to_vec(),
            });
        }
        let r_norm = r.norm();
        if r_norm == 0.0 {
            break Termination::ZeroResidual;
        }
        let col_norms: Vec<f64> = (0..n).map(|c| j.column(c).norm()).collect();
        let g = j.transpose() * &r;
        gradient_test = (0..n)
            .filter(|&c| col_norms[c] > 0.0)
            .map(|c| g[c].abs() / (col_norms[c] * r_norm))
            .fold(0.0, f64::max);
        if gradient_test <= params.gradient_tol {
            break Termination::Gradient;
        }
        // One damped step; on rejection the damping grows and the step is retried.
        iterations += 1;
        let Some(delta) = damped_step(&j, &g, lambda) else {
            lambda *= nu;
            nu *= 2.0;
            continue;
        };
        let trial = &p + &delta;
        evaluations += 1;
        let trial_r = problem.residuals(trial.as_slice()).filter(finite);
        let predicted = -(g.dot(&delta)) - 0.5 * (&j * &delta).norm_squared();
        let accepted = match trial_r {
            Some(tr) => {
                let trial_cost = 0.5 * tr.norm_squared();
                let rho = if predicted > 0.0 {
                    (cost - trial_cost) / predicted
                } else {
                    -1.0
                };
                if rho > 0.0 {
                    let step_scaled = scaled_norm(&col_norms, &delta);
                    let p_scaled = scaled_norm(&col_norms, &p);
                    let actual_rel = (cost - trial_cost) / cost;
                    let predicted_rel = predicted / cost;
                    p = trial;
                    r = tr;
                    cost = trial_cost;
                    history.push(cost);
                    j = problem.jacobian(p.as_slice());
                    lambda *= (1.0f64 / 3.0).max(1.0 - (2.0 * rho - 1.0).powi(3));
                    nu = 2.0;
                    if step_scaled <= params.step_tol * (p_scaled + params.step_tol) {
                        break Termination::Step;
                    }
                    if actual_rel.abs() <= params.cost_tol && predicted_rel <= params.cost_tol {
                        break Termination::Cost;
                    }
                    true
                } else {
                    false
                }
            }
            None => false,
        };
        if !accepted {
            lambda *= nu;
            nu *= 2.0;
            if !lambda.is_finite() || lambda > 1e300 {
                // the damping cannot grow further: no descent direction remains at this
                // precision, which is convergence of the cost
                break Termination::Cost;
            }
        }
    };
    let covariance = covariance(&j, cost, m, n);
    Ok((
        p.as_slice().to_vec(),
        Info {
            iterations,
            evaluations,
            cost,
            cost_history: history,
            termination,
            covariance,
        },
    ))
}

/// The start and its residuals: finite, and at least as many as parameters.
fn start_point<P: Problem>(
    problem: &P,
    start: &[f64],
) -> Result<(DVector<f64>, DVector<f64>), Error> {
    let n = problem.parameters();
    let p = DVector::from_column_slice(start);
    let r = problem
        .residuals(p.as_slice())
        .filter(finite)
        .ok_or_else(|| Error::BadStart {
            start: start.to_vec(),
        })?;
    if r.len() < n {
        return Err(Error::Underdetermined {
            residuals: r.len(),
            parameters: n,
        });
    }
    Ok((p, r))
}

/// The Levenberg–Marquardt step δ of (JᵀJ + λ diag(JᵀJ)) δ = −g (Marquardt's scaling), None if the
/// damped matrix does not factor.
fn damped_step(j: &DMatrix<f64>, g: &DVector<f64>, lambda: f64) -> Option<DVector<f64>> {
    let jtj = j.transpose() * j;
    let mut a = jtj.clone();
    for c in 0..jtj.ncols() {
        a[(c, c)] += lambda * jtj[(c, c)].max(f64::MIN_POSITIVE);
    }
    Some(a.cholesky()?.solve(&(-g)))
}

/// |D v| with D = diag(column norms of J): a step or a point in the scaled variables.
fn scaled_norm(col_norms: &[f64], v: &DVector<f64>) -> f64 {
    col_norms
        .iter()
        .zip(v.iter())
        .map(|(c, x)| (c * x).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// s²(JᵀJ)⁻¹, computed with the columns scaled to unit norm for conditioning.
fn covariance(j: &DMatrix<f64>, cost: f64, m: usize, n: usize) -> Option<DMatrix<f64>> {
    if m <= n {
        return None;
    }
    let scale: Vec<f64> = (0..n).map(|c| j.column(c).norm()).collect();
    if scale.iter().any(|&s| s == 0.0 || !s.is_finite()) {
        return None;
    }
    let mut js = j.clone();
    for (c, s) in scale.iter().enumerate() {
        js.column_mut(c).scale_mut(1.0 / s);
    }
    let inv = (js.transpose() * &js).cholesky()?.inverse();
    let s2 = 2.0 * cost / (m - n) as f64;
    let cov = DMatrix::from_fn(n, n, |a, b| s2 * inv[(a, b)] / (scale[a] * scale[b]));
    cov.iter().all(|x| x.is_finite()).then_some(cov)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// y = a·exp(−b·x) sampled at given points.
    struct Exp {
        x: Vec<f64>,
        y: Vec<f64>,
    }
    impl Problem for Exp {
        fn parameters(&self) -> usize {
            2
        }
        fn residuals(&self, p: &[f64]) -> Option<DVector<f64>> {
            (p[1] > -10.0).then(|| {
                DVector::from_iterator(
                    self.x.len(),
                    self.x
                        .iter()
                        .zip(&self.y)
                        .map(|(x, y)| p[0] * (-p[1] * x).exp() - y),
                )
            })
        }
        fn jacobian(&self, p: &[f64]) -> DMatrix<f64> {
            DMatrix::from_fn(self.x.len(), 2, |i, c| {
                let e = (-p[1] * self.x[i]).exp();
                if c == 0 {
                    e
                } else {
                    -p[0] * self.x[i] * e
                }
            })
        }
    }

    #[test]
    fn exact_data_is_recovered_to_rounding() {
        let x: Vec<f64> = (0..20).map(|i| i as f64 * 0.2).collect();
        let y = x.iter().map(|x| 3.0 * (-0.7 * x).exp()).collect();
        let (p, info) = solve(&Exp { x, y }, &[1.0, 0.1], &Params::default()).unwrap();
        // rounding of a well-conditioned 2-parameter problem
        const TOL: f64 = 1e-10;
        assert!(
            (p[0] - 3.0).abs() < TOL && (p[1] - 0.7).abs() < TOL,
            "{p:?}"
        );
        assert!(info.cost < 1e-20);
        assert!(info.cost_history.windows(2).all(|w| w[1] <= w[0]));
    }

    #[test]
    fn linear_model_matches_the_normal_equations_covariance() {
        // For a linear model LM is exact in one step and Σ = s²(XᵀX)⁻¹ is the textbook result.
        struct Line {
            x: Vec<f64>,
            y: Vec<f64>,
        }
        impl Problem for Line {
            fn parameters(&self) -> usize {
                2
            }
            fn residuals(&self, p: &[f64]) -> Option<DVector<f64>> {
                Some(DVector::from_iterator(
                    self.x.len(),
                    self.x.iter().zip(&self.y).map(|(x, y)| p[0] + p[1] * x - y),
                ))
            }
            fn jacobian(&self, _p: &[f64]) -> DMatrix<f64> {
                DMatrix::from_fn(self.x.len(), 2, |i, c| if c == 0 { 1.0 } else { self.x[i] })
            }
        }
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        let x: Vec<f64> = (0..30).map(|i| i as f64).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|x| 1.0 + 0.5 * x + rng.random_range(-0.3..0.3))
            .collect();
        let (p, info) = solve(
            &Line {
                x: x.clone(),
                y: y.clone(),
            },
            &[0.0, 0.0],
            &Params::default(),
        )
        .unwrap();
        let nf = x.len() as f64;
        let (sx, sxx) = (x.iter().sum::<f64>(), x.iter().map(|v| v * v).sum::<f64>());
        let (sy, sxy) = (
            y.iter().sum::<f64>(),
            x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>(),
        );
        let det = nf * sxx - sx * sx;
        let b = (nf * sxy - sx * sy) / det;
        let a = (sy - b * sx) / nf;
        let ssr: f64 = x.iter().zip(&y).map(|(x, y)| (a + b * x - y).powi(2)).sum();
        let s2 = ssr / (nf - 2.0);
        let se_b = (s2 * nf / det).sqrt();
        let se = info.std_errors().unwrap();
        // closed-form normal equations versus the iterative solve: rounding only
        const TOL: f64 = 1e-9;
        assert!((p[0] - a).abs() < TOL && (p[1] - b).abs() < TOL);
        assert!((se[1] / se_b - 1.0).abs() < TOL, "{} {}", se[1], se_b);
    }

    #[test]
    fn infeasible_start_and_underdetermined_are_errors() {
        let e = Exp {
            x: vec![0.0, 1.0],
            y: vec![1.0, 0.5],
        };
        assert!(matches!(
            solve(&e, &[1.0, -20.0], &Params::default()),
            Err(Error::BadStart { .. })
        ));
        let e1 = Exp {
            x: vec![0.0],
            y: vec![1.0],
        };
        assert!(matches!(
            solve(&e1, &[1.0, 1.0], &Params::default()),
            Err(Error::Underdetermined { .. })
        ));
    }
}
