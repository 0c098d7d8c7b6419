//! Throughput of `ge`, `ia` (both depth 6) and `exact` on the 3D jittered cubic lattice filling
//! a ball (spacing a = 1, jitter ±0.15a, r = 1.2a), in one run so that their ratios are
//! meaningful. `BOUNDARY_BENCH_N` sets the particle count (default 200,000; the figure is
//! 1,000,000). Per-core rates: run under `RAYON_NUM_THREADS=1`.

use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use boundary_ge::{GeDetector, GeParams};
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
    let mut group = c.benchmark_group(format!("jittered_ball_{}", set.len()));
    group.sample_size(10);
    group.throughput(Throughput::Elements(set.len() as u64));
    group.bench_function("ge_depth6", |b| {
        b.iter(|| {
            GeDetector::try_new(GeParams { depth: 6 })
                .expect("depth in range")
                .detect_3d(&set, r)
                .expect("runs")
        })
    });
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
