//! `svm` against `exact`: scale-free features, model files, held-out scores, the cascade.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{AnyParticleSet, BoundaryDetector, Confusion, ParticleSet, Point, Radius};
use boundary_core::{Dim, SupportedDim};
use boundary_exact::ExactDetector;
use boundary_scenes::certify::ulps;
use boundary_scenes::{jittered_lattice_ball, jittered_lattice_disc, shared_set};
use boundary_svm::{
    compute_features, particle_features, shipped_model, ModelChoice, Refine, SvmDetector, SvmModel,
    SvmParams,
};

fn with_refine(refine: Refine) -> SvmDetector {
    SvmDetector::try_new(SvmParams {
        refine,
        ..SvmParams::default()
    })
    .unwrap()
}

fn scaled<const D: usize>(set: &ParticleSet<D>, factor: f64) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    ParticleSet::new(set.positions().iter().map(|p| p * factor).collect()).unwrap()
}

fn score(predicted: &[bool], truth: &[bool]) -> Confusion {
    Confusion::from_labels(predicted, truth).unwrap()
}

/// Scaling positions and r by 2^k changes every feature by at most 1e-12 relative (plus
/// 1e-12 absolute for the features that are zero): only rounding differs.
#[test]
fn features_are_scale_free() {
    fn check<const D: usize>(set: &ParticleSet<D>, r: f64)
    where
        Dim<D>: SupportedDim,
    {
        let base = compute_features(set, set.len(), Radius::new(r).unwrap()).unwrap();
        for k in [-7, -1, 3, 12] {
            let factor = 2f64.powi(k);
            let s = scaled(set, factor);
            let f = compute_features(&s, s.len(), Radius::new(r * factor).unwrap()).unwrap();
            for (i, (a, b)) in base.iter().zip(&f).enumerate() {
                for q in 0..a.len() {
                    assert!(
                        (a[q] - b[q]).abs() <= 1e-12 * a[q].abs().max(1.0),
                        "particle {i}, feature {q}, scale 2^{k}: {} vs {}",
                        a[q],
                        b[q]
                    );
                }
            }
        }
    }
    check(&jittered_lattice_disc(12.0, 0.2, 3), 1.5);
    let (ball, _) = jittered_lattice_ball(2000, 0.15, 4);
    check(&ball, 1.2);
}

/// A model written to a file and loaded with `model=PATH` gives bit-identical decisions.
#[test]
fn model_file_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let set = jittered_lattice_disc(15.0, 0.2, 5);
    let r = Radius::new(1.5).unwrap();
    let reference = SvmDetector::default().detect_2d(&set, r).unwrap();
    let path = dir.path().join("model.json");
    std::fs::write(&path, shipped_model(2).unwrap().to_json()).unwrap();
    let loaded = SvmDetector::try_new(SvmParams {
        model: ModelChoice::from_file(path.to_str().unwrap()).unwrap(),
        ..SvmParams::default()
    })
    .unwrap();
    assert_eq!(loaded.describe().0[1].value, path.to_str().unwrap());
    assert_eq!(loaded.params().model.label(), path.to_str().unwrap());
    let again = loaded.detect_2d(&set, r).unwrap();
    assert_eq!(again, reference);
}

#[test]
fn bad_model_files_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.json");
    let load = |path: &std::path::Path| ModelChoice::from_file(path.to_str().unwrap());
    let e = load(&missing).unwrap_err();
    assert!(e.to_string().contains("missing.json"), "{e}");
    let garbage = dir.path().join("garbage.json");
    std::fs::write(&garbage, "{\"format\": \"boundary-svm model\", \"dim\": 2").unwrap();
    let e = load(&garbage).unwrap_err();
    assert!(e.to_string().contains("garbage.json"), "{e}");
    let mut bad = shipped_model(3).unwrap().clone();
    bad.feature_scale[0] = -1.0;
    let invalid = dir.path().join("invalid.json");
    std::fs::write(&invalid, bad.to_json()).unwrap();
    let e = load(&invalid).unwrap_err();
    assert!(
        e.to_string().contains("invalid.json") && e.to_string().contains("scales"),
        "{e}"
    );
    // A model built in memory is checked by try_new, the error naming its label.
    let e = SvmDetector::try_new(SvmParams {
        model: ModelChoice::custom("in-memory", bad),
        ..SvmParams::default()
    })
    .unwrap_err();
    assert!(
        e.to_string().contains("in-memory") && e.to_string().contains("scales"),
        "{e}"
    );
}

/// A 3D model used on a 2D set is an error that names the model.
#[test]
fn model_of_the_wrong_dimension_is_an_error() {
    let d = SvmDetector::try_new(SvmParams {
        model: ModelChoice::custom("my3d.json", shipped_model(3).unwrap().clone()),
        ..SvmParams::default()
    })
    .unwrap();
    let set = jittered_lattice_disc(5.0, 0.1, 1);
    let e = d.detect_2d(&set, Radius::new(1.5).unwrap()).unwrap_err();
    assert!(e.to_string().contains("my3d.json"), "{e}");
}

