//! The `homogenize` stage: a material card (hyperfoam, seed eq. 5.3, plus the Prony terms of
//! `[viscoelastic]`, seed eq. 5.8) fitted to the tangent-modulus law (seed eq. 5.1) or to the
//! discrete stage's compression curve ([`crate::homogenize`]; the branches the discrete stage
//! handed over, [`super::handoff`]). Writes `material.json` and `material.inp` in the output
//! folder, and the fit's own files under `homogenize/`; hands the card to the continuum stage.
//!
//! For an ensemble (`turf.realisations` > 1) the card is fitted to the realisations' mean
//! curve, and the same fit is repeated on every realisation's own curve to show how far the
//! card's constants move from one turf to the next: the mean, 95 % interval, minimum and
//! maximum of each constant ([`super::ensemble`]) in the summary (`card_*`),
//! `homogenize/ensemble.json` and `homogenize/card_spread.csv` (the term constants over the
//! cards with the mean card's number of terms, E⁰ and the misfit over all).

use super::ensemble;
use super::handoff::{Compression, Curves, Filed, Handoff};
use super::{StageContext, StageError, StageOutput};
use crate::homogenize::curve::StressStrainCurve;
use crate::homogenize::{
    self, card::MaterialCard, tangent_law::TangentLaw, HomogenizeOutput, HomogenizeParams,
    Relaxation, Source,
};
use crate::numerics::statistics::Estimate;
use crate::report::csv::Table;
use crate::report::{write_atomic, write_json};
use crate::scene::homogenize::{Curve, Homogenize};
use crate::scene::{ResolvedScene, Scene, Stage};
use rayon::prelude::*;
use std::collections::BTreeMap;

fn failed(message: String) -> StageError {
    StageError::Failed {
        stage: Stage::Homogenize,
        message,
    }
}

/// Run the stage.
pub(super) fn run(scene: &ResolvedScene, ctx: &StageContext) -> Result<StageOutput, StageError> {
    let s = &scene.scene;
    let h = s
        .homogenize
        .as_ref()
        .ok_or_else(|| failed("needs [homogenize]".into()))?;
    let realisations = s.turf.as_ref().map_or(1, |t| t.realisations);
    let mut curves = None;
    let source = match h.curve {
        Curve::TangentLaw => {
            let (Some(e0), Some(e_inf), Some(eps0)) = (h.e0, h.e_inf, h.eps0) else {
                return Err(failed(
                    "curve = \"tangent-law\" needs e0, e_inf and eps0".into(),
                ));
            };
            Source::TangentLaw(
                TangentLaw::new(e0.0, e_inf.0, eps0.0).map_err(|e| failed(e.to_string()))?,
            )
        }
        Curve::Loading | Curve::Unloading => {
            if !ctx.previous.iter().any(|r| r.stage == Stage::Discrete) {
                return Err(failed(
                    "fitting the discrete stage's compression curve needs the discrete stage \
                     to have run first"
                        .into(),
                ));
            }
            let compression = curves.insert(compression(ctx)?);
            let what = match realisations > 1 {
                false => "discrete stage".to_string(),
                true => ensemble_name(ctx, realisations),
            };
            let filed = branch(&compression.fitted, h.curve)?;
            curve_source(filed, ctx, format!("{what}, {}", filed.file.display()))?
        }
    };
    let params = fit_params(h, s, source)?;
    let out = homogenize::run(&params).map_err(|e| failed(e.to_string()))?;
    let report = |source| StageError::Report {
        stage: Stage::Homogenize,
        source,
    };
    let summary = homogenize::write_outputs(&out, &ctx.out_dir.join("homogenize"))
        .map_err(|e| failed(e.to_string()))?;
    write_card(&out.card, ctx).map_err(report)?;
    let handoff = Some(Handoff::Card(out.card.clone()));
    let mut values = BTreeMap::from([
        ("fit_rms_rel".to_string(), summary.fit_rms_rel),
        ("fit_max_rel".to_string(), summary.fit_max_rel),
        ("strain_max".to_string(), summary.strain_max),
        (
            "hyperfoam_terms_requested".to_string(),
            summary.terms_requested as f64,
        ),
        (
            "hyperfoam_terms_used".to_string(),
            summary.terms_used as f64,
        ),
        ("wall_time_fit_s".to_string(), out.seconds),
    ]);
    let m = &out.hyperfoam_fit.material;
    for (i, t) in m.terms.iter().enumerate() {
        values.insert(format!("hyperfoam_mu{}_GPa", i + 1), t.mu);
        values.insert(format!("hyperfoam_alpha{}", i + 1), t.alpha);
        values.insert(format!("hyperfoam_beta{}", i + 1), t.beta);
    }
    let mut files = vec!["material.json".to_string(), "material.inp".to_string()];
    files.extend(summary.files.iter().map(|f| format!("homogenize/{f}")));
    if let Some(compression) = curves.filter(|_| realisations > 1) {
        let spread = card_spread(h, s, ctx, &compression, &summary)?;
        values.extend(spread.values);
        files.extend(spread.files);
    }
    Ok(StageOutput {
        values,
        tables: Vec::new(),
        evaluations: out.hyperfoam_fit.info.evaluations as u64,
        files: files.into_iter().map(Into::into).collect(),
        warnings: summary.warnings.clone(),
        handoff,
    })
}

