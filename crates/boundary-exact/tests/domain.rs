//! `exact` in a domain: solid half-spaces against brute-force enumeration in exact rationals
//! (`boundary_scenes::brute`, written without any code of `exact`), near-ties included; walls,
//! periodic images and phases against the sets they stand for, built in the test.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{
    AnyParticleSet, BoundaryDetector, Domain, HalfSpace, ParticleSet, Periodic, Point, Radius,
};
use boundary_core::{Dim, SupportedDim};
use boundary_exact::ExactDetector;
use boundary_scenes::brute::solid_uncovered_by_enumeration;

/// A small deterministic generator (the scenes must not change between runs).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Labels of `set` with `solids` by brute force: every other particle is a ball of radius `r`.
/// A particle whose closed ball stays clear of every solid by `r/100` gets its label without
/// the solids (which cannot reach it) by the same brute force, so only the layer next to the
/// solids pays for the larger cell.
fn brute<const D: usize>(set: &ParticleSet<D>, r: f64, solids: &[HalfSpace]) -> Vec<bool>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let solids: Vec<(usize, bool, f64)> = solids
        .iter()
        .map(|h| (h.axis(), h.solid_below(), h.value()))
        .collect();
    let rows: Vec<[f64; D]> = set
        .positions()
        .iter()
        .map(|p| std::array::from_fn(|k| p[k]))
        .collect();
    (0..rows.len())
        .map(|i| {
            let others: Vec<([f64; D], f64)> = rows
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| (*q, r))
                .collect();
            let clear = solids.iter().all(|&(axis, below, c)| {
                let depth = if below {
                    rows[i][axis] - c
                } else {
                    c - rows[i][axis]
                };
                depth > 1.01 * r
            });
            if clear {
                solid_uncovered_by_enumeration(rows[i], r, &others, &[])
            } else {
                solid_uncovered_by_enumeration(rows[i], r, &others, &solids)
            }
        })
        .collect()
}

fn exact_in<const D: usize>(set: &ParticleSet<D>, r: f64, solids: &[HalfSpace]) -> Vec<bool>
where
    AnyParticleSet: From<ParticleSet<D>>,
{
    let domain = solids.iter().fold(Domain::new(), |d, h| d.with_solid(*h));
    ExactDetector::default()
        .detect_in(
            &AnyParticleSet::from(set.clone()),
            &domain,
            Radius::new(r).unwrap(),
        )
        .unwrap()
        .detection
        .labels
        .into_vec()
}

/// A jittered block of `nx` × `ny` (× `nz`) particles of spacing 1, resting at height 0.5 on
/// the floor `y = 0`: some particles pushed into the floor by the jitter.
fn block<const D: usize>(counts: [usize; D], jitter: f64, seed: u64) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    let mut rng = Lcg(seed);
    let total: usize = counts.iter().product();
    let mut points = Vec::with_capacity(total);
    for k in 0..total {
        let mut rest = k;
        let p = Point::<D>::from_fn(|axis, _| {
            let c = rest % counts[axis];
            rest /= counts[axis];
            let base = if axis == 1 { c as f64 + 0.5 } else { c as f64 };
            base + jitter * (rng.next() - 0.5)
        });
        points.push(p);
    }
    ParticleSet::new(points).unwrap()
}

#[test]
fn floors_and_tanks_match_brute_force_in_2d_and_3d() {
    let floor = |c: f64| HalfSpace::new(1, true, c).unwrap();
    for seed in 1..4 {
        let set = block([7, 4], 0.6, seed);
        for r in [0.62, 0.8, 1.1] {
            let bare = exact_in(&set, r, &[]);
            for c in [0.0, 0.3, 0.5, 0.9] {
                let solids = [floor(c)];
                let labels = exact_in(&set, r, &solids);
                assert_eq!(
                    labels,
                    brute(&set, r, &solids),
                    "2D seed {seed}, r {r}, floor y<{c}"
                );
                // Below 1/√2 spacings the jittered block is all boundary, floor or not.
                if r > 0.75 {
                    assert_ne!(labels, bare, "the floor y<{c} covers some particles");
                }
            }
        }
    }
    // A 3D tank: floor, two side walls and the back wall (one side open), fluid touching them.
    {
        let seed = 1;
        let set = block([4, 3, 3], 0.5, seed);
        let tank = [
            floor(0.1),
            HalfSpace::new(0, true, -0.4).unwrap(),
            HalfSpace::new(0, false, 3.4).unwrap(),
            HalfSpace::new(2, true, -0.45).unwrap(),
        ];
        let labels = exact_in(&set, 0.95, &tank);
        assert_eq!(labels, brute(&set, 0.95, &tank), "3D seed {seed}");
        let bare = exact_in(&set, 0.95, &[]);
        assert!(
            labels.iter().filter(|&&b| b).count() < bare.iter().filter(|&&b| b).count(),
            "the tank covers some particles"
        );
    }
}

