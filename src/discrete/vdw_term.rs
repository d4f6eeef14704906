//! The tube–tube van der Waals energy of many tubes as one [`EnergyTerm`]: the line-pair
//! potential of [`super::vdw`] summed over the segment pairs of the [`super::broadphase`]
//! neighbour list, periodic images included, same-tube pairs closer than the self-exclusion
//! arclength left out.
//!
//! Segment pairs are evaluated in parallel (rayon) into a list in pair order and summed
//! sequentially in that order, so the energy, gradient and Hessian are bitwise the same with
//! any number of threads.

use parry3d_f64::math::Vector;
use rayon::prelude::*;

use super::broadphase::{Broadphase, BroadphaseInfo, PeriodicBox, SegmentPair, SegmentSet};
use super::energy::EnergyTerm;
use super::vdw::{
    energy_segment_segment, LinePairPotential, QuadSegment, SegmentPairEnergy, VdwError, VdwKernel,
    VdwParams,
};
use super::vdw_table::{energy_segment_segment_tabulated, InnerTable, D_STEP, X_STEP};
use crate::numerics::quadrature::gauss_legendre_unit;

/// Where one tube's nodes sit in the coordinate vector: nodes `first_node ..
/// first_node + nodes`, consecutive nodes joined by segments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeLayout {
    /// index of the first node
    pub first_node: usize,
    /// number of nodes (≥ 2)
    pub nodes: usize,
    /// outer radius, nm
    pub radius: f64,
}

/// One listed segment pair as geometry: segment indices (in tube order, each tube's segments
/// consecutive), axis end points (nm; `b` at the periodic image the pair refers to) and the sum
/// of the outer radii (nm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairGeometry {
    /// the two segment indices
    pub segments: [usize; 2],
    /// first segment's axis ends
    pub a: [Vector; 2],
    /// second segment's axis ends, at its periodic image
    pub b: [Vector; 2],
    /// r_a + r_b, nm
    pub r_sum: f64,
}

/// Per-segment data fixed at set-up.
#[derive(Debug, Clone, Copy)]
struct SegmentInfo {
    tube: u32,
    /// reference arclength of the segment's start along its tube, nm
    arc0: f64,
    /// reference length, nm
    length0: f64,
    panels: usize,
    radius: f64,
}

/// Fixed data the pair filter needs (kept apart from the broadphase, which it borrows).
struct Exclusion {
    info: Vec<SegmentInfo>,
    /// per tube: same-tube pairs closer than this in arclength are excluded, nm
    arc: Vec<f64>,
    /// segments whose pairs among themselves are left out (empty: none)
    inert: Vec<bool>,
}

impl Exclusion {
    fn keep(&self, p: &SegmentPair) -> bool {
        if !self.inert.is_empty() && self.inert[p.a as usize] && self.inert[p.b as usize] {
            return false;
        }
        let (a, b) = (&self.info[p.a as usize], &self.info[p.b as usize]);
        if a.tube != b.tube || p.shift != [0, 0] {
            return true;
        }
        let (first, second) = if a.arc0 <= b.arc0 { (a, b) } else { (b, a) };
        second.arc0 - (first.arc0 + first.length0) >= self.arc[a.tube as usize]
    }
}

/// The van der Waals energy of a set of tubes.
pub struct VdwTerm {
    pot: LinePairPotential,
    /// the inner integral's table ([`VdwKernel::Tabulated`]), or `None` for the point quadrature
    table: Option<InnerTable>,
    rule: Vec<(f64, f64)>,
    exclusion: Exclusion,
    broadphase: Broadphase,
}

