//! Single-rod problems with their supports and loads, ready for either solver: the clamped
//! cantilever under a dead tip load (Bisshopp & Drucker, Q. Appl. Math. 3, 272, 1945) and the
//! pinned–pinned column under end displacement (the post-buckled elastica). The rod lies along
//! +x from the origin; bending happens in the x–y plane.

use super::constraints::{ClampedEnd, FixedDofs, PointLoads, RodEnd};
use super::rod::{straight_points, Rod, RodError, RodStiffness};
use super::solve::{Info, SolveError, Sum};
use super::solve_fire::{minimize_fire, FireParams};
use super::solve_newton::{minimize_newton, NewtonParams};

/// One rod, its supports and loads, and its current configuration.
#[derive(Debug, Clone)]
pub struct RodProblem {
    /// the rod (nodes 0 … n)
    pub rod: Rod,
    /// tangent clamp at the first node, if clamped
    pub clamp: Option<ClampedEnd>,
    /// dead loads
    pub loads: PointLoads,
    /// supports and prescribed coordinates
    pub fixed: FixedDofs,
    /// node coordinates (nm), 3 per node
    pub x: Vec<f64>,
}

impl RodProblem {
    /// Straight cantilever of `segments` segments and length `length` (nm) along +x, clamped at
    /// node 0 (pinned + tangent clamp), free at node n, carrying the dead force `tip` (nN) there.
    pub fn cantilever(
        segments: usize,
        length: f64,
        stiffness: RodStiffness,
        tip: [f64; 3],
    ) -> Result<Self, RodError> {
        let rest = straight_points([0.0; 3], [1.0, 0.0, 0.0], length, segments);
        let rod = Rod::straight(0, &rest, stiffness)?;
        let x: Vec<f64> = rest.iter().flatten().copied().collect();
        let clamp = Some(ClampedEnd::new(&rod, RodEnd::First, &x));
        let mut fixed = FixedDofs::free(rod.nodes());
        fixed.pin(0);
        let mut loads = PointLoads::new();
        loads.add(segments, tip);
        Ok(RodProblem {
            rod,
            clamp,
            loads,
            fixed,
            x,
        })
    }

    /// Pinned–pinned column along +x: node 0 pinned, node n held on the axis (y = z = 0) with its
    /// x coordinate prescribed (displacement control, see [`RodProblem::set_end_shortening`]).
    /// The start shape carries the imperfection y = `imperfection` · sin(πs/L) (nm).
    pub fn pinned_column(
        segments: usize,
        length: f64,
        stiffness: RodStiffness,
        imperfection: f64,
    ) -> Result<Self, RodError> {
        let rest = straight_points([0.0; 3], [1.0, 0.0, 0.0], length, segments);
        let rod = Rod::straight(0, &rest, stiffness)?;
        let mut x: Vec<f64> = rest.iter().flatten().copied().collect();
        for i in 0..=segments {
            x[3 * i + 1] = imperfection * (std::f64::consts::PI * i as f64 / segments as f64).sin();
        }
        let mut fixed = FixedDofs::free(rod.nodes());
        fixed.pin(0).pin(segments);
        Ok(RodProblem {
            rod,
            clamp: None,
            loads: PointLoads::new(),
            fixed,
            x,
        })
    }

    /// Index of the last node.
    pub fn tip(&self) -> usize {
        self.rod.nodes() - 1
    }

    /// Prescribe the end shortening Δ (nm) of the pinned column: x_n = L − Δ, the x coordinates
    /// of the other nodes scaled with it (a start guess without a crushed end segment).
    pub fn set_end_shortening(&mut self, shortening: f64) {
        let n = self.tip();
        let scale = (self.rod.rest_length() - shortening) / self.x[3 * n];
        for i in 0..=n {
            self.x[3 * i] *= scale;
        }
    }

    /// The total energy as one term.
    fn model(&mut self) -> Sum<'_> {
        let mut terms: Vec<&mut dyn super::energy::EnergyTerm> =
            vec![&mut self.rod, &mut self.loads];
        if let Some(c) = self.clamp.as_mut() {
            terms.push(c);
        }
        Sum(terms)
    }

    /// Energy (aJ) and gradient (nN) at the current configuration.
    pub fn energy_gradient(&mut self) -> (f64, Vec<f64>) {
        let x = self.x.clone();
        let mut g = vec![0.0; x.len()];
        let e = super::energy::EnergyTerm::energy_gradient(&self.model(), &x, &mut g);
        (e, g)
    }

    /// Axial force (nN, > 0 compressive) the column carries: the reaction at the prescribed
    /// end, −∂E/∂x_n.
    pub fn end_load(&mut self) -> f64 {
        let n = self.tip();
        -self.energy_gradient().1[3 * n]
    }

    /// Solve for equilibrium by Newton from the current configuration.
    pub fn solve_newton(&mut self, params: &NewtonParams) -> Result<Info, SolveError> {
        let mut x = std::mem::take(&mut self.x);
        let fixed = self.fixed.clone();
        let result = minimize_newton(&mut self.model(), &fixed, &mut x, params);
        self.x = x;
        result
    }

    /// Solve for equilibrium by FIRE from the current configuration.
    pub fn solve_fire(&mut self, params: &FireParams) -> Result<Info, SolveError> {
        let mut x = std::mem::take(&mut self.x);
        let fixed = self.fixed.clone();
        let result = minimize_fire(&mut self.model(), &fixed, &mut x, params);
        self.x = x;
        result
    }
}
