//! The turf's lateral and shear RVE tests (issue 19, item 2): the nominal stress each records,
//! (1/V₀) dE*/dε from the configuration (the image pairs' virial and the clamps' reactions, or
//! the tips' reactions), against central differences of the equilibrium energy E*(ε); and the
//! scene key that selects them.

use crate::discrete_compression::{newton, relaxed_system};
use turf::discrete::drive::CompressionParams;
use turf::discrete::rve::{drive_rve, RveLoading, RveRecord};

/// Where the derivative is checked: two steps in, contacts already loaded.
const STRAIN: f64 = 0.02;
/// Strain offset of the central difference: 2e-4 × 200 nm = 0.04 nm of box, small against
/// every contact's range (the van der Waals switch acts over ~1 nm).
const FD_STEP: f64 = 2e-4;
/// The stress against the energy difference: the central difference's error δ² σ''/6 and the
/// solver residual (1e-6 nN per dof) over the step are both below 1e-5 of σ here (measured
/// agreement 1e-7 lateral, 4e-6 shear); 1e-4 relative is ten times above them.
const FD_TOL: f64 = 1e-4;

/// The last record of a one-step drive from the relaxed small turf to `strain`, with V₀.
fn equilibrium(loading: RveLoading, strain: f64, steps: usize) -> (RveRecord, f64) {
    let (mut sys, mut x) = relaxed_system();
    let volume = sys.area * sys.height(&x);
    let params = CompressionParams {
        strain_max: strain,
        steps,
        unload: false,
        retract: None,
    };
    let run = drive_rve(&mut sys, &mut x, loading, &params, &newton(), &mut |_| {}).unwrap();
    assert_eq!(run.stopped, None);
    let recs = run.records;
    (*recs.last().unwrap(), volume)
}

#[test]
fn the_lateral_and_shear_stresses_are_the_derivatives_of_the_equilibrium_energy() {
    for loading in [RveLoading::Lateral, RveLoading::Shear] {
        let (rec, volume) = equilibrium(loading, STRAIN, 2);
        let (plus, _) = equilibrium(loading, STRAIN + FD_STEP, 2);
        let (minus, _) = equilibrium(loading, STRAIN - FD_STEP, 2);
        let fd = (plus.energy - minus.energy) / (2.0 * FD_STEP * volume);
        eprintln!(
            "{loading:?}: σ = {:e} GPa, (1/V₀) dE*/dε = {fd:e} GPa, contacts {}",
            rec.stress, rec.state.contacts
        );
        assert!(
            rec.stress != 0.0,
            "{loading:?}: the test must load the turf"
        );
        assert!(
            (fd - rec.stress).abs() < FD_TOL * rec.stress.abs(),
            "{loading:?}: σ = {} GPa, from the energy {fd} GPa",
            rec.stress
        );
    }
}

/// Squeezed laterally far beyond what the tubes can make room for (90 % in three steps), the
/// drive stops at the first equilibrium with tubes through each other and keeps the steps
/// before it; no kept state has tubes overlapping beyond the limit.
#[test]
fn a_lateral_drive_that_pushes_tubes_through_each_other_stops_and_keeps_the_steps_before() {
    let (mut sys, mut x) = relaxed_system();
    let params = CompressionParams {
        strain_max: 0.9,
        steps: 3,
        unload: false,
        retract: None,
    };
    let run = drive_rve(
        &mut sys,
        &mut x,
        RveLoading::Lateral,
        &params,
        &newton(),
        &mut |_| {},
    )
    .unwrap();
    let why = run
        .stopped
        .expect("the tubes cannot fit in a tenth of the box");
    eprintln!("{why}; {} steps kept", run.records.len());
    assert!(why.contains("interpenetrate"), "{why}");
    assert!(run.records.len() < 4);
    assert!(run
        .records
        .iter()
        .all(|r| r.state.min_gap >= -turf::discrete::rve::OVERLAP_LIMIT_NM));
}