impl VdwTerm {
    /// Set up the interaction of `tubes` at reference configuration `x0` (nm): calibrates the
    /// potential, fixes each segment's reference length and quadrature, builds the neighbour
    /// list.
    pub fn new(
        params: &VdwParams,
        tubes: &[TubeLayout],
        x0: &[f64],
        pbox: PeriodicBox,
    ) -> Result<Self, VdwError> {
        let pot = LinePairPotential::calibrate(params)?;
        let n_nodes = x0.len() / 3;
        if x0.len() % 3 != 0 || x0.iter().any(|v| !v.is_finite()) {
            return Err(VdwError::Layout(
                "coordinates must be finite, 3 per node".into(),
            ));
        }
        for p in [pbox.lx, pbox.ly].into_iter().flatten() {
            if !(p.is_finite() && p > 0.0) {
                return Err(VdwError::InvalidParameter {
                    name: "period",
                    value: p,
                    allowed: "finite and > 0",
                });
            }
        }
        let mut info = Vec::new();
        let mut nodes = Vec::new();
        let mut arc = Vec::new();
        for (t, tube) in tubes.iter().enumerate() {
            if tube.nodes < 2 || tube.first_node + tube.nodes > n_nodes {
                return Err(VdwError::Layout(format!(
                    "tube {t}: nodes {}..{} outside 0..{n_nodes} or fewer than 2",
                    tube.first_node,
                    tube.first_node + tube.nodes
                )));
            }
            if !(tube.radius.is_finite() && tube.radius > 0.0) {
                return Err(VdwError::InvalidParameter {
                    name: "radius",
                    value: tube.radius,
                    allowed: "finite and > 0",
                });
            }
            let r_sum = 2.0 * tube.radius;
            let panel = params.panel_fraction * pot.width(r_sum);
            arc.push(params.self_exclusion_factor * pot.cutoff(r_sum));
            let mut s = 0.0;
            for k in 0..tube.nodes - 1 {
                let (i, j) = (tube.first_node + k, tube.first_node + k + 1);
                let l0 = (0..3)
                    .map(|c| (x0[3 * j + c] - x0[3 * i + c]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                if l0 <= 0.0 {
                    return Err(VdwError::Layout(format!(
                        "tube {t}: segment {k} has zero length"
                    )));
                }
                info.push(SegmentInfo {
                    tube: t as u32,
                    arc0: s,
                    length0: l0,
                    panels: (l0 / panel).ceil().max(1.0) as usize,
                    radius: tube.radius,
                });
                nodes.push([i, j]);
                s += l0;
            }
        }
        let reach = info
            .iter()
            .map(|s| s.radius + 0.5 * params.gap_cut)
            .collect();
        let exclusion = Exclusion {
            info,
            arc,
            inert: Vec::new(),
        };
        let table = match params.kernel {
            VdwKernel::Quadrature => None,
            VdwKernel::Tabulated => Some(Self::table(&pot, tubes)?),
        };
        let segs = SegmentSet { nodes, reach };
        let broadphase = Broadphase::new(segs, pbox, params.skin, x0, &|p| exclusion.keep(p));
        Ok(VdwTerm {
            pot,
            table,
            rule: gauss_legendre_unit(params.gauss_order),
            exclusion,
            broadphase,
        })
    }

    /// The inner integral's table for `tubes`, which must share one outer radius (a table
    /// holds one radius sum).
    fn table(pot: &LinePairPotential, tubes: &[TubeLayout]) -> Result<InnerTable, VdwError> {
        let r = tubes.first().map_or(1.0, |t| t.radius);
        if let Some(t) = tubes.iter().find(|t| (t.radius - r).abs() > 1e-12 * r) {
            return Err(VdwError::InvalidParameter {
                name: "kernel",
                value: t.radius,
                allowed: "the tabulated kernel needs one tube radius (radius_cv = 0); \
                          use the quadrature kernel for polydisperse turfs",
            });
        }
        Ok(InnerTable::new(pot, 2.0 * r, D_STEP, X_STEP))
    }

    /// The calibrated line-pair potential.
    pub fn potential(&self) -> &LinePairPotential {
        &self.pot
    }

    /// The current neighbour list.
    pub fn pairs(&self) -> &[SegmentPair] {
        self.broadphase.pairs()
    }

    /// Broadphase counters.
    pub fn broadphase_info(&self) -> BroadphaseInfo {
        self.broadphase.info()
    }

    /// Number of quadrature panels of each segment.
    pub fn panels(&self) -> Vec<usize> {
        self.exclusion.info.iter().map(|s| s.panels).collect()
    }

    /// Every listed pair's two segment axes at `x` (nm), the second at its periodic image, with
    /// the sum of the tubes' outer radii: the geometry the contact statistics of
    /// [`super::structure`] read. Call after `prepare(x)` so that the list is current.
    pub fn pair_geometry(&self, x: &[f64]) -> Vec<PairGeometry> {
        let segs = self.broadphase.segments();
        let pbox = self.broadphase.periodic_box();
        let ends = |i: usize, off: Vector| {
            let v = |n: usize| Vector::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]) + off;
            [v(segs.nodes[i][0]), v(segs.nodes[i][1])]
        };
        self.pairs()
            .iter()
            .map(|p| {
                let (a, b) = (p.a as usize, p.b as usize);
                PairGeometry {
                    segments: [a, b],
                    a: ends(a, Vector::ZERO),
                    b: ends(b, pbox.offset(p.shift)),
                    r_sum: self.exclusion.info[a].radius + self.exclusion.info[b].radius,
                }
            })
            .collect()
    }

