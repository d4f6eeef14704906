//! Fingerprints the source the binary is built from, so that results cached or kept by one
//! build are not handed over by another: `TURF_SOURCE_HASH` is the FNV-1a 64-bit hash of every
//! file under `src/` (paths and contents, in path order), `Cargo.toml`, `Cargo.lock` and the
//! enabled cargo features. The stage cache, the sweep points' kept results and the ensemble's
//! kept realisations key on it (`turf::BUILD`); `summary.json` records it.

use std::path::{Path, PathBuf};

fn fnv1a64(h: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(h, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            files_under(&path, out);
        } else {
            out.push(path);
        }
    }
}

fn main() {
    let mut files = Vec::new();
    files_under(Path::new("src"), &mut files);
    files.sort();
    files.extend(["Cargo.toml", "Cargo.lock"].map(PathBuf::from));
    let mut h = 0xcbf2_9ce4_8422_2325;
    for file in &files {
        h = fnv1a64(h, file.to_string_lossy().as_bytes());
        h = fnv1a64(h, &std::fs::read(file).unwrap_or_default());
    }
    let mut features: Vec<String> = std::env::vars()
        .filter_map(|(k, _)| k.strip_prefix("CARGO_FEATURE_").map(str::to_owned))
        .collect();
    features.sort();
    h = fnv1a64(h, features.join(",").as_bytes());
    println!("cargo:rustc-env=TURF_SOURCE_HASH={h:016x}");
    for watched in ["src", "Cargo.toml", "Cargo.lock", "build.rs"] {
        println!("cargo:rerun-if-changed={watched}");
    }
}
