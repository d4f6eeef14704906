//! End conditions and loads of the discrete rods.
//!
//! - Supports are fixed degrees of freedom ([`FixedDofs`]): the solvers never move them, so a
//!   prescribed displacement is a fixed dof whose coordinate the caller sets before solving
//!   (displacement control). Clamped end = the first two nodes fixed (position and tangent);
//!   pinned end = the node fixed, the rod free to turn about it; free end = nothing fixed.
//!   The reaction at a fixed dof is the energy gradient there ([`FixedDofs::reactions`]).
//! - A clamped end can instead be the end node pinned plus [`ClampedEnd`], the bending energy
//!   of the end vertex against a fixed tangent t: W = (K/ℓ₀) |κb(t, x₁ − x₀)|², the vertex weight
//!   K/(2ℓ̄) with the half Voronoi cell ℓ̄ = ℓ₀/2 of an end node. This puts the clamp exactly at
//!   the end node (second-order accurate; fixing the first two nodes instead moves the clamp
//!   by about half a segment, a first-order error: ≈ 2 % in the Euler load at 50 segments).
//! - Dead point loads are an energy term, E = −Σ F·x_node ([`PointLoads`]), so that every force
//!   stays the gradient of an energy. Sign: F is the force applied to the node (nN); a
//!   compressive axial load P > 0 on an end pointing along +x is F = (−P, 0, 0).

use nalgebra::Vector3;

use super::energy::EnergyTerm;
use super::rod::Rod;
use super::rod_kernels::bend_vertex;

/// Which coordinates of the flat vector (3 per node) are held fixed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FixedDofs {
    fixed: Vec<bool>,
}

impl FixedDofs {
    /// Nothing fixed, for `nodes` nodes.
    pub fn free(nodes: usize) -> Self {
        FixedDofs {
            fixed: vec![false; 3 * nodes],
        }
    }

    /// Number of coordinates (3 × nodes).
    pub fn len(&self) -> usize {
        self.fixed.len()
    }

    /// True when there are no coordinates at all.
    pub fn is_empty(&self) -> bool {
        self.fixed.is_empty()
    }

    /// Fix one coordinate (`dof` = 3 × node + axis).
    pub fn fix(&mut self, dof: usize) -> &mut Self {
        self.fixed[dof] = true;
        self
    }

    /// Pinned end: the node's position is fixed, the rod may turn about it.
    pub fn pin(&mut self, node: usize) -> &mut Self {
        for a in 0..3 {
            self.fixed[3 * node + a] = true;
        }
        self
    }

    /// Clamped end: the end node and its neighbour are fixed, which fixes the end tangent.
    pub fn clamp(&mut self, end: usize, neighbour: usize) -> &mut Self {
        self.pin(end).pin(neighbour)
    }

    /// Is coordinate `dof` fixed?
    pub fn is_fixed(&self, dof: usize) -> bool {
        self.fixed[dof]
    }

    /// Indices of the free coordinates, ascending.
    pub fn free_dofs(&self) -> Vec<usize> {
        (0..self.fixed.len()).filter(|&k| !self.fixed[k]).collect()
    }

    /// Largest |component| of `grad` over the free coordinates: the force residual (nN).
    pub fn residual(&self, grad: &[f64]) -> f64 {
        grad.iter()
            .zip(&self.fixed)
            .filter(|(_, &f)| !f)
            .fold(0.0, |m, (g, _)| m.max(g.abs()))
    }

    /// Reaction forces (nN) at the fixed coordinates: the force the support exerts on the rod is
    /// −∂E/∂x, so the load the rod carries there is `grad[dof]`; returned as (dof, grad[dof]).
    pub fn reactions(&self, grad: &[f64]) -> Vec<(usize, f64)> {
        (0..self.fixed.len())
            .filter(|&k| self.fixed[k])
            .map(|k| (k, grad[k]))
            .collect()
    }
}

/// Dead (direction-fixed) point loads: E = −Σ F·x_node.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointLoads {
    loads: Vec<(usize, [f64; 3])>,
}

impl PointLoads {
    /// No loads.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add force `force` (nN) on node `node`.
    pub fn add(&mut self, node: usize, force: [f64; 3]) -> &mut Self {
        self.loads.push((node, force));
        self
    }

    /// Scale every load by `factor` (load stepping).
    pub fn scaled(&self, factor: f64) -> Self {
        PointLoads {
            loads: self
                .loads
                .iter()
                .map(|&(n, f)| (n, f.map(|v| v * factor)))
                .collect(),
        }
    }
}

impl EnergyTerm for PointLoads {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut energy = 0.0;
        for &(n, f) in &self.loads {
            for a in 0..3 {
                energy -= f[a] * x[3 * n + a];
                grad[3 * n + a] -= f[a];
            }
        }
        energy
    }

    fn hessian(&self, _x: &[f64], _out: &mut Vec<(usize, usize, f64)>) {}
}

