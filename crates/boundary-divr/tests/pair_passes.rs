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
    // Fewer than half the particles classified: each visits its own neighbours.
    every_method(&set, set.len() / 3, 1.2);
}

/// `randles` (the lower triangle of its matrix only) and `asymmetry` against their sums
/// written out here, per particle, over `for_each_neighbour_volume`, as the criteria were
/// written before their pass over the pairs: the same labels and margins, bit for bit.
#[test]
fn randles_and_asymmetry_match_their_sums_written_out() {
    use boundary_asymmetry::{AsymmetrySums, DEFAULT_DENSITY_RATIO, DEFAULT_THRESHOLD};
    use boundary_core::nalgebra::SMatrix;
    use boundary_core::Point;
    use boundary_randles::positive_definite;
    use boundary_sph::SUPPORT_FACTOR;

    let (ball, _) = boundary_scenes::jittered_lattice_ball(20_000, 0.15, 13);
    let r = Radius::new(1.2).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let randles = RandlesDetector::default();
    let asymmetry = AsymmetryDetector::default();
    let (ctx_r, ctx_a) = pool.install(|| {
        (
            SphContext::new(&ball, randles.smoothing().kernel_at(r)).unwrap(),
            SphContext::new(&ball, asymmetry.smoothing().kernel_at(r)).unwrap(),
        )
    });
    let n = ball.len();
    let (got_r, got_a) = pool.install(|| {
        (
            randles.classify_all(&ctx_r, n),
            asymmetry.classify_all(&ctx_a, n),
        )
    });
    let mu = randles.mu(3);
    let (mut boundary_r, mut boundary_a) = (0, 0);
    for i in 0..n {
        let kernel = ctx_r.kernel();
        let inv_h = 1.0 / kernel.h();
        let mut b = SMatrix::<f64, 3, 3>::zeros();
        ctx_r.for_each_neighbour_volume(i, |volume, xji, d| {
            if d > 0.0 {
                let x = xji * inv_h;
                let w = volume * kernel.reduced_gradient_weight(d * inv_h);
                b += (x * w) * x.transpose();
            }
        });
        let expected = !positive_definite(&(b - SMatrix::<f64, 3, 3>::identity() * mu));
        assert_eq!(got_r[i].boundary, expected, "randles: particle {i}");
        boundary_r += usize::from(expected);

        let kernel = ctx_a.kernel();
        let inv_h = 1.0 / kernel.h();
        let volumes = ctx_a.reduced_volumes();
        let mut offset = Point::<3>::zeros();
        let mut smallest = volumes[i];
        let mut has_neighbour = false;
        ctx_a.for_each_neighbour_volume(i, |volume, xji, d| {
            let q = d * inv_h;
            offset += xji * (inv_h * kernel.reduced_value(q));
            smallest = smallest.min(volume);
            has_neighbour |= d > 0.0 && q < SUPPORT_FACTOR;
        });
        let sums = AsymmetrySums {
            offset,
            density: 1.0 / volumes[i],
            reference_density: 1.0 / smallest,
            has_neighbour,
        };
        let (t, ratio) = (DEFAULT_THRESHOLD, DEFAULT_DENSITY_RATIO);
        let value = sums.value();
        assert_eq!(
            got_a[i].boundary,
            value.is_boundary(t, ratio),
            "asymmetry: particle {i}"
        );
        assert_eq!(
            got_a[i].margin.to_bits(),
            value.margin(t, ratio).to_bits(),
            "asymmetry: particle {i}"
        );
        boundary_a += usize::from(got_a[i].boundary);
    }
    assert!(boundary_r > 100 && boundary_r < n / 2, "{boundary_r}");
    assert!(boundary_a > 100 && boundary_a < n / 2, "{boundary_a}");
}

#[test]
fn the_pair_pass_gives_each_particles_own_verdict_bit_for_bit_2d() {
    let disc = boundary_scenes::jittered_lattice_disc(90.0, 0.2, 5);
    assert!(disc.len() > 17 * 1024, "{} particles", disc.len());
    every_method(&disc, disc.len(), 1.3);
}
