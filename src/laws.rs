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
//!
//! **Thermally shifted law** (seed §5.2, Fig 5.3; PHYSICS.md "Thermally shifted law"): the free
//! tube ends vibrate with an RMS amplitude u (seed eq. 5.9, `theory::thermal`) much larger than
//! z₀, so the indenter meets a smeared interaction. [`ThermallyShifted`] stretches the *whole*
//! attractive branch affinely about z₀: for h ≥ z₀,
//!
//! p_s(h) = p(z₀ + (h − z₀)/b) / b,  b = 1 + u/(h_int − z₀),
//!
//! with h_int the base law's tangent intercept at the tail's inflection. Written as a gap map,
//! φ_s(h) = φ(H(h)) with H = z₀ + (h − z₀)/b, so φ_s(z₀) = −γ and φ_s(∞) = 0: γ is kept exactly,
//! the intercept moves by exactly u and the peak tension falls to σ_max/b — no part of the
//! attraction keeps the base law's peak. Below z₀ the base repulsion stays, joined to the
//! stretched branch by a C² blend of width [`SHIFT_BLEND_FRACTION`]·z₀ on the repulsive side so
//! that the stiffness is continuous at z₀. p_s = p(H)H' and k_s = k(H)H'² + p(H)H'' are exact
//! derivatives (tested below by finite differences).
//!
//! [`SurfaceLaw`] is the one type engines take: either law behind the same methods.

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
        // s^(m−1) and s^(n−1) by products (powi with a run-time exponent is a library call,
        // a third of the discrete engine's time in the van der Waals kernel)
        let s2 = s * s;
        let (sm1, sn1) = match self.kind {
            LjKind::Lj93 => (s2, (s2 * s2) * (s2 * s2)),
            LjKind::Lj104 => {
                let s3 = s2 * s;
                (s3, s3 * s3 * s3)
            }
        };
        let (sn, sm) = (sn1 * s, sm1 * s);
        let phi = c * self.z0 * (sn1 / (n - 1) as f64 - sm1 / (m - 1) as f64);
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

impl LennardJones {
    /// Gap of the inflection point of the attractive tail of p(h) (d²p/dh² = 0 beyond the
    /// largest tension), nm: h_i = z₀ (n(n+1)/(m(m+1)))^(1/(n−m)).
    pub fn gap_at_tail_inflection(&self) -> f64 {
        let (n, m) = self.kind.exponents();
        let ratio = (n * (n + 1)) as f64 / (m * (m + 1)) as f64;
        self.z0 * ratio.powf(1.0 / (n - m) as f64)
    }

    /// Where the tangent to p(h) at the tail's inflection point crosses p = 0, nm: the range of
    /// the attraction that the thermal shift moves outward by u (seed Fig 5.3, "α_int").
    pub fn tangent_intercept(&self) -> f64 {
        let hi = self.gap_at_tail_inflection();
        let (_, p, k) = self.raw(hi);
        hi - p / k
    }
}

/// What a [`ThermallyShifted`] law is built from (its serialised form).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThermalShiftSpec {
    /// the Lennard-Jones law being shifted
    pub base: LennardJones,
    /// thermal amplitude u of the tube ends (seed eq. 5.9), nm; u ≥ 0
    pub u: f64,
}

/// Why a thermally shifted law cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LawError {
    /// γ or z₀ not positive and finite
    #[error("the base law needs γ > 0 and z₀ > 0 (finite), got γ = {gamma}, z₀ = {z0}")]
    BadBase {
        /// γ, J/m²
        gamma: f64,
        /// z₀, nm
        z0: f64,
    },
    /// u negative or not finite
    #[error("the thermal amplitude u must be ≥ 0 and finite, got {0} nm")]
    BadShift(f64),
}

/// Width of the repulsive-side blend, as a fraction of z₀: over z₀ − w ≤ h ≤ z₀ the gap map's
/// slope falls smoothly from 1 (the base repulsion) to 1/b (the stretched attraction), so the
/// stiffness is continuous at z₀ for Newton. It only translates the repulsion below z₀ − w
/// outward by w(1 − 1/b)/2 ≤ 0.01 z₀; γ, the intercept and the peak tension are untouched.
pub const SHIFT_BLEND_FRACTION: f64 = 0.02;

