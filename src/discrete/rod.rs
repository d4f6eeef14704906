//! A tube as a discrete spatial elastica: a chain of nodes that stretches and bends
//! (seed chapter 2.4).
//!
//! Energy of one rod with nodes x₀ … x_n, edges e_j = x_{j+1} − x_j (rest lengths ℓ_j):
//!
//! E = Σ_j EA/(2ℓ_j) (|e_j| − ℓ_j)²  +  Σ_{i=1}^{n−1} K/(ℓ_{i−1} + ℓ_i) |κb_i − κb_i⁰|²,
//!
//! κb_i = 2 (e_{i−1} × e_i)/(|e_{i−1}||e_i| + e_{i−1}·e_i) (Bergou et al. 2008), whose continuum
//! limit is ∫ (½ EA ε² + ½ K κ²) ds. Bending is isotropic and twist-free: the rod carries no
//! material frame, which is exact for a rod with no applied torque and a circular section.
//!
//! The natural shape enters through κb_i⁰, the curvature binormals of the rest polygon, stored in
//! the laboratory frame. For a straight rest shape (κb⁰ = 0) the energy is invariant under any
//! rigid motion. For a pre-bent rest shape it is invariant under translations only: rotating a
//! pre-bent rod by a finite angle costs energy, so natural shapes are meant for tubes whose
//! curvature stays near its rest orientation (the turf scenes); a frame-transported natural
//! curvature (Bergou's material frame) is not implemented.
//!
//! Kernels: [`super::rod_kernels`]. Many rods: [`RodSet`] evaluates them in parallel (rayon) and
//! sums in rod order, so 1 and 2 threads give identical numbers.

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::energy::EnergyTerm;
use super::rod_kernels::{
    bend_vertex, bend_vertex_gradient, curvature_binormal, stretch_edge, stretch_edge_gradient,
};

/// Elastic constants of a tube section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodStiffness {
    /// bending stiffness K = YI (nN·nm²)
    pub bending: f64,
    /// axial stiffness EA (nN)
    pub axial: f64,
}

impl RodStiffness {
    /// Hollow cylinder of Young's modulus `youngs` (GPa) and radii `r_outer`, `r_inner` (nm):
    /// I = π(r_o⁴ − r_i⁴)/4 (axial moment), A = π(r_o² − r_i²).
    pub fn hollow_tube(youngs: f64, r_outer: f64, r_inner: f64) -> Self {
        let pi = std::f64::consts::PI;
        RodStiffness {
            bending: youngs * pi * (r_outer.powi(4) - r_inner.powi(4)) / 4.0,
            axial: youngs * pi * (r_outer.powi(2) - r_inner.powi(2)),
        }
    }

    /// The turf's tube (PHYSICS.md): Y = 0.4 TPa, r_o = 20 nm, r_i = 17.3 nm, so
    /// K ≈ 2.21×10⁷ nN·nm² and EA ≈ 1.27×10⁵ nN.
    pub fn turf_tube() -> Self {
        Self::hollow_tube(400.0, 20.0, 17.3)
    }
}

/// Nodes of a straight polygon: `segments` equal segments of total length `length` (nm) from
/// `origin` (nm) along `direction` (normalised here).
pub fn straight_points(
    origin: [f64; 3],
    direction: [f64; 3],
    length: f64,
    segments: usize,
) -> Vec<[f64; 3]> {
    let d = Vector3::from(direction).normalize();
    (0..=segments)
        .map(|i| {
            let s = length * i as f64 / segments as f64;
            [0, 1, 2].map(|a| origin[a] + s * d[a])
        })
        .collect()
}

/// Why a rod could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RodError {
    /// fewer than two nodes
    #[error("a rod needs at least 2 nodes, got {0}")]
    TooFewNodes(usize),
    /// a rest edge of zero or non-finite length
    #[error("rest edge {0} has zero or non-finite length")]
    DegenerateEdge(usize),
    /// a rest vertex folds back on itself (turning angle π)
    #[error("rest vertex {0} folds back (turning angle π)")]
    FoldedVertex(usize),
    /// a stiffness that is not positive and finite
    #[error("rod stiffness must be positive and finite, got K = {bending}, EA = {axial}")]
    BadStiffness {
        /// K (nN·nm²)
        bending: f64,
        /// EA (nN)
        axial: f64,
    },
}

