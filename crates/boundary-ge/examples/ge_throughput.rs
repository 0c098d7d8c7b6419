//! Quick throughput check: `cargo run --release -p boundary-ge --example ge_throughput [N [R]]`.
//! Jittered cubic lattice ball (`boundary_scenes::jittered_lattice_ball`: spacing 1, jitter
//! ±0.15, seed 7; r = R, default 1.2), `ge` at depth 6 and `exact` for reference in the same
//! run, 1 and 2 threads. `R` about 2.2 gives a dense neighbourhood (about 150 neighbours within
//! 2r). `BOUNDARY_SKIP_EXACT=1` skips `exact` (for instruction counts of `ge` alone).
#![allow(clippy::unwrap_used, clippy::print_stdout)] // a measuring tool: failing loudly is fine
use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use boundary_ge::GeDetector;
use boundary_scenes::jittered_lattice_ball;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(400_000);
    let r: f64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1.2);
    let skip_exact = std::env::var_os("BOUNDARY_SKIP_EXACT").is_some();
    let threads: &[usize] = if skip_exact { &[1] } else { &[1, 2] };
    let set = jittered_lattice_ball(n, 0.15, 7).0;
    let r = Radius::new(r).unwrap();
    for &threads in threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut rates = Vec::new();
        let detectors: Vec<Box<dyn BoundaryDetector>> = if skip_exact {
            vec![Box::new(GeDetector::default())]
        } else {
            vec![
                Box::new(GeDetector::default()),
                Box::new(ExactDetector::default()),
            ]
        };
        for det in &detectors {
            let t = Instant::now();
            let d = pool.install(|| det.detect_3d(&set, r).unwrap());
            let s = t.elapsed().as_secs_f64();
            let rate = set.len() as f64 / s;
            rates.push(rate);
            println!(
                "{} n = {} r = {} threads = {threads}: {:.3} s, {:.0} particles/s, {} boundary",
                det.name(),
                set.len(),
                r.get(),
                s,
                rate,
                d.labels.boundary_count()
            );
        }
        if let [ge, exact] = rates[..] {
            println!(
                "ge/exact rate ratio, threads = {threads}: {:.4}",
                ge / exact
            );
        }
    }
}
