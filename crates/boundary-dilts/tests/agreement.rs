//! `dilts` and `exact` decide the same definition by independent geometry (sphere covering vs.
//! restricted Voronoi cells): their labels must agree particle by particle, except where the
//! exact margin says the particle is a near-tie (|margin| below `NEAR_TIE · r`).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{Dim, SupportedDim};
use boundary_scenes::{cubic_lattice, shared_set, square_lattice, SHARED_SCENES};

use boundary_core::{BoundaryDetector, Detection, ParticleSet, Radius};
use boundary_dilts::DiltsDetector;
use boundary_exact::ExactDetector;
use proptest::prelude::*;
use rand::{rngs::StdRng, Rng, SeedableRng};

/// Relative band around a tie inside which the two methods may disagree.
const NEAR_TIE: f64 = 1e-6;

fn both<const D: usize>(set: &ParticleSet<D>, r: f64) -> (Detection, Detection)
where
    Dim<D>: SupportedDim,
{
    let r = Radius::new(r).unwrap();
    let any = set.clone().to_any();
    (
        ExactDetector::default().detect(&any, r).unwrap(),
        DiltsDetector::default().detect(&any, r).unwrap(),
    )
}

/// Indices where the methods disagree on a particle that is not a near-tie.
fn disagreements<const D: usize>(set: &ParticleSet<D>, r: f64) -> Vec<usize>
where
    Dim<D>: SupportedDim,
{
    let (exact, dilts) = both(set, r);
    let margin = exact.margin.as_ref().unwrap();
    (0..set.len())
        .filter(|&i| exact.labels.is_boundary(i) != dilts.labels.is_boundary(i))
        .filter(|&i| margin[i].abs() > NEAR_TIE * r)
        .collect()
}

fn assert_agree<const D: usize>(what: &str, set: &ParticleSet<D>, r: f64)
where
    Dim<D>: SupportedDim,
{
    let bad = disagreements(set, r);
    assert!(bad.is_empty(), "{what} r={r}: dilts != exact at {bad:?}");
}

#[test]
fn shared_scenes_agree_particle_by_particle() {
    for &(_, dim, file, r, _, _, _) in SHARED_SCENES {
        if dim == 2 {
            if let Some(set) = shared_set::<2>(file).unwrap() {
                assert_agree(file, &set, r);
            }
        } else if let Some(set) = shared_set::<3>(file).unwrap() {
            assert_agree(file, &set, r);
        }
    }
}

#[test]
fn perfect_lattices_at_tie_and_generic_radii_agree_exactly() {
    // Ties are interior for both methods, so perfect lattices agree even at tie radii.
    let square = ParticleSet::from_rows(&square_lattice(9, 1.0)).unwrap();
    for r in [
        0.6,
        std::f64::consts::FRAC_1_SQRT_2,
        0.8,
        1.0,
        1.2,
        1.5,
        2.0,
    ] {
        let (e, d) = both(&square, r);
        assert_eq!(e.labels, d.labels, "square lattice r={r}");
    }
    let cubic = ParticleSet::from_rows(&cubic_lattice(7, 1.0)).unwrap();
    for r in [
        0.8,
        3f64.sqrt() / 2.0,
        0.9,
        1.0,
        1.2,
        std::f64::consts::SQRT_2,
        1.6,
    ] {
        let (e, d) = both(&cubic, r);
        assert_eq!(e.labels, d.labels, "cubic lattice r={r}");
    }
}

fn jittered<const D: usize>(n_side: usize, jitter: f64, seed: u64) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    let mut rng = StdRng::seed_from_u64(seed);
    let total = n_side.pow(D as u32);
    let rows: Vec<[f64; D]> = (0..total)
        .map(|k| {
            let mut p = [0.0; D];
            let mut rest = k;
            for c in p.iter_mut() {
                *c = (rest % n_side) as f64 + rng.gen_range(-jitter..=jitter);
                rest /= n_side;
            }
            p
        })
        .collect();
    ParticleSet::from_rows(&rows).unwrap()
}

