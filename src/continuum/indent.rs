//! The indentation driver: schedule → increments → results. It reads as the algorithm:
//! resolve the sizes from the scene ([`resolve`]), build the mesh and the solid
//! (axis u_r = 0, base bonded u = 0), then for each schedule segment march the indenter depth
//! (and time) in increments, solving each by Newton ([`super::newton`]); a failed increment
//! is halved and retried, a quick one lets the increment grow back. Displacement control:
//! the depth δ(t) follows the segments (approach/load/unload at a rate, hold for a time); the
//! load is P = ∂Π/∂δ. Through a machine spring or under load control ([`super::machine`]) the
//! schedule drives Δ or P̂ instead and δ is an unknown. With adhesion ([`super::adhesion`]) the
//! schedule may start clear of the surface (`start` < 0) and the LJ law replaces the penalty;
//! contact damping, if given, is integrated over each step (except on load-controlled
//! segments) and its dissipation is reported per row against the strain energy. Under load
//! control an unloading segment that finds no equilibrium after every halving has reached the
//! pull-off: the indenter separates there and the run ends ([`IndentResult::separated_nN`]).

use super::adhesion::{self, AdhesionParams};
use super::arclength::{ArcLengthParams, Curve};
use super::assembly::{Assembler, AssemblyStats, Solid};
use super::contact::{Contact, Damping, ProfilePoint, SmoothPenalty, SurfaceLaw};
use super::element::Kinematics;
use super::indenter::Indenter;
use super::machine::{Drive, Driven, Machine};
use super::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
use super::material::linear::LinearElastic;
use super::material::viscoelastic::{validate_prony, PronyTerm, Viscoelastic};
use super::material::{Elastic, Voigt};
use super::mesh::{self, BlockSpec, EdgeZone, Mesh, MeshReport};
use super::newton::{self, NewtonParams};
use super::transfer;
use super::FeError;
use crate::numerics::quadrature::gauss_legendre_unit;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// One segment of the displacement schedule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Segment {
    /// move the indenter to depth `to` (nm) at `rate` (nm/s), deeper or shallower
    Load {
        /// target depth δ, nm
        to: f64,
        /// speed, nm/s (> 0)
        rate: f64,
    },
    /// keep the depth for `time` (s)
    Hold {
        /// duration, s
        time: f64,
    },
    /// as `Load`, named for the way back
    Unload {
        /// target depth δ, nm
        to: f64,
        /// speed, nm/s (> 0)
        rate: f64,
    },
    /// move the indenter (or the drive) towards the surface: a depth in every control
    Approach {
        /// target depth, nm
        to: f64,
        /// speed, nm/s (> 0)
        rate: f64,
    },
}

/// The material: an elastic model and optional Prony terms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialParams {
    /// the elastic model
    pub elastic: Elastic,
    /// Prony terms (empty: elastic, no history)
    #[serde(default)]
    pub prony: Vec<PronyTerm>,
}

/// Mesh sizes; unset ones are derived from the expected contact radius a (from the indenter
/// at the deepest point of the schedule).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MeshParams {
    /// block width, nm (default `size_factor`·a)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// block depth, nm (default `size_factor`·a)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub depth: Option<f64>,
    /// smallest element, nm (default a/`elements_per_radius`; of the order of z₀ with adhesion)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub smallest: Option<f64>,
    /// block size in contact radii (≥ 10; see [`DEFAULT_BLOCK_FACTOR`])
    pub size_factor: f64,
    /// elements across the contact radius in the fine zone
    pub elements_per_radius: f64,
    /// fine zone radius in contact radii
    pub fine_radius: f64,
    /// fine zone depth in contact radii
    pub fine_depth: f64,
    /// size growth per unit distance from the fine zone (see [`DEFAULT_GRADING`])
    pub grading: f64,
    /// refuse a generated mesh of more elements than this
    pub max_elements: usize,
    /// a Gmsh 2.2 mesh to use instead (surface at its top, axis at r = 0)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gmsh_file: Option<std::path::PathBuf>,
    /// a fine zone that follows the contact edge ([`mesh::edge_block`]), remeshed as the edge
    /// moves (with adhesion, the Newton method and a generated mesh); unset: off (validated
    /// at μ = 1, 2 and 5 only, docs/validation-continuum.md)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<bool>,
    /// half-width (and depth) of the adaptive band of smallest elements, in process zones
    /// (see [`DEFAULT_EDGE_ZONE`])
    pub edge_zone: f64,
}

/// Default half-width of the adaptive band of smallest elements around the contact edge, in
/// process zones ℓ (the half-space solver refines ±(2ℓ + 2 % of the radius) around the edge
/// at pull-off, [`crate::halfspace`]; the band is remeshed once the edge has moved by half of
/// it, [`EDGE_SAFE`]).
pub const DEFAULT_EDGE_ZONE: f64 = 4.0;
/// The mesh follows the edge once it has moved beyond the band's edges by more than this
/// fraction of the band's half-width (so it stays ≥ 2ℓ inside the band with the default); a
/// band wider than needed by more than twice this is narrowed.
pub const EDGE_SAFE: f64 = 0.5;
/// The band spans the contact edge (gap below the law's contact gap g_c) out to the outermost
/// gap below this many g_c: as in the half-space solver, a coarse ring at a small gap is
/// unstable on its own (its self-compliance times the law's stiffness exceeds 1) and snaps,
/// pinning the edge and jumping with it; beyond 3g_c the 9-3 law's stiffness is below 1/80 of
/// its peak.
pub const BAND_GAPS: f64 = 3.0;

