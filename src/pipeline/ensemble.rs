//! Ensembles of turf realisations (`turf.realisations`; DESIGN.md "Work items, ensembles and
//! scale-out"). A realisation is one turf drawn from the scene's statistics — the same density,
//! lengths, tilts and waviness, another random draw — and compressed along the same strain
//! path. This module holds what every stage of an ensemble shares:
//!
//! - the seed of realisation k, [`realisation_seed`]: k = 0 keeps `scene.seed` (so a
//!   one-realisation run is the run without the key), k ≥ 1 gets `scene.seed` XOR a bijective
//!   63-bit mix of k, so the seeds of one scene are all distinct and each can be written back
//!   into a scene file to rerun that realisation alone;
//! - where its files go, [`realisation_dir`]: realisation 0 in the output folder under the
//!   names a single run uses, realisation k ≥ 1 in `realisations/rKKK/` under the same names;
//! - the reduction of the realisations' curves, step by step along the common strain path
//!   ([`PathEnsemble`]), and of any scalar they report ([`Estimate`]): the mean and the
//!   two-sided 95 % confidence interval of the mean, x̄ ± t₀.₉₇₅,ₙ₋₁ s/√n (Student t with
//!   n − 1 degrees of freedom, s the sample standard deviation of the n realisations that
//!   finished; [`crate::numerics::statistics`]). One realisation has no interval, and the
//!   files say so instead of writing a NaN.

use crate::homogenize::curve_analysis::Branch;
use crate::numerics::statistics::Estimate;
use crate::report::csv::Table;
use crate::report::plot::{Plot, Series};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What the files write where an interval cannot be computed.
pub const NO_INTERVAL: &str =
    "none: a confidence interval needs at least two realisations, and one gave this value";

/// How the intervals are computed, as the result files state it.
pub const INTERVAL_DEFINITION: &str = "two-sided 95 % confidence interval of the mean over the \
    realisations that finished: mean ± t(0.975, n − 1) · s / √n, Student t with n − 1 degrees \
    of freedom, s the sample standard deviation";

/// Seeds a scene file can hold: TOML integers are signed 64-bit, so `scene.seed` < 2⁶³.
const SEED_MASK: u64 = (1 << 63) - 1;

/// The splitmix64 finaliser (Steele, Lea & Flood 2014) on 63 bits: each step (an xor-shift,
/// a multiplication by an odd constant modulo 2⁶³) is a bijection of [0, 2⁶³), and 0 ↦ 0.
fn mix63(mut z: u64) -> u64 {
    z &= SEED_MASK;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9) & SEED_MASK;
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb) & SEED_MASK;
    z ^ (z >> 31)
}

/// The seed of realisation `k` of a scene with seed `seed`: `seed` itself for k = 0, and
/// `seed` XOR mix(k) otherwise — distinct for distinct k (the mix is a bijection), and below
/// 2⁶³ like every seed a scene can hold, so any realisation can be run alone with
/// `--set scene.seed=<its seed>` (the seeds are listed in `discrete_ensemble.json`).
pub fn realisation_seed(seed: u64, k: usize) -> u64 {
    seed ^ mix63(k as u64)
}

/// The folder of realisation `k`'s files, relative to the output folder: the output folder
/// itself for k = 0, `realisations/rKKK` otherwise.
pub fn realisation_dir(k: usize) -> PathBuf {
    if k == 0 {
        PathBuf::new()
    } else {
        PathBuf::from(format!("realisations/r{k:03}"))
    }
}

/// The realisation whose file `name` is `file` (relative to the output folder): 0 for `name`
/// itself, k for `realisations/rKKK/name`, `None` for any other file.
pub fn realisation_of(file: &Path, name: &str) -> Option<usize> {
    if file == Path::new(name) {
        return Some(0);
    }
    let dir = file.strip_prefix("realisations").ok()?;
    let mut parts = dir.components();
    let k = parts
        .next()?
        .as_os_str()
        .to_str()?
        .strip_prefix('r')?
        .parse()
        .ok()?;
    (k > 0 && parts.as_path() == Path::new(name) && realisation_dir(k).join(name) == file)
        .then_some(k)
}

/// Put `e` into `values` as `<base>_mean<unit>`, `<base>_min<unit>`, `<base>_max<unit>`,
/// `<base>_n` and, with two or more samples, `<base>_ci95_low<unit>` and
/// `<base>_ci95_high<unit>` (`unit` is the name's unit suffix, e.g. `_GPa`, or empty).
pub fn put_estimate(values: &mut BTreeMap<String, f64>, base: &str, unit: &str, e: &Estimate) {
    let mut put = |what: &str, v: f64| {
        values.insert(format!("{base}_{what}{unit}"), v);
    };
    put("mean", e.mean);
    put("min", e.min);
    put("max", e.max);
    if let Some((lo, hi)) = e.ci95 {
        put("ci95_low", lo);
        put("ci95_high", hi);
    }
    values.insert(format!("{base}_n"), e.n as f64);
}

