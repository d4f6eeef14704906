//! Synthetic data with known constants plus Gaussian noise: the fits recover the constants
//! within the standard errors they report, and those errors are calibrated (z-scores over many
//! noise seeds have unit spread).

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use turf::homogenize::curve::StressStrainCurve;
use turf::homogenize::fit_hyperfoam::{fit_hyperfoam, HyperfoamFitParams};
use turf::homogenize::hyperfoam::{beta_from_nu, Hyperfoam, Mode};
use turf::homogenize::tangent_law::{fit_tangent_law, TangentFitParams, TangentLaw};

/// |fitted − true| ≤ 3 standard errors for every constant (a 3σ band; with seeded noise the
/// outcome is deterministic).
const Z_MAX: f64 = 3.0;
/// Root-mean-square z over many seeds must be near 1 if the reported errors are right; the band
/// allows the sampling spread of an RMS over 4 × 40 values (±~15 %) plus nonlinearity.
const Z_RMS_BAND: (f64, f64) = (0.7, 1.4);
/// The errors must also be small enough for the test to mean something.
const SE_REL_MAX: f64 = 0.2;

/// Stress noise: 0.5 % of the peak stress.
const NOISE: f64 = 0.005;

fn normal(rng: &mut Pcg64) -> f64 {
    // Box–Muller
    let u: f64 = rng.random_range(f64::EPSILON..1.0);
    let v: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

fn truth(nu: f64) -> Hyperfoam {
    let b = beta_from_nu(nu);
    Hyperfoam::new(&[0.3, 0.05], &[15.0, 2.0], &[b, b]).unwrap()
}

/// 100 points on (0, 0.5], stress noise `noise` × the peak, lateral noise 1e-3.
fn data(m: &Hyperfoam, seed: u64, lateral: bool, noise: f64) -> StressStrainCurve {
    let mut rng = Pcg64::seed_from_u64(seed);
    let strain: Vec<f64> = (1..=100).map(|k| 0.005 * k as f64).collect();
    let states: Vec<_> = strain
        .iter()
        .map(|&e| m.drive(Mode::Uniaxial, 1.0 - e).unwrap())
        .collect();
    let peak = -states.last().unwrap().nominal[0];
    let stress = states
        .iter()
        .map(|s| -s.nominal[0] + noise * peak * normal(&mut rng))
        .collect();
    let lat = lateral.then(|| {
        states
            .iter()
            .map(|s| s.stretch[1] - 1.0 + 1e-3 * normal(&mut rng))
            .collect()
    });
    StressStrainCurve::new(strain, stress, lat, "synthetic").unwrap()
}

fn params() -> HyperfoamFitParams {
    HyperfoamFitParams {
        terms: 2,
        strain_max: 0.5,
        ..Default::default()
    }
}

/// z-scores of (μ₁, μ₂, α₁, α₂) and β, terms matched by descending α.
fn zscores(m: &Hyperfoam, seed: u64, lateral: bool, noise: f64) -> (Vec<f64>, Option<f64>) {
    let f = fit_hyperfoam(&data(m, seed, lateral, noise), &params()).unwrap();
    let se = f.std_errors.clone().expect("noisy data give a covariance");
    let mut idx: Vec<usize> = (0..2).collect();
    idx.sort_by(|&a, &b| {
        f.material.terms[b]
            .alpha
            .total_cmp(&f.material.terms[a].alpha)
    });
    let mut z = Vec::new();
    for (k, &i) in idx.iter().enumerate() {
        let (got, want) = (f.material.terms[i], m.terms[k]);
        assert!(
            se.mu[i] < SE_REL_MAX * want.mu && se.alpha[i] < SE_REL_MAX * want.alpha,
            "{se:?}"
        );
        z.push((got.mu - want.mu) / se.mu[i]);
        z.push((got.alpha - want.alpha) / se.alpha[i]);
    }
    let zb = lateral.then(|| (f.material.terms[0].beta - m.terms[0].beta) / se.beta);
    (z, zb)
}

#[test]
fn two_term_hyperfoam_is_recovered_within_its_standard_errors() {
    let m = truth(0.0);
    let (z, _) = zscores(&m, 1, false, NOISE);
    assert!(z.iter().all(|z| z.abs() <= Z_MAX), "{z:?}");
    let all: Vec<f64> = (0..40)
        .flat_map(|s| zscores(&m, 100 + s, false, NOISE).0)
        .collect();
    let rms = (all.iter().map(|z| z * z).sum::<f64>() / all.len() as f64).sqrt();
    assert!(rms > Z_RMS_BAND.0 && rms < Z_RMS_BAND.1, "z rms {rms}");
}

#[test]
fn lateral_strain_fixes_beta() {
    let m = truth(0.2);
    // with ν > 0 the two terms are less distinct over this range: less noise keeps the
    // errors below SE_REL_MAX
    let (z, zb) = zscores(&m, 2, true, NOISE / 5.0);
    assert!(z.iter().all(|z| z.abs() <= Z_MAX), "{z:?}");
    assert!(zb.unwrap().abs() <= Z_MAX, "{zb:?}");
    // without the lateral column the fit assumes β = 0
    let f = fit_hyperfoam(&data(&m, 2, false, NOISE), &params()).unwrap();
    assert!(f.material.terms.iter().all(|t| t.beta == 0.0));
}

#[test]
fn tangent_law_is_recovered_within_its_standard_errors() {
    let law = TangentLaw::seed(0.075);
    let mut zs = Vec::new();
    for seed in 0..30 {
        let mut rng = Pcg64::seed_from_u64(seed);
        let strain: Vec<f64> = (1..=80).map(|k| 0.005 * k as f64).collect();
        let stress = strain
            .iter()
            .map(|&e| law.stress(e) + 2e-4 * normal(&mut rng))
            .collect();
        let c = StressStrainCurve::new(strain, stress, None, "synthetic").unwrap();
        let f = fit_tangent_law(&c, &TangentFitParams::default()).unwrap();
        let se = f.std_errors.unwrap();
        let got = [f.law.e0, f.law.e_inf, f.law.eps0];
        let want = [law.e0, law.e_inf, law.eps0];
        for k in 0..3 {
            assert!(se[k] < SE_REL_MAX * want[k], "{se:?}");
            let z = (got[k] - want[k]) / se[k];
            if seed == 0 {
                assert!(z.abs() <= Z_MAX, "{k}: {z}");
            }
            zs.push(z);
        }
    }
    let rms = (zs.iter().map(|z| z * z).sum::<f64>() / zs.len() as f64).sqrt();
    assert!(rms > Z_RMS_BAND.0 && rms < Z_RMS_BAND.1, "z rms {rms}");
}

/// Issue 23: a curve saved by a spreadsheet — UTF-8 byte-order mark, quoted header and
/// fields — reads as the plain CSV does (it was refused).
#[test]
fn a_curve_with_a_bom_and_quoted_fields_reads_like_the_plain_one() {
    let plain =
        "strain,stress_MPa\n0.01,6.3\n0.02,11.4\n0.03,15.6\n0.04,19.2\n0.05,22.3\n0.06,25.0\n";
    let quoted = "\u{feff}\"strain\",\"stress_MPa\"\r\n\"0.01\",\"6.3\"\r\n\"0.02\", \"11.4\"\r\n\"0.03\",\"15.6\"\r\n\"0.04\",\"19.2\"\r\n\"0.05\",\"22.3\"\r\n\"0.06\",\"25.0\"\r\n";
    let a = StressStrainCurve::from_csv(plain, "plain.csv").unwrap();
    let b = StressStrainCurve::from_csv(quoted, "quoted.csv").unwrap();
    assert_eq!(a.strain, b.strain);
    assert_eq!(a.stress, b.stress);
}
