//! Newton's method for the discretised half-space under a bordering (control) equation.
//!
//! Unknowns x = (H₀ … H_{N−1}, D): the nodal gaps and the approach. Residuals
//!
//! R_i = H_i + D − ρ_i²/2 − Σ_j A_ij P̄(H_j)   (i < N),   R_N = H₀ − H₀\*, D − D\*, or τ·(x − x₀) − Δs,
//!
//! with the exact Jacobian ∂R_i/∂H_j = δ_ij − A_ij k̄(H_j), ∂R_i/∂D = 1, and a last row that
//! prescribes the central gap ([`Control::CentralGap`]), the approach ([`Control::Approach`],
//! used to move a stable solution onto another grid, where H₀ is far more sensitive to the
//! discretisation than D on the contact branch) or a pseudo-arclength step
//! ([`Control::Arc`], continuation). The bordered dense system is factorised by faer's
//! partial-pivoting LU (it is indefinite). The unit tangent of the solution path is the null
//! vector of the N×(N+1) equilibrium Jacobian, from the same bordered system with an orientation
//! vector as last row; it gives the predictor and the exact slopes dD/ds and
//! dF̄/ds = Σ_j w_j k̄_j dH_j/ds used to locate jump points and pull-off.
//!
//! The collocation system is not symmetric (ring-averaged displacements would be), so it is not
//! the gradient of a discrete energy; the Jacobian is the exact derivative of the residual
//! (checked by finite differences below).

use super::grid::Grid;
use super::influence::{influence_matrix, scaled_factor};
use super::{HalfspaceError, HalfspaceParams, Problem, Traction};
use crate::numerics::newton::{self, NewtonError, NewtonParams, NewtonProblem, Trial};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// The uniform zone must also cover every radius where the gap is below this (z₀) and the law
/// stiffens with the gap (k̄ = dP̄/dH > 0, beyond the peak tension). A graded ring of width s at
/// such a gap H is unstable on its own (the diagonal 1 − A_ii k̄(H) of the Jacobian turns
/// negative, a discrete jump of one ring) once its self-compliance A_ii ∝ μ^{3/2}s times k̄
/// exceeds 1; beyond H = 3 the LJ stiffness is below 0.1 γ/z₀² (9-3: 0.098), about a fifth of
/// its value at H = 2, so graded cells are safe there. Where k̄ < 0 (gaps below the peak
/// tension, inside the contact) the diagonal exceeds 1 whatever the cell, and the grid may be
/// graded: at large μ that is most of the contact (a flat neck at H ≈ 1 on the unstable branch).
pub(crate) const NEAR_GAP: f64 = 3.0;

/// Step halvings tried before a Newton step is accepted anyway.
const MAX_BACKTRACKS: usize = 8;

/// A solution of the discretised problem (scaled units).
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// nodal gaps H_i, z₀
    pub gaps: Vec<f64>,
    /// approach D, z₀
    pub approach: f64,
}

/// The unit tangent of the solution path in (H₀ … H_{N−1}, D) space, d/ds along the
/// (Euclidean) arclength s, and the load slope it implies.
#[derive(Debug, Clone, PartialEq)]
pub struct Tangent {
    /// dH_i/ds
    pub gaps: Vec<f64>,
    /// dD/ds
    pub approach: f64,
    /// dF̄/ds = Σ_j w_j k̄_j dH_j/ds
    pub load: f64,
}

impl Tangent {
    /// The tangent as one vector (gaps, then D).
    pub fn vector(&self) -> Vec<f64> {
        let mut v = self.gaps.clone();
        v.push(self.approach);
        v
    }

    /// The same tangent pointing the other way.
    pub fn reversed(&self) -> Tangent {
        Tangent {
            gaps: self.gaps.iter().map(|t| -t).collect(),
            approach: -self.approach,
            load: -self.load,
        }
    }
}

/// What the last (bordering) equation prescribes.
#[derive(Debug, Clone, PartialEq)]
pub enum Control {
    /// the central gap H(0), z₀
    CentralGap(f64),
    /// the approach D, z₀
    Approach(f64),
    /// pseudo-arclength (Keller): direction · (x − origin) = length, x = (gaps, D); regular
    /// through turning points of every component, including folds of H(0)
    Arc {
        /// unit tangent at the origin
        direction: Vec<f64>,
        /// the previous solution (gaps, D)
        origin: Vec<f64>,
        /// step along the direction
        length: f64,
    },
}

