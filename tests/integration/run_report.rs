//! The per-run `report.md`: written by the pipeline from the summary, also when a stage fails,
//! naming every stage run with its cost, embedding its plots, and giving the error and the
//! stages that did not finish.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use turf::pipeline::{run_with, RunOptions, StageContext, StageError, StageOutput};
use turf::report::csv::Table;
use turf::report::plot::{Plot, Series};
use turf::scene::{load_str, ResolvedScene, Stage};

const SCENE: &str = r#"
[scene]
name = "report-test"
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
    std::env::temp_dir().join(format!("turf-report-{tag}-{}", std::process::id()))
}

#[test]
fn a_failed_run_reports_each_stage_its_cost_its_plot_and_the_failure() {
    let loaded = load_str(SCENE, Path::new("report.toml"), &[]).unwrap();
    let dir = temp_dir("failed");
    let opts = RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let mut runner = |stage: Stage, _: &ResolvedScene, ctx: &StageContext| match stage {
        Stage::Theory => {
            Plot::new("curve", "depth (nm)", "load (nN)")
                .with(Series::line("jkr", vec![0.0, 1.0], vec![0.0, 2.0]))
                .write(&ctx.out_dir.join("plots"), "theory_curve")
                .unwrap();
            Ok(StageOutput {
                values: BTreeMap::from([("pull_off_normalised".to_string(), -1.5)]),
                tables: vec![(
                    "curve".to_string(),
                    Table::new().column("depth_nm", vec![0.0, 1.0]),
                )],
                evaluations: 17,
                files: vec![
                    "plots/theory_curve.svg".into(),
                    "plots/theory_curve.png".into(),
                ],
                ..StageOutput::default()
            })
        }
        _ => Err(StageError::Failed {
            stage,
            message: "did not converge at step 3".into(),
        }),
    };
    let report = run_with(&loaded, &opts, &mut runner).unwrap();
    assert!(report.failure.is_some());
    let md = std::fs::read_to_string(dir.join("report.md")).expect("report.md is written");
    for part in [
        "# Run report: report-test",
        "`report.toml`",
        "status: **stopped**",
        "| 1 | theory |",
        "| 2 | halfspace |",
        "### 1. theory — ",
        "17 evaluations",
        "| `pull_off_normalised` | -1.5 |",
        "![plots/theory_curve.svg](plots/theory_curve.svg)",
        "[theory_curve.csv](theory_curve.csv)",
        "## The run stopped",
        "stage 'halfspace' failed: did not converge at step 3",
        "Planned but not finished: halfspace.",
        "## Resolved parameters",
        "tabor_mu",
        "\"radius\": 1000.0",
    ] {
        assert!(md.contains(part), "missing {part:?} in:\n{md}");
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_complete_run_reports_every_stage_and_no_failure() {
    let loaded = load_str(SCENE, Path::new("report.toml"), &[]).unwrap();
    let dir = temp_dir("complete");
    let opts = RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let mut runner = |_: Stage, _: &ResolvedScene, _: &StageContext| {
        Ok(StageOutput {
            evaluations: 5,
            ..StageOutput::default()
        })
    };
    let report = run_with(&loaded, &opts, &mut runner).unwrap();
    assert!(report.failure.is_none());
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("status: complete"), "{md}");
    assert!(
        md.contains("### 1. theory") && md.contains("### 2. halfspace"),
        "{md}"
    );
    assert!(
        md.contains("Total: ") && md.contains("10 evaluations over 2 stages"),
        "{md}"
    );
    assert!(!md.contains("The run stopped"), "{md}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_sweep_reports_each_value_with_its_stages_in_its_folder() {
    let scene = format!(
        "{SCENE}[sweep]\nkey = \"adhesion.gamma\"\nvalues = [\"0.05 J/m^2\", \"0.1 J/m^2\"]\n"
    );
    let loaded = load_str(&scene, Path::new("report.toml"), &[]).unwrap();
    let dir = temp_dir("sweep");
    let opts = RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let mut runner = |stage: Stage, _: &ResolvedScene, _: &StageContext| match stage {
        Stage::Halfspace => Err(StageError::Failed {
            stage,
            message: "stopped on purpose".into(),
        }),
        _ => Ok(StageOutput {
            tables: vec![(
                "curve".to_string(),
                Table::new().column("depth_nm", vec![0.0]),
            )],
            evaluations: 2,
            ..StageOutput::default()
        }),
    };
    run_with(&loaded, &opts, &mut runner).unwrap();
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for part in [
        "## Sweep over `adhesion.gamma`",
        "(`sweep_000/`)",
        "[theory_curve.csv](sweep_000/theory_curve.csv)",
        "stage 'halfspace' failed: stopped on purpose",
        "Planned but not finished: halfspace.",
    ] {
        assert!(md.contains(part), "missing {part:?} in:\n{md}");
    }
    std::fs::remove_dir_all(dir).ok();
}
