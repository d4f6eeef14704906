//! Turf generation (seed §2.4, Fig 1.1): nominally vertical, slightly wavy
//! tubes grown from the substrate z = 0 in a box periodic in x and y.
//!
//! Tube i starts at a base point bᵢ on the substrate (uniform in the box, no two bases closer
//! than the sum of their outer radii plus the equilibrium gap, periodic distance) and grows
//! straight along a direction dᵢ, waving horizontally:
//!
//! xᵢ(s) = bᵢ + s dᵢ + A [c u(s; e₀, φ₀) + √(1 − c²) u(s; eᵢ, φᵢ)],
//! u(s; e, φ) = (sin(2πs/λ + φ) − sin φ) e,  0 ≤ s ≤ Lᵢ,
//!
//! sampled at ⌈Lᵢ/ℓ⌉ + 1 equally spaced s. Real turfs grow collectively (seed §1.1, Fig 1.1:
//! the tubes of a forest lean and wave together, crowding keeps neighbours nearly parallel), so
//! the direction and the waviness have a turf-wide part and a per-tube part:
//!
//! - dᵢ is a per-tube tilt about the turf's mean growth direction d₀ (tilted from z by
//!   `mean_tilt` towards the azimuth `mean_azimuth`): the two components of the per-tube tilt
//!   are normal with standard deviation `tilt_spread` in the frame that the rotation taking z to
//!   d₀ (about z × d₀) carries along; its magnitude is clipped so that dᵢ stays within
//!   80° of z. Two tubes then diverge by ~√2 `tilt_spread` whatever the mean tilt, which is
//!   what lets long tubes grow clear of each other in a small periodic box.
//! - the wave has a turf-wide part (direction e₀, phase φ₀, drawn once when the coherence
//!   c = `wave_coherence` > 0) and a per-tube part (eᵢ, φᵢ); the per-tube amplitude is
//!   A√(1 − c²), so neighbours wave apart by at most 2A√(1 − c²).
//!
//! With `mean_tilt` = 0 and c = 0 this is the independent-tube turf (same random draws). Growth is overlap-free along the whole length:
//! every segment of a candidate tube is checked against every segment of the tubes already
//! grown, and of their periodic images (and its own) in x and y, for every image shift the
//! tubes' bounding boxes can reach; the axes must stay r_a + r_b + 0.34 nm apart (the
//! equilibrium gap). Bounding boxes per tube and per segment, and a height band search (node
//! heights increase along a tube), prune before the exact segment–segment distance. A tube
//! that crosses is redrawn (base, tilt, wave direction and phase; its radius and length are
//! kept) up to a fixed number of attempts, after which generation fails with
//! [`TurfError::Interpenetrating`]. Lengths are log-normal (mean, coefficient of
//! variation), outer radii normal (mean, coefficient of variation, inner radius scaled with
//! the outer one). The first two nodes of each tube are clamped (position and tangent at the
//! substrate). Every random number comes from one `Pcg64` seeded by `seed`, drawn in a fixed
//! order, so a turf is portable and reproducible.
//!
//! Relaxation (contacts forming, bending locked in, E = U − Γ of seed eq. 1.1) needs the rod
//! energy and a static solver: [`EnergyBalance`] is the report it fills.

use std::f64::consts::PI;

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use serde::{Deserialize, Serialize};

use parry3d_f64::math::Vector;
use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;

use super::broadphase::PeriodicBox;
use super::vdw_term::TubeLayout;

/// The `[turf]` generation parameters (internal units: nm, rad).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TurfParams {
    /// areal density of tubes, 1/nm² (1e-4 /nm² = 10¹⁰ tubes/cm²)
    pub density: f64,
    /// box side along x (periodic), nm
    pub box_x: f64,
    /// box side along y (periodic), nm
    pub box_y: f64,
    /// mean outer radius r_o, nm (PHYSICS.md: 20 nm)
    pub radius_outer: f64,
    /// inner radius for the mean outer radius, nm (PHYSICS.md: 17.3 nm)
    pub radius_inner: f64,
    /// coefficient of variation of the outer radius (normal, clipped at ±3σ)
    pub radius_cv: f64,
    /// mean tube length (growth parameter s), nm
    pub length_mean: f64,
    /// coefficient of variation of the length (log-normal)
    pub length_cv: f64,
    /// standard deviation of each component of a tube's tilt about the mean direction, rad
    pub tilt_spread: f64,
    /// tilt of the turf-wide mean growth direction from z, rad, in [0, 80°)
    pub mean_tilt: f64,
    /// azimuth of the mean growth direction from x, rad
    pub mean_azimuth: f64,
    /// waviness amplitude A, nm
    pub wave_amplitude: f64,
    /// fraction c ∈ [0, 1] of the waviness shared by all tubes (the per-tube part is √(1 − c²))
    pub wave_coherence: f64,
    /// waviness wavelength λ, nm
    pub wave_length: f64,
    /// target segment length ℓ, nm
    pub segment_length: f64,
    /// random seed
    pub seed: u64,
}

