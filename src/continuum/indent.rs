//! The indentation problem (seed chapter 4): what a run is given ([`IndentParams`]: material,
//! indenter, mesh, contact or adhesion, machine, schedule, solver), the sizes it resolves them
//! to ([`resolve`]: contact radius, mesh block and process-zone band, penalty), the mesh it
//! starts on, and what it produces ([`IndentResult`]: one [`Row`] per converged increment,
//! snapshots at the end of each segment, the meshes of an adaptive run, the cost). The march
//! that solves it is [`super::march`]'s [`run_indent`](super::run_indent). Displacement
//! control: the depth δ(t) follows the segments (approach/load/unload at a rate, hold for a
//! time); the load is P = ∂Π/∂δ. Through a machine spring or under load control
//! ([`super::machine`]) the schedule drives Δ or P̂ instead and δ is an unknown. With adhesion
//! ([`super::adhesion`]) the schedule may start clear of the surface (`start` < 0) and the LJ
//! law replaces the penalty.

use super::adhesion::{self, AdhesionParams};
use super::assembly::{AssemblyStats, Solid};
use super::bifurcation::CriticalPoint;
use super::contact::{Contact, ProfilePoint, SmoothPenalty, SurfaceLaw};
use super::element::Kinematics;
use super::indenter::Indenter;
use super::machine::Machine;
use super::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
use super::material::linear::LinearElastic;
use super::material::viscoelastic::{validate_prony, PronyTerm, Viscoelastic};
use super::material::{Elastic, Voigt};
use super::mesh::{self, BlockSpec, EdgeZone, Mesh, MeshReport, TAIL_TIERS};
use super::newton::NewtonParams;
use super::FeError;
use serde::{Deserialize, Serialize};

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
    /// moves (with adhesion, the Newton method, a generated mesh and a frictionless indenter);
    /// unset: on where available and the band is narrower than the contact, the expected
    /// contact radius a > 2 `edge_zone` ℓ (validated at μ = 1, 2, 5 and 10,
    /// docs/validation-continuum.md "Adaptive mesh")
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
/// The gaps that bound the band's tiers: where the smallest elements h₀ start, the gap of the
/// law's largest tension (inside it the law is a stable, stiff spring on a smooth field), and
/// where each tier ends: the smallest elements while the stiffness of the law's attractive tail
/// can exceed half its largest k_t, the tier of 2^(k+1) h₀ while it can exceed k_t / 2^(k+2).
/// As in the half-space solver, a coarse ring at a small gap is unstable on its own: a ring of
/// surface elements of size h is stable while its compliance ~h/E* times the law's stiffness
/// stays below 1, and h₀ = ℓ/10 with ℓ = E*γ/σ₀² ≈ E*/k_t, so each tier keeps the margin of
/// the smallest elements where the law is at its stiffest (9-3: the band starts at 1.20 z₀, its
/// smallest elements end at 1.85 z₀ and its tiers at 2.23, 2.67, 3.18, 3.78, 4.50, 5.35, 6.36
/// and 7.56 z₀; beyond the last the law allows 512 h₀, more than the contact's surface
/// elements at μ ≤ 10).
/// Computed once per run ([`TierGaps::of`]), read at every look at the band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TierGaps {
    /// where the smallest elements start: the gap of the law's largest tension, nm
    pub start: f64,
    /// where the smallest elements, then each tier, end, nm
    pub ends: [f64; TAIL_TIERS + 1],
}

impl TierGaps {
    /// The gaps of `law` ([`tier_gaps`]).
    pub fn of(law: &dyn SurfaceLaw) -> Self {
        let (start, ends) = tier_gaps(law);
        TierGaps { start, ends }
    }
}