/// Isolated particles, pairs and duplicates: one label each, isolated ones boundary.
#[test]
fn degenerate_sets() {
    let d = SvmDetector::default();
    let r = Radius::new(1.0).unwrap();
    let set = ParticleSet::from_rows(&[[0.0, 0.0], [0.0, 0.0], [0.5, 0.0], [50.0, 50.0]]).unwrap();
    let labels = d.detect_2d(&set, r).unwrap().labels;
    assert_eq!(labels.len(), 4);
    assert!(labels.is_boundary(3));
    let set = ParticleSet::<3>::new(vec![Point::<3>::zeros()]).unwrap();
    assert!(d.detect_3d(&set, r).unwrap().labels.is_boundary(0));
    // At most D distinct neighbours cannot cover S_i: a centre with 3 neighbours in 3D (and
    // two duplicates of itself) is boundary, as are its neighbours.
    let rows = [
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.3, 0.0, 0.0],
        [0.0, 0.3, 0.0],
        [-0.2, -0.2, 0.1],
    ];
    let set = ParticleSet::from_rows(&rows).unwrap();
    let det = d.detect_3d(&set, r).unwrap();
    assert_eq!(det.labels.boundary_count(), 6);
    assert!(det.margin.unwrap().iter().all(|&m| m >= 0.0));
    let empty = ParticleSet::<3>::new(vec![]).unwrap();
    assert!(d.detect_3d(&empty, r).unwrap().labels.is_empty());
}

/// The owned part of a set with ghosts gets the labels of the whole set.
#[test]
fn owned_particles_match_the_whole_set() {
    let (ball, _) = jittered_lattice_ball(3000, 0.15, 9);
    let r = Radius::new(1.2).unwrap();
    for refine in [Refine::None, Refine::Exact] {
        let d = with_refine(refine);
        let all = d.detect_3d(&ball, r).unwrap().labels;
        let any = AnyParticleSet::from(ball.clone());
        let owned = d.detect_owned(&any, 1000, r).unwrap().labels;
        assert_eq!(owned.as_slice(), &all.as_slice()[..1000], "{refine:?}");
    }
}

/// The cascade with `exact` has no false positive and the SVM's recall; with `ge` it keeps
/// every true boundary particle the SVM found (ge is certified).
#[test]
fn cascade_against_exact() {
    let Some(set) = shared_set::<2>("particles2d/sandim_vortex_spin_frame_100_1698.csv").unwrap()
    else {
        return;
    };
    let r = Radius::new(0.022105).unwrap();
    let truth = ExactDetector::default().detect_2d(&set, r).unwrap().labels;
    let svm = SvmDetector::default().detect_2d(&set, r).unwrap().labels;
    let plain = score(svm.as_slice(), truth.as_slice());
    for refine in [Refine::Exact, Refine::Ge] {
        let d = with_refine(refine);
        let c = d.detect_2d(&set, r).unwrap();
        assert!(c.margin.is_none());
        let cascade = score(c.labels.as_slice(), truth.as_slice());
        assert_eq!(cascade.tp, plain.tp, "{refine:?}");
        assert!(cascade.fp <= plain.fp, "{refine:?}");
        if refine == Refine::Exact {
            assert_eq!(cascade.fp, 0);
            assert_eq!(cascade.fpr(), 0.0);
        }
        // Nothing the SVM called interior became boundary.
        for (i, (&s, &b)) in svm.as_slice().iter().zip(c.labels.as_slice()).enumerate() {
            assert!(s || !b, "particle {i}");
        }
    }
}

/// Perfect square and cubic lattices at radii around and away from their tie radius
/// (`a/√2`, `a√3/2`): `1e-6` relative off the tie, where no rounding can decide, and at the
/// rounded tie and 4 ulps either side (the hard-case lattices), where only an exact
/// predicate can: no false negative against `exact`. Below the tie every particle is
/// boundary (the certificate sees the uncovered diagonal points); above it, the outer
/// layer; at and within a few ulps of it, the near-tie particles go to `exact`, so the
/// labels are `exact`'s there (no false positive either).
#[test]
fn perfect_lattices_have_no_false_negative() {
    fn check<const D: usize>(set: &ParticleSet<D>, tie: f64)
    where
        AnyParticleSet: From<ParticleSet<D>>,
    {
        let labels = |r: f64| {
            let set = AnyParticleSet::from(set.clone());
            let r = Radius::new(r).unwrap();
            let truth = ExactDetector::default().detect(&set, r).unwrap().labels;
            let svm = SvmDetector::default().detect(&set, r).unwrap().labels;
            (svm, truth)
        };
        for r in [ulps(tie, -4), tie, ulps(tie, 4)] {
            let (svm, truth) = labels(r);
            assert_eq!(svm, truth, "{D}D lattice at r = {r:e}");
        }
        for r in [
            0.6,
            tie * (1.0 - 1e-6),
            tie * (1.0 + 1e-6),
            0.8,
            0.9,
            1.0,
            1.2,
            1.5,
            2.0,
        ] {
            let (svm, truth) = labels(r);
            let c = score(svm.as_slice(), truth.as_slice());
            assert_eq!(c.fn_, 0, "{D}D lattice, r = {r}: {c:?}");
        }
    }
    let square: Vec<[f64; 2]> = (0..144)
        .map(|k| [(k % 12) as f64, (k / 12) as f64])
        .collect();
    check(&ParticleSet::from_rows(&square).unwrap(), 0.5f64.sqrt());
    let cubic: Vec<[f64; 3]> = (0..343)
        .map(|k| [(k % 7) as f64, (k / 7 % 7) as f64, (k / 49) as f64])
        .collect();
    check(&ParticleSet::from_rows(&cubic).unwrap(), 0.75f64.sqrt());
}

