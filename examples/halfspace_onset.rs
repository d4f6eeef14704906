//! Smallest Tabor parameter with a jump-to-contact (an S-shaped load–approach curve) for LJ 9-3
//! and 10-4, by bisection on the presence of a turning point in the approach.
//! Run: `cargo run -j1 --example halfspace_onset`.

use turf::halfspace::{trace_curve, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// Bisection stops when the bracket is this narrow in μ.
const MU_TOL: f64 = 1e-3;

fn main() -> anyhow::Result<()> {
    // default steps, then steps 50× finer: near the onset the S is tiny and two turning
    // points inside one continuation step would be missed
    let fine = HalfspaceParams {
        max_step: 0.005,
        max_gap_change: 0.005,
        ..HalfspaceParams::default()
    };
    for (label, params) in [
        ("default steps", HalfspaceParams::default()),
        ("fine steps", fine),
    ] {
        for kind in [LjKind::Lj93, LjKind::Lj104] {
            let has_s = |mu: f64| -> anyhow::Result<bool> {
                Ok(trace_curve(&Problem::scaled(mu, kind)?, &params)?
                    .jump_in
                    .is_some())
            };
            let (mut lo, mut hi) = (0.2, 1.0);
            anyhow::ensure!(
                !has_s(lo)? && has_s(hi)?,
                "bracket [0.2, 1] does not hold the onset"
            );
            while hi - lo > MU_TOL {
                let mid = 0.5 * (lo + hi);
                if has_s(mid)? {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            println!(
                "{label}, {kind:?}: S-curve onset at mu = {:.3} (between {lo:.4} and {hi:.4})",
                0.5 * (lo + hi)
            );
        }
    }
    Ok(())
}
