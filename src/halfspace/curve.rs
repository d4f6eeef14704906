//! Tracing the load–approach S-curve by continuation in the central gap, and locating its
//! special points: jump-in and jump-out (turning points of the approach D, where dD/dH(0) = 0)
//! and pull-off (the minimum load, where dF̄/dH(0) = 0).
//!
//! Tracing starts at a central gap beyond jump-in from the rigid profile and steps H(0)
//! downwards with a tangent predictor; the step grows after easy solves, shrinks after hard
//! ones, keeps the predicted change of every nodal gap below `max_gap_change`, and is cut back
//! on failure. A sign change of a slope between two points is refined by the Illinois (modified
//! regula falsi) method on the slope, each evaluation a Newton solve from the nearer end.

use super::solve::{State, System, Tangent};
use super::{Cost, HalfspaceError, HalfspaceParams, Problem, Scales, Traction};
use std::time::Instant;

/// A point of the curve, scaled units (see [`super`]): load in πγR, gaps in z₀, radii in √(Rz₀).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// central gap H(0)
    pub central_gap: f64,
    /// approach D (positive towards the surface)
    pub approach: f64,
    /// load F̄ = P/(πγR), positive compressive
    pub load: f64,
    /// contact radius (where h = z₀)
    pub contact_radius: f64,
    /// dD/dH(0): negative on stable branches under displacement control
    pub slope_approach: f64,
    /// dF̄/dH(0)
    pub slope_load: f64,
}

/// A located special point of the curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurningPoint {
    /// the point
    pub point: CurvePoint,
}

/// The traced curve and its special points.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// Tabor parameter μ
    pub tabor: f64,
    /// the points, in order of decreasing central gap
    pub points: Vec<CurvePoint>,
    /// jump-to-contact on approach under displacement control (first maximum of D); `None`
    /// when the curve has no S (small μ)
    pub jump_in: Option<CurvePoint>,
    /// jump-out on retraction under displacement control (the minimum of D after jump-in)
    pub jump_out: Option<CurvePoint>,
    /// pull-off under load control: the minimum load
    pub pull_off: CurvePoint,
    /// grid nodes
    pub nodes: usize,
    /// rigid estimate of the scaled load of the truncated tail at pull-off
    pub tail_load: f64,
    /// cost of the trace
    pub cost: Cost,
    /// factors to internal units (load nN, gap nm, radius nm)
    pub scales: Scales,
}

/// One converged point with its state and tangent.
#[derive(Clone)]
pub(crate) struct Solved {
    pub(crate) h0: f64,
    pub(crate) state: State,
    pub(crate) tangent: Tangent,
    pub(crate) point: CurvePoint,
}

/// Solve at `h0` from a neighbouring solved point, with the tangent predictor.
pub(crate) fn solve_from<T: Traction>(
    sys: &System<'_, T>,
    from: &Solved,
    h0: f64,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Solved, HalfspaceError> {
    let dh = h0 - from.h0;
    let guess = State {
        gaps: from
            .state
            .gaps
            .iter()
            .zip(&from.tangent.gaps)
            .map(|(g, t)| g + dh * t)
            .collect(),
        approach: from.state.approach + dh * from.tangent.approach,
    };
    let (state, iterations) = sys.solve(h0, guess, params)?;
    cost.newton_iterations += iterations;
    cost.solves += 1;
    finish(sys, h0, state)
}

/// Tangent and curve point of a converged state.
pub(crate) fn finish<T: Traction>(
    sys: &System<'_, T>,
    h0: f64,
    state: State,
) -> Result<Solved, HalfspaceError> {
    let tangent = sys.tangent(&state, h0)?;
    let point = CurvePoint {
        central_gap: h0,
        approach: state.approach,
        load: sys.load(&state),
        contact_radius: sys.contact_radius(&state),
        slope_approach: tangent.approach,
        slope_load: tangent.load,
    };
    Ok(Solved {
        h0,
        state,
        tangent,
        point,
    })
}

/// Which slope vanishes at the point sought.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Slope {
    /// dD/dH(0): jump points
    Approach,
    /// dF̄/dH(0): pull-off
    Load,
}

impl Slope {
    fn of(self, p: &CurvePoint) -> f64 {
        match self {
            Slope::Approach => p.slope_approach,
            Slope::Load => p.slope_load,
        }
    }
}

