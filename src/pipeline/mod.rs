//! From a scene to results: runs the stages of the scene's [`Plan`](crate::scene::Plan) in
//! order, times each one and counts its evaluations, and writes `summary.json` and the CSV
//! curves into the output folder through [`crate::report`] (atomically, NaN refused).
//!
//! Each stage is one engine behind one function `fn run_<stage>(&ResolvedScene, &StageContext)
//! -> Result<StageOutput, StageError>`, plugged in by one arm of [`run_stage`]. A stage whose
//! engine is not in this build is an error naming the stage, never a placeholder result. A run
//! that fails midway keeps what it finished: `summary.json` is rewritten after every stage and
//! records the stages done and the error. At the end (also after a failure) the run's
//! `report.md` is written from the summary ([`crate::report::markdown`]).
//!
//! `summary.json`: `turf_version`, `turf_build` ([`crate::BUILD`]), `file`, `units` (the
//! internal units), `scene` (the fully resolved scene in internal units), `derived`, `plan`,
//! then either `stages` (one record per stage run: `stage`, `wall_time_s`, `evaluations`,
//! `values`, `files`, `cached`,
//! `cache_key` for a cached stage, and `warnings` when the stage has any) or, for a `[sweep]`,
//! `sweep` (`key`, one entry per value with its own `value_internal`, `derived` and `stages`,
//! and `files`: `sweep.csv` and the plots across the points, [`sweep_table`]), and `error`
//! when the run stopped early (`complete` says whether every stage ran); `stale_files` lists
//! files an earlier run into the same folder wrote and this one did not (reported on the
//! terminal too, never deleted).
//!
//! The `discrete` and `homogenize` stages are cached under `cache/` in the output folder by a
//! hash of their inputs ([`cache`]): a re-run whose inputs to them did not change (only FE
//! keys changed, or another point of a sweep) copies their files from the cache instead of
//! recomputing, records `cached: true` (its `wall_time_s` is then the time of the copy; the
//! values, including the stage's own wall times, are those of the run that computed it), and
//! says so on the terminal.

pub mod cache;
mod continuum_stage;
pub use continuum_stage::{mesh_preview, MeshPreview};
mod discrete_stage;
pub use discrete_stage::{CHECKPOINT, ENSEMBLE_CSV};
pub mod ensemble;
mod halfspace_stage;
pub mod handoff;
mod homogenize_stage;
pub mod items;
#[cfg(feature = "mpi")]
pub mod mpi;
mod rve_stage;
pub mod shard;
mod sweep_table;
mod theory_stage;
mod turf_setup;
pub use turf_setup::scene_turf;

use crate::report::{csv::Table, write_json, ReportError};
use crate::scene::{Loaded, ResolvedScene, Stage};
pub use handoff::{Handoff, ENSEMBLE_LOADING_CSV, LOADING_CSV};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a stage sees besides the scene.
pub struct StageContext<'a> {
    /// the folder the stage writes its files into
    pub out_dir: &'a Path,
    /// the stages already run for this scene, with their results
    pub previous: &'a [StageRecord],
    /// what the stages already run handed over ([`handoff`]): the discrete stage's curves,
    /// the homogenize stage's card
    pub handoffs: &'a [Handoff],
    /// the run's progress bar (on a terminal, not with --json): long stages report their
    /// progress in its message
    pub progress: Option<&'a indicatif::ProgressBar>,
    /// continue from a checkpoint in `out_dir` if there is one ([`RunOptions::resume`])
    pub resume: bool,
    /// the run's work items keep their results ([`items`]): an ensemble reuses the
    /// realisations kept in their folders and keeps those it computes; a serial run computes
    /// every realisation
    pub keep_realisations: bool,
}

impl StageContext<'_> {
    /// What `stage` handed over, read from its cache entry if it was reused (`Ok(None)`: the
    /// stage did not run or handed nothing over).
    pub fn handed(&self, stage: Stage) -> Result<Option<Handoff>, handoff::CachedHandoffError> {
        match self.handoffs.iter().find(|h| h.stage() == stage) {
            Some(h) => h.read(),
            None => Ok(None),
        }
    }
}

