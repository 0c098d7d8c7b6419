//! Quick throughput check: `cargo run --release -p boundary-exact --example throughput [N]
//! [THREADS,...]`. Jittered cubic lattice ball (spacing 1, jitter ±0.15, r = 1.2), by default
//! on 1 and 2 threads (`... throughput 50000 1` runs one thread only, e.g. under callgrind).
#![allow(clippy::unwrap_used)] // a measuring tool: failing loudly is fine
use boundary_core::{BoundaryDetector, ParticleSet, Point, Radius};
use boundary_exact::ExactDetector;
use std::time::Instant;

fn ball(n_target: usize) -> ParticleSet<3> {
    let radius = (3.0 * n_target as f64 / (4.0 * std::f64::consts::PI)).cbrt();
    let m = radius.ceil() as i64;
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut pts = Vec::new();
    for x in -m..=m {
        for y in -m..=m {
            for z in -m..=m {
                let p = Point::<3>::new(x as f64, y as f64, z as f64);
                if p.norm() <= radius {
                    pts.push(p.map(|c| c + 0.3 * (uniform() - 0.5)));
                }
            }
        }
    }
    ParticleSet::new(pts).unwrap()
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let set = ball(n);
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
        let d = pool.install(|| ExactDetector.detect_3d(&set, r).unwrap());
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
