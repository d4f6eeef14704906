//! The ladder of `turf bench`: one question per block, answered by every fidelity that can.
//!
//! - LJ 9-3 pull-off of a sphere at μ = 0.5 and 2 (R/z₀ = 1000): Maugis–Dugdale (seed 3.10–3.13,
//!   λ = 1.16 μ), the half-space solver, the FE at small and at finite strain. Reference: the
//!   half-space pull-off extrapolated over its three grids (docs/validation-halfspace.md).
//! - Hertz (seed 3.1): a 1 µm sphere 10 nm into a linear block (E = 0.7 GPa, ν = 0.3), the FE at
//!   both kinematics against P = (4/3)E*R^½δ^(3/2).
//! - A 50-segment tube as a cantilever under a tip load PL²/K = 2 (Bisshopp–Drucker elastica).
//! - The turf (full ladder only): the quickstart scene's 9 tubes compressed discretely against
//!   the hyperfoam card homogenised from them, the card's error against the discrete curve and
//!   the speed-up, and the card's FE indentation cost.
//! - Turf indentation (`--turf-indent`): in [`super::turf_indent`].

use super::presets::tabor_sphere;
use super::sweeps::{cantilever_deflection, hertz_load, HERTZ_E_STAR};
use super::{timed, BenchError, Cost, Row};
use crate::continuum::element::Kinematics;
use crate::continuum::events::normalised_pull_off;
use crate::continuum::{run_indent, FeError, IndentParams, IndentResult};
use crate::halfspace::{pull_off, HalfspaceParams, Problem};
use crate::laws::LjKind;
use crate::pipeline::{self, RunOptions, RunReport, StageError, StageRecord};
use crate::scene::Stage;
use crate::theory::{tabor::lambda_per_mu, Control, Model};
use std::path::{Path, PathBuf};

/// Bisshopp–Drucker tip deflection δ_v/L at PL²/K = 2, to five decimals (Mattiasson, Int. J.
/// Numer. Meth. Eng. 17, 145, 1981; checked by shooting in tests/integration/discrete_rod_cantilever.rs).
const CANTILEVER_ALPHA_2: f64 = 0.49346;
/// R/z₀ of the pull-off problems (the Fig 4.6 problem of docs/validation-continuum.md).
const R_OVER_Z0: f64 = 1000.0;

/// FE run that keeps what a stopped run had.
fn indent(p: &IndentParams) -> Result<IndentResult, BenchError> {
    match run_indent(p, &mut |_| {}) {
        Ok(r) => Ok(r),
        Err(FeError::Stopped(r)) => Ok(*r),
        Err(e) => Err(e.into()),
    }
}

fn kin_name(k: Kinematics) -> &'static str {
    match k {
        Kinematics::Small => "FE small strain",
        Kinematics::Finite => "FE finite strain",
    }
}

/// Pull-off at Tabor μ by every fidelity; the FE only when `fe`.
pub fn pull_off_rows(mu: f64, fe: bool) -> Vec<Row> {
    let problem = format!("pull-off P/(πγR), LJ 9-3 sphere, μ = {mu}");
    let lambda = lambda_per_mu(LjKind::Lj93) * mu;
    let (md, c_md) = timed(|| Model::Maugis { lambda }.pull_off(Control::Load));
    let md = md.map_err(BenchError::from);
    let (hs, c_hs) = timed(|| {
        Problem::scaled(mu, LjKind::Lj93).and_then(|p| pull_off(&p, &HalfspaceParams::default()))
    });
    let (reference, source, hs_row) = match &hs {
        Ok(h) => (h.extrapolated, "half-space, extrapolated", Ok(h.normalized)),
        Err(e) => (
            md.as_ref().copied().unwrap_or(f64::NAN),
            "Maugis–Dugdale (the half-space failed)",
            Err(BenchError::from(e.clone())),
        ),
    };
    let hs_note = hs.as_ref().map_or(String::new(), |h| {
        format!(
            "finest of 3 grids; its own error estimate {:.1e}",
            h.error_estimate
        )
    });
    let mut rows = vec![
        Row::new(
            &problem,
            "theory (Maugis–Dugdale)",
            md,
            (reference, source),
            c_md,
            format!("λ = {lambda:.3}; the error is the Dugdale law's, not discretisation"),
        ),
        Row::new(
            &problem,
            "halfspace",
            hs_row,
            (reference, source),
            c_hs,
            hs_note,
        ),
    ];
    if fe {
        for kin in [Kinematics::Small, Kinematics::Finite] {
            let p = tabor_sphere(mu, R_OVER_Z0, LjKind::Lj93, kin);
            let (r, cost) = timed(|| indent(&p));
            let (answer, note) = match r {
                Ok(r) => {
                    let s = r.summary();
                    (
                        normalised_pull_off(&r).ok_or(BenchError::NoPullOff),
                        format!(
                            "R/z₀ = {R_OVER_Z0}, {} elements, damping {:.2} % of the strain energy{}",
                            r.mesh_report.elements,
                            100.0 * s.damping_dissipated_aJ / s.max_strain_energy_aJ,
                            if kin == Kinematics::Finite {
                                "; the error includes the physical finite-strain difference"
                            } else {
                                ""
                            }
                        ),
                    )
                }
                Err(e) => (Err(e), String::new()),
            };
            rows.push(Row::new(
                &problem,
                kin_name(kin),
                answer,
                (reference, source),
                cost,
                note,
            ));
        }
    }
    rows
}

