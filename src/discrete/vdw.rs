//! Tube–tube van der Waals interaction as a line-pair potential between tube axes
//! (seed §2.4: contact energy per unit length γ_L; docs/discrete-contacts.md).
//!
//! Two tube axes interact through an energy per unit length² u(ρ) of the distance ρ between a
//! point of one axis and a point of the other; the energy of two tubes is the double line
//! integral E = ∫∫ u(|x_a(s) − x_b(t)|) ds dt over reference (material) arclength. The density
//! is the Lennard-Jones wall–wall energy per unit area φ(g) ([`crate::laws::LennardJones`]) of
//! the surface gap g = ρ − r_a − r_b, halved and switched off smoothly:
//!
//! u(ρ) = ½ φ_w(g) S(g),  S = 1 for g ≤ g_s, quintic smoothstep to 0 at g_c (C²).
//!
//! With u = ½φ_w the double line integral reproduces, to leading order in range/radius, the
//! Derjaguin energies of two parallel cylinders (E/L = ∫ φ_w(g + x²/R) dx) and of two crossed
//! cylinders (E = 2πR ∫_g^∞ φ_w), so w (the depth of φ_w) is a wall–wall work of adhesion and
//! the crossed-tube energy follows from the same w. The two free numbers, w and the law's z₀,
//! are calibrated once so that two parallel tubes of the reference radius have their minimum
//! line energy −γ_L at the axis separation 2r_o + 0.34 nm ([`LinePairPotential::calibrate`]).
//!
//! The double integral is evaluated with composite Gauss–Legendre quadrature at *material*
//! points of each segment (fixed parameters t, weights ∝ reference length): the energy is a sum
//! over point pairs, so gradient and Hessian are its exact derivatives, junctions between
//! segments are seamless, and the sliding corrugation is set by the panel length relative to the
//! interaction width √(2 D₀ z₀) alone, not by the segment length ([`energy_segment_segment`]).

use crate::numerics::quadrature::gauss_legendre_unit;
use std::f64::consts::PI;

use parry3d_f64::math::Vector;
use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;
use serde::{Deserialize, Serialize};

use crate::laws::{LennardJones, LjKind};

/// Parameters of the tube–tube interaction (internal units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct VdwParams {
    /// contact energy per unit length γ_L of two parallel reference tubes, nN (PHYSICS.md: ~1 nN
    /// for 40-nm multi-walled tubes)
    pub gamma_l: f64,
    /// outer radius of the reference tubes at which γ_L is specified, nm
    pub radius_ref: f64,
    /// equilibrium wall–wall gap of parallel tubes, nm (graphite interlayer spacing 0.34 nm)
    pub gap_eq: f64,
    /// wall–wall law: 9-3 (thick walls, default) or 10-4 (monolayer)
    pub law: LjKind,
    /// gap at which the smooth switch-off starts, nm
    pub gap_switch: f64,
    /// gap beyond which the interaction is exactly zero, nm
    pub gap_cut: f64,
    /// quadrature panel length as a fraction of the interaction width √(2 D₀ z₀)
    pub panel_fraction: f64,
    /// Gauss–Legendre points per panel
    pub gauss_order: usize,
    /// Verlet skin of the neighbour list, nm
    pub skin: f64,
    /// same-tube segment pairs closer in arclength than this factor times the cutoff distance
    /// 2r + g_c are excluded (≥ 1, so that a straight tube has no self-energy)
    pub self_exclusion_factor: f64,
    /// how the inner line integral over the partner segment is evaluated (default: the point
    /// quadrature, the reference; scenes default to the table, `[turf.vdw] kernel`)
    pub kernel: VdwKernel,
}

/// How the double line integral of a segment pair is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum VdwKernel {
    /// material Gauss points on both segments, summed pair by pair (the reference)
    #[default]
    Quadrature,
    /// Gauss points on one segment, the integral over the other from a table of
    /// G(d, x) ([`super::vdw_table`]); needs one tube radius
    Tabulated,
}

impl Default for VdwParams {
    fn default() -> Self {
        VdwParams {
            gamma_l: 1.0,
            radius_ref: 20.0,
            gap_eq: 0.34,
            law: LjKind::Lj93,
            gap_switch: 1.0,
            gap_cut: 2.5,
            panel_fraction: 0.75,
            gauss_order: 4,
            skin: 1.0,
            self_exclusion_factor: PI / 2.0,
            kernel: VdwKernel::Quadrature,
        }
    }
}

