//! `[homogenize]`: fit a material card (hyperfoam terms, seed eq. 5.3, plus the Prony terms of
//! `[viscoelastic]`) to a stress–strain curve — the discrete stage's loading or unloading
//! curve, or the tangent-modulus law (seed eq. 5.1) Eᵗ(ε) = E⁰e^(−ε/ε₀) + E^∞(1 − e^(−ε/ε₀)).

use super::check::Checker;
use super::quantity::{Number, Pressure};
use serde::{Deserialize, Serialize};

/// Which curve to fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Curve {
    /// the discrete stage's loading curve
    Loading,
    /// the discrete stage's unloading curve (needs `compression.unload = true`)
    Unloading,
    /// the tangent-modulus law with `e0`, `e_inf`, `eps0` (no discrete stage needed)
    TangentLaw,
}

/// Largest number of hyperfoam terms a fit may ask for (the fit's own bound; a card read from
/// a file may hold up to [`crate::continuum::material::hyperfoam::MAX_TERMS`]).
pub const MAX_TERMS: usize = crate::homogenize::fit_hyperfoam::MAX_FIT_TERMS;

/// `[homogenize]`: fit options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Homogenize {
    /// Hyperfoam terms N, 1 to 3 (as `turf homogenize --terms`). Default 1 (the seed's Table 5.1).
    /// At most: a degenerate term is dropped and the stage says so (`hyperfoam_terms_used`).
    #[serde(default = "default_terms")]
    pub terms: usize,
    /// Largest nominal compressive strain fitted, in (0, 1). Default: `compression.to`, or 0.3
    /// for the tangent law (the range that reproduces the seed's Table 5.1, docs/homogenize.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strain_max: Option<Number>,
    /// `"loading"`, `"unloading"` or `"tangent-law"`. Default `"loading"`.
    #[serde(default = "default_curve")]
    pub curve: Curve,
    /// Hold the hyperfoam's E⁰ = 2Σμᵢ(1 + ν) at the tangent law's E⁰ (fitted to the curve
    /// first), fitting only the αᵢ and the split of μ — as the seed's Table 5.1 does. Default:
    /// true for `"tangent-law"`, false for a curve. Use it when the curve is past its knee at
    /// its first point (a buckling plateau): a free fit then extrapolates E⁰ and can push an α
    /// to its bound (docs/homogenize.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pin_e0: Option<bool>,
    /// Tangent law: initial modulus E⁰, GPa (seed: 700 MPa).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e0: Option<Pressure>,
    /// Tangent law: final modulus E^∞, GPa (seed: 70 MPa).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e_inf: Option<Pressure>,
    /// Tangent law: decay strain ε₀, positive (seed: 0.05 to 0.15).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eps0: Option<Number>,
}

fn default_terms() -> usize {
    1
}
fn default_curve() -> Curve {
    Curve::Loading
}

impl Homogenize {
    pub(crate) fn check(&mut self, c: &mut Checker, compression_to: Option<f64>) {
        if self.terms < 1 || self.terms > MAX_TERMS {
            c.bad(
                "homogenize.terms",
                format!("{} is not allowed: must lie in 1..={MAX_TERMS}", self.terms),
            );
        }
        let law = self.curve == Curve::TangentLaw;
        for (key, present) in [
            ("homogenize.e0", self.e0.is_some()),
            ("homogenize.e_inf", self.e_inf.is_some()),
            ("homogenize.eps0", self.eps0.is_some()),
        ] {
            if law && !present {
                c.bad(
                    key,
                    "is missing: curve = \"tangent-law\" needs e0, e_inf and eps0",
                );
            }
            if !law && present {
                c.unused(key, "unless curve = \"tangent-law\"");
            }
        }
        c.positive_opt("homogenize.e0", self.e0);
        c.positive_opt("homogenize.e_inf", self.e_inf);
        if let Some(e) = self.eps0 {
            c.number_in("homogenize.eps0", e.0, 0.0, f64::INFINITY, true);
        }
        let fallback = if law {
            Some(crate::homogenize::fit_hyperfoam::DEFAULT_STRAIN_MAX)
        } else {
            compression_to
        };
        if self.strain_max.is_none() {
            self.strain_max = fallback.map(Number);
        }
        if let Some(s) = self.strain_max {
            c.number_in("homogenize.strain_max", s.0, 0.0, 1.0, true);
            if let (false, Some(to)) = (law, compression_to) {
                if s.0 > to {
                    c.bad(
                        "homogenize.strain_max",
                        format!("{} is not allowed: the discrete curve only reaches compression.to = {to}", s.0),
                    );
                }
            }
        }
    }
}