/// Hertz load at δ = 10 nm by the FE at both kinematics on the default mesh.
pub fn hertz_rows() -> Vec<Row> {
    let (radius, depth, e_star) = (1000.0, 10.0, HERTZ_E_STAR);
    let reference = crate::theory::hertz::load_from_depth(depth, radius, e_star);
    let problem = "Hertz load (nN), R = 1 µm, δ = 10 nm, E = 0.7 GPa, ν = 0.3";
    let source = "Hertz (4/3)E*R^½δ^(3/2)";
    let per_radius = crate::continuum::indent::MeshParams::default().elements_per_radius;
    [Kinematics::Small, Kinematics::Finite]
        .into_iter()
        .map(|kin| {
            let (r, cost) = timed(|| hertz_load(kin, per_radius, 5, vec![], depth, 10.0));
            let note = match (&r, kin) {
                (Ok((_, elements)), Kinematics::Finite) => format!(
                    "{elements} elements; Hertz is small-strain: ≈ −0.3 a/R of the error is physical"
                ),
                (Ok((_, elements)), _) => format!("{elements} elements"),
                (Err(_), _) => String::new(),
            };
            Row::new(
                problem,
                kin_name(kin),
                r.map(|(p, _)| p),
                (reference, source),
                cost,
                note,
            )
        })
        .collect()
}

/// The large-deflection cantilever by the discrete engine (50 segments).
pub fn cantilever_row() -> Row {
    let (r, cost) = timed(|| cantilever_deflection(50));
    let note = r.as_ref().map_or(String::new(), |(_, it)| {
        format!("50 segments, {it} Newton iterations")
    });
    Row::new(
        "cantilever tip deflection δ_v/L at PL²/K = 2",
        "discrete (elastica chain)",
        r.map(|(d, _)| d),
        (CANTILEVER_ALPHA_2, "Bisshopp–Drucker elastica"),
        cost,
        note,
    )
}

/// The quickstart chain: discrete compression of 9 tubes, the card fitted to it, the card's FE
/// indentation. Rows: the discrete stress at the largest strain (the reference), the card's
/// stress there (its error and speed-up), the FE indentation of the card (its cost).
pub fn turf_rows(out: &Path) -> Vec<Row> {
    let problem = "turf compression: nominal stress at the largest strain (GPa)";
    match quickstart(out) {
        Ok(q) => {
            let reference = (q.discrete_stress, "discrete tubes (9 × 2 µm)");
            let speedup = q.discrete_cost.wall_s / q.card_cost.wall_s.max(1e-9);
            vec![
                Row::new(
                    problem,
                    "discrete (9 tubes, Newton)",
                    Ok(q.discrete_stress),
                    reference,
                    q.discrete_cost,
                    format!("ε = {:.3}; wall of the discrete stage", q.strain),
                ),
                Row::new(
                    problem,
                    "homogenised card (hyperfoam)",
                    Ok(q.card_stress),
                    reference,
                    q.card_cost,
                    format!(
                        "RMS over the loading curve {:.2e} of its largest stress; card evaluation \
                         {speedup:.1e}× faster than the tubes (fit: {:.2} s)",
                        q.card_rms, q.fit_s
                    ),
                ),
                Row::new(
                    "turf indentation: peak load of the quickstart test (nN)",
                    "FE on the card (finite strain, adhesion, Prony)",
                    Ok(q.fe_peak),
                    (f64::NAN, "none"),
                    q.fe_cost,
                    "adhesive and viscoelastic: no discrete counterpart (the tubes have neither); \
                     the card against a discrete sphere indentation is the --turf-indent rung"
                        .into(),
                ),
            ]
        }
        Err(e) => vec![failed_row(problem, "quickstart chain", e)],
    }
}

/// The one row of a chain that failed before it had an answer.
pub(super) fn failed_row(problem: &str, fidelity: &str, e: BenchError) -> Row {
    let cost = Cost {
        wall_s: 0.0,
        cpu_s: None,
    };
    Row::new(
        problem,
        fidelity,
        Err(e),
        (f64::NAN, "—"),
        cost,
        String::new(),
    )
}

struct Quickstart {
    strain: f64,
    discrete_stress: f64,
    discrete_cost: Cost,
    card_stress: f64,
    card_rms: f64,
    card_cost: Cost,
    fit_s: f64,
    fe_peak: f64,
    fe_cost: Cost,
}

