//! The rapier3d preview of a scene's turf compression (cargo feature `rapier`), against the
//! static engine's curve of the same realisation: σ(ε) at the same strains, the relative error
//! (RMS and largest over the loading points, relative to the reference's largest stress) and
//! the wall time.
//!
//! `cargo run --release --features rapier --example rapier_preview -- SCENE REALISATION
//! [REFERENCE_CSV] [key=value ...]` with keys relax, per, hold, stability, damping, contacts
//! (0/1), multibody (0/1), increments, to (the largest strain),
//! iterations (rapier's solver iterations). REFERENCE_CSV: the discrete stage's `stress_strain.csv` of that
//! realisation (columns strain, stress_GPa).

use std::path::Path;
use turf::discrete::rapier_preview::{preview_compression, PreviewParams};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = args.first().ok_or("usage: SCENE REALISATION [REFERENCE_CSV] [k=v ...]")?;
    let index: usize = args.get(1).ok_or("REALISATION missing")?.parse()?;
    let mut p = PreviewParams::default();
    let mut reference = None;
    let loaded = turf::scene::load(Path::new(scene), &[])?;
    let s = &loaded.base.scene;
    let k = s.compression.as_ref().ok_or("no [compression]")?;
    let mut increments = k.steps;
    let mut strain_max = k.to.0;
    for a in &args[2..] {
        match a.split_once('=') {
            Some(("relax", v)) => p.relax_steps = v.parse()?,
            Some(("per", v)) => p.steps_per_increment = v.parse()?,
            Some(("hold", v)) => p.hold_steps = v.parse()?,
            Some(("stability", v)) => p.stability = v.parse()?,
            Some(("damping", v)) => p.damping = v.parse()?,
            Some(("contacts", v)) => p.contacts = v == "1",
            Some(("multibody", v)) => p.multibody = v == "1",
            Some(("increments", v)) => increments = v.parse()?,
            Some(("to", v)) => strain_max = v.parse()?,
            Some(("iterations", v)) => p.solver_iterations = v.parse()?,
            Some(_) => return Err(format!("unknown key in {a}").into()),
            None => reference = Some(a.clone()),
        }
    }
    let t = s.turf.as_ref().ok_or("no [turf]")?;
    let (turf, mut sys) = turf::pipeline::scene_turf_system(s, index)?;
    let preview = preview_compression(&turf, &mut sys, t.tube.youngs.0, strain_max, increments, &p);
    println!("strain,stress_GPa,min_gap_nm,joint_error_nm,top_nm");
    for r in &preview.steps {
        println!(
            "{:.6},{:.6e},{:.4},{:.3e},{:.2}",
            r.strain, r.stress, r.min_gap, r.joint_error, r.top
        );
    }
    eprintln!(
        "rapier preview: {} tubes, {} rapier steps, {:.2} s wall, mass/inertia {:.3e}/{:.3e}, {p:?}",
        turf.tubes.len(),
        preview.rapier_steps,
        preview.wall_s,
        preview.mass.0,
        preview.mass.1
    );
    let min_gap = preview
        .steps
        .iter()
        .map(|r| r.min_gap)
        .fold(f64::INFINITY, f64::min);
    eprintln!("smallest tube gap over the drive {min_gap:.3} nm");
    if let Some(path) = reference {
        let text = std::fs::read_to_string(&path)?;
        let mut lines = text.lines();
        let head: Vec<&str> = lines.next().ok_or("empty reference")?.split(',').collect();
        let col = |name: &str| head.iter().position(|h| *h == name);
        let (ce, cs) = (
            col("strain").ok_or("no strain column")?,
            col("stress_GPa").ok_or("no stress_GPa column")?,
        );
        let rows: Vec<(f64, f64)> = lines
            .filter_map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                Some((f.get(ce)?.parse().ok()?, f.get(cs)?.parse().ok()?))
            })
            .collect();
        let scale = rows.iter().fold(0.0f64, |m, r| m.max(r.1.abs()));
        let mut errs = Vec::new();
        for r in preview.steps.iter().skip(1) {
            if let Some(q) = rows.iter().find(|q| (q.0 - r.strain).abs() < 1e-6) {
                errs.push((r.stress - q.1) / scale);
            }
        }
        let rms = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len().max(1) as f64).sqrt();
        let max = errs.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        eprintln!(
            "against {path}: {} common strains, RMS error {:.1} %, max {:.1} % (of the reference's largest stress {:.4e} GPa)",
            errs.len(),
            100.0 * rms,
            100.0 * max,
            scale
        );
    }
    Ok(())
}
