//! Meshes of the axisymmetric block under the indenter: r ∈ [0, W], z ∈ [−D, 0], the indented
//! surface at z = 0, the symmetry axis at r = 0 and a rigid base at z = −D.
//!
//! [`graded_block`] builds a balanced quadtree: square cells of the smallest size h₀ in the fine
//! zone under the contact (r ≤ r_f, z ≥ −d_f), growing away from it as h ≤ h₀ + g·d (d the
//! distance to the fine zone, g the grading), with neighbouring cells differing by at most a
//! factor 2 (2:1 balance). A cell without hanging nodes is split into two triangles; a cell
//! with hanging nodes on its edges gets a centre node and a fan. Every triangle then has angles
//! of at least 45° (right isosceles: no slivers), sizes change smoothly, and the element count grows only
//! logarithmically with the block size, so the block can be 50× the contact radius (PHYSICS.md:
//! a rigid base at depth L adds a compliance error of ≈ 0.42 a/L). [`edge_block`] builds the
//! same kind of mesh fine only over a band that follows the contact edge ([`EdgeZone`], adaptive
//! meshing; the state moves between meshes by [`super::transfer`]). [`read_msh`] reads a Gmsh
//! ASCII mesh (format 2.2) instead.

use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// Why a mesh cannot be built or read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// the sizes are not usable
    #[error("mesh: {0}")]
    Invalid(String),
    /// the requested sizes ask for more elements than allowed
    #[error(
        "mesh: the sizes ask for more than {max} elements (smallest {smallest} nm over a fine zone \
         {fine_radius} nm wide and {fine_depth} nm deep, block {width} × {depth} nm) — coarsen \
         mesh.smallest, shrink the fine zone (a smaller load or depth), or raise mesh.max_elements \
         (at most what the memory ceiling holds, TURF_MAX_MEMORY)"
    )]
    TooLarge {
        /// the ceiling
        max: usize,
        /// h₀, nm
        smallest: f64,
        /// r_f, nm
        fine_radius: f64,
        /// d_f, nm
        fine_depth: f64,
        /// W, nm
        width: f64,
        /// D, nm
        depth: f64,
    },
    /// a Gmsh file could not be parsed
    #[error("Gmsh mesh, line {line}: {reason}")]
    Msh {
        /// 1-based line number
        line: usize,
        /// what is wrong
        reason: String,
    },
}

/// Resolved sizes of a graded block (all in nm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BlockSpec {
    /// requested width W (rounded to a whole number of root cells)
    pub width: f64,
    /// requested depth D (rounded likewise)
    pub depth: f64,
    /// smallest element size h₀ (cell side)
    pub smallest: f64,
    /// radius of the fine zone r_f
    pub fine_radius: f64,
    /// depth of the fine zone d_f
    pub fine_depth: f64,
    /// growth of the cell size per unit distance from the fine zone (e.g. 0.3)
    pub grading: f64,
    /// refuse a mesh of more triangles than this (its memory and solve time would be out of
    /// reach: ~3 kB per element in the solve, docs/validation.md "Extremes")
    pub max_elements: usize,
}

/// A triangle mesh of the block.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// node positions (r, z), nm
    pub nodes: Vec<[f64; 2]>,
    /// triangles, counter-clockwise in (r, z)
    pub triangles: Vec<[usize; 3]>,
    /// nodes of the free surface z = 0, by increasing r
    pub surface: Vec<usize>,
    /// nodes on the axis r = 0
    pub axis: Vec<usize>,
    /// nodes on the base z = −D
    pub bottom: Vec<usize>,
    /// block width, nm
    pub width: f64,
    /// block depth, nm
    pub depth: f64,
}

