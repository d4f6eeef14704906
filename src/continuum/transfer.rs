//! The state of a run carried from one mesh of the block to another (adaptive meshing, issue
//! 17): nodal displacements by linear interpolation in the old triangles, element values (the
//! Prony history of [`super::material::viscoelastic`], one set per CST) by the L² projection onto
//! constants under the axisymmetric measure dV = 2πr dr dz:
//!
//!   h_T = ∫_T h_old r dA / ∫_T r dA,
//!
//! the integral over each new triangle T computed exactly by clipping it against the old
//! triangles it overlaps. The projection conserves ∫ h dV over the block to round-off, returns
//! a field the new mesh represents (old field piecewise constant on it) unchanged, and the
//! interpolation returns any continuous piecewise-linear field of the old mesh at the nodes of a
//! nested mesh exactly, so a mesh that does not move (or is refined and coarsened back) does
//! not drift.

use super::mesh::Mesh;

/// No neighbour across an edge (the edge lies on the block's boundary).
const NONE: usize = usize::MAX;
/// Intersections smaller than this fraction of the new triangle's area are round-off.
const AREA_EPS: f64 = 1e-12;

/// Point location in a conforming triangulation by walking across edges.
pub struct Locator<'a> {
    mesh: &'a Mesh,
    /// triangle across edge k (vertex k to k + 1) of every triangle
    neighbours: Vec<[usize; 3]>,
    /// the tolerance of the orientation tests: how far beyond an edge a point may lie and
    /// still count as on it, nm (round-off of the block's coordinates, far below any element)
    eps: f64,
}

fn cross(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

impl<'a> Locator<'a> {
    /// The edge adjacency of `mesh`.
    pub fn new(mesh: &'a Mesh) -> Self {
        let mut edges = std::collections::HashMap::with_capacity(3 * mesh.triangles.len());
        let mut neighbours = vec![[NONE; 3]; mesh.triangles.len()];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if let Some((u, j)) = edges.remove(&(b, a)) {
                    neighbours[t][k] = u;
                    let nb: &mut [usize; 3] = &mut neighbours[u];
                    nb[j] = t;
                } else {
                    edges.insert((a, b), (t, k));
                }
            }
        }
        let scale = mesh.width.max(mesh.depth);
        Locator {
            mesh,
            neighbours,
            eps: 1e-12 * scale,
        }
    }

    fn corners(&self, t: usize) -> [[f64; 2]; 3] {
        self.mesh.triangles[t].map(|n| self.mesh.nodes[n])
    }

    /// The triangle containing `p`, walking from `start` (a point outside the block gives the
    /// boundary triangle the walk ends in).
    pub fn locate(&self, p: [f64; 2], start: usize) -> usize {
        let mut t = start;
        for _ in 0..self.mesh.triangles.len() {
            let c = self.corners(t);
            // leave across the edge that p lies most clearly beyond, by its distance from the
            // edge's line (a tolerance on the cross product itself would scale with the edge,
            // and let a point a whole small element away count as inside)
            let (k, worst) = (0..3)
                .map(|k| {
                    let (a, b) = (c[k], c[(k + 1) % 3]);
                    (k, cross(a, b, p) / (b[0] - a[0]).hypot(b[1] - a[1]))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("three edges");
            if worst >= -self.eps || self.neighbours[t][k] == NONE {
                return t;
            }
            t = self.neighbours[t][k];
        }
        t
    }

    /// Barycentric coordinates of `p` in triangle `t`.
    fn barycentric(&self, t: usize, p: [f64; 2]) -> [f64; 3] {
        let c = self.corners(t);
        let area = cross(c[0], c[1], c[2]);
        let l1 = cross(c[2], c[0], p) / area;
        let l2 = cross(c[0], c[1], p) / area;
        [1.0 - l1 - l2, l1, l2]
    }
}

/// The nodal field `u` (`stride` values per node) of `old` at the nodes of `new`, interpolated
/// linearly in the old triangles.
pub fn interpolate_nodal(old: &Mesh, u: &[f64], stride: usize, new: &Mesh) -> Vec<f64> {
    let loc = Locator::new(old);
    let mut out = vec![0.0; stride * new.nodes.len()];
    let mut t = 0;
    for (n, &p) in new.nodes.iter().enumerate() {
        t = loc.locate(p, t);
        let w = loc.barycentric(t, p);
        let tri = old.triangles[t];
        for k in 0..stride {
            out[stride * n + k] = (0..3).map(|a| w[a] * u[stride * tri[a] + k]).sum();
        }
    }
    out
}

/// Area and ∫ r dA of the polygon `poly`.
fn moments(poly: &[[f64; 2]]) -> (f64, f64) {
    let (mut a, mut sr) = (0.0, 0.0);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let c = p[0] * q[1] - q[0] * p[1];
        a += c;
        sr += c * (p[0] + q[0]);
    }
    (0.5 * a, sr / 6.0)
}

