//! The one-pass SPH-sum criteria classify every particle at once with a pass over the pairs
//! (`SphCriterion::classify_all`, each pair's kernel evaluated once for both particles): the
//! verdicts, margins included, must be those of each particle's own pass
//! (`SphCriterion::classify`) bit for bit, on one thread and on several ranges of the cell
//! order swept in parallel, in 2D and 3D, with exact duplicates and ghosts.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_asymmetry::AsymmetryDetector;
use boundary_core::{ParticleSet, Radius};
use boundary_divr::DivrDetector;
use boundary_marrone::MarroneDetector;
use boundary_muller::MullerDetector;
use boundary_randles::RandlesDetector;
use boundary_sph::{SphContext, SphCriterion, Verdict};

/// The verdicts of the first `count` particles of `set` by both paths, with the context built
/// and the passes run on `threads` threads.
fn both<C: SphCriterion, const D: usize>(
    criterion: &C,
    set: &ParticleSet<D>,
    count: usize,
    r: f64,
    threads: usize,
) -> (Vec<Verdict>, Vec<Verdict>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let r = Radius::new(r).unwrap();
        let ctx = SphContext::new(set, criterion.smoothing().kernel_at(r)).unwrap();
        let alone: Vec<Verdict> = (0..count).map(|i| criterion.classify(&ctx, i)).collect();
        (alone, criterion.classify_all(&ctx, count))
    })
}

/// Bit for bit, `NaN` margins (label-only criteria) included.
fn assert_same<C: SphCriterion, const D: usize>(
    criterion: &C,
    set: &ParticleSet<D>,
    count: usize,
    r: f64,
) {
    for threads in [1, 2] {
        let (alone, all) = both(criterion, set, count, r, threads);
        assert_eq!(all.len(), count);
        let mut boundary = 0;
        for (i, (a, b)) in alone.iter().zip(&all).enumerate() {
            assert_eq!(a.boundary, b.boundary, "{}: particle {i}", C::METHOD);
            assert_eq!(
                a.margin.to_bits(),
                b.margin.to_bits(),
                "{}: particle {i}",
                C::METHOD
            );
            boundary += usize::from(a.boundary);
        }
        // Both labels occur: the comparison is not between two constant answers.
        assert!(
            boundary > 0 && boundary < count,
            "{}: {boundary}",
            C::METHOD
        );
    }
}

fn every_method<const D: usize>(set: &ParticleSet<D>, count: usize, r: f64) {
    assert_same(&DivrDetector::default(), set, count, r);
    assert_same(&MullerDetector::default(), set, count, r);
    assert_same(&MarroneDetector::default(), set, count, r);
    assert_same(&RandlesDetector::default(), set, count, r);
    assert_same(&AsymmetryDetector::default(), set, count, r);
}

/// About 20 blocks of the neighbour lists: two ranges of the parallel pair pass on two
/// threads, so pairs cross a cut. Exact duplicates of a few particles; the last 500 particles
/// are ghosts (neighbours only).
#[test]
fn the_pair_pass_gives_each_particles_own_verdict_bit_for_bit_3d() {
    let (ball, _) = boundary_scenes::jittered_lattice_ball(20_000, 0.15, 11);
    let mut rows: Vec<[f64; 3]> = ball.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    rows.extend_from_within(1000..1020);
    let set = ParticleSet::from_rows(&rows).unwrap();
    every_method(&set, set.len() - 500, 1.2);
}

#[test]
fn the_pair_pass_gives_each_particles_own_verdict_bit_for_bit_2d() {
    let disc = boundary_scenes::jittered_lattice_disc(90.0, 0.2, 5);
    assert!(disc.len() > 17 * 1024, "{} particles", disc.len());
    every_method(&disc, disc.len(), 1.3);
}
