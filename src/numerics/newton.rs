//! Newton's method with a backtracking line search: the one iteration the continuum, discrete
//! and half-space solvers share (and the arc-length corrector, with full steps).
//!
//! Each iteration: take the residual r at the iterate x; stop when the history of ‖r‖ has
//! converged ([`NewtonParams::converged`]); else ask the problem for a direction d (its own
//! linear algebra: sparse LU or Cholesky, a shifted Cholesky past an instability, a dense LU,
//! a bordered solve) and try x + s d with s from the problem's first step (1, or less where the
//! problem caps the change), shortening s (halving it, unless the problem interpolates) until the
//! problem accepts the trial (its merit: Armijo on an energy, [`armijo`], or a decrease of ‖r‖).
//! What a problem decides — the norm, the direction, the merit, how much shorter the next trial
//! is, what to do when every shortening fails, a step past the accepted one — is a plug-in
//! ([`NewtonProblem`]); the loop, its counts and its errors are here.

use serde::{Deserialize, Serialize};

/// Newton parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct NewtonParams {
    /// iterations before giving up
    pub max_iterations: usize,
    /// relative residual tolerance (to the problem's reference: a force in play, or the first
    /// residual)
    pub rtol: f64,
    /// absolute residual tolerance, in the residual's units
    pub atol: f64,
    /// halvings of the step before the line search gives up
    pub max_backtracks: usize,
    /// Armijo constant c
    pub armijo: f64,
    /// a residual below this fraction of the first one that no longer halves per iteration has
    /// reached round-off (e.g. of C − I in large, barely strained elements): converged. 1e-6:
    /// a 10 µm Hertz block unloading to δ → 0 floors at ~4e-7 of the increment's first
    /// residual (the net force there is tiny, so the relative test alone never passes). 0: off
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

/// A residual that has stopped halving counts as round-off only below this fraction of the
/// reference: a round-off floor lies many decades below the forces in play, while a first
/// residual inflated by a stiff machine spring (K Δ for K ≫ the contact stiffness) can put 1e-6
/// of it at a third of the load (tests/integration/extremes.rs, stiff spring).
const STALL_CEILING: f64 = 1e-3;

impl NewtonParams {
    /// The tolerance on the residual for a problem whose reference is `reference`:
    /// max(rtol · reference, atol).
    pub fn tolerance(&self, reference: f64) -> f64 {
        tolerance(self.atol, self.rtol, reference)
    }

    /// The convergence test on a residual history (the last entry is the current residual):
    /// within [`Self::tolerance`] of `reference`, or stalled at round-off (see `stagnation`).
    pub fn converged(&self, residuals: &[f64], reference: f64) -> bool {
        let (Some(&rn), Some(&r0)) = (residuals.last(), residuals.first()) else {
            return false;
        };
        let stalled = residuals.len() > 1
            && rn <= self.stagnation * r0
            && rn > 0.5 * residuals[residuals.len() - 2]
            && rn <= STALL_CEILING * reference;
        rn <= self.tolerance(reference) || stalled
    }
}

/// How a converged solve went.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct NewtonInfo {
    /// Newton iterations (directions computed)
    pub iterations: usize,
    /// residual norm at each iteration, the starting one first
    pub residuals: Vec<f64>,
    /// total step halvings of the line search
    pub backtracks: usize,
}

/// A residual history for a message: the whole list when it is short, else the first, the
/// smallest (with its iteration) and the last — a failed solve of a thousand iterations must
/// not write a thousand numbers into an error.
pub fn residual_history(residuals: &[f64]) -> String {
    const WHOLE: usize = 8;
    if residuals.len() <= WHOLE {
        let list: Vec<String> = residuals.iter().map(|r| format!("{r:.3e}")).collect();
        return format!("[{}]", list.join(", "));
    }
    let (at, least) = residuals
        .iter()
        .copied()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, residuals[0]));
    format!(
        "{:.3e} at the start, smallest {least:.3e} at iteration {at}, {:.3e} at the last of {}",
        residuals[0],
        residuals[residuals.len() - 1],
        residuals.len()
    )
}

/// Why Newton failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NewtonError<E> {
    /// the iteration limit was reached
    #[error(
        "no convergence in {iterations} iterations (residuals {})",
        residual_history(residuals)
    )]
    NoConvergence {
        /// iterations done
        iterations: usize,
        /// residual history
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
    /// the problem could not be evaluated or its linear system not solved
    #[error("{0}")]
    Problem(E),
}

/// The problem's verdict on a trial point.
#[derive(Debug, Clone, PartialEq)]
pub enum Trial {
    /// taken: the problem moved the iterate there
    Accepted,
    /// not taken, and why
    Rejected(String),
}