/// The discretised problem on one grid: influence matrix, load weights and the law.
pub struct System<'a, T: Traction> {
    problem: &'a Problem<T>,
    /// the radial grid
    pub grid: Grid,
    influence: Vec<f64>,
    weights: Vec<f64>,
}

impl<'a, T: Traction> System<'a, T> {
    /// Assemble the influence matrix on `grid`.
    pub fn new(problem: &'a Problem<T>, grid: Grid) -> Self {
        let influence = influence_matrix(&grid, scaled_factor(problem.tabor()));
        let weights = grid.load_weights();
        System {
            problem,
            grid,
            influence,
            weights,
        }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.grid.len()
    }

    /// True if there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.grid.is_empty()
    }

    /// Scaled pressures and stiffnesses at the nodal gaps.
    fn law(&self, gaps: &[f64]) -> (Vec<f64>, Vec<f64>) {
        gaps.iter().map(|&h| self.problem.scaled_law(h)).unzip()
    }

    /// Scaled load F̄ = Σ w_j P̄(H_j).
    pub fn load(&self, state: &State) -> f64 {
        let (p, _) = self.law(&state.gaps);
        p.iter().zip(&self.weights).map(|(p, w)| p * w).sum()
    }

    /// Nodal surface displacements U_i = Σ_j A_ij P̄_j, z₀.
    pub fn displacement(&self, pressures: &[f64]) -> Vec<f64> {
        let n = self.len();
        (0..n)
            .map(|i| {
                let row = &self.influence[i * n..(i + 1) * n];
                row.iter().zip(pressures).map(|(a, p)| a * p).sum()
            })
            .collect()
    }

    /// The residual vector (length N + 1) at `state` under `control`.
    pub fn residual(&self, state: &State, control: &Control) -> Vec<f64> {
        let (p, _) = self.law(&state.gaps);
        let u = self.displacement(&p);
        let mut r: Vec<f64> = (0..self.len())
            .map(|i| {
                let rho = self.grid.nodes[i];
                state.gaps[i] + state.approach - 0.5 * rho * rho - u[i]
            })
            .collect();
        r.push(match control {
            Control::CentralGap(h0) => state.gaps[0] - h0,
            Control::Approach(d) => state.approach - d,
            Control::Arc {
                direction,
                origin,
                length,
            } => {
                let x = state.gaps.iter().chain(std::iter::once(&state.approach));
                x.zip(origin)
                    .zip(direction)
                    .map(|((x, o), t)| (x - o) * t)
                    .sum::<f64>()
                    - length
            }
        });
        r
    }

    /// The exact Jacobian of [`Self::residual`], (N+1)×(N+1).
    pub fn jacobian(&self, state: &State, control: &Control) -> Mat<f64> {
        let n = self.len();
        let (_, k) = self.law(&state.gaps);
        let last_row = |j: usize| match control {
            Control::CentralGap(_) => f64::from(u8::from(j == 0)),
            Control::Approach(_) => f64::from(u8::from(j == n)),
            Control::Arc { direction, .. } => direction[j],
        };
        Mat::from_fn(n + 1, n + 1, |i, j| {
            if i == n {
                last_row(j)
            } else if j == n {
                1.0
            } else {
                f64::from(u8::from(i == j)) - self.influence[i * n + j] * k[j]
            }
        })
    }

    /// The unit path tangent at a converged state, oriented so that its product with
    /// `orientation` (a vector in (gaps, D) space, e.g. the previous tangent) is positive: the
    /// null vector of the N×(N+1) equilibrium Jacobian, from the bordered system with
    /// `orientation` as the last row (LU with partial pivoting; the bordered matrix is
    /// indefinite).
    pub fn tangent(&self, state: &State, orientation: &[f64]) -> Result<Tangent, HalfspaceError> {
        let n = self.len();
        let control = Control::Arc {
            direction: orientation.to_vec(),
            origin: vec![0.0; n + 1],
            length: 0.0,
        };
        let lu = self.jacobian(state, &control).partial_piv_lu();
        let mut rhs = Mat::from_fn(n + 1, 1, |i, _| f64::from(u8::from(i == n)));
        lu.solve_in_place(&mut rhs);
        let norm = (0..=n)
            .map(|i| rhs[(i, 0)] * rhs[(i, 0)])
            .sum::<f64>()
            .sqrt();
        let t: Vec<f64> = (0..=n).map(|i| rhs[(i, 0)] / norm).collect();
        if t.iter().any(|v| !v.is_finite()) {
            return Err(HalfspaceError::NonFinite {
                central_gap: state.gaps[0],
            });
        }
        let (_, k) = self.law(&state.gaps);
        let load = (0..n).map(|j| self.weights[j] * k[j] * t[j]).sum();
        Ok(Tangent {
            approach: t[n],
            gaps: t[..n].to_vec(),
            load,
        })
    }

    /// Newton from `guess` to the solution under `control`. Returns the state and the number
    /// of iterations; `Err` (with the last residual) if it does not converge.
    pub fn solve(
        &self,
        control: &Control,
        guess: State,
        params: &HalfspaceParams,
    ) -> Result<(State, usize), HalfspaceError> {
        let central_gap = match control {
            Control::CentralGap(h0) => *h0,
            _ => guess.gaps[0],
        };
        let mut x = guess.gaps;
        x.push(guess.approach);
        let mut balance = Balance {
            system: self,
            control,
            central_gap,
            params,
            residual: Vec::new(),
            last_trial: Vec::new(),
        };
        let newton = NewtonParams {
            max_iterations: params.max_iterations,
            max_backtracks: MAX_BACKTRACKS - 1,
            ..NewtonParams::default()
        };
        match newton::solve(&mut balance, &mut x, &newton) {
            Ok(info) => Ok((state_of(&x), info.iterations)),
            Err(NewtonError::NoConvergence {
                iterations,
                residuals,
            }) => Err(HalfspaceError::NoConvergence {
                central_gap,
                residual: residuals.last().copied().unwrap_or(f64::INFINITY),
                iterations,
                step: 0.0,
            }),
            // (the line search takes its last trial rather than fail)
            Err(NewtonError::LineSearch { iteration, .. }) => Err(HalfspaceError::NoConvergence {
                central_gap,
                residual: largest(&balance.residual),
                iterations: iteration,
                step: 0.0,
            }),
            Err(NewtonError::Problem(e)) => Err(e),
        }
    }

    /// The rigid-sphere state (no deformation) with central gap `h0`: a starting guess far out.
    pub fn rigid(&self, h0: f64) -> State {
        State {
            gaps: self.grid.nodes.iter().map(|r| h0 + 0.5 * r * r).collect(),
            approach: -h0,
        }
    }

    /// Contact radius: outermost radius where H = 1 (p changes sign), scaled; 0 if H(0) > 1.
    pub fn contact_radius(&self, state: &State) -> f64 {
        let g = &state.gaps;
        match (1..g.len()).rev().find(|&i| g[i - 1] <= 1.0 && g[i] > 1.0) {
            Some(i) => {
                let (r0, r1) = (self.grid.nodes[i - 1], self.grid.nodes[i]);
                r0 + (1.0 - g[i - 1]) / (g[i] - g[i - 1]) * (r1 - r0)
            }
            None => 0.0,
        }
    }

    /// Indices of the nodes whose gap is below `NEAR_GAP` where the law stiffens with the gap
    /// (k̄ > 0): the rings that could jump on their own on a coarse cell
    /// ([`NEAR_GAP`]).
    pub fn soft_nodes(&self, state: &State) -> Vec<usize> {
        (0..self.len())
            .filter(|&i| {
                let h = state.gaps[i];
                h < NEAR_GAP && self.problem.scaled_law(h).1 > 0.0
            })
            .collect()
    }

    /// Rigid estimate of the load carried by the attraction beyond the outer edge, 2φ̄(H_edge).
    pub fn tail_load(&self, state: &State) -> f64 {
        let b = *self.grid.edges.last().unwrap_or(&0.0);
        let h_edge = self.grid.interpolate(&state.gaps, b) + 0.5 * b * b
            - 0.5 * self.grid.nodes.last().map_or(0.0, |r| r * r);
        2.0 * self.problem.scaled_tail_energy(h_edge)
    }

    /// A starting state on this grid from a converged state on grid `other`: the surface
    /// displacement U = H − ρ²/2 + D (smooth) interpolated linearly, continued beyond the old
    /// domain as the Boussinesq far field U ∝ 1/ρ (a constant there put the guess ~0.2 z₀ off at
    /// the outer node at μ = 10, where the outer cells are wide and U ~ μ^{3/2}F̄/ρ is large), and
    /// the same approach. Interpolating H itself would add the chord error of the parabola,
    /// Δρ²/8, which is large on the graded outer cells.
    pub fn transfer(&self, other: &Grid, state: &State) -> State {
        let d = state.approach;
        let displacement: Vec<f64> = other
            .nodes
            .iter()
            .zip(&state.gaps)
            .map(|(r, h)| h - 0.5 * r * r + d)
            .collect();
        let (r_last, u_last) = (other.nodes[other.len() - 1], displacement[other.len() - 1]);
        State {
            gaps: self
                .grid
                .nodes
                .iter()
                .map(|&r| {
                    let u = if r > r_last {
                        u_last * r_last / r
                    } else {
                        other.interpolate(&displacement, r)
                    };
                    u - d + 0.5 * r * r
                })
                .collect(),
            approach: d,
        }
    }
}

