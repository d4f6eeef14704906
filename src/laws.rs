//! Force–separation laws shared by every engine: Lennard-Jones 9-3 (seed eq. 4.1) and 10-4
//! (seed eq. 5.10), normalised by the work of adhesion γ and the equilibrium separation z₀.
//!
//! For exponents (n, m) the pressure between the surfaces at gap h (positive repulsive) is
//!
//! p(h) = C [(z₀/h)ⁿ − (z₀/h)ᵐ],  C = γ / (z₀ (1/(m−1) − 1/(n−1))),
//!
//! so C = 8γ/(3z₀) for 9-3 and 9γ/(2z₀) for 10-4 (PHYSICS.md). The energy per unit area is
//! φ(h) = ∫ₕ^∞ p dh' = C z₀ [(z₀/h)ⁿ⁻¹/(n−1) − (z₀/h)ᵐ⁻¹/(m−1)], with φ(z₀) = −γ and
//! φ(∞) = 0, and the stiffness is k(h) = dp/dh. Energy, pressure and stiffness are exact
//! derivatives of one another (tested below by finite differences).
//!
//! **Penetration guard.** Newton iterates may cross h ≤ 0, where the law is singular. Below
//! h_c = z₀/2 (where the repulsion is already ~500 C) the energy is continued by its
//! second-order Taylor expansion about h_c, so φ, p and k stay finite and continuous for every
//! h; a converged solution never sits there in practice (engines report the minimum gap).
//!
//! Units: γ in J/m² (= nN/nm), z₀ and h in nm, p in GPa, φ in J/m², k in GPa/nm.

use serde::{Deserialize, Serialize};

/// Which Lennard-Jones exponents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LjKind {
    /// 9-3 law (seed eq. 4.1): integrated half-spaces
    Lj93,
    /// 10-4 law (seed eq. 5.10): integrated monolayer
    Lj104,
}

impl LjKind {
    /// Repulsive and attractive exponents (n, m) of the pressure.
    pub fn exponents(self) -> (i32, i32) {
        match self {
            LjKind::Lj93 => (9, 3),
            LjKind::Lj104 => (10, 4),
        }
    }
}

/// A Lennard-Jones surface law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LennardJones {
    /// exponents
    pub kind: LjKind,
    /// work of adhesion γ, J/m² (= nN/nm)
    pub gamma: f64,
    /// equilibrium separation z₀, nm
    pub z0: f64,
}

/// Fraction of z₀ below which the energy is continued quadratically.
const GUARD_FRACTION: f64 = 0.5;

impl LennardJones {
    /// A law; `gamma` and `z0` must be positive and finite (checked by the scene).
    pub fn new(kind: LjKind, gamma: f64, z0: f64) -> Self {
        LennardJones { kind, gamma, z0 }
    }

    /// The prefactor C of the pressure, GPa.
    pub fn prefactor(&self) -> f64 {
        let (n, m) = self.kind.exponents();
        self.gamma / (self.z0 * (1.0 / (m - 1) as f64 - 1.0 / (n - 1) as f64))
    }

    /// (φ, p, k) of the pure power law at h > 0.
    fn raw(&self, h: f64) -> (f64, f64, f64) {
        let (n, m) = self.kind.exponents();
        let c = self.prefactor();
        let s = self.z0 / h;
        let sn = s.powi(n);
        let sm = s.powi(m);
        let phi = c * self.z0 * (s.powi(n - 1) / (n - 1) as f64 - s.powi(m - 1) / (m - 1) as f64);
        let p = c * (sn - sm);
        let k = c * (-(n as f64) * sn + (m as f64) * sm) / h;
        (phi, p, k)
    }

    /// Energy per unit area φ(h), pressure p(h) = −dφ/dh and stiffness k(h) = dp/dh, together.
    pub fn eval(&self, h: f64) -> (f64, f64, f64) {
        let hc = GUARD_FRACTION * self.z0;
        if h >= hc {
            return self.raw(h);
        }
        let (phi, p, k) = self.raw(hc);
        let d = h - hc;
        // φ ≈ φc − p_c d − ½ k_c d² (φ' = −p, φ'' = −k)
        (phi - p * d - 0.5 * k * d * d, p + k * d, k)
    }

    /// Energy per unit area φ(h), J/m².
    pub fn energy(&self, h: f64) -> f64 {
        self.eval(h).0
    }

