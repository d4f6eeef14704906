//! Cost of the half-space solver: pull-off at μ = 1 with the refinement study (the headline
//! "under a second" figure), one trace, and the dense Newton solve against grid size.
//! Run: `cargo bench --bench halfspace` (or `-- --quick`).

use criterion::{criterion_group, criterion_main, Criterion};
use turf::halfspace::{pull_off, trace_curve, HalfspaceParams, Problem};
use turf::laws::LjKind;

fn bench_halfspace(c: &mut Criterion) {
    let mut group = c.benchmark_group("halfspace");
    group.sample_size(10);
    let params = HalfspaceParams::default();
    for kind in [LjKind::Lj93, LjKind::Lj104] {
        let problem = Problem::scaled(1.0, kind).unwrap();
        group.bench_function(format!("pull_off_mu1_{kind:?}"), |b| {
            b.iter(|| pull_off(&problem, &params).unwrap())
        });
    }
    // trace cost against grid size (cells per process zone)
    let problem = Problem::scaled(1.0, LjKind::Lj93).unwrap();
    for cells in [6.0, 12.0, 24.0, 48.0] {
        let p = HalfspaceParams {
            cells_per_zone: cells,
            ..params
        };
        group.bench_function(format!("trace_mu1_cells{cells}"), |b| {
            b.iter(|| trace_curve(&problem, &p).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench_halfspace);
criterion_main!(benches);
