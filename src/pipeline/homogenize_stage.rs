//! The `homogenize` stage: a material card (hyperfoam, seed eq. 5.3, plus the Prony terms of
//! `[viscoelastic]`, seed eq. 5.8) fitted to the tangent-modulus law (seed eq. 5.1) or to the
//! discrete stage's compression curve ([`crate::homogenize`]; the branch files the discrete
//! stage wrote into the output folder). Writes `material.json` and
//! `material.inp` in the output folder, and the fit's own files under `homogenize/`.

use super::discrete_stage::{LOADING_CSV, UNLOADING_CSV};
use super::{StageContext, StageError, StageOutput};
use crate::homogenize::{
    self, card::MaterialCard, tangent_law::TangentLaw, HomogenizeParams, Relaxation, Source,
};
use crate::report::{write_atomic, write_json};
use crate::scene::homogenize::Curve;
use crate::scene::{ResolvedScene, Stage};
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
            let file = match h.curve {
                Curve::Loading => LOADING_CSV,
                _ => UNLOADING_CSV,
            };
            let path = ctx.out_dir.join(file);
            let curve = homogenize::read_curve(&path).map_err(|e| failed(e.to_string()))?;
            Source::Curve {
                curve,
                name: format!("discrete stage, {file}"),
            }
        }
    };
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
    let out = homogenize::run(&params).map_err(|e| failed(e.to_string()))?;
    // on a terminal the warnings show as they arise; they are always in homogenize/summary.json
    if let Some(bar) = ctx.progress {
        for w in &out.hyperfoam_fit.warnings {
            bar.println(format!("homogenize: warning: {w}"));
        }
    }
    let report = |source| StageError::Report {
        stage: Stage::Homogenize,
        source,
    };
    let summary = homogenize::write_outputs(&out, &ctx.out_dir.join("homogenize"))
        .map_err(|e| failed(e.to_string()))?;
    write_card(&out.card, ctx).map_err(report)?;
    let mut values = BTreeMap::from([
        ("fit_rms_rel".to_string(), summary.fit_rms_rel),
        ("fit_max_rel".to_string(), summary.fit_max_rel),
        ("strain_max".to_string(), summary.strain_max),
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
    Ok(StageOutput {
        values,
        tables: Vec::new(),
        evaluations: out.hyperfoam_fit.info.evaluations as u64,
        files: files.into_iter().map(Into::into).collect(),
    })
}

/// The cards at the top of the output folder, where the continuum stage and users look.
fn write_card(card: &MaterialCard, ctx: &StageContext) -> Result<(), crate::report::ReportError> {
    write_json(&ctx.out_dir.join("material.json"), &card.to_json())?;
    write_atomic(&ctx.out_dir.join("material.inp"), card.to_inp().as_bytes())
}
