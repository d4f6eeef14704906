//! The grid-refinement study of the pull-off. The curve is traced on the trace grid
//! ([`super::trace_grid`]); the pull-off is then recomputed on three grids, uniform over the
//! edge at pull-off (where the gap opens through the peak tension, [`soft_band`]) ± (2ℓ + 2 % of
//! its radius) and over every radius whose ring could jump on its own, graded inside the contact
//! and outside (a grid uniform over the whole contact took ≈ 3000 nodes at μ = 10), each with all
//! cells smaller by `refinement_ratio` (r). On each grid the minimum of F̄ is found by a secant
//! search on dF̄/dD from the previous grid's solution; if that fails, the whole curve is traced on
//! that grid instead. With values F₁, F₂, F₃ the observed order is
//! p = ln((F₂ − F₁)/(F₃ − F₂))/ln r, and the Richardson error estimate of F₃ is
//! |F₃ − F₂|/(r^p − 1); when the sequence is not monotone or p is outside [1/2, 4] the estimate
//! falls back to |F₃ − F₂| (conservative). The tail estimate is added to the error.

use super::curve::CurvePoint;
use super::curve::{locate, remesh, soft_band, step_from, trace_on, Slope, Solved};
use super::grid::GridSpec;
use super::solve::System;
use super::trace_grid::{process_zone, trace_grid};
use super::{Cost, HalfspaceError, HalfspaceParams, Problem, Scales, Traction};
use std::rc::Rc;
use std::time::Instant;

/// One grid of the refinement study.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RefinementLevel {
    /// nodes
    pub nodes: usize,
    /// pull-off on this grid, P/(πγR)
    pub pull_off: f64,
    /// wall time of this level, s
    pub wall_time: f64,
}

/// Pull-off with its grid-refinement study.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PullOff {
    /// Tabor parameter μ
    pub tabor: f64,
    /// pull-off P/(πγR) on the finest grid (negative)
    pub normalized: f64,
    /// estimated absolute error of `normalized` (Richardson + truncated tail)
    pub error_estimate: f64,
    /// Richardson-extrapolated value
    pub extrapolated: f64,
    /// observed order of convergence (NaN if the sequence was not monotone)
    pub observed_order: f64,
    /// the grids, coarse to fine
    pub levels: Vec<RefinementLevel>,
    /// approach at pull-off, z₀
    pub approach: f64,
    /// central gap at pull-off, z₀
    pub central_gap: f64,
    /// contact radius at pull-off, √(Rz₀)
    pub contact_radius: f64,
    /// jump-in on approach under displacement control, from the trace (trace grid, no error
    /// estimate); `None` without an S-curve
    pub jump_in: Option<CurvePoint>,
    /// jump-out on retraction under displacement control, from the trace
    pub jump_out: Option<CurvePoint>,
    /// rigid estimate of the scaled load of the truncated tail
    pub tail_load: f64,
    /// total cost (trace + every level)
    pub cost: Cost,
    /// factors to internal units
    pub scales: Scales,
}

impl PullOff {
    /// Pull-off force in nN (negative: tensile).
    pub fn force(&self) -> f64 {
        self.normalized * self.scales.load
    }
}

/// The pull-off grid: uniform over the edge at pull-off (where the gap opens through the peak
/// tension, [`soft_band`]) ± (2ℓ + 2 % of its radius) and out to `near` (where the gap is still
/// small), graded towards the centre and outwards.
fn pull_off_grid(
    mu: f64,
    (edge, near): (f64, f64),
    outer: f64,
    params: &HalfspaceParams,
) -> GridSpec {
    let ell = process_zone(mu);
    let half_width = 2.0 * ell + 0.02 * edge;
    GridSpec {
        fine_spacing: ell / params.cells_per_zone,
        zone_lo: (edge - half_width).max(0.0),
        zone_hi: (edge + half_width).max(near),
        growth: params.growth,
        outer,
    }
}

