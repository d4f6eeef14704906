//! Lennard-Jones adhesion between the rigid sphere indenter and the tubes: the
//! surface law of the continuum indentation ([`SurfaceLaw`], plain or thermally
//! shifted, seed eqs. 4.1, 5.10 and §5.2) acting between the sphere and each tube, integrated
//! over the tube as a line of material.
//!
//! **Across the tube (Derjaguin).** A tube of outer radius r whose axis point is at distance ρ
//! from the centre of a sphere of radius R has the surface gap g = ρ − R − r. Across the tube,
//! at an offset x from the line of closest approach, the gap is g + x²/(2r*) with
//! 1/r* = 1/r + 1/R (a cylinder against a sphere, both curvatures), so the energy per unit
//! length of tube is
//!
//! λ(g) = ∫ φ_c(g + x²/(2r*)) dx = √(2r*) ∫ φ_c(g + τ²) dτ,
//!
//! with φ the law's energy per unit area and φ_c = φ·S its smooth truncation: S the quintic
//! smoothstep (C², [`super::vdw::switch`]) from 1 at h_s to 0 at the cutoff h_c =
//! z₀ + `cutoff_ranges`·(h_int − z₀), h_int the law's tangent intercept (the range of its
//! attraction; shifted laws reach b times further, so the cutoff follows the stretch) and
//! h_s = z₀ + `switch_fraction`·(h_c − z₀). The τ integral is a fixed composite Gauss–Legendre
//! rule in ξ with τ = τ_max ξ² (points gathered where the integrand is sharp, near τ = 0), so
//! λ' = −√(2r*) Σ W p_c and λ'' = −√(2r*) Σ W k_c are the exact derivatives of the λ computed,
//! with p_c = pS − φS′ and k_c = kS + 2pS′ − φS″. Pulled straight off, a tube side-on to a large
//! sphere adheres with the line energy Γ = −min λ (nN), and a straight tube meeting the sphere
//! end-on has the tip pull-off force max(−λ) = Γ (the docs' "Adhesive sphere").
//!
//! **Along the tube (material quadrature).** E = Σ_segments ∫₀^{ℓ₀} λ(g(s)) ds, s the
//! reference arclength, the axis point x(t) = (1 − t)x_a + t x_b, each segment split into
//! ⌈ℓ₀/(f z₀)⌉ equal panels (f = `panel_fraction`) of `order` Gauss points. The points are
//! material and their spacing is set by the law's core width z₀, not by the segment length, so
//! a tip's pull-off does not depend on how the tube is cut (node-lumping, ℓ/2·λ at the end node,
//! would make it proportional to the segment length). Only the panels that meet the cutoff
//! sphere |x − c| < R + r + h_c are visited — the interval of t solved from a quadratic —
//! which changes no term of the sum (the others are exactly zero). The gradient and Hessian are
//! those of the sum: ∂λ(g(x))/∂x = λ'u and ∂²/∂x∂x = λ''uuᵀ + λ'(I − uuᵀ)/ρ, u = (x − c)/ρ,
//! chained to the two nodes by the linear shape functions. The force of the tubes on the
//! sphere, pushing it up, is F = −∂E/∂H = Σ W λ' u_z (H the height of its lowest point).

use nalgebra::{Matrix3, Vector3};

use super::energy::EnergyTerm;
use super::vdw::switch;
use super::vdw_term::TubeLayout;
use crate::laws::SurfaceLaw;
use crate::numerics::quadrature::gauss_legendre_unit;

/// The truncation and quadratures of the sphere's line law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereLjParams {
    /// the cutoff h_c in ranges of the law beyond z₀: h_c = z₀ + this·(h_int − z₀)
    pub cutoff_ranges: f64,
    /// where the switch-off starts, as a fraction of h_c − z₀ beyond z₀
    pub switch_fraction: f64,
    /// panels of the cross-section rule in ξ
    pub section_panels: usize,
    /// Gauss points per panel (both rules)
    pub order: usize,
    /// panel length along the tube, in z₀
    pub panel_fraction: f64,
}

