//! Load control through the two-spring transducer of seed §2.3 (Fig 2.1a, eqs. 2.1–2.7):
//! support springs k₁ in parallel with the specimen, load frame k₂ in series, P̂ = k₁h + Q,
//! h = δ + Q/k₂ (`turf::continuum::machine::Machine::LoadFrame`). Checked on the Hertz
//! problem (rigid 1 µm sphere, E = 0.7 GPa, ν = 0.3):
//! - every converged row satisfies the machine's equilibrium, as `theory::indentation_law` does;
//! - during a hold with Prony relaxation the force on the specimen falls while the depth creeps
//!   along dQ/dδ = −χ, χ = (1/k₁ + 1/k₂)⁻¹ (seed 2.6, `Rheology::chi`);
//! - an elastic specimen carries the Hertz load at its depth whatever the machine, and the
//!   applied force is larger by the support springs' share;
//! - k₁ → 0 with a rigid frame (k₂ = ∞) is plain load control, row by row.

use turf::continuum::element::Kinematics;
use turf::continuum::machine::Machine;
use turf::continuum::material::viscoelastic::PronyTerm;
use turf::continuum::{run_indent, IndentParams, IndentResult, Segment};
use turf::theory::indentation_law::Rheology;

/// Support springs k₁, nN/nm: a third of the specimen's stiffness 2aE* ≈ 150 nN/nm at
/// δ = 10 nm, so the springs take a visible share of the applied force.
const K1: f64 = 50.0;
/// Load frame k₂, nN/nm: stiff but finite, so h ≠ δ.
const K2: f64 = 1e4;
/// Largest applied force, nN (the specimen's Hertz load at ≈ 8 nm).
const P_MAX: f64 = 1200.0;
/// Machine equilibrium P̂ = k₁h + Q and the hold slope hold to Newton's tolerance (residual
/// ≤ 1e-9 of the forces in play, ~1e-6 nN here) over load changes of ~10² nN: 1e-6 relative
/// leaves three decades of margin and fails on any wrong term (k₁δ alone is ~25 % of P̂).
const MACHINE_TOL: f64 = 1e-6;
/// The hold's creep must be measurable for its slope to mean anything, nm.
const MIN_CREEP_NM: f64 = 0.1;
/// dQ/dδ over a creep ≥ 0.1 nm: Newton's residual (~1e-6 nN) over ΔQ = χΔδ ≥ 5 nN is
/// ≤ 2e-7 relative; 1e-4 is margin, far below any wrong machine term (k₂'s share is 0.5 %).
const HOLD_SLOPE_TOL: f64 = 1e-4;
/// The Hertz contract of `tests/integration/continuum_hertz.rs` on the default mesh (measured +0.8 %).
const HERTZ_TOL: f64 = 0.02;
/// k₁ → 0, k₂ = ∞ against plain load control: the same equations up to round-off in χ = 0 and
/// t = 1, and Newton's tolerance.
const LIMIT_TOL: f64 = 1e-8;

fn frame(k1: f64, k2: f64) -> Machine {
    Machine::LoadFrame { k1, k2 }
}

fn params(machine: Machine) -> IndentParams {
    let mut p = IndentParams::hertz_example();
    p.kinematics = Kinematics::Small;
    p.machine = machine;
    p.schedule = vec![
        Segment::Load {
            to: P_MAX,
            rate: P_MAX,
        },
        Segment::Unload {
            to: 0.25 * P_MAX,
            rate: P_MAX,
        },
    ];
    p.solver.increments = 6;
    p
}

