//! The turf indentation rung of `turf bench --turf-indent` ([`TURF_SPHERE`]): a rigid sphere
//! pressed into a 1 µm turf of ≈ 100 tubes, discretely on several turfs of the same statistics
//! (the reference: their mean, its 95 % interval the realisation scatter) and by the FE on the
//! hyperfoam card homogenised from the flat-platen compression of one of them (seed 5.3; finite
//! strain, no adhesion) — with the sphere's tips free to slide (frictionless) and held where
//! they touch (`compression.sphere_tangential` / `indenter.tangential = "stick"`), the same
//! contact in both fidelities: the loads at fixed depths, the card's error and the costs. With
//! held tips the FE also runs on the transversely isotropic card of the same turf (its lateral
//! and shear RVE tests, docs/homogenize.md).

use super::ladder::{failed_row, ChainRun};
use super::{BenchError, Cost, Row};
use crate::numerics::interpolate;
use crate::numerics::statistics::Estimate;
use crate::scene::Stage;
use std::path::Path;

/// The turf indentation rung: a scene of the full chain (flat-platen compression of a turf →
/// hyperfoam card → sphere on the card, no adhesion, rigid displacement control) whose
/// `[scene]`, `[turf]` and `[compression]` are also run with the sphere of its `[indenter]`
/// pressed on the tubes themselves, to the schedule's deepest depth, on each turf of `seeds`.
#[derive(Debug, Clone)]
pub struct TurfIndentSpec<'a> {
    /// the chain scene's text (e.g. `scenes/turf_sphere.toml`)
    pub scene: &'a str,
    /// its name, for messages and the output folders
    pub name: &'a str,
    /// depths (nm) at which the loads are compared, within the FE's schedule
    pub depths: &'a [f64],
    /// steps of the discrete sphere's drive
    pub sphere_steps: usize,
    /// the seeds of the discrete turfs (same statistics) indented by the sphere: their mean
    /// load is the reference, its 95 % interval the realisation scatter the card's error is
    /// judged against (the card comes from the scene's own seed)
    pub seeds: &'a [u64],
    /// the adhesive sphere, in both fidelities, beside the frictionless and held ones (`None`:
    /// not run)
    pub adhesive: Option<Adhesive<'a>>,
}

/// The adhesive sphere of the rung: tips held, the `[adhesion]` law between the sphere and the
/// tubes (discrete, `compression.sphere_adhesion`, shifted when the table shifts) and the card's
/// surface (FE), loaded to the deepest depth, unloaded and retracted `retract` nm above the
/// first touch in both: the loads at the rung's depths and the pull-off.
#[derive(Debug, Clone)]
pub struct Adhesive<'a> {
    /// the `[adhesion]` table's keys (TOML), damping included for the FE's jump-in
    pub table: &'a str,
    /// how far the sphere is raised above its first touch after unloading, nm
    pub retract: f64,
    /// steps of the discrete retract
    pub retract_steps: usize,
    /// where the FE's approach starts, nm above the surface (clear of the law's range)
    pub approach_from: f64,
}

/// The rung of `turf bench --turf-indent`: `scenes/turf_sphere.toml`, loads at 40, 70 and
/// 100 nm, four turfs.
pub const TURF_SPHERE: TurfIndentSpec<'static> = TurfIndentSpec {
    scene: include_str!("../../scenes/turf_sphere.toml"),
    name: "turf_sphere",
    depths: &[40.0, 70.0, 100.0],
    sphere_steps: 11,
    seeds: &[3, 4, 5, 6],
    adhesive: Some(Adhesive {
        table: TURF_SPHERE_ADHESION,
        retract: 20.0,
        retract_steps: 40,
        approach_from: 5.0,
    }),
};

/// The adhesive rung's law: the seed's LJ 10-4 (z₀ = 0.34 nm) shifted for the tips' thermal
/// vibration (u from the 2 µm tubes at 300 K), at γ = 20 mJ/m² — the seed's 0.46 J/m² would
/// put the card's contact at a Tabor parameter near 10, beyond the FE's fixed mesh (its process
/// zone is then sub-nanometre: docs/benchmarks.md "Turf indentation rung"); the damping carries
/// the FE through the jump-in (seed eq. 4.4).
const TURF_SPHERE_ADHESION: &str = r#"
law = "lj104"
gamma = "20 mJ/m^2"
z0 = "0.34 nm"
thermal_shift = true
temperature = "300 K"
[damping]
c0 = 1e-6
gap = "3 nm"
"#;

