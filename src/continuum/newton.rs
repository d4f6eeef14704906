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
//!
//! **Descent** ([`descend`], the snap of [`super::march`]): past a fold of the depth, K is
//! indefinite and Newton's step heads for the saddle of the unstable branch as readily as for
//! a minimum. The descent instead factors K + σ·diag|K| by Cholesky, with the smallest σ of the
//! ladder 0, σ₀, 10σ₀, … that is positive definite (the last σ/10 tried first; Nocedal & Wright,
//! Alg. 3.3, with the scaled shift of Levenberg–Marquardt), so every step is a descent
//! direction; it accepts a trial on Armijo's decrease of Π (or, once Π's changes sink into
//! round-off, on a lower residual with Π not higher) and stops only at a point where the
//! residual is at tolerance *and* its last step needed no shift (K positive definite at the
//! last iterate, a step of round-off size away): a strict local minimum. Near a fold K is
//! nearly singular and its unshifted step can be orders of magnitude longer than the jump
//! itself; where every halving of a direction is rejected (Π higher, or a trial outside the
//! material's range), the next direction is shifted at least ten times harder, hence shorter.

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
    /// Solve (K + σ·diag|K|) d = rhs by Cholesky; `None` where that matrix is not positive
    /// definite.
    fn solve_shifted(
        &mut self,
        values: &[f64],
        shift: f64,
        rhs: &[f64],
    ) -> Result<Option<Vec<f64>>, FeError>;
}

/// The shift ladder of the descent: the first nonzero σ, its growth, and how many
/// factorisations one direction may try.
const SHIFT_START: f64 = 1e-8;
const SHIFT_GROWTH: f64 = 10.0;
const MAX_SHIFTS: usize = 30;

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
    /// descent (see the module doc): the shift of the last direction
    descent: Option<f64>,
    /// a descent at a minimum whose residual sank into round-off (see `exhausted`)
    stalled: bool,
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
        // a descent stops at a minimum: its last direction needed no shift
        self.stalled
            || self.descent.is_none_or(|shift| shift == 0.0)
                && self
                    .point
                    .as_ref()
                    .is_some_and(|pt| self.params.converged(residuals, pt.reference))
    }

    /// A descent whose unshifted Newton step (K positive definite) finds neither a lower Π
    /// nor a lower residual, with the residual below `stagnation` of the forces in play, sits
    /// at a minimum to round-off: converged. Any other descent direction rejected at every
    /// length is replaced by a harder-shifted one.
    fn exhausted(&mut self, _x: &mut [f64]) -> bool {
        let floor = self
            .point
            .as_ref()
            .is_some_and(|pt| norm(&pt.residual) <= self.params.stagnation * pt.reference);
        self.stalled = self.descent == Some(0.0) && floor;
        if self.stalled {
            return true;
        }
        // a descent direction that could not be taken at any length: the next one starts ten
        // times above this one's shift (`direction` tries a tenth of the last shift first)
        match self.descent {
            Some(shift) => {
                self.descent = Some(shift.max(SHIFT_START) * SHIFT_GROWTH * SHIFT_GROWTH);
                true
            }
            None => false,
        }
    }

    fn direction(&mut self, _x: &[f64]) -> Result<Vec<f64>, FeError> {
        let pt = self.point.as_ref().ok_or(FeError::NoPoint)?;
        let rhs: Vec<f64> = pt.residual.iter().map(|r| -r).collect();
        let Some(last) = self.descent else {
            return self.sys.solve(&pt.values, &rhs);
        };
        let mut shift = if last / SHIFT_GROWTH < SHIFT_START {
            0.0
        } else {
            last / SHIFT_GROWTH
        };
        for _ in 0..MAX_SHIFTS {
            if let Some(d) = self.sys.solve_shifted(&pt.values, shift, &rhs)? {
                self.descent = Some(shift);
                return Ok(d);
            }
            shift = if shift == 0.0 {
                SHIFT_START.max(last / SHIFT_GROWTH)
            } else {
                shift * SHIFT_GROWTH
            };
        }
        Err(FeError::NotDescending { shift })
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
        ) || (norm(&next.residual) < rn
            // a descent takes a lower residual only where Π did not rise beyond round-off
            // (near a minimum its changes sink below it)
            && (self.descent.is_none() || next.energy <= pt.energy + allowance))
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
    iterate(sys, x, params, None)
}

/// Descend from `x` (overwritten) to a strict local minimum of Π (see the module doc).
pub fn descend(
    sys: &mut dyn NewtonSystem,
    x: &mut [f64],
    params: &NewtonParams,
) -> Result<NewtonInfo, NewtonError> {
    iterate(sys, x, params, Some(0.0))
}

