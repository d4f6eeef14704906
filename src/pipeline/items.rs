//! A scene's work items (DESIGN.md "Work items, ensembles and scale-out"): the units that
//! `turf run --shard I/N` slices for a job array and that MPI ranks share out
//! ([`super::shard`], `super::mpi`). A serial `turf run` runs the same work in one process and
//! keeps none of the results below.
//!
//! - A sweep point without an ensemble is one item, [`Item::Point`]: every stage of the point,
//!   into its folder. Its records and error are kept in `point_result.json` there, with the
//!   point's resolved scene they came from; a later item with the same scene reuses them.
//! - A sweep point with an ensemble (`turf.realisations` = N > 1 and a discrete stage) is N
//!   items [`Item::Realisation`], each one realisation of the discrete stage, kept in the
//!   realisation's folder (`discrete_realisation.json`, the discrete stage's). Once all N
//!   are done, the point's reduction, an [`Item::Point`], runs its stages: the discrete stage
//!   reduces the kept realisations instead of computing them, then the stages after it run.
//!
//! A failed item is a result: kept and reported, not recomputed (the engines are
//! deterministic); an interrupted one is not kept, and a re-run computes only the items not
//! kept. [`assemble`] writes the summary of a serial run from the points' results.

use super::{
    earlier_files, finish, new_summary, points, run_point, run_stage, Point, RunOptions, RunReport,
    StageError, StageRecord,
};
use crate::report::{write_json, ReportError};
use crate::scene::{Loaded, ResolvedScene, Stage};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// The file in a point's folder that keeps its result.
pub const POINT_RESULT: &str = "point_result.json";

/// One unit of work.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Item {
    /// realisation `k` of the ensemble of point `point`
    Realisation {
        /// the point (0 without a sweep)
        point: usize,
        /// the realisation
        k: usize,
    },
    /// every stage of point `point`
    Point {
        /// the point (0 without a sweep)
        point: usize,
    },
}

impl Item {
    /// The item's point.
    pub fn point(self) -> usize {
        match self {
            Item::Realisation { point, .. } | Item::Point { point } => point,
        }
    }

    /// The item for messages: `sweep_001 r002`, `sweep_001`, `r002`, `scene`.
    pub fn label(self, swept: bool) -> String {
        let point = format!("sweep_{:03}", self.point());
        match (self, swept) {
            (Item::Realisation { k, .. }, true) => format!("{point} r{k:03}"),
            (Item::Realisation { k, .. }, false) => format!("r{k:03}"),
            (Item::Point { .. }, true) => point,
            (Item::Point { .. }, false) => "scene".into(),
        }
    }
}

/// A scene's items.
#[derive(Debug, Clone, PartialEq)]
pub struct Items {
    /// the items that can run in any order: each point without an ensemble, each
    /// realisation of the others
    pub work: Vec<Item>,
    /// the reductions of the ensemble points, each ready once its point's realisations are
    /// done
    pub reductions: Vec<Item>,
}

impl Items {
    /// The items of `points`, in point order.
    pub fn of(points: &[Point]) -> Self {
        let mut items = Items {
            work: Vec::new(),
            reductions: Vec::new(),
        };
        for p in points {
            match ensemble_size(p.scene) {
                Some(n) => {
                    let point = p.index;
                    items
                        .work
                        .extend((0..n).map(|k| Item::Realisation { point, k }));
                    items.reductions.push(Item::Point { point });
                }
                None => items.work.push(Item::Point { point: p.index }),
            }
        }
        items
    }

    /// How many work items point `point` has.
    pub fn work_of(&self, point: usize) -> usize {
        self.work.iter().filter(|i| i.point() == point).count()
    }
}

/// The ensemble's size of a point whose discrete stage compresses N > 1 turfs.
fn ensemble_size(scene: &ResolvedScene) -> Option<usize> {
    let s = &scene.scene;
    let discrete = scene.plan.stages.iter().any(|p| p.stage == Stage::Discrete);
    let n = s.turf.as_ref().map_or(1, |t| t.realisations);
    (discrete && s.rods.is_none() && n > 1).then_some(n)
}

/// What an item gave.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Outcome {
    /// the item
    pub item: Item,
    /// why it failed, if it did
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// reused from an earlier run rather than computed
    pub kept: bool,
    /// wall-clock time of the item, s
    pub seconds: f64,
    /// the stages run, for a point item
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<StageRecord>,
}

impl Outcome {
    /// The outcome of `item` before it ran: no error, no stages.
    pub fn new(item: Item) -> Self {
        Outcome {
            item,
            error: None,
            kept: false,
            seconds: 0.0,
            stages: Vec::new(),
        }
    }
}