/// The state (H, D) the unknowns `x` stand for.
fn state_of(x: &[f64]) -> State {
    let n = x.len() - 1;
    State {
        gaps: x[..n].to_vec(),
        approach: x[n],
    }
}

/// The half-space's plug-ins to the Newton loop: the max norm of R, the bordered Jacobian
/// solved by dense LU, the largest change of any unknown capped at
/// [`HalfspaceParams::max_newton_change`], and a trial accepted when ‖R‖₂ decreases (the
/// Newton direction is a descent direction of ‖R‖₂², not of the max norm); after
/// [`MAX_BACKTRACKS`] halvings the last trial is taken anyway.
struct Balance<'s, 'a, T: Traction> {
    system: &'s System<'a, T>,
    control: &'s Control,
    /// H(0) prescribed or at the guess, for the error messages
    central_gap: f64,
    params: &'s HalfspaceParams,
    /// R at the iterate
    residual: Vec<f64>,
    /// the last rejected trial
    last_trial: Vec<f64>,
}

impl<T: Traction> NewtonProblem for Balance<'_, '_, T> {
    type Error = HalfspaceError;

    fn residual(&mut self, x: &[f64]) -> Result<f64, HalfspaceError> {
        self.residual = self.system.residual(&state_of(x), self.control);
        let norm = self.residual.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !norm.is_finite() {
            return Err(HalfspaceError::NonFinite {
                central_gap: self.central_gap,
            });
        }
        Ok(norm)
    }

