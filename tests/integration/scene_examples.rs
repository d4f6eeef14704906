//! Every scene in `scenes/` loads, validates and plans the stages its header promises; the
//! overrides and sweeps behave as documented.

use std::path::{Path, PathBuf};
use turf::scene::{load, load_str, Stage};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn stages(file: &str) -> Vec<Stage> {
    let loaded = load(&scenes_dir().join(file), &[]).unwrap_or_else(|e| panic!("{e}"));
    loaded.base.plan.stages.iter().map(|s| s.stage).collect()
}

/// Relative tolerance on derived numbers recomputed here from their closed forms (only
/// rounding differs).
const ROUNDING: f64 = 1e-12;

#[test]
fn every_scene_in_the_folder_loads_and_is_tested_here() {
    let tested = [
        "adhesion_pulloff_sweep.toml",
        "hertz.toml",
        "hyperfoam_indent.toml",
        "jkr_sphere.toml",
        "quickstart.toml",
        "rods_cantilever.toml",
        "seed_card.toml",
        "turf_compression.toml",
        "turf_indent.toml",
        "turf_rve.toml",
        "turf_short_dense.toml",
        "turf_sphere.toml",
    ];
    let mut found: Vec<String> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    found.sort();
    assert_eq!(found, tested, "a scene was added without a test here");
    for f in tested {
        let text = std::fs::read_to_string(scenes_dir().join(f)).unwrap();
        assert!(
            text.starts_with("# "),
            "{f} must open with its header comment"
        );
        assert!(
            text.contains("Validated against"),
            "{f} must say what validates it"
        );
        load(&scenes_dir().join(f), &[]).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// The seed's turf simulations (`scenes/seed/`, seed Figs 6.7–6.11): each one passes what
/// `turf check` does (load, validate, plan), plans the continuum stage, and says in its header
/// what it shows, what validates it and what it costs.
#[test]
fn every_seed_scene_checks_and_plans_the_continuum_stage() {
    let seed = [
        "fig6_11_load_control.toml",
        "fig6_7_hyperfoam.toml",
        "fig6_7_linear.toml",
        "fig6_8_adhesion.toml",
        "fig6_9_relaxation.toml",
    ];
    let dir = scenes_dir().join("seed");
    let mut found: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    found.sort();
    assert_eq!(found, seed, "a seed scene was added without a test here");
    for f in seed {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(text.starts_with("# "), "{f} must open with its header");
        for word in ["Shows", "Validated against", "Cost"] {
            assert!(text.contains(word), "{f}: the header must say {word}");
        }
        let loaded = load(&dir.join(f), &[]).unwrap_or_else(|e| panic!("{f}: {e}"));
        let planned: Vec<Stage> = loaded.base.plan.stages.iter().map(|s| s.stage).collect();
        assert!(planned.contains(&Stage::Continuum), "{f}: {planned:?}");
    }
}

#[test]
fn seed_card_runs_homogenize_alone_and_reproduces_table_5_1() {
    assert_eq!(stages("seed_card.toml"), [Stage::Homogenize]);
    let l = load(&scenes_dir().join("seed_card.toml"), &[]).unwrap();
    let dir = std::env::temp_dir().join(format!("turf-seed-card-{}", std::process::id()));
    let opts = turf::pipeline::RunOptions {
        out: Some(dir.clone()),
        progress: false,
        resume: false,
    };
    let report = turf::pipeline::run(&l, &opts).unwrap();
    assert!(report.failure.is_none());
    let card = turf::homogenize::read_card(&dir.join("material.inp")).unwrap();
    // Table 5.1 at ε₀ = 0.05: μ = 350 MPa, α = 18.8 (3 %, the tolerance)
    let hf = &card.hyperfoam.terms[0];
    assert!((hf.mu - 0.35).abs() < 1e-9 && (hf.alpha / 18.8 - 1.0).abs() < 0.03);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn jkr_sphere_plans_theory_and_halfspace_with_its_tabor_number() {
    assert_eq!(stages("jkr_sphere.toml"), [Stage::Theory, Stage::Halfspace]);
    let l = load(&scenes_dir().join("jkr_sphere.toml"), &[]).unwrap();
    let d = &l.base.derived;
    // E* = E/(1-ν²), μ = (Rγ²/(E*² z0³))^(1/3) with R = 100 nm, γ = 0.05, z0 = 0.34, E = 1, ν = 0.3
    let es = 1.0 / (1.0 - 0.09);
    let mu = (100.0 * 0.05f64.powi(2) / (es * es * 0.34f64.powi(3))).cbrt();
    assert!((d.effective_modulus_gpa.unwrap() / es - 1.0).abs() < ROUNDING);
    assert!((d.tabor_mu.unwrap() / mu - 1.0).abs() < ROUNDING);
    // Maugis λ ≈ 1.16 μ for LJ 9-3 (PHYSICS.md): λ/μ = σ0 z0 (9/(2π))^(1/3)/γ, σ0 = 16γ/(9√3 z0)
    let ratio = 16.0 / (9.0 * 3f64.sqrt()) * (9.0 / (2.0 * std::f64::consts::PI)).cbrt();
    assert!((d.maugis_lambda.unwrap() / d.tabor_mu.unwrap() / ratio - 1.0).abs() < 1e-9);
    assert!((ratio - 1.16).abs() < 0.005);
}

#[test]
fn hertz_has_no_adhesion_physics_and_a_mesh_from_the_contact_radius() {
    assert_eq!(stages("hertz.toml"), [Stage::Theory, Stage::Continuum]);
    let l = load(&scenes_dir().join("hertz.toml"), &[]).unwrap();
    let p = &l.base.plan;
    let adhesion = p.physics.iter().find(|s| s.name == "lj_adhesion").unwrap();
    assert!(!adhesion.on);
    let a = (1000.0f64 * 4.0).sqrt();
    let m = l.base.derived.mesh.unwrap();
    assert!((m.width_nm / (200.0 * a) - 1.0).abs() < ROUNDING);
    assert!((m.depth_nm / (200.0 * a) - 1.0).abs() < ROUNDING);
    assert!((m.grading - 1.2).abs() < ROUNDING);
    assert!((m.smallest_nm / (a / 20.0) - 1.0).abs() < ROUNDING);
}

#[test]
fn hyperfoam_indent_runs_only_the_continuum_with_everything_on() {
    assert_eq!(stages("hyperfoam_indent.toml"), [Stage::Continuum]);
    let l = load(&scenes_dir().join("hyperfoam_indent.toml"), &[]).unwrap();
    for name in [
        "lj_adhesion",
        "thermal_shift",
        "contact_damping",
        "viscoelastic",
    ] {
        let s = l.base.plan.physics.iter().find(|s| s.name == name).unwrap();
        assert!(s.on, "{name} should be on");
    }
    // blunt Berkovich tip depth R(1 - sin 70.3°)
    let tip = l.base.scene.indenter.as_ref().unwrap().tip_depth.unwrap().0;
    let expect = 1800.0 * (1.0 - 70.3f64.to_radians().sin());
    assert!((tip / expect - 1.0).abs() < ROUNDING);
}

#[test]
fn rods_cantilever_is_discrete_only() {
    assert_eq!(stages("rods_cantilever.toml"), [Stage::Discrete]);
}

#[test]
fn turf_rve_is_discrete_only_in_either_mode() {
    assert_eq!(stages("turf_rve.toml"), [Stage::Discrete]);
    let shear = load(
        &scenes_dir().join("turf_rve.toml"),
        &["compression.mode=\"shear\"".to_string()],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(shear.base.plan.stages[0]
        .why
        .contains("sheared along the tubes"));
    assert_eq!(
        shear.base.scene.compression.map(|k| k.mode),
        Some(turf::scene::compression::Mode::Shear)
    );
}

/// The turf whose tubes give a card like the seed's: short, level, dense, grown collectively
/// (the only way the generator grows them this dense), compressed and homogenised.
#[test]
fn turf_short_dense_is_compressed_and_homogenised() {
    assert_eq!(
        stages("turf_short_dense.toml"),
        [Stage::Discrete, Stage::Homogenize]
    );
    let l = load(&scenes_dir().join("turf_short_dense.toml"), &[]).unwrap();
    let turf = l.base.scene.turf.as_ref().unwrap();
    // 2e10 /cm² in a 707.1 nm box: 100 tubes, this turf's RVE
    assert_eq!(l.base.derived.tube_count, Some(100.0));
    assert_eq!(turf.realisations, 4);
}

#[test]
fn turf_compression_is_discrete_only() {
    assert_eq!(stages("turf_compression.toml"), [Stage::Discrete]);
}

#[test]
fn turf_indent_is_the_whole_chain_with_the_thermal_amplitude_of_its_tubes() {
    assert_eq!(
        stages("turf_indent.toml"),
        [Stage::Discrete, Stage::Homogenize, Stage::Continuum]
    );
    let l = load(&scenes_dir().join("turf_indent.toml"), &[]).unwrap();
    let u = l.base.derived.thermal_shift_nm.unwrap();
    // PHYSICS.md: these tubes at 300 K give u ≈ 4.6 nm (two significant figures)
    assert!((u - 4.6).abs() < 0.05, "u = {u}");
    let chi = l.base.derived.machine_series_stiffness.unwrap();
    let expect = 1.0 / (1.0 / 210e6 + 1.0 / 100.0);
    assert!((chi / expect - 1.0).abs() < ROUNDING);
}

#[test]
fn quickstart_is_the_chain_on_a_small_turf_with_its_tubes_thermal_shift() {
    assert_eq!(
        stages("quickstart.toml"),
        [Stage::Discrete, Stage::Homogenize, Stage::Continuum]
    );
    let l = load(&scenes_dir().join("quickstart.toml"), &[]).unwrap();
    // seed eq. 5.9 scales as l^(3/2): 2 µm tubes shift by (2/7)^(3/2) of the 7 µm tubes' u
    let u = l.base.derived.thermal_shift_nm.unwrap();
    let seed_u = turf::theory::thermal::Cantilever::seed()
        .rms_tip_amplitude(300.0)
        .unwrap();
    assert!(
        (u / (seed_u * (2.0f64 / 7.0).powf(1.5)) - 1.0).abs() < ROUNDING,
        "u = {u}"
    );
    assert_eq!(l.base.derived.tube_count, Some(9.0));
    // a card's moduli are known only at run time: no mesh sizes derived before the run
    assert!(l.base.derived.mesh.is_none());
    // the tabulated van der Waals kernel by default, the quadrature on request; the plan says which
    let kernel = |overrides: &[String]| {
        let l = load(&scenes_dir().join("quickstart.toml"), overrides).unwrap();
        let s = l
            .base
            .plan
            .physics
            .iter()
            .find(|s| s.name == "tube_contacts");
        s.unwrap().detail.clone()
    };
    assert!(kernel(&[]).contains("tabulated kernel"), "{}", kernel(&[]));
    let quad = kernel(&["turf.vdw.kernel=\"quadrature\"".to_string()]);
    assert!(quad.contains("quadrature kernel"), "{quad}");
    // cache keys: a quadrature turf serialises without the key (as every turf did before the
    // table existed), a tabulated one with it, so neither reuses the other's results
    let turf_json = |overrides: &[String]| {
        let l = load(&scenes_dir().join("quickstart.toml"), overrides).unwrap();
        serde_json::to_string(&l.base.scene.turf).unwrap()
    };
    assert!(turf_json(&[]).contains("\"kernel\":\"tabulated\""));
    assert!(!turf_json(&["turf.vdw.kernel=\"quadrature\"".to_string()]).contains("kernel"));
}

#[test]
fn set_overrides_are_applied_and_converted() {
    let f = scenes_dir().join("jkr_sphere.toml");
    let l = load(&f, &["adhesion.gamma=0.2 J/m^2".to_string()]).unwrap();
    assert_eq!(l.base.scene.adhesion.as_ref().unwrap().gamma.0, 0.2);
    let l = load(
        &f,
        &[
            "adhesion.law=\"lj104\"".into(),
            "indenter.radius=200".into(),
        ],
    )
    .unwrap();
    assert_eq!(l.base.scene.indenter.as_ref().unwrap().radius.0, 200.0);
    let f = scenes_dir().join("hertz.toml");
    let l = load(&f, &["schedule.segment[0].to=6 nm".into()]).unwrap();
    assert_eq!(l.base.derived.schedule.unwrap().max_depth_nm, 6.0);
    let l = load(&f, &["schedule.segment.1.rate=\"2 nm/s\"".into()]).unwrap();
    assert_eq!(l.base.derived.schedule.unwrap().duration_s, 4.0 + 2.0);
}

#[test]
fn adhesion_pulloff_sweep_covers_tabor_mu_from_dmt_to_one() {
    assert!(stages("adhesion_pulloff_sweep.toml").contains(&Stage::Continuum));
    let l = load(&scenes_dir().join("adhesion_pulloff_sweep.toml"), &[]).unwrap();
    let mus: Vec<f64> = l
        .sweep
        .iter()
        .map(|p| p.scene.derived.tabor_mu.unwrap())
        .collect();
    // the γ values are rounded to 4 digits: μ to 1e-3 of 0.1, 0.5, 1
    for (mu, want) in mus.iter().zip([0.1, 0.5, 1.0]) {
        assert!((mu / want - 1.0).abs() < 1e-3, "{mu} vs {want}");
    }
}

#[test]
fn a_sweep_resolves_every_value() {
    let text = std::fs::read_to_string(scenes_dir().join("jkr_sphere.toml")).unwrap()
        + "\n[sweep]\nkey = \"adhesion.gamma\"\nvalues = [0.001, \"0.01 J/m^2\", 0.1]\n";
    let l = load_str(&text, &scenes_dir().join("sweep.toml"), &[]).unwrap();
    let mus: Vec<f64> = l
        .sweep
        .iter()
        .map(|p| p.scene.derived.tabor_mu.unwrap())
        .collect();
    assert_eq!(mus.len(), 3);
    // μ ∝ γ^(2/3)
    assert!((mus[1] / mus[0] / 10f64.powf(2.0 / 3.0) - 1.0).abs() < 1e-9);
    assert!(mus[2] > mus[1]);
    // 1 J/m² puts this sphere at μ ≈ 13, beyond the half-space solver's validated range: the
    // sweep is refused at that point, naming [halfspace]
    let beyond = load_str(
        &text.replace(
            "values = [0.001, \"0.01 J/m^2\", 0.1]",
            "values = [0.1, 1.0]",
        ),
        &scenes_dir().join("sweep.toml"),
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(
        beyond.contains("halfspace") && beyond.contains("validated range"),
        "{beyond}"
    );
}

#[test]
fn load_rates_are_read_per_second() {
    let l = load(&scenes_dir().join("turf_indent.toml"), &[]).unwrap();
    let t = l.base.derived.schedule.unwrap();
    // approach 20 nm at 10 nm/s, load 20 uN at 2 uN/s, hold 10 s, unload to −1 uN at 2 uN/s
    assert!(
        (t.duration_s - (2.0 + 10.0 + 10.0 + 10.5)).abs() < 1e-9,
        "{}",
        t.duration_s
    );
    assert_eq!(t.max_load_nn, 20_000.0);
}
