//! `divr` on cases computed by hand: a lattice whose kernel support holds only the four
//! nearest neighbours (a closed form), the interior value `d` of a uniform lattice (and how
//! close the discrete sum comes to it), the isolated particles, the layer expansion against
//! brute force, and the spatial-temporal variant's rules.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{BoundaryDetector, Labels, ParticleSet, Radius};
use boundary_divr::{DivrDetector, DivrParams, Threshold};
use boundary_scenes::jittered_lattice_disc;
use boundary_sph::Kernel;

fn square(n: usize) -> ParticleSet<2> {
    let rows: Vec<[f64; 2]> = (0..n * n)
        .map(|k| [(k % n) as f64, (k / n) as f64])
        .collect();
    ParticleSet::from_rows(&rows).unwrap()
}

fn cube(n: usize) -> ParticleSet<3> {
    let rows: Vec<[f64; 3]> = (0..n * n * n)
        .map(|k| [(k % n) as f64, (k / n % n) as f64, (k / (n * n)) as f64])
        .collect();
    ParticleSet::from_rows(&rows).unwrap()
}

/// A 5 x 5 lattice of spacing 1 at h = 0.6 (support 1.2): the centre and its four neighbours
/// each see exactly their four axis neighbours at q = 1/0.6 = 5/3. With Wendland C2,
/// f(q) = (1 − q/2)^4 (1 + 2q) and −f'(q)/q = 5 (1 − q/2)^3, so (σ cancels)
/// V = 1/(σ (f(0) + 4 f(q))) and ∇·r = 4 V σ 5 (1 − q/2)^3 q². With 1 − q/2 = 1/6:
/// ∇·r = (20 · 25/9 / 216) / (1 + 4 · 13/3 / 1296) = (125/486) / (985/972) = 50/197.
#[test]
fn a_nearest_neighbour_kernel_gives_the_closed_form() {
    let d = DivrDetector::try_new(DivrParams {
        h_over_r: 0.6,
        ..DivrParams::default()
    })
    .unwrap();
    let a = d.analyse(&square(5), Radius::new(1.0).unwrap()).unwrap();
    assert!(
        (a.divergence[12] - 50.0 / 197.0).abs() < 1e-14,
        "{}",
        a.divergence[12]
    );
    assert_eq!(a.neighbours[12], 4);
    // So narrow a kernel sees no interior at all: every particle is below 1.5.
    assert_eq!(a.labels.boundary_count(), 25);
    // The corner sees 2 neighbours (< d + 1 = 3): isolated; the edge particles 3: not.
    assert!(a.isolated.is_boundary(0) && !a.isolated.is_boundary(2));
}

/// In the continuum ∇·r = d exactly (∫ (y − x)·∇_x W dy = d ∫ W = d for a normalised
/// kernel); on a lattice with summation-density volumes the sum is a quadrature of that
/// integral, below d by 6% at h = Δx and within 1% from h = 1.5Δx (both kernels, 2D and 3D),
/// the tolerances asserted here. At a flat face it is close to d/2 + a little (the face
/// particle's own half-space plus the missing half's volumes).
#[test]
fn the_interior_of_a_uniform_lattice_has_divergence_close_to_the_dimension() {
    for kernel in Kernel::ALL {
        for (h, tolerance) in [(1.0, 0.07), (1.5, 0.01), (2.0, 0.01), (3.0, 0.01)] {
            let d = DivrDetector::try_new(DivrParams {
                kernel,
                ..DivrParams::default()
            })
            .unwrap();
            let r = Radius::new(h).unwrap();
            let a2 = d.analyse(&square(21), r).unwrap();
            let centre = a2.divergence[220];
            assert!(
                (centre / 2.0 - 1.0).abs() < tolerance,
                "{kernel} h {h}: 2D centre {centre}"
            );
            let face = a2.divergence[10];
            assert!(face > 1.0 && face < 1.6, "{kernel} h {h}: 2D edge {face}");
            let a3 = d.analyse(&cube(15), r).unwrap();
            let centre = a3.divergence[7 + 7 * 15 + 7 * 225];
            assert!(
                (centre / 3.0 - 1.0).abs() < tolerance,
                "{kernel} h {h}: 3D centre {centre}"
            );
            let face = a3.divergence[7 + 7 * 15];
            assert!(face > 1.5 && face < 2.5, "{kernel} h {h}: 3D face {face}");
        }
    }
}

