//! Gauss–Legendre quadrature on [0, 1], the one rule every engine integrates with: the
//! surface tractions of the FE contact (`continuum::contact`) and the line–line van der Waals
//! energy of the discrete tubes (`discrete::vdw`). Nodes are the roots of the Legendre
//! polynomial P_n (Newton on the three-term recurrence), weights 2/((1 − x²)P_n'(x)²), mapped
//! from [−1, 1] to [0, 1]; exact for polynomials of degree 2n − 1.

use std::f64::consts::PI;

/// Gauss–Legendre rule on [0, 1]: (node, weight) pairs, nodes ascending.
pub fn gauss_legendre_unit(n: usize) -> Vec<(f64, f64)> {
    let legendre = |x: f64| {
        // (P_n(x), P_n'(x)) by the three-term recurrence
        let (mut p0, mut p1) = (1.0, x);
        for k in 2..=n {
            let kf = k as f64;
            let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
            p0 = p1;
            p1 = p2;
        }
        let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
        (p1, dp)
    };
    let mut rule: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre(x);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre(x);
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * (1.0 + x), 0.5 * w)
        })
        .collect();
    rule.sort_by(|a, b| a.0.total_cmp(&b.0));
    rule
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for n in 1..=8 {
            let rule = gauss_legendre_unit(n);
            let wsum: f64 = rule.iter().map(|r| r.1).sum();
            assert!((wsum - 1.0).abs() < 1e-14);
            // ∫₀¹ t^(2n−1) dt = 1/(2n)
            let k = 2 * n - 1;
            let q: f64 = rule.iter().map(|&(t, w)| w * t.powi(k as i32)).sum();
            assert!((q - 1.0 / (2 * n) as f64).abs() < 1e-13, "n = {n}");
        }
    }

    #[test]
    fn the_low_orders_are_the_closed_forms() {
        let two = gauss_legendre_unit(2);
        let a = 0.5 / 3f64.sqrt();
        assert!((two[0].0 - (0.5 - a)).abs() < 1e-15 && (two[0].1 - 0.5).abs() < 1e-15);
        let three = gauss_legendre_unit(3);
        let b = 0.5 * 0.6f64.sqrt();
        assert!((three[0].0 - (0.5 - b)).abs() < 1e-15);
        assert!((three[1].1 - 8.0 / 18.0).abs() < 1e-15);
    }
}
