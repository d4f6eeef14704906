//! End conditions and loads of the discrete rods (issue 7, item 1).
//!
//! - Supports are fixed degrees of freedom ([`FixedDofs`]): the solvers never move them, so a
//!   prescribed displacement is a fixed dof whose coordinate the caller sets before solving
//!   (displacement control). Clamped end = the first two nodes fixed (position and tangent);
//!   pinned end = the node fixed, the rod free to turn about it; free end = nothing fixed.
//!   The reaction at a fixed dof is the energy gradient there ([`FixedDofs::reactions`]).
//! - Dead point loads are an energy term, E = −Σ F·x_node ([`PointLoads`]), so that every force
//!   stays the gradient of an energy. Sign: F is the force applied to the node (nN); a
//!   compressive axial load P > 0 on an end pointing along +x is F = (−P, 0, 0).

use super::energy::EnergyTerm;

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
