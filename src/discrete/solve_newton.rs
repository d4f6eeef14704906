//! Newton minimisation on the sparse Hessian with a shift and an Armijo line search.
//!
//! Each iteration: assemble H (free coordinates only) and factor H + μI by sparse Cholesky. The
//! first shift tried is the last iteration's divided by `shift_growth` (μ = 0 once that falls
//! below `shift_start` · max|H_kk|, and after an unshifted iteration); while the factorisation
//! fails (H indefinite, e.g. past a buckling load) μ grows by `shift_growth`, from the last
//! nonzero shift divided by `shift_growth` when it was 0 (Nocedal & Wright, Numerical
//! Optimization, Alg. 3.3, with the shift remembered across iterations: a descent through an
//! indefinite region does not pay a failed unshifted factorisation, nor climb from 1e-10 · max|H_kk|,
//! at every iteration). The step p solves (H + μI) p = −g, a descent direction; the step length α
//! shortens from 1 — to the minimiser of the cubic through the energy and slope at 0 and at
//! the rejected trial, within [α/10, α/2] — until E(x + αp) ≤ E(x) + c₁ α gᵀp (Armijo), or —
//! once energy differences sink into round-off — until the residual decreases. A shifted step accepted at α = 1 is doubled
//! while the energy keeps falling (up to [`MAX_EXPANSION`] times): the shift holds the step along
//! soft directions to about |g|/μ, often far short of where the energy stops falling.
//!
//! The Hessian's entries reach the sparse system through [`FreeHessian`], which keeps the map
//! from the model's entries to the system's values while the model lists the same entries, and
//! the symbolic factorisation is kept while the compressed pattern stays the same.

use super::constraints::FixedDofs;
use super::energy::EnergyTerm;
use super::solve::{Evaluator, Info, SolveError};
use crate::numerics::newton::{self, armijo, NewtonError, NewtonProblem, Trial};
use crate::numerics::sparse::{Pattern, SparseError, SparseSystem};

/// Newton settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonParams {
    /// absolute force-residual tolerance (nN)
    pub atol: f64,
    /// tolerance relative to the starting residual
    pub rtol: f64,
    /// iteration limit
    pub max_iterations: usize,
    /// Armijo sufficient-decrease constant c₁
    pub armijo: f64,
    /// step halvings before the line search gives up
    pub max_backtracks: usize,
    /// first shift, relative to the largest diagonal entry of H
    pub shift_start: f64,
    /// factor by which the shift grows (and the remembered shift shrinks)
    pub shift_growth: f64,
    /// shifted factorisations tried per iteration before giving up
    pub max_shifts: usize,
}

impl Default for NewtonParams {
    fn default() -> Self {
        NewtonParams {
            atol: 1e-10,
            rtol: 1e-8,
            max_iterations: 200,
            armijo: 1e-4,
            max_backtracks: 40,
            shift_start: 1e-10,
            shift_growth: 10.0,
            max_shifts: 40,
        }
    }
}

impl NewtonParams {
    /// The Newton loop's part of the settings (the convergence test is on the first residual,
    /// without a round-off stall test).
    pub fn newton(&self) -> newton::NewtonParams {
        newton::NewtonParams {
            max_iterations: self.max_iterations,
            rtol: self.rtol,
            atol: self.atol,
            max_backtracks: self.max_backtracks,
            armijo: self.armijo,
            stagnation: 0.0,
        }
    }
}

/// Largest multiple of the Newton step the expansion past an instability tries.
const MAX_EXPANSION: f64 = 64.0;

/// Relative size of energy differences that count as round-off (double precision summing a few
/// thousand terms).
const ENERGY_NOISE: f64 = 1e-12;