/// Why an interaction could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VdwError {
    /// a parameter outside its allowed range
    #[error("vdw parameter `{name}` = {value} is not allowed: {allowed}")]
    InvalidParameter {
        /// parameter name
        name: &'static str,
        /// offending value
        value: f64,
        /// what is allowed
        allowed: &'static str,
    },
    /// the calibration found no z₀ putting the minimum at the requested gap
    #[error(
        "vdw calibration failed: no z0 in [{lo}, {hi}] nm puts the parallel minimum at {gap} nm"
    )]
    Calibration {
        /// lower end of the bracket, nm
        lo: f64,
        /// upper end of the bracket, nm
        hi: f64,
        /// requested equilibrium gap, nm
        gap: f64,
    },
    /// a tube layout inconsistent with the coordinate vector
    #[error("tube layout: {0}")]
    Layout(String),
}

impl VdwParams {
    /// Check every parameter's range.
    pub fn validate(&self) -> Result<(), VdwError> {
        let pos = |name, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(VdwError::InvalidParameter {
                    name,
                    value,
                    allowed: "finite and > 0",
                })
            }
        };
        pos("gamma_l", self.gamma_l)?;
        pos("radius_ref", self.radius_ref)?;
        pos("gap_eq", self.gap_eq)?;
        pos("gap_switch", self.gap_switch)?;
        pos("panel_fraction", self.panel_fraction)?;
        pos("skin", self.skin)?;
        if !(self.gap_cut.is_finite() && self.gap_cut > self.gap_switch) {
            return Err(VdwError::InvalidParameter {
                name: "gap_cut",
                value: self.gap_cut,
                allowed: "finite and > gap_switch",
            });
        }
        if self.gap_switch <= self.gap_eq {
            return Err(VdwError::InvalidParameter {
                name: "gap_switch",
                value: self.gap_switch,
                allowed: "> gap_eq",
            });
        }
        if !(1..=16).contains(&self.gauss_order) {
            return Err(VdwError::InvalidParameter {
                name: "gauss_order",
                value: self.gauss_order as f64,
                allowed: "1 ..= 16",
            });
        }
        if !(self.self_exclusion_factor.is_finite() && self.self_exclusion_factor >= 1.0) {
            return Err(VdwError::InvalidParameter {
                name: "self_exclusion_factor",
                value: self.self_exclusion_factor,
                allowed: ">= 1 (a straight tube must not interact with itself)",
            });
        }
        Ok(())
    }
}

/// Quintic smoothstep switch S(g) and its first two derivatives: 1 below `on`, 0 above `off`.
pub(crate) fn switch(g: f64, on: f64, off: f64) -> (f64, f64, f64) {
    if g <= on {
        return (1.0, 0.0, 0.0);
    }
    if g >= off {
        return (0.0, 0.0, 0.0);
    }
    let w = off - on;
    let x = (g - on) / w;
    let x2 = x * x;
    let s = 1.0 - x2 * x * (10.0 - 15.0 * x + 6.0 * x2);
    let ds = -30.0 * x2 * (1.0 - x) * (1.0 - x) / w;
    let d2s = -60.0 * x * (1.0 - x) * (1.0 - 2.0 * x) / (w * w);
    (s, ds, d2s)
}

/// Panels of the reference quadrature of the calibration integrals (per unit of the range).
const CALIBRATION_PANELS: usize = 400;
/// Gauss points per calibration panel.
const CALIBRATION_ORDER: usize = 8;
/// Relative tolerance of the bisection on z₀.
const CALIBRATION_TOL: f64 = 1e-13;

/// The calibrated axis–axis line-pair potential u(ρ) (energy per length², nN/nm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinePairPotential {
    /// wall–wall law φ_w: its γ is the implied wall–wall work of adhesion w (J/m²), its z₀ the
    /// calibrated length (nm)
    pub wall: LennardJones,
    /// gap at which the switch-off starts, nm
    pub gap_switch: f64,
    /// cutoff gap, nm
    pub gap_cut: f64,
}

impl LinePairPotential {
    /// u, du/dρ, d²u/dρ² at axis distance `rho` (nm) between axes of tubes whose outer radii sum
    /// to `r_sum` (nm).
    #[inline]
    pub fn eval(&self, rho: f64, r_sum: f64) -> (f64, f64, f64) {
        let g = rho - r_sum;
        if g >= self.gap_cut {
            return (0.0, 0.0, 0.0);
        }
        let (phi, p, k) = self.wall.eval(g);
        let (s, ds, d2s) = switch(g, self.gap_switch, self.gap_cut);
        // φ' = −p, φ'' = −k
        (
            0.5 * phi * s,
            0.5 * (-p * s + phi * ds),
            0.5 * (-k * s - 2.0 * p * ds + phi * d2s),
        )
    }

