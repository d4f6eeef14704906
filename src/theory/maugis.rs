//! The Maugis–Dugdale model of adhesion (Maugis 1992; seed 3.10–3.11 with the OCR-garbled
//! powers of ā restored, in the notation of Johnson & Greenwood 1997, PHYSICS.md).
//!
//! The attraction is a constant tension σ₀ over the annulus a ≤ r ≤ c; with m = c/a and
//! ā, P̄, δ̄ normalised as in [`super`] (λ = σ₀(9R/(2πγE\*²))^(1/3)):
//!
//! - (i)  (λā²/2)[(m²−2)·arcsec m + √(m²−1)] + (4λ²ā/3)[√(m²−1)·arcsec m − m + 1] = 1
//! - (ii) P̄ = ā³ − λā²[√(m²−1) + m²·arcsec m]
//! - (iii) δ̄ = ā² − (4/3)λā√(m²−1)
//!
//! **Solving (i) for m.** With s = √(m²−1) and arcsec m = atan s, the left side minus 1,
//! F(m), is −1 at m = 1, grows without bound, and is strictly increasing (dF/dm =
//! λā²(m atan s + s/m) + (4λ²ā/3)(m atan s/s + 1/m − 1) > 0 since m·atan s ≥ s). So each ā > 0
//! has exactly one m. It is found in y = ln(m − 1), which resolves both m − 1 ~ 1/(λ²ā) → 0
//! (JKR end) and m ~ 1/(ā√λ) → ∞ (DMT end), by Newton's method safeguarded by a bracket that is
//! expanded until F changes sign (bisection whenever Newton leaves it). The small-s forms of
//! (m²−2)atan s + s = s² atan s + (s − atan s) avoid cancellation.
//!
//! **Pull-off.** Load control: the minimum of P̄(ā) over ā > 0, found by a logarithmic scan
//! (bracketing only) refined by golden-section search in ln ā; when the minimum sits at the
//! small-ā end (small λ) the limit ā → 0⁺ is reported. Displacement control: the contact jumps
//! off at the end of the stable branch, where dδ̄/dā = 0 — the first local minimum of δ̄ met
//! coming down from large ā; if δ̄ decreases all the way to ā → 0⁺ (no S-curve, small λ) the
//! branch ends there and P̄(0⁺) is reported.

use super::{positive, Control, NormalizedPoint, TheoryError};

/// Tolerances and search ranges of the Maugis–Dugdale solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaugisParams {
    /// convergence of y = ln(m − 1): |Δy| below this ends Newton
    pub tol_y: f64,
    /// Newton/bisection iterations allowed per root
    pub max_iter: usize,
    /// smallest contact radius ā of the pull-off search (the ā → 0⁺ limit is taken here)
    pub a_min: f64,
    /// largest contact radius ā of the pull-off search (beyond the JKR pull-off at 1.145)
    pub a_max: f64,
    /// scan points per decade of ā used to bracket the extrema
    pub per_decade: usize,
    /// golden-section tolerance in ln ā
    pub tol_ln_a: f64,
}

impl Default for MaugisParams {
    fn default() -> Self {
        MaugisParams {
            tol_y: 1e-13,
            max_iter: 200,
            a_min: 1e-7,
            a_max: 4.0,
            per_decade: 24,
            tol_ln_a: 1e-9,
        }
    }
}

/// A solved point of the Maugis–Dugdale curve.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct MaugisPoint {
    /// contact radius ā
    pub a_bar: f64,
    /// m = c/a ≥ 1, the outer radius of the Dugdale zone over the contact radius
    pub m: f64,
    /// m − 1, held separately: it is ~1/(λ²ā) and would lose its digits in m at large λ
    pub m_minus_one: f64,
    /// load P̄
    pub p_bar: f64,
    /// approach δ̄
    pub delta_bar: f64,
    /// iterations of the root solve
    pub iterations: usize,
}

impl From<MaugisPoint> for NormalizedPoint {
    fn from(p: MaugisPoint) -> Self {
        NormalizedPoint {
            a_bar: p.a_bar,
            p_bar: p.p_bar,
            delta_bar: p.delta_bar,
        }
    }
}

/// A pull-off: where and at what load the contact comes apart.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PullOff {
    /// normalised pull-off load P̄ (negative)
    pub p_bar: f64,
    /// contact radius ā at pull-off (the search's `a_min` when the branch ends at ā → 0⁺)
    pub a_bar: f64,
    /// approach δ̄ at pull-off
    pub delta_bar: f64,
    /// true when the extremum is the ā → 0⁺ end of the branch rather than an interior one
    pub at_zero_contact: bool,
    /// curve points evaluated
    pub evaluations: usize,
}