/// Size and quality figures of a mesh.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeshReport {
    /// number of triangles
    pub elements: usize,
    /// number of nodes
    pub nodes: usize,
    /// degrees of freedom (2 per node, before constraints)
    pub dofs: usize,
    /// smallest triangle area, nm²
    pub smallest_area_nm2: f64,
    /// largest triangle area, nm²
    pub largest_area_nm2: f64,
    /// smallest interior angle, degrees
    pub min_angle_deg: f64,
    /// shortest surface segment, nm
    pub smallest_surface_segment_nm: f64,
    /// block width, nm
    pub width_nm: f64,
    /// block depth, nm
    pub depth_nm: f64,
}

/// Default ceiling on the number of triangles: a million elements take ~3 GB and minutes per
/// increment here (the 214,769-element Hertz mesh: 615 MB, docs/validation.md "Extremes").
pub const DEFAULT_MAX_ELEMENTS: usize = 1_000_000;

type Cell = (u32, u64, u64); // (level, i, j)

/// A band of fine elements that follows the contact edge (adaptive meshing): cells of
/// the smallest size h₀ over r ∈ [e₁ − w, e₂ + w] down to depth w, growing as h₀ + g·d away from
/// it, and at the surface over the contact (r ≤ e₂ + w) no larger than `surface` (growing as
/// `surface` + g·d below it). Usually e₁ = e₂ = e, the edge; while the edge jumps the band spans
/// the edge before and after. The process zone at the edge needs h₀; the contact's interior
/// only needs the sphere's profile resolved, so the element count grows like log(a/h₀) instead
/// of (a/h₀)².
///
/// Beyond e₂ the band goes on in [`TAIL_TIERS`] coarser tiers over the law's attractive tail:
/// tier k has cells of 2^(k+1) h₀ over r ∈ [e₁ − w, t_k + w] (depth w), where the law is soft
/// enough for them (`continuum::indent::band_span` sets the radii t_k from the gaps).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EdgeZone {
    /// the innermost edge e₁ the band covers, nm (0 before contact: the band sits at the axis)
    pub inner: f64,
    /// the outermost radius e₂ ≥ e₁ the band of h₀ covers, nm
    pub outer: f64,
    /// the outer radii t_k ≥ e₂ of the coarser tiers, nm (t_k = e₂: the tier adds nothing)
    pub tail: [f64; TAIL_TIERS],
    /// half-width w of the band, also its depth, nm
    pub half_width: f64,
    /// the largest surface element over the contact, nm (≥ h₀)
    pub surface: f64,
}

/// Coarser tiers of the band beyond its part of smallest elements, at 2, 4, … 256 h₀.
pub const TAIL_TIERS: usize = 8;

impl EdgeZone {
    /// The band at `inner`..`outer` without coarser tiers.
    pub fn plain(inner: f64, outer: f64, half_width: f64, surface: f64) -> Self {
        EdgeZone {
            inner,
            outer,
            tail: [outer; TAIL_TIERS],
            half_width,
            surface,
        }
    }

    /// The outermost radius any tier covers, nm.
    pub fn reach(&self) -> f64 {
        self.tail.iter().fold(self.outer, |a, &t| a.max(t))
    }
}

/// A graded, balanced quadtree triangulation of the block, fine over the zone r ≤ r_f,
/// z ≥ −d_f of `spec`.
pub fn graded_block(spec: &BlockSpec) -> Result<Mesh, MeshError> {
    let BlockSpec {
        smallest: h0,
        fine_radius,
        fine_depth,
        grading,
        ..
    } = *spec;
    quadtree(spec, &|s, r0, _r1, d0| {
        let dr = (r0 - fine_radius).max(0.0);
        let dz = (d0 - fine_depth).max(0.0);
        s > h0 + grading * dr.hypot(dz)
    })
}

