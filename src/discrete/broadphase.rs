//! Broadphase for segment–segment interactions: a parry BVH over segment
//! boxes, refitted as tubes move, periodic images in x and y, and a Verlet neighbour list.
//!
//! A pair (a, b, s) means: segment a interacts with segment b translated by s·(L_x, L_y, 0).
//! Segment i has a *reach* ρᵢ (its tube radius plus half the cutoff gap); a pair is listed when
//! the exact segment–segment distance is below ρ_a + ρ_b + skin. Boxes loosened by ρᵢ + skin/2
//! overlap whenever that holds, so the BVH only prunes. The list stays valid (contains every
//! pair within ρ_a + ρ_b) until some node has moved more than skin/2 since the build, because a
//! segment's points move no further than its farthest node ([`Broadphase::update`] rebuilds then).
//!
//! Periodic images use shifts s ∈ {−1, 0, 1} along each periodic axis by default
//! ([`ImageSearch::Nearest`]), so tubes must stay within about half a box width of each other;
//! [`ImageSearch::Span`] searches |s| ≤ k instead, k the fewest whole periods that the nodes'
//! span plus the interaction reach covers (a turf packed into a box smaller than its tubes'
//! lean). Each unordered pair is listed once, canonically: a < b, or a = b with s
//! lexicographically positive (a segment and its own image); [`brute_force_pairs`] always
//! searches the span.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;

use super::vdw::ImageSearch;

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
    pub fn offset(&self, s: [i8; 2]) -> Vector {
        Vector::new(
            f64::from(s[0]) * self.lx.unwrap_or(0.0),
            f64::from(s[1]) * self.ly.unwrap_or(0.0),
            0.0,
        )
    }

    /// All image shifts to search, (0, 0) first: |s| ≤ `reach` along each periodic axis.
    fn shifts(&self, reach: [i8; 2]) -> Vec<[i8; 2]> {
        let range = |p: Option<f64>, k: i8| match p {
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
    /// being that of all nodes. Tubes that stay within half a box of it need only ±1; a dense
    /// turf whose tubes lean across several boxes needs more.
    fn reach(&self, segs: &SegmentSet, x: &[f64], skin: f64) -> [i8; 2] {
        let rho = segs.reach.iter().fold(0.0f64, |m, &r| m.max(r));
        let axis = |d: usize, l: Option<f64>| -> i8 {
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
                k.clamp(1.0, f64::from(i8::MAX)) as i8
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
    pub shift: [i8; 2],
}

impl SegmentPair {
    /// The canonical form of the pair (a, b, s) ≡ (b, a, −s); `None` for a segment with itself.
    fn canonical(a: u32, b: u32, s: [i8; 2]) -> Option<SegmentPair> {
        let neg = [-s[0], -s[1]];
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
    x_ref: Vec<f64>,
    pairs: Vec<SegmentPair>,
    info: BroadphaseInfo,
    search: ImageSearch,
}

impl Broadphase {
    /// Build the tree and the first pair list at configuration `x`, searching the nearest
    /// periodic images.
    pub fn new(
        segs: SegmentSet,
        pbox: PeriodicBox,
        skin: f64,
        x: &[f64],
        keep: &dyn Fn(&SegmentPair) -> bool,
    ) -> Self {
        Self::with_search(segs, pbox, skin, ImageSearch::Nearest, x, keep)
    }

    /// Build the tree and the first pair list at configuration `x`, searching the periodic
    /// images as `search` says.
    pub fn with_search(
        segs: SegmentSet,
        pbox: PeriodicBox,
        skin: f64,
        search: ImageSearch,
        x: &[f64],
        keep: &dyn Fn(&SegmentPair) -> bool,
    ) -> Self {
        let boxes: Vec<Aabb> = (0..segs.nodes.len())
            .map(|i| segment_box(&segs, x, i, skin))
            .collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
        let mut bp = Broadphase {
            segs,
            pbox,
            skin,
            bvh,
            workspace: BvhWorkspace::default(),
            x_ref: x.to_vec(),
            pairs: Vec::new(),
            info: BroadphaseInfo::default(),
            search,
        };
        bp.collect_pairs(x, keep);
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

    /// Bring the pair list up to date for `x`: rebuild (refit the tree, collect pairs) when any
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

    /// Refit the tree and collect the pairs at `x`.
    fn rebuild(&mut self, x: &[f64], keep: &dyn Fn(&SegmentPair) -> bool) {
        for i in 0..self.segs.nodes.len() {
            let b = segment_box(&self.segs, x, i, self.skin);
            self.bvh.insert_or_update_partially(b, i as u32, 0.0);
        }
        self.bvh.refit(&mut self.workspace);
        self.x_ref.clear();
        self.x_ref.extend_from_slice(x);
        self.collect_pairs(x, keep);
    }

    fn collect_pairs(&mut self, x: &[f64], keep: &dyn Fn(&SegmentPair) -> bool) {
        let mut cand = Vec::new();
        self.bvh
            .traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |i, j| {
                cand.extend(SegmentPair::canonical(i, j, [0, 0]))
            });
        // the span is taken with a skin of motion to spare: the list is kept until a node
        // moves skin/2, which may widen the span by skin
        let reach = match self.search {
            ImageSearch::Nearest => [1, 1],
            ImageSearch::Span => self.pbox.reach(&self.segs, x, 2.0 * self.skin),
        };
        for s in self.pbox.shifts(reach).into_iter().skip(1) {
            let off = self.pbox.offset(s);
            for a in 0..self.segs.nodes.len() {
                // boxes of b + off overlapping a's box ⇔ b's box overlapping a's box − off
                let mut q = segment_box(&self.segs, x, a, self.skin);
                q.mins -= off;
                q.maxs -= off;
                cand.extend(
                    self.bvh
                        .intersect_aabb(&q)
                        .filter_map(|b| SegmentPair::canonical(a as u32, b, s)),
                );
            }
        }
        cand.sort();
        cand.dedup();
        let (segs, pbox, skin) = (&self.segs, &self.pbox, self.skin);
        cand.retain(|p| keep(p) && segs.within(x, pbox, p, skin));
        self.pairs = cand;
        self.info.builds += 1;
    }
}

/// Bounding box of segment i loosened by its reach + skin/2.
fn segment_box(segs: &SegmentSet, x: &[f64], i: usize, skin: f64) -> Aabb {
    let [p, q] = segs.ends(x, i);
    Aabb::from_points([p, q]).loosened(segs.reach[i] + 0.5 * skin)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two segments two periods and 1 nm apart (a tube leaning across two boxes): the pair at
    /// shift −2 is missed by the default search of ±1, found by the span search, by the tree
    /// and by brute force alike.
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
        assert!(
            !bp.pairs().contains(&want),
            "the nearest images only by default"
        );
        let bp = Broadphase::with_search(segs.clone(), pbox, 0.5, ImageSearch::Span, &x, &keep);
        assert!(bp.pairs().contains(&want), "{:?}", bp.pairs());
        assert_eq!(bp.pairs(), brute_force_pairs(&segs, &x, &pbox, 0.5, &keep));
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
