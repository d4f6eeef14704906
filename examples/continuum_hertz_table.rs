//! Hertz convergence table for `docs/validation-continuum.md`: a rigid sphere (R = 1 µm) into
//! a linear block (E = 0.7 GPa, ν = 0.3) to δ/R = 0.01, under mesh refinement (elements per
//! contact radius), block size and grading, both kinematics. Run:
//! `cargo run --release --example continuum_hertz_table [depth_nm]`.

use turf::continuum::element::Kinematics;
use turf::continuum::{run_indent, IndentParams, Segment};

fn main() {
    let depth: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10.0);
    let radius: f64 = 1000.0;
    println!("| kinematics | elements/a | block/a | grading | elements | P/P_H − 1 | a/a_H − 1 | time (s) |");
    println!("|---|---|---|---|---|---|---|---|");
    for kin in [Kinematics::Small, Kinematics::Finite] {
        for (per_a, size, grading) in [
            (5.0, 200.0, 0.2),
            (10.0, 200.0, 0.2),
            (20.0, 200.0, 0.2),
            (40.0, 200.0, 0.2),
            (20.0, 50.0, 0.2),
            (20.0, 100.0, 0.2),
            (20.0, 500.0, 0.2),
            (20.0, 200.0, 0.3),
            (20.0, 200.0, 0.1),
        ] {
            let mut p = IndentParams::hertz_example();
            p.kinematics = kin;
            p.mesh.elements_per_radius = per_a;
            p.mesh.size_factor = size;
            p.mesh.grading = grading;
            p.schedule = vec![Segment::Load {
                to: depth,
                rate: 10.0,
            }];
            p.solver.increments = 10;
            let r = match run_indent(&p, &mut |_| {}) {
                Ok(r) => r,
                Err(e) => {
                    println!("| {kin:?} | {per_a} | {size} | {grading} | failed: {e} |");
                    continue;
                }
            };
            let row = r.rows.last().unwrap();
            let e_star = r.resolved.reduced_modulus_GPa;
            let p_h = 4.0 / 3.0 * e_star * radius.sqrt() * depth.powf(1.5);
            let a_h = (radius * depth).sqrt();
            println!(
                "| {kin:?} | {per_a} | {size} | {grading} | {} | {:+.4} | {:+.4} | {:.2} |",
                r.mesh_report.elements,
                row.load_nN / p_h - 1.0,
                row.contact_radius_nm / a_h - 1.0,
                r.stats.wall_s
            );
        }
    }
}
