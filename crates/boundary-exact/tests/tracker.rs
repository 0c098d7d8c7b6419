//! The tracker's labels equal a full `exact` detection at every step, bit for bit.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{
    AnyParticleSet, BoundaryDetector, Domain, HalfSpace, Labels, ParticleSet, Periodic, Point,
    Radius,
};
use boundary_exact::{ExactDetector, Tracker};
use proptest::prelude::*;

/// Runs the tracker over `frames` and checks every step against a full detection in `domain`;
/// returns the number of particles recomputed at each step.
fn check_sequence(frames: &[AnyParticleSet], r: f64, domain: Domain) -> Vec<usize> {
    let r = Radius::new(r).unwrap();
    let mut tracker = Tracker::new(r, Some(1), domain.clone()).unwrap();
    let mut recomputed = vec![];
    for (step, set) in frames.iter().enumerate() {
        let full = boundary_core::detect_in(&ExactDetector::default(), set, &domain, r).unwrap();
        let labels = tracker.update(set).unwrap().clone();
        assert_eq!(
            first_difference(&labels, &full.detection.labels),
            None,
            "step {step}"
        );
        recomputed.push(tracker.recomputed());
    }
    recomputed
}

fn first_difference(a: &Labels, b: &Labels) -> Option<usize> {
    assert_eq!(a.len(), b.len());
    (0..a.len()).find(|&i| a.is_boundary(i) != b.is_boundary(i))
}

fn set2(points: &[[f64; 2]]) -> AnyParticleSet {
    ParticleSet::from_rows(points).unwrap().to_any()
}

/// A tiny deterministic generator (xorshift), uniform in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn jittered_square(side: usize, jitter: f64, rng: &mut Rng) -> Vec<[f64; 2]> {
    (0..side * side)
        .map(|k| {
            [
                (k % side) as f64 + jitter * (rng.next() - 0.5),
                (k / side) as f64 + jitter * (rng.next() - 0.5),
            ]
        })
        .collect()
}

/// The Enright-advected jittered sphere, 12 steps at several displacements per step: the
/// labels of a full detection every step, and at small steps far fewer particles recomputed.
#[test]
fn enright_sequence_matches_full_detection() {
    for displacement in [0.01, 0.05, 0.5] {
        let (frames, h) = boundary_scenes::enright_sequence(4000, displacement, 12);
        let frames: Vec<_> = frames.iter().map(|f| f.to_any()).collect();
        let n = frames[0].len();
        let recomputed = check_sequence(&frames, 1.5 * h, Domain::new());
        assert_eq!(recomputed[0], n);
        if displacement <= 0.01 {
            let later: usize = recomputed[1..].iter().sum();
            assert!(later < 12 * n / 4, "{displacement}: {recomputed:?} of {n}");
        }
    }
}

/// The thesis author's 200 vortex frames (2D, 1698 particles, the same particle on the same
/// line): frames far apart in time, so most steps fall back to full detections.
#[test]
fn vortex_frames_match_full_detection() {
    let data = boundary_scenes::SharedData::from_env();
    let mut frames = vec![];
    for k in 1..=200 {
        let file = format!("sequences/sandim_vortex_spin/frame_{k:03}.csv");
        let set = data
            .set::<2>(&file)
            .unwrap_or_else(|e| panic!("{e}"))
            .unwrap_or_else(|| panic!("{file} is missing"));
        frames.push(set.to_any());
    }
    assert!(frames.iter().all(|f| f.len() == 1698));
    check_sequence(&frames, 0.022105, Domain::new());
}

/// A perfect rectangular lattice whose cell diagonal passes through `2r`: spacing `(3 + δ, 4)`
/// at `r = 2.5`, an exact tie at `δ = 0` (3-4-5), with `δ` stepping by `2^-30` (every
/// coordinate exact). The inner particles are interior up to and at the tie, and boundary
/// from the first step beyond it; the tracker flips them at exactly that step.
#[test]
fn lattice_drifting_through_its_tie_flips_exactly_there() {
    let inner = |i: usize| (1..7).contains(&(i % 8)) && (1..7).contains(&(i / 8));
    let mut frames = vec![];
    for j in -3i32..=3 {
        let a = 3.0 + j as f64 * 2f64.powi(-30);
        let rows: Vec<[f64; 2]> = (0..64)
            .map(|k| [(k % 8) as f64 * a + 0.25, (k / 8) as f64 * 4.0 - 0.5])
            .collect();
        frames.push(set2(&rows));
    }
    let r = Radius::new(2.5).unwrap();
    let mut tracker = Tracker::new(r, Some(1), Domain::new()).unwrap();
    for (step, set) in frames.iter().enumerate() {
        let j = step as i32 - 3;
        let full = ExactDetector::default().detect(set, r).unwrap();
        let labels = tracker.update(set).unwrap();
        assert_eq!(first_difference(labels, &full.labels), None, "step {step}");
        for i in (0..64).filter(|&i| inner(i)) {
            assert_eq!(labels.is_boundary(i), j > 0, "particle {i}, δ = {j}·2^-30");
        }
    }
    // 3D: spacing (2 + δ, 3, 6) at r = 3.5 (2-3-6-7).
    let mut tracker = Tracker::new(Radius::new(3.5).unwrap(), Some(1), Domain::new()).unwrap();
    for j in -2i32..=2 {
        let a = 2.0 + j as f64 * 2f64.powi(-30);
        let rows: Vec<[f64; 3]> = (0..125)
            .map(|k| {
                [
                    (k % 5) as f64 * a,
                    (k / 5 % 5) as f64 * 3.0,
                    (k / 25) as f64 * 6.0,
                ]
            })
            .collect();
        let set = ParticleSet::from_rows(&rows).unwrap().to_any();
        let full = ExactDetector::default()
            .detect(&set, Radius::new(3.5).unwrap())
            .unwrap();
        let labels = tracker.update(&set).unwrap();
        assert_eq!(first_difference(labels, &full.labels), None, "δ = {j}");
        // The centre particle (2, 2, 2).
        assert_eq!(labels.is_boundary(62), j > 0, "δ = {j}·2^-30");
    }
}