/// What the sphere does with what it touches, in both fidelities.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tip {
    /// slides freely
    Frictionless,
    /// held where it first touched
    Held,
    /// held, and adhering through the [`Adhesive`] law
    Adhesive,
}

impl Tip {
    /// Adhesive and held first: the frictionless FE run, the scene as written, is the chain
    /// folder's last.
    const ALL: [Tip; 3] = [Tip::Adhesive, Tip::Held, Tip::Frictionless];

    /// The value of `compression.sphere_tangential` and `indenter.tangential`.
    fn key(self) -> &'static str {
        match self {
            Tip::Frictionless => "frictionless",
            Tip::Held | Tip::Adhesive => "stick",
        }
    }

    fn name(self) -> &'static str {
        match self {
            Tip::Frictionless => "frictionless",
            Tip::Held => "held",
            Tip::Adhesive => "adhesive held",
        }
    }

    /// The word in the discrete runs' folder names.
    fn folder(self) -> &'static str {
        match self {
            Tip::Adhesive => "adhesive",
            t => t.name(),
        }
    }

    /// The tip conditions `spec` runs.
    fn of(spec: &TurfIndentSpec) -> Vec<Tip> {
        Tip::ALL
            .into_iter()
            .filter(|&t| t != Tip::Adhesive || spec.adhesive.is_some())
            .collect()
    }
}

/// The `(depth_nm, load_nN)` columns of a `load_depth.csv` written by the discrete or the
/// continuum stage (loading part only: up to the deepest point).
fn read_load_depth(path: &Path) -> Result<(Vec<f64>, Vec<f64>), BenchError> {
    let text = std::fs::read_to_string(path).map_err(|error| BenchError::Io {
        path: path.to_path_buf(),
        error,
    })?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| BenchError::NoColumn {
                path: path.to_path_buf(),
                column: name.to_string(),
            })
    };
    let (d, p) = (col("depth_nm")?, col("load_nN")?);
    let (mut depth, mut load) = (Vec::new(), Vec::new());
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        let num = |c: usize| {
            cells
                .get(c)
                .and_then(|v| v.parse::<f64>().ok())
                .ok_or_else(|| BenchError::NotANumber {
                    path: path.to_path_buf(),
                    line: i + 2,
                })
        };
        let (x, y) = (num(d)?, num(p)?);
        if depth.last().is_some_and(|&last| x < last) {
            break;
        }
        depth.push(x);
        load.push(y);
    }
    Ok((depth, load))
}

/// The scene `spec.scene` parsed, for the derived scenes.
fn parse(spec: &TurfIndentSpec) -> Result<toml::Table, BenchError> {
    spec.scene
        .parse()
        .map_err(|e: toml::de::Error| BenchError::Toml {
            scene: spec.name.to_string(),
            message: e.message().to_string(),
        })
}

fn missing(spec: &TurfIndentSpec, what: &'static str) -> BenchError {
    BenchError::Missing {
        scene: spec.name.to_string(),
        what,
    }
}

/// The chain scene with the FE indenter's tangential contact `tip`; with a card file `card`,
/// its FE alone on that card (no `[turf]`, `[compression]` or `[homogenize]`).
fn chain_scene(spec: &TurfIndentSpec, tip: Tip, card: Option<&Path>) -> Result<String, BenchError> {
    use toml::Value;
    let mut doc = parse(spec)?;
    let Some(Value::Table(i)) = doc.get_mut("indenter") else {
        return Err(missing(spec, "[indenter]"));
    };
    i.insert("tangential".into(), Value::String(tip.key().into()));
    if let (Tip::Adhesive, Some(a)) = (tip, &spec.adhesive) {
        adhesive_schedule(spec, a, &mut doc)?;
    }
    if let Some(path) = card {
        let Some(Value::Table(m)) = doc.get_mut("material") else {
            return Err(missing(spec, "[material]"));
        };
        m.insert("card".into(), Value::String(path.display().to_string()));
        doc.retain(|k, _| !matches!(k, "turf" | "compression" | "homogenize"));
    }
    Ok(toml::to_string(&doc)?)
}

