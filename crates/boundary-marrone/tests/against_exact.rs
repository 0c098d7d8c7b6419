//! `marrone` against `exact`: on jittered lattice balls (2D and 3D) the outer shell is found
//! and the deep interior is interior; M stays above an honest floor on shared SPH scenes; the
//! two steps each do their part; degenerate input does not panic; labels do not depend on the
//! threads or on a domain decomposition with the method's halo.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{BoundaryDetector, Labels, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_marrone::{MarroneDetector, MarroneParams};
use boundary_scenes::against;
use boundary_scenes::{jittered_lattice_ball, jittered_lattice_disc};
use boundary_sph::Kernel;

fn labels<const D: usize>(d: &MarroneDetector, set: &ParticleSet<D>, r: f64) -> Labels
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    d.detect(&set.to_any(), Radius::new(r).unwrap())
        .unwrap()
        .labels
}

/// The outermost particles (within 0.3 spacings of the rim) are all boundary, the particles
/// deeper than one kernel support plus a spacing are all interior, and the exact boundary is
/// found with Rec >= 0.95.
fn check_ball<const D: usize>(d: &MarroneDetector, set: &ParticleSet<D>, radius: f64, r: f64)
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let core = 2.0 * d.params().h_over_r * r + 1.0;
    against::check_ball(d, &ExactDetector::default(), set, radius, r, core, 0.95).unwrap();
}

#[test]
fn lattice_balls_have_a_boundary_rim_and_an_interior_core() {
    let d = MarroneDetector::default();
    check_ball(&d, &jittered_lattice_disc(20.0, 0.15, 1), 20.0, 1.2);
    let (ball, radius) = jittered_lattice_ball(8000, 0.15, 2);
    check_ball(&d, &ball, radius, 1.2);
    // The cubic spline and a larger h behave the same on these.
    let cubic = MarroneDetector::try_new(MarroneParams {
        kernel: Kernel::CubicSpline,
        h_over_r: 1.3,
        ..MarroneParams::default()
    })
    .unwrap();
    check_ball(&cubic, &ball, radius, 1.2);
}

#[test]
fn the_scan_alone_finds_the_shell_and_the_lambda_cuts_bracket_the_default() {
    let (ball, radius) = jittered_lattice_ball(8000, 0.15, 3);
    let r = 1.2;
    // Scan only: every particle with λ > 0 goes through the scan region, which alone still
    // finds the shell and leaves the core.
    let scan_only = MarroneDetector::try_new(MarroneParams {
        lambda_surface: 0.0,
        lambda_interior: 1e9,
        ..MarroneParams::default()
    })
    .unwrap();
    check_ball(&scan_only, &ball, radius, r);
    // λ only (no candidates): a coarser answer, a superset of the default's boundary on this
    // ball when the cut is at 0.75, and a subset when it is at 0.2.
    let default = labels(&MarroneDetector::default(), &ball, r);
    let generous = MarroneDetector::try_new(MarroneParams {
        lambda_surface: 0.75,
        ..MarroneParams::default()
    })
    .unwrap();
    let generous = labels(&generous, &ball, r);
    let strict = MarroneDetector::try_new(MarroneParams {
        lambda_interior: 0.2,
        ..MarroneParams::default()
    })
    .unwrap();
    let strict = labels(&strict, &ball, r);
    for i in 0..ball.len() {
        assert!(!default.is_boundary(i) || generous.is_boundary(i), "{i}");
        assert!(!strict.is_boundary(i) || default.is_boundary(i), "{i}");
    }
    assert!(generous.boundary_count() > default.boundary_count());
    assert!(strict.boundary_count() < default.boundary_count());
    // λ itself: about 1 deep inside, small at the rim.
    let lambdas = MarroneDetector::default()
        .lambdas(&ball, Radius::new(r).unwrap())
        .unwrap();
    for (p, l) in ball.positions().iter().zip(&lambdas) {
        if p.norm() < radius - 4.0 {
            assert!(*l > 0.75, "λ = {l} at depth {}", radius - p.norm());
        }
    }
}

