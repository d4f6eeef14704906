//! One load–approach S-curve of the half-space solver as CSV on stdout (scaled units).
//! Run: `cargo run -j1 --example halfspace_curve -- MU [lj93|lj104]`.

use turf::halfspace::{trace_curve, HalfspaceParams, Problem};
use turf::laws::LjKind;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let mu: f64 = args.next().map_or(Ok(1.0), |a| a.parse())?;
    let kind = match args.next().as_deref() {
        Some("lj104") => LjKind::Lj104,
        _ => LjKind::Lj93,
    };
    let curve = trace_curve(&Problem::scaled(mu, kind)?, &HalfspaceParams::default())?;
    println!("central_gap,approach,load,contact_radius,dD_ds,dF_ds");
    for p in &curve.points {
        println!(
            "{},{},{},{},{},{}",
            p.central_gap, p.approach, p.load, p.contact_radius, p.slope_approach, p.slope_load
        );
    }
    eprintln!(
        "mu {mu}: pull-off {:.6} (H0 {:.4}, a {:.4}), jump-in {:?}, jump-out {:?}, {} nodes, {} remeshes, {:?}",
        curve.pull_off.load,
        curve.pull_off.central_gap,
        curve.pull_off.contact_radius,
        curve.jump_in.map(|p| (p.load, p.approach)),
        curve.jump_out.map(|p| (p.load, p.approach)),
        curve.nodes,
        curve.remeshes,
        curve.cost
    );
    Ok(())
}
