//! A sticking sphere (`indenter.tangential = "stick"`, `turf::continuum::contact::Stick`) on the
//! linear-elastic block of the Hertz check, small kinematics. Goodman (1962): the normal and
//! tangential contact problems couple through (1 − 2ν)/(1 − ν), so a surface held where it
//! touched carries the frictionless (Hertz) load when ν → 1/2 and more than it when ν < 1/2,
//! where a frictionless surface slides inward under the sphere and the held one cannot.

use turf::continuum::element::Kinematics;
use turf::continuum::indent::Tangential;
use turf::continuum::material::linear::LinearElastic;
use turf::continuum::material::Elastic;
use turf::continuum::{run_indent, IndentParams, IndentResult, Segment};

fn run(poisson: f64, tangential: Tangential) -> IndentResult {
    let mut p = IndentParams::hertz_example();
    p.kinematics = Kinematics::Small;
    p.material.elastic = Elastic::Linear(LinearElastic {
        youngs: 0.7,
        poisson,
    });
    p.contact.tangential = tangential;
    // two segments: a snapshot at 5 nm and one at 10 nm
    p.schedule = vec![
        Segment::Load {
            to: 5.0,
            rate: 10.0,
        },
        Segment::Load {
            to: 10.0,
            rate: 10.0,
        },
    ];
    p.solver.increments = 5;
    run_indent(&p, &mut |_| {}).unwrap()
}

/// How far the surface nodes within radius `within` moved radially between the snapshots at
/// 5 and 10 nm: the largest |Δu_r|, nm.
fn radial_change(r: &IndentResult, within: f64) -> f64 {
    let (a, b) = (&r.snapshots[0], &r.snapshots[1]);
    r.mesh
        .surface
        .iter()
        .filter(|&&n| r.mesh.nodes[n][0] > 0.0 && r.mesh.nodes[n][0] < within)
        .map(|&n| (b.displacement[2 * n] - a.displacement[2 * n]).abs())
        .fold(0.0, f64::max)
}

#[test]
fn stick_carries_the_frictionless_load_when_incompressible_and_more_below() {
    for (poisson, low, high) in [(0.49, 0.995, 1.01), (0.0, 1.01, 1.15)] {
        let (free, held) = (
            run(poisson, Tangential::Frictionless),
            run(poisson, Tangential::Stick),
        );
        let (a, b) = (free.rows.last().unwrap(), held.rows.last().unwrap());
        let ratio = b.load_nN / a.load_nN;
        println!(
            "ν = {poisson}: frictionless {:.3} nN, stick {:.3} nN, ratio {ratio:.4}; contact radius {:.2} / {:.2} nm",
            a.load_nN, b.load_nN, a.contact_radius_nm, b.contact_radius_nm
        );
        assert!((low..high).contains(&ratio), "ν = {poisson}: ratio {ratio}");
        if poisson == 0.0 {
            // the surface in contact at 5 nm (inside 0.8 of its contact radius there): sliding
            // inward as the sphere goes on to 10 nm when frictionless, held where it is when
            // sticking (to the penalty's compliance)
            let a5 = |r: &IndentResult| {
                r.rows
                    .iter()
                    .find(|row| (row.depth_nm - 5.0).abs() < 1e-9)
                    .unwrap()
                    .contact_radius_nm
            };
            let (s_free, s_held) = (
                radial_change(&free, 0.8 * a5(&free)),
                radial_change(&held, 0.8 * a5(&held)),
            );
            println!("largest |Δu_r| from 5 to 10 nm inside 0.8a(5 nm): frictionless {s_free:.4} nm, held {s_held:.2e} nm");
            assert!(s_free > 0.1, "frictionless surface should slide inward");
            // the penalty's compliance τ/k_t (k_t = k_n = 100E*/h₀) allows ≈ 1e-3 of the slide
            assert!(s_held < 1e-2 * s_free, "held surface slid {s_held} nm");
        }
    }
}
