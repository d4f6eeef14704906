//! Analysis of a compression curve (seed §2.4 eqs. 2.13–2.14, §5.1 eq. 5.1).
//!
//! From the loading (and unloading) branch of nominal stress σ against nominal strain ε:
//!
//! - the tangent modulus Eᵗ = Δσ/Δε between consecutive loading points, at the mid strains;
//! - the fit of the tangent-modulus law (5.1), Eᵗ(ε) = E⁰e^(−ε/ε₀) + E^∞(1 − e^(−ε/ε₀)),
//!   through [`crate::homogenize::tangent_law::fit_tangent_law`], giving E⁰, E^∞, ε₀;
//! - the threshold stress, **defined as σ₀ = E⁰ε₀**: the stress at which the two linear regimes
//!   of (5.1) meet — the initial line σ = E⁰ε and the large-strain asymptote
//!   σ = E^∞ε + (E⁰ − E^∞)ε₀ intersect at ε = ε₀, σ = E⁰ε₀. Below σ₀ the turf is stiff (E⁰),
//!   above it the tangent has fallen towards E^∞: the threshold of the seed's micromechanics;
//! - the loading work W = ∫σ dε along loading and the hysteresis (W − W_unload)/W, the fraction
//!   of the work not recovered on unloading (trapezoidal rule on the recorded steps).
//!
//! Works per unit volume are in GPa (= GJ/m³).

use super::curve::{CurveError, StressStrainCurve};
use super::quality;
use super::tangent_law::{fit_tangent_law, TangentFitParams, TangentLawError, TangentLawFit};

/// One branch of the curve, strain ascending.
#[derive(Debug, Clone, PartialEq)]
pub struct Branch {
    /// nominal compressive strain
    pub strain: Vec<f64>,
    /// nominal compressive stress, GPa
    pub stress: Vec<f64>,
}

impl Branch {
    /// ∫σ dε over the branch (trapezoidal), GPa.
    pub fn work(&self) -> f64 {
        self.strain
            .windows(2)
            .zip(self.stress.windows(2))
            .map(|(e, s)| 0.5 * (s[0] + s[1]) * (e[1] - e[0]))
            .sum()
    }

    /// Tangent moduli Δσ/Δε (GPa) at the mid strains of consecutive points.
    pub fn tangent(&self) -> Vec<(f64, f64)> {
        self.strain
            .windows(2)
            .zip(self.stress.windows(2))
            .map(|(e, s)| (0.5 * (e[0] + e[1]), (s[1] - s[0]) / (e[1] - e[0])))
            .collect()
    }
}

/// The analysed curve.
#[derive(Debug, Clone)]
pub struct CurveAnalysis {
    /// loading branch
    pub loading: Branch,
    /// unloading branch (strain ascending), if unloaded
    pub unloading: Option<Branch>,
    /// largest stress on loading, GPa
    pub peak_stress: f64,
    /// ∫σ dε on loading, GPa
    pub loading_work: f64,
    /// ∫σ dε on unloading, GPa
    pub unloading_work: Option<f64>,
    /// fit of (5.1) to the loading branch, or why it failed
    pub fit: Result<TangentLawFit, FitFailure>,
}

