//! The speed–accuracy trade: one ladder of problems, each answered by every fidelity
//! that can answer it — closed form, half-space, FE at small and at finite strain, discrete
//! tubes, the homogenised card — with its answer, the reference it is judged against, its error
//! and its cost; and refinement sweeps (grid, mesh, segments, time step) giving error against
//! cost. `turf bench` runs both and writes `bench.json`, `bench.md` and the plots.
//!
//! No wall-clock time is asserted anywhere: the figures are measurements, reported.

pub mod ladder;
pub mod presets;
pub mod sweeps;
pub mod turf_indent;

use crate::report::plot::{Plot, Series};
use crate::report::{write_atomic, write_json, ReportError};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Why a bench answer, sweep or chain run could not be had.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// the FE run failed
    #[error(transparent)]
    Fe(#[from] crate::continuum::FeError),
    /// the half-space solver failed
    #[error(transparent)]
    Halfspace(#[from] crate::halfspace::HalfspaceError),
    /// a closed form could not be evaluated
    #[error(transparent)]
    Theory(#[from] crate::theory::TheoryError),
    /// a discrete rod could not be built
    #[error(transparent)]
    Rod(#[from] crate::discrete::rod::RodError),
    /// the discrete Newton solve failed
    #[error(transparent)]
    Solve(#[from] crate::discrete::solve::SolveError),
    /// a bench scene could not be loaded
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// a run's report could not be written
    #[error(transparent)]
    Report(#[from] ReportError),
    /// a discrete curve could not be read
    #[error(transparent)]
    Curve(#[from] crate::homogenize::curve::CurveError),
    /// a material card could not be read
    #[error(transparent)]
    Card(#[from] crate::homogenize::card::CardError),
    /// a card could not be evaluated
    #[error(transparent)]
    Hyperfoam(#[from] crate::homogenize::hyperfoam::HyperfoamError),
    /// a file or folder could not be read or removed
    #[error("{}: {error}", path.display())]
    Io {
        /// the file or folder
        path: PathBuf,
        /// why
        error: std::io::Error,
    },
    /// the FE converged no increment
    #[error("no increment converged")]
    NoIncrement,
    /// the FE stopped short of the depth asked for
    #[error("stopped at δ = {depth:.3} nm")]
    Stopped {
        /// the last converged depth, nm
        depth: f64,
    },
    /// the FE never reached the pull-off
    #[error("no pull-off reached")]
    NoPullOff,
    /// a chain scene's run failed at a stage
    #[error("{file}: {failure}")]
    Chain {
        /// the scene's name
        file: String,
        /// the stage's failure, as reported
        failure: String,
    },
    /// a chain run has no record of a stage
    #[error("no {stage:?} stage in {}", dir.display())]
    NoStage {
        /// the stage
        stage: crate::scene::Stage,
        /// the run's folder
        dir: PathBuf,
    },
    /// a stage record lacks a value
    #[error("the {stage} stage reported no {name}")]
    NoValue {
        /// the stage
        stage: crate::scene::Stage,
        /// the value's name
        name: String,
    },
    /// the discrete curve has no points
    #[error("empty discrete curve")]
    EmptyCurve,
    /// a CSV file lacks a column
    #[error("{}: no column {column}", path.display())]
    NoColumn {
        /// the file
        path: PathBuf,
        /// the column
        column: String,
    },
    /// a CSV cell is not a number
    #[error("{}: line {line}: not a number", path.display())]
    NotANumber {
        /// the file
        path: PathBuf,
        /// the line (1-based)
        line: usize,
    },
    /// a bench scene's text is not TOML
    #[error("{scene}: {message}")]
    Toml {
        /// the scene's name
        scene: String,
        /// the parser's message
        message: String,
    },
    /// a derived scene could not be written as TOML
    #[error(transparent)]
    TomlWrite(#[from] toml::ser::Error),
    /// a bench scene lacks a section or key
    #[error("{scene}: no {what}")]
    Missing {
        /// the scene's name
        scene: String,
        /// the section or key, as written in the scene
        what: &'static str,
    },
    /// a depth lies beyond a load–depth curve
    #[error("δ = {depth} nm is beyond the curve (to {end:.1} nm)")]
    BeyondCurve {
        /// the depth asked for, nm
        depth: f64,
        /// the curve's deepest point, nm
        end: f64,
    },
    /// a card fit failed
    #[error(transparent)]
    Fit(#[from] crate::homogenize::fit_hyperfoam::FitError),
    /// an error with a note on the run it came from
    #[error("{error}; {note}")]
    Noted {
        /// the error
        error: Box<BenchError>,
        /// the note
        note: String,
    },
}

/// The cost of one answer: wall time and the CPU time of the whole process over the same span
/// (all threads; Linux `/proc/self/stat`, `None` elsewhere).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cost {
    /// wall-clock time, s
    pub wall_s: f64,
    /// user + system CPU time of the process, s
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cpu_s: Option<f64>,
}

/// CPU time (user + system) of this process so far, s. `/proc/self/stat` counts in clock
/// ticks of USER_HZ, which the Linux ABI fixes at 100 per second.
fn process_cpu_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // fields after the command name in parentheses (which may itself hold spaces)
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the whole line: 12th and 13th after ')'
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

/// Run `f` and measure its cost.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, Cost) {
    let (cpu0, t0) = (process_cpu_s(), Instant::now());
    let out = f();
    let wall_s = t0.elapsed().as_secs_f64();
    let cpu_s = match (cpu0, process_cpu_s()) {
        (Some(a), Some(b)) => Some(b - a),
        _ => None,
    };
    (out, Cost { wall_s, cpu_s })
}

/// One answer of the ladder.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// the question, e.g. "pull-off P/(πγR), LJ 9-3, μ = 2"
    pub problem: String,
    /// who answered: "theory (Maugis–Dugdale)", "halfspace", "FE small strain", …
    pub fidelity: String,
    /// the answer (`None`: this fidelity failed, see `note`)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub answer: Option<f64>,
    /// the reference it is judged against (`None`: there is none yet)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
    /// where the reference comes from
    pub reference_source: String,
    /// |answer/reference − 1|
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rel_error: Option<f64>,
    /// what it cost
    pub cost: Cost,
    /// resolution used, failure, or what the error contains besides discretisation
    pub note: String,
}

impl Row {
    /// A row with its relative error computed from `answer` and `reference`.
    pub fn new(
        problem: &str,
        fidelity: &str,
        answer: Result<f64, BenchError>,
        reference: (f64, &str),
        cost: Cost,
        note: String,
    ) -> Self {
        let (answer, note) = match answer {
            Ok(a) if a.is_finite() => (Some(a), note),
            Ok(a) => (None, format!("non-finite answer {a}; {note}")),
            Err(e) => (None, format!("failed: {e}")),
        };
        let r = Some(reference.0).filter(|r| r.is_finite() && *r != 0.0);
        Row {
            problem: problem.into(),
            fidelity: fidelity.into(),
            answer,
            reference: r,
            reference_source: reference.1.into(),
            rel_error: answer.zip(r).map(|(a, r)| (a / r - 1.0).abs()),
            cost,
            note,
        }
    }
}

/// One point of a refinement sweep.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SweepPoint {
    /// the swept setting (cells per zone, elements per radius, segments, increments)
    pub setting: f64,
    /// degrees of freedom or elements, where meaningful
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size: Option<usize>,
    /// the answer at this setting
    pub answer: f64,
    /// |answer/reference − 1|
    pub rel_error: f64,
    /// its cost
    pub cost: Cost,
}

/// A refinement sweep: error against cost for one setting of one fidelity.
#[derive(Debug, Clone, Serialize)]
pub struct Sweep {
    /// short name, used for the plot's file name
    pub name: String,
    /// the problem and the fidelity
    pub title: String,
    /// what is swept
    pub setting: String,
    /// the reference value
    pub reference: f64,
    /// where it comes from
    pub reference_source: String,
    /// the points, coarse to fine (failed settings are left out and listed in `failures`)
    pub points: Vec<SweepPoint>,
    /// settings that failed, with the reason
    pub failures: Vec<String>,
}

/// Everything `turf bench` measured.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    /// turf's version
    pub turf_version: &'static str,
    /// rayon threads the engines ran on
    pub threads: usize,
    /// `--quick`: the expensive rows and points were skipped
    pub quick: bool,
    /// the ladder
    pub rows: Vec<Row>,
    /// the sweeps
    pub sweeps: Vec<Sweep>,
}

fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("—".into(), |v| format!("{v:.digits$}"))
}

fn fmt_err(e: Option<f64>) -> String {
    e.map_or("—".into(), |e| format!("{:.2e}", e))
}

impl BenchReport {
    /// The report as Markdown tables.
    pub fn to_markdown(&self) -> String {
        let mut s = format!(
            "# turf bench\n\nturf {}, {} threads{}. Costs are wall / CPU seconds of this run \
             (CPU: all threads of the process).\n\n## Ladder\n\n\
             | problem | fidelity | answer | reference | error | wall (s) | CPU (s) | note |\n\
             |---|---|---|---|---|---|---|---|\n",
            self.turf_version,
            self.threads,
            if self.quick { ", --quick" } else { "" }
        );
        for r in &self.rows {
            s += &format!(
                "| {} | {} | {} | {} ({}) | {} | {:.3} | {} | {} |\n",
                r.problem,
                r.fidelity,
                fmt_opt(r.answer, 6),
                fmt_opt(r.reference, 6),
                r.reference_source,
                fmt_err(r.rel_error),
                r.cost.wall_s,
                fmt_opt(r.cost.cpu_s, 2),
                r.note
            );
        }
        for w in &self.sweeps {
            s += &format!(
                "\n## {}\n\nReference {:.6} ({}). Plot: `plots/sweep_{}.svg`.\n\n\
                 | {} | size | answer | error | wall (s) | CPU (s) |\n|---|---|---|---|---|---|\n",
                w.title, w.reference, w.reference_source, w.name, w.setting
            );
            for p in &w.points {
                s += &format!(
                    "| {} | {} | {:.6} | {:.2e} | {:.3} | {} |\n",
                    p.setting,
                    p.size.map_or("—".into(), |n| n.to_string()),
                    p.answer,
                    p.rel_error,
                    p.cost.wall_s,
                    fmt_opt(p.cost.cpu_s, 2)
                );
            }
            for f in &w.failures {
                s += &format!("\nFailed: {f}\n");
            }
        }
        s
    }
}

/// What `turf bench` runs.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// skip the FE pull-offs at μ = 2, the turf chain and the finest sweep points
    pub quick: bool,
    /// folder of the turf chain's own runs (`<out>/quickstart`, `<out>/turf_sphere…`)
    pub out: PathBuf,
    /// also run the turf indentation rung ([`turf_indent::TURF_SPHERE`]: ≈ 50 min cold; its
    /// discrete stages are cached under `out`, so a re-run takes seconds)
    pub turf_indent: bool,
}

/// One task of the bench: its name (for progress) and what it adds to the report.
type Task<'a> = (&'static str, Box<dyn Fn(&mut BenchReport) + 'a>);

/// The tasks of the bench, in order.
fn tasks(opts: &BenchOptions) -> Vec<Task<'_>> {
    let q = opts.quick;
    let mut t: Vec<Task<'_>> = vec![
        (
            "pull-off μ = 0.5",
            Box::new(|r| r.rows.extend(ladder::pull_off_rows(0.5, true))),
        ),
        (
            "pull-off μ = 2",
            Box::new(move |r| r.rows.extend(ladder::pull_off_rows(2.0, !q))),
        ),
        ("Hertz", Box::new(|r| r.rows.extend(ladder::hertz_rows()))),
        (
            "cantilever",
            Box::new(|r| r.rows.push(ladder::cantilever_row())),
        ),
    ];
    if !q {
        t.push((
            "turf chain",
            Box::new(|r| r.rows.extend(ladder::turf_rows(&opts.out))),
        ));
    }
    if opts.turf_indent {
        t.push((
            "turf indentation: tubes against the card",
            Box::new(|r| {
                r.rows.extend(turf_indent::turf_indent_rows(
                    &opts.out,
                    &turf_indent::TURF_SPHERE,
                ))
            }),
        ));
    }
    t.push((
        "sweep: half-space grid",
        Box::new(move |r| push_sweep(r, sweeps::halfspace_grid(q))),
    ));
    t.push((
        "sweep: FE mesh",
        Box::new(move |r| r.sweeps.push(sweeps::fe_hertz_mesh(q))),
    ));
    t.push((
        "sweep: FE time step",
        Box::new(move |r| push_sweep(r, sweeps::fe_time_step(q))),
    ));
    t.push((
        "sweep: rod segments",
        Box::new(move |r| r.sweeps.push(sweeps::rod_segments(q))),
    ));
    t
}

/// A sweep whose reference could not be computed is reported as a failed sweep.
fn push_sweep(r: &mut BenchReport, s: Result<Sweep, BenchError>) {
    match s {
        Ok(s) => r.sweeps.push(s),
        Err(e) => r.sweeps.push(Sweep {
            name: "failed".into(),
            title: "a sweep whose reference failed".into(),
            setting: String::new(),
            reference: 0.0,
            reference_source: String::new(),
            points: vec![],
            failures: vec![e.to_string()],
        }),
    }
}

/// The number of tasks `run` will report through `on_task`.
pub fn task_count(opts: &BenchOptions) -> usize {
    tasks(opts).len()
}

/// Run the ladder and the sweeps; `on_task` is told each task's name before it starts.
pub fn run(opts: &BenchOptions, on_task: &mut dyn FnMut(&str)) -> BenchReport {
    let mut report = BenchReport {
        turf_version: env!("CARGO_PKG_VERSION"),
        threads: rayon::current_num_threads(),
        quick: opts.quick,
        rows: Vec::new(),
        sweeps: Vec::new(),
    };
    for (name, task) in tasks(opts) {
        on_task(name);
        task(&mut report);
    }
    report
}

/// Write `bench.json`, `bench.md` and `plots/ladder.svg|png`, `plots/sweep_<name>.svg|png`
/// (error against wall time, log–log) into `dir`.
pub fn write(report: &BenchReport, dir: &Path) -> Result<(), ReportError> {
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|cause| ReportError::Io {
        path: plots.display().to_string(),
        cause,
    })?;
    write_atomic(&dir.join("bench.md"), report.to_markdown().as_bytes())?;
    write_json(&dir.join("bench.json"), report)?;
    let mut ladder = Plot::new(
        "turf bench: error against cost",
        "wall time (s)",
        "relative error",
    )
    .log_log();
    let mut fidelities: Vec<&str> = Vec::new();
    for r in &report.rows {
        if !fidelities.contains(&r.fidelity.as_str()) {
            fidelities.push(&r.fidelity);
        }
    }
    for f in fidelities {
        let (x, y): (Vec<f64>, Vec<f64>) = report
            .rows
            .iter()
            .filter(|r| r.fidelity == f)
            .filter_map(|r| Some((r.cost.wall_s, r.rel_error?)))
            .unzip();
        if !x.is_empty() {
            ladder = ladder.with(Series::points(f, x, y));
        }
    }
    ladder.write(&plots, "ladder")?;
    for s in report.sweeps.iter().filter(|s| !s.points.is_empty()) {
        let (x, y): (Vec<f64>, Vec<f64>) = s
            .points
            .iter()
            .map(|p| (p.cost.wall_s, p.rel_error))
            .unzip();
        Plot::new(&s.title, "wall time (s)", "relative error")
            .log_log()
            .with(Series::line(&s.setting, x, y))
            .write(&plots, &format!("sweep_{}", s.name))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timing_measures_cpu_of_a_busy_loop() {
        let (x, c) = timed(|| (0..20_000_000u64).fold(0u64, |a, i| a.wrapping_add(i * i)));
        assert!(x > 0 && c.wall_s > 0.0);
        // on Linux the CPU clock advances in 10 ms ticks; elsewhere it is absent
        if let Some(cpu) = c.cpu_s {
            assert!(
                (0.0..=c.wall_s * 2.0 + 0.02).contains(&cpu),
                "{cpu} vs {}",
                c.wall_s
            );
        }
    }

    #[test]
    fn a_failed_answer_has_no_error_and_says_why() {
        let cost = Cost {
            wall_s: 0.1,
            cpu_s: None,
        };
        let r = Row::new(
            "p",
            "f",
            Err(BenchError::NoPullOff),
            (2.0, "x"),
            cost,
            "".into(),
        );
        assert!(r.answer.is_none() && r.rel_error.is_none() && r.note.contains("no pull-off"));
        let r = Row::new("p", "f", Ok(f64::NAN), (2.0, "x"), cost, "".into());
        assert!(r.answer.is_none() && r.note.contains("non-finite"));
        let no_reference = Row::new("p", "f", Ok(1.0), (f64::NAN, "none"), cost, "".into());
        assert!(no_reference.reference.is_none() && no_reference.rel_error.is_none());
        let r = Row::new("p", "f", Ok(2.02), (2.0, "x"), cost, "".into());
        assert!((r.rel_error.unwrap() - 0.01).abs() < 1e-12);
        let report = BenchReport {
            turf_version: "0",
            threads: 1,
            quick: true,
            rows: vec![r, no_reference],
            sweeps: vec![],
        };
        let md = report.to_markdown();
        assert!(md.contains("| p | f | 2.020000 |") && !md.contains("NaN"));
        // absent numbers are left out of the JSON, which refuses nulls
        let dir = std::env::temp_dir().join(format!("turf-bench-{}", std::process::id()));
        write(&report, &dir).unwrap();
        let json = std::fs::read_to_string(dir.join("bench.json")).unwrap();
        assert!(!json.contains("null"));
        std::fs::remove_dir_all(dir).ok();
    }
}
