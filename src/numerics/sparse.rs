//! Sparse linear solves through faer, with the symbolic analysis reused across Newton iterations.
//!
//! An engine describes its matrix once by the (row, col) positions of its entries — duplicates
//! allowed, they are summed — and then solves repeatedly with new values in the same order.
//! Cholesky (`Side::Lower`, so only entries with row ≥ col are read) for symmetric positive
//! definite systems; LU for indefinite ones (bordered arc-length systems), since faer's sparse
//! LDLᵀ is unreliable on saddle points (see `CRATES.md`). This module is the only one that
//! calls faer's sparse API.

use faer::prelude::Solve;
use faer::sparse::linalg::solvers::{Llt, Lu, SymbolicLlt, SymbolicLu};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Mat, Side};

/// Why a sparse solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SparseError {
    /// the pattern could not be built (an index out of range)
    #[error("sparse pattern invalid: {0}")]
    Pattern(String),
    /// values or right-hand side do not match the pattern
    #[error("sparse system: expected {expected} values, got {got}")]
    Length {
        /// what the pattern needs
        expected: usize,
        /// what was given
        got: usize,
    },
    /// a value or the right-hand side is NaN or infinite
    #[error("sparse system: non-finite entry in the matrix or right-hand side")]
    NonFinite,
    /// Cholesky met a non-positive pivot: the matrix is not positive definite
    #[error("sparse Cholesky: matrix not positive definite")]
    NotPositiveDefinite,
    /// LU met a zero pivot
    #[error("sparse LU: matrix singular")]
    Singular,
}

/// A fixed sparsity pattern with its cached symbolic factorisations.
pub struct SparseSystem {
    n: usize,
    entries: usize,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    llt: Option<SymbolicLlt<usize>>,
    lu: Option<SymbolicLu<usize>>,
}

