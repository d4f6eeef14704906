//! Broadphase for segment–segment interactions: a parry BVH over segment
//! boxes, rebuilt as tubes move, periodic images in x and y, and a Verlet neighbour list.
//!
//! A pair (a, b, s) means: segment a interacts with segment b translated by s·(L_x, L_y, 0).
//! Segment i has a *reach* ρᵢ (its tube radius plus half the cutoff gap); a pair is listed when
//! the exact segment–segment distance is below ρ_a + ρ_b + skin. Boxes loosened by ρᵢ + skin/2
//! overlap whenever that holds, so the BVH only prunes. The list stays valid (contains every
//! pair within ρ_a + ρ_b) until some node has moved more than skin/2 since the build, because a
//! segment's points move no further than its farthest node ([`Broadphase::update`] rebuilds then).
//!
//! Periodic images, complete however far the tubes lean (under compression a tube leaning
//! across more than half a box meets images at shift ±2 or beyond). The search works on
//! *pieces*: each segment cut into parts no longer than a period along each periodic axis, each
//! part's loosened box wrapped into the primary cell by whole periods w. The tree holds the
//! wrapped boxes, which therefore all lie within about one period of the cell; piece u is
//! queried at every shift s whose translate of its box still overlaps the box bounding all
//! wrapped boxes (a few shifts), and a hit v is the segment pair at shift w_u + s − w_v. A long
//! or far-flung segment (a trial state of a line search) costs pieces in proportion to its
//! length in periods, never a search over every image of the box bounding the turf. Each
//! unordered pair is listed once, canonically: a < b, or a = b with s lexicographically
//! positive (a segment and its own image); [`brute_force_pairs`] searches every shift the
//! nodes' span allows.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;
use rayon::prelude::*;

/// A periodic box in x and y (each axis periodic or not); z is never periodic (substrate).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PeriodicBox {
    /// period along x, nm (`None`: open)
    pub lx: Option<f64>,
    /// period along y, nm (`None`: open)
    pub ly: Option<f64>,
}

impl PeriodicBox {
    /// The translation (nm) of image shift `s`.
    pub fn offset(&self, s: [i32; 2]) -> Vector {
        Vector::new(
            f64::from(s[0]) * self.lx.unwrap_or(0.0),
            f64::from(s[1]) * self.ly.unwrap_or(0.0),
            0.0,
        )
    }

    /// All image shifts |s| ≤ `reach` along each periodic axis, (0, 0) first.
    fn shifts(&self, reach: [i32; 2]) -> Vec<[i32; 2]> {
        let range = |p: Option<f64>, k: i32| match p {
            Some(_) => std::iter::once(0)
                .chain((1..=k.max(1)).flat_map(|i| [-i, i]))
                .collect(),
            None => vec![0],
        };
        let mut out = Vec::new();
        for &sx in &range(self.lx, reach[0]) {
            for &sy in &range(self.ly, reach[1]) {
                out.push([sx, sy]);
            }
        }
        out
    }

    /// The image shifts that can bring two segments of `segs` at `x` within reach + `skin`
    /// of each other: ⌈(span + 2ρ_max + skin)/L⌉ − 1 along each axis (at least 1), the span
    /// being that of all nodes (the brute-force reference's bound).
    fn reach(&self, segs: &SegmentSet, x: &[f64], skin: f64) -> [i32; 2] {
        let rho = segs.reach.iter().fold(0.0f64, |m, &r| m.max(r));
        let axis = |d: usize, l: Option<f64>| -> i32 {
            let Some(l) = l.filter(|l| *l > 0.0) else {
                return 1;
            };
            let (lo, hi) = x
                .chunks_exact(3)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p[d]), hi.max(p[d]))
                });
            let k = ((hi - lo + 2.0 * rho + skin) / l).ceil() - 1.0;
            if k.is_finite() {
                k.clamp(1.0, f64::from(i16::MAX)) as i32
            } else {
                1
            }
        };
        [axis(0, self.lx), axis(1, self.ly)]
    }
}

/// One candidate interaction: segment `a` with segment `b` translated by `shift`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SegmentPair {
    /// first segment index
    pub a: u32,
    /// second segment index
    pub b: u32,
    /// image shift of `b` in box periods (x, y)
    pub shift: [i32; 2],
}