/// M of the default detector on the shared scenes, with floors below today's values
/// (recorded in the sweep report) so that a regression fails.
#[test]
fn shared_scenes_keep_m_at_or_above_the_recorded_floors() {
    let floors = [
        ("sandim_vortex_001", 0.95),
        ("sandim_vortex_050", 0.85),
        ("bunny14_r0.05", 0.85),
        ("dambreak23_r0.05", 0.9),
        ("dualsphysics_dambreak3d", 0.95),
    ];
    against::check_shared_floors(
        &MarroneDetector::default(),
        &ExactDetector::default(),
        &floors,
    )
    .unwrap();
}

/// The same labels for a jittered lattice and its copies scaled by 1e-100 to 8e99 at r
/// scaled alike (r from 1.2e-100 to 9.6e99: the ends of `Radius`'s range): the kernel sums and the scan are computed in units of h (before, the
/// kernel's h^-D made every volume 0 or infinite at r = 1e150 in 3D).
#[test]
fn labels_are_the_same_for_the_scene_scaled_across_the_supported_radius_range() {
    fn check<const D: usize>(set: &ParticleSet<D>, r: f64, d: &MarroneDetector)
    where
        boundary_core::Dim<D>: boundary_core::SupportedDim,
    {
        let base = labels(d, set, r);
        let lambdas = d.lambdas(set, Radius::new(r).unwrap()).unwrap();
        for s in [1e-100, 1e-9, 1e-3, 0.37, 1e3, 1e9, 8e99] {
            let scaled = ParticleSet::new(set.positions().iter().map(|p| p * s).collect()).unwrap();
            assert_eq!(labels(d, &scaled, r * s), base, "{D}D {d}, scale {s}");
            let got = d.lambdas(&scaled, Radius::new(r * s).unwrap()).unwrap();
            for (x, y) in got.iter().zip(&lambdas) {
                assert!((x - y).abs() < 1e-12, "{D}D {d}, scale {s}: λ {x} vs {y}");
            }
        }
    }
    let disc = jittered_lattice_disc(9.0, 0.2, 5);
    let (ball, _) = jittered_lattice_ball(1500, 0.2, 6);
    for d in [
        MarroneDetector::default(),
        MarroneDetector::try_new(MarroneParams {
            lambda_surface: 0.1,
            lambda_interior: 0.9,
            cone_angle: 30.0,
            kernel: Kernel::CubicSpline,
            h_over_r: 1.3,
        })
        .unwrap(),
    ] {
        check(&disc, 1.2, &d);
        check(&ball, 1.2, &d);
    }
}

#[test]
fn degenerate_input_gives_the_documented_labels() {
    let d = MarroneDetector::default();
    let r = Radius::new(1.0).unwrap();
    let empty = ParticleSet::<3>::new(Vec::new()).unwrap();
    assert!(d.detect_3d(&empty, r).unwrap().labels.is_empty());
    let single = ParticleSet::from_rows(&[[1e6, -1e6]]).unwrap();
    assert_eq!(d.detect_2d(&single, r).unwrap().labels.as_slice(), [true]);
    // A pair, coincident or not, and a straight line: B is singular, λ = 0.
    let pair = ParticleSet::from_rows(&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]).unwrap();
    assert_eq!(d.detect_3d(&pair, r).unwrap().labels.boundary_count(), 2);
    let line: Vec<[f64; 2]> = (0..10).map(|k| [0.5 * k as f64, 0.0]).collect();
    let line = ParticleSet::from_rows(&line).unwrap();
    assert_eq!(d.detect_2d(&line, r).unwrap().labels.boundary_count(), 10);
    // Every particle twice: no panic, a sensible answer (the core of a 6^3 lattice at
    // r = 1.2 with h = r is not all boundary).
    let rows = boundary_scenes::cubic_lattice(6, 1.0);
    let doubled: Vec<[f64; 3]> = rows.iter().chain(rows.iter()).copied().collect();
    let doubled = ParticleSet::from_rows(&doubled).unwrap();
    let l = d
        .detect_3d(&doubled, Radius::new(1.2).unwrap())
        .unwrap()
        .labels;
    assert_eq!(l.len(), 432);
    assert!(l.boundary_count() < 432);
    for k in 0..216 {
        assert_eq!(
            l.is_boundary(k),
            l.is_boundary(k + 216),
            "copies of {k} agree"
        );
    }
}

#[test]
fn labels_do_not_depend_on_threads_or_decomposition() {
    against::check_threads_and_decomposition(&MarroneDetector::default()).unwrap();
}
