//! Frictionless interaction of the specimen's surface with the rigid indenter through a
//! surface law: Π_c = ∫ φ(g) dA, dA = 2πr ds (seed §4.2, eq. 4.1 for the Lennard-Jones law of
//! the adhesion issue), the gap g taken at the current surface point.
//!
//! **Which area** ([`SurfaceArea`]). Under finite kinematics the area element is either the
//! reference one, dA₀ = 2πR dS, or the current one, da = 2πr ds. A surface law stands for the
//! interaction of the surface's atoms (for a turf, its tube ends) with the indenter; stretching
//! the surface does not create atoms, so their number per *reference* area is fixed and the
//! energy is ∫ φ(g) dA₀ ([`SurfaceArea::Reference`], the default for adhesion). Integrating
//! over the current area instead adds to the surface a stress φ(g) per unit length: −γ in the
//! contact, a surface that lowers its energy by stretching, with nothing but the bulk to resist
//! it at short wavelengths. Under strong adhesion on a compliant solid (μ = 3, R/z₀ = 200,
//! γ/E\* = 0.37 z₀) that pins the contact edge element by element and the pull-off grows
//! without bound as the mesh refines (docs/validation-continuum.md); on the reference area it
//! converges. [`SurfaceArea::Current`] is kept for the repulsive penalty (a pressure on the
//! current surface) and for comparison.
//!
//! The surface z = 0 is a chain of straight segments between surface nodes x₁, x₂. On each,
//! Gauss–Legendre points ξ_q with weights w_q on [0, 1] give
//!
//! Π_seg = 2π Σ_q w_q L r_q φ(g(x_q)),  x_q = (1 − ξ_q)x₁ + ξ_q x₂,  L = |x₂ − x₁|,
//!
//! whose gradient and Hessian in (x₁, x₂) are exact: with φ′ = −p, φ″ = −k (k = dp/dg),
//! ∂φ = −p ∇g Nₐ, ∂²φ = (−k ∇g⊗∇g − p ∇²g) NₐN_b, ∂L = [−e, e], ∂²L = (I − e⊗e)/L blocks,
//! ∂r_q = Nₐ on the r components; the product rule on L·r·φ gives the rest. On the
//! current area (finite kinematics, [`SurfaceArea::Current`]) L and r are the current ones; on
//! the reference area, and always under small kinematics, they are the reference ones and only
//! φ varies. The load on the indenter is
//! P = ∂Π_c/∂δ = −2π Σ w L r p n_z (compressive positive, since ∂g/∂δ = n_z).
//!
//! **Small kinematics** linearise the contact as Hertz and the half-space solver do: the
//! surface point keeps its reference radius (x_q = (R_q, Z_q + u_z)), so only u_z enters the
//! gap (∇g = (0, n_z), ∇²g = diag(0, ∂²g/∂z²)) and the surface and its area are the reference
//! ones. Using the current radius R + u_r instead adds a second-order term ≈ 2u_r/R to the
//! profile that made the small-strain Hertz load ≈ 1 % too high.
//!
//! The law enters only through [`SurfaceLaw::eval`] → (φ, p, k), so the Lennard-Jones law of
//! [`crate::laws`] plugs into the same code (implemented below). For frictionless contact
//! without adhesion, [`SmoothPenalty`] is purely repulsive and acts only on penetration:
//! zero for g ≥ 0, p = k_n g²/(2h_r) for −h_r ≤ g < 0, and p = k_n(−g − h_r/2) for g < −h_r
//! (φ, p and k continuous): a C² energy, so Newton sees no jump in the tangent. The contact
//! edge is g = 0 and the surface penetrates by d = √(2h_r p/k_n) (quadratic branch), a depth
//! error that the defaults (k_n = 100E*/h₀, h_r = 10⁻³h₀) keep below 10⁻³h₀ at Hertz pressures.
//! (A law acting at 0 < g < h_r instead holds the surface h_r *below* the indenter: the
//! solid is then indented by δ + h_r, +1.5h_r/δ in the Hertz load.)
//!
//! **Stick** ([`Stick`], the option "held" of the discrete sphere, `crate::discrete::sphere_stick`):
//! a surface point that is in contact at the end of an increment (g below the law's contact
//! gap) is tied to the point of the indenter it touches, where it first touched. In the
//! indenter's frame y = (r, z + δ) (the frame [`Indenter::gap`] works in), the anchor stores
//! the point's y at first touch, a, and the indenter's normal there, n; with P = I − n⊗n the
//! held points add the energy per area
//!
//! e_t = ½ k_t vᵀP v,  v = y − a,
//!
//! whose gradient in the point is k_t P v, its Hessian k_t P, and ∂e_t/∂δ = k_t (P v)_z (so the
//! load on the indenter carries the held surface's tangential pull), ∂²e_t/∂δ∂y = k_t P e_z,
//! ∂²e_t/∂δ² = k_t P_zz. The anchors are frozen during an increment (e_t is then a conservative
//! energy the Newton loop minimises) and renewed after it ([`Contact::renew_anchors`]): points
//! newly in contact are tied, points that have left contact let go. The point is the current
//! surface point under both kinematics (under small kinematics the radial displacement is what
//! the hold resists, so it cannot be dropped as in the gap); the area factor is the law's.

