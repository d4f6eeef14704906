//! `[material]`: the indented solid — linear elastic, hyperfoam (seed eq. 5.3, the Abaqus
//! `*HYPERFOAM` form with the OCR errors corrected in PHYSICS.md), or a material card.
//!
//! Hyperfoam: U = Σᵢ 2μᵢ/αᵢ² [λ₁^αᵢ + λ₂^αᵢ + λ₃^αᵢ − 3 + (1/βᵢ)(J^(−αᵢβᵢ) − 1)], with
//! μ₀ = Σμᵢ, K₀ = Σ 2μᵢ(1/3 + βᵢ), βᵢ = νᵢ/(1 − 2νᵢ).

use super::check::Checker;
use super::quantity::{Number, Pressure};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Constitutive model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MaterialModel {
    /// isotropic linear elasticity: `youngs`, `poisson`
    Linear,
    /// Hill–Storåkers hyperfoam: arrays `mu`, `alpha`, `beta`
    Hyperfoam,
    /// a material card (`material.json` written by `turf homogenize` or this run's homogenize
    /// stage)
    Card,
}

/// `[material]`: the indented solid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// `"linear"`, `"hyperfoam"` or `"card"`. Required.
    pub model: MaterialModel,
    /// Young's modulus E, GPa (linear only). Required for `"linear"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs: Option<Pressure>,
    /// Poisson's ratio ν, 0 ≤ ν < 0.5 (linear only). Required for `"linear"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson: Option<Number>,
    /// Hyperfoam moduli μᵢ, GPa (one per term). Required for `"hyperfoam"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<Vec<Pressure>>,
    /// Hyperfoam exponents αᵢ (pure numbers, μᵢαᵢ > 0). Required for `"hyperfoam"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<Vec<Number>>,
    /// Hyperfoam compressibility βᵢ = νᵢ/(1 − 2νᵢ) ≥ 0. Default all zero (ν = 0, the seed's
    /// turf, Table 5.1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<Vec<Number>>,
    /// Path of a material card (JSON), relative to the scene file (`"card"` only). Default:
    /// the card fitted by this run's homogenize stage, which then must be asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub card: Option<PathBuf>,
}

impl Material {
    pub(crate) fn check(&mut self, c: &mut Checker, scene_dir: &Path) {
        let linear = self.model == MaterialModel::Linear;
        let foam = self.model == MaterialModel::Hyperfoam;
        let card = self.model == MaterialModel::Card;
        let why = match self.model {
            MaterialModel::Linear => "with model = \"linear\"",
            MaterialModel::Hyperfoam => "with model = \"hyperfoam\"",
            MaterialModel::Card => "with model = \"card\"",
        };
        for (key, present, wanted) in [
            ("material.youngs", self.youngs.is_some(), linear),
            ("material.poisson", self.poisson.is_some(), linear),
            ("material.mu", self.mu.is_some(), foam),
            ("material.alpha", self.alpha.is_some(), foam),
            ("material.beta", self.beta.is_some(), foam),
            ("material.card", self.card.is_some(), card),
        ] {
            if present && !wanted {
                c.unused(key, why);
            }
        }
        if linear {
            self.check_linear(c);
        }
        if foam {
            self.check_hyperfoam(c);
        }
        if let Some(path) = &mut self.card {
            let full = scene_dir.join(&*path);
            if !full.is_file() {
                c.bad(
                    "material.card",
                    format!(
                        "\"{}\" is not a readable file (looked for {}); give a card written by `turf homogenize`",
                        path.display(),
                        full.display()
                    ),
                );
            }
            *path = full;
        }
    }

    fn check_linear(&self, c: &mut Checker) {
        match self.youngs {
            Some(e) => c.positive("material.youngs", e),
            None => c.bad(
                "material.youngs",
                "is missing: model = \"linear\" needs Young's modulus",
            ),
        }
        match self.poisson {
            Some(nu) => c.number_in("material.poisson", nu.0, 0.0, 0.5, false),
            None => c.bad(
                "material.poisson",
                "is missing: model = \"linear\" needs Poisson's ratio in [0, 0.5)",
            ),
        }
    }

    fn check_hyperfoam(&mut self, c: &mut Checker) {
        let (Some(mu), Some(alpha)) = (&self.mu, &self.alpha) else {
            c.bad(
                "material",
                "model = \"hyperfoam\" needs the arrays mu and alpha (and optionally beta)",
            );
            return;
        };
        let n = mu.len();
        if n == 0 {
            c.bad("material.mu", "is empty: give at least one hyperfoam term");
            return;
        }
        let beta = self.beta.get_or_insert_with(|| vec![Number(0.0); n]);
        for (key, len) in [
            ("material.alpha", alpha.len()),
            ("material.beta", beta.len()),
        ] {
            if len != n {
                c.bad(
                    key,
                    format!("has {len} entries but material.mu has {n}: the arrays mu, alpha, beta must have equal length"),
                );
            }
        }
        for (i, (m, a)) in mu.iter().zip(alpha).enumerate() {
            if m.0 * a.0 <= 0.0 {
                c.bad(
                    format!("material.alpha[{i}]"),
                    format!(
                        "{} with mu = {} GPa is not allowed: each term needs mu·alpha > 0",
                        a.0, m.0
                    ),
                );
            }
        }
        for (i, b) in beta.iter().enumerate() {
            if b.0 < 0.0 {
                c.bad(
                    format!("material.beta[{i}]"),
                    format!("{} is not allowed: beta = nu/(1 - 2 nu) must be >= 0", b.0),
                );
            }
        }
        let mu0: f64 = mu.iter().map(|m| m.0).sum();
        if mu0 <= 0.0 {
            c.bad(
                "material.mu",
                format!("sums to {mu0} GPa: the initial shear modulus sum(mu) must be positive"),
            );
        }
    }

    /// Initial shear modulus μ₀ = Σμᵢ (hyperfoam) or E/(2(1+ν)) (linear), GPa.
    pub fn initial_shear_modulus(&self) -> Option<f64> {
        match self.model {
            MaterialModel::Linear => Some(self.youngs?.0 / (2.0 * (1.0 + self.poisson?.0))),
            MaterialModel::Hyperfoam => Some(self.mu.as_ref()?.iter().map(|m| m.0).sum()),
            MaterialModel::Card => None,
        }
    }

    /// Initial Young's modulus and Poisson's ratio (E, ν) where the section gives them: the
    /// hyperfoam's small-strain limit is E = 2μ₀(1 + ν) with ν = β/(1 + 2β) of the first term.
    pub fn initial_elastic(&self) -> Option<(f64, f64)> {
        match self.model {
            MaterialModel::Linear => Some((self.youngs?.0, self.poisson?.0)),
            MaterialModel::Hyperfoam => {
                let mu0 = self.initial_shear_modulus()?;
                let b = self.beta.as_ref()?.first()?.0;
                let nu = b / (1.0 + 2.0 * b);
                Some((2.0 * mu0 * (1.0 + nu), nu))
            }
            MaterialModel::Card => None,
        }
    }
}
