//! Arc-length continuation (Riks, seed §4.3 and Fig 4.6): the equilibrium of an elastic solid
//! against the indenter, r(u, δ) = ∂Π/∂u = 0, is one curve in (u, δ) whatever drives the
//! indenter. Displacement control cannot pass its folds in δ (the S-curve's jump-in and
//! jump-out), so Newton needs contact damping to jump; arc-length follows the curve through
//! them, unstable branch included, and the jumps become limit points.
//!
//! Each step predicts along the unit tangent t of the curve (K_uu t_u + g t_δ = 0, with
//! g = ∂²Π/∂u∂δ, in the norm ‖(u, δ)‖² = Σu² + δ²) by the arc length Δl, then corrects on the
//! hyperplane through the prediction normal to t (Riks' linearised constraint). Each corrector
//! iteration solves the bordered system [K_uu g; t_uᵀ t_δ] by bordering: a = K_uu⁻¹(−r),
//! b = K_uu⁻¹g from one factorisation, Δδ = (−c − t_u·a)/(t_δ − t_u·b), Δu = a − bΔδ. Beyond a
//! fold in δ, K_uu at fixed δ is indefinite: the factorisation falls back from Cholesky to LU
//! ([`super::assembly::Assembler::factor`]). The next tangent is (−b, 1) of the last corrector
//! iteration, oriented along the step just taken (the secant), so the path does not turn
//! back on itself at a fold. Optionally ([`ArcLengthParams::contraction`]) the corrector keeps
//! the factorisation while the residual contracts fast enough (modified Newton). Step control: Δl ← Δl·√(N_target/N) after a step of N iterations
//! (at most ×[`ArcLengthParams::max_growth`]), halved on failure; no step advances the
//! controlled variable by more than the schedule's largest increment. A step counts as failed
//! too when it left the curve it started on ([`ArcLengthParams::max_correction`],
//! [`ArcLengthParams::max_turn`]): near a snapping surface several branches lie close together,
//! and a long step's hyperplane meets the wrong one.
//!
//! At each converged point the negative eigenvalues of K_uu are counted (the inertia of its
//! LDLᵀ factorisation; none where the corrector's last factorisation was a Cholesky), and each
//! step whose count changes is classified as a fold or a bifurcation ([`super::bifurcation`]),
//! with its critical mode, into [`IndentResult::critical_points`].
//!
//! The drive only decides where a schedule segment ends and what the drive column holds: δ
//! (displacement control), Δ = δ + P/K (a machine spring), or P (load control). A segment ends
//! where its controlled variable first reaches the target in the segment's direction (found by
//! a last correction with the constraint "control = target"). Under load control, a fold of
//! P on an unloading segment is the pull-off: the indenter separates there, as in the Newton
//! driver. Time has no meaning on an elastic curve: the time column advances by the control's
//! travel over the segment's rate.

use super::assembly::{Assembler, Evaluation, Solid};
use super::bifurcation::{classify, critical_mode, CriticalPoint};
use super::contact::Contact;
use super::element::Kinematics;
use super::indent::{
    snapshot, ArcLengthParams, IndentParams, IndentResult, Progress, Row, Segment,
};
use super::machine::Machine;
use super::newton::NewtonParams;
use super::FeError;
use crate::numerics::newton::{self, norm, NewtonError, NewtonProblem, Trial};

