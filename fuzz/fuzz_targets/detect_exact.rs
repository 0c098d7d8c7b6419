//! Arbitrary small particle sets through `exact`: never panics, one label per particle, and
//! agreement with a brute-force check of the definition on sampled sphere points where the
//! margin is clear of a tie.
#![no_main]

use boundary_core::{BoundaryDetector, ParticleSet, Point, Radius};
use boundary_exact::ExactDetector;
use libfuzzer_sys::fuzz_target;

fn coord(b: &[u8]) -> f64 {
    // Small integers and halves on a coarse grid: many duplicates, ties and lattices.
    f64::from(i16::from_le_bytes([b[0], b[1]]) % 64) * 0.25
}

fuzz_target!(|data: &[u8]| {
    if data.len() < 3 {
        return;
    }
    let r = 0.25 + f64::from(data[0] % 16) * 0.125;
    let dim3 = data[1] & 1 == 1;
    let body = &data[2..];
    if dim3 {
        let pts: Vec<Point<3>> = body
            .chunks_exact(6)
            .take(64)
            .map(|c| Point::<3>::new(coord(&c[0..2]), coord(&c[2..4]), coord(&c[4..6])))
            .collect();
        let set = ParticleSet::new(pts).expect("finite");
        let d = ExactDetector
            .detect_3d(&set, Radius::new(r).expect("positive"))
            .expect("exact never fails on a valid set");
        assert_eq!(d.labels.len(), set.len());
        check_sampled(
            &set,
            r,
            d.labels.as_slice(),
            d.margin.as_deref().unwrap_or(&[]),
        );
    } else {
        let pts: Vec<Point<2>> = body
            .chunks_exact(4)
            .take(64)
            .map(|c| Point::<2>::new(coord(&c[0..2]), coord(&c[2..4])))
            .collect();
        let set = ParticleSet::new(pts).expect("finite");
        let d = ExactDetector
            .detect_2d(&set, Radius::new(r).expect("positive"))
            .expect("exact never fails on a valid set");
        assert_eq!(d.labels.len(), set.len());
        check_sampled(
            &set,
            r,
            d.labels.as_slice(),
            d.margin.as_deref().unwrap_or(&[]),
        );
    }
});

/// A particle labelled interior must have every sampled point of its sphere covered.
fn check_sampled<const D: usize>(set: &ParticleSet<D>, r: f64, labels: &[bool], margin: &[f64]) {
    let p = set.positions();
    for i in 0..set.len() {
        if labels[i] || margin[i] > -1e-6 * r {
            continue;
        }
        for k in 0..200 {
            let dir = if D == 2 {
                let a = k as f64 * std::f64::consts::TAU / 200.0;
                Point::<D>::from_fn(|c, _| if c == 0 { a.cos() } else { a.sin() })
            } else {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / 200.0;
                let phi = k as f64 * 2.399_963_229_728_653;
                let s = (1.0 - z * z).sqrt();
                Point::<D>::from_fn(|c, _| [s * phi.cos(), s * phi.sin(), z][c])
            };
            let x = p[i] + dir * r;
            let covered =
                (0..set.len()).any(|j| p[j] != p[i] && (x - p[j]).norm() <= r * (1.0 + 1e-9));
            assert!(
                covered,
                "particle {i} labelled interior but a point of its sphere is uncovered"
            );
        }
    }
}