/// s − atan s, accurate for small s.
fn s_minus_atan(s: f64) -> f64 {
    if s < 1e-2 {
        let s2 = s * s;
        s * s2 * (1.0 / 3.0 - s2 * (1.0 / 5.0 - s2 * (1.0 / 7.0 - s2 / 9.0)))
    } else {
        s - s.atan()
    }
}

/// F(m) of equation (i) and dF/dy, with m = 1 + e^y.
fn residual(lambda: f64, a_bar: f64, y: f64) -> (f64, f64) {
    let em = y.exp(); // m − 1
    let m = 1.0 + em;
    let s = (em * (2.0 + em)).sqrt();
    let at = s.atan();
    let c1 = 0.5 * lambda * a_bar * a_bar;
    let c2 = 4.0 / 3.0 * lambda * lambda * a_bar;
    let f = c1 * (s * s * at + s_minus_atan(s)) + c2 * (s * at - em) - 1.0;
    // d/dm of the brackets: 2(m atan s + s/m) and (m atan s/s + 1/m − 1)
    let ratio = if s > 0.0 { at / s } else { 1.0 };
    let dfdm = c1 * 2.0 * (m * at + s / m) + c2 * (m * ratio + 1.0 / m - 1.0);
    (f, dfdm * em)
}

/// Solve equation (i) for m at contact radius ā and return the curve point.
pub fn point(lambda: f64, a_bar: f64, params: &MaugisParams) -> Result<MaugisPoint, TheoryError> {
    positive("Maugis λ", lambda)?;
    positive("contact radius ā", a_bar)?;
    // y ∈ [−700, 300] keeps e^y and m² finite; the bracket grows from y = 0 in steps of 4
    const Y_LOW: f64 = -700.0;
    const Y_HIGH: f64 = 300.0;
    let (mut lo, mut hi) = (0.0_f64, 0.0_f64);
    while residual(lambda, a_bar, lo).0 > 0.0 {
        lo -= 4.0;
        if lo < Y_LOW {
            return Err(TheoryError::OutOfDomain {
                what: "Maugis ā",
                value: a_bar,
                allowed: "a point where the Dugdale zone is resolvable in f64 (m − 1 > 1e-300)"
                    .into(),
            });
        }
    }
    while residual(lambda, a_bar, hi).0 < 0.0 {
        hi += 4.0;
        if hi > Y_HIGH {
            return Err(TheoryError::OutOfDomain {
                what: "Maugis ā",
                value: a_bar,
                allowed: "a point where m = c/a < e^300".into(),
            });
        }
    }
    if lo == hi {
        lo -= 4.0;
    }
    let mut y = 0.5 * (lo + hi);
    let mut last = f64::INFINITY;
    for it in 1..=params.max_iter {
        let (f, df) = residual(lambda, a_bar, y);
        if !f.is_finite() || !df.is_finite() {
            return Err(TheoryError::NotFinite {
                what: "Maugis residual",
                value: f,
            });
        }
        last = f;
        if f == 0.0 {
            return Ok(finish(lambda, a_bar, y, it));
        }
        if f < 0.0 {
            lo = y;
        } else {
            hi = y;
        }
        let newton = y - f / df;
        let next = if df > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let step = (next - y).abs();
        y = next;
        if step < params.tol_y * (1.0 + y.abs()) || hi - lo < params.tol_y {
            return Ok(finish(lambda, a_bar, y, it));
        }
    }
    Err(TheoryError::NoConvergence {
        what: "Maugis–Dugdale equation for m",
        iterations: params.max_iter,
        residual: last,
    })
}

/// P̄ and δ̄ from (ii), (iii) at the solved y = ln(m − 1).
fn finish(lambda: f64, a_bar: f64, y: f64, iterations: usize) -> MaugisPoint {
    let em = y.exp();
    let m = 1.0 + em;
    let s = (em * (2.0 + em)).sqrt();
    MaugisPoint {
        a_bar,
        m,
        m_minus_one: em,
        p_bar: a_bar.powi(3) - lambda * a_bar * a_bar * (s + m * m * s.atan()),
        delta_bar: a_bar * a_bar - 4.0 / 3.0 * lambda * a_bar * s,
        iterations,
    }
}

/// The curve at the given contact radii.
pub fn curve(
    lambda: f64,
    a_bars: &[f64],
    params: &MaugisParams,
) -> Result<Vec<MaugisPoint>, TheoryError> {
    a_bars.iter().map(|&a| point(lambda, a, params)).collect()
}

