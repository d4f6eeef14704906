//! Writing results: CSV tables, JSON summaries, plots (SVG and PNG), VTK files for ParaView and
//! the per-run Markdown report.
//!
//! Every file is written atomically ([`write_atomic`]): to a temporary file beside the target,
//! then renamed, so an interrupted run never leaves a half-written result; a write that fails
//! (a full disk) removes its temporary file. Non-finite numbers are refused before anything is
//! written. A plot is an illustration: a stage that cannot write one says so in a warning
//! ([`plot::write_or_warn`]) and keeps its other results.

pub mod csv;
pub mod markdown;
pub mod plot;
pub mod vtk;

use std::io::Write;
use std::path::Path;

/// Why a result could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// the file system refused
    #[error("cannot write {path}: {cause}")]
    Io {
        /// the file
        path: String,
        /// the cause (in the message, so not chained again as the error's source)
        cause: std::io::Error,
    },
    /// a NaN or infinite value was about to be written
    #[error("refusing to write {path}: non-finite value in {what}")]
    NonFinite {
        /// the file
        path: String,
        /// which column or field
        what: String,
    },
    /// the data is inconsistent (columns of different lengths, ...)
    #[error("cannot write {path}: {reason}")]
    Invalid {
        /// the file
        path: String,
        /// what is wrong
        reason: String,
    },
    /// the plotting backend failed
    #[error("cannot draw {path}: {reason}")]
    Plot {
        /// the file
        path: String,
        /// the backend's message
        reason: String,
    },
}

/// Write `bytes` to `path` atomically, creating parent folders.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    let io = |cause| ReportError::Io {
        path: path.display().to_string(),
        cause,
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    finish_temp(&tmp, path, written)
}

/// Rename the temporary file `tmp` onto `path` once `written` succeeded; on any failure remove
/// `tmp` (a full disk must not leave half-written temporaries behind) and name `path` and the
/// OS's reason.
pub(crate) fn finish_temp(
    tmp: &Path,
    path: &Path,
    written: std::io::Result<()>,
) -> Result<(), ReportError> {
    let result = written.and_then(|()| std::fs::rename(tmp, path));
    result.map_err(|cause| {
        let _ = std::fs::remove_file(tmp);
        ReportError::Io {
            path: path.display().to_string(),
            cause,
        }
    })
}

/// Write a JSON value atomically (pretty-printed), refusing any non-finite number.
///
/// `serde_json` turns NaN into `null` silently; this checks the value first so that a result
/// file never hides a failed computation.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> Result<(), ReportError> {
    let v = serde_json::to_value(value).map_err(|e| ReportError::Invalid {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    if let Some(field) = first_null_number(&v, String::new()) {
        return Err(ReportError::NonFinite {
            path: path.display().to_string(),
            what: field,
        });
    }
    let text = serde_json::to_string_pretty(&v).expect("a JSON value always serialises");
    write_atomic(path, text.as_bytes())
}

/// serde_json writes NaN and ±inf as `null`; a `null` where the schema has numbers is the only
/// trace. Fields that are legitimately optional are skipped by `skip_serializing_if` upstream,
/// so any null left is reported.
fn first_null_number(v: &serde_json::Value, at: String) -> Option<String> {
    match v {
        serde_json::Value::Null => Some(if at.is_empty() { "value".into() } else { at }),
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, x)| first_null_number(x, format!("{at}[{i}]"))),
        serde_json::Value::Object(o) => o.iter().find_map(|(k, x)| {
            let p = if at.is_empty() {
                k.clone()
            } else {
                format!("{at}.{k}")
            };
            first_null_number(x, p)
        }),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_removes_its_temporary_file_and_names_the_path() {
        let dir = std::env::temp_dir().join(format!("turf-report-fail-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        // a folder where the file should be: the rename onto it fails for every user
        let path = dir.join("summary.json");
        std::fs::create_dir_all(&path).unwrap();
        let e = write_atomic(&path, b"{}").unwrap_err();
        assert!(e.to_string().contains("summary.json"), "{e}");
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["summary.json"], "the temporary file is gone");
        std::fs::remove_dir_all(dir).ok();
    }

    #[test]
    fn json_with_nan_is_refused_and_nothing_is_written() {
        let dir = std::env::temp_dir().join(format!("turf-report-{}", std::process::id()));
        let path = dir.join("s.json");
        #[derive(serde::Serialize)]
        struct S {
            ok: f64,
            bad: f64,
        }
        let e = write_json(
            &path,
            &S {
                ok: 1.0,
                bad: f64::NAN,
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("bad"), "{e}");
        assert!(!path.exists());
        write_json(&path, &S { ok: 1.0, bad: 2.0 }).unwrap();
        assert!(std::fs::read_to_string(&path)
            .unwrap()
            .contains("\"bad\": 2.0"));
        std::fs::remove_dir_all(dir).ok();
    }
}
