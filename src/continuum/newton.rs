//! Newton's method with a backtracking line search on the total potential, for the equilibrium
//! of one increment: find x with ∇Π(x) = 0 by K Δx = −∇Π, x ← x + sΔx.
//!
//! The step length s starts at 1 and is halved until the energy decreases sufficiently
//! (Armijo: Π(x + sΔx) ≤ Π(x) + c s ∇Π·Δx, with a round-off allowance) or the residual norm
//! decreases; a trial that cannot be evaluated (an inverted element) is also halved. The
//! iteration converges when ‖∇Π‖ ≤ max(rtol·F_ref, atol), F_ref the magnitude of the forces
//! in play (reactions included), so the criterion does not depend on the units of the problem.
//! Non-convergence is an error carrying the residual history; the caller cuts the increment
//! back. The iteration is [`crate::numerics::newton::solve`]; this module holds the continuum's
//! plug-ins to it.

use super::FeError;
use crate::numerics::newton::{self as driver, armijo, norm, NewtonProblem, Trial};
pub use crate::numerics::newton::{NewtonInfo, NewtonParams};

/// Why Newton failed: the problem's failures are the continuum's errors.
pub type NewtonError = driver::NewtonError<FeError>;

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
    fn evaluate(&mut self, x: &[f64], tangent: bool) -> Result<Point, FeError>;
    /// Solve K d = rhs with K given by `values`.
    fn solve(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, FeError>;
}

/// The continuum's plug-ins to the Newton loop: the L2 norm of ∇Π against the reference force,
/// the problem's own linear solve, and a trial accepted on Armijo's decrease of Π (with a
/// round-off allowance) or on a decrease of the residual; a trial that cannot be evaluated (an
/// inverted element) is rejected.
struct Potential<'a> {
    sys: &'a mut dyn NewtonSystem,
    params: &'a NewtonParams,
    /// the iterate's point (with its tangent)
    point: Option<Point>,
    trial: Vec<f64>,
}

impl Potential<'_> {
    fn point(&self) -> Result<&Point, FeError> {
        self.point.as_ref().ok_or(FeError::NoPoint)
    }
}

impl NewtonProblem for Potential<'_> {
    type Error = FeError;

    fn residual(&mut self, x: &[f64]) -> Result<f64, FeError> {
        if self.point.is_none() {
            self.point = Some(self.sys.evaluate(x, true)?);
        }
        Ok(norm(&self.point()?.residual))
    }

    fn converged(&self, residuals: &[f64]) -> bool {
        self.point
            .as_ref()
            .is_some_and(|pt| self.params.converged(residuals, pt.reference))
    }

    fn direction(&mut self, _x: &[f64]) -> Result<Vec<f64>, FeError> {
        let pt = self.point.as_ref().ok_or(FeError::NoPoint)?;
        let rhs: Vec<f64> = pt.residual.iter().map(|r| -r).collect();
        self.sys.solve(&pt.values, &rhs)
    }

    fn try_step(&mut self, x: &mut [f64], dx: &[f64], s: f64) -> Result<Trial, FeError> {
        for ((t, xi), di) in self.trial.iter_mut().zip(x.iter()).zip(dx) {
            *t = xi + s * di;
        }
        let next = match self.sys.evaluate(&self.trial, true) {
            Ok(next) => next,
            Err(e) => return Ok(Trial::Rejected(e.to_string())),
        };
        let pt = self.point()?;
        let slope: f64 = pt.residual.iter().zip(dx).map(|(r, d)| r * d).sum();
        let rn = norm(&pt.residual);
        let allowance = 1e-12 * pt.energy.abs();
        if armijo(
            pt.energy,
            next.energy,
            self.params.armijo,
            s,
            slope,
            allowance,
        ) || norm(&next.residual) < rn
        {
            x.copy_from_slice(&self.trial);
            self.point = Some(next);
            return Ok(Trial::Accepted);
        }
        Ok(Trial::Rejected(format!(
            "energy {:.6e} → {:.6e}, residual {rn:.3e} → {:.3e}",
            pt.energy,
            next.energy,
            norm(&next.residual)
        )))
    }
}

/// Solve ∇Π(x) = 0 from the starting point `x` (overwritten by the solution).
pub fn solve(
    sys: &mut dyn NewtonSystem,
    x: &mut [f64],
    params: &NewtonParams,
) -> Result<NewtonInfo, NewtonError> {
    let mut problem = Potential {
        sys,
        params,
        point: None,
        trial: x.to_vec(),
    };
    driver::solve(&mut problem, x, params)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Π = Σ (x_i⁴/4 + x_i²/2 − b_i x_i): a convex problem with a dense enough nonlinearity.
    struct Quartic {
        b: Vec<f64>,
    }

    impl NewtonSystem for Quartic {
        fn evaluate(&mut self, x: &[f64], _tangent: bool) -> Result<Point, FeError> {
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
        fn solve(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, FeError> {
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
}
