//! The `turf` binary: `turf check` (text and --json), error exits, and `turf run`'s behaviour
//! while no engine is built in (a clear error naming the stage, a summary of what finished).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run the `turf` binary from the crate's folder.
pub(crate) fn turf(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_turf"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the turf binary runs")
}

/// Bytes of an output as text.
pub(crate) fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn check_prints_the_plan_and_runs_nothing() {
    let out = turf(&["check", "scenes/jkr_sphere.toml"]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for part in [
        "scene 'jkr_sphere'",
        "1. theory",
        "2. halfspace",
        "Tabor μ",
        "[off] viscoelastic",
        "no internal variables",
        "adhesion.gamma",
        "J/m^2",
        "nothing was run",
    ] {
        assert!(stdout.contains(part), "missing {part:?} in:\n{stdout}");
    }
    assert!(!Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("runs/jkr_sphere")
        .exists());
}

#[test]
fn check_json_is_machine_readable_and_honours_set() {
    let out = turf(&[
        "check",
        "scenes/hertz.toml",
        "--json",
        "--set",
        "schedule.segment[0].to=8 nm",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let stages: Vec<&str> = v["plan"]["stages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["stage"].as_str().unwrap())
        .collect();
    assert_eq!(stages, ["theory", "continuum"]);
    assert_eq!(v["scene"]["schedule"]["segment"][0]["to"], 8.0);
    assert_eq!(v["scene"]["indenter"]["radius"], 1000.0);
    assert_eq!(v["derived"]["schedule"]["max_depth_nm"], 8.0);
}

#[test]
fn a_bad_scene_exits_non_zero_with_the_key_in_the_message() {
    let out = turf(&[
        "check",
        "scenes/jkr_sphere.toml",
        "--set",
        "material.poisson=0.5",
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("scenes/jkr_sphere.toml"), "{err}");
    assert!(err.contains("material.poisson (from --set)"), "{err}");
    assert!(err.contains("[0, 0.5)"), "{err}");
    let out = turf(&["check", "scenes/missing.toml"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("cannot read scene scenes/missing.toml"));
}

fn temp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("turf-cli-{tag}-{}", std::process::id()))
}

#[test]
fn run_writes_theory_and_halfspace_results_with_their_cost() {
    let dir = temp("run");
    let out = turf(&[
        "run",
        "scenes/jkr_sphere.toml",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["complete"], true);
    assert_eq!(summary["units"]["length"], "nm");
    assert_eq!(summary["scene"]["adhesion"]["gamma"], 0.05);
    let theory = &summary["stages"][0];
    assert_eq!(theory["stage"], "theory");
    // JKR's load-control pull-off is exactly −3/2 πγR
    let jkr = theory["values"]["jkr_pull_off_normalized_load_control"]
        .as_f64()
        .unwrap();
    assert!((jkr + 1.5).abs() < 1e-9, "{jkr}");
    let hs = &summary["stages"][1];
    assert_eq!(hs["stage"], "halfspace");
    assert!(hs["wall_time_s"].as_f64().unwrap() > 0.0);
    assert!(hs["evaluations"].as_u64().unwrap() > 0);
    // μ ≈ 1.74: between JKR and DMT, converged under refinement (docs/validation-halfspace.md)
    let p = hs["values"]["pull_off_normalized"].as_f64().unwrap();
    assert!(p > -2.0 && p < -1.5, "{p}");
    assert!(hs["values"]["pull_off_error_estimate"].as_f64().unwrap() < 2e-3 * p.abs());
    for f in [
        "theory_curves.csv",
        "halfspace_curve.csv",
        "plots/halfspace_load_depth.svg",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn run_refuses_arc_length_with_relaxation_and_keeps_a_summary() {
    let dir = temp("run-fe");
    let out = turf(&[
        "run",
        "scenes/hyperfoam_indent.toml",
        "--out",
        dir.to_str().unwrap(),
        "--set",
        "solver.method=riks",
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        // arc-length traces an elastic curve; the scene has a Prony term
        err.contains("stage 'continuum' failed")
            && err.contains("arc-length continuation traces an elastic curve: Prony relaxation needs the Newton method"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["complete"], false);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn run_indents_the_hertz_scene_by_finite_elements() {
    let dir = temp("run-hertz");
    let out = turf(&["run", "scenes/hertz.toml", "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let fe = &summary["stages"][1];
    assert_eq!(fe["stage"], "continuum");
    // Hertz contact radius a = √(Rδ) at δ = 4 nm, R = 1 µm; 5 % is issue 4's tolerance
    let a = fe["values"]["contact_radius_at_max_load_nm"]
        .as_f64()
        .unwrap();
    assert!((a / (1000.0f64 * 4.0).sqrt() - 1.0).abs() < 0.05, "{a}");
    for f in ["continuum/load_depth.csv", "continuum/plots/load_depth.svg"] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    assert!(
        std::fs::read_dir(dir.join("continuum/vtk"))
            .unwrap()
            .count()
            > 0
    );
    std::fs::remove_dir_all(dir).ok();
}

/// Regression test: with a 10 µm block the unload to δ → 0 meets a residual floor of ~4e-7 of
/// the increment's first residual (net force ~0 there); Newton must accept that stalled
/// residual rather than give up after 11 halvings.
#[test]
fn unloading_a_large_hertz_block_to_zero_depth_converges() {
    let dir = temp("run-hertz-large");
    let out = turf(&[
        "run",
        "scenes/hertz.toml",
        "--out",
        dir.to_str().unwrap(),
        "--set",
        "mesh.width=\"10 um\"",
        "--set",
        "mesh.depth=\"10 um\"",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bench_quick_reports_every_fidelity_with_its_error_and_cost() {
    let dir = temp("bench");
    let out = turf(&["bench", "--quick", "--json", "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let rows = v["rows"].as_array().unwrap();
    let row = |problem: &str, fidelity: &str| {
        rows.iter()
            .find(|r| r["problem"].as_str().unwrap().contains(problem) && r["fidelity"] == fidelity)
            .unwrap_or_else(|| panic!("no row {problem} / {fidelity}"))
    };
    let err = |r: &serde_json::Value| r["rel_error"].as_f64().expect("an error");
    // the half-space against its own extrapolation: its error estimate is ~1e-4
    assert!(err(row("μ = 0.5", "halfspace")) < 1e-3);
    // the FE at μ = 0.5 on its default mesh: within 0.4 % of the half-space
    // (docs/validation-continuum.md)
    assert!(err(row("μ = 0.5", "FE small strain")) < 4e-3);
    // issue 7: 1 % at 50 segments
    assert!(err(row("cantilever", "discrete (elastica chain)")) < 1e-2);
    // Maugis–Dugdale is another law: a few per cent off at μ = 2, not zero
    let md = err(row("μ = 2", "theory (Maugis–Dugdale)"));
    assert!(md > 1e-3 && md < 0.1, "{md}");
    for r in rows {
        assert!(r["cost"]["wall_s"].as_f64().unwrap() >= 0.0);
    }
    // refinement sweeps of second-order methods: the error falls by ≥ 3 per doubling
    let sweeps = v["sweeps"].as_array().unwrap();
    for name in ["fe_time_step", "rod_segments"] {
        let s = sweeps.iter().find(|s| s["name"] == name).unwrap();
        let e: Vec<f64> = s["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["rel_error"].as_f64().unwrap())
            .collect();
        assert!(e.len() >= 3, "{name}: {e:?}");
        for w in e.windows(2).take(2) {
            assert!(w[0] / w[1] > 3.0, "{name}: {e:?}");
        }
    }
    for f in [
        "bench.json",
        "bench.md",
        "plots/ladder.svg",
        "plots/sweep_rod_segments.png",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let md = std::fs::read_to_string(dir.join("bench.md")).unwrap();
    assert!(!md.contains("NaN") && md.contains("| cantilever"));
    std::fs::remove_dir_all(&dir).ok();
}

/// `turf` with `TURF_MAX_MEMORY` set.
fn turf_with_ceiling(ceiling: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_turf"))
        .args(args)
        .env("TURF_MAX_MEMORY", ceiling)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the turf binary runs")
}

/// Issue 23 item 1: `check` prints each sized stage's memory; a scene beyond the ceiling is
/// refused by `check` and by `run` before anything runs or is written, naming the key, the
/// estimate and the ceiling's source.
#[test]
fn scenes_beyond_the_memory_ceiling_are_refused_by_check_and_run() {
    let out = turf(&["check", "scenes/jkr_sphere.toml"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("memory (estimates; ceiling") && stdout.contains("grid nodes"),
        "{stdout}"
    );
    for (scene, ceiling, key) in [
        (
            "scenes/jkr_sphere.toml",
            "100 kB",
            "halfspace.cells_per_zone",
        ),
        ("scenes/turf_compression.toml", "10 kB", "turf.box"),
        (
            "scenes/rods_cantilever.toml",
            "10 kB",
            "rods.rod[0].segments",
        ),
    ] {
        let out = turf_with_ceiling(ceiling, &["check", scene]);
        let err = text(&out.stderr);
        assert!(
            !out.status.success(),
            "{scene} passed check under {ceiling}"
        );
        assert!(
            err.contains(key) && err.contains("memory ceiling") && err.contains("TURF_MAX_MEMORY"),
            "{err}"
        );
        let dir = temp("ceiling");
        let out = turf_with_ceiling(ceiling, &["run", scene, "--out", dir.to_str().unwrap()]);
        assert!(!out.status.success());
        assert!(text(&out.stderr).contains(key));
        assert!(!dir.exists(), "a refused run wrote {}", dir.display());
    }
    let out = turf(&[
        "check",
        "scenes/rods_cantilever.toml",
        "--set",
        "rods.rod[0].segments=1000000000000",
    ]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("rods.rod[0].segments (from --set)"));
    let out = turf_with_ceiling("lots", &["check", "scenes/hertz.toml"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("TURF_MAX_MEMORY=\"lots\" is not a memory size"));
}

/// `check --json` prints a refusal as a JSON object (it printed plain text).
#[test]
fn check_json_of_a_refused_scene_is_json() {
    let out = turf(&[
        "check",
        "scenes/jkr_sphere.toml",
        "--json",
        "--set",
        "material.poisson=0.5",
    ]);
    assert!(!out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", text(&out.stdout)));
    assert_eq!(v["valid"], false);
    assert_eq!(v["problems"][0]["key"], "material.poisson");
    assert_eq!(v["problems"][0]["from_command_line"], true);
    assert!(v["error"].as_str().unwrap().contains("[0, 0.5)"));
    let out = turf(&["check", "scenes/missing.toml", "--json"]);
    assert!(!out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["error"].as_str().unwrap().contains("cannot read scene"));
    let out = turf(&["check", "scenes/jkr_sphere.toml", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["valid"], true);
    assert!(v["plan"]["memory"]["ceiling"]["bytes"].as_f64().unwrap() > 0.0);
}

#[test]
fn run_refuses_an_empty_output_folder() {
    let out = turf(&["run", "scenes/jkr_sphere.toml", "--out", ""]);
    assert!(!out.status.success());
    // clap refuses the empty value
    assert!(text(&out.stderr).contains("--out"));
    let out = turf(&["run", "scenes/jkr_sphere.toml", "--set", "output.dir=\"\""]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("output.dir"));
}

/// A ramp given by its time (here 1e-300 s) runs: it failed with "rate unresolved".
#[test]
fn a_ramp_given_by_its_time_runs() {
    let dir = temp("by-time");
    std::fs::create_dir_all(&dir).unwrap();
    let scene =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hertz.toml"))
            .unwrap()
            .replacen("rate = \"1 nm/s\"", "time = \"1e-300 s\"", 1);
    let file = dir.join("by_time.toml");
    std::fs::write(&file, scene).unwrap();
    let out = turf(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--set",
        "solver.increments=8",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
            .unwrap();
    assert_eq!(v["complete"], true);
    std::fs::remove_dir_all(&dir).ok();
}

/// Every number in every JSON and CSV file under `dir`, with its file and place if one is not
/// finite (JSON cannot hold NaN: serde_json writes it as null, so a null is reported too).
fn non_finite_numbers(dir: &Path) -> Vec<String> {
    fn walk_json(v: &serde_json::Value, at: String, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Null => out.push(format!("{at}: null")),
            serde_json::Value::Number(n) if !n.as_f64().is_some_and(f64::is_finite) => {
                out.push(format!("{at}: {n}"))
            }
            serde_json::Value::Array(items) => {
                for (i, x) in items.iter().enumerate() {
                    walk_json(x, format!("{at}[{i}]"), out);
                }
            }
            serde_json::Value::Object(map) => {
                for (k, x) in map {
                    walk_json(x, format!("{at}.{k}"), out);
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap().flatten() {
            let p = entry.path();
            let name = p.display().to_string();
            match p.extension().and_then(|e| e.to_str()) {
                _ if p.is_dir() => stack.push(p),
                Some("json") => {
                    let v: serde_json::Value =
                        serde_json::from_str(&std::fs::read_to_string(&p).unwrap())
                            .unwrap_or_else(|e| panic!("{name}: {e}"));
                    walk_json(&v, name, &mut out);
                }
                Some("csv") => {
                    let text = std::fs::read_to_string(&p).unwrap();
                    for (line, row) in text.lines().enumerate().skip(1) {
                        for cell in row.split(',') {
                            if cell.trim().parse::<f64>().is_ok_and(|x| !x.is_finite()) {
                                out.push(format!("{name}:{}: {cell}", line + 1));
                            }
                        }
                    }
                }
                _ => {}
            }
        }
    }
    out
}

/// The example scenes that run in seconds (closed forms, the half-space, the FE, a card, the
/// rods) write only finite numbers into every JSON and CSV file of their output folders.
#[test]
fn every_number_the_fast_example_scenes_write_is_finite() {
    // the walker itself finds a NaN cell and a null
    let probe = temp("finite-probe");
    std::fs::create_dir_all(probe.join("sub")).unwrap();
    std::fs::write(probe.join("sub/a.csv"), "x_nm,y_nN\n1,NaN\n2,3\n").unwrap();
    std::fs::write(probe.join("b.json"), r#"{"v": [1.0, null]}"#).unwrap();
    assert_eq!(non_finite_numbers(&probe).len(), 2);
    std::fs::remove_dir_all(probe).ok();
    for scene in ["jkr_sphere", "hertz", "seed_card", "rods_cantilever"] {
        let dir = temp(&format!("finite-{scene}"));
        let out = turf(&[
            "run",
            &format!("scenes/{scene}.toml"),
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{scene}: {}", text(&out.stderr));
        let bad = non_finite_numbers(&dir);
        assert!(bad.is_empty(), "{scene}: {bad:#?}");
        std::fs::remove_dir_all(dir).ok();
    }
}

/// A plain re-run into a folder holding an interrupted run's checkpoint says that `--resume`
/// exists (and starts over); after a complete run, or one whose discrete stage finished before
/// a later stage failed (its checkpoint is one of the stage's files), it says nothing.
#[test]
fn a_rerun_over_an_interrupted_checkpoint_points_to_resume() {
    let cases = [
        ("interrupted", r#"{"complete": false}"#, true),
        ("complete", r#"{"complete": true}"#, false),
        (
            "later-stage-failed",
            r#"{"complete": false, "stages": [{"stage": "discrete"}], "error": "continuum"}"#,
            false,
        ),
        (
            "discrete-failed",
            r#"{"complete": false, "stages": [{"stage": "theory"}], "error": "discrete"}"#,
            true,
        ),
    ];
    for (name, summary, noted) in cases {
        let dir = temp(&format!("interrupted-{name}"));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(turf::pipeline::CHECKPOINT), "{}").unwrap();
        std::fs::write(dir.join("summary.json"), summary).unwrap();
        let out = turf(&[
            "run",
            "scenes/jkr_sphere.toml",
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let err = text(&out.stderr);
        assert_eq!(
            err.contains("--resume` continues it"),
            noted,
            "{name}: {err}"
        );
        std::fs::remove_dir_all(dir).ok();
    }
}

/// A file-system refusal names the file and the OS reason once (not again as a chained cause).
#[test]
fn an_os_error_is_printed_once() {
    let blocker = temp("os-error-blocker");
    std::fs::write(&blocker, "a file, not a folder").unwrap();
    let out_dir = blocker.join("out");
    let out = turf(&[
        "run",
        "scenes/jkr_sphere.toml",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert_eq!(err.matches("os error").count(), 1, "{err}");
    std::fs::remove_file(blocker).ok();
}
