//! Bad scene input, one kind per test: each must be refused with a message that names the
//! key (and the file and line where there is one) and says what is allowed.

use std::path::Path;
use turf::scene::{load, load_str, SceneError};

/// A valid scene (sphere on a linear solid with adhesion: theory + halfspace).
const GOOD: &str = r#"[scene]
name = "t"

[indenter]
radius = "100 nm"

[material]
model = "linear"
youngs = "1 GPa"
poisson = 0.3

[adhesion]
gamma = "0.05 J/m^2"
z0 = "0.34 nm"

[halfspace]
cells_per_zone = 12
"#;

/// A valid FE scene with a schedule.
const FE: &str = r#"[indenter]
radius = "1 um"

[material]
model = "hyperfoam"
mu = ["350 MPa"]
alpha = [18.8]

[viscoelastic]
g = [0.4]
tau = ["3 s"]

[schedule]
[[schedule.segment]]
kind = "load"
to = "50 nm"
rate = "10 nm/s"

[[schedule.segment]]
kind = "unload"
to = "0 nm"
rate = "10 nm/s"
"#;

/// A valid discrete scene.
const TURF: &str = r#"[turf]
density = "1e10 1/cm^2"
box = ["1 um", "1 um"]

[turf.tube]
r_o = "20 nm"
r_i = "17.3 nm"
youngs = "0.4 TPa"

[turf.growth]
length = "7 um"

[compression]
to = 0.3
"#;

fn error(text: &str, sets: &[&str]) -> String {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    match load_str(text, Path::new("bad.toml"), &sets) {
        Ok(_) => panic!("accepted:\n{text}\nwith {sets:?}"),
        Err(e) => e.to_string(),
    }
}

fn assert_has(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "message lacks {p:?}:\n{msg}");
    }
}

#[test]
fn the_valid_scenes_of_these_tests_load() {
    for text in [GOOD, FE, TURF] {
        load_str(text, Path::new("good.toml"), &[]).unwrap();
    }
}

#[test]
fn unknown_key_names_key_line_and_the_allowed_keys() {
    let text = GOOD.replace("z0 = \"0.34 nm\"", "z0 = \"0.34 nm\"\ngama = 0.1");
    let msg = error(&text, &[]);
    assert_has(
        &msg,
        &[
            "bad.toml",
            "line 15",
            "adhesion.gama",
            "unknown field",
            "`gamma`",
            "`thermal_shift`",
        ],
    );
}

#[test]
fn unknown_section_lists_the_sections() {
    let msg = error(&format!("{GOOD}\n[adhesions]\nx = 1\n"), &[]);
    assert_has(
        &msg,
        &[
            "adhesions",
            "unknown field",
            "`adhesion`",
            "`turf`",
            "`sweep`",
        ],
    );
}

#[test]
fn wrong_dimension_names_the_dimension_expected() {
    let msg = error(&GOOD.replace("\"0.05 J/m^2\"", "\"3 nm\""), &[]);
    assert_has(
        &msg,
        &[
            "line 13",
            "adhesion.gamma",
            "\"3 nm\" is a length",
            "expected a surface energy",
        ],
    );
}

#[test]
fn negative_radius_is_refused() {
    let msg = error(&GOOD.replace("\"100 nm\"", "\"-100 nm\""), &[]);
    assert_has(
        &msg,
        &["line 5", "indenter.radius", "-100 nm", "must be positive"],
    );
}

#[test]
fn inner_radius_not_below_outer_radius_is_refused() {
    let msg = error(&TURF.replace("\"17.3 nm\"", "\"20 nm\""), &[]);
    assert_has(&msg, &["turf.tube.r_i", "20 nm", "0 <= r_i < r_o"]);
}

#[test]
fn poisson_ratio_of_one_half_is_refused() {
    let msg = error(&GOOD.replace("poisson = 0.3", "poisson = 0.5"), &[]);
    assert_has(&msg, &["line 10", "material.poisson", "0.5", "[0, 0.5)"]);
}

