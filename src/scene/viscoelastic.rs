//! `[viscoelastic]`: Prony-series relaxation of the continuum (seed eq. 5.8). Shear and bulk
//! moduli relax with the same factor g(t) = 1 − Σᵢ gᵢ (1 − e^(−t/τᵢ)); the seed's turf has one
//! term, g₁ = μ̄ = 0.4, τ₁ = 3 s. Its absence means no internal variables are built.

use super::check::Checker;
use super::quantity::{Number, Time};
use serde::{Deserialize, Serialize};

/// `[viscoelastic]`: Prony terms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Viscoelastic {
    /// Relative moduli gᵢ, each in (0, 1), with Σgᵢ < 1 (the long-term modulus stays positive).
    pub g: Vec<Number>,
    /// Relaxation times τᵢ, s, each positive; as many as `g`.
    pub tau: Vec<Time>,
}

impl Viscoelastic {
    pub(crate) fn check(&self, c: &mut Checker) {
        if self.g.is_empty() {
            c.bad("viscoelastic.g", "is empty: give at least one Prony term");
        }
        if self.g.len() != self.tau.len() {
            c.bad(
                "viscoelastic.tau",
                format!(
                    "has {} entries but viscoelastic.g has {}: g and tau must have equal length",
                    self.tau.len(),
                    self.g.len()
                ),
            );
        }
        for (i, g) in self.g.iter().enumerate() {
            c.number_in(&format!("viscoelastic.g[{i}]"), g.0, 0.0, 1.0, true);
        }
        for (i, t) in self.tau.iter().enumerate() {
            c.positive(&format!("viscoelastic.tau[{i}]"), *t);
        }
        let sum: f64 = self.g.iter().map(|g| g.0).sum();
        if sum >= 1.0 {
            c.bad(
                "viscoelastic.g",
                format!("sums to {sum}: the Prony terms must sum to less than 1, or the relaxed modulus would vanish or turn negative"),
            );
        }
    }

    /// The long-term fraction of the modulus, 1 − Σgᵢ.
    pub fn long_term_fraction(&self) -> f64 {
        1.0 - self.g.iter().map(|g| g.0).sum::<f64>()
    }
}
