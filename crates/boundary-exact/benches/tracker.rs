//! The incremental tracker against full detections on the Enright-advected jittered sphere
//! (about 2·10^5 particles, r = 1.5h, one thread): 12 steps after the first frame, at several
//! displacements of the fastest particle per step (units of the spacing h). Each pair of
//! benches times the same 12 frames: `full/D` detects each from scratch, `tracker/D` updates a
//! tracker that has seen the first frame (its first, full update is excluded). The ratio of
//! the two is the speed-up; the sweep's sequence tier reports it as a curve with the counts
//! of recomputed particles. Targets: at least 5x at D = 0.01, 2x at D = 0.05.
//! `cargo bench -p boundary-exact --bench tracker`; `BOUNDARY_BENCH_N=20000` and
//! `BOUNDARY_BENCH_DISPLACEMENTS=0.01,0.05` restrict it.
use boundary_core::{BoundaryDetector, Domain, Radius};
use boundary_exact::{ExactDetector, Tracker};
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};

fn env_list<T: std::str::FromStr + Clone>(name: &str, default: &[T]) -> Vec<T> {
    match std::env::var(name) {
        Ok(v) => v.split(',').filter_map(|s| s.trim().parse().ok()).collect(),
        Err(_) => default.to_vec(),
    }
}

fn bench(c: &mut Criterion) {
    let n = env_list("BOUNDARY_BENCH_N", &[200_000usize])[0];
    let displacements = env_list(
        "BOUNDARY_BENCH_DISPLACEMENTS",
        &[0.001, 0.003, 0.01, 0.03, 0.05, 0.1, 0.2, 0.5],
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    let mut group = c.benchmark_group("tracker_enright_sphere");
    group.sample_size(10);
    for d in displacements {
        let (frames, h) = boundary_scenes::enright_sequence(n, d, 12);
        let frames: Vec<_> = frames.iter().map(|f| f.to_any()).collect();
        let r = Radius::new(1.5 * h).expect("positive radius");
        group.bench_with_input(BenchmarkId::new("full", d), &frames, |b, frames| {
            b.iter(|| {
                pool.install(|| {
                    for f in &frames[1..] {
                        ExactDetector::default().detect(f, r).expect("detection");
                    }
                })
            })
        });
        group.bench_with_input(BenchmarkId::new("tracker", d), &frames, |b, frames| {
            b.iter_batched(
                || {
                    let mut t = Tracker::new(r, Some(1), Domain::new()).expect("tracker");
                    t.update(&frames[0]).expect("first update");
                    t
                },
                |mut t| {
                    for f in &frames[1..] {
                        t.update(f).expect("update");
                    }
                    t
                },
                BatchSize::PerIteration,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
