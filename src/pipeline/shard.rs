//! Job arrays: `turf run SCENE --shard I/N` runs the I-th of N slices of the scene's work
//! items ([`super::items`]; work item j, counted from 0, belongs to slice j mod N + 1, so
//! neighbouring sweep values, often of similar cost, go to different slices) and writes
//! [`MANIFEST`] (the scene, the slice, each item's outcome) after every item;
//! `turf merge DIR...` checks that the folders hold all N slices of one scene with every
//! item done, copies them into one output folder, runs the ensembles' reductions and writes
//! the summary a serial run writes ([`super::items::assemble`]).

use super::items::{assemble, outcome_line, run_item, Item, Items, Outcome};
use super::{points, say, RunOptions, RunReport};
use crate::report::{write_json, ReportError};
use crate::scene::{self, Loaded, SceneError};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The manifest a shard writes into its output folder.
pub const MANIFEST: &str = "shard.json";

/// `--shard I/N`: the I-th (1 ≤ I ≤ N) of N slices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// I, from 1
    pub index: usize,
    /// N
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let parse = |part: Option<&str>| part.and_then(|p| p.trim().parse::<usize>().ok());
        let mut parts = s.split('/');
        let (index, count) = match (parse(parts.next()), parse(parts.next()), parts.next()) {
            (Some(i), Some(n), None) => (i, n),
            _ => {
                return Err(format!(
                    "--shard {s}: expected I/N, two whole numbers with 1 ≤ I ≤ N (the I-th of \
                     N slices), e.g. --shard 1/4"
                ))
            }
        };
        if count == 0 || index == 0 || index > count {
            return Err(format!(
                "--shard {s}: I must lie in 1..=N (1..={count}), N ≥ 1, e.g. --shard 1/{}",
                count.max(1)
            ));
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// Whether work item `j` (counted from 0) is in this slice.
    pub fn takes(&self, j: usize) -> bool {
        j % self.count == self.index - 1
    }
}

/// What a shard ran, as [`MANIFEST`] keeps it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Manifest {
    /// the turf version that ran
    pub turf_version: String,
    /// the build that ran ([`crate::BUILD`]; empty in a manifest written before it was kept)
    #[serde(default)]
    pub turf_build: String,
    /// the scene file, absolute
    pub scene: PathBuf,
    /// the `--set` overrides
    pub set: Vec<String>,
    /// `I/N`
    pub shard: String,
    /// the work items of the slice
    pub items: usize,
    /// the outcome of each item run, in the order they finished
    pub outcomes: Vec<Outcome>,
    /// whether every item of the slice has an outcome
    pub complete: bool,
}

/// Run the slice `shard` of the work items of `loaded` (read from `file` with `set`) into
/// the output folder, writing [`MANIFEST`] after every item. `Err` only when a file could
/// not be written.
pub fn run_shard(
    loaded: &Loaded,
    file: &Path,
    set: &[String],
    shard: Shard,
    opts: &RunOptions,
) -> Result<Manifest, ReportError> {
    let out_dir = scene::output_dir(&loaded.base, opts.out.as_deref());
    super::create_dir(&out_dir)?;
    let points = points(loaded, &out_dir);
    let mine: Vec<Item> = Items::of(&points)
        .work
        .into_iter()
        .enumerate()
        .filter_map(|(j, item)| shard.takes(j).then_some(item))
        .collect();
    let mut manifest = Manifest {
        turf_version: env!("CARGO_PKG_VERSION").into(),
        turf_build: crate::BUILD.into(),
        scene: std::path::absolute(file).unwrap_or_else(|_| file.to_path_buf()),
        set: set.to_vec(),
        shard: shard.to_string(),
        items: mine.len(),
        outcomes: Vec::new(),
        complete: mine.is_empty(),
    };
    let path = out_dir.join(MANIFEST);
    write_json(&path, &manifest)?;
    let swept = loaded.base.scene.sweep.is_some();
    for item in mine {
        if crate::interrupt::requested() {
            break;
        }
        let outcome = run_item(&points, item, opts)?;
        let done = manifest.outcomes.len() + 1;
        say(None, &outcome_line(&outcome, swept, done, manifest.items));
        manifest.outcomes.push(outcome);
        manifest.complete = manifest.outcomes.len() == manifest.items;
        write_json(&path, &manifest)?;
    }
    Ok(manifest)
}

/// Why shards could not be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// the folders are not the N slices of one scene, or items are missing
    #[error("{0}")]
    Shards(String),
    /// the scene the shards ran could not be loaded
    #[error("the shards' scene: {0}")]
    Scene(#[from] SceneError),
    /// a file could not be read or written
    #[error(transparent)]
    Report(#[from] ReportError),
}

/// The manifest in `dir`.
fn read_manifest(dir: &Path) -> Result<Manifest, MergeError> {
    let path = dir.join(MANIFEST);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        MergeError::Shards(format!(
            "{}: {e}: not the output folder of `turf run SCENE --shard I/N`",
            path.display()
        ))
    })?;
    serde_json::from_str(&text)
        .map_err(|e| MergeError::Shards(format!("{}: not a shard manifest: {e}", path.display())))
}