#[test]
fn a_solid_through_the_gap_of_two_caps_is_an_exact_tie() {
    // Rows at y = 0.5 and 1.0, spacing 1 in x, r = 0.625: the bottom particle at (0, 0.5) is
    // uncovered exactly on the arc below y = 0.5 − 0.375 = 0.125 between its neighbours' caps
    // (their circles meet S_i at (±0.5, 0.125)). A floor through those points holds the arc:
    // a tie, interior; one ulp lower, the arc's ends poke out: boundary.
    let mut rows = Vec::new();
    for x in -3..=3 {
        rows.push([f64::from(x), 0.5]);
        rows.push([f64::from(x), 1.0]);
    }
    let set = ParticleSet::<2>::from_rows(&rows).unwrap();
    let centre = rows.iter().position(|p| *p == [0.0, 0.5]).unwrap();
    let r = 0.625;
    for (c, boundary) in [
        (0.125, false),
        (0.125f64.next_up(), false),
        (0.125f64.next_down(), true),
    ] {
        let solids = [HalfSpace::new(1, true, c).unwrap()];
        let labels = exact_in(&set, r, &solids);
        assert_eq!(labels[centre], boundary, "floor y<{c:e}");
        assert_eq!(labels, brute(&set, r, &solids), "floor y<{c:e}");
    }
    // The same in 3D along x, with a layer in z: the bottom particle's gap between the caps of
    // its x neighbours and its z neighbours, all at distance 1, and rows 0.5 above.
    let mut rows3 = Vec::new();
    for x in -2..=2 {
        for z in -2..=2 {
            rows3.push([f64::from(x), 0.5, f64::from(z)]);
            rows3.push([f64::from(x), 1.0, f64::from(z)]);
        }
    }
    let set3 = ParticleSet::<3>::from_rows(&rows3).unwrap();
    let centre3 = rows3.iter().position(|p| *p == [0.0, 0.5, 0.0]).unwrap();
    for c in [0.125, 0.125f64.next_down(), -0.1, 0.2] {
        let solids = [HalfSpace::new(1, true, c).unwrap()];
        let labels = exact_in(&set3, r, &solids);
        let expected = brute(&set3, r, &solids);
        assert_eq!(labels[centre3], expected[centre3], "3D floor y<{c:e}");
        assert_eq!(labels, expected, "3D floor y<{c:e}");
    }
}

#[test]
fn spheres_inside_a_solid_are_interior_and_solids_only_remove_boundary() {
    let set = block([6, 4], 0.4, 7);
    let r = Radius::new(0.7).unwrap();
    let bare = ExactDetector::default()
        .detect(&set.to_any(), r)
        .unwrap()
        .labels
        .into_vec();
    // A solid above everything changes nothing; one covering the whole block makes it interior.
    let above = [HalfSpace::new(1, false, 100.0).unwrap()];
    assert_eq!(exact_in(&set, 0.7, &above), bare);
    let all = [HalfSpace::new(1, true, 100.0).unwrap()];
    assert!(exact_in(&set, 0.7, &all).iter().all(|&b| !b));
    // Adding a solid never makes a particle boundary.
    for c in [0.2, 0.6, 1.5, 2.5] {
        let with = exact_in(&set, 0.7, &[HalfSpace::new(1, true, c).unwrap()]);
        for (i, (&w, &b)) in with.iter().zip(&bare).enumerate() {
            assert!(
                !w || b,
                "particle {i} became boundary under the floor y<{c}"
            );
        }
    }
}