    /// Axis distance beyond which u vanishes, nm.
    #[inline]
    pub fn cutoff(&self, r_sum: f64) -> f64 {
        r_sum + self.gap_cut
    }

    /// Energy per unit length (nN) of two infinite parallel straight axes at distance `d` (nm),
    /// and its derivative d/dd (nN/nm): E/L = ∫ u(√(d² + s²)) ds, by fine composite
    /// Gauss–Legendre quadrature (the reference, not the engine's quadrature).
    pub fn parallel_line_energy(&self, d: f64, r_sum: f64) -> (f64, f64) {
        let rc = self.cutoff(r_sum);
        if d >= rc {
            return (0.0, 0.0);
        }
        let s_max = (rc * rc - d * d).sqrt();
        let (mut e, mut de) = (0.0, 0.0);
        integrate(0.0, s_max, |s, w| {
            let rho = (d * d + s * s).sqrt();
            let (u, du, _) = self.eval(rho, r_sum);
            e += 2.0 * w * u;
            de += 2.0 * w * du * d / rho;
        });
        (e, de)
    }

    /// Energy (aJ) of two infinite straight axes crossing at right angles at distance `d`
    /// (nm): E = 2π ∫_d^{ρ_c} u(ρ) ρ dρ (the reference for the engine's crossed energy).
    pub fn crossed_energy(&self, d: f64, r_sum: f64) -> f64 {
        let rc = self.cutoff(r_sum);
        if d >= rc {
            return 0.0;
        }
        let mut e = 0.0;
        integrate(d, rc, |rho, w| {
            e += 2.0 * PI * w * self.eval(rho, r_sum).0 * rho
        });
        e
    }