/// A graded, balanced quadtree triangulation of the block, fine over the band of `zone` (the
/// fine zone sizes of `spec` are not used).
pub fn edge_block(spec: &BlockSpec, zone: &EdgeZone) -> Result<Mesh, MeshError> {
    let BlockSpec {
        smallest: h0,
        grading,
        ..
    } = *spec;
    let EdgeZone {
        inner,
        outer,
        tail,
        half_width: w,
        surface,
    } = *zone;
    if !(inner >= 0.0
        && outer >= inner
        && outer.is_finite()
        && tail.iter().all(|&t| t >= outer && t.is_finite())
        && w > 0.0
        && w.is_finite()
        && surface >= h0)
    {
        return Err(MeshError::Invalid(format!(
            "unusable edge zone {zone:?} (smallest element {h0} nm)"
        )));
    }
    let reach = zone.reach();
    quadtree(spec, &|s, r0, r1, d0| {
        let dz = (d0 - w).max(0.0);
        let tier = |size: f64, hi: f64| {
            let dr = (inner - w - r1).max(r0 - hi - w).max(0.0);
            s > size + grading * dr.hypot(dz)
        };
        let band = tier(h0, outer)
            || (tail.iter())
                .zip(1..)
                .any(|(&t, k)| tier(h0 * 2f64.powi(k), t));
        let strip = s > surface + grading * (r0 - reach - w).max(0.0).hypot(d0);
        band || strip
    })
}

/// The quadtree triangulation of the block whose cells are split while `split(s, r₀, r₁, d₀)`
/// (cell side s, radial extent [r₀, r₁], depth of its top d₀ ≥ 0) asks for it, down to h₀.
fn quadtree(
    spec: &BlockSpec,
    split: &dyn Fn(f64, f64, f64, f64) -> bool,
) -> Result<Mesh, MeshError> {
    let BlockSpec {
        width,
        depth,
        smallest: h0,
        fine_radius,
        fine_depth,
        grading,
        max_elements,
    } = *spec;
    let ok = |v: f64| v > 0.0 && v.is_finite();
    if !(ok(width)
        && ok(depth)
        && ok(h0)
        && grading >= 0.0
        && fine_radius >= 0.0
        && fine_depth >= 0.0)
    {
        return Err(MeshError::Invalid(format!("unusable block sizes {spec:?}")));
    }
    let levels = (width.min(depth) / h0).log2().floor().max(0.0) as u32;
    if levels > 40 {
        return Err(MeshError::Invalid(format!(
            "smallest element {h0} nm is too small for a {width} × {depth} nm block"
        )));
    }
    let root = h0 * 2f64.powi(levels as i32);
    let nx = ((width / root).round() as u64).max(1);
    let ny = ((depth / root).round() as u64).max(1);
    let size = |l: u32| root / 2f64.powi(l as i32);
    // every root cell becomes at least two triangles: a block far wider than deep (or the
    // reverse) is refused before its root cells are listed
    let too_large = || MeshError::TooLarge {
        max: max_elements,
        smallest: h0,
        fine_radius,
        fine_depth,
        width,
        depth,
    };
    if 2.0 * nx as f64 * ny as f64 > max_elements as f64 {
        return Err(too_large());
    }

    // refine by the size criterion
    let mut leaves: BTreeSet<Cell> = BTreeSet::new();
    let mut stack: Vec<Cell> = (0..nx)
        .flat_map(|i| (0..ny).map(move |j| (0, i, j)))
        .collect();
    while let Some((l, i, j)) = stack.pop() {
        let s = size(l);
        if l < levels && split(s, i as f64 * s, (i + 1) as f64 * s, j as f64 * s) {
            stack.extend(children((l, i, j)));
        } else {
            leaves.insert((l, i, j));
            // every leaf becomes at least two triangles
            if 2 * leaves.len() > max_elements {
                return Err(too_large());
            }
        }
    }
    balance(&mut leaves, nx, ny);

    let Triangulation {
        ids,
        triangles,
        centres,
    } = triangulate(&leaves, levels);
    let mut nodes = vec![[0.0; 2]; ids.len() + centres.len()];
    let place = |(a, b): (u64, u64)| [a as f64 * h0, -(b as f64) * h0];
    for (&k, &n) in &ids {
        nodes[n] = place(k);
    }
    for (n, &k) in centres.iter().enumerate() {
        nodes[ids.len() + n] = place(k);
    }
    let jmax = ny << levels;
    let mut surface: Vec<(u64, usize)> = ids
        .iter()
        .filter(|(k, _)| k.1 == 0)
        .map(|(k, &n)| (k.0, n))
        .collect();
    surface.sort_unstable();
    Ok(Mesh {
        surface: surface.into_iter().map(|(_, n)| n).collect(),
        axis: ids
            .iter()
            .filter(|(k, _)| k.0 == 0)
            .map(|(_, &n)| n)
            .collect(),
        bottom: ids
            .iter()
            .filter(|(k, _)| k.1 == jmax)
            .map(|(_, &n)| n)
            .collect(),
        nodes,
        triangles,
        width: nx as f64 * root,
        depth: ny as f64 * root,
    })
}

