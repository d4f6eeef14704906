//! Pull-off of a single tube from the adhesive sphere (issue 19, "the adhesive discrete sphere:
//! single-tube pull-off against the peeling balance"; docs/discrete-contacts.md "Adhesive
//! sphere").
//!
//! A straight vertical tube, clamped at its base, touches the sphere end-on at its tip; the
//! sphere (lowest point H, displacement control) is raised in small steps, each step a static
//! equilibrium, and the force on it is recorded. The sphere's energy with the tube is the line
//! law λ(g) (the surface law integrated across the tube, Derjaguin) integrated along it; for a
//! straight tube along the sphere's normal with its tip at gap g₀,
//!
//! E(g₀) = ∫₀^L λ(g₀ + s) ds,  F = −∂E/∂H = −∂E/∂g₀ = λ(g₀) (λ(g₀ + L) = 0),
//!
//! so the force on the sphere at every equilibrium is λ at the tip's gap, and the pull-off force
//! (the largest tension, reached on the stable branch before the tip jumps off) is
//! F_c = Γ = −min λ: the balance of a peel at θ = 90°, F(1 − cos θ) = Γ, with the work of
//! separation per unit length of tube Γ. For the plain 9-3 law, λ has a closed form (Derjaguin
//! over a cylinder of radius r* = rR/(r + R)):
//!
//! λ(g) = √(2r*) C z₀ [z₀⁸/8 · I₈ g^(−15/2) − z₀²/2 · I₂ g^(−3/2)],  I_k = π Π_{j<k} (j − ½)/j.
//!
//! The check runs with segments of 20, 100 and 200 nm: the material quadrature along the tube
//! resolves the tip on the law's scale whatever the segment length (node-lumping would make
//! the force proportional to it).

use turf::discrete::constraints::FixedDofs;
use turf::discrete::rod::{Rod, RodSet, RodStiffness};
use turf::discrete::solve::Sum;
use turf::discrete::solve_newton::{minimize_newton, NewtonParams};
use turf::discrete::sphere_adhesion::{SphereAdhesion, SphereLjParams};
use turf::discrete::vdw_term::TubeLayout;
use turf::laws::{LennardJones, LjKind, SurfaceLaw, ThermallyShifted};

const R_OUTER: f64 = 20.0;
const R_INNER: f64 = 17.3;
/// The seed tubes' wall modulus, GPa: a stiff tube, so the tip follows the sphere closely.
const YOUNGS: f64 = 400.0;
const LENGTH: f64 = 400.0;
const SPHERE: f64 = 1000.0;
/// The tip's first gap, in z₀.
const START_GAP: f64 = 0.6;
/// The pull-off force against the closed form of the untruncated 9-3 line law: the cutoff
/// lowers Γ by 0.67 % (the convergence table of `sphere_adhesion`), the cross-section rule is
/// converged to 1e-5 and the steps sample the minimum of a smooth F(H) to ~1e-5.
const CLOSED_FORM_TOL: f64 = 0.01;
/// The pull-off force against the engine's own Γ = −min λ (what the equilibria must reproduce
/// whatever the segment length), plain law: the along-tube quadrature (F = λ(g₀) to 1e-5 at
/// every step) and the sampling of the minimum by 5 pm steps; measured ≤ 1e-4.
const OWN_LAW_TOL: f64 = 1e-3;
/// The same for the shifted law: its minimum sits where the stretched attraction meets the
/// unshifted repulsion through a blend 0.007 nm wide, sharper than the along-tube panels
/// (z₀/2 = 0.17 nm) resolve; measured ≤ 6e-4.
const OWN_SHIFTED_TOL: f64 = 2e-3;

/// The tube with segments of `segment` nm, its fixed base, and the adhesive sphere over it.
fn setup(law: SurfaceLaw, segment: f64) -> (RodSet, FixedDofs, SphereAdhesion, Vec<f64>) {
    let n = (LENGTH / segment).round() as usize;
    let nodes: Vec<[f64; 3]> = (0..=n)
        .map(|k| [0.0, 0.0, LENGTH * k as f64 / n as f64])
        .collect();
    let x: Vec<f64> = nodes.iter().flatten().copied().collect();
    let stiffness = RodStiffness::hollow_tube(YOUNGS, R_OUTER, R_INNER);
    let rods = RodSet::new(vec![Rod::straight(0, &nodes, stiffness).unwrap()]);
    let mut fixed = FixedDofs::free(nodes.len());
    fixed.pin(0);
    fixed.pin(1);
    let layout = [TubeLayout {
        first_node: 0,
        nodes: nodes.len(),
        radius: R_OUTER,
    }];
    let top = LENGTH + R_OUTER + law.z0();
    let sphere = SphereAdhesion::new(
        law,
        SPHERE,
        [0.0, 0.0, top],
        &layout,
        &x,
        &SphereLjParams::default(),
    );
    (rods, fixed, sphere, x)
}

