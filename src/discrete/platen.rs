//! Rigid frictionless walls as smooth one-sided penalty energies on the nodes:
//! the compression platen z = H above the turf and the substrate z = 0 below it, or instead of
//! the flat platen a rigid frictionless sphere of radius R whose lowest point is at z = H (the
//! sphere-indentation drive, the discrete counterpart of the continuum
//! indentation of seed ch. 5).
//!
//! A node i of a tube of outer radius r_i penetrates a wall by d_i = z_i + r_i − H (platen,
//! facing down) or d_i = z_w − (z_i − r_i) (substrate at z_w, facing up). The wall energy is
//!
//! E_w = Σ_i (κ/3) ⟨d_i⟩³,  ⟨d⟩ = max(d, 0),
//!
//! C² in the coordinates: ∂E/∂z_i = ±κ⟨d_i⟩², ∂²E/∂z_i² = 2κ⟨d_i⟩. The wall acts only along z
//! (frictionless: no tangential force). For the sphere, centre c = (c_x, c_y, H + R), the
//! penetration is d_i = R + r_i − |x_i − c| and the same cubic penalty gives ∇E = κd²∇d and
//! ∇²E = κ(2d ∇d∇dᵀ + d²∇²d), with ∇d = −u, u = (x − c)/|x − c|, ∇²d = −(I − uuᵀ)/|x − c|:
//! the force is along the sphere's normal (frictionless). The force the turf exerts on the platen, pushing it up,
//! is F = −∂E/∂H = Σ_i κ⟨d_i⟩² (nN; for the sphere Σ_i κ⟨d_i⟩²(−u_z)) — at equilibrium the derivative of the equilibrium energy
//! with respect to the platen height, so the platen force is consistent with the energy the
//! solver minimises. The penetration at a node carrying f is √(f/κ): κ sets how rigid the
//! "rigid" wall is, and must make that small against the platen travel per step.

use nalgebra::{Matrix3, Vector3};

use super::energy::EnergyTerm;

/// The wall's shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// the plane z = H
    Plane,
    /// a sphere of radius `radius` (nm) with its lowest point at (`x`, `y`, H), nm; only with
    /// [`Facing::Down`] (an indenter)
    Sphere {
        /// R, nm
        radius: f64,
        /// x of the lowest point, nm
        x: f64,
        /// y of the lowest point, nm
        y: f64,
    },
}

/// Penetration d of one node, ∇d, ∂d/∂H and ∇²d (`None` where it vanishes: the plane).
struct Penetration {
    depth: f64,
    grad: Vector3<f64>,
    d_height: f64,
    hess: Option<Matrix3<f64>>,
}

/// Which side of the wall the nodes live on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Facing {
    /// a platen at z = H pressing down: nodes must stay below H − r
    Down,
    /// a substrate at z = H: nodes must stay above H + r
    Up,
}

/// Default penalty stiffness κ, nN/nm³: a node carrying 10 nN penetrates by 0.1 nm.
pub const DEFAULT_WALL_STIFFNESS: f64 = 1.0e3;

/// A rigid frictionless wall z = `height` acting on a set of nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    /// wall position, nm
    pub height: f64,
    /// which way it faces
    pub facing: Facing,
    /// penalty stiffness κ, nN/nm³
    pub stiffness: f64,
    /// plane or sphere
    pub shape: Shape,
    /// (node, outer radius in nm) of the nodes it acts on
    nodes: Vec<(usize, f64)>,
}

impl Wall {
    /// A wall acting on `nodes`, each with its tube's outer radius (nm).
    pub fn new(height: f64, facing: Facing, stiffness: f64, nodes: Vec<(usize, f64)>) -> Self {
        Wall {
            height,
            facing,
            stiffness,
            shape: Shape::Plane,
            nodes,
        }
    }

