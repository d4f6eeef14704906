//! Homogeneous tests of the continuum solver on a small block (r ∈ [0, 10], z ∈ [−10, 0] nm):
//! uniaxial compression of a hyperfoam with β = 0 against the closed form
//! T = (2μ/α)(λ^(α−1) − λ^(−1)) with no lateral strain, the transversely isotropic foam along
//! its axis and radially (its matrix alone) against its card's closed forms (issue 19), and stress relaxation under a step
//! strain against g(t) = 1 − μ̄(1 − e^(−t/τ)) (seed eq. 5.8).

use turf::continuum::assembly::{Assembler, Solid};
use turf::continuum::element::Kinematics;
use turf::continuum::machine::{Drive, Driven};
use turf::continuum::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
use turf::continuum::material::viscoelastic::{relaxation, PronyTerm, Viscoelastic};
use turf::continuum::material::Elastic;
use turf::continuum::mesh::{graded_block, BlockSpec, Mesh};
use turf::continuum::newton::{solve, NewtonParams};

/// Closed-form agreement of the issue; a homogeneous field is exact for the CST, so only the
/// Newton tolerance (1e-9 relative) remains.
const CLOSED_FORM_TOL: f64 = 1e-6;
/// Relaxation agreement of the issue; the recurrence is exact for a step and a hold.
const RELAX_TOL: f64 = 1e-3;

const SIDE: f64 = 10.0;

fn block() -> Mesh {
    graded_block(&BlockSpec {
        width: SIDE,
        depth: SIDE,
        smallest: 2.5,
        fine_radius: SIDE,
        fine_depth: SIDE,
        grading: 0.0,
        max_elements: turf::continuum::mesh::DEFAULT_MAX_ELEMENTS,
    })
    .unwrap()
}

fn foam(prony: Vec<PronyTerm>) -> Box<Viscoelastic<Elastic>> {
    Box::new(Viscoelastic {
        elastic: Elastic::Hyperfoam(hyperfoam(0.35, 18.8)),
        prony,
    })
}

fn hyperfoam(mu: f64, alpha: f64) -> Hyperfoam {
    Hyperfoam {
        terms: vec![HyperfoamTerm {
            mu,
            alpha,
            beta: 0.0,
        }],
    }
}

/// Axis u_r = 0, base u_z = 0 (roller), top u_z prescribed.
fn constrain(solid: &mut Solid, mesh: &Mesh) {
    for &n in &mesh.axis {
        solid.fixed[2 * n] = true;
    }
    for &n in mesh.bottom.iter().chain(&mesh.surface) {
        solid.fixed[2 * n + 1] = true;
    }
}

/// Solve with the top at stretch λ (lateral dofs start where they are); returns the total axial force on the top, nN.
fn compress(
    solid: &Solid,
    mesh: &Mesh,
    asm: &mut Assembler,
    u: &mut [f64],
    history: &[f64],
    lambda: f64,
    dt: f64,
) -> f64 {
    // prescribed top, and the homogeneous field as the start for the free axial dofs
    for (n, x) in mesh.nodes.iter().enumerate() {
        u[2 * n + 1] = (lambda - 1.0) * (x[1] + SIDE);
    }
    let mut sys = Driven {
        asm,
        solid,
        contact: None,
        history,
        dt,
        drive: Drive::Depth(0.0),
        force_floor: 1e-12,
    };
    // the unknowns are (u, δ); δ is prescribed (no indenter here)
    let mut x: Vec<f64> = u.iter().copied().chain([0.0]).collect();
    solve(&mut sys, &mut x, &NewtonParams::default()).unwrap();
    u.copy_from_slice(&x[..u.len()]);
    let ev = asm
        .evaluate(solid, None, (u, history), dt, 0.0, false)
        .unwrap();
    mesh.surface.iter().map(|&n| ev.gradient[2 * n + 1]).sum()
}

/// Compress the block of `material` along its axis to each stretch of `lambdas` and check the
/// nominal stress against `closed_form(λ)` with no lateral displacement.
fn uniaxial_matches(
    material: Box<Viscoelastic<Elastic>>,
    lambdas: &[f64],
    closed_form: &dyn Fn(f64) -> f64,
) {
    let mesh = block();
    let mut solid = Solid::new(&mesh, Kinematics::Finite, material).unwrap();
    constrain(&mut solid, &mesh);
    let mut asm = Assembler::new(&solid, None).unwrap();
    let mut u = vec![0.0; solid.dofs()];
    // a non-trivial start, so that Newton has lateral work to undo
    for (n, x) in mesh.nodes.iter().enumerate() {
        u[2 * n] = 0.01 * x[0] * (x[1] / SIDE).sin();
    }
    for &n in &mesh.axis {
        u[2 * n] = 0.0;
    }
    let area = std::f64::consts::PI * SIDE * SIDE;
    for &lambda in lambdas {
        let force = compress(&solid, &mesh, &mut asm, &mut u, &[], lambda, 0.0);
        let t = closed_form(lambda);
        assert!(
            (force / area - t).abs() <= CLOSED_FORM_TOL * t.abs(),
            "λ = {lambda}: {} vs {t}",
            force / area
        );
        let lateral = (0..mesh.nodes.len())
            .map(|n| u[2 * n].abs())
            .fold(0.0, f64::max);
        assert!(
            lateral <= CLOSED_FORM_TOL * SIDE,
            "lateral displacement {lateral}"
        );
    }
}

/// One hyperfoam term's uniaxial nominal stress at β = 0, (2μ/α)(λ^(α−1) − λ^(−1)), GPa.
fn one_term(mu: f64, alpha: f64, lambda: f64) -> f64 {
    2.0 * mu / alpha * (lambda.powf(alpha - 1.0) - 1.0 / lambda)
}