/// `e` as JSON: n, mean, min, max and the interval, or [`NO_INTERVAL`] in its place.
pub fn estimate_json(e: &Estimate) -> serde_json::Value {
    let ci = match e.ci95 {
        Some((lo, hi)) => serde_json::json!([lo, hi]),
        None => NO_INTERVAL.into(),
    };
    serde_json::json!({ "n": e.n, "mean": e.mean, "min": e.min, "max": e.max, "ci95": ci })
}

/// The estimates of the named scalars over the realisations' value maps (each name over the
/// realisations that report it; a name none reports is left out).
pub fn reduce_values<'a>(
    names: &[&str],
    members: impl Iterator<Item = &'a BTreeMap<String, f64>> + Clone,
) -> BTreeMap<String, Estimate> {
    names
        .iter()
        .filter_map(|&name| {
            let samples: Vec<f64> = members
                .clone()
                .filter_map(|m| m.get(name).copied())
                .collect();
            Estimate::of(&samples).map(|e| (name.to_string(), e))
        })
        .collect()
}

/// Split a drive's path into its loading branch (step 0 to the peak) and its unloading branch
/// (peak to the end, reversed to ascending strain), as the discrete analysis reads them.
pub fn branches(strain: &[f64], stress: &[f64], loading: &[bool]) -> (Branch, Option<Branch>) {
    let peak = loading.iter().filter(|l| **l).count();
    let take = |idx: &mut dyn Iterator<Item = usize>| {
        let (strain, stress) = idx.map(|i| (strain[i], stress[i])).unzip();
        Branch { strain, stress }
    };
    let load = take(&mut (0..peak));
    let unload =
        (strain.len() > peak && peak > 0).then(|| take(&mut (peak - 1..strain.len()).rev()));
    (load, unload)
}

/// The realisations' stress along the common strain path, reduced step by step.
#[derive(Debug, Clone)]
pub struct PathEnsemble {
    /// nominal strain of each step
    pub strain: Vec<f64>,
    /// whether each step is on the way down
    pub loading: Vec<bool>,
    /// (realisation index, its stress at each step, GPa), realisations that finished
    pub members: Vec<(usize, Vec<f64>)>,
    /// the stress estimate at each step, GPa
    pub stress: Vec<Estimate>,
}

