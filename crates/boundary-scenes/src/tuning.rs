//! Tuning scenes: seeded scenes made only to choose the default thresholds of the SPH criteria
//! (`muller`, `asymmetry`, `randles`), never listed in `fixtures/scenes.toml`, so that no default is
//! chosen on the scenes the sweep reports.
//!
//! A tuning scene lies in a box of side `side` on a lattice of spacing 1: two or three balls
//! (discs in 2D) of radius 0.2–0.35·side, a pool (the half-space below 0.15–0.3·side along the
//! last axis), two bubbles of radius 1 + (0.06–0.12)·side cut out and three droplets of radius
//! 0.5–2.5; the lattice points inside get uniform jitter `±jitter`. The same seed gives the same
//! scene on every run.

use crate::generate::fill;
use boundary_core::{ParticleSet, Point};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// The tuning scene of `seed` (see the module documentation).
pub fn tuning_scene<const D: usize>(seed: u64, side: f64, jitter: f64) -> ParticleSet<D>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let mut rng = StdRng::seed_from_u64(seed);
    let sphere = |rng: &mut StdRng, (lo, hi): (f64, f64), (rlo, rhi): (f64, f64)| {
        let centre = Point::<D>::from_fn(|_, _| rng.gen_range(lo..hi));
        (centre, rng.gen_range(rlo..rhi))
    };
    let count = rng.gen_range(2..=3);
    let balls: Vec<(Point<D>, f64)> = (0..count)
        .map(|_| {
            sphere(
                &mut rng,
                (0.3 * side, 0.7 * side),
                (0.2 * side, 0.35 * side),
            )
        })
        .collect();
    let bubbles: Vec<(Point<D>, f64)> = (0..2)
        .map(|_| {
            sphere(
                &mut rng,
                (0.25 * side, 0.75 * side),
                (1.0 + 0.06 * side, 1.0 + 0.12 * side),
            )
        })
        .collect();
    let droplets: Vec<(Point<D>, f64)> = (0..3)
        .map(|_| sphere(&mut rng, (0.1 * side, 0.9 * side), (0.5, 2.5)))
        .collect();
    let pool = rng.gen_range(0.15 * side..0.3 * side);
    let within =
        |p: &Point<D>, set: &[(Point<D>, f64)]| set.iter().any(|(c, r)| (p - c).norm() <= *r);
    let points = fill([0.0; D], [side; D], 1.0, jitter, &mut rng, |p| {
        let fluid = within(p, &balls) || p[D - 1] < pool;
        (fluid && !within(p, &bubbles)) || within(p, &droplets)
    });
    ParticleSet::new(points).expect("lattice points with bounded jitter are finite")
}

/// One tuning case: a scene and the resolution it is scored at.
#[derive(Debug, Clone)]
pub struct TuningCase<const D: usize> {
    /// What the case is, for the printed table.
    pub name: String,
    /// The particles.
    pub set: ParticleSet<D>,
    /// The resolution `r`, in lattice spacings.
    pub r: f64,
}

/// The 2D tuning cases: `r` = 1, 1.5, 2, 3, 4 spacings, jitter ±0.05 and ±0.2, two seeds each
/// (20 cases, side 48). Seeds from `base`.
pub fn tuning_cases_2d(base: u64) -> Vec<TuningCase<2>> {
    let mut out = Vec::new();
    for (k, &r) in [1.0, 1.5, 2.0, 3.0, 4.0].iter().enumerate() {
        for (j, &jitter) in [0.05, 0.2].iter().enumerate() {
            for s in 0..2u64 {
                let seed = base + 100 * k as u64 + 10 * j as u64 + s;
                let set = tuning_scene::<2>(seed, 48.0, jitter);
                out.push(TuningCase {
                    name: format!("2D seed {seed} r={r} jitter={jitter} n={}", set.len()),
                    set,
                    r,
                });
            }
        }
    }
    out
}

/// The 3D tuning cases: `r` = 1, 1.5, 2 spacings, jitter ±0.05 and ±0.2, one seed each (6
/// cases, side 16). Seeds from `base`.
pub fn tuning_cases_3d(base: u64) -> Vec<TuningCase<3>> {
    let mut out = Vec::new();
    for (k, &r) in [1.0, 1.5, 2.0].iter().enumerate() {
        for (j, &jitter) in [0.05, 0.2].iter().enumerate() {
            let seed = base + 100 * k as u64 + 10 * j as u64;
            let set = tuning_scene::<3>(seed, 16.0, jitter);
            out.push(TuningCase {
                name: format!("3D seed {seed} r={r} jitter={jitter} n={}", set.len()),
                set,
                r,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tuning_scenes_are_seeded_and_leave_free_surfaces() {
        let a = tuning_scene::<2>(1000, 48.0, 0.05);
        assert_eq!(a, tuning_scene::<2>(1000, 48.0, 0.05));
        assert_ne!(a, tuning_scene::<2>(1001, 48.0, 0.05));
        assert!(a.len() > 400 && a.len() < 48 * 48 * 3 / 4, "{}", a.len());
        let b = tuning_scene::<3>(2000, 16.0, 0.2);
        assert!(
            b.len() > 500 && b.len() < 16 * 16 * 16 * 3 / 4,
            "{}",
            b.len()
        );
        assert_eq!(tuning_cases_2d(7).len(), 20);
        assert_eq!(tuning_cases_3d(7).len(), 6);
    }
}