#[test]
fn unequal_hyperfoam_arrays_are_refused() {
    let msg = error(
        &FE.replace("mu = [\"350 MPa\"]", "mu = [\"350 MPa\", \"10 MPa\"]"),
        &[],
    );
    assert_has(
        &msg,
        &[
            "material.alpha",
            "has 1 entries but material.mu has 2",
            "equal length",
        ],
    );
}

#[test]
fn bad_enum_value_lists_the_allowed_values() {
    let msg = error(
        &GOOD.replace("[adhesion]", "[adhesion]\nlaw = \"lj12\""),
        &[],
    );
    assert_has(&msg, &["adhesion.law", "lj12", "`lj93`", "`lj104`"]);
    let msg = error(
        &GOOD.replace("model = \"linear\"", "model = \"neo-hookean\""),
        &[],
    );
    assert_has(
        &msg,
        &["material.model", "`linear`", "`hyperfoam`", "`card`"],
    );
    let msg = error(
        &format!("{TURF}\n[turf.vdw]\ngamma_line = \"1 nN\"\nkernel = \"fast\"\n"),
        &[],
    );
    assert_has(
        &msg,
        &["turf.vdw.kernel", "fast", "`quadrature`", "`tabulated`"],
    );
}

#[test]
fn malformed_toml_gives_file_line_and_column() {
    let msg = error("[scene]\nname = \"x\"\nseed = = 3\n", &[]);
    assert_has(&msg, &["bad.toml:3:", "malformed TOML"]);
}

#[test]
fn unknown_key_via_set_lists_the_keys_of_that_section() {
    let msg = error(GOOD, &["adhesion.gama=0.1"]);
    assert_has(
        &msg,
        &[
            "adhesion.gama (from --set)",
            "unknown field",
            "`gamma`",
            "`z0`",
        ],
    );
    let msg = error(GOOD, &["nosuch.key=1"]);
    assert_has(&msg, &["nosuch (from --set)", "`indenter`"]);
}

#[test]
fn bad_value_via_set_is_refused_like_a_file_value() {
    let msg = error(GOOD, &["adhesion.gamma=abc"]);
    assert_has(
        &msg,
        &[
            "adhesion.gamma (from --set)",
            "\"abc\" does not start with a number",
            "surface energy",
        ],
    );
    let msg = error(GOOD, &["material.poisson=0.7"]);
    assert_has(&msg, &["material.poisson (from --set)", "[0, 0.5)"]);
}

#[test]
fn set_without_equals_or_with_a_bad_path_is_refused() {
    let msg = error(GOOD, &["adhesion.gamma"]);
    assert_has(&msg, &["--set adhesion.gamma", "KEY=VALUE"]);
    let msg = error(GOOD, &["adhesion..gamma=1"]);
    assert_has(&msg, &["dotted path"]);
    let msg = error(FE, &["schedule.segment[5].to=1"]);
    assert_has(&msg, &["schedule.segment has 2 element(s)", "out of range"]);
}

#[test]
fn missing_file_names_the_file() {
    let e = load(Path::new("/nonexistent/scene.toml"), &[]).unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }));
    assert_has(
        &e.to_string(),
        &["cannot read scene /nonexistent/scene.toml"],
    );
}

#[test]
fn prony_terms_summing_to_one_are_refused() {
    let msg = error(
        &FE.replace(
            "g = [0.4]\ntau = [\"3 s\"]",
            "g = [0.6, 0.4]\ntau = [\"3 s\", \"1 s\"]",
        ),
        &[],
    );
    assert_has(&msg, &["viscoelastic.g", "sums to 1", "less than 1"]);
}

#[test]
fn prony_arrays_of_unequal_length_are_refused() {
    let msg = error(
        &FE.replace("tau = [\"3 s\"]", "tau = [\"3 s\", \"1 s\"]"),
        &[],
    );
    assert_has(
        &msg,
        &["viscoelastic.tau", "has 2 entries but viscoelastic.g has 1"],
    );
}

