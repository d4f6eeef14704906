//! Ensembles of discrete-turf realisations (issue 18, item 3): `turf.realisations = 3` on the
//! 4-tube test turf gives exactly the single runs at the derived seeds, their mean, and a
//! Student-t 95 % interval of the width computed here independently, also when grown from a
//! resumed 2-realisation run; one realisation is the run without the key; bad counts are
//! refused by key and line; failed realisations are named and the others kept.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use turf::pipeline::ensemble::realisation_seed;
use turf::pipeline::{run, RunOptions};
use turf::scene::{load_str, Loaded, Stage};

/// The ensemble's mean is the sum of three stresses over 3: equal to the mean computed here
/// up to the rounding of the two summation orders.
const MEAN_TOL: f64 = 1e-14;
/// The interval's half width t·s/√n against the closed-form t: rounding of s and t only.
const WIDTH_TOL: f64 = 1e-12;

/// The 4-tube test turf (5 steps down and back) in 5 segments a tube, without VTK files.
fn scene() -> String {
    common::SMALL_TURF_SCENE
        .replace("vtk = true", "vtk = false")
        .replace("segment = \"125 nm\"", "segment = \"200 nm\"")
}

fn load(sets: &[String]) -> Loaded {
    load_str(&scene(), Path::new("t.toml"), sets).unwrap()
}

/// Run `loaded` into `dir`, continuing from its checkpoints with `resume`.
fn run_report(loaded: &Loaded, dir: &Path, resume: bool) -> turf::pipeline::RunReport {
    let opts = RunOptions {
        out: Some(dir.to_path_buf()),
        progress: false,
        resume,
    };
    run(loaded, &opts).unwrap()
}

/// [`run_report`], and the run must succeed.
fn run_in(loaded: &Loaded, dir: &Path, resume: bool) {
    let report = run_report(loaded, dir, resume);
    assert!(report.failure.is_none(), "{:?}", report.failure);
}

/// A fresh output folder named by `tag`.
fn fresh_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("turf-ensemble-{tag}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    dir
}

/// Run `loaded` into a fresh folder named by `tag`; the run must succeed.
fn run_into(loaded: &Loaded, tag: &str) -> PathBuf {
    let dir = fresh_dir(tag);
    run_in(loaded, &dir, false);
    dir
}

/// The columns of a CSV file by header name.
fn columns(path: &Path) -> BTreeMap<String, Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut cols: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for line in lines {
        for (name, v) in names.iter().zip(line.split(',')) {
            cols.entry(name.clone())
                .or_default()
                .push(v.parse().unwrap());
        }
    }
    cols
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The values of `stage` in a run's summary.
fn values(dir: &Path, stage: Stage) -> serde_json::Value {
    let summary = json(&dir.join("summary.json"));
    let record = summary["stages"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["stage"] == stage.name())
        .unwrap()
        .clone();
    record["values"].clone()
}

/// t₀.₉₇₅ with 2 degrees of freedom in closed form: F₂(t) = ½ + t/(2√(2 + t²)), so
/// t = (2/(α(2 − α)) − 2)^½ with α = 2(1 − 0.975).
fn t_975_two_dof() -> f64 {
    let alpha: f64 = 0.05;
    (2.0 / (alpha * (2.0 - alpha)) - 2.0).sqrt()
}

/// Mean and half width t·s/√n of three samples.
fn mean_and_half_width(x: [f64; 3]) -> (f64, f64) {
    let mean = (x[0] + x[1] + x[2]) / 3.0;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 2.0;
    (mean, t_975_two_dof() * (var / 3.0).sqrt())
}

fn close(a: f64, b: f64, rel: f64, scale: f64) -> bool {
    (a - b).abs() <= rel * scale.abs().max(a.abs()).max(b.abs()).max(f64::MIN_POSITIVE)
}

