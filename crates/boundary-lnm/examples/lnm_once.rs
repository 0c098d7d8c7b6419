//! `lnm` detections on a generated 3D jittered-lattice ball (spacing 1, jitter ±0.15, r = 1.2),
//! for profilers and thread scans: `lnm_once N VARIANT RUNS` with `VARIANT` one of `fast`,
//! `refined`, or `none` (the set is generated and nothing detected: the baseline to subtract
//! from a `valgrind --tool=callgrind` count). Prints the boundary count and the median wall
//! time of `RUNS` detections (default 1) on the current rayon pool (`RAYON_NUM_THREADS`).

#![allow(clippy::print_stdout)] // an example: its output is the point

use boundary_core::{BoundaryDetector, Radius};
use boundary_lnm::{LnmDetector, LnmParams, LnmVariant};
use boundary_scenes::jittered_lattice_ball;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(300_000);
    let variant = args.next().unwrap_or_else(|| "fast".to_owned());
    let runs: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1).max(1);
    let (set, _) = jittered_lattice_ball(n, 0.15, 42);
    let Some(variant) = LnmVariant::from_name(&variant) else {
        println!("{} particles generated, no detection", set.len());
        return;
    };
    let d = LnmDetector::try_new(LnmParams {
        variant,
        ..Default::default()
    })
    .expect("valid parameters");
    let r = Radius::new(1.2).expect("positive");
    let mut times = Vec::new();
    let mut boundary = 0;
    for _ in 0..runs {
        let start = Instant::now();
        boundary = d.detect_3d(&set, r).expect("runs").labels.boundary_count();
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{} of {} boundary; median {:.4} s over {runs} runs on {} threads",
        boundary,
        set.len(),
        times[runs / 2],
        rayon::current_num_threads()
    );
}
