//! Tracing the load–approach S-curve by pseudo-arclength continuation, and locating its
//! special points: jump-in and jump-out (turning points of the approach D) and pull-off (the
//! load minimum).
//!
//! **Path.** The discrete equilibria form a curve in x = (H₀ … H_{N−1}, D) space. Each step
//! predicts along the unit tangent τ (the null vector of the equilibrium Jacobian, oriented like
//! the previous one) and corrects with Newton on the bordered system whose last equation is
//! τ·(x − x_prev) = Δs (Keller's pseudo-arclength; [`Control::Arc`]). The bordered Jacobian is
//! regular at turning points of D, of the load and of H(0) alike, so the tracer follows the
//! small folds a coarse grid adds when the contact edge crosses a cell (lattice trapping) as well
//! as the physical ones. The step Δs keeps the predicted change of every nodal gap below
//! `max_gap_change` (and of H(0) below `max_step`), grows after a success, is halved on failure,
//! and a corrector that lands farther than `max_gap_change` from its predictor is rejected
//! (it has jumped to another branch).
//!
//! **Special points**, in the order the retraction meets them (the trace runs from far away into
//! contact): jump-in on approach under displacement control is the first maximum of D; jump-out
//! on retraction under displacement control is the deepest minimum of D; pull-off under load control
//! is the deepest minimum of F̄ (on a converged grid each is unique; a coarse grid can add shallow
//! lattice folds of the load, which the deepest minimum ignores). Each is located by the Illinois
//! (modified regula falsi) method on dD/ds or dF̄/ds against the arclength measured along the
//! tangent of one end of the bracketing step.
//!
//! **Grid.** With a large μ the contact edge sweeps a radius many process zones wide; the grid is
//! then fine only over a window around the edge ([`super::trace_grid::trace_grid`]) and is
//! rebuilt around the edge (the state transferred and re-solved) when the edge nears an end of
//! the window.

use super::grid::{Grid, GridSpec};
use super::solve::{Control, State, System, Tangent};
use super::trace_grid::{start_gap, trace_grid};
use super::{Cost, HalfspaceError, HalfspaceParams, Problem, Scales, Traction};
use std::rc::Rc;
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
    /// dD/ds along the path (unit arclength in (gaps, D) space, oriented from far away into
    /// contact): positive where the approach grows, i.e. on branches stable under displacement
    /// control
    pub slope_approach: f64,
    /// dF̄/ds along the same path
    pub slope_load: f64,
}

/// The traced curve and its special points.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Curve {
    /// Tabor parameter μ
    pub tabor: f64,
    /// the points, in the order traced (from far away into contact)
    pub points: Vec<CurvePoint>,
    /// jump-to-contact on approach under displacement control (first maximum of D); `None`
    /// when the curve has no S (small μ)
    pub jump_in: Option<CurvePoint>,
    /// jump-out on retraction under displacement control (the deepest minimum of D)
    pub jump_out: Option<CurvePoint>,
    /// pull-off under load control (the deepest minimum of the load)
    pub pull_off: CurvePoint,
    /// nodes of the grid on which the pull-off was found
    pub nodes: usize,
    /// times the grid was rebuilt around the moving contact edge
    pub remeshes: usize,
    /// rigid estimate of the scaled load of the truncated tail at pull-off
    pub tail_load: f64,
    /// cost of the trace
    pub cost: Cost,
    /// factors to internal units (load nN, gap nm, radius nm)
    pub scales: Scales,
}

/// One converged point with its state and oriented unit tangent.
#[derive(Clone)]
pub(crate) struct Solved {
    pub(crate) state: State,
    pub(crate) tangent: Tangent,
    pub(crate) point: CurvePoint,
}

impl Solved {
    /// The state as one vector (gaps, then D).
    fn vector(&self) -> Vec<f64> {
        let mut v = self.state.gaps.clone();
        v.push(self.state.approach);
        v
    }

