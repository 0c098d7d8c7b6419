//! A radius per particle: power cells. `exact`, `dilts`, `ia` and `ge` support it;
//! the others refuse it with an error naming the limitation. Checked against an independent
//! oracle written here (dense sampling of `S_i` with a Lipschitz bound, so that only the
//! particles it decides rigorously are compared), and uniform radii against today's labels.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
#![cfg(all(
    feature = "exact",
    feature = "dilts",
    feature = "ia",
    feature = "ge",
    feature = "hpr",
    feature = "marrone",
    feature = "muller",
    feature = "asymmetry",
    feature = "randles",
    feature = "lnm",
    feature = "divr",
    feature = "svm"
))]

use boundary::{
    detector_by_name, AnyParticleSet, CoreError, DetectError, ParticleSet, Point, Radius,
};
use boundary::{Dim, SupportedDim};
use rand::{rngs::StdRng, Rng, SeedableRng};

const SUPPORTED: [&str; 4] = ["exact", "dilts", "ia", "ge"];

fn labels(method: &str, set: &AnyParticleSet, r: f64) -> Vec<bool> {
    let d = detector_by_name(method).unwrap();
    d.detect(set, Radius::new(r).unwrap())
        .unwrap_or_else(|e| panic!("{method}: {e}"))
        .labels
        .into_vec()
}

/// A jittered lattice of spacing `a` in the box `[0, side)^D`.
fn jittered<const D: usize>(side: f64, a: f64, jitter: f64, rng: &mut StdRng) -> Vec<Point<D>>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let n = (side / a).round() as usize;
    let mut out = Vec::new();
    for k in 0..n.pow(D as u32) {
        let mut p = Point::<D>::zeros();
        let mut rest = k;
        for axis in 0..D {
            p[axis] = (rest % n) as f64 * a + a * jitter * (rng.gen::<f64>() - 0.5);
            rest /= n;
        }
        out.push(p);
    }
    out
}

/// A two-level set: spacing `a` (radius factor 1) where `x < side/2`, spacing `ratio·a`
/// (radius factor `ratio`) elsewhere, jittered.
fn two_level<const D: usize>(side: f64, a: f64, ratio: f64, seed: u64) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    let mut rng = StdRng::seed_from_u64(seed);
    let mut pts = Vec::new();
    let mut radii = Vec::new();
    for p in jittered::<D>(side, a, 0.3, &mut rng) {
        if p[0] < 0.5 * side {
            pts.push(p);
            radii.push(1.0);
        }
    }
    for p in jittered::<D>(side, ratio * a, 0.3, &mut rng) {
        if p[0] >= 0.5 * side {
            pts.push(p);
            radii.push(ratio);
        }
    }
    ParticleSet::new(pts).unwrap().with_radii(radii).unwrap()
}

/// Sampled oracle: the largest `min_j (|x − p_j| − r_j)` over sample points `x` of `S_i`
/// (positive: uncovered there). The function is 1-Lipschitz in `x`, so a sample spacing `h`
/// decides *boundary* when the value exceeds 0 and *interior* when it is below `−h`;
/// otherwise `None`.
fn oracle<const D: usize>(
    set: &ParticleSet<D>,
    r: f64,
    i: usize,
    samples: &[Point<D>],
    h: f64,
) -> Option<bool>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let p = set.positions()[i];
    let radii = set.radii().unwrap();
    let ri = r * radii[i];
    let others: Vec<(Point<D>, f64)> = (0..set.len())
        .filter(|&j| {
            set.positions()[j] != p && (set.positions()[j] - p).norm() <= ri + r * radii[j]
        })
        .map(|j| (set.positions()[j], r * radii[j]))
        .collect();
    let depth = samples
        .iter()
        .map(|u| {
            let x = p + u * ri;
            others
                .iter()
                .map(|(q, rj)| (x - q).norm() - rj)
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::NEG_INFINITY, f64::max);
    if depth > 1e-9 * ri {
        Some(true)
    } else if depth < -h * ri {
        Some(false)
    } else {
        None
    }
}

