//! Derjaguin–Muller–Toporov (seed 3.7): a Hertzian profile plus the adhesive force of the
//! attraction outside the contact, P = 4E\*a³/(3R) − 2πγR, δ = a²/R; pull-off −2πγR under
//! either control (the contact shrinks stably to a = 0). The λ → 0 limit of Maugis–Dugdale.
//!
//! Units: a, δ, R in nm; E\* in GPa; γ in J/m²; P in nN.

use super::{NormalizedPoint, Sphere};

/// Normalised pull-off P̄ = P/(πγR).
pub const PULL_OFF: f64 = -2.0;

/// DMT in normalised variables: P̄ = ā³ − 2, δ̄ = ā².
pub fn normalized(a_bar: f64) -> NormalizedPoint {
    NormalizedPoint {
        a_bar,
        p_bar: a_bar.powi(3) + PULL_OFF,
        delta_bar: a_bar * a_bar,
    }
}

/// Load at contact radius a, nN: P = 4E\*a³/(3R) − 2πγR.
pub fn load(s: &Sphere, a: f64) -> f64 {
    super::hertz::load(a, s.radius, s.modulus)
        + PULL_OFF * std::f64::consts::PI * s.gamma * s.radius
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn physical_and_normalised_forms_agree() {
        let s = Sphere::new(500.0, 2.0, 0.3).unwrap();
        let sc = s.scales();
        for a_bar in [0.1, 1.0, 3.0] {
            let n = normalized(a_bar);
            let a = a_bar * sc.length;
            // relative round-off of the scale factors
            assert!((load(&s, a) - n.p_bar * sc.force).abs() < 1e-12 * sc.force * 10.0);
            assert!(
                (super::super::hertz::depth(a, s.radius) - n.delta_bar * sc.depth).abs()
                    < 1e-12 * sc.depth * 10.0
            );
        }
    }
}
