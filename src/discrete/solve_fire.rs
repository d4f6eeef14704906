//! FIRE, the fast inertial relaxation engine (Bitzek, Koskinen, Gähler, Moseler & Gumbsch,
//! PRL 97, 170201, 2006): matrix-free minimisation by damped dynamics with unit masses.
//!
//! Each step, with F = −∂E/∂x on the free coordinates: if P = F·v > 0 for more than `n_min`
//! steps, dt ← min(dt f_inc, dt_max) and α ← α f_α; if P ≤ 0, dt ← dt f_dec, α ← α_start,
//! x ← x − ½ dt v and v ← 0 (the half-step back of Guénolé et al., Comput. Mater. Sci. 175,
//! 109584, 2020). Then semi-implicit Euler with the FIRE mixing: v ← v + dt F,
//! v ← (1 − α) v + α |v| F/|F|, x ← x + dt v.
//!
//! Unless given, dt_max = `dt_factor`/√λ_max, with λ_max (nN/nm) estimated by power iteration on
//! finite-difference Hessian–vector products (gradient evaluations only, counted in the cost).

use super::constraints::FixedDofs;
use super::energy::EnergyTerm;
use super::solve::{Evaluator, Info, SolveError};
use crate::numerics::newton::tolerance;

/// FIRE settings (defaults: Bitzek et al. 2006).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FireParams {
    /// absolute force-residual tolerance (nN)
    pub atol: f64,
    /// tolerance relative to the starting residual
    pub rtol: f64,
    /// iteration limit
    pub max_iterations: usize,
    /// largest time step (units of √(nm/(nN/nm)) with unit masses); `None`: from λ_max
    pub dt_max: Option<f64>,
    /// dt_max = dt_factor/√λ_max when `dt_max` is `None`
    pub dt_factor: f64,
    /// the first time step as a fraction of dt_max
    pub dt_start: f64,
    /// steps with P > 0 before dt may grow
    pub n_min: usize,
    /// time-step growth factor
    pub f_inc: f64,
    /// time-step cut on P ≤ 0
    pub f_dec: f64,
    /// initial mixing α
    pub alpha_start: f64,
    /// α decay factor
    pub f_alpha: f64,
}

impl Default for FireParams {
    fn default() -> Self {
        FireParams {
            atol: 1e-10,
            rtol: 1e-8,
            max_iterations: 2_000_000,
            dt_max: None,
            dt_factor: 1.0,
            dt_start: 0.1,
            n_min: 5,
            f_inc: 1.1,
            f_dec: 0.5,
            alpha_start: 0.1,
            f_alpha: 0.99,
        }
    }
}

/// Power-iteration steps for λ_max.
const POWER_STEPS: usize = 30;
/// Relative finite-difference step of the Hessian–vector products.
const HV_STEP: f64 = 1e-7;

/// Minimise the energy of `model` over the coordinates of `x` not fixed in `fixed`, starting
/// from `x` (nm), which holds the solution on success.
pub fn minimize_fire<E: EnergyTerm + ?Sized>(
    model: &mut E,
    fixed: &FixedDofs,
    x: &mut [f64],
    params: &FireParams,
) -> Result<Info, SolveError> {
    let mut ev = Evaluator::new(model, fixed, x)?;
    let n = x.len();
    let free = fixed.free_dofs();
    let mut grad = vec![0.0; n];
    let mut energy = ev.eval(x, &mut grad)?;
    let mut residual = fixed.residual(&grad);
    let tol = tolerance(params.atol, params.rtol, residual);
    let mut history = vec![residual];
    let dt_max = match params.dt_max {
        Some(dt) => dt,
        None => params.dt_factor / largest_eigenvalue(&mut ev, &free, x, &grad)?.sqrt(),
    };
    let mut dt = params.dt_start * dt_max;
    let mut alpha = params.alpha_start;
    let mut since_negative = 0;
    let mut v = vec![0.0; free.len()];

    while residual > tol {
        if ev.cost.iterations >= params.max_iterations {
            return Err(SolveError::NoConvergence {
                residual,
                tolerance: tol,
                cost: ev.finish(),
            });
        }
        ev.cost.iterations += 1;
        let power: f64 = free.iter().zip(&v).map(|(&d, vk)| -grad[d] * vk).sum();
        if power > 0.0 {
            since_negative += 1;
            if since_negative > params.n_min {
                dt = (dt * params.f_inc).min(dt_max);
                alpha *= params.f_alpha;
            }
        } else {
            since_negative = 0;
            dt *= params.f_dec;
            alpha = params.alpha_start;
            for (&d, vk) in free.iter().zip(&v) {
                x[d] -= 0.5 * dt * vk;
            }
            v.iter_mut().for_each(|vk| *vk = 0.0);
        }
        let fnorm = free.iter().map(|&d| grad[d] * grad[d]).sum::<f64>().sqrt();
        for (&d, vk) in free.iter().zip(v.iter_mut()) {
            *vk -= dt * grad[d];
        }
        let vnorm = v.iter().map(|vk| vk * vk).sum::<f64>().sqrt();
        if fnorm > 0.0 {
            for (&d, vk) in free.iter().zip(v.iter_mut()) {
                *vk = (1.0 - alpha) * *vk - alpha * vnorm * grad[d] / fnorm;
            }
        }
        for (&d, vk) in free.iter().zip(&v) {
            x[d] += dt * vk;
        }
        energy = ev.eval(x, &mut grad)?;
        residual = fixed.residual(&grad);
        history.push(residual);
    }
    Ok(Info {
        energy,
        residual,
        tolerance: tol,
        history,
        cost: ev.finish(),
    })
}

