//! Solvers shared by the engines.
//!
//! - [`sparse`]: sparse symmetric positive-definite (Cholesky) and general (LU) solves through
//!   faer, with the symbolic analysis computed once per sparsity pattern and reused.

pub mod sparse;
