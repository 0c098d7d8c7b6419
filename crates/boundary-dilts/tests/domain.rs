//! `dilts` with solid half-spaces: labels against brute-force enumeration in exact rationals
//! (`boundary_scenes::brute`, independent of both `dilts` and `exact`), near-ties included, and
//! against `exact`'s labels in the same domains (both are exact).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{
    BoundaryDetector, Detection, Domain, HalfSpace, ParticleSet, Point, Radius, Solids,
};
use boundary_core::{Dim, SupportedDim};
use boundary_dilts::{DiltsDetector, DiltsParams};
use boundary_exact::ExactDetector;
use boundary_scenes::brute::solid_uncovered_by_enumeration;

/// A deterministic generator: the scenes are the same on every run.
struct Lcg(u64);

impl Lcg {
    /// Uniform in `[0, 1)`.
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `counts[0]` × `counts[1]` (× `counts[2]`) particles of spacing 1, each moved by up to
/// `jitter/2` per axis, the lowest layer at height 0.5 (the floor `y < 0` touches it).
fn block<const D: usize>(counts: [usize; D], jitter: f64, seed: u64) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    let mut rng = Lcg(seed);
    let total: usize = counts.iter().product();
    let points: Vec<Point<D>> = (0..total)
        .map(|k| {
            let mut rest = k;
            Point::<D>::from_fn(|axis, _| {
                let cell = rest % counts[axis];
                rest /= counts[axis];
                let lift = if axis == 1 { 0.5 } else { 0.0 };
                cell as f64 + lift + jitter * (rng.next() - 0.5)
            })
        })
        .collect();
    ParticleSet::new(points).unwrap()
}

fn solids_of(half_spaces: &[HalfSpace]) -> Solids {
    let mut solids = Solids::new();
    for &h in half_spaces {
        solids.push(h);
    }
    solids
}

fn floor(c: f64) -> HalfSpace {
    HalfSpace::new(1, true, c).unwrap()
}

/// Labels by brute force: particle `i` (radius `r·s_i`) against the balls of the others that
/// may reach its sphere (the oracle drops those that do not, exactly), with the solids. With
/// `near_only` (3D, where the oracle is slow), only the particles whose ball reaches a solid
/// (within 1%) are decided (`None` for the others, which no solid can change).
fn brute<const D: usize>(
    set: &ParticleSet<D>,
    r: f64,
    half_spaces: &[HalfSpace],
    near_only: bool,
) -> Vec<Option<bool>>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let solids: Vec<(usize, bool, f64)> = half_spaces
        .iter()
        .map(|h| (h.axis(), h.solid_below(), h.value()))
        .collect();
    let radius = |i: usize| set.radii().map_or(r, |s| r * s[i]);
    let row = |p: &Point<D>| -> [f64; D] { std::array::from_fn(|k| p[k]) };
    let positions = set.positions();
    (0..set.len())
        .map(|i| {
            let near = half_spaces
                .iter()
                .any(|h| h.fluid_depth(positions[i].as_slice()) <= 1.01 * radius(i));
            if near_only && !near {
                return None;
            }
            let others: Vec<([f64; D], f64)> = (0..set.len())
                .filter(|&j| j != i)
                .filter(|&j| {
                    let reach = (radius(i) + radius(j)) * (1.0 + 1e-9);
                    (positions[j] - positions[i]).norm() <= reach
                })
                .map(|j| (row(&positions[j]), radius(j)))
                .collect();
            Some(solid_uncovered_by_enumeration(
                row(&positions[i]),
                radius(i),
                &others,
                &solids,
            ))
        })
        .collect()
}