/// Minimise the energy of `model` over the coordinates of `x` not fixed in `fixed`, starting
/// from `x` (nm), which holds the solution on success.
pub fn minimize_newton<E: EnergyTerm + ?Sized>(
    model: &mut E,
    fixed: &FixedDofs,
    x: &mut [f64],
    params: &NewtonParams,
) -> Result<Info, SolveError> {
    let free = fixed.free_dofs();
    let d = Descent::new(model, fixed, &free, params, x)?;
    let mut index = vec![usize::MAX; x.len()];
    for (k, &dof) in free.iter().enumerate() {
        index[dof] = k;
    }
    let newton = params.newton();
    let tol = newton.tolerance(d.residual);
    let mut problem = Shifted {
        d,
        hessian: FreeHessian::new(&index, free.len()),
        shift: Shift::default(),
        trip: Vec::new(),
        tol,
        slope: 0.0,
        scale: 0.0,
    };
    let solved = newton::solve(&mut problem, x, &newton);
    let d = &mut problem.d;
    // the last evaluation may have been of a trial not taken: leave the model current at x
    d.ev.model.prepare(x);
    match solved {
        Ok(info) => Ok(Info {
            energy: d.energy,
            residual: d.residual,
            tolerance: tol,
            history: info.residuals,
            cost: d.ev.finish(),
        }),
        Err(NewtonError::NoConvergence { .. }) => Err(SolveError::NoConvergence {
            residual: d.residual,
            tolerance: tol,
            cost: d.ev.finish(),
        }),
        Err(NewtonError::LineSearch { .. }) => Err(SolveError::LineSearch {
            residual: d.residual,
            cost: d.ev.finish(),
        }),
        Err(NewtonError::Problem(e)) => Err(e),
    }
}

/// The discrete engine's plug-ins to the Newton loop: the max norm of the free gradient against
/// the first one, the step of the shifted Cholesky ([`Shift`]), a trial accepted on Armijo's
/// decrease of the energy — or, once energy differences sink into round-off, on a decrease of
/// the residual — a trial that folds a vertex rejected, and a full shifted step doubled while
/// the energy keeps falling.
struct Shifted<'a, E: EnergyTerm + ?Sized> {
    d: Descent<'a, E>,
    hessian: FreeHessian<'a>,
    shift: Shift,
    /// the model's Hessian entries (scratch)
    trip: Vec<(usize, usize, f64)>,
    /// the stopping tolerance (nN)
    tol: f64,
    /// gᵀp of the current step, and Σ|g_k x_k| (the scale of the energy's round-off)
    slope: f64,
    scale: f64,
}

impl<E: EnergyTerm + ?Sized> NewtonProblem for Shifted<'_, E> {
    type Error = SolveError;

    fn residual(&mut self, _x: &[f64]) -> Result<f64, SolveError> {
        Ok(self.d.residual)
    }

    fn converged(&self, residuals: &[f64]) -> bool {
        residuals.last().is_some_and(|&r| r <= self.tol)
    }

    fn direction(&mut self, x: &[f64]) -> Result<Vec<f64>, SolveError> {
        let d = &mut self.d;
        d.ev.cost.iterations += 1;
        self.trip.clear();
        // the last evaluation may have been of a trial not taken (an expansion that raised
        // the energy), and the neighbour list rebuilt there need not hold the pairs in reach
        // at x
        d.ev.model.prepare(x);
        d.ev.model.hessian_lower(x, &mut self.trip);
        d.ev.cost.hessian_evaluations += 1;
        self.hessian.load(&self.trip)?;
        let rhs: Vec<f64> = d.free.iter().map(|&dof| -d.grad[dof]).collect();
        let step = self.shift.solve(
            &mut self.hessian,
            &rhs,
            d.params,
            &mut d.ev.cost.factorizations,
        )?;
        self.slope = d.slope_along(&step);
        self.scale = d.free.iter().map(|&k| (d.grad[k] * x[k]).abs()).sum();
        Ok(step)
    }

    fn try_step(&mut self, x: &mut [f64], step: &[f64], alpha: f64) -> Result<Trial, SolveError> {
        self.d.try_step(x, step, alpha, self.slope, self.scale)
    }

    /// The minimiser of the cubic through the energy and slope at 0 and at the rejected `s`
    /// (Nocedal & Wright, Numerical Optimization, eq. 3.59), kept within [s/10, s/2]; half of
    /// `s` after a non-finite trial, and where the energy change is within a hundred times its
    /// round-off (the cubic would fit noise; there the trials are judged on the residual).
    fn shorter(&self, s: f64) -> f64 {
        match self.d.rejected {
            Some((alpha, e1, slope1))
                if alpha == s
                    && (e1 - self.d.energy).abs() > 100.0 * self.d.noise(e1, self.scale) =>
            {
                cubic_step(self.d.energy, self.slope, s, e1, slope1).clamp(0.1 * s, 0.5 * s)
            }
            _ => 0.5 * s,
        }
    }

    /// Past an instability the shift limits the step along the soft directions to about
    /// |g|/μ, and the energy keeps falling well beyond it: double the step while it does.
    fn stepped(&mut self, x: &mut [f64], step: &[f64], alpha: f64) {
        if alpha == 1.0 && self.shift.prev > 0.0 {
            self.d.expand(x, step);
        }
    }
}

