//! The quasi-rheological indentation law (seed 2.1–2.7) against an independent integration of
//! the spring–dashpot network and against the slopes the seed derives.

use turf::theory::indentation_law::{Rheology, Sample, Segment};

fn rheo() -> Rheology {
    Rheology {
        machine_k1: 200.0,
        machine_k2: 5e4,
        specimen_k1: 30.0,
        specimen_k2: 600.0,
        viscosity: 900.0,
    }
}

/// The network solved from scratch: for Kelvin extension d₂ the unknowns (h, δ₁, Q) satisfy
/// P = k₁h + Q, h = δ₁ + d₂ + Q/k₂, Q = K₁δ₁; then η ḋ₂ = Q − K₂d₂. Integrated by RK4.
fn rk4(r: &Rheology, p_of_t: impl Fn(f64) -> f64, t_end: f64, steps: usize) -> (f64, f64) {
    let q_of = |p: f64, d2: f64| {
        // h = (P − Q)/k₁ and h = Q/K₁ + d₂ + Q/k₂ ⇒ Q (1/k₁ + 1/K₁ + 1/k₂) = P/k₁ − d₂
        (p / r.machine_k1 - d2) / (1.0 / r.machine_k1 + 1.0 / r.specimen_k1 + 1.0 / r.machine_k2)
    };
    let rate = |t: f64, d2: f64| (q_of(p_of_t(t), d2) - r.specimen_k2 * d2) / r.viscosity;
    let (mut t, mut d2) = (0.0, 0.0);
    let dt = t_end / steps as f64;
    for _ in 0..steps {
        let k1 = rate(t, d2);
        let k2 = rate(t + 0.5 * dt, d2 + 0.5 * dt * k1);
        let k3 = rate(t + 0.5 * dt, d2 + 0.5 * dt * k2);
        let k4 = rate(t + dt, d2 + dt * k3);
        d2 += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        t += dt;
    }
    let q = q_of(p_of_t(t_end), d2);
    (q, q / r.specimen_k1 + d2)
}

fn schedule() -> [Segment; 3] {
    [
        Segment {
            duration: 2.0,
            end_load: 1e4,
        },
        Segment {
            duration: 10.0,
            end_load: 1e4,
        },
        Segment {
            duration: 2.0,
            end_load: 0.0,
        },
    ]
}

#[test]
fn exact_segments_agree_with_an_independent_rk4_integration() {
    let r = rheo();
    let samples = r.simulate(&schedule(), 50).unwrap();
    let p_of_t = |t: f64| {
        if t <= 2.0 {
            5e3 * t
        } else if t <= 12.0 {
            1e4
        } else {
            1e4 - 5e3 * (t - 12.0)
        }
    };
    for s in samples.iter().filter(|s| s.t > 0.0).step_by(17) {
        // RK4 with 20k steps over ≤ 14 s (τ ≈ 1.4 s): error ~(dt/τ)⁴ ~ 1e-13 relative
        let (q, d) = rk4(&r, p_of_t, s.t, 20_000);
        assert!(
            (q - s.q).abs() < 1e-7 * 1e4,
            "Q at t={}: {q} vs {}",
            s.t,
            s.q
        );
        assert!(
            (d - s.delta).abs() < 1e-7 * s.delta.abs().max(1.0),
            "δ at t={}",
            s.t
        );
    }
}

fn slope(a: &Sample, b: &Sample) -> f64 {
    (b.q - a.q) / (b.delta - a.delta)
}

#[test]
fn hold_slope_is_minus_chi_and_first_loading_slope_is_k1() {
    let r = rheo();
    let samples = r.simulate(&schedule(), 400).unwrap();
    // hold: samples 401..=800; Q relaxes as δ creeps along a line of slope −χ (exact: linear)
    let hold = &samples[401..=800];
    let s = slope(&hold[0], &hold[hold.len() - 1]);
    assert!((s + r.chi()).abs() < 1e-6 * r.chi(), "{s} vs −{}", r.chi());
    assert!(
        hold[hold.len() - 1].delta > hold[0].delta,
        "the depth creeps during the hold"
    );
    // first loading: the secant over the first 1/400 of the ramp (t ≪ τ) is K₁ to O(t/τ)
    let s0 = slope(&samples[0], &samples[1]);
    let t_over_tau = samples[1].t / r.tau();
    assert!(
        (s0 - r.specimen_k1).abs() < 2.0 * t_over_tau * r.specimen_k1,
        "{s0}"
    );
}

#[test]
fn steady_loading_slope_is_the_relaxed_series_stiffness() {
    // a long ramp (≫ τ): dQ/dδ → K₁K₂/(K₁+K₂), ≈ K₁ when K₂ ≫ K₁ (seed 2.7)
    let r = rheo();
    let ramp = [Segment {
        duration: 40.0 * r.tau(),
        end_load: 1e5,
    }];
    let s = r.simulate(&ramp, 1000).unwrap();
    let n = s.len();
    let got = slope(&s[n - 2], &s[n - 1]);
    let want = r.specimen_k1 * r.specimen_k2 / (r.specimen_k1 + r.specimen_k2);
    // transient e^(−40) is gone
    assert!((got - want).abs() < 1e-8 * want, "{got} vs {want}");
}

#[test]
fn bad_constants_are_refused() {
    let mut r = rheo();
    r.viscosity = 0.0;
    assert!(r.simulate(&schedule(), 10).is_err());
    assert!(rheo()
        .simulate(
            &[Segment {
                duration: -1.0,
                end_load: 1.0
            }],
            10
        )
        .is_err());
}