/// The detection of `detector` with the solids `half_spaces` (no wall: every particle owned).
fn detect_in<const D: usize>(
    detector: &dyn BoundaryDetector,
    set: &ParticleSet<D>,
    r: f64,
    half_spaces: &[HalfSpace],
) -> Detection
where
    Dim<D>: SupportedDim,
{
    let domain = half_spaces
        .iter()
        .fold(Domain::new(), |d, &h| d.with_solid(h));
    detector
        .detect_in(&set.to_any(), &domain, Radius::new(r).unwrap())
        .unwrap()
        .detection
}

fn labels<const D: usize>(
    detector: &dyn BoundaryDetector,
    set: &ParticleSet<D>,
    r: f64,
    half_spaces: &[HalfSpace],
) -> Vec<bool>
where
    Dim<D>: SupportedDim,
{
    detect_in(detector, set, r, half_spaces).labels.into_vec()
}

/// `dilts` equals the brute force and `exact`; returns the labels.
fn check<const D: usize>(
    what: &str,
    set: &ParticleSet<D>,
    r: f64,
    half_spaces: &[HalfSpace],
) -> Vec<bool>
where
    Dim<D>: SupportedDim,
{
    let dilts = labels(&DiltsDetector::default(), set, r, half_spaces);
    let expected = brute(set, r, half_spaces, D == 3);
    let wrong: Vec<usize> = (0..set.len())
        .filter(|&i| expected[i].is_some_and(|b| b != dilts[i]))
        .collect();
    assert!(
        wrong.is_empty(),
        "{what}: dilts != brute force at {wrong:?}"
    );
    assert_eq!(
        dilts,
        labels(&ExactDetector::default(), set, r, half_spaces),
        "{what}: dilts != exact"
    );
    dilts
}

#[test]
fn floors_at_several_heights_match_brute_force_in_2d() {
    for seed in 1..3 {
        let set = block([7, 4], 0.6, seed);
        // Floors below the block, through its lowest layer, through one particle exactly (a
        // particle on the solid's surface), and above the lowest layer (particles inside).
        let through = set.positions()[3][1];
        for r in [0.62, 0.8, 1.1] {
            let bare = labels(&DiltsDetector::default(), &set, r, &[]);
            for c in [-0.3, 0.0, 0.3, 0.5, through, 0.9] {
                let what = format!("2D seed {seed}, r {r}, floor y<{c}");
                let with = check(&what, &set, r, &[floor(c)]);
                // A solid only covers: it never makes a particle boundary.
                assert!(with.iter().zip(&bare).all(|(&w, &b)| !w || b), "{what}");
            }
        }
    }
}

#[test]
fn a_floor_and_a_tank_match_brute_force_in_3d() {
    let set = block([3, 3, 3], 0.5, 1);
    let r = 0.9;
    // A floor through the lowest layer (some particles inside the solid).
    check("3D floor y<0.3", &set, r, &[floor(0.3)]);
    // A tank of five half-spaces: floor, two side walls, back and front walls, all touched.
    let tank = [
        floor(0.1),
        HalfSpace::new(0, true, -0.4).unwrap(),
        HalfSpace::new(0, false, 2.4).unwrap(),
        HalfSpace::new(2, true, -0.45).unwrap(),
        HalfSpace::new(2, false, 2.4).unwrap(),
    ];
    let with = check("3D tank", &set, r, &tank);
    let bare = labels(&DiltsDetector::default(), &set, r, &[]);
    let count = |l: &[bool]| l.iter().filter(|&&b| b).count();
    assert!(
        count(&with) < count(&bare),
        "the tank covers some particles"
    );
}

#[test]
fn per_particle_radii_with_a_floor_match_brute_force() {
    let mut rng = Lcg(5);
    let set = block([6, 4], 0.4, 3);
    let factors: Vec<f64> = (0..set.len())
        .map(|_| if rng.next() < 0.5 { 1.0 } else { 1.35 })
        .collect();
    let set = set.with_radii(factors).unwrap();
    for c in [0.0, 0.4, 0.8] {
        check(&format!("radii, floor y<{c}"), &set, 0.6, &[floor(c)]);
    }
    let set3 = block([3, 3, 3], 0.4, 4);
    let factors: Vec<f64> = (0..set3.len())
        .map(|k| if k % 3 == 0 { 1.3 } else { 1.0 })
        .collect();
    let set3 = set3.with_radii(factors).unwrap();
    check("3D radii, floor y<0.3", &set3, 0.7, &[floor(0.3)]);
}

