//! What a stage hands to the stages after it: typed results in memory — the discrete stage's
//! compression branches to `homogenize`, the homogenize stage's card to `continuum` — rather
//! than files read back from the output folder. The files are written for the user and for the
//! cache; a stage reused from the cache hands over its cache entry ([`Handoff::Cached`]), read
//! when a later stage asks for it ([`Handoff::read`]) — the one place a hand-over is read from
//! disk.

use super::{ensemble, StageRecord};
use crate::homogenize::card::{CardError, MaterialCard};
use crate::homogenize::curve_analysis::Branch;
use crate::report::csv::{split_fields, strip_bom, UnclosedQuote};
use crate::scene::Stage;
use std::path::{Path, PathBuf};

/// The files of a turf's branches (a realisation's, in its folder) as the discrete stage writes
/// them for the user and the cache: strain and stress (GPa), strain ascending.
pub const LOADING_CSV: &str = "stress_strain_loading.csv";
/// See [`LOADING_CSV`].
pub const UNLOADING_CSV: &str = "stress_strain_unloading.csv";
/// The ensemble's mean loading branch, what homogenize fits for N > 1.
pub const ENSEMBLE_LOADING_CSV: &str = "ensemble_stress_strain_loading.csv";
/// The ensemble's mean unloading branch.
pub const ENSEMBLE_UNLOADING_CSV: &str = "ensemble_stress_strain_unloading.csv";

/// Why a cached stage's hand-over could not be read back from its cache entry.
#[derive(Debug, thiserror::Error)]
pub enum HandoffError {
    /// a file of the entry could not be read
    #[error("{path}: {cause}")]
    Io {
        /// the file
        path: PathBuf,
        /// the cause
        cause: std::io::Error,
    },
    /// a branch file without the columns the discrete stage writes
    #[error("{}: expected the columns strain, stress_GPa; found {found:?}", path.display())]
    Columns {
        /// the file
        path: PathBuf,
        /// the header found
        found: Vec<String>,
    },
    /// a row that is not two numbers
    #[error("{}: row {row}: not two numbers: {line}", path.display())]
    Row {
        /// the file
        path: PathBuf,
        /// the row (1 = the first after the header)
        row: usize,
        /// the row's text
        line: String,
    },
    /// a row with an unclosed quote
    #[error("{}: {cause}", path.display())]
    Quote {
        /// the file
        path: PathBuf,
        /// the cause
        cause: UnclosedQuote,
    },
    /// the card could not be read
    #[error(transparent)]
    Card(#[from] CardError),
}

/// A cached stage's hand-over that could not be read back.
#[derive(Debug, thiserror::Error)]
#[error(
    "the {stage} stage's cache entry {} could not be read back ({cause}); delete it to \
     recompute the stage",
    entry.display()
)]
pub struct CachedHandoffError {
    /// the stage
    pub stage: Stage,
    /// the entry's folder
    pub entry: PathBuf,
    /// what went wrong
    pub cause: HandoffError,
}

/// A branch of a compression curve and the file (relative to the output folder) that holds
/// it for the user.
#[derive(Debug, Clone, PartialEq)]
pub struct Filed {
    /// the file, relative to the output folder
    pub file: PathBuf,
    /// nominal strain and stress (GPa), strain ascending
    pub branch: Branch,
}

/// The loading branch and, if the turf was unloaded, the unloading branch.
#[derive(Debug, Clone, PartialEq)]
pub struct Curves {
    /// loading branch
    pub loading: Filed,
    /// unloading branch
    pub unloading: Option<Filed>,
}

/// The discrete stage's compression curves.
#[derive(Debug, Clone, PartialEq)]
pub struct Compression {
    /// what a card is fitted to: the run's branches, or an ensemble's mean over the
    /// realisations that finished
    pub fitted: Curves,
    /// an ensemble's finished realisations, each with its own branches, in realisation order
    /// (empty for a single turf)
    pub realisations: Vec<(usize, Curves)>,
}

/// A stage's result for the stages after it.
#[derive(Debug, Clone)]
pub enum Handoff {
    /// the discrete stage's compression curves
    Compression(Compression),
    /// the homogenize stage's material card
    Card(MaterialCard),
    /// a stage reused from the cache: its record and `files`, the cache entry's copies of the
    /// files it wrote
    Cached {
        /// the stage's record
        record: StageRecord,
        /// the entry's folder of files
        files: PathBuf,
    },
}

impl Handoff {
    /// What this hands over, a cached stage's read from its cache entry; `None` for a stage
    /// that hands nothing over (a discrete stage that compressed no turf: explicit rods,
    /// lateral or shear tests).
    pub fn read(&self) -> Result<Option<Handoff>, CachedHandoffError> {
        let Handoff::Cached { record, files } = self else {
            return Ok(Some(self.clone()));
        };
        let read = match record.stage {
            Stage::Discrete => compression_in(record, files).map(|c| c.map(Handoff::Compression)),
            Stage::Homogenize => crate::homogenize::read_card(&files.join("material.json"))
                .map(|c| Some(Handoff::Card(c)))
                .map_err(HandoffError::from),
            Stage::Theory | Stage::Halfspace | Stage::Continuum => Ok(None),
        };
        read.map_err(|cause| CachedHandoffError {
            stage: record.stage,
            entry: files.parent().unwrap_or(files).to_path_buf(),
            cause,
        })
    }

    /// The stage that handed this over.
    pub fn stage(&self) -> Stage {
        match self {
            Handoff::Compression(_) => Stage::Discrete,
            Handoff::Card(_) => Stage::Homogenize,
            Handoff::Cached { record, .. } => record.stage,
        }
    }
}

