//! The march of an indentation along its schedule (seed chapter 4): each segment is crossed in
//! increments of the controlled variable (depth, drive or load) and of time, each solved by
//! Newton ([`super::newton`]) from a predictor that extrapolates the last increment. A failed
//! increment is halved and retried; a quick one lets the increment grow back. On an unloading
//! segment under load control, an increment that fails at the smallest size marks the pull-off:
//! the indenter separates there. With an adaptive mesh ([`MeshParams::adaptive`]) an increment
//! whose contact edge leaves the band of fine elements is solved again on a mesh whose band
//! covers it, the state carried over by [`transfer`]; a band wider than the converged state
//! needs narrows to it. Contact damping, if given, is integrated over each step (except on
//! load-controlled segments) and its dissipation is reported per row against the strain
//! energy. The Riks alternative to this march is [`super::arclength`].
//!
//! [`MeshParams::adaptive`]: super::indent::MeshParams::adaptive

use super::arclength::Curve;
use super::assembly::{Assembler, Evaluation, Solid};
use super::contact::{Anchor, Contact, Damping, ProfilePoint, Stick, SurfaceArea, SurfaceLaw};
use super::element::Kinematics;
use super::indent::{
    band_span, build_mesh, new_solid, resolve, snapshot, Adaptation, IndentParams, IndentResult,
    Method, Progress, Resolved, Row, RunStats, Segment, Span, Tangential, TierGaps, EDGE_SAFE,
    MAX_REMESHES_PER_INCREMENT, MAX_REMESHES_PER_SNAP, SNAP_CHUNK,
};
use super::indenter::IndenterError;
use super::machine::{Drive, Driven, Machine};
use super::mesh::{self, EdgeZone, Mesh};
use super::newton::{self, NewtonParams, NewtonSystem};
use super::snap::Snap;
use super::transfer;
use super::FeError;
use crate::numerics::quadrature::gauss_legendre_unit;
use std::time::Instant;

/// Newton iterations a snap's descent may take: it walks from the last equilibrium, through
/// the unstable region, to the next minimum (tens to hundreds of iterations), where an
/// increment's Newton takes a few.
const SNAP_ITERATIONS: usize = 1000;

/// Run the indentation. A failure midway returns [`FeError::Stopped`] with what was finished;
/// so does an interrupt ([`crate::interrupt::requested`], polled after every converged
/// increment).
pub fn run_indent(
    p: &IndentParams,
    progress: &mut dyn FnMut(&Progress),
) -> Result<IndentResult, FeError> {
    let t_start = Instant::now();
    let resolved = resolve(p)?;
    let mesh = build_mesh(p, &resolved)?;
    let mesh_s = t_start.elapsed().as_secs_f64();
    let penalty = resolved.penalty;
    let law: &dyn SurfaceLaw = match &p.adhesion {
        Some(a) => &a.law,
        None => &penalty,
    };
    let mut run = March::new(p, resolved, mesh, mesh_s, law)?;
    let stop = match p.solver.method {
        Method::Riks => run.trace(progress),
        Method::Newton => run.schedule(progress)?,
    };
    run.finish(stop, t_start.elapsed().as_secs_f64())
}

/// A run under way: the mesh, the solid and its state, the machine's state and the result so
/// far.
pub(super) struct March<'a> {
    p: &'a IndentParams,
    solid: Solid,
    asm: Assembler,
    /// the surface (for profiles and the pattern); each step adds its damping to a copy
    contact: Contact<'a>,
    /// smallest reference force of the residual test, nN
    force_floor: f64,
    /// the band of the current adaptive mesh (None: a fixed mesh)
    zone: Option<EdgeZone>,
    /// the band the next increment is to be solved with, when it differs from `zone`
    pending: Option<EdgeZone>,
    /// a snap that ended outside the band: its end state (carried to the pending mesh, where
    /// the snap goes on from it), the energy Π where it started and its iterations so far
    snap_from: Option<(Vec<f64>, f64, usize)>,
    /// the radii the band must cover at the last converged state
    span: Span,
    /// the gaps the band's tiers end at, of the run's law
    tiers: TierGaps,
    /// the unknowns of the last two converged increments (nodal displacements, then δ)
    u: Vec<f64>,
    u_prev: Vec<f64>,
    /// Prony history of the last converged increment
    history: Vec<f64>,
    /// gaps at the surface quadrature points of the last converged state (damping's gₙ)
    gaps: Vec<f64>,
    /// the sticking indenter's anchors at the surface quadrature points (None: not sticking)
    anchors: Option<Vec<Option<Anchor>>>,
    /// change of the controlled variable over the last converged increment (0: none to
    /// extrapolate)
    last_dv: f64,
    time: f64,
    /// the machine's drive and controlled load at the last converged state
    drive: f64,
    load: f64,
    /// energy dissipated by contact damping, aJ
    dissipated: f64,
    pub(super) result: IndentResult,
}