impl PathEnsemble {
    /// Reduce `members` (each a realisation index and its stress at every step of the path
    /// `strain`, `loading`). An error names a realisation whose curve has another length or a
    /// non-finite stress, or says that there is none.
    pub fn new(
        strain: Vec<f64>,
        loading: Vec<bool>,
        members: Vec<(usize, Vec<f64>)>,
    ) -> Result<Self, String> {
        if members.is_empty() {
            return Err("no realisation finished".into());
        }
        if let Some((k, s)) = members.iter().find(|(_, s)| s.len() != strain.len()) {
            return Err(format!(
                "realisation {k} has {} steps, the path {}",
                s.len(),
                strain.len()
            ));
        }
        let stress = (0..strain.len())
            .map(|i| {
                let at: Vec<f64> = members.iter().map(|(_, s)| s[i]).collect();
                Estimate::of(&at).ok_or_else(|| format!("a non-finite stress at step {i}"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(PathEnsemble {
            strain,
            loading,
            members,
            stress,
        })
    }

    /// The mean stress at each step, GPa.
    pub fn mean(&self) -> Vec<f64> {
        self.stress.iter().map(|e| e.mean).collect()
    }

    /// Whether the intervals exist (two or more realisations).
    pub fn has_interval(&self) -> bool {
        self.members.len() >= 2
    }

    fn bound(&self, high: bool) -> Vec<f64> {
        self.stress
            .iter()
            .map(|e| e.ci95.map_or(e.mean, |(lo, hi)| if high { hi } else { lo }))
            .collect()
    }

    /// The ensemble table: `step, loading, strain, stress_mean_GPa`, with two or more
    /// realisations `stress_ci95_low_GPa, stress_ci95_high_GPa`, then `stress_rKKK_GPa` of
    /// each realisation that finished.
    pub fn table(&self) -> Table {
        self.table_along("strain")
    }

    /// [`Self::table`] with the path's strain column named `strain`.
    pub fn table_along(&self, strain: &str) -> Table {
        let mut t = Table::new()
            .column("step", (0..self.strain.len()).map(|i| i as f64).collect())
            .column(
                "loading",
                self.loading
                    .iter()
                    .map(|&l| f64::from(u8::from(l)))
                    .collect(),
            )
            .column(strain, self.strain.clone())
            .column("stress_mean_GPa", self.mean());
        if self.has_interval() {
            t = t
                .column("stress_ci95_low_GPa", self.bound(false))
                .column("stress_ci95_high_GPa", self.bound(true));
        }
        for (k, s) in &self.members {
            t = t.column(&format!("stress_r{k:03}_GPa"), s.clone());
        }
        t
    }

    /// The mean curve's loading and unloading branches.
    pub fn mean_branches(&self) -> (Branch, Option<Branch>) {
        branches(&self.strain, &self.mean(), &self.loading)
    }

    /// The band plot: each realisation as a thin line, the 95 % band of each branch, the mean.
    pub fn plot(&self) -> Plot {
        self.plot_along("nominal strain")
    }

    /// [`Self::plot`] with the strain axis labelled `strain`.
    pub fn plot_along(&self, strain: &str) -> Plot {
        let mut plot = Plot::new(
            &format!("Turf compression, {} realisations", self.members.len()),
            strain,
            "nominal stress (GPa)",
        );
        if self.has_interval() {
            let (lo, hi) = (self.bound(false), self.bound(true));
            let (lo_load, lo_unload) = branches(&self.strain, &lo, &self.loading);
            let (hi_load, hi_unload) = branches(&self.strain, &hi, &self.loading);
            plot = plot.with(Series::band(
                "95 % confidence interval of the mean",
                &lo_load.strain,
                &lo_load.stress,
                &hi_load.stress,
            ));
            if let (Some(l), Some(h)) = (lo_unload, hi_unload) {
                plot = plot.with(Series::band("", &l.strain, &l.stress, &h.stress));
            }
        }
        for (i, (_, s)) in self.members.iter().enumerate() {
            let label = if i == 0 { "realisations" } else { "" };
            plot = plot.with(Series::thin(label, self.strain.clone(), s.clone()));
        }
        plot.with(Series::line("mean", self.strain.clone(), self.mean()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_keep_the_scene_seed_first_and_are_distinct() {
        for seed in [0, 1, 3, SEED_MASK] {
            assert_eq!(realisation_seed(seed, 0), seed);
            let mut all: Vec<u64> = (0..1000).map(|k| realisation_seed(seed, k)).collect();
            assert!(
                all.iter().all(|&s| s <= SEED_MASK),
                "a scene file holds every seed"
            );
            all.sort_unstable();
            all.dedup();
            assert_eq!(all.len(), 1000, "seed {seed}");
        }
        assert_eq!(realisation_dir(0), PathBuf::new());
        assert_eq!(realisation_dir(7), PathBuf::from("realisations/r007"));
        let f = "stress_strain_loading.csv";
        assert_eq!(realisation_of(Path::new(f), f), Some(0));
        assert_eq!(realisation_of(&realisation_dir(12).join(f), f), Some(12));
        assert_eq!(
            realisation_of(&realisation_dir(12).join("other.csv"), f),
            None
        );
        assert_eq!(
            realisation_of(Path::new("ensemble_stress_strain_loading.csv"), f),
            None
        );
        assert_eq!(
            realisation_of(Path::new("realisations/r000/stress_strain_loading.csv"), f),
            None
        );
    }

    #[test]
    fn a_failed_realisation_is_left_out_and_one_alone_has_no_interval() {
        // realisations 0 and 2 finished, 1 failed (absent); loading 3 steps, unloading 2
        let strain = vec![0.0, 0.1, 0.2, 0.1, 0.0];
        let loading = vec![true, true, true, false, false];
        let e = PathEnsemble::new(
            strain.clone(),
            loading.clone(),
            vec![
                (0, vec![0.0, 1.0, 3.0, 1.0, 0.0]),
                (2, vec![0.0, 3.0, 5.0, 2.0, 0.0]),
            ],
        )
        .unwrap();
        assert_eq!(e.mean(), vec![0.0, 2.0, 4.0, 1.5, 0.0]);
        let t = e.table();
        assert!(t.get("stress_r001_GPa").is_none() && t.get("stress_r002_GPa").is_some());
        // two samples, s = √2 at step 1: half width t₀.₉₇₅,₁ · √2/√2 = tan(0.475 π)
        let half = e.stress[1].half_width().unwrap();
        assert!((half / (0.475 * std::f64::consts::PI).tan() - 1.0).abs() < 1e-12);
        let (load, unload) = e.mean_branches();
        assert_eq!(load.strain, vec![0.0, 0.1, 0.2]);
        assert_eq!(unload.unwrap().stress, vec![0.0, 1.5, 4.0]);
        assert!(e.plot().series.len() >= 4);

        let one = PathEnsemble::new(strain, loading, vec![(2, vec![0.0; 5])]).unwrap();
        let t = one.table();
        assert!(t.get("stress_ci95_low_GPa").is_none());
        let mut values = BTreeMap::new();
        put_estimate(&mut values, "x", "_GPa", &one.stress[1]);
        assert!(values.contains_key("x_mean_GPa") && !values.contains_key("x_ci95_low_GPa"));
        assert_eq!(estimate_json(&one.stress[1])["ci95"], NO_INTERVAL);
        let short = PathEnsemble::new(vec![0.0, 0.1], vec![true; 2], vec![(4, vec![0.0])]);
        assert!(short.unwrap_err().contains("realisation 4"));
    }
}
