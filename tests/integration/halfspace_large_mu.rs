//! Half-space adhesion solver towards the JKR limit (Johnson, Kendall & Roberts 1971): at large
//! Tabor parameter the load-control pull-off tends to −1.5πγR from below (more adhesive) and the
//! displacement-control jump-out load to −(5/6)πγR (from below for 9-3; the 10-4 law crosses it:
//! −0.8205 at μ = 5). μ = 3 is the largest case that
//! traces in a few seconds in the test profile; it already uses the grid window that follows the
//! contact edge (16ℓ < the swept radius) and rebuilds the grid on the way. The heavy sweep up to
//! μ = 10 is `cargo run --release --example halfspace_sweep -- 5 10` (docs/validation-halfspace.md).

use turf::halfspace::{trace_curve, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// JKR load-control pull-off, P/(πγR).
const JKR_PULL_OFF: f64 = -1.5;
/// JKR displacement-control jump-out load, P/(πγR).
const JKR_JUMP_OUT: f64 = -5.0 / 6.0;
/// At μ = 3 the pull-off may lie this far (relative) below JKR's: Maugis–Dugdale at the
/// equivalent λ (3.47 for 9-3, 4.96 for 10-4) is 0.9 % and 0.5 % from JKR, and the LJ law is
/// 2–3 % more adhesive than Maugis–Dugdale at μ ≈ 2–3 (docs/validation-halfspace.md); 4 % admits
/// both, while a solver stuck at intermediate-μ behaviour (μ = 1: 11 % and 7 % from JKR) fails.
const PULL_OFF_TOL: f64 = 0.04;
/// The jump-out load at μ = 3 lies within this (relative) of JKR's −5/6: measured 5 % for 9-3
/// (the approach to the limit is slower under displacement control); twice the distance of a
/// value that has reached the JKR regime, and far from the DMT-like μ = 1 values (24 %, 10 %).
const JUMP_OUT_TOL: f64 = 0.08;

#[test]
fn large_tabor_approaches_jkr_from_below() {
    let params = HalfspaceParams::default();
    for kind in [LjKind::Lj93, LjKind::Lj104] {
        let at = |mu: f64| trace_curve(&Problem::scaled(mu, kind).unwrap(), &params).unwrap();
        let (c2, c3) = (at(2.0), at(3.0));
        let (f2, f3) = (c2.pull_off.load, c3.pull_off.load);
        // below JKR, within the tolerance, and still rising with μ
        assert!(f3 < JKR_PULL_OFF, "{kind:?}: {f3}");
        assert!(
            (f3 / JKR_PULL_OFF - 1.0) < PULL_OFF_TOL,
            "{kind:?}: pull-off {f3} at μ = 3"
        );
        assert!(f3 > f2, "{kind:?}: {f2} at μ = 2, {f3} at μ = 3");
        // the window grid was moved with the contact edge
        assert!(c3.remeshes > 0, "{kind:?}: no remesh at μ = 3");
        let jo = c3.jump_out.expect("an S-curve at μ = 3").load;
        assert!(
            (jo / JKR_JUMP_OUT - 1.0).abs() < JUMP_OUT_TOL,
            "{kind:?}: jump-out {jo} at μ = 3"
        );
        // jump-out on retraction lies before pull-off in load: −5/6 against −1.5 in JKR
        assert!(c3.pull_off.load < jo);
    }
}

/// Beyond μ = 10 the solver refuses at once with the reason (the μ = 20 failed after
/// 35 s and μ = 100 ran on for minutes) instead of tracing.
#[test]
fn beyond_the_validated_range_the_solver_refuses_with_the_reason() {
    use turf::halfspace::{pull_off, HalfspaceError, MAX_VALIDATED_MU};
    let params = HalfspaceParams::default();
    for mu in [20.0, 100.0] {
        let p = Problem::scaled(mu, LjKind::Lj93).unwrap();
        for err in [
            trace_curve(&p, &params).unwrap_err(),
            pull_off(&p, &params).unwrap_err(),
        ] {
            assert!(
                matches!(err, HalfspaceError::BeyondValidatedRange { max, .. } if max == MAX_VALIDATED_MU),
                "{err}"
            );
            assert!(err.to_string().contains("JKR"), "{err}");
        }
    }
    // μ = 10 itself is inside the range (the check does not trace it here: that is the sweep)
    assert!(Problem::scaled(10.0, LjKind::Lj104)
        .unwrap()
        .check_validated_range()
        .is_ok());
}
