//! `randles` against `exact` on generated scenes (accuracy bounds), a hand-computed
//! renormalisation matrix, degenerate input, and invariance under threads, decomposition and
//! scale.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
#![allow(clippy::print_stdout)] // today's scores, beside the bounds

use boundary_core::{BoundaryDetector, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_randles::{RandlesDetector, RandlesParams};
use boundary_scenes::{against, jittered_lattice_ball, jittered_lattice_disc};
use boundary_sph::Kernel;

/// The 3 x 3 square lattice of spacing 1 at `h = 0.6` (support 1.2: each particle sees its
/// axis neighbours at distance 1 only, `q = 1/0.6`), by hand. With Wendland C2,
/// `f(q) = (1 − q/2)^4 (2q + 1)`, `−f'(q)/q = 5(1 − q/2)^3` and `σ = 7/(4π)`, the volume of a
/// particle with `k` neighbours is `h²/(σ(1 + k f))` and a neighbour at unit distance along an
/// axis adds `V_j σ 5(1 − q/2)^3 / h^4` to that axis' diagonal entry of `B`
/// (`(x_j − x_i) ⊗ ∇W_ij` with `∇W_ij = σ h^-4 (−f'(q)/q) (x_j − x_i)`). So
/// - the centre (4 edge neighbours, 3 neighbours each): `λ = 2·g/(1 + 3f)`,
/// - a corner (2 edge neighbours): `λ = g/(1 + 3f)`,
/// - an edge middle (2 corners along the edge, the centre across): `λ = g/(1 + 4f)`,
///
/// with `g = 5(1 − q/2)^3 / h²`.
#[test]
fn the_smallest_eigenvalue_of_a_small_lattice_is_the_hand_computed_one() {
    let h: f64 = 0.6;
    let q = 1.0 / h;
    let f = (1.0 - q / 2.0).powi(4) * (2.0 * q + 1.0);
    let g = 5.0 * (1.0 - q / 2.0).powi(3) / (h * h);
    let centre = 2.0 * g / (1.0 + 3.0 * f);
    let corner = g / (1.0 + 3.0 * f);
    let edge = g / (1.0 + 4.0 * f);
    let rows: Vec<[f64; 2]> = (0..9).map(|k| [(k % 3) as f64, (k / 3) as f64]).collect();
    let set = ParticleSet::from_rows(&rows).unwrap();
    let d = RandlesDetector::default();
    let lambdas = d.lambdas(&set, Radius::new(h).unwrap()).unwrap();
    let expected = [
        corner, edge, corner, edge, centre, edge, corner, edge, corner,
    ];
    for (k, (got, want)) in lambdas.iter().zip(expected).enumerate() {
        assert!((got - want).abs() < 1e-12, "particle {k}: {got} vs {want}");
    }
    // mu between the edge and the centre values: everything but the centre is free surface
    // (decided without λ: no margin).
    let mu = 0.5 * (edge.max(corner) + centre);
    let d = RandlesDetector::try_new(RandlesParams {
        mu_2d: mu,
        ..Default::default()
    })
    .unwrap();
    let got = d.detect_2d(&set, Radius::new(h).unwrap()).unwrap();
    assert_eq!(got.labels.boundary_count(), 8);
    assert!(!got.labels.is_boundary(4));
    assert_eq!(got.margin, None);
}

#[test]
fn jittered_discs_and_balls_are_scored_within_bounds() {
    let d = RandlesDetector::default();
    let r = 1.2;
    let core = 2.0 * r + 1.0;
    let c2 = against::check_ball(
        &d,
        &ExactDetector::default(),
        &jittered_lattice_disc(20.0, 0.15, 1),
        20.0,
        r,
        core,
        0.9,
    )
    .unwrap();
    let (ball, radius) = jittered_lattice_ball(8000, 0.15, 2);
    let c3 =
        against::check_ball(&d, &ExactDetector::default(), &ball, radius, r, core, 0.9).unwrap();
    for (dim, c) in [(2, c2), (3, c3)] {
        println!(
            "{dim}D: Rec {:.4} FPR {:.4} M {:.4}",
            c.recall(),
            c.fpr(),
            c.m()
        );
        assert!(c.fpr() <= 0.01, "{dim}D {c:?}");
    }
}

#[test]
fn degenerate_input_gives_the_documented_labels() {
    let d = RandlesDetector::default();
    let r = Radius::new(1.0).unwrap();
    let empty = ParticleSet::<3>::new(Vec::new()).unwrap();
    assert!(d.detect_3d(&empty, r).unwrap().labels.is_empty());
    let single = ParticleSet::from_rows(&[[1e6, -1e6]]).unwrap();
    assert_eq!(d.detect_2d(&single, r).unwrap().labels.as_slice(), [true]);
    // Singular B: pairs (coincident or not) and a line.
    let pair = ParticleSet::from_rows(&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]).unwrap();
    assert_eq!(d.detect_3d(&pair, r).unwrap().labels.boundary_count(), 2);
    let line: Vec<[f64; 2]> = (0..10).map(|k| [0.5 * k as f64, 0.0]).collect();
    let line = ParticleSet::from_rows(&line).unwrap();
    assert_eq!(d.detect_2d(&line, r).unwrap().labels.boundary_count(), 10);
    // Duplicates add nothing to B: every particle twice gives the copies the same labels.
    let rows = boundary_scenes::cubic_lattice(6, 1.0);
    let doubled: Vec<[f64; 3]> = rows.iter().chain(rows.iter()).copied().collect();
    let l = d
        .detect_3d(
            &ParticleSet::from_rows(&doubled).unwrap(),
            Radius::new(1.2).unwrap(),
        )
        .unwrap()
        .labels;
    assert!(l.boundary_count() < 432);
    for k in 0..216 {
        assert_eq!(l.is_boundary(k), l.is_boundary(k + 216), "copies of {k}");
    }
}

#[test]
fn labels_do_not_depend_on_threads_decomposition_or_scale() {
    let d = RandlesDetector::default();
    against::check_threads_and_decomposition(&d).unwrap();
    let cubic = RandlesDetector::try_new(RandlesParams {
        kernel: Kernel::CubicSpline,
        h_over_r: 1.3,
        ..Default::default()
    })
    .unwrap();
    let (ball, _) = jittered_lattice_ball(1500, 0.2, 6);
    for det in [&d, &cubic] {
        let base = against::labels(det, &ball, 1.2).unwrap();
        for s in [1e-100, 1e-3, 1e9, 7e99] {
            let scaled =
                ParticleSet::new(ball.positions().iter().map(|p| p * s).collect()).unwrap();
            assert_eq!(
                against::labels(det, &scaled, 1.2 * s).unwrap(),
                base,
                "{det} scale {s}"
            );
        }
    }
}