    /// Calibrate w and z₀ so that two parallel tubes of outer radius `params.radius_ref` have
    /// their minimum line energy −γ_L at axis distance 2 r_ref + gap_eq.
    pub fn calibrate(params: &VdwParams) -> Result<Self, VdwError> {
        params.validate()?;
        let r_sum = 2.0 * params.radius_ref;
        let d0 = r_sum + params.gap_eq;
        let unit = |z0: f64| LinePairPotential {
            wall: LennardJones::new(params.law, 1.0, z0),
            gap_switch: params.gap_switch,
            gap_cut: params.gap_cut,
        };
        // the minimum of the Derjaguin line energy sits at a gap ≈ 0.9 z₀: bracket generously
        let (mut lo, mut hi) = (0.5 * params.gap_eq, 2.0 * params.gap_eq);
        let slope = |z0: f64| unit(z0).parallel_line_energy(d0, r_sum).1;
        // a small z₀ leaves d0 on the attractive side (slope > 0), a large one on the repulsive
        if !(slope(lo) > 0.0 && slope(hi) < 0.0) {
            return Err(VdwError::Calibration {
                lo,
                hi,
                gap: params.gap_eq,
            });
        }
        while hi - lo > CALIBRATION_TOL * hi {
            let mid = 0.5 * (lo + hi);
            if slope(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let z0 = 0.5 * (lo + hi);
        let e_unit = unit(z0).parallel_line_energy(d0, r_sum).0;
        let mut pot = unit(z0);
        pot.wall.gamma = -params.gamma_l / e_unit;
        Ok(pot)
    }

    /// The interaction width √(2 D₀ z₀) (nm) of two parallel tubes of outer radii summing to
    /// `r_sum`: the axial length over which the gap opens by z₀.
    pub fn width(&self, r_sum: f64) -> f64 {
        (2.0 * (r_sum + self.wall.z0) * self.wall.z0).sqrt()
    }
}

/// Composite Gauss–Legendre quadrature of a smooth integrand on [a, b]: calls `f(x, weight)`.
fn integrate(a: f64, b: f64, mut f: impl FnMut(f64, f64)) {
    let rule = gauss_legendre_unit(CALIBRATION_ORDER);
    let h = (b - a) / CALIBRATION_PANELS as f64;
    for p in 0..CALIBRATION_PANELS {
        let x0 = a + p as f64 * h;
        for &(t, w) in &rule {
            f(x0 + t * h, w * h);
        }
    }
}

/// One segment as the quadrature sees it: current end positions (nm), and the material
/// quadrature fixed at set-up (number of panels, reference length in nm).
#[derive(Debug, Clone, Copy)]
pub struct QuadSegment {
    /// current end positions, nm
    pub ends: [Vector; 2],
    /// number of equal panels along the segment
    pub panels: usize,
    /// reference (material) length, nm
    pub length0: f64,
}

/// Energy, gradient and (optionally) Hessian of one segment pair, local dof order
/// (a₀, a₁, b₀, b₁) × (x, y, z).
#[derive(Debug, Clone)]
pub struct SegmentPairEnergy {
    /// energy, aJ
    pub energy: f64,
    /// gradient, nN
    pub grad: [f64; 12],
    /// Hessian (row-major 12×12), nN/nm; `None` unless asked for
    pub hessian: Option<Box<[f64; 144]>>,
    /// number of quadrature point pairs inside the cutoff
    pub point_pairs: usize,
    /// smallest surface gap ρ − r_a − r_b over the point pairs inside the cutoff, nm
    /// (+∞ when there are none; negative when the tubes interpenetrate)
    pub min_gap: f64,
}

impl SegmentPairEnergy {
    /// Add the energy, gradient, Hessian and point pairs of `other` (of the same two segments),
    /// and take the smaller of the two smallest gaps.
    pub(super) fn add(&mut self, other: &SegmentPairEnergy) {
        self.energy += other.energy;
        for (g, o) in self.grad.iter_mut().zip(&other.grad) {
            *g += o;
        }
        if let (Some(h), Some(o)) = (self.hessian.as_mut(), &other.hessian) {
            for (v, w) in h.iter_mut().zip(o.iter()) {
                *v += w;
            }
        }
        self.point_pairs += other.point_pairs;
        self.min_gap = self.min_gap.min(other.min_gap);
    }

    /// No energy, no force, a zero Hessian if asked for, no point pair in range.
    pub(super) fn none(want_hessian: bool) -> Self {
        SegmentPairEnergy {
            energy: 0.0,
            grad: [0.0; 12],
            hessian: want_hessian.then(|| Box::new([0.0; 144])),
            point_pairs: 0,
            min_gap: f64::INFINITY,
        }
    }
}

/// Below this axis distance (nm) a point pair has no direction and is skipped (two axes can
/// only get there through a solver failure; the penetration guard keeps u finite before).
pub(super) const RHO_DEGENERATE: f64 = 1e-9;

/// One material quadrature point of a segment: parameter t ∈ [0, 1] along it and weight W
/// (reference length × Gauss weight / panels, nm).
#[derive(Debug, Clone, Copy)]
pub(super) struct QuadPoint {
    pub(super) t: f64,
    pub(super) weight: f64,
}

/// The material quadrature points of `s`, panel by panel (`rule.len()` per panel).
pub(super) fn quadrature_points<'a>(
    rule: &'a [(f64, f64)],
    s: &QuadSegment,
) -> impl Iterator<Item = QuadPoint> + 'a {
    panel_points(rule, s, 0..s.panels)
}

/// The material quadrature points of the panels `panels` of `s`.
fn panel_points<'a>(
    rule: &'a [(f64, f64)],
    s: &QuadSegment,
    panels: std::ops::Range<usize>,
) -> impl Iterator<Item = QuadPoint> + 'a {
    let length0 = s.length0;
    let n = s.panels as f64;
    panels.flat_map(move |p| {
        rule.iter().map(move |&(x, w)| QuadPoint {
            t: (p as f64 + x) / n,
            weight: length0 * w / n,
        })
    })
}

/// Sums over the partners j of one point i of segment a: Σ W_j f_ij and Σ W_j t_j f_ij of the
/// pair forces, and (for the Hessian) Σ W_j t_jᵏ h_ij, k = 0, 1, 2, of the 3×3 pair Hessians.
/// The node gradients and Hessian blocks follow from these because the shape functions of a
/// point are linear in its parameter.
#[derive(Default)]
pub(super) struct PartnerSums {
    energy: f64,
    force: [f64; 3],
    force_t: [f64; 3],
    hess: [[f64; 9]; 3],
}

/// Whether any point of segment `a` comes closer than `rc` (nm) to segment `b`.
pub(super) fn within(a: &QuadSegment, b: &QuadSegment, rc: f64) -> bool {
    let (la, lb) = closest_points_segment_segment_with_locations_nD(
        (&a.ends[0], &a.ends[1]),
        (&b.ends[0], &b.ends[1]),
    );
    let [ua, va] = la.barycentric_coordinates();
    let [ub, vb] = lb.barycentric_coordinates();
    let closest =
        ((a.ends[0] * ua + a.ends[1] * va) - (b.ends[0] * ub + b.ends[1] * vb)).length_squared();
    closest < rc * rc
}

