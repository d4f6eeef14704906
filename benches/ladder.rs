//! The cheap rungs of `turf bench`'s ladder under criterion: the LJ 9-3 pull-off at
//! μ = 0.5 by Maugis–Dugdale and the half-space solver, the FE Hertz load at both kinematics,
//! the 50-segment cantilever. The FE pull-offs and the turf chain take seconds to minutes each
//! and are timed by `turf bench` itself (docs/benchmarks.md).
//! Run: `cargo bench --bench ladder` (or `-- --quick`).

use criterion::{criterion_group, criterion_main, Criterion};
use turf::bench::ladder::{hertz_rows, pull_off_rows};
use turf::bench::sweeps::cantilever_deflection;

fn bench_ladder(c: &mut Criterion) {
    let mut group = c.benchmark_group("ladder");
    group.sample_size(10);
    group.bench_function("pull_off_mu0.5_theory_and_halfspace", |b| {
        b.iter(|| pull_off_rows(0.5, false))
    });
    group.bench_function("hertz_fe_small_and_finite", |b| b.iter(hertz_rows));
    group.bench_function("cantilever_50_segments", |b| {
        b.iter(|| cantilever_deflection(50).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench_ladder);
criterion_main!(benches);