    /// The same point with the path oriented the other way.
    pub(crate) fn reversed(&self) -> Solved {
        let tangent = self.tangent.reversed();
        let point = CurvePoint {
            slope_approach: tangent.approach,
            slope_load: tangent.load,
            ..self.point
        };
        Solved {
            state: self.state.clone(),
            tangent,
            point,
        }
    }
}

/// Tangent (oriented along `orientation`) and curve point of a converged state.
pub(crate) fn finish<T: Traction>(
    sys: &System<'_, T>,
    state: State,
    orientation: &[f64],
) -> Result<Solved, HalfspaceError> {
    let tangent = sys.tangent(&state, orientation)?;
    let point = CurvePoint {
        central_gap: state.gaps[0],
        approach: state.approach,
        load: sys.load(&state),
        contact_radius: sys.contact_radius(&state),
        slope_approach: tangent.approach,
        slope_load: tangent.load,
    };
    Ok(Solved {
        state,
        tangent,
        point,
    })
}

/// Solve with `control` from `guess`; reject a corrector that moves any gap by more than
/// `max_gap_change` from the guess (it has jumped to another branch). The tangent is oriented
/// along `orientation`.
fn correct<T: Traction>(
    sys: &System<'_, T>,
    control: &Control,
    guess: State,
    orientation: &[f64],
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Solved, HalfspaceError> {
    let (state, iterations) = sys.solve(control, guess.clone(), params)?;
    cost.newton_iterations += iterations;
    cost.solves += 1;
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
            step: 0.0,
        });
    }
    finish(sys, state, orientation)
}