/// Why (5.1) could not be fitted to the loading branch. Serialized as its message.
#[derive(Debug, Clone, thiserror::Error)]
pub enum FitFailure {
    /// the loading branch is not a usable stress–strain curve
    #[error(transparent)]
    Curve(#[from] CurveError),
    /// the fit itself failed
    #[error(transparent)]
    Fit(#[from] TangentLawError),
}

impl serde::Serialize for FitFailure {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl CurveAnalysis {
    /// Analyse the branches (each strain ascending; the unloading one as recorded, reversed).
    pub fn new(loading: Branch, unloading: Option<Branch>) -> Self {
        let peak_stress = loading.stress.iter().copied().fold(0.0, f64::max);
        let loading_work = loading.work();
        let unloading_work = unloading.as_ref().map(Branch::work);
        let fit = StressStrainCurve::new(
            loading.strain.clone(),
            loading.stress.clone(),
            None,
            "the discrete loading curve",
        )
        .map_err(FitFailure::from)
        .and_then(|c| Ok(fit_tangent_law(&c, &TangentFitParams::default())?));
        CurveAnalysis {
            loading,
            unloading,
            peak_stress,
            loading_work,
            unloading_work,
            fit,
        }
    }

    /// What the user must know about the fit of (5.1) ([`crate::homogenize::quality`]): a
    /// misfit over the threshold, E^∞ > E⁰, E⁰ collapsed to zero (σ₀ → 0 on a late-rising
    /// curve), ε₀ below the first strain. Empty when the fit represents the curve or failed
    /// (a failed fit shows as its values missing).
    pub fn fit_warnings(&self) -> Vec<String> {
        let Ok(f) = &self.fit else {
            return Vec::new();
        };
        let (e, s) = (&self.loading.strain, &self.loading.stress);
        let mut w = quality::law_warnings(&f.law, e, s, true);
        w.extend(quality::misfit_warning(
            "tangent-law (5.1) fit of the loading curve",
            f.rms_rel,
            None,
        ));
        w
    }

    /// The fit of (5.1) when it is the softening law (5.1) describes (E^∞ ≤ E⁰): a curve that
    /// stiffens (a toe, tubes engaging one after another) drives the fit to E^∞ > E⁰ with ε₀
    /// far beyond the data, where E⁰, E^∞ and ε₀ no longer mean an initial modulus, a
    /// large-strain modulus and the end of a linear range (the fit's warnings say so).
    pub fn softening_fit(&self) -> Option<&TangentLawFit> {
        self.fit.as_ref().ok().filter(|f| f.law.softens())
    }

    /// Threshold stress σ₀ = E⁰ε₀ of the fitted (5.1), GPa (see the module doc); `None` without
    /// a fit, when the fit stiffens (no threshold: [`Self::softening_fit`]) or when the fit's
    /// constants give no finite product.
    pub fn threshold_stress(&self) -> Option<f64> {
        self.softening_fit()
            .map(|f| f.law.e0 * f.law.eps0)
            .filter(|s| s.is_finite())
    }

    /// Fraction of the loading work not recovered on unloading, (W − W_u)/W.
    pub fn hysteresis(&self) -> Option<f64> {
        match self.unloading_work {
            Some(wu) if self.loading_work > 0.0 => {
                Some((self.loading_work - wu) / self.loading_work)
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::homogenize::tangent_law::TangentLaw;

    /// The (5.1) fit of exact law samples recovers the constants to the solver's tolerance.
    const FIT_TOL: f64 = 1e-6;

    #[test]
    fn a_curve_sampled_from_the_law_gives_back_its_constants_and_threshold() {
        let law = TangentLaw::new(0.7, 0.07, 0.08).unwrap();
        let strain: Vec<f64> = (0..=30).map(|k| 0.01 * k as f64).collect();
        let stress = strain.iter().map(|&e| law.stress(e)).collect();
        let a = CurveAnalysis::new(Branch { strain, stress }, None);
        let fit = a.fit.as_ref().unwrap();
        assert!((fit.law.e0 / 0.7 - 1.0).abs() < FIT_TOL);
        assert!((fit.law.eps0 / 0.08 - 1.0).abs() < FIT_TOL);
        assert!((a.threshold_stress().unwrap() / (0.7 * 0.08) - 1.0).abs() < 2.0 * FIT_TOL);
        assert!(a.hysteresis().is_none());
        // the tangent falls
        let t = a.loading.tangent();
        assert!(t.first().unwrap().1 > 5.0 * t.last().unwrap().1);
    }

    #[test]
    fn a_late_rising_curve_gets_a_warning_and_a_law_sample_none() {
        let strain: Vec<f64> = (0..=30).map(|k| 0.01 * k as f64).collect();
        // convex: no initial stiffness, the stress rises late (a buckling turf before contact)
        let stress = strain.iter().map(|&e| 0.1 * e.powi(3)).collect();
        let a = CurveAnalysis::new(
            Branch {
                strain: strain.clone(),
                stress,
            },
            None,
        );
        let w = a.fit_warnings();
        assert!(
            w.iter()
                .any(|x| x.contains("exceeds E0") || x.contains("collapsed")),
            "{:?} {w:?}",
            a.fit.as_ref().map(|f| f.law)
        );
        let law = TangentLaw::seed(0.08);
        let stress = strain.iter().map(|&e| law.stress(e)).collect();
        let a = CurveAnalysis::new(Branch { strain, stress }, None);
        assert!(a.fit_warnings().is_empty(), "{:?}", a.fit_warnings());
    }

    /// A toe: the stress rises slowly, then faster as the shorter tubes reach the platen
    /// (σ = aε + bε², a 9-tube curve with a 10 % length spread looks like this). The fit
    /// stiffens, so there is no threshold, and the constants are flagged as not the law's.
    #[test]
    fn a_toe_that_stiffens_has_no_threshold() {
        let strain: Vec<f64> = (0..=30).map(|k| 0.01 * k as f64).collect();
        let stress = strain.iter().map(|&e| 0.008 * e + 0.04 * e * e).collect();
        let a = CurveAnalysis::new(Branch { strain, stress }, None);
        let fit = a.fit.as_ref().unwrap();
        assert!(fit.law.e_inf > fit.law.e0, "{:?}", fit.law);
        assert!(a.softening_fit().is_none());
        assert!(a.threshold_stress().is_none());
        assert!(a.fit_warnings().iter().any(|w| w.contains("exceeds E0")));
    }

    #[test]
    fn work_and_hysteresis_by_trapezoids() {
        // loading σ = ε on [0, 1] (W = 1/2), unloading σ = ε² sampled exactly at 0, ½, 1
        let loading = Branch {
            strain: vec![0.0, 0.5, 1.0],
            stress: vec![0.0, 0.5, 1.0],
        };
        let unloading = Branch {
            strain: vec![0.0, 0.5, 1.0],
            stress: vec![0.0, 0.25, 1.0],
        };
        let a = CurveAnalysis::new(loading, Some(unloading));
        assert_eq!(a.loading_work, 0.5);
        // trapezoids of ε²: ½·½·¼ + ½·½·(¼ + 1) = 0.375
        assert_eq!(a.unloading_work, Some(0.375));
        assert_eq!(a.hysteresis(), Some(0.25));
    }
}
