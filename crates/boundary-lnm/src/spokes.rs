//! The re-check of the refined variant: the sampled covering test that Bubbles runs on the
//! particles of `L2` cells (its "spoke" version of Dilts' method).
//!
//! A sphere of radius `ρ = SPOKE_RADIUS_OVER_R · r` around the particle is sampled at fixed
//! directions; a sample is covered when it lies within `ρ` of a neighbour closer than `2ρ`
//! (closed balls), and the particle is boundary when some sample is not covered.

use boundary_core::{NeighbourGrid, Point};

/// The radius of the sampled sphere in units of `r`: Bubbles' `DILTS_RADIUS_MULTIPLIER`,
/// applied to its particle radius, the spacing, which `lnm` pairs with `r`.
pub const SPOKE_RADIUS_OVER_R: f64 = 0.75;

/// Samples per turn: Bubbles' `DILTS_LINEAR_SAMPLE_COUNT`.
const SAMPLES: usize = 64;

/// The unit directions of the samples. 2D: `SAMPLES` angles `2πk/SAMPLES`. 3D: the
/// latitude–longitude grid `u = πi/SAMPLES`, `v = 2πj/SAMPLES`, `i, j = 0..=SAMPLES`, with the
/// points that repeat another (the poles, and `v = 2π` beside `v = 0`) kept once.
pub fn spoke_directions<const D: usize>() -> Vec<Point<D>> {
    let step = std::f64::consts::PI / SAMPLES as f64;
    match D {
        2 => (0..SAMPLES)
            .map(|k| {
                let a = 2.0 * step * k as f64;
                Point::<D>::from_fn(|c, _| if c == 0 { a.cos() } else { a.sin() })
            })
            .collect(),
        3 => {
            let mut out = Vec::with_capacity(SAMPLES * (SAMPLES - 1) + 2);
            for i in 0..=SAMPLES {
                let u = step * i as f64;
                let longitudes = if i == 0 || i == SAMPLES { 1 } else { SAMPLES };
                for j in 0..longitudes {
                    let v = 2.0 * step * j as f64;
                    let xyz = [u.sin() * v.cos(), u.sin() * v.sin(), u.cos()];
                    out.push(Point::<D>::from_fn(|c, _| xyz[c]));
                }
            }
            out
        }
        _ => Vec::new(),
    }
}

/// Whether a sample of the sphere of radius `rho` around particle `i` is covered by no ball
/// of radius `rho` around another particle closer than `2 rho` (coincident particles do not
/// cover each other). `grid` holds `positions`, with cells of at least `2 rho`; `near` is
/// scratch space.
///
/// The sample `q = p + rho u` lies within `rho` of a neighbour at `p + d` when
/// `|d − rho u|² <= rho²`, that is `d·u >= |d|² / (2 rho)` (`|u| = 1`): one dot product per
/// sample and neighbour, against a threshold computed once per neighbour.
pub fn spoke_uncovered<const D: usize>(
    grid: &NeighbourGrid<D>,
    positions: &[Point<D>],
    i: usize,
    rho: f64,
    directions: &[Point<D>],
    near: &mut Vec<(Point<D>, f64)>,
) -> bool {
    let p = positions[i];
    let reach2 = 4.0 * rho * rho;
    near.clear();
    grid.for_each_within(&p, 2.0 * rho, |j, d2| {
        if j != i && d2 > 0.0 && d2 < reach2 {
            let d = positions[j] - p;
            near.push((d, d.norm_squared() / (2.0 * rho)));
        }
    });
    // The nearest neighbours cover the largest caps (angular radius `acos(|d| / 2 rho)`):
    // scanned first, they end most scans early. Neighbouring samples are mostly covered by
    // the same ball: it is tried first.
    near.sort_unstable_by(|a, b| a.1.total_cmp(&b.1));
    let mut last = 0;
    'samples: for u in directions {
        if near.get(last).is_some_and(|(d, t)| d.dot(u) >= *t) {
            continue;
        }
        for (k, (d, t)) in near.iter().enumerate() {
            if d.dot(u) >= *t {
                last = k;
                continue 'samples;
            }
        }
        return true;
    }
    false
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use boundary_core::ParticleSet;

    #[test]
    fn the_directions_are_unit_vectors_without_repeats() {
        let two = spoke_directions::<2>();
        let three = spoke_directions::<3>();
        assert_eq!(two.len(), 64);
        assert_eq!(three.len(), 64 * 63 + 2);
        for d in &two {
            assert!((d.norm() - 1.0).abs() < 1e-12);
        }
        for (a, d) in three.iter().enumerate() {
            assert!((d.norm() - 1.0).abs() < 1e-12);
            for e in &three[..a] {
                assert!((d - e).norm() > 1e-9, "{d:?} repeats");
            }
        }
    }

    #[test]
    fn a_square_lattice_covers_its_inner_particles_and_not_its_rim() {
        let rows: Vec<[f64; 2]> = (0..49).map(|k| [(k % 7) as f64, (k / 7) as f64]).collect();
        let set = ParticleSet::from_rows(&rows).unwrap();
        let rho = 0.75; // above the tie radius 1/√2 of the unit square lattice
        let grid = NeighbourGrid::new(&set, 2.0 * rho).unwrap();
        let dirs = spoke_directions::<2>();
        let mut near = Vec::new();
        for k in 0..49 {
            let (x, y) = (k % 7, k / 7);
            let rim = x == 0 || y == 0 || x == 6 || y == 6;
            let got = spoke_uncovered(&grid, set.positions(), k, rho, &dirs, &mut near);
            assert_eq!(got, rim, "particle ({x}, {y})");
        }
        // Below the tie radius the gaps between the balls open: every particle is boundary.
        let rho = 0.7;
        let grid = NeighbourGrid::new(&set, 2.0 * rho).unwrap();
        assert!(spoke_uncovered(
            &grid,
            set.positions(),
            24,
            rho,
            &dirs,
            &mut near
        ));
    }
}