/// The part of the convex polygon `poly` inside the counter-clockwise triangle `tri`
/// (Sutherland–Hodgman).
fn clip(mut poly: Vec<[f64; 2]>, tri: [[f64; 2]; 3]) -> Vec<[f64; 2]> {
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let input = std::mem::take(&mut poly);
        for i in 0..input.len() {
            let (p, q) = (input[i], input[(i + 1) % input.len()]);
            let (sp, sq) = (cross(a, b, p), cross(a, b, q));
            if sp >= 0.0 {
                poly.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                poly.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        if poly.is_empty() {
            break;
        }
    }
    poly
}

/// The element field `h` (`stride` values per triangle) of `old` projected onto constants on
/// the triangles of `new` under the measure r dA (see the module doc).
pub fn project_elementwise(old: &Mesh, h: &[f64], stride: usize, new: &Mesh) -> Vec<f64> {
    let loc = Locator::new(old);
    let mut out = vec![0.0; stride * new.triangles.len()];
    if stride == 0 {
        return out;
    }
    let mut seen = vec![usize::MAX; old.triangles.len()];
    let mut start = 0;
    for (t, tri) in new.triangles.iter().enumerate() {
        let c = tri.map(|n| new.nodes[n]);
        let centroid = [
            (c[0][0] + c[1][0] + c[2][0]) / 3.0,
            (c[0][1] + c[1][1] + c[2][1]) / 3.0,
        ];
        let (area, _) = moments(&c);
        start = loc.locate(centroid, start);
        // every old triangle overlapping T, reached across edges from the one holding its
        // centroid (T is convex, the overlaps tile it)
        let mut stack = vec![start];
        seen[start] = t;
        let (mut weight, mut acc) = (0.0, vec![0.0; stride]);
        while let Some(o) = stack.pop() {
            let piece = clip(c.to_vec(), loc.corners(o));
            if piece.len() < 3 {
                continue;
            }
            let (a, sr) = moments(&piece);
            if a <= AREA_EPS * area {
                continue;
            }
            // on the axis ∫ r dA of a sliver can vanish; the area weight then stands in
            let w = sr.max(0.0);
            weight += w;
            for k in 0..stride {
                acc[k] += w * h[stride * o + k];
            }
            for nb in loc.neighbours[o] {
                if nb != NONE && seen[nb] != t {
                    seen[nb] = t;
                    stack.push(nb);
                }
            }
        }
        for k in 0..stride {
            out[stride * t + k] = acc[k] / weight;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::continuum::mesh::{edge_block, BlockSpec, EdgeZone, DEFAULT_MAX_ELEMENTS};

    /// Round-off of sums over ~10⁴ triangles of values O(1) (relative).
    const ROUND_OFF: f64 = 1e-11;

    fn spec() -> BlockSpec {
        BlockSpec {
            width: 400.0,
            depth: 400.0,
            smallest: 0.5,
            fine_radius: 0.0,
            fine_depth: 0.0,
            grading: 0.2,
            max_elements: DEFAULT_MAX_ELEMENTS,
        }
    }

    fn at(edge: f64) -> Mesh {
        edge_block(&spec(), &EdgeZone::plain(edge, edge, 5.0, 2.0)).unwrap()
    }

    /// ∫ h r dA over the block.
    fn integral(m: &Mesh, h: &[f64]) -> f64 {
        m.triangles
            .iter()
            .zip(h)
            .map(|(t, v)| v * moments(&t.map(|n| m.nodes[n])).1)
            .sum()
    }

    fn field(p: [f64; 2]) -> f64 {
        (0.05 * p[0]).sin() + (0.03 * p[1]).cos() * p[0] / 100.0
    }

    fn centroid_field(m: &Mesh) -> Vec<f64> {
        m.triangles
            .iter()
            .map(|t| {
                let c = t.map(|n| m.nodes[n]);
                field([
                    (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                    (c[0][1] + c[1][1] + c[2][1]) / 3.0,
                ])
            })
            .collect()
    }

    #[test]
    fn projection_conserves_the_integral_between_moved_meshes() {
        let (a, b) = (at(20.0), at(60.0));
        assert_ne!(a.triangles.len(), b.triangles.len());
        let h = centroid_field(&a);
        let hb = project_elementwise(&a, &h, 1, &b);
        let back = project_elementwise(&b, &hb, 1, &a);
        let (ia, ib, iback) = (integral(&a, &h), integral(&b, &hb), integral(&a, &back));
        assert!((ib / ia - 1.0).abs() < ROUND_OFF, "{ia} → {ib}");
        assert!((iback / ia - 1.0).abs() < ROUND_OFF, "{ia} → {iback}");
        // a constant (several components) stays constant
        let c: Vec<f64> = (0..a.triangles.len()).flat_map(|_| [3.0, -1.0]).collect();
        for (k, v) in project_elementwise(&a, &c, 2, &b).iter().enumerate() {
            let want = if k % 2 == 0 { 3.0 } else { -1.0 };
            assert!((v - want).abs() < ROUND_OFF, "{v}");
        }
    }

    /// A band of 0.08 nm elements in a block 2 × 10⁵ nm wide (the seed's γ on the turf card):
    /// the walk's orientation tolerance must follow the triangles, not the block, or it stops
    /// in a neighbour of the triangle holding a point and the projection divides by nothing.
    #[test]
    fn a_band_of_tiny_elements_in_a_wide_block_projects_without_loss() {
        let wide = BlockSpec {
            width: 2e5,
            depth: 2e5,
            smallest: 0.08,
            ..spec()
        };
        let band = |edge: f64| edge_block(&wide, &EdgeZone::plain(edge, edge, 1.0, 0.4)).unwrap();
        let (a, b) = (band(300.0), band(301.0));
        let c: Vec<f64> = (0..a.triangles.len()).flat_map(|_| [3.0, -1.0]).collect();
        let cb = project_elementwise(&a, &c, 2, &b);
        for (k, v) in cb.iter().enumerate() {
            let want = if k % 2 == 0 { 3.0 } else { -1.0 };
            assert!(
                (v - want).abs() < ROUND_OFF,
                "value {k} of {}: {v}",
                cb.len()
            );
        }
        let h = centroid_field(&a);
        let hb = project_elementwise(&a, &h, 1, &b);
        let (ia, ib) = (integral(&a, &h), integral(&b, &hb));
        assert!((ib / ia - 1.0).abs() < ROUND_OFF, "{ia} → {ib}");
    }

    #[test]
    fn a_mesh_that_does_not_move_does_not_drift() {
        let a = at(30.0);
        let h = centroid_field(&a);
        let u: Vec<f64> = a
            .nodes
            .iter()
            .flat_map(|&p| [field(p), -field(p)])
            .collect();
        let (mut hh, mut uu) = (h.clone(), u.clone());
        for _ in 0..5 {
            hh = project_elementwise(&a, &hh, 1, &a);
            uu = interpolate_nodal(&a, &uu, 2, &a);
        }
        let dh = hh
            .iter()
            .zip(&h)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        let du = uu
            .iter()
            .zip(&u)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(dh < ROUND_OFF && du < ROUND_OFF, "{dh} {du}");
    }

    #[test]
    fn interpolation_is_exact_for_linear_fields_and_on_nested_meshes() {
        let (a, b) = (at(20.0), at(60.0));
        let lin = |p: [f64; 2]| 0.3 * p[0] - 0.7 * p[1] + 2.0;
        let u: Vec<f64> = a.nodes.iter().map(|&p| lin(p)).collect();
        let ub = interpolate_nodal(&a, &u, 1, &b);
        for (v, &p) in ub.iter().zip(&b.nodes) {
            assert!((v - lin(p)).abs() < ROUND_OFF * 1e3, "{v} vs {}", lin(p));
        }
        // a mesh with coarser surface elements over the contact is nested in `at` of the same
        // edge: a field of the coarse mesh goes to the fine one and back unchanged
        let coarse = edge_block(&spec(), &EdgeZone::plain(60.0, 60.0, 5.0, 8.0)).unwrap();
        let fine = at(60.0);
        assert!(fine.nodes.len() > coarse.nodes.len());
        let u: Vec<f64> = coarse.nodes.iter().map(|&p| field(p)).collect();
        let back = interpolate_nodal(&fine, &interpolate_nodal(&coarse, &u, 1, &fine), 1, &coarse);
        let d = back
            .iter()
            .zip(&u)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(d < ROUND_OFF, "{d}");
    }
}