/// The compression curves among the files of a discrete stage's `record` (read from `files`).
fn compression_in(record: &StageRecord, files: &Path) -> Result<Option<Compression>, HandoffError> {
    let listed = |name: &str| record.files.iter().any(|f| Path::new(f) == Path::new(name));
    let read = |file: PathBuf| -> Result<Filed, HandoffError> {
        let branch = read_branch(&files.join(&file))?;
        Ok(Filed { file, branch })
    };
    let curves = |loading: &str, unloading: &str| -> Result<Curves, HandoffError> {
        Ok(Curves {
            loading: read(loading.into())?,
            unloading: listed(unloading)
                .then(|| read(unloading.into()))
                .transpose()?,
        })
    };
    if listed(ENSEMBLE_LOADING_CSV) {
        let mut realisations = Vec::new();
        for f in &record.files {
            let f = Path::new(f);
            if let Some(k) = ensemble::realisation_of(f, LOADING_CSV) {
                let unloading = f.with_file_name(UNLOADING_CSV);
                let unloading = listed(&unloading.display().to_string())
                    .then(|| read(unloading))
                    .transpose()?;
                let loading = read(f.to_path_buf())?;
                realisations.push((k, Curves { loading, unloading }));
            }
        }
        let fitted = curves(ENSEMBLE_LOADING_CSV, ENSEMBLE_UNLOADING_CSV)?;
        return Ok(Some(Compression {
            fitted,
            realisations,
        }));
    }
    if !listed(LOADING_CSV) {
        return Ok(None);
    }
    Ok(Some(Compression {
        fitted: curves(LOADING_CSV, UNLOADING_CSV)?,
        realisations: Vec::new(),
    }))
}

/// A branch file as the discrete stage writes it: columns `strain` and `stress_GPa`.
fn read_branch(path: &Path) -> Result<Branch, HandoffError> {
    let text = std::fs::read_to_string(path).map_err(|cause| HandoffError::Io {
        path: path.to_path_buf(),
        cause,
    })?;
    let split = |line: &str| {
        split_fields(line, ',').map_err(|cause| HandoffError::Quote {
            path: path.to_path_buf(),
            cause,
        })
    };
    let mut lines = strip_bom(&text).lines().filter(|l| !l.trim().is_empty());
    let header = split(lines.next().unwrap_or_default())?;
    if header != ["strain", "stress_GPa"] {
        return Err(HandoffError::Columns {
            path: path.to_path_buf(),
            found: header,
        });
    }
    let mut branch = Branch {
        strain: Vec::new(),
        stress: Vec::new(),
    };
    for (row, line) in lines.enumerate() {
        let fields = split(line)?;
        let number = |i: usize| {
            fields
                .get(i)
                .and_then(|f| f.parse().ok())
                .ok_or_else(|| HandoffError::Row {
                    path: path.to_path_buf(),
                    row: row + 1,
                    line: line.to_string(),
                })
        };
        branch.strain.push(number(0)?);
        branch.stress.push(number(1)?);
    }
    Ok(branch)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(files: &[&str]) -> StageRecord {
        StageRecord {
            stage: Stage::Discrete,
            wall_time_s: 0.0,
            evaluations: 0,
            values: Default::default(),
            files: files.iter().map(|f| f.to_string()).collect(),
            cached: true,
            cache_key: None,
            warnings: Vec::new(),
        }
    }

    fn write(dir: &Path, file: &str, branch: &Branch) {
        let table = crate::report::csv::Table::new()
            .column("strain", branch.strain.clone())
            .column("stress_GPa", branch.stress.clone());
        table.write(&dir.join(file)).unwrap();
    }

    /// The branches read from a cache entry are the branches written, bit for bit (the CSV
    /// holds each number's shortest round-trip form), with their files and realisations.
    #[test]
    fn an_ensemble_is_read_back_exactly_from_its_files() {
        let dir = std::env::temp_dir().join(format!("turf-handoff-{}", std::process::id()));
        let b = |k: f64| Branch {
            strain: vec![0.0, 0.1 / 3.0, 0.2],
            stress: vec![0.0, k * std::f64::consts::PI * 1e-3, k * 2e-3],
        };
        let r1 = format!("realisations/r001/{LOADING_CSV}");
        std::fs::create_dir_all(dir.join("realisations/r001")).unwrap();
        write(&dir, ENSEMBLE_LOADING_CSV, &b(1.5));
        write(&dir, LOADING_CSV, &b(1.0));
        write(&dir, &r1, &b(2.0));
        let rec = record(&[
            LOADING_CSV,
            &r1,
            ENSEMBLE_LOADING_CSV,
            "discrete_ensemble.csv",
        ]);
        let cached = |record: StageRecord| Handoff::Cached {
            record,
            files: dir.clone(),
        };
        let Some(Handoff::Compression(c)) = cached(rec).read().unwrap() else {
            panic!("no compression handed over");
        };
        assert_eq!(c.fitted.loading.branch, b(1.5));
        assert_eq!(c.fitted.loading.file, PathBuf::from(ENSEMBLE_LOADING_CSV));
        assert!(c.fitted.unloading.is_none());
        let ks: Vec<usize> = c.realisations.iter().map(|(k, _)| *k).collect();
        assert_eq!(ks, [0, 1]);
        assert_eq!(c.realisations[1].1.loading.branch, b(2.0));
        assert_eq!(c.realisations[1].1.loading.file, PathBuf::from(&r1));
        // a record without a compression curve hands nothing over
        let none = cached(record(&["rods.csv"])).read().unwrap();
        assert!(none.is_none());
        // an entry that does not hold what its record lists is an error naming the entry
        let broken = cached(record(&[
            "realisations/r002/stress_strain_loading.csv",
            ENSEMBLE_LOADING_CSV,
        ]));
        let e = broken.read().unwrap_err().to_string();
        assert!(e.contains("cache entry") && e.contains("r002"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