#[test]
fn inconsistent_schedule_is_refused() {
    let msg = error(&FE.replace("to = \"0 nm\"", "to = \"80 nm\""), &[]);
    assert_has(
        &msg,
        &[
            "schedule.segment[1].to",
            "80 nm",
            "must decrease the depth",
            "50 nm",
        ],
    );
    let msg = error(
        &FE.replace("rate = \"10 nm/s\"\n\n", "rate = \"10 nm/s\"\ntime = 3\n\n"),
        &[],
    );
    assert_has(&msg, &["schedule.segment[0].rate", "give one of them"]);
    let hold = FE.replace("kind = \"unload\"\nto = \"0 nm\"", "kind = \"hold\"");
    let msg = error(&hold, &[]);
    assert_has(
        &msg,
        &[
            "schedule.segment[1].rate",
            "is not used in a hold",
            "schedule.segment[1].time",
            "is missing",
        ],
    );
}

#[test]
fn load_control_reads_targets_as_loads() {
    let text = format!("{FE}\n[machine]\ncontrol = \"load\"\n");
    let msg = error(&text, &[]);
    assert_has(
        &msg,
        &[
            "schedule.segment[0].to",
            "\"50 nm\" is a length",
            "expected a force",
        ],
    );
}

#[test]
fn sweep_key_must_name_an_existing_numeric_key() {
    let msg = error(
        &format!("{GOOD}\n[sweep]\nkey = \"adhesion.beta\"\nvalues = [1, 2]\n"),
        &[],
    );
    assert_has(&msg, &["sweep.key", "existing numeric key"]);
    let msg = error(
        &format!("{GOOD}\n[sweep]\nkey = \"material.model\"\nvalues = [1]\n"),
        &[],
    );
    assert_has(&msg, &["sweep.key", "existing numeric key"]);
}

#[test]
fn every_swept_value_is_validated() {
    let text =
        format!("{GOOD}\n[sweep]\nkey = \"adhesion.gamma\"\nvalues = [\"0.1 J/m^2\", \"2 nm\"]\n");
    let msg = error(&text, &[]);
    assert_has(
        &msg,
        &[
            "sweep.values[1]",
            "\"2 nm\" for adhesion.gamma",
            "expected a surface energy",
        ],
    );
}

#[test]
fn thermal_shift_from_tubes_needs_a_turf() {
    let msg = error(
        &GOOD.replace("z0 = \"0.34 nm\"", "z0 = \"0.34 nm\"\nthermal_shift = true"),
        &[],
    );
    assert_has(
        &msg,
        &["adhesion.thermal_shift", "needs [turf]", "give a length"],
    );
}

#[test]
fn a_section_no_stage_uses_is_refused() {
    let msg = error(&format!("{GOOD}\n[mesh]\ngrading = 1.2\n"), &[]);
    assert_has(&msg, &["mesh", "only used by the continuum stage"]);
    let msg = error(
        "[material]\nmodel = \"linear\"\nyoungs = 1\npoisson = 0.3\n",
        &[],
    );
    assert_has(&msg, &["material", "not used by any stage"]);
}

#[test]
fn missing_required_key_names_the_section_and_key() {
    let msg = error(&GOOD.replace("z0 = \"0.34 nm\"", ""), &[]);
    assert_has(&msg, &["line 12", "adhesion", "missing field `z0`"]);
}

#[test]
fn keys_of_another_model_are_refused() {
    let msg = error(
        &GOOD.replace("poisson = 0.3", "poisson = 0.3\nalpha = [2.0]"),
        &[],
    );
    assert_has(
        &msg,
        &["material.alpha", "is not used with model = \"linear\""],
    );
}

#[test]
fn wrong_type_is_refused() {
    let msg = error(
        &GOOD.replace("cells_per_zone = 12", "cells_per_zone = \"many\""),
        &[],
    );
    assert_has(&msg, &["halfspace.cells_per_zone", "expected"]);
}

