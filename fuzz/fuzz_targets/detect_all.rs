//! Arbitrary small particle sets through every registered detector: `Ok`, one label per
//! particle, and no false negative against `exact` for a certified method.
#![no_main]

use boundary::{detector_by_name, methods, AnyParticleSet, ParticleSet, Point, Radius};
use libfuzzer_sys::fuzz_target;

fn coord(b: &[u8]) -> f64 {
    // A coarse grid of quarters: duplicates, ties, lines and lattices are frequent.
    f64::from(i16::from_le_bytes([b[0], b[1]]) % 64) * 0.25
}

fuzz_target!(|data: &[u8]| {
    if data.len() < 3 {
        return;
    }
    let r = 0.25 + f64::from(data[0] % 16) * 0.125;
    let body = &data[2..];
    let set: AnyParticleSet = if data[1] & 1 == 1 {
        let pts: Vec<Point<3>> = body
            .chunks_exact(6)
            .take(48)
            .map(|c| Point::<3>::new(coord(&c[0..2]), coord(&c[2..4]), coord(&c[4..6])))
            .collect();
        ParticleSet::new(pts).expect("finite").into()
    } else {
        let pts: Vec<Point<2>> = body
            .chunks_exact(4)
            .take(48)
            .map(|c| Point::<2>::new(coord(&c[0..2]), coord(&c[2..4])))
            .collect();
        ParticleSet::new(pts).expect("finite").into()
    };
    let r = Radius::new(r).expect("positive");
    let truth = detector_by_name("exact")
        .expect("registered")
        .detect(&set, r)
        .expect("exact never fails on a valid set")
        .labels;
    for name in methods() {
        let detector = detector_by_name(name).expect("registered");
        let labels = detector
            .detect(&set, r)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .labels;
        assert_eq!(labels.len(), set.len(), "{name}");
        if detector.certified() {
            for i in 0..set.len() {
                assert!(
                    labels.is_boundary(i) || !truth.is_boundary(i),
                    "{name}: particle {i} is a false negative"
                );
            }
        }
    }
});