/// Energy of segment `a` and segment `b` (whose outer radii sum to `r_sum`, nm) as the sum
/// over material Gauss points: E = Σ_i Σ_j W_i W_j u(|p_i − p_j|), W = reference length ×
/// Gauss weight / panels. Only point pairs inside the cutoff are visited — segment pairs
/// farther apart than the cutoff are skipped whole, and for each point of `a` only the panels
/// of `b` inside the cutoff sphere are visited — which changes no term of the sum (u ≡ 0
/// beyond the cutoff); the sums are grouped per point of `a` (round-off level differences
/// from the plain double sum [`energy_segment_segment_unculled`], tested).
pub fn energy_segment_segment(
    pot: &LinePairPotential,
    rule: &[(f64, f64)],
    a: &QuadSegment,
    b: &QuadSegment,
    r_sum: f64,
    want_hessian: bool,
) -> SegmentPairEnergy {
    let mut out = SegmentPairEnergy::none(want_hessian);
    if !within(a, b, pot.cutoff(r_sum)) {
        return out;
    }
    let inner = InnerSum::new(pot, rule, b, r_sum);
    let da = a.ends[1] - a.ends[0];
    for qa in quadrature_points(rule, a) {
        let p = a.ends[0] + da * qa.t;
        if let Some(sums) = inner.partners(p, want_hessian, &mut out) {
            scatter_point(&mut out, &sums, qa);
        }
    }
    out
}

/// The inner sum of the point quadrature: one point p against the material Gauss points of
/// segment b, Σ_j W_j u(|p − p_j|) with its force and Hessian moments.
pub(super) struct InnerSum<'a> {
    pot: &'a LinePairPotential,
    rule: &'a [(f64, f64)],
    b: &'a QuadSegment,
    /// the panels' bounds in b's parameter t, 0 first and 1 last; empty: b's own equal panels
    bounds: Vec<f64>,
    r_sum: f64,
    rc2: f64,
}

impl<'a> InnerSum<'a> {
    /// Set up the sum over `b`'s points (`rule` per panel) for tubes whose outer radii sum to
    /// `r_sum` (nm).
    pub(super) fn new(
        pot: &'a LinePairPotential,
        rule: &'a [(f64, f64)],
        b: &'a QuadSegment,
        r_sum: f64,
    ) -> Self {
        let rc = pot.cutoff(r_sum);
        InnerSum {
            pot,
            rule,
            b,
            bounds: Vec::new(),
            r_sum,
            rc2: rc * rc,
        }
    }

    /// The same sum on panels graded from each end of b instead of b's own: the first
    /// `first` nm of b's reference length long, each next `growth` times longer, up to where
    /// the two ends' panels meet (one panel of at most twice the last width between them).
    pub(super) fn graded(mut self, first: f64, growth: f64) -> Self {
        let l0 = self.b.length0;
        let mut from_end = vec![0.0];
        let (mut s, mut width) = (0.0, first);
        while s + width < 0.5 * l0 {
            s += width;
            from_end.push(s);
            width *= growth;
        }
        self.bounds = from_end.iter().map(|s| s / l0).collect();
        self.bounds
            .extend(from_end.iter().rev().map(|s| (l0 - s) / l0));
        self
    }