/// Merge the shards in `dirs` into `out` (default: the scene's output folder): every slice
/// of one scene must be there with every item done; the ensembles are reduced here. A point
/// that failed is reported in the summary as a serial run reports it.
pub fn merge(
    dirs: &[PathBuf],
    out: Option<&Path>,
    opts: &RunOptions,
) -> Result<RunReport, MergeError> {
    let shards = dirs
        .iter()
        .map(|d| read_manifest(d).map(|m| (d, m)))
        .collect::<Result<Vec<_>, _>>()?;
    let Some((_, first)) = shards.first() else {
        return Err(MergeError::Shards(
            "turf merge needs the shards' folders".into(),
        ));
    };
    let mut slices = BTreeSet::new();
    let mut count = 0;
    for (dir, m) in &shards {
        if m.scene != first.scene || m.set != first.set {
            return Err(MergeError::Shards(format!(
                "{} ran {} {:?}, {} ran {} {:?}: shards of one scene only",
                dir.display(),
                m.scene.display(),
                m.set,
                dirs[0].display(),
                first.scene.display(),
                first.set
            )));
        }
        if m.turf_build != crate::BUILD {
            let ran = if m.turf_build.is_empty() {
                "an older turf".to_string()
            } else {
                format!("turf {}", m.turf_build)
            };
            return Err(MergeError::Shards(format!(
                "{} was run by {ran}, this is turf {}: results kept by one build are not \
                 reused by another (the merge would compute them again); merge with the \
                 binary that ran the shards, or re-run the shards with this one",
                dir.display(),
                crate::BUILD
            )));
        }
        let shard: Shard = m.shard.parse().map_err(MergeError::Shards)?;
        count = shard.count;
        if shard.count
            != first
                .shard
                .parse::<Shard>()
                .map_err(MergeError::Shards)?
                .count
        {
            return Err(MergeError::Shards(format!(
                "{} is shard {}, {} is shard {}: all must be slices of the same N",
                dir.display(),
                m.shard,
                dirs[0].display(),
                first.shard
            )));
        }
        if !slices.insert(shard.index) {
            return Err(MergeError::Shards(format!(
                "shard {} is given twice ({})",
                m.shard,
                dir.display()
            )));
        }
    }
    let missing: Vec<String> = (1..=count)
        .filter(|i| !slices.contains(i))
        .map(|i| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        return Err(MergeError::Shards(format!(
            "shard(s) {} missing: merge needs all {count} slices",
            missing.join(", ")
        )));
    }
    let loaded = scene::load(&first.scene, &first.set)?;
    let out_dir = out.map_or_else(|| scene::output_dir(&loaded.base, None), Path::to_path_buf);
    for (dir, _) in &shards {
        copy_tree(dir, &out_dir, true)?;
    }
    let points = points(&loaded, &out_dir);
    let items = Items::of(&points);
    let done: BTreeMap<Item, &Outcome> = shards
        .iter()
        .flat_map(|(_, m)| m.outcomes.iter().map(|o| (o.item, o)))
        .collect();
    let swept = loaded.base.scene.sweep.is_some();
    let not_done: Vec<String> = items
        .work
        .iter()
        .enumerate()
        .filter(|(_, item)| !done.contains_key(item))
        .map(|(j, item)| format!("{} (shard {}/{count})", item.label(swept), j % count + 1))
        .collect();
    if !not_done.is_empty() {
        return Err(MergeError::Shards(format!(
            "{} item(s) not done: {}; re-run those shards with `turf run {} --shard I/{count} \
             --out DIR` into their folders (they run only what is missing), then merge again",
            not_done.len(),
            not_done.join(", "),
            first.scene.display()
        )));
    }
    let mut outcomes: BTreeMap<usize, Outcome> = done
        .values()
        .filter(|o| matches!(o.item, Item::Point { .. }))
        .map(|o| (o.item.point(), (*o).clone()))
        .collect();
    for (n, item) in items.reductions.iter().enumerate() {
        let outcome = super::items::run_item(&points, *item, opts)?;
        say(
            None,
            &format!(
                "reduction {}",
                outcome_line(&outcome, swept, n + 1, items.reductions.len())
            ),
        );
        outcomes.insert(item.point(), outcome);
    }
    Ok(assemble(&loaded, &out_dir, &outcomes)?)
}

/// Copy the files under `from` into `to`, leaving out a shard's own [`MANIFEST`],
/// `summary.json` and `report.md` at the top (`top`); nothing when both are the same folder.
fn copy_tree(from: &Path, to: &Path, top: bool) -> Result<(), ReportError> {
    let io = |path: &Path| {
        let path = path.display().to_string();
        move |cause| ReportError::Io { path, cause }
    };
    if top && from.canonicalize().ok() == to.canonicalize().ok() {
        return Ok(());
    }
    std::fs::create_dir_all(to).map_err(io(to))?;
    for entry in std::fs::read_dir(from).map_err(io(from))? {
        let entry = entry.map_err(io(from))?;
        let (src, name) = (entry.path(), entry.file_name());
        if top && [MANIFEST, "summary.json", "report.md"].contains(&name.to_str().unwrap_or("")) {
            continue;
        }
        let dst = to.join(&name);
        if entry.file_type().map_err(io(&src))?.is_dir() {
            copy_tree(&src, &dst, false)?;
        } else {
            std::fs::copy(&src, &dst).map_err(io(&dst))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_refuse_by_argument() {
        let s: Shard = "2/3".parse().unwrap();
        assert_eq!((s.index, s.count), (2, 3));
        assert_eq!(s.to_string(), "2/3");
        assert!(s.takes(1) && s.takes(4) && !s.takes(0) && !s.takes(2));
        for bad in ["3/2", "0/2", "1/0", "x", "1/2/3", "1", "-1/2"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert!(e.starts_with(&format!("--shard {bad}: ")), "{e}");
        }
        assert!("3/2"
            .parse::<Shard>()
            .unwrap_err()
            .contains("I must lie in 1..=N (1..=2)"));
    }

    #[test]
    fn every_item_is_in_exactly_one_slice() {
        for count in 1..5 {
            for j in 0..20 {
                let takers = (1..=count)
                    .filter(|&index| Shard { index, count }.takes(j))
                    .count();
                assert_eq!(takers, 1);
            }
        }
    }
}
