//! Solvers shared by the engines.
//!
//! - [`sparse`]: sparse symmetric positive-definite (Cholesky) and general (LU) solves through
//!   faer, with the symbolic analysis computed once per sparsity pattern and reused.
//! - [`newton`]: the Newton iteration with a backtracking line search, its problems plug-ins.
//! - [`least_squares`]: Levenberg–Marquardt with the covariance of the estimate.
//! - [`quadrature`]: Gauss–Legendre rules on [0, 1].
//! - [`statistics`]: the mean of an ensemble and its Student-t 95 % confidence interval.
//! - [`divided_power`]: the divided difference of a power, accurate at repeated arguments.

pub mod least_squares;
pub mod newton;
pub mod quadrature;
pub mod sparse;
pub mod statistics;

/// (c₁^q − c₂^q)/(c₁ − c₂) for c₁, c₂ > 0, exact in the limit c₁ → c₂ (q c^(q−1)): evaluated as
/// c₂^(q−1)·expm1(q ln r)/expm1(ln r), r = c₁/c₂, which keeps full accuracy near r = 1.
pub fn divided_power(c1: f64, c2: f64, q: f64) -> f64 {
    let x = (c1 / c2).ln();
    if x == 0.0 {
        q * c2.powf(q - 1.0)
    } else {
        c2.powf(q - 1.0) * (q * x).exp_m1() / x.exp_m1()
    }
}