fn run(p: &IndentParams) -> IndentResult {
    run_indent(p, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// P̂ = k₁h + Q with h = δ + Q/k₂ the plate position (`drive_nm`), as in the closed form.
fn check_machine_equilibrium(r: &IndentResult, k1: f64, k2: f64) {
    for row in &r.rows[1..] {
        let applied = r.params.machine.applied_load(row.load_nN, row.depth_nm);
        let h = row.depth_nm + row.load_nN / k2;
        assert!((row.drive_nm - h).abs() <= MACHINE_TOL * h.abs().max(1.0));
        assert!((k1 * h + row.load_nN - applied).abs() <= MACHINE_TOL * applied.abs());
    }
}

#[test]
fn hold_relaxes_the_load_along_the_machine_slope() {
    let mut p = params(frame(K1, K2));
    p.mesh.elements_per_radius = 8.0;
    p.material.prony = vec![PronyTerm { g: 0.4, tau: 1.0 }];
    p.schedule = vec![
        Segment::Load {
            to: P_MAX,
            rate: P_MAX,
        },
        Segment::Hold { time: 3.0 },
    ];
    let r = run(&p);
    check_machine_equilibrium(&r, K1, K2);
    let chi = Rheology {
        machine_k1: K1,
        machine_k2: K2,
        specimen_k1: 1.0,
        specimen_k2: 1.0,
        viscosity: 1.0,
    }
    .chi();
    // the hold starts at t = 1 s, where the load segment ends
    let hold: Vec<_> = r
        .rows
        .iter()
        .filter(|row| row.time_s >= 1.0 - 1e-9)
        .collect();
    let (first, last) = (hold[0], hold[hold.len() - 1]);
    let creep = last.depth_nm - first.depth_nm;
    println!(
        "hold: δ {:.4} → {:.4} nm, Q {:.3} → {:.3} nN",
        first.depth_nm, last.depth_nm, first.load_nN, last.load_nN
    );
    assert!(creep > MIN_CREEP_NM, "the depth creeps: {creep} nm");
    assert!(last.load_nN < first.load_nN, "the specimen's force relaxes");
    for row in hold
        .iter()
        .filter(|r| r.depth_nm - first.depth_nm >= MIN_CREEP_NM)
    {
        let slope = (row.load_nN - first.load_nN) / (row.depth_nm - first.depth_nm);
        assert!(
            (slope / -chi - 1.0).abs() < HOLD_SLOPE_TOL,
            "dQ/dδ = {slope} against −χ = {}",
            -chi
        );
    }
}

#[test]
fn elastic_specimen_carries_hertz_and_the_springs_the_rest() {
    let r = run(&params(frame(K1, K2)));
    check_machine_equilibrium(&r, K1, K2);
    let e_star = r.resolved.reduced_modulus_GPa;
    let radius: f64 = 1000.0;
    let mut checked = 0;
    for row in &r.rows[1..] {
        let d = row.depth_nm;
        let hertz = 4.0 / 3.0 * e_star * radius.sqrt() * d.powf(1.5);
        println!(
            "δ = {d:.3} nm: Q = {:.2} nN, Hertz {hertz:.2}, P̂ = {:.2}",
            row.load_nN,
            r.params.machine.applied_load(row.load_nN, d)
        );
        // the validated range of the Hertz check (small kinematics, δ ≥ 4 nm)
        if d >= 4.0 {
            assert!((row.load_nN / hertz - 1.0).abs() < HERTZ_TOL);
            checked += 1;
        }
    }
    assert!(checked >= 3, "{checked} rows in the Hertz range");
    // the support springs carry k₁h: the specimen gets visibly less than the applied force
    let top = r
        .rows
        .iter()
        .max_by(|a, b| a.load_nN.total_cmp(&b.load_nN))
        .unwrap();
    assert!(top.load_nN < 0.9 * P_MAX);
}

#[test]
fn soft_support_and_rigid_frame_is_plain_load_control() {
    let mut a = params(frame(0.0, f64::INFINITY));
    a.mesh.elements_per_radius = 8.0;
    // without support springs nothing holds the indenter before contact: approach by depth
    // first, as plain load control needs
    a.schedule.insert(
        0,
        Segment::Approach {
            to: 2.0,
            rate: 10.0,
        },
    );
    let mut b = a.clone();
    b.machine = Machine::Load;
    let (ra, rb) = (run(&a), run(&b));
    assert_eq!(ra.rows.len(), rb.rows.len());
    for (x, y) in ra.rows.iter().zip(&rb.rows) {
        assert!((x.load_nN - y.load_nN).abs() <= LIMIT_TOL * P_MAX);
        assert!((x.depth_nm - y.depth_nm).abs() <= LIMIT_TOL * y.depth_nm.abs().max(1.0));
        // the plate is the indenter
        assert!((x.drive_nm - x.depth_nm).abs() <= LIMIT_TOL * x.depth_nm.abs().max(1.0));
    }
    // a rigid frame with finite support springs is fine too: h = δ exactly
    let mut c = a.clone();
    c.machine = frame(K1, f64::INFINITY);
    let rc = run(&c);
    check_machine_equilibrium(&rc, K1, f64::INFINITY);
}