/// Why the arc-length corrector or the curve's trace stopped.
#[derive(Debug, thiserror::Error)]
pub enum ArcLengthError {
    /// the model could not be evaluated, solved or recorded
    #[error(transparent)]
    Fe(#[from] FeError),
    /// the corrector was asked for its point before evaluating one (a bug)
    #[error("arc-length corrector: no point")]
    NoPoint,
    /// the bordered system is singular: the constraint is tangent to the curve
    #[error("arc-length corrector: the constraint is tangent to the curve (t_δ − t_u·K⁻¹g = {schur:.3e})")]
    Tangent {
        /// the Schur complement t_δ − t_u·K⁻¹g
        schur: f64,
    },
    /// a step's corrector found a point off the curve the step started on
    #[error("arc-length step left the curve: corrector moved {correction:.2} step lengths, tangent turned {turn:.2} rad")]
    LeftCurve {
        /// the corrector's move over the step length
        correction: f64,
        /// the angle between the tangents at both ends, rad
        turn: f64,
    },
    /// the corrector reached its iteration limit
    #[error(
        "arc-length corrector: no convergence in {iterations} iterations (residuals {})",
        crate::numerics::newton::residual_history(residuals)
    )]
    NoConvergence {
        /// iterations done
        iterations: usize,
        /// residual history, nN
        residuals: Vec<f64>,
    },
    /// the corrector's Newton loop failed otherwise (its line search)
    #[error("{0}")]
    Newton(Box<NewtonError<ArcLengthError>>),
    /// the controlled variable does not change along the curve at a segment's start
    #[error("segment {segment} ({seg:?}): the controlled variable does not change along the curve at its start (no contact under load control?)")]
    Stationary {
        /// the segment's index
        segment: usize,
        /// the segment
        seg: Segment,
    },
    /// a segment took more steps than allowed without reaching its target
    #[error("segment {segment} ({seg:?}): {steps} arc-length steps without reaching the target")]
    TooManySteps {
        /// the segment's index
        segment: usize,
        /// the segment
        seg: Segment,
        /// the step limit
        steps: usize,
    },
    /// a step failed at the smallest length the cutbacks allow
    #[error("segment {segment} ({seg:?}): arc-length step {length:.3e} failed after {cutbacks} halvings at δ = {depth:.6} nm: {reason}")]
    Cutbacks {
        /// the segment's index
        segment: usize,
        /// the segment
        seg: Segment,
        /// the failed step's length
        length: f64,
        /// halvings done
        cutbacks: usize,
        /// the indenter depth where the step started, nm
        depth: f64,
        /// why the last step failed
        reason: Box<ArcLengthError>,
    },
    /// a signal asked the run to stop
    #[error("{}", crate::interrupt::REASON)]
    Interrupted,
}

/// The variable a schedule segment prescribes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// the indenter depth δ
    Depth,
    /// the drive Δ = δ + P/K behind a spring of stiffness K (nN/nm)
    Spring(f64),
    /// the load P
    Load,
}

impl Control {
    /// The controlled variable at depth `delta` and load `load`.
    pub fn value(&self, delta: f64, load: f64) -> f64 {
        match *self {
            Control::Depth => delta,
            Control::Spring(k) => delta + load / k,
            Control::Load => load,
        }
    }

    /// Its derivative along the direction `t` = (t_u, t_δ) at the evaluation `ev`
    /// (dP = g·t_u + k t_δ).
    pub fn rate(&self, t: &[f64], ev: &Evaluation) -> f64 {
        let n = t.len() - 1;
        let d_load = || dot(&ev.load_gradient, &t[..n]) + ev.load_stiffness * t[n];
        match *self {
            Control::Depth => t[n],
            Control::Spring(k) => t[n] + d_load() / k,
            Control::Load => d_load(),
        }
    }
}

/// The extra equation of a corrector.
enum Constraint<'c> {
    /// t·(y − y_p) = 0
    Plane { normal: &'c [f64], point: &'c [f64] },
    /// the controlled variable equals a target
    Target { control: Control, value: f64 },
}

