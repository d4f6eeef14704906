//! Grids for a given Tabor parameter and the grid-refinement study of the pull-off.
//!
//! The process zone at the contact edge (where the gap opens by about z₀) is
//! ℓ ≈ min(1, μ^{−3/2}) wide in scaled radial units (PHYSICS.md); the trace grid is uniform with
//! `cells_per_zone` cells per ℓ over every radius the contact edge visits (up to the JKR radius at
//! zero load, ρ₀ = (9π/2)^{1/3} μ^{1/2}, with margin) and graded outside. The outer radius puts
//! the gap at the edge beyond H_tail, where the rigid tail load 2|φ̄(H_tail)| is below
//! `tail_tolerance`, after allowing for the approach.
//!
//! The pull-off is then recomputed on three grids, uniform from the centre to a little beyond
//! the contact radius at pull-off (a grid fine only near the edge, coarse inside, made Newton
//! fail on the transfer at μ = 3), each with all cells smaller by `refinement_ratio` (r). On
//! each grid the minimum of F̄ is found by a secant search on dF̄/dD from the previous grid's
//! solution; if that fails, the whole curve is traced on that grid instead. With values F₁, F₂, F₃ the observed
//! order is p = ln((F₂ − F₁)/(F₃ − F₂))/ln r, and the Richardson error estimate of F₃ is
//! |F₃ − F₂|/(r^p − 1); when the sequence is not monotone or p is outside [1/2, 4] the estimate
//! falls back to |F₃ − F₂| (conservative). The tail estimate is added to the error.

use super::curve::{finish, locate, solve_from, trace_on, Slope, Solved};
use super::grid::GridSpec;
use super::solve::{Control, System};
use super::{Cost, HalfspaceError, HalfspaceParams, Problem, Scales, Traction};
use std::time::Instant;

/// Process-zone width ℓ = min(1, μ^{−3/2}), scaled radial units.
pub fn process_zone(mu: f64) -> f64 {
    mu.powf(-1.5).min(1.0)
}

/// Outer radius: the gap there exceeds H_tail + (allowance for the approach).
fn outer_radius<T: Traction>(problem: &Problem<T>, mu: f64, params: &HalfspaceParams) -> f64 {
    // smallest H (doubling) whose rigid tail load is below the tolerance
    let mut h_tail = 1.0;
    while 2.0 * problem.scaled_tail_energy(h_tail).abs() > params.tail_tolerance && h_tail < 1e8 {
        h_tail *= 2.0;
    }
    // the approach at F̄ = 0 is below ~ρ₀² (JKR: δ = a²/R − ...), ρ₀² ≈ 5.2μ; plus the start gap
    let approach = 6.0 * mu + super::curve::start_gap(mu, params);
    (2.0 * (h_tail + approach)).sqrt()
}

/// The grid on which the whole curve is traced.
pub fn trace_grid<T: Traction>(problem: &Problem<T>, params: &HalfspaceParams) -> GridSpec {
    let mu = problem.tabor();
    let ell = process_zone(mu);
    let outer = outer_radius(problem, mu, params);
    GridSpec {
        fine_spacing: ell / params.cells_per_zone,
        zone_lo: 0.0,
        zone_hi: 3.0f64.max(1.2 * (4.5 * std::f64::consts::PI).cbrt() * mu.sqrt()),
        growth: params.growth,
        outer,
    }
}

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

/// The pull-off grid: uniform out to the contact radius at pull-off plus 2ℓ + 10 %.
fn pull_off_grid(mu: f64, contact_radius: f64, outer: f64, params: &HalfspaceParams) -> GridSpec {
    let ell = process_zone(mu);
    let half_width = 2.0 * ell + 0.1 * contact_radius;
    GridSpec {
        fine_spacing: ell / params.cells_per_zone,
        zone_lo: 0.0,
        zone_hi: contact_radius + half_width,
        growth: params.growth,
        outer,
    }
}

/// Re-solve the pull-off on `spec`, starting from a converged pull-off on another grid.
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
    let guess = sys.transfer(from_sys, &from.state);
    let (state, iterations) = sys.solve(Control::Approach(from.state.approach), guess, params)?;
    cost.newton_iterations += iterations;
    cost.solves += 1;
    let centre = finish(&sys, state.gaps[0], state)?;
    // bracket the zero of dF̄/dH(0) on this grid by stepping away from the old location
    // walk in the approach D (the pull-off lies on the stable branch, where D is a regular
    // parameter) until dF̄/dD changes sign; steps keep the predicted gap change small
    let per_d = |s: &Solved| {
        s.tangent.gaps.iter().fold(0.0f64, |m, t| m.max(t.abs())) / s.tangent.approach.abs()
    };
    let sign = if Slope::LoadPerApproach.value(&centre) > 0.0 {
        -1.0
    } else {
        1.0
    };
    let mut near = centre;
    const MAX_BRACKET_STEPS: usize = 40;
    let mut step = 0.1 * params.max_gap_change / per_d(&near).max(f64::MIN_POSITIVE);
    for _ in 0..MAX_BRACKET_STEPS {
        let d = near.state.approach + sign * step;
        let far = match solve_from(&sys, &near, Control::Approach(d), params, cost) {
            Ok(far) => far,
            Err(HalfspaceError::NoConvergence { .. }) if step > params.min_step => {
                step *= 0.5;
                continue;
            }
            Err(e) => return Err(e),
        };
        if (Slope::LoadPerApproach.value(&far) > 0.0) != (Slope::LoadPerApproach.value(&near) > 0.0)
        {
            let m = locate(&sys, &near, &far, Slope::LoadPerApproach, params, cost)?;
            return Ok((sys, m));
        }
        near = far;
        step = (2.0 * step).min(params.max_gap_change / per_d(&near).max(f64::MIN_POSITIVE));
    }
    Err(HalfspaceError::NoPullOff {
        start: from.h0,
        end: near.h0,
    })
}

/// Pull-off with a three-grid refinement study and error estimate.
pub fn pull_off<T: Traction>(
    problem: &Problem<T>,
    params: &HalfspaceParams,
) -> Result<PullOff, HalfspaceError> {
    let start = Instant::now();
    let mu = problem.tabor();
    let trace_spec = trace_grid(problem, params);
    let trace_sys = System::new(problem, trace_spec.build());
    let mut cost = Cost {
        max_nodes: trace_sys.len(),
        ..Cost::default()
    };
    let trace = trace_on(&trace_sys, mu, params, &mut cost)?;
    let base = pull_off_grid(
        mu,
        trace.pull_off.point.contact_radius,
        trace_spec.outer,
        params,
    );
    let mut levels = Vec::new();
    let (mut sys, mut solved) = (trace_sys, trace.pull_off);
    for level in 0..3 {
        let t0 = Instant::now();
        let spec = base.refined(params.refinement_ratio.powi(level));
        let (s, m) = match pull_off_on(problem, &sys, &solved, &spec, params, &mut cost) {
            Ok(found) => found,
            // the local search can lose the minimum where the slope dF̄/dD is rough on a grid
            // (the edge crossing cells): trace the whole curve on this grid instead
            Err(_) => {
                let s = System::new(problem, spec.build());
                cost.max_nodes = cost.max_nodes.max(s.len());
                let m = trace_on(&s, mu, params, &mut cost)?.pull_off;
                (s, m)
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
        central_gap: solved.h0,
        contact_radius: solved.point.contact_radius,
        tail_load,
        cost,
        scales: problem.scales(),
    })
}
