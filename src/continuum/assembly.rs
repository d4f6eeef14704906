//! Global assembly: element kernels evaluated in parallel (rayon), results scattered
//! sequentially in element order, so the sums — and the numbers — are the same with any number
//! of threads. The sparse pattern (every element's 6×6 block, every surface segment's 4×4
//! block, a unit diagonal entry per constrained dof) is built once per mesh; faer sums the
//! duplicates in a fixed order and the symbolic factorisation is reused for every solve.
//!
//! Constrained dofs keep their prescribed values: their residual entries are zeroed (the
//! gradient keeps them as reactions), their rows and columns carry only the unit diagonal.

use super::contact::{Contact, SegmentOutput};
use super::element::{self, Geometry, Kinematics, StepContext};
use super::material::ellipticity::{self, AcousticMinimum};
use super::material::{Material, Voigt};
use super::mesh::Mesh;
use super::FeError;
use crate::numerics::sparse::{SparseError, SparseSystem};
use rayon::prelude::*;
use std::time::Instant;

/// The discretised solid: reference nodes, elements, constitutive model and constraints.
pub struct Solid {
    /// reference node positions (r, z), nm
    pub nodes: Vec<[f64; 2]>,
    /// element geometry
    pub elements: Vec<Geometry>,
    /// element kinematics
    pub kinematics: Kinematics,
    /// constitutive model
    pub material: Box<dyn Material>,
    /// per dof (2 per node: u_r, u_z): true if prescribed
    pub fixed: Vec<bool>,
}

impl Solid {
    /// The solid on `mesh`, with no constraints yet.
    pub fn new(
        mesh: &Mesh,
        kinematics: Kinematics,
        material: Box<dyn Material>,
    ) -> Result<Self, FeError> {
        let elements = mesh
            .triangles
            .iter()
            .enumerate()
            .map(|(e, t)| element::geometry(e, *t, t.map(|n| mesh.nodes[n])))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Solid {
            nodes: mesh.nodes.clone(),
            elements,
            kinematics,
            material,
            fixed: vec![false; 2 * mesh.nodes.len()],
        })
    }

    /// Number of dofs.
    pub fn dofs(&self) -> usize {
        2 * self.nodes.len()
    }

    /// History values per element.
    pub fn history_len(&self) -> usize {
        self.material.history_len()
    }

    fn local(&self, g: &Geometry, u: &[f64]) -> [f64; 6] {
        let mut ue = [0.0; 6];
        for (a, &n) in g.nodes.iter().enumerate() {
            ue[2 * a] = u[2 * n];
            ue[2 * a + 1] = u[2 * n + 1];
        }
        ue
    }

    /// Contact segment `i` of `c` under displacements `u` with the indenter at `depth`.
    fn contact_segment(&self, c: &Contact, i: usize, u: &[f64], depth: f64) -> SegmentOutput {
        let s = c.segments[i];
        let x_ref = [self.nodes[s[0]], self.nodes[s[1]]];
        let x = [0, 1].map(|a| {
            let n = s[a];
            [x_ref[a][0] + u[2 * n], x_ref[a][1] + u[2 * n + 1]]
        });
        c.segment(i, x, x_ref, depth, self.kinematics == Kinematics::Small)
    }

    fn context(&self, dt: f64) -> StepContext<'_> {
        StepContext {
            kinematics: self.kinematics,
            material: self.material.as_ref(),
            dt,
        }
    }

    /// Advance every element's history to the end of a converged step.
    pub fn commit(&self, u: &[f64], history: &mut [f64], dt: f64) -> Result<(), FeError> {
        let h = self.history_len();
        if h == 0 {
            return Ok(());
        }
        for (e, (g, hist)) in self.elements.iter().zip(history.chunks_mut(h)).enumerate() {
            let s = element::strain(g, &self.local(g, u), self.kinematics);
            self.material
                .update_history(&s.d, hist, dt)
                .map_err(|source| element::ElementError::Material { element: e, source })?;
        }
        Ok(())
    }

    /// Cauchy stress of every element (GPa, Voigt [rr, zz, θθ, rz]) after a converged step.
    pub fn stresses(&self, u: &[f64], history: &[f64], dt: f64) -> Result<Vec<Voigt>, FeError> {
        let h = self.history_len();
        self.elements
            .par_iter()
            .enumerate()
            .map(|(e, g)| {
                let s = element::strain(g, &self.local(g, u), self.kinematics);
                let hist = &history[e * h..(e + 1) * h];
                let r = self
                    .material
                    .response(&s.d, hist, dt)
                    .map_err(|source| element::ElementError::Material { element: e, source })?;
                Ok(element::cauchy(&s, &r.stress, self.kinematics))
            })
            .collect()
    }
}