/// The triangles of a quadtree's leaves.
struct Triangulation {
    /// corner nodes' numbers by their integer coordinates on the finest level
    ids: BTreeMap<(u64, u64), usize>,
    triangles: Vec<[usize; 3]>,
    /// fan centres' coordinates (numbered after the corners, in order)
    centres: Vec<(u64, u64)>,
}

/// Triangles of the balanced `leaves` (finest level `levels`): two per leaf without hanging
/// nodes, else a fan around a centre node.
fn triangulate(leaves: &BTreeSet<Cell>, levels: u32) -> Triangulation {
    // nodes at integer coordinates of the finest level
    let key = |(l, i, j): Cell, di: u64, dj: u64| -> (u64, u64) {
        let f = 1u64 << (levels - l);
        ((i + di) * f, (j + dj) * f)
    };
    let mut ids: BTreeMap<(u64, u64), usize> = BTreeMap::new();
    for &c in leaves {
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let n = ids.len();
            ids.entry(key(c, di, dj)).or_insert(n);
        }
    }
    let mut triangles = Vec::new();
    let mut centres = Vec::new();
    for &c in leaves {
        let (l, i, j) = c;
        let f = 1u64 << (levels - l);
        let (i0, j0) = (i * f, j * f);
        let (i1, j1) = (i0 + f, j0 + f);
        let h = f / 2;
        // counter-clockwise in (r, z) with z = −j: bottom-left, bottom-right, top-right, top-left
        let corners = [(i0, j1), (i1, j1), (i1, j0), (i0, j0)];
        let mids = [(i0 + h, j1), (i1, j0 + h), (i0 + h, j0), (i0, j0 + h)];
        let mut ring = Vec::with_capacity(8);
        for k in 0..4 {
            ring.push(ids[&corners[k]]);
            if f > 1 {
                if let Some(&m) = ids.get(&mids[k]) {
                    ring.push(m);
                }
            }
        }
        if ring.len() == 4 {
            triangles.push([ring[0], ring[1], ring[2]]);
            triangles.push([ring[0], ring[2], ring[3]]);
        } else {
            let centre = ids.len() + centres.len();
            centres.push((i0 + h, j0 + h));
            for k in 0..ring.len() {
                triangles.push([centre, ring[k], ring[(k + 1) % ring.len()]]);
            }
        }
    }
    Triangulation {
        ids,
        triangles,
        centres,
    }
}

fn children((l, i, j): Cell) -> [Cell; 4] {
    [
        (l + 1, 2 * i, 2 * j),
        (l + 1, 2 * i + 1, 2 * j),
        (l + 1, 2 * i, 2 * j + 1),
        (l + 1, 2 * i + 1, 2 * j + 1),
    ]
}

/// Is the same-level cell `c` a leaf or inside a coarser leaf?
fn covered(leaves: &BTreeSet<Cell>, (l, i, j): Cell) -> bool {
    (0..=l).any(|k| leaves.contains(&(k, i >> (l - k), j >> (l - k))))
}

