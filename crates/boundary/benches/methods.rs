//! Every registered method in one run, so that the ratios between them are meaningful: one
//! criterion group per method on each of two sets:
//! - `ball`: the 3D jittered cubic lattice ball (spacing a = 1, jitter ±0.15a, r = 1.2a, about
//!   58 neighbours within 2r; `boundary_scenes::jittered_lattice_ball`), `BOUNDARY_BENCH_N`
//!   particles (default 1,000,000);
//! - `dense`: a jittered cubic lattice block (jitter ±0.15a) of `BOUNDARY_BENCH_DENSE_N`
//!   particles (default 32,768) at r = 2.2a: about 360 neighbours within 2r, where methods
//!   that look at the whole 2r neighbourhood slow down.
//!
//! One group per method (`<method>/ball`, `<method>/dense`), each detection on
//! `BOUNDARY_BENCH_THREADS` threads (default 1: per-core rates). `BOUNDARY_BENCH_METHODS`
//! (comma-separated) restricts the methods. Example:
//! `BOUNDARY_BENCH_N=1000000 cargo bench -p boundary --bench methods`.

use boundary::{detector_by_name, methods, AnyParticleSet, ParticleSet, Radius};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};

fn env_usize(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(default)
}

/// A jittered cubic lattice block of about `n` particles, spacing 1, jitter ±0.15.
fn dense_block(n: usize) -> AnyParticleSet {
    let side = (n as f64).cbrt().round().max(2.0) as usize;
    let rows = boundary_scenes::certify::jittered_lattice::<3>(side, 0.15, 11);
    ParticleSet::from_rows(&rows)
        .expect("generated coordinates are finite")
        .into()
}

fn bench(c: &mut Criterion) {
    let threads = env_usize("BOUNDARY_BENCH_THREADS", 1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let chosen: Option<Vec<String>> = std::env::var("BOUNDARY_BENCH_METHODS")
        .ok()
        .map(|v| v.split(',').map(|s| s.trim().to_owned()).collect());
    let (ball, _) =
        boundary_scenes::jittered_lattice_ball(env_usize("BOUNDARY_BENCH_N", 1_000_000), 0.15, 7);
    let sets: [(&str, AnyParticleSet, f64); 2] = [
        ("ball", ball.into(), 1.2),
        (
            "dense",
            dense_block(env_usize("BOUNDARY_BENCH_DENSE_N", 32_768)),
            2.2,
        ),
    ];
    for method in methods() {
        if chosen
            .as_ref()
            .is_some_and(|c| !c.iter().any(|m| m == method))
        {
            continue;
        }
        let detector = detector_by_name(method).expect("a registered method");
        let mut group = c.benchmark_group(method);
        group.sample_size(10);
        for (name, set, r) in &sets {
            let r = Radius::new(*r).expect("a valid radius");
            group.throughput(Throughput::Elements(set.len() as u64));
            group.bench_function(*name, |b| {
                b.iter(|| pool.install(|| detector.detect(set, r).expect("runs")))
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
