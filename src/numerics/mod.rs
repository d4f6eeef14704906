//! Solvers shared by the engines.
//!
//! - [`sparse`]: sparse symmetric positive-definite (Cholesky) and general (LU) solves through
//!   faer, with the symbolic analysis computed once per sparsity pattern and reused.
//! - [`least_squares`]: Levenberg–Marquardt with the covariance of the estimate.
//! - [`quadrature`]: Gauss–Legendre rules on [0, 1].
//! - [`statistics`]: the mean of an ensemble and its Student-t 95 % confidence interval.

pub mod least_squares;
pub mod quadrature;
pub mod sparse;
pub mod statistics;