/// Whether a JSON value holds a null anywhere (serde_json's trace of a NaN).
fn has_null(v: &serde_json::Value) -> bool {
    match v {
        serde_json::Value::Null => true,
        serde_json::Value::Array(a) => a.iter().any(has_null),
        serde_json::Value::Object(o) => o.values().any(has_null),
        _ => false,
    }
}

/// Every CSV (each field a finite number) and JSON file (no null) under `dir`, the cache aside.
fn assert_no_nan(dir: &Path) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if path.file_name().unwrap() != "cache" {
                assert_no_nan(&path);
            }
            continue;
        }
        let finite = match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => columns(&path).values().flatten().all(|v| v.is_finite()),
            Some("json") => !has_null(&json(&path)),
            _ => true,
        };
        assert!(finite, "{} holds a non-finite value", path.display());
    }
}

/// Every column of a `stress_strain.csv` but the last (the solve's wall time).
fn without_time(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string())
        .collect()
}

#[test]
fn three_realisations_are_three_single_runs_their_mean_and_a_student_t_interval() {
    // two realisations, then three resumed: the first two continue from their checkpoints
    // (a realisation's checkpoint does not depend on the ensemble's size), the third is new
    let ensemble = run_into(&load(&["turf.realisations=2".into()]), "three");
    run_in(&load(&["turf.realisations=3".into()]), &ensemble, true);
    // realisations 0 and 2 again as single runs, each at its seed (0: the scene's own)
    let singles: Vec<PathBuf> = [0, 2]
        .iter()
        .map(|&k| {
            let seed = realisation_seed(5, k);
            assert_eq!(seed == 5, k == 0, "realisation 0 keeps the scene's seed");
            run_into(
                &load(&[format!("scene.seed={seed}")]),
                &format!("single{k}"),
            )
        })
        .collect();

    // 1. a realisation's curve is the single run's at its seed, to the last bit
    let table = columns(&ensemble.join("discrete_ensemble.csv"));
    let stress: Vec<Vec<f64>> = (0..3)
        .map(|k| table[&format!("stress_r{k:03}_GPa")].clone())
        .collect();
    for (k, d) in [0, 2].iter().zip(&singles) {
        let single = &columns(&d.join("stress_strain.csv"))["stress_GPa"];
        assert_eq!(&stress[*k], single, "realisation {k}");
    }
    assert_ne!(stress[0], stress[1], "distinct seeds give distinct turfs");
    assert_ne!(stress[1], stress[2], "distinct seeds give distinct turfs");
    let report = json(&ensemble.join("discrete_ensemble.json"));
    let seeds: Vec<u64> = report["members"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["seed"].as_u64().unwrap())
        .collect();
    assert_eq!(
        seeds,
        (0..3).map(|k| realisation_seed(5, k)).collect::<Vec<_>>()
    );
    assert_eq!(report["failed"].as_array().unwrap().len(), 0);

    // 2. the mean, and the interval of width t₀.₉₇₅,₂ s/√3 around it, at every step
    assert_eq!(table["stress_mean_GPa"].len(), 11);
    for i in 0..11 {
        let (mean, half) = mean_and_half_width([stress[0][i], stress[1][i], stress[2][i]]);
        let (m, lo, hi) = (
            table["stress_mean_GPa"][i],
            table["stress_ci95_low_GPa"][i],
            table["stress_ci95_high_GPa"][i],
        );
        assert!(
            close(m, mean, MEAN_TOL, 0.0),
            "step {i}: {m} against {mean}"
        );
        assert!(lo <= m && m <= hi, "step {i}: {m} outside [{lo}, {hi}]");
        assert!(
            close(hi - m, half, WIDTH_TOL, mean),
            "step {i}: upper half width"
        );
        assert!(
            close(m - lo, half, WIDTH_TOL, mean),
            "step {i}: lower half width"
        );
    }
    assert!(table["stress_ci95_high_GPa"][5] > table["stress_ci95_low_GPa"][5]);

    // 3. the scalars: mean and interval of the three realisations' values (as the single
    // runs report them)
    let v = values(&ensemble, Stage::Discrete);
    let members = report["members"].as_array().unwrap();
    for (name, base, unit) in [
        ("peak_stress_GPa", "peak_stress", "_GPa"),
        ("hysteresis", "hysteresis", ""),
        ("tangent_e0_GPa", "tangent_e0", "_GPa"),
        ("turf_mean_top_nm", "turf_mean_top", "_nm"),
    ] {
        let x: Vec<f64> = members
            .iter()
            .map(|m| m["values"][name].as_f64().unwrap())
            .collect();
        assert_eq!(x[2], values(&singles[1], Stage::Discrete)[name], "{name}");
        let (mean, half) = mean_and_half_width([x[0], x[1], x[2]]);
        let got = |what: &str| v[format!("ensemble_{base}_{what}{unit}")].as_f64().unwrap();
        assert!(close(got("mean"), mean, MEAN_TOL, 0.0), "{name}");
        assert!(
            close(got("ci95_high") - got("mean"), half, WIDTH_TOL, mean),
            "{name}"
        );
        assert_eq!(v[format!("ensemble_{base}_n")], 3.0);
        // realisation 0's own value under the single run's name
        assert_eq!(v[name].as_f64().unwrap(), x[0], "{name}");
    }
    assert_eq!(v["realisations"], 3.0);
    assert_eq!(v["realisations_failed"], 0.0);
    assert_eq!(v["resumed_after_step"], 10.0, "realisation 0 was whole");
    assert_eq!(members[1]["values"]["resumed_after_step"], 10.0);
    assert!(members[2]["values"].get("resumed_after_step").is_none());

    // 3b. the loading curves against the strain from each turf's mean top, on a common grid
    // inside every realisation's range: each member column is its own curve interpolated
    // there, and the mean theirs
    let top = columns(&ensemble.join("discrete_ensemble_mean_top.csv"));
    let grid = &top["strain_from_mean_top"];
    // as many points as the path's loading steps (step 0 and the 5 down)
    assert_eq!(grid.len(), 6);
    for k in 0..3 {
        let dir = match k {
            0 => ensemble.clone(),
            _ => ensemble.join(format!("realisations/r{k:03}")),
        };
        let own = columns(&dir.join("stress_strain.csv"));
        let (e, s) = (&own["strain_from_mean_top"], &own["stress_GPa"]);
        let loading: Vec<(f64, f64)> = (0..e.len())
            .filter(|&i| own["loading"][i] == 1.0)
            .map(|i| (e[i], s[i]))
            .collect();
        // (ε̄ is formed from the nominal strain on the one side and from the heights on the
        // other: equal to rounding)
        let last = loading[loading.len() - 1].0;
        assert!(grid[0] >= loading[0].0 - 1e-12 && grid[5] <= last + 1e-12);
        for (i, &g) in grid.iter().enumerate() {
            let j = loading
                .iter()
                .position(|p| p.0 >= g)
                .unwrap_or(loading.len() - 1)
                .max(1);
            let ((x0, y0), (x1, y1)) = (loading[j - 1], loading[j]);
            let expected = y0 + (y1 - y0) * (g - x0) / (x1 - x0);
            let got = top[&format!("stress_r{k:03}_GPa")][i];
            assert!(
                (got - expected).abs() <= 1e-9 * expected.abs().max(1e-6),
                "realisation {k} at {g}: {got} against {expected}"
            );
        }
    }
    for (i, &mean) in top["stress_mean_GPa"].iter().enumerate() {
        let m = (0..3)
            .map(|k| top[&format!("stress_r{k:03}_GPa")][i])
            .sum::<f64>()
            / 3.0;
        assert!(close(mean, m, MEAN_TOL, 0.0));
    }

    // 4. realisation 0's files are the single run's; the others sit in their folders
    assert_eq!(
        without_time(&ensemble.join("stress_strain.csv")),
        without_time(&singles[0].join("stress_strain.csv"))
    );
    for f in [
        "stress_strain_loading.csv",
        "discrete_analysis.json",
        "discrete_tangent.csv",
    ] {
        let read = |d: &Path| std::fs::read_to_string(d.join(f)).unwrap();
        assert_eq!(read(&ensemble), read(&singles[0]), "{f}");
        let r2 = ensemble.join("realisations/r002").join(f);
        assert_eq!(
            std::fs::read_to_string(r2).unwrap(),
            read(&singles[1]),
            "{f}"
        );
    }
    assert!(ensemble
        .join("realisations/r001/discrete_checkpoint.json")
        .is_file());

    // 5. homogenize fits the mean and reports the spread of the card over the realisations
    let h = values(&ensemble, Stage::Homogenize);
    assert_eq!(h["realisation_cards"], 3.0);
    assert_eq!(h["card_youngs0_n"], 3.0);
    let (lo, hi) = (
        h["card_youngs0_ci95_low_GPa"].as_f64().unwrap(),
        h["card_youngs0_ci95_high_GPa"].as_f64().unwrap(),
    );
    let mean = h["card_youngs0_mean_GPa"].as_f64().unwrap();
    assert!(lo < mean && mean < hi);
    assert_eq!(
        columns(&ensemble.join("homogenize/card_spread.csv"))["realisation"],
        vec![0.0, 1.0, 2.0]
    );
    let spread = json(&ensemble.join("homogenize/ensemble.json"));
    assert_eq!(
        spread["mean_card"]["fit_rms_rel_to_mean_curve"],
        h["fit_rms_rel"]
    );
    let card = std::fs::read_to_string(ensemble.join("material.json")).unwrap();
    assert!(card.contains("mean of the discrete stage's 3 realisations"));

    // 6. no NaN anywhere; one realisation (the single runs) writes no ensemble file
    assert_no_nan(&ensemble);
    for d in &singles {
        assert_no_nan(d);
        assert!(!d.join("discrete_ensemble.csv").exists());
        assert!(!d.join("realisations").exists());
        let v = values(d, Stage::Discrete);
        assert!(v
            .as_object()
            .unwrap()
            .keys()
            .all(|k| !k.starts_with("ensemble")));
        assert!(values(d, Stage::Homogenize)
            .get("realisation_cards")
            .is_none());
    }
    for d in singles.iter().chain([&ensemble]) {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn one_realisation_resolves_and_caches_as_the_scene_without_the_key() {
    let without = load(&[]);
    let one = load(&["turf.realisations=1".into()]);
    let three = load(&["turf.realisations=3".into()]);
    assert_eq!(without.base.scene, one.base.scene);
    let echo = serde_json::to_value(&one.base.scene).unwrap();
    assert!(echo["turf"].get("realisations").is_none());
    assert_eq!(
        serde_json::to_value(&three.base.scene).unwrap()["turf"]["realisations"],
        3
    );
    let key = |l: &Loaded| turf::pipeline::cache::key(Stage::Discrete, &l.base, &[]).unwrap();
    assert_eq!(key(&without), key(&one));
    assert_ne!(
        key(&one),
        key(&three),
        "the cache keys on the number of realisations"
    );
    let plan = format!("{:?}", three.base.plan);
    assert!(plan.contains("3 realisations"), "{plan}");
}

#[test]
fn a_realisation_count_outside_one_to_a_thousand_is_refused_by_key_and_line() {
    let text = scene().replace("[turf]\n", "[turf]\nrealisations = 0\n");
    let line = text.lines().position(|l| l == "realisations = 0").unwrap() + 1;
    let e = load_str(&text, Path::new("bad.toml"), &[])
        .unwrap_err()
        .to_string();
    for part in [
        "bad.toml",
        &format!("line {line}"),
        "turf.realisations",
        "0 is not allowed",
        "1 to 1000",
    ] {
        assert!(e.contains(part), "{part:?} missing from: {e}");
    }
    let set = |v: &str| {
        load_str(
            &scene(),
            Path::new("bad.toml"),
            &[format!("turf.realisations={v}")],
        )
        .unwrap_err()
        .to_string()
    };
    let e = set("1001");
    assert!(
        e.contains("turf.realisations (from --set): 1001 is not allowed"),
        "{e}"
    );
    for bad in ["-1", "2.5", "three"] {
        let e = set(bad);
        assert!(e.contains("turf.realisations (from --set)"), "{bad}: {e}");
        assert!(
            e.contains("1 to 1000 realisations, a whole number"),
            "{bad}: {e}"
        );
    }
}

#[test]
fn a_realisation_that_fails_is_named_and_the_others_are_kept() {
    // tubes tilted by 1.4 rad in the 200 nm box: the generator cannot grow the fourth tube
    // clear of the others for the seeds of realisations 0, 2 and 3, and grows all four for
    // realisation 1 — the only one left, so the ensemble has a mean and no interval
    let loaded = load(&["turf.realisations=4".into(), "turf.growth.tilt=1.4".into()]);
    let dir = run_into(&loaded, "failing");
    let v = values(&dir, Stage::Discrete);
    assert_eq!(v["realisations_failed"], 3.0);
    assert_eq!(v["realisations_finished"], 1.0);
    let report = json(&dir.join("discrete_ensemble.json"));
    let failed = report["failed"].as_array().unwrap();
    let which: Vec<u64> = failed
        .iter()
        .map(|f| f["realisation"].as_u64().unwrap())
        .collect();
    assert_eq!(which, vec![0, 2, 3]);
    for f in failed {
        let why = f["error"].as_str().unwrap();
        assert!(why.contains("grew only 3 of 4 tubes"), "{why}");
    }
    // realisation 0 wrote nothing under the single run's names; realisation 1 is whole
    assert!(!dir.join("stress_strain.csv").exists());
    assert!(dir
        .join("realisations/r001/stress_strain_loading.csv")
        .is_file());
    let table = columns(&dir.join("discrete_ensemble.csv"));
    assert_eq!(table["stress_mean_GPa"], table["stress_r001_GPa"]);
    assert!(
        !table.contains_key("stress_ci95_low_GPa"),
        "one realisation has no interval"
    );
    assert!(v.get("ensemble_peak_stress_mean_GPa").is_some());
    assert!(v.get("ensemble_peak_stress_ci95_low_GPa").is_none());
    assert_eq!(
        report["estimates"]["peak_stress_GPa"]["ci95"],
        turf::pipeline::ensemble::NO_INTERVAL
    );
    let h = values(&dir, Stage::Homogenize);
    assert_eq!(h["realisation_cards"], 1.0);
    let card = std::fs::read_to_string(dir.join("material.json")).unwrap();
    assert!(card.contains("mean of the 1 of the discrete stage's 4 realisations that finished"));
    assert!(h.get("card_youngs0_ci95_low_GPa").is_none());
    assert_no_nan(&dir);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn when_every_realisation_fails_the_stage_fails_naming_each() {
    // one solver iteration cannot relax a turf whose tubes pull into contact
    let loaded = load(&[
        "turf.realisations=2".into(),
        "compression.max_iterations=1".into(),
    ]);
    let dir = fresh_dir("allfail");
    let e = run_report(&loaded, &dir, false)
        .failure
        .expect("no realisation can finish")
        .to_string();
    for part in [
        "all 2 realisations failed",
        "realisation 0 (seed 5) failed",
        &format!("realisation 1 (seed {}) failed", realisation_seed(5, 1)),
    ] {
        assert!(e.contains(part), "{part:?} missing from: {e}");
    }
    let summary = json(&dir.join("summary.json"));
    assert_eq!(summary["complete"], false);
    std::fs::remove_dir_all(&dir).ok();
}
