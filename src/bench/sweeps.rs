//! Refinement sweeps of `turf bench`: the error of one answer against its cost as one setting is
//! refined, for each engine.
//!
//! - half-space trace grid (cells per process zone) at μ = 1, LJ 9-3: pull-off against the
//!   three-grid extrapolation;
//! - FE mesh (elements per contact radius) on Hertz at δ = 10 nm, small strain;
//! - FE time step (increments of a 10 nm ramp) for a Prony solid (g = 0.5, τ = 1 s) under the
//!   same sphere: the load relative to the elastic one against Lee & Radok's hereditary integral
//!   P(t) = (4/3)(√R/(1 − ν²)) ∫₀ᵗ E(t − s) d[δ^(3/2)](s), exact for a monotone contact at small
//!   strain with shear and bulk relaxing alike (seed 5.8); the ratio cancels the mesh error;
//! - discrete segments per tube on the Bisshopp–Drucker cantilever.
//!
//! The runs the ladder shares with them (the FE Hertz load, the cantilever deflection) live here.

use super::{timed, BenchError, Sweep, SweepPoint};
use crate::continuum::element::Kinematics;
use crate::continuum::material::viscoelastic::PronyTerm;
use crate::continuum::{run_indent, IndentParams, Segment};
use crate::discrete::rod::RodStiffness;
use crate::discrete::rod_problems::RodProblem;
use crate::discrete::solve_newton::NewtonParams;
use crate::halfspace::{pull_off, trace_curve, HalfspaceParams, Problem};
use crate::laws::LjKind;

/// Run `f` at each setting; failures are listed, not plotted.
fn sweep(
    name: &str,
    title: &str,
    setting: &str,
    reference: (f64, &str),
    settings: &[f64],
    f: impl Fn(f64) -> Result<(f64, Option<usize>), BenchError>,
) -> Sweep {
    let mut points = Vec::new();
    let mut failures = Vec::new();
    for &s in settings {
        let (r, cost) = timed(|| f(s));
        match r {
            Ok((answer, size)) if answer.is_finite() => points.push(SweepPoint {
                setting: s,
                size,
                answer,
                rel_error: (answer / reference.0 - 1.0).abs(),
                cost,
            }),
            Ok((answer, _)) => failures.push(format!("{setting} = {s}: answer {answer}")),
            Err(e) => failures.push(format!("{setting} = {s}: {e}")),
        }
    }
    Sweep {
        name: name.into(),
        title: title.into(),
        setting: setting.into(),
        reference: reference.0,
        reference_source: reference.1.into(),
        points,
        failures,
    }
}

/// The half-space pull-off at μ = 1 on trace grids of increasing density.
pub fn halfspace_grid(quick: bool) -> Result<Sweep, BenchError> {
    let problem = Problem::scaled(1.0, LjKind::Lj93)?;
    let reference = pull_off(&problem, &HalfspaceParams::default())?.extrapolated;
    let settings: &[f64] = if quick {
        &[3.0, 6.0, 12.0]
    } else {
        &[3.0, 6.0, 12.0, 24.0, 48.0]
    };
    Ok(sweep(
        "halfspace_grid",
        "Half-space pull-off P/(πγR), LJ 9-3, μ = 1: trace grid",
        "cells per process zone",
        (reference, "three-grid Richardson extrapolation"),
        settings,
        |cells| {
            let params = HalfspaceParams {
                cells_per_zone: cells,
                ..HalfspaceParams::default()
            };
            Ok(trace_curve(&problem, &params).map(|c| (c.pull_off.load, Some(c.nodes)))?)
        },
    ))
}

/// E* of the Hertz example (E = 0.7 GPa, ν = 0.3), GPa.
pub const HERTZ_E_STAR: f64 = 0.7 / (1.0 - 0.3 * 0.3);

/// Hertz (R = 1 µm, E = 0.7 GPa, ν = 0.3) to `depth` at `kinematics`, with a mesh of
/// `per_radius` elements per contact radius, `increments` increments and Prony terms `prony`:
/// the final load and the element count.
pub fn hertz_load(
    kinematics: Kinematics,
    per_radius: f64,
    increments: usize,
    prony: Vec<PronyTerm>,
    depth: f64,
    rate: f64,
) -> Result<(f64, usize), BenchError> {
    let mut p = IndentParams::hertz_example();
    p.kinematics = kinematics;
    p.mesh.elements_per_radius = per_radius;
    p.material.prony = prony;
    p.schedule = vec![Segment::Load { to: depth, rate }];
    p.solver.increments = increments;
    let r = run_indent(&p, &mut |_| {})?;
    let last = r.rows.last().ok_or(BenchError::NoIncrement)?;
    if (last.depth_nm - depth).abs() > 1e-9 {
        return Err(BenchError::Stopped {
            depth: last.depth_nm,
        });
    }
    Ok((last.load_nN, r.mesh_report.elements))
}

/// The FE Hertz load on meshes of increasing density.
pub fn fe_hertz_mesh(quick: bool) -> Sweep {
    let depth = 10.0;
    let reference = crate::theory::hertz::load_from_depth(depth, 1000.0, HERTZ_E_STAR);
    let settings: &[f64] = if quick {
        &[5.0, 10.0, 20.0]
    } else {
        &[5.0, 10.0, 20.0, 40.0]
    };
    sweep(
        "fe_hertz_mesh",
        "FE Hertz load, R = 1 µm, δ = 10 nm, small strain: mesh (block 200a: ≈ 0.3 % floor)",
        "elements per contact radius",
        (reference, "Hertz"),
        settings,
        |n| hertz_load(Kinematics::Small, n, 5, vec![], depth, 10.0).map(|(p, e)| (p, Some(e))),
    )
}