/// The shift μ of H + μI across iterations.
#[derive(Default)]
struct Shift {
    /// the last iteration's
    prev: f64,
    /// the last nonzero one
    memory: f64,
}

impl Shift {
    /// The step p of (H + μI) p = `rhs` with the first shift of the ladder that factors
    /// (counted in `factorizations`). The ladder starts at a tenth of the last iteration's
    /// shift (0 below the floor) and climbs from 0 to the floor, or to a tenth of the last
    /// nonzero shift, then by `shift_growth`. Two rungs are factorised at once
    /// ([`SparseSystem::factor_spd_first_of`]: the second on an idle core, or only if the
    /// first fails), so the shift taken — and the path — is the one trying them in turn gives.
    fn solve(
        &mut self,
        hessian: &mut FreeHessian,
        rhs: &[f64],
        params: &NewtonParams,
        factorizations: &mut usize,
    ) -> Result<Vec<f64>, SolveError> {
        let floor = params.shift_start * hessian.diag_max;
        let next = |shift: f64| {
            if shift == 0.0 {
                floor.max(self.memory / params.shift_growth)
            } else {
                shift * params.shift_growth
            }
        };
        let mut shift = if self.prev / params.shift_growth >= floor {
            self.prev / params.shift_growth
        } else {
            0.0
        };
        // the rung of `shift` on the ladder: `params.max_shifts` rungs may fail
        let mut rung = 0;
        let step = loop {
            if rung < params.max_shifts {
                let higher = next(shift);
                match hessian.solve_shifted_first_of(shift, higher, rhs, factorizations) {
                    Ok((p, second)) => {
                        if second {
                            shift = higher;
                        }
                        break p;
                    }
                    Err(SparseError::NotPositiveDefinite) if rung + 2 <= params.max_shifts => {
                        shift = next(higher);
                        rung += 2;
                    }
                    Err(e) => return Err(e.into()),
                }
            } else {
                *factorizations += 1;
                break hessian.solve_shifted(shift, rhs)?;
            }
        };
        self.prev = shift;
        if shift > 0.0 {
            self.memory = shift;
        }
        Ok(step)
    }
}

/// The iterate's energy, gradient and residual, with the evaluator and the line search's
/// scratch space.
struct Descent<'a, E: EnergyTerm + ?Sized> {
    ev: Evaluator<'a, E>,
    fixed: &'a FixedDofs,
    free: &'a [usize],
    params: &'a NewtonParams,
    grad: Vec<f64>,
    energy: f64,
    residual: f64,
    trial: Vec<f64>,
    grad_trial: Vec<f64>,
    /// the last rejected trial with a finite energy: (α, E, slope along the step there)
    rejected: Option<(f64, f64, f64)>,
}

impl<'a, E: EnergyTerm + ?Sized> Descent<'a, E> {
    fn new(
        model: &'a mut E,
        fixed: &'a FixedDofs,
        free: &'a [usize],
        params: &'a NewtonParams,
        x: &[f64],
    ) -> Result<Self, SolveError> {
        let mut ev = Evaluator::new(model, fixed, x)?;
        let mut grad = vec![0.0; x.len()];
        let energy = ev.eval(x, &mut grad)?;
        let residual = fixed.residual(&grad);
        Ok(Descent {
            ev,
            fixed,
            free,
            params,
            grad,
            energy,
            residual,
            trial: x.to_vec(),
            grad_trial: vec![0.0; x.len()],
            rejected: None,
        })
    }

