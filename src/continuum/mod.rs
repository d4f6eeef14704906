//! Axisymmetric finite-deformation FE indentation (seed chapter 4): a rigid indenter pressed
//! into a block of linear, hyperfoam or viscoelastic material, under displacement control.
//!
//! The total potential of an increment is Π(u) = Σₑ wₑ ψ(Cₑ) + ∫ φ(g) dA, minimised by Newton;
//! every force is its exact gradient, every tangent its exact Hessian (checked by finite
//! differences in each module's tests).
//!
//! - [`mesh`]: graded quadtree triangulation of the block (or a Gmsh file), with a report;
//!   adaptive meshes fine only at the contact edge, the state carried across by [`transfer`].
//! - [`element`]: the axisymmetric CST, total Lagrangian (F with the hoop stretch r/R) or small
//!   strain; the 2πr weight lives in [`element::volume_weight`].
//! - [`material`]: the [`material::Material`] trait; linear, hyperfoam, viscoelastic (Prony).
//! - [`indenter`]: sphere and blunt Berkovich — gap, normal and curvature.
//! - [`contact`]: Π_c = ∫φ(g) dA over the current surface with any [`contact::SurfaceLaw`]
//!   (a repulsive penalty here; Lennard-Jones plugs into the same code).
//! - [`assembly`]: parallel element kernels, deterministic scatter, sparse solves via faer.
//! - [`adhesion`]: the LJ laws of [`crate::laws`] as the surface law, mesh sizes for the
//!   process zone; [`damping`]: viscous contact damping (seed eq. 4.4).
//! - [`machine`]: displacement control, a machine spring K or load control (the indenter
//!   depth as an extra unknown, bordered solves).
//! - [`events`]: jump-in, jump-out and pull-off from the rows; the contact radius definition.
//! - [`newton`]: Newton with line search (Params/Info/Error).
//! - [`arclength`]: Riks arc-length continuation through the folds of the S-curve.
//! - [`indent`]: the problem — [`IndentParams`], the sizes they resolve to, [`IndentResult`].
//! - `march`: the driver, [`run_indent`] — mesh, then the march along the schedule
//!   (increments, cutbacks, remeshing) or the arc-length trace.
//! - [`output`]: CSV, summary, plots and VTU files ([`IndentResult::write`]).

// `!(x > 0.0)` is used on purpose: it also rejects NaN. Index loops mirror the formulas.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

pub mod adhesion;
pub mod arclength;
pub mod assembly;
pub mod bifurcation;
pub mod contact;
pub mod damping;
pub mod element;
pub mod events;
pub mod indent;
pub mod indenter;
pub mod machine;
mod march;
pub mod material;
pub mod mesh;
pub mod newton;
pub mod output;
pub mod snap;
pub mod transfer;

pub use indent::{IndentParams, IndentResult, Progress, Segment};
pub use march::run_indent;

/// Why a continuum run failed.
#[derive(Debug, thiserror::Error)]
pub enum FeError {
    /// the parameters are unusable
    #[error("continuum parameters: {0}")]
    Params(String),
    /// the mesh could not be built or read
    #[error(transparent)]
    Mesh(#[from] mesh::MeshError),
    /// an element failed (inverted, material)
    #[error(transparent)]
    Element(#[from] element::ElementError),
    /// the material parameters are invalid
    #[error(transparent)]
    Material(#[from] material::MaterialError),
    /// the linear solve failed
    #[error(transparent)]
    Sparse(#[from] crate::numerics::sparse::SparseError),
    /// a NaN or infinity appeared
    #[error("non-finite {0}")]
    NonFinite(String),
    /// the run stopped midway; what it finished is kept (its `failure` says why)
    #[error("continuum run stopped: {}", .0.failure.as_deref().unwrap_or("unknown"))]
    Stopped(Box<IndentResult>),
    /// results could not be written
    #[error(transparent)]
    Report(#[from] crate::report::ReportError),
    /// the indenter's dimensions are unusable
    #[error("continuum parameters: {0}")]
    Indenter(#[from] indenter::IndenterError),
    /// the testing machine's springs are unusable
    #[error("continuum parameters: {0}")]
    Machine(#[from] machine::MachineError),
    /// the adhesion law or its damping is unusable
    #[error("continuum parameters: {0}")]
    Adhesion(#[from] adhesion::AdhesionError),
    /// the bordered solve of (u, δ) met a vanishing Schur complement: a limit point of the
    /// load, or no contact under load control
    #[error("bordered solve: the indenter's effective stiffness k − gᵀK⁻¹g = {schur:.3e} nN/nm vanishes (a load limit point, or no contact under load control)")]
    LimitPoint {
        /// the Schur complement k − gᵀK⁻¹g, nN/nm
        schur: f64,
    },
    /// Newton asked for the iterate's point before evaluating it (a bug)
    #[error("Newton: no point evaluated")]
    NoPoint,
    /// the descent found no positive-definite shift of the stiffness
    #[error("descent: K + σ·diag|K| is not positive definite up to σ = {shift:.1e}")]
    NotDescending {
        /// the largest shift tried
        shift: f64,
    },
}