/// One rod occupying the consecutive nodes `first .. first + nodes` of the global vector.
#[derive(Debug, Clone)]
pub struct Rod {
    first: usize,
    stiffness: RodStiffness,
    rest_lengths: Vec<f64>,
    natural: Vec<Vector3<f64>>,
}

impl Rod {
    /// A rod whose rest (natural) shape is the polygon `rest` (nm): rest lengths and natural
    /// curvature binormals are taken from it. `first` is the global index of its first node.
    pub fn natural(
        first: usize,
        rest: &[[f64; 3]],
        stiffness: RodStiffness,
    ) -> Result<Self, RodError> {
        Self::build(first, rest, stiffness, true)
    }

    /// A rod that is straight at rest, with the rest lengths of the polygon `rest` (nm) (its
    /// bends, if any, are strained).
    pub fn straight(
        first: usize,
        rest: &[[f64; 3]],
        stiffness: RodStiffness,
    ) -> Result<Self, RodError> {
        Self::build(first, rest, stiffness, false)
    }

    fn build(
        first: usize,
        rest: &[[f64; 3]],
        stiffness: RodStiffness,
        bent: bool,
    ) -> Result<Self, RodError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(stiffness.bending) || !ok(stiffness.axial) {
            return Err(RodError::BadStiffness {
                bending: stiffness.bending,
                axial: stiffness.axial,
            });
        }
        if rest.len() < 2 {
            return Err(RodError::TooFewNodes(rest.len()));
        }
        let edges: Vec<Vector3<f64>> = rest
            .windows(2)
            .map(|w| Vector3::from(w[1]) - Vector3::from(w[0]))
            .collect();
        let rest_lengths: Vec<f64> = edges.iter().map(|e| e.norm()).collect();
        if let Some(j) = rest_lengths.iter().position(|&l| !ok(l)) {
            return Err(RodError::DegenerateEdge(j));
        }
        let mut natural = Vec::with_capacity(edges.len().saturating_sub(1));
        for (i, w) in edges.windows(2).enumerate() {
            let kb = curvature_binormal(&w[0], &w[1]);
            if !kb.iter().all(|v| v.is_finite()) {
                return Err(RodError::FoldedVertex(i + 1));
            }
            natural.push(if bent { kb } else { Vector3::zeros() });
        }
        Ok(Rod {
            first,
            stiffness,
            rest_lengths,
            natural,
        })
    }

    /// Global index of the first node.
    pub fn first_node(&self) -> usize {
        self.first
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.rest_lengths.len() + 1
    }

    /// Number of segments (edges).
    pub fn segments(&self) -> usize {
        self.rest_lengths.len()
    }

    /// Rest length (nm).
    pub fn rest_length(&self) -> f64 {
        self.rest_lengths.iter().sum()
    }

    /// Elastic constants.
    pub fn stiffness(&self) -> RodStiffness {
        self.stiffness
    }

    fn node(&self, x: &[f64], i: usize) -> Vector3<f64> {
        let k = 3 * (self.first + i);
        Vector3::new(x[k], x[k + 1], x[k + 2])
    }

    fn edge(&self, x: &[f64], j: usize) -> Vector3<f64> {
        self.node(x, j + 1) - self.node(x, j)
    }

    fn bend_weight(&self, i: usize) -> f64 {
        self.stiffness.bending / (self.rest_lengths[i - 1] + self.rest_lengths[i])
    }

    /// The elastic energy split into (stretching, bending), aJ.
    pub fn energy_parts(&self, x: &[f64]) -> (f64, f64) {
        let stretch = (0..self.segments())
            .map(|j| {
                stretch_edge_gradient(&self.edge(x, j), self.rest_lengths[j], self.stiffness.axial)
                    .0
            })
            .sum();
        (stretch, self.vertex_bending(x).iter().sum())
    }

    /// The bending energy of each interior vertex 1 … n − 1 (aJ), in vertex order.
    pub fn vertex_bending(&self, x: &[f64]) -> Vec<f64> {
        (1..self.segments())
            .map(|i| {
                let (e, f) = (self.edge(x, i - 1), self.edge(x, i));
                bend_vertex_gradient(&e, &f, &self.natural[i - 1], self.bend_weight(i)).0
            })
            .collect()
    }

    /// Energy (aJ) with the gradient (nN) added into `grad`, which holds this rod's nodes only
    /// (3 × nodes entries, local numbering).
    fn energy_gradient_local(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut energy = 0.0;
        let mut add = |node: usize, g: &Vector3<f64>, sign: f64| {
            for a in 0..3 {
                grad[3 * node + a] += sign * g[a];
            }
        };
        for (j, &rest) in self.rest_lengths.iter().enumerate() {
            let (w, g) = stretch_edge_gradient(&self.edge(x, j), rest, self.stiffness.axial);
            energy += w;
            add(j, &g, -1.0);
            add(j + 1, &g, 1.0);
        }
        for i in 1..self.segments() {
            let (e, f) = (self.edge(x, i - 1), self.edge(x, i));
            let (w, ge, gf) =
                bend_vertex_gradient(&e, &f, &self.natural[i - 1], self.bend_weight(i));
            energy += w;
            add(i - 1, &ge, -1.0);
            add(i, &(ge - gf), 1.0);
            add(i + 1, &gf, 1.0);
        }
        energy
    }
}

