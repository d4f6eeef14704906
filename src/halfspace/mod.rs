//! Axisymmetric small-strain half-space with Lennard-Jones surface tractions (the Greenwood 1997 /
//! Feng 2000 / Attard–Parker class of solutions): a sphere of radius R against a linear elastic
//! half-space of plane-strain modulus E\*, the surfaces interacting through a law p(h).
//!
//! **Equations.** With the approach Δ (positive when the sphere moves towards the surface), the
//! gap is h(r) = −Δ + r²/(2R) + u(r), where the surface displacement under the surface traction is
//! the Boussinesq integral u(r) = (4/(πE\*)) ∫₀^∞ p(h(s)) s/(r+s) K(2√(rs)/(r+s)) ds, positive
//! pressures (repulsion) opening the gap. The load is P = ∫ 2πr p dr (positive compressive).
//!
//! **Scaled units** (used by every kernel below, as in Greenwood 1997): gaps and Δ in z₀
//! (H = h/z₀, D = Δ/z₀), radii in √(Rz₀) (ρ = r/√(Rz₀)), pressure in γ/z₀ (P̄ = p z₀/γ), load
//! in πγR (F̄ = P/(πγR) = 2∫P̄ρdρ). The equation becomes
//!
//! H(ρ) = −D + ρ²/2 + (4/π) μ^{3/2} ∫ P̄(H(σ)) σ/(ρ+σ) K(2√(ρσ)/(ρ+σ)) dσ,
//!
//! with the Tabor parameter μ = (Rγ²/(E\*² z₀³))^{1/3} (PHYSICS.md; the seed's eq. 3.9 is wrong)
//! the only parameter besides the shape of the law. As μ → 0 the half-space is rigid and the
//! pull-off is −2 (DMT); as μ → ∞ it tends to −1.5 (JKR).
//!
//! **Discretisation.** Piecewise-constant ring pressures on a graded radial grid ([`grid`]),
//! collocated at the nodes, with exact ring influence coefficients from complete elliptic
//! integrals ([`influence`], [`elliptic`]). The grid is fine over the contact edge (a window that
//! moves with it at large μ, rebuilt as the edge moves) and wherever a ring could jump on its own
//! (gaps between the peak tension and 3z₀); the contact interior is graded. The domain
//! is truncated where the neglected attractive tail carries a load below
//! `Params::tail_tolerance`; the remaining tail (estimated as 2φ̄(H) at the outer edge) is
//! reported.
//!
//! **Solution.** Newton on the bordered system (gaps H_i and the approach D) with a last
//! equation that prescribes H(0), D or a pseudo-arclength step ([`solve`]); pseudo-arclength
//! (Keller) continuation traces the whole S-curve through every fold of D, of the load and of
//! H(0) ([`curve`]). Pull-off (the deepest load minimum, i.e. the load-control pull-off) and the
//! jump points (first maximum and last minimum of D: jump-in on approach and jump-out on
//! retraction under displacement control) are located by the secant (Illinois) method on dF̄/ds
//! and dD/ds, computed exactly from the unit tangent of the solution path. [`refinement`] repeats
//! the pull-off on three grids that halve every cell and reports a Richardson error estimate.
//!
//! **Contact radius** is defined as the outermost radius where h = z₀ (where p changes sign from
//! repulsive to attractive), linearly interpolated between nodes; 0 while h(0) > z₀.
//!
//! Entry points: [`Problem`] (from dimensional inputs or from (μ, law)), [`trace_curve`],
//! [`pull_off`], [`HalfspaceParams`].

pub mod curve;
pub mod elliptic;
pub mod grid;
pub mod influence;
pub mod refinement;
pub mod solve;
pub mod trace_grid;

pub use curve::{trace_curve, Curve, CurvePoint};
pub use refinement::{pull_off, PullOff, RefinementLevel};

use crate::laws::{LennardJones, LjKind};
use thiserror::Error;

/// A surface law as the half-space needs it: pressure and stiffness at a gap, and the two
/// constants that scale the problem.
pub trait Traction {
    /// (p(h), dp/dh): pressure in GPa (positive repulsive) and stiffness in GPa/nm at gap h (nm).
    fn pressure_stiffness(&self, h: f64) -> (f64, f64);
    /// Work of adhesion γ, J/m² (= nN/nm).
    fn work_of_adhesion(&self) -> f64;
    /// Equilibrium separation z₀ (the zero of p), nm.
    fn equilibrium_gap(&self) -> f64;
}

impl Traction for LennardJones {
    fn pressure_stiffness(&self, h: f64) -> (f64, f64) {
        let (_, p, k) = self.eval(h);
        (p, k)
    }
    fn work_of_adhesion(&self) -> f64 {
        self.gamma
    }
    fn equilibrium_gap(&self) -> f64 {
        self.z0
    }
}