fn tier_gaps(law: &dyn SurfaceLaw) -> (f64, [f64; TAIL_TIERS + 1]) {
    // log-spaced gaps from g_c to 64 g_c (steps of 0.1 %): the tails of the plain and the
    // thermally shifted laws fall below k_t / 2^(TAIL_TIERS + 1) well inside
    const SAMPLES: usize = 4200;
    let gc = law.contact_gap();
    let gap = |i: usize| gc * 64f64.powf(i as f64 / SAMPLES as f64);
    let laws: Vec<(f64, f64, f64)> = (0..=SAMPLES).map(|i| law.eval(gap(i))).collect();
    // the attractive tail: beyond the largest tension
    let peak = (0..=SAMPLES)
        .min_by(|&i, &j| laws[i].1.total_cmp(&laws[j].1))
        .unwrap_or(0);
    let stiffness: Vec<f64> = laws[peak..].iter().map(|l| l.2.abs()).collect();
    let largest = stiffness.iter().fold(0.0f64, |a, &k| a.max(k));
    let mut gaps = [gap(peak); TAIL_TIERS + 1];
    for (j, g) in gaps.iter_mut().enumerate() {
        let bound = largest / 2f64.powi(j as i32 + 1);
        // the first sample beyond which the stiffness stays below the bound
        if let Some(i) = stiffness.iter().rposition(|&k| k > bound) {
            *g = gap((peak + i + 1).min(SAMPLES));
        }
    }
    (gap(peak), gaps)
}

/// The radii a band must cover on a profile, nm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Span {
    /// the edge of the process zone: the outermost gap below that of the law's largest tension
    pub inner: f64,
    /// the outermost radius that needs the smallest elements
    pub outer: f64,
    /// the outermost radius each coarser tier is needed to
    pub tail: [f64; TAIL_TIERS],
}

impl Span {
    /// Whether the band of `z` misses this span by more than `slack` anywhere.
    pub fn leaves(&self, z: &EdgeZone, slack: f64) -> bool {
        self.inner < z.inner - slack
            || self.outer > z.outer + slack
            || self.tail.iter().zip(&z.tail).any(|(t, b)| *t > b + slack)
    }

    /// Whether the band of `z` is wider than this span needs by more than `slack` at the edge,
    /// at the end of the smallest elements or at the band's end.
    pub fn narrower_than(&self, z: &EdgeZone, slack: f64) -> bool {
        self.inner > z.inner + slack
            || self.outer < z.outer - slack
            || self.zone(z).reach() < z.reach() - slack
    }

    /// The span covering both.
    pub fn union(&self, other: &Span) -> Span {
        let mut tail = self.tail;
        for (t, o) in tail.iter_mut().zip(&other.tail) {
            *t = t.max(*o);
        }
        Span {
            inner: self.inner.min(other.inner),
            outer: self.outer.max(other.outer),
            tail,
        }
    }

    /// The band of `z` moved onto this span.
    pub fn zone(&self, z: &EdgeZone) -> EdgeZone {
        EdgeZone {
            inner: self.inner,
            outer: self.outer,
            tail: self.tail,
            ..*z
        }
    }
}

/// The radii the band must cover on `profile`, its tiers ending at the gaps `tiers`.
pub(super) fn band_span(contact: &Contact, tiers: &TierGaps, profile: &[ProfilePoint]) -> Span {
    let radius = |g: f64| contact.radius_below(profile, g);
    let mut tail = [0.0; TAIL_TIERS];
    for (t, &g) in tail.iter_mut().zip(&tiers.ends[1..]) {
        *t = radius(g);
    }
    Span {
        inner: radius(tiers.start),
        outer: radius(tiers.ends[0]),
        tail,
    }
}
/// Remeshes within one increment at most (a jump moves the edge several times as the mesh
/// around it resolves the law; beyond this the increment is accepted on the last mesh).
pub const MAX_REMESHES_PER_INCREMENT: usize = 3;
/// Remeshes within one snap at most: its descent crosses the whole jump, and the band follows
/// its state as it goes (every [`SNAP_CHUNK`] iterations).
pub const MAX_REMESHES_PER_SNAP: usize = 20;
/// Descent iterations of a snap on an adaptive mesh between looks at whether its state has
/// left the band.
pub const SNAP_CHUNK: usize = 40;

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
    /// what the indenter does along its surface
    pub tangential: Tangential,
}

