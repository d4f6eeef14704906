//! An FE run that stops because its material can localise says so: a 400 nm sphere held on the
//! transversely isotropic card of the 9-tube equal-length turf (the card of
//! `continuum::material::ellipticity`'s test, not elliptic past 2 % compression along the
//! tubes), on a block as deep as the turf. The run stops at a few nm (docs/homogenize.md) and
//! its failure names the element where the material is not elliptic.

use turf::continuum::indent::Tangential;
use turf::continuum::material::hyperfoam::{Hyperfoam, HyperfoamTerm};
use turf::continuum::material::transverse_foam::{FibreTerm, TransverseFoam};
use turf::continuum::material::Elastic;
use turf::continuum::{run_indent, FeError, IndentParams, Segment};

#[test]
fn a_run_stopped_by_a_non_elliptic_card_names_where() {
    let mut p = IndentParams::hertz_example();
    p.indenter = turf::continuum::indenter::Indenter::Sphere { radius: 400.0 };
    p.material.elastic = Elastic::Transverse(TransverseFoam {
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
    });
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
