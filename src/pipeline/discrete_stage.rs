//! The `discrete` stage. `[rods]`: explicit rods in equilibrium under their end loads (tip
//! displacements, node positions as `discrete_rods_nodes.csv`). `[turf]`: a turf generated, relaxed (contacts form, E = U − Γ of seed eq.
//! 1.1) and compressed by the `[compression]` platen to the scene's strain and back
//! ([`crate::discrete`]); the curve analysed (σ₀, the tangent law (5.1), hysteresis).
//!
//! Writes `stress_strain.csv` (every step: strain, stress_GPa, energies, contacts, cost),
//! `stress_strain_loading.csv` and `stress_strain_unloading.csv` (strain ascending, the curves
//! the homogenize stage fits), `discrete_analysis.json` (the fit or why it failed), the
//! tangent moduli as `discrete_tangent.csv`, with `indenter = "sphere"` the load–depth curve
//! `load_depth.csv` (depth below the turf top, load on the sphere), plots under `plots/`, and, with `[output] vtk`,
//! the tubes as VTK polylines at the relaxed state, the peak strain and the end
//! (`vtk/discrete_step_NNN.vtu`). After every strain step it saves `discrete_checkpoint.json`
//! ([`crate::discrete::checkpoint`]); with `--resume` ([`StageContext::resume`]) a run of the
//! same scene continues after the last saved step and gives the uninterrupted curve.
//!
//! An ensemble (`turf.realisations` = N > 1, [`super::ensemble`]) runs the N realisations in
//! parallel (rayon, one per thread), each with its own seed, checkpoint and files: realisation
//! 0 exactly as a single run (its values under the single run's names), realisation k in
//! `realisations/rKKK/` (its curves, analysis, checkpoint and VTK; its plot is the
//! ensemble's). Then the stage reduces them: `discrete_ensemble.csv` (σ at every step
//! of the path: mean, 95 % interval, each realisation), the mean's branches
//! `ensemble_stress_strain_{loading,unloading}.csv`, `discrete_ensemble.json` (seeds, the
//! estimates of the peak stress, σ₀, E⁰, E^∞, ε₀ and the hysteresis, the failures), the
//! summary's `ensemble_*` values and `plots/discrete_ensemble.{svg,png}` (the band). A
//! realisation that fails is named with its seed and reason, keeps the steps it reached, and
//! the ensemble goes on without it; the stage fails only when every realisation failed.
//! In the work items of a shard or MPI run ([`super::items`],
//! [`StageContext::keep_realisations`]) each realisation keeps its result (or its engine's
//! failure) in its folder, `discrete_realisation.json`, with the inputs it came from; the
//! point's reduction, and any later such run into the folder with the same inputs, reuses it
//! instead of recomputing it.

use super::ensemble::{self, PathEnsemble};
use super::handoff::{
    self, Curves, Filed, Handoff, ENSEMBLE_LOADING_CSV, ENSEMBLE_UNLOADING_CSV, LOADING_CSV,
    UNLOADING_CSV,
};
use super::turf_setup::{failed, static_solver, turf_system, vdw_params, Packed};
use super::{StageContext, StageError, StageOutput};
use crate::discrete::checkpoint::{Checkpoint, SavedRelaxation};
use crate::discrete::drive::{
    compress, CompressionParams, DriveError, Resume, Retract, SavedStep, StepRecord,
};
use crate::discrete::explicit_rods::{EndCondition, ExplicitRods, RodSpec};
use crate::discrete::model::{relax, State, StaticSolver, TurfSystem};
use crate::discrete::rod::RodStiffness;
use crate::discrete::rve::OVERLAP_LIMIT_NM;
use crate::discrete::solve_newton::{is_local_minimum, minimize_newton, NewtonParams};
use crate::discrete::structure::Structure;
use crate::discrete::turf::Turf;
use crate::discrete::vdw::VdwParams;
use crate::discrete::vdw_term::TubeLayout;
use crate::homogenize::curve_analysis::{Branch, CurveAnalysis};
use crate::homogenize::tangent_law::TangentLaw;
use crate::numerics::interpolate;
use crate::report::csv::Table;
use crate::report::plot::{Plot, Series};
use crate::report::vtk::{CellKind, DataArray, Grid};
use crate::report::{write_json, ReportError};
use crate::scene::compression::{Compression, Indenter, Platen};
use crate::scene::rods::End;
use crate::scene::{ResolvedScene, Stage};
use crate::theory::micromech::ShapeFactor;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The drive's checkpoint in the output folder, rewritten after every step (`--resume`).
pub const CHECKPOINT: &str = "discrete_checkpoint.json";

/// The relaxation as the summary reports it: the generated and relaxed states and the cost
/// (from the solve, or from the checkpoint of a resumed run).
struct RelaxReport {
    initial: State,
    state: State,
    cost: SavedRelaxation,
}

fn report(source: ReportError) -> StageError {
    StageError::Report {
        stage: Stage::Discrete,
        source,
    }
}

/// The sphere's load–depth curve (every step: depth below the first contact height, load).
const LOAD_DEPTH_CSV: &str = "load_depth.csv";

/// Run the stage: the rods, one turf, or an ensemble of `turf.realisations` turfs.
pub(super) fn run(scene: &ResolvedScene, ctx: &StageContext) -> Result<StageOutput, StageError> {
    let s = &scene.scene;
    if let Some(r) = &s.rods {
        if s.compression.is_some() {
            return Err(failed(
                "[rods] with [compression] is not built: explicit rods are solved under their \
                 end loads"
                    .into(),
            ));
        }
        return run_rods(r, s.output.vtk, ctx);
    }
    let (t, k) = turf_and_compression(s)?;
    if let Some(test) = super::rve_stage::loading(k.mode) {
        return super::rve_stage::run(s, t, k, test, ctx);
    }
    let job = |index: usize| Job::new(s, t, k, index, ctx);
    if t.realisations == 1 {
        return run_realisation(&job(0), &AtomicUsize::new(0)).map(Finished::into_output);
    }
    let done = AtomicUsize::new(0);
    let results: Vec<Result<Finished, StageError>> = (0..t.realisations)
        .into_par_iter()
        .map(|i| {
            let r = if ctx.keep_realisations {
                kept_or_run(&job(i), &done)
            } else {
                run_realisation(&job(i), &done)
            };
            done.fetch_add(1, Ordering::Relaxed);
            r
        })
        .collect();
    ensemble_output(s, results, ctx)
}

/// A work item ([`super::items`]): realisation `index` of the ensemble of `scene` (`dir` the
/// point's folder), kept in its folder for the stage that reduces the ensemble. `Ok(true)`
/// when an earlier run had kept it; a realisation that failed is kept as a failure and
/// returned as the error.
pub(super) fn run_realisation_item(
    scene: &ResolvedScene,
    dir: &Path,
    index: usize,
    resume: bool,
) -> Result<bool, StageError> {
    let s = &scene.scene;
    let (t, k) = turf_and_compression(s)?;
    if super::rve_stage::loading(k.mode).is_some() {
        return Err(failed(
            "compression.mode = \"lateral\" or \"shear\" with turf.realisations > 1 is not \
             built: the lateral and shear tests run one turf (set turf.realisations = 1)"
                .into(),
        ));
    }
    let ctx = StageContext {
        out_dir: dir,
        previous: &[],
        handoffs: &[],
        progress: None,
        resume,
        keep_realisations: true,
    };
    let job = Job::new(s, t, k, index, &ctx);
    let kept = kept(&job)?.is_some();
    kept_or_run(&job, &AtomicUsize::new(0)).map(|_| kept)
}