#[test]
fn a_floor_through_the_meeting_point_of_two_caps_is_an_exact_tie() {
    // Rows at y = 0.5 and 1.0, spacing 1 in x, r = 0.625: the circles of the side neighbours of
    // the particle at (0, 0.5) meet its circle at (±0.5, 0.125), and the arc below them is
    // uncovered. A floor through those points holds the arc: a tie, interior. One ulp lower,
    // two tiny arcs stick out of the floor: boundary.
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
        let what = format!("2D floor y<{c:e}");
        let got = check(&what, &set, r, &[floor(c)]);
        assert_eq!(got[centre], boundary, "{what}");
    }
    // The same in 3D with layers along z: the bottom particle's gaps between the caps of its
    // x and z neighbours, all at distance 1, with the rows 0.5 above.
    let mut rows3 = Vec::new();
    for x in -2..=2 {
        for z in -2..=2 {
            rows3.push([f64::from(x), 0.5, f64::from(z)]);
            rows3.push([f64::from(x), 1.0, f64::from(z)]);
        }
    }
    let set3 = ParticleSet::<3>::from_rows(&rows3).unwrap();
    for c in [0.125, 0.125f64.next_down(), -0.1, 0.2] {
        check(&format!("3D floor y<{c:e}"), &set3, r, &[floor(c)]);
    }
}

#[test]
fn larger_domains_equal_exact_with_walls_and_solids() {
    // No brute force here (too many particles): `exact` is the reference.
    let set = block([60, 20], 0.5, 9);
    let mut wall_rows = Vec::new();
    for x in -2..=62 {
        wall_rows.push([f64::from(x), -0.5]);
    }
    let walls = ParticleSet::<2>::from_rows(&wall_rows).unwrap();
    let r = Radius::new(0.8).unwrap();
    for half_spaces in [
        vec![floor(-0.3)],
        vec![floor(0.2), HalfSpace::new(0, true, -0.3).unwrap()],
        vec![floor(0.6), HalfSpace::new(0, false, 59.2).unwrap()],
    ] {
        let domain = half_spaces
            .iter()
            .fold(Domain::new().with_walls(walls.to_any()), |d, &h| {
                d.with_solid(h)
            });
        let dilts = DiltsDetector::default()
            .detect_in(&set.to_any(), &domain, r)
            .unwrap();
        let exact = ExactDetector::default()
            .detect_in(&set.to_any(), &domain, r)
            .unwrap();
        assert_eq!(
            dilts.detection.labels, exact.detection.labels,
            "{half_spaces:?}"
        );
        assert!(dilts.detection.margin.is_some(), "2D margins with solids");
    }
    let set3 = block([12, 8, 10], 0.5, 2);
    let tank = [
        floor(0.2),
        HalfSpace::new(0, true, -0.3).unwrap(),
        HalfSpace::new(0, false, 11.3).unwrap(),
        HalfSpace::new(2, true, 0.1).unwrap(),
        HalfSpace::new(2, false, 9.2).unwrap(),
    ];
    for r in [0.75, 0.9] {
        assert_eq!(
            labels(&DiltsDetector::default(), &set3, r, &tank),
            labels(&ExactDetector::default(), &set3, r, &tank),
            "3D tank at r {r}"
        );
    }
}

