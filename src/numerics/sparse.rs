//! Sparse linear solves through faer, with the symbolic analysis and the numeric storage reused
//! across Newton iterations.
//!
//! An engine describes its matrix once by the (row, col) positions of its entries — duplicates
//! allowed, they are summed — and then factorises repeatedly with new values in the same order.
//! Cholesky (`Side::Lower`, so only entries with row ≥ col are read) for symmetric positive
//! definite systems; LU for indefinite ones (bordered arc-length systems), since faer's sparse
//! LDLᵀ is unreliable on saddle points (see `CRATES.md`). The system keeps its last numeric
//! factorisation, so one factorisation serves several right-hand sides (the two solves of a
//! bordered system), and it keeps the storage of the factor, of the assembled values and of
//! faer's workspace from one factorisation to the next: nothing of the size of the factor is
//! allocated (and page-faulted in) again. Each factorisation runs on one thread (`Par::Seq`):
//! on the shared 2-core machine faer's rayon factorisation cost 1.6× the CPU of the sequential
//! one for the same result (docs/benchmarks.md). Where a caller has two matrices to try in turn
//! (a shifted Newton step: H + μI, and the next shift if that is indefinite), they are
//! factorised on two threads at once ([`SparseSystem::factor_spd_first_of`]), and a new
//! pattern's symbolic analysis can be started ([`SparseSystem::analyse`]) while the caller
//! assembles the values. This module is the only one that calls faer's sparse API.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use std::sync::atomic::{AtomicBool, Ordering};

/// The parallelism of the factorisations and solves (see the module doc).
const PAR: Par = Par::Seq;

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
    /// a solve was asked for with no successful factorisation to use
    #[error("sparse solve: no factorisation")]
    NoFactor,
    /// faer could not allocate its workspace
    #[error("sparse factorisation: {0}")]
    Memory(String),
}

/// Which numeric factorisation the system holds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Held {
    None,
    Llt,
    Lu,
}

/// A compressed-column pattern (rows sorted, duplicates merged) built from a list of entry
/// positions, with the index in the compressed values of each listed entry.
#[derive(Debug, Clone)]
pub struct Pattern {
    symbolic: SymbolicSparseColMat<usize>,
    slot: Vec<usize>,
}

impl Pattern {
    /// The pattern of an `n × n` matrix with entries at `positions`. A counting sort by column,
    /// then a sort of each column's few rows: linear in the entries.
    pub fn new(n: usize, positions: &[(usize, usize)]) -> Result<Self, SparseError> {
        check_positions(n, positions)?;
        // entries bucketed by column
        let mut start = vec![0usize; n + 1];
        for &(_, c) in positions {
            start[c + 1] += 1;
        }
        for c in 0..n {
            start[c + 1] += start[c];
        }
        let mut next = start.clone();
        let mut order = vec![0usize; positions.len()];
        for (k, &(_, c)) in positions.iter().enumerate() {
            order[next[c]] = k;
            next[c] += 1;
        }
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(positions.len());
        let mut slot = vec![0usize; positions.len()];
        for c in 0..n {
            let bucket = &mut order[start[c]..start[c + 1]];
            bucket.sort_unstable_by_key(|&k| positions[k].0);
            let mut last = None;
            for &k in bucket.iter() {
                let row = positions[k].0;
                if last != Some(row) {
                    row_idx.push(row);
                    last = Some(row);
                }
                slot[k] = row_idx.len() - 1;
            }
            col_ptr[c + 1] = row_idx.len();
        }
        Ok(Pattern {
            symbolic: SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
            slot,
        })
    }