/// A rod's Hessian as 3×3 node blocks: each node's diagonal block and its blocks with the next
/// two nodes (a bending vertex couples nodes i − 1, i, i + 1, so nothing reaches further).
/// Summing every element into these blocks before the entries leave the rod lists each block
/// once — 45 entries per node instead of 117 (36 per edge, 144 per vertex) — which is what the
/// Newton solver's assembly pays for.
struct NodeBlocks {
    /// block (k, k)
    diag: Vec<Matrix3<f64>>,
    /// blocks (k + 1, k) and (k + 2, k)
    sub: [Vec<Matrix3<f64>>; 2],
}

impl NodeBlocks {
    fn new(nodes: usize) -> Self {
        let zeros = |n: usize| vec![Matrix3::zeros(); n];
        NodeBlocks {
            diag: zeros(nodes),
            sub: [
                zeros(nodes.saturating_sub(1)),
                zeros(nodes.saturating_sub(2)),
            ],
        }
    }

    /// Number of entries [`Self::emit`] lists for a rod of `nodes` nodes (`lower`: on and
    /// below the diagonal only).
    fn entries(nodes: usize, lower: bool) -> usize {
        let off = nodes.saturating_sub(1) + nodes.saturating_sub(2);
        if lower {
            6 * nodes + 9 * off
        } else {
            9 * nodes + 18 * off
        }
    }

    /// Add a block Hessian over edge vectors: `edges` lists, for each edge vector of the
    /// element, its (tail, head) local node; `block(a, b)` is the 3×3 block between edge
    /// vectors a and b (symmetric as a whole, so only blocks at or below the node diagonal are
    /// kept).
    fn add_edges(
        &mut self,
        edges: &[(usize, usize)],
        block: impl Fn(usize, usize) -> Matrix3<f64>,
    ) {
        for (a, &(ta, ha)) in edges.iter().enumerate() {
            for (b, &(tb, hb)) in edges.iter().enumerate() {
                let m = block(a, b);
                // e_a = x_ha − x_ta: ∂e_a/∂x_ha = +I, ∂e_a/∂x_ta = −I
                for (na, sa) in [(ha, 1.0), (ta, -1.0)] {
                    for (nb, sb) in [(hb, 1.0), (tb, -1.0)] {
                        let target = match na.checked_sub(nb) {
                            Some(0) => &mut self.diag[nb],
                            Some(d) => &mut self.sub[d - 1][nb],
                            None => continue,
                        };
                        *target += (sa * sb) * m;
                    }
                }
            }
        }
    }

