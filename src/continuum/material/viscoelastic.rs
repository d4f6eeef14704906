//! Finite-strain viscoelasticity with a Prony series applied to the whole stress (seed eq. 5.8:
//! shear and bulk relax with the same factor), integrated by Simo's (1987) recurrence.
//!
//! Relaxation function g(t) = g∞ + Σᵢ gᵢ e^(−t/τᵢ), g∞ = 1 − Σgᵢ (the seed's one-term form
//! g(t) = 1 − μ̄(1 − e^(−t/τ)) is g₁ = μ̄, τ₁ = τ). With S₀(C) the elastic stress,
//!
//! S(t) = g∞ S₀ + Σᵢ gᵢ Hᵢ,   Ḣᵢ + Hᵢ/τᵢ = Ṡ₀,
//!
//! so a step in S₀ decays exactly as g(t). Over a step Δt with S₀ linear in time,
//! Hᵢⁿ⁺¹ = e^(−xᵢ) Hᵢⁿ + aᵢ (S₀ⁿ⁺¹ − S₀ⁿ), xᵢ = Δt/τᵢ, aᵢ = (1 − e^(−xᵢ))/xᵢ — exact for that
//! path and unconditionally stable (|e^(−x)| ≤ 1 for every Δt). The algorithmic stress is
//! S = γ S₀(C) + A with the scalars γ = g∞ + Σgᵢaᵢ and the constant tensor
//! A = Σgᵢ(e^(−xᵢ)Hᵢⁿ − aᵢS₀ⁿ); it is the exact gradient of the incremental potential
//! Ψ(C) = γψ₀(C) + ½A:(C − I) (the constant −½A:I of a step changes neither), with tangent
//! 𝔺 = γ𝔺₀. Ψ is what a solution reports as its strain energy: the incremental potential of
//! the step, of the order of the stored energy but not the free energy of the relaxing solid. History per point: S₀ⁿ then Hᵢⁿ (4 values each).

use super::{contract, Deformation, Evaluated, Material, MaterialError, Response};
use serde::{Deserialize, Serialize};

/// One Prony term.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PronyTerm {
    /// relative modulus gᵢ ∈ [0, 1)
    pub g: f64,
    /// relaxation time τᵢ, s (> 0)
    pub tau: f64,
}

/// An elastic model relaxed by a Prony series (no terms: the elastic model itself).
#[derive(Debug, Clone, PartialEq)]
pub struct Viscoelastic<M> {
    /// the instantaneous elastic response
    pub elastic: M,
    /// the Prony terms
    pub prony: Vec<PronyTerm>,
}

/// Check Σgᵢ < 1, gᵢ ≥ 0 and τᵢ > 0.
pub fn validate_prony(prony: &[PronyTerm]) -> Result<(), MaterialError> {
    let sum: f64 = prony.iter().map(|t| t.g).sum();
    if prony
        .iter()
        .any(|t| !(t.g >= 0.0 && t.tau > 0.0 && t.tau.is_finite()))
        || !(sum < 1.0)
    {
        return Err(MaterialError::Invalid(format!(
            "Prony terms need g ≥ 0, Σg < 1 and τ > 0, got {prony:?}"
        )));
    }
    Ok(())
}

/// g(t) of a Prony series.
pub fn relaxation(prony: &[PronyTerm], t: f64) -> f64 {
    1.0 - prony
        .iter()
        .map(|p| p.g * (1.0 - (-t / p.tau).exp()))
        .sum::<f64>()
}

/// e^(−x) and (1 − e^(−x))/x for x = Δt/τ (→ 1 as x → 0).
fn decay(dt: f64, tau: f64) -> (f64, f64) {
    let x = dt / tau;
    let a = if x == 0.0 { 1.0 } else { -(-x).exp_m1() / x };
    ((-x).exp(), a)
}

impl<M: Material> Material for Viscoelastic<M> {
    fn history_len(&self) -> usize {
        if self.prony.is_empty() {
            0
        } else {
            4 * (1 + self.prony.len())
        }
    }

