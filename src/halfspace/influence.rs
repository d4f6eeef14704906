//! Boussinesq influence coefficients of uniform ring pressures on an elastic half-space.
//!
//! A uniform pressure p on the disc r < a of a half-space with plane-strain modulus E\*
//! (1/E\* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂) moves the surface by (Johnson, *Contact Mechanics*, §3.4)
//!
//! u(r) = (4p/(πE\*)) a E(r/a)                              for r ≤ a,
//! u(r) = (4p/(πE\*)) r [E(a/r) − (1 − a²/r²) K(a/r)]       for r > a,
//!
//! with K, E the complete elliptic integrals ([`super::elliptic`]). A ring b_j < r < b_{j+1} is
//! the difference of two discs, so the influence of a piecewise-constant pressure is exact: the
//! logarithmic singularity of the ring kernel at r = s is integrated in closed form (at r = a the
//! two branches meet at u = 4pa/(πE\*), and (1 − a²/r²)K(a/r) → 0).
//!
//! In the scaled units of [`super`] (ρ = r/√(Rz₀), pressure in γ/z₀, displacement in z₀) the
//! coefficient carries the factor (4/π) μ^{3/2}, μ the Tabor parameter.

use super::elliptic::{elliptic_ke, elliptic_ke_complementary};
use super::grid::Grid;
use std::f64::consts::PI;

/// Displacement at radius `r` of unit pressure on the disc of radius `a`, divided by 4/(πE\*)
/// (a length, in the units of r and a).
pub fn disc_displacement(r: f64, a: f64) -> f64 {
    if a <= 0.0 {
        return 0.0;
    }
    if r <= a {
        a * elliptic_ke(r / a).1
    } else {
        let k = a / r;
        let kp2 = (r - a) * (r + a) / (r * r); // 1 − k² without cancellation
        let (kk, ee) = elliptic_ke_complementary(k, kp2.sqrt());
        r * (ee - kp2 * kk)
    }
}

/// The dense influence matrix A: u_i = Σ_j A_ij p_j, u at node i, p_j the uniform pressure of
/// ring j (nodes and rings of `grid`), multiplied by `scale` (= (4/π)μ^{3/2} in scaled units).
pub fn influence_matrix(grid: &Grid, scale: f64) -> Vec<f64> {
    let n = grid.len();
    let mut a = vec![0.0; n * n];
    let mut prev = vec![0.0; n];
    for (j, &b) in grid.edges.iter().enumerate() {
        for (i, &r) in grid.nodes.iter().enumerate() {
            let u = disc_displacement(r, b);
            if j > 0 {
                a[i * n + j - 1] = scale * (u - prev[i]);
            }
            prev[i] = u;
        }
    }
    a
}

/// Scale factor (4/π) μ^{3/2} of the influence coefficients in scaled units.
pub fn scaled_factor(mu: f64) -> f64 {
    4.0 / PI * mu.powf(1.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_of_a_uniform_disc_moves_by_2pa_over_estar() {
        // u(0) = 2pa/E*: divided by 4/(πE*) that is πa/2
        let a = 1.7;
        assert!((disc_displacement(0.0, a) - PI * a / 2.0).abs() < 1e-14);
    }

    #[test]
    fn branches_meet_at_the_edge() {
        let a = 2.0;
        let inside = disc_displacement(a * (1.0 - 1e-12), a);
        let outside = disc_displacement(a * (1.0 + 1e-9), a);
        assert!((inside - a).abs() < 1e-9 && (outside - a).abs() < 1e-7);
    }

    #[test]
    fn far_field_is_a_point_load() {
        // u → P/(πE* r), P = πa²p: divided by 4/(πE*) that is πa²/(4r)
        let (a, r) = (1.0, 1e3);
        let want = PI * a * a / (4.0 * r);
        assert!((disc_displacement(r, a) - want).abs() < 1e-6 * want);
    }

    #[test]
    fn ring_kernel_matches_direct_quadrature_across_the_singularity() {
        // u(r) = (4/(πE*)) ∫ p(s) s/(r+s) K(2√(rs)/(r+s)) ds for a ring [1, 1.5] at r = 1.2
        // (inside the ring: log-singular integrand). Substituting s = r ± t² removes the
        // singularity only partly, so use many midpoint panels on each side; K ~ ln(1/|s−r|).
        let (b0, b1, r) = (1.0, 1.5, 1.2);
        let f = |s: f64| {
            let k = 2.0 * (r * s).sqrt() / (r + s);
            let kp = (r - s).abs() / (r + s);
            s / (r + s) * elliptic_ke_complementary(k, kp).0
        };
        // ∫_{b0}^{r} and ∫_{r}^{b1} with s = r ∓ t², ds = 2t dt (integrand ~ t ln t → smooth)
        let n = 200_000;
        let mut sum = 0.0;
        for (lo, sign) in [(r - b0, -1.0), (b1 - r, 1.0)] {
            let tmax: f64 = lo.sqrt();
            let dt = tmax / n as f64;
            for i in 0..n {
                let t = (i as f64 + 0.5) * dt;
                sum += f(r + sign * t * t) * 2.0 * t * dt;
            }
        }
        let exact = disc_displacement(r, b1) - disc_displacement(r, b0);
        assert!((sum - exact).abs() < 1e-6 * exact, "{sum} vs {exact}");
    }
}
