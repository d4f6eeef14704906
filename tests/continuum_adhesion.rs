//! Adhesive FE indentation (issue 5) at small strain against the half-space solver, the
//! machine spring, and the damping's share of the energy. Coarse but adequate meshes keep these
//! fast; the full tables come from `cargo run --example continuum_pulloff`.

use turf::continuum::adhesion::{normalised_pull_off, tabor_sphere};
use turf::continuum::element::Kinematics;
use turf::continuum::{run_indent, IndentParams, IndentResult};
use turf::halfspace::{pull_off, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// Agreement of the FE pull-off with the half-space solver asked by issue 5.
const PULL_OFF_TOL: f64 = 0.03;
/// The damping's dissipation against the largest strain energy (issue 5: "negligible", < 1 %).
const DAMPING_SHARE: f64 = 0.01;

fn run(p: &IndentParams) -> IndentResult {
    run_indent(p, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn small_strain_pull_off_matches_the_halfspace_at_mu_1() {
    let mu = 1.0;
    let p = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
    let r = run(&p);
    let fe = normalised_pull_off(&r).expect("pull-off passed");
    let hs = pull_off(
        &Problem::scaled(mu, LjKind::Lj93).unwrap(),
        &HalfspaceParams::default(),
    )
    .unwrap()
    .normalized;
    eprintln!(
        "μ = 1: FE {fe:.4}, half-space {hs:.4}; {} elements, {} increments, {:.1} s",
        r.mesh_report.elements, r.stats.increments, r.stats.wall_s
    );
    assert!((fe / hs - 1.0).abs() < PULL_OFF_TOL, "FE {fe} vs {hs}");
    let s = r.summary();
    assert!(s.events.jump_in.is_some(), "μ = 1 jumps in (onset μ ≈ 0.7)");
    assert!(
        s.damping_dissipated_aJ < DAMPING_SHARE * s.max_strain_energy_aJ,
        "damping {} aJ vs strain {} aJ",
        s.damping_dissipated_aJ,
        s.max_strain_energy_aJ
    );
}