/// Unit sample directions and their spacing bound (the largest distance from a point of the
/// unit sphere to the nearest sample, over-estimated).
fn samples<const D: usize>() -> (Vec<Point<D>>, f64)
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    if D == 2 {
        let n = 4096;
        let pts = (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                let mut p = Point::<D>::zeros();
                p[0] = t.cos();
                p[1] = t.sin();
                p
            })
            .collect();
        (pts, std::f64::consts::PI / n as f64 * 1.01)
    } else {
        // A Fibonacci sphere of n points: spacing about sqrt(4π/n); its covering radius is
        // below 1.5x that (checked below against random directions).
        let n = 12_000;
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let pts: Vec<Point<D>> = (0..n)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
                let rho = (1.0 - z * z).sqrt();
                let t = golden * k as f64;
                let mut p = Point::<D>::zeros();
                p[0] = rho * t.cos();
                p[1] = rho * t.sin();
                p[2] = z;
                p
            })
            .collect();
        let h = 1.5 * (4.0 * std::f64::consts::PI / n as f64).sqrt();
        let mut rng = StdRng::seed_from_u64(7);
        for _ in 0..2000 {
            let mut v = Point::<D>::zeros();
            for k in 0..D {
                v[k] = rng.gen::<f64>() - 0.5;
            }
            let v = v.normalize();
            let nearest = pts
                .iter()
                .map(|p| (p - v).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < h, "the sample spacing bound holds");
        }
        (pts, h)
    }
}

/// Every supported method against the oracle and against `exact` on one set: `exact` and
/// `dilts` equal the oracle wherever it decides and each other everywhere; `ia` and `ge` have
/// no false negative against `exact`.
fn check_against_oracle<const D: usize>(set: ParticleSet<D>, what: &str)
where
    Dim<D>: SupportedDim,
{
    let (dirs, h) = samples::<D>();
    let any = set.to_any();
    let exact = labels("exact", &any, 1.0);
    let mut decided = 0;
    let mut boundary = 0;
    for (i, &label) in exact.iter().enumerate() {
        if let Some(b) = oracle(&set, 1.0, i, &dirs, h) {
            decided += 1;
            boundary += usize::from(b);
            assert_eq!(
                label, b,
                "{what}: exact disagrees with the oracle at particle {i}"
            );
        }
    }
    assert!(
        decided * 10 >= set.len() * 7,
        "{what}: the oracle decides {decided} of {}",
        set.len()
    );
    assert!(
        boundary > 0 && boundary < decided,
        "{what}: both labels occur ({boundary} boundary)"
    );
    assert_eq!(labels("dilts", &any, 1.0), exact, "{what}: dilts");
    for method in ["ia", "ge"] {
        let got = labels(method, &any, 1.0);
        let fn_ = (0..set.len()).filter(|&i| exact[i] && !got[i]).count();
        assert_eq!(fn_, 0, "{what}: {method} has false negatives");
    }
}

#[test]
fn graded_sets_in_2d_match_the_sampled_oracle() {
    for (ratio, seed) in [(2.0, 1), (4.0, 2)] {
        let set = two_level::<2>(24.0, 1.0, ratio, seed).with_radii_scaled(0.8);
        check_against_oracle(set, &format!("2D ratio {ratio}"));
    }
}

#[test]
fn graded_sets_in_3d_match_the_sampled_oracle() {
    for (ratio, seed) in [(2.0, 3), (4.0, 4)] {
        let set = two_level::<3>(8.0, 1.0, ratio, seed).with_radii_scaled(0.8);
        check_against_oracle(set, &format!("3D ratio {ratio}"));
    }
}

/// Smoothly graded: the radius factor grows linearly across the set (0.7 to 1.4 in 2D, 0.8 to
/// 1.6 in 3D) over a jittered lattice of spacing 1 with holes, so both labels occur inside.
#[test]
fn smoothly_graded_sets_match_the_sampled_oracle() {
    fn graded<const D: usize>(side: f64, lo: f64, hi: f64, seed: u64) -> ParticleSet<D>
    where
        Dim<D>: SupportedDim,
    {
        let mut rng = StdRng::seed_from_u64(seed);
        let pts: Vec<Point<D>> = jittered::<D>(side, 1.0, 0.4, &mut rng)
            .into_iter()
            .filter(|_| rng.gen::<f64>() > 0.08)
            .collect();
        let radii = pts.iter().map(|p| lo + (hi - lo) * p[0] / side).collect();
        ParticleSet::new(pts).unwrap().with_radii(radii).unwrap()
    }
    check_against_oracle(graded::<2>(20.0, 0.7, 1.4, 31), "2D smooth");
    check_against_oracle(graded::<3>(7.0, 0.8, 1.6, 32), "3D smooth");
}

