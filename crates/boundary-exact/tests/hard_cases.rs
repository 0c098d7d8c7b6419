//! Hard cases with answers derived by hand, and invariance properties.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_scenes::{cubic_lattice, shared_set, square_lattice};

use boundary_core::{BoundaryDetector, Detection, ParticleSet, Point, Radius};
use boundary_exact::{ExactDetector, ExactParams, TIE_TOLERANCE};
use proptest::prelude::*;

fn run2(rows: &[[f64; 2]], r: f64) -> Detection {
    ExactDetector::default()
        .detect_2d(
            &ParticleSet::from_rows(rows).unwrap(),
            Radius::new(r).unwrap(),
        )
        .unwrap()
}

fn run3(rows: &[[f64; 3]], r: f64) -> Detection {
    ExactDetector::default()
        .detect_3d(
            &ParticleSet::from_rows(rows).unwrap(),
            Radius::new(r).unwrap(),
        )
        .unwrap()
}

/// Number of lattice points not on the outer layer of an n^D block.
fn inner(n: usize, d: u32) -> usize {
    (n - 2).pow(d)
}

#[test]
fn empty_and_tiny_sets() {
    assert!(run2(&[], 1.0).labels.is_empty());
    assert!(run3(&[], 1.0).labels.is_empty());
    // 1, 2, 3 particles: always boundary (fewer than D + 1 balls cannot cover a sphere).
    let d = run2(&[[0.0, 0.0]], 1.0);
    assert_eq!(d.labels.as_slice(), &[true]);
    // An isolated particle's cell is the whole box: the margin saturates at (sqrt(D) - 1) r.
    assert!((d.margin.unwrap()[0] - (2f64.sqrt() - 1.0)).abs() < 1e-12);
    assert_eq!(
        run3(&[[0.0; 3], [0.5, 0.0, 0.0]], 1.0)
            .labels
            .boundary_count(),
        2
    );
    assert_eq!(
        run3(&[[0.0; 3], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0]], 1.0)
            .labels
            .boundary_count(),
        3
    );
    assert_eq!(
        run2(&[[0.0, 0.0], [0.1, 0.0], [0.0, 0.1]], 1.0)
            .labels
            .boundary_count(),
        3
    );
}

#[test]
fn two_particles_at_exactly_two_r() {
    let d = run2(&[[0.0, 0.0], [1.0, 0.0]], 0.5);
    assert_eq!(d.labels.as_slice(), &[true, true]);
    let d = run3(&[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]], 0.5);
    assert_eq!(d.labels.as_slice(), &[true, true]);
}

#[test]
fn exact_duplicates_do_not_cover_each_other() {
    // Two coincident particles alone are both boundary.
    assert_eq!(
        run2(&[[1.0, 1.0], [1.0, 1.0]], 1.0).labels.boundary_count(),
        2
    );
    assert_eq!(run3(&[[1.0; 3], [1.0; 3]], 1.0).labels.boundary_count(), 2);
    // Duplicating every particle of a lattice changes nothing: the duplicate of an interior
    // particle is covered by the same neighbours, and does not cover its twin.
    let base = square_lattice(7, 1.0);
    let mut doubled = base.clone();
    doubled.extend_from_slice(&base);
    let (a, b) = (run2(&base, 0.8), run2(&doubled, 0.8));
    assert_eq!(&b.labels.as_slice()[..base.len()], a.labels.as_slice());
    assert_eq!(&b.labels.as_slice()[base.len()..], a.labels.as_slice());
}

#[test]
fn near_duplicates_are_ordinary_neighbours() {
    // A pair 1e-12 apart alone: each halves the other's cell, both stay boundary.
    let d = run3(&[[0.0; 3], [1e-12, 0.0, 0.0]], 0.01);
    assert_eq!(d.labels.boundary_count(), 2);
    // An interior lattice particle with a near-duplicate twin: both remain interior.
    let mut rows = cubic_lattice(5, 1.0);
    rows.push([2.0 + 1e-12, 2.0, 2.0]);
    let d = run3(&rows, 1.2);
    assert!(!d.labels.is_boundary(62)); // the centre (2, 2, 2)
    assert!(!d.labels.is_boundary(rows.len() - 1));
}

