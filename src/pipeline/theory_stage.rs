//! The `theory` stage: closed-form reference curves for the scene's sphere on a linear solid
//! (seed chapter 3) — Hertz always; with `[adhesion]` also JKR, DMT and Maugis–Dugdale at the
//! scene's λ (derived from the law's maximum tension, `scene::Derived`), with their pull-offs
//! under load and displacement control.

use super::{StageContext, StageError, StageOutput};
use crate::report::csv::Table;
use crate::report::plot::{Plot, Series};
use crate::scene::{ResolvedScene, Stage};
use crate::theory::{hertz, Control, Model, Sphere};
use std::collections::BTreeMap;

/// Points along each closed-form curve.
const POINTS: usize = 160;
/// Largest normalised contact radius ā of the adhesive curves: past the JKR zero-load radius
/// (ā ≈ 1.3) by enough to show the Hertz-like branch.
const A_BAR_MAX: f64 = 3.0;
/// Largest contact radius of a Hertz-only curve, as a fraction of R (paraboloid still ~1 %).
const HERTZ_A_OVER_R: f64 = 0.1;

fn failed(message: String) -> StageError {
    StageError::Failed {
        stage: Stage::Theory,
        message,
    }
}

/// Run the stage.
pub(super) fn run(scene: &ResolvedScene, ctx: &StageContext) -> Result<StageOutput, StageError> {
    let radius = scene
        .scene
        .indenter
        .as_ref()
        .map(|i| i.radius.0)
        .ok_or_else(|| failed("needs [indenter]".into()))?;
    let modulus = scene
        .derived
        .effective_modulus_gpa
        .ok_or_else(|| failed("needs a linear [material] (E*)".into()))?;
    let mut values = BTreeMap::new();
    values.insert("effective_modulus_GPa".to_string(), modulus);
    let mut plot = Plot::new("Closed-form sphere curves", "depth (nm)", "load (nN)");
    let mut evaluations = 0u64;

    let table = match (&scene.scene.adhesion, scene.derived.maugis_lambda) {
        (Some(adhesion), Some(lambda)) => {
            let sphere = Sphere::new(radius, modulus, adhesion.gamma.0)
                .map_err(|e| failed(e.to_string()))?;
            let sc = sphere.scales();
            if let Some(mu) = scene.derived.tabor_mu {
                values.insert("tabor_mu".into(), mu);
            }
            values.insert("maugis_lambda".into(), lambda);
            let a_bar: Vec<f64> = (1..=POINTS)
                .map(|i| A_BAR_MAX * (i as f64 / POINTS as f64).powi(2))
                .collect();
            let mut table = Table::new().column(
                "contact_radius_nm",
                a_bar.iter().map(|a| a * sc.length).collect(),
            );
            let models = [
                ("hertz", Model::Hertz),
                ("jkr", Model::Jkr),
                ("dmt", Model::Dmt),
                ("maugis", Model::Maugis { lambda }),
            ];
            for (name, model) in models {
                let mut depth = Vec::with_capacity(POINTS);
                let mut load = Vec::with_capacity(POINTS);
                for &a in &a_bar {
                    let p = model.point(a).map_err(|e| failed(format!("{name}: {e}")))?;
                    depth.push(p.delta_bar * sc.depth);
                    load.push(p.p_bar * sc.force);
                    evaluations += 1;
                }
                if name != "hertz" {
                    for (control, tag) in [
                        (Control::Load, "load"),
                        (Control::Displacement, "displacement"),
                    ] {
                        let p = model
                            .pull_off(control)
                            .map_err(|e| failed(format!("{name} pull-off: {e}")))?;
                        values.insert(format!("{name}_pull_off_normalized_{tag}_control"), p);
                        values.insert(format!("{name}_pull_off_{tag}_control_nN"), p * sc.force);
                    }
                }
                plot = plot.with(Series::line(name, depth.clone(), load.clone()));
                table = table
                    .column(&format!("{name}_depth_nm"), depth)
                    .column(&format!("{name}_load_nN"), load);
            }
            values.insert(
                "jkr_zero_load_radius_nm".into(),
                crate::theory::jkr::zero_load_radius(&sphere),
            );
            table
        }
        _ => {
            let a_max = scene
                .derived
                .contact_radius_nm
                .unwrap_or(HERTZ_A_OVER_R * radius)
                .min(HERTZ_A_OVER_R * radius);
            let a: Vec<f64> = (1..=POINTS)
                .map(|i| a_max * i as f64 / POINTS as f64)
                .collect();
            let depth: Vec<f64> = a.iter().map(|&a| hertz::depth(a, radius)).collect();
            let load: Vec<f64> = a.iter().map(|&a| hertz::load(a, radius, modulus)).collect();
            evaluations += POINTS as u64;
            plot = plot.with(Series::line("hertz", depth.clone(), load.clone()));
            Table::new()
                .column("contact_radius_nm", a)
                .column("hertz_depth_nm", depth)
                .column("hertz_load_nN", load)
        }
    };
    let mut warnings = Vec::new();
    let files = plot.write_or_warn(
        &ctx.out_dir.join("plots"),
        "theory_load_depth",
        "plots",
        &mut warnings,
    );
    Ok(StageOutput {
        values,
        tables: vec![("curves".into(), table)],
        evaluations,
        files: files.into_iter().map(Into::into).collect(),
        warnings,
        handoff: None,
    })
}
