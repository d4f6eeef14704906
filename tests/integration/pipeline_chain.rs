//! The chain discrete → homogenize → continuum in one scene: the stage cache (a re-run that
//! changes only FE keys reuses the discrete and homogenize stages and says so; a change of a
//! discrete input recomputes), with the pipeline's stand-in runner and with the real engines
//! on a small turf.

use crate::common;

use common::SMALL_TURF_SCENE;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use turf::pipeline::{run, run_with, RunOptions, StageContext, StageError, StageOutput};
use turf::report::csv::Table;
use turf::scene::{load_str, ResolvedScene, Stage};

/// A chain scene: 9 tubes compressed, the loading curve fitted, the card indented with the
/// tubes' thermal shift through a spring.
const CHAIN: &str = r#"
[scene]
name = "chain-test"
seed = 3
[turf]
density = "1e10 1/cm^2"
box = ["300 nm", "300 nm"]
[turf.tube]
r_o = "20 nm"
r_i = "17.3 nm"
youngs = "0.4 TPa"
[turf.growth]
length = "2 um"
[compression]
to = 0.3
steps = 6
[homogenize]
terms = 2
curve = "loading"
[viscoelastic]
g = [0.4]
tau = ["3 s"]
[indenter]
radius = "500 nm"
[material]
model = "card"
[adhesion]
law = "lj104"
gamma = "0.02 J/m^2"
z0 = "0.34 nm"
thermal_shift = true
[machine]
stiffness = "1 uN/nm"
[schedule]
[[schedule.segment]]
kind = "load"
to = "20 nm"
rate = "10 nm/s"
"#;

fn temp_dir(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("turf-chain-{tag}-{}", std::process::id()))
}

/// Calls of each stage by the stand-in runner.
#[derive(Default)]
struct Calls(BTreeMap<Stage, usize>);

impl Calls {
    fn of(&self, s: Stage) -> usize {
        self.0.get(&s).copied().unwrap_or(0)
    }
}

/// A stand-in for the engines: each stage writes one file that names the scene value it read,
/// so a reused file shows which inputs produced it.
fn stand_in(
    calls: &mut Calls,
    stage: Stage,
    scene: &ResolvedScene,
    ctx: &StageContext,
) -> Result<StageOutput, StageError> {
    *calls.0.entry(stage).or_default() += 1;
    let length = scene.scene.turf.as_ref().unwrap().growth.length.0;
    let (file, text) = match stage {
        Stage::Discrete => ("stress_strain_loading.csv", format!("length {length}\n")),
        Stage::Homogenize => (
            "material.json",
            format!("terms {}\n", scene.scene.homogenize.as_ref().unwrap().terms),
        ),
        _ => {
            return Ok(StageOutput {
                values: BTreeMap::from([("max_load_nN".into(), 1.0)]),
                ..StageOutput::default()
            })
        }
    };
    std::fs::create_dir_all(ctx.out_dir).unwrap();
    std::fs::write(ctx.out_dir.join(file), text).unwrap();
    Ok(StageOutput {
        values: BTreeMap::from([("length_nm".into(), length)]),
        tables: vec![("t".into(), Table::new().column("x", vec![length]))],
        evaluations: 7,
        files: vec![file.into()],
        ..StageOutput::default()
    })
}

