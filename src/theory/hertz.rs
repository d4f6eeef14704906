//! Hertz contact of an elastic sphere without adhesion (seed 3.1–3.3, with the stray π of the
//! OCR removed, PHYSICS.md): a³ = 3PR/(4E\*), δ = a²/R, P = (4/3)E\*R^(1/2)δ^(3/2).
//!
//! The paraboloid approximation δ = a²/R is off by about (a/R)²/3 relative; the exact depth of a
//! rigid sphere pressed into a half-space with the same pressure distribution is
//! δ = (a/2) ln((R+a)/(R−a)) (Johnson, Contact Mechanics §5.2), given by [`sphere_depth`] so that
//! finite-element checks can separate the two errors.
//!
//! Units: R, a, δ in nm, E\* in GPa, P in nN.

use super::{positive, NormalizedPoint, TheoryError};

/// Contact radius under load P ≥ 0, nm: a = (3PR/(4E\*))^(1/3).
pub fn contact_radius(load: f64, radius: f64, modulus: f64) -> Result<f64, TheoryError> {
    if !(load.is_finite() && load >= 0.0) {
        return Err(TheoryError::OutOfDomain {
            what: "Hertz load P",
            value: load,
            allowed: "P ≥ 0 (compressive) and finite".into(),
        });
    }
    Ok(
        (3.0 * load * positive("radius R", radius)? / (4.0 * positive("modulus E*", modulus)?))
            .cbrt(),
    )
}

/// Load at contact radius a, nN: P = 4E\*a³/(3R).
pub fn load(a: f64, radius: f64, modulus: f64) -> f64 {
    4.0 * modulus * a.powi(3) / (3.0 * radius)
}

/// Approach of a paraboloid at contact radius a, nm: δ = a²/R.
pub fn depth(a: f64, radius: f64) -> f64 {
    a * a / radius
}

/// Load at approach δ ≥ 0, nN: P = (4/3)E\*R^(1/2)δ^(3/2).
pub fn load_from_depth(delta: f64, radius: f64, modulus: f64) -> f64 {
    4.0 / 3.0 * modulus * radius.sqrt() * delta.max(0.0).powf(1.5)
}

/// Approach of an exact sphere at contact radius 0 ≤ a < R, nm: δ = (a/2) ln((R+a)/(R−a)).
pub fn sphere_depth(a: f64, radius: f64) -> Result<f64, TheoryError> {
    positive("radius R", radius)?;
    if !(a.is_finite() && a >= 0.0 && a < radius) {
        return Err(TheoryError::OutOfDomain {
            what: "contact radius a",
            value: a,
            allowed: format!("0 ≤ a < R = {radius} nm"),
        });
    }
    // ln((R+a)/(R−a)) = 2 atanh(a/R), accurate for small a/R
    Ok(a * (a / radius).atanh())
}

/// Hertz in normalised variables: P̄ = ā³, δ̄ = ā².
pub fn normalized(a_bar: f64) -> NormalizedPoint {
    NormalizedPoint {
        a_bar,
        p_bar: a_bar.powi(3),
        delta_bar: a_bar * a_bar,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// round-off of cube roots and powers
    const TOL: f64 = 1e-12;

    #[test]
    fn load_radius_and_depth_are_consistent() {
        let (r, e) = (1800.0, 1.3);
        for p in [0.1, 10.0, 5e3] {
            let a = contact_radius(p, r, e).unwrap();
            assert!((load(a, r, e) - p).abs() < TOL * p);
            let d = depth(a, r);
            assert!((load_from_depth(d, r, e) - p).abs() < TOL * p);
        }
        assert!(contact_radius(-1.0, r, e).is_err());
        assert!(contact_radius(1.0, 0.0, e).is_err());
    }

    #[test]
    fn exact_sphere_tends_to_paraboloid_with_the_known_correction() {
        let r = 1000.0;
        for a in [1.0, 10.0, 100.0] {
            let exact = sphere_depth(a, r).unwrap();
            let para = depth(a, r);
            // series: (a/2)ln((R+a)/(R−a)) = a²/R (1 + (a/R)²/3 + (a/R)⁴/5 + …)
            let x = a / r;
            let series = para * (1.0 + x * x / 3.0 + x.powi(4) / 5.0);
            // remainder of the series: Σ_{k≥3} x^(2k)/(2k+1) < x⁶/6 for x ≤ 0.1
            assert!((exact - series).abs() < x.powi(6) / 6.0 * para + TOL * para);
        }
        assert!(sphere_depth(1000.0, r).is_err());
    }
}