impl Constraint<'_> {
    /// Value, gradient in u (None: zero) and in δ, and whether the value is a force (then it
    /// joins the residual norm; a linear constraint holds after the first iteration).
    fn linearise<'e>(
        &'e self,
        y: &[f64],
        ev: &'e Evaluation,
    ) -> (f64, Option<&'e [f64]>, f64, bool) {
        let n = y.len() - 1;
        match *self {
            Constraint::Plane { normal, point } => {
                let c = normal
                    .iter()
                    .zip(y.iter().zip(point))
                    .map(|(t, (a, b))| t * (a - b))
                    .sum();
                (c, Some(&normal[..n]), normal[n], false)
            }
            // in force units: P − K(Δ̂ − δ) and P − P̂, as the bordered Newton system has them
            Constraint::Target { control, value } => match control {
                Control::Depth => (y[n] - value, None, 1.0, false),
                Control::Spring(k) => (
                    ev.load - k * (value - y[n]),
                    Some(&ev.load_gradient),
                    ev.load_stiffness + k,
                    true,
                ),
                Control::Load => (
                    ev.load - value,
                    Some(&ev.load_gradient),
                    ev.load_stiffness,
                    true,
                ),
            },
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A converged point of the curve.
pub struct Point {
    /// (u, δ)
    pub y: Vec<f64>,
    /// the evaluation there (energy, load, ...)
    pub ev: Evaluation,
    /// K_uu⁻¹g from the last corrector iteration (the tangent is (−b, 1))
    pub b: Vec<f64>,
    /// corrector iterations that found it
    pub iterations: usize,
    /// negative eigenvalues of K_uu there (None: not counted, or a zero pivot)
    pub negative: Option<usize>,
}

impl Point {
    /// The unit tangent (−b, 1)/‖·‖, oriented so that its product with `along` is positive.
    pub fn tangent(&self, along: impl Fn(&[f64]) -> f64) -> Vec<f64> {
        let mut t: Vec<f64> = self.b.iter().map(|b| -b).collect();
        t.push(1.0);
        let scale = norm(&t);
        let sign = if along(&t) < 0.0 { -1.0 } else { 1.0 };
        t.iter_mut().for_each(|v| *v *= sign / scale);
        t
    }
}

/// The equilibrium curve of an elastic solid against the indenter.
pub struct Curve<'a> {
    /// pattern and factorisations
    pub asm: &'a mut Assembler,
    /// the solid (no history)
    pub solid: &'a Solid,
    /// the contact (no damping)
    pub contact: &'a Contact<'a>,
    /// smallest reference force of the convergence test, nN
    pub force_floor: f64,
    /// the corrector's tolerances and iteration limit
    pub newton: NewtonParams,
    /// [`ArcLengthParams::contraction`]
    pub contraction: f64,
}

impl Curve<'_> {
    fn evaluate(&mut self, y: &[f64], tangent: bool) -> Result<Evaluation, FeError> {
        let n = self.solid.dofs();
        self.asm.evaluate(
            self.solid,
            Some(self.contact),
            (&y[..n], &[]),
            0.0,
            y[n],
            tangent,
        )
    }

    /// Newton on r(u, δ) = 0 with one constraint, from `y`.
    fn correct(
        &mut self,
        mut y: Vec<f64>,
        constraint: &Constraint,
    ) -> Result<Point, ArcLengthError> {
        let newton = NewtonParams {
            max_backtracks: 0,
            ..self.newton
        };
        let mut corrector = Corrector {
            curve: self,
            constraint,
            at: None,
            norm: 0.0,
            reference: 0.0,
            previous: None,
            b: Vec::new(),
            factored: false,
            fresh: true,
        };
        match newton::solve(&mut corrector, &mut y, &newton) {
            Ok(info) => {
                let (ev, _) = corrector.at.ok_or(ArcLengthError::NoPoint)?;
                Ok(Point {
                    y,
                    ev,
                    b: corrector.b,
                    iterations: info.iterations,
                    negative: None,
                })
            }
            Err(NewtonError::NoConvergence {
                iterations,
                residuals,
            }) => Err(ArcLengthError::NoConvergence {
                iterations,
                residuals,
            }),
            Err(NewtonError::Problem(e)) => Err(e),
            Err(e) => Err(ArcLengthError::Newton(Box::new(e))),
        }
    }

    /// `next` while the segment goes on past it; else the point between `pt` and `next` where
    /// the control meets `target` (the segment ends within this step). Whether it ended.
    fn land(
        &mut self,
        pt: &Point,
        next: Point,
        control: Control,
        target: f64,
        dir: f64,
    ) -> Result<(Point, bool), ArcLengthError> {
        let n = self.solid.dofs();
        let v = control.value(pt.y[n], pt.ev.load);
        let v_next = control.value(next.y[n], next.ev.load);
        if !(dir * (v_next - target) >= 0.0) {
            return Ok((next, false));
        }
        // correct onto control = target from the secant's point there
        let f = (target - v) / (v_next - v);
        let guess: Vec<f64> =
            pt.y.iter()
                .zip(&next.y)
                .map(|(a, b)| a + f * (b - a))
                .collect();
        Ok((self.at(guess, control, target)?, true))
    }

    /// The equilibrium at fixed control from the guess `y` (a segment's end, or the start).
    pub fn at(
        &mut self,
        y: Vec<f64>,
        control: Control,
        value: f64,
    ) -> Result<Point, ArcLengthError> {
        self.correct(y, &Constraint::Target { control, value })
    }

    /// `pt`, just found by a corrector, with the negative eigenvalues of its K_uu counted:
    /// none if the corrector's last factorisation, a step of the order of the tolerance away,
    /// was a Cholesky; else by an LDLᵀ factorisation there (the unstable stretches).
    fn counted(&mut self, mut pt: Point) -> Result<Point, ArcLengthError> {
        pt.negative = if self.asm.holds_cholesky() {
            Some(0)
        } else {
            self.asm.negative_eigenvalues(&pt.ev.values)?
        };
        Ok(pt)
    }

    /// The critical point a step from `pt` to `next` passed, if any: its kind from the
    /// inertia and the turn of δ (`t_before`, `t_after` the tangents there), its mode from
    /// K_uu at `next`.
    fn critical(
        &mut self,
        pt: &Point,
        next: &Point,
        t_before: &[f64],
        t_after: &[f64],
        segment: usize,
    ) -> Result<Option<CriticalPoint>, ArcLengthError> {
        let n = self.solid.dofs();
        let fold = t_before[n] * t_after[n] < 0.0;
        let Some(kind) = classify(pt.negative, next.negative, fold) else {
            return Ok(None);
        };
        let (eigenvalue, mode) = critical_mode(self.asm, &next.ev.values, n)?;
        let g = &next.ev.load_gradient;
        let load_alignment = dot(&mode, g).abs() / norm(g).max(f64::MIN_POSITIVE);
        let node = (0..self.solid.nodes.len())
            .max_by(|&i, &j| {
                let m = |k: usize| mode[2 * k].hypot(mode[2 * k + 1]);
                m(i).total_cmp(&m(j))
            })
            .unwrap_or(0);
        let point = CriticalPoint {
            segment,
            kind,
            depth_nm: next.y[n],
            load_nN: next.ev.load,
            negative_before: pt.negative.unwrap_or(0),
            negative_after: next.negative.unwrap_or(0),
            eigenvalue,
            load_alignment,
            mode_radius_nm: self.solid.nodes[node][0],
        };
        Ok(Some(point))
    }

    /// One step of length `dl` from `from` along its unit tangent `t`.
    pub fn step(&mut self, from: &[f64], t: &[f64], dl: f64) -> Result<Point, ArcLengthError> {
        let predicted: Vec<f64> = from.iter().zip(t).map(|(y, t)| y + dl * t).collect();
        self.correct(
            predicted.clone(),
            &Constraint::Plane {
                normal: t,
                point: &predicted,
            },
        )
    }
}

