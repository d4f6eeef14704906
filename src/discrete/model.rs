//! The discrete turf as one potential energy (seed §2.4, eq. 1.1):
//! elastica tubes ([`RodSet`]: stretching + bending), tube–tube van der Waals contacts
//! ([`VdwTerm`]), the substrate and the platen ([`Wall`]), with the clamped tube bases held
//! fixed. A [`TurfSystem`] is built from a generated [`Turf`]; [`relax`] brings it to
//! equilibrium (contacts form, bending energy is locked in) and reports E = U − Γ; the
//! compression drive ([`super::drive`]) moves the platen.

use super::constraints::FixedDofs;
use super::energy::EnergyTerm;
use super::platen::{Facing, Shape, Wall};
use super::rod::{Rod, RodError, RodSet, RodStiffness};
use super::solve::{Info, SolveError};
use super::solve_fire::{minimize_fire, FireParams};
use super::solve_newton::{minimize_newton, NewtonParams};
use super::sphere_adhesion::{SphereAdhesion, SphereLjParams};
use super::sphere_stick::{Anchor, Stick};
use super::structure::{self, Structure};
use super::turf::{EnergyBalance, Turf};
use super::vdw::{VdwError, VdwParams};
use super::vdw_term::{TubeLayout, VdwTerm};
use crate::laws::SurfaceLaw;
use serde::Serialize;

/// Why a model could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// a tube is not a valid rod
    #[error("tube {tube}: {source}")]
    Rod {
        /// tube index
        tube: usize,
        /// cause
        source: RodError,
    },
    /// the contact model could not be set up
    #[error(transparent)]
    Vdw(#[from] VdwError),
}

/// The energy terms of the turf.
pub struct TurfModel {
    /// the tubes' elastic energy
    pub rods: RodSet,
    /// tube–tube contacts; `None`: tubes do not interact
    pub vdw: Option<VdwTerm>,
    /// the substrate z = 0 (keeps free nodes above it)
    pub substrate: Wall,
    /// the compression platen; `None` before the drive starts
    pub platen: Option<Wall>,
    /// LJ adhesion of the sphere indenter (acts only while the platen is set)
    pub sphere_lj: Option<SphereAdhesion>,
    /// the sphere's tangential hold of the nodes it touches (acts only while the platen is set)
    pub stick: Option<Stick>,
}

impl TurfModel {
    /// The sphere's adhesion and hold, while the indenter is in place.
    fn sphere_terms(&self) -> impl Iterator<Item = &dyn EnergyTerm> {
        let on = self.platen.is_some();
        let lj = self.sphere_lj.as_ref().filter(|_| on);
        let stick = self.stick.as_ref().filter(|_| on);
        lj.map(|t| t as &dyn EnergyTerm)
            .into_iter()
            .chain(stick.map(|t| t as &dyn EnergyTerm))
    }

    /// Every term acting now, in the order the Hessian lists them: the rods (whose entries
    /// never change) first, then the contacts, the walls and the sphere's terms.
    fn terms(&self) -> impl Iterator<Item = &dyn EnergyTerm> {
        let rods: &dyn EnergyTerm = &self.rods;
        let substrate: &dyn EnergyTerm = &self.substrate;
        std::iter::once(rods)
            .chain(self.vdw.as_ref().map(|v| v as &dyn EnergyTerm))
            .chain(std::iter::once(substrate))
            .chain(self.platen.as_ref().map(|p| p as &dyn EnergyTerm))
            .chain(self.sphere_terms())
    }
}

impl EnergyTerm for TurfModel {
    fn prepare(&mut self, x: &[f64]) {
        if let Some(v) = self.vdw.as_mut() {
            v.prepare(x);
        }
    }

    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut e = self.rods.energy_gradient(x, grad);
        if let Some(v) = &self.vdw {
            e += v.energy_gradient(x, grad);
        }
        e += self.substrate.energy_gradient(x, grad);
        if let Some(p) = &self.platen {
            e += p.energy_gradient(x, grad);
        }
        for t in self.sphere_terms() {
            e += t.energy_gradient(x, grad);
        }
        e
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for t in self.terms() {
            t.hessian(x, out);
        }
    }

    fn hessian_lower(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for t in self.terms() {
            t.hessian_lower(x, out);
        }
    }
}

/// The static solver of each equilibrium, with its settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StaticSolver {
    /// FIRE (matrix-free)
    Fire(FireParams),
    /// Newton on the sparse Hessian
    Newton(NewtonParams),
}