/// The Newton loop with the plug-ins of [`Potential`].
fn iterate(
    sys: &mut dyn NewtonSystem,
    x: &mut [f64],
    params: &NewtonParams,
    descent: Option<f64>,
) -> Result<NewtonInfo, NewtonError> {
    let mut problem = Potential {
        sys,
        params,
        point: None,
        trial: x.to_vec(),
        descent,
        stalled: false,
    };
    driver::solve(&mut problem, x, params)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Π = Σ (x_i⁴/4 + c x_i²/2 − b_i x_i): convex for c = 1 (a dense enough nonlinearity), a
    /// double well per coordinate for c = −1 (a maximum near 0).
    struct Quartic {
        b: Vec<f64>,
        c: f64,
        /// the largest |x_i| the problem can evaluate
        range: f64,
    }

    impl NewtonSystem for Quartic {
        fn evaluate(&mut self, x: &[f64], _tangent: bool) -> Result<Point, FeError> {
            if x.iter().any(|x| x.abs() > self.range) {
                return Err(FeError::Params(format!("{x:?} out of range")));
            }
            let (b, c) = (&self.b, self.c);
            Ok(Point {
                energy: (x.iter().zip(b))
                    .map(|(x, b)| x.powi(4) / 4.0 + c * x * x / 2.0 - b * x)
                    .sum(),
                residual: x
                    .iter()
                    .zip(b)
                    .map(|(x, b)| x.powi(3) + c * x - b)
                    .collect(),
                reference: norm(b),
                values: x.iter().map(|x| 3.0 * x * x + c).collect(),
            })
        }
        fn solve(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, FeError> {
            Ok(rhs.iter().zip(values).map(|(r, k)| r / k).collect())
        }
        fn solve_shifted(
            &mut self,
            values: &[f64],
            shift: f64,
            rhs: &[f64],
        ) -> Result<Option<Vec<f64>>, FeError> {
            let k: Vec<f64> = values
                .iter()
                .map(|k| k + shift * k.abs().max(1.0))
                .collect();
            k.iter()
                .all(|&k| k > 0.0)
                .then(|| self.solve(&k, rhs))
                .transpose()
        }
    }

    #[test]
    fn descent_reaches_a_minimum_where_newton_finds_the_maximum() {
        let b = vec![0.01, -0.02];
        let start = vec![0.05, 0.1];
        let well = || Quartic {
            b: b.clone(),
            c: -1.0,
            range: f64::INFINITY,
        };
        let mut x = start.clone();
        solve(&mut well(), &mut x, &NewtonParams::default()).unwrap();
        // Newton: the stationary point nearest the start, the maximum x ≈ −b (x³ − x = b)
        for (x, b) in x.iter().zip(&b) {
            assert!((x + b).abs() < 1e-3 && 3.0 * x * x - 1.0 < 0.0, "{x}");
        }
        let mut x = start;
        let info = descend(&mut well(), &mut x, &NewtonParams::default()).unwrap();
        for (x, b) in x.iter().zip(&b) {
            // a root of x³ − x − b with Π'' = 3x² − 1 > 0: a minimum
            assert!(
                (x.powi(3) - x - b).abs() < 1e-9 && 3.0 * x * x - 1.0 > 0.0,
                "{x}"
            );
        }
        assert!(info.iterations > 1);
    }

    /// Just past the inflection of a double well (Π'' = 3x² − 1 ≈ 4e-12) the unshifted step is
    /// ~10¹¹ long: twenty halvings leave it outside the range the problem can evaluate (|x| ≤
    /// 10) or uphill. The descent shifts harder and still reaches the minimum x = 1.
    #[test]
    fn descent_shifts_harder_where_no_length_of_its_step_is_taken() {
        let mut well = Quartic {
            b: vec![0.0],
            c: -1.0,
            range: 10.0,
        };
        let mut x = vec![1.0 / 3f64.sqrt() + 1e-12];
        let params = NewtonParams::default();
        let info = descend(&mut well, &mut x, &params).unwrap();
        assert!((x[0] - 1.0).abs() < 1e-9, "{x:?}");
        assert!(info.backtracks >= params.max_backtracks, "{info:?}");
        // plain Newton fails there
        let mut x = vec![1.0 / 3f64.sqrt() + 1e-12];
        assert!(matches!(
            solve(&mut well, &mut x, &params),
            Err(NewtonError::LineSearch { .. })
        ));
    }

    #[test]
    fn converges_quadratically_from_far_away() {
        let mut p = Quartic {
            b: vec![1000.0, -3.0, 0.5],
            c: 1.0,
            range: f64::INFINITY,
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