    /// The pattern of this pattern's entries followed by `more`: only `more` is sorted, then
    /// merged column by column with the compressed pattern already built (linear in the
    /// entries). The same pattern and slots as [`Pattern::new`] of the whole list.
    pub fn extended(&self, more: &[(usize, usize)]) -> Result<Self, SparseError> {
        let n = self.dim();
        let tail = Pattern::new(n, more)?;
        let (a, b) = (&self.symbolic, &tail.symbolic);
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(a.row_idx().len() + b.row_idx().len());
        // index in the merged pattern of each compressed entry of `self` and of `tail`
        let mut to_a = vec![0usize; a.row_idx().len()];
        let mut to_b = vec![0usize; b.row_idx().len()];
        for c in 0..n {
            let (mut i, end_i) = (a.col_ptr()[c], a.col_ptr()[c + 1]);
            let (mut j, end_j) = (b.col_ptr()[c], b.col_ptr()[c + 1]);
            while i < end_i || j < end_j {
                let ra = if i < end_i {
                    a.row_idx()[i]
                } else {
                    usize::MAX
                };
                let rb = if j < end_j {
                    b.row_idx()[j]
                } else {
                    usize::MAX
                };
                let row = ra.min(rb);
                if ra == row {
                    to_a[i] = row_idx.len();
                    i += 1;
                }
                if rb == row {
                    to_b[j] = row_idx.len();
                    j += 1;
                }
                row_idx.push(row);
            }
            col_ptr[c + 1] = row_idx.len();
        }
        let slot = (self.slot.iter().map(|&s| to_a[s]))
            .chain(tail.slot.iter().map(|&s| to_b[s]))
            .collect();
        Ok(Pattern {
            symbolic: SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
            slot,
        })
    }

    /// Number of rows (and columns).
    pub fn dim(&self) -> usize {
        self.symbolic.ncols()
    }

    /// Number of compressed entries.
    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// For each listed entry, its index in the compressed values.
    pub fn slots(&self) -> &[usize] {
        &self.slot
    }

    /// Whether the two compress to the same pattern (whatever their lists of entries).
    fn same_compressed(&self, other: &Pattern) -> bool {
        self.symbolic.col_ptr() == other.symbolic.col_ptr()
            && self.symbolic.row_idx() == other.symbolic.row_idx()
    }
}

/// A fixed sparsity pattern with its cached symbolic factorisations, the storage of its numeric
/// factorisations and the last of them.
pub struct SparseSystem {
    n: usize,
    /// the matrix's compressed-column pattern, and the slot of each given entry
    pattern: Pattern,
    /// the compressed values of the last matrix
    values: Vec<f64>,
    llt: Option<SymbolicCholesky<usize>>,
    llt_values: Vec<f64>,
    /// a second Cholesky factor's storage and workspace, for [`SparseSystem::factor_spd_first_of`]
    spare: CholeskyStore,
    lu: Option<SymbolicLu<usize>>,
    lu_numeric: NumericLu<usize, f64>,
    held: Held,
    workspace: MemBuffer,
}

impl SparseSystem {
    /// Pattern of an `n × n` matrix from the positions of its entries, in the order the values
    /// will later be given.
    pub fn new(n: usize, positions: &[(usize, usize)]) -> Result<Self, SparseError> {
        Ok(SparseSystem::with_pattern(Pattern::new(n, positions)?))
    }

    /// The system of a pattern built beforehand.
    pub fn with_pattern(pattern: Pattern) -> Self {
        SparseSystem {
            n: pattern.dim(),
            values: vec![0.0; pattern.nnz()],
            pattern,
            llt: None,
            llt_values: Vec::new(),
            spare: CholeskyStore::default(),
            lu: None,
            lu_numeric: NumericLu::new(),
            held: Held::None,
            workspace: MemBuffer::new(StackReq::empty()),
        }
    }

    /// Give the entries in new positions, as a pattern of the same dimension. When it
    /// compresses to the same pattern as before (entries only reordered, duplicated or merged
    /// differently), the symbolic factorisations are kept; otherwise they are rebuilt at the
    /// next factorisation. The workspace is kept either way.
    pub fn set_pattern(&mut self, pattern: Pattern) -> Result<(), SparseError> {
        if pattern.dim() != self.n {
            return Err(SparseError::Length {
                expected: self.n,
                got: pattern.dim(),
            });
        }
        self.held = Held::None;
        if !pattern.same_compressed(&self.pattern) {
            zeroed(&mut self.values, pattern.nnz());
            self.llt = None;
            self.lu = None;
        }
        self.pattern = pattern;
        Ok(())
    }

    /// The pattern the values are given for.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// Number of unknowns.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Sum the given values, one per listed entry, into the compressed matrix.
    fn load(&mut self, values: &[f64]) -> Result<(), SparseError> {
        self.held = Held::None;
        let slot = &self.pattern.slot;
        if values.len() != slot.len() {
            return Err(SparseError::Length {
                expected: slot.len(),
                got: values.len(),
            });
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(SparseError::NonFinite);
        }
        self.values.iter_mut().for_each(|v| *v = 0.0);
        for (&s, &v) in slot.iter().zip(values) {
            self.values[s] += v;
        }
        Ok(())
    }