/// The `[turf]` and `[compression]` of a turf scene, or why the stage cannot run it.
fn turf_and_compression(
    s: &crate::scene::Scene,
) -> Result<(&crate::scene::turf::Turf, &Compression), StageError> {
    let (Some(t), Some(k)) = (&s.turf, &s.compression) else {
        return Err(failed("needs [turf] and [compression]".into()));
    };
    if k.platen == Platen::Bonded {
        return Err(failed(
            "compression.platen = \"bonded\" is not built: the platen is frictionless".into(),
        ));
    }
    Ok((t, k))
}

/// The file in a realisation's folder that keeps its result ([`kept_or_run`]).
const REALISATION_RESULT: &str = "discrete_realisation.json";

/// A realisation's result as kept on disk: the inputs it was computed from, and what it
/// gave or why it failed.
#[derive(serde::Serialize, serde::Deserialize)]
struct Kept {
    inputs: String,
    result: Result<Finished, String>,
}

/// The result kept for `job` by an earlier run or work item with the same inputs, with
/// every file it lists still there; `None` when there is none.
fn kept(job: &Job) -> Result<Option<Result<Finished, String>>, StageError> {
    let inputs = job.inputs()?;
    let path = job.ctx.out_dir.join(job.rel()).join(REALISATION_RESULT);
    let Some(kept) = std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<Kept>(&t).ok())
    else {
        return Ok(None);
    };
    let complete = match &kept.result {
        Ok(f) => f.index == job.index && f.files.iter().all(|p| job.ctx.out_dir.join(p).is_file()),
        Err(_) => true,
    };
    Ok((kept.inputs == inputs && complete).then_some(kept.result))
}

/// Realisation `job.index` of an ensemble: the result an earlier run or work item kept for
/// the same inputs (a failure too: the engines are deterministic), else computed and kept. An
/// interrupted realisation is not kept: it continues from its checkpoint with `--resume`.
fn kept_or_run(job: &Job, done: &AtomicUsize) -> Result<Finished, StageError> {
    if let Some(result) = kept(job)? {
        return result.map_err(failed);
    }
    let result = run_realisation(job, done);
    let keep = match &result {
        Ok(f) => Ok(f),
        Err(StageError::Failed { message, .. }) => Err(message.clone()),
        Err(_) => return result,
    };
    let path = job.ctx.out_dir.join(job.rel()).join(REALISATION_RESULT);
    let kept = serde_json::json!({"inputs": job.inputs()?, "result": keep});
    write_json(&path, &kept).map_err(report)?;
    result
}

/// One realisation of the turf to compress.
struct Job<'a> {
    scene: &'a crate::scene::Scene,
    turf: &'a crate::scene::turf::Turf,
    compression: &'a Compression,
    /// realisation index k (0 for a single turf)
    index: usize,
    /// realisations in the ensemble
    count: usize,
    /// the turf's seed ([`ensemble::realisation_seed`])
    seed: u64,
    ctx: &'a StageContext<'a>,
}

impl<'a> Job<'a> {
    fn new(
        scene: &'a crate::scene::Scene,
        turf: &'a crate::scene::turf::Turf,
        compression: &'a Compression,
        index: usize,
        ctx: &'a StageContext<'a>,
    ) -> Self {
        Job {
            scene,
            turf,
            compression,
            index,
            count: turf.realisations,
            seed: ensemble::realisation_seed(scene.scene.seed, index),
            ctx,
        }
    }

    /// What the realisation's result depends on, as canonical JSON: its seed, the turf
    /// without the ensemble's size, the compression, the sphere's adhesion, the files asked
    /// for, the build ([`crate::BUILD`]).
    fn inputs(&self) -> Result<String, StageError> {
        let single = crate::scene::turf::Turf {
            realisations: 1,
            ..self.turf.clone()
        };
        let s = self.scene;
        let v = serde_json::to_value((
            crate::BUILD,
            self.seed,
            &single,
            self.compression,
            &s.adhesion,
            (s.output.vtk, s.output.plots),
        ))
        .map_err(|e| failed(format!("realisation inputs: {e}")))?;
        Ok(super::cache::canonical_json(&v))
    }

    /// What the realisation's checkpoint is valid for: its own seed and the sections without
    /// the ensemble's size (a checkpoint does not depend on how many realisations run beside it).
    fn fingerprint(&self) -> Result<String, StageError> {
        let single = crate::scene::turf::Turf {
            realisations: 1,
            ..self.turf.clone()
        };
        serde_json::to_string(&(self.seed, &single, self.compression))
            .map_err(|e| failed(format!("scene fingerprint: {e}")))
    }

    /// The realisation's folder relative to the output folder.
    fn rel(&self) -> PathBuf {
        ensemble::realisation_dir(self.index)
    }

    /// The progress message: as a single run has it, prefixed by the ensemble's count.
    fn say(&self, done: &AtomicUsize, what: String) {
        let Some(bar) = self.ctx.progress else {
            return;
        };
        if self.count == 1 {
            bar.set_message(format!("discrete: {what}"));
        } else {
            bar.set_message(format!(
                "discrete: {}/{} realisations done; r{:03}: {what}",
                done.load(Ordering::Relaxed),
                self.count,
                self.index
            ));
        }
    }
}

/// A realisation compressed: its curve, its analysis and what the summary reports of it.
#[derive(serde::Serialize, serde::Deserialize)]
struct Finished {
    index: usize,
    seed: u64,
    /// the path every step: nominal strain, whether on the way down, nominal stress (GPa)
    path: Vec<(f64, bool, f64)>,
    values: BTreeMap<String, f64>,
    /// the tangent table (realisation 0's goes into the summary's tables)
    tangent: Table,
    /// files written, relative to the output folder
    files: Vec<PathBuf>,
    evaluations: u64,
    /// plots that could not be written
    warnings: Vec<String>,
}

impl Finished {
    /// The stage's output for a single realisation (the run without an ensemble).
    fn into_output(self) -> StageOutput {
        let compression = handoff::Compression {
            fitted: self.curves(),
            realisations: Vec::new(),
        };
        StageOutput {
            values: self.values,
            tables: vec![("tangent".into(), self.tangent)],
            evaluations: self.evaluations,
            files: self.files,
            warnings: self.warnings,
            handoff: Some(Handoff::Compression(compression)),
        }
    }

    /// Its loading and unloading branches (as [`analyse`] splits them), in the files
    /// [`write_realisation`] writes them to.
    fn curves(&self) -> Curves {
        let strain: Vec<f64> = self.path.iter().map(|p| p.0).collect();
        let loading: Vec<bool> = self.path.iter().map(|p| p.1).collect();
        let stress: Vec<f64> = self.path.iter().map(|p| p.2).collect();
        let (l, u) = ensemble::branches(&strain, &stress, &loading);
        filed_curves(
            l,
            u,
            &ensemble::realisation_dir(self.index),
            (LOADING_CSV, UNLOADING_CSV),
        )
    }
}