/// The radii the band must cover on `profile`: from the contact edge to the outermost gap
/// below [`BAND_GAPS`] contact gaps, nm.
fn band_span(contact: &Contact, profile: &[ProfilePoint]) -> (f64, f64) {
    let gc = contact.law.contact_gap();
    (
        contact.radius_below(profile, gc),
        contact.radius_below(profile, BAND_GAPS * gc),
    )
}
/// Remeshes within one increment at most (a jump moves the edge several times as the mesh
/// around it resolves the law; beyond this the increment is accepted on the last mesh).
pub const MAX_REMESHES_PER_INCREMENT: usize = 3;

/// Default block size (width and depth) in expected contact radii. Measured on Hertz
/// (docs/validation-continuum.md): a rigid base at depth L stiffens the load by ≈ 0.63 a/L
/// (1.5 × the 0.42 a/L compliance of PHYSICS.md) and a free side at W softens it, by 14 % at
/// W = 20a; at 200a both are ≈ 0.3 %, for ~10 % more elements than 50a (the quadtree grows
/// only logarithmically with the block).
pub const DEFAULT_BLOCK_FACTOR: f64 = 200.0;
/// Default growth of the element size per unit distance from the fine zone (≈ the size ratio
/// of neighbouring elements minus one). The coarse far field of CST elements stiffens the
/// Hertz load by ≈ 2.5 g² (0.2: +0.5 %, 0.3: +0.8 %).
pub const DEFAULT_GRADING: f64 = 0.2;
/// Default elements across the expected contact radius (PHYSICS.md: ~20).
pub const DEFAULT_ELEMENTS_PER_RADIUS: f64 = 20.0;

impl Default for MeshParams {
    fn default() -> Self {
        MeshParams {
            width: None,
            depth: None,
            smallest: None,
            size_factor: DEFAULT_BLOCK_FACTOR,
            elements_per_radius: DEFAULT_ELEMENTS_PER_RADIUS,
            fine_radius: 1.5,
            fine_depth: 0.5,
            grading: DEFAULT_GRADING,
            max_elements: super::mesh::DEFAULT_MAX_ELEMENTS,
            gmsh_file: None,
            adaptive: None,
            edge_zone: DEFAULT_EDGE_ZONE,
        }
    }
}

/// The repulsive contact law and its quadrature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ContactParams {
    /// penalty stiffness k_n in units of E*/h₀ (E* reduced modulus, h₀ smallest element)
    pub penalty_factor: f64,
    /// penalty range h_r in units of h₀
    pub range_fraction: f64,
    /// Gauss points per surface segment (1 to [`MAX_QUADRATURE_POINTS`])
    pub quadrature_points: usize,
}

/// The most Gauss points per surface segment the contact accepts (beyond, the surface
/// segment's own linear interpolation, not the rule, limits the accuracy).
pub const MAX_QUADRATURE_POINTS: usize = 8;

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams {
            penalty_factor: 100.0,
            range_fraction: 0.01,
            quadrature_points: 2,
        }
    }
}

/// How the schedule is followed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// increments of the control, each solved by Newton (contact damping carries the jumps)
    #[default]
    Newton,
    /// arc-length continuation through the folds ([`super::arclength`]; elastic, undamped)
    Riks,
}

/// Increments and Newton.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SolverParams {
    /// Newton increments or arc-length continuation
    pub method: Method,
    /// arc-length step control (with `method = Riks`)
    pub arclength: ArcLengthParams,
    /// Newton's parameters (also the arc-length corrector's)
    pub newton: NewtonParams,
    /// increments per schedule segment (also the largest increment)
    pub increments: usize,
    /// halvings allowed below the largest increment: the smallest increment is 1/2^max_cutbacks
    /// of it; an increment that fails there stops the run (or, retracting under load control,
    /// separates the indenter)
    pub max_cutbacks: usize,
    /// growth factor of the increment after a quick convergence
    pub growth: f64,
    /// Newton iterations counted as quick (the increment then grows back towards the
    /// segment's size). 8: contact increments typically take 5–8 (the active set settles
    /// over the first iterations); with 5, one cutback at contact onset halved every later
    /// increment of the 30k-element Hertz bench (89 increments instead of 50)
    pub quick_iterations: usize,
}

impl Default for SolverParams {
    fn default() -> Self {
        SolverParams {
            method: Method::Newton,
            arclength: ArcLengthParams::default(),
            newton: NewtonParams::default(),
            increments: 20,
            max_cutbacks: 12,
            growth: 1.5,
            quick_iterations: 8,
        }
    }
}

