//! The discrete stage's lateral and shear tests (`compression.mode = "lateral" | "shear"`,
//! [`crate::discrete::rve`]): one turf generated and relaxed as for the axial drive, then the
//! periodic box compressed in x, or the tips sheared in x over the clamped bases, along the
//! `[compression]` strain path.
//!
//! Writes the table `discrete_rve_lateral.csv` or `discrete_rve_shear.csv` (every step:
//! strain, nominal stress σ = (1/V₀) dE*/dε in GPa, the equilibrium energy E*, the tips' fall,
//! energies, contacts, cost), the loading part of it in `discrete_rve_{lateral,shear}_loading.csv`
//! (strain, stress_GPa: what `turf homogenize --lateral-curve / --shear-curve` fits) and summary
//! values `rve_*`: the stress at the largest strain, the
//! secant modulus of the first step, and `rve_work_error_rel`, the trapezoidal work
//! V₀ ∫σ dε against the energy change E*(ε_max) − E*(0) along the loading branch — the stress
//! checked against the energy it is the derivative of (path-dependent snaps between steps
//! widen it; a smooth path gives the trapezoid's O(Δε²)).

use super::ensemble;
use super::turf_setup::{failed, static_solver, turf_system, Packed};
use super::{StageContext, StageError, StageOutput};
use crate::discrete::drive::CompressionParams;
use crate::discrete::model::relax;
use crate::discrete::rve::{drive_rve, RveLoading, RveRecord};
use crate::report::csv::Table;
use crate::scene::compression::{Compression, Mode};
use crate::scene::turf::Turf;
use crate::scene::Scene;
use std::collections::BTreeMap;

/// The RVE test a `compression.mode` asks for, with its name; `None` for the axial drive.
pub(super) fn loading(mode: Mode) -> Option<(RveLoading, &'static str)> {
    match mode {
        Mode::Lateral => Some((RveLoading::Lateral, "lateral")),
        Mode::Shear => Some((RveLoading::Shear, "shear")),
        Mode::Axial => None,
    }
}

