//! Platen compression of a small generated turf (issue 7, items 4–8): relaxation, the drive
//! to 30 % strain and back, the platen force as the derivative of the equilibrium energy, the
//! same curve with 1 and 2 threads, and the pipeline's discrete + homogenize stages.

use std::path::Path;
use turf::discrete::drive::{compress, CompressionParams, StepRecord};
use turf::discrete::model::{relax, StaticSolver, TurfSystem};
use turf::discrete::platen::DEFAULT_WALL_STIFFNESS;
use turf::discrete::solve_newton::NewtonParams;
use turf::discrete::turf::{generate_turf, TurfParams};
use turf::discrete::vdw::VdwParams;

/// Equilibrium force residual, nN (the rods' round-off floor is ~1e-9 nN).
const TOLERANCE: f64 = 1e-6;
/// Platen offset of the finite-difference check, nm: small against every contact's range.
const FD_STEP: f64 = 1e-3;
/// The force from the energy difference: central difference error ~ δ² F''' plus the solver
/// residual over δ (1e-6 nN × nodes / 1e-3 nm): 1e-4 relative is ten times above both.
const FD_TOL: f64 = 1e-4;

/// Four slightly wavy 1-µm tubes of 8 segments in a 200 nm periodic box, tilted and waved
/// little enough that the generator's first growth draws already clear each other.
fn small_turf() -> TurfParams {
    TurfParams {
        density: 1e-4,
        box_x: 200.0,
        box_y: 200.0,
        length_mean: 1000.0,
        length_cv: 0.05,
        tilt_spread: 0.005,
        wave_amplitude: 3.0,
        wave_length: 700.0,
        segment_length: 125.0,
        seed: 5,
        ..TurfParams::default()
    }
}

fn newton() -> StaticSolver {
    StaticSolver::Newton(NewtonParams {
        tol_abs: TOLERANCE,
        tol_rel: 0.0,
        max_iterations: 2000,
        ..NewtonParams::default()
    })
}

fn relaxed_system() -> (TurfSystem, Vec<f64>) {
    let turf = generate_turf(&small_turf()).unwrap();
    let mut sys = TurfSystem::from_turf(
        &turf,
        400.0,
        Some(&VdwParams::default()),
        DEFAULT_WALL_STIFFNESS,
        200.0 * 200.0,
    )
    .unwrap();
    let mut x = turf.coordinates();
    let relaxed = relax(&mut sys, &mut x, &newton()).unwrap();
    assert!(
        relaxed.state.min_gap > 0.0,
        "relaxed tubes must not interpenetrate: generated gap {} nm, relaxed {} nm",
        relaxed.initial.min_gap,
        relaxed.state.min_gap
    );
    (sys, x)
}

fn run_curve() -> Vec<StepRecord> {
    let (mut sys, mut x) = relaxed_system();
    let params = CompressionParams {
        strain_max: 0.3,
        steps: 5,
        unload: true,
    };
    compress(&mut sys, &mut x, &params, &newton(), None, &mut |_, _| {}).unwrap()
}

#[test]
fn the_platen_force_is_minus_the_derivative_of_the_equilibrium_energy() {
    let (mut sys, mut x) = relaxed_system();
    let h0 = sys.height(&x);
    let h = h0 * 0.9;
    let params = CompressionParams {
        strain_max: 0.1,
        steps: 2,
        unload: false,
    };
    let recs = compress(&mut sys, &mut x, &params, &newton(), None, &mut |_, _| {}).unwrap();
    let force = recs.last().unwrap().state.platen_force;
    assert!(force > 0.0, "the platen must carry load at 10 % strain");
    let total = |s: &turf::discrete::model::State| {
        let e = s.energy;
        e.stretching + e.bending + e.vdw + e.walls
    };
    let mut energy_at = |dh: f64| {
        let mut y = x.clone();
        sys.set_platen(h + dh);
        sys.solve(&mut y, &newton()).unwrap();
        total(&sys.state(&y))
    };
    let (ep, em) = (energy_at(FD_STEP), energy_at(-FD_STEP));
    let fd = -(ep - em) / (2.0 * FD_STEP);
    assert!(
        (fd - force).abs() < FD_TOL * force,
        "−dE*/dH = {fd} nN, platen force {force} nN"
    );
}

