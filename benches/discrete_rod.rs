//! Speed of the discrete rods: segment (stretch + bend) energy+gradient evaluations per second,
//! and the time to a static 50-segment cantilever (αL² = 1) at 1e-6 relative residual by Newton
//! and by FIRE. Run: `cargo bench --bench discrete_rod` (numbers in docs/discrete-rods.md).

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use std::hint::black_box;
use turf::discrete::energy::EnergyTerm;
use turf::discrete::rod::{straight_points, Rod, RodSet, RodStiffness};
use turf::discrete::rod_problems::RodProblem;
use turf::discrete::solve_fire::FireParams;
use turf::discrete::solve_newton::NewtonParams;

const LENGTH: f64 = 7000.0;
const SEGMENTS: usize = 50;
const RODS: usize = 200;

fn wavy_rods() -> (RodSet, Vec<f64>) {
    let stiff = RodStiffness::turf_tube();
    let mut rods = Vec::new();
    let mut x = Vec::new();
    for r in 0..RODS {
        let pts = straight_points(
            [0.0, 100.0 * r as f64, 0.0],
            [1.0, 0.0, 0.0],
            LENGTH,
            SEGMENTS,
        );
        rods.push(Rod::straight(r * (SEGMENTS + 1), &pts, stiff).unwrap());
        for (i, p) in pts.iter().enumerate() {
            let w = 50.0 * (0.3 * i as f64 + r as f64).sin();
            x.extend([p[0], p[1] + w, p[2] - w]);
        }
    }
    (RodSet::new(rods), x)
}

fn segment_evaluations(c: &mut Criterion) {
    let (set, x) = wavy_rods();
    let mut g = vec![0.0; x.len()];
    let mut group = c.benchmark_group("rod_segments");
    group.throughput(Throughput::Elements((RODS * SEGMENTS) as u64));
    group.bench_function("energy_gradient_rodset_200x50", |b| {
        b.iter(|| {
            g.iter_mut().for_each(|v| *v = 0.0);
            black_box(set.energy_gradient(black_box(&x), &mut g))
        })
    });
    group.bench_function("hessian_rodset_200x50", |b| {
        let mut h = Vec::new();
        b.iter(|| {
            h.clear();
            set.hessian(black_box(&x), &mut h);
            black_box(h.len())
        })
    });
    let rod = &set.rods()[0];
    group.throughput(Throughput::Elements(SEGMENTS as u64));
    group.bench_function("energy_gradient_single_rod_50", |b| {
        b.iter(|| black_box(rod.energy_gradient(black_box(&x), &mut g)))
    });
    group.bench_function("hessian_single_rod_50", |b| {
        let mut h = Vec::new();
        b.iter(|| {
            h.clear();
            rod.hessian(black_box(&x), &mut h);
            black_box(h.len())
        })
    });
    group.finish();
}

fn static_cantilever(c: &mut Criterion) {
    let stiff = RodStiffness::turf_tube();
    let p = stiff.bending / (LENGTH * LENGTH);
    let problem = RodProblem::cantilever(SEGMENTS, LENGTH, stiff, [0.0, -p, 0.0]).unwrap();
    let mut group = c.benchmark_group("cantilever_50_static");
    group.sample_size(10);
    group.bench_function("newton_rel_1e-6", |b| {
        b.iter_batched(
            || problem.clone(),
            |mut pr| {
                pr.solve_newton(&NewtonParams {
                    rtol: 1e-6,
                    ..NewtonParams::default()
                })
                .unwrap()
            },
            BatchSize::SmallInput,
        )
    });
    group.bench_function("fire_rel_1e-6", |b| {
        b.iter_batched(
            || problem.clone(),
            |mut pr| {
                pr.solve_fire(&FireParams {
                    rtol: 1e-6,
                    ..FireParams::default()
                })
                .unwrap()
            },
            BatchSize::SmallInput,
        )
    });
    group.finish();
}

criterion_group!(benches, segment_evaluations, static_cantilever);
criterion_main!(benches);
