//! Closed-form adhesion theory against its limits and published values: Maugis–Dugdale tends to
//! DMT (λ → 0) and JKR (λ → ∞) point by point and in its pull-off, is monotonic in between and
//! matches the Carpick–Ogletree–Salmeron fit of Maugis' curve at λ = 1; JKR −3/2 and −5/6;
//! DMT −2; Hertz; the seed's thermal amplitude.

use turf::theory::maugis::{self, MaugisParams};
use turf::theory::thermal::Cantilever;
use turf::theory::{dmt, jkr, Control, Model, Sphere};

/// MD at λ = 1e3 differs from JKR by O(1/λ) (the Dugdale zone width ~ 1/(λ²ā) of a): 1e-2
/// covers the measured ~2e-3 with margin but fails for any O(1) error.
const JKR_LIMIT_TOL: f64 = 1e-2;
/// MD at λ = 1e-3 differs from DMT by O(λ^(1/2)): measured ~3e-3.
const DMT_LIMIT_TOL: f64 = 1e-2;

/// λ of the point-by-point DMT comparison
const SMALL_LAMBDA: f64 = 1e-5;

fn params() -> MaugisParams {
    MaugisParams::default()
}

#[test]
fn maugis_pull_off_tends_to_dmt_and_jkr() {
    let small = maugis::pull_off(1e-3, Control::Load, &params()).unwrap();
    let large = maugis::pull_off(1e3, Control::Load, &params()).unwrap();
    println!("λ=1e-3: {small:?}\nλ=1e3: {large:?}");
    assert!((small.p_bar - dmt::PULL_OFF).abs() < DMT_LIMIT_TOL);
    assert!((large.p_bar - jkr::PULL_OFF_LOAD).abs() < JKR_LIMIT_TOL);
    // JKR pull-off at ā³ = 3/2
    assert!((large.a_bar - 1.5f64.cbrt()).abs() < 2.0 * JKR_LIMIT_TOL);
    let small = maugis::pull_off(1e-3, Control::Displacement, &params()).unwrap();
    let large = maugis::pull_off(1e3, Control::Displacement, &params()).unwrap();
    println!("displacement: λ=1e-3: {small:?}\nλ=1e3: {large:?}");
    assert!((small.p_bar - dmt::PULL_OFF).abs() < DMT_LIMIT_TOL);
    assert!((large.p_bar - jkr::PULL_OFF_DISPLACEMENT).abs() < JKR_LIMIT_TOL);
    // JKR jump-off under displacement control at ā³ = 1/6
    assert!((large.a_bar - (1.0f64 / 6.0).cbrt()).abs() < 2.0 * JKR_LIMIT_TOL);
}

#[test]
fn maugis_pull_off_is_monotonic_in_lambda() {
    let mut last = f64::NEG_INFINITY;
    for i in 0..=24 {
        let lambda = 10f64.powf(-3.0 + 6.0 * i as f64 / 24.0);
        let p = maugis::pull_off(lambda, Control::Load, &params())
            .unwrap()
            .p_bar;
        println!("λ = {lambda:.4e}: P̄ = {p:.6}");
        assert!(p > last, "not increasing at λ = {lambda}: {p} after {last}");
        assert!((-2.0..=-1.5).contains(&p));
        last = p;
    }
}

/// The Carpick–Ogletree–Salmeron (1999, J. Colloid Interface Sci. 211, 395) fit of Maugis' pull-off,
/// P̄ = −7/4 + (1/4)(4.04λ^1.4 − 1)/(4.04λ^1.4 + 1), stated accurate to about 1 %.
fn cos_fit(lambda: f64) -> f64 {
    let x = 4.04 * lambda.powf(1.4);
    -1.75 + 0.25 * (x - 1.0) / (x + 1.0)
}

#[test]
fn maugis_pull_off_matches_the_published_curve() {
    // the fit's own error: it departs from the exact Maugis curve by up to ~1.7 % of |P̄|
    // near λ ≈ 0.3 (measured here: 0.030) and ~0.1 % at λ = 1
    const FIT_TOL: f64 = 0.035;
    for lambda in [0.1, 0.3, 1.0, 3.0, 10.0] {
        let p = maugis::pull_off(lambda, Control::Load, &params())
            .unwrap()
            .p_bar;
        println!("λ = {lambda}: P̄ = {p:.5}, COS fit {:.5}", cos_fit(lambda));
        assert!((p - cos_fit(lambda)).abs() < FIT_TOL, "λ = {lambda}: {p}");
    }
}

