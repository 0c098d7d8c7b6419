//! Throughput of `ia` (depth 6) and `exact` on a 3D jittered cubic lattice filling a ball
//! (spacing a = 1, jitter ±0.15a, r = 1.2a), in the same run so that their ratio is meaningful.
//! `BOUNDARY_BENCH_N` sets the particle count (default 200,000; the figure is 1M).

use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use boundary_ia::{IaDetector, IaParams};
use boundary_scenes::jittered_lattice_ball;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn bench(c: &mut Criterion) {
    let n = std::env::var("BOUNDARY_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200_000);
    let (set, _) = jittered_lattice_ball(n, 0.15, 42);
    let r = Radius::new(1.2).expect("positive");
    let mut group = c.benchmark_group("jittered_ball");
    group.sample_size(10);
    group.throughput(Throughput::Elements(set.len() as u64));
    group.bench_function("ia_depth6", |b| {
        b.iter(|| {
            IaDetector::try_new(IaParams { depth: 6 })
                .expect("depth in range")
                .detect_3d(&set, r)
                .expect("runs")
        })
    });
    group.bench_function("exact", |b| {
        b.iter(|| ExactDetector::default().detect_3d(&set, r).expect("runs"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