/// The point at arclength `length` along the tangent of `from` (pseudo-arclength corrector), from
/// `guess` (the tangent predictor if `None`).
pub(crate) fn arc_from<T: Traction>(
    sys: &System<'_, T>,
    from: &Solved,
    length: f64,
    guess: Option<State>,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Solved, HalfspaceError> {
    let t = &from.tangent;
    let guess = guess.unwrap_or_else(|| State {
        gaps: from
            .state
            .gaps
            .iter()
            .zip(&t.gaps)
            .map(|(g, t)| g + length * t)
            .collect(),
        approach: from.state.approach + length * t.approach,
    });
    let direction = t.vector();
    let control = Control::Arc {
        direction: direction.clone(),
        origin: from.vector(),
        length,
    };
    correct(sys, &control, guess, &direction, params, cost)
}

/// One continuation step from `from` along its tangent: the predicted change of every gap at
/// most `gap_step` and of H(0) at most `max_step`, halved on failure down to `min_step`.
/// Returns the new point and the gap step used.
pub(crate) fn step_from<T: Traction>(
    sys: &System<'_, T>,
    from: &Solved,
    gap_step: f64,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<(Solved, f64), HalfspaceError> {
    let t = &from.tangent;
    let largest = t.gaps.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let mut step = gap_step;
    loop {
        let length = (step / largest.max(f64::MIN_POSITIVE))
            .min(params.max_step / t.gaps[0].abs().max(f64::MIN_POSITIVE));
        match arc_from(sys, from, length, None, params, cost) {
            Ok(s) => return Ok((s, step)),
            Err(HalfspaceError::NoConvergence {
                residual,
                iterations,
                ..
            }) => {
                step *= 0.5;
                if step < params.min_step {
                    return Err(HalfspaceError::NoConvergence {
                        central_gap: from.state.gaps[0],
                        residual,
                        iterations,
                        step,
                    });
                }
            }
            Err(e) => return Err(e),
        }
    }
}

/// Which slope vanishes at the point sought.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Slope {
    /// dD/ds: jump points
    Approach,
    /// dF̄/ds: pull-off
    Load,
}

impl Slope {
    /// The slope at a solved point.
    pub(crate) fn value(self, s: &Solved) -> f64 {
        match self {
            Slope::Approach => s.point.slope_approach,
            Slope::Load => s.point.slope_load,
        }
    }
}

/// Locate the zero of a slope between two solved points of one step (`b` after `a` along the
/// tangent of `a`) where it changes sign: Illinois on the arclength σ = τ_a·(x − x_a), each
/// evaluation a pseudo-arclength solve from `a` with the chord as predictor; bisection when
/// Newton cannot reach the secant point; the better end if neither works.
pub(crate) fn locate<T: Traction>(
    sys: &System<'_, T>,
    a: &Solved,
    b: &Solved,
    slope: Slope,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Solved, HalfspaceError> {
    const MAX_SECANT_STEPS: usize = 60;
    let (xa, xb) = (a.vector(), b.vector());
    let chord = |sigma_b: f64, sigma: f64| {
        let f = sigma / sigma_b;
        let n = xa.len() - 1;
        State {
            gaps: (0..n).map(|i| xa[i] + f * (xb[i] - xa[i])).collect(),
            approach: xa[n] + f * (xb[n] - xa[n]),
        }
    };
    let ta = a.tangent.vector();
    let sigma_b: f64 = ta
        .iter()
        .zip(xb.iter().zip(&xa))
        .map(|(t, (b, a))| t * (b - a))
        .sum();
    let (mut lo, mut hi) = ((0.0, a.clone()), (sigma_b, b.clone()));
    let (mut flo, mut fhi) = (slope.value(&lo.1), slope.value(&hi.1));
    let mut side = 0i8;
    for _ in 0..MAX_SECANT_STEPS {
        if (hi.0 - lo.0).abs() < params.locate_tolerance * sigma_b.abs().max(1.0) {
            break;
        }
        let secant = (lo.0 * fhi - hi.0 * flo) / (fhi - flo);
        let mut attempt = None;
        for sigma in [secant, 0.5 * (lo.0 + hi.0)] {
            match arc_from(sys, a, sigma, Some(chord(sigma_b, sigma)), params, cost) {
                Ok(c) => {
                    attempt = Some((sigma, c));
                    break;
                }
                Err(HalfspaceError::NoConvergence { .. }) => continue,
                Err(e) => return Err(e),
            }
        }
        let Some(c) = attempt else { break };
        let fc = slope.value(&c.1);
        if fc == 0.0 {
            return Ok(c.1);
        }
        if (fc > 0.0) == (flo > 0.0) {
            lo = c;
            flo = fc;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        } else {
            hi = c;
            fhi = fc;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        }
    }
    Ok(if slope.value(&lo.1).abs() < slope.value(&hi.1).abs() {
        lo.1
    } else {
        hi.1
    })
}

/// A bracketing step of a special point: the two ends and the system they live on.
struct Bracket<'a, T: Traction> {
    a: Solved,
    b: Solved,
    sys: Rc<System<'a, T>>,
}

impl<'a, T: Traction> Bracket<'a, T> {
    fn locate(
        &self,
        slope: Slope,
        params: &HalfspaceParams,
        cost: &mut Cost,
    ) -> Result<(Solved, Rc<System<'a, T>>), HalfspaceError> {
        let s = locate(&self.sys, &self.a, &self.b, slope, params, cost)?;
        Ok((s, Rc::clone(&self.sys)))
    }
}

/// A traced curve with the states of its special points.
pub(crate) struct Trace<'a, T: Traction> {
    pub(crate) points: Vec<CurvePoint>,
    pub(crate) jump_in: Option<Solved>,
    pub(crate) jump_out: Option<Solved>,
    pub(crate) pull_off: Solved,
    /// the grid (and system) on which `pull_off` was solved
    pub(crate) pull_off_system: Rc<System<'a, T>>,
    /// times the grid was rebuilt around the moving contact edge
    pub(crate) remeshes: usize,
}

/// The edge may come this close (as a fraction of the window width `window_zones` ℓ, 4ℓ for the
/// default 16ℓ) to an end of the uniform zone before the grid is rebuilt around it: the gap opens
/// over a few ℓ ahead of the edge, and the pressure has its crack-tip peak a few ℓ behind it.
const REMESH_MARGIN: f64 = 0.25;