/// `next`, a step of length `l` from `pt` along `t`, if it stayed on the curve it started on;
/// else [`ArcLengthError::LeftCurve`] (the step is cut back). A smooth curve turns little over
/// a step much shorter than its radius of curvature, and the corrector moves the prediction by
/// about κl²/2: a corrector that moved it by more than `max_correction`·l, or a tangent that
/// turned by more than `max_turn`, means the hyperplane met another branch of the curve (the
/// close branches of a snapping surface, ring by ring) rather than this one.
fn follows(
    pt: &Point,
    t: &[f64],
    next: Point,
    l: f64,
    params: &ArcLengthParams,
) -> Result<Point, ArcLengthError> {
    let correction = next
        .y
        .iter()
        .zip(pt.y.iter().zip(t))
        .map(|(y, (y0, t))| (y - y0 - l * t).powi(2))
        .sum::<f64>()
        .sqrt()
        / l;
    let secant: Vec<f64> = next.y.iter().zip(&pt.y).map(|(a, b)| a - b).collect();
    let turn = dot(t, &next.tangent(|u| dot(u, &secant)))
        .clamp(-1.0, 1.0)
        .acos();
    if correction > params.max_correction || turn > params.max_turn {
        return Err(ArcLengthError::LeftCurve { correction, turn });
    }
    Ok(next)
}