/// λ_max (nN/nm) of the Hessian on the free coordinates by power iteration with
/// finite-difference products H v ≈ (g(x + h v) − g(x))/h.
fn largest_eigenvalue<E: EnergyTerm + ?Sized>(
    ev: &mut Evaluator<'_, E>,
    free: &[usize],
    x: &[f64],
    grad: &[f64],
) -> Result<f64, SolveError> {
    let scale = free.iter().fold(1.0_f64, |m, &d| m.max(x[d].abs()));
    let h = HV_STEP * scale;
    // a fixed, deterministic start vector with components in every direction
    let mut v: Vec<f64> = (0..free.len())
        .map(|k| 1.0 + 0.5 * ((k as f64) * 0.618).sin())
        .collect();
    let mut lambda = 0.0;
    let mut xp = x.to_vec();
    let mut gp = vec![0.0; x.len()];
    for _ in 0..POWER_STEPS {
        let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        v.iter_mut().for_each(|a| *a /= norm);
        xp.copy_from_slice(x);
        for (&d, a) in free.iter().zip(&v) {
            xp[d] += h * a;
        }
        ev.eval(&xp, &mut gp)?;
        let hv: Vec<f64> = free.iter().map(|&d| (gp[d] - grad[d]) / h).collect();
        lambda = hv.iter().zip(&v).map(|(a, b)| a * b).sum::<f64>().abs();
        v = hv;
    }
    if lambda > 0.0 && lambda.is_finite() {
        Ok(lambda)
    } else {
        Err(SolveError::NonFinite { iteration: 0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An anisotropic quadratic, E = ½ Σ k_i (x_i − 1)², stiffness ratio 100.
    struct Bowl;
    impl EnergyTerm for Bowl {
        fn energy_gradient(&self, x: &[f64], g: &mut [f64]) -> f64 {
            let k = [1.0, 10.0, 100.0];
            (0..3)
                .map(|i| {
                    g[i] += k[i] * (x[i] - 1.0);
                    0.5 * k[i] * (x[i] - 1.0).powi(2)
                })
                .sum()
        }
        fn hessian(&self, _x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
            out.extend([(0, 0, 1.0), (1, 1, 10.0), (2, 2, 100.0)]);
        }
    }

    #[test]
    fn fire_relaxes_an_anisotropic_bowl_to_its_minimum() {
        let mut x = [0.0, 3.0, -2.0];
        let info = minimize_fire(
            &mut Bowl,
            &FixedDofs::free(1),
            &mut x,
            &FireParams::default(),
        )
        .unwrap();
        assert!(info.residual <= info.tolerance);
        // residual ≤ 1e-8 × 300 nN in a bowl of smallest stiffness 1: |x − 1| ≤ 3e-6
        assert!(x.iter().all(|v| (v - 1.0).abs() < 3e-6), "{x:?}");
        assert!(info.cost.gradient_evaluations > POWER_STEPS);
    }
}
