//! Speed of the tube–tube van der Waals term: point-pair evaluations per second with
//! contacts by the point quadrature and by the tabulated kernel, segment evaluations per second
//! of the whole turf energy with and without contacts, and the broadphase update of 100 tubes
//! × 100 segments.
//!
//! `cargo bench --bench discrete_vdw`; the figures go to docs/benchmarks.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use turf::discrete::broadphase::{Broadphase, SegmentSet};
use turf::discrete::energy::EnergyTerm;
use turf::discrete::rod::{Rod, RodSet, RodStiffness};
use turf::discrete::turf::{generate_turf, TurfParams};
use turf::discrete::vdw::{VdwKernel, VdwParams};
use turf::discrete::vdw_term::VdwTerm;

/// 100 wavy tubes of 100 segments, as in `benches/scenes/turf_100x100.toml` (2 µm tubes,
/// 20 nm segments, tilt 0.1 rad, waviness 50 nm, 1 µm periodic box) as generated — overlap-free,
/// with contacts only where tubes grew within range (the generator refuses overlapping turfs).
fn turf_100x100(kernel: VdwKernel) -> (VdwTerm, Vec<f64>, turf::discrete::turf::Turf) {
    let p = TurfParams {
        density: 1e-4,
        box_x: 1000.0,
        box_y: 1000.0,
        length_mean: 2000.0,
        length_cv: 0.05,
        segment_length: 20.0,
        wave_amplitude: 50.0,
        wave_length: 1000.0,
        tilt_spread: 0.1,
        seed: 3,
        ..TurfParams::default()
    };
    let turf = generate_turf(&p).unwrap();
    let x = turf.coordinates();
    let params = VdwParams {
        kernel,
        ..VdwParams::default()
    };
    let mut term = VdwTerm::new(&params, &turf.layout(), &x, turf.periodic).unwrap();
    term.prepare(&x);
    (term, x, turf)
}

fn bench(c: &mut Criterion) {
    let (term, x, turf) = turf_100x100(VdwKernel::Quadrature);
    let (tabulated, _, _) = turf_100x100(VdwKernel::Tabulated);
    let point_pairs: usize = term
        .evaluate_pairs(&x, false)
        .iter()
        .map(|r| r.point_pairs)
        .sum();
    println!(
        "turf 100 × 100: {} segment pairs listed, {} point pairs in range",
        term.pairs().len(),
        point_pairs
    );
    let mut g = c.benchmark_group("vdw");
    g.sample_size(10);
    g.throughput(Throughput::Elements(point_pairs as u64));
    g.bench_function("energy_gradient_turf_100x100", |b| {
        let mut grad = vec![0.0; x.len()];
        b.iter(|| black_box(term.energy_gradient(black_box(&x), &mut grad)))
    });
    g.bench_function("hessian_turf_100x100", |b| {
        let mut h = Vec::new();
        b.iter(|| {
            h.clear();
            term.hessian(black_box(&x), &mut h);
            black_box(h.len())
        })
    });
    g.bench_function("energy_gradient_turf_100x100_tabulated", |b| {
        let mut grad = vec![0.0; x.len()];
        b.iter(|| black_box(tabulated.energy_gradient(black_box(&x), &mut grad)))
    });
    g.bench_function("hessian_turf_100x100_tabulated", |b| {
        let mut h = Vec::new();
        b.iter(|| {
            h.clear();
            tabulated.hessian(black_box(&x), &mut h);
            black_box(h.len())
        })
    });
    // the whole turf energy (rods + contacts) against the rods alone, per segment
    let rods = RodSet::new(
        turf.tubes
            .iter()
            .zip(turf.layout())
            .map(|(t, l)| Rod::natural(l.first_node, &t.nodes, RodStiffness::turf_tube()).unwrap())
            .collect(),
    );
    g.throughput(Throughput::Elements(rods.segments() as u64));
    g.bench_function("segments_without_contacts_turf_100x100", |b| {
        let mut grad = vec![0.0; x.len()];
        b.iter(|| black_box(rods.energy_gradient(black_box(&x), &mut grad)))
    });
    g.bench_function("segments_with_contacts_turf_100x100", |b| {
        let mut grad = vec![0.0; x.len()];
        b.iter(|| {
            black_box(
                rods.energy_gradient(black_box(&x), &mut grad)
                    + term.energy_gradient(black_box(&x), &mut grad),
            )
        })
    });
    g.throughput(Throughput::Elements(term.pairs().len() as u64));
    let layout = turf.layout();
    let nodes: Vec<[usize; 2]> = layout
        .iter()
        .flat_map(|l| (0..l.nodes - 1).map(move |k| [l.first_node + k, l.first_node + k + 1]))
        .collect();
    let segs = SegmentSet {
        reach: vec![21.25; nodes.len()],
        nodes,
    };
    let keep = |_: &turf::discrete::broadphase::SegmentPair| true;
    let mut bp = Broadphase::new(segs, turf.periodic, 1.0, &x, &keep);
    let mut moved = x.clone();
    let mut sign = 1.0;
    g.bench_function("broadphase_rebuild_and_pairs_100x100", |b| {
        b.iter(|| {
            // every node moves by more than skin/2: a full rebuild and pair collection
            sign = -sign;
            for (m, x0) in moved.iter_mut().zip(&x) {
                *m = x0 + sign * 0.6;
            }
            black_box(bp.update(&moved, &keep))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