/// The band of radii whose nodes need the uniform zone: (innermost, outermost) node radius
/// with gap below [`super::solve::NEAR_GAP`] and k̄ > 0; (0, 0) if none. The inner end is where the gap opens
/// through the peak tension — the contact edge in the process-zone sense (the crack tip at
/// large μ), which lies outside [`System::contact_radius`] (where p changes sign) — and is where
/// the trace and pull-off grids centre their fine zone.
pub(crate) fn soft_band<T: Traction>(sys: &System<'_, T>, state: &State) -> (f64, f64) {
    let soft = sys.soft_nodes(state);
    match (soft.first(), soft.last()) {
        (Some(&i), Some(&j)) => (sys.grid.nodes[i], sys.grid.nodes[j]),
        _ => (0.0, 0.0),
    }
}

/// True if the contact edge `a` is still `margin` inside the uniform zone of `spec`, and the
/// reach `near` of small gaps is inside it.
fn edge_inside(spec: &GridSpec, a: f64, near: f64, margin: f64) -> bool {
    a <= spec.zone_hi - margin
        && (spec.zone_lo <= 0.0 || a >= spec.zone_lo + margin)
        && near <= spec.zone_hi
}

/// Move a converged point onto `sys` (a rebuilt grid): transfer the gaps and the tangent and
/// re-solve at the same D, or at the same H(0) where D moves slower than H(0) along the path.
pub(crate) fn remesh<T: Traction>(
    sys: &System<'_, T>,
    old: &Grid,
    from: &Solved,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Solved, HalfspaceError> {
    let guess = sys.transfer(old, &from.state);
    // the old tangent on the new nodes (constant beyond the old domain: a rigid shift there)
    let mut orientation: Vec<f64> = sys
        .grid
        .nodes
        .iter()
        .map(|&r| old.interpolate(&from.tangent.gaps, r))
        .collect();
    orientation.push(from.tangent.approach);
    // D first where it moves faster than H(0) along the path (on the contact branch), then H(0)
    let by_approach = Control::Approach(from.state.approach);
    let by_gap = Control::CentralGap(from.state.gaps[0]);
    let controls = if from.tangent.approach.abs() > from.tangent.gaps[0].abs() {
        [by_approach, by_gap]
    } else {
        [by_gap, by_approach]
    };
    let mut failure = None;
    for control in &controls {
        match correct(sys, control, guess.clone(), &orientation, params, cost) {
            Ok(s) => return Ok(s),
            Err(e @ HalfspaceError::NoConvergence { .. }) => failure = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(failure.expect("two controls tried"))
}

/// Trace the S-curve from beyond jump-in until the load passes its minimum and reaches
/// `end_load`. The grid is `window(a, r)` for the current contact radius a and reach r of small
/// gaps ([`soft_band`] plus the remesh margin), rebuilt whenever the edge nears an end of its
/// uniform zone or the small gaps reach beyond it (a `window` that ignores its arguments gives
/// one fixed grid).
pub(crate) fn trace_on<'a, T: Traction>(
    problem: &'a Problem<T>,
    window: &dyn Fn(f64, f64) -> GridSpec,
    params: &HalfspaceParams,
    cost: &mut Cost,
) -> Result<Trace<'a, T>, HalfspaceError> {
    let mu = problem.tabor();
    let mut spec = window(0.0, 0.0);
    let mut sys = Rc::new(System::new(problem, spec.build()));
    cost.max_nodes = cost.max_nodes.max(sys.len());
    let h_start = start_gap(mu, params);
    let (state, iterations) =
        sys.solve(&Control::CentralGap(h_start), sys.rigid(h_start), params)?;
    cost.newton_iterations += iterations;
    cost.solves += 1;
    // the trace starts towards smaller central gaps
    let inwards: Vec<f64> = (0..=sys.len())
        .map(|i| -f64::from(u8::from(i == 0)))
        .collect();
    let mut prev = finish(&sys, state, &inwards)?;
    let mut points = vec![prev.point];
    let mut step = params.max_gap_change;
    let mut jump_in: Option<(Solved, Rc<System<'a, T>>)> = None;
    let mut jump_out: Option<Bracket<'a, T>> = None;
    let mut pull_off: Option<Bracket<'a, T>> = None;
    let mut remeshes = 0;
    loop {
        let (a, near) = soft_band(&sys, &prev.state);
        let margin =
            REMESH_MARGIN * params.window_zones * spec.fine_spacing * params.cells_per_zone;
        if !edge_inside(&spec, a, near, margin) {
            let new_spec = window(a, near + margin);
            if new_spec != spec {
                let new_sys = Rc::new(System::new(problem, new_spec.build()));
                cost.max_nodes = cost.max_nodes.max(new_sys.len());
                prev = remesh(&new_sys, &sys.grid, &prev, params, cost)?;
                (spec, sys) = (new_spec, new_sys);
                remeshes += 1;
            }
        }
        let (next, used) = step_from(&sys, &prev, step, params, cost)?;
        step = used;
        let bracket = || Bracket {
            a: prev.clone(),
            b: next.clone(),
            sys: Rc::clone(&sys),
        };
        let (sa0, sa1) = (prev.point.slope_approach, next.point.slope_approach);
        if sa0 > 0.0 && sa1 <= 0.0 && jump_in.is_none() {
            jump_in = Some(bracket().locate(Slope::Approach, params, cost)?);
        } else if sa0 < 0.0
            && sa1 >= 0.0
            && jump_in.is_some()
            && jump_out
                .as_ref()
                .is_none_or(|b| next.point.approach < b.b.point.approach)
        {
            // the deepest minimum of D, for the same reason as the load below
            jump_out = Some(bracket());
        }
        // the deepest load minimum: a coarse cell can add a shallow lattice fold of the load
        // beyond it (10-4 at μ = 10: −1.44 after −1.503 on the trace grid), which the last
        // minimum would pick
        let deeper = pull_off
            .as_ref()
            .is_none_or(|b| next.point.load < b.b.point.load);
        if prev.point.slope_load < 0.0 && next.point.slope_load >= 0.0 && deeper {
            pull_off = Some(bracket());
        }
        points.push(next.point);
        prev = next;
        if pull_off.is_some() && prev.point.load >= params.end_load {
            break;
        }
        if prev.point.central_gap <= params.min_gap {
            break;
        }
        step = (step * 1.5).min(params.max_gap_change);
    }
    let (pull_off, pull_off_system) = pull_off
        .ok_or(HalfspaceError::NoPullOff {
            start: h_start,
            end: prev.point.central_gap,
        })?
        .locate(Slope::Load, params, cost)?;
    let jump_out = match jump_out {
        Some(b) => Some(b.locate(Slope::Approach, params, cost)?.0),
        None => None,
    };
    Ok(Trace {
        points,
        jump_in: jump_in.map(|(s, _)| s),
        jump_out,
        pull_off,
        pull_off_system,
        remeshes,
    })
}

/// Trace the whole load–approach curve of `problem` on the default trace grid, with its jump
/// points and pull-off (on that grid; [`super::pull_off`] adds the refinement study).
pub fn trace_curve<T: Traction>(
    problem: &Problem<T>,
    params: &HalfspaceParams,
) -> Result<Curve, HalfspaceError> {
    problem.check_validated_range()?;
    let start = Instant::now();
    let mut cost = Cost::default();
    let window = |a: f64, near: f64| trace_grid(problem, params, a, near);
    let trace = trace_on(problem, &window, params, &mut cost)?;
    cost.wall_time = start.elapsed().as_secs_f64();
    let sys = &trace.pull_off_system;
    Ok(Curve {
        tabor: problem.tabor(),
        points: trace.points,
        jump_in: trace.jump_in.map(|s| s.point),
        jump_out: trace.jump_out.map(|s| s.point),
        tail_load: sys.tail_load(&trace.pull_off.state),
        pull_off: trace.pull_off.point,
        nodes: sys.len(),
        remeshes: trace.remeshes,
        cost,
        scales: problem.scales(),
    })
}
