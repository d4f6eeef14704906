//! The stage end to end through files: a curve CSV in, `material.json` and `material.inp` out,
//! both read back to the same material; bad curve files refused with the file and the reason.

use turf::homogenize::{self, HomogenizeParams, Relaxation, Source};

/// one unit in the last place
const JSON_TOL_REL: f64 = 1e-15;
/// the .inp carries ten significant digits
const INP_TOL_REL: f64 = 1e-9;

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("turf-hz-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn a_curve_file_becomes_two_cards_that_read_back_alike() {
    let dir = tmp("cards");
    let law = homogenize::tangent_law::TangentLaw::seed(0.1);
    let mut csv = String::from("strain,stress_MPa\n");
    for k in 0..=60 {
        let e = 0.005 * k as f64;
        csv.push_str(&format!("{e},{}\n", 1e3 * law.stress(e)));
    }
    let path = dir.join("curve.csv");
    std::fs::write(&path, csv).unwrap();
    let curve = homogenize::read_curve(&path).unwrap();
    let mut p = HomogenizeParams::new(Source::Curve {
        curve,
        name: path.display().to_string(),
    });
    p.terms = 2;
    p.relaxation = Some(Relaxation::Law {
        mu_bar: 0.4,
        tau: 3.0,
    });
    let out = homogenize::run(&p).unwrap();
    // the curve is the law itself: the fitted law is the law
    let f = out.tangent_fit.as_ref().unwrap();
    assert!((f.law.eps0 / 0.1 - 1.0).abs() < 1e-6, "{:?}", f.law);
    let s = homogenize::write_outputs(&out, &dir.join("out")).unwrap();
    assert!(
        s.fit_rms_rel < 0.02,
        "the hyperfoam fits the law to 2 %: {}",
        s.fit_rms_rel
    );
    let j = homogenize::read_card(&dir.join("out/material.json")).unwrap();
    let i = homogenize::read_card(&dir.join("out/material.inp")).unwrap();
    assert_eq!(j.prony, out.card.prony);
    for (a, b) in j.hyperfoam.terms.iter().zip(&out.card.hyperfoam.terms) {
        // serde_json's float parser may differ from the written value in the last bit
        assert!(
            (a.mu / b.mu - 1.0).abs() < JSON_TOL_REL
                && (a.alpha / b.alpha - 1.0).abs() < JSON_TOL_REL
        );
    }
    for (a, b) in i.hyperfoam.terms.iter().zip(&j.hyperfoam.terms) {
        assert!(
            (a.mu / b.mu - 1.0).abs() < INP_TOL_REL
                && (a.alpha / b.alpha - 1.0).abs() < INP_TOL_REL
        );
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
            .unwrap();
    for key in ["hyperfoam", "tangent_law", "prony", "fit_rms_rel"] {
        assert!(summary.get(key).is_some(), "{key}");
    }
    assert_eq!(summary["prony"]["tau_s"][0], 3.0);
    assert!(summary["tangent_law"]["E0_GPa"].is_number());
    assert!(dir.join("out/plots/homogenize.svg").exists());
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_curve_files_are_refused_naming_the_file() {
    let dir = tmp("bad");
    let cases = [
        ("few.csv", "strain,stress_MPa\n0,0\n0.1,1\n", "at least"),
        (
            "order.csv",
            "strain,stress_MPa\n0,0\n0.02,1\n0.01,2\n0.03,3\n0.04,4\n0.05,5\n",
            "increase strictly",
        ),
        (
            "nan.csv",
            "strain,stress_MPa\n0,0\n0.01,nan\n0.02,2\n0.03,3\n0.04,4\n0.05,5\n",
            "finite",
        ),
        (
            "cols.csv",
            "strain,load_N\n0,0\n0.01,1\n0.02,2\n0.03,3\n0.04,4\n0.05,5\n",
            "unknown column",
        ),
    ];
    for (name, text, why) in cases {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let e = homogenize::read_curve(&p).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(why), "{e}");
    }
    std::fs::remove_dir_all(dir).ok();
}
