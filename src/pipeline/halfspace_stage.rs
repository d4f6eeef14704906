//! The `halfspace` stage: the scene's sphere on a linear half-space with LJ tractions
//! ([`crate::halfspace`]) — the whole load–approach S-curve with its jump points, and the
//! pull-off with a three-grid error estimate. The law is `halfspace.law` (default
//! `adhesion.law`), thermally shifted when the scene asks for it.

use super::{StageContext, StageError, StageOutput};
use crate::halfspace::{pull_off, trace_curve, HalfspaceParams, Problem};
use crate::report::csv::Table;
use crate::report::plot::{Plot, Series};
use crate::scene::{ResolvedScene, Stage};
use std::collections::BTreeMap;

fn failed(message: String) -> StageError {
    StageError::Failed {
        stage: Stage::Halfspace,
        message,
    }
}

/// Run the stage.
pub(super) fn run(scene: &ResolvedScene, ctx: &StageContext) -> Result<StageOutput, StageError> {
    let s = &scene.scene;
    let (Some(indenter), Some(adhesion), Some(hs)) = (&s.indenter, &s.adhesion, &s.halfspace)
    else {
        return Err(failed(
            "needs [indenter], [adhesion] and [halfspace]".into(),
        ));
    };
    let modulus = scene
        .derived
        .effective_modulus_gpa
        .ok_or_else(|| failed("needs a linear [material] (E*)".into()))?;
    let law = adhesion
        .surface_law_of(hs.law.unwrap_or(adhesion.law), scene.scene.turf.as_ref())
        .map_err(|e| failed(format!("adhesion.thermal_shift: {e}")))?;
    let problem =
        Problem::new(indenter.radius.0, modulus, law).map_err(|e| failed(e.to_string()))?;
    let params = HalfspaceParams {
        cells_per_zone: hs.cells_per_zone,
        ..HalfspaceParams::default()
    };
    let curve = trace_curve(&problem, &params).map_err(|e| failed(e.to_string()))?;
    let sc = curve.scales;
    let mut values = BTreeMap::from([
        ("tabor_mu".to_string(), curve.tabor),
        ("pull_off_normalized".to_string(), curve.pull_off.load),
        ("pull_off_nN".to_string(), curve.pull_off.load * sc.load),
        ("grid_nodes".to_string(), curve.nodes as f64),
        ("wall_time_trace_s".to_string(), curve.cost.wall_time),
    ]);
    for (name, point) in [("jump_in", &curve.jump_in), ("jump_out", &curve.jump_out)] {
        if let Some(p) = point {
            values.insert(format!("{name}_load_nN"), p.load * sc.load);
            values.insert(format!("{name}_depth_nm"), p.approach * sc.gap);
        }
    }
    let mut evaluations = curve.cost.newton_iterations as u64;
    if hs.refinement {
        let p = pull_off(&problem, &params).map_err(|e| failed(e.to_string()))?;
        values.insert("pull_off_normalized".into(), p.normalized);
        values.insert("pull_off_nN".into(), p.force());
        values.insert("pull_off_error_estimate".into(), p.error_estimate);
        values.insert("wall_time_refinement_s".into(), p.cost.wall_time);
        evaluations += p.cost.newton_iterations as u64;
    }
    let depth: Vec<f64> = curve.points.iter().map(|p| p.approach * sc.gap).collect();
    let load: Vec<f64> = curve.points.iter().map(|p| p.load * sc.load).collect();
    let table = Table::new()
        .column("depth_nm", depth.clone())
        .column("load_nN", load.clone())
        .column(
            "contact_radius_nm",
            curve
                .points
                .iter()
                .map(|p| p.contact_radius * sc.radial)
                .collect(),
        )
        .column(
            "central_gap_nm",
            curve
                .points
                .iter()
                .map(|p| p.central_gap * sc.gap)
                .collect(),
        );
    let mut warnings = Vec::new();
    let files = Plot::new(
        "Half-space with LJ adhesion",
        "approach δ (nm)",
        "load P (nN)",
    )
    .with(Series::line("half-space", depth, load))
    .write_or_warn(
        &ctx.out_dir.join("plots"),
        "halfspace_load_depth",
        "plots",
        &mut warnings,
    );
    Ok(StageOutput {
        values,
        tables: vec![("curve".into(), table)],
        evaluations,
        files: files.into_iter().map(Into::into).collect(),
        warnings,
        handoff: None,
    })
}
