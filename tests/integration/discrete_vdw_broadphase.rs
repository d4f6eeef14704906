//! The broadphase against brute force, and thread-count independence of the vdW energy
//! (issue 7, item 3; DESIGN: same numbers with 1 and 2 threads).

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use turf::discrete::broadphase::{brute_force_pairs, Broadphase, PeriodicBox, SegmentSet};
use turf::discrete::energy::EnergyTerm;
use turf::discrete::vdw::VdwParams;
use turf::discrete::vdw_term::{TubeLayout, VdwTerm};

/// Random short segments in a periodic box (some crossing its faces), as a flat vector.
fn random_segments(rng: &mut Pcg64, n: usize, l: f64) -> (SegmentSet, Vec<f64>) {
    let mut x = Vec::new();
    let mut nodes = Vec::new();
    let mut reach = Vec::new();
    for i in 0..n {
        let p = [
            rng.random::<f64>() * l,
            rng.random::<f64>() * l,
            rng.random::<f64>() * l,
        ];
        let d = [
            rng.random::<f64>() - 0.5,
            rng.random::<f64>() - 0.5,
            rng.random::<f64>() - 0.5,
        ];
        x.extend(p);
        x.extend([p[0] + 8.0 * d[0], p[1] + 8.0 * d[1], p[2] + 8.0 * d[2]]);
        nodes.push([2 * i, 2 * i + 1]);
        reach.push(1.0 + rng.random::<f64>());
    }
    (SegmentSet { nodes, reach }, x)
}

#[test]
fn bvh_pairs_equal_brute_force_pairs_and_stay_valid_within_the_skin() {
    let mut rng = Pcg64::seed_from_u64(7);
    let l = 40.0;
    let skin = 0.8;
    for pbox in [
        PeriodicBox::default(),
        PeriodicBox {
            lx: Some(l),
            ly: Some(l),
        },
        PeriodicBox {
            lx: None,
            ly: Some(l),
        },
    ] {
        let (segs, mut x) = random_segments(&mut rng, 300, l);
        // keep everything but segments 0..10 with each other (exercises the filter)
        let keep = |p: &turf::discrete::broadphase::SegmentPair| !(p.a < 10 && p.b < 10);
        let mut bp = Broadphase::new(segs.clone(), pbox, skin, &x, &keep);
        assert_eq!(bp.pairs(), brute_force_pairs(&segs, &x, &pbox, skin, &keep));
        assert!(bp.pairs().iter().any(|p| p.shift != [0, 0]) || pbox.lx.is_none());
        for step in 0..6 {
            // small moves (< skin/2): the list is kept and contains every pair within reach
            for v in x.iter_mut() {
                *v += 0.2 * (rng.random::<f64>() - 0.5) * 0.5 * skin;
            }
            let rebuilt = bp.update(&x, &keep);
            let within_reach = brute_force_pairs(&segs, &x, &pbox, 0.0, &keep);
            assert!(within_reach
                .iter()
                .all(|p| bp.pairs().binary_search(p).is_ok()));
            assert!(!rebuilt, "step {step}: moves below skin/2 keep the list");
            // a large move forces a rebuild, refitting the tree; the list is then exact
            x[0] += skin;
            assert!(bp.update(&x, &keep));
            assert_eq!(bp.pairs(), brute_force_pairs(&segs, &x, &pbox, skin, &keep));
        }
    }
}

#[test]
fn energy_and_gradient_are_identical_with_one_and_two_threads() {
    let mut rng = Pcg64::seed_from_u64(11);
    // 12 wavy vertical tubes of radius 5 nm packed in a 40 nm periodic box
    let mut x = Vec::new();
    let mut tubes = Vec::new();
    for _ in 0..12 {
        let base = [rng.random::<f64>() * 40.0, rng.random::<f64>() * 40.0];
        let phase = rng.random::<f64>() * 6.0;
        tubes.push(TubeLayout {
            first_node: x.len() / 3,
            nodes: 21,
            radius: 5.0,
        });
        for k in 0..21 {
            let z = 5.0 * k as f64;
            x.extend([base[0] + 4.0 * (0.1 * z + phase).sin(), base[1], z]);
        }
    }
    let params = VdwParams {
        radius_ref: 5.0,
        ..VdwParams::default()
    };
    let pbox = PeriodicBox {
        lx: Some(40.0),
        ly: Some(40.0),
    };
    let mut term = VdwTerm::new(&params, &tubes, &x, pbox).unwrap();
    term.prepare(&x);
    assert!(term.pairs().len() > 50);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut g = vec![0.0; x.len()];
            let e = term.energy_gradient(&x, &mut g);
            let mut h = Vec::new();
            term.hessian(&x, &mut h);
            (e, g, h)
        })
    };
    let (e1, g1, h1) = run(1);
    let (e2, g2, h2) = run(2);
    assert!(e1 != 0.0);
    assert_eq!(e1.to_bits(), e2.to_bits());
    assert!(g1.iter().zip(&g2).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert_eq!(h1, h2);
}
