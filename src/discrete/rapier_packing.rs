//! Dense turfs by dynamic packing (rapier3d-f64, cargo feature `rapier`; issue 22, use (a)):
//! a generated turf squeezed isotropically in x and y on rigid-body chains until it reaches
//! densities the geometric generator refuses, then handed back as a [`Turf`] in the smaller
//! periodic box for the static engine to relax.
//!
//! The model: each segment of a tube is a rigid capsule of radius r_o + c/2 (c the clearance,
//! by default the van der Waals equilibrium gap, so capsules touching means surfaces at that
//! gap), the segments of a tube joined by spherical impulse joints, the base segment (the two
//! clamped nodes of the static model) a body that keeps its orientation and height but slides
//! on the substrate (the bases must make room for each other as the box shrinks), no gravity. Bending is resisted by the
//! discrete elastica's vertex energy W_i = K/(ℓ_{i−1} + ℓ_i) |κb_i − κb_i⁰|² about the
//! as-grown shape: by default as its small-angle spring, K/ℓ̄ per radian, in position motors of
//! the joints (implicit, so stable at any step: [`Bending::JointSprings`]); or exactly
//! ([`super::rod_kernels::bend_vertex_gradient`]) as torques τ_j = ∂W/∂e_j × e_j on the
//! segments' edge vectors e_j ([`Bending::Torques`], explicit: stable only for a small
//! `stability`). Tubes meet only through rapier's
//! capsule contacts (frictionless, no adhesion: the van der Waals attraction is left to the
//! static relaxation).
//!
//! Compression: every step the box side shrinks by the factor s = 1 − `shrink_per_step` in x
//! and y alike, and every body's centre is remapped affinely, (x, y, z) → (s x, s y, z), bases
//! included; rapier's contact and joint solver then removes the overlaps and joint gaps the
//! remapping made, and the tubes bend around each other. The periodic box is modelled by
//! kinematic ghosts: a copy of each body at every lateral image shift k·(L_x, L_y) that can
//! reach the turf, moved with its body each step; a ghost touches real bodies only, so each of
//! two bodies in contact across the boundary is pushed by the other's image. Since the
//! remapping is affine, the set of ghosts needed is fixed in box-relative coordinates and is
//! chosen once, for the smallest box of the run.
//!
//! At each target density the remapping stops, the chains settle for `hold_steps`, and the
//! state is recorded: nodes (the midpoint of each joint's two anchors), the box, the largest
//! joint gap, and the smallest surface gap between tubes over all periodic images
//! ([`min_surface_gap`], capsules of radius r_o: negative means the tubes interpenetrate).
//!
//! Quasi-statics by mass scaling, as in dynamic relaxation: with rapier's step dt, each body
//! gets the rotational inertia that puts its stiffest bending spring (≈ 16K/ℓ) at
//! ω dt = `stability`, the mass m = 4I/ℓ², and viscous damping.
//!
//! Scenes use it through `[turf.packing]` (one target density, the default settings:
//! `pipeline::turf_setup`); `examples/rapier_packing.rs` exposes every setting.

use super::broadphase::PeriodicBox;
use super::rod::RodStiffness;
use super::rod_kernels::{bend_vertex_gradient, curvature_binormal};
use super::turf::{Tube, Turf};
use nalgebra::Vector3;
use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;
use rapier3d_f64::prelude::*;
use std::time::Instant;

/// Settings of the packing.
#[derive(Debug, Clone, PartialEq)]
pub struct PackingParams {
    /// target densities, tubes/nm² (10¹⁰ /cm² = 10⁻⁴ /nm²), increasing; a state is recorded at
    /// each
    pub densities: Vec<f64>,
    /// relative shrink of the box side per step (the remapping's 1 − s)
    pub shrink_per_step: f64,
    /// steps without remapping at each target before the state is recorded
    pub hold_steps: usize,
    /// added to the capsules' diameter, nm (the capsule radius is r_o + clearance/2)
    pub clearance: f64,
    /// ω dt of the stiffest bending spring of a body (mass scaling), < 2 for stability
    pub stability: f64,
    /// rapier's linear and angular damping, 1/s of its time
    pub damping: f64,
    /// rapier's constraint-solver iterations per step (its default: 4)
    pub solver_iterations: usize,
    /// the packing stops when a joint opens wider than this, nm (the chains tear)
    pub max_joint_gap: f64,
    /// how the chains resist bending
    pub bending: Bending,
    /// an overlap of two tube surfaces deeper than this, nm (rapier's deepest contact, checked
    /// every `check_every` steps), pauses the remapping until it is below half; if it lasts
    /// `pause_steps`, the turf has jammed: the packing stops and records the last state
    /// checked without a pause
    pub max_overlap: f64,
    /// steps an overlap may pause the remapping before the packing stops
    pub pause_steps: usize,
    /// steps between the checks of joints and overlaps (and the snapshots kept)
    pub check_every: usize,
}

