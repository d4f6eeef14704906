//! Tips held where they touch the sphere indenter ("stick"): a node
//! that comes into contact is tied tangentially to the point of the sphere where it first
//! touched, by a penalty spring in the sphere's tangent plane there, moving with the sphere.
//!
//! An anchor stores the node's offset a = x − c from the sphere's centre c at first touch (the
//! touched surface point is c + R a/|a|; the offset's normal part is projected out below, so
//! storing the node's own offset is the same). With n = a/|a| and the tangential projector
//! P = I − nnᵀ, the energy of the held nodes is
//!
//! E_t = Σ_anchors ½ k_t vᵀ P v,  v = x − c − a,
//!
//! exact gradient k_t P v, Hessian k_t P, and force on the sphere −∂E_t/∂H = Σ k_t (P v)_z.
//! Within a load step the anchors are frozen, so E_t is a conservative energy of x alone and the
//! static solvers minimise it like any other term. Between steps (the path-dependent part)
//! [`Stick::update`] ties nodes that have come within `touch_gap` of the surface (gap g =
//! |x − c| − R − r) and lets go of those that have left it or whose normal force N
//! (compressive positive, from the normal terms: the penalty wall and the LJ adhesion) has
//! become tensile beyond `release`. The anchors are state: the drive carries them from step to
//! step and a checkpoint saves them.

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::energy::EnergyTerm;

/// A held node: its index and its offset from the sphere's centre at first touch, nm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    /// the node
    pub node: usize,
    /// x − c when it first touched, nm
    pub offset: [f64; 3],
}

/// The tangential hold of the sphere on the nodes it touches.
#[derive(Debug, Clone, PartialEq)]
pub struct Stick {
    /// tangential penalty stiffness k_t, nN/nm
    pub stiffness: f64,
    /// a node is in contact while its gap g < this, nm
    pub touch_gap: f64,
    /// a held node whose normal force is more tensile than −this (nN) is let go; `None`: only
    /// when it leaves contact
    pub release: Option<f64>,
    /// sphere radius R, nm
    radius: f64,
    /// centre (x, y, H + R), nm
    centre: Vector3<f64>,
    /// (node, outer tube radius nm) of the nodes that can be held
    nodes: Vec<(usize, f64)>,
    /// the held nodes, by node index
    anchors: Vec<Anchor>,
}

impl Stick {
    /// A hold of stiffness `stiffness` (nN/nm) by the sphere of radius `radius` (nm) with its
    /// lowest point at `lowest`, on `nodes` (node, outer radius nm), none held yet.
    pub fn new(
        stiffness: f64,
        touch_gap: f64,
        release: Option<f64>,
        radius: f64,
        lowest: [f64; 3],
        nodes: Vec<(usize, f64)>,
    ) -> Self {
        Stick {
            stiffness,
            touch_gap,
            release,
            radius,
            centre: Vector3::new(lowest[0], lowest[1], lowest[2] + radius),
            nodes,
            anchors: Vec::new(),
        }
    }

    /// Move the sphere's lowest point to height `h` (nm).
    pub fn set_height(&mut self, h: f64) {
        self.centre.z = h + self.radius;
    }

    /// The held nodes.
    pub fn anchors(&self) -> &[Anchor] {
        &self.anchors
    }

    /// Replace the held nodes (a resumed drive), sorted by node.
    pub fn set_anchors(&mut self, anchors: &[Anchor]) {
        self.anchors = anchors.to_vec();
        self.anchors.sort_by_key(|a| a.node);
    }

    /// v = x − c − a and P of one anchor.
    fn spring(&self, x: &[f64], a: &Anchor) -> (Vector3<f64>, Matrix3<f64>) {
        let offset = Vector3::from(a.offset);
        let n = offset / offset.norm();
        let p = Matrix3::identity() - n * n.transpose();
        (node(x, a.node) - self.centre - offset, p)
    }

    /// The force of the held nodes on the sphere, −∂E_t/∂H (nN, positive pushing it up).
    pub fn force(&self, x: &[f64]) -> f64 {
        self.anchors
            .iter()
            .map(|a| {
                let (v, p) = self.spring(x, a);
                self.stiffness * (p * v).z
            })
            .sum()
    }

    /// Between load steps: hold the nodes that have come into contact at `x` and let go of
    /// those that have left it or pull on the sphere beyond `release`; `normal_grad` is the
    /// gradient of the normal terms (wall, adhesion) at `x`, giving each node's normal force
    /// N = −∇E · u (compressive positive), u the outward normal at the node.
    pub fn update(&mut self, x: &[f64], normal_grad: &[f64]) {
        let mut held: Vec<Anchor> = Vec::with_capacity(self.anchors.len());
        let mut old = self.anchors.iter().peekable();
        for &(i, r) in &self.nodes {
            let v = node(x, i) - self.centre;
            let rho = v.norm();
            let gap = rho - self.radius - r;
            let normal = -node(normal_grad, i).dot(&(v / rho));
            while old.peek().is_some_and(|a| a.node < i) {
                old.next();
            }
            let was = old.peek().filter(|a| a.node == i).copied();
            let tensile = self.release.is_some_and(|f| normal < -f);
            let touching = gap < self.touch_gap;
            match was {
                Some(a) if touching && !tensile => held.push(*a),
                None if touching && !tensile => held.push(Anchor {
                    node: i,
                    offset: v.into(),
                }),
                _ => {}
            }
        }
        self.anchors = held;
    }
}

