//! `exact` and `dilts` give the exact labels for the given floating-point input, near-ties
//! included: checked against independent exact-rational computations written for the tests
//! (`boundary_scenes::brute`: lattice ties decided as `2r² >= a²` / `4r² >= 3a²`, and vertex
//! enumeration by brute force over exact rationals for small sets), and against
//! `exact_cover` (the exact covering predicate of `boundary-exact`) on dense decimal lattices.
//! Every test runs both methods.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
#![cfg(all(feature = "exact", feature = "dilts"))]

use boundary::implement::exact_cover;
use boundary::{
    detector_by_name, detector_with_params, AnyParticleSet, BoundaryDetector, DiltsDetector,
    DiltsParams, ExactDetector, ExactParams, ParticleSet, Point, Radius,
};
use boundary::{Dim, SupportedDim};
use boundary_scenes::brute::{lattice_labels_near_tie, uncovered_by_enumeration};
use boundary_scenes::certify::{near_tie_radii as near, ulps};
use boundary_scenes::{cubic_lattice, square_lattice};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// The two exact methods: the name and the labels with the number of exact-predicate calls.
type Counting = fn(&AnyParticleSet, Radius) -> (Vec<bool>, usize);
const METHODS: [(&str, Counting); 2] = [
    ("exact", |set, r| {
        let (d, f) = ExactDetector::default()
            .detect_counting_fallbacks(set, r)
            .unwrap();
        (d.labels.as_slice().to_vec(), f)
    }),
    ("dilts", |set, r| {
        let (d, f) = DiltsDetector::default()
            .detect_counting_fallbacks(set, r)
            .unwrap();
        (d.labels.as_slice().to_vec(), f)
    }),
];

#[test]
fn near_tie_lattices_get_the_exact_labels_in_2d_and_3d() {
    for (name, labels) in METHODS {
        near_tie_lattices(name, labels);
    }
}

fn near_tie_lattices(name: &str, labels: Counting) {
    let labels = |set: AnyParticleSet, r: f64| labels(&set, Radius::new(r).unwrap());
    let tie2 = std::f64::consts::FRAC_1_SQRT_2;
    let tie3 = 3f64.sqrt() / 2.0;
    for offset in [0.0, 1e6, 1e9] {
        for r in near(tie2) {
            let rows: Vec<[f64; 2]> = square_lattice(7, 1.0)
                .iter()
                .map(|p| [p[0] + offset, p[1] - offset])
                .collect();
            let set = ParticleSet::from_rows(&rows).unwrap().into();
            let (got, _) = labels(set, r);
            assert_eq!(
                got,
                lattice_labels_near_tie(2, 7, 1.0, r),
                "{name} 2D r={r:e} +{offset}"
            );
        }
        for r in near(tie3) {
            let rows: Vec<[f64; 3]> = cubic_lattice(5, 1.0)
                .iter()
                .map(|p| [p[0] + offset, p[1] - offset, p[2] + offset])
                .collect();
            let set = ParticleSet::from_rows(&rows).unwrap().into();
            let (got, _) = labels(set, r);
            assert_eq!(
                got,
                lattice_labels_near_tie(3, 5, 1.0, r),
                "{name} 3D r={r:e} +{offset}"
            );
        }
    }
}

#[test]
fn the_issue_example_below_the_tie_is_all_boundary_and_the_opt_in_tie_keeps_the_old_labels() {
    let rows = square_lattice(9, 1.0);
    let set: AnyParticleSet = ParticleSet::from_rows(&rows).unwrap().into();
    let r = Radius::new(std::f64::consts::FRAC_1_SQRT_2 * (1.0 - 1e-10)).unwrap();
    for (name, _) in METHODS {
        let exact = detector_by_name(name).unwrap().detect(&set, r).unwrap();
        assert_eq!(exact.labels.boundary_count(), 81, "{name}");
        let loose = detector_with_params(name, &[("tie", "1e-9")]).unwrap();
        let got = loose.detect(&set, r).unwrap().labels.boundary_count();
        assert_eq!(got, 32, "{name}");
    }
    // exact's margin stays the float margin: about -1e-10 r at the inner particles.
    let m = ExactDetector::default()
        .detect(&set, r)
        .unwrap()
        .margin
        .unwrap()[40];
    assert!(m > 0.0 && m < 2e-10 * r.get(), "{m}");
}

