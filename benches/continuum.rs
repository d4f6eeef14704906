//! Speed of the continuum solver: a ≈30,000-element graded mesh through 50 Hertz increments
//! (rigid sphere R = 1 µm into a linear block to δ = 10 nm). Prints the split between assembly
//! and linear solves and the peak memory, then lets criterion time the whole run.
//! `cargo bench --bench continuum` (figures in docs/benchmarks-continuum.md).

use criterion::{criterion_group, criterion_main, Criterion};
use turf::continuum::{run_indent, IndentParams, Segment};

fn params() -> IndentParams {
    let mut p = IndentParams::hertz_example();
    p.mesh.elements_per_radius = 75.0; // ≈ 30k elements on the default 200a block
    p.mesh.fine_depth = 1.0;
    p.mesh.fine_radius = 2.0;
    p.schedule = vec![Segment::Load {
        to: 10.0,
        rate: 10.0,
    }];
    p.solver.increments = 50;
    p
}

/// Peak resident memory of this process, kB (Linux).
fn peak_rss_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    s.lines()
        .find(|l| l.starts_with("VmHWM:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}

fn bench(c: &mut Criterion) {
    let p = params();
    let r = run_indent(&p, &mut |_| {}).expect("the Hertz benchmark converges");
    let s = r.stats;
    println!(
        "mesh: {} elements, {} dofs; {} increments, {} Newton iterations, {} cutbacks",
        r.mesh_report.elements, r.mesh_report.dofs, s.increments, s.newton_iterations, s.cutbacks
    );
    println!(
        "wall {:.2} s: mesh {:.3} s, assembly {:.2} s ({} evaluations), solves {:.2} s ({} factorisations, {} solves, {} LU fallbacks); peak RSS {:?} kB",
        s.wall_s,
        s.mesh_s,
        s.assembly.assembly_s,
        s.assembly.assemblies,
        s.assembly.solve_s,
        s.assembly.factorisations,
        s.assembly.solves,
        s.assembly.lu_fallbacks,
        peak_rss_kb()
    );
    let mut g = c.benchmark_group("continuum");
    g.sample_size(10);
    g.bench_function("hertz_30k_elements_50_increments", |b| {
        b.iter(|| run_indent(&p, &mut |_| {}).expect("converges"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
