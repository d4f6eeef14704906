//! Critical points on a traced equilibrium curve (seed §4.3; Wriggers & Simo's test): where the
//! stiffness at fixed depth, K_uu, turns singular. The curve r(u, δ) = 0 has two kinds of them.
//! At a **fold** (limit point) in δ the path turns back in δ and one eigenvalue of K_uu crosses
//! zero: the jump-in and jump-out of an adhesive contact. At a **bifurcation** an eigenvalue
//! crosses zero while the path goes on in δ — another equilibrium branch crosses this one, and
//! the one the loading follows may be the other. The count of K_uu's negative eigenvalues
//! (Sylvester's inertia of an LDLᵀ factorisation) at each converged point tells them apart: a
//! step whose count changes by more than its folds in δ explain has passed a bifurcation (the
//! determinant of the bordered system [K_uu g; tᵀ], sign(det K_uu)·sign(t_δ), changed sign).
//! The critical mode — K_uu's eigenvector of the eigenvalue nearest zero, by inverse iteration
//! with one factorisation — is the direction a branch switch would leave the curve along (not
//! built: no traced path has shown a bifurcation yet), and its product with g = ∂²Π/∂u∂δ
//! separates the kinds once more: a fold's mode is loaded by the indenter (φ·g ≠ 0), a simple
//! bifurcation's is not.

use super::assembly::Assembler;
use super::FeError;
use serde::Serialize;

/// What kind of singular point a step passed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CriticalKind {
    /// a limit point in δ: the path turns back, one eigenvalue crosses zero
    Fold,
    /// eigenvalues crossed zero beyond what the folds explain: another branch crosses the path
    Bifurcation,
}

/// One critical point passed by the trace, located to within the step that passed it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[allow(non_snake_case)] // field names carry their units, as the output columns do
pub struct CriticalPoint {
    /// the schedule segment
    pub segment: usize,
    /// fold or bifurcation
    pub kind: CriticalKind,
    /// depth and load at the converged point just past it
    pub depth_nm: f64,
    /// load there, nN
    pub load_nN: f64,
    /// negative eigenvalues of K_uu before and after the step
    pub negative_before: usize,
    /// after the step
    pub negative_after: usize,
    /// K_uu's eigenvalue nearest zero just past it, nN/nm (per unit dof displacement)
    pub eigenvalue: f64,
    /// |φ·g|/‖g‖ for the unit critical mode φ: O(1) at a fold, ≈ 0 at a simple bifurcation
    pub load_alignment: f64,
    /// radius of the node the critical mode moves most, nm
    pub mode_radius_nm: f64,
}

/// The kind of critical point a step passed, from the negative-eigenvalue counts before and
/// after it and whether the path turned back in δ (None: nothing critical, or a count unknown).
pub fn classify(before: Option<usize>, after: Option<usize>, fold: bool) -> Option<CriticalKind> {
    let (a, b) = (before?, after?);
    let crossings = a.abs_diff(b);
    // a fold accounts for one crossing; anything else, or a fold the count does not show
    // (the parity of crossings + folds: the bordered determinant's sign change), is a branch
    if crossings >= 2 || (crossings + usize::from(fold)) % 2 == 1 {
        Some(CriticalKind::Bifurcation)
    } else if fold {
        Some(CriticalKind::Fold)
    } else {
        None
    }
}

/// The critical mode at a stiffness `values` of `dofs` unknowns: K_uu's eigenvalue nearest
/// zero and its unit eigenvector (constrained dofs zero), by inverse iteration x ← K⁻¹x from a
/// seed that moves every free dof, with one factorisation. The eigenvalue is the Rayleigh quotient xᵀy/yᵀy of
/// y = K⁻¹x; iterations stop when it changes by less than 1e-8 relative, or after 60.
pub fn critical_mode(
    asm: &mut Assembler,
    values: &[f64],
    dofs: usize,
) -> Result<(f64, Vec<f64>), FeError> {
    asm.factor(values)?;
    let free = asm.residual(&vec![1.0; dofs]);
    let mut x: Vec<f64> = free
        .iter()
        .enumerate()
        .map(|(i, &f)| f * (1.0 + 0.37 * ((i as f64) * 0.618).sin()))
        .collect();
    normalise(&mut x);
    let mut lambda = f64::NAN;
    for _ in 0..60 {
        let solved = asm.back_solve(&x)?;
        let y = asm.residual(&solved);
        let yy: f64 = y.iter().map(|v| v * v).sum();
        let next = x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>() / yy;
        x = y;
        normalise(&mut x);
        let settled = (next - lambda).abs() <= 1e-8 * next.abs();
        lambda = next;
        if settled {
            break;
        }
    }
    Ok((lambda, x))
}

fn normalise(x: &mut [f64]) {
    let n = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    if n > 0.0 {
        x.iter_mut().for_each(|v| *v /= n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folds_and_branches_are_told_apart_by_the_inertia() {
        use CriticalKind::*;
        // a fold: one crossing, the path turns back
        assert_eq!(classify(Some(0), Some(1), true), Some(Fold));
        assert_eq!(classify(Some(1), Some(0), true), Some(Fold));
        // an eigenvalue crosses while the path goes on in δ: a bifurcation
        assert_eq!(classify(Some(1), Some(2), false), Some(Bifurcation));
        // a fold and a branch in one step, or a turn the count does not show
        assert_eq!(classify(Some(0), Some(2), true), Some(Bifurcation));
        assert_eq!(classify(Some(1), Some(1), true), Some(Bifurcation));
        // nothing, or nothing known
        assert_eq!(classify(Some(1), Some(1), false), None);
        assert_eq!(classify(None, Some(1), true), None);
    }
}
