//! Fuzzing the readers of user files: the scene TOML reader (with `--set` overrides) and the CSV
//! readers (stress–strain curve, relaxation curve, indentation record). Every input must give
//! a value or an error, never a panic, and an accepted curve or record holds finite numbers only.
//!
//! Two forms share the strategies: a fast property test CI runs (a few cases per strategy), and
//! the long run, `#[ignore]`d, which loops over every strategy with fresh random seeds until a
//! wall-time budget is spent and prints the case counts:
//!
//! ```text
//! TURF_FUZZ_SECONDS=1800 cargo test --test integration reader_fuzz::long -- --ignored --nocapture
//! ```
//!
//! A failure is shrunk by proptest and printed as the minimal input; keep it as a regression
//! test in the module of the reader it broke.

use crate::scene_props::{check, check_set, mutated_scene, set_argument, TOML_LIKE};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::time::{Duration, Instant};
use turf::experiment::record::parse_record;
use turf::homogenize::curve::{RelaxationCurve, StressStrainCurve};

/// Column names a reader knows, mixed with near misses and garbage.
const COLUMN_NAMES: [&str; 16] = [
    "strain",
    "strain_nominal",
    "lateral_strain",
    "stress_GPa",
    "stress_MPa",
    "stress_kPa",
    "stress_Pa",
    "time_s",
    "g",
    "Depth (nm)",
    "Load (uN)",
    "Time (s)",
    "depth_nm",
    "load_mN",
    "\"stress, MPa\"",
    "Stress_mpa",
];

/// One CSV field: a plain, odd, quoted, empty or non-finite number, or text.
fn field() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (0.0f64..1.0).prop_map(|x| format!("{x}")),
        2 => any::<f64>().prop_map(|x| format!("{x:e}")),
        1 => prop::sample::select(vec![
            "", "nan", "inf", "-inf", "1e400", "-0", "0x10", "1,5", "\"0.1\"", "\"", "\"\"\"",
            " 3 ", "1e-320", "+.5", "5.", "--1",
        ])
        .prop_map(str::to_string),
        1 => "[-0-9a-zA-Z .e\"]{0,6}",
    ]
}

/// A CSV text: an optional BOM and comment, a header from [`COLUMN_NAMES`], rows of
/// [`field`]s with the header's width (or not), separated by commas or tabs.
fn csv_text() -> impl Strategy<Value = String> {
    (
        any::<bool>(),
        any::<bool>(),
        prop::sample::select(vec![",", "\t", ", "]),
        prop::collection::vec(prop::sample::select(COLUMN_NAMES.to_vec()), 0..4),
        prop::collection::vec(prop::collection::vec(field(), 0..5), 0..12),
    )
        .prop_map(|(bom, comment, sep, header, rows)| {
            let mut text = String::new();
            if bom {
                text.push('\u{feff}');
            }
            if comment {
                text.push_str("# fuzz\n");
            }
            text.push_str(&header.join(sep));
            for row in rows {
                text.push('\n');
                text.push_str(&row.join(sep));
            }
            text
        })
}

/// A valid stress–strain CSV with its numbers perturbed: rows sorted or not, scaled by wild
/// factors (the path past the parser into validation).
fn near_valid_curve() -> impl Strategy<Value = String> {
    (
        prop::sample::select(vec!["stress_GPa", "stress_MPa", "stress_Pa"]),
        prop::collection::vec((0.0f64..1.2, -0.1f64..1.0), 0..14),
        prop::sample::select(vec![1.0, 1e-300, 1e300, -1.0, 0.0]),
        any::<bool>(),
    )
        .prop_map(|(unit, points, scale, lateral)| {
            let mut text = format!("strain,{unit}");
            if lateral {
                text.push_str(",lateral_strain");
            }
            for (i, (e, s)) in points.iter().enumerate() {
                text.push_str(&format!("\n{},{}", e * i as f64 / 10.0, s * scale));
                if lateral {
                    text.push_str(&format!(",{}", 0.3 * e));
                }
            }
            text
        })
}

/// Feed `text` to every CSV reader; what one accepts must hold finite numbers only.
fn check_csv(text: &str) {
    if let Ok(c) = StressStrainCurve::from_csv(text, "fuzz.csv") {
        let all = c.strain.iter().chain(&c.stress);
        assert!(all
            .chain(c.lateral_strain.iter().flatten())
            .all(|x| x.is_finite()));
    }
    if let Ok(c) = RelaxationCurve::from_csv(text, "fuzz.csv") {
        assert!(c.time.iter().chain(&c.value).all(|x| x.is_finite()));
    }
    let _ = parse_record(text, "fuzz.txt");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn csv_readers_never_panic(text in csv_text()) {
        check_csv(&text);
    }

    #[test]
    fn near_valid_curves_never_panic(text in near_valid_curve()) {
        check_csv(&text);
    }
}

/// Run `cases` cases of `strategy` through `test` with a fresh random seed; the number run.
fn batch<S: Strategy>(strategy: S, cases: u32, test: impl Fn(S::Value)) -> u64
where
    S::Value: std::fmt::Debug,
{
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    if let Err(e) = runner.run(&strategy, |v| {
        test(v);
        Ok(())
    }) {
        panic!("fuzz failure: {e}");
    }
    u64::from(cases)
}

/// Cases per strategy between checks of the wall-time budget.
const BATCH: u32 = 2000;

#[test]
#[ignore = "long fuzz run: TURF_FUZZ_SECONDS (default 1800) of wall time"]
fn long() {
    let budget = std::env::var("TURF_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1800);
    let clock = Instant::now();
    let mut counts = [0u64; 6];
    while clock.elapsed() < Duration::from_secs(budget) {
        counts[0] += batch("\\PC{0,300}", BATCH, |t: String| check(&t));
        counts[1] += batch(TOML_LIKE, BATCH, |t: String| check(&t));
        counts[2] += batch(mutated_scene(), BATCH, |t| check(&t));
        counts[3] += batch(set_argument(), BATCH, |(w, a)| check_set(w, &a));
        counts[4] += batch(csv_text(), BATCH, |t| check_csv(&t));
        counts[5] += batch(near_valid_curve(), BATCH, |t| check_csv(&t));
        eprintln!(
            "{:.0} s: cases arbitrary text {}, TOML-like {}, mutated scenes {}, --set {}, CSV {}, near-valid curves {}",
            clock.elapsed().as_secs_f64(),
            counts[0],
            counts[1],
            counts[2],
            counts[3],
            counts[4],
            counts[5]
        );
    }
    eprintln!("total cases: {}", counts.iter().sum::<u64>());
}
