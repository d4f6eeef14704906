//! Newton's method with a backtracking line search on the total potential, for the equilibrium
//! of one increment: find x with ∇Π(x) = 0 by K Δx = −∇Π, x ← x + sΔx.
//!
//! The step length s starts at 1 and is halved until the energy decreases sufficiently
//! (Armijo: Π(x + sΔx) ≤ Π(x) + c s ∇Π·Δx, with a round-off allowance) or the residual norm
//! decreases; a trial that cannot be evaluated (an inverted element) is also halved. The
//! iteration converges when ‖∇Π‖ ≤ max(rtol·F_ref, atol), F_ref the magnitude of the forces
//! in play (reactions included), so the criterion does not depend on the units of the problem.
//! Non-convergence is an error carrying the residual history; the caller cuts the increment
//! back.

use serde::{Deserialize, Serialize};

/// Newton parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct NewtonParams {
    /// iterations before giving up
    pub max_iterations: usize,
    /// relative residual tolerance (to the reference force)
    pub rtol: f64,
    /// absolute residual tolerance, nN
    pub atol: f64,
    /// halvings of the step before the line search gives up
    pub max_backtracks: usize,
    /// Armijo constant c
    pub armijo: f64,
    /// a residual below this fraction of the first one that no longer halves per iteration has
    /// reached round-off (e.g. of C − I in large, barely strained elements): converged. 1e-6:
    /// a 10 µm Hertz block unloading to δ → 0 floors at ~4e-7 of the increment's first
    /// residual (the net force there is tiny, so the relative test alone never passes)
    pub stagnation: f64,
}

impl Default for NewtonParams {
    fn default() -> Self {
        NewtonParams {
            max_iterations: 30,
            rtol: 1e-9,
            atol: 1e-12,
            max_backtracks: 20,
            armijo: 1e-4,
            stagnation: 1e-6,
        }
    }
}

/// How a converged solve went.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct NewtonInfo {
    /// Newton iterations (linear solves)
    pub iterations: usize,
    /// residual norm at each iteration, nN
    pub residuals: Vec<f64>,
    /// total step halvings of the line search
    pub backtracks: usize,
}

/// Why Newton failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NewtonError {
    /// the iteration limit was reached
    #[error("no convergence in {iterations} iterations (residuals {residuals:?})")]
    NoConvergence {
        /// iterations done
        iterations: usize,
        /// residual history, nN
        residuals: Vec<f64>,
    },
    /// the line search found no acceptable step
    #[error("line search failed after {backtracks} halvings at iteration {iteration}: {reason}")]
    LineSearch {
        /// iteration
        iteration: usize,
        /// halvings
        backtracks: usize,
        /// the last trial's problem
        reason: String,
    },
    /// the starting point or the linear solve failed
    #[error("{0}")]
    System(String),
}

/// A point of the problem: energy, gradient (zero on constrained entries), reference force
/// and, if asked for, the tangent's values.
#[derive(Debug, Clone, Default)]
pub struct Point {
    /// Π, aJ
    pub energy: f64,
    /// ∇Π on the free unknowns (0 on constrained ones), nN
    pub residual: Vec<f64>,
    /// magnitude of the forces in play, nN
    pub reference: f64,
    /// tangent values in the problem's sparse pattern (empty if not asked for)
    pub values: Vec<f64>,
}