fn run_stand_in(dir: &Path, calls: &mut Calls, overrides: &[&str]) -> serde_json::Value {
    let sets: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let loaded = load_str(CHAIN, Path::new("chain.toml"), &sets).unwrap();
    let opts = RunOptions {
        out: Some(dir.to_path_buf()),
        progress: false,
        resume: false,
    };
    let mut runner =
        |st: Stage, sc: &ResolvedScene, ctx: &StageContext| stand_in(calls, st, sc, ctx);
    let report = run_with(&loaded, &opts, &mut runner).unwrap();
    assert!(report.failure.is_none(), "{:?}", report.failure);
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn cached(summary: &serde_json::Value) -> Vec<bool> {
    summary["stages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["cached"].as_bool().unwrap())
        .collect()
}

#[test]
fn a_rerun_changing_only_fe_keys_reuses_the_discrete_and_homogenize_stages() {
    let dir = temp_dir("stand-in");
    let mut calls = Calls::default();
    let first = run_stand_in(&dir, &mut calls, &[]);
    assert_eq!(cached(&first), [false, false, false]);
    assert_eq!(
        (calls.of(Stage::Discrete), calls.of(Stage::Homogenize)),
        (1, 1)
    );
    let key = first["stages"][0]["cache_key"]
        .as_str()
        .unwrap()
        .to_string();
    assert_eq!(key.len(), 16);
    assert!(dir
        .join(format!("cache/discrete-{key}/record.json"))
        .is_file());

    // the files handed over are copied back from the cache, not left over from the first run
    for f in [
        "stress_strain_loading.csv",
        "material.json",
        "discrete_t.csv",
    ] {
        std::fs::remove_file(dir.join(f)).unwrap();
    }
    let fe_only = [
        "mesh.smallest=\"0.5 nm\"",
        "adhesion.gamma=\"0.05 J/m^2\"",
        "schedule.segment[0].to=\"30 nm\"",
    ];
    let second = run_stand_in(&dir, &mut calls, &fe_only);
    assert_eq!(cached(&second), [true, true, false]);
    assert_eq!(
        (calls.of(Stage::Discrete), calls.of(Stage::Homogenize)),
        (1, 1),
        "FE keys only: neither stage may run again"
    );
    assert_eq!(calls.of(Stage::Continuum), 2);
    assert_eq!(second["stages"][0]["cache_key"], key.as_str());
    assert_eq!(second["stages"][0]["evaluations"], 7);
    assert_eq!(second["stages"][0]["values"], first["stages"][0]["values"]);
    let files: Vec<&str> = second["stages"][0]["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert_eq!(files, ["stress_strain_loading.csv", "discrete_t.csv"]);
    assert_eq!(
        std::fs::read_to_string(dir.join("stress_strain_loading.csv")).unwrap(),
        "length 2000\n"
    );
    assert!(dir.join("material.json").is_file() && dir.join("discrete_t.csv").is_file());

    // a discrete input recomputes the discrete stage and, downstream, the card
    let third = run_stand_in(&dir, &mut calls, &["turf.growth.length=\"1.5 um\""]);
    assert_eq!(cached(&third), [false, false, false]);
    assert_eq!(
        (calls.of(Stage::Discrete), calls.of(Stage::Homogenize)),
        (2, 2)
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("stress_strain_loading.csv")).unwrap(),
        "length 1500\n"
    );

    // a homogenize input recomputes only the card; the first discrete entry is still there
    let fourth = run_stand_in(&dir, &mut calls, &["homogenize.terms=3"]);
    assert_eq!(cached(&fourth), [true, false, false]);
    assert_eq!(
        (calls.of(Stage::Discrete), calls.of(Stage::Homogenize)),
        (2, 3)
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("stress_strain_loading.csv")).unwrap(),
        "length 2000\n"
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn the_real_discrete_stage_is_reused_when_only_the_fit_changes() {
    let dir = temp_dir("real");
    let opts = RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let summary = |sets: &[&str]| {
        // the shared small turf, loading only, without VTK, under this test's own name
        let sets: Vec<String> = [
            "scene.name=\"chain-cache-real\"",
            "compression.unload=false",
            "output.vtk=false",
        ]
        .iter()
        .chain(sets)
        .map(|s| s.to_string())
        .collect();
        let loaded = load_str(SMALL_TURF_SCENE, Path::new("small.toml"), &sets).unwrap();
        let report = run(&loaded, &opts).unwrap();
        assert!(report.failure.is_none(), "{:?}", report.failure);
        serde_json::to_value(&report.summary).unwrap()
    };
    let first = summary(&[]);
    let curve = std::fs::read(dir.join("stress_strain_loading.csv")).unwrap();
    let second = summary(&["homogenize.strain_max=0.25"]);
    assert_eq!(cached(&first), [false, false]);
    assert_eq!(cached(&second), [true, false]);
    let (d1, d2) = (&first["stages"][0], &second["stages"][0]);
    assert_eq!(d1["values"], d2["values"]);
    assert_eq!(d1["evaluations"], d2["evaluations"]);
    assert_eq!(
        std::fs::read(dir.join("stress_strain_loading.csv")).unwrap(),
        curve
    );
    // the card was refitted on the reused curve, to the new strain range
    assert_eq!(second["stages"][1]["values"]["strain_max"], 0.25);
    // pin_e0 holds the card's E⁰ = 2Σμ (ν = 0) at the tangent law fitted to the same curve,
    // which the discrete stage reports; the free fit's E⁰ is its own
    let pinned = summary(&["homogenize.pin_e0=true"]);
    assert_eq!(cached(&pinned), [true, false]);
    let e0 = |s: &serde_json::Value| {
        let v = &s["stages"][1]["values"];
        2.0 * (1..=2)
            .filter_map(|i| v[format!("hyperfoam_mu{i}_GPa")].as_f64())
            .sum::<f64>()
    };
    let law = pinned["stages"][0]["values"]["tangent_e0_GPa"]
        .as_f64()
        .unwrap();
    // the pin is exact up to the fit's parametrisation (Σμ fixed, split by a softmax)
    assert!(
        (e0(&pinned) / law - 1.0).abs() < 1e-9,
        "{} vs {law}",
        e0(&pinned)
    );
    assert!((e0(&first) / law - 1.0).abs() > 1e-6);
    std::fs::remove_dir_all(dir).ok();
}