/// Split leaves until edge neighbours differ by at most one level (2:1 balance).
fn balance(leaves: &mut BTreeSet<Cell>, nx: u64, ny: u64) {
    loop {
        let mut split = Vec::new();
        for &(l, i, j) in leaves.iter() {
            let (ni, nj) = (nx << l, ny << l);
            // (neighbour, its two children along the shared edge)
            let mut nbrs: Vec<(Cell, [Cell; 2])> = Vec::with_capacity(4);
            let c = l + 1;
            if i + 1 < ni {
                let k = 2 * (i + 1);
                nbrs.push(((l, i + 1, j), [(c, k, 2 * j), (c, k, 2 * j + 1)]));
            }
            if i > 0 {
                let k = 2 * (i - 1) + 1;
                nbrs.push(((l, i - 1, j), [(c, k, 2 * j), (c, k, 2 * j + 1)]));
            }
            if j + 1 < nj {
                let k = 2 * (j + 1);
                nbrs.push(((l, i, j + 1), [(c, 2 * i, k), (c, 2 * i + 1, k)]));
            }
            if j > 0 {
                let k = 2 * (j - 1) + 1;
                nbrs.push(((l, i, j - 1), [(c, 2 * i, k), (c, 2 * i + 1, k)]));
            }
            let too_fine = nbrs
                .iter()
                .any(|(n, kids)| !covered(leaves, *n) && kids.iter().any(|k| !leaves.contains(k)));
            if too_fine {
                split.push((l, i, j));
            }
        }
        if split.is_empty() {
            return;
        }
        for c in split {
            leaves.remove(&c);
            leaves.extend(children(c));
        }
    }
}

