//! The stage cache: a stage whose inputs did not change since an earlier run into the same
//! output folder is not recomputed. Cached stages: `discrete` (minutes to hours) and
//! `homogenize` (its card feeds the continuum stage).
//!
//! **Key.** The FNV-1a 64-bit hash of the canonical JSON (object keys sorted, no whitespace)
//! of: the stage, the build ([`crate::BUILD`]: the turf version and the hash of its source),
//! the resolved scene sections the stage reads (internal units, defaults filled) and the keys
//! of the cached stages it reads from. `discrete`:
//! `[turf]` (with `turf.realisations` when above 1: an ensemble is another result; a
//! one-realisation scene keeps the key it had before the ensemble existed), `[rods]`,
//! `[compression]`, `scene.seed`, `output.vtk`, `output.plots`.
//! `homogenize`: `[homogenize]`, `[viscoelastic]`, and the `discrete` key when it fits the
//! discrete curve. A change of any other key (`[mesh]`, `[adhesion]`, `[schedule]`, ...) keeps
//! the key. A binary built from other source (another version, an edited engine, other cargo
//! features) has other keys: it recomputes rather than reuse what another build computed.
//!
//! **Entry.** `cache/<stage>-<key>/`: `record.json` (the stage record, the key, and the
//! canonical inputs, compared on reuse so a hash collision cannot hand over a wrong result)
//! and `files/`, copies of every file the stage wrote (relative to the output folder). An entry
//! is written into a temporary folder and renamed, so an interrupted run leaves no half entry.
//! Reuse copies the files back into the output folder and marks the record `cached: true`.

use super::StageRecord;
use crate::report::{write_atomic, ReportError};
use crate::scene::homogenize::Curve;
use crate::scene::{ResolvedScene, Stage};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The cache's folder under the output folder.
pub const CACHE_DIR: &str = "cache";

const RECORD: &str = "record.json";
const FILES: &str = "files";

/// FNV-1a, 64 bit (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// `v` as JSON with the keys of every object sorted and no whitespace.
pub fn canonical_json(v: &Value) -> String {
    match v {
        Value::Object(map) => {
            let mut entries: Vec<(&String, &Value)> = map.iter().collect();
            entries.sort_by(|a, b| a.0.cmp(b.0));
            let body: Vec<String> = entries
                .iter()
                .map(|(k, x)| format!("{}:{}", Value::String((*k).clone()), canonical_json(x)))
                .collect();
            format!("{{{}}}", body.join(","))
        }
        Value::Array(items) => {
            let body: Vec<String> = items.iter().map(canonical_json).collect();
            format!("[{}]", body.join(","))
        }
        other => other.to_string(),
    }
}

/// A stage's cache key and the canonical inputs it hashes.
#[derive(Debug, Clone, PartialEq)]
pub struct Key {
    /// the hash, 16 hex digits
    pub hex: String,
    /// the canonical JSON of the inputs
    pub inputs: String,
}

fn to_value<T: serde::Serialize>(x: &T) -> Value {
    // the scene's sections are plain data: serialising them cannot fail
    serde_json::to_value(x).unwrap_or(Value::Null)
}

/// The key of `stage` for `scene` after the stages in `previous`, or `None` for a stage that
/// is not cached (or whose upstream stage ran without a key).
pub fn key(stage: Stage, scene: &ResolvedScene, previous: &[StageRecord]) -> Option<Key> {
    let s = &scene.scene;
    let upstream = |st: Stage| {
        previous
            .iter()
            .find(|r| r.stage == st)
            .and_then(|r| r.cache_key.clone())
    };
    let sections = match stage {
        Stage::Discrete => json!({
            "turf": to_value(&s.turf),
            "rods": to_value(&s.rods),
            "compression": to_value(&s.compression),
            "seed": s.scene.seed,
            "output": {"vtk": s.output.vtk, "plots": s.output.plots},
        }),
        Stage::Homogenize => {
            let h = s.homogenize.as_ref()?;
            let discrete = match h.curve {
                Curve::TangentLaw => Value::Null,
                Curve::Loading | Curve::Unloading => Value::String(upstream(Stage::Discrete)?),
            };
            json!({
                "homogenize": to_value(h),
                "viscoelastic": to_value(&s.viscoelastic),
                "discrete": discrete,
            })
        }
        Stage::Theory | Stage::Halfspace | Stage::Continuum => return None,
    };
    let inputs = canonical_json(&json!({
        "stage": stage.name(),
        "turf_build": crate::BUILD,
        "inputs": sections,
    }));
    Some(Key {
        hex: format!("{:016x}", fnv1a64(inputs.as_bytes())),
        inputs,
    })
}