impl SparseSystem {
    /// Pattern of an `n × n` matrix from the positions of its entries, in the order the values
    /// will later be given.
    pub fn new(n: usize, positions: &[(usize, usize)]) -> Result<Self, SparseError> {
        let pairs: Vec<Pair<usize, usize>> = positions
            .iter()
            .map(|&(row, col)| Pair { row, col })
            .collect();
        if let Some(p) = positions.iter().find(|&&(r, c)| r >= n || c >= n) {
            return Err(SparseError::Pattern(format!(
                "entry ({}, {}) outside a {n}×{n} matrix",
                p.0, p.1
            )));
        }
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| SparseError::Pattern(format!("{e:?}")))?;
        Ok(SparseSystem {
            n,
            entries: positions.len(),
            symbolic,
            argsort,
            llt: None,
            lu: None,
        })
    }

    /// Number of unknowns.
    pub fn dim(&self) -> usize {
        self.n
    }

    fn matrix(&self, values: &[f64]) -> Result<SparseColMat<usize, f64>, SparseError> {
        if values.len() != self.entries {
            return Err(SparseError::Length {
                expected: self.entries,
                got: values.len(),
            });
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(SparseError::NonFinite);
        }
        SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, values)
            .map_err(|e| SparseError::Pattern(format!("{e:?}")))
    }

    /// Factorise a symmetric positive-definite matrix by Cholesky (lower triangle read).
    pub fn factor_spd(&mut self, values: &[f64]) -> Result<Factor, SparseError> {
        let a = self.matrix(values)?;
        if self.llt.is_none() {
            let sym = SymbolicLlt::try_new(a.symbolic(), Side::Lower)
                .map_err(|e| SparseError::Pattern(format!("{e:?}")))?;
            self.llt = Some(sym);
        }
        let sym = self.llt.clone().expect("symbolic Cholesky just built");
        let llt = Llt::try_new_with_symbolic(sym, a.as_ref(), Side::Lower)
            .map_err(|_| SparseError::NotPositiveDefinite)?;
        Ok(Factor {
            n: self.n,
            kind: Kind::Llt(llt),
        })
    }

    /// Factorise a general (possibly indefinite) matrix by LU with partial pivoting.
    pub fn factor_lu(&mut self, values: &[f64]) -> Result<Factor, SparseError> {
        let a = self.matrix(values)?;
        if self.lu.is_none() {
            let sym = SymbolicLu::try_new(a.symbolic())
                .map_err(|e| SparseError::Pattern(format!("{e:?}")))?;
            self.lu = Some(sym);
        }
        let sym = self.lu.clone().expect("symbolic LU just built");
        let lu = Lu::try_new_with_symbolic(sym, a.as_ref()).map_err(|_| SparseError::Singular)?;
        Ok(Factor {
            n: self.n,
            kind: Kind::Lu(Box::new(lu)),
        })
    }

    /// Solve a symmetric positive-definite system by Cholesky (lower triangle read).
    pub fn solve_spd(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, SparseError> {
        check_rhs(self.n, rhs)?;
        self.factor_spd(values)?.solve(rhs)
    }

    /// Solve a general (possibly indefinite) system by LU with partial pivoting.
    pub fn solve_lu(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, SparseError> {
        check_rhs(self.n, rhs)?;
        self.factor_lu(values)?.solve(rhs)
    }
}

enum Kind {
    Llt(Llt<usize, f64>),
    Lu(Box<Lu<usize, f64>>),
}

/// A numeric factorisation, kept to solve several right-hand sides with one matrix (the two
/// solves of a bordered system).
pub struct Factor {
    n: usize,
    kind: Kind,
}

impl Factor {
    /// True if this is an LU factorisation (the matrix was not positive definite).
    pub fn is_lu(&self) -> bool {
        matches!(self.kind, Kind::Lu(_))
    }

    /// Solve A x = rhs.
    pub fn solve(&self, rhs: &[f64]) -> Result<Vec<f64>, SparseError> {
        check_rhs(self.n, rhs)?;
        let b = column(rhs);
        finite_solution(match &self.kind {
            Kind::Llt(f) => f.solve(b),
            Kind::Lu(f) => f.solve(b),
        })
    }
}

fn check_rhs(n: usize, rhs: &[f64]) -> Result<(), SparseError> {
    if rhs.len() != n {
        return Err(SparseError::Length {
            expected: n,
            got: rhs.len(),
        });
    }
    if !rhs.iter().all(|v| v.is_finite()) {
        return Err(SparseError::NonFinite);
    }
    Ok(())
}

fn column(v: &[f64]) -> Mat<f64> {
    Mat::from_fn(v.len(), 1, |i, _| v[i])
}

fn finite_solution(x: Mat<f64>) -> Result<Vec<f64>, SparseError> {
    let out: Vec<f64> = (0..x.nrows()).map(|i| x[(i, 0)]).collect();
    if out.iter().all(|v| v.is_finite()) {
        Ok(out)
    } else {
        Err(SparseError::Singular)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1D Laplacian with Dirichlet ends, entries given with duplicates (element by element).
    fn laplacian(n: usize) -> (Vec<(usize, usize)>, Vec<f64>) {
        let mut pos = Vec::new();
        let mut val = Vec::new();
        for e in 0..=n {
            // element between node e-1 and e (nodes outside 0..n are fixed)
            let nodes = [e.checked_sub(1), (e < n).then_some(e)];
            for a in nodes.iter().flatten() {
                for b in nodes.iter().flatten() {
                    pos.push((*a, *b));
                    val.push(if a == b { 1.0 } else { -1.0 });
                }
            }
        }
        (pos, val)
    }

    fn residual(pos: &[(usize, usize)], val: &[f64], x: &[f64], b: &[f64]) -> f64 {
        let mut r = b.to_vec();
        for (&(i, j), v) in pos.iter().zip(val) {
            r[i] -= v * x[j];
        }
        r.iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    #[test]
    fn cholesky_and_lu_solve_a_laplacian_with_summed_duplicates() {
        let n = 200;
        let (pos, val) = laplacian(n);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut sys = SparseSystem::new(n, &pos).unwrap();
        let x = sys.solve_spd(&val, &b).unwrap();
        assert!(residual(&pos, &val, &x, &b) < 1e-9);
        // reuse of the symbolic analysis with scaled values
        let val2: Vec<f64> = val.iter().map(|v| 2.0 * v).collect();
        let x2 = sys.solve_spd(&val2, &b).unwrap();
        assert!(residual(&pos, &val2, &x2, &b) < 1e-9);
        let y = sys.solve_lu(&val, &b).unwrap();
        assert!(residual(&pos, &val, &y, &b) < 1e-9);
        // one numeric factorisation, several right-hand sides
        let f = sys.factor_spd(&val).unwrap();
        let c: Vec<f64> = (0..n).map(|i| (i as f64 * 0.11).cos()).collect();
        for rhs in [&b, &c] {
            assert!(residual(&pos, &val, &f.solve(rhs).unwrap(), rhs) < 1e-9);
        }
        assert!(!f.is_lu() && sys.factor_lu(&val).unwrap().is_lu());
    }

    #[test]
    fn indefinite_saddle_point_needs_lu() {
        // [[2, 1], [1, 0]] is indefinite.
        let pos = vec![(0, 0), (0, 1), (1, 0), (1, 1)];
        let val = vec![2.0, 1.0, 1.0, 0.0];
        let mut sys = SparseSystem::new(2, &pos).unwrap();
        assert_eq!(
            sys.solve_spd(&val, &[1.0, 1.0]),
            Err(SparseError::NotPositiveDefinite)
        );
        let x = sys.solve_lu(&val, &[1.0, 1.0]).unwrap();
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        assert!(matches!(
            SparseSystem::new(2, &[(2, 0)]),
            Err(SparseError::Pattern(_))
        ));
        let mut sys = SparseSystem::new(1, &[(0, 0)]).unwrap();
        assert_eq!(
            sys.solve_spd(&[f64::NAN], &[1.0]),
            Err(SparseError::NonFinite)
        );
        assert!(matches!(
            sys.solve_spd(&[1.0, 2.0], &[1.0]),
            Err(SparseError::Length { .. })
        ));
    }
}