/// A Lennard-Jones law whose whole attractive branch is stretched affinely about z₀ by the
/// thermal vibration of the tube ends (seed §5.2, PHYSICS.md "Thermally shifted law"): same γ,
/// same z₀ and repulsion, peak tension σ_max/b, tangent intercept moved out by exactly u.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ThermalShiftSpec", into = "ThermalShiftSpec")]
pub struct ThermallyShifted {
    base: LennardJones,
    u: f64,
    /// width w of the repulsive-side blend, nm
    blend: f64,
    /// stretch b = 1 + u/(h_int − z₀) ≥ 1
    stretch: f64,
}

impl TryFrom<ThermalShiftSpec> for ThermallyShifted {
    type Error = LawError;
    fn try_from(s: ThermalShiftSpec) -> Result<Self, LawError> {
        ThermallyShifted::new(s.base, s.u)
    }
}

impl From<ThermallyShifted> for ThermalShiftSpec {
    fn from(t: ThermallyShifted) -> Self {
        ThermalShiftSpec {
            base: t.base,
            u: t.u,
        }
    }
}

impl ThermallyShifted {
    /// Shift `base` by the thermal amplitude `u` (nm): b = 1 + u/(h_int − z₀), with h_int the
    /// base law's tangent intercept (PHYSICS.md).
    pub fn new(base: LennardJones, u: f64) -> Result<Self, LawError> {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !ok(base.gamma) || !ok(base.z0) {
            return Err(LawError::BadBase {
                gamma: base.gamma,
                z0: base.z0,
            });
        }
        if !(u.is_finite() && u >= 0.0) {
            return Err(LawError::BadShift(u));
        }
        let stretch = 1.0 + u / (base.tangent_intercept() - base.z0);
        Ok(ThermallyShifted {
            base,
            u,
            blend: SHIFT_BLEND_FRACTION * base.z0,
            stretch,
        })
    }

    /// The unshifted law.
    pub fn base(&self) -> &LennardJones {
        &self.base
    }

    /// The thermal amplitude u, nm.
    pub fn shift(&self) -> f64 {
        self.u
    }

    /// The stretch b: the attraction's range is b times the base law's, its tension 1/b.
    pub fn stretch(&self) -> f64 {
        self.stretch
    }

    /// The gap map H(h) and its first two derivatives (H, H', H''): φ_s(h) = φ(H(h)).
    ///
    /// For h ≥ z₀, H = z₀ + (h − z₀)/b (the affine stretch, so p_s = p(H)/b); over the blend
    /// z₀ − w ≤ h ≤ z₀, H' = 1/b + (1 − 1/b)(1 − 3t² + 2t³) with t = (h − z₀ + w)/w, H(z₀) = z₀;
    /// below, H = h + w(1 − 1/b)/2. H is C² (H' and H'' continuous), so k_s is continuous.
    fn gap_map(&self, h: f64) -> (f64, f64, f64) {
        let (z0, w, b) = (self.base.z0, self.blend, self.stretch);
        if h >= z0 {
            return (z0 + (h - z0) / b, 1.0 / b, 0.0);
        }
        let excess = 1.0 - 1.0 / b;
        let x = h - (z0 - w);
        if x <= 0.0 {
            return (h + 0.5 * excess * w, 1.0, 0.0);
        }
        let t = x / w;
        // H(h) = z₀ − ∫_h^{z₀} H'; the primitive of H' from z₀ − w is w[t/b + excess(t − t³ + t⁴/2)]
        let at_z0 = w * (1.0 / b + 0.5 * excess);
        let big_h = z0 - at_z0 + w * (t / b + excess * (t - t.powi(3) + 0.5 * t.powi(4)));
        let dh = 1.0 / b + excess * (1.0 - 3.0 * t * t + 2.0 * t.powi(3));
        let ddh = excess * 6.0 * (t * t - t) / w;
        (big_h, dh, ddh)
    }

    /// Energy per unit area φ(h) (J/m²), pressure p(h) (GPa) and stiffness dp/dh (GPa/nm).
    pub fn eval(&self, h: f64) -> (f64, f64, f64) {
        let (big_h, dh, ddh) = self.gap_map(h);
        let (phi, p, k) = self.base.eval(big_h);
        (phi, p * dh, k * dh * dh + p * ddh)
    }

