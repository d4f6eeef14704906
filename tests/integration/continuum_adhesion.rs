//! Adhesive FE indentation (issue 5) at small strain against the half-space solver, the
//! machine spring, and the damping's share of the energy. Coarse but adequate meshes keep these
//! fast; the full tables come from `cargo run --example continuum_pulloff`.

use turf::bench::presets::tabor_sphere;
use turf::continuum::element::Kinematics;
use turf::continuum::events::normalised_pull_off;
use turf::continuum::indent::resolve;
use turf::continuum::machine::Machine;
use turf::continuum::mesh::{edge_block, graded_block, EdgeZone};
use turf::continuum::{run_indent, IndentParams, IndentResult, Segment};
use turf::halfspace::{pull_off, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// Agreement of the FE pull-off with the half-space solver asked by issue 5.
const PULL_OFF_TOL: f64 = 0.03;
/// Spring equilibrium P = K(Δ − δ) at every converged row, relative to πγR (Newton's
/// tolerance is 1e-9 of the forces in play).
const SPRING_TOL: f64 = 1e-6;
/// A jump moves along P = K(Δ − δ) at nearly fixed Δ: the detected jump's slope is −K up to
/// the drive's change over the jump increments (≤ 1/JUMP_RATIO of the gap's change).
const JUMP_SLOPE_TOL: f64 = 0.1;
/// A spring 10⁴ πγR/z₀ stiff against the rigid drive: the compliance 1/K shifts δ by
/// ~1e-4 z₀ at the pull-off, below the increments' resolution of the minimum.
const STIFF_TOL: f64 = 2e-3;
/// Load control separates where the halved load increment (1/2¹² of the 3πγR/140 step) fails:
/// the displacement-controlled minimum is resolved by increments of 0.05 z₀ in δ.
const LOAD_CONTROL_TOL: f64 = 5e-3;
/// The damping's dissipation against the largest strain energy (issue 5: "negligible", < 1 %).
const DAMPING_SHARE: f64 = 0.01;
/// Adaptive against fixed mesh where the fixed one fits (issue 17).
const ADAPTIVE_TOL: f64 = 0.005;
/// Issue 17: the adaptive mesh's element count stays within this factor from μ = 1 to 10.
const ELEMENT_GROWTH: f64 = 2.0;
/// Two meshes (h₀ = 0.7 and 0.5 nm, 3.9 and 5.4 elements per process zone) of a converged
/// pull-off: small strain moves 0.01 % between them; 5× the 0.04 % measured at finite strain.
const MESH_TOL: f64 = 2e-3;
/// A snap against the arc-length trace on the same mesh: the load it lands on, the energy it
/// releases (∫P dδ over the traced S-curve, trapezoids on its steps, the approach branch
/// carried from the traced fold by one P dδ: ≤ 0.2 % of the release here) and the pull-off.
/// Measured 0.03 %, 0.04 % and 0.01 %.
const SNAP_TOL: f64 = 5e-3;
/// Finite against small strain at μ = 3, R/z₀ = 200: a bound on the (measured +1.4 %)
/// finite-deformation effect that the current area's mesh-made +6.7 … +63 % would break.
const FINITE_SHIFT_TOL: f64 = 0.03;

fn run(p: &IndentParams) -> IndentResult {
    run_indent(p, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// The half-space solver's pull-off P/(πγR) for the LJ 9-3 law at Tabor μ (the reference).
fn halfspace_pull_off(mu: f64) -> f64 {
    pull_off(
        &Problem::scaled(mu, LjKind::Lj93).unwrap(),
        &HalfspaceParams::default(),
    )
    .unwrap()
    .normalized
}

#[test]
fn small_strain_pull_off_matches_the_halfspace_at_mu_1() {
    let mu = 1.0;
    let p = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
    let r = run(&p);
    let fe = normalised_pull_off(&r).expect("pull-off passed");
    let hs = halfspace_pull_off(mu);
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

/// μ = 1 through machine springs: equilibrium of the spring at every row, jumps along the
/// line of slope −K, a stiff spring reproducing displacement control, and load control
/// separating at the displacement-controlled load minimum.
#[test]
fn machine_spring_sets_the_jump_slope_and_load_control_the_pull_off() {
    let mu = 1.0;
    let base = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
    let rigid = run(&base);
    let scale = std::f64::consts::PI * base.adhesion.unwrap().law.gamma() * 1000.0;
    let rigid_po = normalised_pull_off(&rigid).unwrap();
    let rigid_out = rigid.summary().events.jump_out.unwrap().before.load_nN / scale;

    // a soft spring K = 0.5 πγR/z₀ per nm
    let k = 0.5 * scale;
    let mut p = base.clone();
    p.machine = Machine::Spring { stiffness: k };
    let soft = run(&p);
    for r in &soft.rows[1..] {
        let spring = k * (r.drive_nm - r.depth_nm);
        assert!(
            (r.load_nN - spring).abs() < SPRING_TOL * scale,
            "P = {} vs K(Δ − δ) = {spring}",
            r.load_nN
        );
    }
    let jump = soft
        .summary()
        .events
        .jump_out
        .expect("the soft spring jumps out");
    let slope =
        (jump.after.load_nN - jump.before.load_nN) / (jump.after.depth_nm - jump.before.depth_nm);
    eprintln!(
        "soft spring: jump-out slope {slope:.4} nN/nm vs −K = {:.4}",
        -k
    );
    assert!(
        (slope / -k - 1.0).abs() < JUMP_SLOPE_TOL,
        "slope {slope} vs {}",
        -k
    );
    // the soft spring jumps between the load minimum and the rigid drive's fold
    let soft_out = jump.before.load_nN / scale;
    eprintln!("jump-out P/(πγR): rigid {rigid_out:.4}, K = 0.5πγR/z₀ {soft_out:.4}, minimum {rigid_po:.4}");
    assert!(rigid_po < soft_out && soft_out < rigid_out);

    // a stiff spring is displacement control
    p.machine = Machine::Spring {
        stiffness: 1e4 * scale,
    };
    let stiff = normalised_pull_off(&run(&p)).unwrap();
    assert!(
        (stiff / rigid_po - 1.0).abs() < STIFF_TOL,
        "{stiff} vs {rigid_po}"
    );

    // load control: approach by depth, then unload the load past the pull-off
    p.machine = Machine::Load;
    p.schedule[1] = Segment::Unload {
        to: -3.0 * scale,
        rate: scale,
    };
    let load = run(&p);
    let po = normalised_pull_off(&load).expect("load control separates");
    eprintln!("load control pull-off {po:.4} vs displacement-control minimum {rigid_po:.4}");
    assert!(load.separated_nN.is_some());
    assert!(
        (po / rigid_po - 1.0).abs() < LOAD_CONTROL_TOL,
        "{po} vs {rigid_po}"
    );
}

/// Adhesion with Prony relaxation (the hyperfoam scene's combination): at a held depth the
/// compressive load relaxes towards the long-term modulus.
#[test]
fn adhesive_contact_relaxes_under_a_hold() {
    let mut p = tabor_sphere(0.5, 1000.0, LjKind::Lj93, Kinematics::Small);
    p.material.prony =
        vec![turf::continuum::material::viscoelastic::PronyTerm { g: 0.4, tau: 1.0 }];
    p.schedule.truncate(1);
    p.schedule.push(Segment::Hold { time: 3.0 });
    let r = run(&p);
    let at = |t: f64| {
        r.rows
            .iter()
            .min_by(|a, b| (a.time_s - t).abs().total_cmp(&(b.time_s - t).abs()))
            .unwrap()
            .load_nN
    };
    let (start, end) = (at(7.0), at(10.0));
    eprintln!("hold: load {start:.3} → {end:.3} nN");
    assert!(end < start && start > 0.0, "{start} → {end}");
}

/// Towards DMT: μ = 0.5 and 0.1 (no jumps) against the half-space, and −2 approached.
#[test]
fn small_strain_pull_off_tends_to_dmt_at_small_mu() {
    let mut last = -1.5;
    for mu in [0.5, 0.1] {
        let r = run(&tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small));
        let fe = normalised_pull_off(&r).expect("pull-off passed");
        let hs = halfspace_pull_off(mu);
        eprintln!("μ = {mu}: FE {fe:.4}, half-space {hs:.4}");
        assert!((fe / hs - 1.0).abs() < PULL_OFF_TOL, "FE {fe} vs {hs}");
        assert!(
            r.summary().events.jump_in.is_none(),
            "no jump-in below μ ≈ 0.7"
        );
        assert!(fe < last && fe > -2.0, "{fe} after {last}");
        last = fe;
    }
}

/// The fine band that follows the contact edge (issue 17), placed at one edge (the sizing
/// radius: JKR's at zero load for these μ; mesh generation alone): its element count stays
/// within 2× from μ = 1 to 10, where the mesh fine over the whole contact grows like μ³. A run
/// also spans the band out to the gap of 3 contact gaps, which widens with μ
/// (docs/validation-continuum.md "Adaptive mesh": 8,462 elements at μ = 1, 32,063 at the μ = 5
/// pull-off).
#[test]
fn adaptive_element_count_stays_flat_in_mu() {
    let mut counts = Vec::new();
    for mu in [1.0, 2.0, 5.0, 10.0] {
        let mut p = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
        p.mesh.adaptive = Some(true);
        let r = resolve(&p).unwrap();
        let a = r.expected_contact_radius_nm;
        let z = r.edge_zone.expect("adaptive");
        let zone = EdgeZone::plain(a, a, z.half_width, z.surface);
        let adaptive = edge_block(&r.block, &zone).unwrap().triangles.len();
        let fixed = graded_block(&r.block).map_or(0, |m| m.triangles.len());
        eprintln!("μ = {mu}: adaptive {adaptive} elements at the edge {a:.1} nm, fixed {fixed}");
        counts.push(adaptive);
    }
    let (lo, hi) = (
        *counts.iter().min().unwrap() as f64,
        *counts.iter().max().unwrap() as f64,
    );
    assert!(hi <= ELEMENT_GROWTH * lo, "{counts:?}");
}

/// Issue 17's acceptance at small strain: with the band following the edge and no damping
/// (the jumps snap), the pull-off at μ = 1 and μ = 10 is within 1 % of the half-space solver's,
/// μ = 10 stays within 50k elements on every mesh, and the meshes the converged increments
/// were solved on grow by at most 2× from μ = 1 to μ = 10 (the meshes a snap passes through on
/// its way are reported, not bounded: docs/validation-continuum.md "Adaptive mesh").
#[test]
#[ignore = "heavy: about 4 min in release"]
fn adaptive_runs_from_mu_1_to_10_match_the_halfspace_on_a_flat_element_count() {
    let mut converged_elements = Vec::new();
    for (mu, clear, increments) in [(1.0, 6.0, 140), (10.0, 26.0, 600)] {
        let mut p = tabor_sphere(mu, 1000.0, LjKind::Lj93, Kinematics::Small);
        p.mesh.adaptive = Some(true);
        p.adhesion.as_mut().unwrap().damping = None;
        // the jumps of μ = 10 come far out: start and end 26 z₀ clear (z₀ = 1 nm)
        p.start = -clear;
        if let Some(Segment::Unload { to, .. }) = p.schedule.get_mut(1) {
            *to = -clear;
        }
        p.solver.increments = increments;
        let mut largest = 0;
        let r = run_indent(&p, &mut |g| largest = largest.max(g.elements))
            .unwrap_or_else(|e| panic!("{e}"));
        let fe = normalised_pull_off(&r).unwrap();
        let hs = halfspace_pull_off(mu);
        let any_mesh = r.adaptation.iter().map(|m| m.elements).max().unwrap();
        eprintln!(
            "μ = {mu}: FE {fe:.4}, half-space {hs:.4} ({:+.2} %); {} meshes, converged on ≤ {largest} elements, any mesh ≤ {any_mesh}; {} snaps; {:.1} s",
            100.0 * (fe / hs - 1.0),
            r.adaptation.len(),
            r.snaps.len(),
            r.stats.wall_s
        );
        assert!((fe / hs - 1.0).abs() < 0.01, "μ = {mu}: {fe} vs {hs}");
        assert!(any_mesh <= 50_000, "μ = {mu}: {any_mesh} elements");
        converged_elements.push(largest as f64);
    }
    let growth = converged_elements[1] / converged_elements[0];
    assert!(growth <= ELEMENT_GROWTH, "{converged_elements:?}");
}

/// Where the mesh fine over the whole contact still fits (μ = 1), the adaptive mesh gives the
/// same pull-off.
#[test]
fn adaptive_and_fixed_meshes_agree_at_mu_1() {
    let mut p = tabor_sphere(1.0, 1000.0, LjKind::Lj93, Kinematics::Small);
    p.mesh.adaptive = Some(true);
    let adaptive = run(&p);
    p.mesh.adaptive = Some(false);
    let fixed = run(&p);
    let (a, f) = (
        normalised_pull_off(&adaptive).unwrap(),
        normalised_pull_off(&fixed).unwrap(),
    );
    eprintln!(
        "μ = 1: adaptive {a:.5} ({} meshes, {}–{} elements), fixed {f:.5} ({} elements)",
        adaptive.adaptation.len(),
        adaptive
            .adaptation
            .iter()
            .map(|m| m.elements)
            .min()
            .unwrap(),
        adaptive
            .adaptation
            .iter()
            .map(|m| m.elements)
            .max()
            .unwrap(),
        fixed.mesh_report.elements
    );
    assert!((a / f - 1.0).abs() < ADAPTIVE_TOL, "{a} vs {f}");
    assert!(adaptive.adaptation.len() > 1 && fixed.adaptation.is_empty());
}

/// The finite-strain pull-off at μ = 3, R/z₀ = 200 (γ/E\* = 0.37 z₀, a compliant solid under
/// strong adhesion) on two meshes: with the law integrated over the reference surface it is
/// mesh-converged and within a few per cent of small strain. Over the current surface the same
/// two meshes gave −1.645 and −1.825 (docs/validation-continuum.md): the stretched surface's
/// negative tension pinned the edge element by element. About 6 min in release:
/// `cargo test --release --test integration -- --ignored finite_pull_off_converges`.
#[test]
#[ignore = "heavy: about 6 min in release"]
fn finite_pull_off_converges_with_the_mesh_on_the_reference_area() {
    let pull_off = |kin, zone: f64| {
        let mut p = tabor_sphere(3.0, 200.0, LjKind::Lj93, kin);
        p.mesh.smallest = Some(zone);
        if let Some(d) = p.adhesion.as_mut().and_then(|a| a.damping.as_mut()) {
            // the default c₀ stops at the jump-in at finite strain (1/2¹² of the increment)
            d.c0 = 3e-5;
        }
        let r = run(&p);
        let f = normalised_pull_off(&r).expect("pull-off passed");
        eprintln!(
            "{kin:?}, h0 {zone} nm: {f:.5} ({} elements, {:.0} s)",
            r.mesh_report.elements, r.stats.wall_s
        );
        f
    };
    let (coarse, fine) = (
        pull_off(Kinematics::Finite, 0.7),
        pull_off(Kinematics::Finite, 0.5),
    );
    let small = pull_off(Kinematics::Small, 0.5);
    // measured 0.04 % apart (small strain: 0.01 %); the current area: 11 %
    assert!((coarse / fine - 1.0).abs() < MESH_TOL, "{coarse} vs {fine}");
    // measured +1.4 %; the current area gave +6.7 % to +63 %, growing with refinement
    assert!(
        (fine / small - 1.0).abs() < FINITE_SHIFT_TOL,
        "{fine} vs {small}"
    );
}

/// Π along the equilibrium curve: dΠ/dδ = P at equilibrium, so between two states of a traced
/// curve Π changes by ∫P dδ (trapezoids over the rows).
fn energy_along(rows: &[turf::continuum::indent::Row]) -> Vec<f64> {
    let mut pi = vec![0.0];
    for w in rows.windows(2) {
        let dw = 0.5 * (w[0].load_nN + w[1].load_nN) * (w[1].depth_nm - w[0].depth_nm);
        pi.push(pi.last().unwrap() + dw);
    }
    pi
}

/// Π and P on the traced curve where its depth first crosses `depth` after row `from`.
fn crossing(
    rows: &[turf::continuum::indent::Row],
    pi: &[f64],
    from: usize,
    depth: f64,
) -> (f64, f64) {
    (from..rows.len() - 1)
        .find_map(|i| {
            let (a, b) = (rows[i].depth_nm - depth, rows[i + 1].depth_nm - depth);
            (a * b <= 0.0 && a != b).then(|| {
                let t = a / (a - b);
                let lerp = |x: f64, y: f64| x + t * (y - x);
                (
                    lerp(pi[i], pi[i + 1]),
                    lerp(rows[i].load_nN, rows[i + 1].load_nN),
                )
            })
        })
        .expect("the curve crosses the depth")
}

/// Without contact damping, Newton meets the jump-in fold at μ = 2 and the march snaps: the drive
/// is held and the state descends to the contact branch. The state it lands in, the energy it
/// releases and the pull-off are the arc-length trace's on the same mesh.
#[test]
fn the_jump_in_snaps_without_damping_onto_the_traced_curve() {
    let mut p = tabor_sphere(2.0, 1000.0, LjKind::Lj93, Kinematics::Small);
    p.mesh.smallest = Some(4.0);
    if let Some(a) = p.adhesion.as_mut() {
        a.damping = None;
    }
    let newton = run(&p);
    p.solver.method = turf::continuum::indent::Method::Riks;
    let riks = run(&p);
    let snap = *newton.snaps.first().expect("the jump-in snaps");
    assert_eq!(snap.segment, 0);
    assert!(snap.energy_released_aJ > 0.0);
    // on the traced curve: the approach branch at the snap's depth, then (past the jump-in and
    // jump-out folds) the contact branch at the same depth
    let pi = energy_along(&riks.rows);
    // the approach branch ends at the jump-in fold, the traced row of largest depth (the snap
    // happens within an increment of it): Π there, carried to the snap's depth by P dδ
    let fold = (0..riks.rows.len() - 1)
        .find(|&k| riks.rows[k + 1].depth_nm < riks.rows[k].depth_nm)
        .expect("the jump-in fold");
    let f = &riks.rows[fold];
    let pi_out = pi[fold] + f.load_nN * (snap.depth_before_nm - f.depth_nm);
    let fold_out = (fold..riks.rows.len() - 1)
        .find(|&k| riks.rows[k + 1].depth_nm > riks.rows[k].depth_nm)
        .expect("the jump-out fold");
    let (pi_in, p_in) = crossing(&riks.rows, &pi, fold_out, snap.depth_after_nm);
    let traced = pi_out - pi_in;
    let (fe, fr) = (
        normalised_pull_off(&newton).unwrap(),
        normalised_pull_off(&riks).unwrap(),
    );
    eprintln!(
        "snap at δ {:.4} nm (traced fold {:.4}): P {:.3} → {:.3} nN (traced {:.3} → {p_in:.3}), released {:.3} aJ (traced {traced:.3}); pull-off {fe:.5} against {fr:.5}",
        snap.depth_before_nm,
        f.depth_nm,
        snap.load_before_nN,
        snap.load_after_nN,
        f.load_nN,
        snap.energy_released_aJ,
    );
    assert!(
        (snap.load_after_nN / p_in - 1.0).abs() < SNAP_TOL,
        "{} vs {p_in}",
        snap.load_after_nN
    );
    assert!((snap.energy_released_aJ / traced - 1.0).abs() < SNAP_TOL);
    assert!((fe / fr - 1.0).abs() < SNAP_TOL);
}