/// What a stage returns: its answer and its cost.
#[derive(Debug, Default)]
pub struct StageOutput {
    /// headline numbers, each name carrying its unit (`pull_off_normalised`, `max_load_nN`)
    pub values: BTreeMap<String, f64>,
    /// curves, written by the pipeline as `<stage>_<name>.csv`
    pub tables: Vec<(String, Table)>,
    /// evaluations of the stage's kernel (residuals, energies, closed forms), its cost measure
    pub evaluations: u64,
    /// other files the stage wrote (plots, VTK, cards), relative to the output folder
    pub files: Vec<PathBuf>,
    /// what the user must know about the answer (a fit that misses its data, a file that
    /// could not be written); printed on the terminal and kept in `summary.json`
    pub warnings: Vec<String>,
    /// what the stages after it use ([`handoff`])
    pub handoff: Option<Handoff>,
}

/// Why a stage did not give an answer.
#[derive(Debug, thiserror::Error)]
pub enum StageError {
    /// the engine is not integrated into this build
    #[error("stage '{0}' is not available in this build")]
    NotAvailable(Stage),
    /// the engine ran and failed (did not converge, ...)
    #[error("stage '{stage}' failed: {message}")]
    Failed {
        /// the stage
        stage: Stage,
        /// the engine's diagnostics
        message: String,
    },
    /// an interrupt ([`crate::interrupt`]) stopped the stage; what it reached is kept
    #[error("stage '{stage}' interrupted: {message}")]
    Interrupted {
        /// the stage
        stage: Stage,
        /// where it stopped and what was kept
        message: String,
    },
    /// the stage's results could not be written
    #[error("stage '{stage}': {source}")]
    Report {
        /// the stage
        stage: Stage,
        /// the cause
        source: ReportError,
    },
}

/// One finished stage, as recorded in `summary.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StageRecord {
    /// the stage
    pub stage: Stage,
    /// wall-clock time of the stage, s
    pub wall_time_s: f64,
    /// evaluations of the stage's kernel
    pub evaluations: u64,
    /// headline numbers, names carrying units
    pub values: BTreeMap<String, f64>,
    /// files written, relative to the output folder
    pub files: Vec<String>,
    /// reused from the stage cache rather than computed in this run
    pub cached: bool,
    /// the stage's cache key (cached stages only), 16 hex digits
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cache_key: Option<String>,
    /// the stage's warnings (fit quality, files not written), empty when there are none
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// Run the engine of `stage`. Each engine plugs in as one arm `Stage::X => x_stage::run(..)`.
pub fn run_stage(
    stage: Stage,
    scene: &ResolvedScene,
    ctx: &StageContext,
) -> Result<StageOutput, StageError> {
    match stage {
        Stage::Theory => theory_stage::run(scene, ctx),
        Stage::Halfspace => halfspace_stage::run(scene, ctx),
        Stage::Homogenize => homogenize_stage::run(scene, ctx),
        Stage::Continuum => continuum_stage::run(scene, ctx),
        Stage::Discrete => discrete_stage::run(scene, ctx),
    }
}

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// output folder (default: `[output] dir`, else `runs/<scene name>`)
    pub out: Option<PathBuf>,
    /// show a progress bar on the terminal
    pub progress: bool,
    /// continue a long stage from the checkpoint an earlier run of the scene left in the
    /// output folder (the discrete drive: `discrete_checkpoint.json`)
    pub resume: bool,
}

/// The internal units, echoed in `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Units {
    /// length unit
    pub length: &'static str,
    /// force unit
    pub force: &'static str,
    /// time unit
    pub time: &'static str,
    /// stress unit
    pub stress: &'static str,
    /// energy unit
    pub energy: &'static str,
    /// surface energy unit
    pub surface_energy: &'static str,
    /// temperature unit
    pub temperature: &'static str,
}

const UNITS: Units = Units {
    length: "nm",
    force: "nN",
    time: "s",
    stress: "GPa",
    energy: "aJ",
    surface_energy: "J/m^2",
    temperature: "K",
};