    /// Gap of the largest tension, nm: z₀ + b(h_m − z₀), h_m the base law's.
    pub fn gap_at_max_tension(&self) -> f64 {
        self.stretched(self.base.gap_at_max_tension())
    }

    /// Gap of the tail's inflection point, nm: z₀ + b(h_i − z₀).
    pub fn gap_at_tail_inflection(&self) -> f64 {
        self.stretched(self.base.gap_at_tail_inflection())
    }

    /// The tangent intercept h_int + u, nm (the stretch is built to move it by exactly u).
    pub fn tangent_intercept(&self) -> f64 {
        self.stretched(self.base.tangent_intercept())
    }

    /// The gap h_s ≥ z₀ that the stretch maps onto a base gap h ≥ z₀.
    fn stretched(&self, h: f64) -> f64 {
        self.base.z0 + self.stretch * (h - self.base.z0)
    }
}

/// A force–separation law as every engine takes it: plain Lennard-Jones or thermally shifted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum SurfaceLaw {
    /// LJ 9-3 or 10-4 (seed eqs. 4.1, 5.10)
    LennardJones(LennardJones),
    /// the thermally shifted law of seed §5.2
    ThermallyShifted(ThermallyShifted),
}

impl From<LennardJones> for SurfaceLaw {
    fn from(l: LennardJones) -> Self {
        SurfaceLaw::LennardJones(l)
    }
}

impl From<ThermallyShifted> for SurfaceLaw {
    fn from(l: ThermallyShifted) -> Self {
        SurfaceLaw::ThermallyShifted(l)
    }
}