/// Everything a continuum indentation needs (plain data).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IndentParams {
    /// the rigid indenter
    pub indenter: Indenter,
    /// the specimen's material
    pub material: MaterialParams,
    /// finite or small kinematics
    #[serde(default)]
    pub kinematics: Kinematics,
    /// mesh sizes
    #[serde(default)]
    pub mesh: MeshParams,
    /// the displacement schedule, starting from δ = 0 at t = 0
    pub schedule: Vec<Segment>,
    /// the contact law
    #[serde(default)]
    pub contact: ContactParams,
    /// increments and Newton
    #[serde(default)]
    pub solver: SolverParams,
    /// initial depth (negative: clear of the surface; needs adhesion to matter), nm
    #[serde(default)]
    pub start: f64,
    /// Lennard-Jones adhesion instead of the repulsive penalty
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adhesion: Option<AdhesionParams>,
    /// how the indenter is driven
    #[serde(default)]
    pub machine: Machine,
}

impl IndentParams {
    /// The Hertz check (`scenes/hertz.toml`): a rigid 1 µm sphere into a linear block
    /// (E = 0.7 GPa, ν = 0.3) to δ/R = 0.01 at 10 nm/s and back.
    pub fn hertz_example() -> Self {
        IndentParams {
            indenter: Indenter::Sphere { radius: 1000.0 },
            material: MaterialParams {
                elastic: Elastic::Linear(LinearElastic {
                    youngs: 0.7,
                    poisson: 0.3,
                }),
                prony: vec![],
            },
            kinematics: Kinematics::Finite,
            mesh: MeshParams::default(),
            schedule: vec![
                Segment::Load {
                    to: 10.0,
                    rate: 10.0,
                },
                Segment::Unload {
                    to: 0.0,
                    rate: 10.0,
                },
            ],
            contact: ContactParams::default(),
            solver: SolverParams::default(),
            start: 0.0,
            adhesion: None,
            machine: Machine::Displacement,
        }
    }

    /// The seed's turf indentation (`scenes/hyperfoam_indent.toml`, seed §6.2): the blunt
    /// Berkovich (1.8 µm tip) into the hyperfoam of Table 5.1 (μ = 350 MPa, α = 18.8 for
    /// ε₀ = 0.05, β = 0) relaxing with μ̄ = 0.4, τ = 3 s: load to 200 nm at 10 nm/s, hold 10 s,
    /// unload.
    pub fn hyperfoam_example() -> Self {
        IndentParams {
            indenter: Indenter::berkovich_tangent(1800.0),
            material: MaterialParams {
                elastic: Elastic::Hyperfoam(Hyperfoam {
                    terms: vec![HyperfoamTerm {
                        mu: 0.35,
                        alpha: 18.8,
                        beta: 0.0,
                    }],
                }),
                prony: vec![PronyTerm { g: 0.4, tau: 3.0 }],
            },
            kinematics: Kinematics::Finite,
            mesh: MeshParams {
                size_factor: 20.0,
                ..MeshParams::default()
            },
            schedule: vec![
                Segment::Load {
                    to: 200.0,
                    rate: 10.0,
                },
                Segment::Hold { time: 10.0 },
                Segment::Unload {
                    to: 0.0,
                    rate: 10.0,
                },
            ],
            contact: ContactParams::default(),
            solver: SolverParams::default(),
            start: 0.0,
            adhesion: None,
            machine: Machine::Displacement,
        }
    }
}

/// Bisection steps for [`spring_depth`]: the bracket [0, Δ] shrinks to 2⁻⁶⁰ of Δ.
const SPRING_DEPTH_BISECTIONS: usize = 60;