/// Generate, relax and compress one realisation, writing its files into its folder. A drive
/// that fails part-way writes the steps it reached (`stress_strain.csv`) before the error.
fn run_realisation(job: &Job, done: &AtomicUsize) -> Result<Finished, StageError> {
    let (s, t, k) = (job.scene, job.turf, job.compression);
    let built = turf_system(s, t, k, job.seed)?;
    let (turf, mut sys, vdw) = (built.turf, built.sys, built.vdw);
    let solver = static_solver(k);
    let mut x = turf.coordinates();
    let fingerprint = job.fingerprint()?;
    let (relaxed, resume) = relaxed_start(job, &mut sys, &mut x, &solver, &fingerprint, done)?;
    // the relaxed structure, before the compression moves `x`
    let structure = vdw.as_ref().and_then(|v| sys.structure(&x, v.gap_switch));
    let start = (&relaxed, resume.as_ref(), fingerprint.as_str());
    let run = Compressed::drive(job, &turf, &mut sys, &mut x, &solver, start, done)?;
    // the curve is the drive's loading and unloading; a retract's steps (negative strain)
    // carry the pull-off alone
    let curve = &run.records[..run.records.len() - k.retract_steps()];
    let analysis = analyse(curve);
    let written = write_realisation(job, &sys, structure.as_ref(), vdw.as_ref(), &run, &analysis)?;
    let mut values: BTreeMap<String, f64> = written.structure_values.into_iter().collect();
    realisation_values(
        &mut values,
        &turf,
        &sys,
        &relaxed,
        resume.as_ref(),
        (&run.records, run.tops),
    );
    analysis_values(&mut values, &analysis, &run.records[k.steps]);
    for (name, v) in built.packed.iter().flat_map(Packed::values) {
        values.insert(name.into(), v);
    }
    let mut warnings = written.warnings;
    warnings.extend(interpenetration_warning(&run.records));
    warnings.extend(pull_off_values(
        &mut values,
        &run.records,
        k.retract.is_some(),
    ));
    let evaluations = relaxed.cost.gradient_evaluations
        + run
            .records
            .iter()
            .map(|r| r.cost.gradient_evaluations)
            .sum::<usize>();
    Ok(Finished {
        index: job.index,
        seed: job.seed,
        path: curve
            .iter()
            .map(|r| (r.strain, r.loading, r.stress))
            .collect(),
        values,
        tangent: written.tangent,
        files: written.files,
        evaluations: evaluations as u64,
        warnings,
    })
}

/// The relaxed turf and, with `--resume`, the steps its checkpoint kept: relaxed here, or read
/// back from the realisation's checkpoint (the states recomputed from its configurations).
/// Refuses a relaxed turf whose tubes interpenetrate.
fn relaxed_start(
    job: &Job,
    sys: &mut TurfSystem,
    x: &mut [f64],
    solver: &StaticSolver,
    fingerprint: &str,
    done: &AtomicUsize,
) -> Result<(RelaxReport, Option<Resume>), StageError> {
    let checkpoint_path = job.ctx.out_dir.join(job.rel()).join(CHECKPOINT);
    let saved = if job.ctx.resume {
        Checkpoint::load(&checkpoint_path, fingerprint, x.len())
            .map_err(|e| failed(e.to_string()))?
    } else {
        None
    };
    let (relaxed, resume) = match &saved {
        Some(c) => {
            // the relaxed configuration is step 0's; its states are recomputed from it
            sys.model.platen = None;
            let initial = sys.state(x);
            let steps = c.saved_steps();
            x.copy_from_slice(&steps[0].x);
            let state = sys.state(x);
            let resume = Resume {
                start_height: c.start_height(),
                steps,
            };
            (
                RelaxReport {
                    initial,
                    state,
                    cost: c.relaxation.clone(),
                },
                Some(resume),
            )
        }
        None => {
            job.say(done, "relaxing the turf".into());
            let r = relax(sys, x, solver)
                .map_err(|e| failed(format!("relaxation of the generated turf: {e}")))?;
            let cost = SavedRelaxation {
                iterations: r.info.cost.iterations,
                gradient_evaluations: r.info.cost.gradient_evaluations,
                seconds: r.info.cost.seconds,
            };
            let report = RelaxReport {
                initial: r.initial,
                state: r.state,
                cost,
            };
            (report, None)
        }
    };
    if relaxed.state.min_gap < 0.0 {
        // a packed turf may start closer than the growth's clearance (the packing stops an
        // overlap only beyond its limit), so its remedy is a lower packing density
        let (which, remedy) = if job.turf.packing.is_some() {
            (
                "packed",
                "the packing left them closer than the van der Waals gap and the relaxation \
                 pulled them through each other — lower turf.packing.density",
            )
        } else {
            (
                "generated",
                "the generator grows the tubes clear of each other, so the relaxation moved \
                 them through each other — lower turf.growth.tilt, waviness or the density",
            )
        };
        return Err(failed(format!(
            "the {which} turf has interpenetrating tubes that the relaxation did not separate \
             (smallest surface gap {:.3} nm; {} contacts, van der Waals energy {:.4e} aJ): \
             {remedy}",
            relaxed.state.min_gap, relaxed.state.contacts, relaxed.state.energy.vdw
        )));
    }
    Ok((relaxed, resume))
}

/// A realisation's compression: every step's record and the VTK frames written on the way.
struct Compressed {
    records: Vec<StepRecord>,
    vtk_files: Vec<PathBuf>,
    /// the relaxed tubes' tops
    tops: Tops,
}

/// The tops of the relaxed tubes (nm): the mean and standard deviation over the tubes. The
/// strain from the mean top, (H̄ − H)/H̄, is a measure of the patch that does not drift with its
/// size as the nominal strain from the tallest tube does.
#[derive(Debug, Clone, Copy)]
struct Tops {
    mean: f64,
    sd: f64,
}

impl Tops {
    /// Of the tubes' `tops`; a turf without a free node (no top to measure) counts as one top
    /// at `tallest`.
    fn of(tops: &[f64], tallest: f64) -> Self {
        if tops.is_empty() {
            return Tops {
                mean: tallest,
                sd: 0.0,
            };
        }
        let n = tops.len() as f64;
        let mean = tops.iter().sum::<f64>() / n;
        let var = tops.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / n;
        Tops {
            mean,
            sd: var.sqrt(),
        }
    }
}

impl Compressed {
    /// Compress from the relaxed turf, saving the checkpoint after every step and the VTK
    /// frames of the first, peak and last steps. A drive that fails part-way writes the steps
    /// it reached (`stress_strain.csv`) and names them in the error.
    /// `start`: the relaxed turf, the steps to resume from and the checkpoint's fingerprint.
    fn drive(
        job: &Job,
        turf: &Turf,
        sys: &mut TurfSystem,
        x: &mut [f64],
        solver: &StaticSolver,
        (relaxed, resume, fingerprint): (&RelaxReport, Option<&Resume>, &str),
        done: &AtomicUsize,
    ) -> Result<Self, StageError> {
        let (k, ctx) = (job.compression, job.ctx);
        let rel = job.rel();
        let checkpoint_path = ctx.out_dir.join(&rel).join(CHECKPOINT);
        let params = CompressionParams {
            strain_max: k.to.0,
            steps: k.steps,
            unload: k.unload,
            retract: k.retract.map(|d| Retract {
                distance: d.0,
                steps: k.retract_steps(),
            }),
        };
        let total = k.path_steps();
        let vtk_steps = [0, k.steps, total];
        let mut vtk_files: Vec<PathBuf> = Vec::new();
        let mut side_error = None;
        let start_height = resume.map_or(sys.start_height(x), |r| r.start_height);
        let tops = Tops::of(&sys.tube_tops(x), sys.height(x));
        let mut reached: Vec<SavedStep> = Vec::new();
        let mut partial: Vec<StepRecord> = Vec::new();
        let mut observe = |rec: &StepRecord, saved: &SavedStep| {
            job.say(
                done,
                format!(
                    "step {}/{total}, strain {:.3}, stress {:.3e} GPa",
                    rec.step, rec.strain, rec.stress
                ),
            );
            if side_error.is_some() {
                return;
            }
            partial.push(*rec);
            reached.push(saved.clone());
            let c = Checkpoint::new(fingerprint, relaxed.cost.clone(), start_height, &reached);
            if let Err(e) = c.save(&checkpoint_path) {
                side_error = Some(failed(e.to_string()));
            } else if job.scene.output.vtk && vtk_steps.contains(&rec.step) {
                let vtu = rel.join(format!("vtk/discrete_step_{:03}.vtu", rec.step));
                match polylines(&turf.layout(), &saved.x).write(&ctx.out_dir.join(&vtu)) {
                    Ok(()) => vtk_files.push(vtu),
                    Err(e) => side_error = Some(report(e)),
                }
            }
        };
        let drive = compress(sys, x, &params, solver, resume, &mut observe);
        let records = match drive {
            Ok(r) => r,
            Err(e) => return Err(Self::failed_part_way(job, &partial, tops, e)),
        };
        if let Some(e) = side_error {
            return Err(e);
        }
        Ok(Compressed {
            records,
            vtk_files,
            tops,
        })
    }