    /// Penetration of node `i` of tube radius `r` (nm) into the wall.
    #[inline]
    fn penetration(&self, x: &[f64], i: usize, r: f64) -> Penetration {
        let p = Vector3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
        let plane = |depth: f64, s: f64| Penetration {
            depth,
            grad: Vector3::new(0.0, 0.0, s),
            d_height: -s,
            hess: None,
        };
        match (self.shape, self.facing) {
            (Shape::Plane, Facing::Down) => plane(p.z + r - self.height, 1.0),
            (Shape::Plane, Facing::Up) => plane(self.height - (p.z - r), -1.0),
            (Shape::Sphere { radius, x, y }, _) => {
                let v = p - Vector3::new(x, y, self.height + radius);
                let rho = v.norm();
                let u = v / rho;
                Penetration {
                    depth: radius + r - rho,
                    grad: -u,
                    d_height: u.z,
                    hess: Some(-(Matrix3::identity() - u * u.transpose()) / rho),
                }
            }
        }
    }

    /// The force on the wall along its outward normal, −∂E/∂H for a platen (nN, positive when
    /// the nodes push it away: up for the platen, down for the substrate).
    pub fn force(&self, x: &[f64]) -> f64 {
        let normal = match self.facing {
            Facing::Down => 1.0,
            Facing::Up => -1.0,
        };
        self.nodes
            .iter()
            .map(|&(i, r)| {
                let p = self.penetration(x, i, r);
                if p.depth > 0.0 {
                    -normal * self.stiffness * p.depth * p.depth * p.d_height
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// The highest z at which a node of tube radius `r` at (`x`, `y`) clears a downward-facing
    /// wall (`None`: the sphere is not above that point); the drive's predictor.
    pub fn ceiling(&self, x: f64, y: f64, r: f64) -> Option<f64> {
        match self.shape {
            Shape::Plane => Some(self.height - r),
            Shape::Sphere {
                radius,
                x: cx,
                y: cy,
            } => {
                let reach2 = (radius + r).powi(2) - (x - cx).powi(2) - (y - cy).powi(2);
                (reach2 > 0.0).then(|| self.height + radius - reach2.sqrt())
            }
        }
    }

    /// Number of nodes touching the wall (d > 0).
    pub fn touching(&self, x: &[f64]) -> usize {
        self.nodes
            .iter()
            .filter(|&&(i, r)| self.penetration(x, i, r).depth > 0.0)
            .count()
    }
}

impl EnergyTerm for Wall {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut e = 0.0;
        for &(i, r) in &self.nodes {
            let p = self.penetration(x, i, r);
            let d = p.depth;
            if d > 0.0 {
                e += self.stiffness * d * d * d / 3.0;
                for a in 0..3 {
                    grad[3 * i + a] += self.stiffness * d * d * p.grad[a];
                }
            }
        }
        e
    }

    /// Every node's entries are listed, zero where it does not touch, so that the list stays
    /// the same while nodes come into and out of contact (the Newton solver then keeps its
    /// assembly map): the plane's one entry ∂²E/∂z², the sphere's 3 × 3 block.
    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        let block: &[(usize, usize)] = match self.shape {
            Shape::Plane => &[(2, 2)],
            Shape::Sphere { .. } => &[
                (0, 0),
                (0, 1),
                (0, 2),
                (1, 0),
                (1, 1),
                (1, 2),
                (2, 0),
                (2, 1),
                (2, 2),
            ],
        };
        for &(i, r) in &self.nodes {
            let p = self.penetration(x, i, r);
            let d = p.depth.max(0.0);
            let mut h = 2.0 * self.stiffness * d * p.grad * p.grad.transpose();
            if let Some(hd) = p.hess {
                h += self.stiffness * d * d * hd;
            }
            out.extend(
                block
                    .iter()
                    .map(|&(a, b)| (3 * i + a, 3 * i + b, h[(a, b)])),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Finite-difference step, nm.
    const FD_STEP: f64 = 1e-6;
    /// Central differences of a C² cubic at this step: error ~ κ h² ≈ 1e-9 relative.
    const FD_TOL: f64 = 1e-7;

    fn setup(facing: Facing) -> (Wall, Vec<f64>) {
        // four nodes, three penetrating by different depths, one clear
        let x = vec![
            0.0, 0.0, 99.5, 1.0, 0.0, 98.0, 2.0, 0.0, 100.3, 3.0, 0.0, 90.0,
        ];
        let x = match facing {
            Facing::Down => x,
            Facing::Up => x.iter().map(|v| -v).collect(),
        };
        let h = match facing {
            Facing::Down => 100.0,
            Facing::Up => -100.0,
        };
        let nodes = vec![(0, 1.0), (1, 2.5), (2, 1.0), (3, 1.0)];
        (Wall::new(h, facing, 50.0, nodes), x)
    }

    /// The sphere indenter over the same nodes: radius 10 nm, lowest point (1.5, 0.7, 97).
    fn sphere() -> (Wall, Vec<f64>) {
        let (mut wall, x) = setup(Facing::Down);
        wall.height = 97.0;
        wall.shape = Shape::Sphere {
            radius: 10.0,
            x: 1.5,
            y: 0.7,
        };
        (wall, x)
    }

    /// The full gradient and Hessian against central differences of the energy and gradient,
    /// and the force on the wall against the energy's derivative in its height.
    fn check_against_finite_differences(wall: &Wall, x: &[f64], sign: f64) {
        assert_eq!(wall.touching(x), 3);
        let n = x.len();
        let mut g = vec![0.0; n];
        let e = wall.energy_gradient(x, &mut g);
        assert!(e > 0.0);
        let mut entries = Vec::new();
        wall.hessian(x, &mut entries);
        let mut h = vec![0.0; n * n];
        for (r, c, v) in entries {
            h[r * n + c] += v;
        }
        for k in 0..n {
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[k] += FD_STEP;
            xm[k] -= FD_STEP;
            let mut gp = vec![0.0; n];
            let mut gm = vec![0.0; n];
            let fd = (wall.energy_gradient(&xp, &mut gp) - wall.energy_gradient(&xm, &mut gm))
                / (2.0 * FD_STEP);
            assert!((fd - g[k]).abs() < FD_TOL * (1.0 + g[k].abs()), "g {k}");
            for j in 0..n {
                let (hjk, fdh) = (h[j * n + k], (gp[j] - gm[j]) / (2.0 * FD_STEP));
                assert!((fdh - hjk).abs() < FD_TOL * (1.0 + hjk.abs()), "h {j} {k}");
            }
        }
        let (mut up, mut dn) = (wall.clone(), wall.clone());
        up.height += FD_STEP;
        dn.height -= FD_STEP;
        let mut scratch = vec![0.0; n];
        let de_dh = (up.energy_gradient(x, &mut scratch) - dn.energy_gradient(x, &mut scratch))
            / (2.0 * FD_STEP);
        let f = wall.force(x);
        assert!(f > 0.0);
        assert!((sign * de_dh - f).abs() < FD_TOL * f, "{:?}", wall.shape);
    }

    #[test]
    fn gradient_hessian_and_platen_force_match_finite_differences() {
        // force on the wall = −∂E/∂H (platen) or +∂E/∂H (substrate, outward normal −z)
        let (wall, x) = setup(Facing::Down);
        check_against_finite_differences(&wall, &x, -1.0);
        let (wall, x) = setup(Facing::Up);
        check_against_finite_differences(&wall, &x, 1.0);
    }

    #[test]
    fn the_sphere_gradient_hessian_and_force_match_finite_differences() {
        let (wall, x) = sphere();
        check_against_finite_differences(&wall, &x, -1.0);
    }

    #[test]
    fn a_clear_wall_has_no_energy() {
        let (mut wall, x) = setup(Facing::Down);
        wall.height = 1e3;
        let mut g = vec![0.0; x.len()];
        assert_eq!(wall.energy_gradient(&x, &mut g), 0.0);
        assert!(g.iter().all(|v| *v == 0.0));
        assert_eq!(wall.force(&x), 0.0);
    }
}
