//! Quick throughput check: `cargo run --release -p boundary-ge --example ge_throughput [N [R]]`.
//! Jittered cubic lattice ball (spacing 1, jitter ±0.15, r = R, default 1.2: the generator of
//! `boundary-exact`'s throughput example), `ge` at depth 6 and `exact` for reference in the same
//! run, 1 and 2 threads. `R` about 2.2 gives a dense neighbourhood (about 150 neighbours within
//! 2r). `BOUNDARY_SKIP_EXACT=1` skips `exact` (for instruction counts of `ge` alone).
#![allow(clippy::unwrap_used, clippy::print_stdout)] // a measuring tool: failing loudly is fine
use boundary_core::{BoundaryDetector, ParticleSet, Point, Radius};
use boundary_exact::ExactDetector;
use boundary_ge::GeDetector;
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
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(400_000);
    let r: f64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1.2);
    let skip_exact = std::env::var_os("BOUNDARY_SKIP_EXACT").is_some();
    let threads: &[usize] = if skip_exact { &[1] } else { &[1, 2] };
    let set = ball(n);
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
            vec![Box::new(GeDetector::default()), Box::new(ExactDetector)]
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