    /// The sums over the partners of the point `p` of segment a (only b's panels inside the
    /// cutoff sphere are visited); its point pairs and smallest gap are counted into `out`.
    /// `None` when no partner is in range.
    pub(super) fn partners(
        &self,
        p: Vector,
        want_hessian: bool,
        out: &mut SegmentPairEnergy,
    ) -> Option<PartnerSums> {
        let b = self.b;
        let db = b.ends[1] - b.ends[0];
        let db2 = db.length_squared();
        // parameter interval of b within the cutoff: |r − t db|² < rc²
        let r = p - b.ends[0];
        let (t_lo, t_hi) = if db2 > 0.0 {
            let rd = r.dot(db);
            let disc = rd * rd - db2 * (r.length_squared() - self.rc2);
            if disc <= 0.0 {
                return None;
            }
            let sq = disc.sqrt();
            ((rd - sq) / db2, (rd + sq) / db2)
        } else if r.length_squared() < self.rc2 {
            (0.0, 1.0)
        } else {
            return None;
        };
        if t_hi < 0.0 || t_lo > 1.0 {
            return None;
        }
        let mut sums = PartnerSums::default();
        if self.bounds.is_empty() {
            let nb = b.panels as f64;
            let first = (t_lo.max(0.0) * nb).floor() as usize;
            let last = ((t_hi.min(1.0) * nb).floor() as usize).min(b.panels - 1);
            for qb in panel_points(self.rule, b, first..last + 1) {
                self.add(&mut sums, out, r - db * qb.t, qb, want_hessian);
            }
        } else {
            // the panels [bounds[k], bounds[k + 1]] that meet [t_lo, t_hi]
            let n = self.bounds.len() - 1;
            let first = self
                .bounds
                .partition_point(|&t| t <= t_lo)
                .saturating_sub(1);
            let last = self.bounds.partition_point(|&t| t < t_hi).clamp(1, n);
            for k in first..last {
                let (t0, h) = (self.bounds[k], self.bounds[k + 1] - self.bounds[k]);
                for &(x, w) in self.rule {
                    let qb = QuadPoint {
                        t: t0 + x * h,
                        weight: b.length0 * w * h,
                    };
                    self.add(&mut sums, out, r - db * qb.t, qb, want_hessian);
                }
            }
        }
        Some(sums)
    }

    /// Add the partner `qb` at `dvec` = p − p_j to `sums` (if inside the cutoff), counting it
    /// into `out`.
    fn add(
        &self,
        sums: &mut PartnerSums,
        out: &mut SegmentPairEnergy,
        dvec: Vector,
        qb: QuadPoint,
        want_hessian: bool,
    ) {
        let rho2 = dvec.length_squared();
        if rho2 >= self.rc2 {
            return;
        }
        let rho = rho2.sqrt();
        if rho < RHO_DEGENERATE {
            return;
        }
        let (u, du, d2u) = self.pot.eval(rho, self.r_sum);
        out.point_pairs += 1;
        out.min_gap = out.min_gap.min(rho - self.r_sum);
        let w = qb.weight;
        sums.energy += w * u;
        let n = [dvec.x / rho, dvec.y / rho, dvec.z / rho];
        let fw = w * du;
        for (k, nk) in n.iter().enumerate() {
            sums.force[k] += fw * nk;
            sums.force_t[k] += fw * qb.t * nk;
        }
        if want_hessian {
            // ∂²u(|r|)/∂r∂r = u'' n nᵀ + (u'/ρ)(I − n nᵀ)
            let alpha = w * (d2u - du / rho);
            let beta = w * du / rho;
            let tw = [1.0, qb.t, qb.t * qb.t];
            for k in 0..3 {
                for l in 0..3 {
                    let v = alpha * n[k] * n[l] + if k == l { beta } else { 0.0 };
                    for (m, hm) in sums.hess.iter_mut().enumerate() {
                        hm[3 * k + l] += tw[m] * v;
                    }
                }
            }
        }
    }
}

/// Add the contributions of one point of `a` (parameter t_a, weight W_a) with all its
/// partners to the pair's energy, gradient and Hessian. Shape-function coefficients of a point
/// pair: c = (1 − t_a, t_a, −(1 − t_b), −t_b) on the nodes (a₀, a₁, b₀, b₁).
pub(super) fn scatter_point(out: &mut SegmentPairEnergy, s: &PartnerSums, qa: QuadPoint) {
    let (ta, wa) = (qa.t, qa.weight);
    out.energy += wa * s.energy;
    for k in 0..3 {
        let (f, ft) = (wa * s.force[k], wa * s.force_t[k]);
        out.grad[k] += (1.0 - ta) * f;
        out.grad[3 + k] += ta * f;
        out.grad[6 + k] -= f - ft;
        out.grad[9 + k] -= ft;
    }
    let Some(h) = out.hessian.as_mut() else {
        return;
    };
    // Σ c_i c_j h over the partners, as combinations of the moments Σ t_bᵏ h
    let [h0, h1, h2] = &s.hess;
    let ca = [1.0 - ta, ta];
    for kl in 0..9 {
        let (m0, m1, m2) = (wa * h0[kl], wa * h1[kl], wa * h2[kl]);
        // a-a, a-b and b-b blocks; b node coefficients −(1 − t_b), −t_b
        let ab = [-(m0 - m1), -m1];
        let bb = [[m0 - 2.0 * m1 + m2, m1 - m2], [m1 - m2, m2]];
        let (k, l) = (kl / 3, kl % 3);
        for i in 0..2 {
            for j in 0..2 {
                let aa = ca[i] * ca[j] * m0;
                h[(3 * i + k) * 12 + 3 * j + l] += aa;
                let x = ca[i] * ab[j];
                h[(3 * i + k) * 12 + 3 * (2 + j) + l] += x;
                h[(3 * (2 + j) + k) * 12 + 3 * i + l] += x;
                h[(3 * (2 + i) + k) * 12 + 3 * (2 + j) + l] += bb[i][j];
            }
        }
    }
}