    /// The trial x + α·`step` (`slope` = gᵀp, `scale` = Σ|g_k x_k|): taken (x moved there) on
    /// Armijo's decrease, or on a lower residual where the energies agree to round-off; an
    /// unphysical trial point (a folded vertex) is rejected.
    fn try_step(
        &mut self,
        x: &mut [f64],
        step: &[f64],
        alpha: f64,
        slope: f64,
        scale: f64,
    ) -> Result<Trial, SolveError> {
        self.trial.copy_from_slice(x);
        for (&d, p) in self.free.iter().zip(step) {
            self.trial[d] += alpha * p;
        }
        self.rejected = None;
        let e_trial = match self.ev.eval(&self.trial, &mut self.grad_trial) {
            Ok(e) => e,
            Err(SolveError::NonFinite { .. }) => {
                return Ok(Trial::Rejected("non-finite energy".into()))
            }
            Err(e) => return Err(e),
        };
        let r_trial = self.fixed.residual(&self.grad_trial);
        let noise = self.noise(e_trial, scale);
        let sufficient = armijo(self.energy, e_trial, self.params.armijo, alpha, slope, 0.0);
        let flat = (e_trial - self.energy).abs() <= noise && r_trial < self.residual;
        if sufficient || flat {
            self.take(x, e_trial);
            return Ok(Trial::Accepted);
        }
        let slope_trial = free_dot(self.free, &self.grad_trial, step);
        self.rejected = Some((alpha, e_trial, slope_trial));
        Ok(Trial::Rejected(format!(
            "energy {:.6e} → {e_trial:.6e}",
            self.energy
        )))
    }

    /// From the full step taken, double it while the energy keeps falling (up to
    /// [`MAX_EXPANSION`] times the step) — tried only while the energy still falls along the
    /// step where it stands (gᵀp < 0 with the gradient already in hand): where it has started
    /// to rise, a doubled step almost never lowers it, and each trial costs an evaluation.
    fn expand(&mut self, x: &mut [f64], step: &[f64]) {
        let mut alpha = 1.0;
        let mut expand = 2.0;
        while expand <= MAX_EXPANSION && self.slope_along(step) < 0.0 {
            for (&d, p) in self.free.iter().zip(step) {
                self.trial[d] = x[d] + (expand - alpha) * p;
            }
            let Ok(e_trial) = self.ev.eval(&self.trial, &mut self.grad_trial) else {
                break;
            };
            if e_trial >= self.energy {
                break;
            }
            self.take(x, e_trial);
            alpha = expand;
            expand *= 2.0;
        }
    }

    /// gᵀp at the current iterate along `step` (over the free coordinates).
    fn slope_along(&self, step: &[f64]) -> f64 {
        free_dot(self.free, &self.grad, step)
    }

    /// The round-off of an energy difference between the iterate and a trial of energy
    /// `e_trial` (`scale` = Σ|g_k x_k|).
    fn noise(&self, e_trial: f64, scale: f64) -> f64 {
        ENERGY_NOISE * (self.energy.abs().max(e_trial.abs()) + scale)
    }

    /// Move to the trial point, of energy `e_trial`.
    fn take(&mut self, x: &mut [f64], e_trial: f64) {
        x.copy_from_slice(&self.trial);
        std::mem::swap(&mut self.grad, &mut self.grad_trial);
        self.energy = e_trial;
        self.residual = self.fixed.residual(&self.grad);
    }
}

/// Σ g[k] p_i over the free coordinates k = `free`[i] (a full-length gradient `g` against a
/// step `p` over the free coordinates).
fn free_dot(free: &[usize], g: &[f64], p: &[f64]) -> f64 {
    free.iter().zip(p).map(|(&k, p)| g[k] * p).sum()
}

