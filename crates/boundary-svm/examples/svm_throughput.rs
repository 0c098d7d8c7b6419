//! `svm` and `exact` in the same run on the jittered ball of the bench (spacing 1, jitter
//! ±0.15, r = 1.2): `cargo run --release -p boundary-svm --example svm_throughput [N [THREADS…]]`
//! (default 1,000,000 particles, 1 and 2 threads). Each method runs twice, alternately (svm,
//! exact, svm, exact), and its faster run is reported. `BOUNDARY_SKIP_EXACT=1` times `svm`
//! only (for `valgrind --tool=callgrind`).
#![allow(clippy::unwrap_used, clippy::print_stdout)] // a measuring tool: failing loudly is fine
use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::jittered_lattice_ball;
use boundary_svm::SvmDetector;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let mut threads: Vec<usize> = args.filter_map(|s| s.parse().ok()).collect();
    if threads.is_empty() {
        threads = vec![1, 2];
    }
    let skip_exact = std::env::var_os("BOUNDARY_SKIP_EXACT").is_some();
    let (set, _) = jittered_lattice_ball(n, 0.15, 42);
    let r = Radius::new(1.2).unwrap();
    let svm = SvmDetector::default();
    for t in threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap();
        let time = |d: &dyn BoundaryDetector| {
            let start = Instant::now();
            let detection = pool.install(|| d.detect_3d(&set, r).unwrap());
            let seconds = start.elapsed().as_secs_f64();
            // A checksum of the margins' bit patterns (svm: the decision values): a change of
            // the float path that should leave the output bit for bit the same must leave it
            // unchanged.
            let checksum = detection
                .margin
                .unwrap_or_default()
                .iter()
                .fold(0u64, |h, m| {
                    (h ^ m.to_bits()).wrapping_mul(0x0100_0000_01b3)
                });
            (seconds, detection.labels.boundary_count(), checksum)
        };
        // Two rounds, each method's faster one reported: the first detection of the process
        // also pays for the allocator's first pages, which the later ones reuse.
        let best = |a: (f64, usize, u64), b: (f64, usize, u64)| if b.0 < a.0 { b } else { a };
        let mut svm_run = time(&svm);
        let mut exact_run = (!skip_exact).then(|| time(&ExactDetector::default()));
        svm_run = best(svm_run, time(&svm));
        if let Some(run) = exact_run {
            exact_run = Some(best(run, time(&ExactDetector::default())));
        }
        let (s_svm, b_svm, c_svm) = svm_run;
        print!(
            "n = {} threads = {t}: svm {s_svm:.3} s ({:.0}/s, {b_svm} boundary, margins {c_svm:016x})",
            set.len(),
            set.len() as f64 / s_svm
        );
        if let Some((s_exact, b_exact, _)) = exact_run {
            println!(
                ", exact {s_exact:.3} s ({:.0}/s, {b_exact} boundary), svm/exact rate {:.2}",
                set.len() as f64 / s_exact,
                s_exact / s_svm
            );
        } else {
            println!();
        }
    }
}