#[test]
fn a_small_turf_compresses_to_30_percent_and_unloads_the_same_with_1_and_2_threads() {
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(run_curve);
    let two = pool(2).install(run_curve);
    assert_eq!(one.len(), 11);
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(a.stress.to_bits(), b.stress.to_bits(), "step {}", a.step);
        assert_eq!(a.state, b.state, "step {}", a.step);
    }
    assert_eq!(one[0].stress, 0.0, "the platen starts touching");
    assert!(one[5].stress > 0.0 && one[5].strain == 0.3);
    assert!(one.iter().all(|r| r.stress >= 0.0 && r.stress.is_finite()));
    assert!(one[5].state.platen_nodes > 0);
    // tubes bend under the platen: more bending energy at the peak than relaxed
    assert!(one[5].state.energy.bending > one[0].state.energy.bending);
}

const SCENE: &str = r#"
[scene]
name = "discrete-pipeline-test"
seed = 5
[turf]
density = "1e10 1/cm^2"
box = ["200 nm", "200 nm"]
[turf.tube]
r_o = "20 nm"
r_i = "17.3 nm"
youngs = "0.4 TPa"
segment = "125 nm"
[turf.growth]
length = "1 um"
length_spread = 0.05
tilt = 0.005
waviness = "3 nm"
wavelength = "700 nm"
[turf.vdw]
gamma_line = "1 nN"
[compression]
to = 0.3
steps = 5
unload = true
solver = "newton"
tolerance = "1e-6 nN"
[homogenize]
curve = "loading"
[output]
vtk = true
plots = false
"#;

#[test]
fn the_pipeline_writes_the_curve_homogenize_fits_it_and_a_resumed_run_repeats_it() {
    let loaded = turf::scene::load_str(SCENE, Path::new("t.toml"), &[]).unwrap();
    let dir = std::env::temp_dir().join(format!("turf-discrete-{}", std::process::id()));
    let opts = turf::pipeline::RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let report = turf::pipeline::run(&loaded, &opts).unwrap();
    assert!(report.failure.is_none(), "{:?}", report.failure);
    let csv = std::fs::read_to_string(dir.join("stress_strain.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.starts_with("step,loading,strain,stress_GPa,"),
        "{header}"
    );
    assert_eq!(csv.lines().count(), 1 + 11);
    for f in [
        "stress_strain_loading.csv",
        "stress_strain_unloading.csv",
        "vtk/discrete_step_000.vtu",
        "vtk/discrete_step_005.vtu",
        "vtk/discrete_step_010.vtu",
        "material.json",
    ] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    let vtu = std::fs::read_to_string(dir.join("vtk/discrete_step_005.vtu")).unwrap();
    assert!(
        vtu.contains("NumberOfCells=\"4\""),
        "four tubes as polylines"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let v = &json["stages"][0]["values"];
    assert_eq!(json["stages"][0]["stage"], "discrete");
    assert_eq!(v["tubes"], 4.0);
    assert!(v["peak_stress_GPa"].as_f64().unwrap() > 0.0);
    // relaxed tubes touch (a contact) without interpenetrating
    let gap = v["relaxed_min_gap_nm"].as_f64().unwrap();
    assert!(gap > 0.0 && gap < 2.5, "smallest relaxed gap {gap} nm");
    assert_eq!(json["stages"][1]["stage"], "homogenize");
    assert!(json["complete"].as_bool().unwrap());

    // interrupted after step 3: keep steps 0–3 of the checkpoint, remove the results, resume
    let checkpoint = dir.join("discrete_checkpoint.json");
    let mut saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&checkpoint).unwrap()).unwrap();
    assert_eq!(saved["steps"].as_array().unwrap().len(), 11);
    saved["steps"].as_array_mut().unwrap().truncate(4);
    std::fs::write(&checkpoint, saved.to_string()).unwrap();
    std::fs::remove_file(dir.join("stress_strain.csv")).unwrap();
    // an interrupted stage never reached the stage cache (it stores finished stages only)
    std::fs::remove_dir_all(dir.join("cache")).unwrap();
    let resumed = turf::pipeline::run(
        &loaded,
        &turf::pipeline::RunOptions {
            resume: true,
            ..opts
        },
    )
    .unwrap();
    assert!(resumed.failure.is_none(), "{:?}", resumed.failure);
    let again = std::fs::read_to_string(dir.join("stress_strain.csv")).unwrap();
    // every column but the wall time of the solves (the last) is the same, to the last digit
    let without_time = |text: &str| -> Vec<String> {
        text.lines()
            .map(|l| l.rsplit_once(',').unwrap().0.to_string())
            .collect()
    };
    assert_eq!(without_time(&again), without_time(&csv));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["stages"][0]["values"]["resumed_after_step"], 3.0);
    // the steps solved again are the uninterrupted run's: the checkpoint is whole once more
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&checkpoint).unwrap()).unwrap();
    assert_eq!(saved["steps"].as_array().unwrap().len(), 11);
    std::fs::remove_dir_all(dir).ok();
}