/// The corrector's plug-ins to the Newton loop: full steps on the bordered system of r(u, δ)
/// and the constraint, the norm of r (and of the constraint when it is a force), at least one
/// iteration, and the factorisation of K_uu kept while the residual contracts (modified
/// Newton, whose linear convergence the round-off stall test does not apply to).
struct Corrector<'c, 'a> {
    curve: &'c mut Curve<'a>,
    constraint: &'c Constraint<'c>,
    /// the evaluation at the iterate and its residual r
    at: Option<(Evaluation, Vec<f64>)>,
    /// the iterate's residual norm and reference force
    norm: f64,
    reference: f64,
    /// the previous iterate's residual norm
    previous: Option<f64>,
    /// K_uu⁻¹g of the last iteration
    b: Vec<f64>,
    /// true once this corrector has factorised (the assembler keeps the factorisation)
    factored: bool,
    /// true if the last correction used a factorisation of the tangent where it was taken
    fresh: bool,
}

impl NewtonProblem for Corrector<'_, '_> {
    type Error = ArcLengthError;

    fn residual(&mut self, y: &[f64]) -> Result<f64, ArcLengthError> {
        let ev = self.curve.evaluate(y, true)?;
        let r = self.curve.asm.residual(&ev.gradient);
        let (c, _, _, force) = self.constraint.linearise(y, &ev);
        let rn = (dot(&r, &r) + if force { c * c } else { 0.0 }).sqrt();
        self.previous = self.at.as_ref().map(|_| self.norm);
        self.reference = ev.force_reference(self.curve.force_floor);
        self.norm = rn;
        self.at = Some((ev, r));
        Ok(rn)
    }

    fn converged(&self, residuals: &[f64]) -> bool {
        let newton = &self.curve.newton;
        let done = if self.fresh {
            newton.converged(residuals, self.reference)
        } else {
            self.norm <= newton.tolerance(self.reference)
        };
        residuals.len() > 1 && done
    }

    fn direction(&mut self, y: &[f64]) -> Result<Vec<f64>, ArcLengthError> {
        let contracting = self
            .previous
            .is_some_and(|p| self.norm <= self.curve.contraction * p);
        self.fresh = !(contracting && self.factored);
        let (ev, r) = self.at.as_ref().ok_or(ArcLengthError::NoPoint)?;
        let asm = &mut self.curve.asm;
        if self.fresh {
            asm.factor(&ev.values)?;
            self.factored = true;
        }
        let minus_r: Vec<f64> = r.iter().map(|v| -v).collect();
        let a = asm.back_solve(&minus_r)?;
        let b = asm.back_solve(&ev.load_gradient)?;
        let (c, c_u, c_d, _) = self.constraint.linearise(y, ev);
        let (ca, cb) = c_u.map_or((0.0, 0.0), |cu| (dot(cu, &a), dot(cu, &b)));
        let schur = c_d - cb;
        // the bordered matrix is regular on a smooth curve (its tangent is unique); a
        // vanishing Schur complement means the constraint is tangent to the curve
        if !(schur.abs() > 1e-12 * (c_d.abs() + cb.abs())) {
            return Err(ArcLengthError::Tangent { schur });
        }
        let d_delta = (-c - ca) / schur;
        let mut dy: Vec<f64> = a.iter().zip(&b).map(|(a, b)| a - b * d_delta).collect();
        dy.push(d_delta);
        self.b = b;
        Ok(dy)
    }

    fn try_step(&mut self, y: &mut [f64], dy: &[f64], s: f64) -> Result<Trial, ArcLengthError> {
        for (yi, di) in y.iter_mut().zip(dy) {
            *yi += s * di;
        }
        Ok(Trial::Accepted)
    }
}

/// The schedule's controlled variable on segment `seg`, its target and the drive's rate
/// (None for a hold, which changes nothing on an elastic curve).
fn segment_control(seg: &Segment, machine: Machine) -> Option<(Control, f64, f64)> {
    let (to, rate) = match *seg {
        Segment::Load { to, rate }
        | Segment::Unload { to, rate }
        | Segment::Approach { to, rate } => (to, rate),
        Segment::Hold { .. } => return None,
    };
    let control = match machine {
        Machine::Spring { stiffness } => Control::Spring(stiffness),
        Machine::Load if !matches!(seg, Segment::Approach { .. }) => Control::Load,
        _ => Control::Depth,
    };
    Some((control, to, rate))
}

