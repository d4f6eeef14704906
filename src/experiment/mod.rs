//! Experiments: reading measured indentation records and fitting the seed's quasi-rheological
//! model (§2.3, eqs. 2.1–2.7) to them — the `turf fit-indentation` command.
//!
//! - [`record`]: the record formats (CSV with unit-carrying columns, the nanoindenter text
//!   export) and their validation.
//! - [`indentation_fit`]: K₁, K₂, η by Levenberg–Marquardt on the plate displacement, with
//!   standard errors, τ (2.5) and the seed's slope checks (2.6, 2.7).
//! - [`read_record`] and [`write_outputs`]: the file side (`fit.json`, `fit.csv`, plots).

pub mod indentation_fit;
pub mod record;

use crate::report::plot::{Plot, Series};
use crate::report::{csv::Table, write_json, ReportError};
use indentation_fit::IndentationFit;
use record::{IndentationRecord, RecordError};
use std::path::{Path, PathBuf};

/// Read and validate a record file (UTF-8 or Latin-1).
pub fn read_record(path: &Path) -> Result<IndentationRecord, RecordError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| RecordError {
        source_name: name.clone(),
        line: None,
        column: None,
        reason: e.to_string(),
    })?;
    record::parse_record(&record::decode(&bytes), &name)
}

/// The default output folder of `turf fit-indentation DATA`: `runs/fit_<file stem>`.
pub fn default_out_dir(data: &Path) -> PathBuf {
    let stem = data
        .file_stem()
        .map_or("record".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from("runs").join(format!("fit_{stem}"))
}

/// What `fit.json` holds: the input, the fit, and the files written.
#[derive(Debug, serde::Serialize)]
pub struct FitSummary<'a> {
    /// the turf version that fitted
    pub turf_version: &'static str,
    /// the record file
    pub file: String,
    /// its format
    pub format: record::Format,
    /// the header names of the time, load and displacement columns used
    pub columns: &'a [String; 3],
    /// the fit
    pub fit: &'a IndentationFit,
    /// files written, relative to the output folder
    pub files: Vec<String>,
}

/// Write `fit.csv` (measured against fitted), `plots/fit_time.svg|png` (displacement against
/// time), `plots/fit_load.svg|png` (load against displacement) and `plots/fit_residual.svg|png`,
/// then `fit.json`.
pub fn write_outputs(
    data: &Path,
    record: &IndentationRecord,
    fit: &IndentationFit,
    dir: &Path,
) -> Result<serde_json::Value, ReportError> {
    let residual: Vec<f64> = record
        .displacement
        .iter()
        .zip(&fit.fitted_displacement)
        .map(|(y, f)| y - f)
        .collect();
    Table::new()
        .column("time_s", record.time.clone())
        .column("load_nN", record.load.clone())
        .column("displacement_nm", record.displacement.clone())
        .column("fitted_displacement_nm", fit.fitted_displacement.clone())
        .column("residual_nm", residual.clone())
        .write(&dir.join("fit.csv"))?;
    let plots = dir.join("plots");
    Plot::new(
        "Indentation record and fitted quasi-rheological model",
        "time (s)",
        "displacement (nm)",
    )
    .with(Series::points(
        "record",
        record.time.clone(),
        record.displacement.clone(),
    ))
    .with(Series::line(
        "fit (seed 2.1-2.7)",
        record.time.clone(),
        fit.fitted_displacement.clone(),
    ))
    .write(&plots, "fit_time")?;
    Plot::new(
        "Load against displacement: record and fit",
        "displacement (nm)",
        "applied load (nN)",
    )
    .with(Series::points(
        "record",
        record.displacement.clone(),
        record.load.clone(),
    ))
    .with(Series::line(
        "fit (seed 2.1-2.7)",
        fit.fitted_displacement.clone(),
        record.load.clone(),
    ))
    .write(&plots, "fit_load")?;
    Plot::new(
        "Displacement residual (record - fit)",
        "time (s)",
        "residual (nm)",
    )
    .with(Series::points(
        "record - fit",
        record.time.clone(),
        residual,
    ))
    .write(&plots, "fit_residual")?;
    let files = [
        "fit.json",
        "fit.csv",
        "plots/fit_time.svg",
        "plots/fit_time.png",
        "plots/fit_load.svg",
        "plots/fit_load.png",
        "plots/fit_residual.svg",
        "plots/fit_residual.png",
    ];
    let summary = FitSummary {
        turf_version: env!("CARGO_PKG_VERSION"),
        file: data.display().to_string(),
        format: record.format,
        columns: &record.columns,
        fit,
        files: files.iter().map(|s| s.to_string()).collect(),
    };
    let path = dir.join("fit.json");
    write_json(&path, &summary)?;
    serde_json::to_value(&summary).map_err(|e| ReportError::Invalid {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}
