//! One-thread time of `exact` and the five one-pass SPH-sum detectors (`divr` with
//! DualSPHysics' thresholds, `marrone`, `muller`, `asymmetry`, `randles`) on a 3D jittered
//! cubic lattice filling a ball (spacing a = 1, jitter ±0.15a, r = 1.2a), in the same run so
//! that their ratios to `exact` are meaningful. Each SPH method is the volume pass (a sweep
//! over the cell pairs on one thread) and one replay of the neighbour lists it keeps; `marrone`
//! adds an eigen-decomposition and its scan, `randles` a Cholesky test. `BOUNDARY_BENCH_N`
//! sets the particle count (default 200,000; the speed targets are stated at 1,000,000, see
//! the `sph_one_thread` example for that size).

use boundary_asymmetry::AsymmetryDetector;
use boundary_core::{BoundaryDetector, Radius};
use boundary_divr::DivrDetector;
use boundary_exact::ExactDetector;
use boundary_marrone::MarroneDetector;
use boundary_muller::MullerDetector;
use boundary_randles::RandlesDetector;
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
    let detectors: [(&str, Box<dyn BoundaryDetector>); 6] = [
        ("exact", Box::new(ExactDetector::default())),
        ("divr", Box::new(DivrDetector::default())),
        ("marrone", Box::new(MarroneDetector::default())),
        ("muller", Box::new(MullerDetector::default())),
        ("asymmetry", Box::new(AsymmetryDetector::default())),
        ("randles", Box::new(RandlesDetector::default())),
    ];
    let mut group = c.benchmark_group("jittered_ball_one_thread");
    group.sample_size(10);
    group.throughput(Throughput::Elements(set.len() as u64));
    for (name, detector) in &detectors {
        group.bench_function(*name, |b| {
            b.iter(|| one.install(|| detector.detect_3d(&set, r).expect("runs")))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