#[test]
fn square_lattice_counts_and_exact_ties() {
    // Interior cells are unit squares with half-diagonal a/sqrt(2).
    let n = 8;
    let rows = square_lattice(n, 1.0);
    assert_eq!(
        run2(&rows, 0.8).labels.boundary_count(),
        n * n - inner(n, 2)
    );
    // At r = a/sqrt(2) every inner particle is an exact tie: interior, margin ~ 0.
    let r = std::f64::consts::FRAC_1_SQRT_2;
    let d = run2(&rows, r);
    assert_eq!(d.labels.boundary_count(), n * n - inner(n, 2));
    let m = d.margin.unwrap();
    let centre = n / 2 * n + n / 2;
    assert!(m[centre].abs() <= TIE_TOLERANCE * r, "{}", m[centre]);
    // Just below the tie radius every particle is boundary (gaps open at the cell corners).
    assert_eq!(run2(&rows, r * (1.0 - 1e-6)).labels.boundary_count(), n * n);
}

#[test]
fn cubic_lattice_counts_and_exact_ties() {
    let n = 6;
    let rows = cubic_lattice(n, 1.0);
    assert_eq!(
        run3(&rows, 1.2).labels.boundary_count(),
        n * n * n - inner(n, 3)
    );
    // fl(√3/2) lies 1 ulp below a·√3/2: the cube corners are uncovered, every particle is
    // boundary (exact labels); the next float up is above the tie: inner particles interior.
    let r = 3f64.sqrt() / 2.0;
    let d = run3(&rows, r);
    assert_eq!(d.labels.boundary_count(), n * n * n);
    let centre = (n / 2 * n + n / 2) * n + n / 2;
    assert!(d.margin.unwrap()[centre].abs() <= TIE_TOLERANCE * r);
    let up = run3(&rows, r.next_up());
    assert_eq!(up.labels.boundary_count(), n * n * n - inner(n, 3));
    // The opt-in tolerance `tie=1e-9` treats the round-off as a tie: interior again.
    let loose = ExactDetector::try_new(ExactParams { tie: TIE_TOLERANCE })
        .unwrap()
        .detect_3d(
            &ParticleSet::from_rows(&rows).unwrap(),
            Radius::new(r).unwrap(),
        )
        .unwrap();
    assert_eq!(loose.labels.boundary_count(), n * n * n - inner(n, 3));
    assert_eq!(
        run3(&rows, r * (1.0 - 1e-6)).labels.boundary_count(),
        n * n * n
    );
}

#[test]
fn far_offset_scenes_keep_their_labels() {
    let rows = cubic_lattice(5, 0.01);
    let base = run3(&rows, 0.012);
    for offset in [1e6, -1e6] {
        let moved: Vec<[f64; 3]> = rows
            .iter()
            .map(|p| [p[0] + offset, p[1] + 0.5 * offset, p[2] - offset])
            .collect();
        assert_eq!(run3(&moved, 0.012).labels, base.labels);
    }
    let rows2 = square_lattice(6, 0.01);
    let moved2: Vec<[f64; 2]> = rows2.iter().map(|p| [p[0] + 1e6, p[1] + 1e6]).collect();
    assert_eq!(run2(&moved2, 0.008).labels, run2(&rows2, 0.008).labels);
}

#[test]
fn collinear_and_coplanar_sets_are_all_boundary() {
    let line: Vec<[f64; 3]> = (0..10).map(|k| [k as f64 * 0.3, 0.0, 0.0]).collect();
    assert_eq!(run3(&line, 1.0).labels.boundary_count(), 10);
    let plane: Vec<[f64; 3]> = square_lattice(6, 0.3)
        .into_iter()
        .map(|p| [p[0], p[1], 0.0])
        .collect();
    assert_eq!(run3(&plane, 1.0).labels.boundary_count(), 36);
}

