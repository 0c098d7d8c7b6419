//! Both variants of `lnm` against a brute-force reading of their rules on small seeded sets
//! (every cell and every pair looked at, no grid, no hashing), and the same labels on 1, 2
//! and 3 threads.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{BoundaryDetector, ParticleSet, Point, Radius};
use boundary_lnm::{LnmDetector, LnmParams, LnmVariant};
use boundary_scenes::against;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::collections::HashMap;

/// The labels of the rules, computed the slow way: `L1` cells have an empty one of their
/// `3^D − 1` neighbours, `L2` cells are beside an `L1` cell of at most `delta` particles;
/// fast: `L1` and `L2` particles are boundary; refined: `L2` particles only when a sample
/// `p + 0.75 r · u` (64 angles in 2D; the 65 x 65 latitude-longitude grid in 3D) lies
/// farther than `0.75 r` from every other particle closer than `1.5 r` and not coincident.
fn brute<const D: usize>(
    points: &[Point<D>],
    r: f64,
    delta: u32,
    variant: LnmVariant,
) -> Vec<bool> {
    let l = 2.0 * r;
    let cell = |p: &Point<D>| -> Vec<i64> { (0..D).map(|k| (p[k] / l).floor() as i64).collect() };
    let mut counts: HashMap<Vec<i64>, u32> = HashMap::new();
    for p in points {
        *counts.entry(cell(p)).or_default() += 1;
    }
    let around = |c: &[i64]| -> Vec<Vec<i64>> {
        let mut out = vec![c.to_vec()];
        for k in 0..D {
            out = out
                .into_iter()
                .flat_map(|v| {
                    [-1, 0, 1].map(|d| {
                        let mut w = v.clone();
                        w[k] += d;
                        w
                    })
                })
                .collect();
        }
        out.retain(|v| v.as_slice() != c);
        out
    };
    let first = |c: &[i64]| around(c).iter().any(|n| !counts.contains_key(n));
    let rho = 0.75 * r;
    let mut directions: Vec<Vec<f64>> = Vec::new();
    if D == 2 {
        for k in 0..64 {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 64.0;
            directions.push(vec![a.cos(), a.sin()]);
        }
    } else {
        for i in 0..=64 {
            for j in 0..=64 {
                let u = std::f64::consts::PI * i as f64 / 64.0;
                let v = 2.0 * std::f64::consts::PI * j as f64 / 64.0;
                directions.push(vec![u.sin() * v.cos(), u.sin() * v.sin(), u.cos()]);
            }
        }
    }
    let uncovered = |i: usize| {
        let p = points[i];
        let near: Vec<&Point<D>> = points
            .iter()
            .enumerate()
            .filter(|(j, c)| {
                let d = (*c - p).norm();
                *j != i && d > 0.0 && d < 2.0 * rho
            })
            .map(|(_, c)| c)
            .collect();
        directions.iter().any(|u| {
            let q: Point<D> = Point::from_fn(|k, _| p[k] + rho * u[k]);
            !near.iter().any(|c| (*c - q).norm() <= rho)
        })
    };
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let c = cell(p);
            if first(&c) {
                return true;
            }
            let second = around(&c)
                .iter()
                .any(|n| counts.get(n).is_some_and(|&m| m <= delta && first(n)));
            second
                && match variant {
                    LnmVariant::Fast => true,
                    LnmVariant::Refined => uncovered(i),
                }
        })
        .collect()
}

/// A jittered lattice blob of spacing 1 with a bubble and some loose particles, seeded.
fn blob<const D: usize>(seed: u64, side: i64) -> Vec<Point<D>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut out = Vec::new();
    let cells = (side as usize).pow(D as u32);
    for k in 0..cells {
        let mut rest = k as i64;
        let p: Point<D> = Point::from_fn(|_, _| {
            let x = rest % side;
            rest /= side;
            x as f64 + rng.gen_range(-0.2..0.2)
        });
        let centre = side as f64 / 2.0;
        let bubble = (p - Point::from_element(centre * 0.8)).norm() < side as f64 / 6.0;
        if !bubble && rng.gen_range(0.0..1.0) > 0.03 {
            out.push(p);
        }
    }
    for _ in 0..5 {
        out.push(Point::from_fn(|_, _| {
            rng.gen_range(-3.0..side as f64 + 3.0)
        }));
    }
    // A duplicate, which does not cover its twin.
    out.push(out[out.len() / 2]);
    out
}

fn detect<const D: usize>(points: &[Point<D>], r: f64, params: LnmParams) -> Vec<bool>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let set = ParticleSet::new(points.to_vec()).unwrap();
    let d = LnmDetector::try_new(params).unwrap();
    against::labels(&d, &set, r).unwrap().as_slice().to_vec()
}

#[test]
fn both_variants_follow_their_rules_on_seeded_sets() {
    for seed in 0..4 {
        for variant in [LnmVariant::Fast, LnmVariant::Refined] {
            for (r, delta) in [(1.2, None), (1.0, Some(3)), (0.9, Some(1))] {
                let params = LnmParams {
                    delta,
                    variant,
                    ..Default::default()
                };
                let p2 = blob::<2>(seed, 24);
                let want = brute(&p2, r, delta.unwrap_or(4), variant);
                assert_eq!(
                    detect(&p2, r, params.clone()),
                    want,
                    "2D {seed} {variant:?} r {r}"
                );
                let p3 = blob::<3>(seed, 11);
                let want = brute(&p3, r, delta.unwrap_or(8), variant);
                let got = detect(&p3, r, params);
                assert_eq!(got, want, "3D {seed} {variant:?} r {r}");
                // The rules are not vacuous here: some L2 particles are re-checked both ways.
                if variant == LnmVariant::Refined && delta.is_none() {
                    let fast = brute(&p3, r, 8, LnmVariant::Fast);
                    let dropped = fast.iter().zip(&got).filter(|(f, g)| **f && !**g).count();
                    assert!(dropped > 0, "3D {seed}: the re-check changed nothing");
                    assert!(got.iter().zip(&fast).all(|(g, f)| !g || *f));
                }
            }
        }
    }
}

#[test]
fn the_labels_are_the_same_on_one_two_and_three_threads() {
    let (ball, _) = boundary_scenes::jittered_lattice_ball(40_000, 0.15, 11);
    let disc = boundary_scenes::jittered_lattice_disc(90.0, 0.15, 12);
    let r = Radius::new(1.2).unwrap();
    for variant in [LnmVariant::Fast, LnmVariant::Refined] {
        let d = LnmDetector::try_new(LnmParams {
            variant,
            ..Default::default()
        })
        .unwrap();
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                (
                    d.detect_3d(&ball, r).unwrap().labels,
                    d.detect_2d(&disc, r).unwrap().labels,
                )
            })
        };
        let one = on(1);
        assert!(one.0.boundary_count() > 0 && one.1.boundary_count() > 0);
        assert_eq!(on(2), one, "{variant:?}");
        assert_eq!(on(3), one, "{variant:?}");
    }
}