impl Mesh {
    /// Element count, smallest/largest area, smallest angle.
    pub fn report(&self) -> MeshReport {
        let mut amin = f64::INFINITY;
        let mut amax = 0.0f64;
        let mut angle = 180.0f64;
        for t in &self.triangles {
            let p = t.map(|n| self.nodes[n]);
            let a = 0.5
                * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                    - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
            amin = amin.min(a);
            amax = amax.max(a);
            for k in 0..3 {
                let (o, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                let u = [b[0] - o[0], b[1] - o[1]];
                let v = [c[0] - o[0], c[1] - o[1]];
                let cos = (u[0] * v[0] + u[1] * v[1]) / (u[0].hypot(u[1]) * v[0].hypot(v[1]));
                angle = angle.min(cos.clamp(-1.0, 1.0).acos().to_degrees());
            }
        }
        let seg = self
            .surface
            .windows(2)
            .map(|w| (self.nodes[w[1]][0] - self.nodes[w[0]][0]).abs())
            .fold(f64::INFINITY, f64::min);
        MeshReport {
            elements: self.triangles.len(),
            nodes: self.nodes.len(),
            dofs: 2 * self.nodes.len(),
            smallest_area_nm2: amin,
            largest_area_nm2: amax,
            min_angle_deg: angle,
            smallest_surface_segment_nm: seg,
            width_nm: self.width,
            depth_nm: self.depth,
        }
    }
}

/// Read a Gmsh ASCII mesh (format 2.2): nodes (x = r, y = z, in nm) and 3-node triangles
/// (element type 2); other elements are ignored. The surface is the set of nodes at the largest
/// z, the axis those at r = 0, the base those at the smallest z (within 1e-9 of the extent).
pub fn read_msh(text: &str) -> Result<Mesh, MeshError> {
    let err = |line: usize, reason: &str| MeshError::Msh {
        line: line + 1,
        reason: reason.into(),
    };
    let lines: Vec<&str> = text.lines().collect();
    let find = |tag: &str| lines.iter().position(|l| l.trim() == tag);
    let (Some(nstart), Some(estart)) = (find("$Nodes"), find("$Elements")) else {
        return Err(err(
            0,
            "missing $Nodes or $Elements (only format 2.2 is read)",
        ));
    };
    let count = |at: usize| -> Result<usize, MeshError> {
        lines
            .get(at + 1)
            .and_then(|l| l.trim().parse().ok())
            .ok_or_else(|| err(at + 1, "expected a count"))
    };
    let mut index = BTreeMap::new();
    let mut nodes = Vec::new();
    for k in 0..count(nstart)? {
        let ln = nstart + 2 + k;
        let f: Vec<f64> = lines
            .get(ln)
            .ok_or_else(|| err(ln, "file ends inside $Nodes"))?
            .split_whitespace()
            .map(|s| s.parse().map_err(|_| err(ln, "bad number")))
            .collect::<Result<_, _>>()?;
        if f.len() < 3 {
            return Err(err(ln, "node needs an id and coordinates"));
        }
        index.insert(f[0] as usize, nodes.len());
        nodes.push([f[1], f[2]]);
    }
    let mut triangles = Vec::new();
    for k in 0..count(estart)? {
        let ln = estart + 2 + k;
        let f: Vec<usize> = lines
            .get(ln)
            .ok_or_else(|| err(ln, "file ends inside $Elements"))?
            .split_whitespace()
            .map(|s| s.parse().map_err(|_| err(ln, "bad integer")))
            .collect::<Result<_, _>>()?;
        if f.len() < 3 || f[1] != 2 {
            continue;
        }
        let ntags = f[2];
        let ids = f
            .get(3 + ntags..6 + ntags)
            .ok_or_else(|| err(ln, "short triangle"))?;
        let mut t = [0usize; 3];
        for (slot, id) in t.iter_mut().zip(ids) {
            *slot = *index.get(id).ok_or_else(|| err(ln, "unknown node"))?;
        }
        let p = t.map(|n| nodes[n]);
        let two_a =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        if two_a < 0.0 {
            t.swap(1, 2);
        }
        triangles.push(t);
    }
    if triangles.is_empty() {
        return Err(err(estart, "no triangles (element type 2)"));
    }
    let (rmax, zmax, zmin) = nodes.iter().fold(
        (f64::NEG_INFINITY, f64::NEG_INFINITY, f64::INFINITY),
        |a, p| (a.0.max(p[0]), a.1.max(p[1]), a.2.min(p[1])),
    );
    let tol = 1e-9 * (rmax.max(zmax - zmin));
    let mut surface: Vec<usize> = (0..nodes.len())
        .filter(|&n| (nodes[n][1] - zmax).abs() <= tol)
        .collect();
    surface.sort_by(|&a, &b| nodes[a][0].total_cmp(&nodes[b][0]));
    // shift so the surface is at z = 0
    nodes.iter_mut().for_each(|p| p[1] -= zmax);
    Ok(Mesh {
        axis: (0..nodes.len())
            .filter(|&n| nodes[n][0].abs() <= tol)
            .collect(),
        bottom: (0..nodes.len())
            .filter(|&n| (nodes[n][1] - (zmin - zmax)).abs() <= tol)
            .collect(),
        surface,
        nodes,
        triangles,
        width: rmax,
        depth: zmax - zmin,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIN_ANGLE_DEG: f64 = 44.999; // halves of squares and fan pieces are right isosceles triangles

    fn spec() -> BlockSpec {
        BlockSpec {
            width: 1000.0,
            depth: 1000.0,
            smallest: 2.0,
            fine_radius: 30.0,
            fine_depth: 10.0,
            grading: 0.3,
            max_elements: DEFAULT_MAX_ELEMENTS,
        }
    }

    #[test]
    fn graded_block_tiles_the_domain_without_slivers() {
        let m = graded_block(&spec()).unwrap();
        let r = m.report();
        // the triangles tile the block exactly
        let area: f64 = m
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|n| m.nodes[n]);
                0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                    - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
            })
            .sum();
        assert!((area - m.width * m.depth).abs() < 1e-9 * area);
        assert!(r.min_angle_deg >= MIN_ANGLE_DEG, "{r:?}");
        assert!((r.smallest_area_nm2 - 2.0).abs() < 1e-12); // half of a 2 nm square
        assert!(r.largest_area_nm2 > 1000.0);
        assert!((r.smallest_surface_segment_nm - 2.0).abs() < 1e-12);
        assert!(r.elements < 20_000, "{r:?}");
        // every edge is shared by two triangles or lies on the boundary (conforming)
        let mut edges = std::collections::HashMap::new();
        for t in &m.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        for ((a, b), n) in edges {
            if n == 1 {
                let (p, q) = (m.nodes[a], m.nodes[b]);
                let on = |v: f64, w: f64| (v - w).abs() < 1e-9;
                let boundary = (on(p[0], 0.0) && on(q[0], 0.0))
                    || (on(p[1], 0.0) && on(q[1], 0.0))
                    || (on(p[0], m.width) && on(q[0], m.width))
                    || (on(p[1], -m.depth) && on(q[1], -m.depth));
                assert!(boundary, "interior edge with one triangle: {p:?} {q:?}");
            } else {
                assert_eq!(n, 2);
            }
        }
        assert!(m
            .surface
            .windows(2)
            .all(|w| m.nodes[w[0]][0] < m.nodes[w[1]][0]));
        assert!(m.axis.iter().all(|&n| m.nodes[n][0] == 0.0));
    }