impl Default for TurfParams {
    fn default() -> Self {
        TurfParams {
            density: 1e-4,
            box_x: 1000.0,
            box_y: 1000.0,
            radius_outer: 20.0,
            radius_inner: 17.3,
            radius_cv: 0.0,
            length_mean: 2000.0,
            length_cv: 0.1,
            tilt_spread: 0.1,
            mean_tilt: 0.0,
            mean_azimuth: 0.0,
            wave_amplitude: 30.0,
            wave_coherence: 0.0,
            wave_length: 800.0,
            segment_length: 50.0,
            seed: 1,
        }
    }
}

/// Why a turf could not be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TurfError {
    /// a parameter outside its allowed range
    #[error("turf parameter `{name}` = {value} is not allowed: {allowed}")]
    InvalidParameter {
        /// parameter name
        name: &'static str,
        /// offending value
        value: f64,
        /// what is allowed
        allowed: &'static str,
    },
    /// the bases could not be placed without overlap
    #[error("placed only {placed} of {wanted} tube bases without overlap: density too high")]
    TooDense {
        /// bases placed
        placed: usize,
        /// bases wanted
        wanted: usize,
    },
    /// a tube could not be grown clear of the tubes already grown
    #[error(
        "grew only {placed} of {wanted} tubes without interpenetration: tube {} crossed an \
         already grown tube (or a periodic image, or its own) in all {attempts} growth \
         attempts; lower the density, tilt, waviness or length",
        placed + 1
    )]
    Interpenetrating {
        /// tubes grown
        placed: usize,
        /// tubes wanted
        wanted: usize,
        /// growth attempts spent on the tube that failed
        attempts: usize,
    },
}

/// Growth draws (base, tilt, wave direction and phase) per tube before the turf is declared
/// impossible: the last tubes of a crowded patch are accepted only when nearly parallel to the
/// others, so they need many draws, while a failing request still ends within seconds.
const GROWTH_ATTEMPTS: usize = 10_000;
/// Attempts per base before the density is declared too high.
const PLACEMENT_ATTEMPTS: usize = 1000;
/// Largest tilt from vertical, rad (80°): tubes must rise from the substrate.
const MAX_TILT: f64 = 80.0 * PI / 180.0;
/// Gap kept between the bases of two tubes, nm (the equilibrium wall gap).
const BASE_GAP: f64 = 0.34;
/// Clipping of the normal radius distribution, in standard deviations.
const RADIUS_CLIP: f64 = 3.0;

impl TurfParams {
    /// Check every parameter's range.
    pub fn validate(&self) -> Result<(), TurfError> {
        let check = |name, value: f64, ok: bool, allowed| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(TurfError::InvalidParameter {
                    name,
                    value,
                    allowed,
                })
            }
        };
        let p = self;
        check("density", p.density, p.density > 0.0, "> 0")?;
        check("box_x", p.box_x, p.box_x > 0.0, "> 0")?;
        check("box_y", p.box_y, p.box_y > 0.0, "> 0")?;
        check("radius_outer", p.radius_outer, p.radius_outer > 0.0, "> 0")?;
        check(
            "radius_inner",
            p.radius_inner,
            (0.0..p.radius_outer).contains(&p.radius_inner),
            "0 <= r_i < r_o",
        )?;
        check(
            "radius_cv",
            p.radius_cv,
            (0.0..1.0 / RADIUS_CLIP).contains(&p.radius_cv),
            "0 <= cv < 1/3",
        )?;
        check("length_mean", p.length_mean, p.length_mean > 0.0, "> 0")?;
        check("length_cv", p.length_cv, p.length_cv >= 0.0, ">= 0")?;
        check("tilt_spread", p.tilt_spread, p.tilt_spread >= 0.0, ">= 0")?;
        check(
            "mean_tilt",
            p.mean_tilt,
            (0.0..MAX_TILT).contains(&p.mean_tilt),
            "0 <= mean tilt < 80 degrees",
        )?;
        check("mean_azimuth", p.mean_azimuth, true, "finite")?;
        check(
            "wave_coherence",
            p.wave_coherence,
            (0.0..=1.0).contains(&p.wave_coherence),
            "0 <= c <= 1",
        )?;
        check(
            "wave_amplitude",
            p.wave_amplitude,
            p.wave_amplitude >= 0.0,
            ">= 0",
        )?;
        check("wave_length", p.wave_length, p.wave_length > 0.0, "> 0")?;
        check(
            "segment_length",
            p.segment_length,
            p.segment_length > 0.0,
            "> 0",
        )?;
        Ok(())
    }
}