/// What Newton needs from a problem.
pub trait NewtonSystem {
    /// Energy, residual and (if `tangent`) the tangent at `x`.
    fn evaluate(&mut self, x: &[f64], tangent: bool) -> Result<Point, String>;
    /// Solve K d = rhs with K given by `values`.
    fn solve(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, String>;
}

/// A residual that has stopped halving counts as round-off only below this fraction of the
/// reference force: a round-off floor lies many decades below the forces in play, while a
/// first residual inflated by a stiff machine spring (K Δ for K ≫ the contact stiffness) can
/// put 1e-6 of it at a third of the load (tests/integration/extremes.rs, stiff spring).
const STALL_CEILING: f64 = 1e-3;

/// The convergence test on a residual history (the last entry is the current residual):
/// below the tolerance relative to the `reference` force, or stalled at round-off.
pub fn converged(residuals: &[f64], reference: f64, params: &NewtonParams) -> bool {
    let (Some(&rn), Some(&r0)) = (residuals.last(), residuals.first()) else {
        return false;
    };
    let stalled = residuals.len() > 1
        && rn <= params.stagnation * r0
        && rn > 0.5 * residuals[residuals.len() - 2]
        && rn <= STALL_CEILING * reference;
    rn <= (params.rtol * reference).max(params.atol) || stalled
}

pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Solve ∇Π(x) = 0 from the starting point `x` (overwritten by the solution).
pub fn solve(
    sys: &mut dyn NewtonSystem,
    x: &mut [f64],
    params: &NewtonParams,
) -> Result<NewtonInfo, NewtonError> {
    let mut info = NewtonInfo::default();
    let mut pt = sys.evaluate(x, true).map_err(NewtonError::System)?;
    let mut trial = x.to_vec();
    loop {
        let rn = norm(&pt.residual);
        info.residuals.push(rn);
        if converged(&info.residuals, pt.reference, params) {
            return Ok(info);
        }
        if info.iterations >= params.max_iterations {
            return Err(NewtonError::NoConvergence {
                iterations: info.iterations,
                residuals: info.residuals,
            });
        }
        info.iterations += 1;
        let rhs: Vec<f64> = pt.residual.iter().map(|r| -r).collect();
        let dx = sys.solve(&pt.values, &rhs).map_err(NewtonError::System)?;
        let slope: f64 = pt.residual.iter().zip(&dx).map(|(r, d)| r * d).sum();
        let mut s = 1.0;
        let mut reason = String::new();
        let mut accepted = None;
        for _ in 0..=params.max_backtracks {
            for ((t, xi), di) in trial.iter_mut().zip(x.iter()).zip(&dx) {
                *t = xi + s * di;
            }
            match sys.evaluate(&trial, true) {
                Ok(next) => {
                    let allowance = 1e-12 * pt.energy.abs();
                    let armijo =
                        next.energy <= pt.energy + params.armijo * s * slope.min(0.0) + allowance;
                    if armijo || norm(&next.residual) < rn {
                        accepted = Some(next);
                        break;
                    }
                    reason = format!(
                        "energy {:.6e} → {:.6e}, residual {rn:.3e} → {:.3e}",
                        pt.energy,
                        next.energy,
                        norm(&next.residual)
                    );
                }
                Err(e) => reason = e,
            }
            s *= 0.5;
            info.backtracks += 1;
        }
        match accepted {
            Some(next) => {
                x.copy_from_slice(&trial);
                pt = next;
            }
            None => {
                return Err(NewtonError::LineSearch {
                    iteration: info.iterations,
                    backtracks: params.max_backtracks,
                    reason,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Π = Σ (x_i⁴/4 + x_i²/2 − b_i x_i): a convex problem with a dense enough nonlinearity.
    struct Quartic {
        b: Vec<f64>,
    }

    impl NewtonSystem for Quartic {
        fn evaluate(&mut self, x: &[f64], _tangent: bool) -> Result<Point, String> {
            Ok(Point {
                energy: x
                    .iter()
                    .zip(&self.b)
                    .map(|(x, b)| x.powi(4) / 4.0 + x * x / 2.0 - b * x)
                    .sum(),
                residual: x
                    .iter()
                    .zip(&self.b)
                    .map(|(x, b)| x.powi(3) + x - b)
                    .collect(),
                reference: norm(&self.b),
                values: x.iter().map(|x| 3.0 * x * x + 1.0).collect(),
            })
        }
        fn solve(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, String> {
            Ok(rhs.iter().zip(values).map(|(r, k)| r / k).collect())
        }
    }

    #[test]
    fn converges_quadratically_from_far_away() {
        let mut p = Quartic {
            b: vec![1000.0, -3.0, 0.5],
        };
        let mut x = vec![0.0; 3];
        let info = solve(&mut p, &mut x, &NewtonParams::default()).unwrap();
        for (x, b) in x.iter().zip(&p.b) {
            assert!((x.powi(3) + x - b).abs() < 1e-9 * 1000.0);
        }
        // the last steps are quadratic
        let r = &info.residuals;
        let n = r.len();
        assert!(
            r[n - 1] < 1e-3 * r[n - 2].max(1e-30) || r[n - 1] == 0.0,
            "{r:?}"
        );
    }

    #[test]
    fn iteration_limit_is_an_error_with_history() {
        let mut p = Quartic { b: vec![1e3] };
        let mut x = vec![0.0];
        let e = solve(
            &mut p,
            &mut x,
            &NewtonParams {
                max_iterations: 2,
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(
            matches!(e, NewtonError::NoConvergence { iterations: 2, ref residuals } if residuals.len() == 3)
        );
    }
}