/// One swept value and what ran for it.
#[derive(Debug, Clone, Serialize)]
pub struct PointSummary {
    /// the swept key's value, as written
    pub value: toml::Value,
    /// the swept key's value in internal units (the point's resolved number; `None` for a
    /// value that is not a number)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value_internal: Option<f64>,
    /// the point's sub-folder, relative to the output folder
    pub dir: String,
    /// the point's derived numbers
    pub derived: crate::scene::Derived,
    /// the stages run
    pub stages: Vec<StageRecord>,
}

/// The `[sweep]` part of the summary.
#[derive(Debug, Clone, Serialize)]
pub struct SweepSummary {
    /// the swept key
    pub key: String,
    /// one entry per value run
    pub points: Vec<PointSummary>,
    /// the table across the points and its plots ([`sweep_table`]), written at the end
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<String>,
}

/// The content of `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// the turf version that ran
    pub turf_version: &'static str,
    /// the build that ran: the version and the hash of its source ([`crate::BUILD`])
    pub turf_build: &'static str,
    /// the scene file
    pub file: String,
    /// the internal units of every number
    pub units: Units,
    /// the fully resolved scene, internal units
    pub scene: serde_json::Value,
    /// derived numbers
    pub derived: crate::scene::Derived,
    /// the plan
    pub plan: crate::scene::Plan,
    /// the stages run (without a sweep)
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<StageRecord>,
    /// the sweep points run
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepSummary>,
    /// whether every stage ran
    pub complete: bool,
    /// why the run stopped early
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// files an earlier run in this folder recorded in its `summary.json` that this run did
    /// not write (kept, never deleted: [`stale_files`])
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stale_files: Vec<String>,
}

/// What a run produced.
#[derive(Debug)]
pub struct RunReport {
    /// the output folder
    pub out_dir: PathBuf,
    /// the summary as written
    pub summary: Summary,
    /// the stage failure that stopped the run, if any
    pub failure: Option<StageError>,
}

/// Run every stage the scene asks for (once per swept value) with the built-in engines.
pub fn run(loaded: &Loaded, opts: &RunOptions) -> Result<RunReport, ReportError> {
    run_with(loaded, opts, &mut run_stage)
}

/// A stage runner: [`run_stage`], or a stand-in in tests of the pipeline itself.
pub type Runner<'r> =
    dyn FnMut(Stage, &ResolvedScene, &StageContext) -> Result<StageOutput, StageError> + 'r;