/// The plain double sum of [`energy_segment_segment`] over every point pair of the two
/// segments, no culling: the reference the culled kernel is tested against. Returns the energy
/// (aJ) and the sum of the magnitudes of its terms (aJ, the scale of its round-off).
pub fn energy_segment_segment_unculled(
    pot: &LinePairPotential,
    rule: &[(f64, f64)],
    a: &QuadSegment,
    b: &QuadSegment,
    r_sum: f64,
) -> (f64, f64) {
    let points_b: Vec<QuadPoint> = quadrature_points(rule, b).collect();
    let (mut e, mut magnitude) = (0.0, 0.0);
    for qa in quadrature_points(rule, a) {
        let p = a.ends[0].lerp(a.ends[1], qa.t);
        for qb in &points_b {
            let rho = (p - b.ends[0].lerp(b.ends[1], qb.t)).length();
            if rho >= RHO_DEGENERATE {
                let term = qa.weight * qb.weight * pot.eval(rho, r_sum).0;
                e += term;
                magnitude += term.abs();
            }
        }
    }
    (e, magnitude)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Finite-difference step, nm.
    const FD_STEP: f64 = 1e-6;
    /// Central differences of smooth functions at this step agree to ~1e-8 relative.
    const FD_TOL: f64 = 1e-6;

    #[test]
    fn switch_is_c2_and_monotone() {
        let (on, off) = (1.0, 2.5);
        for i in 0..=300 {
            let g = 0.9 + 1.7 * i as f64 / 300.0;
            let (s, ds, d2s) = switch(g, on, off);
            let (sp, dsp, _) = switch(g + FD_STEP, on, off);
            let (sm, dsm, _) = switch(g - FD_STEP, on, off);
            assert!((0.0..=1.0).contains(&s) && ds <= 0.0);
            assert!(((sp - sm) / (2.0 * FD_STEP) - ds).abs() < FD_TOL);
            assert!(((dsp - dsm) / (2.0 * FD_STEP) - d2s).abs() < 1e-4);
        }
    }

    #[test]
    fn potential_derivatives_match_finite_differences() {
        let pot = LinePairPotential::calibrate(&VdwParams::default()).unwrap();
        let r_sum = 40.0;
        for i in 0..200 {
            let rho = r_sum + 0.1 + 2.5 * i as f64 / 200.0;
            let (_, du, d2u) = pot.eval(rho, r_sum);
            let (up, dup, _) = pot.eval(rho + FD_STEP, r_sum);
            let (um, dum, _) = pot.eval(rho - FD_STEP, r_sum);
            let scale = 1.0 + du.abs();
            assert!(((up - um) / (2.0 * FD_STEP) - du).abs() < FD_TOL * scale);
            let scale2 = 1.0 + d2u.abs();
            assert!(((dup - dum) / (2.0 * FD_STEP) - d2u).abs() < 1e-4 * scale2);
        }
    }

    #[test]
    fn calibration_puts_the_parallel_minimum_at_gap_eq_with_depth_gamma_l() {
        let params = VdwParams::default();
        let pot = LinePairPotential::calibrate(&params).unwrap();
        let r_sum = 2.0 * params.radius_ref;
        let d0 = r_sum + params.gap_eq;
        let (e0, de0) = pot.parallel_line_energy(d0, r_sum);
        assert!((e0 + params.gamma_l).abs() < 1e-10);
        assert!(de0.abs() < 1e-8);
        // a minimum, not a maximum
        let h = 0.01;
        assert!(pot.parallel_line_energy(d0 + h, r_sum).0 > e0);
        assert!(pot.parallel_line_energy(d0 - h, r_sum).0 > e0);
    }

    /// Random segment pair near contact, with a few panels each.
    pub(in crate::discrete) fn pair(seed: u64) -> (QuadSegment, QuadSegment) {
        let mut s = seed;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let a0 = Vector::new(rnd(), rnd(), rnd());
        let a1 = a0 + Vector::new(10.0 + rnd(), rnd(), rnd());
        let b0 = Vector::new(5.0 * rnd(), 40.5 + rnd(), 3.0 * rnd());
        let b1 = b0 + Vector::new(8.0 * rnd(), 2.0 * rnd(), 8.0 + rnd());
        (
            QuadSegment {
                ends: [a0, a1],
                panels: 3,
                length0: 10.0,
            },
            QuadSegment {
                ends: [b0, b1],
                panels: 4,
                length0: 8.0,
            },
        )
    }

    pub(in crate::discrete) fn flat(a: &QuadSegment, b: &QuadSegment) -> [f64; 12] {
        let mut x = [0.0; 12];
        for (i, v) in [a.ends[0], a.ends[1], b.ends[0], b.ends[1]]
            .iter()
            .enumerate()
        {
            x[3 * i] = v.x;
            x[3 * i + 1] = v.y;
            x[3 * i + 2] = v.z;
        }
        x
    }

    pub(in crate::discrete) fn unflat(
        x: &[f64; 12],
        a: &QuadSegment,
        b: &QuadSegment,
    ) -> (QuadSegment, QuadSegment) {
        let v = |i: usize| Vector::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
        let mut a2 = *a;
        let mut b2 = *b;
        a2.ends = [v(0), v(1)];
        b2.ends = [v(2), v(3)];
        (a2, b2)
    }

    /// Round-off allowance between two orderings of the same sum of ≤ 10⁴ terms of both signs,
    /// relative to the sum of their magnitudes: the worst-case bound n · 2⁻⁵³ for n ≈ 10⁴.
    const REORDER_TOL: f64 = 1e-12;

    #[test]
    fn culling_changes_no_term_of_the_energy() {
        let pot = LinePairPotential::calibrate(&VdwParams::default()).unwrap();
        let rule = gauss_legendre_unit(4);
        let mut interacting = 0;
        for seed in 0..40 {
            let (mut a, mut b) = pair(seed);
            // also far pairs (beyond the cutoff: both sums must be exactly zero)
            let lift = Vector::new(0.0, (seed % 4) as f64 * 1.5, 0.0);
            b.ends = [b.ends[0] + lift, b.ends[1] + lift];
            a.panels = 2 + (seed as usize % 5);
            let culled = energy_segment_segment(&pot, &rule, &a, &b, 40.0, false);
            let (plain, magnitude) = energy_segment_segment_unculled(&pot, &rule, &a, &b, 40.0);
            if magnitude == 0.0 {
                assert_eq!(culled.energy, 0.0, "seed {seed}");
            } else {
                interacting += 1;
                assert!(
                    (culled.energy - plain).abs() <= REORDER_TOL * magnitude,
                    "seed {seed}: {} vs {plain}",
                    culled.energy
                );
            }
        }
        assert!(interacting > 10, "the test must cover interacting pairs");
    }

    #[test]
    fn segment_pair_gradient_and_hessian_match_finite_differences() {
        let pot = LinePairPotential::calibrate(&VdwParams::default()).unwrap();
        let rule = gauss_legendre_unit(4);
        for seed in 0..5 {
            let (a, b) = pair(seed);
            let base = energy_segment_segment(&pot, &rule, &a, &b, 40.0, true);
            assert!(base.point_pairs > 0, "the test pair must interact");
            let x = flat(&a, &b);
            let h = base.hessian.as_ref().unwrap();
            for k in 0..12 {
                let mut xp = x;
                let mut xm = x;
                xp[k] += FD_STEP;
                xm[k] -= FD_STEP;
                let (ap, bp) = unflat(&xp, &a, &b);
                let (am, bm) = unflat(&xm, &a, &b);
                let ep = energy_segment_segment(&pot, &rule, &ap, &bp, 40.0, false);
                let em = energy_segment_segment(&pot, &rule, &am, &bm, 40.0, false);
                let gscale = 1e-3 + base.grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));
                let fd = (ep.energy - em.energy) / (2.0 * FD_STEP);
                assert!((fd - base.grad[k]).abs() < FD_TOL * gscale, "grad {k}");
                let hscale = 1e-3 + h.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for j in 0..12 {
                    let fdh = (ep.grad[j] - em.grad[j]) / (2.0 * FD_STEP);
                    assert!((fdh - h[j * 12 + k]).abs() < 1e-5 * hscale, "hess {j} {k}");
                }
            }
        }
    }
}