use super::damping::ContactDamping;
use super::indenter::Indenter;
use super::mesh::Mesh;
use crate::laws::LennardJones;
use serde::{Deserialize, Serialize};

/// A force–separation law: energy per area φ (J/m²), pressure p = −dφ/dg (GPa, positive
/// repulsive) and stiffness k = dp/dg (GPa/nm) at gap g (nm).
pub trait SurfaceLaw: Send + Sync {
    /// (φ, p, k) at gap `g`.
    fn eval(&self, g: f64) -> (f64, f64, f64);
    /// Gap at which the pressure changes sign (the edge of contact), nm.
    fn contact_gap(&self) -> f64;
}

impl SurfaceLaw for LennardJones {
    fn eval(&self, g: f64) -> (f64, f64, f64) {
        LennardJones::eval(self, g)
    }
    fn contact_gap(&self) -> f64 {
        self.z0
    }
}

/// Either Lennard-Jones law of [`crate::laws`] (plain or thermally shifted): the adhesive
/// contact of seed §4.2 and §5.2, its repulsive core doing the work of the penalty.
impl SurfaceLaw for crate::laws::SurfaceLaw {
    fn eval(&self, g: f64) -> (f64, f64, f64) {
        crate::laws::SurfaceLaw::eval(self, g)
    }
    fn contact_gap(&self) -> f64 {
        self.z0()
    }
}

/// A purely repulsive, C² smoothed penalty law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SmoothPenalty {
    /// penalty stiffness k_n, GPa/nm
    pub stiffness: f64,
    /// range h_r below which the law acts, nm
    pub range: f64,
}

impl SurfaceLaw for SmoothPenalty {
    fn eval(&self, g: f64) -> (f64, f64, f64) {
        let (k, h) = (self.stiffness, self.range);
        let d = -g; // penetration
        if d <= 0.0 {
            (0.0, 0.0, 0.0)
        } else if d <= h {
            (k * d * d * d / (6.0 * h), k * d * d / (2.0 * h), -k * d / h)
        } else {
            let e = d - h;
            (
                k * h * h / 6.0 + 0.5 * k * h * e + 0.5 * k * e * e,
                k * (e + 0.5 * h),
                -k,
            )
        }
    }
    fn contact_gap(&self) -> f64 {
        0.0
    }
}

/// The area element the law's energy per area is integrated over under finite kinematics (see
/// the module doc); small kinematics always use the reference surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceArea {
    /// dA₀ = 2πR dS: the surface's atoms conserved (adhesion's default)
    #[default]
    Reference,
    /// da = 2πr ds: the current surface (the repulsive penalty)
    Current,
}