/// The `[adhesion]` table of `a`.
fn adhesion_table(spec: &TurfIndentSpec, a: &Adhesive) -> Result<toml::Table, BenchError> {
    a.table
        .parse()
        .map_err(|e: toml::de::Error| BenchError::Toml {
            scene: format!("{} [adhesion]", spec.name),
            message: e.message().to_string(),
        })
}

/// The chain scene `doc` made adhesive for the FE: the `[adhesion]` of `a`, the schedule's
/// deepest depth reached from `a.approach_from` nm above the surface and unloaded to `a.retract`
/// nm above it (approach, load, unload at the first segment's rate), on a fixed mesh (the held
/// surface needs one).
fn adhesive_schedule(
    spec: &TurfIndentSpec,
    a: &Adhesive,
    doc: &mut toml::Table,
) -> Result<(), BenchError> {
    use toml::Value;
    let Some(Value::Table(schedule)) = doc.get("schedule") else {
        return Err(missing(spec, "[schedule]"));
    };
    let segments = schedule.get("segment").and_then(Value::as_array);
    let first = segments.and_then(|s| s.first()).and_then(Value::as_table);
    let rate = first
        .and_then(|f| f.get("rate"))
        .cloned()
        .ok_or_else(|| missing(spec, "schedule.segment.rate"))?;
    let deepest = segments
        .and_then(|s| s.last())
        .and_then(|f| f.get("to"))
        .cloned()
        .ok_or_else(|| missing(spec, "schedule.segment.to"))?;
    let segment = |kind: &str, to: Value| {
        let mut t = toml::Table::new();
        t.insert("kind".into(), Value::String(kind.into()));
        t.insert("to".into(), to);
        t.insert("rate".into(), rate.clone());
        Value::Table(t)
    };
    let nm = |v: f64| Value::String(format!("{v} nm"));
    let mut schedule = toml::Table::new();
    schedule.insert("start".into(), nm(-a.approach_from));
    schedule.insert(
        "segment".into(),
        Value::Array(vec![
            segment("approach", nm(0.0)),
            segment("load", deepest),
            segment("unload", nm(-a.retract)),
        ]),
    );
    doc.insert("schedule".into(), Value::Table(schedule));
    doc.insert("adhesion".into(), Value::Table(adhesion_table(spec, a)?));
    if let Some(Value::Table(m)) = doc.get_mut("mesh") {
        m.insert("adaptive".into(), Value::Boolean(false));
    }
    Ok(())
}

/// The transversely isotropic card of the scene's turf (docs/homogenize.md): its lateral and
/// longitudinal-shear RVE tests (30 steps to 30 %, `<name>_lateral`, `<name>_shear`) and the
/// flat compression's loading curve in `chain`, one matrix and one fibre term fitted up to the
/// compression's strain; the card written to `<name>_transverse/`. Returns its path and the
/// cost of the two RVE tests.
fn transverse_card(
    spec: &TurfIndentSpec,
    out: &Path,
    chain: &ChainRun,
) -> Result<(std::path::PathBuf, Cost), BenchError> {
    use crate::homogenize::transverse_foam::{fit_transverse, TransverseFitParams, CARD_JSON};
    use toml::Value;
    let mut curves = Vec::new();
    let mut cost = Cost {
        wall_s: 0.0,
        cpu_s: Some(0.0),
    };
    for mode in ["lateral", "shear"] {
        let mut doc = parse(spec)?;
        doc.retain(|k, _| matches!(k, "scene" | "turf" | "compression"));
        let mut k = toml::Table::new();
        k.insert("mode".into(), Value::String(mode.into()));
        k.insert("to".into(), Value::Float(0.3));
        k.insert("steps".into(), Value::Integer(30));
        k.insert("unload".into(), Value::Boolean(false));
        k.insert("solver".into(), Value::String("newton".into()));
        doc.insert("compression".into(), Value::Table(k));
        let mut o = toml::Table::new();
        o.insert("plots".into(), Value::Boolean(false));
        doc.insert("output".into(), Value::Table(o));
        let run = ChainRun::new(
            &toml::to_string(&doc)?,
            &format!("{} ({mode} RVE test)", spec.name),
            out.join(format!("{}_{mode}", spec.name)),
            false,
            false,
        )?;
        let c = run.cost(Stage::Discrete)?;
        cost.wall_s += c.wall_s;
        cost.cpu_s = cost.cpu_s.zip(c.cpu_s).map(|(a, b)| a + b);
        let file = run.dir.join(format!("discrete_rve_{mode}_loading.csv"));
        curves.push(crate::homogenize::read_curve(&file)?);
    }
    let axial = crate::homogenize::read_curve(&chain.dir.join("stress_strain_loading.csv"))?;
    let strain_max = axial.strain.iter().copied().fold(0.0, f64::max);
    let fit = fit_transverse(
        &axial,
        &curves[0],
        &curves[1],
        &TransverseFitParams {
            matrix_terms: 1,
            fibre_terms: 1,
            strain_max,
        },
    )?;
    let dir = out.join(format!("{}_transverse", spec.name));
    std::fs::create_dir_all(&dir).map_err(|error| BenchError::Io {
        path: dir.clone(),
        error,
    })?;
    let file = dir.join(CARD_JSON);
    let sources = [
        "stress_strain_loading.csv",
        "discrete_rve_lateral_loading.csv",
        "discrete_rve_shear_loading.csv",
    ]
    .map(String::from);
    crate::report::write_json(&file, &fit.card_json(&sources))?;
    Ok((file, cost))
}