/// The Hertz depth δ (nm) at which a spring K (nN/nm) driven to Δ (nm) balances the specimen:
/// K(Δ − δ) = (4/3)E*R^(1/2)δ^(3/2) (δ = Δ when Δ ≤ 0). K → ∞ gives δ = Δ, K → 0 the Hertz
/// depth of the load KΔ.
fn spring_depth(drive: f64, stiffness: f64, e_star: f64, radius: f64) -> f64 {
    if !(drive > 0.0) {
        return drive;
    }
    let excess =
        |d: f64| stiffness * (drive - d) - 4.0 / 3.0 * e_star * radius.sqrt() * d.powf(1.5);
    let (mut lo, mut hi) = (0.0, drive);
    for _ in 0..SPRING_DEPTH_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if excess(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The sizes derived from the parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[allow(non_snake_case)] // field names carry their units, as the output columns do
pub struct Resolved {
    /// deepest point of the schedule, nm
    pub max_depth_nm: f64,
    /// expected contact radius there, nm
    pub expected_contact_radius_nm: f64,
    /// the block that was meshed
    pub block: BlockSpec,
    /// initial Young's modulus of the material, GPa
    pub youngs_GPa: f64,
    /// initial Poisson ratio
    pub poisson: f64,
    /// reduced modulus E* = E/(1 − ν²) against a rigid indenter, GPa
    pub reduced_modulus_GPa: f64,
    /// the repulsive law (used without adhesion)
    pub penalty: SmoothPenalty,
    /// with adhesion: the law's process zone E*γ/σ_peak², nm
    #[serde(skip_serializing_if = "Option::is_none")]
    pub process_zone_nm: Option<f64>,
    /// with adhesion: Tabor's μ against the tip radius
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tabor: Option<f64>,
    /// with an adaptive mesh: the band around the contact edge at the start (edge 0)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_zone: Option<EdgeZone>,
}

/// Resolve the derived sizes (and validate the parameters).
pub fn resolve(p: &IndentParams) -> Result<Resolved, FeError> {
    p.indenter.validate().map_err(FeError::Params)?;
    p.material.elastic.validate()?;
    validate_prony(&p.material.prony)?;
    p.machine.validate().map_err(FeError::Params)?;
    if let Some(a) = &p.adhesion {
        a.validate().map_err(FeError::Params)?;
    }
    if p.solver.method == Method::Riks {
        if !p.material.prony.is_empty() {
            return Err(FeError::Params(
                "arc-length continuation traces an elastic curve: Prony relaxation needs the Newton method".into(),
            ));
        }
        if p.adhesion.as_ref().is_some_and(|a| a.damping.is_some()) {
            return Err(FeError::Params(
                "arc-length continuation passes the folds without contact damping: remove the damping".into(),
            ));
        }
    }
    if !p.start.is_finite() {
        return Err(FeError::Params(format!("start depth {} nm", p.start)));
    }
    let (mut depth, mut load) = (p.start, 0.0f64);
    let (mut max_depth, mut max_load) = (p.start, 0.0f64);
    for s in &p.schedule {
        let by_load = p.machine.load_controlled() && !matches!(s, Segment::Approach { .. });
        match *s {
            Segment::Load { to, rate }
            | Segment::Unload { to, rate }
            | Segment::Approach { to, rate } => {
                let now = if by_load { &mut load } else { &mut depth };
                if !(rate > 0.0 && to.is_finite() && to != *now) {
                    return Err(FeError::Params(format!(
                        "schedule segment {s:?}: rate must be positive, the target finite and different from the current {now}"
                    )));
                }
                *now = to;
            }
            Segment::Hold { time } => {
                if !(time > 0.0 && time.is_finite()) {
                    return Err(FeError::Params(format!(
                        "hold time must be positive, got {time} s"
                    )));
                }
            }
        }
        max_depth = max_depth.max(depth);
        max_load = max_load.max(load);
    }
    let (e, nu) = p.material.elastic.initial_moduli();
    let e_star = e / (1.0 - nu * nu);
    let r = p.indenter.radius();
    if max_load > 0.0 {
        // under load control: the Hertz depth of the largest load sizes the mesh. Through a
        // transducer the specimen carries less than P̂ (k₁ takes k₁δ): the contact is
        // overestimated, which keeps the contact edge inside the fine zone (docs/chain.md)
        max_depth = max_depth.max((0.75 * max_load / (e_star * r.sqrt())).powf(2.0 / 3.0));
    }
    if let Machine::Spring { stiffness } = p.machine {
        // the schedule drives Δ, not δ: a soft spring (K ≪ the contact stiffness) holds the
        // indenter far above the drive, and a mesh sized for δ = Δ would be absurdly coarse
        max_depth = spring_depth(max_depth, stiffness, e_star, r);
    }
    if !(max_depth > 0.0) && p.adhesion.is_none() {
        return Err(FeError::Params(
            "the schedule never indents (no depth > 0)".into(),
        ));
    }
    let a = adhesion::sizing_radius(&p.indenter, e_star, p.adhesion.as_ref(), max_depth);
    let m = &p.mesh;
    if !(m.size_factor >= 10.0) {
        return Err(FeError::Params(format!(
            "mesh.size_factor must be at least 10 (the block ≥ 10 contact radii), got {}",
            m.size_factor
        )));
    }
    let process_zone = match &p.adhesion {
        Some(ad) => Some(
            ad.process_zone(e_star)
                .map_err(|e| FeError::Params(format!("process zone: {e}")))?,
        ),
        None => None,
    };
    let smallest = m.smallest.unwrap_or(
        (a / m.elements_per_radius)
            .min(process_zone.map_or(f64::INFINITY, |l| l / adhesion::ZONE_ELEMENTS)),
    );
    let block = BlockSpec {
        width: m.width.unwrap_or(m.size_factor * a),
        depth: m.depth.unwrap_or(m.size_factor * a),
        smallest,
        fine_radius: m.fine_radius * a,
        fine_depth: m.fine_depth * a,
        grading: m.grading,
        max_elements: m.max_elements,
    };
    let adaptive = match m.adaptive {
        None | Some(false) => false,
        Some(true) => {
            let why = if p.adhesion.is_none() {
                Some("without adhesion (no contact edge to follow)")
            } else if p.solver.method == Method::Riks {
                Some("with arc-length continuation (solver.method = riks)")
            } else if m.gmsh_file.is_some() {
                Some("with a Gmsh mesh")
            } else {
                None
            };
            if let Some(why) = why {
                return Err(FeError::Params(format!(
                    "mesh.adaptive = true is not available {why}: set it to false or remove it"
                )));
            }
            true
        }
    };
    let edge_zone = match (adaptive, process_zone) {
        (true, Some(ell)) => {
            if !(m.edge_zone > 0.0 && m.edge_zone.is_finite()) {
                return Err(FeError::Params(format!(
                    "mesh.edge_zone must be a positive number of process zones, got {}",
                    m.edge_zone
                )));
            }
            Some(EdgeZone {
                inner: 0.0,
                outer: 0.0,
                half_width: m.edge_zone * ell,
                surface: smallest.max(a / m.elements_per_radius),
            })
        }
        _ => None,
    };
    let c = &p.contact;
    if !(c.penalty_factor > 0.0
        && c.range_fraction > 0.0
        && (1..=MAX_QUADRATURE_POINTS).contains(&c.quadrature_points))
    {
        return Err(FeError::Params(format!(
            "unusable contact parameters {c:?}"
        )));
    }
    Ok(Resolved {
        max_depth_nm: max_depth,
        expected_contact_radius_nm: a,
        block,
        youngs_GPa: e,
        poisson: nu,
        reduced_modulus_GPa: e_star,
        penalty: SmoothPenalty {
            stiffness: c.penalty_factor * e_star / smallest,
            range: c.range_fraction * smallest,
        },
        process_zone_nm: process_zone,
        tabor: p
            .adhesion
            .as_ref()
            .and_then(|ad| ad.tabor(p.indenter.radius(), e_star).ok()),
        edge_zone,
    })
}

/// One converged increment.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[allow(non_snake_case)] // field names carry their units, as the output columns do
pub struct Row {
    /// time, s
    pub time_s: f64,
    /// indenter depth δ, nm
    pub depth_nm: f64,
    /// load P, nN (compressive positive)
    pub load_nN: f64,
    /// contact radius, nm
    pub contact_radius_nm: f64,
    /// Newton iterations of the increment
    pub iterations: usize,
    /// the drive Δ through the machine spring, nm (= δ under displacement control; under
    /// load control the load controls and this repeats δ; through a transducer
    /// ([`Machine::LoadFrame`]) it is the plate position h = δ + Q/k₂)
    pub drive_nm: f64,
    /// gap at the surface point nearest the axis, nm
    pub gap_nm: f64,
    /// strain energy of the solid (the incremental potential with relaxation), aJ
    pub strain_energy_aJ: f64,
    /// energy dissipated by contact damping so far, aJ
    pub damping_dissipated_aJ: f64,
    /// schedule segment of the increment (0-based; the initial state is in segment 0)
    pub segment: usize,
}

/// The deformed state at the end of a segment.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// which segment ended
    pub label: String,
    /// time, s
    pub time_s: f64,
    /// depth, nm
    pub depth_nm: f64,
    /// nodal displacements (u_r, u_z), nm
    pub displacement: Vec<f64>,
    /// element Cauchy stresses [rr, zz, θθ, rz], GPa
    pub stress: Vec<Voigt>,
    /// the mesh of the snapshot when it may differ from [`IndentResult::mesh`] (adaptive
    /// meshing); None: that mesh
    pub mesh: Option<Mesh>,
}

/// One mesh of an adaptive run ([`MeshParams::adaptive`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[allow(non_snake_case)] // field names carry their units, as the output columns do
pub struct Adaptation {
    /// converged increments before the mesh took over (it solves the next one)
    pub increment: usize,
    /// time, s
    pub time_s: f64,
    /// the band of smallest elements covers the edges from this radius, nm
    pub inner_nm: f64,
    /// to this one, nm
    pub outer_nm: f64,
    /// triangles of the mesh
    pub elements: usize,
}

/// Work and time spent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct RunStats {
    /// converged increments
    pub increments: usize,
    /// halved increments
    pub cutbacks: usize,
    /// Newton iterations in converged increments
    pub newton_iterations: usize,
    /// assembly and linear-solve totals (failed attempts included)
    pub assembly: AssemblyStats,
    /// mesh generation, s
    pub mesh_s: f64,
    /// the whole run, s
    pub wall_s: f64,
}