    /// Evaluate every listed pair at `x` (in parallel, results in pair order).
    pub fn evaluate_pairs(&self, x: &[f64], want_hessian: bool) -> Vec<SegmentPairEnergy> {
        let segs = self.broadphase.segments();
        let pbox = self.broadphase.periodic_box();
        self.pairs()
            .par_iter()
            .map(|p| {
                let quad = |i: usize, off: Vector| {
                    let s = &self.exclusion.info[i];
                    let [n0, n1] = segs.nodes[i];
                    let v = |n: usize| Vector::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]) + off;
                    QuadSegment {
                        ends: [v(n0), v(n1)],
                        panels: s.panels,
                        length0: s.length0,
                    }
                };
                let (a, b) = (p.a as usize, p.b as usize);
                let (qa, qb) = (quad(a, Vector::ZERO), quad(b, pbox.offset(p.shift)));
                match &self.table {
                    Some(t) => energy_segment_segment_tabulated(
                        &self.pot,
                        t,
                        &self.rule,
                        &qa,
                        &qb,
                        want_hessian,
                    ),
                    None => {
                        let r_sum = self.exclusion.info[a].radius + self.exclusion.info[b].radius;
                        energy_segment_segment(&self.pot, &self.rule, &qa, &qb, r_sum, want_hessian)
                    }
                }
            })
            .collect()
    }

    /// The Hessian entries of every listed pair in contact at `x`, appended to `out` in pair
    /// order: both triangles, or (`lower`) those on and below the diagonal.
    fn hessian_append(&self, x: &[f64], lower: bool, out: &mut Vec<(usize, usize, f64)>) {
        let results = self.evaluate_pairs(x, true);
        for (p, r) in self.pairs().iter().zip(&results) {
            let Some(h) = r.hessian.as_ref().filter(|_| r.point_pairs > 0) else {
                continue;
            };
            let dofs: [usize; 12] = std::array::from_fn(|k| self.dof(p, k));
            for (i, &gi) in dofs.iter().enumerate() {
                for (j, &gj) in dofs.iter().enumerate() {
                    if !lower || gi >= gj {
                        out.push((gi, gj, h[12 * i + j]));
                    }
                }
            }
        }
    }

    /// The periodic box.
    pub fn periodic_box(&self) -> PeriodicBox {
        self.broadphase.periodic_box()
    }

    /// Deform the periodic box to `pbox` at configuration `x` (the neighbour list rebuilt).
    pub fn set_box(&mut self, pbox: PeriodicBox, x: &[f64]) {
        let excl = &self.exclusion;
        self.broadphase.set_box(pbox, x, &|p| excl.keep(p));
    }

    /// Leave out every pair of two segments that both touch a node `touches` flags (the
    /// lateral test's clamped bases, [`super::rve`]), at configuration `x` (list rebuilt).
    pub fn exclude_pairs_among(&mut self, touches: &dyn Fn(usize) -> bool, x: &[f64]) {
        let segs = self.broadphase.segments();
        self.exclusion.inert = segs
            .nodes
            .iter()
            .map(|&[a, b]| touches(a) || touches(b))
            .collect();
        let (excl, pbox) = (&self.exclusion, self.broadphase.periodic_box());
        self.broadphase.set_box(pbox, x, &|p| excl.keep(p));
    }

    /// (∂E/∂L_x, ∂E/∂L_y) at fixed nodes `x`, nN: each pair (a, b, s) sees b's nodes shifted
    /// by s·(L_x, L_y, 0), so a period's derivative is Σ s · (force on b's image) — the virial
    /// of the image pairs. Call after `prepare(x)` so that the list is current.
    pub fn box_gradient(&self, x: &[f64]) -> [f64; 2] {
        let mut g = [0.0; 2];
        for (p, r) in self.pairs().iter().zip(self.evaluate_pairs(x, false)) {
            for (axis, gi) in g.iter_mut().enumerate() {
                let s = f64::from(p.shift[axis]);
                if s != 0.0 {
                    *gi += s * (r.grad[6 + axis] + r.grad[9 + axis]);
                }
            }
        }
        g
    }

    /// Global dof of local dof k (0..12) of pair `p`.
    fn dof(&self, p: &SegmentPair, k: usize) -> usize {
        let segs = self.broadphase.segments();
        let node = match k / 3 {
            0 => segs.nodes[p.a as usize][0],
            1 => segs.nodes[p.a as usize][1],
            2 => segs.nodes[p.b as usize][0],
            _ => segs.nodes[p.b as usize][1],
        };
        3 * node + k % 3
    }
}