/// The minimiser in (0, s) of the cubic with value `e0` and slope `slope0` < 0 at 0, `e1` and
/// `slope1` at `s` (Nocedal & Wright eq. 3.59); where the cubic has no minimiser there, the
/// minimiser of the quadratic through `e0`, `slope0` and `e1`.
fn cubic_step(e0: f64, slope0: f64, s: f64, e1: f64, slope1: f64) -> f64 {
    let d1 = slope0 + slope1 + 3.0 * (e0 - e1) / s;
    let disc = d1 * d1 - slope0 * slope1;
    if disc >= 0.0 {
        let d2 = disc.sqrt();
        let a = s - s * (slope1 + d2 - d1) / (slope1 - slope0 + 2.0 * d2);
        if a.is_finite() && a > 0.0 && a < s {
            return a;
        }
    }
    let q = -slope0 * s * s / (2.0 * (e1 - e0 - slope0 * s));
    if q.is_finite() && q > 0.0 {
        q
    } else {
        0.5 * s
    }
}

/// The Hessian over the free coordinates as a sparse system: its lower triangle, then a
/// diagonal that carries the Newton loop's shift. The model lists only the entries on and
/// below the diagonal ([`EnergyTerm::hessian_lower`]; a turf's contacts would list 144 entries
/// per pair, 78 of them needed). The map from the model's entries (full numbering) to the
/// compressed values is kept while the model lists the same entries in the same order, so an
/// iteration only sums values into their slots, in the model's order. When the list changes,
/// the compressed pattern of the unchanged head of the list (the rods, whose entries never
/// change, come before the contacts) is kept and only the rest is sorted and merged into it;
/// the sparse system keeps its symbolic factorisation if the compressed pattern is unchanged.
struct FreeHessian<'a> {
    /// free number of each coordinate (usize::MAX: fixed)
    index: &'a [usize],
    /// number of free coordinates
    free: usize,
    /// (row, column) of the model's entries the map was built for
    entries: Vec<(usize, usize)>,
    /// for each entry, its slot in `values` (usize::MAX: dropped — fixed or upper triangle)
    slot: Vec<usize>,
    /// slot of each free coordinate's diagonal, where the shift goes
    diagonal: Vec<usize>,
    /// the compressed pattern of the kept entries among the first `head_len` of the list
    head: Option<Pattern>,
    head_len: usize,
    /// the compressed values of the Hessian, and of two shifted ones (scratch)
    values: Vec<f64>,
    shifted: Vec<f64>,
    shifted_higher: Vec<f64>,
    /// largest |diagonal entry| of the Hessian itself
    diag_max: f64,
    system: Option<SparseSystem>,
}

impl<'a> FreeHessian<'a> {
    fn new(index: &'a [usize], free: usize) -> Self {
        FreeHessian {
            index,
            free,
            entries: Vec::new(),
            slot: Vec::new(),
            diagonal: Vec::new(),
            head: None,
            head_len: 0,
            values: Vec::new(),
            shifted: Vec::new(),
            shifted_higher: Vec::new(),
            diag_max: 0.0,
            system: None,
        }
    }

    /// Take the model's entries `trip`. Where they bring a new pattern, its symbolic analysis
    /// runs on a second rayon worker while this thread sums the values.
    fn load(&mut self, trip: &[(usize, usize, f64)]) -> Result<(), SparseError> {
        let changed = trip
            .iter()
            .zip(&self.entries)
            .position(|(t, e)| t.0 != e.0 || t.1 != e.1)
            .or((trip.len() != self.entries.len()).then(|| trip.len().min(self.entries.len())));
        if let Some(first) = changed.or(self.system.is_none().then_some(0)) {
            self.remap(trip, first)?;
        }
        let system = self
            .system
            .as_mut()
            .expect("a system after the first remap");
        let (values, slot) = (&mut self.values, &self.slot);
        self.diag_max = if system.analysed() {
            sum_into_slots(trip, slot, values)
        } else {
            let (analysed, diag_max) =
                rayon::join(|| system.analyse(), || sum_into_slots(trip, slot, values));
            analysed?;
            diag_max
        };
        Ok(())
    }

    /// The free lower-triangle positions of the entries of `trip`.
    fn kept(&self, trip: &[(usize, usize, f64)]) -> Vec<(usize, usize)> {
        trip.iter()
            .map(|&(r, c, _)| (self.index[r], self.index[c]))
            .filter(|&(ri, ci)| ri != usize::MAX && ci != usize::MAX && ri >= ci)
            .collect()
    }