/// The discrete sphere scene derived from the chain scene: its `[scene]` (with `seed`),
/// `[turf]` and `[compression]`, the sphere of `[indenter]` with tips `tip` driven to `depth`
/// below the relaxed height `height` in `steps` steps.
fn sphere_scene(
    spec: &TurfIndentSpec,
    seed: u64,
    tip: Tip,
    depth: f64,
    height: f64,
) -> Result<String, BenchError> {
    use toml::Value;
    let mut doc = parse(spec)?;
    let radius = doc
        .get("indenter")
        .and_then(|i| i.get("radius"))
        .cloned()
        .ok_or_else(|| missing(spec, "indenter.radius"))?;
    doc.retain(|k, _| matches!(k, "scene" | "turf" | "compression"));
    let Some(Value::Table(k)) = doc.get_mut("compression") else {
        return Err(missing(spec, "[compression]"));
    };
    k.insert("indenter".into(), Value::String("sphere".into()));
    k.insert("sphere_radius".into(), radius);
    k.insert("sphere_tangential".into(), Value::String(tip.key().into()));
    k.insert("to".into(), Value::Float(depth / height));
    k.insert("steps".into(), Value::Integer(spec.sphere_steps as i64));
    let adhesive = spec.adhesive.as_ref().filter(|_| tip == Tip::Adhesive);
    k.insert("unload".into(), Value::Boolean(adhesive.is_some()));
    if let Some(a) = adhesive {
        let law = adhesion_table(spec, a)?;
        let shifted = law
            .get("thermal_shift")
            .is_some_and(|v| v.as_bool() != Some(false));
        let kind = if shifted { "lj_shifted" } else { "lj" };
        k.insert("sphere_adhesion".into(), Value::String(kind.into()));
        k.insert("retract".into(), Value::String(format!("{} nm", a.retract)));
        k.insert(
            "retract_steps".into(),
            Value::Integer(a.retract_steps as i64),
        );
        // the law alone: the damping is the FE's
        let mut law = law;
        law.remove("damping");
        doc.insert("adhesion".into(), Value::Table(law));
    }
    let Some(Value::Table(s)) = doc.get_mut("scene") else {
        return Err(missing(spec, "[scene]"));
    };
    s.insert("seed".into(), Value::Integer(seed as i64));
    Ok(toml::to_string(&doc)?)
}

/// Said of a cost taken from the stage cache.
const CACHED: &str = " (reused from the stage cache: the wall recorded when it was computed)";

/// A discrete sphere indentation of one turf.
struct SphereRun {
    seed: u64,
    curve: (Vec<f64>, Vec<f64>),
    cost: Cost,
    tubes: f64,
    cached: bool,
    /// the adhesive sphere's pull-off (nN, negative; 0 if it never pulled) and its depth below
    /// the first touch (nm; none if it never pulled)
    pull_off: Option<(f64, Option<f64>)>,
}