/// Radii 100x apart: a few large balls among many small ones.
#[test]
fn radii_a_hundred_times_apart_match_the_sampled_oracle() {
    let mut rng = StdRng::seed_from_u64(5);
    let mut pts: Vec<Point<2>> = jittered::<2>(12.0, 0.5, 0.4, &mut rng);
    let mut radii = vec![0.45; pts.len()];
    for _ in 0..3 {
        pts.push(Point::<2>::new(
            rng.gen::<f64>() * 12.0,
            rng.gen::<f64>() * 12.0,
        ));
        radii.push(45.0 * rng.gen_range(0.05..0.1));
    }
    let set = ParticleSet::new(pts).unwrap().with_radii(radii).unwrap();
    check_against_oracle(set, "2D ratio 100");
    let mut pts: Vec<Point<3>> = jittered::<3>(5.0, 0.5, 0.4, &mut rng);
    let mut radii = vec![0.45; pts.len()];
    pts.push(Point::<3>::new(2.5, 2.5, 4.0));
    radii.push(45.0 * 0.05);
    let set = ParticleSet::new(pts).unwrap().with_radii(radii).unwrap();
    check_against_oracle(set, "3D ratio 100");
}

trait Scaled {
    fn with_radii_scaled(self, f: f64) -> Self;
}

impl<const D: usize> Scaled for ParticleSet<D> {
    fn with_radii_scaled(self, f: f64) -> Self {
        let radii: Vec<f64> = self.radii().unwrap().iter().map(|s| s * f).collect();
        self.with_radii(radii).unwrap()
    }
}

/// Equal radii are today's definition: the labels of the uniform set, for every supported
/// method, whether the radii hold `r` itself (scale 1) or a factor of it.
#[test]
fn uniform_radii_give_the_uniform_labels() {
    let mut rng = StdRng::seed_from_u64(11);
    let s2 = ParticleSet::new(jittered::<2>(20.0, 1.0, 0.4, &mut rng)).unwrap();
    let s3 = ParticleSet::new(jittered::<3>(7.0, 1.0, 0.4, &mut rng)).unwrap();
    for (set, r) in [(s2.to_any(), 0.8), (s3.to_any(), 1.0)] {
        for method in SUPPORTED {
            let uniform = labels(method, &set, r);
            let n = set.len();
            let with_r = set.clone().with_radii(vec![r; n]).unwrap();
            assert_eq!(labels(method, &with_r, 1.0), uniform, "{method}: radii = r");
            let factor = set.clone().with_radii(vec![0.5; n]).unwrap();
            assert_eq!(
                labels(method, &factor, 2.0 * r),
                uniform,
                "{method}: radii r/2, scale 2"
            );
        }
    }
}

/// Closed-form cases: a sphere inside a bigger neighbour's ball is interior (and boundary once
/// it pokes out); a tiny ball far from everything is boundary; coincident particles do not
/// cover each other whatever their radii.
#[test]
fn containment_and_isolation_are_decided_as_defined() {
    let two = |d: f64, r0: f64, r1: f64| {
        ParticleSet::<2>::from_rows(&[[0.0, 0.0], [d, 0.0]])
            .unwrap()
            .with_radii(vec![r0, r1])
            .unwrap()
            .to_any()
    };
    for method in SUPPORTED {
        // S_0 (radius 1) inside B_1 (radius 2, centre 0.5 away): interior; 1 is boundary.
        assert_eq!(
            labels(method, &two(0.5, 1.0, 2.0), 1.0),
            [false, true],
            "{method}"
        );
        // Poking out: boundary.
        assert_eq!(
            labels(method, &two(0.5, 1.0, 1.4), 1.0),
            [true, true],
            "{method}"
        );
        // Coincident, different radii: neither covers the other.
        assert_eq!(
            labels(method, &two(0.0, 1.0, 3.0), 1.0),
            [true, true],
            "{method}"
        );
        // A tiny ball far away from a big one: both boundary.
        assert_eq!(
            labels(method, &two(50.0, 1e-3, 10.0), 1.0),
            [true, true],
            "{method}"
        );
    }
    // Touching from inside (0.5 + 1 = 1.5): covered by the closed ball. The exact methods say
    // so; `ia` and `ge` may not certify a touching ball (a false positive, never a negative).
    for method in ["exact", "dilts"] {
        assert_eq!(
            labels(method, &two(0.5, 1.0, 1.5), 1.0),
            [false, true],
            "{method}"
        );
    }
}