/// How a chain resists bending at its joints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bending {
    /// angular position motors of the spherical joints (implicit springs in rapier's solver,
    /// stiffness K/ℓ̄ per radian about the as-grown relative orientation, critically damped)
    JointSprings,
    /// explicit torques of the elastica's vertex energy (stable only for small `stability`)
    Torques,
    /// freely jointed chains
    Off,
}

impl Default for PackingParams {
    fn default() -> Self {
        PackingParams {
            densities: vec![1.5e-4, 2e-4, 4e-4, 6e-4],
            shrink_per_step: 2e-4,
            hold_steps: 500,
            clearance: 0.34,
            stability: 0.5,
            damping: 10.0,
            solver_iterations: 8,
            max_joint_gap: 1.0,
            bending: Bending::JointSprings,
            max_overlap: 1.0,
            pause_steps: 1000,
            check_every: 50,
        }
    }
}

/// Why a packing cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PackingError {
    /// the turf's box is not periodic in x and y
    #[error("the packing needs a turf periodic in x and y")]
    NotPeriodic,
    /// no tube, or a tube with fewer than two segments
    #[error("the packing needs tubes of at least two segments (tube {tube} has {segments})")]
    ShortTube {
        /// the tube
        tube: usize,
        /// its segments
        segments: usize,
    },
    /// a target density at or below the turf's, or not finite
    #[error("target density {target} /nm² is not above the turf's {current} /nm²")]
    Target {
        /// the target, 1/nm²
        target: f64,
        /// the density it must exceed, 1/nm²
        current: f64,
    },
}

/// One recorded state of the packing.
#[derive(Debug, Clone, PartialEq)]
pub struct PackedState {
    /// the target density, tubes/nm²
    pub density: f64,
    /// the packed turf in its periodic box (each tube's base wrapped into the box)
    pub turf: Turf,
    /// smallest tube–tube surface gap over all periodic images (radius r_o), nm
    pub min_gap: f64,
    /// largest joint gap (distance between a joint's two anchors), nm
    pub joint_gap: f64,
    /// rapier steps since the start
    pub steps: usize,
    /// wall time since the start (set-up included), s
    pub wall_s: f64,
    /// a target density reached and held (false: the last state checked before the packing
    /// stopped)
    pub at_target: bool,
}

/// The packing's recorded states and how it ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Packing {
    /// one state per target density reached
    pub states: Vec<PackedState>,
    /// why the packing stopped before the last target (`None`: all reached)
    pub stopped: Option<String>,
    /// real bodies and ghosts in the rapier world
    pub bodies: (usize, usize),
    /// the mass and rotational inertia of a body (rapier units)
    pub mass: (f64, f64),
}

/// One tube as rapier bodies: body j is segment j (nodes j, j + 1).
struct Chain {
    bodies: Vec<RigidBodyHandle>,
    /// each segment's end points in its body frame (bottom, top)
    ends: Vec<(Vector, Vector)>,
    /// natural curvature binormals of vertices 1 … n − 1
    natural: Vec<Vector3<f64>>,
    /// bending weights K/(ℓ_{i−1} + ℓ_i) of vertices 1 … n − 1, aJ
    weight: Vec<f64>,
    radius_outer: f64,
    radius_inner: f64,
}

/// A ghost: the image of `body` shifted by `shift` box periods.
struct Ghost {
    handle: RigidBodyHandle,
    body: RigidBodyHandle,
    shift: [f64; 2],
}

