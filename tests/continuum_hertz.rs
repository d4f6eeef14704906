//! Hertz: a rigid sphere on a linear-elastic block (finite and small kinematics) against
//! P = (4/3)E*R^(1/2)δ^(3/2) and a = (Rδ)^(1/2) for δ/R ≤ 0.01, on the default mesh.

use turf::continuum::element::Kinematics;
use turf::continuum::{run_indent, IndentParams, Segment};

/// Load tolerance of the issue (2 %), for the default mesh (20 elements per contact radius,
/// block 50 contact radii: rigid-base error ≈ 0.42 a/L ≈ 0.8 % of the compliance).
const LOAD_TOL: f64 = 0.02;
/// Contact radius tolerance of the issue (5 %): half a surface Gauss interval is 2.5 %.
const RADIUS_TOL: f64 = 0.05;

fn check(kin: Kinematics) {
    let mut p = IndentParams::hertz_example();
    p.kinematics = kin;
    p.schedule = vec![Segment::Load { to: 10.0, rate: 10.0 }];
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
        if d >= 4.0 {
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