#[test]
fn held_spheres_far_solids_and_the_owned_part() {
    let set = block([6, 4], 0.4, 7);
    let r = 0.7;
    let bare = labels(&DiltsDetector::default(), &set, r, &[]);
    // A solid far above changes nothing; one holding the whole block makes it interior, with
    // the margin of a sphere inside a solid.
    let above = HalfSpace::new(1, false, 100.0).unwrap();
    assert_eq!(labels(&DiltsDetector::default(), &set, r, &[above]), bare);
    let all = detect_in(&DiltsDetector::default(), &set, r, &[floor(100.0)]);
    assert_eq!(all.labels.boundary_count(), 0);
    let margin = all.margin.unwrap();
    assert!(margin.iter().all(|&m| m == -std::f64::consts::PI * r));
    // `detect_owned_in` classifies the owned prefix; the rest only covers.
    let any = set.to_any();
    let solids = solids_of(&[floor(0.6)]);
    let radius = Radius::new(r).unwrap();
    let whole = DiltsDetector::default()
        .detect_owned_in(&any, set.len(), &solids, radius)
        .unwrap();
    let part = DiltsDetector::default()
        .detect_owned_in(&any, 10, &solids, radius)
        .unwrap();
    assert_eq!(part.labels.as_slice(), &whole.labels.as_slice()[..10]);
    // No solid: the usual path.
    let none = DiltsDetector::default()
        .detect_owned_in(&any, set.len(), &Solids::new(), radius)
        .unwrap();
    assert_eq!(none, DiltsDetector::default().detect(&any, radius).unwrap());
    // A solid on an axis the set does not have is refused by name.
    let z = solids_of(&[HalfSpace::new(2, true, 0.0).unwrap()]);
    let e = DiltsDetector::default()
        .detect_owned_in(&any, set.len(), &z, radius)
        .unwrap_err()
        .to_string();
    assert!(e.contains("z<0"), "{e}");
}

#[test]
fn the_tolerant_mode_takes_solids_too() {
    // With `tie > 0` a solid cap gets the same tolerance as the neighbours' caps; on jittered
    // scenes (no near-tie) the labels are the exact ones.
    let tolerant = DiltsDetector::try_new(DiltsParams { tie: 1e-12 }).unwrap();
    let set = block([10, 5], 0.5, 4);
    let set3 = block([5, 4, 4], 0.5, 6);
    for c in [0.0, 0.35, 0.7] {
        assert_eq!(
            labels(&tolerant, &set, 0.8, &[floor(c)]),
            labels(&ExactDetector::default(), &set, 0.8, &[floor(c)]),
            "2D floor y<{c}"
        );
        assert_eq!(
            labels(&tolerant, &set3, 0.9, &[floor(c)]),
            labels(&ExactDetector::default(), &set3, 0.9, &[floor(c)]),
            "3D floor y<{c}"
        );
    }
}

#[test]
fn particles_below_the_fluid_surface_of_a_solid_stay_exact() {
    // Every particle of a column pushed into a floor at several depths, around the general
    // (hemisphere or more) and held thresholds of the solid cap.
    let r = 0.8;
    let mut rows = Vec::new();
    for (k, depth) in [
        -0.9, -0.8, -0.7999999, -0.5, -1e-4, 0.0, 1e-4, 7.9e-4, 1e-3, 0.3,
    ]
    .iter()
    .enumerate()
    {
        rows.push([3.0 * k as f64, *depth]);
        rows.push([3.0 * k as f64 + 0.9, *depth + 0.2]);
        rows.push([3.0 * k as f64 - 0.3, *depth + 0.9]);
    }
    let set = ParticleSet::<2>::from_rows(&rows).unwrap();
    check("2D column in a floor", &set, r, &[floor(0.0)]);
    let rows3: Vec<[f64; 3]> = rows
        .iter()
        .enumerate()
        .map(|(k, p)| [p[0], p[1], 0.4 * (k % 3) as f64])
        .collect();
    let set3 = ParticleSet::<3>::from_rows(&rows3).unwrap();
    check("3D column in a floor", &set3, r, &[floor(0.0)]);
}
