//! Prediction throughput of `svm` (features included) against `exact` on a 3D jittered cubic
//! lattice filling a ball (spacing a = 1, jitter ±0.15a, r = 1.2a), in the same run so that
//! their ratio is meaningful; also the cascade `refine=exact`. Run at one thread for
//! particles/s per core: `RAYON_NUM_THREADS=1 cargo bench -p boundary-svm`.
//! `BOUNDARY_BENCH_N` sets the particle count (default 100,000); the 1M ball:
//! `RAYON_NUM_THREADS=1 BOUNDARY_BENCH_N=1000000 cargo bench -p boundary-svm --
//! 'jittered_ball/(svm|exact)$'`.

use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::jittered_lattice_ball;
use boundary_svm::{Refine, SvmDetector, SvmParams};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn bench(c: &mut Criterion) {
    let n = std::env::var("BOUNDARY_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100_000);
    let (set, _) = jittered_lattice_ball(n, 0.15, 42);
    let r = Radius::new(1.2).expect("positive");
    let svm = SvmDetector::default();
    let cascade = SvmDetector::try_new(SvmParams {
        refine: Refine::Exact,
        ..SvmParams::default()
    })
    .expect("valid parameters");
    let mut group = c.benchmark_group("jittered_ball");
    group.sample_size(10);
    group.throughput(Throughput::Elements(set.len() as u64));
    group.bench_function("svm", |b| b.iter(|| svm.detect_3d(&set, r).expect("runs")));
    group.bench_function("svm_refine_exact", |b| {
        b.iter(|| cascade.detect_3d(&set, r).expect("runs"))
    });
    group.bench_function("exact", |b| {
        b.iter(|| ExactDetector::default().detect_3d(&set, r).expect("runs"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
