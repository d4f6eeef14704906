//! The structure of a relaxed turf in the terms of the seed's micromechanics (§2.4, eqs.
//! 2.8–2.14): along each tube, the **contact patches** — arclength where the tube's axis is within
//! r_a + r_b + g of another tube's axis, g the contact gap — and the **free segments** between two
//! consecutive patches of the same tube. From them: the number n of free segments per unit
//! volume, their mean length l, the mean patch length a, and the curvature κ₀ that (2.8) assigns
//! to the bending energy the free segments hold, κ₀² = 2 Σ U_free / (K Σ l): the tubes are
//! stress-free as generated (natural shape), so this is the curvature the relaxation locked in,
//! as in the seed's picture of straight tubes bent by their contacts. θ = κ₀ l/2 is the half-angle
//! of a circular free segment of that curvature (the lost Fig 2.3's geometry, as the text
//! describes it). [`Structure::segments`] hands these to [`crate::theory::micromech`], whose
//! (2.14) then predicts σ₀ from the tubes' own structure.
//!
//! The runs of a tube before its first patch and after its last one (base and tip ends), and tubes
//! with no patch at all, have no free segment between two contacts: their length is reported as
//! the end fraction and their energy left out of κ₀.

use parry3d_f64::math::Vector;

use super::rod::RodSet;
use super::vdw_term::PairGeometry;
use crate::theory::micromech::Segments;

/// Iterations of the golden-section search and of each bisection: (0.618)⁸⁰ ≈ 2e-17 of the
/// segment, and 2⁻⁶⁰ ≈ 1e-18.
const SEARCH_ITERATIONS: usize = 80;

/// The structure statistics of one configuration.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Structure {
    /// contact gap g used to call two axes in contact, nm
    pub contact_gap_nm: f64,
    /// tubes analysed
    pub tubes: usize,
    /// contact patches, all tubes
    pub patches: usize,
    /// free segments (between two patches of one tube), all tubes
    pub free_segments: usize,
    /// n: free segments per unit volume, 1/nm³
    pub number_density_per_nm3: f64,
    /// l: mean free-segment length, nm
    pub free_length_nm: f64,
    /// a: mean contact-patch length, nm
    pub contact_length_nm: f64,
    /// κ₀: curvature equivalent to the free segments' bending energy by (2.8), 1/nm
    pub curvature_per_nm: f64,
    /// θ = κ₀ l/2, rad
    pub theta: f64,
    /// fraction of the tubes' length in contact patches
    pub contact_fraction: f64,
    /// fraction of the tubes' length in end runs (before the first / after the last patch, or a
    /// tube without patches)
    pub end_fraction: f64,
    /// fraction of the bending energy held by the free segments (the seed: all of it)
    pub free_bending_fraction: f64,
}

impl Structure {
    /// The micromechanical segments of (2.8)–(2.14) with bending stiffness `k` (nN·nm²) and
    /// line energy `gamma_l` (nN).
    pub fn segments(&self, k: f64, gamma_l: f64) -> Segments {
        Segments {
            number_density: self.number_density_per_nm3,
            free_length: self.free_length_nm,
            contact_length: self.contact_length_nm,
            bending_stiffness: k,
            line_energy: gamma_l,
        }
    }
}

/// One tube's geometry along its arclength: segment start arclengths (with the total at the end)
/// and the bending energy of each interior vertex.
struct TubeLine {
    arc: Vec<f64>,
    vertex_bending: Vec<f64>,
    bending_stiffness: f64,
}

