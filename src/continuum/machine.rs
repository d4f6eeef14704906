//! The testing machine between the drive and the indenter (seed §6.1, Fig 6.1): the indenter
//! depth δ is an unknown next to the nodal displacements, and the drive adds a term to the
//! total potential —
//!
//! - displacement control (K → ∞): δ = Δ, no unknown;
//! - a machine spring of stiffness K: ½K(Δ − δ)², so P(δ) = K(Δ − δ) at equilibrium and, at a
//!   jump (fixed Δ), the state moves along a line of slope dP/dδ = −K;
//! - load control (K = 0): −P̂δ, so P(δ) = P̂.
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
}

impl Machine {
    /// Check the spring stiffness.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            Machine::Spring { stiffness } if !(stiffness > 0.0 && stiffness.is_finite()) => {
                Err(format!(
                    "machine spring stiffness must be positive and finite, got {stiffness} nN/nm"
                ))
            }
            _ => Ok(()),
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
}

impl Drive {
    /// The drive's energy term at indenter depth δ, aJ (0 under depth control).
    pub fn energy(&self, delta: f64) -> f64 {
        match *self {
            Drive::Depth(_) => 0.0,
            Drive::Spring { stiffness, drive } => 0.5 * stiffness * (drive - delta).powi(2),
            Drive::Load(p) => -p * delta,
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
    fn evaluate(&mut self, x: &[f64], tangent: bool) -> Result<Point, String> {
        let ev = self.evaluation(x, tangent).map_err(|e| e.to_string())?;
        let delta = self.depth(x);
        let (r_delta, k_delta, spring_force) = match self.drive {
            Drive::Depth(_) => (0.0, 1.0, 0.0),
            Drive::Spring { stiffness, drive } => (
                ev.load - stiffness * (drive - delta),
                ev.load_stiffness + stiffness,
                stiffness * (drive - delta),
            ),
            Drive::Load(p) => (ev.load - p, ev.load_stiffness, p),
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

    fn solve(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, String> {
        let n = self.solid.dofs();
        let m = values.len() - n - 1;
        let (k_uu, border, k_dd) = (&values[..m], &values[m..m + n], values[m + n]);
        let factor = self.asm.factor(k_uu).map_err(|e| e.to_string())?;
        let mut a = self
            .asm
            .back_solve(&factor, &rhs[..n])
            .map_err(|e| e.to_string())?;
        if let Drive::Depth(_) = self.drive {
            a.push(0.0);
            return Ok(a);
        }
        // the second solve reuses the factorisation of K_uu
        let b = self
            .asm
            .back_solve(&factor, border)
            .map_err(|e| e.to_string())?;
        let schur = k_dd - dot(border, &b);
        let scale = k_dd.abs().max(dot(border, border).sqrt());
        // a vanishing Schur complement is a limit point of the load (or no contact yet
        // under load control): no increment of δ balances the residual
        if !(schur.abs() > 1e-12 * scale) || !schur.is_finite() {
            return Err(format!(
                "bordered solve: the indenter's effective stiffness k − gᵀK⁻¹g = {schur:.3e} nN/nm vanishes (a load limit point, or no contact under load control)"
            ));
        }
        let d_delta = (rhs[n] - dot(border, &a)) / schur;
        for (ai, bi) in a.iter_mut().zip(&b) {
            *ai -= bi * d_delta;
        }
        a.push(d_delta);
        Ok(a)
    }
}
