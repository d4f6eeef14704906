//! The total potential energy of the discrete model as a sum of terms, each a function of the
//! flat vector of node coordinates x (three per node, nm).
//!
//! Every physical effect — stretching, bending, tube–tube van der Waals, platens — is one
//! [`EnergyTerm`]; solvers (FIRE, Newton) see only the sum. A term's gradient must be the exact
//! derivative of its energy, and its Hessian the exact derivative of its gradient (each term's
//! tests check both by finite differences).

/// One additive term of the potential energy.
pub trait EnergyTerm: Sync {
    /// Bring internal state (neighbour lists, ...) up to date for configuration `x`. Solvers
    /// call this once per iterate, before any evaluation there. Default: nothing to do.
    fn prepare(&mut self, _x: &[f64]) {}

    /// Energy (aJ) at `x`; the gradient (nN) is **added** into `grad`.
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64;

    /// The Hessian (nN/nm) at `x`, **appended** as (row, col, value) entries of the full
    /// symmetric matrix (both triangles; duplicates are summed by the solver).
    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>);
}
