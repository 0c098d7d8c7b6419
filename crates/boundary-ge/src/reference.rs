//! The shortcuts of `label` and `is_boundary` (reach filters, the ball that covered the previous
//! element, the covered-by-distance test, the uncoverable first level, the precomputed mesh)
//! change the work, never a label: checked here against Algorithm 3 as the paper states it,
//! written without any of them: every element from the first level down, each labelled by
//! [`against_ball`] against every neighbour ball.

use super::*;
use boundary_core::{AnyParticleSet, BoundaryDetector};
use boundary_scenes::certify::{hard_cases, jittered_lattice, near_tie_cases};

/// Algorithm 3 without shortcuts for the balls `(centre, (s², inner))`: true if boundary.
fn plain_is_boundary<const D: usize, E: Element<D>>(
    balls: &[(Point<D>, (f64, f64))],
    max_depth: u32,
) -> bool {
    if balls.is_empty() {
        return true;
    }
    let mut stack = E::first_level();
    while let Some(element) = stack.pop() {
        let slab = element.slab();
        let (mut covered, mut touched) = (false, false);
        for (q, ball) in balls {
            match against_ball(slab.as_ref(), q, *ball) {
                Some(true) => covered = true,
                Some(false) => {}
                None => touched = true,
            }
        }
        if covered {
            continue; // R2
        }
        if !touched || element.depth() >= max_depth {
            return true; // R1, R4
        }
        element.children(&mut stack); // R3
    }
    false
}

/// The labels of [`plain_is_boundary`] for `set` at `r` (a radius per particle if the set has
/// them), with the neighbours the detector gathers.
fn plain_labels<const D: usize, E: Element<D>>(
    set: &ParticleSet<D>,
    r: Radius,
    max_depth: u32,
) -> Vec<bool> {
    let positions = set.positions();
    let mut scratch = Scratch::<D, E>::default();
    let radii = set.resolved_radii(r).unwrap_or_else(|_| unreachable!());
    let grid = NeighbourGrid::new(set, r.get()).unwrap_or_else(|_| unreachable!());
    let radius_grid = radii
        .as_ref()
        .map(|radii| RadiusGrid::new(set, radii).unwrap_or_else(|_| unreachable!()));
    (0..set.len())
        .map(|i| {
            let balls: Vec<(Point<D>, (f64, f64))> = match &radius_grid {
                None => {
                    scratch.gather(positions, &grid, i, r.get());
                    let unit = (1.0, inner(1.0));
                    scratch.centres.iter().map(|&q| (q, unit)).collect()
                }
                Some(radius_grid) => {
                    scratch.gather_radii(positions, radius_grid, i);
                    let balls = scratch.balls.iter().map(|&(_, s2, inner)| (s2, inner));
                    scratch.centres.iter().copied().zip(balls).collect()
                }
            };
            plain_is_boundary::<D, E>(&balls, max_depth)
        })
        .collect()
}

/// The detector's labels equal the plain algorithm's, particle by particle, at depths
/// `1..=max_depth`; returns how many particles were boundary at the deepest depth.
fn check_same_labels(set: &AnyParticleSet, r: f64, max_depth: u32, what: &str) -> usize {
    let r = Radius::new(r).unwrap_or_else(|_| unreachable!());
    let mut boundary = 0;
    for depth in 1..=max_depth {
        let fast = GeDetector::try_new(GeParams { depth })
            .unwrap()
            .detect(set, r)
            .unwrap_or_else(|_| unreachable!())
            .labels;
        let plain = match set {
            AnyParticleSet::D2(s) => plain_labels::<2, Arc>(s, r, depth),
            AnyParticleSet::D3(s) => plain_labels::<3, Triangle>(s, r, depth),
        };
        assert_eq!(plain.len(), fast.len());
        for (i, &b) in plain.iter().enumerate() {
            assert_eq!(
                fast.is_boundary(i),
                b,
                "{what}: particle {i} at depth {depth}: fast {}, plain {b}",
                fast.is_boundary(i)
            );
        }
        boundary = plain.iter().filter(|&&b| b).count();
    }
    boundary
}

#[test]
fn shortcuts_keep_the_labels_of_plain_algorithm_3_on_hard_and_near_tie_cases() {
    for case in hard_cases().iter().chain(near_tie_cases().iter()) {
        check_same_labels(&case.set, case.radius, 6, &case.name);
    }
}

#[test]
fn shortcuts_keep_the_labels_of_plain_algorithm_3_on_jittered_and_random_sets() {
    // Jittered lattices from sparse (r = 0.75a: many uncovered first-level elements) to dense
    // (r = 2.2a: over 100 neighbours), and uniform random points (clusters and holes).
    let mut seen_interior = 0;
    for seed in 0..2 {
        for r in [0.75, 0.9, 1.2, 1.6, 2.2] {
            let set3 = AnyParticleSet::D3(
                ParticleSet::from_rows(&jittered_lattice::<3>(6, 0.3, seed))
                    .unwrap_or_else(|_| unreachable!()),
            );
            let b = check_same_labels(&set3, r, 6, &format!("3D jittered r={r} seed {seed}"));
            seen_interior += 216 - b;
            let set2 = AnyParticleSet::D2(
                ParticleSet::from_rows(&jittered_lattice::<2>(14, 0.3, seed))
                    .unwrap_or_else(|_| unreachable!()),
            );
            check_same_labels(&set2, r, 7, &format!("2D jittered r={r} seed {seed}"));
        }
        let random: Vec<[f64; 3]> = jittered_lattice::<3>(6, 0.5, seed + 10)
            .iter()
            .map(|p| [p[0] * 0.7, p[1] * 0.7, p[2] * 0.7])
            .collect();
        let set =
            AnyParticleSet::D3(ParticleSet::from_rows(&random).unwrap_or_else(|_| unreachable!()));
        check_same_labels(&set, 1.0, 6, &format!("3D random seed {seed}"));
    }
    // The comparison is not vacuous: many particles are interior.
    assert!(seen_interior > 300, "{seen_interior}");
}

#[test]
fn shortcuts_keep_the_labels_of_plain_algorithm_3_with_a_radius_per_particle() {
    for seed in 0..2u64 {
        let rows = jittered_lattice::<3>(6, 0.3, seed);
        // Radii 0.9..1.9 times the spacing, deterministic in the index.
        let radii: Vec<f64> = (0..rows.len())
            .map(|k| 0.9 + ((k as u64 * 7919 + seed * 31) % 101) as f64 / 100.0)
            .collect();
        let set = ParticleSet::from_rows(&rows)
            .and_then(|s| s.with_radii(radii))
            .unwrap_or_else(|_| unreachable!());
        check_same_labels(&AnyParticleSet::D3(set), 1.0, 5, "3D radii");
        let rows = jittered_lattice::<2>(12, 0.3, seed);
        let radii: Vec<f64> = (0..rows.len())
            .map(|k| 0.6 + ((k as u64 * 7919 + seed * 31) % 101) as f64 / 100.0)
            .collect();
        let set = ParticleSet::from_rows(&rows)
            .and_then(|s| s.with_radii(radii))
            .unwrap_or_else(|_| unreachable!());
        check_same_labels(&AnyParticleSet::D2(set), 1.0, 6, "2D radii");
    }
}
