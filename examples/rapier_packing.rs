//! Dense turfs by rigid-body packing (cargo feature `rapier`; issue 22, use (a)): a scene's
//! turf, as the discrete stage generates it, packed isotropically in x and y towards target
//! densities on rapier capsule chains ([`turf::discrete::rapier_packing`]), each packed state
//! handed to the static engine and relaxed (Newton, van der Waals), and the tubes' smallest
//! surface gap checked before and after.
//!
//! `cargo run --release --features rapier --example rapier_packing -- SCENE [key=value ...]`
//! with keys `set` (a scene override, `set=turf.box=["1 um","1 um"]`, repeatable),
//! `realisation`, `densities` (comma-separated, 10¹⁰ /cm²), `shrink`, `hold`, `clearance`,
//! `damping`, `iterations`, `stability`, `bending` (springs, torques, off), `relax` (0/1), `dump` (a folder: the packed nodes as
//! CSV per state). One line per target on stdout.

use std::path::Path;
use std::time::Instant;
use turf::discrete::model::{relax, TurfSystem};
use turf::discrete::platen::DEFAULT_WALL_STIFFNESS;
use turf::discrete::rapier_packing::{
    min_surface_gap, min_surface_gap_beyond, pack_turf, Bending, PackingParams,
};
use turf::discrete::turf::Turf;

/// 10¹⁰ tubes/cm² in tubes/nm².
const PER_1E10_CM2: f64 = 1e-4;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = args.first().ok_or("usage: SCENE [key=value ...]")?;
    let mut p = PackingParams::default();
    let mut overrides = Vec::new();
    let mut index = 0usize;
    let mut do_relax = true;
    let mut dump: Option<String> = None;
    for a in &args[1..] {
        match a.split_once('=') {
            Some(("set", v)) => overrides.push(v.to_string()),
            Some(("realisation", v)) => index = v.parse()?,
            Some(("densities", v)) => {
                p.densities = v
                    .split(',')
                    .map(|d| d.trim().parse::<f64>().map(|d| d * PER_1E10_CM2))
                    .collect::<Result<_, _>>()?
            }
            Some(("shrink", v)) => p.shrink_per_step = v.parse()?,
            Some(("hold", v)) => p.hold_steps = v.parse()?,
            Some(("clearance", v)) => p.clearance = v.parse()?,
            Some(("damping", v)) => p.damping = v.parse()?,
            Some(("iterations", v)) => p.solver_iterations = v.parse()?,
            Some(("stability", v)) => p.stability = v.parse()?,
            Some(("relax", v)) => do_relax = v == "1",
            Some(("bending", v)) => {
                p.bending = match v {
                    "springs" => Bending::JointSprings,
                    "torques" => Bending::Torques,
                    "off" => Bending::Off,
                    _ => return Err(format!("bending: springs, torques or off, not {v}").into()),
                }
            }
            Some(("dump", v)) => dump = Some(v.to_string()),
            _ => return Err(format!("unknown argument {a}").into()),
        }
    }
    let loaded = turf::scene::load(Path::new(scene), &overrides)?;
    let s = &loaded.base.scene;
    let (turf, youngs, vdw, solver) = turf::pipeline::scene_turf(s, index)?;
    let area = |t: &Turf| t.periodic.lx.unwrap_or(0.0) * t.periodic.ly.unwrap_or(0.0);
    let (g0, _) = min_surface_gap(&turf);
    eprintln!(
        "generated: smallest gap over image shifts of 2 or more periods {:.3} nm",
        min_surface_gap_beyond(&turf, 2).0
    );
    eprintln!(
        "generated: {} tubes, box {:.1} nm, {:.3}e10 /cm², smallest gap {g0:.3} nm",
        turf.tubes.len(),
        turf.periodic.lx.unwrap_or(0.0),
        turf.tubes.len() as f64 / area(&turf) / PER_1E10_CM2
    );
    let packing = pack_turf(&turf, youngs, &p)?;
    eprintln!(
        "rapier: {} bodies + {} ghosts, mass/inertia {:.3e}/{:.3e}, {p:?}",
        packing.bodies.0, packing.bodies.1, packing.mass.0, packing.mass.1
    );
    if let Some(why) = &packing.stopped {
        eprintln!("packing stopped: {why}");
    }
    println!(
        "at_target,density_1e10cm2,box_nm,steps,pack_wall_s,joint_gap_nm,gap_packed_nm,\
         turf_gap_packed_nm,gap_relaxed_nm,turf_gap_relaxed_nm,relax_iterations,relax_wall_s,\
         extent_over_box,relax_note"
    );
    for st in &packing.states {
        let l = st.turf.periodic.lx.unwrap_or(0.0);
        // how far the tubes reach, in box widths (the larger of x and y)
        let span = |d: usize| {
            let (lo, hi) = st
                .turf
                .tubes
                .iter()
                .flat_map(|t| t.nodes.iter().map(move |n| n[d]))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                });
            hi - lo
        };
        let extent = span(0).max(span(1));
        eprintln!(
            "{:.3}e10 /cm²: smallest gap {:.3} nm at {:?}; over shifts of 2 or more: {:.3} nm",
            st.density / PER_1E10_CM2,
            st.min_gap,
            min_surface_gap(&st.turf).1,
            min_surface_gap_beyond(&st.turf, 2).0
        );
        if let Some(dir) = &dump {
            let mut text = String::from("tube,node,x,y,z\n");
            for (i, t) in st.turf.tubes.iter().enumerate() {
                for (j, n) in t.nodes.iter().enumerate() {
                    text += &format!("{i},{j},{:.4},{:.4},{:.4}\n", n[0], n[1], n[2]);
                }
            }
            std::fs::create_dir_all(dir)?;
            let name = format!("{dir}/packed_{:.2}.csv", st.density / PER_1E10_CM2);
            std::fs::write(name, text)?;
        }
        let (mut turf_before, mut gap_after, mut turf_after) = (f64::NAN, f64::NAN, f64::NAN);
        let (mut iterations, mut relax_s, mut note) = (0usize, 0.0, String::new());
        if do_relax {
            let mut sys = TurfSystem::from_turf(
                &st.turf,
                youngs,
                vdw.as_ref(),
                DEFAULT_WALL_STIFFNESS,
                area(&st.turf),
            )?;
            let mut x = st.turf.coordinates();
            let t0 = Instant::now();
            match relax(&mut sys, &mut x, &solver) {
                Ok(r) => {
                    turf_before = r.initial.min_gap;
                    turf_after = r.state.min_gap;
                    iterations = r.info.cost.iterations;
                    let mut relaxed = st.turf.clone();
                    let mut k = 0;
                    for t in &mut relaxed.tubes {
                        for n in &mut t.nodes {
                            n.copy_from_slice(&x[3 * k..3 * k + 3]);
                            k += 1;
                        }
                    }
                    gap_after = min_surface_gap(&relaxed).0;
                }
                Err(e) => note = format!("relaxation failed: {e}"),
            }
            relax_s = t0.elapsed().as_secs_f64();
        }
        println!(
            "{},{:.4},{:.2},{},{:.2},{:.2e},{:.3},{:.3},{:.3},{:.3},{},{:.2},{:.2},{}",
            st.at_target,
            st.density / PER_1E10_CM2,
            l,
            st.steps,
            st.wall_s,
            st.joint_gap,
            st.min_gap,
            turf_before,
            gap_after,
            turf_after,
            iterations,
            relax_s,
            extent / l,
            note
        );
    }
    Ok(())
}
