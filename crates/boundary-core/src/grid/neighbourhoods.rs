//! Neighbourhoods of every particle, visited in the grid's cell order.
//!
//! [`NeighbourGrid::par_map_within`] hands each particle its neighbourhood as one slice of
//! hits, for methods that read every neighbour within `2r` (`svm`'s features): particles are
//! visited in the grid's cell order (neighbouring particles one after another, so their
//! candidate cells stay in cache), the candidates are read from the grid's cell-sorted
//! positions, and the distance test has no branch per candidate (every candidate is written,
//! a running count keeps the hits). Under `valgrind --tool=callgrind --branch-sim=yes
//! --cache-sim=yes` (`svm`'s features, 10^5 ball) this has fewer mispredicted branches and
//! L1 data misses than one `for_each_within` per particle in input order, for about the same
//! instructions. Sharing one list of candidate rows among the particles of a block of cells
//! does not pay: a block's rows hold about 2.5x the candidates of a point's (at cells of side
//! `r`, radius `2r`), which costs more instructions and more cache misses.
//!
//! **Same neighbours, same order, same distances.** Every particle is given exactly the
//! particles [`NeighbourGrid::for_each_within`] reports for its position, in the same order,
//! with the same `d2`: the candidate rows and the distance come from the same functions. So
//! a caller's sums, taken in that order, are bit-identical to the per-particle query's.
//! Tested against it on random, lattice (distances exactly at the radius), far-from-origin
//! and sparse (hashed) sets, in 2D and 3D.

use super::{dist2, NeighbourGrid};
use crate::Point;
use rayon::prelude::*;
use std::ops::Range;
use std::sync::OnceLock;

/// The particles within the radius of one particle, as [`NeighbourGrid::par_map_within`]
/// gives them: in the order [`NeighbourGrid::for_each_within`] reports them.
#[derive(Debug)]
pub struct Neighbourhood<'a, const D: usize> {
    grid: &'a NeighbourGrid<D>,
    slots: &'a [u32],
    d2: &'a [f64],
}

impl<'a, const D: usize> Neighbourhood<'a, D> {
    /// How many particles (the particle itself and its exact duplicates included).
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Whether there is none (never the case for a particle of the grid: it finds itself).
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// `(d2, p_j)` for each, as [`Neighbourhood::iter`] without the input index (one load
    /// less per neighbour).
    pub fn distances_and_positions(&self) -> impl Iterator<Item = (f64, &'a Point<D>)> + 'a {
        let sorted = &self.grid.sorted;
        self.d2
            .iter()
            .zip(self.slots)
            .map(move |(&d2, &s)| (d2, &sorted[s as usize]))
    }

    /// `(j, d2, p_j)` for each: the input index, the squared distance (as
    /// [`NeighbourGrid::for_each_within`] computes it) and the position.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64, &'a Point<D>)> + 'a {
        let grid = self.grid;
        self.slots.iter().zip(self.d2).map(move |(&s, &d2)| {
            (
                grid.order[s as usize] as usize,
                d2,
                &grid.sorted[s as usize],
            )
        })
    }
}

/// Per-worker buffers: the candidate ranges of the current particle and its hits.
#[derive(Default)]
struct Scratch {
    rows: Vec<Range<usize>>,
    slots: Vec<u32>,
    d2: Vec<f64>,
}

/// Particles of the cell order per parallel task: enough to amortise a task, few enough
/// that two threads share the work of a small set.
const TASK: usize = 1024;