/// Re-solve the pull-off on `spec`, starting from a converged pull-off on another grid: the
/// transferred state is re-solved at the same approach, then the path is followed (pseudo-
/// arclength) in the direction of decreasing load until dF̄/ds changes sign, and the minimum is
/// located in that step.
fn pull_off_on<'a, T: Traction>(
    problem: &'a Problem<T>,
    from_sys: &System<'_, T>,
    from: &Solved,
    spec: &GridSpec,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<(System<'a, T>, Solved), HalfspaceError> {
    let sys = System::new(problem, spec.build());
    cost.max_nodes = cost.max_nodes.max(sys.len());
    let centre = remesh(&sys, &from_sys.grid, from, params, cost)?;
    // walk downhill in load
    let mut near = if centre.point.slope_load > 0.0 {
        centre.reversed()
    } else {
        centre
    };
    // each step moves the edge by about one cell at most (the gaps ahead of it open by
    // max_gap_change); at μ = 10 the flat load minimum of the finer grid lay more than 40 cells
    // from the coarser grid's (LJ 10-4), so allow a few hundred
    const MAX_BRACKET_STEPS: usize = 400;
    let mut step = 0.1 * params.max_gap_change;
    for _ in 0..MAX_BRACKET_STEPS {
        let (far, used) = step_from(&sys, &near, step, params, cost)?;
        if far.point.slope_load >= 0.0 {
            let m = locate(&sys, &near, &far, Slope::Load, params, cost)?;
            return Ok((sys, m));
        }
        near = far;
        step = (2.0 * used).min(params.max_gap_change);
    }
    Err(HalfspaceError::NoPullOff {
        start: from.point.central_gap,
        end: near.point.central_gap,
    })
}

/// Pull-off with a three-grid refinement study and error estimate.
pub fn pull_off<T: Traction>(
    problem: &Problem<T>,
    params: &HalfspaceParams,
) -> Result<PullOff, HalfspaceError> {
    problem.check_validated_range()?;
    let start = Instant::now();
    let mu = problem.tabor();
    let mut cost = Cost::default();
    let window = |a: f64, near: f64| trace_grid(problem, params, a, near);
    let trace = trace_on(problem, &window, params, &mut cost)?;
    let base = pull_off_grid(
        mu,
        soft_band(&trace.pull_off_system, &trace.pull_off.state),
        window(0.0, 0.0).outer,
        params,
    );
    let mut levels = Vec::new();
    let (jump_in, jump_out) = (
        trace.jump_in.map(|s| s.point),
        trace.jump_out.map(|s| s.point),
    );
    let (mut sys, mut solved) = (trace.pull_off_system, trace.pull_off);
    for level in 0..3 {
        let t0 = Instant::now();
        let spec = base.refined(params.refinement_ratio.powi(level));
        let (s, m) = match pull_off_on(problem, &sys, &solved, &spec, params, &mut cost) {
            Ok((s, m)) => (Rc::new(s), m),
            // the local search can lose the minimum where the slope dF̄/dD is rough on a grid
            // (the edge crossing cells): trace the whole curve on this grid instead
            Err(_) => {
                let fixed = |_: f64, _: f64| spec;
                let t = trace_on(problem, &fixed, params, &mut cost)?;
                (t.pull_off_system, t.pull_off)
            }
        };
        levels.push(RefinementLevel {
            nodes: s.len(),
            pull_off: m.point.load,
            wall_time: t0.elapsed().as_secs_f64(),
        });
        sys = s;
        solved = m;
    }
    let tail_load = sys.tail_load(&solved.state);
    let (f1, f2, f3) = (levels[0].pull_off, levels[1].pull_off, levels[2].pull_off);
    let r = params.refinement_ratio;
    let ratio = (f2 - f1) / (f3 - f2);
    let order = if ratio > 1.0 {
        ratio.ln() / r.ln()
    } else {
        f64::NAN
    };
    let (extrapolated, richardson) = if (0.5..=4.0).contains(&order) {
        let e = (f3 - f2) / (r.powf(order) - 1.0);
        (f3 + e, e.abs())
    } else {
        (f3, (f3 - f2).abs())
    };
    cost.wall_time = start.elapsed().as_secs_f64();
    Ok(PullOff {
        tabor: mu,
        normalized: f3,
        error_estimate: richardson + tail_load.abs(),
        extrapolated,
        observed_order: order,
        levels,
        approach: solved.state.approach,
        central_gap: solved.point.central_gap,
        contact_radius: solved.point.contact_radius,
        jump_in,
        jump_out,
        tail_load,
        cost,
        scales: problem.scales(),
    })
}