#[test]
fn bad_radii_are_errors_naming_the_particle() {
    let set =
        || ParticleSet::<3>::from_rows(&[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]).unwrap();
    for (radii, message) in [
        (
            vec![1.0, -1.0, 1.0],
            "particle 1: radius must be positive and finite, got -1",
        ),
        (
            vec![1.0, 1.0, 0.0],
            "particle 2: radius must be positive and finite, got 0",
        ),
        (
            vec![f64::NAN, 1.0, 1.0],
            "particle 0: radius must be positive and finite, got NaN",
        ),
        (
            vec![1.0, 1e200, 1.0],
            "particle 1: radius 1e200 is outside the supported range 1e-100..=1e100",
        ),
        (
            vec![1.0, 1.0],
            "2 radii for 3 particles (one radius per particle)",
        ),
    ] {
        assert_eq!(set().with_radii(radii).unwrap_err().to_string(), message);
    }
    // The scale can push a valid factor out of range: the detector says which particle.
    let set = set().with_radii(vec![1.0, 1e90, 1.0]).unwrap().to_any();
    let err = detector_by_name("exact")
        .unwrap()
        .detect(&set, Radius::new(1e20).unwrap())
        .unwrap_err();
    assert_eq!(
        err,
        DetectError::Core(CoreError::ParticleRadiusOutOfRange {
            index: 1,
            value: 1e110
        })
    );
}

#[test]
fn methods_without_support_refuse_radii_by_name() {
    let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0]])
        .unwrap()
        .with_radii(vec![1.0, 2.0])
        .unwrap()
        .to_any();
    for method in [
        "hpr",
        "marrone",
        "muller",
        "divr",
        "asymmetry",
        "randles",
        "lnm",
        "svm",
    ] {
        let d = detector_by_name(method).unwrap();
        let err = d.detect(&set, Radius::new(1.0).unwrap()).unwrap_err();
        assert!(
            matches!(err, DetectError::PerParticleRadii { method: m, .. } if m == method),
            "{method}: {err}"
        );
        assert!(err
            .to_string()
            .contains("does not support per-particle radii"));
        let owned = d
            .detect_owned(&set, 1, Radius::new(1.0).unwrap())
            .unwrap_err();
        assert!(
            matches!(owned, DetectError::PerParticleRadii { .. }),
            "{method}: {owned}"
        );
    }
}

/// The label of particle 0 of `centre` + `balls` by `method`, at scale 1.
fn label_of_centre<const D: usize>(method: &str, r: f64, balls: &[([f64; D], f64)]) -> bool
where
    Dim<D>: SupportedDim,
{
    let mut rows = vec![[0.0; D]];
    rows.extend(balls.iter().map(|b| b.0));
    let mut radii = vec![r];
    radii.extend(balls.iter().map(|b| b.1));
    let set = ParticleSet::<D>::from_rows(&rows)
        .unwrap()
        .with_radii(radii)
        .unwrap()
        .to_any();
    labels(method, &set, 1.0)[0]
}

