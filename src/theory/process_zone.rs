//! The process zone of an adhesive contact (PHYSICS.md "Process zone of any surface law"): the
//! width over which the gap opens at the edge of an adhesive contact, where the surface law's
//! tension acts,
//!
//! ℓ = E\* γ / σ_peak²,
//!
//! with σ_peak the law's own largest tension ([`SurfaceLaw::max_tension`]): σ_max for a plain
//! Lennard-Jones law (so ℓ ≈ E\*z₀²/γ up to a constant of the law's shape: 0.949 for 9-3,
//! 0.466 for 10-4) and σ_max/b for a thermally shifted one, whose zone is b² times longer. It
//! is the length an adhesive mesh must resolve (PHYSICS.md: ≥ 10 elements across it) and the
//! one Tabor's μ compares with the elastic deformation: ℓ/√(Rz₀) ∝ μ^(−3/2) for a plain law.
//!
//! Units: E\* and σ in GPa, γ in J/m² (= nN/nm), ℓ in nm.

use super::{positive, TheoryError};
use crate::laws::SurfaceLaw;

/// The process zone ℓ = E\*γ/σ_peak² of `law` against a solid of plane-strain modulus
/// `e_star` (GPa), nm.
pub fn process_zone(law: &SurfaceLaw, e_star: f64) -> Result<f64, TheoryError> {
    let e_star = positive("plane-strain modulus E*", e_star)?;
    let gamma = positive("work of adhesion γ", law.gamma())?;
    let sigma = positive("peak tension σ_peak", law.max_tension())?;
    Ok(e_star * gamma / (sigma * sigma))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::{LennardJones, LjKind, ThermallyShifted};

    #[test]
    fn plain_lj93_zone_is_e_star_z0_squared_over_gamma_times_its_shape_constant() {
        let (e, g, z0) = (0.7, 0.46, 0.34);
        let law = SurfaceLaw::from(LennardJones::new(LjKind::Lj93, g, z0));
        // σ_max = 16γ/(9√3 z₀) ⇒ ℓ = E*z₀²/γ · (9√3/16)²
        let want = e * z0 * z0 / g * (9.0 * 3f64.sqrt() / 16.0).powi(2);
        assert!((process_zone(&law, e).unwrap() - want).abs() < 1e-12 * want);
    }

    #[test]
    fn the_shift_lengthens_the_zone_by_b_squared_and_the_seed_zone_is_25_nm() {
        let base = LennardJones::new(LjKind::Lj104, 0.46, 0.34);
        let shifted = ThermallyShifted::new(base, 4.626).unwrap();
        let b = shifted.stretch();
        let (plain, stretched) = (
            process_zone(&SurfaceLaw::from(base), 0.7).unwrap(),
            process_zone(&SurfaceLaw::from(shifted), 0.7).unwrap(),
        );
        assert!((stretched / plain - b * b).abs() < 1e-10 * b * b);
        // PHYSICS.md: seed card E* = 700 MPa, shifted 10-4 law: ℓ ≈ 25 nm
        assert!((stretched - 25.0).abs() < 0.5, "{stretched}");
        assert!(process_zone(&SurfaceLaw::from(base), 0.0).is_err());
    }
}