    /// The error of a drive that failed after `partial`, with those steps written (step 0 at
    /// least, unless a side file failed first).
    fn failed_part_way(job: &Job, partial: &[StepRecord], tops: Tops, e: DriveError) -> StageError {
        let rel = job.rel();
        let file = rel.join("stress_strain.csv");
        let written = !partial.is_empty()
            && steps_table(partial, tops)
                .write(&job.ctx.out_dir.join(&file))
                .is_ok();
        let kept = if written {
            format!(
                " (what it reached, steps 0 to {}, is in {} and {})",
                partial.len() - 1,
                file.display(),
                rel.join(CHECKPOINT).display()
            )
        } else {
            String::new()
        };
        let message = format!("{e}{kept}");
        match e {
            DriveError::Interrupted { .. } => StageError::Interrupted {
                stage: Stage::Discrete,
                message: format!("{message}; `turf run --resume` continues from it"),
            },
            _ => failed(message),
        }
    }
}

/// What [`write_realisation`] wrote and found.
struct Written {
    files: Vec<PathBuf>,
    tangent: Table,
    structure_values: Vec<(String, f64)>,
    warnings: Vec<String>,
}

/// Write a realisation's tables (steps, load–depth under a sphere, branches, tangent), its
/// structure with the micromechanics, its analysis and (realisation 0) its plots.
fn write_realisation(
    job: &Job,
    sys: &TurfSystem,
    structure: Option<&Structure>,
    vdw: Option<&VdwParams>,
    run: &Compressed,
    analysis: &CurveAnalysis,
) -> Result<Written, StageError> {
    let (k, ctx, rel) = (job.compression, job.ctx, job.rel());
    let records = &run.records;
    let mut files = run.vtk_files.clone();
    files.push(rel.join(CHECKPOINT));
    let mut write = |table: &Table, name: &str| -> Result<(), StageError> {
        let file = rel.join(name);
        table.write(&ctx.out_dir.join(&file)).map_err(report)?;
        files.push(file);
        Ok(())
    };
    write(&steps_table(records, run.tops), "stress_strain.csv")?;
    if k.indenter == Indenter::Sphere {
        write(&load_depth_table(records), LOAD_DEPTH_CSV)?;
    }
    write(&branch_table(&analysis.loading), LOADING_CSV)?;
    if let Some(u) = &analysis.unloading {
        write(&branch_table(u), UNLOADING_CSV)?;
    }
    let tangent = tangent_table(&analysis.loading);
    if job.index > 0 {
        // realisation 0's tangent table is the stage's, written by the pipeline
        write(&tangent, "discrete_tangent.csv")?;
    }
    let mut structure_values = Vec::new();
    if let (Some(st), Some(v)) = (structure, vdw) {
        let bending = sys.model.rods.rods()[0].stiffness().bending;
        let json;
        (structure_values, json) = micromechanics(st, bending, v.gamma_l, analysis);
        let structure_file = rel.join("discrete_structure.json");
        write_json(&ctx.out_dir.join(&structure_file), &json).map_err(report)?;
        files.push(structure_file);
    }
    let analysis_file = rel.join("discrete_analysis.json");
    write_json(&ctx.out_dir.join(&analysis_file), &analysis_json(analysis)).map_err(report)?;
    files.push(analysis_file);
    // the other realisations' curves are in the ensemble's band plot
    // realisation 0's fit speaks for a single run (an ensemble adds its mean curve's)
    let mut warnings = match job.index {
        0 => analysis.fit_warnings(),
        _ => Vec::new(),
    };
    if job.scene.output.plots && job.index == 0 {
        files.extend(
            write_plots(analysis, records, &ctx.out_dir.join(&rel), &mut warnings)
                .into_iter()
                .map(|f| rel.join(f)),
        );
    }
    Ok(Written {
        files,
        tangent,
        structure_values,
        warnings,
    })
}

/// Depth below the first contact, platen (sphere) force and branch of every step.
fn load_depth_table(records: &[StepRecord]) -> Table {
    let h0 = records[0].height;
    Table::new()
        .column("depth_nm", records.iter().map(|r| h0 - r.height).collect())
        .column(
            "load_nN",
            records.iter().map(|r| r.state.platen_force).collect(),
        )
        .column(
            "loading",
            records
                .iter()
                .map(|r| f64::from(u8::from(r.loading)))
                .collect(),
        )
}

/// A warning when the drive's equilibria hold two tube surfaces overlapping by more than
/// [`OVERLAP_LIMIT_NM`] (a squeezed contact stays within a few tenths of a nanometre of
/// touching; beyond that the tubes were pushed into each other and the state is unphysical),
/// naming the first such step and the deepest overlap.
fn interpenetration_warning(records: &[StepRecord]) -> Option<String> {
    let first = records
        .iter()
        .find(|r| r.state.min_gap < -OVERLAP_LIMIT_NM)?;
    let deepest = records
        .iter()
        .map(|r| r.state.min_gap)
        .fold(f64::INFINITY, f64::min);
    Some(format!(
        "tubes were pushed into each other during the compression: from step {} (strain \
         {:.3}) two tube surfaces overlap by more than {OVERLAP_LIMIT_NM} nm (deepest {:.2} nm, \
         compression_min_gap_nm), so those steps' states are unphysical; more strain steps \
         (compression.steps) let the tubes get out of each other's way",
        first.step, first.strain, -deepest
    ))
}

/// The pull-off of an adhesive sphere into `values`: the largest tension on it after the peak
/// (`pull_off_nN`, negative) and its depth below the first touch (`pull_off_depth_nm`, negative
/// above it), where it pulled at all; after a retract (`retracted`) a sphere that never pulled
/// has a pull-off of zero, and one that pulls hardest at the retract's last step a warning.
fn pull_off_values(
    values: &mut BTreeMap<String, f64>,
    records: &[StepRecord],
    retracted: bool,
) -> Option<String> {
    let h0 = records.first()?.height;
    let hardest = records
        .iter()
        .filter(|r| !r.loading && r.state.platen_force < 0.0)
        .min_by(|a, b| a.state.platen_force.total_cmp(&b.state.platen_force));
    if let Some(r) = hardest {
        values.insert("pull_off_nN".into(), r.state.platen_force);
        values.insert("pull_off_depth_nm".into(), h0 - r.height);
    } else if retracted {
        values.insert("pull_off_nN".into(), 0.0);
    }
    let last = records.last()?;
    (retracted && hardest.is_some_and(|r| std::ptr::eq(r, last))).then(|| {
        format!(
            "the sphere pulls hardest at the retract's last step ({:.4} nN): the tips may let go \
             further up (raise compression.retract)",
            last.state.platen_force
        )
    })
}