/// Run the plan with `runner` for each stage. A stage failure stops the run and is returned
/// in the report (the summary is written first); only a failure to write the summary is `Err`.
pub fn run_with(
    loaded: &Loaded,
    opts: &RunOptions,
    runner: &mut Runner,
) -> Result<RunReport, ReportError> {
    let out_dir = crate::scene::output_dir(&loaded.base, opts.out.as_deref());
    let mut summary = new_summary(loaded, &out_dir)?;
    let summary_path = out_dir.join("summary.json");
    let earlier = earlier_files(&summary_path);
    let points = points(loaded, &out_dir);
    let total: usize = points.iter().map(|p| p.scene.plan.stages.len()).sum();
    let bar = opts.progress.then(|| progress_bar(total as u64, "stages"));
    let mut failure = None;
    for point in &points {
        if let (Some(sw), Some(entry)) = (summary.sweep.as_mut(), point.entry()) {
            sw.points.push(entry);
        }
        let mut after = |done: &[StageRecord], error: Option<&StageError>| {
            summary.error = error.map(|e| e.to_string());
            store(&mut summary, done);
            write_json(&summary_path, &summary)
        };
        let (_, error) = run_point(point, opts, false, bar.as_ref(), runner, &mut after)?;
        if error.is_some() {
            failure = error;
            break;
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    summary.complete = failure.is_none();
    finish(&mut summary, &earlier, &out_dir)?;
    Ok(RunReport {
        out_dir,
        summary,
        failure,
    })
}

/// The head of the summary of a run of `loaded` into `out_dir`, no stage run yet (an empty
/// `sweep` for a sweep); makes the folder, so that it fails with one clear error before any
/// stage runs.
fn new_summary(loaded: &Loaded, out_dir: &Path) -> Result<Summary, ReportError> {
    let base = &loaded.base;
    let summary = Summary {
        turf_version: env!("CARGO_PKG_VERSION"),
        turf_build: crate::BUILD,
        file: base.file.display().to_string(),
        units: UNITS,
        scene: serde_json::to_value(&base.scene).map_err(|e| ReportError::Invalid {
            path: out_dir.join("summary.json").display().to_string(),
            reason: e.to_string(),
        })?,
        derived: base.derived.clone(),
        plan: base.plan.clone(),
        stages: Vec::new(),
        sweep: base.scene.sweep.as_ref().map(|s| SweepSummary {
            key: s.key.clone(),
            points: Vec::new(),
            files: Vec::new(),
        }),
        complete: false,
        error: None,
        stale_files: Vec::new(),
    };
    create_dir(out_dir)?;
    Ok(summary)
}

/// Make the output folder `dir` (and its parents), or say why it cannot be made.
fn create_dir(dir: &Path) -> Result<(), ReportError> {
    std::fs::create_dir_all(dir).map_err(|cause| ReportError::Io {
        path: dir.display().to_string(),
        cause,
    })
}

/// The end of a run: the stale files listed and reported, `summary.json` and `report.md`
/// written.
fn finish(
    summary: &mut Summary,
    earlier: &BTreeSet<String>,
    out_dir: &Path,
) -> Result<(), ReportError> {
    let files = sweep_table::write(summary, out_dir);
    if let Some(sw) = summary.sweep.as_mut() {
        sw.files = files;
    }
    summary.stale_files = stale_files(earlier, summary, out_dir);
    if !summary.stale_files.is_empty() {
        say(
            None,
            &format!(
                "warning: {} file(s) in {} come from an earlier run and were not written by this \
                 one (listed as stale_files in summary.json; remove them or run into a fresh \
                 --out): {}",
                summary.stale_files.len(),
                out_dir.display(),
                summary.stale_files.join(", ")
            ),
        );
    }
    write_json(&out_dir.join("summary.json"), summary)?;
    crate::report::markdown::write_run_report(summary, out_dir).map(|_| ())
}

/// One point of a run: the scene without a sweep, or one swept value.
pub struct Point<'a> {
    /// the point's index (0 without a sweep)
    pub index: usize,
    /// the swept key (empty without a sweep; the point's own scene no longer has it)
    pub key: &'a str,
    /// the swept value (`None` without a sweep)
    pub value: Option<&'a toml::Value>,
    /// the point's resolved scene
    pub scene: &'a ResolvedScene,
    /// the run's output folder (home of the stage cache)
    pub root: PathBuf,
    /// the point's folder relative to `root`: `sweep_NNN`, or empty without a sweep
    pub rel: String,
}

impl Point<'_> {
    /// The folder the point's stages write into.
    pub fn dir(&self) -> PathBuf {
        match self.rel.as_str() {
            "" => self.root.clone(),
            rel => self.root.join(rel),
        }
    }

    /// The point's entry in the summary's `sweep` (`None` without a sweep), its stages still
    /// empty.
    fn entry(&self) -> Option<PointSummary> {
        self.value.map(|v| PointSummary {
            value: v.clone(),
            value_internal: self.resolved_value(),
            dir: self.rel.clone(),
            derived: self.scene.derived.clone(),
            stages: Vec::new(),
        })
    }

    /// The swept key's number in the point's resolved scene (internal units), found by the
    /// key's dotted path in the scene as `summary.json` writes it.
    fn resolved_value(&self) -> Option<f64> {
        let scene = serde_json::to_value(&self.scene.scene).ok()?;
        self.key
            .split('.')
            .try_fold(&scene, |v, part| v.get(part))?
            .as_f64()
    }
}

/// The points of `loaded` run into `out_dir`: the scene itself, or one per swept value.
pub fn points<'a>(loaded: &'a Loaded, out_dir: &Path) -> Vec<Point<'a>> {
    if loaded.sweep.is_empty() {
        return vec![Point {
            index: 0,
            key: "",
            value: None,
            scene: &loaded.base,
            root: out_dir.to_path_buf(),
            rel: String::new(),
        }];
    }
    let key = loaded
        .base
        .scene
        .sweep
        .as_ref()
        .map_or("", |s| s.key.as_str());
    let point = |(index, p): (usize, &'a crate::scene::SweepPoint)| Point {
        index,
        key,
        value: Some(&p.value),
        scene: &p.scene,
        root: out_dir.to_path_buf(),
        rel: format!("sweep_{index:03}"),
    };
    loaded.sweep.iter().enumerate().map(point).collect()
}