/// One generated tube.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tube {
    /// node positions, nm; node 0 on the substrate
    pub nodes: Vec<[f64; 3]>,
    /// outer radius, nm
    pub radius_outer: f64,
    /// inner radius, nm
    pub radius_inner: f64,
}

/// A generated turf: tubes and the periodic box.
#[derive(Debug, Clone, PartialEq)]
pub struct Turf {
    /// the tubes
    pub tubes: Vec<Tube>,
    /// periodic in x and y
    pub periodic: PeriodicBox,
}

impl Turf {
    /// The flat coordinate vector (3 per node, tubes one after another), nm.
    pub fn coordinates(&self) -> Vec<f64> {
        self.tubes
            .iter()
            .flat_map(|t| t.nodes.iter().flatten().copied())
            .collect()
    }

    /// Where each tube's nodes sit in [`Turf::coordinates`].
    pub fn layout(&self) -> Vec<TubeLayout> {
        let mut first = 0;
        self.tubes
            .iter()
            .map(|t| {
                let l = TubeLayout {
                    first_node: first,
                    nodes: t.nodes.len(),
                    radius: t.radius_outer,
                };
                first += t.nodes.len();
                l
            })
            .collect()
    }

    /// Indices of the clamped nodes: the first two of each tube (position and tangent at the
    /// substrate).
    pub fn clamped_nodes(&self) -> Vec<usize> {
        self.layout()
            .iter()
            .flat_map(|l| [l.first_node, l.first_node + 1])
            .collect()
    }
}

/// Standard normal deviate (Box–Muller on two uniforms: portable).
fn normal(rng: &mut Pcg64) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// The rotation taking z to the mean growth direction d₀ (tilted by θ₀ towards azimuth φ₀),
/// about the horizontal axis k = z × d₀ / |z × d₀| = (−sin φ₀, cos φ₀, 0) (Rodrigues). θ₀ = 0
/// gives the identity exactly.
#[derive(Clone, Copy)]
struct Rotation {
    axis: [f64; 3],
    cos: f64,
    sin: f64,
}

impl Rotation {
    fn from_z_to(tilt: f64, azimuth: f64) -> Self {
        Rotation {
            axis: [-azimuth.sin(), azimuth.cos(), 0.0],
            cos: tilt.cos(),
            sin: tilt.sin(),
        }
    }

    /// R v = v cos θ + (k × v) sin θ + k (k·v)(1 − cos θ).
    fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        let k = self.axis;
        let kxv = [
            k[1] * v[2] - k[2] * v[1],
            k[2] * v[0] - k[0] * v[2],
            k[0] * v[1] - k[1] * v[0],
        ];
        let kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
        std::array::from_fn(|d| v[d] * self.cos + kxv[d] * self.sin + k[d] * kv * (1.0 - self.cos))
    }
}

/// A horizontal wave: direction angle (from x) and phase, rad.
#[derive(Clone, Copy)]
struct Wave {
    direction: f64,
    phase: f64,
}

impl Wave {
    /// Horizontal offset a (sin(2πs/λ + φ) − sin φ) e at arc parameter s, nm.
    fn offset(&self, s: f64, wavelength: f64, amplitude: f64) -> [f64; 2] {
        let w = amplitude * ((2.0 * PI * s / wavelength + self.phase).sin() - self.phase.sin());
        [w * self.direction.cos(), w * self.direction.sin()]
    }
}

/// A grown tube's nodes with its outer radius and axis-aligned bounding box (of the axis).
struct Grown {
    nodes: Vec<[f64; 3]>,
    radius: f64,
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Grown {
    fn new(nodes: Vec<[f64; 3]>, radius: f64) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for n in &nodes {
            for d in 0..3 {
                lo[d] = lo[d].min(n[d]);
                hi[d] = hi[d].max(n[d]);
            }
        }
        Grown {
            nodes,
            radius,
            lo,
            hi,
        }
    }
}

