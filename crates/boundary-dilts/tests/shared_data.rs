//! `dilts` reproduces the independent boundary counts of `../shared/data/README.md`.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_scenes::{shared_set, SHARED_SCENES};

use boundary_core::{BoundaryDetector, Radius};
use boundary_dilts::DiltsDetector;
use std::time::Instant;

#[test]
fn reproduces_the_reference_boundary_counts() {
    let mut report = Vec::new();
    let mut mismatch = false;
    for &(_, dim, file, r, _, expected, _) in SHARED_SCENES {
        let radius = Radius::new(r).unwrap();
        let start = Instant::now();
        let det = if dim == 2 {
            let Some(set) = shared_set::<2>(file).unwrap() else {
                continue;
            };
            DiltsDetector::default().detect_2d(&set, radius)
        } else {
            let Some(set) = shared_set::<3>(file).unwrap() else {
                continue;
            };
            DiltsDetector::default().detect_3d(&set, radius)
        }
        .unwrap();
        let count = det.labels.boundary_count();
        mismatch |= count != expected;
        // Timing is reported for information only (includes reading the CSV).
        report.push(format!(
            "{file} r={r}: {count} (expected {expected}) in {:.2} s",
            start.elapsed().as_secs_f64()
        ));
    }
    println!("{}", report.join("\n"));
    assert!(!mismatch, "count mismatch:\n{}", report.join("\n"));
}
