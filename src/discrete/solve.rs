//! Quasi-static equilibrium of the discrete model: minimise the total energy over the free
//! coordinates.
//!
//! Two solvers, selectable per scene, each reporting its [`Cost`]:
//!
//! - [`solve_newton::minimize_newton`]: Newton on the sparse Hessian (faer Cholesky through
//!   [`crate::numerics::sparse::SparseSystem`]), a shift μI added when the Hessian is not
//!   positive definite (buckling), and a backtracking Armijo line search on the energy.
//! - [`solve_fire::minimize_fire`]: FIRE (Bitzek et al., PRL 97, 170201, 2006), matrix-free.
//!
//! Both stop on the force residual r = max |∂E/∂x_k| over free coordinates k:
//! r ≤ max(`atol`, `rtol` · r₀), r₀ the residual at the starting point.

use std::time::Instant;

use super::constraints::FixedDofs;
use super::energy::EnergyTerm;
use crate::numerics::sparse::SparseError;

/// Several energy terms as one.
pub struct Sum<'a>(pub Vec<&'a mut dyn EnergyTerm>);

impl EnergyTerm for Sum<'_> {
    fn prepare(&mut self, x: &[f64]) {
        for t in self.0.iter_mut() {
            t.prepare(x);
        }
    }

    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        self.0.iter().map(|t| t.energy_gradient(x, grad)).sum()
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for t in &self.0 {
            t.hessian(x, out);
        }
    }

    fn hessian_lower(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for t in &self.0 {
            t.hessian_lower(x, out);
        }
    }
}

/// What a solve cost.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cost {
    /// solver iterations (Newton steps, FIRE steps)
    pub iterations: usize,
    /// energy + gradient evaluations of the whole model
    pub gradient_evaluations: usize,
    /// Hessian assemblies
    pub hessian_evaluations: usize,
    /// sparse Cholesky factorisations (including failed, shifted attempts)
    pub factorizations: usize,
    /// wall time (s)
    pub seconds: f64,
}

/// A converged solve.
#[derive(Debug, Clone, PartialEq)]
pub struct Info {
    /// energy at the solution (aJ)
    pub energy: f64,
    /// final force residual (nN)
    pub residual: f64,
    /// the tolerance it met (nN)
    pub tolerance: f64,
    /// residual after each iteration (nN), the starting one first
    pub history: Vec<f64>,
    /// what it cost
    pub cost: Cost,
}

/// Why a solve failed; each carries the cost spent.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// vector lengths disagree
    #[error("x has {x} entries but the fixed-dof mask has {mask}")]
    Dimension {
        /// len(x)
        x: usize,
        /// len(mask)
        mask: usize,
    },
    /// NaN or infinity in the energy or gradient
    #[error("non-finite energy or gradient at iteration {iteration}")]
    NonFinite {
        /// where
        iteration: usize,
    },
    /// iteration limit reached
    #[error("no convergence in {} iterations: residual {residual:.3e} nN > tolerance {tolerance:.3e} nN", cost.iterations)]
    NoConvergence {
        /// last residual (nN)
        residual: f64,
        /// required (nN)
        tolerance: f64,
        /// spent
        cost: Cost,
    },
    /// the line search found no acceptable step
    #[error("line search failed at iteration {} (residual {residual:.3e} nN)", cost.iterations)]
    LineSearch {
        /// residual there (nN)
        residual: f64,
        /// spent
        cost: Cost,
    },
    /// no shift made the Hessian positive definite, or the sparse solve failed
    #[error("sparse solve failed: {0}")]
    Sparse(#[from] SparseError),
}

/// Evaluation bookkeeping shared by the solvers.
pub(crate) struct Evaluator<'a, E: EnergyTerm + ?Sized> {
    pub model: &'a mut E,
    pub cost: Cost,
    start: Instant,
}

impl<'a, E: EnergyTerm + ?Sized> Evaluator<'a, E> {
    pub fn new(model: &'a mut E, fixed: &FixedDofs, x: &[f64]) -> Result<Self, SolveError> {
        if x.len() != fixed.len() {
            return Err(SolveError::Dimension {
                x: x.len(),
                mask: fixed.len(),
            });
        }
        Ok(Evaluator {
            model,
            cost: Cost::default(),
            start: Instant::now(),
        })
    }

    /// prepare + energy + gradient at x, checked finite.
    pub fn eval(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, SolveError> {
        self.model.prepare(x);
        grad.iter_mut().for_each(|g| *g = 0.0);
        let e = self.model.energy_gradient(x, grad);
        self.cost.gradient_evaluations += 1;
        if e.is_finite() && grad.iter().all(|g| g.is_finite()) {
            Ok(e)
        } else {
            Err(SolveError::NonFinite {
                iteration: self.cost.iterations,
            })
        }
    }

    pub fn finish(&mut self) -> Cost {
        self.cost.seconds = self.start.elapsed().as_secs_f64();
        self.cost
    }
}
