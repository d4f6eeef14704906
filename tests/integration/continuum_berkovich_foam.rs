//! The seed's turf indentation without adhesion, end to end: the blunt Berkovich (1.8 µm
//! spherical tip, 70.3° cone beyond the tip depth of 105 nm) into the Table 5.1 hyperfoam
//! (μ = 0.35 GPa, α = 18.8, β = 0) with one Prony term (μ̄ = 0.4, τ = 3 s) acting on the whole
//! stress (seed 5.8): load to 200 nm, hold, unload.
//!
//! Reference for the hold: shear and bulk relax alike, so after a long hold at fixed depth
//! every internal variable has relaxed to μ̄ times the elastic stress of the current
//! deformation, the stress field is (1 − μ̄) times an elastic one, and the load tends to
//! (1 − μ̄) P_e(δ), P_e the purely elastic load at the same depth — exactly, up to e^(−t/τ).

use turf::continuum::{run_indent, IndentParams, Segment};

/// The hold lasts 15τ: e^(−15) ≈ 3e-7 of the relaxing part remains.
const HOLD_TIME_S: f64 = 45.0;
/// Relative tolerance on (1 − μ̄) P_e: the penalty contact's penetration changes with the load
/// level (≈ 3e-3 h₀ of √(p) dependence, see continuum::contact), well below 1e-3 of the depth.
const RELAXED_TOL: f64 = 2e-3;

fn coarse(mut p: IndentParams) -> IndentParams {
    p.mesh.elements_per_radius = 6.0;
    p.solver.increments = 10;
    p
}

#[test]
fn berkovich_hyperfoam_load_hold_unload() {
    let load = Segment::Load {
        to: 200.0,
        rate: 10.0,
    };
    let mut visco = coarse(IndentParams::hyperfoam_example());
    visco.schedule = vec![
        load,
        Segment::Hold { time: HOLD_TIME_S },
        Segment::Unload {
            to: 0.0,
            rate: 10.0,
        },
    ];
    let mut elastic = coarse(IndentParams::hyperfoam_example());
    elastic.material.prony.clear();
    elastic.schedule = vec![load];
    let v = run_indent(&visco, &mut |_| {}).unwrap();
    let e = run_indent(&elastic, &mut |_| {}).unwrap();
    let p_elastic = e.rows.last().unwrap().load_nN;

    let at = |t: f64| {
        v.rows
            .iter()
            .position(|r| (r.time_s - t).abs() < 1e-9)
            .unwrap()
    };
    let (peak, hold_end) = (at(20.0), at(20.0 + HOLD_TIME_S));
    let loading = &v.rows[..=peak];
    assert!(loading.windows(2).all(|w| w[1].load_nN > w[0].load_nN));
    assert!(loading
        .windows(2)
        .all(|w| w[1].contact_radius_nm > w[0].contact_radius_nm));
    // relaxation during loading: below the elastic load, above the fully relaxed one
    let p_peak = v.rows[peak].load_nN;
    assert!(p_peak < p_elastic && p_peak > 0.6 * p_elastic);
    // the hold relaxes monotonically to (1 − μ̄) P_e
    let hold = &v.rows[peak..=hold_end];
    assert!(hold.windows(2).all(|w| w[1].load_nN < w[0].load_nN));
    let relaxed = v.rows[hold_end].load_nN / (0.6 * p_elastic) - 1.0;
    println!(
        "P_e = {p_elastic:.1} nN, peak {p_peak:.1} nN, relaxed/(0.6 P_e) − 1 = {relaxed:+.2e}"
    );
    assert!(relaxed.abs() < RELAXED_TOL, "{relaxed}");
    // unloading: no adhesion, so the load never turns tensile and ends at zero
    let unload = &v.rows[hold_end..];
    assert!(unload.iter().all(|r| r.load_nN >= 0.0));
    assert_eq!(unload.last().unwrap().load_nN, 0.0);
    // the deepest point is on the cone (tip depth 105 nm)
    assert!(v.rows[peak].depth_nm > 105.0);
}