/// Measure the structure of the turf `rods` at `x` (nm) from the listed segment pairs `pairs`
/// (segments numbered tube by tube in the order of `rods`, as [`super::vdw_term::VdwTerm`]
/// numbers them), with contact gap `gap` (nm) and the turf's volume `volume` (nm³).
pub fn measure(
    rods: &RodSet,
    pairs: &[PairGeometry],
    x: &[f64],
    gap: f64,
    volume: f64,
) -> Structure {
    let lines: Vec<TubeLine> = rods
        .rods()
        .iter()
        .map(|r| {
            let node = |i: usize| {
                let k = 3 * (r.first_node() + i);
                Vector::new(x[k], x[k + 1], x[k + 2])
            };
            let mut arc = vec![0.0];
            for j in 0..r.segments() {
                arc.push(arc[j] + (node(j + 1) - node(j)).length());
            }
            TubeLine {
                arc,
                vertex_bending: r.vertex_bending(x),
                bending_stiffness: r.stiffness().bending,
            }
        })
        .collect();
    // segment index → (tube, local segment)
    let owner: Vec<(usize, usize)> = lines
        .iter()
        .enumerate()
        .flat_map(|(t, l)| (0..l.arc.len() - 1).map(move |k| (t, k)))
        .collect();
    let mut contact: Vec<Vec<[f64; 2]>> = vec![Vec::new(); lines.len()];
    for p in pairs {
        let reach = p.r_sum + gap;
        for (seg, own, other) in [(p.segments[0], p.a, p.b), (p.segments[1], p.b, p.a)] {
            if let Some([t0, t1]) = within(own, other, reach) {
                let (t, k) = owner[seg];
                let (s0, s1) = (lines[t].arc[k], lines[t].arc[k + 1]);
                contact[t].push([s0 + t0 * (s1 - s0), s0 + t1 * (s1 - s0)]);
            }
        }
    }
    let mut totals = Totals::default();
    for (line, intervals) in lines.iter().zip(contact) {
        totals.add(line, &merge(intervals));
    }
    totals.finish(gap, lines.len(), volume)
}

/// Sums over the tubes.
#[derive(Default)]
struct Totals {
    length: f64,
    patches: usize,
    patch_length: f64,
    free: usize,
    free_length: f64,
    end_length: f64,
    free_bending: f64,
    bending: f64,
    /// Σ K l over the free segments, nN·nm³
    stiffness_length: f64,
}

impl Totals {
    /// Add one tube with its merged, sorted contact patches.
    fn add(&mut self, line: &TubeLine, patches: &[[f64; 2]]) {
        let total = *line.arc.last().unwrap_or(&0.0);
        self.length += total;
        self.bending += line.vertex_bending.iter().sum::<f64>();
        self.patches += patches.len();
        self.patch_length += patches.iter().map(|p| p[1] - p[0]).sum::<f64>();
        match (patches.first(), patches.last()) {
            (Some(first), Some(last)) => self.end_length += first[0] + (total - last[1]),
            _ => self.end_length += total,
        }
        for w in patches.windows(2) {
            let (start, end) = (w[0][1], w[1][0]);
            self.free += 1;
            self.free_length += end - start;
            self.stiffness_length += line.bending_stiffness * (end - start);
            // interior vertex v sits at arclength arc[v]
            self.free_bending += line
                .vertex_bending
                .iter()
                .enumerate()
                .filter(|&(i, _)| line.arc[i + 1] > start && line.arc[i + 1] < end)
                .map(|(_, u)| u)
                .sum::<f64>();
        }
    }

    fn finish(self, gap: f64, tubes: usize, volume: f64) -> Structure {
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        let free_length = ratio(self.free_length, self.free as f64);
        let curvature = ratio(2.0 * self.free_bending, self.stiffness_length).sqrt();
        Structure {
            contact_gap_nm: gap,
            tubes,
            patches: self.patches,
            free_segments: self.free,
            number_density_per_nm3: ratio(self.free as f64, volume),
            free_length_nm: free_length,
            contact_length_nm: ratio(self.patch_length, self.patches as f64),
            curvature_per_nm: curvature,
            theta: 0.5 * curvature * free_length,
            contact_fraction: ratio(self.patch_length, self.length),
            end_fraction: ratio(self.end_length, self.length),
            free_bending_fraction: ratio(self.free_bending, self.bending),
        }
    }
}

/// Merge arclength intervals into disjoint sorted patches (touching or overlapping ones join).
fn merge(mut intervals: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    intervals.sort_by(|p, q| p[0].total_cmp(&q[0]));
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(intervals.len());
    for iv in intervals {
        match out.last_mut() {
            Some(last) if iv[0] <= last[1] => last[1] = last[1].max(iv[1]),
            _ => out.push(iv),
        }
    }
    out
}

