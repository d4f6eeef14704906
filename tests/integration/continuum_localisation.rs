//! Localisation of a turf card (`continuum::material::ellipticity`): the transversely isotropic
//! card of the 9-tube equal-length turf (`turf homogenize --terms 1` on its axial, lateral and
//! shear curves, 2026-12-04; its fibre term, α = 242, is the tubes' collective buckling step)
//! loses strong ellipticity past that step, and an FE run that stops on it says where.

use turf::continuum::indent::Tangential;
use turf::continuum::material::ellipticity::in_plane_minimum;
use turf::continuum::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
use turf::continuum::material::transverse_foam::{FibreTerm, TransverseFoam};
use turf::continuum::material::{Deformation, Elastic, Material};
use turf::continuum::{run_indent, FeError, IndentParams, Segment};

/// The 9-tube equal-length turf's transversely isotropic card.
fn turf_card() -> TransverseFoam {
    TransverseFoam {
        matrix: Hyperfoam {
            terms: vec![HyperfoamTerm {
                mu: 3.210171062971217e-5,
                alpha: 0.010000000136118464,
                beta: 0.0,
            }],
        },
        fibre: vec![FibreTerm {
            mu: 0.2342467233819765,
            alpha: 242.36654836409758,
        }],
        shear: 0.004080080229341831,
    }
}

/// Compressed along the tubes with no lateral strain (F = diag(1, λ), ν = 0) the card is
/// elliptic at 1 % and not at 2 %: a kink band costs nothing past the buckling step.
#[test]
fn the_turf_card_loses_ellipticity_past_its_buckling_step() {
    let card = turf_card();
    for (lz, elliptic) in [(1.0, true), (0.99, true), (0.98, false), (0.95, false)] {
        let r = card
            .response(&Deformation::from_c([1.0, lz * lz, 1.0, 0.0]), &[], 0.0)
            .unwrap();
        let q = in_plane_minimum(&r, [[1.0, 0.0], [0.0, lz]], 180);
        println!(
            "λ_Z = {lz}: least acoustic eigenvalue {:.4e} GPa at {:.0}°",
            q.eigenvalue, q.normal_deg
        );
        assert_eq!(q.eigenvalue > 0.0, elliptic, "λ_Z = {lz}: {q:?}");
    }
}

/// A 400 nm sphere held on the card, on a block as deep as the turf: the run stops at a few nm
/// (docs/homogenize.md) and its failure names the element where the card is not elliptic.
#[test]
fn a_run_stopped_by_a_non_elliptic_card_names_where() {
    let mut p = IndentParams::hertz_example();
    p.indenter = turf::continuum::indenter::Indenter::Sphere { radius: 400.0 };
    p.material.elastic = Elastic::Transverse(turf_card());
    p.mesh.depth = Some(2019.6);
    p.contact.tangential = Tangential::Stick;
    p.schedule = vec![Segment::Load {
        to: 50.0,
        rate: 10.0,
    }];
    p.solver.increments = 10;
    // the stop, not how small an increment gets before it, is what is tested
    p.solver.max_cutbacks = 4;
    match run_indent(&p, &mut |_| {}) {
        Err(FeError::Stopped(r)) => {
            let why = r.failure.unwrap_or_default();
            println!("{why}");
            let reached = r.rows.last().unwrap().depth_nm;
            assert!(reached > 0.5 && reached < 10.0, "stopped at {reached} nm");
            assert!(why.contains("not elliptic at element"), "{why}");
        }
        other => panic!("expected a stop, got {:?}", other.map(|r| r.rows.len())),
    }
}
