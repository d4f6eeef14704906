//! FIRE and Newton reach the same static cantilever (αL² = PL²/K = 1, 20 segments), each
//! reporting its cost.

use turf::discrete::rod::RodStiffness;
use turf::discrete::rod_problems::RodProblem;
use turf::discrete::solve_fire::FireParams;
use turf::discrete::solve_newton::NewtonParams;

const LENGTH: f64 = 7000.0;
/// Small enough to keep FIRE's run short at opt-level 1.
const SEGMENTS: usize = 20;
/// Both stop at residual 1e-7 P; with the softest stiffness ~3K/L³ that leaves a tip error
/// ≲ 1e-7 · L/3, far below this bound on the relative difference of the tip deflections.
const AGREE_TOL: f64 = 1e-5;
const REL_RESIDUAL: f64 = 1e-7;

#[test]
fn fire_and_newton_agree_on_the_cantilever() {
    let stiff = RodStiffness::turf_tube();
    let p = stiff.bending / (LENGTH * LENGTH);
    let mut a = RodProblem::cantilever(SEGMENTS, LENGTH, stiff, [0.0, -p, 0.0]).unwrap();
    let mut b = a.clone();
    let newton = a
        .solve_newton(&NewtonParams {
            rtol: REL_RESIDUAL,
            ..NewtonParams::default()
        })
        .unwrap();
    let fire = b
        .solve_fire(&FireParams {
            rtol: REL_RESIDUAL,
            ..FireParams::default()
        })
        .unwrap();
    println!("Newton: {:?}", newton.cost);
    println!("FIRE:   {:?}", fire.cost);
    let tip = a.tip();
    let (ya, yb) = (a.x[3 * tip + 1], b.x[3 * tip + 1]);
    assert!((ya / yb - 1.0).abs() < AGREE_TOL, "{ya} vs {yb}");
    assert!(newton.residual <= newton.tolerance && fire.residual <= fire.tolerance);
    assert!(newton.cost.factorizations >= newton.cost.iterations);
    assert_eq!(fire.cost.factorizations, 0);
}