impl Traction for crate::laws::SurfaceLaw {
    fn pressure_stiffness(&self, h: f64) -> (f64, f64) {
        let (_, p, k) = self.eval(h);
        (p, k)
    }
    fn work_of_adhesion(&self) -> f64 {
        self.gamma()
    }
    /// The shifted law keeps the repulsive core, so p still vanishes at the base law's z₀.
    fn equilibrium_gap(&self) -> f64 {
        self.z0()
    }
}

/// A sphere against a half-space with a surface law.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem<T: Traction = LennardJones> {
    /// sphere radius R, nm
    pub radius: f64,
    /// plane-strain modulus E\*, GPa (1/E\* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂)
    pub modulus: f64,
    /// surface law
    pub law: T,
}

/// Conversion factors from scaled to internal units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Scales {
    /// load unit πγR, nN
    pub load: f64,
    /// gap and approach unit z₀, nm
    pub gap: f64,
    /// radial unit √(Rz₀), nm
    pub radial: f64,
}

impl Problem<LennardJones> {
    /// A problem in scaled units: R = z₀ = γ = 1 and E\* = μ^{−3/2}, so the Tabor parameter is μ.
    pub fn scaled(mu: f64, kind: LjKind) -> Result<Self, HalfspaceError> {
        Problem::new(1.0, mu.powf(-1.5), LennardJones::new(kind, 1.0, 1.0))
    }
}

/// The largest Tabor μ the solver is validated at (μ = 10 for both laws, within 0.62 % / 0.20 % of
/// JKR: docs/validation-halfspace.md). Beyond it the process zone, ∝ μ^(−3/2), asks for grids the
/// crack-tip fine zone has not been shown to follow, and JKR is the answer to that accuracy.
pub const MAX_VALIDATED_MU: f64 = 10.0;

impl<T: Traction> Problem<T> {
    /// `Err` when Tabor's μ lies beyond [`MAX_VALIDATED_MU`].
    pub fn check_validated_range(&self) -> Result<(), HalfspaceError> {
        // a relative margin so that a μ of 10 computed through a round trip of units passes
        let mu = self.tabor();
        if mu > MAX_VALIDATED_MU * (1.0 + 1e-9) {
            return Err(HalfspaceError::BeyondValidatedRange {
                mu,
                max: MAX_VALIDATED_MU,
            });
        }
        Ok(())
    }

    /// A problem from dimensional inputs (R in nm, E\* in GPa); all must be positive and finite.
    pub fn new(radius: f64, modulus: f64, law: T) -> Result<Self, HalfspaceError> {
        let checks = [
            ("radius", radius),
            ("modulus", modulus),
            ("gamma", law.work_of_adhesion()),
            ("z0", law.equilibrium_gap()),
        ];
        for (name, value) in checks {
            if !(value.is_finite() && value > 0.0) {
                return Err(HalfspaceError::BadInput { name, value });
            }
        }
        Ok(Problem {
            radius,
            modulus,
            law,
        })
    }

    /// Tabor parameter μ = (Rγ²/(E\*² z₀³))^{1/3} ([`crate::theory::tabor`]).
    pub fn tabor(&self) -> f64 {
        let sphere = crate::theory::Sphere {
            radius: self.radius,
            modulus: self.modulus,
            gamma: self.law.work_of_adhesion(),
        };
        crate::theory::tabor::mu_of(&sphere, self.law.equilibrium_gap())
    }

    /// Units of the scaled results.
    pub fn scales(&self) -> Scales {
        let (g, z0) = (self.law.work_of_adhesion(), self.law.equilibrium_gap());
        Scales {
            load: std::f64::consts::PI * g * self.radius,
            gap: z0,
            radial: (self.radius * z0).sqrt(),
        }
    }

    /// Scaled pressure and stiffness (P̄, dP̄/dH) at scaled gap H.
    pub fn scaled_law(&self, gap: f64) -> (f64, f64) {
        let (g, z0) = (self.law.work_of_adhesion(), self.law.equilibrium_gap());
        let (p, k) = self.law.pressure_stiffness(gap * z0);
        (p * z0 / g, k * z0 * z0 / g)
    }

    /// Scaled energy per unit area φ̄(H) = ∫_H^∞ P̄ dH', by quadrature of the law (used only
    /// for the far-field tail estimate).
    pub fn scaled_tail_energy(&self, gap: f64) -> f64 {
        // ∫_H^∞ P̄ dH' with H' = H/t, dH' = H/t² dt, t ∈ (0, 1]: smooth for power-law tails
        const PANELS: usize = 64;
        let mut sum = 0.0;
        for i in 0..PANELS {
            let t = (i as f64 + 0.5) / PANELS as f64;
            sum += self.scaled_law(gap / t).0 * gap / (t * t);
        }
        sum / PANELS as f64
    }
}