/// The element whose state is least elliptic ([`ellipticity`]): its index, reference centroid
/// (R, Z) and the acoustic minimum there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeastElliptic {
    /// element index
    pub element: usize,
    /// reference centroid (R, Z), nm
    pub centroid: [f64; 2],
    /// the least in-plane acoustic eigenvalue and its normal
    pub minimum: AcousticMinimum,
}

impl Solid {
    /// The element of least in-plane acoustic stiffness under displacements `u` (the
    /// instantaneous response, history as given), normals every 5°; `None` without elements.
    pub fn least_elliptic(
        &self,
        u: &[f64],
        history: &[f64],
    ) -> Result<Option<LeastElliptic>, FeError> {
        let h = self.history_len();
        let found = self
            .elements
            .par_iter()
            .enumerate()
            .map(|(e, g)| {
                let s = element::strain(g, &self.local(g, u), self.kinematics);
                let r = self
                    .material
                    .response(&s.d, &history[e * h..(e + 1) * h], 0.0)
                    .map_err(|source| element::ElementError::Material { element: e, source })?;
                let z = g.nodes.iter().map(|&n| self.nodes[n][1]).sum::<f64>() / 3.0;
                Ok(LeastElliptic {
                    element: e,
                    centroid: [g.r_c, z],
                    minimum: ellipticity::in_plane_minimum(&r, s.f, 36),
                })
            })
            .collect::<Result<Vec<_>, FeError>>()?;
        Ok(found
            .into_iter()
            .min_by(|a, b| a.minimum.eigenvalue.total_cmp(&b.minimum.eigenvalue)))
    }
}

/// Totals of the work done, for the benchmarks.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct AssemblyStats {
    /// evaluations of energy, forces and tangent
    pub assemblies: usize,
    /// wall time in assembly, s
    pub assembly_s: f64,
    /// numeric factorisations of the stiffness
    pub factorisations: usize,
    /// linear solves (back substitutions with a factorisation)
    pub solves: usize,
    /// wall time in factorisations and solves, s
    pub solve_s: f64,
    /// factorisations where Cholesky failed and LU was used
    pub lu_fallbacks: usize,
    /// LDLᵀ factorisations that counted the stiffness's negative eigenvalues (arc-length, at
    /// each converged point; their time is in `solve_s`)
    pub inertias: usize,
}

/// Energy, gradient and tangent of the whole problem at one state.
#[derive(Debug, Clone, Default)]
pub struct Evaluation {
    /// Π, aJ
    pub energy: f64,
    /// ∂Π/∂u for every dof (reactions on the constrained ones), nN
    pub gradient: Vec<f64>,
    /// P = ∂Π/∂δ, the indenter load, nN
    pub load: f64,
    /// √(Σₑ ‖fₑ‖²) over the elements: the scale of the forces summed at the nodes, so of the
    /// round-off in the residual, nN
    pub force_scale: f64,
    /// tangent values in the pattern's order (empty if not asked for)
    pub values: Vec<f64>,
    /// the elements' share of `energy` (strain energy, or the incremental potential of a
    /// viscoelastic step), aJ
    pub strain_energy: f64,
    /// the contact damping pseudo-potential's share of `energy`, aJ
    pub damping_energy: f64,
    /// ∂²Π/∂u∂δ for every dof (constrained entries zeroed), nN/nm
    pub load_gradient: Vec<f64>,
    /// ∂²Π/∂δ², nN/nm
    pub load_stiffness: f64,
}

impl Evaluation {
    /// The magnitude of the forces in play, for the convergence test: the gradient (reactions
    /// included), the load, a round-off share of the element forces, and at least `floor`.
    pub fn force_reference(&self, floor: f64) -> f64 {
        let gnorm = self.gradient.iter().map(|g| g * g).sum::<f64>().sqrt();
        gnorm
            .max(self.load.abs())
            .max(1e-3 * self.force_scale)
            .max(floor)
    }
}

/// The sparse pattern of a solid (and contact surface) with its factorisation.
pub struct Assembler {
    system: SparseSystem,
    fixed_dofs: Vec<usize>,
    /// (index in the values, dof) of every diagonal entry: the shifted factorisation
    diagonal: Vec<(usize, usize)>,
    /// the work done so far
    pub stats: AssemblyStats,
}