/// Distance (nm) from the point `p` to the segment `s`.
fn point_segment_distance(p: Vector, s: [Vector; 2]) -> f64 {
    let e = s[1] - s[0];
    let ee = e.dot(e);
    let t = if ee > 0.0 {
        ((p - s[0]).dot(e) / ee).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (s[0] + e * t)).length()
}

/// The parameter interval [t₀, t₁] ⊂ [0, 1] of the points of segment `own` within `reach` (nm)
/// of segment `other`, or `None`. The distance from a point moving linearly along `own` to the
/// convex set `other` is convex in t, so the set is one interval: its minimum by golden-section
/// search, its ends by bisection.
fn within(own: [Vector; 2], other: [Vector; 2], reach: f64) -> Option<[f64; 2]> {
    let d = |t: f64| point_segment_distance(own[0] + (own[1] - own[0]) * t, other);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..SEARCH_ITERATIONS {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if d(m1) <= d(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let t_min = 0.5 * (lo + hi);
    if d(t_min) > reach {
        return None;
    }
    // the end between `out` (beyond reach) and `inside`
    let edge = |mut out: f64, mut inside: f64| {
        for _ in 0..SEARCH_ITERATIONS {
            let mid = 0.5 * (out + inside);
            if d(mid) <= reach {
                inside = mid;
            } else {
                out = mid;
            }
        }
        inside
    };
    let t0 = if d(0.0) <= reach {
        0.0
    } else {
        edge(0.0, t_min)
    };
    let t1 = if d(1.0) <= reach {
        1.0
    } else {
        edge(1.0, t_min)
    };
    Some([t0, t1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::rod::{Rod, RodStiffness};

    fn v(x: f64, y: f64, z: f64) -> Vector {
        Vector::new(x, y, z)
    }

    #[test]
    fn the_contact_interval_of_parallel_and_crossed_axes() {
        // parallel: `own` along z from 0 to 100 at x = 0, `other` from z = 50 to 150 at x = 40.5
        let own = [v(0.0, 0.0, 0.0), v(0.0, 0.0, 100.0)];
        let other = [v(40.5, 0.0, 50.0), v(40.5, 0.0, 150.0)];
        let [t0, t1] = within(own, other, 41.0).unwrap();
        // points with z < 50 are within reach while the end cap distance √(40.5² + (50 − z)²) ≤ 41
        let z0 = 50.0 - (41.0f64.powi(2) - 40.5f64.powi(2)).sqrt();
        assert!((t0 - z0 / 100.0).abs() < 1e-12 && t1 == 1.0, "{t0} {t1}");
        assert!(within(own, other, 40.4).is_none());
        // crossed at right angles, axis distance 40.5: |t − ½|·100 ≤ √(41² − 40.5²)
        let other = [v(40.5, -50.0, 50.0), v(40.5, 50.0, 50.0)];
        let [t0, t1] = within(own, other, 41.0).unwrap();
        let half = (41.0f64.powi(2) - 40.5f64.powi(2)).sqrt() / 100.0;
        assert!((t0 - (0.5 - half)).abs() < 1e-12 && (t1 - (0.5 + half)).abs() < 1e-12);
    }

    #[test]
    fn intervals_merge_into_patches() {
        let m = merge(vec![[5.0, 6.0], [0.0, 2.0], [1.0, 3.0], [3.0, 4.0]]);
        assert_eq!(m, vec![[0.0, 4.0], [5.0, 6.0]]);
    }

    /// A straight tube along z and beside it, 40.34 nm away (in contact), a tube straight at rest
    /// that leaves it over the arclength [150, 350] nm as a circular bow of half-angle θ = 0.2
    /// (kinked by θ where it leaves and rejoins), 10 nm segments.
    #[test]
    fn a_bowed_tube_between_two_patches_gives_one_free_segment_of_its_curvature() {
        let (r_sum, gap, seg) = (40.0, 1.0, 10.0);
        let k = 2.0e7;
        let stiffness = RodStiffness {
            bending: k,
            axial: 1.0e5,
        };
        let (l, theta) = (200.0, 0.2_f64);
        let kappa = 2.0 * theta / l;
        let chord = 2.0 * theta.sin() / kappa;
        let base = r_sum + 0.34;
        let bowed: Vec<[f64; 3]> = (0..=50)
            .map(|i| {
                let s = seg * i as f64;
                if s <= 150.0 {
                    [base, 0.0, s]
                } else if s >= 350.0 {
                    [base, 0.0, s - l + chord]
                } else {
                    let phi = -theta + kappa * (s - 150.0);
                    let x = base + (phi.cos() - theta.cos()) / kappa;
                    [x, 0.0, 150.0 + (theta.sin() + phi.sin()) / kappa]
                }
            })
            .collect();
        let height = bowed[50][2];
        let straight: Vec<[f64; 3]> = (0..=50)
            .map(|i| [0.0, 0.0, height * i as f64 / 50.0])
            .collect();
        let rods = RodSet::new(vec![
            Rod::straight(0, &straight, stiffness).unwrap(),
            Rod::straight(51, &bowed, stiffness).unwrap(),
        ]);
        let mut x: Vec<f64> = straight.iter().flatten().copied().collect();
        x.extend(bowed.iter().flatten());
        // every segment pair between the tubes (a complete list: only pairs within reach count)
        let node = |n: usize| v(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
        let mut pairs = Vec::new();
        for a in 0..50 {
            for b in 0..50 {
                pairs.push(PairGeometry {
                    segments: [a, 50 + b],
                    a: [node(a), node(a + 1)],
                    b: [node(51 + b), node(52 + b)],
                    r_sum,
                });
            }
        }
        let s = measure(&rods, &pairs, &x, gap, 1e6);
        // two patches on each tube, one free segment on each (the straight tube's is unbent)
        assert_eq!((s.patches, s.free_segments), (4, 2), "{s:?}");
        assert_eq!(s.number_density_per_nm3, 2.0 / 1e6);
        // the bowed tube is free where x > r_sum + g, i.e. |φ| < φ_g with cos φ_g = cos θ +
        // (g − 0.34)κ: arclength 2φ_g/κ. The straight tube's points are free where their distance
        // to the arc, R − |p − c| (centre c = (0.34 + r_sum − R cos θ, ·), R = 1/κ), exceeds
        // r_sum + g: height 2√((R − r_sum − g)² − c_x²). The chords sit inside the arc by their
        // sagitta seg²κ/8 = 0.025 nm, which moves each end by ≈ 0.13 nm.
        let phi_g = (theta.cos() + (gap - 0.34) * kappa).acos();
        let radius = 1.0 / kappa;
        let c_x = base - radius * theta.cos();
        let straight_free = 2.0 * ((radius - r_sum - gap).powi(2) - c_x * c_x).sqrt();
        let expected = 0.5 * (2.0 * phi_g / kappa + straight_free);
        assert!(
            (s.free_length_nm - expected).abs() < 0.5,
            "{} vs {expected}",
            s.free_length_nm
        );
        // κ₀² = 2 Σ U_free/(K Σ l): the bowed tube's vertices at s = 160 … 340 turn by κ·seg,
        // each holding K/(2 seg)·(2 tan(κ seg/2))² (the kinks at 150 and 350 are in the patches)
        let u_vertex = k / (2.0 * seg) * (2.0 * (0.5 * kappa * seg).tan()).powi(2);
        let kappa0 = (2.0 * 19.0 * u_vertex / (k * 2.0 * expected)).sqrt();
        assert!(
            (s.curvature_per_nm / kappa0 - 1.0).abs() < 2e-3,
            "{} vs {kappa0}",
            s.curvature_per_nm
        );
        assert!((s.theta - 0.5 * kappa0 * expected).abs() < 1e-3 * s.theta);
        assert!(s.free_bending_fraction < 1.0 && s.free_bending_fraction > 0.0);
        // the patches reach both ends of both tubes: no end runs, the rest is in contact
        let polyline = |p: &[[f64; 3]]| -> f64 {
            p.windows(2)
                .map(|w| (v(w[1][0], w[1][1], w[1][2]) - v(w[0][0], w[0][1], w[0][2])).length())
                .sum()
        };
        let length = polyline(&straight) + polyline(&bowed);
        assert_eq!(s.end_fraction, 0.0);
        let contact = s.contact_fraction * length + 2.0 * s.free_length_nm;
        assert!(
            (contact / length - 1.0).abs() < 1e-12,
            "{contact} vs {length}"
        );
    }
}
