//! The testing machine between the drive and the indenter (seed §6.1, Fig 6.1): the indenter
//! depth δ is an unknown next to the nodal displacements, and the drive adds a term to the
//! total potential —
//!
//! - displacement control (K → ∞): δ = Δ, no unknown;
//! - a machine spring of stiffness K: ½K(Δ − δ)², so P(δ) = K(Δ − δ) at equilibrium and, at a
//!   jump (fixed Δ), the state moves along a line of slope dP/dδ = −K;
//! - load control (K = 0): −P̂δ, so P(δ) = P̂;
//! - load control through a Hysitron-type transducer (seed §2.3, Fig 2.1a, eqs. 2.1–2.7): the
//!   force P̂ acts on a plate at position h held by support springs k₁ (in parallel, to the
//!   frame) and reaching the indenter through the load-frame spring k₂ (in series), so
//!   Π_m = ½k₁h² + ½k₂(h − δ)² − P̂h. Its minimum over h, at h = (P̂ + k₂δ)/(k₁ + k₂), is
//!   Π_m(δ) = ½χδ² − tP̂δ (+ a constant) with χ = (1/k₁ + 1/k₂)⁻¹ and t = 1/(1 + k₁/k₂): a
//!   spring χ driven at Δ = P̂/k₁, written in this form so that k₁ → 0 (plain load control)
//!   and k₂ → ∞ (a rigid frame) stay exact. The force on the specimen is Q = tP̂ − χδ, so during
//!   a hold dQ/dδ = −χ (seed 2.6), and the plate sits at h = δ + Q/k₂ with P̂ = k₁h + Q.
//!
//! The Newton system in (u, δ) is bordered: [K_uu g; gᵀ k][Δu; Δδ] = −[r_u; r_δ] with
//! g = ∂²Π_c/∂u∂δ and k = ∂²Π_c/∂δ² (+K). It can be indefinite even when K_uu is definite (on
//! the unstable branch under load control), so it is solved by bordering (CRATES.md pitfall):
//! a = K_uu⁻¹(−r_u), b = K_uu⁻¹g, Δδ = (−r_δ − gᵀa)/(k − gᵀb), Δu = a − bΔδ — two solves with
//! one factorisation of the definite stiffness, never a factorisation of the indefinite matrix.

use super::assembly::{Assembler, Evaluation, Solid};
use super::contact::Contact;
use super::newton::{NewtonSystem, Point};
use super::FeError;
use serde::{Deserialize, Serialize};

/// Why the testing machine's springs are unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MachineError {
    /// the machine spring is not positive and finite
    #[error("machine spring stiffness must be positive and finite, got {stiffness} nN/nm")]
    Stiffness {
        /// K, nN/nm
        stiffness: f64,
    },
    /// the transducer's springs are out of range
    #[error("load-frame springs: k1 must be finite and ≥ 0, k2 positive (may be infinite), got k1 = {k1}, k2 = {k2} nN/nm")]
    LoadFrame {
        /// k₁, nN/nm
        k1: f64,
        /// k₂, nN/nm
        k2: f64,
    },
}

/// How the indenter is driven.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "control", rename_all = "lowercase")]
pub enum Machine {
    /// the schedule prescribes the indenter depth (K → ∞)
    #[default]
    Displacement,
    /// the schedule prescribes the drive Δ, coupled to the indenter by a spring
    Spring {
        /// spring stiffness K, nN/nm (> 0)
        stiffness: f64,
    },
    /// the schedule prescribes the load P (K = 0) after any approach segments, which
    /// prescribe the depth
    Load,
    /// the schedule prescribes the force P̂ on the plate of a two-spring transducer (after any
    /// approach segments, which prescribe the depth)
    LoadFrame {
        /// k₁: support springs in parallel with the specimen (plate to frame), nN/nm (≥ 0;
        /// 0 is plain load control)
        k1: f64,
        /// k₂: load-frame spring in series with the specimen, nN/nm (> 0; may be infinite)
        k2: f64,
    },
}