#[test]
fn non_finite_numbers_are_refused() {
    let msg = error(&GOOD.replace("poisson = 0.3", "poisson = nan"), &[]);
    assert_has(&msg, &["material.poisson", "not a finite number"]);
}

#[test]
fn turf_too_dense_for_its_tubes_is_refused() {
    let msg = error(&TURF.replace("1e10 1/cm^2", "1e12 1/cm^2"), &[]);
    assert_has(&msg, &["turf.density", "less than a tube diameter"]);
}

#[test]
fn every_problem_is_reported_at_once() {
    let text = GOOD
        .replace("\"100 nm\"", "\"-100 nm\"")
        .replace("poisson = 0.3", "poisson = 0.6");
    let e = load_str(&text, Path::new("bad.toml"), &[]).unwrap_err();
    let keys: Vec<&str> = e.problems().iter().map(|p| p.key.as_str()).collect();
    assert_eq!(keys, ["indenter.radius", "material.poisson"]);
    assert_has(&e.to_string(), &["2 problems"]);
}

#[test]
fn collective_growth_keys_out_of_range_are_refused() {
    let text = TURF.replace(
        "length = \"7 um\"",
        "length = \"7 um\"\nmean_tilt = 1.5\nwave_coherence = 1.2",
    );
    let msg = error(&text, &[]);
    assert_has(
        &msg,
        &[
            "turf.growth.mean_tilt",
            "1.5",
            "turf.growth.wave_coherence",
            "1.2",
            "[0, 1]",
        ],
    );
}

#[test]
fn the_sphere_indenter_keys_are_checked() {
    let sphere = TURF.replace("to = 0.3", "to = 0.3\nindenter = \"sphere\"");
    load_str(
        &sphere.replace("indenter", "sphere_radius = \"500 nm\"\nindenter"),
        Path::new("good.toml"),
        &[],
    )
    .unwrap();
    let msg = error(&sphere, &[]);
    assert_has(&msg, &["bad.toml", "compression.sphere_radius", "required"]);
    let msg = error(&sphere, &["compression.sphere_radius=\"-5 nm\""]);
    assert_has(&msg, &["compression.sphere_radius", "must be positive"]);
    let msg = error(TURF, &["compression.sphere_radius=\"5 nm\""]);
    assert_has(
        &msg,
        &["compression.sphere_radius", "\"platen\"", "\"sphere\""],
    );
    let msg = error(TURF, &["compression.indenter=\"cone\""]);
    assert_has(&msg, &["compression.indenter", "`platen`", "`sphere`"]);
}