/// The realisation's size, relaxation and compression cost into `values`.
fn realisation_values(
    values: &mut BTreeMap<String, f64>,
    turf: &Turf,
    sys: &TurfSystem,
    relaxed: &RelaxReport,
    resume: Option<&Resume>,
    (records, tops): (&[StepRecord], Tops),
) {
    let mut put = |name: &str, v: f64| {
        values.insert(name.to_string(), v);
    };
    put("tubes", turf.tubes.len() as f64);
    put("segments", sys.model.rods.segments() as f64);
    put("box_area_nm2", sys.area);
    if let Some(r) = resume {
        put("resumed_after_step", (r.steps.len() - 1) as f64);
    }
    let b0 = relaxed.initial.energy.balance();
    let b = relaxed.state.energy.balance();
    put("generated_elastic_aJ", b0.elastic);
    put("generated_contact_aJ", b0.contact);
    put("generated_contacts", relaxed.initial.contacts as f64);
    put("relaxed_elastic_aJ", b.elastic);
    put("relaxed_bending_aJ", relaxed.state.energy.bending);
    put("relaxed_stretching_aJ", relaxed.state.energy.stretching);
    put("relaxed_contact_aJ", b.contact);
    put("relaxed_total_aJ", b.total);
    put("relaxed_contacts", relaxed.state.contacts as f64);
    if relaxed.state.min_gap.is_finite() {
        put("relaxed_min_gap_nm", relaxed.state.min_gap);
    }
    // the closest two tube surfaces came along the drive (negative: into each other's van der
    // Waals wall; beyond about −1 nm, pushed into each other: docs/discrete-compression.md)
    let closest = records
        .iter()
        .map(|r| r.state.min_gap)
        .fold(f64::INFINITY, f64::min);
    if closest.is_finite() {
        put("compression_min_gap_nm", closest);
    }
    put("relaxation_iterations", relaxed.cost.iterations as f64);
    put("wall_time_relaxation_s", relaxed.cost.seconds);
    put("turf_height_nm", records[0].height);
    put("turf_mean_top_nm", tops.mean);
    put("turf_top_sd_nm", tops.sd);
    put(
        "wall_time_compression_s",
        records.iter().map(|r| r.cost.seconds).sum(),
    );
    put(
        "compression_iterations",
        records.iter().map(|r| r.cost.iterations).sum::<usize>() as f64,
    );
}

/// The curve's analysis (peak, work, hysteresis, the fitted (5.1) law, σ₀) and the contacts at
/// the `peak` step into `values`.
fn analysis_values(
    values: &mut BTreeMap<String, f64>,
    analysis: &CurveAnalysis,
    peak: &StepRecord,
) {
    let mut put = |name: &str, v: f64| {
        values.insert(name.to_string(), v);
    };
    put("peak_stress_GPa", analysis.peak_stress);
    put("loading_work_GPa", analysis.loading_work);
    if let Some(w) = analysis.unloading_work {
        put("unloading_work_GPa", w);
    }
    if let Some(h) = analysis.hysteresis() {
        put("hysteresis", h);
    }
    if let Ok(f) = &analysis.fit {
        put("tangent_e0_GPa", f.law.e0);
        put("tangent_e_inf_GPa", f.law.e_inf);
        put("tangent_eps0", f.law.eps0);
        put("tangent_fit_rms_rel", f.rms_rel);
    }
    if let Some(s0) = analysis.threshold_stress() {
        put("sigma0_GPa", s0);
    }
    put("contacts_at_peak", peak.state.contacts as f64);
}

/// The realisations' loading curves against the strain from each one's mean top,
/// ε̄ = (H̄ − H)/H̄ = 1 − (1 − ε)H₀/H̄ (ε the nominal strain from its tallest top H₀),
/// interpolated linearly onto as many equally spaced ε̄ as the path has loading steps, over the
/// range every realisation covers, and reduced as the path is. `None` without that range (or
/// without the tops in a realisation's values).
fn mean_top_ensemble(finished: &[Finished]) -> Option<PathEnsemble> {
    let curves = finished
        .iter()
        .map(|f| {
            let h0 = f.values.get("turf_height_nm")?;
            let top = f.values.get("turf_mean_top_nm")?;
            let (strain, stress): (Vec<f64>, Vec<f64>) = f
                .path
                .iter()
                .filter(|p| p.1)
                .map(|&(e, _, s)| (1.0 - (1.0 - e) * h0 / top, s))
                .unzip();
            Some((f.index, strain, stress))
        })
        .collect::<Option<Vec<_>>>()?;
    let n = curves[0].1.len();
    let lo = curves.iter().map(|c| c.1[0]).fold(f64::MIN, f64::max);
    let hi = curves.iter().map(|c| c.1[n - 1]).fold(f64::MAX, f64::min);
    if !(n >= 2 && hi > lo) {
        return None;
    }
    // both ends exactly: each is some realisation's own first or last point
    let mut grid: Vec<f64> = (0..n)
        .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
        .collect();
    grid[n - 1] = hi;
    let members = curves
        .iter()
        .map(|(k, strain, stress)| {
            let at = grid.iter().map(|&e| interpolate(strain, stress, e));
            Some((*k, at.collect::<Option<Vec<f64>>>()?))
        })
        .collect::<Option<Vec<_>>>()?;
    PathEnsemble::new(grid, vec![true; n], members).ok()
}

/// The scalars of a realisation that the ensemble reduces, as (summary name without the unit,
/// unit suffix): what [`CurveAnalysis`] gives — the peak stress, σ₀, the fitted (5.1) law and
/// the hysteresis — the relaxed structure with the micromechanics' σ₀ from it, and the tubes'
/// tops (the tallest, their mean and spread: the nominal strain's origin against the mean's).
const ENSEMBLE_SCALARS: [(&str, &str); 15] = [
    ("peak_stress", "_GPa"),
    ("sigma0", "_GPa"),
    ("tangent_e0", "_GPa"),
    ("tangent_e_inf", "_GPa"),
    ("tangent_eps0", ""),
    ("hysteresis", ""),
    ("structure_free_length", "_nm"),
    ("structure_contact_length", "_nm"),
    ("structure_curvature", "_per_nm"),
    ("structure_theta", ""),
    ("micromech_sigma0_printed", "_GPa"),
    ("micromech_sigma0_arc", "_GPa"),
    ("turf_height", "_nm"),
    ("turf_mean_top", "_nm"),
    ("turf_top_sd", "_nm"),
];

/// The fitted (5.1) law's constants among a realisation's values.
const LAW: [&str; 3] = ["tangent_e0_GPa", "tangent_e_inf_GPa", "tangent_eps0"];

/// A realisation's values as the ensemble reduces them: the fitted law's constants only where
/// the fit is the softening law (5.1) describes, E^∞ ≤ E⁰ ([`CurveAnalysis::softening_fit`]; σ₀
/// is left out by the analysis itself). A stiffening fit's constants mean nothing as such and
/// run to any size (E^∞ of 10⁵ GPa on a 9-tube curve with a long toe), so one of them would
/// swamp the mean.
fn law_if_softening(values: &BTreeMap<String, f64>) -> BTreeMap<String, f64> {
    let mut v = values.clone();
    let law = |k: usize| v.get(LAW[k]).copied();
    if let (Some(e0), Some(e_inf), Some(eps0)) = (law(0), law(1), law(2)) {
        if !(TangentLaw { e0, e_inf, eps0 }).softens() {
            LAW.iter().for_each(|k| {
                v.remove(*k);
            });
        }
    }
    v
}

/// The ensemble's mean stress–strain curve along the common path, every step.
pub const ENSEMBLE_CSV: &str = "discrete_ensemble.csv";
/// The ensemble's mean loading curve against the strain from each turf's mean top.
pub const ENSEMBLE_MEAN_TOP_CSV: &str = "discrete_ensemble_mean_top.csv";
/// Its strain column, as in `stress_strain.csv`.
const MEAN_TOP_STRAIN: &str = "strain_from_mean_top";
/// The ensemble's report: seeds, estimates, failures.
const ENSEMBLE_JSON: &str = "discrete_ensemble.json";