#[test]
fn radius_from_tiny_to_huge() {
    for scale in [1e-9, 1e-3, 1.0, 1e3, 1e9] {
        let rows: Vec<[f64; 3]> = cubic_lattice(5, scale);
        assert_eq!(run3(&rows, 1.2 * scale).labels.boundary_count(), 125 - 27);
    }
}

#[test]
fn thread_count_does_not_change_labels() {
    let Some(set) = shared_set::<3>("particles3d/splashsurf_dam_break_frame_9_6859.csv").unwrap()
    else {
        return;
    };
    let r = Radius::new(0.05).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| ExactDetector::default().detect_3d(&set, r).unwrap())
    };
    let one = run(1);
    assert_eq!(run(2), one);
    assert_eq!(run(5), one);
}

/// A jittered lattice patch: random but with well-spread particles, the setting of SPH data.
fn jittered_rows<const D: usize>(jitter: &[f64], n_side: usize) -> Vec<Point<D>>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let count = n_side.pow(D as u32);
    (0..count)
        .map(|k| {
            Point::<D>::from_fn(|axis, _| {
                let idx = (k / n_side.pow(axis as u32)) % n_side;
                idx as f64 + 0.3 * jitter[(k * D + axis) % jitter.len()]
            })
        })
        .collect()
}

fn labels_away_from_ties(d: &Detection, r: f64) -> Vec<Option<bool>> {
    let m = d.margin.as_ref().unwrap();
    m.iter()
        .map(|&x| (x.abs() > 1e-6 * r).then_some(x > 0.0))
        .collect()
}

fn agree(a: &[Option<bool>], b: &[Option<bool>]) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| x.is_none() || y.is_none() || x == y)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn invariant_under_rigid_motion_scaling_and_permutation(
        jitter in proptest::collection::vec(-1.0f64..1.0, 64),
        angles in (0.0f64..6.3, 0.0f64..6.3, 0.0f64..6.3),
        shift in (-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3),
        scale in 1e-3f64..1e3,
        r in 0.6f64..1.4,
        rotate_by in 0usize..1000,
    ) {
        use boundary_core::nalgebra::{Rotation2, Rotation3, Vector3};
        // 3D
        let pts = jittered_rows::<3>(&jitter, 5);
        let set = ParticleSet::new(pts.clone()).unwrap();
        let base = ExactDetector::default().detect_3d(&set, Radius::new(r).unwrap()).unwrap();
        let base_l = labels_away_from_ties(&base, r);
        let rot = Rotation3::from_euler_angles(angles.0, angles.1, angles.2);
        let t = Vector3::new(shift.0, shift.1, shift.2);
        let moved: Vec<_> = pts.iter().map(|p| (rot * p + t) * scale).collect();
        let d = ExactDetector::default()
            .detect_3d(&ParticleSet::new(moved).unwrap(), Radius::new(r * scale).unwrap())
            .unwrap();
        prop_assert!(agree(&labels_away_from_ties(&d, r * scale), &base_l));
        // Permutation: rotate the input order.
        let k = rotate_by % pts.len();
        let mut perm = pts.clone();
        perm.rotate_left(k);
        let d = ExactDetector::default()
            .detect_3d(&ParticleSet::new(perm).unwrap(), Radius::new(r).unwrap())
            .unwrap();
        let mut back = labels_away_from_ties(&d, r);
        back.rotate_right(k);
        prop_assert_eq!(back, base_l);
        // 2D
        let pts2 = jittered_rows::<2>(&jitter, 7);
        let base2 = ExactDetector::default()
            .detect_2d(&ParticleSet::new(pts2.clone()).unwrap(), Radius::new(r).unwrap())
            .unwrap();
        let rot2 = Rotation2::new(angles.0);
        let moved2: Vec<_> = pts2
            .iter()
            .map(|p| (rot2 * p + t.xy()) * scale)
            .collect();
        let d2 = ExactDetector::default()
            .detect_2d(&ParticleSet::new(moved2).unwrap(), Radius::new(r * scale).unwrap())
            .unwrap();
        prop_assert!(agree(
            &labels_away_from_ties(&d2, r * scale),
            &labels_away_from_ties(&base2, r)
        ));
    }
}