#[test]
fn the_sphere_contact_keys_are_checked() {
    let sphere = TURF.replace(
        "to = 0.3",
        "to = 0.3\nindenter = \"sphere\"\nsphere_radius = \"500 nm\"",
    );
    let adhesion = "\n[adhesion]\ngamma = \"0.46 J/m^2\"\nz0 = \"0.34 nm\"\n";
    let shifted = format!("{sphere}{adhesion}thermal_shift = \"4.6 nm\"\n");
    // valid: each adhesion with its [adhesion], stick with its settings
    for (text, sets) in [
        (
            format!("{sphere}{adhesion}"),
            vec!["compression.sphere_adhesion=\"lj\""],
        ),
        (
            shifted.clone(),
            vec!["compression.sphere_adhesion=\"lj_shifted\""],
        ),
        (
            sphere.clone(),
            vec![
                "compression.sphere_tangential=\"stick\"",
                "compression.stick_stiffness=\"50 nN/nm\"",
                "compression.stick_release=\"2 nN\"",
            ],
        ),
    ] {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        load_str(&text, Path::new("good.toml"), &sets).unwrap();
    }
    // bad values name the key and the allowed values
    let msg = error(&sphere, &["compression.sphere_adhesion=\"glue\""]);
    assert_has(
        &msg,
        &[
            "bad.toml",
            "compression.sphere_adhesion",
            "`none`",
            "`lj`",
            "`lj_shifted`",
        ],
    );
    let msg = error(&sphere, &["compression.sphere_tangential=\"slip\""]);
    assert_has(
        &msg,
        &["compression.sphere_tangential", "`frictionless`", "`stick`"],
    );
    // adhesion without [adhesion], shifted without a shift
    let msg = error(&sphere, &["compression.sphere_adhesion=\"lj\""]);
    assert_has(&msg, &["compression.sphere_adhesion", "needs [adhesion]"]);
    let msg = error(
        &format!("{sphere}{adhesion}"),
        &["compression.sphere_adhesion=\"lj_shifted\""],
    );
    assert_has(
        &msg,
        &["compression.sphere_adhesion", "thermal_shift", "\"lj\""],
    );
    // the sphere's keys on a platen, stick keys without stick, bad stick values
    let msg = error(TURF, &["compression.sphere_tangential=\"stick\""]);
    assert_has(
        &msg,
        &["compression.sphere_tangential", "indenter = \"sphere\""],
    );
    let msg = error(&sphere, &["compression.stick_stiffness=\"5 nN/nm\""]);
    assert_has(
        &msg,
        &[
            "compression.stick_stiffness",
            "sphere_tangential = \"stick\"",
        ],
    );
    let stick = "compression.sphere_tangential=\"stick\"";
    let msg = error(
        &sphere,
        &[stick, "compression.stick_stiffness=\"-5 nN/nm\""],
    );
    assert_has(&msg, &["compression.stick_stiffness", "must be positive"]);
    let msg = error(&sphere, &[stick, "compression.stick_release=\"-1 nN\""]);
    assert_has(&msg, &["compression.stick_release", ">= 0"]);
    // [adhesion] with a frictionless, non-adhesive discrete sphere is used by nothing
    let msg = error(&format!("{sphere}{adhesion}"), &[]);
    assert_has(&msg, &["adhesion", "not used by any stage"]);
    // the retract: an adhesive sphere that unloads; its steps only with it
    let lj = "compression.sphere_adhesion=\"lj\"";
    let (unload, retract) = ("compression.unload=true", "compression.retract=\"5 nm\"");
    let adhesive = format!("{sphere}{adhesion}");
    let sets: Vec<String> = [lj, unload, retract, "compression.retract_steps=10"]
        .map(String::from)
        .to_vec();
    load_str(&adhesive, Path::new("good.toml"), &sets).unwrap();
    let msg = error(&sphere, &[unload, retract]);
    assert_has(
        &msg,
        &["compression.retract", "sphere_adhesion", "pull-off"],
    );
    let msg = error(&adhesive, &[lj, "compression.unload=false", retract]);
    assert_has(&msg, &["compression.retract", "unload = true"]);
    let msg = error(&adhesive, &[lj, unload, "compression.retract=\"-5 nm\""]);
    assert_has(&msg, &["compression.retract", "must be positive"]);
    let msg = error(&adhesive, &[lj, unload, "compression.retract_steps=10"]);
    assert_has(
        &msg,
        &["compression.retract_steps", "without compression.retract"],
    );
    let msg = error(
        &adhesive,
        &[lj, unload, retract, "compression.retract_steps=0"],
    );
    assert_has(&msg, &["compression.retract_steps"]);
}

// ---------------------------------------------------------------------------------------------
// Issue 23: every size bounded before it is allocated, every number representable

/// The rods scene of the memory tests: one cantilever of `segments` segments.
fn rods(segments: &str) -> String {
    format!(
        r#"[rods.tube]
r_o = "20 nm"
r_i = "17.3 nm"
youngs = "0.4 TPa"

[[rods.rod]]
points = [["0 nm", "0 nm", "0 nm"], ["7 um", "0 nm", "0 nm"]]
segments = {segments}
"#
    )
}