/// A scene run through the whole pipeline into `dir`, with its cost; a stage failure is an
/// error, except with `keep_stopped_fe` a continuum stage that stopped (its
/// `continuum/load_depth.csv` holds the increments it reached). `fresh`: empty `dir` first, so
/// no stage is reused from its cache.
pub(super) struct ChainRun {
    pub(super) dir: PathBuf,
    pub(super) loaded: crate::scene::Loaded,
    pub(super) report: RunReport,
    pub(super) total: Cost,
}

impl ChainRun {
    pub(super) fn new(
        text: &str,
        file: &str,
        dir: PathBuf,
        fresh: bool,
        keep_stopped_fe: bool,
    ) -> Result<Self, BenchError> {
        if fresh && dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(|error| BenchError::Io {
                path: dir.clone(),
                error,
            })?;
        }
        let loaded = crate::scene::load_str(text, Path::new(file), &[])?;
        let opts = RunOptions {
            out: Some(dir.clone()),
            progress: false,
            resume: false,
        };
        let (report, total) = timed(|| pipeline::run(&loaded, &opts));
        let report = report?;
        match &report.failure {
            // an FE that stopped keeps its rows so far: the caller reads what it reached
            Some(StageError::Failed {
                stage: Stage::Continuum,
                ..
            }) if keep_stopped_fe => {}
            Some(f) => {
                return Err(BenchError::Chain {
                    file: file.to_string(),
                    failure: f.to_string(),
                })
            }
            None => {}
        }
        Ok(ChainRun {
            dir,
            loaded,
            report,
            total,
        })
    }

    pub(super) fn stage(&self, s: Stage) -> Result<&StageRecord, BenchError> {
        self.report
            .summary
            .stages
            .iter()
            .find(|r| r.stage == s)
            .ok_or_else(|| BenchError::NoStage {
                stage: s,
                dir: self.dir.clone(),
            })
    }

    pub(super) fn value(&self, s: Stage, name: &str) -> Result<f64, BenchError> {
        self.stage(s)?
            .values
            .get(name)
            .copied()
            .ok_or_else(|| BenchError::NoValue {
                stage: s,
                name: name.to_string(),
            })
    }

    /// The cost of stage `s`: the stage records carry wall time only, so the CPU of the whole
    /// run is split by wall share. A stage reused from the cache costs what it cost when it was
    /// computed: the sum of its own `wall_time_*` values, CPU unknown.
    pub(super) fn cost(&self, s: Stage) -> Result<Cost, BenchError> {
        let r = self.stage(s)?;
        if r.cached {
            let wall = r
                .values
                .iter()
                .filter(|(k, _)| k.starts_with("wall_time_"))
                .map(|(_, v)| v)
                .sum();
            return Ok(Cost {
                wall_s: wall,
                cpu_s: None,
            });
        }
        Ok(Cost {
            wall_s: r.wall_time_s,
            cpu_s: self
                .total
                .cpu_s
                .map(|c| c * r.wall_time_s / self.total.wall_s.max(1e-9)),
        })
    }

    /// Whether stage `s` was reused from the cache.
    pub(super) fn cached(&self, s: Stage) -> bool {
        self.stage(s).is_ok_and(|r| r.cached)
    }
}

fn quickstart(out: &Path) -> Result<Quickstart, BenchError> {
    use crate::homogenize::hyperfoam::Mode;
    let run = ChainRun::new(
        include_str!("../../scenes/quickstart.toml"),
        "scenes/quickstart.toml",
        out.join("quickstart"),
        true,
        false,
    )?;
    let dir = &run.dir;
    let discrete_cost = run.cost(Stage::Discrete)?;
    let fit_s = run.stage(Stage::Homogenize)?.wall_time_s;
    let fe_cost = run.cost(Stage::Continuum)?;
    let fe_peak = run.value(Stage::Continuum, "max_load_nN")?;
    let curve = crate::homogenize::read_curve(&dir.join(pipeline::LOADING_CSV))?;
    let card = crate::homogenize::read_card(&dir.join("material.json"))?;
    let (card_stress, card_cost) = timed(|| {
        curve
            .strain
            .iter()
            .map(|&e| {
                card.hyperfoam
                    .drive(Mode::Uniaxial, 1.0 - e)
                    .map(|s| -s.nominal[0])
            })
            .collect::<Result<Vec<f64>, _>>()
    });
    let card_stress = card_stress?;
    let n = curve.stress.len();
    let last = *curve.stress.last().ok_or(BenchError::EmptyCurve)?;
    let scale = curve.stress.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    let rms = (curve
        .stress
        .iter()
        .zip(&card_stress)
        .map(|(d, c)| (d - c).powi(2))
        .sum::<f64>()
        / n as f64)
        .sqrt()
        / scale.max(f64::MIN_POSITIVE);
    Ok(Quickstart {
        strain: *curve.strain.last().unwrap_or(&0.0),
        discrete_stress: last,
        discrete_cost,
        card_stress: card_stress[n - 1],
        card_rms: rms,
        card_cost,
        fit_s,
        fe_peak,
        fe_cost,
    })
}
