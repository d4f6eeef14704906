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

    /// The Hessian's entries on and below the diagonal (row ≥ column), appended in the order
    /// [`Self::hessian`] lists them: what a solver that stores one triangle of the symmetric
    /// matrix assembles. Default: [`Self::hessian`] filtered; a term with many entries lists
    /// the lower triangle directly.
    fn hessian_lower(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        let start = out.len();
        self.hessian(x, out);
        let mut kept = start;
        for k in start..out.len() {
            if out[k].0 >= out[k].1 {
                out[kept] = out[k];
                kept += 1;
            }
        }
        out.truncate(kept);
    }
}

/// Finite-difference checks shared by the terms' tests.
#[cfg(test)]
pub(crate) mod fd {
    use super::EnergyTerm;

    /// The largest errors of `term`'s gradient against central differences of its energy and
    /// of its Hessian against central differences of its gradient, at `x` with step `h`, each
    /// relative to the largest entry of the gradient and of the Hessian; asserts on the way
    /// that its lower triangle ([`EnergyTerm::hessian_lower`]) is its Hessian's, entry by entry.
    pub(crate) fn relative_errors(term: &dyn EnergyTerm, x: &[f64], h: f64) -> (f64, f64) {
        let n = x.len();
        let mut g = vec![0.0; n];
        term.energy_gradient(x, &mut g);
        let mut entries = Vec::new();
        term.hessian(x, &mut entries);
        let mut lower = Vec::new();
        term.hessian_lower(x, &mut lower);
        let below: Vec<_> = entries.iter().copied().filter(|e| e.0 >= e.1).collect();
        assert_eq!(
            lower, below,
            "hessian_lower lists the entries of hessian on and below the diagonal, in its order"
        );
        let mut hess = vec![0.0; n * n];
        for (r, c, v) in entries {
            hess[r * n + c] += v;
        }
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        let (gscale, hscale) = (largest(&g), largest(&hess));
        let (mut eg, mut eh) = (0.0f64, 0.0f64);
        for k in 0..n {
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[k] += h;
            xm[k] -= h;
            let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
            let fd = (term.energy_gradient(&xp, &mut gp) - term.energy_gradient(&xm, &mut gm))
                / (2.0 * h);
            eg = eg.max((fd - g[k]).abs() / gscale);
            for j in 0..n {
                eh = eh.max(((gp[j] - gm[j]) / (2.0 * h) - hess[j * n + k]).abs() / hscale);
            }
        }
        (eg, eh)
    }
}