/// Solver settings. Lengths in scaled units (gaps in z₀, radii in √(Rz₀)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfspaceParams {
    /// fine grid cells per process-zone width ℓ = min(1, μ^{−3/2}) (PHYSICS.md)
    pub cells_per_zone: f64,
    /// growth of the spacing away from the fine zone, per unit distance
    pub growth: f64,
    /// the uniform zone of the trace grid is at most this many process-zone widths ℓ wide and
    /// moves with the contact edge (large μ); narrower zones cover the whole curve
    pub window_zones: f64,
    /// the truncated attractive tail may carry at most this scaled load (rigid estimate)
    pub tail_tolerance: f64,
    /// central gap H(0) where tracing starts; `None`: 3 + 3μ^{3/7}, beyond jump-in
    pub start_gap: Option<f64>,
    /// tracing stops once pull-off is passed and the scaled load F̄ reaches this value
    pub end_load: f64,
    /// tracing gives up below this central gap
    pub min_gap: f64,
    /// first and largest continuation step in H(0)
    pub max_step: f64,
    /// smallest continuation step before giving up
    pub min_step: f64,
    /// predicted change of any nodal gap per step is kept below this
    pub max_gap_change: f64,
    /// Newton: residual tolerance (max norm, scaled gap units)
    pub tolerance: f64,
    /// Newton: iterations before a step is cut back
    pub max_iterations: usize,
    /// Newton: largest change of any gap per iteration (the step is scaled down beyond it)
    pub max_newton_change: f64,
    /// secant search on turning points: tolerance on H(0)
    pub locate_tolerance: f64,
    /// refinement study: ratio of cell sizes between successive grids
    pub refinement_ratio: f64,
}

impl Default for HalfspaceParams {
    fn default() -> Self {
        HalfspaceParams {
            cells_per_zone: 12.0,
            growth: 0.15,
            window_zones: 16.0,
            tail_tolerance: 1e-5,
            start_gap: None,
            end_load: 0.0,
            min_gap: 0.3,
            max_step: 0.25,
            min_step: 1e-7,
            max_gap_change: 0.2,
            tolerance: 1e-10,
            max_iterations: 25,
            max_newton_change: 0.5,
            locate_tolerance: 1e-9,
            refinement_ratio: 2.0,
        }
    }
}

/// Cost of an answer.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Cost {
    /// Newton iterations (each one dense LU factorisation)
    pub newton_iterations: usize,
    /// converged nonlinear solves
    pub solves: usize,
    /// wall time, s
    pub wall_time: f64,
    /// largest grid used (nodes)
    pub max_nodes: usize,
}

impl Cost {
    /// Add another cost (wall time and counts summed, nodes maxed).
    pub fn add(&mut self, other: &Cost) {
        self.newton_iterations += other.newton_iterations;
        self.solves += other.solves;
        self.wall_time += other.wall_time;
        self.max_nodes = self.max_nodes.max(other.max_nodes);
    }
}

/// What went wrong.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum HalfspaceError {
    /// an input is not positive and finite
    #[error("half-space input {name} = {value} must be positive and finite")]
    BadInput {
        /// which input
        name: &'static str,
        /// its value
        value: f64,
    },
    /// Newton did not converge even at the smallest continuation step
    #[error("Newton did not converge at central gap H(0) = {central_gap} z0 (residual {residual:e} after {iterations} iterations, step {step:e})")]
    NoConvergence {
        /// central gap of the failed solve, z₀
        central_gap: f64,
        /// last residual (max norm)
        residual: f64,
        /// iterations spent
        iterations: usize,
        /// continuation step when it gave up
        step: f64,
    },
    /// a non-finite number appeared
    #[error("non-finite value in the half-space solve at central gap H(0) = {central_gap} z0")]
    NonFinite {
        /// central gap, z₀
        central_gap: f64,
    },
    /// Tabor's μ beyond the range the solver is validated over
    #[error(
        "Tabor μ = {mu} is beyond the half-space solver's validated range μ ≤ {max} \
         (docs/validation-halfspace.md): its pull-off there is already within 0.6 % of JKR's \
         −1.5 πγR under load control (−5/6 under displacement control), so use JKR \
         (`turf theory pulloff --model jkr`), or the FE for a finite-strain answer"
    )]
    BeyondValidatedRange {
        /// the problem's Tabor μ
        mu: f64,
        /// the largest validated μ
        max: f64,
    },
    /// the curve ended without a pull-off
    #[error("no load minimum found between H(0) = {start} and {end} z0")]
    NoPullOff {
        /// start of tracing
        start: f64,
        /// where tracing stopped
        end: f64,
    },
}
