//! The calibrated tube–tube potential for a few tube radii: the wall–wall law it implies
//! (z₀, work of adhesion w), the parallel line energy, and the crossed-tube energy at contact
//! beside the Derjaguin estimate 2πR ∫ φ_w for crossed cylinders of radius R.
//!
//! `cargo run --example discrete_vdw_calibration` (numbers quoted in docs/discrete-contacts.md).

use turf::discrete::vdw::{LinePairPotential, VdwParams};
use turf::laws::LjKind;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("law   r_o/nm  z0/nm    w/(J/m2)  E_par(D0)/nN  E_x(D0)/aJ  Derjaguin/aJ  width/nm");
    for law in [LjKind::Lj93, LjKind::Lj104] {
        for r in [0.7, 5.0, 20.0] {
            let params = VdwParams {
                law,
                radius_ref: r,
                ..VdwParams::default()
            };
            let pot = LinePairPotential::calibrate(&params)?;
            let r_sum = 2.0 * r;
            let d0 = r_sum + params.gap_eq;
            let (e_par, _) = pot.parallel_line_energy(d0, r_sum);
            let e_x = pot.crossed_energy(d0, r_sum);
            // Derjaguin, crossed equal cylinders = sphere of radius r on a flat:
            // E = 2πr ∫_g^∞ φ_w(h) S(h) dh (same switched wall law)
            let n = 20000;
            let (g0, gc) = (params.gap_eq, params.gap_cut);
            let h = (gc - g0) / n as f64;
            let integral: f64 = (0..n)
                .map(|k| {
                    let g = g0 + (k as f64 + 0.5) * h;
                    2.0 * pot.eval(r_sum + g, r_sum).0 * h
                })
                .sum();
            let derjaguin = 2.0 * std::f64::consts::PI * r * integral;
            println!(
                "{:5} {r:6.1}  {:.4}  {:.4}    {e_par:.6}     {e_x:9.4}   {derjaguin:9.4}   {:.3}",
                format!("{law:?}"),
                pot.wall.z0,
                pot.wall.gamma,
                pot.width(r_sum)
            );
        }
    }
    Ok(())
}