#[test]
fn tie_parameter_is_validated_and_listed() {
    for (name, _) in METHODS {
        let d = detector_by_name(name).unwrap();
        assert_eq!(d.describe().to_string(), "tie=0", "{name}");
        for bad in ["-1e-9", "NaN", "inf", "x"] {
            assert!(
                detector_with_params(name, &[("tie", bad)]).is_err(),
                "{name} {bad}"
            );
        }
        assert!(
            detector_with_params(name, &[("depth", "3")]).is_err(),
            "{name}"
        );
        let d = detector_with_params(name, &[("tie", "1e-9")]).unwrap();
        assert_eq!(d.describe().to_string(), "tie=0.000000001", "{name}");
    }
    let exact = ExactDetector::try_new(ExactParams { tie: 1e-9 }).unwrap();
    assert_eq!(exact.params().tie, 1e-9);
    let dilts = DiltsDetector::try_new(DiltsParams { tie: 1e-9 }).unwrap();
    assert_eq!(dilts.params().tie, 1e-9);
}

/// A centre at `c`, and neighbours `c + s·(u + jitter)` for the unit directions `u` of a
/// lattice's nearest shell, each coordinate jittered by a relative `jitter`: near-cospherical
/// (the cell vertices all lie within about `jitter` of the tie radius `s·tie`).
fn jittered_shell<const D: usize>(
    c: [f64; D],
    s: f64,
    jitter: f64,
    rng: &mut StdRng,
) -> Vec<[f64; D]>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let mut rows = vec![c];
    for axis in 0..D {
        for sign in [1.0, -1.0] {
            let mut p = c;
            for (k, x) in p.iter_mut().enumerate() {
                let u = if k == axis { sign } else { 0.0 };
                *x += s * (u + rng.gen_range(-jitter..=jitter));
            }
            rows.push(p);
        }
    }
    rows
}

fn check_random_near_cospherical<const D: usize>(
    name: &str,
    labels: Counting,
    offset: f64,
    s: f64,
) -> usize
where
    ParticleSet<D>: Into<AnyParticleSet>,
    Dim<D>: SupportedDim,
{
    let mut rng = StdRng::seed_from_u64(20 + D as u64);
    let tie = if D == 2 {
        std::f64::consts::FRAC_1_SQRT_2
    } else {
        3f64.sqrt() / 2.0
    };
    let mut fallbacks = 0;
    let mut both = [0usize; 2];
    for trial in 0..40 {
        let jitter = [0.0, 1e-15, 1e-13, 1e-11][trial % 4];
        let rows = jittered_shell::<D>([offset; D], s, jitter, &mut rng);
        // The float reach of the centre's cell (its tie radius up to rounding), then a few
        // ulps either side of it: offsets round the coordinates far more than the jitter.
        let r0 = s * tie;
        let set: AnyParticleSet = ParticleSet::from_rows(&rows).unwrap().into();
        let m = ExactDetector::default()
            .detect(&set, Radius::new(r0).unwrap())
            .unwrap()
            .margin
            .unwrap()[0];
        let r = ulps(r0 + m, rng.gen_range(-6..=6));
        let truth = uncovered_by_enumeration(rows[0], &rows[1..], r);
        let (got, f) = labels(&set, Radius::new(r).unwrap());
        assert_eq!(
            got[0], truth,
            "{name} D={D} trial {trial} offset {offset} r={r:e}"
        );
        fallbacks += f;
        both[truth as usize] += 1;
    }
    // Both answers occur: the cases are near-ties indeed.
    assert!(both[0] > 0 && both[1] > 0, "{both:?}");
    fallbacks
}

#[test]
fn random_near_cospherical_sets_match_brute_force_enumeration() {
    for (name, labels) in METHODS {
        // The exact predicate runs (these are near-ties the float filters cannot decide).
        assert!(check_random_near_cospherical::<2>(name, labels, 0.0, 1.0) > 0);
        assert!(check_random_near_cospherical::<3>(name, labels, 0.0, 1.0) > 0);
    }
}

#[test]
fn large_offsets_at_small_r_match_brute_force_enumeration() {
    for (name, labels) in METHODS {
        for offset in [1e6, 1e9] {
            check_random_near_cospherical::<2>(name, labels, offset, 0.01);
            check_random_near_cospherical::<3>(name, labels, offset, 0.01);
        }
    }
}

