//! `ia` is certified: no exact-boundary particle is ever labelled interior (Rec = 1 against
//! `exact`), at every depth 1..=8, on the shared scenes and the hard cases; and deeper trees
//! never label fewer particles interior.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_scenes::{cubic_lattice, shared_set, square_lattice, SHARED_SCENES};

use boundary_core::{BoundaryDetector, Labels, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_ia::IaDetector;
use proptest::prelude::*;
use rand::{rngs::StdRng, Rng, SeedableRng};

/// Labels of `ia` at depths `1..=max_depth` on `set`; asserts Rec = 1 against exact at each
/// depth and that the interior set only grows with depth. Returns the false-positive counts.
fn certify<const D: usize>(what: &str, set: &ParticleSet<D>, r: f64, max_depth: u32) -> Vec<usize> {
    let any = set.to_any();
    let radius = Radius::new(r).unwrap();
    let exact = ExactDetector.detect(&any, radius).unwrap().labels;
    let mut previous: Option<Labels> = None;
    let mut fps = Vec::new();
    for depth in 1..=max_depth {
        let ia = IaDetector::new(depth).detect(&any, radius).unwrap().labels;
        let missed: Vec<usize> = (0..set.len())
            .filter(|&i| exact.is_boundary(i) && !ia.is_boundary(i))
            .collect();
        assert!(
            missed.is_empty(),
            "{what} r={r} depth {depth}: false negatives {missed:?}"
        );
        if let Some(prev) = &previous {
            let lost: Vec<usize> = (0..set.len())
                .filter(|&i| !prev.is_boundary(i) && ia.is_boundary(i))
                .collect();
            assert!(
                lost.is_empty(),
                "{what} depth {depth}: interior at depth {} but not now: {lost:?}",
                depth - 1
            );
        }
        fps.push(ia.boundary_count() - exact.boundary_count());
        previous = Some(ia);
    }
    fps
}

#[test]
fn shared_scenes_depth_1_to_8() {
    for &(_, dim, file, r, _, _, _) in SHARED_SCENES {
        let fps = if dim == 2 {
            certify(file, &shared_set::<2>(file).unwrap(), r, 8)
        } else {
            certify(file, &shared_set::<3>(file).unwrap(), r, 8)
        };
        println!("{file} r={r}: FP by depth {fps:?}");
    }
}

fn jittered<const D: usize>(n_side: usize, jitter: f64, seed: u64) -> ParticleSet<D> {
    let mut rng = StdRng::seed_from_u64(seed);
    let rows: Vec<[f64; D]> = (0..n_side.pow(D as u32))
        .map(|k| {
            let mut p = [0.0; D];
            let mut rest = k;
            for c in p.iter_mut() {
                *c = (rest % n_side) as f64 + rng.gen_range(-jitter..=jitter);
                rest /= n_side;
            }
            p
        })
        .collect();
    ParticleSet::from_rows(&rows).unwrap()
}

#[test]
fn hard_cases_depth_1_to_8() {
    let square = ParticleSet::from_rows(&square_lattice(12, 1.0)).unwrap();
    for r in [std::f64::consts::FRAC_1_SQRT_2, 0.8, 1.0, 1.5] {
        certify("square lattice", &square, r, 8);
    }
    let cubic = ParticleSet::from_rows(&cubic_lattice(7, 1.0)).unwrap();
    for r in [3f64.sqrt() / 2.0, 1.0, 1.2] {
        certify("cubic lattice", &cubic, r, 8);
    }
    // Duplicates: every particle twice.
    let rows = cubic_lattice(5, 1.0);
    let doubled: Vec<[f64; 3]> = rows.iter().chain(rows.iter()).copied().collect();
    certify(
        "duplicates",
        &ParticleSet::from_rows(&doubled).unwrap(),
        1.2,
        8,
    );
    let pair = ParticleSet::from_rows(&[[0.0, 0.0], [0.0, 0.0]]).unwrap();
    let labels = IaDetector::new(8)
        .detect_2d(&pair, Radius::new(1.0).unwrap())
        .unwrap()
        .labels;
    assert_eq!(
        labels.boundary_count(),
        2,
        "coincident particles do not cover each other"
    );
    // Far offset.
    let far: Vec<[f64; 3]> = jittered::<3>(8, 0.2, 4)
        .positions()
        .iter()
        .map(|p| [1e6 + 0.01 * p[0], -1e6 + 0.01 * p[1], 1e6 + 0.01 * p[2]])
        .collect();
    certify(
        "far offset",
        &ParticleSet::from_rows(&far).unwrap(),
        0.012,
        8,
    );
    // Flat sets: a line in 2D, a plane in 3D, all boundary.
    let line: Vec<[f64; 2]> = (0..20).map(|k| [k as f64 * 0.5, 0.0]).collect();
    certify("line", &ParticleSet::from_rows(&line).unwrap(), 1.0, 8);
    let plane: Vec<[f64; 3]> = square_lattice(6, 1.0)
        .iter()
        .map(|p| [p[0], p[1], 0.0])
        .collect();
    certify("plane", &ParticleSet::from_rows(&plane).unwrap(), 1.5, 8);
    for seed in 0..2 {
        certify("jittered 2D", &jittered::<2>(20, 0.3, seed), 0.9, 8);
        certify("jittered 3D", &jittered::<3>(9, 0.3, seed), 1.1, 8);
    }
}

#[test]
fn deep_trees_approach_the_exact_labels_on_jittered_lattices() {
    // Away from ties, a deep enough tree decides every particle: the false positives left at
    // depth 8 are only particles whose exact margin is tiny.
    let set = jittered::<3>(10, 0.15, 9);
    let r = 1.2;
    let fps = certify("jittered 3D", &set, r, 8);
    assert!(fps[7] * 50 <= set.len(), "FP by depth {fps:?}");
    assert!(fps[0] > fps[7], "FP by depth {fps:?}");
}

#[test]
fn parameters_are_validated() {
    let mut d = IaDetector::default();
    assert_eq!(d.params().to_string(), "depth=6");
    d.set_param("depth", "3").unwrap();
    assert_eq!(d.depth(), 3);
    for bad in ["0", "17", "-1", "x", "2.5"] {
        let err = d.set_param("depth", bad).unwrap_err();
        assert!(err.to_string().contains(bad), "{err}");
    }
    assert!(d.set_param("gamma", "1").is_err());
    assert_eq!(d.depth(), 3);
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
        let exact = ExactDetector.detect(&set, radius).unwrap().labels;
        let ia = IaDetector::new(depth).detect(&set, radius).unwrap().labels;
        for i in 0..pts.len() {
            prop_assert!(!exact.is_boundary(i) || ia.is_boundary(i), "particle {}", i);
        }
    }
}