/// Raise the sphere from the tip's gap 0.6 z₀ (in the repulsive range: the line law's minimum
/// lies below z₀, its integrand reaching out to larger gaps) to `to` nm in steps of `step` nm:
/// the most tensile force on the sphere, nN (negative).
fn pull(law: SurfaceLaw, segment: f64, step: f64, to: f64) -> f64 {
    let (mut rods, fixed, mut sphere, mut x) = setup(law, segment);
    let params = NewtonParams {
        atol: 1e-9,
        rtol: 0.0,
        max_iterations: 200,
        ..NewtonParams::default()
    };
    let mut least = 0.0f64;
    let start = START_GAP * law.z0();
    let steps = ((to - start) / step).ceil() as usize;
    for k in 0..=steps {
        let h = LENGTH + R_OUTER + start + k as f64 * step;
        sphere.set_height(h);
        let mut sum = Sum(vec![&mut rods, &mut sphere]);
        minimize_newton(&mut sum, &fixed, &mut x, &params)
            .unwrap_or_else(|e| panic!("segment {segment} nm, sphere at {h} nm: {e}"));
        least = least.min(sphere.force(&x));
    }
    least
}

/// Γ = −min λ of the engine's line law, by a scan refined to 1e-6 nm.
fn gamma_of_engine(law: SurfaceLaw) -> f64 {
    let (_, _, sphere, _) = setup(law, LENGTH);
    let line = sphere.line_law(0);
    let (mut lo, mut hi) = (0.5 * law.z0(), 20.0 * law.tangent_intercept());
    for _ in 0..40 {
        // golden-free ternary search on a unimodal minimum
        let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if line.eval(a).0 < line.eval(b).0 {
            hi = b;
        } else {
            lo = a;
        }
    }
    -line.eval(0.5 * (lo + hi)).0
}

/// ∫ (g + τ²)^(−k) dτ over ℝ, divided by g^(½ − k).
fn power_integral(k: i32) -> f64 {
    std::f64::consts::PI * (1..k).map(|j| (j as f64 - 0.5) / j as f64).product::<f64>()
}

/// Γ of the untruncated plain LJ 9-3 line law in closed form: λ(g) = A g^(−15/2) − B g^(−3/2),
/// whose minimum is at g⁶ = 5A/B.
fn gamma_closed_form_93(law: &LennardJones) -> f64 {
    let r_star = R_OUTER * SPHERE / (R_OUTER + SPHERE);
    let (c, z0) = (law.prefactor(), law.z0);
    let s = (2.0 * r_star).sqrt() * c * z0;
    let a = s * z0.powi(8) / 8.0 * power_integral(8);
    let b = s * z0.powi(2) / 2.0 * power_integral(2);
    let g = (5.0 * a / b).powf(1.0 / 6.0);
    -(a * g.powf(-7.5) - b * g.powf(-1.5))
}

#[test]
fn an_end_on_tip_pulls_off_at_the_line_adhesion_energy_whatever_the_segment_length() {
    let plain = LennardJones::new(LjKind::Lj93, 0.46, 0.34);
    let closed = gamma_closed_form_93(&plain);
    let own = gamma_of_engine(plain.into());
    let shifted: SurfaceLaw =
        ThermallyShifted::new(LennardJones::new(LjKind::Lj104, 0.46, 0.34), 4.626)
            .unwrap()
            .into();
    let own_shifted = gamma_of_engine(shifted);
    eprintln!("LJ 9-3: Γ closed form {closed:.5} nN, engine's law {own:.5} nN");
    eprintln!("shifted LJ 10-4 (u = 4.626 nm): engine's law Γ {own_shifted:.5} nN");
    for segment in [20.0, 100.0, 200.0] {
        let f = -pull(plain.into(), segment, 0.005, 0.8);
        eprintln!(
            "segment {segment} nm, LJ 9-3: pull-off {f:.5} nN ({:+.2e} vs closed form, {:+.2e} vs Γ of the law)",
            f / closed - 1.0,
            f / own - 1.0
        );
        assert!((f / closed - 1.0).abs() < CLOSED_FORM_TOL);
        assert!((f / own - 1.0).abs() < OWN_LAW_TOL);
        let f = -pull(shifted, segment, 0.01, 1.0);
        eprintln!(
            "segment {segment} nm, shifted 10-4: pull-off {f:.5} nN ({:+.2e} vs Γ of the law)",
            f / own_shifted - 1.0
        );
        assert!((f / own_shifted - 1.0).abs() < OWN_SHIFTED_TOL);
    }
}
