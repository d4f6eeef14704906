//! Johnson–Kendall–Roberts adhesion of an elastic sphere (seed 3.4–3.6; the seed's stray π is
//! removed, PHYSICS.md). Parametrised by the contact radius a:
//!
//! P(a) = 4E\*a³/(3R) − √(8πγE\*a³),  δ(a) = a²/R − √(2πγa/E\*),
//!
//! equivalent to a³ = (3R/(4E\*))(P + 3πγR + √(6πγRP + (3πγR)²)) on the branch dP/da > 0.
//! Zero-load radius a₀³ = 9πγR²/(2E\*). Pull-off: under load control at the minimum of P,
//! P = −(3/2)πγR (a³ = a₀³/4); under displacement control at the minimum of δ,
//! P = −(5/6)πγR (a³ = a₀³/36). Normalised: P̄ = ā³ − √6 ā^(3/2), δ̄ = ā² − (2/3)√6 ā^(1/2)
//! (Johnson & Greenwood 1997).
//!
//! Units: a, δ, R in nm; E\* in GPa; γ in J/m²; P in nN.

use super::{Control, NormalizedPoint, Sphere, TheoryError};
use std::f64::consts::PI;

/// Normalised pull-off under load control.
pub const PULL_OFF_LOAD: f64 = -1.5;
/// Normalised pull-off under displacement control.
pub const PULL_OFF_DISPLACEMENT: f64 = -5.0 / 6.0;

/// Normalised pull-off P̄ under the given control.
pub fn pull_off(control: Control) -> f64 {
    match control {
        Control::Load => PULL_OFF_LOAD,
        Control::Displacement => PULL_OFF_DISPLACEMENT,
    }
}

/// Load at contact radius a, nN.
pub fn load(s: &Sphere, a: f64) -> f64 {
    4.0 * s.modulus * a.powi(3) / (3.0 * s.radius)
        - (8.0 * PI * s.gamma * s.modulus * a.powi(3)).sqrt()
}

/// Approach at contact radius a, nm (negative: the sphere is pulled out beyond first contact).
pub fn depth(s: &Sphere, a: f64) -> f64 {
    a * a / s.radius - (2.0 * PI * s.gamma * a / s.modulus).sqrt()
}

/// Contact radius at load P ≥ −(3/2)πγR on the stable branch, nm (seed 3.4 corrected).
pub fn contact_radius(s: &Sphere, load: f64) -> Result<f64, TheoryError> {
    let w = 3.0 * PI * s.gamma * s.radius;
    let disc = 6.0 * PI * s.gamma * s.radius * load + w * w;
    if !load.is_finite() || disc < 0.0 {
        return Err(TheoryError::OutOfDomain {
            what: "JKR load P",
            value: load,
            allowed: format!("P ≥ −(3/2)πγR = {} nN", -0.5 * w),
        });
    }
    Ok((3.0 * s.radius / (4.0 * s.modulus) * (load + w + disc.sqrt())).cbrt())
}

/// Contact radius at zero load, nm: a₀³ = 9πγR²/(2E\*) (seed 3.5 corrected).
pub fn zero_load_radius(s: &Sphere) -> f64 {
    (9.0 * PI * s.gamma * s.radius * s.radius / (2.0 * s.modulus)).cbrt()
}

/// JKR in normalised variables.
pub fn normalized(a_bar: f64) -> NormalizedPoint {
    let r6 = 6f64.sqrt();
    NormalizedPoint {
        a_bar,
        p_bar: a_bar.powi(3) - r6 * a_bar.powf(1.5),
        delta_bar: a_bar * a_bar - 2.0 / 3.0 * r6 * a_bar.sqrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// round-off of cube roots and square roots at these magnitudes
    const TOL: f64 = 1e-10;

    fn sphere() -> Sphere {
        Sphere::new(1800.0, 0.7, 0.46).unwrap()
    }

    #[test]
    fn contact_radius_inverts_the_load() {
        let s = sphere();
        let pf = PI * s.gamma * s.radius;
        for p in [-1.5 * pf, -pf, 0.0, 3.0 * pf, 100.0 * pf] {
            let a = contact_radius(&s, p).unwrap();
            assert!((load(&s, a) - p).abs() < TOL * pf, "{p}");
        }
        assert!(
            (contact_radius(&s, 0.0).unwrap() - zero_load_radius(&s)).abs()
                < TOL * zero_load_radius(&s)
        );
        assert!(contact_radius(&s, -1.6 * pf).is_err());
    }

    #[test]
    fn pull_offs_are_the_extrema_of_load_and_depth() {
        let s = sphere();
        let (a0, pf) = (zero_load_radius(&s), PI * s.gamma * s.radius);
        // load control: dP/da = 0 at a³ = a₀³/4
        let a = a0 / 4f64.cbrt();
        let e = 1e-6 * a;
        assert!((load(&s, a) / pf - PULL_OFF_LOAD).abs() < TOL);
        assert!(load(&s, a + e) > load(&s, a) && load(&s, a - e) > load(&s, a));
        // displacement control: dδ/da = 0 at a³ = a₀³/36
        let a = a0 / 36f64.cbrt();
        let e = 1e-6 * a;
        assert!((load(&s, a) / pf - PULL_OFF_DISPLACEMENT).abs() < TOL);
        assert!(depth(&s, a + e) > depth(&s, a) && depth(&s, a - e) > depth(&s, a));
    }

    #[test]
    fn normalised_form_matches_the_physical_one() {
        let s = sphere();
        let sc = s.scales();
        for a_bar in [0.05, 0.5, 1.0, 2.5] {
            let n = normalized(a_bar);
            let a = a_bar * sc.length;
            assert!((load(&s, a) / sc.force - n.p_bar).abs() < TOL);
            assert!((depth(&s, a) / sc.depth - n.delta_bar).abs() < TOL);
        }
    }
}
