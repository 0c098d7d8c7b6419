//! One-thread time of `divr` (DualSPHysics' thresholds) and `marrone` on a 3D jittered cubic
//! lattice filling a ball (spacing a = 1, jitter ±0.15a, r = 1.2a), in the same run so that
//! their ratio is meaningful: `divr` is one neighbour pass after the volumes, `marrone` the
//! same pass with a matrix, its eigen-decomposition and the scan. `BOUNDARY_BENCH_N` sets the
//! particle count (default 200,000; the speed target is stated at 1,000,000).

use boundary_core::{BoundaryDetector, Radius};
use boundary_divr::DivrDetector;
use boundary_marrone::MarroneDetector;
use boundary_scenes::jittered_lattice_ball;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn bench(c: &mut Criterion) {
    let n = std::env::var("BOUNDARY_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200_000);
    let (set, _) = jittered_lattice_ball(n, 0.15, 42);
    let r = Radius::new(1.2).expect("positive");
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let mut group = c.benchmark_group("jittered_ball_one_thread");
    group.sample_size(10);
    group.throughput(Throughput::Elements(set.len() as u64));
    group.bench_function("divr", |b| {
        b.iter(|| one.install(|| DivrDetector::default().detect_3d(&set, r).expect("runs")))
    });
    group.bench_function("marrone", |b| {
        b.iter(|| one.install(|| MarroneDetector::default().detect_3d(&set, r).expect("runs")))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