#[test]
fn walls_periodic_images_and_phases_equal_the_sets_they_stand_for() {
    let r = Radius::new(0.8).unwrap();
    let fluid = block([8, 4], 0.3, 11);
    let mut wall_rows = Vec::new();
    for x in -3..=10 {
        for y in [-0.5, -1.5] {
            wall_rows.push([f64::from(x), y]);
        }
    }
    let walls = ParticleSet::<2>::from_rows(&wall_rows).unwrap();
    // Walls: the labels of the union's fluid part.
    let mut union: Vec<Point<2>> = fluid.positions().to_vec();
    union.extend(walls.positions());
    let union = ParticleSet::new(union).unwrap();
    let expected: Vec<bool> = ExactDetector::default()
        .detect(&union.to_any(), r)
        .unwrap()
        .labels
        .into_vec()[..fluid.len()]
        .to_vec();
    let domain = Domain::new().with_walls(walls.to_any());
    let got = ExactDetector::default()
        .detect_in(&fluid.to_any(), &domain, r)
        .unwrap();
    assert_eq!(got.detection.labels.into_vec(), expected);
    assert!(got.interface.is_none());

    // Periodic in x over [-0.5, 7.5]: the labels of the set with its images at ±8 written out.
    let periodic = Periodic::new(0, -0.5, 7.5).unwrap();
    let mut with_images: Vec<Point<2>> = fluid.positions().to_vec();
    for shift in [8.0, -8.0] {
        with_images.extend(
            fluid
                .positions()
                .iter()
                .map(|p| Point::<2>::new(p[0] + shift, p[1])),
        );
    }
    let with_images = ParticleSet::new(with_images).unwrap();
    let expected: Vec<bool> = ExactDetector::default()
        .detect(&with_images.to_any(), r)
        .unwrap()
        .labels
        .into_vec()[..fluid.len()]
        .to_vec();
    let got = ExactDetector::default()
        .detect_in(&fluid.to_any(), &Domain::new().with_periodic(periodic), r)
        .unwrap();
    assert_eq!(got.detection.labels.into_vec(), expected);
    // With images no particle on the periodic faces is boundary for lack of a neighbour there.
    assert!(
        expected.iter().filter(|&&b| b).count()
            < ExactDetector::default()
                .detect(&fluid.to_any(), r)
                .unwrap()
                .labels
                .boundary_count()
    );

    // Phases: the lower two rows phase 0, the upper two phase 1. An interface particle is one
    // that the whole fluid covers but its own phase (and the walls) does not.
    let phases: Vec<u32> = fluid
        .positions()
        .iter()
        .map(|p| u32::from(p[1] > 2.0))
        .collect();
    let domain = Domain::new()
        .with_walls(walls.to_any())
        .with_phases(phases.clone());
    let got = ExactDetector::default()
        .detect_in(&fluid.to_any(), &domain, r)
        .unwrap();
    let free = got.detection.labels.clone().into_vec();
    let interface = got.interface.unwrap().into_vec();
    for k in [0u32, 1] {
        let members: Vec<usize> = (0..fluid.len()).filter(|&i| phases[i] == k).collect();
        let mut own: Vec<Point<2>> = members.iter().map(|&i| fluid.positions()[i]).collect();
        own.extend(walls.positions());
        let own = ExactDetector::default()
            .detect(&ParticleSet::new(own).unwrap().to_any(), r)
            .unwrap()
            .labels;
        for (slot, &i) in members.iter().enumerate() {
            assert_eq!(
                interface[i],
                own.is_boundary(slot) && !free[i],
                "particle {i}"
            );
        }
    }
    assert!(
        interface.iter().any(|&b| b),
        "the two phases meet: some interface"
    );
}

#[test]
fn a_period_shorter_than_the_reach_is_refused_by_name() {
    let fluid = block([4, 2], 0.0, 1);
    let domain = Domain::new().with_periodic(Periodic::new(0, -0.5, 1.0).unwrap());
    let e = ExactDetector::default()
        .detect_in(&fluid.to_any(), &domain, Radius::new(0.8).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("period 1.5 is shorter than the reach 1.6"),
        "{e}"
    );
}
