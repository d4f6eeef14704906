//! Fig 4.6: damped Newton against arc-length (Riks) on the Tabor-sphere problem (issue 5), and
//! the pull-off through a machine spring K read off the traced retraction (the first minimum of
//! Δ = δ + P/K), against the half-space S-curve read the same way.
//! `cargo run --release --example continuum_riks -- <mu> [lj93|lj104] [R/z0] [small|finite]`
//! Env `C0` (Newton's damping coefficient, GPa·s/nm), `ZONE` (smallest element, nm), `INC`
//! (increments per segment), `ONLY=riks` (skip the Newton run), `CSV` (write both runs' rows
//! under this folder), `CONTRACTION` (the corrector's modified-Newton contraction factor) and
//! `RIKS_INC` (the arc-length run's increments per segment, its step cap), `MAX_STEPS` (its
//! steps per segment before it stops, default 5000), `LOG=1` (every
//! converged row on stderr: segment, δ/z₀, P/(πγR), iterations, negative eigenvalues of K_uu,
//! wall seconds). Prints the folds and bifurcations the trace passed. At finite kinematics
//! the solid is `tabor_sphere`'s compressible neo-Hookean (hyperfoam α = 2, β = 0, μ = E*/2).

use turf::bench::presets::tabor_sphere;
use turf::continuum::element::Kinematics;
use turf::continuum::events::normalised_pull_off;
use turf::continuum::events::{curve_distance, dissipation_split, spring_pull_off};
use turf::continuum::indent::Method;
use turf::continuum::{run_indent, IndentParams, IndentResult};
use turf::halfspace::{trace_curve, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// Machine stiffnesses K z₀/(πγR) of the table (∞: displacement control; load control last).
const STIFFNESSES: [f64; 9] = [f64::INFINITY, 30.0, 10.0, 3.0, 1.0, 0.5, 0.3, 0.1, 0.03];

/// Rows within this distance of the traced curve (scaled δ/z₀, P/(πγR)) count as on a stable
/// branch when the damping dissipation is split: the 1 % of the curves' agreement.
const ON_BRANCH: f64 = 0.01;

fn run(p: &IndentParams, scale: f64) -> IndentResult {
    let log = std::env::var("LOG").is_ok_and(|v| v == "1");
    let z0 = z0_of(p);
    let t0 = std::time::Instant::now();
    let mut progress = |q: &turf::continuum::indent::Progress| {
        if log {
            eprintln!(
                "  seg {} δ/z0 {:.5} P/(πγR) {:.5} its {} neg {} t {:.1} s",
                q.segment,
                q.row.depth_nm / z0,
                q.row.load_nN / scale,
                q.row.iterations,
                q.negative_eigenvalues.map_or("?".into(), |k| k.to_string()),
                t0.elapsed().as_secs_f64()
            );
        }
    };
    match run_indent(p, &mut progress) {
        Ok(r) => r,
        Err(turf::continuum::FeError::Stopped(r)) => {
            eprintln!("stopped: {:?}", r.failure);
            *r
        }
        Err(e) => panic!("{e}"),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mu: f64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(0.75);
    let kind = match args.get(1).map(String::as_str) {
        Some("lj104") => LjKind::Lj104,
        _ => LjKind::Lj93,
    };
    let rz: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(1000.0);
    let kin = match args.get(3).map(String::as_str) {
        Some("finite") => Kinematics::Finite,
        _ => Kinematics::Small,
    };
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
    let mut newton = tabor_sphere(mu, rz, kind, kin);
    if let Some(h) = env("ZONE") {
        newton.mesh.smallest = Some(h);
    }
    if let Some(n) = env("INC") {
        newton.solver.increments = n as usize;
    }
    if let Some(c0) = env("C0") {
        if let Some(d) = newton.adhesion.as_mut().and_then(|a| a.damping.as_mut()) {
            d.c0 = c0;
        }
    }
    let mut riks = newton.clone();
    riks.solver.method = Method::Riks;
    if let Some(c) = env("CONTRACTION") {
        riks.solver.arclength.contraction = c;
    }
    if let Some(n) = env("RIKS_INC") {
        riks.solver.increments = n as usize;
    }
    if let Some(n) = env("MAX_STEPS") {
        riks.solver.arclength.max_steps = n as usize;
    }
    if let Some(a) = riks.adhesion.as_mut() {
        a.damping = None;
    }
    let scale = std::f64::consts::PI * newton.adhesion.unwrap().law.gamma() * rz;
    let only_riks = std::env::var("ONLY").is_ok_and(|v| v == "riks");
    let traced = run(&riks, scale);
    let s = traced.summary();
    println!(
        "mu {mu} {kind:?} R/z0 {rz} {kin:?}: {} elements, h0 {:.3} nm",
        traced.mesh_report.elements, traced.resolved.block.smallest
    );
    println!(
        "  riks:   pull-off {:.4}; fold in δ {:?} P {:?}; fold out δ {:?} P {:?}; {} steps, {} cutbacks, {} iterations, {} factorisations ({} LU, {} LDLᵀ inertias), wall {:.1} s (assembly {:.1}, solve {:.1})",
        normalised_pull_off(&traced).unwrap_or(f64::NAN),
        s.events.fold_in.map(|r| r.drive_nm),
        s.events.fold_in.map(|r| r.load_nN / scale),
        s.events.fold_out.map(|r| r.drive_nm),
        s.events.fold_out.map(|r| r.load_nN / scale),
        traced.stats.increments,
        traced.stats.cutbacks,
        traced.stats.newton_iterations,
        traced.stats.assembly.factorisations,
        traced.stats.assembly.lu_fallbacks,
        traced.stats.assembly.inertias,
        traced.stats.wall_s,
        traced.stats.assembly.assembly_s,
        traced.stats.assembly.solve_s
    );
    for c in &traced.critical_points {
        println!(
            "  {:?} (segment {}): δ/z0 {:.4} P/(πγR) {:.4}, negative eigenvalues {} → {}, λ_min {:.3e} nN/nm, |φ·g|/‖g‖ {:.3e}, mode at r = {:.1} nm",
            c.kind,
            c.segment,
            c.depth_nm / z0_of(&riks),
            c.load_nN / scale,
            c.negative_before,
            c.negative_after,
            c.eigenvalue,
            c.load_alignment,
            c.mode_radius_nm,
        );
    }
    if let Ok(dir) = std::env::var("CSV") {
        traced
            .write(&std::path::Path::new(&dir).join("riks"))
            .unwrap();
    }
    // the retraction, scaled: δ/z₀, P/(πγR); the half-space curve is traced into contact
    let z0 = newton.adhesion.unwrap().law.z0();
    let last = traced.rows.last().map_or(0, |r| r.segment);
    let fe: Vec<(f64, f64)> = traced
        .rows
        .iter()
        .filter(|r| r.segment == last)
        .map(|r| (r.depth_nm / z0, r.load_nN / scale))
        .collect();
    let hs: Vec<(f64, f64)> = match trace_curve(
        &Problem::scaled(mu, kind).unwrap(),
        &HalfspaceParams::default(),
    ) {
        Ok(c) => c
            .points
            .iter()
            .rev()
            .map(|q| (q.approach, q.load))
            .collect(),
        Err(e) => {
            eprintln!("half-space curve: {e}");
            Vec::new()
        }
    };
    println!("  | K z0/(πγR) | FE pull-off P/(πγR) | FE drive Δ/z0 | half-space P/(πγR) | half-space Δ/z0 |");
    let ks = STIFFNESSES.iter().map(|&k| Some(k)).chain([None]);
    for k in ks {
        let (a, b) = (spring_pull_off(&fe, k), spring_pull_off(&hs, k));
        let cell = |x: Option<(f64, f64)>, i: usize| {
            x.map_or("—".to_string(), |v| {
                format!("{:.4}", if i == 0 { v.1 } else { v.0 })
            })
        };
        println!(
            "  | {} | {} | {} | {} | {} |",
            k.map_or("0 (load control)".to_string(), |k| format!("{k}")),
            cell(a, 0),
            cell(a, 1),
            cell(b, 0),
            cell(b, 1)
        );
    }
    if only_riks {
        return;
    }
    let stepped = run(&newton, scale);
    let n = stepped.summary();
    let (worst, at, compared) = curve_distance(&stepped.rows, &traced.rows, z0, scale);
    let (on, off) = dissipation_split(&stepped.rows, &traced.rows, z0, scale, ON_BRANCH);
    println!(
        "  newton damping on the stable branches (rows within {ON_BRANCH} of the Riks curve) {on:.3e} aJ ({:.3} % of the strain energy), off them (jumps) {off:.3e} aJ; cycle work ∮P dδ: newton {:.3e} aJ, riks {:.3e} aJ",
        100.0 * on / n.max_strain_energy_aJ,
        cycle_work(&stepped.rows),
        cycle_work(&traced.rows)
    );
    println!(
        "  newton: pull-off {:.4}; jump-in at δ {:?}, jump-out at δ {:?} P {:?}; damping {:.3e} aJ / strain {:.3e} aJ ({:.3} %); {} increments, {} cutbacks, wall {:.1} s",
        normalised_pull_off(&stepped).unwrap_or(f64::NAN),
        n.events.jump_in.map(|j| j.before.drive_nm),
        n.events.jump_out.map(|j| j.before.drive_nm),
        n.events.jump_out.map(|j| j.before.load_nN / scale),
        n.damping_dissipated_aJ,
        n.max_strain_energy_aJ,
        100.0 * n.damping_dissipated_aJ / n.max_strain_energy_aJ,
        stepped.stats.increments,
        stepped.stats.cutbacks,
        stepped.stats.wall_s
    );
    println!(
        "  stable branches: largest distance of a Newton row from the Riks curve in (δ/z0, P/πγR) {worst:.4} at δ {:?} P {:?}, over {compared} rows",
        at.map(|r| r.drive_nm),
        at.map(|r| r.load_nN / scale)
    );
    if let Ok(dir) = std::env::var("CSV") {
        stepped
            .write(&std::path::Path::new(&dir).join("newton"))
            .unwrap();
    }
}

/// The adhesion law's z₀ of a run, nm (1 without adhesion).
fn z0_of(p: &IndentParams) -> f64 {
    p.adhesion.map_or(1.0, |a| a.law.z0())
}

/// The work ∮P dδ done on the solid over the rows (trapezoidal): over a closed cycle of an
/// elastic solid, the energy dissipated (by damping and by the time stepping).
fn cycle_work(rows: &[turf::continuum::indent::Row]) -> f64 {
    rows.windows(2)
        .map(|w| 0.5 * (w[0].load_nN + w[1].load_nN) * (w[1].depth_nm - w[0].depth_nm))
        .sum()
}