/// The indenter's tangential contact.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Tangential {
    /// no tangential force: the surface slides freely
    #[default]
    Frictionless,
    /// the surface in contact is held where it first touched ([`super::contact::Stick`]),
    /// by a tangential penalty as stiff as the normal one
    Stick,
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
            tangential: Tangential::Frictionless,
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

/// Arc-length parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ArcLengthParams {
    /// corrector iterations a step aims at (Crisfield's I_d)
    pub target_iterations: usize,
    /// largest growth of Δl from one step to the next
    pub max_growth: f64,
    /// steps per schedule segment before the run stops (a curve that never reaches the target)
    pub max_steps: usize,
    /// modified Newton in the corrector: keep the factorisation of K_uu while each iteration
    /// reduces the residual at least by this factor, refactorise otherwise (0: full Newton,
    /// a factorisation per iteration)
    pub contraction: f64,
    /// a step whose corrector moves the prediction by more than this many step lengths has
    /// left the curve: it is cut back
    pub max_correction: f64,
    /// a step whose tangent turns by more than this, rad, has left the curve: it is cut back
    pub max_turn: f64,
}

impl Default for ArcLengthParams {
    fn default() -> Self {
        ArcLengthParams {
            target_iterations: 5,
            max_growth: 2.0,
            max_steps: 5000,
            contraction: 0.0,
            max_correction: 0.5,
            max_turn: 0.5,
        }
    }
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
    /// an increment that fails at its smallest size snaps: the drive (or, loading under load
    /// control, the load) is held and the state descends to the next local minimum
    /// ([`super::snap`]); not where the material has lost ellipticity, nor on a retraction
    /// under load control (there the failure is the pull-off); false: the run stops there
    pub snap: bool,
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
            snap: true,
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
    validate(p)?;
    let (mut max_depth, max_load) = schedule_reach(p)?;
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
    let on = match (adaptive(p)?, process_zone) {
        (Some(on), _) => on,
        // unset: where the band (4ℓ either side of the edge) is narrower than the contact; a
        // wider one would cover it all, as the fixed mesh does, at the cost of remeshing
        (None, Some(ell)) => a > 2.0 * m.edge_zone * ell,
        (None, None) => false,
    };
    let edge_zone = match (on, process_zone) {
        (true, Some(ell)) => Some(edge_zone(m, ell, smallest.max(a / m.elements_per_radius))?),
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

/// Check what the sizes do not: the parts' own parameters and the combinations the solvers
/// cannot run.
fn validate(p: &IndentParams) -> Result<(), FeError> {
    p.indenter.validate()?;
    p.material.elastic.validate()?;
    validate_prony(&p.material.prony)?;
    p.machine.validate()?;
    if let Some(a) = &p.adhesion {
        a.validate()?;
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
    if p.contact.tangential == Tangential::Stick {
        // the anchors are path state renewed after each converged increment of the march; the
        // arc-length path does not carry them (nor does the adaptive mesh's transfer, which
        // `adaptive` leaves off for a sticking indenter)
        if p.solver.method == Method::Riks {
            return Err(FeError::Params(
                "a sticking indenter holds the surface by anchors renewed increment by increment: it needs the Newton method, not arc-length".into(),
            ));
        }
    }
    if !p.start.is_finite() {
        return Err(FeError::Params(format!("start depth {} nm", p.start)));
    }
    Ok(())
}

/// The deepest depth and the largest load the schedule drives to (each 0 if never driven),
/// checking its segments.
fn schedule_reach(p: &IndentParams) -> Result<(f64, f64), FeError> {
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
    Ok((max_depth, max_load))
}

/// Whether the mesh follows the contact edge (`mesh.adaptive`), refused where there is no edge
/// to follow or the run cannot remesh.
/// Whether the mesh follows the contact edge: as set, or None where it is unset and available
/// (`resolve` then decides by the size of the band against the contact).
fn adaptive(p: &IndentParams) -> Result<Option<bool>, FeError> {
    let why_not = if p.adhesion.is_none() {
        Some("without adhesion (no contact edge to follow)")
    } else if p.solver.method == Method::Riks {
        Some("with arc-length continuation (solver.method = riks)")
    } else if p.mesh.gmsh_file.is_some() {
        Some("with a Gmsh mesh")
    } else if p.contact.tangential == Tangential::Stick {
        Some("with a sticking indenter (its anchors are not carried across meshes)")
    } else {
        None
    };
    Ok(match (p.mesh.adaptive, why_not) {
        (Some(false), _) | (None, Some(_)) => Some(false),
        (None, None) => None,
        (Some(true), None) => Some(true),
        (Some(true), Some(why)) => {
            return Err(FeError::Params(format!(
                "mesh.adaptive = true is not available {why}: set it to false or remove it"
            )))
        }
    })
}

/// The band of fine elements around the contact edge: `mesh.edge_zone` process zones `ell`
/// either side, surface elements over the contact no larger than `surface` (nm).
fn edge_zone(m: &MeshParams, ell: f64, surface: f64) -> Result<EdgeZone, FeError> {
    if !(m.edge_zone > 0.0 && m.edge_zone.is_finite()) {
        return Err(FeError::Params(format!(
            "mesh.edge_zone must be a positive number of process zones, got {}",
            m.edge_zone
        )));
    }
    Ok(EdgeZone::plain(0.0, 0.0, m.edge_zone * ell, surface))
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
    /// and its coarser tiers (2, 4, … 256 h₀) to these, nm
    pub tail_nm: [f64; TAIL_TIERS],
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
    /// arc-length: the folds and bifurcations the traced curve passed
    pub critical_points: Vec<CriticalPoint>,
    /// Newton: the snaps through instabilities at a fixed drive ([`super::snap`])
    pub snaps: Vec<super::snap::Snap>,
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
    /// arc-length: negative eigenvalues of the stiffness at fixed depth there (0 on a stable
    /// branch under displacement control; None where not counted)
    pub negative_eigenvalues: Option<usize>,
}

/// The sizes and the mesh a run of `p` would build, without solving anything (`turf check`).
pub fn mesh_preview(p: &IndentParams) -> Result<(Resolved, MeshReport), FeError> {
    let r = resolve(p)?;
    let mesh = build_mesh(p, &r)?;
    Ok((r, mesh.report()))
}

/// Build the (first) mesh of a run: the band at the axis when adaptive.
pub(super) fn build_mesh(p: &IndentParams, r: &Resolved) -> Result<Mesh, FeError> {
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

/// The solid of a run on `mesh`: axis u_r = 0, base bonded u = 0.
pub(super) fn new_solid(p: &IndentParams, mesh: &Mesh) -> Result<Solid, FeError> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::{LennardJones, LjKind};

    /// The 9-3 law's band starts at its largest tension, 3^(1/6) z₀ = 1.2009 z₀, and its tiers
    /// change where its tail stiffness falls to 1/2, 1/4, … 1/512 of its largest,
    /// k(h) ∝ 3(z₀/h)⁴ − 9(z₀/h)¹⁰ with the largest 0.4698 at h = 1.399 z₀ (roots of the closed
    /// form), to the sampling step of 0.1 %.
    #[test]
    fn the_band_tiers_change_where_the_tail_softens() {
        let z0 = 0.5;
        let law = LennardJones::new(LjKind::Lj93, 0.05, z0);
        let (start, gaps) = tier_gaps(&law);
        assert!(
            (start / z0 - 3f64.powf(1.0 / 6.0)).abs() < 1.5e-3,
            "{start}"
        );
        let want = [
            1.8546, 2.2345, 2.6679, 3.1770, 3.7799, 4.4959, 5.3468, 6.3586, 7.5618,
        ];
        for (g, want) in gaps.iter().zip(want) {
            assert!((g / z0 / want - 1.0).abs() < 2e-3, "{gaps:?}");
        }
    }
}
