//! Stability at the extremes of the parameters (issue 9, item 3): each case either converges to
//! the correct answer where one is known (a closed form or a limit) or stops with a named error
//! — never NaN, never a panic, never a hang. One section per extreme; the heavy cases are
//! `#[ignore]`d and run by `cargo test --release --test integration extremes:: -- --ignored` (numbers in
//! docs/validation.md, "Extremes").

use turf::bench::presets::tabor_sphere;
use turf::continuum::element::Kinematics;
use turf::continuum::events::normalised_pull_off;
use turf::continuum::machine::Machine;
use turf::continuum::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
use turf::continuum::material::linear::LinearElastic;
use turf::continuum::material::viscoelastic::{PronyTerm, Viscoelastic};
use turf::continuum::material::{Deformation, Elastic, Material};
use turf::continuum::{run_indent, IndentParams, IndentResult, Segment};
use turf::discrete::broadphase::PeriodicBox;
use turf::discrete::energy::EnergyTerm;
use turf::discrete::turf::{generate_turf, TurfError, TurfParams};
use turf::discrete::vdw::VdwParams;
use turf::discrete::vdw_term::{TubeLayout, VdwTerm};
use turf::halfspace::{pull_off, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// Indenter radius of the Hertz problems, nm (`IndentParams::hertz_example`).
const RADIUS: f64 = 1000.0;

fn run(p: &IndentParams) -> IndentResult {
    run_indent(p, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// Every number a run reports is finite.
fn assert_finite(r: &IndentResult) {
    for row in &r.rows {
        for v in [
            row.depth_nm,
            row.load_nN,
            row.drive_nm,
            row.contact_radius_nm,
        ] {
            assert!(v.is_finite(), "non-finite value in row {row:?}");
        }
    }
}

/// Hertz load (nN) at depth `d` (nm) for reduced modulus `e_star` (GPa).
fn hertz(e_star: f64, d: f64) -> f64 {
    4.0 / 3.0 * e_star * RADIUS.sqrt() * d.powf(1.5)
}

/// The Hertz example at small strain loaded to `depth` nm in `increments` steps.
fn hertz_small(depth: f64, increments: usize) -> IndentParams {
    let mut p = IndentParams::hertz_example();
    p.kinematics = Kinematics::Small;
    p.schedule = vec![Segment::Load {
        to: depth,
        rate: depth,
    }];
    p.solver.increments = increments;
    p
}

// ---------------------------------------------------------------------------------------------
// Tabor μ from 0.01 to 10

/// DMT: at μ = 0.01 elasticity lowers |pull-off| below 2 by 0.04 % (tests/integration/halfspace_limits.rs);
/// 0.5 % is the half-space's mesh error budget with a decade of margin.
const DMT_TOL: f64 = 0.005;
/// FE against the half-space, as issue 5 asks (tests/integration/continuum_adhesion.rs).
const FE_PULL_OFF_TOL: f64 = 0.03;
/// μ = 10 lies beyond Maugis–Dugdale λ ≈ 11.6, 0.3 % from JKR; the LJ law is 2–3 % more
/// adhesive than Maugis–Dugdale at μ ≈ 2–3 (docs/validation-halfspace.md): 3 % below −1.5.
const JKR_TOL: f64 = 0.03;

#[test]
fn halfspace_at_mu_0_01_gives_dmt() {
    for kind in [LjKind::Lj93, LjKind::Lj104] {
        let po = pull_off(
            &Problem::scaled(0.01, kind).unwrap(),
            &HalfspaceParams::default(),
        )
        .unwrap();
        println!("{kind:?} μ = 0.01: {}", po.normalized);
        assert!(po.normalized.is_finite());
        assert!((po.normalized / -2.0 - 1.0).abs() < DMT_TOL, "{po:?}");
    }
}

#[test]
fn fe_at_mu_0_01_small_strain_matches_the_halfspace() {
    let mu = 0.01;
    let mut p = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
    // No jump at μ = 0.01, so no damping is needed; `tabor_sphere`'s fixed c₀ would carry
    // ~12 % of πγR here (c₀ ġ over the ~10⁴ nm² of the interaction zone, against γ ∝ μ^(3/2)),
    // making the pull-off look more adhesive than DMT.
    p.adhesion.as_mut().unwrap().damping = None;
    // The forces in play are ~1e-4 of μ = 1's: at the default rtol (1e-9 of them) Newton meets
    // the conditioning floor of the graded block (~1e-9 nN, 1e-4 of the first residual, above
    // the stagnation test) and the run stops with that diagnostic; 1e-8 is still 1e-7 of the
    // pull-off force.
    p.solver.newton.rtol = 1e-8;
    // and a 20a block (1.3 µm; the tail beyond it at gaps > 800 z₀ carries < 1e-4 of the
    // load) halves that floor against the 50a default
    p.mesh.size_factor = 20.0;
    let r = run(&p);
    assert_finite(&r);
    let fe = normalised_pull_off(&r).expect("pull-off passed");
    let hs = pull_off(
        &Problem::scaled(mu, LjKind::Lj93).unwrap(),
        &HalfspaceParams::default(),
    )
    .unwrap()
    .normalized;
    println!(
        "μ = 0.01: FE {fe:.5}, half-space {hs:.5}; {} elements, {:.1} s",
        r.mesh_report.elements, r.stats.wall_s
    );
    assert!((fe / hs - 1.0).abs() < FE_PULL_OFF_TOL);
    assert!(r.summary().events.jump_in.is_none(), "no jump at μ = 0.01");
}

/// Heavy in the dev profile: ≈ 70 s for both laws in release (trace + three-grid study; the
/// fine zone follows the crack tip and the contact interior is graded, docs/validation-halfspace.md).
/// Run: `cargo test --release --test integration -- --ignored extremes::halfspace_at_mu_10`.
#[test]
#[ignore = "≈ 70 s in release, several minutes in the dev profile"]
fn halfspace_at_mu_10_approaches_jkr() {
    for kind in [LjKind::Lj93, LjKind::Lj104] {
        let po = pull_off(
            &Problem::scaled(10.0, kind).unwrap(),
            &HalfspaceParams::default(),
        )
        .unwrap();
        let f = po.normalized;
        println!(
            "{kind:?} μ = 10: pull-off {f} ± {:.1e}, jump-out {:?}, {:.1} s",
            po.error_estimate, po.jump_out, po.cost.wall_time
        );
        assert!(f < -1.5 && f / -1.5 - 1.0 < JKR_TOL, "{po:?}");
        // the grid error must be far below the distance from JKR that the test measures
        assert!(po.error_estimate < 0.1 * (f + 1.5).abs(), "{po:?}");
        let jump_out = po.jump_out.expect("a large jump at μ = 10");
        // JKR's displacement-control jump-out is at −5/6 πγR; μ = 5 gave −0.854 / −0.803 (2.5 % /
        // 3.6 % off, trace grid, no error estimate), so 5 % admits no wrong branch
        assert!(
            (jump_out.load / (-5.0 / 6.0) - 1.0).abs() < 0.05,
            "{jump_out:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Hyperfoam α up to 30

/// Closed form at a material point: the stress is evaluated, not solved, so only round-off in
/// λ^(α−1) remains (1e-12 relative is ~10⁴ ulp).
const POINT_TOL: f64 = 1e-12;

fn foam30() -> Hyperfoam {
    Hyperfoam {
        terms: vec![HyperfoamTerm {
            mu: 0.35,
            alpha: 30.0,
            beta: 0.0,
        }],
    }
}

#[test]
fn hyperfoam_alpha_30_uniaxial_matches_the_closed_form() {
    let (mu, alpha) = (0.35, 30.0);
    let m = foam30();
    // compression to 30 % of the height and tension to 1.5 (λ^29 = 1.3e5)
    for lam in [0.3f64, 0.5, 0.8, 0.99, 1.01, 1.2, 1.5] {
        let r = m
            .response(&Deformation::from_c([1.0, lam * lam, 1.0, 0.0]), &[], 0.0)
            .unwrap();
        let t = 2.0 * mu / alpha * (lam.powf(alpha - 1.0) - 1.0 / lam);
        // nominal stress T = λS_zz
        assert!(
            (r.stress[1] * lam - t).abs() <= POINT_TOL * t.abs(),
            "λ = {lam}: {} vs {t}",
            r.stress[1] * lam
        );
        assert!(r.tangent.iter().flatten().all(|v| v.is_finite()));
    }
}

#[test]
fn hyperfoam_alpha_30_indentation_converges_between_its_moduli() {
    let mut p = hertz_small(2.0, 4);
    p.kinematics = Kinematics::Finite;
    p.material.elastic = Elastic::Hyperfoam(foam30());
    p.mesh.elements_per_radius = 8.0;
    let r = run(&p);
    assert_finite(&r);
    assert!(r.failure.is_none(), "{:?}", r.failure);
    // E = 2μ, ν = 0: Hertz with E* = 0.7 GPa is the small-strain limit. In compression the
    // foam first softens, T ≈ −2με(1 − (α − 3)ε/2) (the λ^(α−1) term only stiffens it near
    // densification), so the load lies below Hertz at E₀ (plus the coarse mesh's ≤ 3 %,
    // docs/validation-continuum.md) ...
    let last = r.rows.last().unwrap();
    let p_h = hertz(0.7, last.depth_nm);
    println!(
        "α = 30, δ = {:.2} nm: P = {:.3} nN, Hertz at E₀ {p_h:.3} ({} elements)",
        last.depth_nm, last.load_nN, r.mesh_report.elements
    );
    assert!(last.load_nN < 1.03 * p_h);
    // ... and above the Hertz load of the tangent modulus at the compressive strain ε = a/R,
    // more than the largest under a Hertz contact ((2/π)a/R):
    // dT/dλ = (2μ/α)((α−1)λ^(α−2) + λ^(−2)) at λ = 1 − a/R
    let lam = 1.0 - (RADIUS * last.depth_nm).sqrt() / RADIUS;
    let e_t = 2.0 * 0.35 / 30.0 * (29.0 * lam.powf(28.0) + lam.powi(-2));
    assert!(last.load_nN > hertz(e_t, last.depth_nm));
}

// ---------------------------------------------------------------------------------------------
// Machine stiffness from 1e-6 to 1e6 × the contact stiffness

/// Contact stiffness 2aE* of the Hertz example at δ = 10 nm (a = 100 nm, E* = 0.769 GPa), nN/nm.
const CONTACT_STIFFNESS: f64 = 2.0 * 100.0 * 0.7 / (1.0 - 0.09);
/// A spring 1e6 × the contact stiffness moves the indenter off the drive by P/K, which changes
/// the load by k_c/K = 1e-6 relative; 1e-5 allows for Newton's 1e-9 and that shift.
const STIFF_LIMIT_TOL: f64 = 1e-5;
/// Hertz on the default mesh (tests/integration/continuum_hertz.rs, measured +0.8 % at small strain).
const HERTZ_TOL: f64 = 0.02;
/// Spring equilibrium P = K(Δ − δ): Newton's tolerance is 1e-9 of the forces in play.
const SPRING_TOL: f64 = 1e-7;

#[test]
fn stiff_machine_spring_is_displacement_control() {
    let rigid = hertz_small(10.0, 5);
    let mut stiff = rigid.clone();
    stiff.machine = Machine::Spring {
        stiffness: 1e6 * CONTACT_STIFFNESS,
    };
    let (a, b) = (run(&rigid), run(&stiff));
    assert_finite(&b);
    assert_eq!(a.rows.len(), b.rows.len());
    for (x, y) in a.rows.iter().zip(&b.rows).skip(1) {
        println!(
            "δ {} / {}: P {} / {}",
            x.depth_nm, y.depth_nm, x.load_nN, y.load_nN
        );
        assert!((y.drive_nm - x.depth_nm).abs() < 1e-12 * x.depth_nm);
        assert!((y.load_nN / x.load_nN - 1.0).abs() < STIFF_LIMIT_TOL);
    }
}

/// P = K(Δ − δ) = KΔ(1 − δ/Δ): the load is prescribed up to δ/Δ = Kδ/P, which for a Hertz
/// contact grows as P^(−1/3) towards small loads: 3.3e-5 at P = 0.1 nN (δ = 0.021 nm), less
/// above. Checked on the rows above `LOAD_CONTROL_FROM`.
const LOAD_CONTROL_TOL: f64 = 1e-4;
/// The smallest load where the load-control limit is checked, nN.
const LOAD_CONTROL_FROM: f64 = 0.1;

#[test]
fn soft_machine_spring_is_load_control() {
    let k = 1e-6 * CONTACT_STIFFNESS;
    // a drive Δ = P/K reaching 1000 nN, from out of contact: the mesh is sized for the
    // spring's Hertz depth, not for δ = Δ (`indent::spring_depth`), and no Newton iterate may
    // pass through the sphere into a false equilibrium (`Indenter::check_depth`)
    let mut p = hertz_small(1000.0 / k, 5);
    p.machine = Machine::Spring { stiffness: k };
    let r = run(&p);
    assert_finite(&r);
    let e_star = r.resolved.reduced_modulus_GPa;
    let mut checked = 0;
    for row in &r.rows[1..] {
        let (d, load) = (row.depth_nm, row.load_nN);
        println!(
            "Δ = {:.4e} nm: δ = {d:.4} nm, P = {load:.3} nN",
            row.drive_nm
        );
        // equilibrium of the spring, and P = KΔ: the load is prescribed
        assert!((k * (row.drive_nm - d) - load).abs() <= SPRING_TOL * load.abs().max(1.0));
        if load >= LOAD_CONTROL_FROM {
            assert!((load / (k * row.drive_nm) - 1.0).abs() < LOAD_CONTROL_TOL);
        }
        if d >= 4.0 {
            assert!((load / hertz(e_star, d) - 1.0).abs() < HERTZ_TOL);
            checked += 1;
        }
    }
    assert!(checked >= 2, "{checked} rows in the Hertz range");
}

// ---------------------------------------------------------------------------------------------
// τ much shorter and much longer than the time step

/// The Prony recurrence is exact for a strain ramp of SVK (S₀ linear in C) from rest and for a
/// hold; round-off only.
const PRONY_TOL: f64 = 1e-12;

#[test]
fn prony_limits_relaxed_and_unrelaxed_are_exact() {
    let g = 0.4;
    let c = [0.99, 0.96, 0.99, 0.005];
    let dt = 1.0;
    for tau in [1e-3 * dt, 1e3 * dt, 1e-12 * dt, 1e12 * dt] {
        let m = Viscoelastic {
            elastic: LinearElastic {
                youngs: 0.7,
                poisson: 0.3,
            },
            prony: vec![PronyTerm { g, tau }],
        };
        let s0 = m
            .elastic
            .response(&Deformation::from_c(c), &[], dt)
            .unwrap()
            .stress;
        let hist = vec![0.0; m.history_len()];
        // a ramp from rest to c over dt: S = S₀[(1 − g) + g(τ/Δt)(1 − e^(−Δt/τ))]
        let x = dt / tau;
        let factor = 1.0 - g + g * (-(-x).exp_m1() / x);
        let r = m.response(&Deformation::from_c(c), &hist, dt).unwrap();
        for k in 0..4 {
            assert!(r.stress[k].is_finite());
            assert!((r.stress[k] - factor * s0[k]).abs() <= PRONY_TOL * s0[1].abs());
        }
        // the limits: τ ≪ Δt relaxed (1 − g), τ ≫ Δt unrelaxed (1)
        let limit = if tau < dt { 1.0 - g } else { 1.0 };
        assert!((factor - limit).abs() <= 1e-3 * limit, "τ = {tau}");
        // and a hold of dt after the ramp decays the viscous part by e^(−Δt/τ)
        let mut h = hist.clone();
        m.update_history(&Deformation::from_c(c), &mut h, dt)
            .unwrap();
        let s = m.response(&Deformation::from_c(c), &h, dt).unwrap().stress;
        let held = 1.0 - g + g * (-(-x).exp_m1() / x) * (-x).exp();
        for k in 0..4 {
            assert!(
                (s[k] - held * s0[k]).abs() <= PRONY_TOL * s0[1].abs(),
                "τ = {tau}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// ν up to 0.49: CST locks

/// Measured +5.13 % at ν = 0.49 on the default mesh (docs/validation-continuum.md,
/// "Near-incompressibility"); the bound asserts that the known locking error does not grow.
/// It is not fixed: CST locks volumetrically as ν → 0.5.
const LOCKING_BOUND: f64 = 0.06;

#[test]
fn nearly_incompressible_hertz_locks_within_the_known_bound() {
    let mut p = hertz_small(4.0, 2);
    p.material.elastic = Elastic::Linear(LinearElastic {
        youngs: 0.7,
        poisson: 0.49,
    });
    let r = run(&p);
    assert_finite(&r);
    let row = r.rows.last().unwrap();
    let err = row.load_nN / hertz(r.resolved.reduced_modulus_GPa, row.depth_nm) - 1.0;
    println!(
        "ν = 0.49: P/P_H − 1 = {err:+.4} ({} elements)",
        r.mesh_report.elements
    );
    // locking only stiffens
    assert!(err > 0.0 && err < LOCKING_BOUND, "{err}");
}

// ---------------------------------------------------------------------------------------------
// Meshes from 1e3 to 1e5 elements

/// Hertz at ≈ 7 elements per contact radius: measured +1.0 % at 10 per radius
/// (docs/validation-continuum.md); 3 % for the coarser mesh.
const COARSE_HERTZ_TOL: f64 = 0.03;

fn mesh_case(elements_per_radius: f64) -> IndentResult {
    let mut p = hertz_small(10.0, 2);
    p.mesh.elements_per_radius = elements_per_radius;
    let r = run(&p);
    assert_finite(&r);
    let row = r.rows.last().unwrap();
    let err = row.load_nN / hertz(r.resolved.reduced_modulus_GPa, row.depth_nm) - 1.0;
    println!(
        "{} elements: P/P_H − 1 = {err:+.5}, {:.1} s",
        r.mesh_report.elements, r.stats.wall_s
    );
    assert!(err.abs() < COARSE_HERTZ_TOL);
    r
}

#[test]
fn mesh_of_a_thousand_elements_gives_hertz() {
    let r = mesh_case(7.0);
    assert!((500..2000).contains(&r.mesh_report.elements));
}

/// Heavy: 100,798 elements, 50 s wall and 327 MB in the test profile (docs/validation.md
/// Extremes); run with `cargo test --release --test integration -- --ignored extremes::mesh_of_a_hundred`.
#[test]
#[ignore = "100k-element mesh: ~50 s and 330 MB, too heavy for the default suite"]
fn mesh_of_a_hundred_thousand_elements_gives_hertz() {
    let r = mesh_case(240.0);
    assert!(r.mesh_report.elements > 70_000);
}

/// A mesh beyond `mesh.max_elements` is refused before it is built, with the sizes that asked for
/// it, instead of a run that fills the memory (the seed's γ on a 25 MPa card asked for ≳ 10⁷
/// elements: docs/chain.md). The ceiling is lowered here so the refusal is cheap; the Hertz
/// case at 240 elements per radius has 100,798 elements.
#[test]
fn a_mesh_beyond_the_element_ceiling_is_refused_with_its_sizes() {
    let mut p = hertz_small(10.0, 2);
    p.mesh.elements_per_radius = 240.0;
    p.mesh.max_elements = 20_000;
    let Err(e) = run_indent(&p, &mut |_| {}) else {
        panic!("a 100k-element mesh under a 20k ceiling was built");
    };
    let msg = e.to_string();
    assert!(
        msg.contains("more than 20000 elements") && msg.contains("mesh.max_elements"),
        "{msg}"
    );
    // the same problem at 7 elements per radius (≈ 1.5k elements) runs under the same ceiling
    p.mesh.elements_per_radius = 7.0;
    assert!(run_indent(&p, &mut |_| {}).is_ok());
}

// ---------------------------------------------------------------------------------------------
// Tubes nearly parallel or crossing at small angles

/// Two one-segment tubes, 400 nm long, at the equilibrium axis distance, B turned by `angle`
/// towards the axis `about` (1: in the plane of both axes, nearly parallel; 2: about the
/// common normal, crossing). Returns (energy in aJ, gradient, coordinates).
fn two_segments(params: &VdwParams, angle: f64, about: usize) -> (f64, Vec<f64>, Vec<f64>) {
    let r = params.radius_ref;
    let d0 = 2.0 * r + params.gap_eq;
    let half = 200.0;
    let mut dir = [angle.cos(), 0.0, 0.0];
    dir[about] = angle.sin();
    let mut x = vec![-half, 0.0, 0.0, half, 0.0, 0.0];
    for s in [-1.0, 1.0] {
        x.extend([s * half * dir[0], d0 + s * half * dir[1], s * half * dir[2]]);
    }
    let (e, g) = vdw_energy(params, &x, &x);
    (e, g, x)
}

/// Energy (aJ) and gradient at `x` of the two tubes whose reference (material) configuration
/// is `x0`.
fn vdw_energy(params: &VdwParams, x0: &[f64], x: &[f64]) -> (f64, Vec<f64>) {
    let layout: Vec<TubeLayout> = (0..2)
        .map(|t| TubeLayout {
            first_node: 2 * t,
            nodes: 2,
            radius: params.radius_ref,
        })
        .collect();
    let mut term = VdwTerm::new(params, &layout, x0, PeriodicBox::default()).unwrap();
    term.prepare(x);
    let mut g = vec![0.0; x.len()];
    let e = term.energy_gradient(x, &mut g);
    (e, g)
}

/// The energy is even in the angle: E(θ) and E(−θ) come from mirrored point pairs, equal up
/// to round-off (1e-12 relative over ~10³ point pairs); 1e-9 is margin.
const EVEN_TOL: f64 = 1e-9;
/// Agreement of the curvature (E(θ) − E(0))/θ² at 1e-6 and 1e-5 rad (see the test).
const CURVATURE_TOL: f64 = 1e-3;
/// Step of the fourth-order central differences, nm.
const FD_STEP: f64 = 1e-4;
/// Finite differences against the analytic gradient. The second-order error has a large
/// constant (moving a 400 nm segment's end sweeps its points across the narrow LJ well):
/// measured 6e-4 nN at h = 1e-4 and 6e-6 nN at h = 1e-5. The fourth-order stencil cuts it to
/// ~(h/0.03 nm)² of that, ~1e-8 nN, leaving round-off 1e-13 E/h ~ 4e-7 nN; 1e-5 of the
/// largest component (≥ 0.5 nN here) is a factor ≥ 10 above.
const FD_TOL: f64 = 1e-5;

#[test]
fn nearly_parallel_and_small_angle_crossings_are_finite_continuous_and_consistent() {
    let params = VdwParams::default();
    for about in [1, 2] {
        let (e0, _, _) = two_segments(&params, 0.0, about);
        assert!(e0 < 0.0 && e0.is_finite());
        for angle in [1e-6, 1e-3, 1e-2, 0.1] {
            let (e, g, x) = two_segments(&params, angle, about);
            let (em, _, _) = two_segments(&params, -angle, about);
            println!("about {about}, θ = {angle:e}: E = {e:.9} aJ (θ = 0: {e0:.9})");
            assert!(e.is_finite() && g.iter().all(|v| v.is_finite()));
            // round-off scales with the terms summed: relative to the larger energy (at 0.1 rad
            // the ends overlap, E ≈ 6e9 aJ, and the two sums differ by 1e-15 of that)
            let magnitude = e.abs().max(e0.abs());
            assert!(
                (e - em).abs() <= EVEN_TOL * magnitude,
                "even in θ: {e} vs {em}"
            );
            let scale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let h = FD_STEP;
            for k in 0..x.len() {
                let at = |t: f64| {
                    let mut y = x.clone();
                    y[k] += t;
                    vdw_energy(&params, &x, &y).0
                };
                let fd = (8.0 * (at(h) - at(-h)) - (at(2.0 * h) - at(-2.0 * h))) / (12.0 * h);
                assert!(
                    (fd - g[k]).abs() <= FD_TOL * scale,
                    "θ = {angle}, dof {k}: {fd} vs {}",
                    g[k]
                );
            }
        }
        // continuity through the small angles, with no 0/0: E(θ) − E(0) = Cθ² + O(θ⁴), so
        // the curvature estimates at 1e-6 and 1e-5 rad agree up to the next term (measured
        // 2.3 % between 1e-5 and 1e-4, so ~2e-4 here) and round-off (1e-13 of E over
        // Cθ² ~ 7e-7 of E at 1e-6 rad: 1.5e-7)
        let curvature = |a: f64| (two_segments(&params, a, about).0 - e0) / (a * a);
        let (c1, c2) = (curvature(1e-6), curvature(1e-5));
        println!("about {about}: (E(θ) − E(0))/θ² = {c1:.6e} (1e-6), {c2:.6e} (1e-5)");
        assert!((c1 / c2 - 1.0).abs() < CURVATURE_TOL, "{c1} vs {c2}");
    }
}

// ---------------------------------------------------------------------------------------------
// Very dense turfs

fn dense(density: f64) -> TurfParams {
    TurfParams {
        density,
        box_x: 400.0,
        box_y: 400.0,
        length_mean: 400.0,
        ..TurfParams::default()
    }
}

#[test]
fn a_turf_denser_than_close_packing_is_refused() {
    // hexagonal close packing of 40.34 nm circles holds 7.1e-4 /nm²: 2e-3 cannot be placed
    // (the growth of a tube fails first: bases are placed tube by tube)
    let e = generate_turf(&dense(2e-3)).expect_err("denser than close packing");
    assert!(matches!(
        e,
        TurfError::TooDense { .. } | TurfError::Interpenetrating { .. }
    ));
    let msg = e.to_string();
    println!("{msg}");
    assert!(msg.contains("density"), "{msg}");
}

#[test]
fn a_turf_at_the_equilibrium_spacing_is_generated_clear_or_refused() {
    // spacing 1/√n = 44.7 nm, 4.4 nm above the equilibrium axis distance 2r + 0.34
    match generate_turf(&dense(5e-4)) {
        Ok(t) => {
            let x = t.coordinates();
            assert!(x.iter().all(|v| v.is_finite()));
            println!("generated {} tubes", t.tubes.len());
        }
        Err(e) => {
            let msg = e.to_string();
            println!("{msg}");
            assert!(msg.contains("density"), "{msg}");
        }
    }
}
