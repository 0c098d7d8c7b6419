//! Quick throughput check: `cargo run --release -p boundary-exact --example throughput [N]
//! [THREADS,...]`. Jittered cubic lattice ball (spacing 1, jitter ±0.15, r = 1.2), by default
//! on 1 and 2 threads (`... throughput 50000 1` runs one thread only, e.g. under callgrind).
#![allow(clippy::unwrap_used)] // a measuring tool: failing loudly is fine
use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::jittered_lattice_ball;
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let set = jittered_lattice_ball(n, 0.15, 7).0;
    let r = Radius::new(1.2).unwrap();
    let threads: Vec<usize> = std::env::args()
        .nth(2)
        .map(|s| s.split(',').filter_map(|t| t.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![1, 2]);
    for threads in threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let t = Instant::now();
        let d = pool.install(|| ExactDetector::default().detect_3d(&set, r).unwrap());
        let s = t.elapsed().as_secs_f64();
        // A checksum of the margins' bit patterns: a change of the float path that should
        // leave the output bit for bit the same must leave it unchanged.
        let checksum = d.margin.unwrap().iter().fold(0u64, |h, m| {
            (h ^ m.to_bits()).wrapping_mul(0x0100_0000_01b3)
        });
        println!(
            "n = {} threads = {threads}: {:.3} s, {:.0} particles/s, {} boundary, margins {checksum:016x}",
            set.len(),
            s,
            set.len() as f64 / s,
            d.labels.boundary_count()
        );
    }
}