/// Pull-off of the Maugis–Dugdale sphere at transition parameter λ under `control`.
pub fn pull_off(
    lambda: f64,
    control: Control,
    params: &MaugisParams,
) -> Result<PullOff, TheoryError> {
    positive("Maugis λ", lambda)?;
    let (lo, hi) = (params.a_min.ln(), params.a_max.ln());
    let n = ((hi - lo) / std::f64::consts::LN_10 * params.per_decade as f64).ceil() as usize + 1;
    let grid: Vec<f64> = (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect();
    let pts: Vec<MaugisPoint> = grid
        .iter()
        .map(|&x| point(lambda, x.exp(), params))
        .collect::<Result<_, _>>()?;
    let objective = |p: &MaugisPoint| match control {
        Control::Load => p.p_bar,
        Control::Displacement => p.delta_bar,
    };
    let best = match control {
        // global minimum of P̄ on the scan
        Control::Load => (0..n)
            .min_by(|&i, &j| objective(&pts[i]).total_cmp(&objective(&pts[j])))
            .unwrap_or(0),
        // first local minimum of δ̄ coming down from large ā
        Control::Displacement => (1..n)
            .rev()
            .find(|&i| objective(&pts[i - 1]) >= objective(&pts[i]))
            .unwrap_or(0),
    };
    if best == 0 {
        let p = pts[0];
        return Ok(PullOff {
            p_bar: p.p_bar,
            a_bar: p.a_bar,
            delta_bar: p.delta_bar,
            at_zero_contact: true,
            evaluations: n,
        });
    }
    if best == n - 1 {
        return Err(TheoryError::OutOfDomain {
            what: "Maugis pull-off search: the extremum lies at the upper end ā",
            value: params.a_max,
            allowed: "a larger MaugisParams::a_max".into(),
        });
    }
    let (x, evals) = golden_section(grid[best - 1], grid[best + 1], params.tol_ln_a, |x| {
        point(lambda, x.exp(), params).map(|p| objective(&p))
    })?;
    let p = point(lambda, x.exp(), params)?;
    Ok(PullOff {
        p_bar: p.p_bar,
        a_bar: p.a_bar,
        delta_bar: p.delta_bar,
        at_zero_contact: false,
        evaluations: n + evals + 1,
    })
}

/// Minimise f on [a, b] (unimodal there) by golden-section search to |b − a| < tol.
fn golden_section(
    mut a: f64,
    mut b: f64,
    tol: f64,
    f: impl Fn(f64) -> Result<f64, TheoryError>,
) -> Result<(f64, usize), TheoryError> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    let mut evals = 2;
    while (b - a).abs() > tol {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d)?;
        }
        evals += 1;
    }
    Ok((0.5 * (a + b), evals))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_root_satisfies_equation_one_across_lambda() {
        let p = MaugisParams::default();
        for lambda in [1e-3, 0.1, 1.0, 10.0, 1e3] {
            for a in [1e-6, 1e-3, 0.1, 1.0, 3.9] {
                let pt = point(lambda, a, &p).unwrap();
                let y = pt.m_minus_one.ln();
                // Newton stops at |Δy| < 1e-13(1+|y|): |F| ≤ |dF/dy|·|Δy| plus round-off
                let (f, df) = residual(lambda, a, y);
                assert!(
                    f.abs() < 1e-12 * (1.0 + y.abs()) * df.abs() + 1e-14,
                    "λ={lambda} ā={a}: {f}"
                );
                assert!(pt.m >= 1.0);
            }
        }
    }

    #[test]
    fn residual_derivative_matches_finite_differences() {
        for (lambda, a, y) in [(0.5, 0.8, -1.0), (10.0, 1.2, -5.0), (0.01, 0.05, 3.0)] {
            let e = 1e-6;
            let fd = (residual(lambda, a, y + e).0 - residual(lambda, a, y - e).0) / (2.0 * e);
            let d = residual(lambda, a, y).1;
            // central difference with step 1e-6: truncation ~1e-12, round-off ~1e-10
            assert!((fd - d).abs() < 1e-7 * d.abs().max(1.0), "{fd} {d}");
        }
    }

    #[test]
    fn series_and_direct_forms_of_s_minus_atan_agree_at_the_switch() {
        let s: f64 = 1e-2;
        let direct = s - s.atan();
        // direct form loses ~eps/s² relative accuracy here
        assert!((s_minus_atan(s * (1.0 - 1e-12)) - direct).abs() < 1e-10 * direct);
    }
}