/// The point at ξ ∈ [0, 1] along a surface segment whose current ends are `x` and reference
/// ends `x_ref`: current under finite kinematics, (R, Z + u_z) under small.
fn surface_point(x: [[f64; 2]; 2], x_ref: [[f64; 2]; 2], xi: f64, small: bool) -> [f64; 2] {
    let lerp = |a: f64, b: f64| (1.0 - xi) * a + xi * b;
    let r = if small {
        lerp(x_ref[0][0], x_ref[1][0])
    } else {
        lerp(x[0][0], x[1][0])
    };
    [r, lerp(x[0][1], x[1][1])]
}

/// The surface, indenter and law of one interaction.
pub struct Contact<'a> {
    /// surface segments (node pairs, increasing r)
    pub segments: Vec<[usize; 2]>,
    /// the indenter
    pub indenter: Indenter,
    /// the law
    pub law: &'a dyn SurfaceLaw,
    /// quadrature on [0, 1]
    pub quadrature: Vec<(f64, f64)>,
    /// viscous contact damping over the current step, if any
    pub damping: Option<Damping<'a>>,
    /// the tangential hold of the points in contact, if any
    pub stick: Option<Stick<'a>>,
    /// the area element under finite kinematics
    pub area: SurfaceArea,
}

/// A surface point held by the indenter: where it first touched, in the indenter's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Anchor {
    /// y = (r, z + δ) at first touch, nm
    pub point: [f64; 2],
    /// the indenter's outward normal there
    pub normal: [f64; 2],
}

/// The tangential hold over one increment: the anchors of the quadrature points (segment-major,
/// as [`Contact::profile`]; `None`: free) and the stiffness per area.
#[derive(Debug, Clone, Copy)]
pub struct Stick<'a> {
    /// k_t, GPa/nm (energy per area per nm²)
    pub stiffness: f64,
    /// one entry per surface quadrature point
    pub anchors: &'a [Option<Anchor>],
}

impl Stick<'_> {
    /// (e_t, ∂e_t/∂y, ∂²e_t/∂y², ∂e_t/∂δ, ∂²e_t/∂δ∂y, ∂²e_t/∂δ²) of the anchor `a` at the
    /// point `y` (indenter frame): see the module doc.
    fn eval(&self, a: &Anchor, y: [f64; 2]) -> PointTerms {
        let k = self.stiffness;
        let n = a.normal;
        let v = [y[0] - a.point[0], y[1] - a.point[1]];
        let vn = n[0] * v[0] + n[1] * v[1];
        let pv = [v[0] - vn * n[0], v[1] - vn * n[1]];
        let proj = |i: usize, j: usize| (i == j) as u8 as f64 - n[i] * n[j];
        PointTerms {
            phi: 0.5 * k * (v[0] * pv[0] + v[1] * pv[1]),
            grad: [k * pv[0], k * pv[1]],
            hess: [
                [k * proj(0, 0), k * proj(0, 1)],
                [k * proj(1, 0), k * proj(1, 1)],
            ],
            d: k * pv[1],
            d_grad: [k * proj(1, 0), k * proj(1, 1)],
            dd: k * proj(1, 1),
        }
    }
}

/// The energy per area at one surface point and its derivatives in the point's position and
/// in the depth δ.
#[derive(Debug, Clone, Copy, Default)]
struct PointTerms {
    phi: f64,
    grad: [f64; 2],
    hess: [[f64; 2]; 2],
    d: f64,
    d_grad: [f64; 2],
    dd: f64,
}

impl PointTerms {
    /// The law's terms at gap `gp` with (φ, p, k) = `law` (see the module doc).
    fn of_law(gp: &super::indenter::Gap, (phi, p, k): (f64, f64, f64)) -> Self {
        let n = gp.normal;
        let h = gp.hessian;
        let mut t = PointTerms {
            phi,
            d: -p * n[1],
            dd: -k * n[1] * n[1] - p * h[1][1],
            ..Default::default()
        };
        for i in 0..2 {
            t.grad[i] = -p * n[i];
            t.d_grad[i] = -k * n[1] * n[i] - p * h[1][i];
            for j in 0..2 {
                t.hess[i][j] = -k * n[i] * n[j] - p * h[i][j];
            }
        }
        t
    }

