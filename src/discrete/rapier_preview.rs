//! A dynamic preview of the platen compression on rigid-body chains (rapier3d-f64, cargo
//! feature `rapier`): each tube a chain of rigid capsules (one per segment of the elastica
//! chain, radius r_o) joined by spherical joints, the base segment fixed (the clamp), capsule
//! contacts between tubes by rapier, and every force of the static model that does not stretch
//! a segment applied as an external load each step:
//!
//! - bending: the discrete elastica's vertex energy W_i = K/(ℓ_{i−1} + ℓ_i) |κb_i − κb_i⁰|²
//!   ([`super::rod_kernels::bend_vertex_gradient`]) on the rigid segments' edge vectors e_j;
//!   the torque on segment j is τ_j = ∂W/∂e_j × e_j (δe_j = δθ_j × e_j), so the joints carry
//!   bending springs of stiffness ≈ 4K/ℓ;
//! - van der Waals (turf's own [`super::vdw_term::VdwTerm`]), substrate and platen
//!   ([`super::platen::Wall`]): −∂E/∂x at each node, applied at the top end of the segment
//!   below it.
//!
//! Quasi-statics by mass scaling (dynamic relaxation): with the step dt = 1 (pseudo-time), each
//! body gets the mass and rotational inertia that put the stiffest spring it can meet — a
//! parallel van der Waals contact over the whole segment, the bending springs — at ω dt =
//! `stability`, and viscous damping. The platen moves down one strain increment over
//! `steps_per_increment` steps, then holds for `hold_steps`; the stress is the platen's force
//! F/A at the end of the hold, as in [`super::drive`].
//!
//! Segments are inextensible here (rigid bodies): the static engine's stretching energy is
//! absent, which at EA/K ≈ 6×10⁻³ nm⁻² (the turf tube) matters only in tube buckling modes.

use super::model::TurfSystem;
use super::rod::RodStiffness;
use super::rod_kernels::{bend_vertex_gradient, curvature_binormal};
use super::turf::Turf;
use crate::discrete::energy::EnergyTerm;
use nalgebra::Vector3;
use rapier3d_f64::prelude::*;
use std::time::Instant;

/// Settings of the preview.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreviewParams {
    /// rapier steps without the platen before the drive (contacts form)
    pub relax_steps: usize,
    /// rapier steps over which the platen moves one strain increment
    pub steps_per_increment: usize,
    /// rapier steps at the increment's platen height before the stress is read
    pub hold_steps: usize,
    /// ω dt of the stiffest spring a body can meet (mass scaling), < 2 for stability
    pub stability: f64,
    /// linear and angular damping (rapier's damping factor, per unit pseudo-time)
    pub damping: f64,
    /// keep rapier's capsule–capsule contacts between tubes (non-penetration)
    pub contacts: bool,
    /// joints as a reduced-coordinate multibody (exact joints) instead of impulse joints
    pub multibody: bool,
    /// rapier's constraint-solver iterations per step (its default: 4)
    pub solver_iterations: usize,
}

impl Default for PreviewParams {
    fn default() -> Self {
        PreviewParams {
            relax_steps: 2000,
            steps_per_increment: 200,
            hold_steps: 200,
            stability: 0.5,
            damping: 0.05,
            contacts: true,
            multibody: false,
            solver_iterations: 4,
        }
    }
}

/// One increment of the preview.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreviewStep {
    /// nominal strain (H₀ − H)/H₀
    pub strain: f64,
    /// nominal stress F/A, GPa
    pub stress: f64,
    /// smallest tube–tube surface gap, nm (negative: interpenetration)
    pub min_gap: f64,
    /// largest joint gap (distance between the two anchors of a joint), nm
    pub joint_error: f64,
    /// top of the turf, max(z + r) over the free nodes, nm
    pub top: f64,
}

/// The preview's curve and cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Preview {
    /// the relaxed state (ε = 0) then one record per increment
    pub steps: Vec<PreviewStep>,
    /// rapier steps taken in all
    pub rapier_steps: usize,
    /// wall time of the whole preview (set-up, relaxation, drive), s
    pub wall_s: f64,
    /// the translational mass and rotational inertia of a body (pseudo-units)
    pub mass: (f64, f64),
}

/// One tube as rapier bodies: body j is segment j (nodes j, j + 1).
struct Chain {
    first_node: usize,
    bodies: Vec<RigidBodyHandle>,
    /// each segment's end points in its body frame (bottom, top)
    ends: Vec<(Vector, Vector)>,
    /// natural curvature binormals of vertices 1 … n − 1 (lab frame)
    natural: Vec<Vector3<f64>>,
    /// bending weights K/(ℓ_{i−1} + ℓ_i) of vertices 1 … n − 1, aJ
    weight: Vec<f64>,
}

fn na(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

fn gl(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn node(x: &[f64], n: usize) -> Vector3<f64> {
    Vector3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2])
}

