//! The sweep across its points: what a parameter study reads first. One row per swept value
//! (`sweep.csv`), its columns the swept value in internal units and every stage value that
//! every point reports (`<stage>.<name>`, the name carrying its unit), and a plot against the
//! swept value of each headline value that every point has — the discrete stage's peak
//! stress, E⁰ and σ₀ of the fitted (5.1), a pull-off — drawn with the 95 % band of the
//! ensemble's mean where the points are ensembles (`turf.realisations` > 1).

use super::{say, Summary, SweepSummary};
use crate::report::csv::Table;
use crate::report::plot::{Plot, Series};
use std::collections::BTreeMap;
use std::path::Path;

/// The cross-point table's file name.
pub const SWEEP_CSV: &str = "sweep.csv";

/// Values plotted against the swept value, as (name without its unit, unit suffix).
const HEADLINE: [(&str, &str); 5] = [
    ("peak_stress", "_GPa"),
    ("tangent_e0", "_GPa"),
    ("sigma0", "_GPa"),
    ("pull_off", "_nN"),
    ("pull_off_normalized", ""),
];

/// Every point's values, flattened to `<stage>.<name>`.
fn point_values(sweep: &SweepSummary) -> Vec<BTreeMap<String, f64>> {
    sweep
        .points
        .iter()
        .map(|p| {
            p.stages
                .iter()
                .flat_map(|s| {
                    let stage = s.stage.name();
                    s.values
                        .iter()
                        .map(move |(k, v)| (format!("{stage}.{k}"), *v))
                })
                .collect()
        })
        .collect()
}

/// The columns every point has: the swept value `x` ([`abscissa`]), then each
/// `<stage>.<name>` that every point reports.
fn table(sweep: &SweepSummary, x: &(String, Vec<f64>)) -> Table {
    let values = point_values(sweep);
    let mut t = Table::new().column(&x.0, x.1.clone());
    if let Some((first, rest)) = values.split_first() {
        for name in first
            .keys()
            .filter(|k| rest.iter().all(|r| r.contains_key(*k)))
        {
            t = t.column(name, values.iter().map(|v| v[name]).collect());
        }
    }
    t
}

/// The swept value of each point in internal units, named after the key, or the point's index
/// where a value has no number.
fn abscissa(sweep: &SweepSummary) -> (String, Vec<f64>) {
    let numbers: Option<Vec<f64>> = sweep.points.iter().map(|p| p.value_internal).collect();
    match numbers {
        Some(v) => (sweep.key.clone(), v),
        None => (
            "point".into(),
            (0..sweep.points.len()).map(|i| i as f64).collect(),
        ),
    }
}

/// Write `sweep.csv` and the headline plots into `out_dir`; returns the files written. A file
/// that cannot be written is said on stderr and skipped: the points' own results are kept.
pub fn write(summary: &Summary, out_dir: &Path) -> Vec<String> {
    let Some(sweep) = &summary.sweep else {
        return Vec::new();
    };
    if sweep.points.is_empty() {
        return Vec::new();
    }
    let x = abscissa(sweep);
    let t = table(sweep, &x);
    let mut files = Vec::new();
    match t.write(&out_dir.join(SWEEP_CSV)) {
        Ok(()) => files.push(SWEEP_CSV.to_string()),
        Err(e) => say(None, &format!("warning: {SWEEP_CSV} not written: {e}")),
    }
    if summary.scene["output"]["plots"].as_bool() == Some(false) {
        return files;
    }
    let mut warnings = Vec::new();
    for (stage, name, plot) in plots(sweep, &t, &x) {
        let stem = format!("sweep_{stage}_{name}");
        files.extend(plot.write_or_warn(&out_dir.join("plots"), &stem, "plots", &mut warnings));
    }
    for w in warnings {
        say(None, &format!("warning: sweep: {w}"));
    }
    files
}

/// One plot per headline value every point has, per stage of the first point: the value
/// against the swept one, with the ensemble's mean and band when every point has them.
fn plots(sweep: &SweepSummary, t: &Table, x: &(String, Vec<f64>)) -> Vec<(String, String, Plot)> {
    let stages = sweep.points.first().map_or(&[][..], |p| &p.stages[..]);
    let mut out = Vec::new();
    for stage in stages.iter().map(|s| s.stage.name()) {
        for (base, unit) in HEADLINE {
            let col = |name: &str| t.get(&format!("{stage}.{name}")).map(<[f64]>::to_vec);
            let mean = col(&format!("ensemble_{base}_mean{unit}"));
            let band = col(&format!("ensemble_{base}_ci95_low{unit}"))
                .zip(col(&format!("ensemble_{base}_ci95_high{unit}")));
            let single = col(&format!("{base}{unit}"));
            let label = format!("{base}{unit}");
            let x_label = format!("{} (internal units: nm, nN, s, GPa, J/m^2)", x.0);
            let title = format!("{stage}: {label} across the sweep");
            let mut plot = Plot::new(&title, &x_label, &label);
            match (mean, band, single) {
                (Some(m), Some((lo, hi)), _) => {
                    plot = plot
                        .with(Series::band("95 % interval of the mean", &x.1, &lo, &hi))
                        .with(Series::line("mean of the realisations", x.1.clone(), m));
                }
                (Some(m), None, _) => {
                    plot = plot.with(Series::line("mean of the realisations", x.1.clone(), m))
                }
                (None, _, Some(y)) => plot = plot.with(Series::line(&label, x.1.clone(), y)),
                (None, _, None) => continue,
            }
            out.push((stage.to_string(), base.to_string(), plot));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{PointSummary, StageRecord};
    use crate::scene::Stage;

    fn point(value: f64, values: &[(&str, f64)]) -> PointSummary {
        PointSummary {
            value: toml::Value::String(format!("{value} nN")),
            value_internal: Some(value),
            dir: String::new(),
            derived: Default::default(),
            stages: vec![StageRecord {
                stage: Stage::Discrete,
                wall_time_s: 1.0,
                evaluations: 1,
                values: values.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
                files: Vec::new(),
                cached: false,
                cache_key: None,
                warnings: Vec::new(),
            }],
        }
    }

    /// The table has one row per point and the columns every point reports, in the points'
    /// order; a value one point lacks (a fit that failed there) is left out, not filled.
    #[test]
    fn the_table_holds_the_values_every_point_reports() {
        let sweep = SweepSummary {
            key: "turf.vdw.gamma_line".into(),
            points: vec![
                point(0.1, &[("peak_stress_GPa", 0.004), ("tangent_e0_GPa", 0.03)]),
                point(1.0, &[("peak_stress_GPa", 0.005)]),
                point(
                    10.0,
                    &[("peak_stress_GPa", 0.003), ("tangent_e0_GPa", 0.06)],
                ),
            ],
            files: Vec::new(),
        };
        let x = abscissa(&sweep);
        let t = table(&sweep, &x);
        assert_eq!(t.get("turf.vdw.gamma_line"), Some(&[0.1, 1.0, 10.0][..]));
        assert_eq!(
            t.get("discrete.peak_stress_GPa"),
            Some(&[0.004, 0.005, 0.003][..])
        );
        assert!(t.get("discrete.tangent_e0_GPa").is_none());
        let drawn: Vec<String> = plots(&sweep, &t, &x).into_iter().map(|p| p.1).collect();
        assert_eq!(drawn, vec!["peak_stress".to_string()]);
        // a point without a number for its value: the index stands in
        let mut other = sweep.clone();
        other.points[1].value_internal = None;
        assert_eq!(abscissa(&other), ("point".to_string(), vec![0.0, 1.0, 2.0]));
    }
}
