//! `[rods]` through the pipeline's discrete stage (issue 7, item 9): scenes/rods_cantilever.toml
//! against Bisshopp–Drucker's large-deflection cantilever.

use std::path::Path;

/// Issue 7: the large-deflection cantilever within 1 %.
const TOL: f64 = 0.01;
/// Mattiasson's table at PL²/K = 1: tip deflection and shortening over L.
const DELTA_V: f64 = 0.30172;
const DELTA_H: f64 = 0.05643;

#[test]
fn the_cantilever_scene_matches_bisshopp_drucker() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/rods_cantilever.toml");
    let loaded = turf::scene::load(&file, &[]).unwrap();
    let dir = std::env::temp_dir().join(format!("turf-rods-{}", std::process::id()));
    let opts = turf::pipeline::RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let report = turf::pipeline::run(&loaded, &opts).unwrap();
    assert!(report.failure.is_none(), "{:?}", report.failure);
    let v = &report.summary.stages[0].values;
    let (l, k) = (v["rod0_length_nm"], v["bending_stiffness_nN_nm2"]);
    // the scene's load, 4 digits: PL²/K = 1 within 1e-4 (δ_v moves by < 1e-5 of L)
    assert!((0.4515 * l * l / k - 1.0).abs() < 1e-4);
    let dv = -v["rod0_tip_dy_nm"] / l;
    let dh = -v["rod0_tip_dx_nm"] / l;
    println!("δ_v/L = {dv:.6} (ref {DELTA_V}), δ_h/L = {dh:.6} (ref {DELTA_H})");
    assert!((dv / DELTA_V - 1.0).abs() < TOL, "δ_v/L = {dv}");
    assert!((dh / DELTA_H - 1.0).abs() < TOL, "δ_h/L = {dh}");
    assert!(dir.join("discrete_rods_nodes.csv").is_file());
    std::fs::remove_dir_all(dir).ok();
}