    #[test]
    fn a_gmsh_file_is_read() {
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 -1 0\n4 0 -1 0\n$EndNodes\n$Elements\n3\n1 1 2 0 1 1 2\n2 2 2 0 1 1 3 2\n3 2 2 0 1 1 4 3\n$EndElements\n";
        let m = read_msh(text).unwrap();
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(m.surface.len(), 2);
        assert_eq!(m.bottom.len(), 2);
        assert_eq!(m.axis.len(), 2);
        assert!(read_msh("$Nodes\n1\n").is_err());
    }

    /// The tiers of the band: h₀ out to e₂ + w, then 2h₀, 4h₀, 8h₀ out to each tier's radius
    /// + w, and fewer elements than the band of h₀ over the whole span.
    #[test]
    fn the_band_coarsens_by_tiers_beyond_its_smallest_elements() {
        let plain = EdgeZone::plain(100.0, 140.0, 10.0, 16.0);
        let tiered = EdgeZone {
            tail: [180.0, 220.0, 300.0, 300.0, 300.0, 300.0, 300.0, 300.0],
            ..plain
        };
        let whole = EdgeZone::plain(100.0, 300.0, 10.0, 16.0);
        let (p, t, w) = (
            edge_block(&spec(), &plain).unwrap(),
            edge_block(&spec(), &tiered).unwrap(),
            edge_block(&spec(), &whole).unwrap(),
        );
        // the largest surface segment starting in each radial window
        let largest = |m: &Mesh, lo: f64, hi: f64| {
            m.surface
                .windows(2)
                .map(|s| (m.nodes[s[0]][0], m.nodes[s[1]][0]))
                .filter(|&(a, _)| a >= lo && a < hi)
                .fold(0.0f64, |acc, (a, b)| acc.max(b - a))
        };
        let h0 = spec().smallest;
        assert_eq!(largest(&t, 90.0, 150.0), h0);
        assert_eq!(largest(&t, 150.0, 190.0), 2.0 * h0);
        assert_eq!(largest(&t, 190.0, 230.0), 4.0 * h0);
        assert_eq!(largest(&t, 230.0, 310.0), 8.0 * h0);
        assert_eq!(largest(&w, 90.0, 310.0), h0);
        let count = |m: &Mesh| m.triangles.len();
        assert!(count(&p) < count(&t) && count(&t) < count(&w));
        assert_eq!(tiered.reach(), 300.0);
        // a tier inside the band of h₀ is refused
        let bad = EdgeZone {
            tail: [120.0, 220.0, 300.0, 300.0, 300.0, 300.0, 300.0, 300.0],
            ..plain
        };
        assert!(edge_block(&spec(), &bad).is_err());
    }
}
