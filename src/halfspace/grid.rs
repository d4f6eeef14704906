//! Radial grids for the ring discretisation, graded from a refinement zone outwards.
//!
//! The nodes ρ₀ = 0 < ρ₁ < … carry the collocation points; ring j spans [b_j, b_{j+1}] with
//! b₀ = 0, b_j = (ρ_{j−1} + ρ_j)/2 and the last edge half a spacing beyond the last node. The
//! local spacing is s(ρ) = s_f + g·d(ρ), d the distance from the zone [ρ_lo, ρ_hi] where the gap
//! changes fastest (the contact edge), so the grid is uniform there and geometric far away.
//! Halving s_f and g together halves every cell: that is the refinement family used for the
//! grid-convergence study ([`super::refinement`]).

/// Where and how finely to refine, in scaled radial units (ρ = r/√(Rz₀)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSpec {
    /// spacing inside the zone
    pub fine_spacing: f64,
    /// inner end of the uniform zone
    pub zone_lo: f64,
    /// outer end of the uniform zone
    pub zone_hi: f64,
    /// growth of the spacing per unit distance from the zone (dimensionless)
    pub growth: f64,
    /// outer radius of the loaded domain
    pub outer: f64,
}

/// Nodes and ring edges.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// collocation radii ρ_i, starting at 0
    pub nodes: Vec<f64>,
    /// ring edges b_j (one more than nodes)
    pub edges: Vec<f64>,
}

impl GridSpec {
    /// The same grid with every spacing divided by `factor`.
    pub fn refined(&self, factor: f64) -> GridSpec {
        GridSpec {
            fine_spacing: self.fine_spacing / factor,
            growth: self.growth / factor,
            ..*self
        }
    }

    /// Local spacing s(ρ).
    fn spacing(&self, rho: f64) -> f64 {
        let d = (self.zone_lo - rho).max(rho - self.zone_hi).max(0.0);
        self.fine_spacing + self.growth * d
    }

    /// The number of nodes [`Self::build`] makes, in closed form (no grid is built): the
    /// uniform zone holds (ρ_hi − ρ_lo)/s_f cells and a graded stretch of length L beside it
    /// ln(1 + gL/s_f)/g (from dρ/di = s_f + g·d). Within a few nodes of the count.
    pub fn estimated_len(&self) -> f64 {
        let graded = |length: f64| {
            let length = length.max(0.0);
            if self.growth > 0.0 {
                (self.growth * length / self.fine_spacing).ln_1p() / self.growth
            } else {
                length / self.fine_spacing
            }
        };
        let lo = self.zone_lo.min(self.outer);
        let hi = self.zone_hi.clamp(lo, self.outer);
        2.0 + graded(lo) + (hi - lo) / self.fine_spacing + graded(self.outer - hi)
    }

    /// Build the grid (at least two nodes).
    pub fn build(&self) -> Grid {
        let mut nodes = vec![0.0];
        let mut rho = 0.0;
        while rho < self.outer {
            // midpoint rule for dρ/di = s(ρ): smooth grading on both sides of the zone
            let half = rho + 0.5 * self.spacing(rho);
            rho += self.spacing(half);
            nodes.push(rho);
        }
        let n = nodes.len();
        let mut edges = Vec::with_capacity(n + 1);
        edges.push(0.0);
        edges.extend(nodes.windows(2).map(|w| 0.5 * (w[0] + w[1])));
        edges.push(nodes[n - 1] + 0.5 * (nodes[n - 1] - nodes[n - 2]));
        Grid { nodes, edges }
    }
}

impl Grid {
    /// Number of nodes (= rings).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True if the grid has no nodes (never for a built grid).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Ring weights w_j = b_{j+1}² − b_j², so the scaled load 2∫P̄ρdρ is Σ w_j P̄_j.
    pub fn load_weights(&self) -> Vec<f64> {
        self.edges
            .windows(2)
            .map(|e| e[1] * e[1] - e[0] * e[0])
            .collect()
    }

    /// Linear interpolation of nodal values `f` at radius `rho` (constant beyond the ends).
    pub fn interpolate(&self, f: &[f64], rho: f64) -> f64 {
        let i = self.nodes.partition_point(|&x| x <= rho);
        if i == 0 {
            return f[0];
        }
        if i >= self.nodes.len() {
            return f[f.len() - 1];
        }
        let (x0, x1) = (self.nodes[i - 1], self.nodes[i]);
        let t = (rho - x0) / (x1 - x0);
        f[i - 1] + t * (f[i] - f[i - 1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> GridSpec {
        GridSpec {
            fine_spacing: 0.05,
            zone_lo: 1.0,
            zone_hi: 2.0,
            growth: 0.2,
            outer: 30.0,
        }
    }

    #[test]
    fn grid_is_uniform_in_the_zone_and_graded_outside() {
        let g = spec().build();
        for w in g.nodes.windows(2) {
            assert!(w[1] > w[0]);
            let mid = 0.5 * (w[0] + w[1]);
            if (1.1..1.9).contains(&mid) {
                assert!((w[1] - w[0] - 0.05).abs() < 1e-12);
            }
        }
        assert!(*g.nodes.last().unwrap() >= 30.0);
        assert_eq!(g.edges.len(), g.nodes.len() + 1);
    }

    #[test]
    fn weights_sum_to_the_disc_area() {
        let g = spec().build();
        let b = *g.edges.last().unwrap();
        let s: f64 = g.load_weights().iter().sum();
        assert!((s - b * b).abs() < 1e-10 * b * b);
    }

    #[test]
    fn estimated_length_is_within_a_few_nodes_of_the_built_grid() {
        for factor in [1.0, 2.0, 4.0, 16.0] {
            let s = spec().refined(factor);
            let (built, est) = (s.build().len() as f64, s.estimated_len());
            assert!((built - est).abs() <= 3.0 + 0.02 * built, "{built} {est}");
        }
    }

    #[test]
    fn refinement_halves_the_spacing() {
        let coarse = spec().build().len();
        let fine = spec().refined(2.0).build().len();
        assert!(
            (fine as f64 / coarse as f64 - 2.0).abs() < 0.1,
            "{coarse} {fine}"
        );
    }
}