#[test]
fn maugis_reproduces_jkr_and_dmt_curves_point_by_point() {
    for a in [0.3, 0.7, 1.0, 1.5, 2.5] {
        let md = maugis::point(1e3, a, &params()).unwrap();
        let j = jkr::normalized(a);
        assert!(
            (md.p_bar - j.p_bar).abs() < JKR_LIMIT_TOL,
            "ā={a}: {} vs {}",
            md.p_bar,
            j.p_bar
        );
        assert!((md.delta_bar - j.delta_bar).abs() < JKR_LIMIT_TOL, "ā={a}");
        // the curve approaches DMT like √λ·ā² (0.02 at ā = 2.5 for λ = 1e-3): compare at 1e-5
        let md = maugis::point(SMALL_LAMBDA, a, &params()).unwrap();
        let d = dmt::normalized(a);
        assert!(
            (md.p_bar - d.p_bar).abs() < DMT_LIMIT_TOL,
            "ā={a}: {} vs {}",
            md.p_bar,
            d.p_bar
        );
        // the Dugdale zone (c̄ ≈ 2/√(πλ)) lowers δ̄ by (8/3)√(λ/π) at small λ; the rest is O(λ)
        let offset = 8.0 / 3.0 * (SMALL_LAMBDA / std::f64::consts::PI).sqrt();
        assert!(
            (md.delta_bar - d.delta_bar + offset).abs() < DMT_LIMIT_TOL,
            "ā={a}: {}",
            md.delta_bar
        );
    }
}

#[test]
fn maugis_input_errors_are_errors() {
    assert!(maugis::pull_off(0.0, Control::Load, &params()).is_err());
    assert!(maugis::pull_off(-1.0, Control::Load, &params()).is_err());
    assert!(maugis::point(1.0, f64::NAN, &params()).is_err());
}

#[test]
fn jkr_dmt_and_hertz_pull_offs() {
    assert_eq!(Model::Jkr.pull_off(Control::Load).unwrap(), -1.5);
    assert!((Model::Jkr.pull_off(Control::Displacement).unwrap() + 5.0 / 6.0).abs() < 1e-15);
    assert_eq!(Model::Dmt.pull_off(Control::Load).unwrap(), -2.0);
    assert_eq!(Model::Dmt.pull_off(Control::Displacement).unwrap(), -2.0);
    // JKR's normalised curve: min P̄ and min δ̄ found numerically on a fine grid
    let grid: Vec<f64> = (1..40_000).map(|i| i as f64 * 1e-4).collect();
    let min_p = grid
        .iter()
        .map(|&a| jkr::normalized(a).p_bar)
        .fold(f64::INFINITY, f64::min);
    assert!((min_p + 1.5).abs() < 1e-6);
    let at_min_delta = grid
        .iter()
        .map(|&a| jkr::normalized(a))
        .min_by(|x, y| x.delta_bar.total_cmp(&y.delta_bar))
        .unwrap();
    // ā spacing 1e-4 near ā = 0.55: P̄ error ~ dP̄/dā · 1e-4 ~ 2e-4
    assert!((at_min_delta.p_bar + 5.0 / 6.0).abs() < 5e-4);
}

#[test]
fn hertz_jkr_with_vanishing_adhesion_and_zero_load_radius() {
    let s = Sphere::new(1800.0, 1.0, 1e-9).unwrap();
    for p in [1e3, 1e5] {
        let h = turf::theory::hertz::contact_radius(p, s.radius, s.modulus).unwrap();
        let j = jkr::contact_radius(&s, p).unwrap();
        // JKR − Hertz in a³ ~ √(6πγR/P) relative: ≤ 2e-4 here
        assert!((h - j).abs() < 1e-3 * h);
    }
    let s = Sphere::new(1800.0, 1.0, 0.46).unwrap();
    let a0 = jkr::zero_load_radius(&s);
    assert!(jkr::load(&s, a0).abs() < 1e-9 * std::f64::consts::PI * s.gamma * s.radius);
    // a₀ in normalised units: ā³ = 6 (P̄ = ā³ − √6 ā^(3/2) = 0)
    assert!((a0 / s.scales().length - 6f64.cbrt()).abs() < 1e-12);
}

#[test]
fn seed_tube_thermal_amplitude_is_4_6_nm() {
    let u = Cantilever::seed().rms_tip_amplitude(300.0).unwrap();
    println!("u = {u} nm");
    // hand calculation: u² = 0.4243·(7000)³·4.1419e-3/(400·(20⁴ − 17.3⁴)) = 21.40 nm²
    assert!((u - 4.626).abs() < 0.005, "{u}");
}