/// What a run produced.
#[derive(Debug, Clone)]
#[allow(non_snake_case)] // field names carry their units, as the output columns do
pub struct IndentResult {
    /// the parameters
    pub params: IndentParams,
    /// the derived sizes
    pub resolved: Resolved,
    /// the mesh (with adaptive meshing, the last one)
    pub mesh: Mesh,
    /// its figures
    pub mesh_report: MeshReport,
    /// with adaptive meshing: every mesh of the run, the first at increment 0
    pub adaptation: Vec<Adaptation>,
    /// one row per converged increment (and the initial state)
    pub rows: Vec<Row>,
    /// deformed states at the end of each segment
    pub snapshots: Vec<Snapshot>,
    /// work and time
    pub stats: RunStats,
    /// why the run stopped early, if it did
    pub failure: Option<String>,
    /// under load control: the specimen's load Q at the last equilibrium of an unloading
    /// segment beyond which none was found (the load-control pull-off, to within the last
    /// halved increment; through a transducer the applied P̂ there is larger by k₁h); the
    /// indenter separates there and the rest of the schedule is skipped
    pub separated_nN: Option<f64>,
}

/// Progress of a run, for the caller's display.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// schedule segment (0-based)
    pub segment: usize,
    /// number of segments
    pub segments: usize,
    /// the increment just converged
    pub row: Row,
    /// triangles of the mesh it converged on
    pub elements: usize,
}