impl StaticSolver {
    /// Minimise the energy of `model` over the free coordinates, from `x` (solution on return).
    pub fn solve<E: EnergyTerm + ?Sized>(
        &self,
        model: &mut E,
        fixed: &FixedDofs,
        x: &mut [f64],
    ) -> Result<Info, SolveError> {
        match self {
            StaticSolver::Fire(p) => minimize_fire(model, fixed, x, p),
            StaticSolver::Newton(p) => minimize_newton(model, fixed, x, p),
        }
    }
}

/// A turf ready to solve: its energy, the fixed coordinates, the box.
pub struct TurfSystem {
    /// the energy
    pub model: TurfModel,
    /// clamped bases
    pub fixed: FixedDofs,
    /// (node, outer radius nm) of every free node: the nodes the walls act on
    pub wall_nodes: Vec<(usize, f64)>,
    /// penalty stiffness of the walls, nN/nm³
    pub wall_stiffness: f64,
    /// area of the box, nm² (the platen's nominal area)
    pub area: f64,
    /// what presses on the turf: the flat platen ([`Shape::Plane`], the default) or a sphere
    pub indenter: Shape,
}

/// How the sphere indenter meets the tubes beyond the frictionless penalty contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereContact {
    /// the LJ surface law between sphere and tubes; `None`: no adhesion
    pub adhesion: Option<SurfaceLaw>,
    /// the tangential hold; `None`: frictionless
    pub stick: Option<StickSettings>,
}

/// The stick option's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickSettings {
    /// tangential penalty stiffness k_t, nN/nm
    pub stiffness: f64,
    /// tensile normal force (nN) beyond which a held node is let go; `None`: only on leaving
    pub release: Option<f64>,
}

/// The energy of a configuration by part, aJ.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct EnergyParts {
    /// stretching energy of the tubes
    pub stretching: f64,
    /// bending energy of the tubes
    pub bending: f64,
    /// van der Waals energy (negative when tubes adhere; Γ = −this)
    pub vdw: f64,
    /// energy of the walls: the penalty of the platen (or sphere) and substrate, and the
    /// sphere's LJ adhesion and tangential hold when it has them
    pub walls: f64,
}

impl EnergyParts {
    /// The elastic energy U = stretching + bending, aJ.
    pub fn elastic(&self) -> f64 {
        self.stretching + self.bending
    }

    /// E = U − Γ (seed eq. 1.1).
    pub fn balance(&self) -> EnergyBalance {
        EnergyBalance::new(self.elastic(), self.vdw)
    }
}

/// What a configuration looks like: energies, contacts, wall forces.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct State {
    /// energies by part
    pub energy: EnergyParts,
    /// segment pairs in contact: listed pairs with at least one quadrature point pair inside
    /// the interaction cutoff
    pub contacts: usize,
    /// smallest surface gap between tubes over the quadrature point pairs in range, nm (+∞
    /// without contacts; negative: tubes interpenetrate, the state is unphysical)
    pub min_gap: f64,
    /// force of the turf on the platen, nN (0 without a platen): −∂E/∂H of every term that
    /// moves with it (penalty, the sphere's adhesion and hold)
    pub platen_force: f64,
    /// nodes touching the platen
    pub platen_nodes: usize,
}

impl TurfSystem {
    /// Build the system of a generated turf: each tube a rod whose natural shape is its
    /// as-grown shape (stress-free until contacts or the platen bend it), Young's modulus
    /// `youngs` (GPa) on each tube's own hollow section, the first two nodes of each tube fixed
    /// (clamped base), contacts from `vdw` (none if `None`), walls of stiffness
    /// `wall_stiffness` (nN/nm³).
    pub fn from_turf(
        turf: &Turf,
        youngs: f64,
        vdw: Option<&VdwParams>,
        wall_stiffness: f64,
        area: f64,
    ) -> Result<Self, ModelError> {
        let layout = turf.layout();
        let x0 = turf.coordinates();
        let mut rods = Vec::with_capacity(turf.tubes.len());
        for (t, (tube, l)) in turf.tubes.iter().zip(&layout).enumerate() {
            let stiffness = RodStiffness::hollow_tube(youngs, tube.radius_outer, tube.radius_inner);
            rods.push(
                Rod::natural(l.first_node, &tube.nodes, stiffness)
                    .map_err(|source| ModelError::Rod { tube: t, source })?,
            );
        }
        let nodes = x0.len() / 3;
        let mut fixed = FixedDofs::free(nodes);
        let clamped = turf.clamped_nodes();
        for &n in &clamped {
            fixed.pin(n);
        }
        let wall_nodes: Vec<(usize, f64)> = layout
            .iter()
            .flat_map(|l| (l.first_node..l.first_node + l.nodes).map(move |n| (n, l.radius)))
            .filter(|(n, _)| !clamped.contains(n))
            .collect();
        let vdw = match vdw {
            Some(p) => Some(VdwTerm::new(p, &layout, &x0, turf.periodic)?),
            None => None,
        };
        Ok(TurfSystem {
            model: TurfModel {
                rods: RodSet::new(rods),
                vdw,
                substrate: Wall::new(0.0, Facing::Up, wall_stiffness, wall_nodes.clone()),
                platen: None,
                sphere_lj: None,
                stick: None,
            },
            fixed,
            wall_nodes,
            wall_stiffness,
            area,
            indenter: Shape::Plane,
        })
    }

