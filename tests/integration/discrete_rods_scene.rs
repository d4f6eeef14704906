//! `[rods]` through the pipeline's discrete stage (issue 7, item 9): scenes/rods_cantilever.toml
//! against Bisshopp–Drucker's large-deflection cantilever.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Issue 7: the large-deflection cantilever within 1 %.
const TOL: f64 = 0.01;
/// Mattiasson's table at PL²/K = 1: tip deflection and shortening over L.
const DELTA_V: f64 = 0.30172;
const DELTA_H: f64 = 0.05643;

/// Run scenes/rods_cantilever.toml with `sets` into a fresh folder: the discrete stage's values
/// and the folder.
fn run_cantilever(tag: &str, sets: &[String]) -> (BTreeMap<String, f64>, PathBuf) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/rods_cantilever.toml");
    let loaded = turf::scene::load(&file, sets).unwrap();
    let dir = std::env::temp_dir().join(format!("turf-rods-{tag}-{}", std::process::id()));
    let opts = turf::pipeline::RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let report = turf::pipeline::run(&loaded, &opts).unwrap();
    assert!(report.failure.is_none(), "{:?}", report.failure);
    (report.summary.stages[0].values.clone(), dir)
}

#[test]
fn the_cantilever_scene_matches_bisshopp_drucker() {
    let (values, dir) = run_cantilever("bd", &[]);
    let v = &values;
    let (l, k) = (v["rod0_length_nm"], v["bending_stiffness_nN_nm2"]);
    // the scene's load, 4 digits: PL²/K = 1 within 1e-4 (δ_v moves by < 1e-5 of L)
    assert!((0.4515 * l * l / k - 1.0).abs() < 1e-4);
    let dv = -v["rod0_tip_dy_nm"] / l;
    let dh = -v["rod0_tip_dx_nm"] / l;
    println!("δ_v/L = {dv:.6} (ref {DELTA_V}), δ_h/L = {dh:.6} (ref {DELTA_H})");
    assert!((dv / DELTA_V - 1.0).abs() < TOL, "δ_v/L = {dv}");
    assert!((dh / DELTA_H - 1.0).abs() < TOL, "δ_h/L = {dh}");
    assert!(dir.join("discrete_rods_nodes.csv").is_file());
    assert_eq!(
        v["stable_equilibrium"], 1.0,
        "the bent cantilever is a minimum"
    );
    std::fs::remove_dir_all(dir).ok();
}

/// A straight clamped–free column loaded axially at 9× its Euler load π²K/(4L²) (1.11 nN for
/// this 7 µm tube) is in equilibrium straight — Newton converges there — but unstable: the
/// stage says so (`stable_equilibrium` = 0) instead of reporting the straight shape as the
/// answer.
#[test]
fn a_straight_column_beyond_its_euler_load_is_reported_unstable() {
    let load = "rods.rod[0].load=[\"-10 nN\", \"0 nN\", \"0 nN\"]".to_string();
    let (values, dir) = run_cantilever("euler", &[load]);
    let v = &values;
    let k = v["bending_stiffness_nN_nm2"];
    let l = v["rod0_length_nm"];
    let euler = std::f64::consts::PI.powi(2) * k / (4.0 * l * l);
    assert!(
        10.0 / euler > 8.0 && 10.0 / euler < 10.0,
        "{}",
        10.0 / euler
    );
    // it stayed straight, and is flagged
    assert!(v["rod0_tip_dy_nm"].abs() < 1e-6 && v["rod0_tip_dz_nm"].abs() < 1e-6);
    assert_eq!(v["stable_equilibrium"], 0.0);
    std::fs::remove_dir_all(dir).ok();
}