impl Assembler {
    /// Build the pattern once.
    pub fn new(solid: &Solid, contact: Option<&Contact>) -> Result<Self, FeError> {
        let mut pos = Vec::with_capacity(36 * solid.elements.len());
        for g in &solid.elements {
            let d: [usize; 6] = dofs_of(&g.nodes);
            for p in d {
                for q in d {
                    pos.push((p, q));
                }
            }
        }
        if let Some(c) = contact {
            for s in &c.segments {
                let d: [usize; 4] = dofs_of(s);
                for p in d {
                    for q in d {
                        pos.push((p, q));
                    }
                }
            }
        }
        let fixed_dofs: Vec<usize> = (0..solid.dofs()).filter(|&d| solid.fixed[d]).collect();
        pos.extend(fixed_dofs.iter().map(|&d| (d, d)));
        let diagonal = (pos.iter().enumerate())
            .filter(|(_, (p, q))| p == q)
            .map(|(k, &(d, _))| (k, d))
            .collect();
        Ok(Assembler {
            system: SparseSystem::new(solid.dofs(), &pos)?,
            fixed_dofs,
            diagonal,
            stats: AssemblyStats::default(),
        })
    }

    /// Energy, gradient, load and (if `tangent`) the tangent at displacements `u` with the
    /// indenter at `depth`, history at the start of a step of length `dt`.
    pub fn evaluate(
        &mut self,
        solid: &Solid,
        contact: Option<&Contact>,
        state: (&[f64], &[f64]),
        dt: f64,
        depth: f64,
        tangent: bool,
    ) -> Result<Evaluation, FeError> {
        let t0 = Instant::now();
        let (u, history) = state;
        let h = solid.history_len();
        let ctx = solid.context(dt);
        let outs = solid
            .elements
            .par_iter()
            .enumerate()
            .map(|(e, g)| {
                let hist = &history[e * h..(e + 1) * h];
                element::evaluate(e, g, &solid.local(g, u), &ctx, hist, tangent)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut ev = Evaluation {
            energy: 0.0,
            gradient: vec![0.0; solid.dofs()],
            load: 0.0,
            force_scale: 0.0,
            values: Vec::new(),
            strain_energy: 0.0,
            damping_energy: 0.0,
            load_gradient: vec![0.0; solid.dofs()],
            load_stiffness: 0.0,
        };
        if tangent {
            ev.values.reserve(36 * outs.len());
        }
        for (g, o) in solid.elements.iter().zip(&outs) {
            let d: [usize; 6] = dofs_of(&g.nodes);
            ev.energy += o.energy;
            ev.strain_energy += o.energy;
            ev.force_scale += o.force.iter().map(|f| f * f).sum::<f64>();
            for (p, &dp) in d.iter().enumerate() {
                ev.gradient[dp] += o.force[p];
                if tangent {
                    for (q, &dq) in d.iter().enumerate() {
                        let free = !solid.fixed[dp] && !solid.fixed[dq];
                        ev.values.push(if free { o.stiffness[p][q] } else { 0.0 });
                    }
                }
            }
        }
        if let Some(c) = contact {
            for (i, s) in c.segments.iter().enumerate() {
                let o = solid.contact_segment(c, i, u, depth);
                let d: [usize; 4] = dofs_of(s);
                ev.energy += o.energy;
                ev.damping_energy += o.damping;
                ev.load += o.load;
                ev.load_stiffness += o.load_stiffness;
                for (p, &dp) in d.iter().enumerate() {
                    ev.gradient[dp] += o.force[p];
                    if !solid.fixed[dp] {
                        ev.load_gradient[dp] += o.load_gradient[p];
                    }
                    if tangent {
                        for (q, &dq) in d.iter().enumerate() {
                            let free = !solid.fixed[dp] && !solid.fixed[dq];
                            ev.values.push(if free { o.stiffness[p][q] } else { 0.0 });
                        }
                    }
                }
            }
        }
        if tangent {
            ev.values.extend(self.fixed_dofs.iter().map(|_| 1.0));
        }
        ev.force_scale = ev.force_scale.sqrt();
        if !ev.energy.is_finite() || ev.gradient.iter().any(|v| !v.is_finite()) {
            // where: the first element, else the first contact segment (evaluated again: only
            // on this path) that is not finite
            let finite = |energy: f64, force: &[f64]| {
                energy.is_finite() && force.iter().all(|f| f.is_finite())
            };
            let bad_segment = || {
                contact.and_then(|c| {
                    (0..c.segments.len()).find(|&i| {
                        let o = solid.contact_segment(c, i, u, depth);
                        !finite(o.energy, &o.force)
                    })
                })
            };
            let at = match outs.iter().position(|o| !finite(o.energy, &o.force)) {
                Some(e) => format!("element {e}"),
                None => match bad_segment() {
                    Some(i) => format!("contact segment {i}"),
                    None => "no single element or segment (their sum overflowed)".into(),
                },
            };
            return Err(FeError::NonFinite(format!("energy or forces at {at}")));
        }
        self.stats.assemblies += 1;
        self.stats.assembly_s += t0.elapsed().as_secs_f64();
        Ok(ev)
    }

    /// The residual: the gradient with constrained entries zeroed.
    pub fn residual(&self, gradient: &[f64]) -> Vec<f64> {
        let mut r = gradient.to_vec();
        for &d in &self.fixed_dofs {
            r[d] = 0.0;
        }
        r
    }

    /// Factorise K: Cholesky, or LU when K is not positive definite (beyond a limit point of
    /// the depth, K at fixed depth is indefinite). The factorisation is kept for
    /// [`Assembler::back_solve`] until the next one.
    pub fn factor(&mut self, values: &[f64]) -> Result<(), FeError> {
        let t0 = Instant::now();
        let out = match self.system.factor_spd(values) {
            Err(SparseError::NotPositiveDefinite) => {
                self.stats.lu_fallbacks += 1;
                self.system.factor_lu(values)
            }
            other => other,
        };
        self.stats.factorisations += 1;
        self.stats.solve_s += t0.elapsed().as_secs_f64();
        Ok(out?)
    }

    /// Factorise K + σ·diag|K| by Cholesky (Levenberg–Marquardt's scaled shift, so the graded
    /// mesh's small and large elements are shifted alike): `Ok(false)` where it is not positive
    /// definite. The factorisation is kept for [`Assembler::back_solve`].
    pub fn factor_shifted(&mut self, values: &[f64], shift: f64) -> Result<bool, FeError> {
        let t0 = Instant::now();
        let mut kdd = vec![0.0; self.system.dim()];
        for &(k, d) in &self.diagonal {
            kdd[d] += values[k];
        }
        let mut shifted = values.to_vec();
        for &(k, d) in &self.diagonal {
            // the whole σ|K_dd| on the first entry of each dof's diagonal
            shifted[k] += shift * std::mem::take(&mut kdd[d]).abs();
        }
        let out = self.system.factor_spd(&shifted);
        self.stats.factorisations += 1;
        self.stats.solve_s += t0.elapsed().as_secs_f64();
        match out {
            Ok(()) => Ok(true),
            Err(SparseError::NotPositiveDefinite) => Ok(false),
            Err(e) => Err(e.into()),
        }
    }

    /// True if the factorisation held is a Cholesky: the stiffness it factorised is positive
    /// definite.
    pub fn holds_cholesky(&self) -> bool {
        self.system.is_cholesky()
    }

    /// The number of negative eigenvalues of the stiffness `values` (None where the LDLᵀ
    /// factorisation meets a zero pivot); drops the factorisation held.
    pub fn negative_eigenvalues(&mut self, values: &[f64]) -> Result<Option<usize>, FeError> {
        let t0 = Instant::now();
        let out = match self.system.negative_eigenvalues(values) {
            Ok(n) => Ok(Some(n)),
            Err(SparseError::Singular) => Ok(None),
            Err(e) => Err(e),
        };
        self.stats.inertias += 1;
        self.stats.solve_s += t0.elapsed().as_secs_f64();
        Ok(out?)
    }

    /// Solve K d = rhs with the last factorisation of [`Assembler::factor`].
    pub fn back_solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, FeError> {
        let t0 = Instant::now();
        let out = self.system.solve(rhs);
        self.stats.solves += 1;
        self.stats.solve_s += t0.elapsed().as_secs_f64();
        Ok(out?)
    }
}

/// The dofs (u_r, u_z per node) of `N` nodes; `M` = 2N.
fn dofs_of<const N: usize, const M: usize>(nodes: &[usize; N]) -> [usize; M] {
    let mut d = [0; M];
    for (a, &n) in nodes.iter().enumerate() {
        d[2 * a] = 2 * n;
        d[2 * a + 1] = 2 * n + 1;
    }
    d
}