impl SurfaceLaw {
    /// Energy per unit area φ(h) (J/m²), pressure p(h) = −dφ/dh (GPa), stiffness dp/dh (GPa/nm).
    pub fn eval(&self, h: f64) -> (f64, f64, f64) {
        match self {
            SurfaceLaw::LennardJones(l) => l.eval(h),
            SurfaceLaw::ThermallyShifted(l) => l.eval(h),
        }
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

    /// Gap of the largest tension, nm.
    pub fn gap_at_max_tension(&self) -> f64 {
        match self {
            SurfaceLaw::LennardJones(l) => l.gap_at_max_tension(),
            SurfaceLaw::ThermallyShifted(l) => l.gap_at_max_tension(),
        }
    }

    /// The largest tensile pressure σ₀ = −min p (positive), GPa.
    pub fn max_tension(&self) -> f64 {
        -self.pressure(self.gap_at_max_tension())
    }

    /// Where the tangent at the tail's inflection point crosses p = 0, nm (the law's range:
    /// h_int of the base law, h_int + u once shifted).
    pub fn tangent_intercept(&self) -> f64 {
        match self {
            SurfaceLaw::LennardJones(l) => l.tangent_intercept(),
            SurfaceLaw::ThermallyShifted(l) => l.tangent_intercept(),
        }
    }

    /// The stretch b of the attractive branch (1 for a plain law).
    pub fn stretch(&self) -> f64 {
        match self {
            SurfaceLaw::LennardJones(_) => 1.0,
            SurfaceLaw::ThermallyShifted(l) => l.stretch(),
        }
    }

    /// The thermal shift u, nm (0 for a plain law).
    pub fn shift(&self) -> f64 {
        match self {
            SurfaceLaw::LennardJones(_) => 0.0,
            SurfaceLaw::ThermallyShifted(l) => l.shift(),
        }
    }

    /// Work of adhesion γ = −φ(z₀), J/m².
    pub fn gamma(&self) -> f64 {
        self.base().gamma
    }

    /// Equilibrium separation z₀ (p(z₀) = 0), nm.
    pub fn z0(&self) -> f64 {
        self.base().z0
    }

    /// The unshifted Lennard-Jones law.
    pub fn base(&self) -> &LennardJones {
        match self {
            SurfaceLaw::LennardJones(l) => l,
            SurfaceLaw::ThermallyShifted(l) => l.base(),
        }
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

    /// ∫_{z0}^{∞} −p dh by the midpoint rule in s = z₀/h (h = z₀/s), n cells.
    fn work_of_separation(law: &SurfaceLaw, n: usize) -> f64 {
        let z0 = law.z0();
        (0..n)
            .map(|i| {
                let s = (i as f64 + 0.5) / n as f64;
                -law.pressure(z0 / s) * z0 / (s * s) / n as f64
            })
            .sum()
    }

    fn shifted_laws() -> Vec<SurfaceLaw> {
        laws()
            .into_iter()
            .flat_map(|l| {
                [0.0, 0.3, 4.6]
                    .into_iter()
                    .map(move |u| ThermallyShifted::new(l, u).unwrap().into())
            })
            .collect()
    }

    #[test]
    fn shifted_law_keeps_gamma_by_quadrature() {
        for law in shifted_laws() {
            // the stretched tail reaches b·z₀/s: 400k midpoint cells in s resolve it to ~1e-9
            let w = work_of_separation(&law, 400_000);
            assert!((w - law.gamma()).abs() < 1e-6 * law.gamma(), "{w} {law:?}");
            assert!((law.energy(law.z0()) + law.gamma()).abs() < 1e-14);
            assert!(law.pressure(law.z0()).abs() < 1e-12);
        }
    }

    #[test]
    fn shifted_law_moves_the_tangent_intercept_by_exactly_u() {
        for base in laws() {
            for u in [0.3, 4.6] {
                let t = ThermallyShifted::new(base, u).unwrap();
                let law = SurfaceLaw::from(t);
                // find the tail's inflection independently: dk/dh = 0 by central differences,
                // bisected between the largest tension and far out
                let dk = |h: f64| {
                    let e = 1e-6 * h;
                    (law.stiffness(h + e) - law.stiffness(h - e)) / (2.0 * e)
                };
                let (mut lo, mut hi) =
                    (law.gap_at_max_tension() * 1.01, 100.0 * base.z0 + 50.0 * u);
                assert!(dk(lo) > 0.0 && dk(hi) < 0.0);
                for _ in 0..100 {
                    let mid = 0.5 * (lo + hi);
                    if dk(mid) > 0.0 {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                let (_, p, k) = law.eval(lo);
                let intercept = lo - p / k;
                let want = base.tangent_intercept() + u;
                // FD of k with step 1e-6 h locates the inflection to ~1e-7 relative
                assert!(
                    (intercept - want).abs() < 1e-6 * want,
                    "{intercept} vs {want}"
                );
                assert!((lo - t.gap_at_tail_inflection()).abs() < 1e-5 * lo);
            }
        }
    }

    #[test]
    fn shifted_law_derivatives_are_exact_and_continuous() {
        for law in shifted_laws() {
            let z0 = law.z0();
            let w = SHIFT_BLEND_FRACTION * z0;
            let hm = law.gap_at_max_tension();
            for &h in &[
                0.3 * z0,
                0.9 * z0,
                z0 - 1.5 * w,
                z0 - 0.999 * w,
                z0 - 0.5 * w,
                z0 - 0.001 * w,
                1.001 * z0,
                1.05 * z0,
                0.5 * (z0 + hm),
                0.999 * hm,
                1.001 * hm,
                2.0 * hm,
                10.0 * hm,
                40.0 * z0,
            ] {
                // a step well inside the blend, so no difference straddles a joint
                let e = 1e-4 * w;
                let p_fd = -(law.energy(h + e) - law.energy(h - e)) / (2.0 * e);
                let k_fd = (law.pressure(h + e) - law.pressure(h - e)) / (2.0 * e);
                let (_, p, k) = law.eval(h);
                let scale = law.gamma() / z0;
                assert!(
                    (p - p_fd).abs() <= FD_TOL * p.abs().max(scale),
                    "p at {h}: {p} {p_fd}"
                );
                assert!(
                    (k - k_fd).abs() <= FD_TOL * k.abs().max(scale / z0),
                    "k at {h}: {k} {k_fd}"
                );
            }
            // continuity of φ, p and k across the joints of the blend, z₀ − w and z₀
            for joint in [z0 - w, z0] {
                let e = 1e-9 * z0;
                let (a, b) = (law.eval(joint - e), law.eval(joint + e));
                assert!((a.0 - b.0).abs() < 1e-6 * law.gamma());
                assert!((a.1 - b.1).abs() < 1e-6 * law.gamma() / z0);
                assert!(
                    (a.2 - b.2).abs() < 1e-5 * a.2.abs().max(law.gamma() / (z0 * z0)),
                    "k at {joint}: {} {}",
                    a.2,
                    b.2
                );
            }
        }
    }

    #[test]
    fn the_whole_attraction_is_stretched_and_the_peak_falls_by_b() {
        for base in laws() {
            for u in [0.3, 4.6] {
                let t = ThermallyShifted::new(base, u).unwrap();
                let law = SurfaceLaw::from(t);
                let b = t.stretch();
                assert!((b - (1.0 + u / (base.tangent_intercept() - base.z0))).abs() < 1e-14);
                // σ_max/b, located by scanning p_s independently of the closed form
                let (h_lo, h_hi) = (base.z0, base.z0 + 10.0 * b * base.z0);
                let n = 200_000;
                let scanned = (0..=n)
                    .map(|i| -law.pressure(h_lo + (h_hi - h_lo) * i as f64 / n as f64))
                    .fold(f64::MIN, f64::max);
                let want = base.max_tension() / b;
                assert!((law.max_tension() - want).abs() < 1e-12 * want);
                assert!((scanned - want).abs() < 1e-4 * want, "{scanned} vs {want}");
                // the tension everywhere past z₀ is the base law's at the mapped gap, over b
                for x in [1.001, 1.01, 1.1, 1.5, 3.0] {
                    let h = base.z0 * x;
                    let mapped = base.z0 + (h - base.z0) / b;
                    assert!((law.pressure(h) - base.pressure(mapped) / b).abs() < 1e-14);
                }
                // the blend touches neither γ, nor the intercept, nor the peak
                assert!((law.energy(law.z0()) + law.gamma()).abs() < 1e-15);
                assert!((law.tangent_intercept() - base.tangent_intercept() - u).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn seed_numbers_of_the_shifted_law() {
        // PHYSICS.md: γ = 0.46 J/m², z₀ = 0.34 nm, u = 4.626 nm
        let cases = [
            (LjKind::Lj104, 0.4517, 0.6211, 17.46, 1.983, 0.1136),
            (LjKind::Lj93, f64::NAN, f64::NAN, 13.68, 1.389, 0.1015),
        ];
        for (kind, hi, hint, b, smax, speak) in cases {
            let base = LennardJones::new(kind, 0.46, 0.34);
            let t = ThermallyShifted::new(base, 4.626).unwrap();
            // the quoted figures carry four significant digits
            let close = |a: f64, b: f64| (a - b).abs() < 6e-4 * b;
            if hi.is_finite() {
                assert!(close(base.gap_at_tail_inflection(), hi));
                assert!(close(base.tangent_intercept(), hint));
            }
            assert!(close(t.stretch(), b), "{kind:?} b = {}", t.stretch());
            assert!(close(base.max_tension(), smax));
            let law = SurfaceLaw::from(t);
            assert!(close(law.max_tension(), speak), "{}", law.max_tension());
        }
    }

    #[test]
    fn zero_shift_is_the_base_law_and_the_shift_lowers_the_tension() {
        for base in laws() {
            let t = ThermallyShifted::new(base, 0.0).unwrap();
            for &x in &[0.4, 1.0, 1.1, 1.3, 3.0] {
                let (a, b) = (t.eval(x * base.z0), base.eval(x * base.z0));
                assert!((a.0 - b.0).abs() < 1e-14 && (a.1 - b.1).abs() < 1e-12);
            }
            let law = SurfaceLaw::from(base);
            assert!((law.max_tension() - base.max_tension()).abs() < 1e-12);
            let shifted = SurfaceLaw::from(ThermallyShifted::new(base, 4.6).unwrap());
            assert!(shifted.max_tension() < 0.2 * base.max_tension());
            assert!(shifted.max_tension() > 0.0);
        }
        assert!(ThermallyShifted::new(laws()[0], -1.0).is_err());
        assert!(ThermallyShifted::new(LennardJones::new(LjKind::Lj93, 0.0, 1.0), 1.0).is_err());
    }

    #[test]
    fn surface_law_round_trips_through_json() {
        for law in shifted_laws()
            .into_iter()
            .chain(laws().map(SurfaceLaw::from))
        {
            let text = serde_json::to_string(&law).unwrap();
            let back: SurfaceLaw = serde_json::from_str(&text).unwrap();
            assert_eq!(back, law, "{text}");
        }
        let bad =
            r#"{"law":"thermally_shifted","base":{"kind":"lj93","gamma":0.4,"z0":0.3},"u":-2}"#;
        assert!(serde_json::from_str::<SurfaceLaw>(bad).is_err());
    }
}