    /// Pressure p(h), GPa, positive repulsive.
    pub fn pressure(&self, h: f64) -> f64 {
        self.eval(h).1
    }

    /// Stiffness dp/dh, GPa/nm.
    pub fn stiffness(&self, h: f64) -> f64 {
        self.eval(h).2
    }

    /// Gap of the largest tension (the inflection point of φ), nm.
    pub fn gap_at_max_tension(&self) -> f64 {
        let (n, m) = self.kind.exponents();
        self.z0 * (n as f64 / m as f64).powf(1.0 / (n - m) as f64)
    }

    /// The largest tensile pressure σ₀ = −min p (positive), GPa. For 9-3 this is
    /// 16γ/(9√3 z₀) (PHYSICS.md); it is the Dugdale stress that maps the law onto Maugis' λ.
    pub fn max_tension(&self) -> f64 {
        -self.pressure(self.gap_at_max_tension())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FD_TOL: f64 = 1e-6; // central differences with step 1e-5·z₀: error ~1e-10 relative

    fn laws() -> [LennardJones; 2] {
        [
            LennardJones::new(LjKind::Lj93, 0.46, 0.34),
            LennardJones::new(LjKind::Lj104, 0.2, 0.5),
        ]
    }

    #[test]
    fn prefactors_match_the_seed() {
        let l = LennardJones::new(LjKind::Lj93, 1.0, 1.0);
        assert!((l.prefactor() - 8.0 / 3.0).abs() < 1e-14);
        let l = LennardJones::new(LjKind::Lj104, 1.0, 1.0);
        assert!((l.prefactor() - 4.5).abs() < 1e-14);
        // seed: 9γ/(2z₀) = 36.5/6 GPa with z₀ = 0.34 nm ⇒ γ ≈ 0.46 J/m²
        let gamma: f64 = 36.5 / 6.0 * 2.0 * 0.34 / 9.0;
        assert!((gamma - 0.46).abs() < 0.01);
    }

    #[test]
    fn energy_at_z0_is_minus_gamma_and_pressure_vanishes() {
        for l in laws() {
            assert!((l.energy(l.z0) + l.gamma).abs() < 1e-14);
            assert!(l.pressure(l.z0).abs() < 1e-12);
            assert!(l.energy(1e6 * l.z0).abs() < 1e-11 * l.gamma);
        }
    }

    #[test]
    fn work_of_separation_is_gamma_by_quadrature() {
        for l in laws() {
            // ∫_{z0}^{∞} −p dh with h = z0/s, dh = −z0/s² ds, s ∈ (0, 1]
            let n = 200_000;
            let mut w = 0.0;
            for i in 0..n {
                let s = (i as f64 + 0.5) / n as f64;
                w += -l.pressure(l.z0 / s) * l.z0 / (s * s) / n as f64;
            }
            assert!((w - l.gamma).abs() < 1e-6 * l.gamma, "{w}");
        }
    }

    #[test]
    fn pressure_and_stiffness_are_exact_derivatives_everywhere() {
        for l in laws() {
            // (not exactly at the guard h_c = z₀/2, where dk/dh jumps and a central difference straddles it)
            for &x in &[0.1, 0.45, 0.499, 0.501, 0.55, 0.9, 1.0, 1.2, 2.0, 5.0, -1.0] {
                let h = x * l.z0;
                let e = 1e-5 * l.z0;
                let p_fd = -(l.energy(h + e) - l.energy(h - e)) / (2.0 * e);
                let k_fd = (l.pressure(h + e) - l.pressure(h - e)) / (2.0 * e);
                let (_, p, k) = l.eval(h);
                assert!(
                    (p - p_fd).abs() <= FD_TOL * p.abs().max(l.prefactor()),
                    "p at {x}"
                );
                assert!(
                    (k - k_fd).abs() <= FD_TOL * k.abs().max(l.prefactor() / l.z0),
                    "k at {x}: {k} vs {k_fd}"
                );
            }
        }
    }

    #[test]
    fn max_tension_of_lj93_is_16_over_9_root3() {
        let l = LennardJones::new(LjKind::Lj93, 0.3, 0.4);
        let want = 16.0 * 0.3 / (9.0 * 3f64.sqrt() * 0.4);
        assert!((l.max_tension() - want).abs() < 1e-12 * want);
        assert!(l.stiffness(l.gap_at_max_tension()).abs() < 1e-9 * l.prefactor() / l.z0);
    }
}