fn entry_dir(root: &Path, stage: Stage, key: &Key) -> PathBuf {
    root.join(CACHE_DIR).join(format!("{stage}-{}", key.hex))
}

/// The entry's folder relative to the output folder, for messages.
pub fn entry_name(stage: Stage, key: &Key) -> String {
    format!("{CACHE_DIR}/{stage}-{}/", key.hex)
}

#[derive(serde::Serialize, serde::Deserialize)]
struct Entry {
    key: String,
    inputs: String,
    /// the record; its values read back exactly (serde_json's `float_roundtrip`)
    record: StageRecord,
}

fn copy(from: &Path, to: &Path) -> Result<(), ReportError> {
    let bytes = std::fs::read(from).map_err(|e| ReportError::Invalid {
        path: to.display().to_string(),
        reason: format!("the stage cache could not read {}: {e}", from.display()),
    })?;
    write_atomic(to, &bytes)
}

/// The cached record of `stage` under `root` (the run's output folder) with its files copied
/// into `dir` (the folder the stage writes into), and the entry's own copy of the files (what
/// the stage hands over is read from there), or `None` when there is no complete entry for
/// these inputs.
pub fn reuse(
    root: &Path,
    dir: &Path,
    stage: Stage,
    key: &Key,
) -> Result<Option<(StageRecord, PathBuf)>, ReportError> {
    let entry = entry_dir(root, stage, key);
    let Ok(text) = std::fs::read_to_string(entry.join(RECORD)) else {
        return Ok(None);
    };
    let Ok(cached) = serde_json::from_str::<Entry>(&text) else {
        return Ok(None);
    };
    if cached.key != key.hex || cached.inputs != key.inputs || cached.record.stage != stage {
        return Ok(None);
    }
    let mut record = cached.record;
    let files = entry.join(FILES);
    if !record.files.iter().all(|f| files.join(f).is_file()) {
        return Ok(None);
    }
    for f in &record.files {
        copy(&files.join(f), &dir.join(f))?;
    }
    record.cached = true;
    Ok(Some((record, files)))
}

/// Keep `record` and copies of its files (in `dir`) under `root` for later runs.
pub fn store(root: &Path, dir: &Path, key: &Key, record: &StageRecord) -> Result<(), ReportError> {
    let entry = entry_dir(root, record.stage, key);
    let tmp = root.join(CACHE_DIR).join(format!(
        ".tmp-{}-{}-{}",
        record.stage,
        key.hex,
        std::process::id()
    ));
    let io = |path: &Path| {
        let path = path.display().to_string();
        move |cause| ReportError::Io { path, cause }
    };
    if tmp.exists() {
        std::fs::remove_dir_all(&tmp).map_err(io(&tmp))?;
    }
    for f in &record.files {
        copy(&dir.join(f), &tmp.join(FILES).join(f))?;
    }
    let entry_json = Entry {
        key: key.hex.clone(),
        inputs: key.inputs.clone(),
        record: record.clone(),
    };
    crate::report::write_json(&tmp.join(RECORD), &entry_json)?;
    if entry.exists() {
        std::fs::remove_dir_all(&entry).map_err(io(&entry))?;
    }
    std::fs::rename(&tmp, &entry).map_err(io(&entry))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a64_matches_the_published_test_vectors() {
        // Fowler–Noll–Vo reference values
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn canonical_json_does_not_depend_on_key_order() {
        let a: Value = serde_json::from_str(r#"{"b": [1, {"y": 2, "x": 1.5}], "a": "s"}"#).unwrap();
        let b: Value = serde_json::from_str(r#"{"a": "s", "b": [1, {"x": 1.5, "y": 2}]}"#).unwrap();
        assert_eq!(canonical_json(&a), canonical_json(&b));
        assert_eq!(canonical_json(&a), r#"{"a":"s","b":[1,{"x":1.5,"y":2}]}"#);
    }

    /// The key hashes the build (version and source hash), so another build recomputes.
    #[test]
    fn the_key_names_the_build_it_was_computed_by() {
        let (version, source) = crate::BUILD.split_once('+').unwrap();
        assert_eq!(version, env!("CARGO_PKG_VERSION"));
        assert_eq!(source.len(), 16);
        assert!(source.chars().all(|c| c.is_ascii_hexdigit()), "{source}");
        let scene = crate::scene::load_str(
            include_str!("../../scenes/quickstart.toml"),
            Path::new("quickstart.toml"),
            &[],
        )
        .unwrap();
        let k = key(Stage::Discrete, &scene.base, &[]).unwrap();
        let build = format!(r#""turf_build":"{}""#, crate::BUILD);
        assert!(k.inputs.contains(&build), "{}", k.inputs);
        assert_eq!(k.hex, format!("{:016x}", fnv1a64(k.inputs.as_bytes())));
    }
}
