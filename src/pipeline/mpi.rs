//! The MPI transport of the work items (cargo feature `mpi`, rsmpi): under `mpirun -n N turf
//! run SCENE` every rank loads the scene and lists its items ([`super::items`]); rank 0
//! coordinates and works, the other ranks work. The coordinator hands out the next work item
//! to whichever worker reports a result (dynamic load balancing: items differ 10–100× in
//! cost), queues an ensemble point's reduction once its realisations are all done, and, when
//! every item is done, writes the summary a serial run writes ([`super::items::assemble`]).
//!
//! Rank 0's worker is a thread beside the coordinator; only the coordinator's thread calls MPI
//! (`MPI_THREAD_FUNNELED` is enough). Messages are JSON: a worker sends a [`Report`] (its first
//! says it is ready), the coordinator answers with the next `Option<Item>` (`None`: stop).
//! Files go straight from each worker into the output folder, so the ranks need one shared
//! file system (as on any cluster's scratch). Both sides poll instead of blocking, so an idle
//! rank leaves its core to the others: the first look again after [`POLL_FIRST`], each wait
//! twice the last up to [`COORDINATOR_POLL`] for the coordinator (little CPU while items run
//! for minutes, quick answers in a burst of short items) and [`WORKER_POLL`] for a worker
//! waiting for its next item (which usually comes at once).

use super::items::{assemble, outcome_line, run_item, Item, Items, Outcome};
use super::{points, say, Point, RunOptions, RunReport};
use crate::report::ReportError;
use crate::scene::{self, Loaded};
use mpi::traits::*;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, VecDeque};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The first wait for a message.
pub const POLL_FIRST: Duration = Duration::from_micros(50);
/// The coordinator's longest wait between two looks for a report.
pub const COORDINATOR_POLL: Duration = Duration::from_millis(1);
/// A worker's longest wait between two looks for its next item.
pub const WORKER_POLL: Duration = Duration::from_micros(200);

/// Look for a message with `receive` until there is one, waiting longer between looks, up
/// to `longest`.
fn wait_for<T>(longest: Duration, mut receive: impl FnMut() -> Option<T>) -> T {
    let mut wait = POLL_FIRST;
    loop {
        if let Some(t) = receive() {
            return t;
        }
        std::thread::sleep(wait);
        wait = (wait * 2).min(longest);
    }
}

/// The environment variables by which a launcher (Open MPI's, PMI, PMIx, MPICH's Hydra)
/// tells a process that it is one rank of several.
const LAUNCHED: [&str; 4] = ["OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"];

/// Whether this process was started by `mpirun`/`srun`.
pub fn launched() -> bool {
    LAUNCHED.iter().any(|v| std::env::var_os(v).is_some())
}

/// A worker's message to the coordinator.
#[derive(Serialize, Deserialize)]
struct Report {
    /// the item it finished (none in its first message)
    outcome: Option<Outcome>,
    /// how long it waited for this item after reporting the previous one, µs
    wait_us: Option<f64>,
}

/// Who sent a report: rank 0's worker thread, or another rank.
#[derive(Clone, Copy)]
enum Worker {
    Local,
    Rank(mpi::Rank),
}

/// Run `loaded` over the ranks of `mpirun`. Rank 0 returns the report of the run; the other
/// ranks `None`. `Err` when MPI cannot start or the summary cannot be written.
pub fn run(loaded: &Loaded, opts: &RunOptions) -> Result<Option<RunReport>, ReportError> {
    let (universe, _) =
        mpi::initialize_with_threading(mpi::Threading::Funneled).ok_or_else(|| {
            ReportError::Invalid {
                path: "MPI".into(),
                reason: "MPI could not be initialised (it was already)".into(),
            }
        })?;
    let world = universe.world();
    let out_dir = scene::output_dir(&loaded.base, opts.out.as_deref());
    super::create_dir(&out_dir)?;
    let points = points(loaded, &out_dir);
    if world.rank() != 0 {
        let root = world.process_at_rank(0);
        work(
            &points,
            opts,
            |r| root.send(&r[..]),
            || {
                let (msg, status) = root.immediate_matched_probe()?;
                Some((msg, status).matched_receive_vec::<u8>().0)
            },
        );
        return Ok(None);
    }
    let start = Instant::now();
    let (to_local, local_items) = mpsc::channel::<Vec<u8>>();
    let (local_reports, from_local) = mpsc::channel::<Vec<u8>>();
    let pts = &points;
    let outcomes = std::thread::scope(|scope| {
        scope.spawn(move || {
            let send = |r: Vec<u8>| {
                local_reports.send(r).ok();
            };
            work(pts, opts, send, || local_items.try_recv().ok());
        });
        let receive = || {
            if let Ok(r) = from_local.try_recv() {
                return Some((Worker::Local, r));
            }
            let probed = world.any_process().immediate_matched_probe()?;
            let rank = probed.1.source_rank();
            Some((Worker::Rank(rank), probed.matched_receive_vec::<u8>().0))
        };
        let send = |w: Worker, item: Option<Item>| {
            let bytes = serde_json::to_vec(&item).unwrap_or_default();
            match w {
                Worker::Local => {
                    to_local.send(bytes).ok();
                }
                Worker::Rank(r) => world.process_at_rank(r).send(&bytes[..]),
            }
        };
        let workers = usize::try_from(world.size()).unwrap_or(1);
        coordinate(loaded, &points, workers, receive, send)
    });
    let (outcomes, waits) = outcomes;
    let items = outcomes.len();
    let report = assemble(loaded, &out_dir, &outcomes)?;
    say(
        None,
        &overhead_line(&waits, world.size(), start.elapsed().as_secs_f64(), items),
    );
    Ok(Some(report))
}