    /// Take the compressed values (in the pattern's order, duplicates already summed).
    fn load_compressed(&mut self, values: &[f64]) -> Result<(), SparseError> {
        self.held = Held::None;
        if values.len() != self.values.len() {
            return Err(SparseError::Length {
                expected: self.values.len(),
                got: values.len(),
            });
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(SparseError::NonFinite);
        }
        self.values.copy_from_slice(values);
        Ok(())
    }

    /// Grow (never shrink) the workspace to hold `req`.
    fn reserve(&mut self, req: StackReq) -> Result<(), SparseError> {
        reserve(&mut self.workspace, req)
    }

    /// Factorise a symmetric positive-definite matrix by Cholesky (lower triangle read); the
    /// factorisation is kept for [`SparseSystem::solve`].
    pub fn factor_spd(&mut self, values: &[f64]) -> Result<(), SparseError> {
        self.load(values)?;
        self.factor_llt()
    }

    /// Cholesky of the loaded values.
    fn factor_llt(&mut self) -> Result<(), SparseError> {
        self.symbolic_cholesky()?;
        let sym = self.llt.as_ref().expect("symbolic Cholesky just built");
        let a = SparseColMatRef::new(self.pattern.symbolic.as_ref(), &self.values);
        factor_llt_into(sym, a, &mut self.llt_values, &mut self.workspace)?;
        self.held = Held::Llt;
        Ok(())
    }

    /// Cholesky of the first of two matrices (compressed values, as for
    /// [`SparseSystem::solve_spd_compressed`]) that is positive definite, held for
    /// [`SparseSystem::solve`]: `Ok(false)` if `first` factored, `Ok(true)` if `second` did.
    /// `second` is factorised on another rayon worker while `first` is, where one is free to
    /// take it, and otherwise only if `first` failed (never when `first` has already
    /// factored), so a caller that would try `second` after `first` fails gets the same factor
    /// as trying them in turn, in the wall time of one factorisation where a core is idle.
    /// `factorizations` counts those run (1 or 2).
    pub fn factor_spd_first_of(
        &mut self,
        first: &[f64],
        second: &[f64],
        factorizations: &mut usize,
    ) -> Result<bool, SparseError> {
        self.held = Held::None;
        for v in [first, second] {
            if v.len() != self.values.len() {
                return Err(SparseError::Length {
                    expected: self.values.len(),
                    got: v.len(),
                });
            }
        }
        self.symbolic_cholesky()?;
        let sym = self.llt.as_ref().expect("symbolic Cholesky just built");
        let pattern = self.pattern.symbolic.as_ref();
        let first_done = AtomicBool::new(false);
        let (main, spare) = (&mut self.llt_values, &mut self.spare);
        let (a, b) = rayon::join(
            || {
                let r = check_finite(first).and_then(|()| {
                    factor_llt_into(
                        sym,
                        SparseColMatRef::new(pattern, first),
                        main,
                        &mut self.workspace,
                    )
                });
                first_done.store(r.is_ok(), Ordering::Release);
                r
            },
            || {
                if first_done.load(Ordering::Acquire) {
                    return None;
                }
                Some(check_finite(second).and_then(|()| {
                    factor_llt_into(
                        sym,
                        SparseColMatRef::new(pattern, second),
                        &mut spare.values,
                        &mut spare.workspace,
                    )
                }))
            },
        );
        *factorizations += 1 + usize::from(b.is_some());
        let second = match (a, b) {
            (Ok(()), _) => false,
            (Err(SparseError::NotPositiveDefinite), Some(b)) => {
                b?;
                std::mem::swap(&mut self.llt_values, &mut self.spare.values);
                true
            }
            (Err(e), _) => return Err(e),
        };
        self.held = Held::Llt;
        Ok(second)
    }

    /// Whether the pattern's symbolic Cholesky analysis is built.
    pub fn analysed(&self) -> bool {
        self.llt.is_some()
    }

    /// Build the pattern's symbolic Cholesky analysis now, rather than at the next
    /// factorisation (so that a caller can overlap it with other work).
    pub fn analyse(&mut self) -> Result<(), SparseError> {
        self.symbolic_cholesky()
    }