/// The stage's output for an ensemble: realisation 0's values and files under the names of a
/// single run, the realisations' mean and 95 % interval (`ensemble_*` values,
/// [`ENSEMBLE_CSV`], the mean branches, [`ENSEMBLE_JSON`], the band plot), and the failed
/// realisations named with their reasons. Fails only when no realisation finished.
fn ensemble_output(
    s: &crate::scene::Scene,
    results: Vec<Result<Finished, StageError>>,
    ctx: &StageContext,
) -> Result<StageOutput, StageError> {
    let count = results.len();
    let (finished, failures) = partition(s, results);
    let failure_text: Vec<String> = failures
        .iter()
        .map(|(i, seed, why)| format!("realisation {i} (seed {seed}) failed: {why}"))
        .collect();
    let Some(first) = finished.first() else {
        return Err(failed(format!(
            "all {count} realisations failed: {}",
            failure_text.join("; ")
        )));
    };
    for line in &failure_text {
        let line = format!("discrete: {line}; the ensemble goes on without it");
        match ctx.progress {
            Some(bar) => bar.println(line),
            None => eprintln!("{line}"),
        }
    }
    let path = &first.path;
    let ensemble = PathEnsemble::new(
        path.iter().map(|p| p.0).collect(),
        path.iter().map(|p| p.1).collect(),
        finished
            .iter()
            .map(|f| (f.index, f.path.iter().map(|p| p.2).collect()))
            .collect(),
    )
    .map_err(failed)?;
    let names: Vec<String> = ENSEMBLE_SCALARS
        .iter()
        .map(|(base, unit)| format!("{base}{unit}"))
        .collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let members: Vec<BTreeMap<String, f64>> = finished
        .iter()
        .map(|f| law_if_softening(&f.values))
        .collect();
    let scalars = ensemble::reduce_values(&names, members.iter());

    let mut out = StageOutput {
        warnings: finished.iter().flat_map(|f| f.warnings.clone()).collect(),
        ..StageOutput::default()
    };
    let mut files: Vec<PathBuf> = Vec::new();
    let write = |table: Table, name: &str, files: &mut Vec<PathBuf>| -> Result<(), StageError> {
        table.write(&ctx.out_dir.join(name)).map_err(report)?;
        files.push(name.into());
        Ok(())
    };
    write(ensemble.table(), ENSEMBLE_CSV, &mut files)?;
    let mean_top = mean_top_ensemble(&finished);
    if let Some(e) = &mean_top {
        write(
            e.table_along(MEAN_TOP_STRAIN),
            ENSEMBLE_MEAN_TOP_CSV,
            &mut files,
        )?;
    }
    let (mean_loading, mean_unloading) = ensemble.mean_branches();
    write(
        branch_table(&mean_loading),
        ENSEMBLE_LOADING_CSV,
        &mut files,
    )?;
    if let Some(u) = &mean_unloading {
        write(branch_table(u), ENSEMBLE_UNLOADING_CSV, &mut files)?;
    }
    let fitted = filed_curves(
        mean_loading.clone(),
        mean_unloading.clone(),
        Path::new(""),
        (ENSEMBLE_LOADING_CSV, ENSEMBLE_UNLOADING_CSV),
    );
    let realisations = finished.iter().map(|f| (f.index, f.curves())).collect();
    out.handoff = Some(Handoff::Compression(handoff::Compression {
        fitted,
        realisations,
    }));
    let mean_analysis = CurveAnalysis::new(mean_loading, mean_unloading);
    let stiffening = finished
        .iter()
        .zip(&members)
        .filter(|(f, m)| f.values.contains_key(LAW[0]) && !m.contains_key(LAW[0]))
        .count();
    if stiffening > 0 {
        out.warnings.push(format!(
            "{stiffening} of {} realisations' tangent-law (5.1) fits stiffen (Einf > E0: their \
             curves rise late); the ensemble's E0, Einf, eps0 and sigma0 are those of the others",
            finished.len()
        ));
    }
    let mean_warnings = mean_analysis.fit_warnings().into_iter();
    out.warnings
        .extend(mean_warnings.map(|w| format!("mean curve of the realisations: {w}")));
    let mut estimates = serde_json::Map::new();
    for ((base, unit), name) in ENSEMBLE_SCALARS.iter().zip(&names) {
        if let Some(e) = scalars.get(*name) {
            ensemble::put_estimate(&mut out.values, &format!("ensemble_{base}"), unit, e);
            estimates.insert(name.to_string(), ensemble::estimate_json(e));
        }
    }
    let json = ensemble_json(count, &finished, &failures, estimates, &mean_analysis);
    write_json(&ctx.out_dir.join(ENSEMBLE_JSON), &json).map_err(report)?;
    files.push(ENSEMBLE_JSON.into());
    if s.output.plots {
        let written = ensemble.plot().write_or_warn(
            &ctx.out_dir.join("plots"),
            "discrete_ensemble",
            "plots",
            &mut out.warnings,
        );
        files.extend(written.into_iter().map(PathBuf::from));
        if let Some(e) = &mean_top {
            let written = e
                .plot_along("strain from the tubes' mean top, (H_mean - H)/H_mean")
                .write_or_warn(
                    &ctx.out_dir.join("plots"),
                    "discrete_ensemble_mean_top",
                    "plots",
                    &mut out.warnings,
                );
            files.extend(written.into_iter().map(PathBuf::from));
        }
    }
    out.values.insert("realisations".into(), count as f64);
    out.values
        .insert("realisations_finished".into(), finished.len() as f64);
    out.values
        .insert("realisations_failed".into(), failures.len() as f64);
    for f in finished {
        out.evaluations += f.evaluations;
        out.files.extend(f.files);
        if f.index == 0 {
            out.values.extend(f.values);
            out.tables.push(("tangent".into(), f.tangent));
        }
    }
    out.files.extend(files);
    Ok(out)
}

/// A failed realisation: its index, its seed and why it failed.
type Failure = (usize, u64, String);

/// The finished realisations and the failed ones, in realisation order.
fn partition(
    s: &crate::scene::Scene,
    results: Vec<Result<Finished, StageError>>,
) -> (Vec<Finished>, Vec<Failure>) {
    let mut finished = Vec::new();
    let mut failures = Vec::new();
    for (i, r) in results.into_iter().enumerate() {
        match r {
            Ok(f) => finished.push(f),
            Err(e) => {
                let why = match e {
                    StageError::Failed { message, .. } => message,
                    StageError::Report { source, .. } => source.to_string(),
                    other => other.to_string(),
                };
                failures.push((i, ensemble::realisation_seed(s.scene.seed, i), why));
            }
        }
    }
    (finished, failures)
}

/// `discrete_ensemble.json`: the estimates with their intervals, the mean curve's analysis,
/// every finished member's values and every failure.
fn ensemble_json(
    count: usize,
    finished: &[Finished],
    failures: &[Failure],
    estimates: serde_json::Map<String, serde_json::Value>,
    mean_analysis: &CurveAnalysis,
) -> serde_json::Value {
    let members: Vec<serde_json::Value> = finished
        .iter()
        .map(|f| {
            serde_json::json!({
                "realisation": f.index,
                "seed": f.seed,
                "dir": ensemble::realisation_dir(f.index).display().to_string(),
                "values": f.values,
            })
        })
        .collect();
    let failed_json: Vec<serde_json::Value> = failures
        .iter()
        .map(|(i, seed, why)| serde_json::json!({"realisation": i, "seed": seed, "error": why}))
        .collect();
    serde_json::json!({
        "realisations": count,
        "finished": finished.len(),
        "confidence_interval": ensemble::INTERVAL_DEFINITION,
        "estimates": estimates,
        "mean_curve": analysis_json(mean_analysis),
        "members": members,
        "failed": failed_json,
    })
}