    /// Rebuild the map and the system's pattern for the entries of `trip`, which agree with
    /// the last list up to entry `first`.
    fn remap(&mut self, trip: &[(usize, usize, f64)], first: usize) -> Result<(), SparseError> {
        if self.head.is_none() || first < self.head_len {
            // the first list is the head; later the head shrinks to what stays the same
            self.head_len = if self.head.is_none() {
                trip.len()
            } else {
                first
            };
            self.head = Some(Pattern::new(self.free, &self.kept(&trip[..self.head_len]))?);
        }
        let head = self.head.as_ref().expect("head pattern just built");
        let mut rest = self.kept(&trip[self.head_len..]);
        rest.extend((0..self.free).map(|k| (k, k)));
        let pattern = head.extended(&rest)?;
        self.entries.clear();
        self.entries.extend(trip.iter().map(|t| (t.0, t.1)));
        self.slot.clear();
        let mut slots = pattern.slots().iter();
        for &(r, c, _) in trip {
            let (ri, ci) = (self.index[r], self.index[c]);
            self.slot
                .push(if ri != usize::MAX && ci != usize::MAX && ri >= ci {
                    *slots.next().expect("one slot per kept entry")
                } else {
                    usize::MAX
                });
        }
        self.diagonal = slots.copied().collect();
        self.values.resize(pattern.nnz(), 0.0);
        match &mut self.system {
            Some(s) => s.set_pattern(pattern),
            None => {
                self.system = Some(SparseSystem::with_pattern(pattern));
                Ok(())
            }
        }
    }

    /// Solve (H + shift·I) p = rhs by Cholesky.
    fn solve_shifted(&mut self, shift: f64, rhs: &[f64]) -> Result<Vec<f64>, SparseError> {
        Self::shift_into(&self.values, &self.diagonal, shift, &mut self.shifted);
        let system = self.system.as_mut().ok_or(SparseError::NoFactor)?;
        system.solve_spd_compressed(&self.shifted, rhs)
    }

    /// Solve (H + μI) p = rhs by Cholesky with the first of `shift`, `higher` for which H + μI
    /// factors ([`SparseSystem::factor_spd_first_of`]); with p, whether it was `higher`.
    fn solve_shifted_first_of(
        &mut self,
        shift: f64,
        higher: f64,
        rhs: &[f64],
        factorizations: &mut usize,
    ) -> Result<(Vec<f64>, bool), SparseError> {
        Self::shift_into(&self.values, &self.diagonal, shift, &mut self.shifted);
        Self::shift_into(
            &self.values,
            &self.diagonal,
            higher,
            &mut self.shifted_higher,
        );
        let system = self.system.as_mut().ok_or(SparseError::NoFactor)?;
        let second =
            system.factor_spd_first_of(&self.shifted, &self.shifted_higher, factorizations)?;
        Ok((system.solve(rhs)?, second))
    }

    /// `values` with `shift` added at the `diagonal` slots, into `out`.
    fn shift_into(values: &[f64], diagonal: &[usize], shift: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(values);
        for &d in diagonal {
            out[d] += shift;
        }
    }
}

/// The entries `trip` summed into the compressed `values` at their `slot`s (`usize::MAX`:
/// dropped); returns the largest |diagonal entry|.
fn sum_into_slots(trip: &[(usize, usize, f64)], slot: &[usize], values: &mut [f64]) -> f64 {
    values.iter_mut().for_each(|v| *v = 0.0);
    let mut diag_max = 0.0_f64;
    for (t, &k) in trip.iter().zip(slot) {
        if k != usize::MAX {
            values[k] += t.2;
            if t.0 == t.1 {
                diag_max = diag_max.max(t.2.abs());
            }
        }
    }
    diag_max
}