/// Stiffness (nN/nm) of a parallel van der Waals contact over `length` nm at the equilibrium
/// gap: d²(E/L)/dd² by central differences of the reference line energy.
fn contact_stiffness(sys: &TurfSystem, r_sum: f64, length: f64) -> f64 {
    let Some(v) = &sys.model.vdw else {
        return 0.0;
    };
    let pot = v.potential();
    let h = 1e-3;
    // the minimum of the parallel line energy, then its curvature there
    let d0 = (0..400)
        .map(|k| r_sum + 0.05 + 0.005 * k as f64)
        .min_by(|a, b| {
            pot.parallel_line_energy(*a, r_sum)
                .0
                .total_cmp(&pot.parallel_line_energy(*b, r_sum).0)
        })
        .unwrap_or(r_sum);
    let k = (0..40)
        .map(|i| d0 - 0.2 + 0.01 * i as f64)
        .map(|d| {
            (pot.parallel_line_energy(d + h, r_sum).1 - pot.parallel_line_energy(d - h, r_sum).1)
                / (2.0 * h)
        })
        .fold(0.0f64, f64::max);
    k * length
}

/// The rapier world of a turf.
struct World {
    world: PhysicsWorld,
    chains: Vec<Chain>,
}

impl World {
    fn build(turf: &Turf, sys: &TurfSystem, youngs: f64, p: &PreviewParams) -> (Self, (f64, f64)) {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        world.integration_parameters.dt = 1.0;
        world.integration_parameters.num_solver_iterations = p.solver_iterations;
        let layout = turf.layout();
        // mass scaling: the stiffest spring a body meets at ω dt = stability
        let (mut k_tr, mut k_rot) = (0.0f64, 0.0f64);
        let mut per_length: Vec<(f64, f64)> = Vec::new();
        for t in &turf.tubes {
            let s = RodStiffness::hollow_tube(youngs, t.radius_outer, t.radius_inner);
            let r_sum = 2.0 * t.radius_outer;
            let k_line = match per_length.iter().find(|(r, _)| *r == r_sum) {
                Some(&(_, k)) => k,
                None => {
                    let k = contact_stiffness(sys, r_sum, 1.0);
                    per_length.push((r_sum, k));
                    k
                }
            };
            for w in t.nodes.windows(2) {
                let l = (na(Vector::from(w[1])) - na(Vector::from(w[0]))).norm();
                k_rot = k_rot.max(16.0 * s.bending / l);
                k_tr = k_tr.max(k_line * l);
                k_tr = k_tr.max(2.0 * sys.wall_stiffness * 0.5);
            }
        }
        let s2 = p.stability * p.stability;
        // forces at a segment's ends turn it about its centre with the lever ℓ/2
        let l_max = turf
            .tubes
            .iter()
            .flat_map(|t| t.nodes.windows(2))
            .map(|w| (na(Vector::from(w[1])) - na(Vector::from(w[0]))).norm())
            .fold(0.0f64, f64::max);
        let mass = k_tr / s2;
        let inertia = (k_rot / s2).max(0.25 * mass * l_max * l_max);
        let mut chains = Vec::with_capacity(turf.tubes.len());
        for (t, l) in turf.tubes.iter().zip(&layout) {
            let s = RodStiffness::hollow_tube(youngs, t.radius_outer, t.radius_inner);
            let pts: Vec<Vector> = t.nodes.iter().map(|&a| Vector::from(a)).collect();
            let mut bodies = Vec::new();
            let mut ends = Vec::new();
            for (j, w) in pts.windows(2).enumerate() {
                let mid = 0.5 * (w[0] + w[1]);
                let (a, b) = (w[0] - mid, w[1] - mid);
                let builder = if j == 0 {
                    RigidBodyBuilder::fixed()
                } else {
                    RigidBodyBuilder::dynamic()
                        .additional_mass_properties(MassProperties::new(
                            Vector::ZERO,
                            mass,
                            Vector::splat(inertia),
                        ))
                        .linear_damping(p.damping)
                        .angular_damping(p.damping)
                        .can_sleep(false)
                };
                let collider = ColliderBuilder::capsule_from_endpoints(a, b, t.radius_outer)
                    .density(0.0)
                    .friction(0.0)
                    .collision_groups(if p.contacts {
                        InteractionGroups::all()
                    } else {
                        InteractionGroups::none()
                    });
                let (h, _) = world.insert(builder.translation(mid), collider);
                if let Some(&prev) = bodies.last() {
                    let (_, top_prev): (Vector, Vector) = ends[j - 1];
                    let joint = SphericalJointBuilder::new()
                        .local_anchor1(top_prev)
                        .local_anchor2(a)
                        .contacts_enabled(false);
                    if p.multibody {
                        world.insert_multibody_joint(prev, h, joint);
                    } else {
                        world.insert_impulse_joint(prev, h, joint);
                    }
                }
                bodies.push(h);
                ends.push((a, b));
            }
            let edges: Vec<Vector3<f64>> = pts.windows(2).map(|w| na(w[1] - w[0])).collect();
            let natural = edges
                .windows(2)
                .map(|e| curvature_binormal(&e[0], &e[1]))
                .collect();
            let weight = edges
                .windows(2)
                .map(|e| s.bending / (e[0].norm() + e[1].norm()))
                .collect();
            chains.push(Chain {
                first_node: l.first_node,
                bodies,
                ends,
                natural,
                weight,
            });
        }
        (World { world, chains }, (mass, inertia))
    }