impl Machine {
    /// Check the spring stiffness.
    pub fn validate(&self) -> Result<(), MachineError> {
        match *self {
            Machine::Spring { stiffness } if !(stiffness > 0.0 && stiffness.is_finite()) => {
                Err(MachineError::Stiffness { stiffness })
            }
            Machine::LoadFrame { k1, k2 } if !(k1 >= 0.0 && k1.is_finite() && k2 > 0.0) => {
                Err(MachineError::LoadFrame { k1, k2 })
            }
            _ => Ok(()),
        }
    }

    /// Whether the schedule's load, hold and unload segments prescribe a force (approach
    /// segments always prescribe the depth).
    pub fn load_controlled(&self) -> bool {
        matches!(self, Machine::Load | Machine::LoadFrame { .. })
    }

    /// What an increment at controlled value `v` prescribes (`by_load`: a load-controlled
    /// segment, see [`Machine::load_controlled`]).
    pub fn drive(&self, by_load: bool, v: f64) -> Drive {
        match *self {
            Machine::Spring { stiffness } => Drive::Spring {
                stiffness,
                drive: v,
            },
            Machine::Load if by_load => Drive::Load(v),
            Machine::LoadFrame { k1, k2 } if by_load => Drive::Frame { k1, k2, load: v },
            _ => Drive::Depth(v),
        }
    }

    /// The controlled force in equilibrium with specimen force `q` (nN) at depth `delta` (nm):
    /// P̂ = k₁h + Q with h = δ + Q/k₂ through the transducer, Q otherwise.
    pub fn applied_load(&self, q: f64, delta: f64) -> f64 {
        match *self {
            Machine::LoadFrame { k1, k2 } => q * (1.0 + k1 / k2) + k1 * delta,
            _ => q,
        }
    }
}

/// What one increment prescribes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Drive {
    /// the indenter depth δ, nm
    Depth(f64),
    /// the drive Δ (nm) through a spring K (nN/nm)
    Spring {
        /// K, nN/nm
        stiffness: f64,
        /// Δ, nm
        drive: f64,
    },
    /// the load P̂, nN
    Load(f64),
    /// the force P̂ on a two-spring transducer's plate ([`Machine::LoadFrame`])
    Frame {
        /// support springs k₁, nN/nm
        k1: f64,
        /// load-frame spring k₂, nN/nm
        k2: f64,
        /// P̂, nN
        load: f64,
    },
}

impl Drive {
    /// The drive's energy term at indenter depth δ, aJ (0 under depth control).
    pub fn energy(&self, delta: f64) -> f64 {
        match *self {
            Drive::Depth(_) => 0.0,
            Drive::Spring { stiffness, drive } => 0.5 * stiffness * (drive - delta).powi(2),
            Drive::Load(p) => -p * delta,
            Drive::Frame { load, .. } => {
                let (chi, t) = self.frame_constants();
                0.5 * chi * delta * delta - t * load * delta
            }
        }
    }

    /// The force the drive exerts on the indenter at depth δ (compressive positive), nN: the
    /// equilibrium value of the specimen's load (= −∂(energy)/∂δ; P̂ under load control, 0
    /// under depth control, where δ is no unknown).
    pub fn force(&self, delta: f64) -> f64 {
        match *self {
            Drive::Depth(_) => 0.0,
            Drive::Spring { stiffness, drive } => stiffness * (drive - delta),
            Drive::Load(p) => p,
            Drive::Frame { load, .. } => {
                let (chi, t) = self.frame_constants();
                t * load - chi * delta
            }
        }
    }

    /// ∂(force)/∂δ's magnitude: the drive's stiffness on the indenter, nN/nm.
    pub fn stiffness(&self) -> f64 {
        match *self {
            Drive::Depth(_) | Drive::Load(_) => 0.0,
            Drive::Spring { stiffness, .. } => stiffness,
            Drive::Frame { .. } => self.frame_constants().0,
        }
    }

    /// Where the driven end sits for depth δ and specimen force `q`, nm: the drive Δ through
    /// a spring, the transducer plate h = δ + Q/k₂, the indenter δ otherwise.
    pub fn position(&self, delta: f64, q: f64) -> f64 {
        match *self {
            Drive::Spring { drive, .. } => drive,
            Drive::Frame { k2, .. } => delta + q / k2,
            _ => delta,
        }
    }

