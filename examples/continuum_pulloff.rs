//! FE pull-off of the Tabor-sphere problem against the half-space solver (issue 5).
//! `cargo run --example continuum_pulloff -- <mu> [R/z0] [small|finite] [lj93|lj104]`
//! Env `EPR` (elements per contact radius), `ZONE` (overrides the smallest element, nm),
//! `INC` (increments per segment), `C0` (damping coefficient, GPa·s/nm; 0: none, the jumps snap), `CSV` (write the rows to this folder),
//! `CLEAR` (start and end this many z₀ clear of the surface instead of 6: the jumps of μ ≥ 5
//! happen farther out), `VERBOSE` (print every increment), `ADAPTIVE` (0: one mesh fine over the whole contact, 1: a fine band that follows the edge;
//! unset: the default, adaptive where the band is narrower than the contact), `BAND` (the band's half-width in process zones).

use turf::bench::presets::tabor_sphere;
use turf::continuum::element::Kinematics;
use turf::continuum::events::normalised_pull_off;
use turf::continuum::run_indent;
use turf::halfspace::{pull_off, HalfspaceParams, Problem};
use turf::laws::LjKind;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mu: f64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(1.0);
    let rz: f64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1000.0);
    let kin = match args.get(2).map(String::as_str) {
        Some("finite") => Kinematics::Finite,
        _ => Kinematics::Small,
    };
    let kind = match args.get(3).map(String::as_str) {
        Some("lj104") => LjKind::Lj104,
        _ => LjKind::Lj93,
    };
    let mut p = tabor_sphere(mu, rz, kind, kin);
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
    if let Some(e) = env("EPR") {
        p.mesh.elements_per_radius = e;
    }
    if let Some(h) = env("ZONE") {
        p.mesh.smallest = Some(h);
    }
    if let Some(c0) = env("C0") {
        if let Some(a) = p.adhesion.as_mut() {
            match a.damping.as_mut() {
                // C0=0: no damping, the jumps snap (src/continuum/snap.rs)
                Some(_) if c0 == 0.0 => a.damping = None,
                Some(d) => d.c0 = c0,
                None => {}
            }
        }
    }
    if let Some(a) = env("ADAPTIVE") {
        p.mesh.adaptive = Some(a != 0.0);
    }
    if let Some(b) = env("BAND") {
        p.mesh.edge_zone = b;
    }
    if let Some(c) = env("CLEAR") {
        // start and end the schedule c z₀ clear of the surface (z₀ = 1 nm)
        p.start = -c;
        if let Some(turf::continuum::Segment::Unload { to, .. }) = p.schedule.get_mut(1) {
            *to = -c;
        }
    }
    if let Some(n) = env("INC") {
        p.solver.increments = n as usize;
    }
    let verbose = std::env::var("VERBOSE").is_ok();
    let r = match run_indent(&p, &mut |g| {
        if verbose {
            eprintln!(
                "δ {:.3} P {:.4} edge {:.3} nm, {} elements, {} iterations",
                g.row.depth_nm,
                g.row.load_nN,
                g.row.contact_radius_nm,
                g.elements,
                g.row.iterations
            );
        }
    }) {
        Ok(r) => r,
        Err(turf::continuum::FeError::Stopped(r)) => {
            eprintln!("stopped: {:?}", r.failure);
            *r
        }
        Err(e) => panic!("{e}"),
    };
    if let Ok(dir) = std::env::var("CSV") {
        r.write(std::path::Path::new(&dir)).unwrap();
    }
    let hs = pull_off(
        &Problem::scaled(mu, kind).unwrap(),
        &HalfspaceParams::default(),
    )
    .map(|h| h.normalized)
    .unwrap_or(f64::NAN);
    let s = r.summary();
    let fe = normalised_pull_off(&r).unwrap_or(f64::NAN);
    let scale = std::f64::consts::PI * p.adhesion.unwrap().law.gamma() * p.indenter.radius();
    println!(
        "mu {mu} R/z0 {rz} {kin:?} {kind:?}: FE {fe:.4} half-space {hs:.4} ({:+.2} %); jump-out load {:?}; damping {:.3e} aJ / strain {:.3e} aJ ({:.3} %)",
        100.0 * (fe / hs - 1.0),
        s.events.jump_out.map(|j| j.before.load_nN / scale),
        s.damping_dissipated_aJ,
        s.max_strain_energy_aJ,
        100.0 * s.damping_dissipated_aJ / s.max_strain_energy_aJ
    );
    println!(
        "  mesh {} elements, h0 {:.3} nm, a_sizing {:.1} nm; {} increments, {} cutbacks, {} Newton, wall {:.1} s (assembly {:.1}, solve {:.1})",
        r.mesh_report.elements,
        r.resolved.block.smallest,
        r.resolved.expected_contact_radius_nm,
        r.stats.increments,
        r.stats.cutbacks,
        r.stats.newton_iterations,
        r.stats.wall_s,
        r.stats.assembly.assembly_s,
        r.stats.assembly.solve_s
    );
    if let (Some(first), Some(most)) = (
        r.adaptation.first(),
        r.adaptation.iter().map(|m| m.elements).max(),
    ) {
        println!(
            "  adaptive: {} meshes, {} to {most} elements (first {})",
            r.adaptation.len(),
            r.adaptation.iter().map(|m| m.elements).min().unwrap_or(0),
            first.elements
        );
    }
    for (name, jump) in [
        ("jump-in", s.events.jump_in),
        ("jump-out", s.events.jump_out),
    ] {
        if let Some(j) = jump {
            println!(
                "  {name} at δ {:.3} nm, P/(πγR) {:.3} → {:.3}",
                j.before.drive_nm,
                j.before.load_nN / scale,
                j.after.load_nN / scale
            );
        }
    }
    for snap in &r.snaps {
        println!(
            "  snap (segment {}) at drive {:.4} nm: δ {:.4} → {:.4} nm, P/(πγR) {:.4} → {:.4}, released {:.4e} aJ in {} iterations",
            snap.segment,
            snap.drive_nm,
            snap.depth_before_nm,
            snap.depth_after_nm,
            snap.load_before_nN / scale,
            snap.load_after_nN / scale,
            snap.energy_released_aJ,
            snap.iterations
        );
    }
}