#[test]
fn isolated_particles_are_boundary_and_reported() {
    let d = DivrDetector::default();
    let r = Radius::new(1.0).unwrap();
    let single = ParticleSet::from_rows(&[[3.0, 4.0]]).unwrap();
    let a = d.analyse(&single, r).unwrap();
    assert_eq!((a.divergence[0], a.neighbours[0]), (0.0, 0));
    assert_eq!(a.isolated.as_slice(), [true]);
    assert_eq!(a.labels.as_slice(), [true]);
    // Coincident pair: one neighbour each, no distance, ∇·r = 0.
    let pair = ParticleSet::from_rows(&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]).unwrap();
    let a = d.analyse(&pair, r).unwrap();
    assert_eq!(a.divergence, [0.0, 0.0]);
    assert_eq!(a.isolated.boundary_count(), 2);
    // A line of three 1.2 apart in 2D (support 2): the ends have 1 neighbour, the middle 2,
    // all fewer than 3: isolated and boundary; with min_neighbours = 2 the middle is not
    // isolated, but ∇·r is far below 1.5.
    let three = ParticleSet::from_rows(&[[0.0, 0.0], [1.2, 0.0], [2.4, 0.0]]).unwrap();
    assert_eq!(d.analyse(&three, r).unwrap().isolated.as_slice(), [true; 3]);
    let two = DivrDetector::try_new(DivrParams {
        min_neighbours: Some(2),
        ..DivrParams::default()
    })
    .unwrap();
    let a = two.analyse(&three, r).unwrap();
    assert_eq!(a.isolated.as_slice(), [true, false, true]);
    assert_eq!(a.labels.as_slice(), [true; 3]);
    // analyse gives detect's labels.
    let disc = jittered_lattice_disc(8.0, 0.2, 4);
    assert_eq!(
        d.analyse(&disc, r).unwrap().labels,
        d.detect_2d(&disc, r).unwrap().labels
    );
    let empty = ParticleSet::<3>::new(Vec::new()).unwrap();
    assert!(d.detect_3d(&empty, r).unwrap().labels.is_empty());
}

#[test]
fn one_layer_flags_every_particle_within_h_of_a_flagged_one() {
    let disc = jittered_lattice_disc(10.0, 0.2, 7);
    let r = Radius::new(1.2).unwrap();
    let base = DivrDetector::default().detect_2d(&disc, r).unwrap();
    let layered = DivrDetector::try_new(DivrParams {
        layers: 1,
        ..DivrParams::default()
    })
    .unwrap()
    .detect_2d(&disc, r)
    .unwrap();
    let p = disc.positions();
    for i in 0..disc.len() {
        let brute =
            (0..disc.len()).any(|j| base.labels.is_boundary(j) && (p[i] - p[j]).norm() <= 1.2);
        assert_eq!(layered.labels.is_boundary(i), brute, "{i}");
    }
    assert!(layered.labels.boundary_count() > base.labels.boundary_count());
    assert_eq!(layered.margin, base.margin, "the margin is the criterion's");
}

#[test]
fn the_spatial_temporal_variant_needs_a_previous_flag_nearby() {
    let disc = jittered_lattice_disc(12.0, 0.25, 9);
    let r = Radius::new(1.2).unwrap();
    let any = disc.to_any();
    // A threshold close to the interior value, so that the jitter puts spurious low values
    // inside the disc, which the variant removes.
    let d = DivrDetector::try_new(DivrParams {
        threshold: Threshold::Value(1.85),
        ..DivrParams::default()
    })
    .unwrap();
    let plain = d.detect_2d(&disc, r).unwrap();
    let a = d.analyse(&disc, r).unwrap();
    let n = disc.len();
    // Every particle flagged before: the plain labels. None: the isolated ones only.
    let all = d
        .detect_following(&any, r, &Labels::new(vec![true; n]))
        .unwrap();
    assert_eq!(all, plain);
    let none = d
        .detect_following(&any, r, &Labels::new(vec![false; n]))
        .unwrap();
    assert_eq!(none.labels, a.isolated);
    // Only the particles beyond 9 from the centre flagged before: a low value deeper than
    // 9 − 2h counts no more; the others keep their plain label.
    let p = disc.positions();
    let previous: Labels = p.iter().map(|x| x.norm() > 9.0).collect();
    let got = d.detect_following(&any, r, &previous).unwrap().labels;
    for i in 0..n {
        let near = (0..n).any(|j| previous.is_boundary(j) && (p[i] - p[j]).norm() <= 2.4);
        let expected = (plain.labels.is_boundary(i) && near) || a.isolated.is_boundary(i);
        assert_eq!(got.is_boundary(i), expected, "{i}");
    }
    assert!(got.boundary_count() < plain.labels.boundary_count());
    // A previous-label count that does not match is an error naming both counts.
    let err = d
        .detect_following(&any, r, &Labels::new(vec![false; n - 1]))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(&format!("{} previous labels for {n}", n - 1)),
        "{err}"
    );
    let radii = disc.clone().with_radii(vec![1.0; n]).unwrap().to_any();
    assert!(d.detect_following(&radii, r, &previous).is_err());
    // The named thresholds order the labels: a higher value flags a superset.
    let at = |t: Threshold| {
        DivrDetector::try_new(DivrParams {
            threshold: t,
            ..DivrParams::default()
        })
        .unwrap()
        .detect_2d(&disc, r)
        .unwrap()
        .labels
    };
    let (low, high) = (at(Threshold::Value(1.2)), at(Threshold::Chrono));
    for i in 0..n {
        assert!(!low.is_boundary(i) || high.is_boundary(i));
    }
    assert!(low.boundary_count() < high.boundary_count());
}
