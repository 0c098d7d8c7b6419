//! The tracker against full detections on the Enright-advected jittered sphere, one thread:
//! `cargo run --release -p boundary-exact --example tracker_ratio [N] [DISPLACEMENTS,...]`
//! (fastest particle's displacement per step in spacings; 12 steps each). Prints per step the
//! particles recomputed, and the ratio of the full detection's time to the update's, first
//! update excluded.
#![allow(clippy::unwrap_used)] // a measuring tool: failing loudly is fine
use boundary_core::{BoundaryDetector, Domain, Radius};
use boundary_exact::{ExactDetector, Tracker};
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(200_000);
    let displacements: Vec<f64> = std::env::args()
        .nth(2)
        .map(|s| s.split(',').filter_map(|t| t.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![0.001, 0.003, 0.01, 0.03, 0.05, 0.1, 0.2, 0.5]);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for d in displacements {
        let (frames, h) = boundary_scenes::enright_sequence(n, d, 12);
        let r = Radius::new(1.5 * h).unwrap();
        let mut tracker = Tracker::new(r, Some(1), Domain::new()).unwrap();
        let (mut full_s, mut track_s, mut counts) = (0.0, 0.0, vec![]);
        let mut first = (0.0, 0.0);
        for (k, f) in frames.iter().enumerate() {
            let set = f.to_any();
            let t = Instant::now();
            let full = pool.install(|| ExactDetector::default().detect(&set, r).unwrap());
            let tf = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let labels = tracker.update(&set).unwrap().clone();
            let tt = t.elapsed().as_secs_f64();
            assert_eq!(labels, full.labels);
            if k > 0 {
                full_s += tf;
                track_s += tt;
            } else {
                first = (tf, tt);
            }
            counts.push(tracker.recomputed());
        }
        println!(
            "n = {} displacement {d}: first update {:.3} s (full {:.3} s); then full {:.3} s, \
             tracker {:.3} s, ratio {:.2}; recomputed {:?}",
            frames[0].len(),
            first.1,
            first.0,
            full_s,
            track_s,
            full_s / track_s,
            counts
        );
    }
}
