//! Throughput of `hpr` (default parameters) and `exact` on the 3D jittered cubic lattice ball
//! (spacing a = 1, jitter ±0.15a, r = 1.2a; `boundary_scenes::jittered_lattice_ball`), in the
//! same group so that their ratio is meaningful, at all threads of the machine (set
//! `RAYON_NUM_THREADS=1` for the per-core figure). Default size 200k particles;
//! `BOUNDARY_BENCH_N=1000000` (or a comma-separated list) sets the sizes.

use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use boundary_hpr::HprDetector;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};

fn sizes() -> Vec<usize> {
    match std::env::var("BOUNDARY_BENCH_N") {
        Ok(n) => n.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
        Err(_) => vec![200_000],
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("hpr_3d_jittered_ball");
    group.sample_size(10);
    for n in sizes() {
        let (set, _) = boundary_scenes::jittered_lattice_ball(n, 0.15, 42);
        let r = Radius::new(1.2).expect("positive radius");
        group.throughput(Throughput::Elements(set.len() as u64));
        let detector = HprDetector::default();
        group.bench_with_input(BenchmarkId::new("hpr", set.len()), &set, |b, set| {
            b.iter(|| detector.detect_3d(set, r).expect("runs"))
        });
        group.bench_with_input(BenchmarkId::new("exact", set.len()), &set, |b, set| {
            b.iter(|| ExactDetector.detect_3d(set, r).expect("runs"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
