//! `ge` is certified: no exact-boundary particle is ever labelled interior (Rec = 1 against
//! `exact`) at every depth 1..=8, on the generated fixture scenes, the shared scenes and the hard
//! cases; and deeper meshes never label fewer particles interior.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{BoundaryDetector, Labels, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_ge::{GeDetector, GeParams, MAX_DEPTH};
use boundary_scenes::certify::{certify_every_case, check_depths, jittered_lattice, Case};
use proptest::prelude::*;

fn by_depth(set: &boundary_core::AnyParticleSet, r: Radius, max: u32) -> Vec<Labels> {
    (1..=max)
        .map(|d| {
            GeDetector::try_new(GeParams { depth: d })
                .unwrap()
                .detect(set, r)
                .unwrap()
                .labels
        })
        .collect()
}

/// The generated fixtures, the shared scenes, the hard cases and the near-tie lattices of
/// `boundary_scenes::certify::near_tie_cases` (within 1e-10 relative or 4 ulps of their tie
/// radius, 2D and 3D, where the exact labels flip): no false negative at depths 1 to 8.
#[test]
fn every_scene_and_hard_case_depth_1_to_8() {
    let radius = |case: &Case| Radius::new(case.radius).unwrap();
    let report = certify_every_case(
        |case| {
            ExactDetector::default()
                .detect(&case.set, radius(case))
                .unwrap()
                .labels
        },
        |case, depth| {
            GeDetector::try_new(GeParams { depth })
                .unwrap()
                .detect(&case.set, radius(case))
                .unwrap()
                .labels
        },
        8,
    );
    match report {
        Ok(lines) => lines.iter().for_each(|line| println!("{line}")),
        Err(failures) => panic!("{failures:#?}"),
    }
}

#[test]
fn coincident_particles_do_not_cover_each_other() {
    let pair = ParticleSet::from_rows(&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]).unwrap();
    let labels = GeDetector::try_new(GeParams { depth: 8 })
        .unwrap()
        .detect_3d(&pair, Radius::new(1.0).unwrap())
        .unwrap()
        .labels;
    assert_eq!(labels.boundary_count(), 2);
}

#[test]
fn deep_meshes_approach_the_exact_labels_on_jittered_lattices() {
    // Away from ties, a deep enough mesh decides nearly every particle.
    for (set, r) in [
        (
            ParticleSet::from_rows(&jittered_lattice::<3>(10, 0.15, 9))
                .unwrap()
                .to_any(),
            1.2,
        ),
        (
            ParticleSet::from_rows(&jittered_lattice::<2>(30, 0.15, 9))
                .unwrap()
                .to_any(),
            0.9,
        ),
    ] {
        let r = Radius::new(r).unwrap();
        let truth = ExactDetector::default().detect(&set, r).unwrap().labels;
        let fps = check_depths(&truth, &by_depth(&set, r, 8)).unwrap();
        assert!(fps[7] * 50 <= set.len(), "FP by depth {fps:?}");
        assert!(fps[0] > fps[7], "FP by depth {fps:?}");
    }
}

#[test]
fn parameters_are_validated_never_clamped() {
    let d = GeDetector::default();
    assert_eq!(d.describe().to_string(), "depth=6");
    assert_eq!(d.params(), &GeParams::default());
    let d = GeDetector::try_new(GeParams { depth: 3 }).unwrap();
    assert_eq!(
        (d.params().depth, d.describe().to_string()),
        (3, "depth=3".into())
    );
    for bad in [0, MAX_DEPTH + 1, u32::MAX] {
        let err = GeDetector::try_new(GeParams { depth: bad }).unwrap_err();
        assert!(err.to_string().contains(&bad.to_string()), "{err}");
    }
    assert!(GeDetector::try_new(GeParams { depth: MAX_DEPTH }).is_ok());
}

#[test]
fn owned_particles_get_the_labels_of_the_whole_set() {
    let set = ParticleSet::from_rows(&jittered_lattice::<3>(8, 0.2, 3))
        .unwrap()
        .to_any();
    let r = Radius::new(1.1).unwrap();
    let all = GeDetector::default().detect(&set, r).unwrap().labels;
    let owned = GeDetector::default().detect_owned(&set, 100, r).unwrap();
    assert_eq!(owned.labels.as_slice(), &all.as_slice()[..100]);
    assert!(GeDetector::default()
        .detect_owned(&set, set.len() + 1, r)
        .is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    #[test]
    fn random_sets_have_no_false_negatives(
        pts in prop::collection::vec(prop::array::uniform3(0.0f64..3.0), 1..100),
        r in 0.3f64..1.2,
        depth in 1u32..7,
    ) {
        let set = ParticleSet::from_rows(&pts).unwrap().to_any();
        let radius = Radius::new(r).unwrap();
        let exact = ExactDetector::default().detect(&set, radius).unwrap().labels;
        let ge = GeDetector::try_new(GeParams { depth }).unwrap().detect(&set, radius).unwrap().labels;
        for i in 0..pts.len() {
            prop_assert!(!exact.is_boundary(i) || ge.is_boundary(i), "particle {}", i);
        }
    }

    #[test]
    fn random_2d_sets_have_no_false_negatives(
        pts in prop::collection::vec(prop::array::uniform2(0.0f64..3.0), 1..100),
        r in 0.3f64..1.2,
        depth in 1u32..9,
    ) {
        let set = ParticleSet::from_rows(&pts).unwrap().to_any();
        let radius = Radius::new(r).unwrap();
        let exact = ExactDetector::default().detect(&set, radius).unwrap().labels;
        let ge = GeDetector::try_new(GeParams { depth }).unwrap().detect(&set, radius).unwrap().labels;
        for i in 0..pts.len() {
            prop_assert!(!exact.is_boundary(i) || ge.is_boundary(i), "particle {}", i);
        }
    }
}