/// What [`run_point`] calls after each stage: the records so far, the failure if any.
type AfterStage<'a> =
    dyn FnMut(&[StageRecord], Option<&StageError>) -> Result<(), ReportError> + 'a;

/// Run the stages of `point` in order, calling `after` with the records so far and the
/// failure, if any, after each stage; stops at the first failure. `keep`: as a work item
/// ([`StageContext::keep_realisations`]). `Err` only when `after` fails (the summary could not
/// be written).
fn run_point(
    point: &Point,
    opts: &RunOptions,
    keep: bool,
    bar: Option<&indicatif::ProgressBar>,
    runner: &mut Runner,
    after: &mut AfterStage,
) -> Result<(Vec<StageRecord>, Option<StageError>), ReportError> {
    let (scene, dir, key) = (point.scene, point.dir(), point.key);
    let mut done: Vec<StageRecord> = Vec::new();
    let mut handed: Vec<Handoff> = Vec::new();
    for planned in &scene.plan.stages {
        let stage = planned.stage;
        if let Some(b) = bar {
            b.set_message(match point.value {
                Some(v) => format!("{stage} ({key} = {v})"),
                None => stage.to_string(),
            });
        }
        let ctx = StageContext {
            out_dir: &dir,
            previous: &done,
            handoffs: &handed,
            progress: bar,
            resume: opts.resume,
            keep_realisations: keep,
        };
        let mut failure = run_cached(stage, scene, &point.root, &ctx, runner)
            .map(|(record, handoff)| {
                done.push(record);
                handed.extend(handoff);
            })
            .err();
        if let Some(b) = bar {
            b.inc(1);
        }
        if failure.is_none() && crate::interrupt::requested() {
            failure = Some(StageError::Interrupted {
                stage,
                message: format!("{}, after the stage finished", crate::interrupt::REASON),
            });
        }
        after(&done, failure.as_ref())?;
        if failure.is_some() {
            return Ok((done, failure));
        }
    }
    Ok((done, None))
}

/// The files a `summary.json` lists (each stage's `files`, a sweep point's under its `dir`,
/// the sweep's table and plots, and the `stale_files` it reported in turn), relative to the
/// output folder.
fn listed_files(summary: &serde_json::Value) -> BTreeSet<String> {
    let stage_files = |stages: &serde_json::Value, dir: &str| -> Vec<String> {
        let files = stages.as_array().into_iter().flatten().flat_map(|s| {
            s["files"]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|f| f.as_str())
        });
        files
            .map(|f| match dir {
                "" => f.to_string(),
                d => format!("{d}/{f}"),
            })
            .collect()
    };
    let mut all: BTreeSet<String> = stage_files(&summary["stages"], "").into_iter().collect();
    for p in summary["sweep"]["points"].as_array().into_iter().flatten() {
        all.extend(stage_files(&p["stages"], p["dir"].as_str().unwrap_or("")));
    }
    let across = summary["sweep"]["files"].as_array().into_iter().flatten();
    all.extend(across.filter_map(|f| f.as_str()).map(str::to_string));
    let stale = summary["stale_files"].as_array().into_iter().flatten();
    all.extend(stale.filter_map(|f| f.as_str()).map(str::to_string));
    all
}

/// The files the `summary.json` at `path` (an earlier run's, if any) lists.
fn earlier_files(path: &Path) -> BTreeSet<String> {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .map_or_else(BTreeSet::new, |v| listed_files(&v))
}

/// The files an earlier run listed that this run did not write and that are still in
/// `out_dir`. They are reported, not deleted: the folder may be one the user chose with
/// `--out` and still holds results they want to compare (docs/scenes.md, "Output folder").
fn stale_files(earlier: &BTreeSet<String>, summary: &Summary, out_dir: &Path) -> Vec<String> {
    let mut written = summary.clone();
    written.stale_files.clear();
    let now = serde_json::to_value(&written).map_or_else(|_| BTreeSet::new(), |v| listed_files(&v));
    earlier
        .difference(&now)
        .filter(|f| out_dir.join(f).is_file())
        .cloned()
        .collect()
}

