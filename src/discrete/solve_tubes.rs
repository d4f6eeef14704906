//! Nonlinear block Gauss–Seidel over the tubes: each tube relaxed by Newton with every other
//! tube held where it is, tube after tube, before the Newton solve of the whole turf.
//!
//! The snaps of a compression step (contacts zipping shut, tubes buckling) are local events; a
//! Newton step on the whole turf takes one step length and one shift for all the events in
//! progress at once, and spends about one iteration per two new contacts. A tube solved alone
//! takes its own step lengths and shifts, on a system of a few hundred coordinates. The energy
//! of one tube's problem differs from the turf's by terms that do not depend on that tube's
//! nodes, so every step accepted in a tube's solve lowers the turf's energy by as much: the
//! sweep is a descent of the turf's energy.
//!
//! A tube's solve keeps the neighbour list of the sweep's start and does not let a node move
//! farther than the list's Verlet bound (half the skin) from where the list was built; a solve
//! that meets the bound rebuilds the list and goes on.

use std::sync::atomic::{AtomicBool, Ordering};

use super::constraints::FixedDofs;
use super::energy::EnergyTerm;
use super::model::TurfSystem;
use super::platen::Wall;
use super::rod::Rod;
use super::solve::SolveError;
use super::solve_newton::{minimize_newton, NewtonParams};
use super::vdw_term::VdwTerm;

/// One tube's energy with every other tube held at `x`, on a copy of its coordinates.
struct TubeProblem<'a> {
    x: &'a [f64],
    nodes: std::ops::Range<usize>,
    rod: Rod,
    vdw: Option<(&'a VdwTerm, Vec<usize>)>,
    walls: Vec<Wall>,
    /// the tube's nodes where the neighbour list was built, and how far they may move
    verlet: (&'a [f64], f64),
    /// set when a trial point left the Verlet bound
    bound: AtomicBool,
}

impl TubeProblem<'_> {
    fn within_bound(&self, local: &[f64]) -> bool {
        let (x_ref, reach) = self.verlet;
        let r2 = reach * reach;
        let inside = local
            .chunks_exact(3)
            .zip(x_ref.chunks_exact(3))
            .all(|(p, q)| {
                (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2) <= r2
            });
        if !inside {
            self.bound.store(true, Ordering::Relaxed);
        }
        inside
    }
}

impl EnergyTerm for TubeProblem<'_> {
    fn energy_gradient(&self, local: &[f64], grad: &mut [f64]) -> f64 {
        if !self.within_bound(local) {
            return f64::INFINITY;
        }
        let mut e = self.rod.energy_gradient(local, grad);
        if let Some((vdw, pairs)) = &self.vdw {
            e += vdw.energy_of_nodes(self.x, self.nodes.clone(), local, pairs, grad, None);
        }
        for w in &self.walls {
            e += w.energy_gradient(local, grad);
        }
        e
    }

    fn hessian(&self, local: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        self.rod.hessian(local, out);
        if let Some((vdw, pairs)) = &self.vdw {
            let mut g = vec![0.0; local.len()];
            vdw.energy_of_nodes(self.x, self.nodes.clone(), local, pairs, &mut g, Some(out));
        }
        for w in &self.walls {
            w.hessian(local, out);
        }
    }
}

/// What the sweeps cost and did.
#[derive(Debug, Clone, Copy, Default)]
pub struct SweepCost {
    /// Newton iterations summed over the tubes' solves
    pub iterations: usize,
    /// tube solves (including those restarted after a list rebuild)
    pub solves: usize,
    /// neighbour-list rebuilds forced by a solve that met the Verlet bound
    pub rebuilds: usize,
}

/// Restarts of one tube's solve after a list rebuild, per sweep.
const MAX_RESTARTS: usize = 20;

/// `sweeps` Gauss–Seidel sweeps over the tubes of `sys` from `x` (moved in place), each tube's
/// Newton solve with `params`. Nothing is done when the sphere's adhesion or hold is on.
pub fn sweep_tubes(
    sys: &mut TurfSystem,
    x: &mut [f64],
    sweeps: usize,
    params: &NewtonParams,
) -> SweepCost {
    let mut cost = SweepCost::default();
    if sys.model.sphere_lj.is_some() || sys.model.stick.is_some() {
        return cost;
    }
    let rods: Vec<Rod> = sys.model.rods.rods().to_vec();
    for _ in 0..sweeps {
        sys.model.prepare(x);
        for rod in &rods {
            let nodes = rod.first_node()..rod.first_node() + rod.nodes();
            let dofs = 3 * nodes.start..3 * nodes.end;
            let mut fixed = FixedDofs::free(rod.nodes());
            for (k, d) in dofs.clone().enumerate() {
                if sys.fixed.is_fixed(d) {
                    fixed.fix(k);
                }
            }
            for _ in 0..MAX_RESTARTS {
                let mut local = x[dofs.clone()].to_vec();
                let hit = {
                    let model = &sys.model;
                    let mut walls = vec![model.substrate.on_nodes(nodes.clone())];
                    walls.extend(model.platen.as_ref().map(|p| p.on_nodes(nodes.clone())));
                    let vdw = model.vdw.as_ref();
                    let verlet = vdw.map_or((&x[dofs.clone()], f64::INFINITY), |v| {
                        let (x_ref, reach) = v.verlet();
                        (&x_ref[dofs.clone()], reach)
                    });
                    let mut problem = TubeProblem {
                        x,
                        nodes: nodes.clone(),
                        rod: rod.moved_to(0),
                        vdw: vdw.map(|v| (v, v.pairs_touching(nodes.clone()))),
                        walls,
                        verlet,
                        bound: AtomicBool::new(false),
                    };
                    cost.solves += 1;
                    cost.iterations +=
                        match minimize_newton(&mut problem, &fixed, &mut local, params) {
                            Ok(info) => info.cost.iterations,
                            Err(
                                SolveError::NoConvergence { cost, .. }
                                | SolveError::LineSearch { cost, .. },
                            ) => cost.iterations,
                            Err(_) => 0,
                        };
                    problem.bound.load(Ordering::Relaxed)
                };
                x[dofs.clone()].copy_from_slice(&local);
                if !hit {
                    break;
                }
                if let Some(v) = sys.model.vdw.as_mut() {
                    v.set_box(v.periodic_box(), x);
                    cost.rebuilds += 1;
                }
            }
        }
        if std::env::var_os("TURF_TUBE_TRACE").is_some() {
            let g = {
                let mut g = vec![0.0; x.len()];
                sys.model.prepare(x);
                let e = sys.model.energy_gradient(x, &mut g);
                (e, sys.fixed.residual(&g))
            };
            eprintln!(
                "  sweep: energy {:.6e} aJ, residual {:.3e} nN, {:?}",
                g.0, g.1, cost
            );
        }
    }
    sys.model.prepare(x);
    cost
}