impl Default for SphereLjParams {
    /// The defaults of the convergence checks in docs/discrete-contacts.md ("Adhesive
    /// sphere"): the cutoff lowers Γ = −min λ by 0.7 % (9-3, plain or shifted) and 0.07 %
    /// (10-4); the cross-section rule is converged to 1e-4.
    fn default() -> Self {
        SphereLjParams {
            cutoff_ranges: 20.0,
            switch_fraction: 0.5,
            section_panels: 16,
            order: 4,
            panel_fraction: 0.5,
        }
    }
}

/// Energy per unit length λ(g) of one tube near the sphere, nN (= aJ/nm).
#[derive(Debug, Clone, PartialEq)]
pub struct LineLaw {
    law: SurfaceLaw,
    /// √(2r*), nm^½
    scale: f64,
    /// the switch starts at h_s, nm
    on: f64,
    /// and ends at the cutoff h_c, nm
    off: f64,
    /// the cross-section rule: (τ², weight) with both halves of the even integrand
    section: Vec<(f64, f64)>,
}

impl LineLaw {
    /// The line law of a tube of outer radius `tube` (nm) against a sphere of radius `sphere`
    /// (nm) under `law`.
    pub fn new(law: SurfaceLaw, tube: f64, sphere: f64, p: &SphereLjParams) -> Self {
        let z0 = law.z0();
        let off = z0 + p.cutoff_ranges * (law.tangent_intercept() - z0);
        let on = z0 + p.switch_fraction * (off - z0);
        // τ² up to h_c + z₀ covers every gap g ≥ −z₀ (deeper, the guarded repulsion is cut)
        let tau_max = (off + z0).sqrt();
        let rule = gauss_legendre_unit(p.order);
        let panels = p.section_panels;
        let section = (0..panels)
            .flat_map(|j| {
                rule.iter().map(move |&(t, w)| {
                    let xi = (j as f64 + t) / panels as f64;
                    let tau = tau_max * xi * xi;
                    // dτ = 2 τ_max ξ dξ; the factor 2 takes the half x < 0
                    (tau * tau, 2.0 * 2.0 * tau_max * xi * w / panels as f64)
                })
            })
            .collect();
        LineLaw {
            law,
            scale: (2.0 * tube * sphere / (tube + sphere)).sqrt(),
            on,
            off,
            section,
        }
    }

    /// The cutoff h_c: λ = 0 for g ≥ h_c, nm.
    pub fn cutoff(&self) -> f64 {
        self.off
    }

    /// The truncated surface law (φ_c, p_c, k_c) at gap `h`.
    fn surface(&self, h: f64) -> (f64, f64, f64) {
        let (s, ds, dds) = switch(h, self.on, self.off);
        if s == 0.0 && ds == 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let (phi, p, k) = self.law.eval(h);
        (phi * s, p * s - phi * ds, k * s + 2.0 * p * ds - phi * dds)
    }

    /// λ(g) (nN), λ'(g) (nN/nm) and λ''(g) (nN/nm²).
    pub fn eval(&self, g: f64) -> (f64, f64, f64) {
        if g >= self.off {
            return (0.0, 0.0, 0.0);
        }
        let (mut e, mut de, mut dde) = (0.0, 0.0, 0.0);
        for &(tau2, w) in &self.section {
            let h = g + tau2;
            if h >= self.off {
                break;
            }
            let (phi, p, k) = self.surface(h);
            e += w * phi;
            de -= w * p;
            dde -= w * k;
        }
        (self.scale * e, self.scale * de, self.scale * dde)
    }
}

/// One segment of a tube with its material quadrature.
#[derive(Debug, Clone, Copy)]
struct Segment {
    /// its two nodes
    nodes: [usize; 2],
    /// the tube's line law (index into [`SphereAdhesion::laws`])
    law: usize,
    /// outer radius of the tube, nm
    radius: f64,
    /// reference length, nm
    length0: f64,
    /// equal panels along it
    panels: usize,
}