    /// Node coordinates of the chains (node j + 1 = top of segment j), and the largest joint gap.
    fn coordinates(&self, x: &mut [f64]) -> f64 {
        let mut gap = 0.0f64;
        for c in &self.chains {
            for (j, (&h, &(a, b))) in c.bodies.iter().zip(&c.ends).enumerate() {
                let pose = self.world.bodies[h].position();
                let (pa, pb) = (pose.transform_point(a), pose.transform_point(b));
                let n = c.first_node + j;
                if j == 0 {
                    x[3 * n..3 * n + 3].copy_from_slice(&pa.to_array());
                } else {
                    gap = gap.max((na(pa) - node(x, n)).norm());
                }
                x[3 * (n + 1)..3 * (n + 1) + 3].copy_from_slice(&pb.to_array());
            }
        }
        gap
    }

    /// Apply the loads of configuration `x` (bending torques, −∂E/∂x of van der Waals and walls).
    fn apply_loads(&mut self, sys: &mut TurfSystem, x: &[f64], grad: &mut [f64]) {
        grad.fill(0.0);
        let m = &mut sys.model;
        if let Some(v) = m.vdw.as_mut() {
            v.prepare(x);
            v.energy_gradient(x, grad);
        }
        m.substrate.energy_gradient(x, grad);
        if let Some(p) = &m.platen {
            p.energy_gradient(x, grad);
        }
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
                torque[i - 1] += ge.cross(e);
                torque[i] += gf.cross(f);
            }
            for j in 1..n {
                let rb = &mut self.world.bodies[c.bodies[j]];
                rb.reset_forces(false);
                rb.add_torque(gl(&torque[j]), true);
                let top = c.first_node + j + 1;
                let f = -node(grad, top);
                rb.add_force_at_point(gl(&f), gl(&node(x, top)), true);
            }
        }
    }
}

/// Relax the turf of `sys` (built from `turf`, tubes of Young's modulus `youngs`, GPa) on
/// rapier chains, then compress it to `strain_max` in `increments` equal increments.
pub fn preview_compression(
    turf: &Turf,
    sys: &mut TurfSystem,
    youngs: f64,
    strain_max: f64,
    increments: usize,
    p: &PreviewParams,
) -> Preview {
    let start = Instant::now();
    let (mut w, mass) = World::build(turf, sys, youngs, p);
    let mut x = turf.coordinates();
    let mut grad = vec![0.0; x.len()];
    let mut rapier_steps = 0;
    sys.model.platen = None;
    let mut step = |w: &mut World, sys: &mut TurfSystem, x: &mut Vec<f64>| -> f64 {
        let gap = w.coordinates(x);
        w.apply_loads(sys, x, &mut grad);
        w.world.step();
        rapier_steps += 1;
        gap
    };
    for _ in 0..p.relax_steps {
        step(&mut w, sys, &mut x);
    }
    let mut steps = Vec::new();
    let mut record = |w: &World, sys: &mut TurfSystem, x: &mut Vec<f64>, strain: f64| {
        let joint_error = w.coordinates(x);
        let state = sys.state(x);
        steps.push(PreviewStep {
            strain,
            stress: state.platen_force / sys.area,
            min_gap: state.min_gap,
            joint_error,
            top: sys.height(x),
        });
    };
    w.coordinates(&mut x);
    let h0 = sys.start_height(&x);
    sys.set_platen(h0);
    record(&w, sys, &mut x, 0.0);
    for k in 1..=increments {
        let (e0, e1) = (
            strain_max * (k - 1) as f64 / increments as f64,
            strain_max * k as f64 / increments as f64,
        );
        for s in 1..=p.steps_per_increment {
            let e = e0 + (e1 - e0) * s as f64 / p.steps_per_increment as f64;
            sys.set_platen(h0 * (1.0 - e));
            step(&mut w, sys, &mut x);
        }
        for _ in 0..p.hold_steps {
            step(&mut w, sys, &mut x);
        }
        record(&w, sys, &mut x, e1);
    }
    Preview {
        steps,
        rapier_steps,
        wall_s: start.elapsed().as_secs_f64(),
        mass,
    }
}
