//! Nonlinear block Gauss–Seidel over domains of neighbouring tubes, before the Newton solve of
//! the whole turf.
//!
//! The snaps of a compression step (contacts zipping shut, tubes buckling) are local events.
//! A Newton step on the whole turf takes one step length and one shift for all the events in
//! progress at once, so its iterations grow with the number of events, hence with the patch,
//! and each iteration costs as much as the patch: the work of a step grows like N². A domain —
//! the tubes whose lateral centroids share a cell of a grid over the box — solved by Newton
//! with every other tube held takes its own steps and shifts on a system of a few thousand
//! coordinates. The energy of a domain's problem differs from the turf's by terms that do not
//! depend on the domain's nodes, so every step accepted in a domain's solve lowers the turf's
//! energy by as much: a sweep over the domains is a descent of the turf's energy. Sweeps
//! alternate between the grid and the grid moved by half a cell, so that tubes on a cell's
//! edge share a domain with their neighbours across it every other sweep.
//!
//! A domain's solve keeps the neighbour list of the sweep and does not let a node move farther
//! than the list's Verlet bound (half the skin) from where the list was built; a solve that
//! meets the bound rebuilds the list and goes on from where it stopped.

use std::sync::atomic::{AtomicBool, Ordering};

use super::constraints::FixedDofs;
use super::energy::EnergyTerm;
use super::model::TurfSystem;
use super::platen::Wall;
use super::rod::Rod;
use super::solve::SolveError;
use super::solve_newton::{minimize_newton, NewtonParams};
use super::vdw_term::VdwTerm;

/// The domain sweeps' settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainParams {
    /// tubes per domain (on average)
    pub tubes: usize,
    /// sweeps over the domains before the Newton solve of the whole turf
    pub sweeps: usize,
    /// Newton iterations per domain solve
    pub max_iterations: usize,
    /// the neighbour list's skin during the sweeps, nm (at least the model's): a domain's
    /// solve moves its nodes up to half of it before the list is rebuilt
    pub skin: f64,
}

/// What the sweeps did and cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DomainCost {
    /// Newton iterations summed over the domains' solves
    pub iterations: usize,
    /// the Newton iterations weighted by the share of the turf's free coordinates each
    /// domain holds: the sweeps' work in iterations on the whole turf
    pub weighted_iterations: f64,
    /// domain solves (including those restarted after a list rebuild)
    pub solves: usize,
    /// neighbour-list rebuilds forced by a solve that met the Verlet bound
    pub rebuilds: usize,
}

/// Restarts of one domain's solve after a list rebuild, per sweep.
const MAX_RESTARTS: usize = 20;

/// One domain's energy with every other tube held at `x`, on a copy of its coordinates.
struct DomainProblem<'a> {
    x: &'a [f64],
    /// local number of each node of the turf (usize::MAX: held)
    local_of: &'a [usize],
    /// the turf's node of each local node
    nodes: &'a [usize],
    rods: Vec<Rod>,
    vdw: Option<(&'a VdwTerm, Vec<usize>)>,
    walls: Vec<Wall>,
    /// where the neighbour list was built (the turf's numbering), and how far a node may move
    verlet: (&'a [f64], f64),
    /// set when a trial point left the Verlet bound
    bound: AtomicBool,
}

impl DomainProblem<'_> {
    fn local(&self, n: usize) -> Option<usize> {
        let l = self.local_of[n];
        (l != usize::MAX).then_some(l)
    }

    fn within_bound(&self, local: &[f64]) -> bool {
        let (x_ref, reach) = self.verlet;
        let inside = self.nodes.iter().enumerate().all(|(l, &n)| {
            let (p, q) = (&local[3 * l..3 * l + 3], &x_ref[3 * n..3 * n + 3]);
            (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2) <= reach * reach
        });
        if !inside {
            self.bound.store(true, Ordering::Relaxed);
        }
        inside
    }
}