/// Clamp of a rod end to a fixed tangent, as the bending energy of the end vertex (pin the end
/// node as well).
#[derive(Debug, Clone, PartialEq)]
pub struct ClampedEnd {
    end: usize,
    inner: usize,
    tangent: Vector3<f64>,
    weight: f64,
}

/// Which end of a rod.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RodEnd {
    /// the first node
    First,
    /// the last node
    Last,
}

impl ClampedEnd {
    /// Clamp end `end` of `rod`, whose nodes are at `x` (nm), to its current tangent.
    pub fn new(rod: &Rod, end: RodEnd, x: &[f64]) -> Self {
        let (first, last) = (rod.first_node(), rod.first_node() + rod.nodes() - 1);
        let (e, i) = match end {
            RodEnd::First => (first, first + 1),
            RodEnd::Last => (last, last - 1),
        };
        let p = |n: usize| Vector3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
        let edge = p(i) - p(e);
        ClampedEnd {
            end: e,
            inner: i,
            tangent: edge.normalize(),
            weight: rod.stiffness().bending / edge.norm(),
        }
    }

    fn edge(&self, x: &[f64]) -> Vector3<f64> {
        let p = |n: usize| Vector3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
        p(self.inner) - p(self.end)
    }
}

impl EnergyTerm for ClampedEnd {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let (w, g, _) = bend_vertex(&self.tangent, &self.edge(x), &Vector3::zeros(), self.weight);
        for a in 0..3 {
            grad[3 * self.inner + a] += g[3 + a];
            grad[3 * self.end + a] -= g[3 + a];
        }
        w
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        let (_, _, h) = bend_vertex(&self.tangent, &self.edge(x), &Vector3::zeros(), self.weight);
        for (na, sa) in [(self.inner, 1.0), (self.end, -1.0)] {
            for (nb, sb) in [(self.inner, 1.0), (self.end, -1.0)] {
                for r in 0..3 {
                    for c in 0..3 {
                        out.push((3 * na + r, 3 * nb + c, sa * sb * h[(3 + r, 3 + c)]));
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamp_pin_and_residual_skip_fixed_dofs() {
        let mut fixed = FixedDofs::free(3);
        fixed.clamp(0, 1).fix(7);
        assert_eq!(fixed.free_dofs(), vec![6, 8]);
        let g = [9.0, 9.0, 9.0, 9.0, 9.0, 9.0, 1.0, 9.0, -2.0];
        assert_eq!(fixed.residual(&g), 2.0);
        assert_eq!(fixed.reactions(&g).len(), 7);
    }

    #[test]
    fn clamp_gradient_and_hessian_match_finite_differences() {
        use crate::discrete::rod::{straight_points, RodStiffness};
        let pts = straight_points([0.0; 3], [1.0, 0.5, 0.0], 3.0, 3);
        let stiff = RodStiffness {
            bending: 2.0,
            axial: 5.0,
        };
        let rod = Rod::straight(0, &pts, stiff).unwrap();
        let x0: Vec<f64> = pts.iter().flatten().copied().collect();
        let clamp = ClampedEnd::new(&rod, RodEnd::Last, &x0);
        let mut x = x0.clone();
        x[6] += 0.2;
        x[7] -= 0.3;
        x[11] += 0.1;
        let mut g = vec![0.0; x.len()];
        let w = clamp.energy_gradient(&x, &mut g);
        assert!(w > 0.0 && g[..6].iter().all(|&v| v == 0.0));
        let mut trip = Vec::new();
        clamp.hessian(&x, &mut trip);
        let h = 1e-6;
        for k in 6..12 {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[k] += h;
            xm[k] -= h;
            let (mut gp, mut gm) = (vec![0.0; 12], vec![0.0; 12]);
            let fd = (clamp.energy_gradient(&xp, &mut gp) - clamp.energy_gradient(&xm, &mut gm))
                / (2.0 * h);
            // central differences of O(1) data: error ~1e-10
            assert!((fd - g[k]).abs() < 1e-7);
            for r in 6..12 {
                let hk: f64 = trip
                    .iter()
                    .filter(|t| t.0 == r && t.1 == k)
                    .map(|t| t.2)
                    .sum();
                assert!(((gp[r] - gm[r]) / (2.0 * h) - hk).abs() < 1e-7);
            }
        }
        // at the clamped tangent the energy vanishes
        assert_eq!(clamp.energy_gradient(&x0, &mut g), 0.0);
    }

    #[test]
    fn point_load_energy_is_minus_work_and_gradient_is_minus_force() {
        let mut loads = PointLoads::new();
        loads.add(1, [1.0, -2.0, 0.5]);
        let x = [0.0, 0.0, 0.0, 3.0, 4.0, 5.0];
        let mut g = [0.0; 6];
        let e = loads.scaled(2.0).energy_gradient(&x, &mut g);
        assert_eq!(e, -2.0 * (3.0 - 8.0 + 2.5));
        assert_eq!(g, [0.0, 0.0, 0.0, -2.0, 4.0, -1.0]);
    }
}