    fn response(&self, d: &Deformation, history: &[f64], dt: f64) -> Evaluated {
        let r0 = self.elastic.response(d, &[], dt)?;
        if self.prony.is_empty() {
            return Ok(r0);
        }
        let bad = history.iter().filter(|v| !v.is_finite()).count();
        if bad > 0 {
            return Err(MaterialError::NonFiniteHistory {
                bad,
                len: history.len(),
            });
        }
        let s0n = &history[..4];
        let g_inf = 1.0 - self.prony.iter().map(|p| p.g).sum::<f64>();
        let mut gamma = g_inf;
        let mut a_t = [0.0; 4];
        for (i, p) in self.prony.iter().enumerate() {
            let (e, a) = decay(dt, p.tau);
            gamma += p.g * a;
            let h = &history[4 * (i + 1)..4 * (i + 2)];
            for k in 0..4 {
                a_t[k] += p.g * (e * h[k] - a * s0n[k]);
            }
        }
        let mut stress = [0.0; 4];
        for k in 0..4 {
            stress[k] = gamma * r0.stress[k] + a_t[k];
        }
        let mut tangent = r0.tangent;
        tangent.iter_mut().flatten().for_each(|v| *v *= gamma);
        // the incremental potential up to a constant of the step: ½A:(C − I) instead of ½A:C
        // (same stress and tangent), so the reported energy is of the order of stress × strain
        // rather than carrying ½tr A, which grows as the stress relaxes during a hold
        // (½A:(C − I) = A:E)
        Ok(Response {
            energy: gamma * r0.energy + contract(&a_t, d.green()),
            stress,
            tangent,
        })
    }

    fn update_history(
        &self,
        d: &Deformation,
        history: &mut [f64],
        dt: f64,
    ) -> Result<(), MaterialError> {
        if self.prony.is_empty() {
            return Ok(());
        }
        let s0 = self.elastic.response(d, &[], dt)?.stress;
        for (i, p) in self.prony.iter().enumerate() {
            let (e, a) = decay(dt, p.tau);
            for k in 0..4 {
                let s0n = history[k];
                let h = &mut history[4 * (i + 1) + k];
                *h = e * *h + a * (s0[k] - s0n);
            }
        }
        history[..4].copy_from_slice(&s0);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::fd;
    use super::super::hyperfoam::{Hyperfoam, HyperfoamTerm};
    use super::*;

    const RELAX_TOL: f64 = 1e-12; // the recurrence is exact for a step followed by a hold
    const FD_TOL: f64 = 1e-6; // as for the hyperfoam

    fn model() -> Viscoelastic<Hyperfoam> {
        Viscoelastic {
            elastic: Hyperfoam {
                terms: vec![HyperfoamTerm {
                    mu: 0.35,
                    alpha: 9.1,
                    beta: 0.1,
                }],
            },
            prony: vec![
                PronyTerm { g: 0.4, tau: 3.0 },
                PronyTerm { g: 0.1, tau: 0.2 },
            ],
        }
    }

    #[test]
    fn a_step_relaxes_as_g_of_t_whatever_the_time_step() {
        let m = model();
        let c = [0.9, 0.7, 1.0, 0.02];
        let s0 = m
            .elastic
            .response(&Deformation::from_c(c), &[], 0.0)
            .unwrap()
            .stress;
        let mut hist = vec![0.0; m.history_len()];
        // the step itself, applied in an instant
        assert_eq!(
            m.response(&Deformation::from_c(c), &hist, 0.0)
                .unwrap()
                .stress,
            s0
        );
        m.update_history(&Deformation::from_c(c), &mut hist, 0.0)
            .unwrap();
        let mut t = 0.0;
        for dt in [0.05, 0.5, 2.0, 7.0, 0.01] {
            t += dt;
            let s = m
                .response(&Deformation::from_c(c), &hist, dt)
                .unwrap()
                .stress;
            m.update_history(&Deformation::from_c(c), &mut hist, dt)
                .unwrap();
            let g = relaxation(&m.prony, t);
            for k in 0..4 {
                assert!(
                    (s[k] - g * s0[k]).abs() < RELAX_TOL * s0[1].abs(),
                    "t = {t}"
                );
            }
        }
    }

    #[test]
    fn algorithmic_stress_and_tangent_derive_from_the_incremental_potential() {
        let m = model();
        let mut hist = vec![0.0; m.history_len()];
        m.update_history(&Deformation::from_c([0.95, 0.8, 1.0, 0.01]), &mut hist, 0.3)
            .unwrap();
        let (es, ed) = fd::mismatch(&m, &[0.9, 0.75, 1.02, 0.03], &hist, 0.4);
        assert!(es < FD_TOL && ed < FD_TOL, "{es} {ed}");
    }

    /// A history that is not finite (a corrupt projection from another mesh) is refused with
    /// a named error, not passed on as a NaN stress.
    #[test]
    fn a_history_that_is_not_finite_is_refused() {
        let m = model();
        let mut hist = vec![0.0; m.history_len()];
        hist[5] = f64::NAN;
        hist[9] = f64::INFINITY;
        let r = m.response(&Deformation::from_c([0.9, 0.75, 1.02, 0.03]), &hist, 0.4);
        assert_eq!(r, Err(MaterialError::NonFiniteHistory { bad: 2, len: 12 }));
    }
}
