//! `turf theory` run as a user would: JSON out, units in, clear errors.

use std::process::Command;

fn turf(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_turf"))
        .args(args)
        .output()
        .expect("the turf binary runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn json(args: &[&str]) -> serde_json::Value {
    let (ok, out, err) = turf(args);
    assert!(ok, "{args:?} failed: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

#[test]
fn pulloff_json() {
    let v = json(&["theory", "pulloff", "--model", "jkr", "--json"]);
    assert_eq!(v["pull_off_normalized"], -1.5);
    assert_eq!(v["model"], "jkr");
    let v = json(&[
        "theory",
        "pulloff",
        "--model",
        "jkr",
        "--control",
        "displacement",
        "--json",
    ]);
    assert!((v["pull_off_normalized"].as_f64().unwrap() + 5.0 / 6.0).abs() < 1e-12);
    let v = json(&[
        "theory", "pulloff", "--model", "maugis", "--lambda", "1000", "--json",
    ]);
    assert!((v["pull_off_normalized"].as_f64().unwrap() + 1.5).abs() < 1e-2);
    let v = json(&[
        "theory", "pulloff", "--model", "maugis", "--mu", "1", "--json",
    ]);
    // --mu converts through the LJ 9-3 law: λ = 1.157 μ
    assert!((v["lambda"].as_f64().unwrap() - 1.1573).abs() < 1e-3);
}

#[test]
fn tabor_json_with_units() {
    let v = json(&[
        "theory",
        "tabor",
        "--radius",
        "1.8 um",
        "--modulus",
        "1 GPa",
        "--gamma",
        "0.46 J/m^2",
        "--z0",
        "0.34 nm",
        "--json",
    ]);
    // μ = (Rγ²/(E*²z₀³))^(1/3) = (1800·0.2116/0.039304)^(1/3)
    let mu = (1800.0f64 * 0.46 * 0.46 / 0.34f64.powi(3)).cbrt();
    assert!((v["mu"].as_f64().unwrap() - mu).abs() < 1e-9 * mu);
    assert!((v["lambda"].as_f64().unwrap() / mu - 1.1573).abs() < 1e-3);
}

#[test]
fn thermal_json_for_the_seed_tube() {
    let v = json(&[
        "theory",
        "thermal",
        "--length",
        "7 um",
        "--ro",
        "20 nm",
        "--ri",
        "17.3 nm",
        "--youngs",
        "0.4 TPa",
        "--temperature",
        "300 K",
        "--json",
    ]);
    assert!((v["u_rms_nm"].as_f64().unwrap() - 4.626).abs() < 0.005);
}

#[test]
fn curve_writes_csv_and_plots() {
    let dir = std::env::temp_dir().join(format!("turf-theory-cli-{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let v = json(&[
        "theory",
        "curve",
        "--model",
        "maugis",
        "--radius",
        "1.8 um",
        "--modulus",
        "1 GPa",
        "--gamma",
        "0.46 J/m^2",
        "--lambda",
        "1",
        "--points",
        "30",
        "--out",
        d,
        "--json",
    ]);
    assert_eq!(v["points"], 30);
    let csv = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    assert!(csv.starts_with("depth_nm,load_nN,contact_radius_nm,a_bar,p_bar,delta_bar"));
    assert_eq!(csv.lines().count(), 31);
    assert!(dir.join("plots/curve.svg").exists() && dir.join("plots/curve.png").exists());
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_input_gives_a_clear_message() {
    let (ok, _, err) = turf(&[
        "theory",
        "tabor",
        "--radius",
        "1.8 GPa",
        "--modulus",
        "1 GPa",
        "--gamma",
        "0.46 J/m^2",
        "--z0",
        "0.34 nm",
    ]);
    assert!(!ok);
    assert!(err.contains("--radius") && err.contains("length"), "{err}");
    let (ok, _, err) = turf(&["theory", "pulloff", "--model", "maugis", "--lambda=-2"]);
    assert!(!ok);
    assert!(err.contains("λ must be positive"), "{err}");
    assert!(!err.contains("panicked"));
    let (ok, _, err) = turf(&["theory", "pulloff", "--model", "maugis", "--lambda", "abc"]);
    assert!(!ok && err.contains("abc"), "{err}");
}

#[test]
fn halfspace_json_reports_pull_off_error_and_cost() {
    // μ = 0.05 is near the DMT limit: −2 within the 1.5 % of tests/integration/halfspace_limits.rs
    let v = json(&["theory", "halfspace", "--mu", "0.05", "--json"]);
    let p = v["pull_off_normalized"].as_f64().unwrap();
    assert!((p + 2.0).abs() < 0.03, "{p}");
    assert!(v["error_estimate"].as_f64().unwrap() < 1e-3);
    assert_eq!(v["levels"].as_array().unwrap().len(), 3);
    assert!(v["cost"]["newton_iterations"].as_u64().unwrap() > 0);
    let (ok, _, err) = turf(&["theory", "halfspace", "--mu=-1"]);
    assert!(!ok && err.contains("μ"), "{err}");
}

/// `turf theory law` for both laws: the stretch, peak and intercept of PHYSICS.md's seed
/// numbers (γ = 0.46 J/m², z₀ = 0.34 nm, u = 4.626 nm, quoted to four figures), the process
/// zone E*γ/σ_peak², and the p(h) table with its plot.
#[test]
fn law_json_for_both_laws_with_the_seed_numbers() {
    // (law, b, σ_max/b in GPa)
    for (law, b, peak) in [("lj104", 17.46, 0.1136), ("lj93", 13.68, 0.1015)] {
        let dir =
            std::env::temp_dir().join(format!("turf-theory-law-{law}-{}", std::process::id()));
        let v = json(&[
            "theory",
            "law",
            "--law",
            law,
            "--gamma",
            "0.46 J/m^2",
            "--z0",
            "0.34 nm",
            "--shift",
            "4.626 nm",
            "--modulus",
            "700 MPa",
            "--out",
            dir.to_str().unwrap(),
            "--json",
        ]);
        let f = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"));
        assert_eq!(v["law"], law);
        assert!((f("stretch") - b).abs() < 6e-4 * b, "{v}");
        assert!((f("peak_tension_GPa") - peak).abs() < 6e-4 * peak, "{v}");
        assert!((f("peak_tension_GPa") * f("stretch") - f("base_peak_tension_GPa")).abs() < 1e-12);
        let ell = 0.7 * 0.46 / f("peak_tension_GPa").powi(2);
        assert!((f("process_zone_nm") - ell).abs() < 1e-12 * ell);
        assert!(f("tangent_intercept_nm") > 4.626 + 0.34);
        let csv = std::fs::read_to_string(dir.join("law.csv")).unwrap();
        assert!(csv.starts_with("gap_nm,base_pressure_GPa,shifted_pressure_GPa"));
        assert!(dir.join("plots/law.svg").exists());
        std::fs::remove_dir_all(&dir).ok();
    }
    // from the tube: u of seed eq. 5.9 (4.626 nm for the seed's tube); no --modulus, no zone
    let v = json(&[
        "theory",
        "law",
        "--gamma",
        "0.46 J/m^2",
        "--z0",
        "0.34 nm",
        "--thermal-tube",
        "7 um,20 nm,17.3 nm,0.4 TPa,300 K",
        "--json",
    ]);
    assert!((v["u_nm"].as_f64().unwrap() - 4.626).abs() < 1e-3, "{v}");
    assert!(v.get("process_zone_nm").is_none());
    // a malformed tube and a negative shift are refused by name
    for (bad, flag) in [
        (
            ["--thermal-tube", "7 um,20 nm"].as_slice(),
            "--thermal-tube",
        ),
        (["--shift=-1 nm"].as_slice(), "--shift"),
    ] {
        let args: Vec<&str> = ["theory", "law", "--gamma", "1", "--z0", "1"]
            .into_iter()
            .chain(bad.iter().copied())
            .collect();
        let (ok, _, err) = turf(&args);
        assert!(!ok && err.contains(flag), "{err}");
    }
}

/// Issue 23: a count beyond 10⁷ points or samples is refused before anything is allocated or
/// written, naming the flag and the maximum.
#[test]
fn counts_beyond_the_maximum_are_refused_naming_the_flag() {
    let out = std::env::temp_dir().join(format!("turf-counts-{}", std::process::id()));
    let o = out.to_str().unwrap();
    let (ok, _, err) = turf(&[
        "theory",
        "curve",
        "--model",
        "hertz",
        "--radius",
        "1 um",
        "--modulus",
        "1 GPa",
        "--points",
        "1000000000",
        "--out",
        o,
    ]);
    assert!(
        !ok && err.contains("--points 1000000000") && err.contains("10000000"),
        "{err}"
    );
    let (ok, _, err) = turf(&[
        "theory",
        "indentation-law",
        "--machine-k1",
        "200 N/m",
        "--machine-k2",
        "1e5 N/m",
        "--specimen-k1",
        "100 N/m",
        "--specimen-k2",
        "50 N/m",
        "--viscosity",
        "1 uN*s/nm",
        "--peak",
        "10 uN",
        "--load-time",
        "10 s",
        "--hold-time",
        "10 s",
        "--unload-time",
        "10 s",
        "--samples",
        "1000000000",
        "--out",
        o,
    ]);
    assert!(!ok && err.contains("--samples 1000000000"), "{err}");
    let law = "E0=700MPa,Einf=70MPa,eps0=0.05";
    let (ok, _, err) = turf(&[
        "homogenize",
        "--tangent-law",
        law,
        "--samples",
        "1000000000",
        "--out",
        o,
    ]);
    assert!(!ok && err.contains("--samples 1000000000"), "{err}");
    // hyperfoam terms: 1 to 3, as homogenize.terms in a scene
    for n in ["0", "4"] {
        let (ok, _, err) = turf(&["homogenize", "--tangent-law", law, "--terms", n, "--out", o]);
        assert!(
            !ok && err.contains(&format!("--terms {n}")) && err.contains("1..=3"),
            "{err}"
        );
    }
    assert!(!out.exists(), "a refused command wrote {}", out.display());
}

/// Issue 23: a tube of 1e300 nm overflows u = (0.4243 l³kT/(Y(r_o⁴ − r_i⁴)))^(1/2); it printed
/// `"u_rms_nm": null` and exited 0.
#[test]
fn thermal_amplitude_beyond_double_precision_is_an_error() {
    let (ok, out, err) = turf(&[
        "theory", "thermal", "--length", "1e300", "--ro", "20 nm", "--ri", "17.3 nm", "--youngs",
        "0.4 TPa", "--json",
    ]);
    assert!(!ok, "{out}");
    assert!(
        err.contains("--length 1e300") && err.contains("not finite"),
        "{err}"
    );
    assert!(!out.contains("null"), "{out}");
}

#[test]
fn halfspace_beyond_its_validated_range_is_refused_with_the_reason() {
    let (ok, _, err) = turf(&["theory", "halfspace", "--mu", "100", "--json"]);
    assert!(!ok);
    assert!(
        err.contains("validated range μ ≤ 10") && err.contains("JKR"),
        "{err}"
    );
}