    /// The symbolic Cholesky (and LDLᵀ) analysis of the pattern, built once.
    fn symbolic_cholesky(&mut self) -> Result<(), SparseError> {
        if self.llt.is_none() {
            let sym = factorize_symbolic_cholesky(
                self.pattern.symbolic.as_ref(),
                Side::Lower,
                Default::default(),
                Default::default(),
            )
            .map_err(|e| SparseError::Pattern(format!("{e:?}")))?;
            zeroed(&mut self.llt_values, sym.len_val());
            zeroed(&mut self.spare.values, sym.len_val());
            self.llt = Some(sym);
        }
        Ok(())
    }

    /// Factorise a general (possibly indefinite) matrix by LU with partial pivoting; the
    /// factorisation is kept for [`SparseSystem::solve`].
    pub fn factor_lu(&mut self, values: &[f64]) -> Result<(), SparseError> {
        self.load(values)?;
        if self.lu.is_none() {
            let sym = factorize_symbolic_lu(self.pattern.symbolic.as_ref(), Default::default())
                .map_err(|e| SparseError::Pattern(format!("{e:?}")))?;
            self.lu = Some(sym);
        }
        let sym = self.lu.as_ref().expect("symbolic LU just built");
        let req = sym
            .factorize_numeric_lu_scratch::<f64>(PAR, Default::default())
            .or(sym.solve_in_place_scratch::<f64>(1, PAR));
        self.reserve(req)?;
        let sym = self.lu.as_ref().expect("symbolic LU just built");
        sym.factorize_numeric_lu(
            &mut self.lu_numeric,
            SparseColMatRef::new(self.pattern.symbolic.as_ref(), &self.values),
            PAR,
            MemStack::new(&mut self.workspace),
            Default::default(),
        )
        .map_err(|_| SparseError::Singular)?;
        self.held = Held::Lu;
        Ok(())
    }

