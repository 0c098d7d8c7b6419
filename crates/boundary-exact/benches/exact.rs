//! Throughput of `exact` on the 3D jittered cubic lattice ball (spacing a, jitter ±0.15a,
//! r = 1.2a) at 100k and 1M particles, 1 and 2 threads.
//! `cargo bench -p boundary-exact`; `BOUNDARY_BENCH_N=100000` restricts the sizes.
use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};

fn sizes() -> Vec<usize> {
    match std::env::var("BOUNDARY_BENCH_N") {
        Ok(n) => n.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
        Err(_) => vec![100_000, 1_000_000],
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("exact_3d_jittered_ball");
    group.sample_size(10);
    for n in sizes() {
        let (set, _) = boundary_scenes::jittered_lattice_ball(n, 0.15, 7);
        let r = Radius::new(1.2).expect("positive radius"); // spacing a = 1
        group.throughput(Throughput::Elements(set.len() as u64));
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool");
            group.bench_with_input(
                BenchmarkId::new(format!("{threads}_threads"), set.len()),
                &set,
                |b, set| b.iter(|| pool.install(|| ExactDetector::default().detect_3d(set, r))),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
