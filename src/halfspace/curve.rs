//! Tracing the load–approach S-curve by continuation in the central gap, and locating its
//! special points: jump-in and jump-out (turning points of the approach D, where dD/dH(0) = 0)
//! and pull-off (the minimum load, where dF̄/dH(0) = 0).
//!
//! Tracing starts at a central gap beyond jump-in from the rigid profile and steps H(0)
//! downwards with a tangent predictor (the corrector prescribes D instead of H(0) where
//! |dD/dH(0)| > 1: on the contact branch H(0) barely moves and the H(0)-bordered system is
//! badly conditioned); the step grows after easy solves, shrinks after hard
//! ones, keeps the predicted change of every nodal gap below `max_gap_change`, and is cut back
//! on failure. A sign change of a slope between two points is refined by the Illinois (modified
//! regula falsi) method on the slope, each evaluation a Newton solve from the nearer end.

use super::solve::{Control, State, System, Tangent};
use super::{Cost, HalfspaceError, HalfspaceParams, Problem, Scales, Traction};
use std::time::Instant;

/// A point of the curve, scaled units (see [`super`]): load in πγR, gaps in z₀, radii in √(Rz₀).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
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

/// The traced curve and its special points.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
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

/// Solve under `control` from a neighbouring solved point, with the tangent predictor.
pub(crate) fn solve_from<T: Traction>(
    sys: &System<'_, T>,
    from: &Solved,
    control: Control,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Solved, HalfspaceError> {
    // path parameter change Δ(H(0)) implied by the target
    let dh = match control {
        Control::CentralGap(h0) => h0 - from.h0,
        Control::Approach(d) => (d - from.state.approach) / from.tangent.approach,
    };
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
    let (state, iterations) = sys.solve(control, guess.clone(), params)?;
    cost.newton_iterations += iterations;
    cost.solves += 1;
    // a corrector that lands far from the predictor has jumped to another branch
    let moved = state
        .gaps
        .iter()
        .zip(&guess.gaps)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    if moved > params.max_gap_change {
        return Err(HalfspaceError::NoConvergence {
            central_gap: state.gaps[0],
            residual: moved,
            iterations,
            step: dh,
        });
    }
    finish(sys, state.gaps[0], state)
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

/// One continuation step of at most `step` in H(0) in `direction` (±1) from `from`, limited so
/// that the predicted change of every gap stays below `max_gap_change`, halved on failure down
/// to `min_step`. Returns the new point and the step used.
pub(crate) fn step_from<T: Traction>(
    sys: &System<'_, T>,
    from: &Solved,
    direction: f64,
    step: f64,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<(Solved, f64), HalfspaceError> {
    let largest = from.tangent.gaps.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let mut dh = step.min(params.max_gap_change / largest.max(f64::MIN_POSITIVE));
    loop {
        let h = from.h0 + direction * dh;
        // prescribe whichever of H(0) and D moves faster along the path: H(0) is regular
        // through the turning points of D, D is better conditioned on the contact branch,
        // where H(0) hardly moves
        let control = if from.tangent.approach.abs() > 1.0 {
            Control::Approach(from.state.approach + from.tangent.approach * (h - from.h0))
        } else {
            Control::CentralGap(h)
        };
        match solve_from(sys, from, control, params, cost) {
            Ok(s) => return Ok((s, dh)),
            Err(HalfspaceError::NoConvergence {
                residual,
                iterations,
                ..
            }) => {
                dh *= 0.5;
                if dh < params.min_step {
                    return Err(HalfspaceError::NoConvergence {
                        central_gap: h,
                        residual,
                        iterations,
                        step: dh,
                    });
                }
            }
            Err(e) => return Err(e),
        }
    }
}

/// Which slope vanishes at the point sought, and along which path parameter it is sought.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Slope {
    /// dD/dH(0) against H(0): jump points
    Approach,
    /// dF̄/dH(0) against H(0): pull-off on the trace
    Load,
    /// dF̄/dD against D: pull-off on a stable branch (well scaled where H(0) barely moves)
    LoadPerApproach,
}

impl Slope {
    fn of(self, p: &CurvePoint) -> f64 {
        match self {
            Slope::Approach => p.slope_approach,
            Slope::Load => p.slope_load,
            Slope::LoadPerApproach => p.slope_load / p.slope_approach,
        }
    }

    /// The slope at a solved point.
    pub(crate) fn value(self, s: &Solved) -> f64 {
        self.of(&s.point)
    }

    /// The abscissa of the search.
    fn abscissa(self, s: &Solved) -> f64 {
        match self {
            Slope::LoadPerApproach => s.state.approach,
            _ => s.h0,
        }
    }

    fn control(self, x: f64) -> Control {
        match self {
            Slope::LoadPerApproach => Control::Approach(x),
            _ => Control::CentralGap(x),
        }
    }
}

/// Locate the zero of a slope between two solved points where it changes sign (Illinois;
/// bisection when Newton cannot reach the secant point; the better end if neither works).
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
        let (xa, xb) = (slope.abscissa(&a), slope.abscissa(&b));
        if (xa - xb).abs() < params.locate_tolerance * xa.abs().max(1.0) {
            break;
        }
        // the secant point, or the midpoint if Newton cannot reach it
        let secant = (xa * fb - xb * fa) / (fb - fa);
        let mut attempt = None;
        for x in [secant, 0.5 * (xa + xb)] {
            let from = if (x - xa).abs() < (x - xb).abs() {
                &a
            } else {
                &b
            };
            match solve_from(sys, from, slope.control(x), params, cost) {
                Ok(c) => {
                    attempt = Some(c);
                    break;
                }
                Err(HalfspaceError::NoConvergence { .. }) => continue,
                Err(e) => return Err(e),
            }
        }
        let Some(c) = attempt else { break };
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
    let (state, iterations) =
        sys.solve(Control::CentralGap(h_start), sys.rigid(h_start), params)?;
    cost.newton_iterations += iterations;
    cost.solves += 1;
    let mut prev = finish(sys, h_start, state)?;
    let mut points = vec![prev.point];
    let mut step = params.max_step;
    let mut jump_in: Option<Solved> = None;
    let mut jump_out: Option<Solved> = None;
    let mut pull_off: Option<Solved> = None;
    loop {
        let (next, used) = step_from(sys, &prev, -1.0, step, params, cost)?;
        step = used;
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
            if pull_off
                .as_ref()
                .is_none_or(|p| m.point.load < p.point.load)
            {
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
    let sys = System::new(
        problem,
        super::refinement::trace_grid(problem, params).build(),
    );
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