    /// χ = (1/k₁ + 1/k₂)⁻¹ and t = 1/(1 + k₁/k₂) of a frame drive (written so that k₁ = 0 and
    /// k₂ = ∞ are exact); (0, 0) for the other drives.
    fn frame_constants(&self) -> (f64, f64) {
        match *self {
            Drive::Frame { k1, k2, .. } => (1.0 / (1.0 / k1 + 1.0 / k2), 1.0 / (1.0 + k1 / k2)),
            _ => (0.0, 0.0),
        }
    }
}

/// One increment's equilibrium in the unknowns x = (u, δ) (δ last).
pub struct Driven<'a> {
    /// pattern and factorisation of K_uu
    pub asm: &'a mut Assembler,
    /// the solid
    pub solid: &'a Solid,
    /// the contact, if any
    pub contact: Option<&'a Contact<'a>>,
    /// history at the start of the step
    pub history: &'a [f64],
    /// time step, s
    pub dt: f64,
    /// what the increment prescribes
    pub drive: Drive,
    /// smallest reference force for the convergence test, nN
    pub force_floor: f64,
}

impl Driven<'_> {
    /// The indenter depth the state `x` stands for.
    pub fn depth(&self, x: &[f64]) -> f64 {
        match self.drive {
            Drive::Depth(d) => d,
            _ => x[self.solid.dofs()],
        }
    }

    /// The FE evaluation at `x` (without the drive's term).
    pub fn evaluation(&mut self, x: &[f64], tangent: bool) -> Result<Evaluation, FeError> {
        let n = self.solid.dofs();
        let depth = self.depth(x);
        self.asm.evaluate(
            self.solid,
            self.contact,
            (&x[..n], self.history),
            self.dt,
            depth,
            tangent,
        )
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl NewtonSystem for Driven<'_> {
    fn evaluate(&mut self, x: &[f64], tangent: bool) -> Result<Point, FeError> {
        let ev = self.evaluation(x, tangent)?;
        let delta = self.depth(x);
        let (r_delta, k_delta, spring_force) = match self.drive {
            Drive::Depth(_) => (0.0, 1.0, 0.0),
            d => {
                let f = d.force(delta);
                (ev.load - f, ev.load_stiffness + d.stiffness(), f)
            }
        };
        let reference = ev.force_reference(self.force_floor).max(spring_force.abs());
        let mut residual = self.asm.residual(&ev.gradient);
        residual.push(r_delta);
        let mut values = ev.values;
        if tangent {
            values.extend_from_slice(&ev.load_gradient);
            values.push(k_delta);
        }
        Ok(Point {
            energy: ev.energy + self.drive.energy(delta),
            residual,
            reference,
            values,
        })
    }

    fn solve(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, FeError> {
        let (m, k_dd) = (self.k_uu_len(values), values[values.len() - 1]);
        self.asm.factor(&values[..m])?;
        let (x, schur) = self.back_substitute(values, rhs, k_dd)?;
        let g = &values[m..values.len() - 1];
        let scale = k_dd.abs().max(dot(g, g).sqrt());
        // a vanishing Schur complement is a limit point of the load (or no contact yet
        // under load control): no increment of δ balances the residual
        match schur {
            Some(schur) if !(schur.abs() > 1e-12 * scale) || !schur.is_finite() => {
                Err(FeError::LimitPoint { schur })
            }
            _ => Ok(x),
        }
    }

    fn solve_shifted(
        &mut self,
        values: &[f64],
        shift: f64,
        rhs: &[f64],
    ) -> Result<Option<Vec<f64>>, FeError> {
        let (m, k_dd) = (self.k_uu_len(values), values[values.len() - 1]);
        if !self.asm.factor_shifted(&values[..m], shift)? {
            return Ok(None);
        }
        // the whole matrix is positive definite iff K_uu + σ diag and the Schur complement are
        let (x, schur) = self.back_substitute(values, rhs, k_dd * (1.0 + shift))?;
        Ok(schur.is_none_or(|s| s > 0.0).then_some(x))
    }
}

impl Driven<'_> {
    /// The length of K_uu's values in the tangent `values` (K_uu, ∂²Π/∂u∂δ, the depth's row).
    fn k_uu_len(&self, values: &[f64]) -> usize {
        values.len() - self.solid.dofs() - 1
    }

    /// With K_uu factorised: the solution for `rhs` by bordering, the depth's diagonal taking
    /// `k_dd`, and the Schur complement k_dd − gᵀK_uu⁻¹g (none under displacement control,
    /// where δ is given).
    fn back_substitute(
        &mut self,
        values: &[f64],
        rhs: &[f64],
        k_dd: f64,
    ) -> Result<(Vec<f64>, Option<f64>), FeError> {
        let n = self.solid.dofs();
        let m = self.k_uu_len(values);
        let border = &values[m..m + n];
        let mut a = self.asm.back_solve(&rhs[..n])?;
        if let Drive::Depth(_) = self.drive {
            a.push(0.0);
            return Ok((a, None));
        }
        // the second solve reuses the factorisation of K_uu
        let b = self.asm.back_solve(border)?;
        let schur = k_dd - dot(border, &b);
        let d_delta = (rhs[n] - dot(border, &a)) / schur;
        for (ai, bi) in a.iter_mut().zip(&b) {
            *ai -= bi * d_delta;
        }
        a.push(d_delta);
        Ok((a, Some(schur)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of a quadratic energy are exact up to round-off of its size
    /// (~1e6 aJ here): 1e-6 relative to the forces (~1e3 nN).
    const FD_TOL: f64 = 1e-6;

    fn drives() -> Vec<Drive> {
        vec![
            Drive::Spring {
                stiffness: 1e3,
                drive: 40.0,
            },
            Drive::Load(2e3),
            Drive::Frame {
                k1: 100.0,
                k2: 2.1e8,
                load: 2e4,
            },
            Drive::Frame {
                k1: 0.0,
                k2: 1e4,
                load: 2e4,
            },
            Drive::Frame {
                k1: 100.0,
                k2: f64::INFINITY,
                load: 2e4,
            },
        ]
    }

    #[test]
    fn force_and_stiffness_are_derivatives_of_the_energy() {
        let (delta, h) = (30.0, 1e-3);
        for d in drives() {
            let fd_force = -(d.energy(delta + h) - d.energy(delta - h)) / (2.0 * h);
            let fd_stiff = -(d.force(delta + h) - d.force(delta - h)) / (2.0 * h);
            let scale = d.force(delta).abs().max(1.0);
            assert!((fd_force - d.force(delta)).abs() < FD_TOL * scale, "{d:?}");
            assert!((fd_stiff - d.stiffness()).abs() < FD_TOL * scale, "{d:?}");
        }
    }

    #[test]
    fn transducer_is_the_minimum_over_the_plate_and_has_its_limits() {
        // ½k₁h² + ½k₂(h − δ)² − P̂h at its minimum h* differs from the reduced energy by a
        // constant: compare two depths
        let (k1, k2, p) = (100.0, 1e4, 2e4);
        let full = |delta: f64| {
            let h = (p + k2 * delta) / (k1 + k2);
            0.5 * k1 * h * h + 0.5 * k2 * (h - delta).powi(2) - p * h
        };
        let d = Drive::Frame { k1, k2, load: p };
        let change = d.energy(50.0) - d.energy(10.0);
        assert!((change - (full(50.0) - full(10.0))).abs() < FD_TOL * full(10.0).abs());
        // the plate: P̂ = k₁h + Q
        let m = Machine::LoadFrame { k1, k2 };
        let q = d.force(30.0);
        assert!((m.applied_load(q, 30.0) - p).abs() < FD_TOL * p);
        assert!((k1 * d.position(30.0, q) + q - p).abs() < FD_TOL * p);
        // k₁ = 0 is load control; k₂ = ∞ a rigid frame (plate = indenter)
        let soft = Drive::Frame {
            k1: 0.0,
            k2: f64::INFINITY,
            load: p,
        };
        assert_eq!((soft.force(30.0), soft.stiffness()), (p, 0.0));
        let rigid = Drive::Frame {
            k1,
            k2: f64::INFINITY,
            load: p,
        };
        assert_eq!(rigid.position(30.0, rigid.force(30.0)), 30.0);
        assert_eq!(rigid.stiffness(), k1);
    }
}
