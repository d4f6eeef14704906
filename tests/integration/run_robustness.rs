//! `turf run` when the world misbehaves: a file it cannot write (a full disk, a path that is a
//! folder), an interrupt in the middle of the continuum stage, an output folder that holds an
//! earlier run's files, and the homogenize command's fits that do not represent their data.
//! Each case is made with paths that fail for every user, root included (a folder where a file
//! should go, a regular file where a folder should be), not with permissions.

use crate::cli_run::{text, turf};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// `turf run scenes/jkr_sphere.toml --out DIR` (theory and half-space: a second or two) and
/// its stderr, asserting that it succeeded.
fn run_jkr(dir: &Path) -> String {
    let out = turf(&[
        "run",
        "scenes/jkr_sphere.toml",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    err
}

/// A fresh (removed if present) folder name under the system's temporary folder.
fn temp(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("turf-robust-{tag}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    dir
}

/// The `summary.json` of the run in `dir`.
fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Every temporary file (`.NAME.tmpPID…`) under `dir`.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        if path.is_dir() {
            found.extend(temporaries(&path));
        } else if entry.file_name().to_string_lossy().contains(".tmp") {
            found.push(path);
        }
    }
    found
}

#[test]
fn a_plot_that_cannot_be_written_is_a_warning_and_the_other_results_are_kept() {
    let dir = temp("plots");
    std::fs::create_dir_all(&dir).unwrap();
    // `plots` is a regular file: no plot can go under it
    std::fs::write(dir.join("plots"), "not a folder").unwrap();
    let err = run_jkr(&dir);
    assert!(err.contains("warning: plot not written"), "{err}");
    assert!(err.contains("plots/theory_load_depth.svg"), "{err}");
    let s = summary(&dir);
    assert_eq!(s["complete"], true);
    let theory = &s["stages"][0];
    assert!(theory["warnings"][0]
        .as_str()
        .unwrap()
        .contains("theory_load_depth"));
    let listed: Vec<&str> = theory["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert_eq!(
        listed,
        ["theory_curves.csv"],
        "plots not written are not listed"
    );
    assert!(dir.join("theory_curves.csv").is_file());
    assert!(dir.join("halfspace_curve.csv").is_file());
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_summary_that_cannot_be_written_leaves_no_temporary_file() {
    let dir = temp("summary");
    // a folder where summary.json should be: the rename onto it fails
    std::fs::create_dir_all(dir.join("summary.json")).unwrap();
    let out = turf(&[
        "run",
        "scenes/jkr_sphere.toml",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("summary.json"), "{err}");
    assert!(temporaries(&dir).is_empty(), "{:?}", temporaries(&dir));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn files_of_an_earlier_run_that_this_run_did_not_write_are_listed_not_deleted() {
    let dir = temp("stale");
    std::fs::create_dir_all(dir.join("sweep_007")).unwrap();
    std::fs::write(dir.join("continuum_old.csv"), "x\n1\n").unwrap();
    std::fs::write(dir.join("sweep_007/halfspace_curve.csv"), "x\n1\n").unwrap();
    // the earlier run's summary lists its files; one of them the user already removed
    let earlier = serde_json::json!({
        "complete": true,
        "stages": [{"stage": "theory", "files": ["theory_curves.csv", "continuum_old.csv", "gone.csv"]}],
        "sweep": {"key": "adhesion.gamma", "points": [
            {"dir": "sweep_007", "stages": [{"files": ["halfspace_curve.csv"]}]}
        ]},
    });
    std::fs::write(dir.join("summary.json"), earlier.to_string()).unwrap();
    let err = run_jkr(&dir);
    assert!(err.contains("2 file(s)"), "{err}");
    assert!(err.contains("continuum_old.csv"), "{err}");
    let s = summary(&dir);
    assert_eq!(
        s["stale_files"],
        serde_json::json!(["continuum_old.csv", "sweep_007/halfspace_curve.csv"])
    );
    assert!(dir.join("continuum_old.csv").is_file(), "kept");
    // while they are there, every run says so; once removed, none does
    let again = turf(&[
        "run",
        "scenes/jkr_sphere.toml",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(text(&again.stderr).contains("2 file(s)"));
    std::fs::remove_file(dir.join("continuum_old.csv")).unwrap();
    std::fs::remove_dir_all(dir.join("sweep_007")).unwrap();
    let clean = turf(&[
        "run",
        "scenes/jkr_sphere.toml",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(clean.status.success());
    assert!(!text(&clean.stderr).contains("earlier run"));
    assert!(summary(&dir).get("stale_files").is_none());
    std::fs::remove_dir_all(dir).ok();
}

/// Start `turf run ARGS`, wait until `ready()` (polled every 50 ms, at most a minute), send
/// SIGINT and wait for the process to end (at most a minute); its exit status and stderr.
#[cfg(unix)]
fn interrupted_run(args: &[&str], ready: impl Fn() -> bool) -> (std::process::ExitStatus, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_turf"))
        .arg("run")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let wait_for = |what: &str, done: &mut dyn FnMut() -> bool| {
        let start = Instant::now();
        while !done() {
            assert!(start.elapsed() < Duration::from_secs(60), "{what}");
            std::thread::sleep(Duration::from_millis(50));
        }
    };
    wait_for("the run never got ready", &mut || ready());
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let mut status = None;
    wait_for("no stop after SIGINT", &mut || {
        status = child.try_wait().unwrap();
        status.is_some()
    });
    let mut err = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
    (status.unwrap(), err)
}

/// SIGINT to `turf run` in the middle of a long continuum stage: the run stops at the next
/// increment, `summary.json` says `complete = false` with an error naming the stage and the
/// interrupt, and the rows reached are in `continuum/load_depth.csv`.
#[cfg(unix)]
#[test]
fn an_interrupted_continuum_stage_is_recorded_and_keeps_its_rows() {
    let dir = temp("sigint");
    let d = dir.to_str().unwrap();
    let args = [
        "scenes/hertz.toml",
        "--set",
        "solver.increments=200000",
        "--out",
        d,
    ];
    // the theory stage and the mesh take well under a second; the 200,000 increments minutes
    let t0 = Instant::now();
    let (status, err) = interrupted_run(&args, || t0.elapsed() > Duration::from_secs(3));
    assert!(!status.success(), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    let s = summary(&dir);
    assert_eq!(s["complete"], false);
    let e = s["error"].as_str().unwrap();
    assert!(e.starts_with("stage 'continuum' interrupted"), "{e}");
    assert!(e.contains("SIGINT"), "{e}");
    assert_eq!(
        s["stages"][0]["stage"], "theory",
        "the finished stage is kept"
    );
    let rows = std::fs::read_to_string(dir.join("continuum/load_depth.csv")).unwrap();
    assert!(rows.lines().count() > 2, "{rows}");
    std::fs::remove_dir_all(dir).ok();
}

/// SIGINT during the discrete drive (a small turf in 400 strain steps): the drive stops after
/// the step it is solving, the curve so far and the checkpoint are kept, and the error points
/// to `--resume`.
#[cfg(unix)]
#[test]
fn an_interrupted_discrete_stage_keeps_its_checkpoint_and_points_to_resume() {
    let dir = temp("sigint-discrete");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("small.toml");
    let text = crate::common::SMALL_TURF_SCENE
        .replace("steps = 5", "steps = 400")
        .replace("vtk = true", "vtk = false");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let checkpoint = out.join(turf::pipeline::CHECKPOINT);
    let args = [scene.to_str().unwrap(), "--out", out.to_str().unwrap()];
    // ready once the first strain step is checkpointed
    let (status, err) = interrupted_run(&args, || checkpoint.is_file());
    assert!(!status.success(), "{err}");
    let s = summary(&out);
    assert_eq!(s["complete"], false);
    let e = s["error"].as_str().unwrap();
    assert!(e.starts_with("stage 'discrete' interrupted"), "{e}");
    assert!(e.contains("--resume"), "{e}");
    assert!(checkpoint.is_file());
    assert!(out.join("stress_strain.csv").is_file(), "the curve so far");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn tangent_laws_the_card_cannot_represent_are_said_out_loud() {
    let dir = temp("laws");
    let cases = [
        // ε₀ far below the first sample: a straight line of slope E^∞, E⁰ unseen
        ("E0=700MPa,Einf=70MPa,eps0=1e-300", "E0 is not seen"),
        // a stiffening tangent
        ("E0=70MPa,Einf=700MPa,eps0=0.1", "exceeds E0"),
    ];
    for (law, said) in cases {
        let out = turf(&[
            "homogenize",
            "--tangent-law",
            law,
            "--out",
            dir.to_str().unwrap(),
            "--json",
        ]);
        let err = text(&out.stderr);
        assert!(out.status.success(), "{law}: {err}");
        assert!(err.contains(said), "{law}: {err}");
        let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let warnings = s["warnings"].as_array().unwrap();
        assert!(
            warnings.iter().any(|w| w.as_str().unwrap().contains(said)),
            "{law}: {warnings:?}"
        );
        let q = &s["fit_quality"];
        let rms = q["hyperfoam_rms_rel"].as_f64().unwrap();
        if rms > q["rms_warn"].as_f64().unwrap() {
            assert_eq!(q["acceptable"], false);
            assert!(err.contains("does not represent the curve"), "{law}: {err}");
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

/// `turf check` of a long sweep was quadratic: every point's scene carried (and re-read) the
/// whole list of values. Each point now resolves the scene without `[sweep]`, so its size does
/// not grow with the number of values (a structural check: tests assert no wall-clock limits).
#[test]
fn a_sweep_point_does_not_carry_the_whole_sweep() {
    let base = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/jkr_sphere.toml"),
    )
    .unwrap();
    let point_size = |n: usize| {
        let values: Vec<String> = (0..n)
            .map(|i| format!("\"{} J/m^2\"", 0.01 + 0.01 * i as f64 / n as f64))
            .collect();
        let text = format!(
            "{base}\n[sweep]\nkey = \"adhesion.gamma\"\nvalues = [{}]\n",
            values.join(", ")
        );
        let loaded = turf::scene::load_str(&text, Path::new("sweep.toml"), &[]).unwrap();
        assert_eq!(loaded.sweep.len(), n);
        let last = &loaded.sweep[n - 1].scene;
        assert!(last.scene.sweep.is_none());
        serde_json::to_string(last).unwrap().len()
    };
    let (small, large) = (point_size(10), point_size(1000));
    // the values differ in their digits only
    assert!(large < small + 64, "{small} {large}");
}

/// The quickstart's own card: two terms asked for, the fit degenerate (equal α, the second
/// term 10⁻³ of Σμ), so the card is the one-term fit, and the summary says so with the misfit.
#[test]
fn the_quickstart_curve_gets_the_one_term_card_it_supports_and_says_why() {
    let dir = temp("quickstart-card");
    let out = turf(&[
        "homogenize",
        "--curve",
        "tests/integration/data/quickstart_loading.csv",
        "--terms",
        "2",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(s["terms_requested"], 2);
    assert_eq!(s["terms_used"], 1);
    assert_eq!(s["hyperfoam"]["alpha"].as_array().unwrap().len(), 1);
    let first = s["warnings"][0].as_str().unwrap();
    assert!(first.starts_with("2 terms requested, 1 used"), "{first}");
    assert!(err.contains("2 terms requested, 1 used"), "{err}");
    // a 9-tube curve: the misfit is over the threshold and said so
    assert_eq!(s["fit_quality"]["acceptable"], false);
    assert!(s["fit_rms_rel"].as_f64().unwrap() > 0.05);
    assert!(err.contains("does not represent the curve"), "{err}");
    // the card the FE reads, and CalculiX's two-term form of it
    let card = turf::homogenize::read_card(&dir.join("material.json")).unwrap();
    assert_eq!(card.hyperfoam.terms.len(), 1);
    let inp = std::fs::read_to_string(dir.join("material.inp")).unwrap();
    assert!(inp.contains("*HYPERFOAM, N=2"), "{inp}");
    std::fs::remove_dir_all(dir).ok();
}