impl EnergyTerm for VdwTerm {
    fn prepare(&mut self, x: &[f64]) {
        let excl = &self.exclusion;
        self.broadphase.update(x, &|p| excl.keep(p));
    }

    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let results = self.evaluate_pairs(x, false);
        let mut e = 0.0;
        for (p, r) in self.pairs().iter().zip(&results) {
            e += r.energy;
            for (k, g) in r.grad.iter().enumerate() {
                grad[self.dof(p, k)] += g;
            }
        }
        e
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        self.hessian_append(x, false, out);
    }

    fn hessian_lower(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        self.hessian_append(x, true, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Finite-difference step, nm.
    const FD_STEP: f64 = 1e-6;

    /// Three short wavy tubes near contact, one pair through a periodic image.
    fn tangle() -> (Vec<TubeLayout>, Vec<f64>) {
        let mut x = Vec::new();
        let mut tubes = Vec::new();
        let mut add = |pts: Vec<[f64; 3]>, x: &mut Vec<f64>| {
            tubes.push(TubeLayout {
                first_node: x.len() / 3,
                nodes: pts.len(),
                radius: 20.0,
            });
            x.extend(pts.iter().flatten());
        };
        // along x at y ≈ 0
        add(
            (0..5)
                .map(|k| [10.0 * k as f64, 0.3 * (k as f64).sin(), 0.0])
                .collect(),
            &mut x,
        );
        // parallel at gap ≈ 0.6 nm, beyond the end of the first; its image (−90 nm in x)
        // meets the first tube's other end
        add(
            (0..5)
                .map(|k| [50.0 + 9.0 * k as f64, 40.6, 0.5 * (k as f64).sin()])
                .collect(),
            &mut x,
        );
        // crossing the first at right angles from above, gap ≈ 0.6 nm
        add(
            (0..5)
                .map(|k| [20.0, -30.0 + 15.0 * k as f64, 40.6 + 0.2 * k as f64])
                .collect(),
            &mut x,
        );
        (tubes, x)
    }

    #[test]
    fn gradient_and_hessian_match_finite_differences() {
        for kernel in [VdwKernel::Quadrature, VdwKernel::Tabulated] {
            check_derivatives(kernel);
        }
    }

    fn check_derivatives(kernel: VdwKernel) {
        let (tubes, x) = tangle();
        let pbox = PeriodicBox {
            lx: Some(90.0),
            ly: None,
        };
        let params = VdwParams {
            kernel,
            ..VdwParams::default()
        };
        let mut term = VdwTerm::new(&params, &tubes, &x, pbox).unwrap();
        term.prepare(&x);
        assert!(term.pairs().iter().any(|p| p.shift != [0, 0]));
        let e = term.energy_gradient(&x, &mut vec![0.0; x.len()]);
        assert!(e < 0.0, "the tangle must adhere");
        let mut trip = Vec::new();
        term.hessian(&x, &mut trip);
        let n = x.len();
        let mut h = vec![0.0; n * n];
        for (i, j, v) in trip {
            h[i * n + j] += v;
        }
        let hmax = h.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        // central differences at 1e-6 nm are good to ~1e-8 of the largest entry
        let (eg, eh) = crate::discrete::energy::fd::relative_errors(&term, &x, FD_STEP);
        assert!(eg < 1e-6 && eh < 1e-5, "gradient {eg}, Hessian {eh}");
        // symmetry of the assembled Hessian
        for i in 0..n {
            for j in 0..n {
                assert!((h[i * n + j] - h[j * n + i]).abs() <= 1e-12 * hmax);
            }
        }
    }

    #[test]
    fn the_box_gradient_matches_finite_differences_of_the_period() {
        let (tubes, x) = tangle();
        let pbox = |lx: f64| PeriodicBox {
            lx: Some(lx),
            ly: None,
        };
        let mut term = VdwTerm::new(&VdwParams::default(), &tubes, &x, pbox(90.0)).unwrap();
        term.prepare(&x);
        let g = term.box_gradient(&x);
        assert!(
            g[0] != 0.0 && g[1] == 0.0,
            "the image pair must load the x period: {g:?}"
        );
        let mut energy = |lx: f64| {
            term.set_box(pbox(lx), &x);
            term.energy_gradient(&x, &mut vec![0.0; x.len()])
        };
        let fd = (energy(90.0 + FD_STEP) - energy(90.0 - FD_STEP)) / (2.0 * FD_STEP);
        // central differences at 1e-6 nm, as the node gradient above
        assert!(
            (fd - g[0]).abs() < 1e-6 * g[0].abs(),
            "{fd} against {}",
            g[0]
        );
    }

    /// The two kernels evaluate the same double integral. With fine panels (f = 0.1) they agree
    /// to 2e-9 relative on the tangle (the table's inner integral is right); at the default
    /// f = 0.75 each errs by the outer Gauss points' discretisation (3.5e-6 and 8e-6 relative
    /// here), which both must keep below 1e-5.
    #[test]
    fn the_tabulated_kernel_gives_the_quadrature_energy() {
        let (tubes, x) = tangle();
        let pbox = PeriodicBox {
            lx: Some(90.0),
            ly: None,
        };
        let energy = |kernel, panel_fraction| {
            let params = VdwParams {
                kernel,
                panel_fraction,
                ..VdwParams::default()
            };
            let mut term = VdwTerm::new(&params, &tubes, &x, pbox).unwrap();
            term.prepare(&x);
            term.energy_gradient(&x, &mut vec![0.0; x.len()])
        };
        let fine = energy(VdwKernel::Quadrature, 0.1);
        let rel = |e: f64| ((e - fine) / fine).abs();
        let tabulated_fine = energy(VdwKernel::Tabulated, 0.1);
        assert!(rel(tabulated_fine) < 1e-8, "{tabulated_fine} vs {fine}");
        for kernel in [VdwKernel::Quadrature, VdwKernel::Tabulated] {
            let e = energy(kernel, 0.75);
            assert!(rel(e) < 1e-5, "{kernel:?}: {e} vs {fine}");
        }
    }

    #[test]
    fn the_tabulated_kernel_refuses_two_radii() {
        let (mut tubes, x) = tangle();
        tubes[1].radius = 21.0;
        let params = VdwParams {
            kernel: VdwKernel::Tabulated,
            ..VdwParams::default()
        };
        let err = VdwTerm::new(&params, &tubes, &x, PeriodicBox::default()).err();
        assert!(
            matches!(err, Some(VdwError::InvalidParameter { name: "kernel", .. })),
            "{err:?}"
        );
    }

    #[test]
    fn a_straight_tube_alone_has_no_energy() {
        let x: Vec<f64> = (0..30).flat_map(|k| [0.0, 0.0, 3.0 * k as f64]).collect();
        let tubes = [TubeLayout {
            first_node: 0,
            nodes: 30,
            radius: 20.0,
        }];
        let mut term =
            VdwTerm::new(&VdwParams::default(), &tubes, &x, PeriodicBox::default()).unwrap();
        term.prepare(&x);
        let mut g = vec![0.0; x.len()];
        assert_eq!(term.energy_gradient(&x, &mut g), 0.0);
    }

    #[test]
    fn bad_layouts_are_errors() {
        let x = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let bad = TubeLayout {
            first_node: 1,
            nodes: 2,
            radius: 20.0,
        };
        let pb = PeriodicBox::default();
        assert!(VdwTerm::new(&VdwParams::default(), &[bad], &x, pb).is_err());
        let zero = TubeLayout {
            first_node: 0,
            nodes: 2,
            radius: 0.0,
        };
        assert!(VdwTerm::new(&VdwParams::default(), &[zero], &x, pb).is_err());
    }
}