/// Image shifts k (in periods `l`) along one axis for which the interval [lo_b, hi_b] + k·l
/// comes within `gap` of [lo_a, hi_a]: every shift whose image can reach, however far the
/// tubes lean out of the box.
fn shift_range(lo_a: f64, hi_a: f64, lo_b: f64, hi_b: f64, gap: f64, l: f64) -> (i64, i64) {
    (
        ((lo_a - hi_b - gap) / l).ceil() as i64,
        ((hi_a - lo_b + gap) / l).floor() as i64,
    )
}

/// Distance (nm) between the segments [a0, a1] and [b0, b1] (parry's closest points).
fn segment_distance(a0: [f64; 3], a1: [f64; 3], b0: [f64; 3], b1: [f64; 3]) -> f64 {
    let v = |p: [f64; 3]| Vector::new(p[0], p[1], p[2]);
    let (a0, a1, b0, b1) = (v(a0), v(a1), v(b0), v(b1));
    let (la, lb) = closest_points_segment_segment_with_locations_nD((&a0, &a1), (&b0, &b1));
    let [ua, va] = la.barycentric_coordinates();
    let [ub, vb] = lb.barycentric_coordinates();
    ((a0 * ua + a1 * va) - (b0 * ub + b1 * vb)).length()
}

/// Whether the axes of `a` and of every periodic image of `b` stay at least
/// r_a + r_b + [`BASE_GAP`] apart (`same`: `b` is `a` itself, so only its images count).
/// Prefilters: the tubes' bounding boxes select the image shifts; node heights increase along
/// a tube, so a binary search picks the segments of `b` in the height band of each segment of
/// `a`; then a segment bounding-box test before the exact distance.
fn clear_of(a: &Grown, b: &Grown, same: bool, box_x: f64, box_y: f64) -> bool {
    let gap = a.radius + b.radius + BASE_GAP;
    if a.lo[2] > b.hi[2] + gap || b.lo[2] > a.hi[2] + gap {
        return true;
    }
    let (kx0, kx1) = shift_range(a.lo[0], a.hi[0], b.lo[0], b.hi[0], gap, box_x);
    let (ky0, ky1) = shift_range(a.lo[1], a.hi[1], b.lo[1], b.hi[1], gap, box_y);
    for kx in kx0..=kx1 {
        for ky in ky0..=ky1 {
            if same && kx == 0 && ky == 0 {
                continue;
            }
            let off = [kx as f64 * box_x, ky as f64 * box_y];
            let shifted = |n: [f64; 3]| [n[0] + off[0], n[1] + off[1], n[2]];
            for sa in a.nodes.windows(2) {
                let (za, zb) = (sa[0][2].min(sa[1][2]), sa[0][2].max(sa[1][2]));
                // segments j of b with z_j ≤ zb + gap and z_{j+1} ≥ za − gap
                let first = b
                    .nodes
                    .partition_point(|n| n[2] < za - gap)
                    .saturating_sub(1);
                let last = b.nodes.partition_point(|n| n[2] <= zb + gap);
                let end = (last + 1).min(b.nodes.len());
                if first + 1 >= end {
                    continue;
                }
                for sb in b.nodes[first..end].windows(2) {
                    let (b0, b1) = (shifted(sb[0]), shifted(sb[1]));
                    let apart = (0..2).any(|d| {
                        sa[0][d].min(sa[1][d]) > b0[d].max(b1[d]) + gap
                            || b0[d].min(b1[d]) > sa[0][d].max(sa[1][d]) + gap
                    });
                    if !apart && segment_distance(sa[0], sa[1], b0, b1) < gap {
                        return false;
                    }
                }
            }
        }
    }
    true
}