/// Sizes far beyond any machine's memory (petabytes and more, so any ceiling refuses them):
/// each is refused by the loader, before anything is allocated, naming its key, the estimate,
/// the ceiling and how to lower it.
#[test]
fn sizes_beyond_the_memory_ceiling_are_refused_naming_their_keys() {
    let e = error(TURF, &["turf.box=[\"1 m\", \"1 m\"]"]);
    assert_has(
        &e,
        &[
            "turf.box",
            "1.000e14 tubes",
            "memory ceiling",
            "smaller turf.box or turf.density",
        ],
    );
    let e = error(GOOD, &["halfspace.cells_per_zone=1000000000"]);
    assert_has(
        &e,
        &[
            "halfspace.cells_per_zone",
            "grid nodes",
            "memory ceiling",
            "lower halfspace.cells_per_zone",
        ],
    );
    let e = error(&rods("1000000000000"), &[]);
    assert_has(
        &e,
        &[
            "rods.rod[0].segments",
            "rod nodes",
            "memory ceiling",
            "fewer segments",
        ],
    );
    let e = error(FE, &["mesh.max_elements=1000000000000000"]);
    assert_has(
        &e,
        &[
            "mesh.max_elements",
            "1.000e15 elements",
            "memory ceiling",
            "at most",
        ],
    );
    // a tube segment of a femtometre along a 7 µm tube: 7e9 segments per tube
    let e = error(TURF, &["turf.tube.segment=1e-6"]);
    assert_has(&e, &["turf.box", "turf.tube.segment", "memory ceiling"]);
}

#[test]
fn the_memory_estimate_of_a_valid_scene_is_in_its_plan() {
    let l = load_str(&rods("20"), Path::new("r.toml"), &[]).unwrap();
    let m = l.base.plan.memory.expect("a memory estimate");
    assert!(m.ceiling.bytes > 0.0);
    assert_eq!(m.stages.len(), 1);
    assert!(m.stages[0].bytes > 0.0 && m.stages[0].bytes < 1e6);
    let l = load_str(GOOD, Path::new("g.toml"), &[]).unwrap();
    let hs = &l.base.plan.memory.unwrap().stages[0];
    assert!(hs.bytes > 1e3 && hs.bytes < 1e9, "{hs:?}");
}

#[test]
fn cells_per_zone_must_be_a_whole_number() {
    let e = error(GOOD, &["halfspace.cells_per_zone=12.5"]);
    assert_has(&e, &["halfspace.cells_per_zone", "12.5", "whole number"]);
}

#[test]
fn an_empty_output_folder_is_refused() {
    let e = error(GOOD, &["output.dir=\"\""]);
    assert_has(&e, &["output.dir", "name a folder"]);
}

#[test]
fn homogenize_terms_are_limited_to_what_the_fit_supports() {
    let law = "[homogenize]\ncurve = \"tangent-law\"\ne0 = \"700 MPa\"\ne_inf = \"70 MPa\"\neps0 = 0.05\n";
    load_str(&format!("{law}terms = 3\n"), Path::new("h.toml"), &[]).unwrap();
    let e = error(&format!("{law}terms = 4\n"), &[]);
    assert_has(&e, &["homogenize.terms", "4", "1..=3"]);
}

/// A ramp given by its time gets its rate resolved at load (it failed at run time with "rate
/// unresolved"); a time or rate whose rate or duration is not a finite positive number is
/// refused naming the key.
#[test]
fn a_ramp_given_by_time_is_resolved_and_unrepresentable_ones_are_refused() {
    let by_time = FE.replacen("rate = \"10 nm/s\"", "time = \"5 s\"", 1);
    let l = load_str(&by_time, Path::new("t.toml"), &[]).unwrap();
    let seg = &l.base.scene.schedule.as_ref().unwrap().segment[0];
    assert_eq!(
        seg.rate.as_ref().and_then(|r| r.number()),
        Some(10.0),
        "{seg:?}"
    );
    // 1e-300 s is representable: a rate of 5e301 nm/s
    let instant = FE.replacen("rate = \"10 nm/s\"", "time = \"1e-300 s\"", 1);
    load_str(&instant, Path::new("t.toml"), &[]).unwrap();
    let subnormal = FE.replacen("rate = \"10 nm/s\"", "time = \"1e-320 s\"", 1);
    let e = error(&subnormal, &[]);
    assert_has(&e, &["schedule.segment[0].time", "finite positive"]);
    let e = error(FE, &["schedule.segment[0].rate=1e-320"]);
    assert_has(&e, &["schedule.segment[0].rate", "finite positive time"]);
}