#[test]
fn generic_random_sets_match_brute_force_enumeration() {
    // Clearly decided particles too (the float filters alone decide them): same answer.
    for (name, labels) in METHODS {
        let mut rng = StdRng::seed_from_u64(3);
        for trial in 0..30 {
            let n = rng.gen_range(4..9);
            let rows: Vec<[f64; 3]> = (0..n)
                .map(|_| std::array::from_fn(|_| rng.gen_range(-1.0..1.0)))
                .collect();
            let r = rng.gen_range(0.4..1.2);
            let set: AnyParticleSet = ParticleSet::from_rows(&rows).unwrap().into();
            let (got, _) = labels(&set, Radius::new(r).unwrap());
            for (i, &label) in got.iter().enumerate() {
                let others: Vec<[f64; 3]> = rows
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, p)| *p)
                    .collect();
                assert_eq!(
                    label,
                    uncovered_by_enumeration(rows[i], &others, r),
                    "{name} trial {trial} particle {i}"
                );
            }
        }
    }
}

/// Every particle of `rows` at `r`: the method's labels and the exact predicate of
/// `exact_cover` alone must agree (and, for `exact`, its list-based entry
/// point); returns the fallback count.
fn agree_with_the_exact_predicate<const D: usize>(
    name: &str,
    labels: Counting,
    rows: &[[f64; D]],
    r: f64,
) -> usize
where
    ParticleSet<D>: Into<AnyParticleSet>,
    Dim<D>: SupportedDim,
{
    let set: AnyParticleSet = ParticleSet::from_rows(rows).unwrap().into();
    let radius = Radius::new(r).unwrap();
    let (got, fallbacks) = labels(&set, radius);
    let points: Vec<Point<D>> = rows.iter().map(|&p| p.into()).collect();
    for (i, p) in points.iter().enumerate() {
        let others: Vec<Point<D>> = points
            .iter()
            .enumerate()
            .filter(|&(j, q)| j != i && (q - p).norm() < 2.5 * r)
            .map(|(_, q)| *q)
            .collect();
        let truth = exact_cover::sphere_uncovered(p, &others, r);
        assert_eq!(got[i], truth, "{name} D={D} particle {i}");
        let as2 = |q: &Point<D>| Point::<2>::from_fn(|k, _| q[k]);
        let as3 = |q: &Point<D>| Point::<3>::from_fn(|k, _| q[k]);
        let listed = match D {
            2 => {
                let others: Vec<Point<2>> = others.iter().map(as2).collect();
                boundary_exact::sphere_uncovered_2d(&as2(p), &others, radius)
            }
            _ => {
                let others: Vec<Point<3>> = others.iter().map(as3).collect();
                boundary_exact::sphere_uncovered_3d(&as3(p), &others, radius)
            }
        };
        assert_eq!(listed, truth, "D={D} particle {i}, list-based");
    }
    fallbacks
}

#[test]
fn dense_decimal_lattices_get_the_exact_labels_and_exact_settles_them_by_certificates() {
    // As `pysph_case5`: a body-centred cubic lattice of cube side 0.0225 (not dyadic: full
    // 53-bit mantissas, so the exact predicate takes its big-integer path) at r = 0.0253, with
    // dozens of neighbours whose bisectors pass exactly through the cell vertices (every clip
    // of `exact`'s float cell flagged near-degenerate). Both methods give the exact
    // predicate's labels; `exact`'s certificates settle every particle (0 fallbacks; 122
    // without the moved planes of its interior certificate).
    let a = 0.0225;
    let r = 0.0253;
    let mut rows3: Vec<[f64; 3]> = Vec::new();
    for k in 0..6 * 6 * 6 {
        let c = [k % 6, k / 6 % 6, k / 36].map(|x| x as f64 * a);
        rows3.push([c[0] + 0.0225, c[1] + 0.0225, c[2] + 0.01125]);
        rows3.push([c[0] + 0.03375, c[1] + 0.03375, c[2] + 0.0225]);
    }
    // Its 2D analogue: a centred square lattice (a square and its centres).
    let mut rows2: Vec<[f64; 2]> = Vec::new();
    for k in 0..10 * 10 {
        let c = [k % 10, k / 10].map(|x| x as f64 * a);
        rows2.push([c[0] + 0.0225, c[1] + 0.01125]);
        rows2.push([c[0] + 0.03375, c[1] + 0.0225]);
    }
    for (name, labels) in METHODS {
        let f3 = agree_with_the_exact_predicate(name, labels, &rows3, r);
        let f2 = agree_with_the_exact_predicate(name, labels, &rows2, r);
        if name == "exact" {
            assert_eq!((f2, f3), (0, 0));
        }
    }
    // Both labels occur (surface and inside).
    let set: AnyParticleSet = ParticleSet::from_rows(&rows3).unwrap().into();
    let (got, _) = METHODS[0].1(&set, Radius::new(r).unwrap());
    assert!(got.iter().any(|&b| b) && got.iter().any(|&b| !b));
}