    /// The entries of global node numbers `n0 + k` into `out` (of length [`Self::entries`]):
    /// both triangles, or (`lower`) those on and below the diagonal, in the same order.
    fn emit(&self, n0: usize, lower: bool, out: &mut [(usize, usize, f64)]) {
        let mut slots = out.iter_mut();
        let mut put = |row: usize, col: usize, m: &Matrix3<f64>, transpose: bool| {
            for r in 0..3 {
                for c in 0..3 {
                    let (i, j) = (3 * (n0 + row) + r, 3 * (n0 + col) + c);
                    if lower && i < j {
                        continue;
                    }
                    let v = if transpose { m[(c, r)] } else { m[(r, c)] };
                    *slots.next().expect("one slot per entry") = (i, j, v);
                }
            }
        };
        for (k, m) in self.diag.iter().enumerate() {
            put(k, k, m, false);
        }
        for (d, blocks) in self.sub.iter().enumerate() {
            for (k, m) in blocks.iter().enumerate() {
                put(k + d + 1, k, m, false);
                if !lower {
                    put(k, k + d + 1, m, true);
                }
            }
        }
    }
}

impl Rod {
    /// Number of Hessian entries the rod lists (`lower`: on and below the diagonal only).
    fn hessian_entries(&self, lower: bool) -> usize {
        NodeBlocks::entries(self.nodes(), lower)
    }

    /// The rod's Hessian entries into `out` (of length [`Self::hessian_entries`]): both
    /// triangles, or (`lower`) those on and below the diagonal.
    fn hessian_into(&self, x: &[f64], lower: bool, out: &mut [(usize, usize, f64)]) {
        let mut blocks = NodeBlocks::new(self.nodes());
        for (j, &rest) in self.rest_lengths.iter().enumerate() {
            let (_, _, h) = stretch_edge(&self.edge(x, j), rest, self.stiffness.axial);
            blocks.add_edges(&[(j, j + 1)], |_, _| h);
        }
        for i in 1..self.segments() {
            let (e, f) = (self.edge(x, i - 1), self.edge(x, i));
            let (_, _, h) = bend_vertex(&e, &f, &self.natural[i - 1], self.bend_weight(i));
            blocks.add_edges(&[(i - 1, i), (i, i + 1)], |a, b| {
                h.fixed_view::<3, 3>(3 * a, 3 * b).into_owned()
            });
        }
        blocks.emit(self.first, lower, out);
    }

    /// The rod's entries appended to `out` (`lower`: on and below the diagonal only).
    fn hessian_append(&self, x: &[f64], lower: bool, out: &mut Vec<(usize, usize, f64)>) {
        let start = out.len();
        out.resize(start + self.hessian_entries(lower), (0, 0, 0.0));
        self.hessian_into(x, lower, &mut out[start..]);
    }
}

impl EnergyTerm for Rod {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let range = 3 * self.first..3 * (self.first + self.nodes());
        self.energy_gradient_local(x, &mut grad[range])
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        self.hessian_append(x, false, out);
    }

    fn hessian_lower(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        self.hessian_append(x, true, out);
    }
}

/// Many rods as one energy term, evaluated rod by rod in parallel; each rod's contribution is
/// computed on its own and the results are summed in rod order (deterministic with any number
/// of threads).
#[derive(Debug, Clone, Default)]
pub struct RodSet {
    rods: Vec<Rod>,
}

impl RodSet {
    /// A set of rods (their node ranges may not overlap).
    pub fn new(rods: Vec<Rod>) -> Self {
        RodSet { rods }
    }

    /// The rods.
    pub fn rods(&self) -> &[Rod] {
        &self.rods
    }

    /// Total number of segments.
    pub fn segments(&self) -> usize {
        self.rods.iter().map(Rod::segments).sum()
    }

    /// The elastic energy of all rods split into (stretching, bending), aJ, summed in rod order.
    pub fn energy_parts(&self, x: &[f64]) -> (f64, f64) {
        self.rods
            .iter()
            .map(|r| r.energy_parts(x))
            .fold((0.0, 0.0), |(s, b), (ds, db)| (s + ds, b + db))
    }
}