/// `[rods]`: the rods in equilibrium under their end loads (Newton, default tolerances).
fn run_rods(
    r: &crate::scene::rods::Rods,
    vtk: bool,
    ctx: &StageContext,
) -> Result<StageOutput, StageError> {
    let specs: Vec<RodSpec> = r
        .rod
        .iter()
        .map(|rod| RodSpec {
            points: rod.points.iter().map(|p| p.map(|c| c.0)).collect(),
            ends: rod.ends.map(|e| match e {
                End::Clamped => EndCondition::Clamped,
                End::Pinned => EndCondition::Pinned,
                End::Free => EndCondition::Free,
            }),
            load: rod.load.map(|f| f.map(|c| c.0)),
            segments: rod.segments,
        })
        .collect();
    let stiffness = RodStiffness::hollow_tube(r.tube.youngs.0, r.tube.r_o.0, r.tube.r_i.0);
    let vdw = r.vdw.as_ref().map(vdw_params).transpose()?;
    let mut rods = ExplicitRods::new(&specs, stiffness, r.tube.r_o.0, vdw.as_ref())
        .map_err(|e| failed(e.to_string()))?;
    let mut x = rods.x0.clone();
    let info = minimize_newton(
        &mut rods.model,
        &rods.fixed,
        &mut x,
        &NewtonParams::default(),
    )
    .map_err(|e| failed(format!("equilibrium of the rods: {e}")))?;
    // an equilibrium need not be stable: a straight rod beyond its Euler load is one
    let stable = is_local_minimum(&rods.model, &rods.fixed, &x)
        .map_err(|e| failed(format!("stability of the rods' equilibrium: {e}")))?;
    if let (false, Some(bar)) = (stable, ctx.progress) {
        bar.println(
            "discrete: warning: the rods' equilibrium is unstable (its Hessian is indefinite: a \
             saddle, e.g. a straight rod beyond its Euler load); give the rods an imperfection \
             (a slightly bent `points` list) to find the buckled shape",
        );
    }
    let mut values = BTreeMap::from([
        (
            "stable_equilibrium".to_string(),
            if stable { 1.0 } else { 0.0 },
        ),
        ("energy_aJ".to_string(), info.energy),
        ("residual_nN".to_string(), info.residual),
        ("newton_iterations".to_string(), info.cost.iterations as f64),
        ("wall_time_solve_s".to_string(), info.cost.seconds),
        ("bending_stiffness_nN_nm2".to_string(), stiffness.bending),
    ]);
    let (mut rod_col, mut node_col) = (Vec::new(), Vec::new());
    let mut pos = [Vec::new(), Vec::new(), Vec::new()];
    for (i, l) in rods.layout.iter().enumerate() {
        let last = l.first_node + l.nodes - 1;
        for (a, name) in ["dx", "dy", "dz"].iter().enumerate() {
            let d = x[3 * last + a] - rods.x0[3 * last + a];
            values.insert(format!("rod{i}_tip_{name}_nm"), d);
        }
        values.insert(
            format!("rod{i}_length_nm"),
            rods.model.rods.rods()[i].rest_length(),
        );
        for n in l.first_node..=last {
            rod_col.push(i as f64);
            node_col.push((n - l.first_node) as f64);
            for (a, p) in pos.iter_mut().enumerate() {
                p.push(x[3 * n + a]);
            }
        }
    }
    let [px, py, pz] = pos;
    let nodes = Table::new()
        .column("rod", rod_col)
        .column("node", node_col)
        .column("x_nm", px)
        .column("y_nm", py)
        .column("z_nm", pz);
    let mut files = Vec::new();
    if vtk {
        let rel = PathBuf::from("vtk/discrete_rods.vtu");
        polylines(&rods.layout, &x)
            .write(&ctx.out_dir.join(&rel))
            .map_err(report)?;
        files.push(rel);
    }
    Ok(StageOutput {
        values,
        tables: vec![("rods_nodes".into(), nodes)],
        evaluations: info.cost.gradient_evaluations as u64,
        files,
        warnings: Vec::new(),
        handoff: None,
    })
}

/// Loading (step 0 to the peak) and unloading (peak to the end, reversed to ascending strain).
/// The relaxed structure (contact patches, free segments) and what the seed's micromechanics
/// (2.14) predicts from it with the printed and the arc f(θ), beside the tubes' own σ₀ and peak:
/// `structure_*` and `micromech_*` summary values, and the JSON of `discrete_structure.json`
/// (a prediction outside its f(θ)'s domain is left out of the values and explained there).
fn micromechanics(
    st: &Structure,
    bending: f64,
    gamma_l: f64,
    analysis: &CurveAnalysis,
) -> (Vec<(String, f64)>, serde_json::Value) {
    let seg = st.segments(bending, gamma_l);
    let mut values = vec![
        ("structure_patches".to_string(), st.patches as f64),
        ("structure_free_segments".into(), st.free_segments as f64),
        ("structure_contact_fraction".into(), st.contact_fraction),
        ("structure_end_fraction".into(), st.end_fraction),
    ];
    // means over no patch or no free segment are not values (an ensemble must not average them)
    if st.patches > 0 {
        values.push(("structure_contact_length_nm".into(), st.contact_length_nm));
    }
    let mut predictions = serde_json::Map::new();
    if st.free_segments == 0 {
        let why = "no free segment between two contacts of one tube: (2.14) has nothing to count";
        predictions.insert("not_predicted".into(), why.into());
    } else {
        values.push(("structure_free_length_nm".into(), st.free_length_nm));
        values.push(("structure_curvature_per_nm".into(), st.curvature_per_nm));
        values.push(("structure_theta".into(), st.theta));
    }
    let shapes = [(ShapeFactor::Printed, "printed"), (ShapeFactor::Arc, "arc")];
    for (shape, name) in shapes.into_iter().filter(|_| st.free_segments > 0) {
        let p = seg.threshold_stress(st.curvature_per_nm, st.theta, shape);
        predictions.insert(
            name.into(),
            match p {
                Ok(sigma) => {
                    values.push((format!("micromech_sigma0_{name}_GPa"), sigma));
                    serde_json::json!({ "sigma0_GPa": sigma })
                }
                Err(e) => serde_json::json!({ "not_predicted": e.to_string() }),
            },
        );
    }
    let mut json = serde_json::json!({
        "definition": "contact patches: arclength of a tube whose axis is within r_a + r_b + gap \
            of another tube's axis; free segments: between two consecutive patches of one tube; \
            n per unit volume of the box up to the turf's top; kappa0 from the free segments' \
            bending energy by (2.8); theta = kappa0 l / 2",
        "structure": st,
        "bending_stiffness_nN_nm2": bending,
        "line_energy_nN": gamma_l,
        "micromechanics_sigma0": predictions,
        "tubes_peak_stress_GPa": analysis.peak_stress,
    });
    // the tubes' own σ₀ where the tangent law was fitted (a null would not be written)
    if let Some(s0) = analysis.threshold_stress() {
        json["tubes_sigma0_GPa"] = s0.into();
    }
    (values, json)
}

fn analyse(records: &[StepRecord]) -> CurveAnalysis {
    let col = |f: fn(&StepRecord) -> f64| records.iter().map(f).collect::<Vec<f64>>();
    let loading: Vec<bool> = records.iter().map(|r| r.loading).collect();
    let (l, u) = ensemble::branches(&col(|r| r.strain), &col(|r| r.stress), &loading);
    CurveAnalysis::new(l, u)
}

fn steps_table(records: &[StepRecord], tops: Tops) -> Table {
    let col = |f: &dyn Fn(&StepRecord) -> f64| records.iter().map(f).collect::<Vec<f64>>();
    Table::new()
        .column("step", col(&|r| r.step as f64))
        .column("loading", col(&|r| if r.loading { 1.0 } else { 0.0 }))
        .column("strain", col(&|r| r.strain))
        .column("stress_GPa", col(&|r| r.stress))
        .column("platen_height_nm", col(&|r| r.height))
        .column(
            MEAN_TOP_STRAIN,
            col(&|r| (tops.mean - r.height) / tops.mean),
        )
        .column("platen_force_nN", col(&|r| r.state.platen_force))
        .column("bending_aJ", col(&|r| r.state.energy.bending))
        .column("stretching_aJ", col(&|r| r.state.energy.stretching))
        .column("vdw_aJ", col(&|r| r.state.energy.vdw))
        .column("walls_aJ", col(&|r| r.state.energy.walls))
        .column("contacts", col(&|r| r.state.contacts as f64))
        .column("platen_nodes", col(&|r| r.state.platen_nodes as f64))
        .column("iterations", col(&|r| r.cost.iterations as f64))
        .column("solve_s", col(&|r| r.cost.seconds))
}

