//! The narrow band: a boundary widened to the particles near it, as solvers need a few
//! layers of surface particles (a free-surface condition, shifting, surface tension).

use crate::{AnyParticleSet, CoreError, Labels, NeighbourGrid, ParticleSet};
use rayon::prelude::*;

impl Labels {
    /// The labels widened by `distance`: particle `i` is flagged iff some particle flagged in
    /// `self` lies within `distance` of it (closed: `|x_i − x_j| <= distance`, `j = i`
    /// included, so every flagged particle stays flagged). `set` holds the particles the
    /// labels describe, in the same order. With the resolution `r` of a detection,
    /// `distance = K·r` gives the band of `K` radii (`--band K` on the command line).
    ///
    /// Policy: coincident duplicates of a flagged particle are flagged (distance 0);
    /// `distance` must be finite and `> 0`, else [`CoreError::InvalidRadius`]; labels of
    /// another length than `set` give [`CoreError::LengthMismatch`]. One neighbour query per
    /// unflagged particle on the core grid (cells of `distance`), in parallel; the result
    /// does not depend on the thread count.
    ///
    /// ```
    /// use boundary_core::{Labels, ParticleSet};
    ///
    /// // Ten particles on a line, the first flagged: a band of 2.5 adds the next two.
    /// let rows: Vec<[f64; 2]> = (0..10).map(|k| [k as f64, 0.0]).collect();
    /// let set = ParticleSet::from_rows(&rows).unwrap();
    /// let labels: Labels = (0..10).map(|k| k == 0).collect();
    /// let band = labels.widen(&set, 2.5).unwrap();
    /// assert_eq!(band.boundary_count(), 3);
    /// ```
    pub fn widen<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        distance: f64,
    ) -> Result<Labels, CoreError> {
        if self.len() != set.len() {
            return Err(CoreError::LengthMismatch {
                predicted: self.len(),
                truth: set.len(),
            });
        }
        // The grid checks `distance` (finite, > 0) and the extent.
        let grid = NeighbourGrid::new(set, distance)?;
        let flagged = self.as_slice();
        let positions = set.positions();
        Ok((0..set.len())
            .into_par_iter()
            .map(|i| {
                let mut near = flagged[i];
                if !near {
                    grid.for_each_within(&positions[i], distance, |j, _| near |= flagged[j]);
                }
                near
            })
            .collect::<Vec<bool>>()
            .into_iter()
            .collect())
    }

    /// [`Labels::widen`] for a set whose dimension is known at run time.
    pub fn widen_any(&self, set: &AnyParticleSet, distance: f64) -> Result<Labels, CoreError> {
        match set {
            AnyParticleSet::D2(s) => self.widen(s, distance),
            AnyParticleSet::D3(s) => self.widen(s, distance),
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    fn brute<const D: usize>(labels: &Labels, set: &ParticleSet<D>, distance: f64) -> Labels {
        let p = set.positions();
        (0..set.len())
            .map(|i| {
                (0..set.len()).any(|j| labels.is_boundary(j) && (p[i] - p[j]).norm() <= distance)
            })
            .collect()
    }

    fn random<const D: usize>(n: usize, seed: u64) -> (ParticleSet<D>, Labels)
    where
        crate::Dim<D>: crate::SupportedDim,
    {
        let mut rng = StdRng::seed_from_u64(seed);
        let rows: Vec<[f64; D]> = (0..n)
            .map(|_| std::array::from_fn(|_| rng.gen_range(-5.0..5.0)))
            .collect();
        let labels: Labels = (0..n).map(|_| rng.gen_bool(0.05)).collect();
        (ParticleSet::from_rows(&rows).unwrap(), labels)
    }

    #[test]
    fn widening_matches_brute_force_on_random_sets() {
        for seed in 0..4 {
            let (set2, labels2) = random::<2>(600, seed);
            let (set3, labels3) = random::<3>(600, seed + 10);
            for distance in [0.05, 0.3, 1.0, 2.5, 20.0] {
                let got = labels2.widen(&set2, distance).unwrap();
                assert_eq!(
                    got,
                    brute(&labels2, &set2, distance),
                    "2D {seed} {distance}"
                );
                let got = labels3.widen_any(&set3.to_any(), distance).unwrap();
                assert_eq!(
                    got,
                    brute(&labels3, &set3, distance),
                    "3D {seed} {distance}"
                );
            }
        }
    }

    #[test]
    fn the_band_is_closed_keeps_duplicates_and_checks_its_input() {
        // Points 1 apart: a band of exactly 1 reaches the next one (closed); a duplicate of
        // the flagged particle is flagged.
        let set =
            ParticleSet::from_rows(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 0.0]]).unwrap();
        let labels = Labels::new(vec![true, false, false, false]);
        let band = labels.widen(&set, 1.0).unwrap();
        assert_eq!(band.as_slice(), [true, true, false, true]);
        let none = Labels::new(vec![false; 4]);
        assert_eq!(none.widen(&set, 100.0).unwrap(), none);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                labels.widen(&set, bad),
                Err(CoreError::InvalidRadius(_))
            ));
        }
        let short = Labels::new(vec![true]);
        assert_eq!(
            short.widen(&set, 1.0),
            Err(CoreError::LengthMismatch {
                predicted: 1,
                truth: 4
            })
        );
        let empty = ParticleSet::<3>::new(Vec::new()).unwrap();
        assert!(Labels::default().widen(&empty, 1.0).unwrap().is_empty());
    }
}