/// One quadrature point's contribution: weight × (λ, λ'u, Hessian), at parameter t.
struct PointTerm {
    t: f64,
    energy: f64,
    grad: Vector3<f64>,
    hess: Matrix3<f64>,
}

/// The adhesive sphere: the line law between the sphere and every tube segment.
#[derive(Debug, Clone)]
pub struct SphereAdhesion {
    /// radius R, nm
    radius: f64,
    /// centre (x, y, H + R), nm
    centre: Vector3<f64>,
    /// one line law per tube
    laws: Vec<LineLaw>,
    segments: Vec<Segment>,
    /// the Gauss rule along a panel, on [0, 1]
    rule: Vec<(f64, f64)>,
}

impl SphereAdhesion {
    /// The sphere of radius `radius` (nm) with its lowest point at (`x`, `y`, `height`) acting
    /// through `law` on the tubes `layout`, whose reference (material) lengths are those of the
    /// configuration `x0` (nm).
    pub fn new(
        law: SurfaceLaw,
        radius: f64,
        lowest: [f64; 3],
        layout: &[TubeLayout],
        x0: &[f64],
        p: &SphereLjParams,
    ) -> Self {
        let panel = p.panel_fraction * law.z0();
        let mut segments = Vec::new();
        let laws = layout
            .iter()
            .enumerate()
            .map(|(k, tube)| {
                for n in tube.first_node..tube.first_node + tube.nodes - 1 {
                    let length0 = (point(x0, n + 1) - point(x0, n)).norm();
                    segments.push(Segment {
                        nodes: [n, n + 1],
                        law: k,
                        radius: tube.radius,
                        length0,
                        panels: ((length0 / panel).ceil() as usize).max(1),
                    });
                }
                LineLaw::new(law, tube.radius, radius, p)
            })
            .collect();
        SphereAdhesion {
            radius,
            centre: Vector3::new(lowest[0], lowest[1], lowest[2] + radius),
            laws,
            segments,
            rule: gauss_legendre_unit(p.order),
        }
    }

    /// Move the sphere's lowest point to height `h` (nm).
    pub fn set_height(&mut self, h: f64) {
        self.centre.z = h + self.radius;
    }

    /// The surface law's equilibrium separation z₀, nm.
    pub fn rest_gap(&self) -> f64 {
        self.laws.first().map_or(0.0, |l| l.law.z0())
    }

    /// The line law of tube `k`.
    pub fn line_law(&self, k: usize) -> &LineLaw {
        &self.laws[k]
    }

    /// Calls `f` for every quadrature point of `seg` within the cutoff.
    fn visit(&self, x: &[f64], seg: &Segment, mut f: impl FnMut(PointTerm)) {
        let law = &self.laws[seg.law];
        let a = point(x, seg.nodes[0]) - self.centre;
        let d = point(x, seg.nodes[1]) - point(x, seg.nodes[0]);
        let Some((t1, t2)) = within(a, d, self.radius + seg.radius + law.cutoff()) else {
            return;
        };
        let n = seg.panels as f64;
        let first = (t1 * n).floor().max(0.0) as usize;
        let last = ((t2 * n).ceil() as usize).min(seg.panels);
        let panel = seg.length0 / n;
        for p in first..last {
            for &(s, w) in &self.rule {
                let t = (p as f64 + s) / n;
                let v = a + t * d;
                let rho = v.norm();
                let (e, de, dde) = law.eval(rho - self.radius - seg.radius);
                if e == 0.0 && de == 0.0 && dde == 0.0 {
                    continue;
                }
                let u = v / rho;
                let uu = u * u.transpose();
                let weight = w * panel;
                f(PointTerm {
                    t,
                    energy: weight * e,
                    grad: weight * de * u,
                    hess: weight * (dde * uu + de * (Matrix3::identity() - uu) / rho),
                });
            }
        }
    }

    /// The force of the tubes on the sphere, −∂E/∂H (nN, positive pushing it up).
    pub fn force(&self, x: &[f64]) -> f64 {
        let mut f = 0.0;
        for seg in &self.segments {
            // ∂g/∂H = −u_z, and the point's gradient is W λ' u
            self.visit(x, seg, |q| f += q.grad.z);
        }
        f
    }
}