    fn add(&mut self, o: &PointTerms) {
        self.phi += o.phi;
        self.d += o.d;
        self.dd += o.dd;
        for i in 0..2 {
            self.grad[i] += o.grad[i];
            self.d_grad[i] += o.d_grad[i];
            for j in 0..2 {
                self.hess[i][j] += o.hess[i][j];
            }
        }
    }
}

/// Contact damping over one step (seed eq. 4.4) as an incremental pseudo-potential: at each
/// quadrature point ½ c(gₙ)(g − gₙ)²/Δt per unit area, gₙ the gap at the start of the step,
/// so its gradient is the damping pressure c(gₙ)·ġ with ġ = (g − gₙ)/Δt (backward Euler).
/// Freezing c at gₙ keeps the force the exact gradient of an energy the code evaluates.
#[derive(Debug, Clone, Copy)]
pub struct Damping<'a> {
    /// the coefficient c(g)
    pub law: ContactDamping,
    /// gap gₙ at every quadrature point (segment-major, as [`Contact::profile`]), nm
    pub previous: &'a [f64],
    /// step Δt, s (> 0)
    pub dt: f64,
}

/// Energy, force, stiffness and indenter load of one segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentOutput {
    /// Π_seg, aJ
    pub energy: f64,
    /// ∂Π/∂(x₁r, x₁z, x₂r, x₂z), nN
    pub force: [f64; 4],
    /// Hessian, nN/nm
    pub stiffness: [[f64; 4]; 4],
    /// ∂Π/∂δ: this segment's share of the load P, nN
    pub load: f64,
    /// ∂²Π/∂δ∂x: the load's gradient in the nodal positions, nN/nm
    pub load_gradient: [f64; 4],
    /// ∂²Π/∂δ², nN/nm
    pub load_stiffness: f64,
    /// the damping pseudo-potential's share of `energy`, aJ
    pub damping: f64,
}

/// A point of the contact profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfilePoint {
    /// current radius, nm
    pub r: f64,
    /// gap, nm
    pub gap: f64,
    /// pressure, GPa
    pub pressure: f64,
}