impl EnergyTerm for DomainProblem<'_> {
    fn energy_gradient(&self, local: &[f64], grad: &mut [f64]) -> f64 {
        if !self.within_bound(local) {
            return f64::INFINITY;
        }
        let mut e: f64 = self
            .rods
            .iter()
            .map(|r| r.energy_gradient(local, grad))
            .sum();
        if let Some((vdw, pairs)) = &self.vdw {
            e += vdw.energy_of_nodes(self.x, &|n| self.local(n), local, pairs, grad, None);
        }
        e + self
            .walls
            .iter()
            .map(|w| w.energy_gradient(local, grad))
            .sum::<f64>()
    }

    fn hessian(&self, local: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for r in &self.rods {
            r.hessian(local, out);
        }
        if let Some((vdw, pairs)) = &self.vdw {
            let mut g = vec![0.0; local.len()];
            vdw.energy_of_nodes(self.x, &|n| self.local(n), local, pairs, &mut g, Some(out));
        }
        for w in &self.walls {
            w.hessian(local, out);
        }
    }
}

/// The rods of `sys` grouped into domains: the cells of a g × g grid over the box (g² ≈
/// tubes / `per_domain`) holding each tube's lateral centroid, the grid moved by `shift` cells;
/// empty cells left out.
fn domains(sys: &TurfSystem, x: &[f64], per_domain: usize, shift: f64) -> Vec<Vec<usize>> {
    let rods = sys.model.rods.rods();
    let centroids: Vec<[f64; 2]> = rods
        .iter()
        .map(|r| {
            let nodes = r.first_node()..r.first_node() + r.nodes();
            let n = r.nodes() as f64;
            let sum = |axis: usize| nodes.clone().map(|k| x[3 * k + axis]).sum::<f64>() / n;
            [sum(0), sum(1)]
        })
        .collect();
    let pbox = sys.model.vdw.as_ref().map(|v| v.periodic_box());
    let periods = pbox.map_or([None, None], |b| [b.lx, b.ly]);
    let g = ((rods.len() as f64 / per_domain.max(1) as f64)
        .sqrt()
        .round() as usize)
        .max(1);
    // each axis mapped onto [0, 1): by its period, else by the centroids' range
    let unit: Vec<Box<dyn Fn(f64) -> f64>> = (0..2)
        .map(|axis| -> Box<dyn Fn(f64) -> f64> {
            match periods[axis] {
                Some(l) => Box::new(move |v: f64| (v / l).rem_euclid(1.0)),
                None => {
                    let lo = centroids
                        .iter()
                        .map(|c| c[axis])
                        .fold(f64::INFINITY, f64::min);
                    let hi = centroids
                        .iter()
                        .map(|c| c[axis])
                        .fold(f64::NEG_INFINITY, f64::max);
                    let span = (hi - lo).max(f64::MIN_POSITIVE);
                    Box::new(move |v: f64| ((v - lo) / span).min(1.0 - f64::EPSILON))
                }
            }
        })
        .collect();
    let mut cells = vec![Vec::new(); g * g];
    for (t, c) in centroids.iter().enumerate() {
        let cell = |axis: usize| ((unit[axis](c[axis]) * g as f64 + shift) as usize) % g;
        cells[cell(0) * g + cell(1)].push(t);
    }
    cells.retain(|c| !c.is_empty());
    cells
}

