//! The exact detector reproduces the independent boundary counts of `../shared/data/README.md`.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_scenes::{shared_set, SHARED_SCENES};

use boundary_core::{BoundaryDetector, Radius};
use boundary_exact::{ExactDetector, TIE_TOLERANCE};

#[test]
fn reproduces_the_reference_boundary_counts() {
    let mut report = Vec::new();
    for &(_, dim, file, r, _, expected, _) in SHARED_SCENES {
        let radius = Radius::new(r).unwrap();
        let det = if dim == 2 {
            let Some(set) = shared_set::<2>(file).unwrap() else {
                continue;
            };
            ExactDetector::default().detect_2d(&set, radius)
        } else {
            let Some(set) = shared_set::<3>(file).unwrap() else {
                continue;
            };
            ExactDetector::default().detect_3d(&set, radius)
        }
        .unwrap();
        let margins = det.margin.as_ref().unwrap();
        let near_ties = margins
            .iter()
            .filter(|m| m.abs() <= 1e3 * TIE_TOLERANCE * r)
            .count();
        report.push(format!(
            "{file} r={r}: {} (expected {expected}), {near_ties} within 1e-6 r of a tie",
            det.labels.boundary_count()
        ));
        if det.labels.boundary_count() != expected {
            panic!("count mismatch:\n{}", report.join("\n"));
        }
    }
    println!("{}", report.join("\n"));
}