/// Near-ties against the exact-rational power-diagram oracle of `boundary_scenes::brute`
/// (vertex and face enumeration, sharing no code with the detectors): arrangements whose
/// uncovered region closes at a triple point of `S_i` (two neighbour spheres meeting on it),
/// with one radius moved by −4..=4 ulps, and a larger neighbour touching `S_i` from inside.
#[test]
fn near_ties_match_the_exact_rational_power_oracle() {
    use boundary_scenes::brute::power_uncovered_by_enumeration as oracle;
    use boundary_scenes::certify::ulps;
    type Balls = Vec<([f64; 2], f64)>;
    let mut cases: Vec<(String, Balls)> = Vec::new();
    // 2D: neighbours at (±2, 0) and (0, ±3); the circles of (2, 0) and (0, ±3) meet on the
    // unit circle at ±50° when rho1² = 5 − 4cos θ and rho2² = 10 − 6 sin θ (the ball at
    // (−2, 0) is a little larger, so that only the triple points at +x decide).
    let t = 50f64.to_radians();
    let (rho1, rho2) = ((5.0 - 4.0 * t.cos()).sqrt(), (10.0 - 6.0 * t.sin()).sqrt());
    for k in -4..=4 {
        let balls = vec![
            ([2.0, 0.0], ulps(rho1, k)),
            ([-2.0, 0.0], rho1 + 0.01),
            ([0.0, 3.0], rho2),
            ([0.0, -3.0], rho2),
        ];
        cases.push((format!("triple point, rho1 {k:+} ulps"), balls));
        // A larger ball nearly holding the centre, touching S_i from inside at (−1, 0).
        cases.push((
            format!("touching, {k:+} ulps"),
            vec![([0.5, 0.0], ulps(1.5, k))],
        ));
    }
    let mut both = [0usize; 2];
    for (what, balls) in &cases {
        let truth = oracle([0.0, 0.0], 1.0, balls);
        both[usize::from(truth)] += 1;
        for method in ["exact", "dilts"] {
            assert_eq!(
                label_of_centre(method, 1.0, balls),
                truth,
                "{method}: {what}"
            );
        }
        for method in ["ia", "ge"] {
            assert!(
                !truth || label_of_centre(method, 1.0, balls),
                "{method}: {what}: false negative"
            );
        }
    }
    assert!(
        both[0] > 0 && both[1] > 0,
        "both labels occur among the near-ties: {both:?}"
    );
    // 3D: neighbours at (±2, 0, 0) and at 3 on ±y, ±z; the spheres of the x, y and z balls
    // meet on S_i at x = (cos θ, sin θ/√2, sin θ/√2) when rho1² = 5 − 4cos θ and
    // rho3² = 10 − 6 sin θ/√2 (the caps of ±y, ±z overlap, 57° each, 90° apart).
    let rho3 = (10.0 - 6.0 * t.sin() / 2f64.sqrt()).sqrt();
    let mut both = [0usize; 2];
    for k in -4..=4 {
        let balls = [
            ([2.0, 0.0, 0.0], ulps(rho1, k)),
            ([-2.0, 0.0, 0.0], rho1 + 0.01),
            ([0.0, 3.0, 0.0], rho3),
            ([0.0, -3.0, 0.0], rho3),
            ([0.0, 0.0, 3.0], rho3),
            ([0.0, 0.0, -3.0], rho3),
        ];
        let truth = oracle([0.0; 3], 1.0, &balls);
        both[usize::from(truth)] += 1;
        for method in ["exact", "dilts"] {
            assert_eq!(
                label_of_centre(method, 1.0, &balls),
                truth,
                "{method}: 3D {k:+} ulps"
            );
        }
    }
    assert!(
        both[0] > 0 && both[1] > 0,
        "3D: both labels occur: {both:?}"
    );
}

/// Random small arrangements with radii 0.25..4 (many with a larger neighbour near the
/// centre, so that the centre lies outside its own power cell) against the same oracle.
#[test]
fn random_arrangements_match_the_exact_rational_power_oracle() {
    use boundary_scenes::brute::power_uncovered_by_enumeration as oracle;
    let mut rng = StdRng::seed_from_u64(21);
    let mut seen = [0usize; 2];
    for case in 0..160 {
        let ball = |rng: &mut StdRng| {
            let rj = [0.25, 0.5, 1.0, 2.0, 4.0][rng.gen_range(0..5)] * rng.gen_range(0.8..1.2);
            let d = rng.gen_range(0.05..1.0) * (1.0 + rj);
            (d, rj)
        };
        if case % 2 == 0 {
            let balls: Vec<([f64; 2], f64)> = (0..rng.gen_range(3..9))
                .map(|_| {
                    let (d, rj) = ball(&mut rng);
                    let a = rng.gen_range(0.0..std::f64::consts::TAU);
                    ([d * a.cos(), d * a.sin()], rj)
                })
                .collect();
            let truth = oracle([0.0, 0.0], 1.0, &balls);
            seen[usize::from(truth)] += 1;
            for method in ["exact", "dilts"] {
                assert_eq!(
                    label_of_centre(method, 1.0, &balls),
                    truth,
                    "{method}: 2D case {case}"
                );
            }
        } else {
            let balls: Vec<([f64; 3], f64)> = (0..rng.gen_range(4..10))
                .map(|_| {
                    let (d, rj) = ball(&mut rng);
                    let z: f64 = rng.gen_range(-1.0..1.0);
                    let a = rng.gen_range(0.0..std::f64::consts::TAU);
                    let s = (1.0 - z * z).sqrt();
                    ([d * s * a.cos(), d * s * a.sin(), d * z], rj)
                })
                .collect();
            let truth = oracle([0.0; 3], 1.0, &balls);
            seen[usize::from(truth)] += 1;
            for method in ["exact", "dilts"] {
                assert_eq!(
                    label_of_centre(method, 1.0, &balls),
                    truth,
                    "{method}: 3D case {case}"
                );
            }
        }
    }
    assert!(
        seen[0] >= 20 && seen[1] >= 20,
        "both labels occur: {seen:?}"
    );
}
