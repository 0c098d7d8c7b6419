//! The incremental tracker against full detections on the Enright-advected jittered sphere
//! (about 2·10^5 particles, r = 1.5h, one thread): 12 steps after the first frame, at several
//! displacements of the fastest particle per step (units of the spacing h). Each pair of
//! benches times the same 12 frames: `full/D` detects each from scratch, `tracker/D` updates a
//! tracker that has seen the first frame (its first, full update is excluded). The ratio of
//! the two is the speed-up; the sweep's sequence tier reports it as a curve with the counts
//! of recomputed particles. Targets: at least 5x at D = 0.01, 2x at D = 0.05.
//! `tracker_ids/0.01` times the same updates through stable ids with the particles reordered
//! every step and a few replaced (the cost of following particles by id).
//! `cargo bench -p boundary-exact --bench tracker`; `BOUNDARY_BENCH_N=20000` and
//! `BOUNDARY_BENCH_DISPLACEMENTS=0.01,0.05` restrict it.
use boundary_core::{AnyParticleSet, BoundaryDetector, Domain, ParticleSet, Radius};
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

/// The id path at 0.01 spacing per step: the same frames, each step's particles listed in
/// another order (a solver that sorts its particles into cells) with their ids, and a tenth
/// of a percent of them leaving and coming back under new ids. `tracker_ids` against the
/// plain `tracker/0.01` of the group above is the cost of following particles by id.
fn bench_ids(c: &mut Criterion) {
    let n = env_list("BOUNDARY_BENCH_N", &[200_000usize])[0];
    let (frames, h) = boundary_scenes::enright_sequence(n, 0.01, 12);
    let r = Radius::new(1.5 * h).expect("positive radius");
    // Step k: particle i listed at place (i·a_k + k) mod n with a_k odd and prime to n, and
    // every 1000th particle (shifted with k) under a new id.
    let steps: Vec<(AnyParticleSet, Vec<u64>)> = frames
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let n = f.len();
            let a = [1usize, 7919, 104729, 1299709][k % 4];
            let mut order: Vec<usize> = (0..n).collect();
            if a != 1 && n % a != 0 {
                order.sort_by_key(|&i| (i * a + k) % n);
            }
            let rows: Vec<_> = order.iter().map(|&i| f.positions()[i]).collect();
            let ids = order
                .iter()
                .map(|&i| {
                    let fresh = (i + k) % 1000 == 0 && k > 0;
                    (i as u64) + if fresh { (k as u64) << 40 } else { 0 }
                })
                .collect();
            (
                ParticleSet::new(rows).expect("finite positions").to_any(),
                ids,
            )
        })
        .collect();
    let mut group = c.benchmark_group("tracker_enright_sphere");
    group.sample_size(10);
    group.bench_with_input(BenchmarkId::new("tracker_ids", 0.01), &steps, |b, steps| {
        b.iter_batched(
            || {
                let mut t = Tracker::new(r, Some(1), Domain::new()).expect("tracker");
                t.update_with_ids(&steps[0].0, &steps[0].1)
                    .expect("first update");
                t
            },
            |mut t| {
                for (set, ids) in &steps[1..] {
                    t.update_with_ids(set, ids).expect("update");
                }
                t
            },
            BatchSize::PerIteration,
        )
    });
    group.finish();
}

criterion_group!(benches, bench, bench_ids);
criterion_main!(benches);