/// The cards at the top of the output folder, where the continuum stage and users look.
fn write_card(card: &MaterialCard, ctx: &StageContext) -> Result<(), crate::report::ReportError> {
    write_json(&ctx.out_dir.join("material.json"), &card.to_json())?;
    write_atomic(&ctx.out_dir.join("material.inp"), card.to_inp().as_bytes())
}

/// How the ensemble's mean curve is named in the card's provenance: over how many of the
/// `asked` realisations (the discrete stage's `realisations_finished`).
fn ensemble_name(ctx: &StageContext, asked: usize) -> String {
    let finished = ctx
        .previous
        .iter()
        .find(|r| r.stage == Stage::Discrete)
        .and_then(|r| r.values.get("realisations_finished"))
        .map_or(asked, |&n| n as usize);
    if finished == asked {
        format!("mean of the discrete stage's {asked} realisations")
    } else {
        format!("mean of the {finished} of the discrete stage's {asked} realisations that finished")
    }
}

/// The compression curves the discrete stage handed over.
fn compression(ctx: &StageContext) -> Result<Compression, StageError> {
    match ctx
        .handed(Stage::Discrete)
        .map_err(|e| failed(e.to_string()))?
    {
        Some(Handoff::Compression(c)) => Ok(c),
        _ => Err(failed(
            "the discrete stage compressed no turf (explicit rods, or a lateral or shear test): \
             there is no compression curve to fit"
                .into(),
        )),
    }
}

/// The branch of `curves` the scene fits.
fn branch(curves: &Curves, curve: Curve) -> Result<&Filed, StageError> {
    match curve {
        Curve::Unloading => curves.unloading.as_ref().ok_or_else(|| {
            failed(format!(
                "homogenize.curve = \"unloading\": the turf was not unloaded ({} has only a \
                 loading branch)",
                curves.loading.file.display()
            ))
        }),
        _ => Ok(&curves.loading),
    }
}

/// A handed-over branch as the fit's source, named `name` in the card's provenance (its
/// checks name the branch's file in the output folder).
fn curve_source(filed: &Filed, ctx: &StageContext, name: String) -> Result<Source, StageError> {
    let src = ctx.out_dir.join(&filed.file).display().to_string();
    let b = &filed.branch;
    let curve = StressStrainCurve::new(b.strain.clone(), b.stress.clone(), None, &src)
        .map_err(|e| failed(e.to_string()))?;
    Ok(Source::Curve { curve, name })
}

/// The `[homogenize]` and `[viscoelastic]` settings around a source.
fn fit_params(h: &Homogenize, s: &Scene, source: Source) -> Result<HomogenizeParams, StageError> {
    let mut params = HomogenizeParams::new(source);
    params.terms = h.terms;
    if let Some(e) = h.strain_max {
        params.strain_max = e.0;
    }
    params.pin_initial_modulus = h.pin_e0;
    params.relaxation = match &s.viscoelastic {
        None => None,
        Some(v) if v.g.len() == 1 => Some(Relaxation::Law {
            mu_bar: v.g[0].0,
            tau: v.tau[0].0,
        }),
        Some(v) => {
            return Err(failed(format!(
                "[viscoelastic] has {} Prony terms; the card writer takes the seed's one-term \
                 relaxation (5.8) from a scene — fit several terms with `turf homogenize \
                 --relaxation-curve`",
                v.g.len()
            )))
        }
    };
    Ok(params)
}