/// Lee–Radok ratio P_visco/P_elastic at the end of a ramp δ = v t to time `t` for
/// g(t) = 1 − g(1 − e^(−t/τ)): 1 − g + g·(3/2)∫₀¹ e^(−T(1−u)) √u du with T = t/τ, the integral by
/// composite Simpson on u = w² (smooth integrand 2w² e^(−T(1−w²))), 2000 panels: error ≪ 1e-10.
pub fn lee_radok_ratio(g: f64, t_over_tau: f64) -> f64 {
    let n = 2000;
    let h = 1.0 / n as f64;
    let f = |w: f64| 2.0 * w * w * (-t_over_tau * (1.0 - w * w)).exp();
    let mut s = f(0.0) + f(1.0);
    for i in 1..n {
        s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h);
    }
    1.0 - g + g * 1.5 * s * h / 3.0
}

/// The FE load of a relaxing solid during a ramp, relative to the elastic load on the same
/// mesh, as the increments of the ramp grow.
pub fn fe_time_step(quick: bool) -> Result<Sweep, BenchError> {
    let (g, tau, depth, rate) = (0.5, 1.0, 10.0, 10.0);
    let per_radius = 10.0;
    let (elastic, _) = hertz_load(Kinematics::Small, per_radius, 5, vec![], depth, rate)?;
    let reference = lee_radok_ratio(g, depth / rate / tau);
    let settings: &[f64] = if quick {
        &[2.0, 4.0, 8.0]
    } else {
        &[2.0, 4.0, 8.0, 16.0, 32.0, 64.0]
    };
    Ok(sweep(
        "fe_time_step",
        "FE Prony relaxation (g = 0.5, τ = 1 s) over a 1 s ramp to 10 nm: P/P_elastic",
        "increments of the ramp",
        (reference, "Lee & Radok hereditary integral"),
        settings,
        |n| {
            let prony = vec![PronyTerm { g, tau }];
            hertz_load(
                Kinematics::Small,
                per_radius,
                n as usize,
                prony,
                depth,
                rate,
            )
            .map(|(p, e)| (p / elastic, Some(e)))
        },
    ))
}

/// The cantilever tip deflection with increasing segments per tube.
pub fn rod_segments(quick: bool) -> Sweep {
    let settings: &[f64] = if quick {
        &[5.0, 10.0, 20.0, 50.0]
    } else {
        &[5.0, 10.0, 20.0, 50.0, 100.0, 200.0]
    };
    sweep(
        "rod_segments",
        "Cantilever δ_v/L at PL²/K = 2 (table to 5 decimals: 1e-5 floor)",
        "segments per tube",
        (0.49346, "Bisshopp–Drucker elastica"),
        settings,
        |n| cantilever_deflection(n as usize).map(|(d, _)| (d, Some(n as usize + 1))),
    )
}

/// Tip deflection δ_v/L of a clamped tube of `segments` segments at PL²/K = 2, reached by load
/// continuation through PL²/K = 1, with the Newton iterations taken.
pub fn cantilever_deflection(segments: usize) -> Result<(f64, usize), BenchError> {
    let length = 7000.0;
    let stiff = RodStiffness::turf_tube();
    let mut problem = RodProblem::cantilever(segments, length, stiff, [0.0; 3])?;
    let tip = problem.tip();
    let mut iterations = 0;
    for alpha in [1.0, 2.0] {
        let p = alpha * stiff.bending / (length * length);
        problem.loads = crate::discrete::constraints::PointLoads::new();
        problem.loads.add(tip, [0.0, -p, 0.0]);
        let info = problem.solve_newton(&NewtonParams::default())?;
        iterations += info.cost.iterations;
    }
    Ok((-problem.x[3 * tip + 1] / length, iterations))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lee_radok_ratio_has_its_limits() {
        // elastic (g = 0) and instantaneous (t → 0: no time to relax)
        assert!((lee_radok_ratio(0.0, 3.0) - 1.0).abs() < 1e-14);
        assert!((lee_radok_ratio(0.4, 1e-9) - 1.0).abs() < 1e-8);
        // long ramp: ∫₀¹ e^(−T(1−u))√u du = 1/T − 1/(2T²) − 1/(4T³) + …; at T = 100 the third
        // term is 2.5e-7 (times 0.6 in the ratio)
        let t = 100.0;
        let r = lee_radok_ratio(0.4, t);
        assert!(
            (r - (0.6 + 0.6 * (1.0 / t - 0.5 / (t * t)))).abs() < 3e-7,
            "{r}"
        );
        // closed form at T = 1: (3/2)∫₀¹ e^(u−1)√u du = 0.4542..., by a 10⁶-panel midpoint sum
        let n = 1_000_000;
        let m: f64 = (0..n)
            .map(|i| {
                let u = (i as f64 + 0.5) / n as f64;
                (u - 1.0).exp() * u.sqrt()
            })
            .sum::<f64>()
            / n as f64;
        assert!((lee_radok_ratio(1.0, 1.0) - 1.5 * m).abs() < 1e-8);
    }
}