#[test]
fn uniaxial_hyperfoam_compression_matches_the_closed_form_without_lateral_strain() {
    uniaxial_matches(foam(vec![]), &[0.95, 0.8, 0.6, 0.4], &|l| {
        one_term(0.35, 18.8, l)
    });
}

#[test]
fn uniaxial_transverse_foam_compression_along_its_axis_matches_the_closed_form() {
    use turf::continuum::material::transverse_foam::{FibreTerm, TransverseFoam};
    let (matrix, fibre) = ((2e-4, 4.0), (8e-3, 6.5));
    let material = Box::new(Viscoelastic {
        elastic: Elastic::Transverse(TransverseFoam {
            matrix: hyperfoam(matrix.0, matrix.1),
            fibre: vec![FibreTerm {
                mu: fibre.0,
                alpha: fibre.1,
            }],
            shear: 3e-3,
        }),
        prony: vec![],
    });
    uniaxial_matches(material, &[0.95, 0.8, 0.6], &|l| {
        one_term(matrix.0, matrix.1, l) + one_term(fibre.0, fibre.1, l)
    });
}

/// The block compressed radially (its outer face moved to r = λW, the axis held, the base on
/// rollers, the top free): equibiaxial in r and θ, so with β = 0 each nominal stress is its own
/// stretch's; the transverse foam carries this with its matrix alone, P_rr = T_m(λ), and no
/// axial strain (λ_z = 1 exactly: no term pulls along the axis).
#[test]
fn radial_compression_of_the_transverse_foam_is_carried_by_its_matrix_alone() {
    use turf::continuum::material::transverse_foam::{FibreTerm, TransverseFoam};
    let matrix = (2e-4, 4.0);
    let material = Box::new(Viscoelastic {
        elastic: Elastic::Transverse(TransverseFoam {
            matrix: hyperfoam(matrix.0, matrix.1),
            fibre: vec![FibreTerm {
                mu: 8e-3,
                alpha: 6.5,
            }],
            shear: 3e-3,
        }),
        prony: vec![],
    });
    let mesh = block();
    let mut solid = Solid::new(&mesh, Kinematics::Finite, material).unwrap();
    let outer: Vec<usize> = (0..mesh.nodes.len())
        .filter(|&n| mesh.nodes[n][0] >= SIDE * (1.0 - 1e-12))
        .collect();
    for &n in mesh.axis.iter().chain(&outer) {
        solid.fixed[2 * n] = true;
    }
    for &n in &mesh.bottom {
        solid.fixed[2 * n + 1] = true;
    }
    let mut asm = Assembler::new(&solid, None).unwrap();
    let face = 2.0 * std::f64::consts::PI * SIDE * SIDE;
    for lambda in [0.95, 0.8, 0.6] {
        // the homogeneous field as the start, a perturbation on the free axial dofs
        let mut u = vec![0.0; solid.dofs()];
        for (n, x) in mesh.nodes.iter().enumerate() {
            u[2 * n] = (lambda - 1.0) * x[0];
            u[2 * n + 1] = 0.01 * (x[0] / SIDE) * (x[1] + SIDE);
        }
        for &n in &mesh.bottom {
            u[2 * n + 1] = 0.0;
        }
        let mut sys = Driven {
            asm: &mut asm,
            solid: &solid,
            contact: None,
            history: &[],
            dt: 0.0,
            drive: Drive::Depth(0.0),
            force_floor: 1e-12,
        };
        let mut x: Vec<f64> = u.iter().copied().chain([0.0]).collect();
        solve(&mut sys, &mut x, &NewtonParams::default()).unwrap();
        let n = u.len();
        u.copy_from_slice(&x[..n]);
        let ev = asm
            .evaluate(&solid, None, (&u, &[]), 0.0, 0.0, false)
            .unwrap();
        let force: f64 = outer.iter().map(|&n| ev.gradient[2 * n]).sum();
        let t = one_term(matrix.0, matrix.1, lambda);
        assert!(
            (force / face - t).abs() <= CLOSED_FORM_TOL * t.abs(),
            "λ = {lambda}: {} vs {t}",
            force / face
        );
        let axial = (0..mesh.nodes.len())
            .map(|n| u[2 * n + 1].abs())
            .fold(0.0, f64::max);
        assert!(
            axial <= CLOSED_FORM_TOL * SIDE,
            "axial displacement {axial}"
        );
    }
}

#[test]
fn step_strain_relaxes_as_g_of_t() {
    let prony = vec![PronyTerm { g: 0.4, tau: 3.0 }];
    let mesh = block();
    let mut solid = Solid::new(&mesh, Kinematics::Finite, foam(prony.clone())).unwrap();
    constrain(&mut solid, &mesh);
    let mut asm = Assembler::new(&solid, None).unwrap();
    let mut u = vec![0.0; solid.dofs()];
    let mut history = vec![0.0; solid.history_len() * solid.elements.len()];
    let lambda = 0.7;
    // the step, in a time negligible against τ
    let dt0 = 1e-9;
    let f0 = compress(&solid, &mesh, &mut asm, &mut u, &history, lambda, dt0);
    solid.commit(&u, &mut history, dt0).unwrap();
    let mut t = dt0;
    for dt in [0.1, 0.4, 1.0, 2.5, 5.0, 10.0] {
        let f = compress(&solid, &mesh, &mut asm, &mut u, &history, lambda, dt);
        solid.commit(&u, &mut history, dt).unwrap();
        t += dt;
        let g = relaxation(&prony, t) / relaxation(&prony, dt0);
        assert!((f / f0 - g).abs() < RELAX_TOL, "t = {t}: {} vs {g}", f / f0);
    }
}