/// The sizes and the mesh a run of `p` would build, without solving anything (`turf check`).
pub fn mesh_preview(p: &IndentParams) -> Result<(Resolved, MeshReport), FeError> {
    let r = resolve(p)?;
    let mesh = build_mesh(p, &r)?;
    Ok((r, mesh.report()))
}

/// Build the (first) mesh of a run: the band at the axis when adaptive.
fn build_mesh(p: &IndentParams, r: &Resolved) -> Result<Mesh, FeError> {
    if let Some(z) = &r.edge_zone {
        return Ok(mesh::edge_block(&r.block, z)?);
    }
    match &p.mesh.gmsh_file {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| FeError::Params(format!("cannot read {}: {e}", path.display())))?;
            Ok(mesh::read_msh(&text)?)
        }
        None => Ok(mesh::graded_block(&r.block)?),
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

/// The state at the end of segment `si` (`x` = (u, δ)) on `mesh` (None: the run's only mesh).
pub(super) fn snapshot(
    si: usize,
    time: f64,
    x: &[f64],
    solid: &Solid,
    history: &[f64],
    mesh: Option<&Mesh>,
) -> Result<Snapshot, FeError> {
    let n = solid.dofs();
    Ok(Snapshot {
        label: format!("segment{si}"),
        time_s: time,
        depth_nm: x[n],
        displacement: x[..n].to_vec(),
        stress: solid.stresses(&x[..n], history, 0.0)?,
        mesh: mesh.cloned(),
    })
}

/// What lives on the mesh of a run: the solid, its assembler and the state (the displacements
/// of the last two converged increments, δ last, and the Prony history).
struct OnMesh<'a> {
    solid: &'a mut Solid,
    asm: &'a mut Assembler,
    u: &'a mut Vec<f64>,
    u_prev: &'a mut Vec<f64>,
    history: &'a mut Vec<f64>,
}

/// Move the run onto the mesh of `zone` ([`mesh::edge_block`]): the state carried over by
/// [`transfer`], the solid and the contact surface rebuilt, the mesh recorded in
/// `result.adaptation`. Returns the gaps of the carried state on the new surface (the damping's
/// start-of-step gaps).
fn remesh(
    p: &IndentParams,
    zone: &EdgeZone,
    time: f64,
    contact: &mut Contact,
    result: &mut IndentResult,
    on: OnMesh,
) -> Result<Vec<f64>, FeError> {
    let new_mesh = mesh::edge_block(&result.resolved.block, zone)?;
    let old = &result.mesh;
    let n = on.solid.dofs();
    let carry = |x: &[f64]| {
        let mut y = transfer::interpolate_nodal(old, &x[..n], 2, &new_mesh);
        y.push(x[n]);
        y
    };
    *on.u = carry(on.u);
    *on.u_prev = carry(on.u_prev);
    *on.history = transfer::project_elementwise(old, on.history, on.solid.history_len(), &new_mesh);
    *on.solid = new_solid(p, &new_mesh)?;
    contact.segments = Contact::segments_of(&new_mesh);
    let stats = on.asm.stats;
    *on.asm = Assembler::new(on.solid, Some(contact))?;
    on.asm.stats = stats;
    let n = on.solid.dofs();
    let small = p.kinematics == Kinematics::Small;
    let gaps = contact
        .profile(&current(on.solid, on.u), &on.solid.nodes, on.u[n], small)
        .iter()
        .map(|q| q.gap)
        .collect();
    result.adaptation.push(Adaptation {
        increment: result.stats.increments,
        time_s: time,
        inner_nm: zone.inner,
        outer_nm: zone.outer,
        elements: new_mesh.triangles.len(),
    });
    result.mesh_report = new_mesh.report();
    result.mesh = new_mesh;
    Ok(gaps)
}

/// Current node positions X + u.
fn current(solid: &Solid, u: &[f64]) -> Vec<[f64; 2]> {
    solid
        .nodes
        .iter()
        .enumerate()
        .map(|(n, x)| [x[0] + u[2 * n], x[1] + u[2 * n + 1]])
        .collect()
}

/// The solid of a run on `mesh`: axis u_r = 0, base bonded u = 0.
fn new_solid(p: &IndentParams, mesh: &Mesh) -> Result<Solid, FeError> {
    let material = Viscoelastic {
        elastic: p.material.elastic.clone(),
        prony: p.material.prony.clone(),
    };
    let mut solid = Solid::new(mesh, p.kinematics, Box::new(material))?;
    for &n in &mesh.axis {
        solid.fixed[2 * n] = true;
    }
    for &n in &mesh.bottom {
        solid.fixed[2 * n] = true;
        solid.fixed[2 * n + 1] = true;
    }
    Ok(solid)
}

