//! Solvers shared by the engines.
//!
//! - [`sparse`]: sparse symmetric positive-definite (Cholesky) and general (LU) solves through
//!   faer, with the symbolic analysis computed once per sparsity pattern and reused.
//! - [`newton`]: the Newton iteration with a backtracking line search, its problems plug-ins.
//! - [`least_squares`]: Levenberg–Marquardt with the covariance of the estimate.
//! - [`quadrature`]: Gauss–Legendre rules on [0, 1].
//! - [`statistics`]: the mean of an ensemble and its Student-t 95 % confidence interval.
//! - [`divided_power`]: the divided difference of a power, accurate at repeated arguments.
//! - [`expm1_minus_x`]: eˣ − 1 − x, accurate at small x.
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

/// eˣ − 1 − x to full relative precision: its Taylor series where |x| < 1/2 (where
/// `exp_m1(x) − x` would lose the leading digits to cancellation: at x = 10⁻⁴ it keeps only
/// half of them), `exp_m1(x) − x` beyond.
pub fn expm1_minus_x(x: f64) -> f64 {
    if x.abs() >= 0.5 {
        return x.exp_m1() - x;
    }
    // Σ_{n ≥ 2} xⁿ/n!: each term at most a quarter of the last, 30 terms reach 2⁻⁶⁰
    let (mut term, mut sum) = (0.5 * x * x, 0.0);
    for n in 3..32 {
        sum += term;
        if term.abs() <= f64::EPSILON * 1e-2 * sum.abs() {
            break;
        }
        term *= x / n as f64;
    }
    sum
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

    #[test]
    fn expm1_minus_x_keeps_its_digits_at_small_x_and_joins_at_one_half() {
        // x²/2 + x³/6 + x⁴/24 + x⁵/120: the series to below 10⁻¹⁷ of the sum at x = 1e-4
        let x: f64 = 1e-4;
        let exact = x * x / 2.0 + x.powi(3) / 6.0 + x.powi(4) / 24.0 + x.powi(5) / 120.0;
        assert!((expm1_minus_x(x) - exact).abs() < 2e-16 * exact);
        assert!(
            (expm1_minus_x(-x)
                - (x * x / 2.0 - x.powi(3) / 6.0 + x.powi(4) / 24.0 - x.powi(5) / 120.0))
                .abs()
                < 2e-16 * exact
        );
        assert_eq!(expm1_minus_x(0.0), 0.0);
        // the series and the direct form meet at |x| = 1/2 to round-off
        for x in [0.5f64, -0.5] {
            let below = expm1_minus_x(x - x.signum() * 1e-15);
            assert!((below - (x.exp_m1() - x)).abs() < 1e-14, "{x}: {below}");
        }
    }
}
