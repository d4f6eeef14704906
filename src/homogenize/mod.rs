//! Homogenisation (seed chapter 5.1): from a compressive stress–strain curve — computed by the
//! discrete engine, measured, or the idealised tangent law (5.1) — to a material card for the
//! continuum stage and for Abaqus/CalculiX.
//!
//! The stage runs in named steps ([`run`]):
//! 1. the curve: a [`curve::StressStrainCurve`] from CSV, or the law sampled on (0, ε_max];
//! 2. the tangent law (5.1): given, or fitted to the curve with standard errors
//!    ([`tangent_law::fit_tangent_law`]);
//! 3. the hyperfoam (5.3) with N = 1…3 terms fitted to the curve ([`fit_hyperfoam::fit_hyperfoam`];
//!    lateral strain, if measured, fixes β; E⁰ pinned for an idealised law);
//! 4. the relaxation (5.8) as a Prony series, from μ̄, τ or fitted to a relaxation curve
//!    ([`prony`]);
//! 5. the fit-quality checks ([`quality`]): a misfit above its threshold, a degenerate or
//!    collapsed tangent law, an α at its bound are warnings, printed and kept in the summary;
//! 6. the cards `material.json` and `material.inp` ([`card::MaterialCard`]), a summary, the
//!    curves and a plot ([`write_outputs`]).
//!
//! The discrete stage's own reading of its curve — branches, σ₀ = E⁰ε₀, work and hysteresis —
//! is [`curve_analysis`].
//!
//! Entry points: [`run`] (pure: data in, card and fits out), [`write_outputs`] (the files),
//! [`hyperfoam::Hyperfoam::drive`] (single-point driver used to check cards).

pub mod card;
pub mod curve;
pub mod curve_analysis;
pub mod fit_hyperfoam;
pub mod hyperfoam;
pub mod prony;
pub mod quality;
pub mod tangent_law;
pub mod transverse_foam;

use crate::numerics::least_squares as lsq;
use card::{MaterialCard, Provenance};
use curve::{RelaxationCurve, StressStrainCurve};
use fit_hyperfoam::{FitError, HyperfoamFit, HyperfoamFitParams, DEFAULT_STRAIN_MAX};
use hyperfoam::Mode;
use prony::{Prony, PronyFit};
use std::path::{Path, PathBuf};
use tangent_law::{TangentLaw, TangentLawFit};

/// Default number of points at which an idealised tangent law is sampled for the fit.
pub const DEFAULT_SAMPLES: usize = 200;

/// What the card is fitted to.
#[derive(Debug, Clone)]
pub enum Source {
    /// the idealised law (5.1), sampled uniformly on (0, strain_max]
    TangentLaw(TangentLaw),
    /// a curve; `name` (e.g. the file path) goes into the provenance
    Curve {
        /// the data
        curve: StressStrainCurve,
        /// where it came from
        name: String,
    },
}

/// The relaxation to put on the card.
#[derive(Debug, Clone)]
pub enum Relaxation {
    /// seed (5.8): μ̄ and τ (s)
    Law {
        /// relaxed fraction μ̄ = (μ₀ − μ_∞)/μ₀
        mu_bar: f64,
        /// relaxation time, s
        tau: f64,
    },
    /// fit an N-term series to a relaxation curve
    Curve {
        /// the data
        curve: RelaxationCurve,
        /// where it came from
        name: String,
        /// number of Prony terms
        terms: usize,
    },
}

/// Settings of the homogenisation stage (the `[homogenize]` scene section, the CLI flags).
#[derive(Debug, Clone)]
pub struct HomogenizeParams {
    /// the data
    pub source: Source,
    /// hyperfoam terms N (1…3), default 1 as the seed
    pub terms: usize,
    /// upper end of the fitted nominal compressive strain, default
    /// [`DEFAULT_STRAIN_MAX`] = 0.3 (reproduces Table 5.1)
    pub strain_max: f64,
    /// points at which a tangent law is sampled, default [`DEFAULT_SAMPLES`]
    pub samples: usize,
    /// hold the hyperfoam's E⁰ at the tangent law's E⁰. `None` = the default: yes for an
    /// idealised law (the seed's Table 5.1 has μ = E⁰/2), no for a curve
    pub pin_initial_modulus: Option<bool>,
    /// the relaxation, if any
    pub relaxation: Option<Relaxation>,
    /// least-squares settings shared by the fits
    pub solver: lsq::Params,
}