#[test]
fn jittered_lattices_agree_across_radii() {
    for seed in 0..4 {
        let set2 = jittered::<2>(24, 0.3, seed);
        let set3 = jittered::<3>(11, 0.3, seed);
        for r in [0.55, 0.7, 0.9, 1.2, 1.6] {
            assert_agree("jittered 2D", &set2, r);
            assert_agree("jittered 3D", &set3, r);
        }
    }
}

#[test]
fn duplicates_far_offsets_and_flat_sets() {
    // Every particle of a lattice doubled: duplicates do not cover each other, but the copy's
    // neighbours do, so labels equal those of the single lattice for both methods.
    let rows = cubic_lattice(5, 1.0);
    let doubled: Vec<[f64; 3]> = rows.iter().chain(rows.iter()).copied().collect();
    let set = ParticleSet::from_rows(&doubled).unwrap();
    let (e, d) = both(&set, 1.2);
    assert_eq!(e.labels, d.labels);
    assert_eq!(d.labels.boundary_count(), 2 * (125 - 27));

    // Far offset: coordinates ~1e6, r = 0.012.
    let far: Vec<[f64; 3]> = jittered::<3>(8, 0.25, 9)
        .positions()
        .iter()
        .map(|p| [1e6 + 0.01 * p[0], -2e6 + 0.01 * p[1], 3e6 + 0.01 * p[2]])
        .collect();
    assert_agree("far offset", &ParticleSet::from_rows(&far).unwrap(), 0.012);

    // A planar sheet in 3D: every particle is boundary for both.
    let sheet: Vec<[f64; 3]> = square_lattice(6, 1.0)
        .iter()
        .map(|p| [p[0], p[1], 0.0])
        .collect();
    let (_, d) = both(&ParticleSet::from_rows(&sheet).unwrap(), 1.5);
    assert_eq!(d.labels.boundary_count(), 36);
}

#[test]
fn margin_2d_matches_the_label_and_is_in_length_units() {
    let set = jittered::<2>(12, 0.2, 3);
    for r in [0.6, 1.0] {
        let (_, d) = both(&set, r);
        let m = d.margin.unwrap();
        for (i, &mi) in m.iter().enumerate() {
            assert_eq!(mi > 0.0, d.labels.is_boundary(i), "particle {i}");
            assert!(mi.abs() <= std::f64::consts::PI * r + 1e-12);
        }
    }
    // An isolated particle: the whole circle is uncovered, margin π·r.
    let lone = ParticleSet::from_rows(&[[0.0, 0.0], [10.0, 0.0]]).unwrap();
    let (_, d) = both(&lone, 0.5);
    assert!((d.margin.unwrap()[0] - std::f64::consts::PI * 0.5).abs() < 1e-12);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn random_small_sets_agree(
        pts in prop::collection::vec(prop::array::uniform3(0.0f64..3.0), 1..120),
        r in 0.3f64..1.2,
    ) {
        let set = ParticleSet::from_rows(&pts).unwrap();
        prop_assert!(disagreements(&set, r).is_empty());
    }
}

/// Found by the `detect_all` fuzz target: particle 4 has only two neighbours within
/// 2r, so it is boundary. Their caps on `S_4` are externally tangent (angle between centres
/// 125.26° = α_0 + α_2 exactly: cos = −1/√3 on both sides). Counted as crossed, the touching
/// circles would never be probed by criterion (c), and a probe at the tangency point stepped
/// `STEP` = 1e-7 rad along the common tangent leaves both caps only to second order (about
/// 1e-14 in `x·u`, below `COVER_TOLERANCE`): interior, a false negative. So a tangency does
/// not count as a crossing.
#[test]
fn externally_tangent_caps_do_not_cover() {
    let rows = [
        [-0.25, -0.25, -0.5],
        [15.75, 0.0, 15.75],
        [0.0, 0.0, 0.0],
        [0.0, -3.25, -0.25],
        [-0.25, -0.25, -0.25],
    ];
    let set = ParticleSet::from_rows(&rows).unwrap();
    let (exact, dilts) = both(&set, 0.375);
    assert_eq!(exact.labels.boundary_count(), 5);
    assert_eq!(dilts.labels.as_slice(), exact.labels.as_slice());
}
