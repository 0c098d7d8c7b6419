//! `dilts` reproduces the independent boundary counts of `../shared/data/README.md`.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use boundary_core::{BoundaryDetector, Radius};
use boundary_dilts::DiltsDetector;
use std::time::Instant;

#[test]
fn reproduces_the_reference_boundary_counts() {
    let mut report = Vec::new();
    let mut mismatch = false;
    for &(file, dim, r, expected) in common::SHARED_SCENES {
        let radius = Radius::new(r).unwrap();
        let start = Instant::now();
        let det = if dim == 2 {
            DiltsDetector.detect_2d(&common::read_csv::<2>(file), radius)
        } else {
            DiltsDetector.detect_3d(&common::read_csv::<3>(file), radius)
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
