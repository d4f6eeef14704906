//! Adhesive FE indentation (issue 5) at small strain against the half-space solver, the
//! machine spring, and the damping's share of the energy. Coarse but adequate meshes keep these
//! fast; the full tables come from `cargo run --example continuum_pulloff`.

use turf::continuum::adhesion::AdhesionParams;
use turf::continuum::damping::ContactDamping;
use turf::continuum::element::Kinematics;
use turf::continuum::indenter::Indenter;
use turf::continuum::machine::Machine;
use turf::continuum::material::linear::LinearElastic;
use turf::continuum::material::Elastic;
use turf::continuum::{run_indent, IndentParams, IndentResult, Segment};
use turf::halfspace::{pull_off, HalfspaceParams, Problem};
use turf::laws::{LennardJones, LjKind};

/// Agreement of the FE pull-off with the half-space solver asked by issue 5.
const PULL_OFF_TOL: f64 = 0.03;
/// The damping's dissipation against the largest strain energy (issue 5: "negligible", < 1 %).
const DAMPING_SHARE: f64 = 0.01;

/// A rigid sphere (R = `r_over_z0`·z₀, z₀ = 1 nm) on a linear block (E* = 1 GPa), γ set for
/// Tabor's μ: approach from 6z₀ clear to δ = 1 nm, retract to 6z₀ clear, at 1 nm/s.
fn adhesive(mu: f64, r_over_z0: f64, kind: LjKind, kinematics: Kinematics) -> IndentParams {
    let (z0, e_star) = (1.0, 1.0);
    let r = r_over_z0 * z0;
    let gamma = mu.powf(1.5) * e_star * (z0 * z0 * z0 / r).sqrt();
    let mut p = IndentParams::hertz_example();
    p.indenter = Indenter::Sphere { radius: r };
    p.material.elastic = Elastic::Linear(LinearElastic {
        youngs: e_star,
        poisson: 0.0,
    });
    p.kinematics = kinematics;
    p.start = -6.0 * z0;
    p.schedule = vec![
        Segment::Approach { to: z0, rate: 1.0 },
        Segment::Unload {
            to: -6.0 * z0,
            rate: 1.0,
        },
    ];
    p.adhesion = Some(AdhesionParams {
        law: LennardJones::new(kind, gamma, z0).into(),
        damping: Some(ContactDamping {
            c0: 1e-4,
            gap: 6.0 * z0,
            eta: 0.5,
        }),
    });
    p.solver.increments = 140;
    p
}

fn run(p: &IndentParams) -> IndentResult {
    run_indent(p, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn normalised_pull_off(r: &IndentResult) -> f64 {
    let s = r.summary();
    let po = s.events.pull_off.expect("pull-off passed");
    let a = r.params.adhesion.unwrap();
    let radius = r.params.indenter.radius();
    po.load_nN / (std::f64::consts::PI * a.law.gamma() * radius)
}

#[test]
fn small_strain_pull_off_matches_the_halfspace_at_mu_1() {
    let mu = 1.0;
    let p = adhesive(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
    let r = run(&p);
    let fe = normalised_pull_off(&r);
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