/// Generate a turf from `p` (deterministic in `p.seed`).
pub fn generate_turf(p: &TurfParams) -> Result<Turf, TurfError> {
    p.validate()?;
    let wanted = (p.density * p.box_x * p.box_y).round() as usize;
    let mut rng = Pcg64::seed_from_u64(p.seed);
    let ln_sigma2 = (1.0 + p.length_cv * p.length_cv).ln();
    let ln_mu = p.length_mean.ln() - 0.5 * ln_sigma2;
    let periodic_dist2 = |a: [f64; 2], b: [f64; 2]| {
        let wrap = |d: f64, l: f64| d - l * (d / l).round();
        wrap(a[0] - b[0], p.box_x).powi(2) + wrap(a[1] - b[1], p.box_y).powi(2)
    };
    let mean = Rotation::from_z_to(p.mean_tilt, p.mean_azimuth);
    // the turf-wide wave is drawn only when it is used, so that c = 0 keeps the random stream
    // (and the turf) of independent tubes
    let coherent = p.wave_amplitude * p.wave_coherence;
    let independent = p.wave_amplitude * (1.0 - p.wave_coherence.powi(2)).sqrt();
    let common = (p.wave_coherence > 0.0).then(|| Wave {
        direction: rng.random::<f64>() * 2.0 * PI,
        phase: rng.random::<f64>() * 2.0 * PI,
    });
    let mut bases: Vec<([f64; 2], f64)> = Vec::with_capacity(wanted);
    let mut grown: Vec<Grown> = Vec::with_capacity(wanted);
    for _ in 0..wanted {
        let radius = p.radius_outer
            * (1.0 + p.radius_cv * normal(&mut rng).clamp(-RADIUS_CLIP, RADIUS_CLIP));
        // drawn once per tube, after the first base: a redraw changes where and how the tube
        // grows, not its length
        let mut length = None;
        let mut accepted = None;
        for _ in 0..GROWTH_ATTEMPTS {
            let mut base = None;
            for _ in 0..PLACEMENT_ATTEMPTS {
                let b = [rng.random::<f64>() * p.box_x, rng.random::<f64>() * p.box_y];
                let free = bases
                    .iter()
                    .all(|&(c, rc)| periodic_dist2(b, c) >= (radius + rc + BASE_GAP).powi(2));
                if free {
                    base = Some(b);
                    break;
                }
            }
            let Some(base) = base else {
                return Err(TurfError::TooDense {
                    placed: bases.len(),
                    wanted,
                });
            };
            let length =
                *length.get_or_insert_with(|| (ln_mu + ln_sigma2.sqrt() * normal(&mut rng)).exp());
            let (tx, ty) = (
                p.tilt_spread * normal(&mut rng),
                p.tilt_spread * normal(&mut rng),
            );
            let tilt = tx.hypot(ty).min(MAX_TILT - p.mean_tilt);
            let azimuth = ty.atan2(tx);
            let dir = mean.rotate([
                tilt.sin() * azimuth.cos(),
                tilt.sin() * azimuth.sin(),
                tilt.cos(),
            ]);
            let own = Wave {
                direction: rng.random::<f64>() * 2.0 * PI,
                phase: rng.random::<f64>() * 2.0 * PI,
            };
            let n = (length / p.segment_length).ceil().max(2.0) as usize;
            let nodes = (0..=n)
                .map(|k| {
                    let s = length * k as f64 / n as f64;
                    let w = common.map_or([0.0; 2], |c| c.offset(s, p.wave_length, coherent));
                    let v = own.offset(s, p.wave_length, independent);
                    [
                        base[0] + s * dir[0] + w[0] + v[0],
                        base[1] + s * dir[1] + w[1] + v[1],
                        s * dir[2],
                    ]
                })
                .collect();
            let cand = Grown::new(nodes, radius);
            let clear = clear_of(&cand, &cand, true, p.box_x, p.box_y)
                && grown
                    .iter()
                    .all(|g| clear_of(&cand, g, false, p.box_x, p.box_y));
            if clear {
                accepted = Some((base, cand));
                break;
            }
        }
        let Some((base, cand)) = accepted else {
            return Err(TurfError::Interpenetrating {
                placed: grown.len(),
                wanted,
                attempts: GROWTH_ATTEMPTS,
            });
        };
        bases.push((base, radius));
        grown.push(cand);
    }
    let tubes = grown
        .into_iter()
        .map(|g| Tube {
            nodes: g.nodes,
            radius_outer: g.radius,
            radius_inner: p.radius_inner * g.radius / p.radius_outer,
        })
        .collect();
    Ok(Turf {
        tubes,
        periodic: PeriodicBox {
            lx: Some(p.box_x),
            ly: Some(p.box_y),
        },
    })
}

/// The energy balance of a relaxed turf (seed eq. 1.1): E = U − Γ, with U the elastic (bending
/// and stretching) energy and Γ the contact energy, Γ = −(van der Waals energy) > 0 when
/// tubes adhere. All in aJ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EnergyBalance {
    /// elastic energy U, aJ
    pub elastic: f64,
    /// contact energy Γ, aJ
    pub contact: f64,
    /// total E = U − Γ, aJ
    pub total: f64,
}

