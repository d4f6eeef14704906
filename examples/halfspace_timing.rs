//! Wall time and accuracy of the half-space solver against grid size at μ = 1: the table of
//! docs/benchmarks-halfspace.md. Run: `cargo run -j1 --example halfspace_timing` (dev profile:
//! dependencies at opt-level 3, this crate at 1) or with `--release`.

use std::time::Instant;
use turf::halfspace::{pull_off, trace_curve, HalfspaceParams, Problem};
use turf::laws::LjKind;

/// Repetitions per timing (the minimum is reported).
const REPEATS: usize = 5;

fn main() -> anyhow::Result<()> {
    println!("law    cells/zone  trace_nodes  trace_s  pull_off    error_est  po_nodes(max)  po_s   newton");
    for kind in [LjKind::Lj93, LjKind::Lj104] {
        let problem = Problem::scaled(1.0, kind)?;
        for cells in [4.0, 6.0, 8.0, 12.0, 16.0, 24.0] {
            let params = HalfspaceParams {
                cells_per_zone: cells,
                ..HalfspaceParams::default()
            };
            let mut t_trace = f64::INFINITY;
            let mut t_po = f64::INFINITY;
            let mut result = None;
            let mut nodes = 0;
            for _ in 0..REPEATS {
                let t0 = Instant::now();
                let curve = trace_curve(&problem, &params)?;
                t_trace = t_trace.min(t0.elapsed().as_secs_f64());
                nodes = curve.nodes;
                let t0 = Instant::now();
                let po = pull_off(&problem, &params)?;
                t_po = t_po.min(t0.elapsed().as_secs_f64());
                result = Some(po);
            }
            let po = result.expect("REPEATS > 0");
            println!(
                "{kind:?}  {cells:5.0}  {nodes:6}  {t_trace:8.4}  {:10.6}  {:9.2e}  {:6}  {t_po:7.4}  {}",
                po.normalized, po.error_estimate, po.cost.max_nodes, po.cost.newton_iterations
            );
        }
    }
    Ok(())
}
