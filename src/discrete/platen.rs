//! Rigid frictionless walls as smooth one-sided penalty energies on the nodes (issue 7, item 6):
//! the compression platen z = H above the turf and the substrate z = 0 below it.
//!
//! A node i of a tube of outer radius r_i penetrates a wall by d_i = z_i + r_i − H (platen,
//! facing down) or d_i = z_w − (z_i − r_i) (substrate at z_w, facing up). The wall energy is
//!
//! E_w = Σ_i (κ/3) ⟨d_i⟩³,  ⟨d⟩ = max(d, 0),
//!
//! C² in the coordinates: ∂E/∂z_i = ±κ⟨d_i⟩², ∂²E/∂z_i² = 2κ⟨d_i⟩. The wall acts only along z
//! (frictionless: no tangential force). The force the turf exerts on the platen, pushing it up,
//! is F = −∂E/∂H = Σ_i κ⟨d_i⟩² (nN) — at equilibrium the derivative of the equilibrium energy
//! with respect to the platen height, so the platen force is consistent with the energy the
//! solver minimises. The penetration at a node carrying f is √(f/κ): κ sets how rigid the
//! "rigid" wall is, and must make that small against the platen travel per step.

use super::energy::EnergyTerm;

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
            nodes,
        }
    }

    /// Penetration of node `i` of radius `r` (nm), and dd/dz.
    #[inline]
    fn penetration(&self, z: f64, r: f64) -> (f64, f64) {
        match self.facing {
            Facing::Down => (z + r - self.height, 1.0),
            Facing::Up => (self.height - (z - r), -1.0),
        }
    }

    /// The force on the wall along its outward normal, −∂E/∂H for a platen (nN, positive when
    /// the nodes push it away: up for the platen, down for the substrate).
    pub fn force(&self, x: &[f64]) -> f64 {
        self.nodes
            .iter()
            .map(|&(i, r)| {
                let d = self.penetration(x[3 * i + 2], r).0;
                if d > 0.0 {
                    self.stiffness * d * d
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// Number of nodes touching the wall (d > 0).
    pub fn touching(&self, x: &[f64]) -> usize {
        self.nodes
            .iter()
            .filter(|&&(i, r)| self.penetration(x[3 * i + 2], r).0 > 0.0)
            .count()
    }
}

impl EnergyTerm for Wall {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut e = 0.0;
        for &(i, r) in &self.nodes {
            let (d, dz) = self.penetration(x[3 * i + 2], r);
            if d > 0.0 {
                e += self.stiffness * d * d * d / 3.0;
                grad[3 * i + 2] += dz * self.stiffness * d * d;
            }
        }
        e
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for &(i, r) in &self.nodes {
            let (d, _) = self.penetration(x[3 * i + 2], r);
            if d > 0.0 {
                out.push((3 * i + 2, 3 * i + 2, 2.0 * self.stiffness * d));
            }
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

    #[test]
    fn gradient_hessian_and_platen_force_match_finite_differences() {
        for facing in [Facing::Down, Facing::Up] {
            let (wall, x) = setup(facing);
            assert_eq!(wall.touching(&x), 3);
            let mut g = vec![0.0; x.len()];
            let e = wall.energy_gradient(&x, &mut g);
            assert!(e > 0.0);
            let mut h = Vec::new();
            wall.hessian(&x, &mut h);
            for k in 0..x.len() {
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[k] += FD_STEP;
                xm[k] -= FD_STEP;
                let mut gp = vec![0.0; x.len()];
                let mut gm = vec![0.0; x.len()];
                let fd = (wall.energy_gradient(&xp, &mut gp) - wall.energy_gradient(&xm, &mut gm))
                    / (2.0 * FD_STEP);
                assert!((fd - g[k]).abs() < FD_TOL * (1.0 + g[k].abs()), "g {k}");
                let hk: f64 = h.iter().filter(|t| t.0 == k && t.1 == k).map(|t| t.2).sum();
                let fdh = (gp[k] - gm[k]) / (2.0 * FD_STEP);
                assert!((fdh - hk).abs() < FD_TOL * (1.0 + hk.abs()), "h {k}");
            }
            // force on the wall = −∂E/∂H (platen) or +∂E/∂H (substrate, outward normal −z)
            let (mut up, mut dn) = (wall.clone(), wall.clone());
            up.height += FD_STEP;
            dn.height -= FD_STEP;
            let mut scratch = vec![0.0; x.len()];
            let de_dh = (up.energy_gradient(&x, &mut scratch)
                - dn.energy_gradient(&x, &mut scratch))
                / (2.0 * FD_STEP);
            let sign = match facing {
                Facing::Down => -1.0,
                Facing::Up => 1.0,
            };
            let f = wall.force(&x);
            assert!(f > 0.0);
            assert!((sign * de_dh - f).abs() < FD_TOL * f, "{facing:?}");
        }
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