    fn converged(&self, residuals: &[f64]) -> bool {
        residuals.last().is_some_and(|&r| r < self.params.tolerance)
    }

    fn direction(&mut self, x: &[f64]) -> Result<Vec<f64>, HalfspaceError> {
        let m = x.len();
        let lu = self
            .system
            .jacobian(&state_of(x), self.control)
            .partial_piv_lu();
        let mut dx = Mat::from_fn(m, 1, |i, _| -self.residual[i]);
        lu.solve_in_place(&mut dx);
        let dx: Vec<f64> = (0..m).map(|i| dx[(i, 0)]).collect();
        if !largest(&dx).is_finite() {
            return Err(HalfspaceError::NonFinite {
                central_gap: self.central_gap,
            });
        }
        Ok(dx)
    }

    fn first_step(&self, dx: &[f64]) -> f64 {
        (self.params.max_newton_change / largest(dx)).min(1.0)
    }

    fn try_step(&mut self, x: &mut [f64], dx: &[f64], s: f64) -> Result<Trial, HalfspaceError> {
        let norm2: f64 = self.residual.iter().map(|v| v * v).sum();
        self.last_trial = x.iter().zip(dx).map(|(x, d)| x + s * d).collect();
        let r_trial = self
            .system
            .residual(&state_of(&self.last_trial), self.control);
        let trial2: f64 = r_trial.iter().map(|v| v * v).sum();
        if trial2 < norm2 {
            x.copy_from_slice(&self.last_trial);
            return Ok(Trial::Accepted);
        }
        Ok(Trial::Rejected(format!("‖R‖₂² {norm2:.3e} → {trial2:.3e}")))
    }

    fn exhausted(&mut self, x: &mut [f64]) -> bool {
        x.copy_from_slice(&self.last_trial);
        true
    }
}

/// The largest |entry|.
fn largest(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, d| m.max(d.abs()))
}

#[cfg(test)]
mod tests {
    use super::super::grid::GridSpec;
    use super::*;
    use crate::laws::LjKind;

    const FD_TOL: f64 = 1e-6; // central differences, step 1e-6: truncation ~1e-10, rounding ~1e-9

