//! Hertz: a rigid sphere on a linear-elastic block, small and finite kinematics, against
//! P = (4/3)E*R^(1/2)δ^(3/2) and a = (Rδ)^(1/2) for 0.004 ≤ δ/R ≤ 0.01, on the default mesh
//! (sized for δ = 10 nm: block 200a, 20 elements per contact radius). The convergence table is
//! in `docs/validation-continuum.md`. Also: the same numbers with 1 and 2 threads.

use turf::continuum::element::Kinematics;
use turf::continuum::{run_indent, IndentParams, Segment};

/// Load tolerance of the issue (2 %), for the default mesh. The default mesh is measured at
/// +0.8 % (small kinematics; block 200a and grading 0.2 account for ≈ 0.3 % + 0.5 %).
const LOAD_TOL: f64 = 0.02;
/// Contact radius tolerance of the issue (5 %): half a surface Gauss interval is 2.5 %.
const RADIUS_TOL: f64 = 0.05;

fn check(kin: Kinematics) {
    let mut p = IndentParams::hertz_example();
    p.kinematics = kin;
    p.schedule = vec![Segment::Load {
        to: 10.0,
        rate: 10.0,
    }];
    p.solver.increments = 5;
    let r = run_indent(&p, &mut |_| {}).unwrap();
    let e_star = r.resolved.reduced_modulus_GPa;
    let radius: f64 = 1000.0;
    for row in &r.rows[1..] {
        let d = row.depth_nm;
        let p_h = 4.0 / 3.0 * e_star * radius.sqrt() * d.powf(1.5);
        let a_h = (radius * d).sqrt();
        let ep = row.load_nN / p_h - 1.0;
        let ea = row.contact_radius_nm / a_h - 1.0;
        println!("{kin:?} δ = {d:.2} nm: P/P_H − 1 = {ep:+.4}, a/a_H − 1 = {ea:+.4}");
        // Hertz is a small-strain theory: finite kinematics departs from it at first order in
        // a/R (SVK softening in compression plus geometry; measured ≈ −0.3 a/R against small
        // kinematics), so the 2 % contract holds there only up to δ/R = 0.005.
        let in_range = match kin {
            Kinematics::Small => d >= 4.0,
            Kinematics::Finite => (4.0..=5.0).contains(&d),
        };
        if in_range {
            assert!(ep.abs() < LOAD_TOL, "load off by {ep} at δ = {d}");
            assert!(ea.abs() < RADIUS_TOL, "radius off by {ea} at δ = {d}");
        }
    }
    println!("{:?}", r.mesh_report);
}

#[test]
fn hertz_finite_kinematics() {
    check(Kinematics::Finite);
}

#[test]
fn hertz_small_kinematics() {
    check(Kinematics::Small);
}

#[test]
fn one_and_two_threads_give_identical_numbers() {
    let mut p = IndentParams::hertz_example();
    p.mesh.elements_per_radius = 8.0;
    p.schedule = vec![Segment::Load {
        to: 10.0,
        rate: 10.0,
    }];
    p.solver.increments = 3;
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run_indent(&p, &mut |_| {}).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.rows, b.rows);
    assert_eq!(a.snapshots, b.snapshots);
}