/// Run the indentation. A failure midway returns [`FeError::Stopped`] with what was finished;
/// so does an interrupt ([`crate::interrupt::requested`], polled after every converged
/// increment).
pub fn run_indent(
    p: &IndentParams,
    progress: &mut dyn FnMut(&Progress),
) -> Result<IndentResult, FeError> {
    let t_start = Instant::now();
    let resolved = resolve(p)?;
    let mut zone = resolved.edge_zone;
    let mesh = build_mesh(p, &resolved)?;
    let mesh_s = t_start.elapsed().as_secs_f64();
    let mut solid = new_solid(p, &mesh)?;
    let penalty = resolved.penalty;
    let law: &dyn SurfaceLaw = match &p.adhesion {
        Some(a) => &a.law,
        None => &penalty,
    };
    let damping_law = p.adhesion.as_ref().and_then(|a| a.damping);
    // the surface (for profiles and the pattern); each step adds its damping to a copy
    let mut contact = Contact {
        segments: Contact::segments_of(&mesh),
        indenter: p.indenter,
        law,
        quadrature: gauss_legendre_unit(p.contact.quadrature_points),
        damping: None,
    };
    let mut asm = Assembler::new(&solid, Some(&contact))?;
    let a = resolved.expected_contact_radius_nm;
    // the forces in play are at least the elastic scale at the contact and, with adhesion, the
    // DMT pull-off 2πγR (the largest adhesive load): the residual tolerance is relative to them
    let adhesive_force = p.adhesion.as_ref().map_or(0.0, |ad| {
        2.0 * std::f64::consts::PI * ad.law.gamma() * p.indenter.radius()
    });
    let force_floor = (1e-6 * resolved.reduced_modulus_GPa * a * a).max(adhesive_force);

    let small = p.kinematics == Kinematics::Small;
    let mut ndof = solid.dofs();
    // the unknowns: nodal displacements, then the indenter depth δ
    let mut u = vec![0.0; ndof + 1];
    u[ndof] = p.start;
    let mut u_prev = u.clone();
    let profile0 = contact.profile(&current(&solid, &u), &solid.nodes, p.start, small);
    let mut gaps: Vec<f64> = profile0.iter().map(|q| q.gap).collect();
    // the radii the adaptive band must cover at the last converged state
    let mut span = band_span(&contact, &profile0);
    // the band the next increment is to be solved with, when it differs from the current one
    let mut pending: Option<EdgeZone> = None;
    let mut history = vec![0.0; solid.history_len() * solid.elements.len()];
    let ev0 = asm.evaluate(
        &solid,
        Some(&contact),
        (&u[..ndof], &history),
        0.0,
        p.start,
        false,
    )?;
    let mut result = IndentResult {
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
                elements: mesh.triangles.len(),
            })
            .collect(),
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
    if p.solver.method == Method::Riks {
        let mut curve = Curve {
            asm: &mut asm,
            solid: &solid,
            contact: &contact,
            force_floor,
            newton: p.solver.newton,
            contraction: p.solver.arclength.contraction,
        };
        let outcome = curve.trace(p, u, &mut result, progress);
        result.stats.assembly = asm.stats;
        result.stats.wall_s = t_start.elapsed().as_secs_f64();
        return match outcome {
            Ok(()) => Ok(result),
            Err(why) => {
                result.failure = Some(why);
                Err(FeError::Stopped(Box::new(result)))
            }
        };
    }
    let mut last_dv = 0.0;
    let (mut time, mut drive) = (0.0, p.start);
    let mut load = p.machine.applied_load(ev0.load, p.start);
    let mut dissipated = 0.0;
    let base = 1.0 / p.solver.increments.max(1) as f64;

    'schedule: for (si, seg) in p.schedule.iter().enumerate() {
        let (v0, target, duration, by_load) = segment_span(seg, p.machine, drive, load);
        let t0 = time;
        let mut value = v0;
        let (mut done, mut step, mut cutbacks) = (0.0f64, base, 0usize);
        let mut remeshes = 0usize;
        while done < 1.0 - 1e-12 {
            // adaptive: move onto the mesh asked for by the last increment
            if let Some(z) = pending.take() {
                let on = OnMesh {
                    solid: &mut solid,
                    asm: &mut asm,
                    u: &mut u,
                    u_prev: &mut u_prev,
                    history: &mut history,
                };
                gaps = remesh(p, &z, time, &mut contact, &mut result, on)?;
                ndof = solid.dofs();
                last_dv = 0.0;
                zone = Some(z);
            }
            let s = step.min(1.0 - done);
            let new_value = v0 + (target - v0) * (done + s);
            let dt = duration * s;
            let dv = new_value - value;
            let mode = p.machine.drive(by_load, new_value);
            // predictor: extrapolate the last increment's change of (u, δ)
            let mut x = u.clone();
            if last_dv != 0.0 && dv * last_dv > 0.0 {
                let ratio = dv / last_dv;
                for ((xi, ui), pi) in x.iter_mut().zip(&u).zip(&u_prev) {
                    *xi += ratio * (ui - pi);
                }
            }
            if let Drive::Depth(d) = mode {
                x[ndof] = d;
            }
            let step_contact = Contact {
                segments: contact.segments.clone(),
                quadrature: contact.quadrature.clone(),
                // not on load-controlled segments: a damped step can hold a load beyond the
                // static limit (the viscous force making up the difference), so the
                // separation load would depend on c₀
                damping: damping_law.filter(|_| !by_load).map(|law| Damping {
                    law,
                    previous: &gaps,
                    dt,
                }),
                ..contact
            };
            let mut sys = Driven {
                asm: &mut asm,
                solid: &solid,
                contact: Some(&step_contact),
                history: &history,
                dt,
                drive: mode,
                force_floor,
            };
            let solved = newton::solve(&mut sys, &mut x, &p.solver.newton)
                .map_err(|e| e.to_string())
                .and_then(|info| p.indenter.check_depth(x[ndof]).map(|()| info));
            // adaptive: an edge that left the band is solved again on a mesh whose band spans
            // it and the last converged one (that state carried over)
            if let (Some(z), Ok(_)) = (&zone, &solved) {
                let trial = contact.profile(&current(&solid, &x), &solid.nodes, x[ndof], small);
                let (lo, hi) = band_span(&contact, &trial);
                let reach = EDGE_SAFE * z.half_width;
                if (lo < z.inner - reach || hi > z.outer + reach)
                    && remeshes < MAX_REMESHES_PER_INCREMENT
                {
                    remeshes += 1;
                    pending = Some(EdgeZone {
                        inner: lo.min(span.0),
                        outer: hi.max(span.1),
                        ..*z
                    });
                    continue;
                }
            }
            match solved {
                Ok(info) => {
                    let ev = sys.evaluation(&x, false)?;
                    let depth = x[ndof];
                    solid.commit(&x[..ndof], &mut history, dt)?;
                    u_prev = std::mem::replace(&mut u, x);
                    last_dv = dv;
                    value = new_value;
                    done += s;
                    time = t0 + duration * done;
                    dissipated += 2.0 * ev.damping_energy;
                    let profile = contact.profile(&current(&solid, &u), &solid.nodes, depth, small);
                    gaps.clear();
                    gaps.extend(profile.iter().map(|q| q.gap));
                    drive = mode.position(depth, ev.load);
                    // the controlled force: P̂ = Q except through the transducer's springs
                    load = p.machine.applied_load(ev.load, depth);
                    let row = Row {
                        time_s: time,
                        depth_nm: depth,
                        load_nN: ev.load,
                        contact_radius_nm: contact.contact_radius(&profile),
                        iterations: info.iterations,
                        drive_nm: drive,
                        gap_nm: gaps.first().copied().unwrap_or(0.0),
                        strain_energy_aJ: ev.strain_energy,
                        damping_dissipated_aJ: dissipated,
                        segment: si,
                    };
                    result.rows.push(row);
                    result.stats.increments += 1;
                    result.stats.newton_iterations += info.iterations;
                    progress(&Progress {
                        segment: si,
                        segments: p.schedule.len(),
                        row,
                        elements: solid.elements.len(),
                    });
                    remeshes = 0;
                    if crate::interrupt::requested() {
                        result.failure = Some(crate::interrupt::REASON.into());
                        result.stats.assembly = asm.stats;
                        result.stats.wall_s = t_start.elapsed().as_secs_f64();
                        return Err(FeError::Stopped(Box::new(result)));
                    }
                    if info.iterations <= p.solver.quick_iterations {
                        step = (step * p.solver.growth).min(base);
                    }
                    // a band wider than the converged state needs (after a jump, or as the
                    // contact shrinks) narrows to it
                    span = band_span(&contact, &profile);
                    if let Some(z) = &zone {
                        let reach = 2.0 * EDGE_SAFE * z.half_width;
                        if span.0 > z.inner + reach || span.1 < z.outer - reach {
                            pending = Some(EdgeZone {
                                inner: span.0,
                                outer: span.1,
                                ..*z
                            });
                        }
                    }
                }
                Err(e) => {
                    cutbacks += 1;
                    result.stats.cutbacks += 1;
                    step *= 0.5;
                    last_dv = 0.0;
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
                        result.separated_nN = result.rows.last().map(|r| r.load_nN);
                        let own = zone.map(|_| &result.mesh);
                        let snap = snapshot(si, time, &u, &solid, &history, own)?;
                        result.snapshots.push(snap);
                        break 'schedule;
                    }
                    if exhausted {
                        result.failure = Some(format!(
                            "segment {si} ({seg:?}): increment to {new_value:.6} {} at t = {:.6} s failed at the smallest increment (1/2^{} of the base; {cutbacks} halvings in this segment): {e}",
                            if by_load { "nN" } else { "nm" },
                            t0 + duration * (done + s),
                            p.solver.max_cutbacks
                        ));
                        result.stats.assembly = asm.stats;
                        result.stats.wall_s = t_start.elapsed().as_secs_f64();
                        return Err(FeError::Stopped(Box::new(result)));
                    }
                }
            }
        }
        let own = zone.map(|_| &result.mesh);
        let snap = snapshot(si, time, &u, &solid, &history, own)?;
        result.snapshots.push(snap);
    }
    result.stats.assembly = asm.stats;
    result.stats.wall_s = t_start.elapsed().as_secs_f64();
    Ok(result)
}