/// What the Newton loop needs from a problem; the defaults are plain Newton with
/// backtracking.
pub trait NewtonProblem {
    /// The problem's own failure (evaluation, linear solve).
    type Error;

    /// The residual norm at the iterate `x` (evaluated here or kept from the accepted trial).
    fn residual(&mut self, x: &[f64]) -> Result<f64, Self::Error>;

    /// Whether the residual history (the current one last) has converged.
    fn converged(&self, residuals: &[f64]) -> bool;

    /// The Newton direction at the iterate `x`.
    fn direction(&mut self, x: &[f64]) -> Result<Vec<f64>, Self::Error>;

    /// The step length tried first along `direction` (1 unless the problem caps the change).
    fn first_step(&self, _direction: &[f64]) -> f64 {
        1.0
    }

    /// Try x + s·direction: on [`Trial::Accepted`] the problem has moved `x` there.
    fn try_step(&mut self, x: &mut [f64], direction: &[f64], s: f64) -> Result<Trial, Self::Error>;

    /// The step length to try after `s` was rejected: half of it, unless the problem
    /// interpolates what it learnt at `s`.
    fn shorter(&self, s: f64) -> f64 {
        0.5 * s
    }

    /// Every halving was rejected: true if the problem moved `x` to a point it takes anyway
    /// (the iteration goes on), false to fail with [`NewtonError::LineSearch`].
    fn exhausted(&mut self, _x: &mut [f64]) -> bool {
        false
    }

    /// After the step `s` along `direction` was taken (e.g. to go further along it).
    fn stepped(&mut self, _x: &mut [f64], _direction: &[f64], _s: f64) {}
}

/// Armijo's sufficient decrease of an energy from `e0` to `e1` at step `s` along a direction of
/// slope `slope` (ascent directions count as flat), with a round-off `allowance`.
pub fn armijo(e0: f64, e1: f64, c: f64, s: f64, slope: f64, allowance: f64) -> bool {
    e1 <= e0 + c * s * slope.min(0.0) + allowance
}

/// The residual tolerance max(rtol · reference, atol) (also FIRE's, which is not Newton).
pub fn tolerance(atol: f64, rtol: f64, reference: f64) -> f64 {
    (rtol * reference).max(atol)
}