/// E = 1e300 GPa: E*² overflows, Tabor μ and Maugis λ come out 0 and the theory stage failed
/// at run time without naming a key.
#[test]
fn a_modulus_beyond_double_precision_is_refused_at_material_youngs() {
    let e = error(GOOD, &["material.youngs=1e300"]);
    assert_has(&e, &["material.youngs", "Tabor μ = 0", "double precision"]);
}

#[test]
fn a_halfspace_beyond_its_validated_tabor_range_is_refused_at_check() {
    // γ = 5 J/m² on this sphere: μ ≈ 21
    let e = error(GOOD, &["adhesion.gamma=5 J/m^2"]);
    assert_has(
        &e,
        &["halfspace", "Tabor μ", "validated range μ ≤ 10", "JKR"],
    );
}

#[test]
fn the_compression_mode_is_checked() {
    let msg = error(&TURF.replace("to = 0.3", "to = 0.3\nmode = \"twist\""), &[]);
    assert_has(
        &msg,
        &[
            "bad.toml",
            "compression.mode",
            "twist",
            "`axial`",
            "`lateral`",
            "`shear`",
        ],
    );
    let sphere = "to = 0.3\nmode = \"shear\"\nindenter = \"sphere\"\nsphere_radius = \"300 nm\"";
    let msg = error(&TURF.replace("to = 0.3", sphere), &[]);
    assert_has(
        &msg,
        &["compression.mode", "\"shear\"", "indenter = \"platen\""],
    );
    let homogenize = format!("{TURF}mode = \"lateral\"\n\n[homogenize]\ncurve = \"loading\"\n");
    let msg = error(&homogenize, &[]);
    assert_has(
        &msg,
        &["compression.mode", "only \"axial\"", "[homogenize]"],
    );
    for mode in ["lateral", "shear"] {
        let text = TURF.replace("to = 0.3", &format!("to = 0.3\nmode = \"{mode}\""));
        load_str(&text, Path::new("good.toml"), &[]).unwrap();
    }
}

#[test]
fn a_packing_must_be_denser_than_the_growth_and_leave_room_for_the_tubes() {
    let packed = |d: &str| {
        TURF.replace(
            "[compression]",
            &format!("[turf.packing]\ndensity = \"{d}\"\n\n[compression]"),
        )
    };
    let msg = error(&packed("0.5e10 1/cm^2"), &[]);
    assert_has(
        &msg,
        &[
            "bad.toml",
            "turf.packing.density",
            "must exceed turf.density",
        ],
    );
    // 8e10 /cm²: a mean spacing of 35.4 nm for tubes 40 nm across
    let msg = error(&packed("8e10 1/cm^2"), &[]);
    assert_has(&msg, &["turf.packing.density", "less than a tube diameter"]);
    let msg = error(&packed("3e10 1/cm^2"), &["turf.periodic=false"]);
    assert_has(&msg, &["turf.packing", "needs a periodic box"]);
    // a table created by --set is named as coming from it, not by the line of [turf]
    let msg = error(TURF, &["turf.packing.density=\"0.5e10 1/cm^2\""]);
    assert_has(&msg, &["turf.packing.density (from --set)", "must exceed"]);
    let sound = packed("3e10 1/cm^2");
    if cfg!(feature = "rapier") {
        load_str(&sound, Path::new("good.toml"), &[]).unwrap();
    } else {
        let msg = error(&sound, &[]);
        assert_has(&msg, &["turf.packing", "cargo feature `rapier`"]);
    }
}