/// Locate the zero of a slope between two solved points where it changes sign (Illinois).
pub(crate) fn locate<T: Traction>(
    sys: &System<'_, T>,
    a: &Solved,
    b: &Solved,
    slope: Slope,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Solved, HalfspaceError> {
    let (mut a, mut b) = (a.clone(), b.clone());
    let (mut fa, mut fb) = (slope.of(&a.point), slope.of(&b.point));
    let mut side = 0i8;
    const MAX_SECANT_STEPS: usize = 60;
    for _ in 0..MAX_SECANT_STEPS {
        if (a.h0 - b.h0).abs() < params.locate_tolerance {
            break;
        }
        let h = (a.h0 * fb - b.h0 * fa) / (fb - fa);
        let from = if (h - a.h0).abs() < (h - b.h0).abs() {
            &a
        } else {
            &b
        };
        let c = solve_from(sys, from, h, params, cost)?;
        let fc = slope.of(&c.point);
        if fc == 0.0 {
            return Ok(c);
        }
        if (fc > 0.0) == (fa > 0.0) {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    Ok(if slope.of(&a.point).abs() < slope.of(&b.point).abs() {
        a
    } else {
        b
    })
}

/// Default starting central gap, beyond jump-in: 3 + 3μ^{3/7} (the bulge of the surface under
/// the attraction grows like μ^{3/2}H^{−7/2} for a 9-3 tail, so instability sets in near H ~ μ^{3/7}).
pub(crate) fn start_gap(mu: f64, params: &HalfspaceParams) -> f64 {
    params
        .start_gap
        .unwrap_or_else(|| 3.0 + 3.0 * mu.powf(3.0 / 7.0))
}

/// A traced curve on one grid, with the states of its special points.
pub(crate) struct Trace {
    pub(crate) points: Vec<CurvePoint>,
    pub(crate) jump_in: Option<Solved>,
    pub(crate) jump_out: Option<Solved>,
    pub(crate) pull_off: Solved,
}

/// Trace the S-curve on `sys` from beyond jump-in until the load passes its minimum and
/// reaches `end_load`.
pub(crate) fn trace_on<T: Traction>(
    sys: &System<'_, T>,
    mu: f64,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Trace, HalfspaceError> {
    let h_start = start_gap(mu, params);
    let (state, iterations) = sys.solve(h_start, sys.rigid(h_start), params)?;
    cost.newton_iterations += iterations;
    cost.solves += 1;
    let mut prev = finish(sys, h_start, state)?;
    let mut points = vec![prev.point];
    let mut step = params.max_step;
    let mut jump_in: Option<Solved> = None;
    let mut jump_out: Option<Solved> = None;
    let mut pull_off: Option<Solved> = None;
    loop {
        let largest = prev.tangent.gaps.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        let dh = step.min(params.max_gap_change / largest.max(1e-300));
        let h = prev.h0 - dh;
        let next = match solve_from(sys, &prev, h, params, cost) {
            Ok(s) => s,
            Err(HalfspaceError::NoConvergence {
                residual,
                iterations,
                ..
            }) => {
                step = 0.5 * dh;
                if step < params.min_step {
                    return Err(HalfspaceError::NoConvergence {
                        central_gap: h,
                        residual,
                        iterations,
                        step: dh,
                    });
                }
                continue;
            }
            Err(e) => return Err(e),
        };
        // turning points of D: − → + is jump-in (D maximum), + → − after it is jump-out
        let (sa0, sa1) = (prev.point.slope_approach, next.point.slope_approach);
        if sa0 < 0.0 && sa1 >= 0.0 && jump_in.is_none() {
            jump_in = Some(locate(sys, &prev, &next, Slope::Approach, params, cost)?);
        } else if sa0 > 0.0 && sa1 <= 0.0 && jump_in.is_some() && jump_out.is_none() {
            jump_out = Some(locate(sys, &prev, &next, Slope::Approach, params, cost)?);
        }
        // load minimum: dF̄/dH(0) goes from + to −
        if prev.point.slope_load > 0.0 && next.point.slope_load <= 0.0 {
            let m = locate(sys, &prev, &next, Slope::Load, params, cost)?;
            if pull_off.as_ref().is_none_or(|p| m.point.load < p.point.load) {
                pull_off = Some(m);
            }
        }
        points.push(next.point);
        prev = next;
        if pull_off.is_some() && prev.point.load >= params.end_load {
            break;
        }
        if prev.h0 <= params.min_gap {
            break;
        }
        step = (step * 1.5).min(params.max_step);
    }
    let pull_off = pull_off.ok_or(HalfspaceError::NoPullOff {
        start: h_start,
        end: prev.h0,
    })?;
    Ok(Trace {
        points,
        jump_in,
        jump_out,
        pull_off,
    })
}

/// Trace the whole load–approach curve of `problem` on the default trace grid, with its jump
/// points and pull-off (on that grid; [`super::pull_off`] adds the refinement study).
pub fn trace_curve<T: Traction>(
    problem: &Problem<T>,
    params: &HalfspaceParams,
) -> Result<Curve, HalfspaceError> {
    let start = Instant::now();
    let mu = problem.tabor();
    let sys = System::new(problem, super::refinement::trace_grid(problem, params).build());
    let mut cost = Cost {
        max_nodes: sys.len(),
        ..Cost::default()
    };
    let trace = trace_on(&sys, mu, params, &mut cost)?;
    cost.wall_time = start.elapsed().as_secs_f64();
    Ok(Curve {
        tabor: mu,
        points: trace.points,
        jump_in: trace.jump_in.map(|s| s.point),
        jump_out: trace.jump_out.map(|s| s.point),
        tail_load: sys.tail_load(&trace.pull_off.state),
        pull_off: trace.pull_off.point,
        nodes: sys.len(),
        cost,
        scales: problem.scales(),
    })
}
