//! Solvers shared by the engines.
//!
//! - [`sparse`]: sparse symmetric positive-definite (Cholesky) and general (LU) solves through
//!   faer, with the symbolic analysis computed once per sparsity pattern and reused.
//! - [`newton`]: the Newton iteration with a backtracking line search, its problems plug-ins.
//! - [`least_squares`]: Levenberg–Marquardt with the covariance of the estimate.
//! - [`quadrature`]: Gauss–Legendre rules on [0, 1].
//! - [`statistics`]: the mean of an ensemble and its Student-t 95 % confidence interval.
//! - [`divided_power`]: the divided difference of a power, accurate at repeated arguments.
//! - [`interpolate`]: a piecewise-linear curve's value.

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

/// `y(x)` on the piecewise-linear curve through `(xs, ys)` (`xs` increasing), `None` outside.
pub fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> Option<f64> {
    let i = xs.windows(2).position(|w| w[0] <= x && x <= w[1])?;
    let t = (x - xs[i]) / (xs[i + 1] - xs[i]).max(f64::MIN_POSITIVE);
    Some(ys[i] + t * (ys[i + 1] - ys[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_piecewise_linear_curve_is_read_between_its_points_and_not_beyond() {
        let (xs, ys) = ([0.0, 1.0, 3.0], [2.0, 4.0, 0.0]);
        assert_eq!(interpolate(&xs, &ys, 0.0), Some(2.0));
        assert_eq!(interpolate(&xs, &ys, 0.5), Some(3.0));
        assert_eq!(interpolate(&xs, &ys, 2.0), Some(2.0));
        assert_eq!(interpolate(&xs, &ys, 3.0), Some(0.0));
        assert_eq!(interpolate(&xs, &ys, -1e-9), None);
        assert_eq!(interpolate(&xs, &ys, 3.0 + 1e-9), None);
    }
}