/// What the spread of the card over the realisations adds to the stage's output.
struct Spread {
    values: BTreeMap<String, f64>,
    files: Vec<String>,
}

/// A card's constant: (name without unit, unit suffix, value).
type Constant = (String, &'static str, f64);

/// The card's constants of one fit: the initial Young's modulus, then μᵢ, αᵢ, βᵢ of the terms
/// in ascending αᵢ (a fit may list its terms in any order), then the fit's relative RMS misfit
/// to its own curve.
fn card_constants(out: &HomogenizeOutput) -> Vec<Constant> {
    let m = &out.hyperfoam_fit.material;
    let mut terms = m.terms.clone();
    terms.sort_by(|a, b| a.alpha.total_cmp(&b.alpha));
    let mut c = vec![("youngs0".to_string(), "_GPa", m.initial_youngs_modulus())];
    for (i, t) in terms.iter().enumerate() {
        c.push((format!("mu{}", i + 1), "_GPa", t.mu));
        c.push((format!("alpha{}", i + 1), "", t.alpha));
        c.push((format!("beta{}", i + 1), "", t.beta));
    }
    c.push(("fit_rms_rel".to_string(), "", out.hyperfoam_fit.rms_rel));
    c
}

/// The realisations' cards reduced constant by constant (the summary's `card_*` estimates,
/// their JSON, the realisations with the mean card's number of terms, `card_spread.csv`).
struct Reduced {
    values: BTreeMap<String, f64>,
    estimates: serde_json::Map<String, serde_json::Value>,
    alike: Vec<usize>,
    table: Table,
}

/// Reduce the realisations' `cards` over the realisations. A card that kept another number of
/// terms than the mean card's `terms` (a degenerate term dropped in one realisation and not in
/// another) numbers its terms differently: its μᵢ, αᵢ, βᵢ are not those of the others, so the
/// spread of the term constants is over the cards with the mean card's count (the table's
/// rows), that of E⁰ and the misfit over every card.
fn reduce_cards(cards: &[(usize, Vec<Constant>)], terms: usize) -> Reduced {
    let alike: Vec<&(usize, Vec<Constant>)> = cards
        .iter()
        .filter(|(_, c)| c.len() == constants_of(terms))
        .collect();
    let mut values = BTreeMap::from([
        ("realisation_cards".to_string(), cards.len() as f64),
        ("realisation_cards_alike".to_string(), alike.len() as f64),
    ]);
    let mut estimates = serde_json::Map::new();
    let mut table = Table::new().column(
        "realisation",
        alike.iter().map(|(k, _)| *k as f64).collect(),
    );
    let template = alike.first().copied().or(cards.first()).map(|(_, c)| c);
    for (i, (name, unit, _)) in template.into_iter().flatten().enumerate() {
        let per_term = ["mu", "alpha", "beta"].iter().any(|p| name.starts_with(p));
        let samples: Vec<f64> = if per_term {
            alike.iter().map(|(_, c)| c[i].2).collect()
        } else {
            cards
                .iter()
                .filter_map(|(_, c)| c.iter().find(|x| &x.0 == name).map(|x| x.2))
                .collect()
        };
        if let Some(e) = Estimate::of(&samples) {
            ensemble::put_estimate(&mut values, &format!("card_{name}"), unit, &e);
            estimates.insert(format!("{name}{unit}"), ensemble::estimate_json(&e));
        }
        table = table.column(
            &format!("{name}{unit}"),
            alike.iter().map(|(_, c)| c[i].2).collect(),
        );
    }
    Reduced {
        values,
        estimates,
        alike: alike.iter().map(|(k, _)| *k).collect(),
        table,
    }
}

/// How many constants [`card_constants`] lists for a card of `terms` terms.
fn constants_of(terms: usize) -> usize {
    2 + 3 * terms
}

/// Fit the card to every realisation's own curve (the branch the scene fits, of the
/// realisations the discrete stage handed over in `compression`) and reduce each constant over
/// the realisations. A realisation whose fit fails is named in `homogenize/ensemble.json` and
/// left out.
fn card_spread(
    h: &Homogenize,
    s: &Scene,
    ctx: &StageContext,
    compression: &Compression,
    mean: &homogenize::Summary,
) -> Result<Spread, StageError> {
    let fits: Vec<(usize, Result<Vec<Constant>, String>)> = compression
        .realisations
        .par_iter()
        .map(|(k, curves)| {
            let fit = branch(curves, h.curve)
                .and_then(|f| {
                    let name = format!("realisation {k}, {}", f.file.display());
                    curve_source(f, ctx, name)
                })
                .and_then(|src| fit_params(h, s, src))
                .map_err(|e| e.to_string())
                .and_then(|p| homogenize::run(&p).map_err(|e| e.to_string()));
            (*k, fit.map(|o| card_constants(&o)))
        })
        .collect();
    let mut cards: Vec<(usize, Vec<Constant>)> = Vec::new();
    let mut failures: Vec<serde_json::Value> = Vec::new();
    for (k, fit) in fits {
        match fit {
            Ok(c) => cards.push((k, c)),
            Err(e) => failures.push(serde_json::json!({"realisation": k, "error": e})),
        }
    }
    let reduced = reduce_cards(&cards, mean.terms_used);
    let mut values = reduced.values;
    values.insert(
        "realisation_cards_failed".to_string(),
        failures.len() as f64,
    );
    let (estimates, alike, table) = (reduced.estimates, reduced.alike, reduced.table);
    let json = serde_json::json!({
        "mean_card": {
            "fitted_to": "the mean curve of the realisations",
            "fit_rms_rel_to_mean_curve": mean.fit_rms_rel,
            "fit_max_rel_to_mean_curve": mean.fit_max_rel,
        },
        "realisation_cards": {
            "what": "the same fit repeated on each realisation's own curve; terms in ascending alpha",
            "confidence_interval": ensemble::INTERVAL_DEFINITION,
            "constants": estimates,
            "fitted": cards.len(),
            "with_the_mean_cards_terms": alike,
            "term_constants_over": "the cards with the mean card's number of terms (listed); \
                youngs0 and fit_rms_rel over every fitted card",
            "failed": failures,
        },
    });
    let report = |source| StageError::Report {
        stage: Stage::Homogenize,
        source,
    };
    let dir = ctx.out_dir.join("homogenize");
    write_json(&dir.join("ensemble.json"), &json).map_err(report)?;
    table.write(&dir.join("card_spread.csv")).map_err(report)?;
    Ok(Spread {
        values,
        files: vec![
            "homogenize/ensemble.json".into(),
            "homogenize/card_spread.csv".into(),
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A card of `terms` terms, E⁰ = `e0`, term i of μ = e0/(2·terms), α = 10(i + 1), β = 0.
    fn card(e0: f64, terms: usize, rms: f64) -> Vec<Constant> {
        let mut c = vec![("youngs0".to_string(), "_GPa", e0)];
        for i in 0..terms {
            c.push((format!("mu{}", i + 1), "_GPa", e0 / (2.0 * terms as f64)));
            c.push((format!("alpha{}", i + 1), "", 10.0 * (i + 1) as f64));
            c.push((format!("beta{}", i + 1), "", 0.0));
        }
        c.push(("fit_rms_rel".to_string(), "", rms));
        c
    }

    #[test]
    fn cards_that_kept_other_term_counts_are_reduced_where_they_compare() {
        // realisations 0 and 2 kept two terms like the mean card, realisation 1 dropped one
        let cards = vec![
            (0, card(0.02, 2, 0.05)),
            (1, card(0.04, 1, 0.07)),
            (2, card(0.03, 2, 0.06)),
        ];
        let r = reduce_cards(&cards, 2);
        assert_eq!(r.alike, vec![0, 2]);
        assert_eq!(r.values["realisation_cards"], 3.0);
        assert_eq!(r.values["realisation_cards_alike"], 2.0);
        // E⁰ and the misfit over all three, the terms over the two alike
        assert_eq!(r.values["card_youngs0_n"], 3.0);
        assert!((r.values["card_youngs0_mean_GPa"] - 0.03).abs() < 1e-15);
        assert!((r.values["card_fit_rms_rel_mean"] - 0.06).abs() < 1e-15);
        assert_eq!(r.values["card_mu2_n"], 2.0);
        assert!((r.values["card_mu1_mean_GPa"] - 0.00625).abs() < 1e-15);
        assert_eq!(r.values["card_alpha2_mean"], 20.0);
        // when no card has the mean card's count the term constants have no spread
        let r = reduce_cards(&cards, 3);
        assert!(r.alike.is_empty());
        assert_eq!(r.values["card_youngs0_n"], 3.0);
        assert!(!r.values.keys().any(|k| k.starts_with("card_mu")));
    }
}