    fn system(problem: &Problem) -> System<'_, LennardJones> {
        let spec = GridSpec {
            fine_spacing: 0.1,
            zone_lo: 0.0,
            zone_hi: 2.0,
            growth: 0.3,
            outer: 10.0,
        };
        System::new(problem, spec.build())
    }
    use crate::laws::LennardJones;

    #[test]
    fn jacobian_matches_finite_differences() {
        let problem = Problem::scaled(1.0, LjKind::Lj93).unwrap();
        let sys = system(&problem);
        let n = sys.len();
        // a state with gaps around z₀, where the law is stiff and changes sign
        let mut state = sys.rigid(0.9);
        state
            .gaps
            .iter_mut()
            .enumerate()
            .for_each(|(i, g)| *g += 0.05 * (i as f64).sin());
        let arc = Control::Arc {
            direction: (0..=n).map(|i| (0.3 * i as f64).cos()).collect(),
            origin: (0..=n).map(|i| 0.01 * i as f64).collect(),
            length: 0.2,
        };
        for control in [Control::CentralGap(0.9), Control::Approach(1.1), arc] {
            let j = sys.jacobian(&state, &control);
            let e = 1e-6;
            for col in [0, 3, n / 2, n] {
                let mut plus = state.clone();
                let mut minus = state.clone();
                if col < n {
                    plus.gaps[col] += e;
                    minus.gaps[col] -= e;
                } else {
                    plus.approach += e;
                    minus.approach -= e;
                }
                let rp = sys.residual(&plus, &control);
                let rm = sys.residual(&minus, &control);
                for row in 0..=n {
                    let fd = (rp[row] - rm[row]) / (2.0 * e);
                    let tol = FD_TOL * j[(row, col)].abs().max(1.0);
                    assert!(
                        (fd - j[(row, col)]).abs() < tol,
                        "({row},{col}) {fd} vs {}",
                        j[(row, col)]
                    );
                }
            }
        }
    }

    #[test]
    fn newton_converges_and_tangent_matches_finite_differences() {
        // the unit tangent against the normalised difference of two converged solutions at
        // H(0) ± e, and dF̄/ds against the load difference over the same arclength
        let problem = Problem::scaled(1.0, LjKind::Lj93).unwrap();
        let sys = system(&problem);
        let n = sys.len();
        let params = HalfspaceParams::default();
        let h0 = 1.3;
        let (s0, _) = sys
            .solve(&Control::CentralGap(h0), sys.rigid(h0), &params)
            .unwrap();
        let towards_larger_h0: Vec<f64> = (0..=n).map(|i| f64::from(u8::from(i == 0))).collect();
        let t = sys.tangent(&s0, &towards_larger_h0).unwrap();
        let e = 1e-5;
        let (sp, _) = sys
            .solve(&Control::CentralGap(h0 + e), s0.clone(), &params)
            .unwrap();
        let (sm, _) = sys
            .solve(&Control::CentralGap(h0 - e), s0.clone(), &params)
            .unwrap();
        let mut dx: Vec<f64> = sp.gaps.iter().zip(&sm.gaps).map(|(a, b)| a - b).collect();
        dx.push(sp.approach - sm.approach);
        let ds = dx.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(t.gaps[0] > 0.0, "orientation");
        for (i, (fd, exact)) in dx.iter().zip(t.vector()).enumerate() {
            assert!(
                (fd / ds - exact).abs() < FD_TOL * 10.0,
                "{i}: {} vs {exact}",
                fd / ds
            );
        }
        let df = (sys.load(&sp) - sys.load(&sm)) / ds;
        assert!(
            (df - t.load).abs() < 1e-5 * t.load.abs().max(1.0),
            "{df} {}",
            t.load
        );
    }

    #[test]
    fn far_field_displacement_equals_point_load() {
        // Boussinesq far field u → P/(πE* r): the ring coefficients and the load weights must
        // describe the same load, so the scaled far-field displacement is F̄ μ^{3/2}/ρ
        let mu: f64 = 0.7;
        let problem = Problem::scaled(mu, LjKind::Lj93).unwrap();
        let sys = system(&problem);
        let n = sys.len();
        let p: Vec<f64> = sys.grid.nodes.iter().map(|r| (-r * r).exp()).collect();
        let f: f64 = p
            .iter()
            .zip(sys.grid.load_weights())
            .map(|(p, w)| p * w)
            .sum();
        // displacement at a far radius through the same ring coefficients
        let rho = 1e3;
        let u: f64 = (0..n)
            .map(|j| {
                let (b0, b1) = (sys.grid.edges[j], sys.grid.edges[j + 1]);
                scaled_factor(mu)
                    * (super::super::influence::disc_displacement(rho, b1)
                        - super::super::influence::disc_displacement(rho, b0))
                    * p[j]
            })
            .sum();
        // P = πγR F̄, u = P/(πE* r) ⇒ U = u/z₀ = F̄ μ^{3/2} / ρ in scaled units
        let want = f * mu.powf(1.5) / rho;
        assert!((u - want).abs() < 1e-5 * want.abs(), "{u} vs {want}");
    }
}