/// The certificate never calls an interior particle boundary: on jittered sets and
/// lattices, every particle the features certify is boundary for `exact`.
#[test]
fn certified_particles_are_boundary_for_exact() {
    fn check<const D: usize>(set: &ParticleSet<D>, r: f64) -> usize
    where
        AnyParticleSet: From<ParticleSet<D>>,
    {
        let r = Radius::new(r).unwrap();
        let truth = ExactDetector::default()
            .detect(&AnyParticleSet::from(set.clone()), r)
            .unwrap()
            .labels;
        let features = particle_features(set, set.len(), r).unwrap();
        let mut certified = 0;
        for (i, p) in features.iter().enumerate() {
            if p.certified_boundary(D) {
                certified += 1;
                assert!(truth.is_boundary(i), "particle {i} certified but interior");
            }
        }
        certified
    }
    let mut total = 0;
    for (r, jitter) in [(0.9, 0.2), (1.5, 0.3), (2.5, 0.1)] {
        total += check(&jittered_lattice_disc(15.0, jitter, 11), r);
    }
    let (ball, _) = jittered_lattice_ball(3000, 0.3, 12);
    for r in [0.8, 1.2, 1.8] {
        total += check(&ball, r);
    }
    assert!(total > 1000, "the certificate fired only {total} times");
}

/// The held-out scores quoted in `docs/METHODS.md` (`svm`), recomputed: the shipped models on
/// scenes of other simulations than any training scene (the trainer generates its own; see
/// boundary-svm-train). `cargo xtask train-svm` prints the same rows for every scene of the
/// sweep in its training report.
#[test]
fn quoted_held_out_scores_are_reproduced() {
    /// `None`: the data is missing and `BOUNDARY_ALLOW_MISSING_DATA=1` (a skip).
    fn confusion<const D: usize>(file: &str, r: f64) -> Option<[u64; 4]>
    where
        AnyParticleSet: From<ParticleSet<D>>,
        Dim<D>: SupportedDim,
    {
        let set = shared_set::<D>(file).unwrap()?;
        let r = Radius::new(r).unwrap();
        let any = AnyParticleSet::from(set);
        let truth = ExactDetector::default().detect(&any, r).unwrap().labels;
        let svm = SvmDetector::default().detect(&any, r).unwrap().labels;
        let c = score(svm.as_slice(), truth.as_slice());
        Some([c.tp, c.fn_, c.fp, c.tn])
    }
    // [TP, FN, FP, TN], as quoted.
    let cases = [
        (
            confusion::<2>(
                "particles2d/sandim_vortex_spin_frame_100_1698.csv",
                0.022105,
            ),
            QUOTED_VORTEX_100,
        ),
        (
            confusion::<3>(
                "particles3d/splashsurf_double_dam_break_frame_26_4732.csv",
                0.1,
            ),
            QUOTED_DOUBLE_DAMBREAK_R01,
        ),
        (
            confusion::<3>("particles3d/splashsurf_dam_break_frame_23_24389.csv", 0.05),
            QUOTED_DAMBREAK23_R005,
        ),
    ];
    for (got, quoted) in cases {
        if let Some(got) = got {
            assert_eq!(got, quoted);
        }
    }
}

const QUOTED_VORTEX_100: [u64; 4] = [437, 0, 0, 1261];
const QUOTED_DOUBLE_DAMBREAK_R01: [u64; 4] = [4140, 15, 37, 540];
const QUOTED_DAMBREAK23_R005: [u64; 4] = [8134, 122, 18, 16115];

/// The JSON of the shipped models parses to a valid model of its dimension.
#[test]
fn shipped_models_are_valid() {
    for dim in [2, 3] {
        let m: &SvmModel = shipped_model(dim).unwrap();
        assert_eq!(m.dim, dim);
        assert!(!m.support_vectors.is_empty());
        m.validate().unwrap();
    }
}
