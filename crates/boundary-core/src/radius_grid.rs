//! Neighbour queries for sets with a radius per particle ([`ParticleSet::with_radii`]).
//!
//! Particle `j` can cover part of `S_i` only if `|p_i − p_j| <= r_i + r_j`. One uniform grid
//! queried at `r_i + r_max` would scan, for a small particle beside large ones, every small
//! particle within `r_max`: with radii 100x apart that is 10⁶ times too many in 3D. So the
//! particles are split into *levels* by radius (a factor 2 per level), each level with its own
//! [`NeighbourGrid`] of cell size its largest radius; particle `i` queries level `L` at
//! `r_i + r_max(L)` and keeps the `j` with `d² <= ((r_i + r_j)(1 + 1e-12))²`. The slack makes
//! the result a superset of the exact neighbours (the squared distances carry a relative
//! rounding error of a few `u`): certified callers decide the borderline ones exactly.

use crate::{CoreError, NeighbourGrid, ParticleSet, Point};

/// Relative slack of the reach test `d <= r_i + r_j`, far above the rounding of `d²`.
pub const REACH_SLACK: f64 = 1e-12;

/// One level: the particles whose radius lies in `[lo, 2·lo)`.
#[derive(Debug, Clone)]
struct Level<const D: usize> {
    r_max: f64,
    grid: NeighbourGrid<D>,
    /// Input index of each particle of the level, in the level's own order.
    index: Vec<usize>,
}

/// A neighbour index for particles of differing radii; see the module documentation.
#[derive(Debug, Clone)]
pub struct RadiusGrid<const D: usize> {
    levels: Vec<Level<D>>,
    radii: Vec<f64>,
}

impl<const D: usize> RadiusGrid<D> {
    /// Builds the index over `set` with radius `radii[i]` for particle `i` (the set's resolved
    /// radii, [`ParticleSet::resolved_radii`]). Panics if `radii` does not have one entry per
    /// particle; fails as [`NeighbourGrid::new`] does.
    pub fn new(set: &ParticleSet<D>, radii: &[f64]) -> Result<Self, CoreError> {
        assert_eq!(radii.len(), set.len(), "one radius per particle");
        let r_min = radii.iter().copied().fold(f64::INFINITY, f64::min);
        let mut members: Vec<Vec<usize>> = Vec::new();
        for (i, &r) in radii.iter().enumerate() {
            // Level k holds radii in [r_min·2^k, r_min·2^(k+1)) (up to rounding of the log,
            // which only moves a particle to a neighbouring level: each level's grid uses its
            // own true largest radius, so any grouping is correct).
            let k = (r / r_min).log2().floor().max(0.0) as usize;
            if members.len() <= k {
                members.resize_with(k + 1, Vec::new);
            }
            members[k].push(i);
        }
        let levels = members
            .into_iter()
            .filter(|m| !m.is_empty())
            .map(|index| {
                let r_max = index.iter().map(|&i| radii[i]).fold(0.0, f64::max);
                let grid = NeighbourGrid::new(&set.subset(&index), r_max)?;
                Ok(Level { r_max, grid, index })
            })
            .collect::<Result<Vec<_>, CoreError>>()?;
        Ok(RadiusGrid {
            levels,
            radii: radii.to_vec(),
        })
    }

    /// The radius of particle `i`.
    pub fn radius(&self, i: usize) -> f64 {
        self.radii[i]
    }

    /// The radii, in input order.
    pub fn radii(&self) -> &[f64] {
        &self.radii
    }

    /// The largest radius.
    pub fn max_radius(&self) -> f64 {
        self.levels.iter().map(|l| l.r_max).fold(0.0, f64::max)
    }

    /// Calls `f(j, d2)` for every particle `j` (input index) with
    /// `d² <= ((r + r_j)(1 + REACH_SLACK))²` from the point `q` of radius `r`: a superset of
    /// the particles whose ball reaches the sphere of radius `r` around `q`. If `q` is a
    /// particle, it and its exact duplicates are reported with `d2 = 0`. Order unspecified but
    /// deterministic.
    pub fn for_each_reaching<F: FnMut(usize, f64)>(&self, q: &Point<D>, r: f64, mut f: F) {
        for level in &self.levels {
            let reach = (r + level.r_max) * (1.0 + REACH_SLACK);
            level.grid.for_each_within(q, reach, |local, d2| {
                let j = level.index[local];
                let limit = (r + self.radii[j]) * (1.0 + REACH_SLACK);
                if d2 <= limit * limit {
                    f(j, d2);
                }
            });
        }
    }

    /// The neighbours of particle `i` (other than its exact duplicates) in its own units, as
    /// `ia` and `ge` use them: `(d_j/r_i − s_j, (p_j − p_i)/r_i, s_j)` with `s_j = r_j/r_i`,
    /// sorted by the first entry (how far the ball reaches past `p_i`: the likeliest cover
    /// first). `out` is cleared first.
    pub fn scaled_neighbours(
        &self,
        positions: &[Point<D>],
        i: usize,
        out: &mut Vec<(f64, Point<D>, f64)>,
    ) {
        let p = positions[i];
        let r = self.radii[i];
        out.clear();
        self.for_each_reaching(&p, r, |j, d2| {
            if d2 > 0.0 {
                let s = self.radii[j] / r;
                out.push((d2.sqrt() / r - s, (positions[j] - p) / r, s));
            }
        });
        out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force against the grid on a set with radii spanning a factor 1000.
    #[test]
    fn reaching_neighbours_match_brute_force() {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = 400;
        let pts: Vec<[f64; 3]> = (0..n)
            .map(|_| [next() * 10.0, next() * 10.0, next() * 10.0])
            .collect();
        let radii: Vec<f64> = (0..n).map(|_| 0.01 * 1000f64.powf(next())).collect();
        let set = ParticleSet::<3>::from_rows(&pts).unwrap();
        let grid = RadiusGrid::new(&set, &radii).unwrap();
        assert!(
            grid.levels.len() >= 9,
            "radii over a factor 1000 make ten levels"
        );
        for i in 0..n {
            let mut got = Vec::new();
            grid.for_each_reaching(&set.positions()[i], radii[i], |j, _| got.push(j));
            got.sort_unstable();
            let want: Vec<usize> = (0..n)
                .filter(|&j| {
                    (set.positions()[i] - set.positions()[j]).norm() <= radii[i] + radii[j]
                })
                .collect();
            assert_eq!(got, want, "particle {i}");
        }
    }

    #[test]
    fn equal_radii_make_one_level() {
        let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]]).unwrap();
        let grid = RadiusGrid::new(&set, &[0.5, 0.5, 0.5]).unwrap();
        assert_eq!(grid.levels.len(), 1);
        let mut got = Vec::new();
        grid.for_each_reaching(&set.positions()[1], 0.5, |j, d2| got.push((j, d2)));
        got.sort_by_key(|x| x.0);
        assert_eq!(got, vec![(0, 1.0), (1, 0.0)]);
    }
}