/// Branches with the files (under `dir`, named `names`) that hold them.
fn filed_curves(
    loading: Branch,
    unloading: Option<Branch>,
    dir: &Path,
    names: (&str, &str),
) -> Curves {
    Curves {
        loading: Filed {
            file: dir.join(names.0),
            branch: loading,
        },
        unloading: unloading.map(|branch| Filed {
            file: dir.join(names.1),
            branch,
        }),
    }
}

fn branch_table(b: &Branch) -> Table {
    Table::new()
        .column("strain", b.strain.clone())
        .column("stress_GPa", b.stress.clone())
}

fn tangent_table(b: &Branch) -> Table {
    let (strain, modulus) = b.tangent().into_iter().unzip();
    Table::new()
        .column("strain", strain)
        .column("tangent_GPa", modulus)
}

fn analysis_json(a: &CurveAnalysis) -> serde_json::Value {
    let fit = match &a.fit {
        Ok(f) => {
            let mut fit = serde_json::json!({
                "e0_GPa": f.law.e0,
                "e_inf_GPa": f.law.e_inf,
                "eps0": f.law.eps0,
                "rms_rel": f.rms_rel,
            });
            // an exact or degenerate fit has none (a null or a NaN would refuse the file)
            fit["std_errors"] = match f.std_errors {
                Some(e) if e.iter().all(|x| x.is_finite()) => e.to_vec().into(),
                _ => "not estimated: the fit is exact or its covariance is singular".into(),
            };
            fit
        }
        Err(e) => serde_json::json!({ "error": e }),
    };
    let mut json = serde_json::json!({
        "tangent_law_fit": fit,
        "sigma0_definition": "E0 * eps0 of the fitted tangent law (5.1): the stress where the initial line E0*eps meets the large-strain asymptote",
        "peak_stress_GPa": a.peak_stress,
        "loading_work_GPa": a.loading_work,
    });
    // absent rather than null: a null reads as a failed number (crate::report::write_json)
    for (name, v) in [
        ("sigma0_GPa", a.threshold_stress()),
        ("unloading_work_GPa", a.unloading_work),
        ("hysteresis", a.hysteresis()),
    ] {
        if let Some(v) = v {
            json[name] = v.into();
        }
    }
    json
}

/// The realisation's plots under `out/plots`; returns the paths written, relative to `out`
/// (a plot that cannot be written is a warning).
fn write_plots(
    a: &CurveAnalysis,
    records: &[StepRecord],
    out: &Path,
    warnings: &mut Vec<String>,
) -> Vec<PathBuf> {
    let dir = out.join("plots");
    let mut stress =
        Plot::new("Turf compression", "nominal strain", "nominal stress (GPa)").with(Series::line(
            "loading",
            a.loading.strain.clone(),
            a.loading.stress.clone(),
        ));
    if let Some(u) = &a.unloading {
        stress = stress.with(Series::dashed(
            "unloading",
            u.strain.clone(),
            u.stress.clone(),
        ));
    }
    let (te, tm): (Vec<f64>, Vec<f64>) = a.loading.tangent().into_iter().unzip();
    let mut tangent = Plot::new("Tangent modulus", "nominal strain", "tangent modulus (GPa)")
        .with(Series::points("discrete", te.clone(), tm));
    if let Ok(f) = &a.fit {
        let fit = te.iter().map(|&e| f.law.tangent(e)).collect();
        tangent = tangent.with(Series::line("fit of (5.1)", te, fit));
    }
    let strain: Vec<f64> = records.iter().map(|r| r.strain).collect();
    let col = |f: &dyn Fn(&StepRecord) -> f64| records.iter().map(f).collect::<Vec<f64>>();
    let energy = Plot::new(
        "Energy split",
        "nominal strain (loading, then unloading)",
        "energy (aJ)",
    )
    .with(Series::points(
        "bending",
        strain.clone(),
        col(&|r| r.state.energy.bending),
    ))
    .with(Series::points(
        "stretching",
        strain.clone(),
        col(&|r| r.state.energy.stretching),
    ))
    .with(Series::points(
        "contact Γ = −vdW",
        strain.clone(),
        col(&|r| -r.state.energy.vdw),
    ));
    let contacts = Plot::new("Contacts", "nominal strain", "segment pairs in contact").with(
        Series::points("contacts", strain, col(&|r| r.state.contacts as f64)),
    );
    let mut files = Vec::new();
    for (plot, stem) in [
        (stress, "discrete_stress_strain"),
        (tangent, "discrete_tangent"),
        (energy, "discrete_energy"),
        (contacts, "discrete_contacts"),
    ] {
        let written = plot.write_or_warn(&dir, stem, "plots", warnings);
        files.extend(written.into_iter().map(PathBuf::from));
    }
    files
}

/// The tubes at configuration `x` as VTK polylines, with the tube index and radius per cell.
fn polylines(layout: &[TubeLayout], x: &[f64]) -> Grid {
    let points = x.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    let cells = layout
        .iter()
        .map(|l| {
            (
                CellKind::PolyLine,
                (l.first_node..l.first_node + l.nodes).collect(),
            )
        })
        .collect();
    Grid {
        points,
        cells,
        point_data: Vec::new(),
        cell_data: vec![
            DataArray {
                name: "tube".into(),
                components: 1,
                values: (0..layout.len()).map(|i| i as f64).collect(),
            },
            DataArray {
                name: "radius_nm".into(),
                components: 1,
                values: layout.iter().map(|l| l.radius).collect(),
            },
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::model::{EnergyParts, State};

    fn record(step: usize, min_gap: f64) -> StepRecord {
        StepRecord {
            step,
            loading: true,
            strain: 0.01 * step as f64,
            height: 2000.0,
            stress: 0.0,
            state: State {
                energy: EnergyParts::default(),
                contacts: 3,
                min_gap,
                platen_force: 0.0,
                platen_nodes: 0,
            },
            cost: Default::default(),
        }
    }

    /// A realisation whose (5.1) fit stiffens gives the ensemble no law constants; a softening
    /// one gives all three; the other values pass either way.
    #[test]
    fn the_ensemble_reduces_only_softening_laws() {
        let values = |e0: f64, e_inf: f64| {
            BTreeMap::from([
                (LAW[0].to_string(), e0),
                (LAW[1].to_string(), e_inf),
                (LAW[2].to_string(), 0.05),
                ("peak_stress_GPa".to_string(), 0.004),
            ])
        };
        let soft = law_if_softening(&values(0.03, 0.001));
        assert_eq!(soft, values(0.03, 0.001));
        let stiff = law_if_softening(&values(0.008, 6e5));
        assert!(LAW.iter().all(|k| !stiff.contains_key(*k)));
        assert_eq!(stiff.get("peak_stress_GPa"), Some(&0.004));
    }

    /// Squeezed contacts (a few tenths of a nanometre inside the wall) pass; an overlap beyond
    /// 1 nm is named by its first step and its deepest value.
    #[test]
    fn tubes_pushed_into_each_other_are_warned_of() {
        let squeezed: Vec<_> = [0.3, 0.1, -0.2, -0.9]
            .iter()
            .enumerate()
            .map(|(k, &g)| record(k, g))
            .collect();
        assert_eq!(interpenetration_warning(&squeezed), None);
        let pushed: Vec<_> = [0.3, -0.2, -1.5, -3.2, -2.0]
            .iter()
            .enumerate()
            .map(|(k, &g)| record(k, g))
            .collect();
        let w = interpenetration_warning(&pushed).expect("a warning");
        assert!(w.contains("from step 2 (strain 0.020)"), "{w}");
        assert!(w.contains("deepest 3.20 nm"), "{w}");
        assert_eq!(interpenetration_warning(&[record(0, f64::INFINITY)]), None);
    }
}
