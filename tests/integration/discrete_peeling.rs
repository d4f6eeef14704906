//! Peeling of two adhered tubes (issue 7, "two tubes: peeling consistent with the balance of
//! bending and adhesion energy").
//!
//! Tube B (straight at rest) lies adhered on a fixed straight tube A along x. Its far end is
//! pinned; its near end is lifted to a height H above the contact line with its x and y free,
//! so the only load there is vertical: a 90° peel. Steady-state peeling of an elastica with a
//! frictionless, uncorrugated line contact is a translation of the bent zone along A: when the
//! front advances by dX, the end rises by dX, the bending energy stays, the stretching energy
//! stays (adhered and peeled parts carry the same tension), and the adhesion γ_L dX is spent.
//! So the lifting force is F = γ_L (Kendall's 90° peel, here without an elastic term), the
//! equilibrium energy rises at dE*/dH = γ_L, and the bending energy of the peeled arc is the
//! elastica's: with θ the angle from A, K θ'²/2 = F (1 − sin θ), whence the curvature at the
//! front κ_c = √(2γ_L/K) (energy release ½Kκ_c² = γ_L) and
//! U_b = ∫ K θ'²/2 ds = √(Kγ_L/2) ∫₀^{π/2} √(1 − sin θ) dθ = (2√2 − 2) √(Kγ_L/2).
//!
//! On the discrete chain the front is trapped between nodes, so the force at a given lift
//! oscillates (here ±8 % about γ_L with the front's position relative to the nodes); the
//! energy rate dE*/dH over a range of lifts, which is the lift-averaged force, is the balance
//! tested.
//!
//! The tubes have the seed's section (r_o = 20 nm, r_i = 17.3 nm) with a wall modulus of
//! 0.4 GPa (a thousandth of the seed's) so that the bending length ℓ_b = √(K/γ_L) = 149 nm fits
//! a few times into a tube of a hundred segments; the balance is scale-free in K.

use turf::discrete::broadphase::PeriodicBox;
use turf::discrete::constraints::FixedDofs;
use turf::discrete::energy::EnergyTerm;
use turf::discrete::rod::{Rod, RodSet, RodStiffness};
use turf::discrete::solve::Sum;
use turf::discrete::solve_newton::{minimize_newton, NewtonParams};
use turf::discrete::vdw::VdwParams;
use turf::discrete::vdw_term::{TubeLayout, VdwTerm};

const R_OUTER: f64 = 20.0;
const R_INNER: f64 = 17.3;
/// Wall modulus, GPa (see the module doc).
const YOUNGS: f64 = 0.4;
/// Segment length of both tubes, nm: a fifteenth of the bending length.
const SEGMENT: f64 = 10.0;
/// Force residual of each equilibrium, nN: 1e-6 of γ_L.
const TOLERANCE: f64 = 1e-6;
/// The rate dE*/dH of the equilibrium energy against γ_L over the steady lifts (2 to 3.4
/// bending lengths). The line energy of the parallel pair is −γ_L to 1e-5
/// (tests/integration/discrete_vdw_two_tubes.rs); the rest of the budget: the arm is not yet vertical at
/// its end (F = γ_L / sin θ_end, 1 − sin θ_end ≈ (4 tan(π/8) e^{−H/ℓ_b})²/2 ≈ 4e-3 at
/// H = 2 ℓ_b), the stretching energy grows with the tension as the lift builds up (~0.4 aJ over
/// the range, 2e-3), and the discrete front is trapped between nodes (the lifting force
/// oscillates by ±8 % with the front's position relative to the 10 nm nodes; the energy rate
/// between two lifts averages it out but keeps ~1e-3 of it). Budget 1.5 %; measured 0.47 % (set
/// after the first run of this test, with this budget). An arm leaning 10° from vertical
/// would need Kendall's F = γ_L/(1 − cos 80°) = 1.21 γ_L.
const RATE_TOL: f64 = 0.015;
/// The bending energy of the peeled arc against the sharp-front elastica value: the contact
/// front is a cohesive zone of length ~√(2 g_cut/κ_c) ≈ 25 nm (where the gap opens from 0.34
/// to the 3.4 nm cutoff) against the 149 nm bending length, and in it the curvature is below
/// κ_c; 10 % bounds that zone's share of the energy (the bending energy density is at most γ_L
/// there: ~25 aJ of 87 aJ, and the zone only partly lacks it).
const BENDING_TOL: f64 = 0.1;

struct Peel {
    rods: RodSet,
    vdw: VdwTerm,
    fixed: FixedDofs,
    x: Vec<f64>,
    /// index of B's lifted end node
    end: usize,
    /// axis separation of the adhered pair, nm
    d0: f64,
    stiffness: RodStiffness,
}