/// The node's position, nm.
fn node(x: &[f64], n: usize) -> Vector3<f64> {
    Vector3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2])
}

impl EnergyTerm for Stick {
    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut e = 0.0;
        for a in &self.anchors {
            let (v, p) = self.spring(x, a);
            let pv = p * v;
            e += 0.5 * self.stiffness * v.dot(&pv);
            for k in 0..3 {
                grad[3 * a.node + k] += self.stiffness * pv[k];
            }
        }
        e
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for a in &self.anchors {
            let (_, p) = self.spring(x, a);
            for r in 0..3 {
                for c in 0..3 {
                    out.push((3 * a.node + r, 3 * a.node + c, self.stiffness * p[(r, c)]));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::energy::fd::relative_errors;

    const FD_STEP: f64 = 1e-5;
    /// The energy is quadratic: central differences are exact up to rounding.
    const FD_TOL: f64 = 1e-7;

    /// Sphere R = 10 nm, lowest point at the origin; three nodes of radius 1 nm: one touching
    /// under the pole, one on the flank, one far away.
    fn held() -> (Stick, Vec<f64>) {
        let x = vec![0.2, 0.1, -0.95, 7.0, 0.0, 10.0 - 7.2, 30.0, 0.0, -20.0];
        let mut s = Stick::new(
            50.0,
            0.0,
            Some(0.5),
            10.0,
            [0.0, 0.0, 0.0],
            vec![(0, 1.0), (1, 1.0), (2, 1.0)],
        );
        s.update(&x, &[0.0; 9]);
        (s, x)
    }

    #[test]
    fn touching_nodes_are_held_and_far_ones_not() {
        let (s, _) = held();
        let nodes: Vec<usize> = s.anchors().iter().map(|a| a.node).collect();
        assert_eq!(nodes, vec![0, 1]);
    }

    #[test]
    fn gradient_hessian_and_force_match_finite_differences() {
        let (mut s, mut x) = held();
        // move the nodes and the sphere so the springs are stretched every way
        x[0] += 0.3;
        x[1] -= 0.2;
        x[4] += 0.4;
        x[5] -= 0.1;
        s.set_height(0.15);
        let n = x.len();
        assert!(s.energy_gradient(&x, &mut vec![0.0; n]) > 0.0);
        let (eg, eh) = relative_errors(&s, &x, FD_STEP);
        assert!(
            eg < FD_TOL && eh < FD_TOL,
            "gradient {eg:.1e}, Hessian {eh:.1e}"
        );
        let (mut up, mut dn) = (s.clone(), s.clone());
        up.set_height(0.15 + FD_STEP);
        dn.set_height(0.15 - FD_STEP);
        let mut t = vec![0.0; n];
        let de_dh =
            (up.energy_gradient(&x, &mut t) - dn.energy_gradient(&x, &mut t)) / (2.0 * FD_STEP);
        assert!((s.force(&x) + de_dh).abs() < FD_TOL * (1.0 + de_dh.abs()));
    }

    #[test]
    fn the_spring_is_tangential_and_moves_with_the_sphere() {
        let (mut s, mut x) = held();
        // pressing a held node straight in along its normal stores nothing
        let a = s.anchors()[1];
        let n = Vector3::from(a.offset).normalize();
        for k in 0..3 {
            x[3 + k] -= 0.05 * n[k];
        }
        let mut g = vec![0.0; 9];
        let e0 = s.energy_gradient(&x, &mut g);
        assert!(e0.abs() < 1e-12);
        // the sphere and the nodes translated together store nothing
        s.set_height(2.0);
        for k in [2, 5] {
            x[k] += 2.0;
        }
        assert!(s.energy_gradient(&x, &mut g).abs() < 1e-12);
    }

    #[test]
    fn nodes_are_let_go_when_they_leave_or_pull_beyond_the_release() {
        let (mut s, mut x) = held();
        // node 0 pulls on the sphere with 1 nN (> release 0.5 nN): its normal force is
        // −∇E·u with u pointing down at the pole, so a gradient of −1 nN along z is tensile
        let mut grad = vec![0.0; 9];
        grad[2] = -1.0;
        s.update(&x, &grad);
        assert_eq!(s.anchors().len(), 1);
        // node 1 moves off the surface and is let go; node 0, no longer pulling, is held
        // again where it now touches
        x[3] += 3.0;
        x[0] += 0.1;
        s.update(&x, &[0.0; 9]);
        assert_eq!(s.anchors().len(), 1);
        assert_eq!(s.anchors()[0].node, 0);
        assert!((s.anchors()[0].offset[0] - 0.3).abs() < 1e-15);
        // and an anchor survives the round trip through the checkpoint's JSON bit for bit
        let (s, _) = held();
        let text = serde_json::to_string(s.anchors()).unwrap();
        let back: Vec<Anchor> = serde_json::from_str(&text).unwrap();
        assert_eq!(back, s.anchors());
    }
}