    /// The number of negative eigenvalues of a symmetric matrix (lower triangle read): by
    /// Sylvester's law of inertia, the number of negative pivots of its LDLᵀ factorisation in
    /// the fill-reducing order, without pivoting. That needs no zero pivot on the way: a
    /// matrix with a positive diagonal and a few negative eigenvalues (a stiffness past a
    /// limit or bifurcation point) passes, a saddle point with a zero block does not (then
    /// [`SparseError::Singular`]). Drops the factorisation held.
    pub fn negative_eigenvalues(&mut self, values: &[f64]) -> Result<usize, SparseError> {
        self.load(values)?;
        self.symbolic_cholesky()?;
        let sym = self.llt.as_ref().expect("symbolic Cholesky just built");
        let req = sym.factorize_numeric_ldlt_scratch::<f64>(PAR, Default::default());
        self.reserve(req)?;
        let sym = self.llt.as_ref().expect("symbolic Cholesky just built");
        sym.factorize_numeric_ldlt(
            &mut self.llt_values,
            SparseColMatRef::new(self.pattern.symbolic.as_ref(), &self.values),
            Side::Lower,
            LdltRegularization::default(),
            PAR,
            MemStack::new(&mut self.workspace),
            Default::default(),
        )
        .map_err(|_| SparseError::Singular)?;
        // D sits where L's unit diagonal would: first in each column (simplicial), on the
        // diagonal of each supernode's column-major diagonal block (supernodal)
        let d = &self.llt_values;
        let negative = match sym.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => s.col_ptr()[..self.n]
                .iter()
                .filter(|&&k| d[k] < 0.0)
                .count(),
            SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
                .map(|k| {
                    let width = s.supernode_end()[k] - s.supernode_begin()[k];
                    let below = s.col_ptr_for_row_idx()[k + 1] - s.col_ptr_for_row_idx()[k];
                    let rows = width + below;
                    let block = &d[s.col_ptr_for_val()[k]..s.col_ptr_for_val()[k + 1]];
                    (0..width).filter(|&j| block[j * rows + j] < 0.0).count()
                })
                .sum(),
        };
        Ok(negative)
    }

    /// True if the factorisation held is an LU (the matrix was not positive definite).
    pub fn is_lu(&self) -> bool {
        self.held == Held::Lu
    }

    /// True if the factorisation held is a Cholesky (the matrix was positive definite).
    pub fn is_cholesky(&self) -> bool {
        self.held == Held::Llt
    }

    /// Solve A x = rhs with the factorisation held (the last successful `factor_*` since the
    /// last failed one).
    pub fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>, SparseError> {
        check_rhs(self.n, rhs)?;
        let mut x = rhs.to_vec();
        let n = self.n;
        let b = MatMut::from_column_major_slice_mut(&mut x, n, 1);
        match self.held {
            Held::None => return Err(SparseError::NoFactor),
            Held::Llt => {
                let sym = self.llt.as_ref().expect("a Cholesky factorisation is held");
                LltRef::new(sym, &self.llt_values).solve_in_place_with_conj(
                    Conj::No,
                    b,
                    PAR,
                    MemStack::new(&mut self.workspace),
                );
            }
            Held::Lu => {
                let sym = self.lu.as_ref().expect("an LU factorisation is held");
                LuRef::new_unchecked(sym, &self.lu_numeric).solve_in_place_with_conj(
                    Conj::No,
                    b,
                    PAR,
                    MemStack::new(&mut self.workspace),
                );
            }
        }
        if x.iter().all(|v| v.is_finite()) {
            Ok(x)
        } else {
            Err(SparseError::Singular)
        }
    }

    /// Solve a symmetric positive-definite system by Cholesky (lower triangle read).
    pub fn solve_spd(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, SparseError> {
        check_rhs(self.n, rhs)?;
        self.factor_spd(values)?;
        self.solve(rhs)
    }

    /// [`SparseSystem::solve_spd`] with the values already compressed (the pattern's order, one
    /// per compressed entry, duplicates summed).
    pub fn solve_spd_compressed(
        &mut self,
        values: &[f64],
        rhs: &[f64],
    ) -> Result<Vec<f64>, SparseError> {
        check_rhs(self.n, rhs)?;
        self.load_compressed(values)?;
        self.factor_llt()?;
        self.solve(rhs)
    }

    /// Solve a general (possibly indefinite) system by LU with partial pivoting.
    pub fn solve_lu(&mut self, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, SparseError> {
        check_rhs(self.n, rhs)?;
        self.factor_lu(values)?;
        self.solve(rhs)
    }
}

/// The storage of a second numeric Cholesky factor: its values and faer's workspace.
struct CholeskyStore {
    values: Vec<f64>,
    workspace: MemBuffer,
}

impl Default for CholeskyStore {
    fn default() -> Self {
        CholeskyStore {
            values: Vec::new(),
            workspace: MemBuffer::new(StackReq::empty()),
        }
    }
}

/// Cholesky of `a` (lower triangle read) with the symbolic analysis `sym`, into `l_values`,
/// growing `workspace` as needed.
fn factor_llt_into(
    sym: &SymbolicCholesky<usize>,
    a: SparseColMatRef<'_, usize, f64>,
    l_values: &mut [f64],
    workspace: &mut MemBuffer,
) -> Result<(), SparseError> {
    let req = sym
        .factorize_numeric_llt_scratch::<f64>(PAR, Default::default())
        .or(sym.solve_in_place_scratch::<f64>(1, PAR));
    reserve(workspace, req)?;
    sym.factorize_numeric_llt(
        l_values,
        a,
        Side::Lower,
        LltRegularization::default(),
        PAR,
        MemStack::new(workspace),
        Default::default(),
    )
    .map_err(|_| SparseError::NotPositiveDefinite)?;
    Ok(())
}

/// Grow (never shrink) `workspace` to hold `req`.
fn reserve(workspace: &mut MemBuffer, req: StackReq) -> Result<(), SparseError> {
    if !MemStack::new(workspace).can_hold(req) {
        *workspace = MemBuffer::try_new(req).map_err(|e| SparseError::Memory(format!("{e:?}")))?;
    }
    Ok(())
}

/// `v` as `len` zeros, in the storage it has (a factor's values are tens of megabytes, and a
/// new allocation is faulted in page by page).
fn zeroed(v: &mut Vec<f64>, len: usize) {
    v.clear();
    v.resize(len, 0.0);
}

/// `NonFinite` unless every value is finite.
fn check_finite(values: &[f64]) -> Result<(), SparseError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SparseError::NonFinite)
    }
}