/// Random jumps of up to 0.5 spacing: a few particles at most steps (the others drift a
/// little), every particle at some; both the incremental path and the fallback run.
#[test]
fn random_jumps_of_half_a_spacing_match_full_detection() {
    let mut rng = Rng(7);
    let mut points = jittered_square(20, 0.3, &mut rng);
    let mut frames = vec![set2(&points)];
    for step in 0..24 {
        let chance = if step % 8 == 7 { 1.0 } else { 0.01 };
        for p in points.iter_mut() {
            if rng.next() < chance {
                p[0] += (rng.next() - 0.5) * 1.0;
                p[1] += (rng.next() - 0.5) * 1.0;
            } else {
                p[0] += 1e-3 * (rng.next() - 0.5);
            }
        }
        frames.push(set2(&points));
    }
    let counts = check_sequence(&frames, 0.9, Domain::new());
    let n = points.len();
    // Before the first jump of everything the steps are incremental; after it the set is
    // disordered, most particles are boundary, and a boundary particle counts the largest
    // displacement anywhere: each 0.5 jump spends its budget, and full detections run.
    assert!(counts[1..8].iter().all(|&c| c < n / 2), "{counts:?}");
    assert!(
        counts.iter().filter(|&&c| c == n).count() >= 4,
        "{counts:?}"
    );
}

/// A block of particles leaves the set's neighbourhood and comes back, while the rest drifts.
#[test]
fn particles_leaving_and_coming_back_match_full_detection() {
    let mut rng = Rng(11);
    let base = jittered_square(16, 0.2, &mut rng);
    let mut frames = vec![];
    for step in 0..10 {
        let away = match step {
            0..=2 => 0.0,
            3..=5 => 30.0 * (step - 2) as f64,
            _ => 0.0,
        };
        let rows: Vec<[f64; 2]> = base
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let drift = 0.003 * step as f64;
                if (i % 16) < 5 && (i / 16) < 5 {
                    [p[0] + away + drift, p[1]]
                } else {
                    [p[0] + drift, p[1] - drift]
                }
            })
            .collect();
        frames.push(set2(&rows));
    }
    check_sequence(&frames, 0.8, Domain::new());
}

/// Exact duplicates appear and disappear: they never cover each other.
#[test]
fn duplicates_appearing_and_vanishing_match_full_detection() {
    let mut rng = Rng(3);
    let base = jittered_square(10, 0.2, &mut rng);
    let mut frames = vec![];
    for step in 0..6 {
        let mut rows = base.clone();
        if step % 2 == 1 {
            rows[45] = rows[44];
            rows[12] = rows[13];
        }
        frames.push(set2(&rows));
    }
    check_sequence(&frames, 0.75, Domain::new());
}

/// Moving walls, solids, periodic axes and per-particle radii: the labels of a full
/// detection in the domain.
#[test]
fn domains_and_radii_match_full_detection() {
    let mut rng = Rng(5);
    let base = jittered_square(12, 0.2, &mut rng);
    let frames: Vec<AnyParticleSet> = (0..6)
        .map(|s| {
            let rows: Vec<[f64; 2]> = base
                .iter()
                .map(|p| [p[0] + 0.01 * s as f64, p[1] + 1.0 - 0.004 * s as f64])
                .collect();
            set2(&rows)
        })
        .collect();
    let r = 0.8;
    let wall = |y: f64| -> AnyParticleSet {
        let rows: Vec<[f64; 2]> = (0..14).map(|k| [k as f64 - 1.0, y]).collect();
        set2(&rows)
    };
    // Walls that move: checked step by step against detect_in with the walls of the step.
    let radius = Radius::new(r).unwrap();
    let mut tracker = Tracker::new(radius, Some(1), Domain::new().with_walls(wall(0.0))).unwrap();
    let mut saved = 0;
    for (s, set) in frames.iter().enumerate() {
        let walls = wall(0.02 * s as f64);
        tracker.move_walls(walls.clone()).unwrap();
        let domain = Domain::new().with_walls(walls);
        let full =
            boundary_core::detect_in(&ExactDetector::default(), set, &domain, radius).unwrap();
        let labels = tracker.update(set).unwrap();
        assert_eq!(
            first_difference(labels, &full.detection.labels),
            None,
            "walls, step {s}"
        );
        saved += set.len() - tracker.recomputed();
    }
    assert!(saved > 0, "moving walls: nothing saved");
    let solid = Domain::new().with_solid(HalfSpace::parse("y<0.9").unwrap());
    check_sequence(&frames, r, solid);
    let periodic = Domain::new().with_periodic(Periodic::new(0, -0.5, 11.5).unwrap());
    check_sequence(&frames, r, periodic);
    let graded: Vec<AnyParticleSet> = frames
        .iter()
        .map(|f| {
            let radii = (0..f.len()).map(|i| 1.0 + 0.3 * (i % 3) as f64).collect();
            f.clone().with_radii(radii).unwrap()
        })
        .collect();
    check_sequence(&graded, r, Domain::new());
}