/// The coordinator: hands out the items of `points` to `workers` workers as they report, and
/// returns the outcomes of the point items and the workers' waits (µs) for items that were
/// ready when they asked.
fn coordinate(
    loaded: &Loaded,
    points: &[Point],
    workers: usize,
    mut receive: impl FnMut() -> Option<(Worker, Vec<u8>)>,
    send: impl Fn(Worker, Option<Item>),
) -> (BTreeMap<usize, Outcome>, Vec<f64>) {
    let items = Items::of(points);
    let total = items.work.len() + items.reductions.len();
    let mut left: BTreeMap<usize, usize> = items
        .reductions
        .iter()
        .map(|r| (r.point(), items.work_of(r.point())))
        .collect();
    let mut ready: VecDeque<Item> = items.work.iter().copied().collect();
    ready.extend(items.reductions.iter().filter(|r| left[&r.point()] == 0));
    let (mut idle, mut outcomes, mut waits) = (Vec::new(), BTreeMap::new(), Vec::new());
    let (mut outstanding, mut finished) = (0usize, 0usize);
    let swept = loaded.base.scene.sweep.is_some();
    while !(ready.is_empty() && outstanding == 0 && idle.len() == workers) {
        let (worker, bytes) = wait_for(COORDINATOR_POLL, &mut receive);
        let report: Report = match serde_json::from_slice(&bytes) {
            Ok(r) => r,
            Err(e) => {
                say(
                    None,
                    &format!("mpi: a worker's message was not understood: {e}"),
                );
                continue;
            }
        };
        if let Some(w) = report.wait_us {
            waits.push(w);
        }
        if let Some(o) = report.outcome {
            outstanding -= 1;
            finished += 1;
            say(None, &outcome_line(&o, swept, finished, total));
            match o.item {
                Item::Realisation { point, .. } => {
                    let n = left.entry(point).or_default();
                    *n = n.saturating_sub(1);
                    if *n == 0 {
                        ready.push_back(Item::Point { point });
                    }
                }
                Item::Point { point } => {
                    outcomes.insert(point, o);
                }
            }
        }
        idle.push(worker);
        while let Some(item) = (!idle.is_empty()).then(|| ready.pop_front()).flatten() {
            if let Some(w) = idle.pop() {
                send(w, Some(item));
                outstanding += 1;
            }
        }
    }
    for w in idle {
        send(w, None);
    }
    (outcomes, waits)
}

/// A worker: says it is ready, then runs each item it is sent and reports it, until told to
/// stop. `send` delivers a report, `receive` looks for the coordinator's answer.
fn work(
    points: &[Point],
    opts: &RunOptions,
    send: impl Fn(Vec<u8>),
    mut receive: impl FnMut() -> Option<Vec<u8>>,
) {
    let mut report = Report {
        outcome: None,
        wait_us: None,
    };
    loop {
        send(serde_json::to_vec(&report).unwrap_or_default());
        let asked = Instant::now();
        let bytes = wait_for(WORKER_POLL, &mut receive);
        let wait_us = asked.elapsed().as_secs_f64() * 1e6;
        let Ok(Some(item)) = serde_json::from_slice::<Option<Item>>(&bytes) else {
            return;
        };
        let outcome = run_item(points, item, opts).unwrap_or_else(|e| Outcome {
            error: Some(e.to_string()),
            ..Outcome::new(item)
        });
        report = Report {
            outcome: Some(outcome),
            wait_us: Some(wait_us),
        };
    }
}

/// The closing line: items, ranks, wall time and the coordinator's overhead per item.
fn overhead_line(waits: &[f64], ranks: mpi::Rank, seconds: f64, points: usize) -> String {
    let mut w = waits.to_vec();
    w.sort_by(f64::total_cmp);
    let median = w.get(w.len() / 2).copied().unwrap_or(0.0);
    format!(
        "mpi: {points} point(s) on {ranks} rank(s) in {seconds:.3} s; coordinator overhead per \
         item (a worker's wait from its report to its next item): median {median:.0} µs over \
         {} items",
        w.len()
    )
}