/// Whether `x` is a strict local minimum of `model` over the free coordinates: its Hessian
/// there admits an unshifted Cholesky factorisation. A converged Newton solve can sit on a
/// saddle (a straight rod loaded beyond its Euler load is in equilibrium, but unstable): this
/// tells the two apart.
pub fn is_local_minimum<E: EnergyTerm + ?Sized>(
    model: &E,
    fixed: &FixedDofs,
    x: &[f64],
) -> Result<bool, SolveError> {
    let free = fixed.free_dofs();
    let mut index = vec![usize::MAX; x.len()];
    for (k, &d) in free.iter().enumerate() {
        index[d] = k;
    }
    let mut trip = Vec::new();
    model.hessian_lower(x, &mut trip);
    let mut h = FreeHessian::new(&index, free.len());
    h.load(&trip)?;
    match h.solve_shifted(0.0, &vec![1.0; free.len()]) {
        Ok(_) => Ok(true),
        Err(SparseError::NotPositiveDefinite) => Ok(false),
        Err(e) => Err(e.into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interpolated step is the exact minimiser when the energy along the step is a
    /// quadratic or a cubic, and a fallback where the cubic has no minimiser inside.
    #[test]
    fn the_cubic_step_finds_the_minimiser_of_a_quadratic_and_of_a_cubic() {
        // φ = (α − 0.3)² − 0.09
        let a = cubic_step(0.0, -0.6, 1.0, 0.4, 1.4);
        assert!((a - 0.3).abs() < 1e-12, "{a}");
        // φ = α³ − α, minimum at 1/√3
        let a = cubic_step(0.0, -1.0, 1.0, 0.0, 2.0);
        assert!((a - 1.0 / 3f64.sqrt()).abs() < 1e-12, "{a}");
        // φ = −α + 2α² on a step of 2: the quadratic's minimiser 0.25
        let a = cubic_step(0.0, -1.0, 2.0, 6.0, 7.0);
        assert!((a - 0.25).abs() < 1e-12, "{a}");
    }

    /// A quartic double well in 2D, E = (x² − 1)² + 2 y² − x y: indefinite Hessian at the origin.
    struct Well;
    impl EnergyTerm for Well {
        fn energy_gradient(&self, x: &[f64], g: &mut [f64]) -> f64 {
            g[0] += 4.0 * x[0] * (x[0] * x[0] - 1.0) - x[1];
            g[1] += 4.0 * x[1] - x[0];
            (x[0] * x[0] - 1.0).powi(2) + 2.0 * x[1] * x[1] - x[0] * x[1]
        }
        fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
            out.extend([
                (0, 0, 12.0 * x[0] * x[0] - 4.0),
                (0, 1, -1.0),
                (1, 0, -1.0),
                (1, 1, 4.0),
            ]);
        }
    }

    #[test]
    fn newton_leaves_a_saddle_region_and_finds_the_minimum() {
        // start near the saddle at the origin; the third coordinate is fixed
        let mut x = [0.05, 0.0, 0.0];
        let mut fixed = FixedDofs::free(1);
        fixed.fix(2);
        let info = minimize_newton(&mut Well, &fixed, &mut x, &NewtonParams::default()).unwrap();
        assert!(info.residual <= info.tolerance);
        assert!(
            info.cost.factorizations > info.cost.iterations,
            "shifted at the start"
        );
        // minimum: y = x/4, x² = 1 + 1/16
        assert!((x[0] - (17.0_f64 / 16.0).sqrt()).abs() < 1e-9);
        assert!((x[1] - x[0] / 4.0).abs() < 1e-9);
        assert_eq!(x[2], 0.0);
    }

    #[test]
    fn a_saddle_is_told_from_a_minimum() {
        let mut fixed = FixedDofs::free(1);
        fixed.fix(2);
        // the origin is an equilibrium (zero gradient) with an indefinite Hessian
        assert!(!is_local_minimum(&Well, &fixed, &[0.0, 0.0, 0.0]).unwrap());
        let xm = (17.0_f64 / 16.0).sqrt();
        assert!(is_local_minimum(&Well, &fixed, &[xm, xm / 4.0, 0.0]).unwrap());
    }

    #[test]
    fn wrong_length_is_an_error() {
        let r = minimize_newton(
            &mut Well,
            &FixedDofs::free(2),
            &mut [0.0; 3],
            &NewtonParams::default(),
        );
        assert!(matches!(r, Err(SolveError::Dimension { .. })));
    }
}