fn check_positions(n: usize, positions: &[(usize, usize)]) -> Result<(), SparseError> {
    match positions.iter().find(|&&(r, c)| r >= n || c >= n) {
        Some(p) => Err(SparseError::Pattern(format!(
            "entry ({}, {}) outside a {n}×{n} matrix",
            p.0, p.1
        ))),
        None => Ok(()),
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
        sys.factor_spd(&val).unwrap();
        assert!(!sys.is_lu());
        let c: Vec<f64> = (0..n).map(|i| (i as f64 * 0.11).cos()).collect();
        for rhs in [&b, &c] {
            assert!(residual(&pos, &val, &sys.solve(rhs).unwrap(), rhs) < 1e-9);
        }
        sys.factor_lu(&val2).unwrap();
        assert!(sys.is_lu());
        assert!(residual(&pos, &val2, &sys.solve(&c).unwrap(), &c) < 1e-9);
        // a failed factorisation leaves nothing to solve with
        let bad: Vec<f64> = val.iter().map(|v| -v).collect();
        assert_eq!(sys.factor_spd(&bad), Err(SparseError::NotPositiveDefinite));
        assert_eq!(sys.solve(&b), Err(SparseError::NoFactor));
    }

    #[test]
    fn new_positions_for_the_same_or_another_pattern_solve_correctly() {
        let n = 50;
        let (pos, val) = laplacian(n);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut sys = SparseSystem::new(n, &pos).unwrap();
        sys.solve_spd(&val, &b).unwrap();
        // the same entries listed backwards: same compressed pattern, new slots
        let (rpos, rval): (Vec<_>, Vec<_>) = pos.iter().zip(&val).rev().unzip();
        sys.set_pattern(Pattern::new(n, &rpos).unwrap()).unwrap();
        let x = sys.solve_spd(&rval, &b).unwrap();
        assert!(residual(&rpos, &rval, &x, &b) < 1e-9);
        // one more off-diagonal pair: another pattern
        let (mut mpos, mut mval) = (pos.clone(), val.clone());
        mpos.extend([(0, n - 1), (n - 1, 0)]);
        mval.extend([-0.1, -0.1]);
        sys.set_pattern(Pattern::new(n, &mpos).unwrap()).unwrap();
        let y = sys.solve_spd(&mval, &b).unwrap();
        assert!(residual(&mpos, &mval, &y, &b) < 1e-9);
        // values given for the old pattern are refused, not misread
        assert!(matches!(
            sys.solve_spd(&val, &b),
            Err(SparseError::Length { .. })
        ));
        assert!(matches!(
            Pattern::new(n, &[(n, 0)]),
            Err(SparseError::Pattern(_))
        ));
        assert!(matches!(
            sys.set_pattern(Pattern::new(n + 1, &pos).unwrap()),
            Err(SparseError::Length { .. })
        ));
    }

    #[test]
    fn an_extended_pattern_is_the_pattern_of_the_whole_list() {
        let n = 40;
        let (mut pos, _) = laplacian(n);
        // entries the first part lacks (a far coupling) and repeats of ones it has
        pos.extend([(n - 1, 0), (0, n - 1), (3, 3), (n - 1, 0), (7, 6)]);
        for split in [0, 1, pos.len() / 2, pos.len() - 3, pos.len()] {
            let head = Pattern::new(n, &pos[..split]).unwrap();
            let merged = head.extended(&pos[split..]).unwrap();
            let whole = Pattern::new(n, &pos).unwrap();
            assert!(merged.same_compressed(&whole), "split {split}");
            assert_eq!(merged.slots(), whole.slots(), "split {split}");
        }
    }

    #[test]
    fn compressed_values_factor_like_listed_ones() {
        let n = 30;
        let (pos, val) = laplacian(n);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut sys = SparseSystem::new(n, &pos).unwrap();
        let x = sys.solve_spd(&val, &b).unwrap();
        let mut compressed = vec![0.0; sys.pattern().nnz()];
        for (&s, v) in sys.pattern().slots().iter().zip(&val) {
            compressed[s] += v;
        }
        assert_eq!(sys.solve_spd_compressed(&compressed, &b).unwrap(), x);
        assert!(matches!(
            sys.solve_spd_compressed(&val, &b),
            Err(SparseError::Length { .. })
        ));
    }

    #[test]
    fn the_first_of_two_matrices_that_factors_is_held_and_solved_with() {
        let n = 100;
        let (pos, val) = laplacian(n);
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut sys = SparseSystem::new(n, &pos).unwrap();
        // the Laplacian's eigenvalues lie in (0, 4): shifted by −3 it is indefinite
        let compressed = |shift: f64| {
            let mut c = vec![0.0; sys.pattern().nnz()];
            let mut shifted = vec![false; n];
            for (&s, (&(i, j), v)) in sys.pattern().slots().iter().zip(pos.iter().zip(&val)) {
                c[s] += v;
                if i == j && !shifted[i] {
                    c[s] += shift;
                    shifted[i] = true;
                }
            }
            c
        };
        let (spd, indefinite) = (compressed(0.0), compressed(-3.0));
        let alone = sys.solve_spd_compressed(&spd, &b).unwrap();
        // the second factors where the first does not: the same factor as taking it alone
        let mut count = 0;
        assert_eq!(
            sys.factor_spd_first_of(&indefinite, &spd, &mut count),
            Ok(true)
        );
        assert_eq!(count, 2);
        assert_eq!(sys.solve(&b).unwrap(), alone);
        // the first factors: it is held, and on one thread the second is never tried
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let mut count = 0;
        let first = one.install(|| sys.factor_spd_first_of(&spd, &indefinite, &mut count));
        assert_eq!((first, count), (Ok(false), 1));
        assert_eq!(sys.solve(&b).unwrap(), alone);
        // neither factors: nothing is held
        let mut count = 0;
        assert_eq!(
            sys.factor_spd_first_of(&indefinite, &indefinite, &mut count),
            Err(SparseError::NotPositiveDefinite)
        );
        assert_eq!(count, 2);
        assert_eq!(sys.solve(&b), Err(SparseError::NoFactor));
        // a non-finite first matrix is an error, not a reason to take the second
        let mut nan = spd.clone();
        nan[0] = f64::NAN;
        assert_eq!(
            sys.factor_spd_first_of(&nan, &spd, &mut count),
            Err(SparseError::NonFinite)
        );
        assert!(matches!(
            sys.factor_spd_first_of(&spd, &val, &mut count),
            Err(SparseError::Length { .. })
        ));
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

    /// The Laplacian of an m^d grid (2d + 1 points) with Dirichlet sides, shifted by −σ, and
    /// how many of its eigenvalues 2d − 2Σᵢcos(kᵢπ/(m+1)) − σ, kᵢ = 1..m, are negative.
    fn shifted_grid_laplacian(
        m: usize,
        d: u32,
        sigma: f64,
    ) -> (Vec<(usize, usize)>, Vec<f64>, usize) {
        let n = m.pow(d);
        let (mut pos, mut val) = (Vec::new(), Vec::new());
        for i in 0..n {
            pos.push((i, i));
            val.push(2.0 * d as f64 - sigma);
            for axis in 0..d {
                let stride = m.pow(axis);
                if (i / stride) % m + 1 < m {
                    pos.extend([(i, i + stride), (i + stride, i)]);
                    val.extend([-1.0, -1.0]);
                }
            }
        }
        let h = std::f64::consts::PI / (m + 1) as f64;
        let mut negative = 0;
        for i in 0..n {
            let lambda: f64 = (0..d)
                .map(|axis| {
                    let k = (i / m.pow(axis)) % m + 1;
                    2.0 - 2.0 * (k as f64 * h).cos()
                })
                .sum();
            assert!(
                (lambda - sigma).abs() > 1e-6,
                "σ too close to an eigenvalue"
            );
            negative += usize::from(lambda < sigma);
        }
        (pos, val, negative)
    }

    #[test]
    fn the_negative_pivots_count_the_negative_eigenvalues() {
        // a 2-D grid (simplicial factor) and a 3-D one (supernodal), each at shifts from
        // definite to well inside the spectrum, against the closed-form eigenvalues
        for (m, d, supernodal) in [(30, 2, false), (16, 3, true)] {
            for sigma in [0.01, 0.3, 1.01, 2.7, 3.3] {
                let (pos, val, expected) = shifted_grid_laplacian(m, d, sigma);
                let mut sys = SparseSystem::new(m.pow(d), &pos).unwrap();
                let negative = sys.negative_eigenvalues(&val).unwrap();
                assert_eq!(negative, expected, "m = {m}, d = {d}, σ = {sigma}");
                let raw = sys.llt.as_ref().unwrap().raw();
                assert_eq!(
                    matches!(raw, SymbolicCholeskyRaw::Supernodal(_)),
                    supernodal,
                    "{m}^{d} grid: not the factor kind this case is meant to exercise"
                );
            }
        }
        assert_eq!(shifted_grid_laplacian(30, 2, 0.01).2, 0);
        assert!(shifted_grid_laplacian(16, 3, 0.3).2 > 0);
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