impl<const D: usize> NeighbourGrid<D> {
    /// `f(state, i, neighbourhood)` for every particle `i < count` (input index), where the
    /// neighbourhood holds the particles within `radius` of `p_i` exactly as
    /// [`NeighbourGrid::for_each_within`] reports them (same particles, order and `d2`; the
    /// particle itself included); the results in input order. The particles are visited in
    /// the grid's cell order, in parallel (rayon); `init` makes one `state` per worker (a
    /// caller's scratch buffers). See the module documentation of `grid/neighbourhoods.rs`.
    ///
    /// ```
    /// use boundary_core::{NeighbourGrid, ParticleSet};
    ///
    /// let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0], [5.0, 5.0]]).unwrap();
    /// let grid = NeighbourGrid::new(&set, 1.0).unwrap();
    /// let counts = grid.par_map_within(1.0, set.len(), || (), |_, _, n| n.len());
    /// assert_eq!(counts, vec![2, 2, 1]);
    /// ```
    pub fn par_map_within<S, T>(
        &self,
        radius: f64,
        count: usize,
        init: impl Fn() -> S + Sync + Send,
        f: impl Fn(&mut S, usize, &Neighbourhood<'_, D>) -> T + Sync + Send,
    ) -> Vec<T>
    where
        T: Send + Sync + Default,
    {
        let count = count.min(self.order.len());
        let r2 = radius * radius;
        // Each result is set at its input index by the worker that computes it: no serial
        // pass puts them back in input order (on many threads such a pass, a permutation of
        // every result, was a large part of the time).
        let results: Vec<OnceLock<T>> = (0..count).map(|_| OnceLock::new()).collect();
        self.order.par_chunks(TASK).enumerate().for_each_init(
            || (init(), Scratch::default()),
            |(state, scratch), (task, order)| {
                if crate::stop::requested() {
                    return;
                }
                for (s, &i) in (task * TASK..).zip(order) {
                    let i = i as usize;
                    if i >= count {
                        continue;
                    }
                    let k = self.hits(&self.sorted[s], radius, r2, scratch);
                    let n = Neighbourhood {
                        grid: self,
                        slots: &scratch.slots[..k],
                        d2: &scratch.d2[..k],
                    };
                    // Set once: `order` lists each particle once.
                    let _ = results[i].set(f(state, i, &n));
                }
            },
        );
        results
            .into_par_iter()
            .map(|r| r.into_inner().unwrap_or_default())
            .collect()
    }

    /// Writes the slots and squared distances of the particles within `radius` of `q`
    /// (`r2 = radius²`) to the front of `scratch.slots` / `scratch.d2`, in the order
    /// [`NeighbourGrid::for_each_within`] reports them; returns how many.
    fn hits(&self, q: &Point<D>, radius: f64, r2: f64, scratch: &mut Scratch) -> usize {
        scratch.rows.clear();
        let mut candidates = 0;
        self.for_each_candidate_range(q, radius, |range| {
            candidates += range.len();
            scratch.rows.push(range);
        });
        if scratch.slots.len() < candidates {
            scratch.slots.resize(candidates, 0);
            scratch.d2.resize(candidates, 0.0);
        }
        let slots = &mut scratch.slots[..candidates];
        let d2s = &mut scratch.d2[..candidates];
        let mut k = 0;
        for range in &scratch.rows {
            let first = range.start;
            for (t, p) in self.sorted[range.clone()].iter().enumerate() {
                let d2 = dist2(p, q);
                // Every candidate is written; only hits advance `k` (no branch per candidate).
                slots[k] = (first + t) as u32;
                d2s[k] = d2;
                k += (d2 <= r2) as usize;
            }
        }
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::tests::random_set;
    use crate::ParticleSet;
    use crate::{Dim, SupportedDim};

    /// What `for_each_within` reports for every particle `i < count`, in its order.
    fn per_particle<const D: usize>(
        grid: &NeighbourGrid<D>,
        set: &ParticleSet<D>,
        radius: f64,
        count: usize,
    ) -> Vec<Vec<(usize, u64, [u64; D])>> {
        set.positions()[..count]
            .iter()
            .map(|q| {
                let mut v = Vec::new();
                grid.for_each_within(q, radius, |j, d2| {
                    let p = set.positions()[j];
                    v.push((j, d2.to_bits(), std::array::from_fn(|k| p[k].to_bits())));
                });
                v
            })
            .collect()
    }

    /// What `par_map_within` gives, in the same form (bit patterns: the same distances and
    /// positions, not merely close ones).
    fn blocked<const D: usize>(
        grid: &NeighbourGrid<D>,
        radius: f64,
        count: usize,
    ) -> Vec<Vec<(usize, u64, [u64; D])>> {
        grid.par_map_within(
            radius,
            count,
            || (),
            |_, _, n| {
                n.iter()
                    .map(|(j, d2, p)| (j, d2.to_bits(), std::array::from_fn(|k| p[k].to_bits())))
                    .collect()
            },
        )
    }

    fn check<const D: usize>(set: &ParticleSet<D>, cell: f64, radii: &[f64]) {
        let grid = NeighbourGrid::new(set, cell).unwrap();
        for &radius in radii {
            for count in [set.len(), set.len() / 3] {
                assert_eq!(
                    blocked(&grid, radius, count),
                    per_particle(&grid, set, radius, count),
                    "cell {cell}, radius {radius}, count {count}"
                );
            }
        }
    }

    /// A perfect lattice of spacing 1 (coordinates are integers plus `offset`): many pairs at
    /// exactly 1, √2, 2, … from each other, so radii at those values test the closed bound.
    fn lattice<const D: usize>(side: usize, offset: f64) -> ParticleSet<D>
    where
        Dim<D>: SupportedDim,
    {
        let n = side.pow(D as u32);
        ParticleSet::new(
            (0..n)
                .map(|mut c| {
                    Point::<D>::from_fn(|_, _| {
                        let x = (c % side) as f64;
                        c /= side;
                        offset + x
                    })
                })
                .collect(),
        )
        .unwrap()
    }

    #[test]
    fn each_particle_gets_exactly_what_a_query_gives_in_2d_and_3d() {
        check(
            &random_set::<2>(1, 700, 10.0, 0.0),
            0.5,
            &[0.0, 0.3, 1.0, 1.7],
        );
        check(&random_set::<3>(2, 700, 6.0, -3.0), 0.6, &[0.4, 1.2, 2.0]);
        // Cells wider and narrower than the radius.
        check(&random_set::<3>(3, 400, 5.0, 0.0), 2.5, &[1.0]);
        check(&random_set::<2>(4, 400, 5.0, 0.0), 0.1, &[0.45]);
    }

    #[test]
    fn particles_exactly_at_the_radius_are_included_as_by_a_query() {
        // Distances 1, 2 (and √2, √5, … for the others) are exact: the closed bound.
        check(&lattice::<3>(7, 0.0), 1.0, &[1.0, 2.0]);
        check(&lattice::<2>(12, 0.0), 1.0, &[1.0, 2.0, 3.0]);
        check(&lattice::<3>(6, 0.0), 0.5, &[1.0, 2.0]);
    }

    #[test]
    fn far_from_the_origin_and_duplicates_match_a_query() {
        check(&random_set::<3>(5, 300, 0.2, 1e6), 0.04, &[0.02, 0.04]);
        check(&lattice::<2>(9, 1e7), 1.0, &[1.0, 2.0]);
        let mut rows: Vec<[f64; 2]> = (0..50).map(|k| [k as f64 * 0.3, 0.0]).collect();
        rows.extend_from_slice(&[[0.3, 0.0], [0.3, 0.0], [3.0, 0.0]]);
        check(
            &ParticleSet::<2>::from_rows(&rows).unwrap(),
            0.3,
            &[0.0, 0.3, 0.6],
        );
    }

    #[test]
    fn the_hashed_layout_and_an_empty_set_go_through_the_same_interface() {
        let rows = [
            [0.0, 0.0, 0.0],
            [1e6, 1e6, 1e6],
            [0.005, 0.0, 0.0],
            [1e6, 1e6, 1e6],
        ];
        let set = ParticleSet::<3>::from_rows(&rows).unwrap();
        let grid = NeighbourGrid::new(&set, 0.02).unwrap();
        assert!(grid.is_hashed());
        check(&set, 0.02, &[0.01, 0.02]);
        let counts = grid.par_map_within(0.01, 4, || (), |_, _, n| n.len());
        assert_eq!(counts, vec![2, 2, 2, 2]);
        let empty = ParticleSet::<2>::new(Vec::new()).unwrap();
        let grid = NeighbourGrid::new(&empty, 1.0).unwrap();
        assert!(grid
            .par_map_within(1.0, 5, || (), |_, _, n| n.len())
            .is_empty());
    }

    #[test]
    fn results_come_back_in_input_order_whatever_the_cell_order() {
        let set = random_set::<3>(6, 500, 4.0, 0.0);
        let grid = NeighbourGrid::new(&set, 0.7).unwrap();
        // The input index comes back at its own place, whatever the cell order.
        let got = grid.par_map_within(1.4, set.len(), Vec::<usize>::new, |seen, i, _| {
            seen.push(i);
            i
        });
        assert_eq!(got, (0..set.len()).collect::<Vec<_>>());
    }
}