impl Curve<'_> {
    fn row(&self, pt: &Point, time: f64, segment: usize, machine: Machine, small: bool) -> Row {
        let n = self.solid.dofs();
        let delta = pt.y[n];
        let current: Vec<[f64; 2]> = self
            .solid
            .nodes
            .iter()
            .enumerate()
            .map(|(i, x)| [x[0] + pt.y[2 * i], x[1] + pt.y[2 * i + 1]])
            .collect();
        let profile = self
            .contact
            .profile(&current, &self.solid.nodes, delta, small);
        Row {
            time_s: time,
            depth_nm: delta,
            load_nN: pt.ev.load,
            contact_radius_nm: self.contact.contact_radius(&profile),
            iterations: pt.iterations,
            drive_nm: match machine {
                Machine::Spring { stiffness } => {
                    Control::Spring(stiffness).value(delta, pt.ev.load)
                }
                _ => delta,
            },
            gap_nm: profile.first().map_or(0.0, |q| q.gap),
            strain_energy_aJ: pt.ev.strain_energy,
            damping_dissipated_aJ: 0.0,
            segment,
        }
    }

    /// Count a converged point: its row, the run's totals and the progress report.
    fn record(
        &self,
        pt: &Point,
        time: f64,
        segment: usize,
        p: &IndentParams,
        result: &mut IndentResult,
        progress: &mut dyn FnMut(&Progress),
    ) -> Result<(), ArcLengthError> {
        result.stats.increments += 1;
        result.stats.newton_iterations += pt.iterations;
        let small = p.kinematics == Kinematics::Small;
        let row = self.row(pt, time, segment, p.machine, small);
        result.rows.push(row);
        progress(&Progress {
            segment,
            segments: p.schedule.len(),
            row,
            elements: self.solid.elements.len(),
            negative_eigenvalues: pt.negative,
        });
        if crate::interrupt::requested() {
            return Err(ArcLengthError::Interrupted);
        }
        Ok(())
    }

    /// Trace the schedule of `p` from the state `y` (u, δ = start): rows, snapshots and, under
    /// load control, the separation go into `result`. An error says why the curve stopped
    /// (the rows so far are kept in `result`).
    pub fn trace(
        &mut self,
        p: &IndentParams,
        y: Vec<f64>,
        result: &mut IndentResult,
        progress: &mut dyn FnMut(&Progress),
    ) -> Result<(), ArcLengthError> {
        let n = self.solid.dofs();
        let small = p.kinematics == Kinematics::Small;
        let start = self.at(y, Control::Depth, p.start)?;
        let mut pt = self.counted(start)?;
        result.rows[0] = self.row(&pt, 0.0, 0, p.machine, small);
        let mut time = 0.0;
        let mut dl: Option<f64> = None;
        for (si, seg) in p.schedule.iter().enumerate() {
            let Some((control, target, rate)) = segment_control(seg, p.machine) else {
                if let Segment::Hold { time: hold } = *seg {
                    time += hold;
                }
                continue;
            };
            let v0 = control.value(pt.y[n], pt.ev.load);
            let dir = (target - v0).signum();
            let dv_max = (target - v0).abs() / p.solver.increments.max(1) as f64;
            let mut t = pt.tangent(|t| dir * control.rate(t, &pt.ev));
            let mut length = dl.unwrap_or(dv_max / control.rate(&t, &pt.ev).abs());
            if !(length.is_finite() && length > 0.0) {
                return Err(ArcLengthError::Stationary {
                    segment: si,
                    seg: *seg,
                });
            }
            let mut advancing = true;
            let (mut cutbacks, mut steps) = (0, 0);
            loop {
                steps += 1;
                if steps > p.solver.arclength.max_steps {
                    return Err(ArcLengthError::TooManySteps {
                        segment: si,
                        seg: *seg,
                        steps: p.solver.arclength.max_steps,
                    });
                }
                // no step advances the control by more than the largest increment
                let speed = control.rate(&t, &pt.ev).abs();
                let l = if speed > 0.0 {
                    length.min(dv_max / speed)
                } else {
                    length
                };
                let stepped = self
                    .step(&pt.y, &t, l)
                    .and_then(|next| follows(&pt, &t, next, l, &p.solver.arclength));
                let next = match stepped {
                    Ok(next) => next,
                    Err(e) => {
                        cutbacks += 1;
                        result.stats.cutbacks += 1;
                        length = 0.5 * l;
                        if cutbacks > p.solver.max_cutbacks {
                            return Err(ArcLengthError::Cutbacks {
                                segment: si,
                                seg: *seg,
                                length: l,
                                cutbacks,
                                depth: pt.y[n],
                                reason: Box::new(e),
                            });
                        }
                        continue;
                    }
                };
                cutbacks = 0;
                let v = control.value(pt.y[n], pt.ev.load);
                let (next, reached) = self.land(&pt, next, control, target, dir)?;
                let next = self.counted(next)?;
                let v_end = control.value(next.y[n], next.ev.load);
                time += (v_end - v).abs() / rate;
                self.record(&next, time, si, p, result, progress)?;
                let secant: Vec<f64> = next.y.iter().zip(&pt.y).map(|(a, b)| a - b).collect();
                let t_next = next.tangent(|t| dot(t, &secant));
                let its = next.iterations.max(1) as f64;
                let target_its = p.solver.arclength.target_iterations as f64;
                length = l * (target_its / its).sqrt().min(p.solver.arclength.max_growth);
                let critical = self.critical(&pt, &next, &t, &t_next, si)?;
                t = t_next;
                pt = next;
                if let Some(point) = critical {
                    result.critical_points.push(point);
                }
                if reached {
                    break;
                }
                let now_advancing = dir * control.rate(&t, &pt.ev) > 0.0;
                if control == Control::Load && dir < 0.0 && advancing && !now_advancing {
                    // the load passed its minimum: under load control the indenter separates
                    let last = &result.rows[result.rows.len() - 2..];
                    result.separated_nN = Some(last[0].load_nN.min(last[1].load_nN));
                    result
                        .snapshots
                        .push(snapshot(si, time, &pt.y, self.solid, &[], None)?);
                    return Ok(());
                }
                advancing = now_advancing;
            }
            dl = Some(length);
            result
                .snapshots
                .push(snapshot(si, time, &pt.y, self.solid, &[], None)?);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point at `y` whose tangent is (−b, 1) normalised.
    fn point(y: Vec<f64>, b: f64) -> Point {
        Point {
            y,
            ev: Evaluation::default(),
            b: vec![b],
            iterations: 1,
            negative: None,
        }
    }

    #[test]
    fn a_step_that_jumps_to_another_branch_is_refused() {
        // one dof u and δ: the curve through the origin along δ (tangent (0, 1)), l = 0.1
        let params = ArcLengthParams::default();
        let (t, l) = ([0.0, 1.0], 0.1);
        let from = point(vec![0.0, 0.0], 0.0);
        // on the line, same tangent: kept
        assert!(follows(&from, &t, point(vec![0.0, 0.1], 0.0), l, &params).is_ok());
        // a small correction (0.2 l) and a small turn (0.1 rad): kept
        let bent = point(vec![0.02, 0.1], -(0.1f64).tan());
        assert!(follows(&from, &t, bent, l, &params).is_ok());
        // the corrector moved the point two step lengths: refused
        let far = follows(&from, &t, point(vec![0.2, 0.1], 0.0), l, &params);
        assert!(
            matches!(far, Err(ArcLengthError::LeftCurve { correction, .. }) if (correction - 2.0).abs() < 1e-12)
        );
        // on the prediction, but the tangent there turned by atan 5 = 1.37 rad: refused
        let turned = follows(&from, &t, point(vec![0.0, 0.1], -5.0), l, &params);
        assert!(
            matches!(turned, Err(ArcLengthError::LeftCurve { turn, .. }) if (turn - 5f64.atan()).abs() < 1e-12)
        );
    }

    #[test]
    fn control_rates_are_the_derivatives_of_the_control_values() {
        // P(δ, u) linearised: dP = g·du + k dδ; Δ = δ + P/K
        let ev = Evaluation {
            load: 3.0,
            load_gradient: vec![0.5, -2.0],
            load_stiffness: 4.0,
            ..Evaluation::default()
        };
        let t = [0.3, 0.1, -0.7];
        let d_load = 0.5 * 0.3 - 2.0 * 0.1 + 4.0 * -0.7;
        assert_eq!(Control::Depth.rate(&t, &ev), -0.7);
        assert!((Control::Load.rate(&t, &ev) - d_load).abs() < 1e-15);
        assert!((Control::Spring(2.0).rate(&t, &ev) - (-0.7 + d_load / 2.0)).abs() < 1e-15);
        assert_eq!(Control::Spring(2.0).value(1.0, 3.0), 2.5);
    }
}
