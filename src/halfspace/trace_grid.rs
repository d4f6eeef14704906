//! The grids the half-space curve is traced on (PHYSICS.md): the process zone at the contact
//! edge is ℓ ≈ min(1, μ^{−3/2}) wide in scaled radial units; the trace grid is uniform with
//! `cells_per_zone` cells per ℓ over every radius the contact edge visits (up to the JKR radius at
//! zero load, ρ₀ = (9π/2)^{1/3} μ^{1/2}, with margin) — or, at large μ, over a window that follows
//! the edge — and graded outside. The outer radius puts the gap at the edge beyond H_tail, where
//! the rigid tail load 2|φ̄(H_tail)| is below `tail_tolerance`, after allowing for the approach
//! from the starting gap.

use super::grid::GridSpec;
use super::{HalfspaceParams, Problem, Traction};

/// Default starting central gap, beyond jump-in: 3 + 3μ^{3/7} (the bulge of the surface under
/// the attraction grows like μ^{3/2}H^{−7/2} for a 9-3 tail, so instability sets in near H ~ μ^{3/7}).
pub(crate) fn start_gap(mu: f64, params: &HalfspaceParams) -> f64 {
    params
        .start_gap
        .unwrap_or_else(|| 3.0 + 3.0 * mu.powf(3.0 / 7.0))
}

/// Process-zone width ℓ = min(1, μ^{−3/2}), scaled radial units.
pub fn process_zone(mu: f64) -> f64 {
    mu.powf(-1.5).min(1.0)
}

/// Outer radius: the gap there exceeds H_tail + (allowance for the approach).
fn outer_radius<T: Traction>(problem: &Problem<T>, mu: f64, params: &HalfspaceParams) -> f64 {
    // smallest H (doubling) whose rigid tail load is below the tolerance
    let mut h_tail = 1.0;
    while 2.0 * problem.scaled_tail_energy(h_tail).abs() > params.tail_tolerance && h_tail < 1e8 {
        h_tail *= 2.0;
    }
    // the approach at F̄ = 0 is below ~ρ₀² (JKR: δ = a²/R − ...), ρ₀² ≈ 5.2μ; plus the start gap
    let approach = 6.0 * mu + start_gap(mu, params);
    (2.0 * (h_tail + approach)).sqrt()
}

/// The grid on which the curve is traced while the contact edge is near radius `edge`: uniform
/// with `cells_per_zone` cells per ℓ over a zone that covers every radius the edge visits (up to
/// 1.2 × the JKR radius at zero load, ρ₀ = (9π/2)^{1/3} μ^{1/2}, and at least 3) when that zone
/// is at most `window_zones` ℓ wide (then `edge` and `near` are ignored); otherwise (large μ)
/// over a window of that width from 40 % of it behind the edge to 60 % ahead (the edge grows
/// along the trace), extended out to `near`; `edge` and `near` are the ends of the band of rings
/// that could jump on their own ([`super::curve::soft_band`]). Graded towards the centre and
/// outwards.
pub fn trace_grid<T: Traction>(
    problem: &Problem<T>,
    params: &HalfspaceParams,
    edge: f64,
    near: f64,
) -> GridSpec {
    let mu = problem.tabor();
    let ell = process_zone(mu);
    let outer = outer_radius(problem, mu, params);
    let swept = 3.0f64.max(1.2 * (4.5 * std::f64::consts::PI).cbrt() * mu.sqrt());
    let window = params.window_zones * ell;
    let (zone_lo, zone_hi) = if swept <= window {
        (0.0, swept)
    } else {
        let lo = (edge - 0.4 * window).max(0.0);
        (lo, (lo + window).max(near))
    };
    GridSpec {
        fine_spacing: ell / params.cells_per_zone,
        zone_lo,
        zone_hi,
        growth: params.growth,
        outer,
    }
}

/// Nodes of the finest grid [`super::pull_off`] or [`super::trace_curve`] would build with `params`
/// (the trace grid, refined twice by `refinement_ratio` when `refinement`), in closed form: the
/// memory of a run is checked against it before any grid is built.
pub fn estimated_nodes<T: Traction>(
    problem: &Problem<T>,
    params: &HalfspaceParams,
    refinement: bool,
) -> f64 {
    let spec = trace_grid(problem, params, 0.0, 0.0);
    let spec = if refinement {
        spec.refined(params.refinement_ratio.powi(2))
    } else {
        spec
    };
    spec.estimated_len()
}