fn na(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

fn gl(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

const REAL: Group = Group::GROUP_1;
const IMAGE: Group = Group::GROUP_2;

/// The rapier world of a turf being packed.
struct World {
    world: PhysicsWorld,
    chains: Vec<Chain>,
    ghosts: Vec<Ghost>,
    lx: f64,
    ly: f64,
    /// mass and rotational inertia of every free body
    mass: (f64, f64),
    bending: Bending,
}

/// Shift each tube by whole periods so that its base lies in [0, L_x) × [0, L_y).
fn wrap_tubes(tubes: &mut [Tube], lx: f64, ly: f64) {
    for t in tubes {
        let Some(&b) = t.nodes.first() else { continue };
        let (dx, dy) = (-(b[0] / lx).floor() * lx, -(b[1] / ly).floor() * ly);
        for n in &mut t.nodes {
            n[0] += dx;
            n[1] += dy;
        }
    }
}

impl World {
    fn build(
        turf: &Turf,
        youngs: f64,
        p: &PackingParams,
        l_min: f64,
    ) -> Result<Self, PackingError> {
        let (Some(lx), Some(ly)) = (turf.periodic.lx, turf.periodic.ly) else {
            return Err(PackingError::NotPeriodic);
        };
        let mut tubes = turf.tubes.clone();
        wrap_tubes(&mut tubes, lx, ly);
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        let ip = &mut world.integration_parameters;
        ip.num_solver_iterations = p.solver_iterations.max(1);
        // lengths in nm: allowed penetration 0.01 nm, corrective speed 0.1 nm per step
        ip.length_unit = 2.0;
        let dt = ip.dt;
        let omega = p.stability / dt;
        let (mut k_rot, mut l_max) = (0.0f64, 0.0f64);
        for t in &tubes {
            let s = RodStiffness::hollow_tube(youngs, t.radius_outer, t.radius_inner);
            for w in t.nodes.windows(2) {
                let l = (Vector::from(w[1]) - Vector::from(w[0])).length();
                k_rot = k_rot.max(16.0 * s.bending / l);
                l_max = l_max.max(l);
            }
        }
        let inertia = k_rot / (omega * omega);
        let mass = 4.0 * inertia / (l_max * l_max).max(f64::MIN_POSITIVE);
        let real_groups = InteractionGroups::new(REAL, REAL | IMAGE, InteractionTestMode::And);
        let mut chains = Vec::with_capacity(tubes.len());
        for (i, t) in tubes.iter().enumerate() {
            if t.nodes.len() < 3 {
                return Err(PackingError::ShortTube {
                    tube: i,
                    segments: t.nodes.len().saturating_sub(1),
                });
            }
            let s = RodStiffness::hollow_tube(youngs, t.radius_outer, t.radius_inner);
            let radius = t.radius_outer + 0.5 * p.clearance;
            let pts: Vec<Vector> = t.nodes.iter().map(|&a| Vector::from(a)).collect();
            let mut bodies: Vec<RigidBodyHandle> = Vec::new();
            let mut ends: Vec<(Vector, Vector)> = Vec::new();
            for (j, w) in pts.windows(2).enumerate() {
                let mid = 0.5 * (w[0] + w[1]);
                let (a, b) = (w[0] - mid, w[1] - mid);
                let mut builder = RigidBodyBuilder::dynamic()
                    .additional_mass_properties(MassProperties::new(
                        Vector::ZERO,
                        mass,
                        Vector::splat(inertia),
                    ))
                    .linear_damping(p.damping)
                    .angular_damping(p.damping)
                    .can_sleep(false);
                if j == 0 {
                    // the clamp slides on the substrate: no rotation, no lift
                    builder = builder
                        .lock_rotations()
                        .enabled_translations(true, true, false);
                }
                let collider = ColliderBuilder::capsule_from_endpoints(a, b, radius)
                    .density(0.0)
                    .friction(0.0)
                    .collision_groups(real_groups);
                let (h, _) = world.insert(builder.translation(mid), collider);
                if let (Some(&prev), Some(&(bot_prev, top_prev))) = (bodies.last(), ends.last()) {
                    let mut joint = SphericalJointBuilder::new()
                        .local_anchor1(top_prev)
                        .local_anchor2(a)
                        .contacts_enabled(false);
                    if p.bending == Bending::JointSprings {
                        // W ≈ K/(ℓ_e + ℓ_f) φ² for small angles: a spring K/ℓ̄ per radian
                        let l_mean = 0.5 * ((top_prev - bot_prev).length() + (b - a).length());
                        let k = s.bending / l_mean;
                        let c = 2.0 * (k * inertia).sqrt();
                        for axis in [JointAxis::AngX, JointAxis::AngY, JointAxis::AngZ] {
                            joint = joint
                                .motor_model(axis, MotorModel::ForceBased)
                                .motor_position(axis, 0.0, k, c);
                        }
                    }
                    world.insert_impulse_joint(prev, h, joint);
                }
                bodies.push(h);
                ends.push((a, b));
            }
            let edges: Vec<Vector3<f64>> = pts.windows(2).map(|w| na(w[1] - w[0])).collect();
            chains.push(Chain {
                bodies,
                ends,
                natural: edges
                    .windows(2)
                    .map(|e| curvature_binormal(&e[0], &e[1]))
                    .collect(),
                weight: edges
                    .windows(2)
                    .map(|e| s.bending / (e[0].norm() + e[1].norm()))
                    .collect(),
                radius_outer: t.radius_outer,
                radius_inner: t.radius_inner,
            });
        }
        let mut w = World {
            world,
            chains,
            ghosts: Vec::new(),
            lx,
            ly,
            mass: (mass, inertia),
            bending: p.bending,
        };
        w.add_ghosts(&tubes, p, l_min);
        Ok(w)
    }

    /// Ghosts of every body at every image shift that can come within reach of the turf, in
    /// box-relative coordinates, for the smallest box side `l_min` of the run.
    fn add_ghosts(&mut self, tubes: &[Tube], p: &PackingParams, l_min: f64) {
        let (lx, ly) = (self.lx, self.ly);
        let r_max = tubes.iter().map(|t| t.radius_outer).fold(0.0, f64::max) + p.clearance;
        // reach: two capsules plus room for the tubes to move, relative to the smallest box
        let margin = (2.0 * r_max + 50.0) / l_min;
        let rel = |v: Vector| [v.x / lx, v.y / ly];
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for t in tubes {
            for n in &t.nodes {
                let u = rel(Vector::from(*n));
                for d in 0..2 {
                    lo[d] = lo[d].min(u[d]);
                    hi[d] = hi[d].max(u[d]);
                }
            }
        }
        let reach = |d: usize| ((hi[d] - lo[d]) + 2.0 * margin).ceil() as i64;
        let (kx, ky) = (reach(0), reach(1));
        let groups = InteractionGroups::new(IMAGE, REAL, InteractionTestMode::And);
        for (t, c) in tubes.iter().zip(&self.chains) {
            for (j, w) in t.nodes.windows(2).enumerate() {
                let (ua, ub) = (rel(Vector::from(w[0])), rel(Vector::from(w[1])));
                let body = c.bodies[j];
                let (a, b) = c.ends[j];
                let radius = t.radius_outer + 0.5 * p.clearance;
                for sx in -kx..=kx {
                    for sy in -ky..=ky {
                        if sx == 0 && sy == 0 {
                            continue;
                        }
                        let s = [sx as f64, sy as f64];
                        let near = (0..2).all(|d| {
                            let (smin, smax) = (ua[d].min(ub[d]) + s[d], ua[d].max(ub[d]) + s[d]);
                            smax > lo[d] - margin && smin < hi[d] + margin
                        });
                        if !near {
                            continue;
                        }
                        let pose = *self.world.bodies[body].position();
                        let ghost = RigidBodyBuilder::kinematic_position_based()
                            .translation(pose.translation + Vector::new(s[0] * lx, s[1] * ly, 0.0));
                        let collider = ColliderBuilder::capsule_from_endpoints(a, b, radius)
                            .density(0.0)
                            .friction(0.0)
                            .collision_groups(groups);
                        let (handle, _) = self.world.insert(ghost, collider);
                        self.ghosts.push(Ghost {
                            handle,
                            body,
                            shift: s,
                        });
                    }
                }
            }
        }
    }

    /// Remap every body's centre laterally by the factor `s` and the box with it.
    fn remap(&mut self, s: f64) {
        self.lx *= s;
        self.ly *= s;
        for c in &self.chains {
            for &h in &c.bodies {
                let rb = &mut self.world.bodies[h];
                let t = rb.translation();
                rb.set_translation(Vector::new(s * t.x, s * t.y, t.z), true);
            }
        }
    }

    /// Move each ghost onto its body's image (a teleport: ghosts carry no velocity).
    fn place_ghosts(&mut self) {
        for g in &self.ghosts {
            let pose = *self.world.bodies[g.body].position();
            let offset = Vector::new(g.shift[0] * self.lx, g.shift[1] * self.ly, 0.0);
            let ghost = &mut self.world.bodies[g.handle];
            ghost.set_position(
                Pose::from_parts(pose.translation + offset, pose.rotation),
                true,
            );
        }
    }

    /// Bending torques of the current shape on every free segment.
    fn apply_bending(&mut self) {
        for c in &self.chains {
            let n = c.bodies.len();
            let edges: Vec<Vector3<f64>> = c
                .bodies
                .iter()
                .zip(&c.ends)
                .map(|(&h, &(a, b))| na(self.world.bodies[h].rotation() * (b - a)))
                .collect();
            let mut torque = vec![Vector3::zeros(); n];
            for i in 1..n {
                let (e, f) = (&edges[i - 1], &edges[i]);
                let (_, ge, gf) = bend_vertex_gradient(e, f, &c.natural[i - 1], c.weight[i - 1]);
                // δe = δθ × e gives δW = (e × ∂W/∂e)·δθ, so τ = −e × ∂W/∂e = ∂W/∂e × e
                torque[i - 1] += ge.cross(e);
                torque[i] += gf.cross(f);
            }
            for (&h, t) in c.bodies.iter().zip(&torque).skip(1) {
                let rb = &mut self.world.bodies[h];
                rb.reset_forces(false);
                rb.add_torque(gl(t), true);
            }
        }
    }

    /// The deepest overlap of two tube surfaces among rapier's contacts, nm (≤ 0: none):
    /// the capsules' penetration less the clearance they carry.
    fn deepest_overlap(&self, clearance: f64) -> f64 {
        self.world
            .narrow_phase
            .contact_pairs()
            .filter_map(|c| c.find_deepest_contact())
            .map(|(_, c)| -c.dist - clearance)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    fn step(&mut self, remap: Option<f64>) {
        if let Some(s) = remap {
            self.remap(s);
        }
        if self.bending == Bending::Torques {
            self.apply_bending();
        }
        self.place_ghosts();
        self.world.step();
    }

    /// The turf of the current state (nodes at the joints' midpoints) and the largest joint gap.
    fn turf(&self) -> (Turf, f64) {
        let mut gap = 0.0f64;
        let mut tubes = Vec::with_capacity(self.chains.len());
        for c in &self.chains {
            let seg: Vec<(Vector, Vector)> = c
                .bodies
                .iter()
                .zip(&c.ends)
                .map(|(&h, &(a, b))| {
                    let pose = self.world.bodies[h].position();
                    (pose.transform_point(a), pose.transform_point(b))
                })
                .collect();
            let mut nodes = Vec::with_capacity(seg.len() + 1);
            nodes.push(seg[0].0.to_array());
            for j in 0..seg.len() {
                let top = seg[j].1;
                let node = match seg.get(j + 1) {
                    // the clamped pair (nodes 0, 1) stays exact: the base segment stays rigid
                    Some(next) if j > 0 => {
                        gap = gap.max((next.0 - top).length());
                        0.5 * (top + next.0)
                    }
                    Some(next) => {
                        gap = gap.max((next.0 - top).length());
                        top
                    }
                    None => top,
                };
                nodes.push(node.to_array());
            }
            tubes.push(Tube {
                nodes,
                radius_outer: c.radius_outer,
                radius_inner: c.radius_inner,
            });
        }
        wrap_tubes(&mut tubes, self.lx, self.ly);
        let turf = Turf {
            tubes,
            periodic: PeriodicBox {
                lx: Some(self.lx),
                ly: Some(self.ly),
            },
        };
        (turf, gap)
    }
}

fn area(t: &Turf) -> f64 {
    t.periodic.lx.unwrap_or(f64::INFINITY) * t.periodic.ly.unwrap_or(f64::INFINITY)
}

/// Pack `turf` (tubes of Young's modulus `youngs`, GPa) towards each density of `p` in turn;
/// stop at the first joint wider than `max_joint_gap` or overlap deeper than `max_overlap`.
pub fn pack_turf(turf: &Turf, youngs: f64, p: &PackingParams) -> Result<Packing, PackingError> {
    let start = Instant::now();
    let (Some(lx0), Some(ly0)) = (turf.periodic.lx, turf.periodic.ly) else {
        return Err(PackingError::NotPeriodic);
    };
    let n = turf.tubes.len() as f64;
    let mut current = n / (lx0 * ly0);
    for &target in &p.densities {
        if !(target.is_finite() && target > current) {
            return Err(PackingError::Target { target, current });
        }
        current = target;
    }
    let rho0 = n / (lx0 * ly0);
    let l_min = lx0.min(ly0) * (rho0 / current).sqrt();
    let mut w = World::build(turf, youngs, p, l_min)?;
    let bodies = (w.world.bodies.len() - w.ghosts.len(), w.ghosts.len());
    let mass = w.mass;
    let s = 1.0 - p.shrink_per_step.clamp(1e-8, 0.5);
    let every = p.check_every.max(1);
    let mut steps = 0usize;
    let mut states = Vec::new();
    let mut stopped = None;
    let record = |w: &World, steps: usize, at_target: bool| {
        let (packed, joint_gap) = w.turf();
        let (min_gap, _) = min_surface_gap(&packed);
        PackedState {
            density: n / (w.lx * w.ly),
            turf: packed,
            min_gap,
            joint_gap,
            steps,
            wall_s: start.elapsed().as_secs_f64(),
            at_target,
        }
    };
    // the last state that passed the checks: (turf, joint gap, steps, wall)
    let mut last_good: Option<(Turf, f64, usize, f64)> = None;
    // steps since an overlap paused the remapping (0: not paused)
    let mut paused = 0usize;
    'targets: for &target in &p.densities {
        let l_target = lx0 * (rho0 / target).sqrt();
        let mut hold = 0;
        while hold < p.hold_steps || w.lx > l_target {
            if paused > 0 {
                w.step(None);
                paused += 1;
            } else if w.lx > l_target {
                w.step(Some((l_target / w.lx).max(s)));
            } else {
                w.step(None);
                hold += 1;
            }
            steps += 1;
            if steps % every != 0 {
                continue;
            }
            let (packed, gap) = w.turf();
            let overlap = w.deepest_overlap(p.clearance);
            if std::env::var_os("TURF_PACK_TRACE").is_some() {
                eprintln!(
                    "step {steps} box {:.2} joint gap {gap:.3e} overlap {overlap:.3}",
                    w.lx
                );
            }
            // an overlap pauses the remapping until the contacts have pushed it below half
            // the limit; one that outlasts `pause_steps` means the tubes cannot make room
            if paused == 0 && overlap > p.max_overlap {
                paused = 1;
            } else if paused > 0 && overlap <= 0.5 * p.max_overlap {
                paused = 0;
            }
            // a NaN gap (a blown-up chain) stops the packing too
            let why = if gap.is_nan() || gap > p.max_joint_gap {
                Some(format!("a joint opened {gap:.3} nm"))
            } else if paused > p.pause_steps {
                Some(format!(
                    "tube surfaces still overlap by {overlap:.3} nm after {} steps without \
                     remapping (jammed)",
                    paused - 1
                ))
            } else {
                None
            };
            if let Some(why) = why {
                stopped = Some(format!(
                    "{why} at {:.4e} /nm² (box {:.2} nm), step {steps}",
                    n / (w.lx * w.ly),
                    w.lx
                ));
                if let Some((turf, joint_gap, steps, wall_s)) = last_good.take() {
                    let (min_gap, _) = min_surface_gap(&turf);
                    states.push(PackedState {
                        density: n / area(&turf),
                        turf,
                        min_gap,
                        joint_gap,
                        steps,
                        wall_s,
                        at_target: false,
                    });
                }
                break 'targets;
            }
            if paused == 0 {
                last_good = Some((packed, gap, steps, start.elapsed().as_secs_f64()));
            }
        }
        states.push(record(&w, steps, true));
    }
    Ok(Packing {
        states,
        stopped,
        bodies,
        mass,
    })
}

/// Where the smallest gap of [`min_surface_gap`] lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GapPair {
    /// the two tubes
    pub tubes: (usize, usize),
    /// the image shift of the second, in box periods
    pub shift: [i64; 2],
    /// the closest point on the first tube's axis, nm
    pub at: [f64; 3],
}

/// Smallest surface gap (nm) between the tubes of `turf` over all periodic images (any shift,
/// not only the nearest), axes as segments with the tubes' outer radii; a tube with its own
/// image counts, segments of one tube with each other do not. Negative: interpenetration. Also
/// the pair of tubes where it occurs.
pub fn min_surface_gap(turf: &Turf) -> (f64, Option<GapPair>) {
    min_surface_gap_beyond(turf, 0)
}

/// [`min_surface_gap`] over the image pairs whose shift is at least `min_shift` periods along
/// x or y (`min_shift` = 2: the pairs a search of the shifts −1, 0, 1 would miss).
pub fn min_surface_gap_beyond(turf: &Turf, min_shift: i64) -> (f64, Option<GapPair>) {
    let (lx, ly) = (
        turf.periodic.lx.unwrap_or(f64::INFINITY),
        turf.periodic.ly.unwrap_or(f64::INFINITY),
    );
    struct Seg {
        tube: usize,
        a: Vector,
        b: Vector,
        r: f64,
        lo: [f64; 2],
        hi: [f64; 2],
    }
    let segs: Vec<Seg> = turf
        .tubes
        .iter()
        .enumerate()
        .flat_map(|(i, t)| {
            t.nodes.windows(2).map(move |w| {
                let (a, b) = (Vector::from(w[0]), Vector::from(w[1]));
                Seg {
                    tube: i,
                    a,
                    b,
                    r: t.radius_outer,
                    lo: [a.x.min(b.x), a.y.min(b.y)],
                    hi: [a.x.max(b.x), a.y.max(b.y)],
                }
            })
        })
        .collect();
    // only gaps below this are resolved exactly (anything larger is "no contact")
    const FAR: f64 = 50.0;
    let range = |lo_a: f64, hi_a: f64, lo_b: f64, hi_b: f64, l: f64, cut: f64| {
        if !l.is_finite() {
            return (0, 0);
        }
        // shifts k with [lo_b + kl, hi_b + kl] within cut of [lo_a, hi_a]
        (
            ((lo_a - hi_b - cut) / l).ceil() as i64,
            ((hi_a - lo_b + cut) / l).floor() as i64,
        )
    };
    let mut best = (f64::INFINITY, None);
    for (ia, a) in segs.iter().enumerate() {
        for b in &segs[ia..] {
            let cut = a.r + b.r + FAR;
            let (x0, x1) = range(a.lo[0], a.hi[0], b.lo[0], b.hi[0], lx, cut);
            let (y0, y1) = range(a.lo[1], a.hi[1], b.lo[1], b.hi[1], ly, cut);
            for kx in x0..=x1 {
                for ky in y0..=y1 {
                    // a tube's own shape is the rod's business, not a contact
                    if a.tube == b.tube && kx == 0 && ky == 0 || kx.abs().max(ky.abs()) < min_shift
                    {
                        continue;
                    }
                    let off = Vector::new(kx as f64 * lx, ky as f64 * ly, 0.0);
                    let off = Vector::new(
                        if off.x.is_finite() { off.x } else { 0.0 },
                        if off.y.is_finite() { off.y } else { 0.0 },
                        0.0,
                    );
                    let (b0, b1) = (b.a + off, b.b + off);
                    let (la, lb) =
                        closest_points_segment_segment_with_locations_nD((&a.a, &a.b), (&b0, &b1));
                    let [ua, va] = la.barycentric_coordinates();
                    let [ub, vb] = lb.barycentric_coordinates();
                    let d = ((a.a * ua + a.b * va) - (b0 * ub + b1 * vb)).length();
                    let gap = d - a.r - b.r;
                    if gap < best.0 {
                        let p = a.a * ua + a.b * va;
                        best = (
                            gap,
                            Some(GapPair {
                                tubes: (a.tube, b.tube),
                                shift: [kx, ky],
                                at: p.to_array(),
                            }),
                        );
                    }
                }
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight vertical tube of `segments` segments of 200 nm at (x, y).
    fn tube(x: f64, y: f64, segments: usize) -> Tube {
        Tube {
            nodes: (0..=segments).map(|k| [x, y, 200.0 * k as f64]).collect(),
            radius_outer: 20.0,
            radius_inner: 17.3,
        }
    }

    /// The gap check against a hand count: two vertical tubes 70 nm apart in a 120 nm box meet
    /// their images 50 nm away (gap 10 nm); in a 300 nm box the nearest is the tube itself
    /// (gap 30 nm).
    #[test]
    fn min_surface_gap_counts_images() {
        let mut turf = Turf {
            tubes: vec![tube(10.0, 10.0, 3), tube(80.0, 10.0, 3)],
            periodic: PeriodicBox {
                lx: Some(120.0),
                ly: Some(1000.0),
            },
        };
        let (g, at) = min_surface_gap(&turf);
        assert!((g - 10.0).abs() < 1e-9, "gap {g}");
        assert_eq!(at.map(|a| a.shift[0].abs()), Some(1));
        turf.periodic.lx = Some(300.0);
        let (g, at) = min_surface_gap(&turf);
        assert!((g - 30.0).abs() < 1e-9, "gap {g}");
        assert_eq!(at.map(|a| a.shift), Some([0, 0]));
    }

    /// Two tubes whose tops lean towards each other (60 nm apart), squeezed from a 300 nm to a
    /// 120 nm box: remapped alone, the tops would sit 24 nm apart, 16 nm into each other:
    /// rapier's contacts keep the capsules apart (gap ≥ −0.5 nm), the joints closed, the
    /// clamps upright on the substrate.
    #[test]
    fn packing_keeps_two_tubes_apart() {
        let mut a = tube(75.0, 150.0, 4);
        let mut b = tube(225.0, 150.0, 4);
        for (k, n) in a.nodes.iter_mut().enumerate().skip(2) {
            n[0] += 15.0 * (k - 1) as f64;
        }
        for (k, n) in b.nodes.iter_mut().enumerate().skip(2) {
            n[0] -= 15.0 * (k - 1) as f64;
        }
        let turf = Turf {
            tubes: vec![a, b],
            periodic: PeriodicBox {
                lx: Some(300.0),
                ly: Some(300.0),
            },
        };
        let rho0 = 2.0 / 9e4;
        let p = PackingParams {
            densities: vec![rho0 * 2.5 * 2.5],
            shrink_per_step: 2e-3,
            hold_steps: 200,
            ..PackingParams::default()
        };
        let out = pack_turf(&turf, 400.0, &p).expect("packing");
        assert!(out.stopped.is_none(), "{:?}", out.stopped);
        let s = &out.states[0];
        assert!((s.turf.periodic.lx.unwrap_or(0.0) - 120.0).abs() < 1e-6);
        assert!(s.min_gap > -0.5, "tubes overlap: gap {}", s.min_gap);
        assert!(s.joint_gap < 0.1, "joint gap {}", s.joint_gap);
        // the clamp slides but stays on the substrate, upright
        for t in &s.turf.tubes {
            let (b, c) = (t.nodes[0], t.nodes[1]);
            assert!(b[2].abs() < 1e-9, "base lifted to {}", b[2]);
            assert!((c[0] - b[0]).abs() < 1e-6 && (c[1] - b[1]).abs() < 1e-6);
        }
    }

    #[test]
    fn refuses_a_target_below_the_turf() {
        let turf = Turf {
            tubes: vec![tube(10.0, 10.0, 3)],
            periodic: PeriodicBox {
                lx: Some(100.0),
                ly: Some(100.0),
            },
        };
        let p = PackingParams {
            densities: vec![1e-5],
            ..PackingParams::default()
        };
        assert!(matches!(
            pack_turf(&turf, 400.0, &p),
            Err(PackingError::Target { .. })
        ));
    }
}