/// The Euclidean norm.
pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Solve the problem from the iterate `x` (overwritten by the solution).
pub fn solve<P: NewtonProblem + ?Sized>(
    problem: &mut P,
    x: &mut [f64],
    params: &NewtonParams,
) -> Result<NewtonInfo, NewtonError<P::Error>> {
    let mut info = NewtonInfo::default();
    loop {
        let rn = problem.residual(x).map_err(NewtonError::Problem)?;
        info.residuals.push(rn);
        if problem.converged(&info.residuals) {
            return Ok(info);
        }
        if info.iterations >= params.max_iterations {
            return Err(NewtonError::NoConvergence {
                iterations: info.iterations,
                residuals: info.residuals,
            });
        }
        info.iterations += 1;
        let direction = problem.direction(x).map_err(NewtonError::Problem)?;
        let mut s = problem.first_step(&direction);
        let mut reason = String::new();
        let mut taken = false;
        for _ in 0..=params.max_backtracks {
            match problem
                .try_step(x, &direction, s)
                .map_err(NewtonError::Problem)?
            {
                Trial::Accepted => {
                    taken = true;
                    break;
                }
                Trial::Rejected(why) => reason = why,
            }
            s = problem.shorter(s);
            info.backtracks += 1;
        }
        if !taken {
            if !problem.exhausted(x) {
                return Err(NewtonError::LineSearch {
                    iteration: info.iterations,
                    backtracks: params.max_backtracks,
                    reason,
                });
            }
            continue;
        }
        problem.stepped(x, &direction, s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_residual_history_is_summarised_in_a_message() {
        assert_eq!(residual_history(&[1.0, 0.5]), "[1.000e0, 5.000e-1]");
        let mut r = vec![2.0, 1.0, 0.1];
        r.extend(std::iter::repeat_n(0.3, 997));
        let text = residual_history(&r);
        assert_eq!(
            text,
            "2.000e0 at the start, smallest 1.000e-1 at iteration 2, 3.000e-1 at the last of 1000"
        );
        let e = NewtonError::<String>::NoConvergence {
            iterations: 999,
            residuals: r,
        };
        assert!(e.to_string().len() < 200, "{e}");
    }

    /// Π = Σ (e^{x_i} − b_i x_i), minimum at x_i = ln b_i: a convex problem whose full Newton
    /// steps from far away overflow, solved with the default plug-ins and an Armijo merit.
    struct Exponential {
        b: Vec<f64>,
        trial: Vec<f64>,
    }

    impl Exponential {
        fn new(b: Vec<f64>) -> Self {
            Exponential {
                trial: vec![0.0; b.len()],
                b,
            }
        }
        fn energy(&self, x: &[f64]) -> f64 {
            x.iter().zip(&self.b).map(|(x, b)| x.exp() - b * x).sum()
        }
        fn gradient(&self, x: &[f64]) -> Vec<f64> {
            x.iter().zip(&self.b).map(|(x, b)| x.exp() - b).collect()
        }
    }

    impl NewtonProblem for Exponential {
        type Error = String;
        fn residual(&mut self, x: &[f64]) -> Result<f64, String> {
            Ok(norm(&self.gradient(x)))
        }
        fn converged(&self, residuals: &[f64]) -> bool {
            NewtonParams::default().converged(residuals, norm(&self.b))
        }
        fn direction(&mut self, x: &[f64]) -> Result<Vec<f64>, String> {
            Ok(self
                .gradient(x)
                .iter()
                .zip(x)
                .map(|(g, x)| -g / x.exp())
                .collect())
        }
        fn try_step(&mut self, x: &mut [f64], d: &[f64], s: f64) -> Result<Trial, String> {
            for ((t, xi), di) in self.trial.iter_mut().zip(x.iter()).zip(d) {
                *t = xi + s * di;
            }
            let slope: f64 = self.gradient(x).iter().zip(d).map(|(g, d)| g * d).sum();
            let (e0, e1) = (self.energy(x), self.energy(&self.trial));
            if armijo(e0, e1, 1e-4, s, slope, 0.0) {
                x.copy_from_slice(&self.trial);
                Ok(Trial::Accepted)
            } else {
                Ok(Trial::Rejected(format!("energy {e0} → {e1}")))
            }
        }
    }

    #[test]
    fn converges_quadratically_from_far_away() {
        let mut p = Exponential::new(vec![1000.0, 3.0, 0.5]);
        let mut x = vec![0.0; 3];
        let info = solve(&mut p, &mut x, &NewtonParams::default()).unwrap();
        for (g, x) in p.gradient(&x).iter().zip(&x) {
            assert!(g.abs() < 1e-9 * 1000.0, "x = {x}");
        }
        // the full step from 0 to x = 999 overflows: the line search halves it
        assert!(info.backtracks > 0);
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
        let mut p = Exponential::new(vec![1e3]);
        let mut x = vec![0.0];
        let params = NewtonParams {
            max_iterations: 2,
            ..Default::default()
        };
        let e = solve(&mut p, &mut x, &params).unwrap_err();
        assert!(
            matches!(e, NewtonError::NoConvergence { iterations: 2, ref residuals } if residuals.len() == 3)
        );
    }

    /// An ascent direction is never accepted: the line search fails with its count and reason.
    #[test]
    fn a_direction_that_never_decreases_fails_the_line_search() {
        struct Uphill(Exponential);
        impl NewtonProblem for Uphill {
            type Error = String;
            fn residual(&mut self, x: &[f64]) -> Result<f64, String> {
                self.0.residual(x)
            }
            fn converged(&self, residuals: &[f64]) -> bool {
                self.0.converged(residuals)
            }
            fn direction(&mut self, x: &[f64]) -> Result<Vec<f64>, String> {
                Ok(self.0.direction(x)?.iter().map(|d| -d).collect())
            }
            fn try_step(&mut self, x: &mut [f64], d: &[f64], s: f64) -> Result<Trial, String> {
                self.0.try_step(x, d, s)
            }
        }
        let mut p = Uphill(Exponential::new(vec![5.0]));
        let mut x = vec![0.0];
        let params = NewtonParams {
            max_backtracks: 7,
            ..Default::default()
        };
        let e = solve(&mut p, &mut x, &params).unwrap_err();
        assert!(
            matches!(e, NewtonError::LineSearch { iteration: 1, backtracks: 7, ref reason } if reason.starts_with("energy")),
            "{e}"
        );
        assert_eq!(
            x,
            vec![0.0],
            "a failed line search leaves the iterate where it was"
        );
    }

    #[test]
    fn the_stall_test_needs_a_residual_that_stopped_halving_far_below_the_reference() {
        let p = NewtonParams::default();
        // stopped halving at 1e-7 of the first residual, far below the reference: round-off
        assert!(p.converged(&[1.0, 1e-7, 0.9e-7], 1.0));
        // still halving: not stalled
        assert!(!p.converged(&[1.0, 1e-7, 0.4e-7], 1.0));
        // stopped, but at a third of the reference: not round-off
        assert!(!p.converged(&[1.0, 1e-7, 0.9e-7], 3e-7));
        // off
        let off = NewtonParams {
            stagnation: 0.0,
            ..p
        };
        assert!(!off.converged(&[1.0, 1e-7, 0.9e-7], 1.0));
    }
}