impl Contact<'_> {
    /// Segments along the surface of `mesh`.
    pub fn segments_of(mesh: &Mesh) -> Vec<[usize; 2]> {
        mesh.surface.windows(2).map(|w| [w[0], w[1]]).collect()
    }

    /// Evaluate segment number `index` (for the damping's start-of-step gaps) with current
    /// ends `x` and reference ends `x_ref`.
    pub fn segment(
        &self,
        index: usize,
        x: [[f64; 2]; 2],
        x_ref: [[f64; 2]; 2],
        depth: f64,
        small: bool,
    ) -> SegmentOutput {
        let two_pi = 2.0 * std::f64::consts::PI;
        // the geometry of the area element: the reference surface, or the current one
        let on_reference = small || self.area == SurfaceArea::Reference;
        let geo = if on_reference { x_ref } else { x };
        let d = [geo[1][0] - geo[0][0], geo[1][1] - geo[0][1]];
        let len = d[0].hypot(d[1]);
        let e = [d[0] / len, d[1] / len];
        let mut dl = [0.0; 4];
        let mut d2l = [[0.0; 4]; 4];
        if !on_reference {
            dl = [-e[0], -e[1], e[0], e[1]];
            for i in 0..2 {
                for j in 0..2 {
                    let a = ((i == j) as u8 as f64 - e[i] * e[j]) / len;
                    d2l[i][j] = a;
                    d2l[i + 2][j + 2] = a;
                    d2l[i][j + 2] = -a;
                    d2l[i + 2][j] = -a;
                }
            }
        }
        let mut out = SegmentOutput {
            energy: 0.0,
            force: [0.0; 4],
            stiffness: [[0.0; 4]; 4],
            load: 0.0,
            load_gradient: [0.0; 4],
            load_stiffness: 0.0,
            damping: 0.0,
        };
        let nq = self.quadrature.len();
        for (q, &(xi, w)) in self.quadrature.iter().enumerate() {
            let nsh = [1.0 - xi, xi];
            let xq = surface_point(x, x_ref, xi, small);
            let r = nsh[0] * geo[0][0] + nsh[1] * geo[1][0];
            let mut gp = self.indenter.gap(xq, depth);
            if small {
                // the gap depends on u_z only (see the module doc)
                gp.normal[0] = 0.0;
                gp.hessian = [[0.0, 0.0], [0.0, gp.hessian[1][1]]];
            }
            let (mut phi, mut p, mut k) = self.law.eval(gp.gap);
            let c = two_pi * w;
            if let Some(d) = &self.damping {
                let gn = d.previous[index * nq + q];
                let cd = d.law.coefficient(gn) / d.dt;
                let dg = gp.gap - gn;
                let e = 0.5 * cd * dg * dg;
                phi += e;
                p -= cd * dg;
                k -= cd;
                out.damping += c * len * r * e;
            }
            let held = self
                .stick
                .as_ref()
                .and_then(|s| s.anchors[index * nq + q].as_ref().map(|a| (s, a)));
            if phi == 0.0 && p == 0.0 && k == 0.0 && held.is_none() {
                continue;
            }
            let mut pt = PointTerms::of_law(&gp, (phi, p, k));
            let mut hold_d = None;
            if let Some((s, a)) = held {
                let y = surface_point(x, x_ref, xi, false);
                let t = s.eval(a, [y[0], y[1] + depth]);
                hold_d = Some(t.d);
                pt.add(&t);
            }
            let mut dphi = [0.0; 4];
            let mut d2phi = [[0.0; 4]; 4];
            let mut dr = [0.0; 4];
            for a in 0..2 {
                if !on_reference {
                    dr[2 * a] = nsh[a];
                }
                for i in 0..2 {
                    dphi[2 * a + i] = pt.grad[i] * nsh[a];
                    for b in 0..2 {
                        for j in 0..2 {
                            d2phi[2 * a + i][2 * b + j] = pt.hess[i][j] * nsh[a] * nsh[b];
                        }
                    }
                }
            }
            let phi = pt.phi;
            out.energy += c * len * r * phi;
            // P = ∂Π/∂δ: the law's share −p n_z, the hold's ∂e_t/∂δ
            out.load -= c * len * r * p * gp.normal[1];
            if let Some(d) = hold_d {
                out.load += c * len * r * d;
            }
            out.load_stiffness += c * len * r * pt.dd;
            for s in 0..4 {
                let (a, i) = (s / 2, s % 2);
                let dphi_d = pt.d_grad[i] * nsh[a];
                out.load_gradient[s] += c * ((r * dl[s] + len * dr[s]) * pt.d + len * r * dphi_d);
                out.force[s] += c * (r * phi * dl[s] + len * phi * dr[s] + len * r * dphi[s]);
                for t in 0..4 {
                    out.stiffness[s][t] += c
                        * (r * phi * d2l[s][t]
                            + phi * (dl[s] * dr[t] + dr[s] * dl[t])
                            + r * (dl[s] * dphi[t] + dphi[s] * dl[t])
                            + len * (dr[s] * dphi[t] + dphi[s] * dr[t])
                            + len * r * d2phi[s][t]);
                }
            }
        }
        out
    }

    /// Gap and pressure at every quadrature point of the surface, by increasing r: current
    /// positions under finite kinematics, reference radius and current height under small.
    pub fn profile(
        &self,
        current: &[[f64; 2]],
        reference: &[[f64; 2]],
        depth: f64,
        small: bool,
    ) -> Vec<ProfilePoint> {
        let mut pts = Vec::with_capacity(self.segments.len() * self.quadrature.len());
        for s in &self.segments {
            let x = [current[s[0]], current[s[1]]];
            let x_ref = [reference[s[0]], reference[s[1]]];
            for &(xi, _) in &self.quadrature {
                let x = surface_point(x, x_ref, xi, small);
                let g = self.indenter.gap(x, depth).gap;
                pts.push(ProfilePoint {
                    r: x[0],
                    gap: g,
                    pressure: self.law.eval(g).1,
                });
            }
        }
        pts
    }

    /// The anchors after a converged increment at `depth` ([`Stick`]): every quadrature point
    /// in contact (gap below the law's contact gap) keeps its anchor in `previous` or, newly in
    /// contact, is tied where it is; every other point is free.
    pub fn renew_anchors(
        &self,
        current: &[[f64; 2]],
        reference: &[[f64; 2]],
        depth: f64,
        small: bool,
        previous: &[Option<Anchor>],
    ) -> Vec<Option<Anchor>> {
        let mut anchors = Vec::with_capacity(previous.len());
        for s in &self.segments {
            let x = [current[s[0]], current[s[1]]];
            let x_ref = [reference[s[0]], reference[s[1]]];
            for &(xi, _) in &self.quadrature {
                let k = anchors.len();
                let g = self
                    .indenter
                    .gap(surface_point(x, x_ref, xi, small), depth)
                    .gap;
                anchors.push((g < self.law.contact_gap()).then(|| {
                    previous.get(k).copied().flatten().unwrap_or_else(|| {
                        let y = surface_point(x, x_ref, xi, false);
                        Anchor {
                            point: [y[0], y[1] + depth],
                            normal: self.indenter.gap(y, depth).normal,
                        }
                    })
                }));
            }
        }
        anchors
    }

    /// Contact radius (nm): the outermost radius where the gap reaches the law's contact gap,
    /// interpolated linearly between the last point inside and the first outside; 0 without
    /// contact.
    pub fn contact_radius(&self, profile: &[ProfilePoint]) -> f64 {
        self.radius_below(profile, self.law.contact_gap())
    }

    /// The outermost radius where the gap reaches `edge` (nm), interpolated as in
    /// [`Self::contact_radius`]; 0 if the gap is nowhere below it.
    pub fn radius_below(&self, profile: &[ProfilePoint], edge: f64) -> f64 {
        let Some(last) = profile.iter().rposition(|p| p.gap < edge) else {
            return 0.0;
        };
        match profile.get(last + 1) {
            None => profile[last].r,
            Some(next) => {
                let a = &profile[last];
                let t = (edge - a.gap) / (next.gap - a.gap);
                a.r + t * (next.r - a.r)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::LjKind;
    use crate::numerics::quadrature::gauss_legendre_unit;

    const FD_TOL: f64 = 1e-6; // central differences with step 1e-6 nm

    fn check(law: &dyn SurfaceLaw, ind: Indenter, x: [[f64; 2]; 2], depth: f64, small: bool) {
        for area in [SurfaceArea::Reference, SurfaceArea::Current] {
            check_area(law, ind, x, depth, (small, area));
        }
    }

    /// `kin`: (small kinematics, area element).
    fn check_area(
        law: &dyn SurfaceLaw,
        ind: Indenter,
        x: [[f64; 2]; 2],
        depth: f64,
        kin: (bool, SurfaceArea),
    ) {
        check_with(law, ind, x, depth, kin, None, None);
        // damping with start-of-step gaps a little above the current ones (closing gap)
        let previous: Vec<f64> = (0..3)
            .map(|q| ind.gap(x[0], depth).gap + 0.05 * (q + 1) as f64)
            .collect();
        let d = Damping {
            law: ContactDamping {
                c0: 0.7,
                gap: 1e3,
                eta: 0.5,
            },
            previous: &previous,
            dt: 0.3,
        };
        check_with(law, ind, x, depth, kin, Some(d), None);
        // two of the three points held, anchored off their current places, one free
        let anchor = |dy: [f64; 2], angle: f64| {
            Some(Anchor {
                point: [x[0][0] + dy[0], x[0][1] + depth + dy[1]],
                normal: [angle.sin(), -angle.cos()],
            })
        };
        let anchors = [anchor([0.3, -0.2], 0.2), None, anchor([-0.1, 0.05], -0.4)];
        let stick = Stick {
            stiffness: 2.5,
            anchors: &anchors,
        };
        check_with(law, ind, x, depth, kin, None, Some(stick));
        check_with(law, ind, x, depth, kin, Some(d), Some(stick));
    }

    fn check_with(
        law: &dyn SurfaceLaw,
        ind: Indenter,
        x: [[f64; 2]; 2],
        depth: f64,
        (small, area): (bool, SurfaceArea),
        damping: Option<Damping>,
        stick: Option<Stick>,
    ) {
        let c = Contact {
            segments: vec![],
            indenter: ind,
            law,
            quadrature: gauss_legendre_unit(3),
            damping,
            stick,
            area,
        };
        let x_ref = [[x[0][0] - 0.1, 0.0], [x[1][0] + 0.2, 0.0]];
        let o = c.segment(0, x, x_ref, depth, small);
        assert!(o.energy != 0.0);
        assert_eq!(damping.is_some(), o.damping > 0.0);
        let fmax = o.force.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let kmax = o
            .stiffness
            .iter()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        let h = 1e-6;
        for t in 0..4 {
            let (mut xp, mut xm) = (x, x);
            xp[t / 2][t % 2] += h;
            xm[t / 2][t % 2] -= h;
            let (op, om) = (
                c.segment(0, xp, x_ref, depth, small),
                c.segment(0, xm, x_ref, depth, small),
            );
            let f_fd = (op.energy - om.energy) / (2.0 * h);
            assert!((f_fd - o.force[t]).abs() < FD_TOL * fmax, "force {t}");
            for s in 0..4 {
                let k_fd = (op.force[s] - om.force[s]) / (2.0 * h);
                assert!(
                    (k_fd - o.stiffness[s][t]).abs() < FD_TOL * kmax,
                    "K[{s}][{t}]"
                );
            }
            let lg_fd = (op.load - om.load) / (2.0 * h);
            assert!(
                (lg_fd - o.load_gradient[t]).abs() < FD_TOL * kmax,
                "∂P/∂x {t}: {lg_fd} vs {}",
                o.load_gradient[t]
            );
        }
        let (op, om) = (
            c.segment(0, x, x_ref, depth + h, small),
            c.segment(0, x, x_ref, depth - h, small),
        );
        let l_fd = (op.energy - om.energy) / (2.0 * h);
        assert!((l_fd - o.load).abs() < FD_TOL * o.load.abs().max(fmax));
        let ls_fd = (op.load - om.load) / (2.0 * h);
        assert!((ls_fd - o.load_stiffness).abs() < FD_TOL * kmax, "∂P/∂δ");
        for t in 0..4 {
            let g_fd = (op.force[t] - om.force[t]) / (2.0 * h);
            assert!(
                (g_fd - o.load_gradient[t]).abs() < FD_TOL * kmax,
                "∂f/∂δ {t}"
            );
        }
    }

    #[test]
    fn penalty_law_is_a_c2_repulsion() {
        let law = SmoothPenalty {
            stiffness: 3.0,
            range: 0.2,
        };
        for g in [-0.5, -0.25, -0.199, -0.05, -0.01, 0.01, 0.3] {
            let h = 1e-6;
            let (phi, p, k) = law.eval(g);
            assert!(p >= 0.0 && phi >= 0.0);
            assert_eq!(p == 0.0, g >= 0.0, "acts on penetration only");
            assert!(((law.eval(g - h).0 - law.eval(g + h).0) / (2.0 * h) - p).abs() < 1e-8);
            let k_fd = (law.eval(g + h).1 - law.eval(g - h).1) / (2.0 * h);
            assert!((k_fd - k).abs() < 1e-6, "{g}: {k_fd} vs {k}");
        }
        // φ, p and k are continuous where the branches meet (g = 0 and g = −h_r)
        for g in [0.0, -0.2] {
            let (a, b) = (law.eval(g - 1e-12), law.eval(g + 1e-12));
            assert!(
                (a.0 - b.0).abs() < 1e-10 && (a.1 - b.1).abs() < 1e-10 && (a.2 - b.2).abs() < 1e-10
            );
        }
    }

    #[test]
    fn segment_force_stiffness_and_load_match_finite_differences() {
        let pen = SmoothPenalty {
            stiffness: 3.0,
            range: 0.5,
        };
        let lj = LennardJones::new(LjKind::Lj93, 0.2, 0.5);
        let sphere = Indenter::Sphere { radius: 50.0 };
        let x = [[3.0, -0.9], [4.5, -1.1]];
        for small in [false, true] {
            check(&pen, sphere, x, 1.3, small);
            check(&lj, sphere, x, 0.5, small);
            let shifted: crate::laws::SurfaceLaw =
                crate::laws::ThermallyShifted::new(lj, 0.4).unwrap().into();
            check(&shifted, sphere, [[3.0, -0.3], [4.5, -0.4]], 0.2, small);
            check(
                &lj,
                Indenter::berkovich_tangent(50.0),
                [[20.0, -4.0], [22.0, -4.2]],
                6.0,
                small,
            );
        }
    }

    #[test]
    fn stretching_the_surface_at_a_fixed_gap_changes_only_the_current_area_energy() {
        // a segment at the bottom of a wide sphere (gap z₀ to within r²/2R = 2e-5 nm), its
        // outer node pulled out along the surface: the atoms of the reference segment stay the
        // same, so the reference-area energy stays; the current-area one grows with the area
        let lj = LennardJones::new(LjKind::Lj93, 0.2, 0.5);
        let ind = Indenter::Sphere { radius: 1e6 };
        let x_ref = [[3.0, 0.0], [4.0, 0.0]];
        let depth = -0.5;
        let energy = |x: [[f64; 2]; 2], area| {
            let c = Contact {
                segments: vec![],
                indenter: ind,
                law: &lj,
                quadrature: gauss_legendre_unit(3),
                damping: None,
                stick: None,
                area,
            };
            c.segment(0, x, x_ref, depth, false).energy
        };
        let stretched = [[3.0, 0.0], [5.0, 0.0]];
        let (e0, e1) = (
            energy(x_ref, SurfaceArea::Reference),
            energy(stretched, SurfaceArea::Reference),
        );
        assert!(e0 < 0.0 && ((e1 - e0) / e0).abs() < 1e-6, "{e0} {e1}");
        let (c0, c1) = (
            energy(x_ref, SurfaceArea::Current),
            energy(stretched, SurfaceArea::Current),
        );
        // areas π(r₂² − r₁²): 7π against 16π
        assert!((c0 - e0).abs() < 1e-12 * e0.abs());
        assert!((c1 / c0 - 16.0 / 7.0).abs() < 1e-5, "{}", c1 / c0);
    }

    #[test]
    fn contact_radius_interpolates_the_gap_at_the_edge() {
        let law = SmoothPenalty {
            stiffness: 1.0,
            range: 0.1,
        };
        let c = Contact {
            segments: vec![],
            indenter: Indenter::Sphere { radius: 10.0 },
            law: &law,
            quadrature: gauss_legendre_unit(2),
            damping: None,
            stick: None,
            area: SurfaceArea::Current,
        };
        let pts = |g: [f64; 3]| -> Vec<ProfilePoint> {
            (0..3)
                .map(|i| ProfilePoint {
                    r: i as f64,
                    gap: g[i],
                    pressure: 0.0,
                })
                .collect()
        };
        assert_eq!(c.contact_radius(&pts([0.1, 0.2, 0.3])), 0.0);
        assert!((c.contact_radius(&pts([-0.1, -0.1, 0.1])) - 1.5).abs() < 1e-12);
    }
}