/// A point's result as kept in [`POINT_RESULT`].
#[derive(Serialize, Deserialize)]
struct PointResult {
    /// the canonical JSON of the build ([`crate::BUILD`]) and the point's resolved scene
    inputs: String,
    stages: Vec<StageRecord>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    error: Option<String>,
}

/// What a point's result depends on.
fn point_inputs(scene: &ResolvedScene) -> String {
    let v = serde_json::to_value((crate::BUILD, &scene.scene));
    super::cache::canonical_json(&v.unwrap_or(serde_json::Value::Null))
}

/// The result kept for `point` with its current inputs and all its files.
fn kept_point(point: &Point) -> Option<PointResult> {
    let dir = point.dir();
    let text = std::fs::read_to_string(dir.join(POINT_RESULT)).ok()?;
    let kept: PointResult = serde_json::from_str(&text).ok()?;
    let files = kept.stages.iter().flat_map(|r| &r.files);
    let complete = files.clone().all(|f| dir.join(f).is_file());
    (kept.inputs == point_inputs(point.scene) && complete).then_some(kept)
}

/// Run `item` of `points` (or reuse its kept result). `Err` only when a result could not be
/// written.
pub fn run_item(points: &[Point], item: Item, opts: &RunOptions) -> Result<Outcome, ReportError> {
    let start = Instant::now();
    let point = &points[item.point()];
    let mut outcome = Outcome::new(item);
    match item {
        Item::Realisation { k, .. } => {
            match super::discrete_stage::run_realisation_item(
                point.scene,
                &point.dir(),
                k,
                opts.resume,
            ) {
                Ok(kept) => outcome.kept = kept,
                Err(StageError::Report { source, .. }) => return Err(source),
                Err(e) => outcome.error = Some(e.to_string()),
            }
        }
        Item::Point { .. } => {
            if let Some(kept) = kept_point(point) {
                outcome.kept = true;
                outcome.error = kept.error;
                outcome.stages = kept.stages;
                for r in &mut outcome.stages {
                    r.cached = true;
                }
            } else {
                let (stages, error) =
                    run_point(point, opts, true, None, &mut run_stage, &mut |_, _| Ok(()))?;
                if !matches!(
                    error,
                    Some(StageError::Interrupted { .. } | StageError::Report { .. })
                ) {
                    let kept = PointResult {
                        inputs: point_inputs(point.scene),
                        stages: stages.clone(),
                        error: error.as_ref().map(|e| e.to_string()),
                    };
                    write_json(&point.dir().join(POINT_RESULT), &kept)?;
                }
                outcome.error = error.map(|e| e.to_string());
                outcome.stages = stages;
            }
        }
    }
    outcome.seconds = start.elapsed().as_secs_f64();
    Ok(outcome)
}

/// The line on the terminal for a finished item.
pub fn outcome_line(o: &Outcome, swept: bool, done: usize, total: usize) -> String {
    let what = match (&o.error, o.kept) {
        (Some(e), _) => format!("failed: {e}"),
        (None, true) => "kept from an earlier run".into(),
        (None, false) => format!("done in {:.3} s", o.seconds),
    };
    format!("item {done}/{total} ({}): {what}", o.item.label(swept))
}

/// Write the summary (and `report.md`) of `loaded` run into `out_dir` from the outcomes of
/// its point items, as a serial run writes it; a point without an outcome is reported as not
/// run, a failed point with its error. The summary's `error` lists them, prefixed by the
/// point's folder.
pub fn assemble(
    loaded: &Loaded,
    out_dir: &Path,
    outcomes: &BTreeMap<usize, Outcome>,
) -> Result<RunReport, ReportError> {
    let mut summary = new_summary(loaded, out_dir)?;
    let earlier = earlier_files(&out_dir.join("summary.json"));
    let mut errors = Vec::new();
    for point in points(loaded, out_dir) {
        let (stages, error) = match outcomes.get(&point.index) {
            Some(o) => (o.stages.clone(), o.error.clone()),
            None => (Vec::new(), Some("not run".to_string())),
        };
        if let Some(e) = error {
            errors.push(match point.rel.as_str() {
                "" => e,
                rel => format!("{rel}: {e}"),
            });
        }
        match (summary.sweep.as_mut(), point.entry()) {
            (Some(sw), Some(mut entry)) => {
                entry.stages = stages;
                sw.points.push(entry);
            }
            _ => summary.stages = stages,
        }
    }
    summary.complete = errors.is_empty();
    summary.error = (!errors.is_empty()).then(|| errors.join("; "));
    finish(&mut summary, &earlier, out_dir)?;
    Ok(RunReport {
        out_dir: out_dir.to_path_buf(),
        summary,
        failure: None,
    })
}