/// `params.sweeps` Gauss–Seidel sweeps over the domains of `sys` from `x` (moved in place),
/// each domain's Newton solve with `newton` capped at `params.max_iterations`. Nothing is done
/// while the sphere's adhesion or hold acts (their terms are not split by domain).
pub fn sweep_domains(
    sys: &mut TurfSystem,
    x: &mut [f64],
    params: &DomainParams,
    newton: &NewtonParams,
) -> DomainCost {
    let mut cost = DomainCost::default();
    if sys.model.sphere_lj.is_some() || sys.model.stick.is_some() {
        return cost;
    }
    let local_params = NewtonParams {
        max_iterations: params.max_iterations,
        ..*newton
    };
    let total_free = sys.fixed.free_dofs().len().max(1) as f64;
    let rods: Vec<Rod> = sys.model.rods.rods().to_vec();
    let mut local_of = vec![usize::MAX; x.len() / 3];
    let skin = sys.model.vdw.as_ref().map(|v| v.skin());
    if let (Some(v), Some(s)) = (sys.model.vdw.as_mut(), skin) {
        v.set_skin(s.max(params.skin), x);
    }
    for sweep in 0..params.sweeps {
        sys.model.prepare(x);
        let shift = if sweep % 2 == 1 { 0.5 } else { 0.0 };
        for domain in domains(sys, x, params.tubes, shift) {
            let mut nodes = Vec::new();
            let mut local_rods = Vec::new();
            for &t in &domain {
                let r = &rods[t];
                local_rods.push(r.moved_to(nodes.len()));
                nodes.extend(r.first_node()..r.first_node() + r.nodes());
            }
            for (l, &n) in nodes.iter().enumerate() {
                local_of[n] = l;
            }
            let mut fixed = FixedDofs::free(nodes.len());
            for (l, &n) in nodes.iter().enumerate() {
                for axis in 0..3 {
                    if sys.fixed.is_fixed(3 * n + axis) {
                        fixed.fix(3 * l + axis);
                    }
                }
            }
            let share = fixed.free_dofs().len() as f64 / total_free;
            for _ in 0..MAX_RESTARTS {
                let mut local: Vec<f64> = nodes
                    .iter()
                    .flat_map(|&n| x[3 * n..3 * n + 3].iter().copied())
                    .collect();
                let hit = {
                    let model = &sys.model;
                    let local_fn = |n: usize| (local_of[n] != usize::MAX).then(|| local_of[n]);
                    let mut walls = vec![model.substrate.restricted(&local_fn)];
                    walls.extend(model.platen.as_ref().map(|p| p.restricted(&local_fn)));
                    let vdw = model.vdw.as_ref();
                    let verlet = vdw.map_or((&x[..], f64::INFINITY), |v| v.verlet());
                    let mut problem = DomainProblem {
                        x,
                        local_of: &local_of,
                        nodes: &nodes,
                        rods: local_rods.clone(),
                        vdw: vdw.map(|v| {
                            let in_domain = |n: usize| local_of[n] != usize::MAX;
                            (v, v.pairs_touching(&in_domain))
                        }),
                        walls,
                        verlet,
                        bound: AtomicBool::new(false),
                    };
                    cost.solves += 1;
                    let (iterations, converged) =
                        match minimize_newton(&mut problem, &fixed, &mut local, &local_params) {
                            Ok(info) => (info.cost.iterations, true),
                            Err(
                                SolveError::NoConvergence { cost, .. }
                                | SolveError::LineSearch { cost, .. },
                            ) => (cost.iterations, false),
                            Err(_) => (0, true),
                        };
                    cost.iterations += iterations;
                    cost.weighted_iterations += iterations as f64 * share;
                    !converged && problem.bound.load(Ordering::Relaxed)
                };
                for (l, &n) in nodes.iter().enumerate() {
                    x[3 * n..3 * n + 3].copy_from_slice(&local[3 * l..3 * l + 3]);
                }
                if !hit {
                    break;
                }
                if let Some(v) = sys.model.vdw.as_mut() {
                    v.set_box(v.periodic_box(), x);
                    cost.rebuilds += 1;
                }
            }
            for &n in &nodes {
                local_of[n] = usize::MAX;
            }
        }
        if std::env::var_os("TURF_DOMAIN_TRACE").is_some() {
            let mut g = vec![0.0; x.len()];
            sys.model.prepare(x);
            let e = sys.model.energy_gradient(x, &mut g);
            eprintln!(
                "  sweep {sweep}: energy {e:.6e} aJ, residual {:.3e} nN, {cost:?}",
                sys.fixed.residual(&g)
            );
        }
    }
    if let (Some(v), Some(s)) = (sys.model.vdw.as_mut(), skin) {
        v.set_skin(s, x);
    }
    cost
}