/// Put the current point's records into the summary (its last sweep point, or its stages).
fn store(summary: &mut Summary, done: &[StageRecord]) {
    match summary.sweep.as_mut().and_then(|s| s.points.last_mut()) {
        Some(p) => p.stages = done.to_vec(),
        None => summary.stages = done.to_vec(),
    }
}

/// Reuse the stage's cached result when its inputs are unchanged (saying so on stderr, above
/// the progress bar when there is one), else run it and keep the result in the cache. `root` is the run's output folder (the cache's home), `dir`
/// the folder this stage writes into (a sweep point's sub-folder).
fn run_cached(
    stage: Stage,
    scene: &ResolvedScene,
    root: &Path,
    ctx: &StageContext,
    runner: &mut Runner,
) -> Result<(StageRecord, Option<Handoff>), StageError> {
    let report = |source| StageError::Report { stage, source };
    let (dir, progress) = (ctx.out_dir, ctx.progress);
    let Some(key) = cache::key(stage, scene, ctx.previous) else {
        return run_one(stage, scene, ctx, runner);
    };
    let start = Instant::now();
    if let Some((mut record, files)) = cache::reuse(root, dir, stage, &key).map_err(report)? {
        record.wall_time_s = start.elapsed().as_secs_f64();
        let line = format!(
            "{stage}: inputs unchanged, reused {} (not recomputed)",
            cache::entry_name(stage, &key)
        );
        say(progress, &line);
        let handoff = Handoff::Cached {
            record: record.clone(),
            files,
        };
        return Ok((record, Some(handoff)));
    }
    let (mut record, handoff) = run_one(stage, scene, ctx, runner)?;
    record.cache_key = Some(key.hex.clone());
    cache::store(root, dir, &key, &record).map_err(report)?;
    Ok((record, handoff))
}

/// Run one stage, time it and write its tables.
fn run_one(
    stage: Stage,
    scene: &ResolvedScene,
    ctx: &StageContext,
    runner: &mut Runner,
) -> Result<(StageRecord, Option<Handoff>), StageError> {
    let dir = ctx.out_dir;
    let start = Instant::now();
    let out = runner(stage, scene, ctx)?;
    let wall_time_s = start.elapsed().as_secs_f64();
    if let Some((name, _)) = out.values.iter().find(|(_, v)| !v.is_finite()) {
        return Err(StageError::Failed {
            stage,
            message: format!("the engine returned a non-finite value for {name}"),
        });
    }
    for w in &out.warnings {
        say(ctx.progress, &format!("{stage}: warning: {w}"));
    }
    let mut files: Vec<String> = out.files.iter().map(|f| f.display().to_string()).collect();
    for (name, table) in &out.tables {
        let file = format!("{stage}_{name}.csv");
        table
            .write(&dir.join(&file))
            .map_err(|source| StageError::Report { stage, source })?;
        files.push(file);
    }
    let record = StageRecord {
        stage,
        wall_time_s,
        evaluations: out.evaluations,
        values: out.values,
        files,
        cached: false,
        cache_key: None,
        warnings: out.warnings,
    };
    Ok((record, out.handoff))
}

/// A line for the user on stderr: above the progress bar when there is one.
pub(crate) fn say(progress: Option<&indicatif::ProgressBar>, line: &str) {
    match progress {
        Some(bar) => bar.println(line),
        None => eprintln!("{line}"),
    }
}