fn straight(x0: f64, z: f64, length: f64) -> Vec<[f64; 3]> {
    let n = (length / SEGMENT).round() as usize;
    (0..=n)
        .map(|k| [x0 + length * k as f64 / n as f64, 0.0, z])
        .collect()
}

fn peel() -> Peel {
    let params = VdwParams::default();
    let d0 = 2.0 * R_OUTER + params.gap_eq;
    // A from −200 nm to 1300 nm, B adhered on top of it from 0 to 1000 nm
    let a = straight(-200.0, 0.0, 1500.0);
    let b = straight(0.0, d0, 1000.0);
    let stiffness = RodStiffness::hollow_tube(YOUNGS, R_OUTER, R_INNER);
    let rods = RodSet::new(vec![
        Rod::straight(0, &a, stiffness).unwrap(),
        Rod::straight(a.len(), &b, stiffness).unwrap(),
    ]);
    let layout = [
        TubeLayout {
            first_node: 0,
            nodes: a.len(),
            radius: R_OUTER,
        },
        TubeLayout {
            first_node: a.len(),
            nodes: b.len(),
            radius: R_OUTER,
        },
    ];
    let x: Vec<f64> = a.iter().chain(&b).flatten().copied().collect();
    let vdw = VdwTerm::new(&params, &layout, &x, PeriodicBox::default()).unwrap();
    let mut fixed = FixedDofs::free(x.len() / 3);
    for n in 0..a.len() {
        fixed.pin(n);
    }
    fixed.pin(a.len());
    let end = a.len() + b.len() - 1;
    fixed.fix(3 * end + 2);
    Peel {
        rods,
        vdw,
        fixed,
        x,
        end,
        d0,
        stiffness,
    }
}

/// Equilibrium with B's end lifted to `h` above the adhered height: (energy, bending energy of
/// B, vdW energy, lifting force = ∂E/∂z_end).
fn lift(p: &mut Peel, h: f64) -> (f64, f64, f64, f64) {
    p.x[3 * p.end + 2] = p.d0 + h;
    let params = NewtonParams {
        atol: TOLERANCE,
        rtol: 0.0,
        max_iterations: 500,
        ..NewtonParams::default()
    };
    let mut sum = Sum(vec![&mut p.rods, &mut p.vdw]);
    let info = minimize_newton(&mut sum, &p.fixed, &mut p.x, &params)
        .unwrap_or_else(|e| panic!("lift {h} nm: {e}"));
    let mut grad = vec![0.0; p.x.len()];
    sum.prepare(&p.x);
    let e = sum.energy_gradient(&p.x, &mut grad);
    let force = grad[3 * p.end + 2];
    let bending = p.rods.rods()[1].energy_parts(&p.x).1;
    p.vdw.prepare(&p.x);
    let vdw = p.vdw.energy_gradient(&p.x, &mut vec![0.0; p.x.len()]);
    assert!((e - info.energy).abs() <= 1e-9 * e.abs().max(1.0));
    (e, bending, vdw, force)
}

#[test]
fn steady_peeling_costs_gamma_l_per_length_and_bends_like_the_elastica() {
    let mut p = peel();
    let gamma = VdwParams::default().gamma_l;
    let k = p.stiffness.bending;
    let l_b = (k / gamma).sqrt();
    // lift in steps of a tenth of the bending length up to 3.4 bending lengths
    let step = 0.1 * l_b;
    let mut history = Vec::new();
    let mut h = 0.0;
    while h < 3.4 * l_b {
        h += step;
        history.push((h, lift(&mut p, h)));
    }
    let bending_ref = (2.0 * 2f64.sqrt() - 2.0) * (k * gamma / 2.0).sqrt();
    for (h, (e, ub, vdw, f)) in &history {
        println!(
            "H = {h:8.1} nm: E* = {e:10.3} aJ, U_b = {ub:8.3} aJ (elastica {bending_ref:.3}), \
             vdW = {vdw:10.3} aJ, F = {f:.6} nN"
        );
    }
    // lifts from 2 bending lengths on are steady
    let steady: Vec<_> = history.iter().filter(|(h, _)| *h > 2.0 * l_b).collect();
    assert!(steady.len() >= 10);
    for (h, (_, ub, _, _)) in &steady {
        assert!(
            (ub / bending_ref - 1.0).abs() < BENDING_TOL,
            "H = {h}: bending {ub} aJ against the elastica's {bending_ref}"
        );
    }
    // the energy released per length of lift: dE*/dH = γ_L (the work of the lifting force)
    let (h1, (e1, ..)) = steady[0];
    let (h2, (e2, ..)) = steady[steady.len() - 1];
    let rate = (e2 - e1) / (h2 - h1);
    println!("dE*/dH over H = {h1:.1} … {h2:.1} nm: {rate:.5} nN (γ_L = {gamma})");
    assert!((rate / gamma - 1.0).abs() < RATE_TOL, "dE*/dH = {rate}");
}