impl EnergyBalance {
    /// From the elastic energy and the van der Waals energy (both aJ).
    pub fn new(elastic: f64, vdw: f64) -> Self {
        EnergyBalance {
            elastic,
            contact: -vdw,
            total: elastic + vdw,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_turf_other_seed_other_turf() {
        let p = TurfParams::default();
        let a = generate_turf(&p).unwrap();
        assert_eq!(a, generate_turf(&p).unwrap());
        let b = generate_turf(&TurfParams { seed: 2, ..p }).unwrap();
        assert_ne!(a.coordinates(), b.coordinates());
    }

    #[test]
    fn tubes_start_on_the_substrate_inside_the_box_without_overlapping_bases() {
        // 500 nm tubes: 200 tilted 2 µm tubes in this box cannot all grow clear of each other
        let p = TurfParams {
            density: 2e-4,
            radius_cv: 0.2,
            length_mean: 500.0,
            ..TurfParams::default()
        };
        let t = generate_turf(&p).unwrap();
        assert_eq!(t.tubes.len(), 200);
        for (i, a) in t.tubes.iter().enumerate() {
            let b = a.nodes[0];
            assert!(
                b[2] == 0.0 && (0.0..p.box_x).contains(&b[0]) && (0.0..p.box_y).contains(&b[1])
            );
            assert!(a.nodes.iter().all(|n| n[2] >= 0.0));
            assert!(a.nodes.windows(2).all(|w| w[1][2] > w[0][2]), "tubes rise");
            for c in &t.tubes[..i] {
                let d = c.nodes[0];
                let wrap = |v: f64, l: f64| v - l * (v / l).round();
                let dist = wrap(b[0] - d[0], p.box_x).hypot(wrap(b[1] - d[1], p.box_y));
                assert!(dist >= a.radius_outer + c.radius_outer + BASE_GAP - 1e-9);
            }
        }
        assert_eq!(t.clamped_nodes().len(), 2 * t.tubes.len());
        assert_eq!(
            t.coordinates().len(),
            3 * t.layout().iter().map(|l| l.nodes).sum::<usize>()
        );
    }

    #[test]
    fn length_and_tilt_statistics_follow_the_parameters() {
        // sparse and short enough that few growth draws are rejected for crossing another tube
        // (a rejection favours small tilts and would bias <tilt²>)
        let p = TurfParams {
            density: 1e-4,
            box_x: 6325.0,
            box_y: 6325.0,
            radius_outer: 5.0,
            radius_inner: 4.0,
            length_mean: 200.0,
            length_cv: 0.3,
            tilt_spread: 0.1,
            wave_amplitude: 0.0,
            ..TurfParams::default()
        };
        let t = generate_turf(&p).unwrap();
        let n = t.tubes.len() as f64;
        let lengths: Vec<f64> = t
            .tubes
            .iter()
            .map(|tube| {
                let (a, b) = (tube.nodes[0], *tube.nodes.last().unwrap());
                ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
            })
            .collect();
        let mean = lengths.iter().sum::<f64>() / n;
        let sd = (lengths.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / n).sqrt();
        // 4000 samples: standard error of the mean 0.3/√4000 ≈ 0.5 %; 3 % is > 5 standard errors
        assert!((mean / p.length_mean - 1.0).abs() < 0.03, "mean {mean}");
        assert!(
            (sd / mean / p.length_cv - 1.0).abs() < 0.1,
            "cv {}",
            sd / mean
        );
        // straight tubes: tilt² = tx² + ty², so <tilt²> = 2 spread²
        let mean_tilt2 = t
            .tubes
            .iter()
            .map(|tube| {
                let (a, b) = (tube.nodes[0], tube.nodes[1]);
                let h = (b[0] - a[0]).hypot(b[1] - a[1]);
                h.atan2(b[2] - a[2]).powi(2)
            })
            .sum::<f64>()
            / n;
        assert!(
            (mean_tilt2 / (2.0 * 0.01) - 1.0).abs() < 0.1,
            "tilt² {mean_tilt2}"
        );
    }

    #[test]
    fn impossible_densities_and_bad_parameters_are_errors() {
        // straight vertical tubes: only the bases can collide
        let dense = TurfParams {
            density: 1e-2,
            tilt_spread: 0.0,
            wave_amplitude: 0.0,
            ..TurfParams::default()
        };
        assert!(matches!(
            generate_turf(&dense),
            Err(TurfError::TooDense { .. })
        ));
        let bad = TurfParams {
            radius_inner: 30.0,
            ..TurfParams::default()
        };
        assert!(matches!(
            generate_turf(&bad),
            Err(TurfError::InvalidParameter { .. })
        ));
    }

    /// The turf of scenes/turf_compression.toml (9 tubes in a 300 nm periodic box, tilt 0.1,
    /// waviness 50 nm over 1 µm) with tubes `length` nm long (the scene's: 7 µm).
    fn scene_turf(length: f64) -> TurfParams {
        TurfParams {
            density: 1e-4,
            box_x: 300.0,
            box_y: 300.0,
            radius_outer: 20.0,
            radius_inner: 17.3,
            length_mean: length,
            length_cv: 0.05,
            tilt_spread: 0.1,
            wave_amplitude: 50.0,
            wave_length: 1000.0,
            segment_length: 350.0,
            seed: 7,
            ..TurfParams::default()
        }
    }

    /// Smallest axis distance minus r_a + r_b + BASE_GAP over every segment pair, by brute
    /// force over all pairs and image shifts −3…3 (the tubes lean out of the box by up to a
    /// few box widths), without the generator's prefilters.
    fn smallest_clearance(t: &Turf, p: &TurfParams) -> f64 {
        let mut worst = f64::INFINITY;
        for (i, a) in t.tubes.iter().enumerate() {
            for (j, b) in t.tubes.iter().enumerate().skip(i) {
                for kx in -3..=3 {
                    for ky in -3..=3 {
                        if i == j && kx == 0 && ky == 0 {
                            continue;
                        }
                        let (ox, oy) = (f64::from(kx) * p.box_x, f64::from(ky) * p.box_y);
                        for sa in a.nodes.windows(2) {
                            for sb in b.nodes.windows(2) {
                                let m = |n: [f64; 3]| [n[0] + ox, n[1] + oy, n[2]];
                                let d = segment_distance(sa[0], sa[1], m(sb[0]), m(sb[1]));
                                let need = a.radius_outer + b.radius_outer + BASE_GAP;
                                worst = worst.min(d - need);
                            }
                        }
                    }
                }
            }
        }
        worst
    }

    #[test]
    fn tilted_wavy_tubes_grow_clear_of_each_other_and_their_images() {
        // 2 µm tubes grow clear of each other; the scene's 7 µm tubes cannot (below)
        let p = scene_turf(2000.0);
        let t = generate_turf(&p).unwrap();
        assert_eq!(t.tubes.len(), 9);
        // the tubes do lean out of the box by more than one width, so the far images matter
        let reach = t
            .tubes
            .iter()
            .flat_map(|tube| tube.nodes.iter().map(|n| (n[0] - tube.nodes[0][0]).abs()))
            .fold(0.0, f64::max);
        let clearance = smallest_clearance(&t, &p);
        assert!(
            clearance >= 0.0,
            "clearance {clearance} nm, reach {reach} nm"
        );
        assert_eq!(t, generate_turf(&p).unwrap());
    }

    #[test]
    fn independently_tilted_7_um_tubes_cannot_grow_clear() {
        let err = generate_turf(&scene_turf(7000.0)).unwrap_err();
        assert!(
            matches!(err, TurfError::Interpenetrating { wanted: 9, .. }),
            "{err}"
        );
    }

    #[test]
    fn collectively_grown_7_um_tubes_of_the_scene_grow_clear() {
        // scenes/turf_compression.toml: the patch leans by 0.1 rad, each tube by 0.02 rad about
        // that, 80 % of the 50 nm wave shared
        let p = TurfParams {
            mean_tilt: 0.1,
            mean_azimuth: 0.0,
            tilt_spread: 0.02,
            wave_coherence: 0.8,
            ..scene_turf(7000.0)
        };
        let t = generate_turf(&p).unwrap();
        assert_eq!(t.tubes.len(), 9);
        let clearance = smallest_clearance(&t, &p);
        assert!(clearance >= 0.0, "clearance {clearance} nm");
        // the patch leans as a whole along x: every top is displaced by about L sin 0.1 ≈ 700
        // nm along x, spread by the per-tube tilt (≈ 0.02 × 7 µm = 140 nm rms) and the wave
        for tube in &t.tubes {
            let (b, top) = (tube.nodes[0], *tube.nodes.last().unwrap());
            let lean = (top[0] - b[0]) / top[2];
            assert!((lean - 0.1f64.tan()).abs() < 0.1, "lean {lean}");
        }
    }

    /// Unit vector of the straight tube's first segment.
    fn first_direction(tube: &Tube) -> [f64; 3] {
        let (a, b) = (tube.nodes[0], tube.nodes[1]);
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d.map(|c| c / n)
    }

    #[test]
    fn tilts_spread_about_the_mean_direction() {
        // sparse straight short tubes (few rejections, so no bias towards parallel tubes)
        let (theta, phi, spread) = (0.4, 1.0, 0.05);
        let p = TurfParams {
            density: 1e-4,
            box_x: 6325.0,
            box_y: 6325.0,
            radius_outer: 5.0,
            radius_inner: 4.0,
            length_mean: 200.0,
            length_cv: 0.0,
            tilt_spread: spread,
            mean_tilt: theta,
            mean_azimuth: phi,
            wave_amplitude: 0.0,
            ..TurfParams::default()
        };
        let t = generate_turf(&p).unwrap();
        let d0 = [
            f64::sin(theta) * f64::cos(phi),
            f64::sin(theta) * f64::sin(phi),
            f64::cos(theta),
        ];
        let n = t.tubes.len() as f64;
        let mut mean = [0.0; 3];
        let mut angle2 = 0.0;
        for tube in &t.tubes {
            let d = first_direction(tube);
            let cos = (d[0] * d0[0] + d[1] * d0[1] + d[2] * d0[2]).min(1.0);
            angle2 += cos.acos().powi(2) / n;
            (0..3).for_each(|k| mean[k] += d[k] / n);
        }
        // 4000 tubes: the mean direction's error is ~spread/√4000 ≈ 8e-4 per component; 4e-3
        // is five standard errors
        for k in 0..3 {
            assert!((mean[k] - d0[k]).abs() < 4e-3, "mean {mean:?} vs {d0:?}");
        }
        // the angle to d₀ is the per-tube tilt: <angle²> = 2 spread² (10 %: 1/√4000 ≈ 1.6 %
        // standard error of a χ² mean with 2 degrees of freedom, six of them)
        assert!(
            (angle2 / (2.0 * spread * spread) - 1.0).abs() < 0.1,
            "angle² {angle2}"
        );
    }

    #[test]
    fn fully_coherent_waves_make_translated_copies() {
        // no per-tube tilt, one length, c = 1: every tube is the same wavy curve translated;
        // c = 0.5 keeps a per-tube part, so the shapes differ
        let p = TurfParams {
            density: 1e-4,
            box_x: 300.0,
            box_y: 300.0,
            length_mean: 2000.0,
            length_cv: 0.0,
            tilt_spread: 0.0,
            mean_tilt: 0.2,
            wave_amplitude: 20.0,
            wave_length: 700.0,
            wave_coherence: 1.0,
            segment_length: 100.0,
            ..TurfParams::default()
        };
        let shape = |t: &Tube| -> Vec<[f64; 3]> {
            let b = t.nodes[0];
            t.nodes
                .iter()
                .map(|n| [n[0] - b[0], n[1] - b[1], n[2] - b[2]])
                .collect()
        };
        // same shapes up to the rounding of the translation (coordinates of order 10³ nm)
        let same = |a: &[[f64; 3]], b: &[[f64; 3]]| {
            a.iter()
                .zip(b)
                .all(|(u, v)| (0..3).all(|k| (u[k] - v[k]).abs() < 1e-9))
        };
        let t = generate_turf(&p).unwrap();
        let first = shape(&t.tubes[0]);
        assert!(first.iter().any(|n| n[0].hypot(n[1]) > 100.0), "it leans");
        assert!(t.tubes.iter().all(|tube| same(&shape(tube), &first)));
        let half = generate_turf(&TurfParams {
            wave_coherence: 0.5,
            ..p
        })
        .unwrap();
        let first = shape(&half.tubes[0]);
        assert!(!half.tubes[1..]
            .iter()
            .any(|tube| same(&shape(tube), &first)));
    }

    #[test]
    fn out_of_range_growth_parameters_are_errors() {
        for bad in [
            TurfParams {
                mean_tilt: 1.5,
                ..TurfParams::default()
            },
            TurfParams {
                wave_coherence: 1.2,
                ..TurfParams::default()
            },
        ] {
            assert!(matches!(
                generate_turf(&bad),
                Err(TurfError::InvalidParameter { .. })
            ));
        }
    }

    #[test]
    fn an_impossible_growth_request_is_an_error() {
        // 20 tubes in a 300 nm box, each waving ±300 nm over 3 µm: the bases fit, the tubes
        // cannot all miss each other
        let p = TurfParams {
            density: 20.0 / 9e4,
            box_x: 300.0,
            box_y: 300.0,
            length_mean: 3000.0,
            wave_amplitude: 300.0,
            wave_length: 1000.0,
            segment_length: 100.0,
            ..TurfParams::default()
        };
        let err = generate_turf(&p).unwrap_err();
        let TurfError::Interpenetrating {
            placed,
            wanted,
            attempts,
        } = err
        else {
            panic!("{err}");
        };
        assert!(placed < wanted && wanted == 20 && attempts == GROWTH_ATTEMPTS);
        assert!(err.to_string().contains("without interpenetration"));
    }

    #[test]
    fn energy_balance_signs() {
        let b = EnergyBalance::new(3.0, -5.0);
        assert_eq!((b.contact, b.total), (5.0, -2.0));
    }
}