/// A progress bar over `len` steps counted in `unit` (stages, tasks).
pub fn progress_bar(len: u64, unit: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template(&format!(
        "{{spinner}} [{{elapsed_precise}}] {{bar:30}} {{pos}}/{{len}} {unit}  {{msg}}"
    )) {
        bar.set_style(style);
    }
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load_str;

    const SCENE: &str = r#"
[scene]
name = "pipeline-test"
[indenter]
radius = "1 um"
[material]
model = "linear"
youngs = "1 GPa"
poisson = 0.3
[adhesion]
gamma = "0.05 J/m^2"
z0 = "0.34 nm"
[halfspace]
cells_per_zone = 12
"#;

    fn temp_dir(tag: &str) -> PathBuf {
        std::env::temp_dir().join(format!("turf-pipeline-{tag}-{}", std::process::id()))
    }

    #[test]
    fn a_stage_that_cannot_run_is_an_error_naming_it_and_the_summary_is_kept() {
        // theory runs first, then the continuum stage must refuse arc-length on a relaxing
        // material (an elastic curve has no time), by name, and the theory result must stay
        // in summary.json
        let fe = format!(
            "{SCENE}\n[viscoelastic]\ng = [0.4]\ntau = [\"3 s\"]\n[schedule]\n[[schedule.segment]]\nkind = \"load\"\nto = \"5 nm\"\nrate = \"10 nm/s\"\n[solver]\nmethod = \"riks\"\n"
        )
        .replace("[halfspace]\ncells_per_zone = 12\n", "");
        let loaded = load_str(&fe, Path::new("p.toml"), &[]).unwrap();
        let dir = temp_dir("na");
        let opts = RunOptions {
            out: Some(dir.clone()),
            progress: false,
            resume: false,
        };
        let report = run(&loaded, &opts).unwrap();
        let e = report
            .failure
            .expect("the continuum stage refuses arc-length with Prony terms");
        assert!(
            e.to_string().starts_with(
                "stage 'continuum' failed: continuum parameters: arc-length continuation traces an elastic curve"
            ),
            "{e}"
        );
        let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(json["complete"], false);
        assert!(json["error"].as_str().unwrap().contains("continuum"));
        assert_eq!(json["stages"][0]["stage"], "theory");
        assert_eq!(json["scene"]["indenter"]["radius"], 1000.0);
        std::fs::remove_dir_all(dir).ok();
    }

    #[test]
    fn a_failure_midway_keeps_the_stages_that_finished() {
        let loaded = load_str(SCENE, Path::new("p.toml"), &[]).unwrap();
        let dir = temp_dir("midway");
        let opts = RunOptions {
            out: Some(dir.clone()),
            progress: false,
            resume: false,
        };
        let mut runner = |stage: Stage, _: &ResolvedScene, ctx: &StageContext| match stage {
            Stage::Theory => {
                assert!(ctx.previous.is_empty());
                Ok(StageOutput {
                    values: BTreeMap::from([("pull_off_normalised".to_string(), -1.7)]),
                    tables: vec![(
                        "curve".to_string(),
                        Table::new().column("depth_nm", vec![0.0, 1.0]),
                    )],
                    evaluations: 3,
                    ..StageOutput::default()
                })
            }
            _ => {
                assert_eq!(ctx.previous.len(), 1);
                Err(StageError::Failed {
                    stage,
                    message: "did not converge".into(),
                })
            }
        };
        let report = run_with(&loaded, &opts, &mut runner).unwrap();
        assert!(report.failure.is_some());
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(json["stages"][0]["stage"], "theory");
        assert_eq!(json["stages"][0]["evaluations"], 3);
        assert_eq!(json["stages"][0]["values"]["pull_off_normalised"], -1.7);
        assert_eq!(json["stages"].as_array().unwrap().len(), 1);
        assert!(json["error"].as_str().unwrap().contains("halfspace"));
        assert!(dir.join("theory_curve.csv").is_file());
        std::fs::remove_dir_all(dir).ok();
    }

    #[test]
    fn a_nan_from_an_engine_is_refused() {
        let loaded = load_str(SCENE, Path::new("p.toml"), &[]).unwrap();
        let dir = temp_dir("nan");
        let opts = RunOptions {
            out: Some(dir.clone()),
            progress: false,
            resume: false,
        };
        let mut runner = |_: Stage, _: &ResolvedScene, _: &StageContext| {
            Ok(StageOutput {
                values: BTreeMap::from([("x".to_string(), f64::NAN)]),
                ..StageOutput::default()
            })
        };
        let report = run_with(&loaded, &opts, &mut runner).unwrap();
        assert!(report
            .failure
            .unwrap()
            .to_string()
            .contains("non-finite value for x"));
        std::fs::remove_dir_all(dir).ok();
    }
}
