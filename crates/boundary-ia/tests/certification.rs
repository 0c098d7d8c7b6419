//! `ia` is certified: no exact-boundary particle is ever labelled interior (Rec = 1 against
//! `exact`), at every depth 1..=8, on the generated fixture scenes, the shared scenes and the
//! hard cases; and deeper trees never label fewer particles interior.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{AnyParticleSet, BoundaryDetector, Labels, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_ia::{IaDetector, IaParams, MAX_DEPTH};
use boundary_scenes::certify::{certify_every_case, check_depths, jittered_lattice, Case};
use proptest::prelude::*;

fn by_depth(set: &AnyParticleSet, r: Radius, max: u32) -> Vec<Labels> {
    (1..=max)
        .map(|d| {
            IaDetector::try_new(IaParams { depth: d })
                .unwrap()
                .detect(set, r)
                .unwrap()
                .labels
        })
        .collect()
}

/// The generated fixtures, the shared scenes, the hard cases (lattices at and around their
/// tie radii, duplicates and near-duplicates, far offsets, flat and tiny sets) and the near-tie
/// lattices of `boundary_scenes::certify::near_tie_cases` (within 1e-10 relative or 4 ulps of
/// their tie radius, 2D and 3D, where the exact labels flip).
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
            IaDetector::try_new(IaParams { depth })
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
    let pair = ParticleSet::from_rows(&[[0.0, 0.0], [0.0, 0.0]]).unwrap();
    let labels = IaDetector::try_new(IaParams { depth: 8 })
        .unwrap()
        .detect_2d(&pair, Radius::new(1.0).unwrap())
        .unwrap()
        .labels;
    assert_eq!(labels.boundary_count(), 2);
}

#[test]
fn deep_trees_approach_the_exact_labels_on_jittered_lattices() {
    // Away from ties, a deep enough tree decides every particle: the false positives left at
    // depth 8 are only particles whose exact margin is tiny.
    let set = ParticleSet::from_rows(&jittered_lattice::<3>(10, 0.15, 9))
        .unwrap()
        .to_any();
    let r = Radius::new(1.2).unwrap();
    let truth = ExactDetector::default().detect(&set, r).unwrap().labels;
    let fps = check_depths(&truth, &by_depth(&set, r, 8)).unwrap();
    assert!(fps[7] * 50 <= set.len(), "FP by depth {fps:?}");
    assert!(fps[0] > fps[7], "FP by depth {fps:?}");
}

#[test]
fn parameters_are_validated_never_clamped() {
    let d = IaDetector::default();
    assert_eq!(d.describe().to_string(), "depth=6");
    assert_eq!(d.params(), &IaParams::default());
    let d = IaDetector::try_new(IaParams { depth: 3 }).unwrap();
    assert_eq!(
        (d.params().depth, d.describe().to_string()),
        (3, "depth=3".into())
    );
    for bad in [0, MAX_DEPTH + 1, u32::MAX] {
        let err = IaDetector::try_new(IaParams { depth: bad }).unwrap_err();
        assert!(err.to_string().contains(&bad.to_string()), "{err}");
    }
    assert!(IaDetector::try_new(IaParams { depth: MAX_DEPTH }).is_ok());
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
        let ia = IaDetector::try_new(IaParams { depth }).unwrap().detect(&set, radius).unwrap().labels;
        for i in 0..pts.len() {
            prop_assert!(!exact.is_boundary(i) || ia.is_boundary(i), "particle {}", i);
        }
    }
}