/// The FE on the card: its curve, cost and mesh (or why it stopped).
struct FeRun {
    curve: (Vec<f64>, Vec<f64>),
    cost: Cost,
    note: String,
    /// the adhesive sphere's pull-off (nN, negative)
    pull_off: Option<f64>,
}

impl FeRun {
    /// The continuum stage of `chain`, which may have stopped part way.
    fn of(chain: &ChainRun) -> Result<FeRun, BenchError> {
        let curve = read_load_depth(&chain.dir.join("continuum/load_depth.csv"))?;
        let (cost, note) = match &chain.report.failure {
            None => (
                chain.cost(Stage::Continuum)?,
                format!("{:.0} elements", chain.value(Stage::Continuum, "elements")?),
            ),
            // a stopped stage has no record: its wall is what the recorded stages leave
            Some(f) => (
                Cost {
                    wall_s: (chain.total.wall_s
                        - chain
                            .report
                            .summary
                            .stages
                            .iter()
                            .map(|r| r.wall_time_s)
                            .sum::<f64>())
                    .max(0.0),
                    cpu_s: None,
                },
                format!("the FE stopped ({f})"),
            ),
        };
        Ok(FeRun {
            curve,
            cost,
            note,
            pull_off: chain.value(Stage::Continuum, "pull_off_nN").ok(),
        })
    }
}

/// The held FE on the transversely isotropic card of the turf of `chain` ([`transverse_card`]),
/// alone in `<name>_transverse/`, and the cost of the card's RVE tests.
fn transverse_fe(
    spec: &TurfIndentSpec,
    out: &Path,
    chain: &ChainRun,
) -> Result<(FeRun, Cost), BenchError> {
    let (card, making) = transverse_card(spec, out, chain)?;
    let run = ChainRun::new(
        &chain_scene(spec, Tip::Held, Some(&card))?,
        &format!("{} (transversely isotropic card)", spec.name),
        out.join(format!("{}_transverse", spec.name)),
        false,
        true,
    )?;
    Ok((FeRun::of(&run)?, making))
}

/// One tip condition: the discrete sphere on every turf and the FE on the card (and, held, on
/// the transversely isotropic card).
struct TipRuns {
    tip: Tip,
    spheres: Vec<SphereRun>,
    fe: FeRun,
    fe_transverse: Option<Result<FeRun, BenchError>>,
}

/// Everything the rung measured.
struct TurfIndent {
    radius: f64,
    box_nm: f64,
    height: f64,
    /// the flat-platen compression and the fit that make the card
    card_making: Cost,
    fit_rms: f64,
    card_cached: bool,
    /// the seed of the turf the card comes from
    card_seed: u64,
    /// steps of the discrete sphere's drive
    steps: usize,
    /// its deepest depth, nm
    deepest: f64,
    /// the lateral and shear RVE tests that, with the flat compression, make the transversely
    /// isotropic card
    transverse_making: Cost,
    tips: Vec<TipRuns>,
}

