//! One `hpr` detection for profiling: the dense jittered block of the cross-method
//! bench (`N` particles, default 32,768, spacing 1, jitter ±0.15, r = 2.2) or, with the
//! argument `ball`, the jittered lattice ball (`N`, default 100,000, r = 1.2). Prints the
//! time, the rate and a hash of the labels (equal hashes: equal labels). For instruction
//! counts on one thread (`TARGET_DIR`: the build folder, `target` unless configured):
//!
//! ```sh
//! cargo build --release -p boundary-hpr --example profile_dense
//! RAYON_NUM_THREADS=1 N=8000 valgrind --tool=callgrind TARGET_DIR/release/examples/profile_dense
//! ```
#![allow(clippy::print_stdout)] // an example reports on stdout

use boundary_core::{AnyParticleSet, BoundaryDetector, ParticleSet, Radius};
use boundary_hpr::HprDetector;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let ball = std::env::args().nth(1).is_some_and(|a| a == "ball");
    let n: Option<usize> = std::env::var("N").ok().and_then(|v| v.trim().parse().ok());
    let (set, r): (AnyParticleSet, f64) = if ball {
        let (b, _) = boundary_scenes::jittered_lattice_ball(n.unwrap_or(100_000), 0.15, 7);
        (b.into(), 1.2)
    } else {
        let side = (n.unwrap_or(32_768) as f64).cbrt().round().max(2.0) as usize;
        let rows = boundary_scenes::certify::jittered_lattice::<3>(side, 0.15, 11);
        (ParticleSet::from_rows(&rows)?.into(), 2.2)
    };
    let start = Instant::now();
    let labels = HprDetector::default().detect(&set, Radius::new(r)?)?.labels;
    let seconds = start.elapsed().as_secs_f64();
    // FNV-1a over the labels.
    let hash = labels
        .as_slice()
        .iter()
        .fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        });
    println!(
        "{} particles, r = {r}: {} boundary, labels {hash:016x}, {seconds:.3} s, {:.0} particles/s",
        labels.len(),
        labels.boundary_count(),
        labels.len() as f64 / seconds
    );
    Ok(())
}