impl HomogenizeParams {
    /// Defaults around a source.
    pub fn new(source: Source) -> Self {
        HomogenizeParams {
            source,
            terms: 1,
            strain_max: DEFAULT_STRAIN_MAX,
            samples: DEFAULT_SAMPLES,
            pin_initial_modulus: None,
            relaxation: None,
            solver: lsq::Params::default(),
        }
    }
}

/// Why the stage failed.
#[derive(Debug, thiserror::Error)]
pub enum HomogenizeError {
    /// bad settings
    #[error("homogenize: {0}")]
    Invalid(String),
    /// the tangent-law fit failed
    #[error(transparent)]
    TangentLaw(#[from] tangent_law::TangentLawError),
    /// the hyperfoam fit failed
    #[error(transparent)]
    Hyperfoam(#[from] FitError),
    /// the Prony series is invalid or its fit failed
    #[error(transparent)]
    Prony(#[from] prony::PronyError),
    /// a curve was refused
    #[error(transparent)]
    Curve(#[from] curve::CurveError),
    /// writing results failed
    #[error(transparent)]
    Report(#[from] crate::report::ReportError),
}

/// Everything the stage produced.
#[derive(Debug, Clone)]
pub struct HomogenizeOutput {
    /// the card
    pub card: MaterialCard,
    /// the tangent law used (given or fitted)
    pub tangent_law: TangentLaw,
    /// the tangent-law fit, when the source was a curve
    pub tangent_fit: Option<TangentLawFit>,
    /// the hyperfoam fit
    pub hyperfoam_fit: HyperfoamFit,
    /// the Prony fit, when fitted to a relaxation curve
    pub prony_fit: Option<PronyFit>,
    /// the curve fitted (law samples or data)
    pub curve: StressStrainCurve,
    /// every warning of the fits ([`fit_warnings`]), empty when all checks pass
    pub warnings: Vec<String>,
    /// wall time of the fits, s
    pub seconds: f64,
}

/// Every warning of the fits: the hyperfoam's own (stability, terms dropped, α at a bound), the
/// tangent law's constants against the curve, and each misfit over its threshold.
fn fit_warnings(
    hf: &HyperfoamFit,
    law: &TangentLaw,
    tangent_fit: Option<&TangentLawFit>,
    curve: &StressStrainCurve,
) -> Vec<String> {
    let mut w = hf.warnings.clone();
    w.extend(quality::law_warnings(
        law,
        &curve.strain,
        &curve.stress,
        tangent_fit.is_some(),
    ));
    if let Some(f) = tangent_fit {
        w.extend(quality::misfit_warning(
            "tangent-law (5.1) fit",
            f.rms_rel,
            None,
        ));
    }
    w.extend(quality::misfit_warning(
        "hyperfoam card",
        hf.rms_rel,
        Some(hf.max_rel),
    ));
    w
}

/// Run the stage: fit the tangent law (if needed), the hyperfoam and the relaxation; build the
/// card. Pure computation — [`write_outputs`] writes the files.
pub fn run(params: &HomogenizeParams) -> Result<HomogenizeOutput, HomogenizeError> {
    let clock = std::time::Instant::now();
    if !(params.strain_max > 0.0 && params.strain_max < 1.0) {
        return Err(HomogenizeError::Invalid(format!(
            "strain_max = {} must lie in (0, 1)",
            params.strain_max
        )));
    }
    // 1–2. the curve and the tangent law
    let (curve, law, tangent_fit, data) = match &params.source {
        Source::TangentLaw(law) => {
            if params.samples < curve::MIN_POINTS {
                return Err(HomogenizeError::Invalid(format!(
                    "samples = {} (at least {})",
                    params.samples,
                    curve::MIN_POINTS
                )));
            }
            let strain: Vec<f64> = (1..=params.samples)
                .map(|k| params.strain_max * k as f64 / params.samples as f64)
                .collect();
            let stress = strain.iter().map(|&e| law.stress(e)).collect();
            let c = StressStrainCurve::new(strain, stress, None, "tangent law")?;
            let data = format!(
                "tangent law (5.1) E0={} GPa, Einf={} GPa, eps0={}, sampled at {} points on (0, {}]",
                law.e0, law.e_inf, law.eps0, params.samples, params.strain_max
            );
            (c, *law, None, data)
        }
        Source::Curve { curve, name } => {
            let f = tangent_law::fit_tangent_law(
                curve,
                &tangent_law::TangentFitParams {
                    solver: params.solver,
                },
            )?;
            let data = format!(
                "curve {name} ({} points, strain {} to {})",
                curve.strain.len(),
                curve.strain[0],
                curve.strain[curve.strain.len() - 1]
            );
            (curve.clone(), f.law, Some(f), data)
        }
    };
    // 3. the hyperfoam
    let pin = params
        .pin_initial_modulus
        .unwrap_or(matches!(params.source, Source::TangentLaw(_)));
    let hf_params = HyperfoamFitParams {
        terms: params.terms,
        strain_max: params.strain_max,
        initial_modulus: pin.then_some(law.e0),
        solver: params.solver,
    };
    let hyperfoam_fit = fit_hyperfoam::fit_hyperfoam(&curve, &hf_params)?;
    // 4. the relaxation
    let (prony, prony_fit, relax_note) = match &params.relaxation {
        None => (None, None, serde_json::json!("none")),
        Some(Relaxation::Law { mu_bar, tau }) => (
            Some(Prony::from_relaxation(*mu_bar, *tau)?),
            None,
            serde_json::json!({"law": "seed (5.8)", "mu_bar": mu_bar, "tau_s": tau}),
        ),
        Some(Relaxation::Curve { curve, name, terms }) => {
            let f = prony::fit_prony(curve, *terms, &params.solver)?;
            let note = serde_json::json!({"curve": name, "terms": terms, "rms_rel": f.rms_rel});
            (Some(f.prony.clone()), Some(f), note)
        }
    };
    // 5. the checks
    let warnings = fit_warnings(&hyperfoam_fit, &law, tangent_fit.as_ref(), &curve);
    // 6. the card
    let mut fit_note = serde_json::json!({
        "hyperfoam": {
            "terms_requested": params.terms,
            "terms_used": hyperfoam_fit.material.terms.len(),
            "strain_range": [0.0, params.strain_max],
            "points": hyperfoam_fit.points,
            "lateral_strain": curve.lateral_strain.is_some(),
            "residual": "nominal compressive stress, least squares (Levenberg-Marquardt)",
            "fit_rms_rel": hyperfoam_fit.rms_rel,
            "fit_max_rel": hyperfoam_fit.max_rel,
            "warnings": warnings,
        },
        "tangent_law": if tangent_fit.is_some() { "fitted to the curve" } else { "given" },
        "relaxation": relax_note,
    });
    if pin {
        fit_note["hyperfoam"]["initial_modulus_pinned_GPa"] = serde_json::json!(law.e0);
    }
    let card = MaterialCard {
        hyperfoam: hyperfoam_fit.material.clone(),
        prony,
        tangent_law: Some(law),
        provenance: Provenance {
            data,
            fit: fit_note,
            turf_version: env!("CARGO_PKG_VERSION").into(),
        },
    };
    Ok(HomogenizeOutput {
        card,
        tangent_law: law,
        tangent_fit,
        hyperfoam_fit,
        prony_fit,
        curve,
        warnings,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// The `summary.json` of the stage (and `turf homogenize --json`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Summary {
    /// the fitted hyperfoam: `mu_GPa`, `alpha`, `beta`, and their standard errors
    pub hyperfoam: serde_json::Value,
    /// `E0_GPa`, `Einf_GPa`, `eps0` (and `std_err` when fitted)
    pub tangent_law: serde_json::Value,
    /// `g`, `k`, `tau_s` (empty arrays without relaxation)
    pub prony: serde_json::Value,
    /// ‖σ_hyperfoam − σ_data‖/‖σ_data‖ over the fitted range
    pub fit_rms_rel: f64,
    /// max |σ_hyperfoam − σ_data| / max σ_data over the fitted range
    pub fit_max_rel: f64,
    /// fitted range of nominal compressive strain
    pub strain_max: f64,
    /// hyperfoam terms asked for
    pub terms_requested: usize,
    /// hyperfoam terms on the card (fewer than asked when the fit was degenerate: the
    /// warnings say why)
    pub terms_used: usize,
    /// the misfits against their warning thresholds ([`quality`]): `hyperfoam_rms_rel`,
    /// `hyperfoam_max_rel`, `tangent_law_rms_rel` (fitted laws), `rms_warn`, `max_warn`, and
    /// `acceptable` (no misfit over a threshold)
    pub fit_quality: serde_json::Value,
    /// stability, term, tangent-law and misfit warnings
    pub warnings: Vec<String>,
    /// cost: wall time (s) and solver iterations
    pub cost: serde_json::Value,
    /// files written (relative to the output folder)
    pub files: Vec<String>,
}

/// Build the summary of a run.
pub fn summary(out: &HomogenizeOutput, files: Vec<String>) -> Summary {
    let hf = &out.hyperfoam_fit;
    let m = &hf.material;
    let mut hyperfoam =
        serde_json::json!({"mu_GPa": m.mu(), "alpha": m.alpha(), "beta": m.beta(), "nu": hf.nu});
    if let Some(se) = &hf.std_errors {
        hyperfoam["std_err"] = serde_json::to_value(se).expect("serialisable");
    }
    let mut tangent_law = serde_json::to_value(out.tangent_law).expect("serialisable");
    if let Some(se) = out.tangent_fit.as_ref().and_then(|f| f.std_errors) {
        tangent_law["std_err"] =
            serde_json::json!({"E0_GPa": se[0], "Einf_GPa": se[1], "eps0": se[2]});
    }
    if let Some(f) = &out.tangent_fit {
        tangent_law["fit_rms_rel"] = serde_json::json!(f.rms_rel);
    }
    let prony = match &out.card.prony {
        Some(p) => serde_json::to_value(p).expect("serialisable"),
        None => serde_json::json!({"g": [], "k": [], "tau_s": []}),
    };
    let iterations = hf.info.iterations + out.tangent_fit.as_ref().map_or(0, |f| f.info.iterations);
    let tangent_rms = out.tangent_fit.as_ref().map(|f| f.rms_rel);
    let acceptable = quality::misfit_warning("", hf.rms_rel, Some(hf.max_rel)).is_none()
        && tangent_rms.is_none_or(|r| quality::misfit_warning("", r, None).is_none());
    let mut fit_quality = serde_json::json!({
        "hyperfoam_rms_rel": hf.rms_rel,
        "hyperfoam_max_rel": hf.max_rel,
        "rms_warn": quality::RMS_WARN,
        "max_warn": quality::MAX_WARN,
        "acceptable": acceptable,
    });
    if let Some(r) = tangent_rms {
        fit_quality["tangent_law_rms_rel"] = serde_json::json!(r);
    }
    Summary {
        hyperfoam,
        tangent_law,
        prony,
        fit_rms_rel: hf.rms_rel,
        fit_max_rel: hf.max_rel,
        strain_max: hf.strain_max,
        terms_requested: hf.terms_requested,
        terms_used: m.terms.len(),
        fit_quality,
        warnings: out.warnings.clone(),
        cost: serde_json::json!({"time_s": out.seconds, "solver_iterations": iterations}),
        files,
    }
}

/// Write `material.json`, `material.inp`, `homogenize.csv` (data, law and hyperfoam stresses),
/// `plots/homogenize.{svg,png}` (as the seed's Fig 5.2) and `summary.json` into `dir`.
pub fn write_outputs(out: &HomogenizeOutput, dir: &Path) -> Result<Summary, HomogenizeError> {
    use crate::report::{csv::Table, plot::Plot, plot::Series, write_atomic, write_json};
    let mut files: Vec<String> = ["material.json", "material.inp", "homogenize.csv"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    write_json(&dir.join("material.json"), &out.card.to_json())?;
    write_atomic(&dir.join("material.inp"), out.card.to_inp().as_bytes())?;
    let c = &out.curve;
    let m = &out.hyperfoam_fit.material;
    let hf_stress = |e: f64| -> Result<f64, HomogenizeError> {
        m.drive(Mode::Uniaxial, 1.0 - e)
            .map(|s| -s.nominal[0])
            .map_err(|e| HomogenizeError::Invalid(e.to_string()))
    };
    let hf: Vec<f64> = c
        .strain
        .iter()
        .map(|&e| hf_stress(e))
        .collect::<Result<_, _>>()?;
    let law: Vec<f64> = c
        .strain
        .iter()
        .map(|&e| out.tangent_law.stress(e))
        .collect();
    Table::new()
        .column("strain", c.strain.clone())
        .column("stress_data_GPa", c.stress.clone())
        .column("stress_tangent_law_GPa", law.clone())
        .column("stress_hyperfoam_GPa", hf.clone())
        .write(&dir.join("homogenize.csv"))?;
    // smooth curves to the larger of the data range and the fitted range
    let top = c.strain[c.strain.len() - 1].max(out.hyperfoam_fit.strain_max);
    let xs: Vec<f64> = (0..=200).map(|k| top * k as f64 / 200.0).collect();
    let mpa = |v: Vec<f64>| v.into_iter().map(|x| 1e3 * x).collect::<Vec<_>>();
    let law_s = mpa(xs.iter().map(|&e| out.tangent_law.stress(e)).collect());
    let hf_s = mpa(xs.iter().map(|&e| hf_stress(e)).collect::<Result<_, _>>()?);
    let mut plot = Plot::new(
        &format!(
            "Uniaxial compression: tangent law and {}-term hyperfoam",
            m.terms.len()
        ),
        "nominal compressive strain",
        "nominal compressive stress (MPa)",
    );
    if out.tangent_fit.is_some() {
        plot = plot.with(Series::points(
            "data",
            c.strain.clone(),
            mpa(c.stress.clone()),
        ));
    }
    plot = plot
        .with(Series::dashed("tangent law (5.1)", xs.clone(), law_s))
        .with(Series::line("hyperfoam fit", xs, hf_s));
    let mut plot_warnings = Vec::new();
    files.extend(plot.write_or_warn(
        &dir.join("plots"),
        "homogenize",
        "plots",
        &mut plot_warnings,
    ));
    files.push("summary.json".into());
    let mut s = summary(out, files);
    s.warnings.extend(plot_warnings);
    write_json(&dir.join("summary.json"), &s)?;
    Ok(s)
}

/// Read a material card (`.json` or `.inp`) from a file.
pub fn read_card(path: &Path) -> Result<MaterialCard, card::CardError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| card::CardError {
        source_name: name.clone(),
        reason: e.to_string(),
    })?;
    MaterialCard::parse(&text, &name)
}

/// Read a stress–strain curve CSV from a file.
pub fn read_curve(path: &Path) -> Result<StressStrainCurve, curve::CurveError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| curve::CurveError {
        source_name: name.clone(),
        reason: e.to_string(),
    })?;
    StressStrainCurve::from_csv(&text, &name)
}

/// Read a relaxation curve CSV from a file.
pub fn read_relaxation(path: &Path) -> Result<RelaxationCurve, curve::CurveError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| curve::CurveError {
        source_name: name.clone(),
        reason: e.to_string(),
    })?;
    RelaxationCurve::from_csv(&text, &name)
}

/// The default output folder of `turf homogenize`.
pub fn default_out_dir() -> PathBuf {
    PathBuf::from("runs/homogenize")
}