fn turf_indent(out: &Path, spec: &TurfIndentSpec) -> Result<TurfIndent, BenchError> {
    let dir = out.join(spec.name);
    let mut chains = Vec::new();
    for tip in Tip::of(spec) {
        let chain = ChainRun::new(
            &chain_scene(spec, tip, None)?,
            spec.name,
            dir.clone(),
            false,
            true,
        )?;
        let fe = FeRun::of(&chain)?;
        chains.push((tip, fe, chain));
    }
    // the last chain run: its discrete and homogenize stages (the card) are those of all
    let chain = &chains.last().ok_or_else(|| missing(spec, "[indenter]"))?.2;
    let deepest = chain
        .loaded
        .base
        .derived
        .schedule
        .as_ref()
        .map(|t| t.max_depth_nm)
        .ok_or_else(|| missing(spec, "[schedule]"))?;
    let height = chain.value(Stage::Discrete, "turf_height_nm")?;
    let scene = &chain.loaded.base.scene;
    let (flat, fit) = (chain.cost(Stage::Discrete)?, chain.cost(Stage::Homogenize)?);
    let radius = scene.indenter.as_ref().map(|i| i.radius.0);
    let mut t = TurfIndent {
        radius: radius.ok_or_else(|| missing(spec, "[indenter]"))?,
        box_nm: scene.turf.as_ref().map_or(f64::NAN, |t| t.box_size[0].0),
        height,
        card_making: Cost {
            wall_s: flat.wall_s + fit.wall_s,
            cpu_s: flat.cpu_s.zip(fit.cpu_s).map(|(a, b)| a + b),
        },
        fit_rms: chain.value(Stage::Homogenize, "fit_rms_rel")?,
        card_cached: chain.cached(Stage::Discrete),
        card_seed: scene.scene.seed,
        steps: spec.sphere_steps,
        deepest,
        transverse_making: Cost {
            wall_s: 0.0,
            cpu_s: None,
        },
        tips: Vec::new(),
    };
    let mut fe_transverse = Some(transverse_fe(spec, out, chain).map(|(fe, making)| {
        t.transverse_making = making;
        fe
    }));
    for (tip, fe, _) in chains {
        let mut spheres = Vec::new();
        for &s in spec.seeds {
            let text = sphere_scene(spec, s, tip, deepest, height)?;
            let run = ChainRun::new(
                &text,
                &format!(
                    "{} (discrete sphere, {} tips, seed {s})",
                    spec.name,
                    tip.name()
                ),
                out.join(format!("{}_sphere_{}_seed{s}", spec.name, tip.folder())),
                false,
                false,
            )?;
            spheres.push(SphereRun {
                seed: s,
                curve: read_load_depth(&run.dir.join("load_depth.csv"))?,
                cost: run.cost(Stage::Discrete)?,
                tubes: run.value(Stage::Discrete, "tubes")?,
                cached: run.cached(Stage::Discrete),
                pull_off: run.value(Stage::Discrete, "pull_off_nN").ok().map(|f| {
                    let depth = run.value(Stage::Discrete, "pull_off_depth_nm");
                    (f, depth.ok())
                }),
            });
        }
        let fe_transverse = match tip {
            Tip::Held => fe_transverse.take(),
            _ => None,
        };
        t.tips.push(TipRuns {
            tip,
            spheres,
            fe,
            fe_transverse,
        });
    }
    Ok(t)
}

/// The rung's rows: at each depth of `spec` and for each tip condition, the discrete load on
/// the sphere (the mean over the turfs, the reference) and the FE load on the card (its error
/// against that mean; where it falls against the turfs' 95 % interval and the speed-ups in the
/// note); with the adhesive sphere, then its pull-off in both fidelities.
pub fn turf_indent_rows(out: &Path, spec: &TurfIndentSpec) -> Vec<Row> {
    let t = match turf_indent(out, spec) {
        Ok(t) => t,
        Err(e) => {
            let problem = "turf indentation by a sphere: discrete tubes against the card";
            return vec![failed_row(problem, spec.name, e)];
        }
    };
    let mut rows = Vec::new();
    for &d in spec.depths {
        let problem = format!(
            "turf indentation by a {:.0} nm sphere: load at δ = {d:.0} nm (nN)",
            t.radius
        );
        for tips in &t.tips {
            rows.extend(tip_rows(&t, tips, &problem, d));
        }
    }
    let adhesive = t.tips.iter().find(|r| r.tip == Tip::Adhesive);
    if let (Some(tips), Some(a)) = (adhesive, &spec.adhesive) {
        rows.extend(pull_off_rows(&t, tips, a));
    }
    rows
}

/// `y` at depth `d` on the curve `c`.
fn at(c: &(Vec<f64>, Vec<f64>), d: f64) -> Result<f64, BenchError> {
    interpolate(&c.0, &c.1, d).ok_or_else(|| BenchError::BeyondCurve {
        depth: d,
        end: *c.0.last().unwrap_or(&0.0),
    })
}