/// The node's position, nm.
fn point(x: &[f64], n: usize) -> Vector3<f64> {
    Vector3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2])
}

/// The interval of t ∈ [0, 1] where |a + t d| < `reach` (`None` if empty).
fn within(a: Vector3<f64>, d: Vector3<f64>, reach: f64) -> Option<(f64, f64)> {
    let (dd, ad, aa) = (d.dot(&d), a.dot(&d), a.dot(&a) - reach * reach);
    if dd == 0.0 {
        return (aa < 0.0).then_some((0.0, 1.0));
    }
    let disc = ad * ad - dd * aa;
    if disc <= 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let (t1, t2) = ((-ad - root) / dd, (-ad + root) / dd);
    (t2 > 0.0 && t1 < 1.0).then_some((t1.max(0.0), t2.min(1.0)))
}

impl EnergyTerm for SphereAdhesion {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut e = 0.0;
        for seg in &self.segments {
            let [i, j] = seg.nodes;
            self.visit(x, seg, |q| {
                e += q.energy;
                for k in 0..3 {
                    grad[3 * i + k] += (1.0 - q.t) * q.grad[k];
                    grad[3 * j + k] += q.t * q.grad[k];
                }
            });
        }
        e
    }

    /// The 6 × 6 block of every segment with a point within the cutoff.
    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for seg in &self.segments {
            let mut blocks = [[Matrix3::zeros(); 2]; 2];
            let mut any = false;
            self.visit(x, seg, |q| {
                let n = [1.0 - q.t, q.t];
                for (a, row) in blocks.iter_mut().enumerate() {
                    for (b, block) in row.iter_mut().enumerate() {
                        *block += n[a] * n[b] * q.hess;
                    }
                }
                any = true;
            });
            if !any {
                continue;
            }
            for (a, row) in blocks.iter().enumerate() {
                for (b, block) in row.iter().enumerate() {
                    let (i, j) = (seg.nodes[a], seg.nodes[b]);
                    for r in 0..3 {
                        for c in 0..3 {
                            out.push((3 * i + r, 3 * j + c, block[(r, c)]));
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::energy::fd::relative_errors;
    use crate::laws::{LennardJones, LjKind, ThermallyShifted};

    /// Finite-difference step, nm: a hundredth of a percent of z₀.
    const FD_STEP: f64 = 3e-5;
    /// Central differences at that step: truncation ~ (h/z₀)² λ''' ≈ 1e-8 of the scale.
    const FD_TOL: f64 = 1e-6;

    fn plain() -> SurfaceLaw {
        LennardJones::new(LjKind::Lj93, 0.46, 0.34).into()
    }

    fn shifted() -> SurfaceLaw {
        ThermallyShifted::new(LennardJones::new(LjKind::Lj104, 0.46, 0.34), 4.626)
            .unwrap()
            .into()
    }

    /// ∫ (g + τ²)^(−k) dτ over ℝ = π Π_{j<k} (j − ½)/j · g^(½ − k).
    fn power_integral(k: i32, g: f64) -> f64 {
        let c: f64 = (1..k).map(|j| (j as f64 - 0.5) / j as f64).product();
        std::f64::consts::PI * c * g.powf(0.5 - k as f64)
    }

    /// The untruncated line law of a plain LJ (n, m) law in closed form.
    fn closed_form(law: &LennardJones, scale: f64, g: f64) -> f64 {
        let (n, m) = law.kind.exponents();
        let (c, z0) = (law.prefactor(), law.z0);
        scale
            * c
            * z0
            * (z0.powi(n - 1) / (n - 1) as f64 * power_integral(n - 1, g)
                - z0.powi(m - 1) / (m - 1) as f64 * power_integral(m - 1, g))
    }

    #[test]
    fn the_line_law_matches_derjaguin_in_closed_form_up_to_the_cutoff_error() {
        let base = LennardJones::new(LjKind::Lj93, 0.46, 0.34);
        let line = LineLaw::new(base.into(), 20.0, 1e4, &SphereLjParams::default());
        let scale = (2.0 * 20.0 * 1e4 / (1e4 + 20.0_f64)).sqrt();
        // the cutoff drops the integrand's tail beyond h_s: an absolute error of 0.7 % of the
        // line adhesion energy Γ = −min λ at the peak (the convergence table below), growing towards h_s
        let gamma = -closed_form(&base, scale, 1.1 * base.z0);
        for g in [0.25, 0.34, 0.4, 0.6, 1.0] {
            let (e, _, _) = line.eval(g);
            let want = closed_form(&base, scale, g);
            assert!((e - want).abs() < 1e-2 * gamma, "g = {g}: {e} vs {want}");
        }
    }

    /// A few tubes' worth of segments near a sphere of radius 50 nm, lowest point at z = 0: a
    /// bent three-node tube with its tip at gap `tip_gap` below the pole and a second tube
    /// lying sideways at gap `side_gap` under the sphere's flank.
    fn scene(law: SurfaceLaw, tip_gap: f64, side_gap: f64) -> (SphereAdhesion, Vec<f64>) {
        let (r_s, r_t) = (50.0, 3.0);
        let tip = -(r_t + tip_gap);
        // flank point at 20° from the pole, the tube tangent to the sphere there
        let th = 20f64.to_radians();
        let (nx, nz) = (th.sin(), -th.cos());
        let reach = r_s + r_t + side_gap;
        let (px, pz) = (reach * nx, r_s + reach * nz);
        let x = vec![
            0.3,
            0.1,
            tip - 12.0, //
            0.9,
            -0.2,
            tip - 6.0, //
            0.0,
            0.0,
            tip, //
            px - 4.0 * nz,
            0.5,
            pz + 4.0 * nx, //
            px,
            0.0,
            pz, //
            px + 5.0 * nz,
            -0.4,
            pz - 5.0 * nx,
        ];
        let layout = [
            TubeLayout {
                first_node: 0,
                nodes: 3,
                radius: r_t,
            },
            TubeLayout {
                first_node: 3,
                nodes: 3,
                radius: r_t,
            },
        ];
        let p = SphereLjParams::default();
        (
            SphereAdhesion::new(law, r_s, [0.0, 0.0, 0.0], &layout, &x, &p),
            x,
        )
    }

    fn check(term: &SphereAdhesion, x: &[f64]) {
        let (eg, eh) = relative_errors(term, x, FD_STEP);
        assert!(
            eg < FD_TOL && eh < FD_TOL,
            "gradient {eg:.1e}, Hessian {eh:.1e}"
        );
        let n = x.len();
        let mut g = vec![0.0; n];
        term.energy_gradient(x, &mut g);
        let gscale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        // the force on the sphere is −∂E/∂H
        // (moving the sphere moves it against every node at once: a tenth of the step keeps
        // the third derivative's share as small as in the node-wise differences)
        let (mut up, mut dn) = (term.clone(), term.clone());
        let step = 0.1 * FD_STEP;
        up.set_height(step);
        dn.set_height(-step);
        let mut s = vec![0.0; n];
        let de_dh = (up.energy_gradient(x, &mut s) - dn.energy_gradient(x, &mut s)) / (2.0 * step);
        assert!(
            (term.force(x) + de_dh).abs() < FD_TOL * gscale,
            "{} {de_dh}",
            term.force(x)
        );
    }

    #[test]
    fn gradient_hessian_and_force_match_finite_differences() {
        for law in [plain(), shifted()] {
            let peak = law.gap_at_max_tension();
            let cutoff = LineLaw::new(law, 3.0, 50.0, &SphereLjParams::default()).cutoff();
            // repulsive range, near the peak tension, in the tail, across the switch-off
            for (tip, side) in [
                (0.25, 0.3),
                (peak, 0.9 * peak),
                (3.0 * peak, 0.5),
                (0.7 * cutoff, 0.35),
            ] {
                let (term, x) = scene(law, tip, side);
                check(&term, &x);
            }
        }
    }

    #[test]
    fn culling_changes_no_term() {
        // the culled sum against every point of every segment
        let (term, x) = scene(shifted(), 0.5, 0.4);
        let mut all = 0.0;
        for seg in &term.segments {
            let law = &term.laws[seg.law];
            let (a, b) = (point(&x, seg.nodes[0]), point(&x, seg.nodes[1]));
            for p in 0..seg.panels {
                for &(s, w) in &term.rule {
                    let t = (p as f64 + s) / seg.panels as f64;
                    let v = a + t * (b - a) - term.centre;
                    let g = v.norm() - term.radius - seg.radius;
                    all += w * seg.length0 / seg.panels as f64 * law.eval(g).0;
                }
            }
        }
        let e = term.energy_gradient(&x, &mut vec![0.0; x.len()]);
        assert!((e - all).abs() < 1e-12 * all.abs(), "{e} {all}");
    }

    #[test]
    fn a_far_sphere_has_no_energy() {
        let (mut term, x) = scene(plain(), 0.4, 0.4);
        term.set_height(500.0);
        let mut g = vec![0.0; x.len()];
        assert_eq!(term.energy_gradient(&x, &mut g), 0.0);
        assert!(g.iter().all(|v| *v == 0.0));
        assert_eq!(term.force(&x), 0.0);
        let mut h = Vec::new();
        term.hessian(&x, &mut h);
        assert!(h.is_empty());
    }
}

#[cfg(test)]
mod convergence {
    use super::*;
    use crate::laws::{LennardJones, LjKind, ThermallyShifted};

    /// Γ = −min λ over g ∈ [0.2, 10.2] nm by a scan in steps of 0.5 pm.
    fn gamma_line(line: &LineLaw) -> f64 {
        let n = 20000;
        -(0..n)
            .map(|i| line.eval(0.2 + 10.0 * i as f64 / n as f64).0)
            .fold(0.0, f64::min)
    }

    /// The table of docs/discrete-contacts.md "Adhesive sphere": Γ against the cutoff and the
    /// cross-section panels, for a 20 nm tube on a 10 µm sphere, against a reference with a
    /// cutoff of 4000 ranges and 400 panels of 8 points.
    #[test]
    #[ignore = "the table of docs/discrete-contacts.md: cargo test --lib convergence_table -- --ignored --nocapture"]
    fn convergence_table() {
        for law in [
            SurfaceLaw::from(LennardJones::new(LjKind::Lj93, 0.46, 0.34)),
            SurfaceLaw::from(LennardJones::new(LjKind::Lj104, 0.46, 0.34)),
            SurfaceLaw::from(
                ThermallyShifted::new(LennardJones::new(LjKind::Lj104, 0.46, 0.34), 4.626).unwrap(),
            ),
            SurfaceLaw::from(
                ThermallyShifted::new(LennardJones::new(LjKind::Lj93, 0.46, 0.34), 4.626).unwrap(),
            ),
        ] {
            let reference = {
                let p = SphereLjParams {
                    cutoff_ranges: 4000.0,
                    section_panels: 400,
                    order: 8,
                    ..SphereLjParams::default()
                };
                gamma_line(&LineLaw::new(law, 20.0, 1e4, &p))
            };
            println!("law {:?} Γ_ref = {reference}", law.stretch());
            for c in [10.0, 20.0, 30.0, 60.0, 120.0] {
                for panels in [8, 16, 24, 48] {
                    let p = SphereLjParams {
                        cutoff_ranges: c,
                        section_panels: panels,
                        ..SphereLjParams::default()
                    };
                    let line = LineLaw::new(law, 20.0, 1e4, &p);
                    let gm = gamma_line(&line);
                    println!("  cutoff {c} ranges (h_c {:.2} nm) panels {panels}: Γ = {gm:.6} rel {:.2e}", line.cutoff(), gm / reference - 1.0);
                }
            }
        }
    }
}
