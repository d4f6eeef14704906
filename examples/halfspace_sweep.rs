//! Pull-off against the Tabor parameter for LJ 9-3 and 10-4 with the half-space solver: the
//! table of docs/validation-halfspace.md. Run: `cargo run -j1 --release --example halfspace_sweep [mu...]`
//! (default: μ = 0.01 … 10, both laws; jump points from the trace, pull-off with the three-grid study).

use turf::halfspace::{pull_off, HalfspaceParams, Problem};
use turf::laws::LjKind;

fn main() -> anyhow::Result<()> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let mus = if args.is_empty() {
        vec![
            0.01, 0.05, 0.1, 0.2, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0,
        ]
    } else {
        args
    };
    let params = HalfspaceParams::default();
    println!("law    mu     pull_off   error_est  extrap     order  jump_in(F,D)          jump_out(F,D)         a_po   nodes  newton  time_s");
    for kind in [LjKind::Lj93, LjKind::Lj104] {
        for &mu in &mus {
            let problem = Problem::scaled(mu, kind)?;
            let po = pull_off(&problem, &params)?;
            let fmt = |p: Option<turf::halfspace::CurvePoint>| {
                p.map_or("-".to_string(), |p| {
                    format!("({:.4},{:.4})", p.load, p.approach)
                })
            };
            let nodes: Vec<usize> = po.levels.iter().map(|l| l.nodes).collect();
            println!(
                "{:?} {:6.3} {:10.6} {:9.2e} {:10.6} {:6.2} {:21} {:21} {:6.3} {:?} {} {:.3}",
                kind,
                mu,
                po.normalized,
                po.error_estimate,
                po.extrapolated,
                po.observed_order,
                fmt(po.jump_in),
                fmt(po.jump_out),
                po.contact_radius,
                nodes,
                po.cost.newton_iterations,
                po.cost.wall_time
            );
        }
    }
    Ok(())
}