/// The discrete row of one tip condition: `values`, one per turf, their mean the reference
/// (with its 95 % interval), `what` the measurement's own note; and what an FE row is judged
/// against.
fn discrete_row<'a>(
    t: &TurfIndent,
    tips: &TipRuns,
    problem: &str,
    values: Result<Vec<f64>, BenchError>,
    what: &str,
    fidelity: &'a str,
) -> (Row, Reference<'a>) {
    let estimate = values.as_ref().ok().and_then(|l| Estimate::of(l));
    let n = tips.spheres.len();
    let sum = |f: &dyn Fn(&SphereRun) -> Option<f64>| -> Option<f64> {
        tips.spheres.iter().map(f).sum::<Option<f64>>()
    };
    let cost = Cost {
        wall_s: sum(&|s| Some(s.cost.wall_s)).unwrap_or(f64::NAN),
        cpu_s: sum(&|s| s.cost.cpu_s),
    };
    let per_turf = |l: &[f64]| {
        tips.spheres
            .iter()
            .zip(l)
            .map(|(s, v)| format!("seed {} {v:.1}", s.seed))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let interval = |e: &Estimate| match e.ci95 {
        Some((lo, hi)) => format!(
            "95 % interval of the mean [{lo:.1}, {hi:.1}] (±{:.0} %)",
            100.0 * 0.5 * (hi - lo) / e.mean.abs().max(f64::MIN_POSITIVE)
        ),
        None => "one turf: no interval".into(),
    };
    let first = tips.spheres.first();
    let cached = tips.spheres.iter().any(|s| s.cached);
    let note = format!(
        "{}; {}; {:.0} tubes in a {:.0} nm box, height {:.0} nm; {what}; {} steps; the cost is \
         the {n} whole curves'{}",
        values.as_deref().map_or(String::new(), per_turf),
        estimate.as_ref().map_or(String::new(), interval),
        first.map_or(f64::NAN, |s| s.tubes),
        t.box_nm,
        t.height,
        t.steps,
        if cached { CACHED } else { "" }
    );
    let mean = estimate.as_ref().map_or(f64::NAN, |e| e.mean);
    let row = Row::new(
        problem,
        fidelity,
        values.map(|_| mean),
        (f64::NAN, "the reference"),
        cost,
        note,
    );
    let reference = Reference {
        mean,
        interval: estimate.as_ref().and_then(|e| e.ci95),
        source: fidelity,
        turf_wall_s: cost.wall_s / n.max(1) as f64,
    };
    (row, reference)
}

/// The rows of one tip condition at depth `d`: the turfs' mean and the FE on the card (and, held,
/// on the transversely isotropic card).
fn tip_rows(t: &TurfIndent, tips: &TipRuns, problem: &str, d: f64) -> Vec<Row> {
    let name = tips.tip.name();
    let n = tips.spheres.len();
    let loads: Result<Vec<f64>, BenchError> =
        tips.spheres.iter().map(|s| at(&s.curve, d)).collect();
    let fidelity = format!("discrete sphere, {name} tips (mean of {n} turfs)");
    let what = format!("√(2Rδ) = {:.0} nm", (2.0 * t.radius * d).sqrt());
    let (discrete, reference) = discrete_row(t, tips, problem, loads, &what, &fidelity);
    let fe = FeRow {
        label: format!("FE on the card, {name}"),
        answer: at(&tips.fe.curve, d),
        making: None,
    };
    let mut rows = vec![discrete, fe.row(t, tips, &reference, problem)];
    if let Some(fe) = &tips.fe_transverse {
        let label = format!("FE on the transversely isotropic card, {name}");
        let fe = match fe {
            Ok(fe) => fe,
            Err(e) => {
                let failed = BenchError::Chain {
                    file: label.clone(),
                    failure: e.to_string(),
                };
                rows.push(Row::new(
                    problem,
                    &label,
                    Err(failed),
                    (reference.mean, reference.source),
                    Cost {
                        wall_s: 0.0,
                        cpu_s: None,
                    },
                    String::new(),
                ));
                return rows;
            }
        };
        let making = format!(
            "the transversely isotropic card of the same turf (its flat compression and its \
             lateral and shear RVE tests, {:.1} s{})",
            t.transverse_making.wall_s,
            if t.card_cached { CACHED } else { "" }
        );
        let row = FeRow {
            label,
            answer: at(&fe.curve, d),
            making: Some(making),
        };
        rows.push(row.row_of(t, fe, &reference, problem, "finite strain, no adhesion"));
    }
    rows
}

/// The adhesive sphere's pull-off: the turfs' mean (where each turf let go in the note) and the
/// FE's on the card.
fn pull_off_rows(t: &TurfIndent, tips: &TipRuns, a: &Adhesive) -> Vec<Row> {
    let problem = format!(
        "turf pull-off of a {:.0} nm adhesive sphere that holds the tips (nN)",
        t.radius
    );
    let n = tips.spheres.len();
    let forces: Result<Vec<f64>, BenchError> = tips
        .spheres
        .iter()
        .map(|s| {
            s.pull_off.map(|p| p.0).ok_or(BenchError::NoValue {
                stage: Stage::Discrete,
                name: format!("pull_off_nN (seed {})", s.seed),
            })
        })
        .collect();
    let depths: Vec<String> = tips
        .spheres
        .iter()
        .filter_map(|s| {
            s.pull_off
                .map(|p| p.1.map_or("— (never pulled)".into(), |d| format!("{d:.1}")))
        })
        .collect();
    let what = format!(
        "pulled off at δ = {} nm (seed order); unloaded in steps of {:.0} nm, retracted {} nm \
         above the first touch in steps of {:.2} nm: a tip pulls hardest within ≈ 0.1 nm of \
         travel, so the pull-off is sampled at the steps",
        depths.join(", "),
        t.deepest / t.steps as f64,
        a.retract,
        a.retract / a.retract_steps as f64
    );
    let fidelity = format!("discrete sphere, adhesive held tips (mean of {n} turfs)");
    let (discrete, reference) = discrete_row(t, tips, &problem, forces, &what, &fidelity);
    let fe = FeRow {
        label: "FE on the card, adhesive held".into(),
        answer: tips.fe.pull_off.ok_or(BenchError::NoPullOff),
        making: None,
    };
    vec![discrete, fe.row(t, tips, &reference, &problem)]
}

/// A speed-up `r`: "40× faster", "1.5× faster", "7.1× slower".
fn ratio(r: f64) -> String {
    match r {
        r if r >= 10.0 => format!("{r:.0}× faster"),
        r if r >= 1.0 => format!("{r:.1}× faster"),
        r => format!("{:.1}× slower", 1.0 / r.max(f64::MIN_POSITIVE)),
    }
}

/// What an FE row is judged against: the turfs' mean, its 95 % interval, the discrete row it
/// comes from and one turf's sphere run's wall time.
struct Reference<'a> {
    mean: f64,
    interval: Option<(f64, f64)>,
    source: &'a str,
    turf_wall_s: f64,
}