/// A tracker refuses nothing a detection accepts, and errors name the problem.
#[test]
fn non_finite_positions_are_an_error() {
    let mut tracker = Tracker::new(Radius::new(1.0).unwrap(), None, Domain::new()).unwrap();
    let ok = set2(&[[0.0, 0.0], [1.0, 0.0]]);
    assert_eq!(tracker.update(&ok).unwrap().boundary_count(), 2);
    let err = ParticleSet::<2>::from_rows(&[[0.0, f64::NAN]]).unwrap_err();
    assert!(err.to_string().contains('0'), "{err}");
    // A change of dimension starts over.
    let three = ParticleSet::from_rows(&[[0.0, 0.0, 0.0]]).unwrap().to_any();
    assert_eq!(tracker.update(&three).unwrap().boundary_count(), 1);
    assert_eq!(tracker.recomputed(), 1);
}

fn point_strategy() -> impl Strategy<Value = Vec<[f64; 2]>> {
    prop::collection::vec([0.0..4.0f64, 0.0..4.0f64], 1..24)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Random small sets and random sequences of moves (tiny, small, large; some particles
    /// snapped onto others or onto a grid): the tracker equals a full detection every step.
    #[test]
    fn tracker_equals_full_detection_on_random_sequences(
        start in point_strategy(),
        moves in prop::collection::vec((0usize..4, any::<u64>()), 1..8),
        r in 0.3..1.2f64,
    ) {
        let radius = Radius::new(r).unwrap();
        let mut tracker = Tracker::new(radius, Some(1), Domain::new()).unwrap();
        let mut points = start;
        for (step, &(kind, seed)) in std::iter::once(&(0, 0)).chain(&moves).enumerate() {
            let mut rng = Rng(seed | 1);
            let scale = [0.0, 1e-3, 0.05, 0.5][kind];
            for p in points.iter_mut() {
                p[0] += scale * (rng.next() - 0.5);
                p[1] += scale * (rng.next() - 0.5);
                if rng.next() < 0.05 {
                    p[0] = (p[0] * 2.0).round() / 2.0;
                    p[1] = (p[1] * 2.0).round() / 2.0;
                }
            }
            let set = set2(&points);
            let full = ExactDetector::default().detect(&set, radius).unwrap();
            let labels = tracker.update(&set).unwrap();
            prop_assert_eq!(first_difference(labels, &full.labels), None, "step {}", step);
        }
    }
}

/// Particles pass by each other in 3D (a crossing stream), checked every step.
#[test]
fn crossing_streams_in_3d_match_full_detection() {
    let mut rng = Rng(9);
    let base: Vec<Point<3>> = (0..216)
        .map(|k| {
            Point::<3>::new(
                (k % 6) as f64 + 0.2 * rng.next(),
                (k / 6 % 6) as f64 + 0.2 * rng.next(),
                (k / 36) as f64 + 0.2 * rng.next(),
            )
        })
        .collect();
    let frames: Vec<AnyParticleSet> = (0..8)
        .map(|s| {
            let points = base
                .iter()
                .map(|p| {
                    let dir = if p[2] < 3.0 { 1.0 } else { -1.0 };
                    Point::<3>::new(p[0] + dir * 0.07 * s as f64, p[1], p[2])
                })
                .collect();
            ParticleSet::new(points).unwrap().to_any()
        })
        .collect();
    check_sequence(&frames, 1.0, Domain::new());
}

/// A jittered lattice near its tie radius, stretched a little at every step: interior
/// particles turn boundary one by one, on the incremental path (2D and 3D).
#[test]
fn slow_stretch_turns_particles_boundary_one_by_one() {
    let mut rng = Rng(13);
    let base = jittered_square(30, 0.1, &mut rng);
    let frames: Vec<AnyParticleSet> = (0..30)
        .map(|s| {
            let f = 1.0 + 0.002 * s as f64;
            set2(&base.iter().map(|p| [p[0] * f, p[1]]).collect::<Vec<_>>())
        })
        .collect();
    let counts = check_sequence(&frames, 0.74, Domain::new());
    let r = Radius::new(0.74).unwrap();
    let boundary = |f: &AnyParticleSet| {
        ExactDetector::default()
            .detect(f, r)
            .unwrap()
            .labels
            .boundary_count()
    };
    let (first, last) = (boundary(&frames[0]), boundary(&frames[29]));
    assert!(last > first + 50, "{first} -> {last}");
    assert!(
        counts[1..10].iter().all(|&c| c < base.len() / 4),
        "{counts:?}"
    );
    // Backwards: compressed, boundary particles turn interior one by one.
    let backwards: Vec<AnyParticleSet> = frames.iter().rev().cloned().collect();
    check_sequence(&backwards, 0.74, Domain::new());

    let base: Vec<Point<3>> = (0..512)
        .map(|k| {
            Point::<3>::new(
                (k % 8) as f64 + 0.1 * rng.next(),
                (k / 8 % 8) as f64 + 0.1 * rng.next(),
                (k / 64) as f64 + 0.1 * rng.next(),
            )
        })
        .collect();
    let frames: Vec<AnyParticleSet> = (0..20)
        .map(|s| {
            let f = 1.0 + 0.004 * s as f64;
            let points = base
                .iter()
                .map(|p| Point::<3>::new(p[0] * f, p[1], p[2]))
                .collect();
            ParticleSet::new(points).unwrap().to_any()
        })
        .collect();
    check_sequence(&frames, 0.88, Domain::new());
    let r = Radius::new(0.88).unwrap();
    let boundary = |f: &AnyParticleSet| {
        ExactDetector::default()
            .detect(f, r)
            .unwrap()
            .labels
            .boundary_count()
    };
    assert!(boundary(&frames[19]) > boundary(&frames[0]) + 10);
}

/// Runs the tracker with ids over `frames` (positions and ids per step) and checks every step
/// against a full detection; returns the number of particles recomputed at each step.
fn check_with_ids(frames: &[(Vec<[f64; 2]>, Vec<u64>)], r: f64) -> Vec<usize> {
    let radius = Radius::new(r).unwrap();
    let mut tracker = Tracker::new(radius, Some(1), Domain::new()).unwrap();
    let mut recomputed = vec![];
    for (step, (rows, ids)) in frames.iter().enumerate() {
        let set = set2(rows);
        let full = ExactDetector::default().detect(&set, radius).unwrap();
        let labels = tracker.update_with_ids(&set, ids).unwrap();
        assert_eq!(first_difference(labels, &full.labels), None, "step {step}");
        recomputed.push(tracker.recomputed());
    }
    recomputed
}

/// A channel with inflow and outflow: particles drift along x, those past the outlet leave,
/// new ones (new ids) enter at the inlet, and the order is shuffled now and then. Labels of a
/// full detection at every step, with most particles never recomputed.
#[test]
fn inflow_and_outflow_with_ids_match_full_detection() {
    let mut rng = Rng(21);
    let (width, length) = (10usize, 30usize);
    // Particles on a jittered lattice; each lattice column is one inflow batch.
    let mut particles: Vec<([f64; 2], u64)> = vec![];
    let mut next_id = 0u64;
    let column = |x: f64, rng: &mut Rng, next_id: &mut u64| -> Vec<([f64; 2], u64)> {
        (0..width)
            .map(|k| {
                *next_id += 1;
                (
                    [
                        x + 0.2 * (rng.next() - 0.5),
                        k as f64 + 0.2 * (rng.next() - 0.5),
                    ],
                    *next_id * 7 + 3,
                )
            })
            .collect()
    };
    for c in 0..length {
        particles.extend(column(c as f64, &mut rng, &mut next_id));
    }
    let speed = 0.05;
    let mut frames = vec![];
    let mut inlet = 0.0;
    for step in 0..40 {
        for (p, _) in particles.iter_mut() {
            // A shear flow: faster in the middle of the channel.
            let y = p[1] / width as f64;
            p[0] += speed * (1.0 + 0.5 * y * (1.0 - y));
            p[1] += 0.002 * (rng.next() - 0.5);
        }
        inlet += speed;
        particles.retain(|(p, _)| p[0] < length as f64);
        if inlet >= 1.0 {
            inlet -= 1.0;
            particles.extend(column(inlet, &mut rng, &mut next_id));
        }
        if step % 7 == 3 {
            // A solver that reorders its particles (e.g. sorted into cells) every few steps.
            for k in (1..particles.len()).rev() {
                let j = (rng.next() * (k + 1) as f64) as usize;
                particles.swap(k, j.min(k));
            }
        }
        let rows = particles.iter().map(|(p, _)| *p).collect();
        let ids = particles.iter().map(|(_, id)| *id).collect();
        frames.push((rows, ids));
    }
    let recomputed = check_with_ids(&frames, 0.8);
    let total: usize = frames[1..].iter().map(|(rows, _)| rows.len()).sum();
    let done: usize = recomputed[1..].iter().sum();
    // Counts changed at about every 20th step and the order at every 7th: without ids each
    // of those steps would start over.
    assert!(
        frames
            .windows(2)
            .filter(|w| w[0].0.len() != w[1].0.len())
            .count()
            >= 2,
        "the scene has no inflow"
    );
    assert!(done * 4 < total, "recomputed {recomputed:?} of {total}");
}

/// A particle that arrives in a hole covers its neighbours' gap, and one that leaves opens
/// it: the labels flip at once, as a full detection has them.
#[test]
fn a_particle_arriving_or_leaving_flips_its_neighbours() {
    let rows: Vec<[f64; 2]> = (0..144)
        .map(|k| [(k % 12) as f64, (k / 12) as f64])
        .collect();
    let ids: Vec<u64> = (0..144).collect();
    let hole = 6 * 12 + 6;
    let without: Vec<usize> = (0..144).filter(|&k| k != hole).collect();
    let pick = |keep: &[usize]| -> (Vec<[f64; 2]>, Vec<u64>) {
        (
            keep.iter().map(|&k| rows[k]).collect(),
            keep.iter().map(|&k| ids[k]).collect(),
        )
    };
    let all: Vec<usize> = (0..144).collect();
    // r between the lattice's covering tie (√2/2) and its spacing: a full lattice covers its
    // inside, a missing particle leaves its four neighbours uncovered.
    let frames = vec![pick(&all), pick(&without), pick(&all), pick(&without)];
    let recomputed = check_with_ids(&frames, 0.8);
    let full = ExactDetector::default()
        .detect(&set2(&frames[1].0), Radius::new(0.8).unwrap())
        .unwrap();
    let before = ExactDetector::default()
        .detect(&set2(&frames[0].0), Radius::new(0.8).unwrap())
        .unwrap();
    assert_eq!(
        full.labels.boundary_count(),
        before.labels.boundary_count() + 4,
        "the hole opens four boundary particles"
    );
    assert!(recomputed[1..].iter().all(|&n| n < 40), "{recomputed:?}");
}

/// Ids are checked: one per particle, none repeated (the error names both particles); after an
/// update without ids the tracker starts over.
#[test]
fn ids_are_checked_and_follow_only_ids() {
    let mut tracker = Tracker::new(Radius::new(0.8).unwrap(), Some(1), Domain::new()).unwrap();
    let rows: Vec<[f64; 2]> = (0..25).map(|k| [(k % 5) as f64, (k / 5) as f64]).collect();
    let set = set2(&rows);
    let err = tracker.update_with_ids(&set, &[1, 2, 3]).unwrap_err();
    assert!(err.to_string().contains("3 ids for 25 particles"), "{err}");
    let mut ids: Vec<u64> = (100..125).collect();
    ids[17] = ids[4];
    let err = tracker.update_with_ids(&set, &ids).unwrap_err();
    assert!(
        err.to_string()
            .contains("id 104 is given to particles 4 and 17"),
        "{err}"
    );
    ids[17] = 117;
    tracker.update(&set).unwrap();
    tracker.update_with_ids(&set, &ids).unwrap();
    assert_eq!(
        tracker.recomputed(),
        25,
        "ids after an update without: start over"
    );
    // The same ids reversed: the same particles, nothing to recompute.
    let reversed: Vec<[f64; 2]> = rows.iter().rev().copied().collect();
    let back: Vec<u64> = ids.iter().rev().copied().collect();
    let labels = tracker
        .update_with_ids(&set2(&reversed), &back)
        .unwrap()
        .clone();
    assert_eq!(tracker.recomputed(), 0);
    let full = ExactDetector::default()
        .detect(&set2(&reversed), Radius::new(0.8).unwrap())
        .unwrap();
    assert_eq!(labels, full.labels);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Random sequences with ids: particles move (tiny to large), leave, arrive (some onto
    /// others, as duplicates) and are shuffled; the tracker equals a full detection every step.
    #[test]
    fn tracker_with_ids_equals_full_detection_on_random_sequences(
        start in point_strategy(),
        steps in prop::collection::vec((0usize..4, 0usize..4, any::<u64>()), 1..8),
        r in 0.3..1.2f64,
    ) {
        let radius = Radius::new(r).unwrap();
        let mut tracker = Tracker::new(radius, Some(1), Domain::new()).unwrap();
        let mut points: Vec<([f64; 2], u64)> =
            start.into_iter().zip(0u64..).collect();
        let mut next_id = points.len() as u64;
        for (step, &(kind, churn, seed)) in std::iter::once(&(0, 0, 0)).chain(&steps).enumerate() {
            let mut rng = Rng(seed | 1);
            let scale = [0.0, 1e-3, 0.05, 0.5][kind];
            for (p, _) in points.iter_mut() {
                p[0] += scale * (rng.next() - 0.5);
                p[1] += scale * (rng.next() - 0.5);
            }
            for _ in 0..churn {
                if rng.next() < 0.5 && points.len() > 1 {
                    let k = (rng.next() * points.len() as f64) as usize;
                    points.remove(k.min(points.len() - 1));
                }
                let p = if rng.next() < 0.3 && !points.is_empty() {
                    points[(rng.next() * points.len() as f64) as usize % points.len()].0
                } else {
                    [4.0 * rng.next(), 4.0 * rng.next()]
                };
                points.push((p, next_id));
                next_id += 1;
            }
            if churn == 3 {
                points.reverse();
            }
            let rows: Vec<[f64; 2]> = points.iter().map(|(p, _)| *p).collect();
            let ids: Vec<u64> = points.iter().map(|(_, id)| *id).collect();
            let set = set2(&rows);
            let full = ExactDetector::default().detect(&set, radius).unwrap();
            let labels = tracker.update_with_ids(&set, &ids).unwrap();
            prop_assert_eq!(first_difference(labels, &full.labels), None, "step {}", step);
        }
    }
}

/// Ids beside walls: particles flow over a wall floor that slides the other way (every other
/// wall particle bobbing), leave at
/// the outlet, enter at the inlet (a few every step) and are listed in a new order every step;
/// the labels of a full detection in the domain of the step.
#[test]
fn ids_beside_walls_match_full_detection() {
    let mut rng = Rng(33);
    // Every other wall particle bobs up and down: neighbouring walls move differently.
    let wall = |step: usize| -> AnyParticleSet {
        let rows: Vec<[f64; 2]> = (0..60)
            .map(|k| {
                let bob = if k % 2 == 1 {
                    0.25 * (0.9 * step as f64).sin()
                } else {
                    0.0
                };
                [k as f64 - 20.0 - 0.03 * step as f64, -1.0 + bob]
            })
            .collect();
        set2(&rows)
    };
    let radius = Radius::new(0.8).unwrap();
    let mut tracker = Tracker::new(radius, Some(1), Domain::new().with_walls(wall(0))).unwrap();
    let mut particles: Vec<([f64; 2], u64)> = jittered_square(12, 0.2, &mut rng)
        .into_iter()
        .zip(0u64..)
        .collect();
    let mut next_id = 1000u64;
    let mut saved = 0;
    for step in 0..40 {
        for (p, _) in particles.iter_mut() {
            p[0] += 0.05 + 0.01 * p[1] / 12.0;
        }
        // A large outflow at step 20: a third of the particles leave at once.
        let outlet = if step == 20 { 8.0 } else { 12.0 };
        particles.retain(|(p, _)| p[0] < outlet);
        for _ in 0..if step % 2 == 0 { 1 } else { 0 } {
            let y = (rng.next() * 12.0).floor();
            particles.push(([-0.5 + 0.1 * rng.next(), y], next_id));
            next_id += 1;
        }
        for k in (1..particles.len()).rev() {
            let j = (rng.next() * (k + 1) as f64) as usize;
            particles.swap(k, j.min(k));
        }
        let walls = wall(step);
        tracker.move_walls(walls.clone()).unwrap();
        let domain = Domain::new().with_walls(walls);
        let rows: Vec<[f64; 2]> = particles.iter().map(|(p, _)| *p).collect();
        let ids: Vec<u64> = particles.iter().map(|(_, id)| *id).collect();
        let set = set2(&rows);
        let full =
            boundary_core::detect_in(&ExactDetector::default(), &set, &domain, radius).unwrap();
        let labels = tracker.update_with_ids(&set, &ids).unwrap();
        assert_eq!(
            first_difference(labels, &full.detection.labels),
            None,
            "step {step}"
        );
        if step > 0 {
            saved += set.len() - tracker.recomputed();
        }
    }
    assert!(saved > 0, "nothing saved");
}

/// Fixed walls: set once (or given again bit for bit), the labels are those of a full
/// detection with the walls at every step, and most particles are not recomputed; walls given
/// again unchanged keep the saving, and `set_domain` with phases gives the interface labels.
#[test]
fn fixed_walls_and_phases_match_full_detection() {
    let mut rng = Rng(17);
    let base = jittered_square(14, 0.2, &mut rng);
    let floor: Vec<[f64; 2]> = (0..2)
        .flat_map(|layer| (0..18).map(move |k| [k as f64 - 2.0, -0.6 - 0.7 * layer as f64]))
        .collect();
    let walls = set2(&floor);
    let domain = Domain::new().with_walls(walls.clone());
    let r = Radius::new(0.8).unwrap();
    let mut tracker = Tracker::new(r, Some(1), domain.clone()).unwrap();
    let mut recomputed = vec![];
    for s in 0..8 {
        let rows: Vec<[f64; 2]> = base
            .iter()
            .map(|p| {
                [
                    p[0] * (1.0 + 0.002 * s as f64),
                    p[1] * (1.0 - 0.001 * s as f64),
                ]
            })
            .collect();
        let set = set2(&rows);
        if s % 2 == 1 {
            // The same walls again, as a solver passing them every step: nothing changes.
            tracker.move_walls(walls.clone()).unwrap();
        }
        let full = boundary_core::detect_in(&ExactDetector::default(), &set, &domain, r).unwrap();
        let labels = tracker.update(&set).unwrap().clone();
        assert_eq!(
            first_difference(&labels, &full.detection.labels),
            None,
            "step {s}"
        );
        recomputed.push(tracker.recomputed());
        // The floor covers the bottom row: not all of it is boundary.
        assert!((0..14).any(|i| !labels.is_boundary(i)), "step {s}");
    }
    assert_eq!(recomputed[0], base.len());
    assert!(
        recomputed[1..].iter().all(|&c| 3 * c < base.len()),
        "{recomputed:?}"
    );
    // Phases through the domain: the interface labels of a full detection.
    let phases: Vec<u32> = (0..base.len()).map(|i| u32::from(i % 14 >= 7)).collect();
    let set = set2(&base);
    tracker.set_phases(Some(phases.clone()));
    let labels = tracker.update(&set).unwrap().clone();
    let with_phases = domain.clone().with_phases(phases);
    let full = boundary_core::detect_in(&ExactDetector::default(), &set, &with_phases, r).unwrap();
    assert_eq!(labels, full.detection.labels);
    assert_eq!(tracker.interface(), full.interface.as_ref());
    assert!(full.interface.as_ref().unwrap().boundary_count() > 0);
    // Without phases again: no interface, the labels of the walls' domain.
    tracker.set_phases(None);
    let labels = tracker.update(&set).unwrap().clone();
    assert_eq!(tracker.interface(), None);
    let full = boundary_core::detect_in(&ExactDetector::default(), &set, &domain, r).unwrap();
    assert_eq!(labels, full.detection.labels);
    // Removing the walls through set_domain: the labels of the bare cloud.
    tracker.set_domain(Domain::new()).unwrap();
    let labels = tracker.update(&set).unwrap().clone();
    assert_eq!(
        labels,
        ExactDetector::default().detect(&set, r).unwrap().labels
    );
}

/// A long, slow shear beside walls that move: many steps each far below a spacing, so most
/// particles skip their neighbours' check for several steps before a budget is spent (the
/// bound grows by twice each step's largest movement), and enough evaluations over the run
/// that the neighbour lists are compacted. Every step is a full detection's labels; the
/// saving holds (few particles recomputed per step once started).
#[test]
fn slow_shear_beside_moving_walls_matches_full_detection_at_every_step() {
    let mut rng = Rng(29);
    let base = jittered_square(70, 0.2, &mut rng);
    let wall: Vec<[f64; 2]> = (0..90)
        .flat_map(|k| [[k as f64 - 10.0, -1.0], [k as f64 - 10.0, -2.0]])
        .collect();
    let r = Radius::new(0.8).unwrap();
    let mut tracker = Tracker::new(r, Some(2), Domain::new().with_walls(set2(&wall))).unwrap();
    let mut recomputed = vec![];
    for s in 0..60 {
        let t = s as f64;
        // Shear u = 0.0005·y per step, the top faster; the walls slide by 0.01 per step.
        let points: Vec<[f64; 2]> = base
            .iter()
            .map(|p| [p[0] + 0.0005 * t * p[1], p[1]])
            .collect();
        let walls: Vec<[f64; 2]> = wall.iter().map(|w| [w[0] + 0.01 * t, w[1]]).collect();
        let walls = set2(&walls);
        tracker.move_walls(walls.clone()).unwrap();
        let set = set2(&points);
        let labels = tracker.update(&set).unwrap().clone();
        let domain = Domain::new().with_walls(walls);
        let full = boundary_core::detect_in(&ExactDetector::default(), &set, &domain, r).unwrap();
        assert_eq!(
            first_difference(&labels, &full.detection.labels),
            None,
            "step {s}"
        );
        recomputed.push(tracker.recomputed());
    }
    let later: usize = recomputed[1..].iter().sum();
    assert!(later > 0, "{recomputed:?}");
    assert!(later < 59 * base.len() / 10, "{recomputed:?}");
}

/// A slow shear of a jittered square at the scales of the supported resolutions' ends
/// (`r = 1.5·10^±90`) and at 1: the labels of a full detection at every step, and the same
/// saving at every scale (the watched offsets are kept in units of `r`, so their storage
/// neither overflows nor underflows).
#[test]
fn slow_shear_at_extreme_scales_matches_full_detection_and_saves_alike() {
    let mut rng = Rng(77);
    let base = jittered_square(24, 0.3, &mut rng);
    let mut saved = vec![];
    for scale in [1e-90, 1.0, 1e90] {
        let frames: Vec<AnyParticleSet> = (0..16)
            .map(|step| {
                let t = step as f64 * 2e-3;
                let rows: Vec<[f64; 2]> = base
                    .iter()
                    .map(|p| [(p[0] + t * p[1]) * scale, p[1] * (1.0 - 0.5 * t) * scale])
                    .collect();
                set2(&rows)
            })
            .collect();
        let recomputed = check_sequence(&frames, 1.5 * scale, Domain::new());
        let later: usize = recomputed[1..].iter().sum();
        assert!(
            later < 15 * base.len() / 4,
            "scale {scale}: {recomputed:?} of {}",
            base.len()
        );
        saved.push(later);
    }
    // The same motion in units of r: the same particles recomputed, within a few.
    let spread = saved.iter().max().unwrap() - saved.iter().min().unwrap();
    assert!(spread <= saved[1] / 10 + 5, "{saved:?}");
}

/// A set large enough for the passes over every particle to be split among the workers
/// (16,384 particles and more), with steps that hand 128 and more evaluations and the
/// revocations of an inflow to them too, and a step past the grid's skin: the labels of a full
/// detection at every step, on a pool of the tracker's own and on the pool the update is
/// called on.
#[test]
fn a_large_set_splits_its_work_among_the_workers_with_the_same_labels() {
    let mut rng = Rng(41);
    let side = 132;
    let mut rows = jittered_square(side, 0.2, &mut rng);
    let mut ids: Vec<u64> = (0..rows.len() as u64).collect();
    let n = rows.len();
    assert!(n >= 16_384);
    let mut frames = vec![(rows.clone(), ids.clone())];
    // A slow shear: few evaluations, the passes in pieces.
    for _ in 0..2 {
        rows.iter_mut()
            .for_each(|p| p[0] += 0.001 * p[1] / side as f64);
        frames.push((rows.clone(), ids.clone()));
    }
    // 400 particles jump by 0.4 spacings: as many evaluations.
    for k in 0..400 {
        let i = (k * 7919) % n;
        rows[i][0] += 0.4;
    }
    frames.push((rows.clone(), ids.clone()));
    // Everything moves 0.6 spacings (more than the grid's skin at r = 0.9): a new grid, and
    // the boundary particles evaluated again (far budget).
    rows.iter_mut().for_each(|p| p[1] += 0.6);
    frames.push((rows.clone(), ids.clone()));
    // Outflow of the first column, inflow of a new one, and the order reversed.
    let keep: Vec<usize> = (0..rows.len()).filter(|&i| rows[i][0] > 0.5).collect();
    rows = keep.iter().map(|&i| rows[i]).collect();
    ids = keep.iter().map(|&i| ids[i]).collect();
    for k in 0..side {
        rows.push([side as f64, k as f64 + 0.6 + 0.1 * (rng.next() - 0.5)]);
        ids.push((n + k) as u64);
    }
    rows.reverse();
    ids.reverse();
    frames.push((rows, ids));

    let radius = Radius::new(0.9).unwrap();
    let expected: Vec<Labels> = frames
        .iter()
        .map(|(rows, _)| {
            ExactDetector::default()
                .detect(&set2(rows), radius)
                .unwrap()
                .labels
        })
        .collect();
    let on_own_pool = Tracker::new(radius, Some(2), Domain::new()).unwrap();
    let on_callers_pool = Tracker::new(radius, None, Domain::new()).unwrap();
    for mut tracker in [on_own_pool, on_callers_pool] {
        let mut recomputed = vec![];
        for (step, (rows, ids)) in frames.iter().enumerate() {
            let labels = tracker.update_with_ids(&set2(rows), ids).unwrap();
            assert_eq!(
                first_difference(labels, &expected[step]),
                None,
                "step {step}"
            );
            recomputed.push(tracker.recomputed());
        }
        assert_eq!(recomputed[0], n);
        assert!(
            recomputed[1..3].iter().all(|&c| c < n / 20),
            "{recomputed:?}"
        );
        assert!(
            recomputed[3] >= 400 && recomputed[3] < n / 2,
            "{recomputed:?}"
        );
        assert!(recomputed[4] >= 128, "{recomputed:?}");
    }
}

/// An update that evaluates few particles runs on the calling thread alone: with the pool's
/// only worker held busy, updates after the first still finish, with the labels of a full
/// detection (an update that waited for the pool would never return).
#[test]
fn small_updates_run_on_the_calling_thread_alone() {
    use std::sync::{mpsc, Arc};
    use std::time::Duration;

    let mut rng = Rng(43);
    let base = jittered_square(20, 0.2, &mut rng);
    let radius = Radius::new(0.8).unwrap();
    let pool = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap(),
    );
    let mut tracker = Tracker::with_pool(radius, Arc::clone(&pool), Domain::new());
    // The first update evaluates all 400 particles, on the pool.
    tracker.update(&set2(&base)).unwrap();
    assert_eq!(tracker.recomputed(), base.len());

    let (started, is_busy) = mpsc::channel();
    let (release, hold) = mpsc::channel::<()>();
    pool.spawn(move || {
        started.send(()).unwrap();
        let _ = hold.recv();
    });
    is_busy.recv().unwrap();
    let (done, finished) = mpsc::channel();
    std::thread::spawn(move || {
        let mut steps = vec![];
        for step in 1..=6 {
            let rows: Vec<[f64; 2]> = base
                .iter()
                .map(|p| [p[0] + 0.0005 * step as f64 * p[1], p[1]])
                .collect();
            let set = set2(&rows);
            let full = ExactDetector::default().detect(&set, radius).unwrap();
            let labels = tracker.update(&set).unwrap();
            steps.push((first_difference(labels, &full.labels), tracker.recomputed()));
        }
        let _ = done.send(steps);
    });
    let outcome = finished.recv_timeout(Duration::from_secs(120));
    release.send(()).unwrap();
    let steps = outcome.expect("an update waited for the pool's busy worker");
    for (step, (difference, recomputed)) in steps.into_iter().enumerate() {
        assert_eq!(difference, None, "step {}", step + 1);
        assert!(recomputed < 128, "step {}: {recomputed}", step + 1);
    }
}
