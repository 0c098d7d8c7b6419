//! `lnm` on a 3D jittered cubic lattice filling a ball (spacing a = 1, jitter ±0.15a,
//! r = 1.2a), both variants on one and on two threads in the same run, so that the speed-up
//! of the parallel passes is read off one report. `BOUNDARY_BENCH_N` sets the particle count
//! (default 1,000,000, the set of the scale tier's thread scan).

use boundary_core::{BoundaryDetector, Radius};
use boundary_lnm::{LnmDetector, LnmParams, LnmVariant};
use boundary_scenes::jittered_lattice_ball;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn bench(c: &mut Criterion) {
    let n = std::env::var("BOUNDARY_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let (set, _) = jittered_lattice_ball(n, 0.15, 42);
    let r = Radius::new(1.2).expect("positive");
    let mut group = c.benchmark_group("lnm_jittered_ball");
    group.sample_size(10);
    group.throughput(Throughput::Elements(set.len() as u64));
    for variant in [LnmVariant::Fast, LnmVariant::Refined] {
        let d = LnmDetector::try_new(LnmParams {
            variant,
            ..Default::default()
        })
        .expect("valid parameters");
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a thread pool");
            group.bench_function(format!("{}_{threads}_threads", variant.name()), |b| {
                b.iter(|| pool.install(|| d.detect_3d(&set, r).expect("runs")))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