    /// Top of the turf: the largest z + r over the free nodes, nm.
    pub fn height(&self, x: &[f64]) -> f64 {
        self.wall_nodes
            .iter()
            .map(|&(n, r)| x[3 * n + 2] + r)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The top of each tube, the largest z + r over its free nodes (nm): where a platen meets
    /// it. Their largest is [`Self::height`]; their mean does not grow with the patch as the
    /// largest does (the tallest of N tubes stands about σ_L√(2 ln N) above the mean).
    pub fn tube_tops(&self, x: &[f64]) -> Vec<f64> {
        let wall = &self.wall_nodes;
        self.model
            .rods
            .rods()
            .iter()
            .map(|rod| {
                let (first, end) = (rod.first_node(), rod.first_node() + rod.nodes());
                wall[wall.partition_point(|w| w.0 < first)..wall.partition_point(|w| w.0 < end)]
                    .iter()
                    .map(|&(n, r)| x[3 * n + 2] + r)
                    .fold(f64::NEG_INFINITY, f64::max)
            })
            .filter(|t| t.is_finite())
            .collect()
    }

    /// Where the drive starts the platen (the indenter's lowest point), nm: at the top of the
    /// turf ([`Self::height`]), or with the sphere's adhesion z₀ above it, so that the first
    /// tip meets the law at its equilibrium separation rather than deep in its repulsion.
    pub fn start_height(&self, x: &[f64]) -> f64 {
        match &self.model.sphere_lj {
            Some(t) => self.height(x) + t.rest_gap(),
            None => self.height(x),
        }
    }

    /// Give the sphere indenter ([`Self::indenter`], set before) the adhesion and hold of
    /// `contact`, acting on the tubes `layout` with reference configuration `x0` (nm). A node
    /// is in contact for the hold when its gap is below the law's gap of largest tension (with
    /// adhesion) or negative (the penalty contact alone).
    pub fn set_sphere_contact(
        &mut self,
        contact: &SphereContact,
        layout: &[TubeLayout],
        x0: &[f64],
    ) {
        let Shape::Sphere { radius, x, y } = self.indenter else {
            return;
        };
        let lowest = [x, y, self.height(x0)];
        self.model.sphere_lj = contact.adhesion.map(|law| {
            SphereAdhesion::new(law, radius, lowest, layout, x0, &SphereLjParams::default())
        });
        let touch_gap = contact.adhesion.map_or(0.0, |l| l.gap_at_max_tension());
        self.model.stick = contact.stick.map(|s| {
            Stick::new(
                s.stiffness,
                touch_gap,
                s.release,
                radius,
                lowest,
                self.wall_nodes.clone(),
            )
        });
    }

    /// The held nodes (none without the stick option).
    pub fn anchors(&self) -> Vec<Anchor> {
        self.model
            .stick
            .as_ref()
            .map_or_else(Vec::new, |s| s.anchors().to_vec())
    }

    /// Restore the held nodes of a saved step.
    pub fn set_anchors(&mut self, anchors: &[Anchor]) {
        if let Some(s) = self.model.stick.as_mut() {
            s.set_anchors(anchors);
        }
    }

    /// Between load steps, at the equilibrium `x`: hold the nodes that have come into contact,
    /// let go of those that left it or pull beyond the release force ([`Stick::update`]).
    pub fn update_stick(&mut self, x: &[f64]) {
        let m = &mut self.model;
        let (Some(stick), Some(platen)) = (m.stick.as_mut(), m.platen.as_ref()) else {
            return;
        };
        let mut normal = vec![0.0; x.len()];
        platen.energy_gradient(x, &mut normal);
        if let Some(lj) = &m.sphere_lj {
            lj.energy_gradient(x, &mut normal);
        }
        stick.update(x, &normal);
    }

    /// Put the platen (the indenter's lowest point) at height `h` (nm).
    pub fn set_platen(&mut self, h: f64) {
        if let Some(t) = self.model.sphere_lj.as_mut() {
            t.set_height(h);
        }
        if let Some(t) = self.model.stick.as_mut() {
            t.set_height(h);
        }
        match self.model.platen.as_mut() {
            Some(p) => p.height = h,
            None => {
                let mut wall = Wall::new(
                    h,
                    Facing::Down,
                    self.wall_stiffness,
                    self.wall_nodes.clone(),
                );
                wall.shape = self.indenter;
                self.model.platen = Some(wall)
            }
        }
    }

    /// Energies, contacts and platen force at `x` (brings the neighbour list up to date).
    pub fn state(&mut self, x: &[f64]) -> State {
        self.model.prepare(x);
        let m = &self.model;
        let (stretching, bending) = m.rods.energy_parts(x);
        let mut scratch = vec![0.0; x.len()];
        let (vdw, contacts, min_gap) = match &m.vdw {
            Some(v) => {
                let pairs = v.evaluate_pairs(x, false);
                (
                    pairs.iter().map(|p| p.energy).sum(),
                    pairs.iter().filter(|p| p.point_pairs > 0).count(),
                    pairs
                        .iter()
                        .map(|p| p.min_gap)
                        .fold(f64::INFINITY, f64::min),
                )
            }
            None => (0.0, 0, f64::INFINITY),
        };
        let mut walls = m.substrate.energy_gradient(x, &mut scratch);
        let (mut platen_force, mut platen_nodes) = (0.0, 0);
        if let Some(p) = &m.platen {
            walls += p.energy_gradient(x, &mut scratch);
            platen_force = p.force(x);
            platen_nodes = p.touching(x);
            if let Some(t) = m.sphere_lj.as_ref() {
                walls += t.energy_gradient(x, &mut scratch);
                platen_force += t.force(x);
            }
            if let Some(t) = m.stick.as_ref() {
                walls += t.energy_gradient(x, &mut scratch);
                platen_force += t.force(x);
            }
        }
        State {
            energy: EnergyParts {
                stretching,
                bending,
                vdw,
                walls,
            },
            contacts,
            min_gap,
            platen_force,
            platen_nodes,
        }
    }

    /// The structure at `x` in the micromechanics' terms — contact patches within `gap` (nm),
    /// the free segments between them — over the volume of the box up to the turf's top;
    /// `None` without a tube–tube interaction (brings the neighbour list up to date).
    pub fn structure(&mut self, x: &[f64], gap: f64) -> Option<Structure> {
        self.model.prepare(x);
        let volume = self.area * self.height(x);
        let vdw = self.model.vdw.as_ref()?;
        Some(structure::measure(
            &self.model.rods,
            &vdw.pair_geometry(x),
            x,
            gap,
            volume,
        ))
    }

    /// Total energy at `x`, aJ (brings the neighbour list up to date).
    pub fn energy(&mut self, x: &[f64]) -> f64 {
        self.model.prepare(x);
        let mut scratch = vec![0.0; x.len()];
        self.model.energy_gradient(x, &mut scratch)
    }

    /// Solve for equilibrium from `x` (solution on return).
    pub fn solve(&mut self, x: &mut [f64], solver: &StaticSolver) -> Result<Info, SolveError> {
        solver.solve(&mut self.model, &self.fixed, x)
    }
}

/// A relaxed turf: the solve and the state it reached.
#[derive(Debug, Clone)]
pub struct Relaxed {
    /// the solve (cost, residual)
    pub info: Info,
    /// energies and contacts of the generated (unrelaxed) turf
    pub initial: State,
    /// energies and contacts after relaxation
    pub state: State,
}

impl Relaxed {
    /// E = U − Γ after relaxation (seed eq. 1.1).
    pub fn balance(&self) -> EnergyBalance {
        self.state.energy.balance()
    }
}

/// Relax the generated turf at `x` without a platen: tubes come into contact where they are
/// within range, adhere and bend, and the bending energy so stored stays locked in.
pub fn relax(
    sys: &mut TurfSystem,
    x: &mut [f64],
    solver: &StaticSolver,
) -> Result<Relaxed, SolveError> {
    sys.model.platen = None;
    let initial = sys.state(x);
    let info = sys.solve(x, solver)?;
    let state = sys.state(x);
    Ok(Relaxed {
        info,
        initial,
        state,
    })
}