impl SegmentPair {
    /// The canonical form of the pair (a, b, s) ≡ (b, a, −s); `None` for a segment with itself.
    fn canonical(a: u32, b: u32, s: [i32; 2]) -> Option<SegmentPair> {
        let neg = [s[0].saturating_neg(), s[1].saturating_neg()];
        match a.cmp(&b) {
            std::cmp::Ordering::Less => Some(SegmentPair { a, b, shift: s }),
            std::cmp::Ordering::Greater => Some(SegmentPair {
                a: b,
                b: a,
                shift: neg,
            }),
            std::cmp::Ordering::Equal => (s > neg).then_some(SegmentPair { a, b, shift: s }),
        }
    }
}

/// Node pair of each segment, and the reach of each segment (nm).
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentSet {
    /// node indices (into the coordinate vector, 3 per node) of each segment's ends
    pub nodes: Vec<[usize; 2]>,
    /// reach ρᵢ of each segment, nm
    pub reach: Vec<f64>,
}

impl SegmentSet {
    fn ends(&self, x: &[f64], i: usize) -> [Vector; 2] {
        let v = |n: usize| Vector::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
        [v(self.nodes[i][0]), v(self.nodes[i][1])]
    }

    /// Exact distance (nm) between segment a and segment b translated by `offset`.
    fn distance(&self, x: &[f64], a: usize, b: usize, offset: Vector) -> f64 {
        let sa = self.ends(x, a);
        let sb = self.ends(x, b);
        let (b0, b1) = (sb[0] + offset, sb[1] + offset);
        let (la, lb) =
            closest_points_segment_segment_with_locations_nD((&sa[0], &sa[1]), (&b0, &b1));
        let [ua, va] = la.barycentric_coordinates();
        let [ub, vb] = lb.barycentric_coordinates();
        ((sa[0] * ua + sa[1] * va) - (b0 * ub + b1 * vb)).length()
    }

    /// Whether (a, b, shift) is within ρ_a + ρ_b + skin.
    fn within(&self, x: &[f64], pbox: &PeriodicBox, p: &SegmentPair, skin: f64) -> bool {
        let (a, b) = (p.a as usize, p.b as usize);
        self.distance(x, a, b, pbox.offset(p.shift)) < self.reach[a] + self.reach[b] + skin
    }
}