/// How a schedule segment ended.
enum SegmentEnd {
    /// at its target
    Done,
    /// under load control, unloading past the last equilibrium: the indenter separated
    Separated,
    /// the run cannot go on (the reason)
    Stopped(String),
}

/// One increment to solve.
struct Step {
    /// what it prescribes
    mode: Drive,
    /// change of the controlled variable
    dv: f64,
    /// time step, s
    dt: f64,
    /// the load controls (no contact damping)
    by_load: bool,
}

/// What solving an increment gave.
enum Increment {
    /// converged at `x`
    Converged {
        x: Vec<f64>,
        iterations: usize,
        ev: Evaluation,
        /// a snap: the energy it released, aJ
        released: Option<f64>,
    },
    /// converged, with the contact edge outside the band: to be solved again on the pending
    /// mesh
    Remesh,
    /// no equilibrium (why)
    Failed(StepFailure),
}

/// Why an increment found no equilibrium.
#[derive(Debug, thiserror::Error)]
enum StepFailure {
    /// Newton did not converge
    #[error(transparent)]
    Newton(#[from] newton::NewtonError),
    /// Newton converged to a depth the indenter does not represent
    #[error(transparent)]
    Depth(#[from] IndenterError),
}

impl<'a> March<'a> {
    /// The initial state of a run on `mesh`: the indenter at `p.start`, nothing deformed.
    pub(super) fn new(
        p: &'a IndentParams,
        resolved: Resolved,
        mesh: Mesh,
        mesh_s: f64,
        law: &'a dyn SurfaceLaw,
    ) -> Result<Self, FeError> {
        let solid = new_solid(p, &mesh)?;
        let contact = Contact {
            segments: Contact::segments_of(&mesh),
            indenter: p.indenter,
            law,
            quadrature: gauss_legendre_unit(p.contact.quadrature_points),
            damping: None,
            stick: None,
            // the law's atoms conserved with adhesion, a pressure on the current surface for
            // the penalty (see contact.rs)
            area: p.adhesion.as_ref().map_or(SurfaceArea::Current, |a| a.area),
        };
        let mut asm = Assembler::new(&solid, Some(&contact))?;
        let a = resolved.expected_contact_radius_nm;
        // the forces in play are at least the elastic scale at the contact and, with adhesion,
        // the DMT pull-off 2πγR (the largest adhesive load): the residual tolerance is
        // relative to them
        let adhesive_force = p.adhesion.as_ref().map_or(0.0, |ad| {
            2.0 * std::f64::consts::PI * ad.law.gamma() * p.indenter.radius()
        });
        let force_floor = (1e-6 * resolved.reduced_modulus_GPa * a * a).max(adhesive_force);
        let ndof = solid.dofs();
        let mut u = vec![0.0; ndof + 1];
        u[ndof] = p.start;
        let profile0 = profile(&contact, &solid, &u, p.kinematics);
        let gaps: Vec<f64> = profile0.iter().map(|q| q.gap).collect();
        let tiers = TierGaps::of(law);
        let span = band_span(&contact, &tiers, &profile0);
        let history = vec![0.0; solid.history_len() * solid.elements.len()];
        let ev0 = asm.evaluate(
            &solid,
            Some(&contact),
            (&u[..ndof], &history),
            0.0,
            p.start,
            false,
        )?;
        let zone = resolved.edge_zone;
        let result = IndentResult {
            params: p.clone(),
            resolved,
            mesh_report: mesh.report(),
            adaptation: zone
                .iter()
                .map(|z| Adaptation {
                    increment: 0,
                    time_s: 0.0,
                    inner_nm: z.inner,
                    outer_nm: z.outer,
                    tail_nm: z.tail,
                    elements: mesh.triangles.len(),
                })
                .collect(),
            critical_points: Vec::new(),
            snaps: Vec::new(),
            mesh,
            rows: vec![Row {
                time_s: 0.0,
                depth_nm: p.start,
                load_nN: ev0.load,
                contact_radius_nm: 0.0,
                iterations: 0,
                drive_nm: p.start,
                gap_nm: gaps.first().copied().unwrap_or(0.0),
                strain_energy_aJ: 0.0,
                damping_dissipated_aJ: 0.0,
                segment: 0,
            }],
            snapshots: Vec::new(),
            stats: RunStats {
                mesh_s,
                ..RunStats::default()
            },
            failure: None,
            separated_nN: None,
        };
        Ok(March {
            p,
            solid,
            asm,
            contact,
            force_floor,
            zone,
            pending: None,
            snap_from: None,
            span,
            tiers,
            u_prev: u.clone(),
            u,
            history,
            anchors: (p.contact.tangential == Tangential::Stick).then(|| vec![None; gaps.len()]),
            gaps,
            last_dv: 0.0,
            time: 0.0,
            drive: p.start,
            load: p.machine.applied_load(ev0.load, p.start),
            dissipated: 0.0,
            result,
        })
    }

    /// Follow the equilibrium path by arc length instead ([`Curve::trace`]); the reason it
    /// stopped early, if it did.
    pub(super) fn trace(&mut self, progress: &mut dyn FnMut(&Progress)) -> Option<String> {
        let mut curve = Curve {
            asm: &mut self.asm,
            solid: &self.solid,
            contact: &self.contact,
            force_floor: self.force_floor,
            newton: self.p.solver.newton,
            contraction: self.p.solver.arclength.contraction,
        };
        curve
            .trace(self.p, self.u.clone(), &mut self.result, progress)
            .err()
            .map(|e| e.to_string())
    }

    /// March through the schedule, a snapshot at the end of each segment; the reason the run
    /// stopped early, if it did.
    pub(super) fn schedule(
        &mut self,
        progress: &mut dyn FnMut(&Progress),
    ) -> Result<Option<String>, FeError> {
        for (si, seg) in self.p.schedule.iter().enumerate() {
            let end = self.segment(si, seg, progress)?;
            if let SegmentEnd::Stopped(why) = end {
                return Ok(Some(why));
            }
            let own = self.zone.map(|_| &self.result.mesh);
            let snap = snapshot(si, self.time, &self.u, &self.solid, &self.history, own)?;
            self.result.snapshots.push(snap);
            if let SegmentEnd::Separated = end {
                break;
            }
        }
        Ok(None)
    }

    /// The result, with what the run cost; [`FeError::Stopped`] with it if it stopped early.
    pub(super) fn finish(
        mut self,
        stop: Option<String>,
        wall_s: f64,
    ) -> Result<IndentResult, FeError> {
        self.result.stats.assembly = self.asm.stats;
        self.result.stats.wall_s = wall_s;
        match stop {
            None => Ok(self.result),
            Some(why) => {
                let why = why + &self.localisation_note();
                self.result.failure = Some(why);
                Err(FeError::Stopped(Box::new(self.result)))
            }
        }
    }

    /// Why a stopped march may have stopped for good: a material state at the last converged
    /// increment that is not strongly elliptic ([`crate::continuum::material::ellipticity`]).
    /// Empty when every element is elliptic (or the check itself fails).
    fn localisation_note(&self) -> String {
        let n = self.solid.dofs();
        match self.solid.least_elliptic(&self.u[..n], &self.history) {
            Ok(Some(l)) if l.minimum.eigenvalue <= 0.0 => format!(
                "; at the last converged increment the material is not elliptic at element {} \
                 (reference centroid r = {:.1} nm, z = {:.1} nm; least acoustic eigenvalue \
                 {:.3e} GPa, band normal {:.0}° from the axis): a band can localise there and a \
                 local continuum has no length to set its width, so no mesh-independent answer \
                 exists beyond this depth with this material",
                l.element, l.centroid[0], l.centroid[1], l.minimum.eigenvalue, l.minimum.normal_deg
            ),
            _ => String::new(),
        }
    }

    /// Cross segment `si` of the schedule.
    fn segment(
        &mut self,
        si: usize,
        seg: &Segment,
        progress: &mut dyn FnMut(&Progress),
    ) -> Result<SegmentEnd, FeError> {
        let p = self.p;
        let (v0, target, duration, by_load) = segment_span(seg, p.machine, self.drive, self.load);
        let base = 1.0 / p.solver.increments.max(1) as f64;
        let t0 = self.time;
        let mut value = v0;
        let (mut done, mut step, mut cutbacks) = (0.0f64, base, 0usize);
        let mut remeshes = 0usize;
        // the increment that failed at its smallest size is solved again by a snap
        let mut snapping = false;
        while done < 1.0 - 1e-12 {
            if let Some(z) = self.pending.take() {
                self.remesh(z)?;
            }
            let s = step.min(1.0 - done);
            let new_value = v0 + (target - v0) * (done + s);
            let inc = Step {
                mode: p.machine.drive(by_load, new_value),
                dv: new_value - value,
                dt: duration * s,
                by_load,
            };
            let most = match snapping {
                true => MAX_REMESHES_PER_SNAP,
                false => MAX_REMESHES_PER_INCREMENT,
            };
            match self.increment(&inc, remeshes < most, snapping)? {
                Increment::Remesh => remeshes += 1,
                Increment::Converged {
                    x,
                    iterations,
                    ev,
                    released,
                } => {
                    value = new_value;
                    done += s;
                    self.time = t0 + duration * done;
                    let before = self.result.rows.last().copied();
                    self.commit(si, &inc, x, iterations, &ev, progress)?;
                    remeshes = 0;
                    if let (Some(released), Some(b), Some(a)) =
                        (released, before, self.result.rows.last())
                    {
                        self.result.snaps.push(Snap {
                            segment: si,
                            time_s: self.time,
                            drive_nm: a.drive_nm,
                            depth_before_nm: b.depth_nm,
                            depth_after_nm: a.depth_nm,
                            load_before_nN: b.load_nN,
                            load_after_nN: a.load_nN,
                            energy_released_aJ: released,
                            iterations,
                        });
                        // the snap's change is no trend to extrapolate
                        self.last_dv = 0.0;
                        snapping = false;
                    }
                    if crate::interrupt::requested() {
                        return Ok(SegmentEnd::Stopped(crate::interrupt::REASON.into()));
                    }
                    if iterations <= p.solver.quick_iterations {
                        step = (step * p.solver.growth).min(base);
                    }
                }
                Increment::Failed(e) if snapping => {
                    return Ok(SegmentEnd::Stopped(format!(
                        "segment {si} ({seg:?}): the increment to {new_value:.6} {} failed at the smallest size, and the snap there (a descent at the held drive, src/continuum/snap.rs) found no minimum: {e}",
                        if by_load { "nN" } else { "nm" }
                    )));
                }
                Increment::Failed(e) => {
                    cutbacks += 1;
                    self.result.stats.cutbacks += 1;
                    step *= 0.5;
                    self.last_dv = 0.0;
                    // `max_cutbacks` bounds how small an increment may get: base / 2^max. A
                    // count of the halvings over the whole segment would fail a long segment
                    // with a few recovered cutbacks (a contact edge sweeping over surface
                    // nodes) at an increment halved once (hyperfoam_indent.toml,
                    // docs/validation-continuum.md); a count reset at each converged increment
                    // would let a load-controlled retraction creep towards the pull-off fold
                    // in ever smaller converged steps without end
                    let exhausted = step < base * 0.5f64.powi(p.solver.max_cutbacks as i32);
                    if exhausted && by_load && target < v0 {
                        // the specimen's force at the last equilibrium (= the controlled
                        // load P̂ without transducer springs)
                        self.result.separated_nN = self.result.rows.last().map(|r| r.load_nN);
                        return Ok(SegmentEnd::Separated);
                    }
                    // a material that lost ellipticity localises in a band as thin as the
                    // mesh allows: no snap has a mesh-independent end there, the run stops
                    // and names the element
                    if exhausted && p.solver.snap && self.localisation_note().is_empty() {
                        // hold the drive (or the load) of the increment that failed and
                        // descend from the last equilibrium to the next minimum
                        snapping = true;
                        step = s;
                    } else if exhausted {
                        return Ok(SegmentEnd::Stopped(format!(
                            "segment {si} ({seg:?}): increment to {new_value:.6} {} at t = {:.6} s failed at the smallest increment (1/2^{} of the base; {cutbacks} halvings in this segment): {e}",
                            if by_load { "nN" } else { "nm" },
                            t0 + duration * (done + s),
                            p.solver.max_cutbacks
                        )));
                    }
                }
            }
        }
        Ok(SegmentEnd::Done)
    }

    /// Solve one increment from the predictor. With an adaptive mesh (and `may_remesh`), a
    /// converged state whose contact edge left the band is not taken: the band that spans it
    /// and the last converged one (after a snap, it alone) is made pending.
    fn increment(
        &mut self,
        inc: &Step,
        may_remesh: bool,
        snap: bool,
    ) -> Result<Increment, FeError> {
        let p = self.p;
        let ndof = self.solid.dofs();
        // predictor: extrapolate the last increment's change of (u, δ); a snap descends from
        // the last equilibrium, or goes on from where it ended on the last mesh
        let resumed = self.snap_from.take().filter(|_| snap);
        let mut x = resumed
            .as_ref()
            .map_or_else(|| self.u.clone(), |(x, ..)| x.clone());
        if !snap && self.last_dv != 0.0 && inc.dv * self.last_dv > 0.0 {
            let ratio = inc.dv / self.last_dv;
            for ((xi, ui), pi) in x.iter_mut().zip(&self.u).zip(&self.u_prev) {
                *xi += ratio * (ui - pi);
            }
        }
        if let Drive::Depth(d) = inc.mode {
            x[ndof] = d;
        }
        let damping_law = p.adhesion.as_ref().and_then(|a| a.damping);
        let step_contact = Contact {
            segments: self.contact.segments.clone(),
            quadrature: self.contact.quadrature.clone(),
            // not on load-controlled segments: a damped step can hold a load beyond the static
            // limit (the viscous force making up the difference), so the separation load would
            // depend on c₀
            damping: damping_law.filter(|_| !inc.by_load).map(|law| Damping {
                law,
                previous: &self.gaps,
                dt: inc.dt,
            }),
            stick: self.anchors.as_deref().map(|anchors| Stick {
                stiffness: self.result.resolved.penalty.stiffness,
                anchors,
            }),
            ..self.contact
        };
        let mut sys = Driven {
            asm: &mut self.asm,
            solid: &self.solid,
            contact: Some(&step_contact),
            history: &self.history,
            dt: inc.dt,
            drive: inc.mode,
            force_floor: self.force_floor,
        };
        let solved = if snap {
            // a carried snap state the new mesh cannot evaluate (an element the interpolation
            // inverted) restarts the snap from the last equilibrium on it
            if resumed.is_some() && sys.evaluate(&x, false).is_err() {
                x.copy_from_slice(&self.u);
            }
            let start = match (&resumed, sys.evaluate(&x, false)) {
                (Some((_, start, _)), _) => *start,
                (None, Ok(pt)) => pt.energy,
                (None, Err(e)) => {
                    return Ok(Increment::Failed(newton::NewtonError::Problem(e).into()))
                }
            };
            // on an adaptive mesh the descent looks every SNAP_CHUNK iterations whether its
            // state has left the band, and goes on from there on a mesh that follows it
            let follow = self.zone.filter(|_| may_remesh);
            let mut done = resumed.as_ref().map_or(0, |r| r.2);
            let descended = loop {
                let params = NewtonParams {
                    max_iterations: match follow {
                        Some(_) => SNAP_CHUNK,
                        None => SNAP_ITERATIONS,
                    },
                    ..p.solver.newton
                };
                match (follow, newton::descend(&mut sys, &mut x, &params)) {
                    (
                        Some(z),
                        Err(newton::NewtonError::NoConvergence {
                            iterations,
                            residuals,
                        }),
                    ) => {
                        done += iterations;
                        if done >= SNAP_ITERATIONS {
                            // the whole snap's count, the last chunk's residuals
                            break Err(newton::NewtonError::NoConvergence {
                                iterations: done,
                                residuals,
                            });
                        }
                        let now = profile(&self.contact, &self.solid, &x, p.kinematics);
                        let span = band_span(&self.contact, &self.tiers, &now);
                        if span.leaves(&z, EDGE_SAFE * z.half_width) {
                            self.pending = Some(span.zone(&z));
                            self.snap_from = Some((x, start, done));
                            return Ok(Increment::Remesh);
                        }
                    }
                    (_, other) => break other,
                }
            };
            descended.and_then(|mut info| {
                info.iterations += done;
                let end = sys
                    .evaluate(&x, false)
                    .map_err(newton::NewtonError::Problem)?;
                Ok((info, Some(start - end.energy)))
            })
        } else {
            newton::solve(&mut sys, &mut x, &p.solver.newton).map(|info| (info, None))
        };
        let solved = solved
            .map_err(StepFailure::from)
            .and_then(|info| Ok(p.indenter.check_depth(x[ndof]).map(|()| info)?));
        let (info, released) = match solved {
            Ok(info) => info,
            Err(e) => return Ok(Increment::Failed(e)),
        };
        if let Some(z) = &self.zone {
            let trial = profile(&self.contact, &self.solid, &x, p.kinematics);
            let span = band_span(&self.contact, &self.tiers, &trial);
            if span.leaves(z, EDGE_SAFE * z.half_width) && may_remesh {
                // a continuous increment passes the edges between its start and its end (and
                // the damping reads its start): the band spans both, and the increment is
                // solved again from its start; a snap only needs its end, and goes on from it
                let needed = match released {
                    Some(released) => {
                        let end = sys.evaluate(&x, false)?.energy;
                        self.snap_from = Some((x, end + released, info.iterations));
                        span
                    }
                    None => span.union(&self.span),
                };
                self.pending = Some(needed.zone(z));
                return Ok(Increment::Remesh);
            }
        }
        let ev = sys.evaluation(&x, false)?;
        Ok(Increment::Converged {
            x,
            iterations: info.iterations,
            ev,
            released,
        })
    }

    /// Take the converged state `x` of increment `inc` (at `self.time`): commit the history,
    /// move the machine, record the row, and narrow the band if the state needs less of it.
    fn commit(
        &mut self,
        si: usize,
        inc: &Step,
        x: Vec<f64>,
        iterations: usize,
        ev: &Evaluation,
        progress: &mut dyn FnMut(&Progress),
    ) -> Result<(), FeError> {
        let p = self.p;
        let ndof = self.solid.dofs();
        let depth = x[ndof];
        self.solid.commit(&x[..ndof], &mut self.history, inc.dt)?;
        self.u_prev = std::mem::replace(&mut self.u, x);
        self.last_dv = inc.dv;
        self.dissipated += 2.0 * ev.damping_energy;
        let profile = profile(&self.contact, &self.solid, &self.u, p.kinematics);
        self.gaps.clear();
        self.gaps.extend(profile.iter().map(|q| q.gap));
        if let Some(previous) = &self.anchors {
            let now = current(&self.solid, &self.u);
            let small = p.kinematics == Kinematics::Small;
            let renewed =
                self.contact
                    .renew_anchors(&now, &self.solid.nodes, depth, small, previous);
            self.anchors = Some(renewed);
        }
        self.drive = inc.mode.position(depth, ev.load);
        // the controlled force: P̂ = Q except through the transducer's springs
        self.load = p.machine.applied_load(ev.load, depth);
        let row = Row {
            time_s: self.time,
            depth_nm: depth,
            load_nN: ev.load,
            contact_radius_nm: self.contact.contact_radius(&profile),
            iterations,
            drive_nm: self.drive,
            gap_nm: self.gaps.first().copied().unwrap_or(0.0),
            strain_energy_aJ: ev.strain_energy,
            damping_dissipated_aJ: self.dissipated,
            segment: si,
        };
        self.result.rows.push(row);
        self.result.stats.increments += 1;
        self.result.stats.newton_iterations += iterations;
        progress(&Progress {
            segment: si,
            segments: p.schedule.len(),
            row,
            elements: self.solid.elements.len(),
            negative_eigenvalues: None,
        });
        // a band wider than the converged state needs (after a jump, or as the contact
        // shrinks) narrows to it
        self.span = band_span(&self.contact, &self.tiers, &profile);
        if let Some(z) = &self.zone {
            if self.span.narrower_than(z, 2.0 * EDGE_SAFE * z.half_width) {
                self.pending = Some(self.span.zone(z));
            }
        }
        Ok(())
    }

    /// Move the run onto the mesh of `zone` ([`mesh::edge_block`]): the state carried over by
    /// [`transfer`], the solid and the contact surface rebuilt, the mesh recorded in
    /// `result.adaptation`, the gaps of the carried state taken as the damping's start-of-step
    /// gaps.
    fn remesh(&mut self, zone: EdgeZone) -> Result<(), FeError> {
        let p = self.p;
        let new_mesh = mesh::edge_block(&self.result.resolved.block, &zone)?;
        let old = &self.result.mesh;
        let n = self.solid.dofs();
        let carry = |x: &[f64]| {
            let mut y = transfer::interpolate_nodal(old, &x[..n], 2, &new_mesh);
            y.push(x[n]);
            y
        };
        self.u = carry(&self.u);
        self.u_prev = carry(&self.u_prev);
        self.snap_from = (self.snap_from.take()).map(|(x, start, n)| (carry(&x), start, n));
        self.history =
            transfer::project_elementwise(old, &self.history, self.solid.history_len(), &new_mesh);
        self.solid = new_solid(p, &new_mesh)?;
        self.contact.segments = Contact::segments_of(&new_mesh);
        let stats = self.asm.stats;
        self.asm = Assembler::new(&self.solid, Some(&self.contact))?;
        self.asm.stats = stats;
        self.gaps = profile(&self.contact, &self.solid, &self.u, p.kinematics)
            .iter()
            .map(|q| q.gap)
            .collect();
        self.result.adaptation.push(Adaptation {
            increment: self.result.stats.increments,
            time_s: self.time,
            inner_nm: zone.inner,
            outer_nm: zone.outer,
            tail_nm: zone.tail,
            elements: new_mesh.triangles.len(),
        });
        self.result.mesh_report = new_mesh.report();
        self.result.mesh = new_mesh;
        self.last_dv = 0.0;
        self.zone = Some(zone);
        Ok(())
    }
}

/// The controlled variable at the start of a segment and its target: (value, target,
/// duration, by load).
fn segment_span(seg: &Segment, machine: Machine, drive: f64, load: f64) -> (f64, f64, f64, bool) {
    let by_load = machine.load_controlled() && !matches!(seg, Segment::Approach { .. });
    let now = if by_load { load } else { drive };
    match *seg {
        Segment::Load { to, rate }
        | Segment::Unload { to, rate }
        | Segment::Approach { to, rate } => (now, to, (to - now).abs() / rate, by_load),
        Segment::Hold { time } => (now, now, time, by_load),
    }
}

/// The contact profile of the state `x` = (u, δ) of `solid`: the surface at the current node
/// positions X + u against the indenter at depth δ.
fn profile(
    contact: &Contact,
    solid: &Solid,
    x: &[f64],
    kinematics: Kinematics,
) -> Vec<ProfilePoint> {
    let small = kinematics == Kinematics::Small;
    contact.profile(&current(solid, x), &solid.nodes, x[solid.dofs()], small)
}

/// The current node positions X + u of the state `x` = (u, δ) of `solid`.
fn current(solid: &Solid, x: &[f64]) -> Vec<[f64; 2]> {
    solid
        .nodes
        .iter()
        .enumerate()
        .map(|(n, p)| [p[0] + x[2 * n], p[1] + x[2 * n + 1]])
        .collect()
}