impl EnergyTerm for RodSet {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let parts: Vec<(f64, Vec<f64>)> = self
            .rods
            .par_iter()
            .map(|rod| {
                let mut g = vec![0.0; 3 * rod.nodes()];
                let e = rod.energy_gradient_local(x, &mut g);
                (e, g)
            })
            .collect();
        let mut energy = 0.0;
        for (rod, (e, g)) in self.rods.iter().zip(parts) {
            energy += e;
            let k = 3 * rod.first;
            for (dst, src) in grad[k..k + g.len()].iter_mut().zip(g) {
                *dst += src;
            }
        }
        energy
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        self.hessian_append(x, false, out);
    }

    fn hessian_lower(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        self.hessian_append(x, true, out);
    }
}

impl RodSet {
    /// Every rod's entries appended to `out` (`lower`: on and below the diagonal only), each
    /// rod filling its own stretch in parallel, in rod order.
    fn hessian_append(&self, x: &[f64], lower: bool, out: &mut Vec<(usize, usize, f64)>) {
        let start = out.len();
        let total: usize = self.rods.iter().map(|r| r.hessian_entries(lower)).sum();
        out.resize(start + total, (0, 0, 0.0));
        let mut parts = Vec::with_capacity(self.rods.len());
        let mut rest = &mut out[start..];
        for rod in &self.rods {
            let (part, tail) = rest.split_at_mut(rod.hessian_entries(lower));
            parts.push((rod, part));
            rest = tail;
        }
        parts
            .into_par_iter()
            .for_each(|(rod, part)| rod.hessian_into(x, lower, part));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;

    /// Central differences (step 1e-5 nm on a 10 nm rod): truncation and round-off both far
    /// below 1e-6 of the largest entry.
    const FD_TOL: f64 = 1e-6;
    const H: f64 = 1e-5;

    #[test]
    fn energy_parts_sum_to_the_energy() {
        let mut rng = Pcg64::seed_from_u64(11);
        let (rod, rest) = random_rod(&mut rng, 0, 9);
        let x: Vec<f64> = rest
            .iter()
            .flatten()
            .map(|v| v + rng.random_range(-0.1..0.1))
            .collect();
        let mut g = vec![0.0; x.len()];
        let e = rod.energy_gradient(&x, &mut g);
        let (s, b) = rod.energy_parts(&x);
        assert!(s > 0.0 && b > 0.0);
        // same terms, two summation orders
        assert!((s + b - e).abs() <= 1e-12 * e);
    }

    fn random_rod(rng: &mut Pcg64, first: usize, n: usize) -> (Rod, Vec<[f64; 3]>) {
        let rest: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                [
                    i as f64 + rng.random_range(-0.2..0.2),
                    rng.random_range(-0.3..0.3),
                    rng.random_range(-0.3..0.3),
                ]
            })
            .collect();
        let stiff = RodStiffness {
            bending: 3.0,
            axial: 20.0,
        };
        (Rod::natural(first, &rest, stiff).unwrap(), rest)
    }

    #[test]
    fn rod_gradient_and_hessian_match_finite_differences() {
        let mut rng = Pcg64::seed_from_u64(3);
        let (rod, rest) = random_rod(&mut rng, 1, 7);
        let n = 3 * (rod.nodes() + 2);
        // a random deformed configuration (node 0 and the last node belong to no rod)
        let mut x = vec![0.0; n];
        for (i, p) in rest.iter().enumerate() {
            for a in 0..3 {
                x[3 * (i + 1) + a] = p[a] + rng.random_range(-0.3..0.3);
            }
        }
        let (eg, eh) = crate::discrete::energy::fd::relative_errors(&rod, &x, H);
        assert!(eg < FD_TOL && eh < FD_TOL, "gradient {eg}, Hessian {eh}");
        let mut g = vec![0.0; n];
        rod.energy_gradient(&x, &mut g);
        // nodes outside the rod get nothing
        assert!(g[..3].iter().chain(&g[n - 3..]).all(|&v| v == 0.0));
    }

    #[test]
    fn rest_shape_has_zero_energy_and_straight_rod_is_rotation_invariant() {
        let mut rng = Pcg64::seed_from_u64(5);
        let (rod, rest) = random_rod(&mut rng, 0, 6);
        let x: Vec<f64> = rest.iter().flatten().copied().collect();
        let mut g = vec![0.0; x.len()];
        assert!(rod.energy_gradient(&x, &mut g).abs() < 1e-20);
        let straight = Rod::straight(0, &rest, rod.stiffness()).unwrap();
        let mut g0 = vec![0.0; x.len()];
        let e0 = straight.energy_gradient(&x, &mut g0);
        // rotate by 1 rad about z and translate
        let (c, s) = (1.0_f64.cos(), 1.0_f64.sin());
        let y: Vec<f64> = rest
            .iter()
            .flat_map(|p| [c * p[0] - s * p[1] + 2.0, s * p[0] + c * p[1], p[2] - 1.0])
            .collect();
        let e1 = straight.energy_gradient(&y, &mut g0);
        assert!((e0 - e1).abs() < 1e-12 * e0.abs());
    }

    #[test]
    fn straight_rod_bent_into_an_arc_stores_half_k_kappa_squared() {
        // a circular arc of radius R, n segments: E → K L /(2R²) as n grows
        let (r, angle, n) = (50.0, 1.0, 400);
        let pts: Vec<[f64; 3]> = (0..=n)
            .map(|i| {
                let t = angle * i as f64 / n as f64;
                [r * t.sin(), r * (1.0 - t.cos()), 0.0]
            })
            .collect();
        let stiff = RodStiffness::turf_tube();
        let chord: Vec<[f64; 3]> = pts.clone();
        let rod = Rod::straight(0, &chord, stiff).unwrap();
        let x: Vec<f64> = pts.iter().flatten().copied().collect();
        let mut g = vec![0.0; x.len()];
        let e = rod.energy_gradient(&x, &mut g);
        let l = rod.rest_length();
        let exact = stiff.bending * l / (2.0 * r * r);
        // the end vertices miss half a Voronoi cell each: relative deficit 1/n
        assert!((e / exact - 1.0).abs() < 1.5 / n as f64);
    }

    #[test]
    fn rod_set_matches_the_sum_of_its_rods_bitwise() {
        let mut rng = Pcg64::seed_from_u64(9);
        let (a, ra) = random_rod(&mut rng, 0, 5);
        let (b, rb) = random_rod(&mut rng, 5, 8);
        let x: Vec<f64> = ra.iter().chain(&rb).flatten().map(|v| v * 1.01).collect();
        let mut g1 = vec![0.0; x.len()];
        let e1 = a.energy_gradient(&x, &mut g1) + b.energy_gradient(&x, &mut g1);
        let set = RodSet::new(vec![a, b]);
        let mut g2 = vec![0.0; x.len()];
        let e2 = set.energy_gradient(&x, &mut g2);
        assert_eq!(e1, e2);
        assert_eq!(g1, g2);
        assert_eq!(set.segments(), 4 + 7);
        // the lower triangle the Newton solver assembles: the full list's, in its order
        let (mut full, mut lower) = (Vec::new(), Vec::new());
        set.hessian(&x, &mut full);
        set.hessian_lower(&x, &mut lower);
        full.retain(|e| e.0 >= e.1);
        assert_eq!(lower, full);
    }

    #[test]
    fn rod_set_gives_identical_numbers_with_one_and_two_threads() {
        let mut rng = Pcg64::seed_from_u64(21);
        let mut rods = Vec::new();
        let mut x = Vec::new();
        for r in 0..6 {
            let (rod, rest) = random_rod(&mut rng, 9 * r, 9);
            rods.push(rod);
            x.extend(rest.iter().flatten().map(|v| v * 1.02 + 0.01));
        }
        let set = RodSet::new(rods);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut g = vec![0.0; x.len()];
                let e = set.energy_gradient(&x, &mut g);
                let mut h = Vec::new();
                set.hessian(&x, &mut h);
                (e, g, h)
            })
        };
        assert_eq!(run(1), run(2));
    }

    #[test]
    fn tube_constants_match_physics_md() {
        let s = RodStiffness::turf_tube();
        assert!((s.bending / 2.21e7 - 1.0).abs() < 5e-3);
        assert!(Rod::straight(0, &[[0.0; 3]], s).is_err());
        assert!(Rod::straight(0, &[[0.0; 3], [0.0; 3]], s).is_err());
    }
}