/// An FE row: its label, its answer and how its card was made when it is not the isotropic
/// card of the flat compression.
struct FeRow {
    label: String,
    answer: Result<f64, BenchError>,
    making: Option<String>,
}

impl FeRow {
    /// The row of the tip condition's FE run on the isotropic card.
    fn row(self, t: &TurfIndent, tips: &TipRuns, reference: &Reference, problem: &str) -> Row {
        let physics = match tips.tip {
            Tip::Adhesive => "finite strain, adhesion",
            _ => "finite strain, no adhesion",
        };
        self.row_of(t, &tips.fe, reference, problem, physics)
    }

    /// The row of the FE run `fe` against `reference`.
    fn row_of(
        self,
        t: &TurfIndent,
        fe: &FeRun,
        reference: &Reference,
        problem: &str,
        physics: &str,
    ) -> Row {
        let inside = match (&self.answer, reference.interval) {
            (Ok(a), Some((lo, hi))) if (lo..=hi).contains(a) => "inside the turfs' 95 % interval; ",
            (Ok(_), Some(_)) => "outside the turfs' 95 % interval; ",
            _ => "",
        };
        let making = self.making.unwrap_or_else(|| {
            format!(
                "card fitted to the seed-{} turf's flat compression (rms {:.1} %)",
                t.card_seed,
                100.0 * t.fit_rms
            )
        });
        let w = reference.turf_wall_s;
        Row::new(
            problem,
            &format!("{} ({physics})", self.label),
            self.answer.map_err(|e| BenchError::Noted {
                error: Box::new(e),
                note: fe.note.clone(),
            }),
            (reference.mean, reference.source),
            fe.cost,
            format!(
                "{inside}{making}; {}; {} than a turf's sphere run, {:.2}× with the \
                 flat compression and fit (compression + fit {:.1} s{})",
                fe.note,
                ratio(w / fe.cost.wall_s.max(1e-9)),
                w / (fe.cost.wall_s + t.card_making.wall_s).max(1e-9),
                t.card_making.wall_s,
                if t.card_cached { CACHED } else { "" }
            ),
        )
    }
}