/// The O(n²) reference: every canonical pair within reach + skin that `keep` accepts, sorted.
pub fn brute_force_pairs(
    segs: &SegmentSet,
    x: &[f64],
    pbox: &PeriodicBox,
    skin: f64,
    keep: &dyn Fn(&SegmentPair) -> bool,
) -> Vec<SegmentPair> {
    let n = segs.nodes.len() as u32;
    let mut out = Vec::new();
    for s in pbox.shifts(pbox.reach(segs, x, skin)) {
        for a in 0..n {
            for b in a..n {
                if let Some(p) = SegmentPair::canonical(a, b, s) {
                    if keep(&p) && segs.within(x, pbox, &p, skin) {
                        out.push(p);
                    }
                }
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

/// Counters of the broadphase's work.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BroadphaseInfo {
    /// neighbour-list builds so far
    pub builds: usize,
    /// calls to [`Broadphase::update`] that kept the list
    pub reuses: usize,
}

/// The BVH, its workspace, the Verlet reference positions and the current pair list.
pub struct Broadphase {
    segs: SegmentSet,
    pbox: PeriodicBox,
    skin: f64,
    bvh: Bvh,
    workspace: BvhWorkspace,
    pieces: Vec<Piece>,
    x_ref: Vec<f64>,
    pairs: Vec<SegmentPair>,
    info: BroadphaseInfo,
}

/// Part of a segment searched as one box: the segment, and the whole periods its box was
/// moved by into the primary cell (the box in the tree is the piece's box − w·(L_x, L_y)).
#[derive(Debug, Clone, Copy)]
struct Piece {
    seg: u32,
    wrap: [i32; 2],
}

/// Most pieces one segment is cut into, and most image shifts searched along an axis from one
/// piece: bounds reached only by a trial state stretched across ~10² periods, whose
/// stretching energy rules it out; the list is complete below them.
const MAX_PIECES: usize = 256;
const MAX_WINDOW: i32 = 16;

impl Broadphase {
    /// Build the tree and the first pair list at configuration `x`.
    pub fn new(
        segs: SegmentSet,
        pbox: PeriodicBox,
        skin: f64,
        x: &[f64],
        keep: &dyn Fn(&SegmentPair) -> bool,
    ) -> Self {
        let mut bp = Broadphase {
            segs,
            pbox,
            skin,
            bvh: Bvh::new(),
            workspace: BvhWorkspace::default(),
            pieces: Vec::new(),
            x_ref: Vec::new(),
            pairs: Vec::new(),
            info: BroadphaseInfo::default(),
        };
        bp.rebuild(x, keep);
        bp
    }

    /// The current pair list (sorted, canonical).
    pub fn pairs(&self) -> &[SegmentPair] {
        &self.pairs
    }

    /// Build and reuse counters.
    pub fn info(&self) -> BroadphaseInfo {
        self.info
    }

    /// The segments.
    pub fn segments(&self) -> &SegmentSet {
        &self.segs
    }

    /// The periodic box.
    pub fn periodic_box(&self) -> PeriodicBox {
        self.pbox
    }

    /// Bring the pair list up to date for `x`: rebuild (the tree and the pairs) when any
    /// node has moved more than skin/2 since the last build; otherwise keep it. Returns whether
    /// it rebuilt.
    pub fn update(&mut self, x: &[f64], keep: &dyn Fn(&SegmentPair) -> bool) -> bool {
        let limit = 0.25 * self.skin * self.skin;
        let moved = x
            .chunks_exact(3)
            .zip(self.x_ref.chunks_exact(3))
            .any(|(p, q)| {
                let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit
            });
        if !moved {
            self.info.reuses += 1;
            return false;
        }
        self.rebuild(x, keep);
        true
    }

    /// Change the periods to `pbox` (the box deforming, [`super::rve`]) and rebuild the list
    /// at `x`: image pairs move by the change of period, which the Verlet test on node motion
    /// does not see.
    pub fn set_box(&mut self, pbox: PeriodicBox, x: &[f64], keep: &dyn Fn(&SegmentPair) -> bool) {
        self.pbox = pbox;
        self.rebuild(x, keep);
    }

    /// Cut and wrap the pieces at `x`, build the tree over them and collect the pairs.
    fn rebuild(&mut self, x: &[f64], keep: &dyn Fn(&SegmentPair) -> bool) {
        let (pieces, boxes) = wrapped_pieces(&self.segs, &self.pbox, x, self.skin);
        self.bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
        self.pieces = pieces;
        self.x_ref.clear();
        self.x_ref.extend_from_slice(x);
        self.collect_pairs(x, &boxes, keep);
    }

    /// List the pairs at `x` from the pieces' wrapped `boxes` (those the tree holds).
    fn collect_pairs(&mut self, x: &[f64], boxes: &[Aabb], keep: &dyn Fn(&SegmentPair) -> bool) {
        let pieces = &self.pieces;
        let pair = |u: u32, v: u32, s: [i32; 2]| {
            let (pu, pv) = (pieces[u as usize], pieces[v as usize]);
            let shift = [0, 1].map(|d| pu.wrap[d].saturating_add(s[d]).saturating_sub(pv.wrap[d]));
            SegmentPair::canonical(pu.seg, pv.seg, shift)
        };
        let mut cand = Vec::new();
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |u, v| {
                cand.extend(pair(u, v, [0, 0]))
            });
        let Some(all) = boxes.iter().copied().reduce(|u, b| u.merged(&b)) else {
            self.pairs.clear();
            return;
        };
        for (u, q) in boxes.iter().enumerate() {
            let [wx, wy] = [(0, self.pbox.lx), (1, self.pbox.ly)]
                .map(|(d, l)| image_window(q.mins[d], q.maxs[d], all.mins[d], all.maxs[d], l));
            for sx in wx[0]..=wx[1] {
                for sy in wy[0]..=wy[1] {
                    if [sx, sy] == [0, 0] {
                        continue;
                    }
                    // boxes of v + s·L overlapping u's box ⇔ v's box overlapping u's box − s·L
                    let off = self.pbox.offset([sx, sy]);
                    let mut q = *q;
                    q.mins -= off;
                    q.maxs -= off;
                    cand.extend(
                        self.bvh
                            .intersect_aabb(&q)
                            .filter_map(|v| pair(u as u32, v, [sx, sy])),
                    );
                }
            }
        }
        // sorted and filtered on rayon's workers (the same list as serially: the order is
        // restored by the sort and kept by the filter)
        cand.par_sort_unstable();
        cand.dedup();
        cand.retain(|p| keep(p));
        let (segs, pbox, skin) = (&self.segs, &self.pbox, self.skin);
        self.pairs = cand
            .into_par_iter()
            .filter(|p| segs.within(x, pbox, p, skin))
            .collect();
        self.info.builds += 1;
    }
}

/// The image shifts s (one axis) for which the interval [lo, hi] − s·l overlaps the interval
/// [all_lo, all_hi] bounding every wrapped piece, at most [`MAX_WINDOW`] either side; `[0, 0]`
/// on an open axis.
fn image_window(lo: f64, hi: f64, all_lo: f64, all_hi: f64, l: Option<f64>) -> [i32; 2] {
    let Some(l) = l.filter(|l| *l > 0.0) else {
        return [0, 0];
    };
    let bound = |v: f64| v.clamp(-f64::from(MAX_WINDOW), f64::from(MAX_WINDOW)) as i32;
    [
        bound(((lo - all_hi) / l).ceil()),
        bound(((hi - all_lo) / l).floor()),
    ]
}

/// Each segment cut into pieces no longer than a period along each periodic axis (at most
/// [`MAX_PIECES`]), and each piece's box, loosened by the segment's reach + skin/2, moved by
/// whole periods so that its centre lies in the primary cell.
fn wrapped_pieces(
    segs: &SegmentSet,
    pbox: &PeriodicBox,
    x: &[f64],
    skin: f64,
) -> (Vec<Piece>, Vec<Aabb>) {
    let periods = [pbox.lx, pbox.ly].map(|l| l.filter(|l| *l > 0.0));
    let mut pieces = Vec::with_capacity(segs.nodes.len());
    let mut boxes = Vec::with_capacity(segs.nodes.len());
    for (i, &rho) in segs.reach.iter().enumerate() {
        let [p, q] = segs.ends(x, i);
        let cuts = (0..2)
            .filter_map(|d| periods[d].map(|l| ((q[d] - p[d]).abs() / l).ceil()))
            .fold(1.0f64, |m, c| if c.is_finite() { m.max(c) } else { m })
            .min(MAX_PIECES as f64) as usize;
        for k in 0..cuts {
            let at = |t: f64| p + (q - p) * t;
            let b =
                Aabb::from_points([at(k as f64 / cuts as f64), at((k + 1) as f64 / cuts as f64)])
                    .loosened(rho + 0.5 * skin);
            let centre = b.center();
            let wrap = [0, 1].map(|d| match periods[d] {
                Some(l) => (centre[d] / l)
                    .floor()
                    .clamp(-f64::from(i32::MAX / 4), f64::from(i32::MAX / 4))
                    as i32,
                None => 0,
            });
            let off = pbox.offset(wrap);
            pieces.push(Piece {
                seg: i as u32,
                wrap,
            });
            boxes.push(Aabb::new(b.mins - off, b.maxs - off));
        }
    }
    (pieces, boxes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two segments two periods and 1 nm apart (a tube leaning across two boxes): the pair at
    /// shift −2, which a search of the nearest images (±1) misses, is found by the tree as by
    /// brute force.
    #[test]
    fn images_beyond_one_period_are_found() {
        let segs = SegmentSet {
            nodes: vec![[0, 1], [2, 3]],
            reach: vec![1.0, 1.0],
        };
        let x = [0.0, 0.0, 0.0, 0.0, 0.0, 5.0, 81.0, 0.0, 0.0, 81.0, 0.0, 5.0];
        let pbox = PeriodicBox {
            lx: Some(40.0),
            ly: Some(40.0),
        };
        let keep = |_: &SegmentPair| true;
        let bp = Broadphase::new(segs.clone(), pbox, 0.5, &x, &keep);
        let want = SegmentPair {
            a: 0,
            b: 1,
            shift: [-2, 0],
        };
        assert!(bp.pairs().contains(&want), "{:?}", bp.pairs());
        assert_eq!(bp.pairs(), brute_force_pairs(&segs, &x, &pbox, 0.5, &keep));
    }

    /// Chains of segments leaning across one to four boxes in x and y, in a small box: the
    /// tree's list equals brute force's, and it holds shifts beyond ±1.
    #[test]
    fn leaning_chains_in_a_small_box_match_brute_force() {
        let (tubes, per) = (6, 8);
        let pbox = PeriodicBox {
            lx: Some(30.0),
            ly: Some(25.0),
        };
        let mut x = Vec::new();
        let mut nodes = Vec::new();
        for t in 0..tubes {
            let lean = [15.0 * (t as f64 + 1.0), -9.0 * t as f64];
            let base = [7.0 * t as f64, 3.0 * t as f64];
            for k in 0..=per {
                let h = k as f64 / per as f64;
                let wiggle = 2.0 * (3.0 * h + t as f64).sin();
                x.extend([
                    base[0] + lean[0] * h + wiggle,
                    base[1] + lean[1] * h,
                    40.0 * h,
                ]);
            }
            let first = t * (per + 1);
            nodes.extend((0..per).map(|k| [first + k, first + k + 1]));
        }
        let segs = SegmentSet {
            reach: vec![1.5; nodes.len()],
            nodes,
        };
        let keep = |_: &SegmentPair| true;
        let bp = Broadphase::new(segs.clone(), pbox, 0.5, &x, &keep);
        assert_eq!(bp.pairs(), brute_force_pairs(&segs, &x, &pbox, 0.5, &keep));
        assert!(bp.pairs().iter().any(|p| p.shift[0].abs() > 1));
    }

    /// A segment stretched across twenty periods (a line-search trial) among short ones: cut
    /// into pieces, its contacts with every image it passes are listed as brute force lists
    /// them; one flung 10⁹ periods away costs no search beyond the pieces' bound.
    #[test]
    fn a_segment_stretched_across_many_periods_is_searched_in_pieces() {
        let segs = SegmentSet {
            nodes: vec![[0, 1], [2, 3], [4, 5]],
            reach: vec![1.0; 3],
        };
        let pbox = PeriodicBox {
            lx: Some(40.0),
            ly: Some(40.0),
        };
        let keep = |_: &SegmentPair| true;
        let mut x = vec![
            0.0, 5.0, 2.0, 800.0, 5.0, 2.0, // stretched along x at y = 5
            10.0, 4.0, 0.0, 10.0, 4.0, 9.0, // upright, crossing it
            30.0, 30.0, 0.0, 30.0, 30.0, 9.0, // upright, far from it
        ];
        let bp = Broadphase::new(segs.clone(), pbox, 0.5, &x, &keep);
        assert_eq!(bp.pairs(), brute_force_pairs(&segs, &x, &pbox, 0.5, &keep));
        assert_eq!(
            bp.pairs().iter().filter(|p| p.a == 0 && p.b == 1).count(),
            20
        );
        x[3] = 4e10;
        let bp = Broadphase::new(segs.clone(), pbox, 0.5, &x, &keep);
        assert!(bp.pieces.len() <= MAX_PIECES + 2);
        assert!(bp
            .pairs()
            .iter()
            .all(|p| p.shift.iter().all(|s| s.abs() < i32::MAX / 2)));
    }

    #[test]
    fn canonical_pairs_are_unique() {
        let p = SegmentPair::canonical(3, 1, [1, -1]).unwrap();
        assert_eq!(p, SegmentPair::canonical(1, 3, [-1, 1]).unwrap());
        assert!(SegmentPair::canonical(2, 2, [0, 0]).is_none());
        let s = SegmentPair::canonical(2, 2, [1, 0]);
        assert!(s.is_some() ^ SegmentPair::canonical(2, 2, [-1, 0]).is_some());
    }

    #[test]
    fn segment_distance_of_crossed_segments() {
        let segs = SegmentSet {
            nodes: vec![[0, 1], [2, 3]],
            reach: vec![1.0, 1.0],
        };
        let x = [-1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0, 2.0, 0.0, 1.0, 2.0];
        assert!((segs.distance(&x, 0, 1, Vector::ZERO) - 2.0).abs() < 1e-14);
        let off = Vector::new(0.0, 0.0, -1.5);
        assert!((segs.distance(&x, 0, 1, off) - 0.5).abs() < 1e-14);
    }
}