/// Run the test `loading` ([`loading`]) on realisation 0 of `[turf]`.
pub(super) fn run(
    s: &Scene,
    t: &Turf,
    k: &Compression,
    (loading, name): (RveLoading, &str),
    ctx: &StageContext,
) -> Result<StageOutput, StageError> {
    if t.realisations != 1 {
        return Err(failed(format!(
            "compression.mode = \"{name}\" with turf.realisations = {} is not built: the lateral \
             and shear tests run one turf (set turf.realisations = 1)",
            t.realisations
        )));
    }
    let seed = ensemble::realisation_seed(s.scene.seed, 0);
    let built = turf_system(s, t, k, seed)?;
    let (turf, mut sys) = (built.turf, built.sys);
    let solver = static_solver(k);
    let mut x = turf.coordinates();
    let say = |what: String| {
        if let Some(bar) = ctx.progress {
            bar.set_message(format!("discrete ({name}): {what}"));
        }
    };
    say("relaxing the turf".into());
    let relaxed = relax(&mut sys, &mut x, &solver)
        .map_err(|e| failed(format!("relaxation of the generated turf: {e}")))?;
    // V₀ = A H₀, H₀ the relaxed turf's top (as the drive takes it)
    let volume = sys.area * sys.height(&x);
    let params = CompressionParams {
        strain_max: k.to.0,
        steps: k.steps,
        unload: k.unload,
        retract: None,
    };
    let mut observe = |r: &RveRecord| {
        say(format!(
            "step {}, strain {:.3}, stress {:.3e} GPa",
            r.step, r.strain, r.stress
        ))
    };
    let run = drive_rve(&mut sys, &mut x, loading, &params, &solver, &mut observe)
        .map_err(|e| failed(format!("{name} test: {e}")))?;
    let records = run.records;
    // the loading records reached (all of them when the drive went to the end)
    let loaded = records.len().min(k.steps + 1);
    if loaded < 2 {
        return Err(failed(format!(
            "{name} test: {}",
            run.stopped.as_deref().unwrap_or("no step reached")
        )));
    }

    let mut values = BTreeMap::new();
    let mut put = |key: &str, v: f64| {
        values.insert(format!("rve_{key}"), v);
    };
    let peak = &records[loaded - 1];
    let first = &records[1];
    put("stress_at_peak_GPa", peak.stress);
    put("secant_modulus_first_step_GPa", first.stress / first.strain);
    put("work_error_rel", work_error(&records[..loaded], volume));
    put("tip_drop_at_peak_nm", peak.tip_drop);
    put("contacts_at_peak", peak.state.contacts as f64);
    put("relaxed_contacts", relaxed.state.contacts as f64);
    // the closest two tubes' surfaces came over the whole drive (negative: interpenetration);
    // absent when no pair was ever within the van der Waals cutoff
    let closest = records
        .iter()
        .map(|r| r.state.min_gap)
        .fold(relaxed.state.min_gap, f64::min);
    if closest.is_finite() {
        put("min_gap_nm", closest);
    }
    put("volume_nm3", volume);
    for (name, v) in built.packed.iter().flat_map(Packed::values) {
        put(name, v);
    }
    put(
        "wall_time_s",
        relaxed.info.cost.seconds + records.iter().map(|r| r.cost.seconds).sum::<f64>(),
    );
    put(
        "iterations",
        records.iter().map(|r| r.cost.iterations).sum::<usize>() as f64,
    );
    let evaluations = relaxed.info.cost.gradient_evaluations
        + records
            .iter()
            .map(|r| r.cost.gradient_evaluations)
            .sum::<usize>();
    Ok(StageOutput {
        values,
        tables: vec![
            (format!("rve_{name}"), table(&records)),
            (
                format!("rve_{name}_loading"),
                loading_table(&records[..loaded]),
            ),
        ],
        evaluations: evaluations as u64,
        files: Vec::new(),
        warnings: run
            .stopped
            .map(|why| format!("{name} test stopped early at {why}"))
            .into_iter()
            .collect(),
        handoff: None,
    })
}

/// |V₀ ∫σ dε − ΔE*| / |ΔE*| over the loading records (trapezoids; `volume` V₀ in nm³).
fn work_error(loading: &[RveRecord], volume: f64) -> f64 {
    let work: f64 = loading
        .windows(2)
        .map(|w| 0.5 * (w[0].stress + w[1].stress) * (w[1].strain - w[0].strain))
        .sum::<f64>()
        * volume;
    let change = loading[loading.len() - 1].energy - loading[0].energy;
    (work - change).abs() / change.abs()
}

/// The loading branch as a curve `turf homogenize --lateral-curve | --shear-curve` reads.
fn loading_table(records: &[RveRecord]) -> Table {
    Table::new()
        .column("strain", records.iter().map(|r| r.strain).collect())
        .column("stress_GPa", records.iter().map(|r| r.stress).collect())
}

fn table(records: &[RveRecord]) -> Table {
    let col = |f: &dyn Fn(&RveRecord) -> f64| records.iter().map(f).collect::<Vec<f64>>();
    Table::new()
        .column("step", col(&|r| r.step as f64))
        .column("loading", col(&|r| if r.loading { 1.0 } else { 0.0 }))
        .column("strain", col(&|r| r.strain))
        .column("stress_GPa", col(&|r| r.stress))
        .column("energy_aJ", col(&|r| r.energy))
        .column("tip_drop_nm", col(&|r| r.tip_drop))
        .column("bending_aJ", col(&|r| r.state.energy.bending))
        .column("stretching_aJ", col(&|r| r.state.energy.stretching))
        .column("vdw_aJ", col(&|r| r.state.energy.vdw))
        .column("contacts", col(&|r| r.state.contacts as f64))
        .column("iterations", col(&|r| r.cost.iterations as f64))
        .column("solve_s", col(&|r| r.cost.seconds))
}
