//! Arc-length continuation (Riks) of the adhesive FE indentation (issue 5, seed Fig 4.6): the
//! same curve as damped Newton on its stable branches, the folds of the S-curve where the
//! half-space solver has them, and the machine spring read off one traced curve. Default
//! (coarse, μ ≤ 1) meshes of `tabor_sphere`; the μ = 2 figures come from
//! `cargo run --release --example continuum_riks -- 2`.

use turf::bench::presets::tabor_sphere;
use turf::continuum::bifurcation::CriticalKind;
use turf::continuum::element::Kinematics;
use turf::continuum::events::normalised_pull_off;
use turf::continuum::events::{curve_distance, spring_pull_off};
use turf::continuum::indent::Method;
use turf::continuum::machine::Machine;
use turf::continuum::{run_indent, IndentParams, IndentResult, Segment};
use turf::halfspace::{trace_curve, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// Issue 5: damped Newton and arc-length give the same curve within 1 % — the largest
/// distance of a Newton row from the traced curve in (δ/z₀, P/(πγR)).
const CURVE_TOL: f64 = 0.01;
/// The two pull-offs are the minimum rows of two samplings of one curve (Newton every
/// 0.05 z₀ of δ, arc-length at its own steps): the minimum is flat, so they agree to ≲ 1e-3.
const PULL_OFF_AGREEMENT: f64 = 2e-3;
/// Damping's dissipation against the largest strain energy (issue 5: < 1 %).
const DAMPING_SHARE: f64 = 0.01;
/// FE against the half-space (folds and pull-off): the 3 % of issue 5's small-strain contract.
const HALFSPACE_TOL: f64 = 0.03;
/// A fold row of a traced curve against the refined minimum of Δ = δ + P/K on another trace of
/// the same curve: both sample the fold at the arc-length steps (~0.05 z₀ in δ).
const FOLD_SAMPLING_TOL: f64 = 0.01;

fn run(p: &IndentParams) -> IndentResult {
    run_indent(p, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn riks(mu: f64) -> IndentParams {
    let mut p = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
    p.solver.method = Method::Riks;
    p.adhesion.as_mut().unwrap().damping = None;
    p
}

fn scale(p: &IndentParams) -> f64 {
    std::f64::consts::PI * p.adhesion.unwrap().law.gamma() * p.indenter.radius()
}

#[test]
fn riks_and_damped_newton_trace_the_same_curve_at_mu_075() {
    let mu = 0.75;
    let newton = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
    let (stepped, traced) = (run(&newton), run(&riks(mu)));
    let (d, at, compared) = curve_distance(&stepped.rows, &traced.rows, 1.0, scale(&newton));
    let (pn, pr) = (
        normalised_pull_off(&stepped).unwrap(),
        normalised_pull_off(&traced).unwrap(),
    );
    let s = stepped.summary();
    eprintln!(
        "μ = 0.75: distance {d:.4} at {:?} over {compared} rows; pull-off Newton {pn:.4}, Riks {pr:.4}; damping {:.3} % of the strain energy",
        at.map(|r| (r.drive_nm, r.load_nN / scale(&newton))),
        100.0 * s.damping_dissipated_aJ / s.max_strain_energy_aJ
    );
    assert!(compared > 100, "{compared} rows compared");
    assert!(d < CURVE_TOL, "distance {d}");
    assert!((pn / pr - 1.0).abs() < PULL_OFF_AGREEMENT, "{pn} vs {pr}");
    assert!(s.damping_dissipated_aJ < DAMPING_SHARE * s.max_strain_energy_aJ);
    // the traced curve turns at its folds instead of jumping
    let e = traced.summary().events;
    assert!(e.fold_in.is_some() && e.fold_out.is_some() && e.jump_in.is_none());
}

/// μ = 1: both folds and the pull-off where the half-space S-curve has them; a spring and
/// load control traced on the same curve.
#[test]
fn riks_passes_both_folds_and_any_machine_at_mu_1() {
    let mu = 1.0;
    let p = riks(mu);
    let sc = scale(&p);
    let traced = run(&p);
    let hs = trace_curve(
        &Problem::scaled(mu, LjKind::Lj93).unwrap(),
        &HalfspaceParams::default(),
    )
    .unwrap();
    let e = traced.summary().events;
    let (fin, fout) = (e.fold_in.unwrap(), e.fold_out.unwrap());
    let (hin, hout) = (hs.jump_in.unwrap(), hs.jump_out.unwrap());
    let po = normalised_pull_off(&traced).unwrap();
    eprintln!(
        "μ = 1 fold in δ {:.4} (half-space {:.4}), fold out δ {:.4} P {:.4} (half-space {:.4}, {:.4}), pull-off {po:.4} ({:.4}); {} steps, {} LU of {} factorisations",
        fin.depth_nm, hin.approach, fout.depth_nm, fout.load_nN / sc, hout.approach, hout.load,
        hs.pull_off.load, traced.stats.increments, traced.stats.assembly.lu_fallbacks,
        traced.stats.assembly.factorisations
    );
    for (fe, half) in [
        (fin.depth_nm, hin.approach),
        (fout.depth_nm, hout.approach),
        (po, hs.pull_off.load),
    ] {
        assert!((fe / half - 1.0).abs() < HALFSPACE_TOL, "{fe} vs {half}");
    }
    assert!(
        traced.stats.assembly.lu_fallbacks > 0,
        "the unstable branch is indefinite"
    );
    // the inertia of K_uu sees the same folds, two per segment: one eigenvalue crosses zero
    // where the trace turns in δ (0 → 1 → 0 negative), the indenter loads the critical mode,
    // and no other branch crosses the S-curve
    let critical = &traced.critical_points;
    assert_eq!(critical.len(), 4, "{critical:?}");
    for (c, (before, after)) in critical.iter().zip([(0, 1), (1, 0), (0, 1), (1, 0)]) {
        assert_eq!(c.kind, CriticalKind::Fold, "{c:?}");
        assert_eq!((c.negative_before, c.negative_after), (before, after));
        assert!(c.load_alignment > 0.05, "{c:?}");
    }
    let z0 = p.adhesion.unwrap().law.z0();
    for (c, fold) in [(&critical[0], fin), (&critical[1], fout)] {
        assert!(
            (c.depth_nm - fold.depth_nm).abs() < 0.01 * z0,
            "{c:?} vs {fold:?}"
        );
    }

    // a spring K = 0.5 πγR/z₀: its fold is the displacement trace's point of slope −K
    let k = 0.5 * sc;
    let retraction: Vec<(f64, f64)> = traced
        .rows
        .iter()
        .filter(|r| r.segment == 1)
        .map(|r| (r.depth_nm, r.load_nN / sc))
        .collect();
    let (_, expected) = spring_pull_off(&retraction, Some(k / sc)).unwrap();
    let mut sp = p.clone();
    sp.machine = Machine::Spring { stiffness: k };
    let spring = run(&sp);
    let out = spring.summary().events.fold_out.unwrap();
    eprintln!(
        "spring K = 0.5 πγR/z₀: fold at P/(πγR) {:.4}, slope −K on the rigid trace at {expected:.4}",
        out.load_nN / sc
    );
    assert!((out.load_nN / sc - expected).abs() < FOLD_SAMPLING_TOL);
    for r in &spring.rows {
        assert!(
            (r.drive_nm - r.depth_nm - r.load_nN / k).abs() < 1e-12 * r.drive_nm.abs().max(1.0)
        );
    }

    // load control separates at the load minimum
    let mut lp = p.clone();
    lp.machine = Machine::Load;
    lp.schedule[1] = Segment::Unload {
        to: -3.0 * sc,
        rate: sc,
    };
    let load = run(&lp);
    let sep = load.separated_nN.expect("load control separates") / sc;
    eprintln!("load control separates at {sep:.4} (displacement-traced minimum {po:.4})");
    assert!((sep / po - 1.0).abs() < PULL_OFF_AGREEMENT, "{sep} vs {po}");
}
