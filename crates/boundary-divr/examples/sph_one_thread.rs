//! One-thread speed of `exact` and the five one-pass SPH-sum detectors on the 3D jittered
//! lattice ball (spacing 1, jitter ±0.15, seed 7, r = 1.2), measured alternating in one run so
//! that the ratios to `exact` are meaningful on a shared machine.
//!
//! ```text
//! cargo run --release -p boundary-divr --example sph_one_thread -- [N] [ROUNDS] [METHODS]
//! ```
//! `N` particles (default 1,000,000), `ROUNDS` alternating rounds (default 3; the best of
//! each method is reported), `METHODS` a comma-separated subset of
//! `exact,divr,marrone,muller,asymmetry,randles` (default all; with one method and one round
//! it is a profiling target for callgrind). `BOUNDARY_THREADS=2` runs them on a pool of two
//! threads instead of one (for a thread scan under `perf stat`, whose task clock shows the
//! work the threads add).

use boundary_asymmetry::AsymmetryDetector;
use boundary_core::{BoundaryDetector, ParticleSet, Radius};
use boundary_divr::DivrDetector;
use boundary_exact::ExactDetector;
use boundary_marrone::MarroneDetector;
use boundary_muller::MullerDetector;
use boundary_randles::RandlesDetector;
use boundary_scenes::jittered_lattice_ball;
use std::io::Write;
use std::time::Instant;

fn run(name: &str, set: &ParticleSet<3>, r: Radius) -> usize {
    let detector: Box<dyn BoundaryDetector> = match name {
        "exact" => Box::new(ExactDetector::default()),
        "divr" => Box::new(DivrDetector::default()),
        "marrone" => Box::new(MarroneDetector::default()),
        "muller" => Box::new(MullerDetector::default()),
        "asymmetry" => Box::new(AsymmetryDetector::default()),
        "randles" => Box::new(RandlesDetector::default()),
        other => panic!("unknown method {other}"),
    };
    detector
        .detect_3d(set, r)
        .expect("the ball is a valid scene")
        .labels
        .boundary_count()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args
        .get(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let rounds: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(3);
    let methods: Vec<String> = args
        .get(3)
        .map(|s| s.split(',').map(str::to_owned).collect())
        .unwrap_or_else(|| {
            ["exact", "divr", "marrone", "muller", "asymmetry", "randles"]
                .map(str::to_owned)
                .to_vec()
        });
    let (set, _) = jittered_lattice_ball(n, 0.15, 7);
    let r = Radius::new(1.2).expect("positive");
    let threads: usize = std::env::var("BOUNDARY_THREADS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let mut best = vec![f64::INFINITY; methods.len()];
    let mut counts = vec![0; methods.len()];
    let mut out = std::io::stdout().lock();
    for round in 0..rounds {
        for (k, m) in methods.iter().enumerate() {
            let start = Instant::now();
            counts[k] = one.install(|| run(m, &set, r));
            let t = start.elapsed().as_secs_f64();
            best[k] = best[k].min(t);
            writeln!(out, "round {round} {m:>9} {t:7.3} s").expect("stdout");
        }
    }
    let exact = methods.iter().position(|m| m == "exact").map(|k| best[k]);
    writeln!(
        out,
        "{} particles, {threads} thread(s), best of {rounds}",
        set.len()
    )
    .expect("stdout");
    writeln!(
        out,
        "method     time_s  Mparticles/s  speed/exact  boundary"
    )
    .expect("stdout");
    for (k, m) in methods.iter().enumerate() {
        let rate = set.len() as f64 / best[k] / 1e6;
        let ratio = exact.map_or(f64::NAN, |e| e / best[k]);
        writeln!(
            out,
            "{m:<9} {:7.3}  {rate:12.3}  {ratio:11.2}  {}",
            best[k], counts[k]
        )
        .expect("stdout");
    }
}
