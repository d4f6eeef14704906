//! The projection of a symmetric matrix onto the positive-semidefinite cone: the element-wise
//! convexification of projected Newton (Teran, Sifakis, Irving & Fedkiw, SCA 2005, §4; used with
//! contact barriers by Li et al., IPC, SIGGRAPH 2020). Each element's Hessian block has its
//! negative eigenvalues set to zero before assembly, so the assembled matrix is
//! positive-semidefinite without a shift common to the whole system: an element past an
//! instability stops pulling the step, while every other element keeps its own curvature.

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, DimDiff, DimSub, SMatrix, SymmetricEigen, U1};

/// Eigenvalues above −`ROUND_OFF` times the largest |eigenvalue| count as zero: an element's
/// rigid motions give it exact zero eigenvalues that round-off puts on either side of 0.
const ROUND_OFF: f64 = 1e-12;

/// Iteration limit of the eigen-solve (a symmetric 12 × 12 converges in a few dozen).
const MAX_SWEEPS: usize = 1000;

/// The positive-semidefinite part V max(Λ, 0) Vᵀ of the symmetric matrix `m`, in place.
/// Returns whether `m` changed (it had an eigenvalue below −[`ROUND_OFF`] times its largest
/// |eigenvalue|); a matrix with a non-finite entry, or whose eigen-solve does not converge, is
/// left alone.
pub fn project_psd<const N: usize>(m: &mut SMatrix<f64, N, N>) -> bool
where
    Const<N>: DimSub<U1>,
    DefaultAllocator: Allocator<DimDiff<Const<N>, U1>>,
{
    if !m.iter().all(|v| v.is_finite()) {
        return false;
    }
    let Some(eig) = SymmetricEigen::<f64, Const<N>>::try_new(*m, f64::EPSILON, MAX_SWEEPS) else {
        return false;
    };
    let largest = eig.eigenvalues.amax();
    if eig.eigenvalues.iter().all(|&l| l >= -ROUND_OFF * largest) {
        return false;
    }
    let flip = std::env::var_os("TURF_PSD_ABS").is_some();
    let clamped = eig
        .eigenvalues
        .map(|l| if flip { l.abs() } else { l.max(0.0) });
    *m = eig.eigenvectors
        * SMatrix::<f64, N, N>::from_diagonal(&clamped)
        * eig.eigenvectors.transpose();
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn a_psd_matrix_is_left_alone_and_an_indefinite_one_loses_its_negative_part() {
        let mut a = Matrix3::new(2.0, 1.0, 0.0, 1.0, 2.0, 0.0, 0.0, 0.0, 1.0);
        let before = a;
        assert!(!project_psd(&mut a));
        assert_eq!(a, before);
        // eigenvalues 3, −1 (vectors (1, 1, 0)/√2, (1, −1, 0)/√2) and 2
        let mut b = Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 2.0);
        assert!(project_psd(&mut b));
        let expected = Matrix3::new(1.5, 1.5, 0.0, 1.5, 1.5, 0.0, 0.0, 0.0, 2.0);
        assert!((b - expected).amax() < 1e-12, "{b}");
        // the kept eigenpairs are unchanged
        let v = Vector3::new(1.0, 1.0, 0.0);
        assert!((b * v - 3.0 * v).amax() < 1e-12);
    }
}
