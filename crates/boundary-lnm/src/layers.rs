//! The layers of LNM on the occupied cells of a voxel grid: no particle here, only cell
//! indices and counts, so the rules are tested on hand-made grids.
//!
//! Two implementations of the same rules: [`Cells`], a hash map of the occupied cells (the
//! reference, and the path for sets whose cells are scattered), and a dense array over the
//! bounding box of the occupied cells ([`particle_layers`] picks it when the box holds at most
//! [`DENSE_CELLS_PER_PARTICLE`] cells per particle), whose passes are all parallel: the
//! counts are atomic sums, and the layers of a cell read only counts and the first layer.

use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::sync::atomic::{AtomicU32, Ordering};

/// The dense array is used when the cells' bounding box (with a margin of one cell) holds at
/// most this many cells per particle, plus 4096 cells: its memory stays a few bytes per
/// cell, and every cell of the box is visited once per pass.
pub const DENSE_CELLS_PER_PARTICLE: usize = 8;
/// Cells always allowed to the dense array, so that small sets take it too.
const DENSE_SLACK: usize = 4096;

/// The layer of an occupied cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layer {
    /// `L1`: a cell of its `3^D − 1` neighbours is empty.
    First,
    /// `L2`: not `L1`, and a neighbour is an `L1` cell holding at most `δ` particles.
    Second,
    /// Neither: its particles are interior.
    Inner,
}

/// The `3^D − 1` offsets of the cells around a cell (faces, edges and corners).
pub fn neighbour_offsets<const D: usize>() -> Vec<[i64; D]> {
    let total = 3usize.pow(D as u32);
    (0..total)
        .map(|k| {
            let mut rest = k;
            std::array::from_fn(|_| {
                let digit = (rest % 3) as i64 - 1;
                rest /= 3;
                digit
            })
        })
        .filter(|o: &[i64; D]| o.iter().any(|&c| c != 0))
        .collect()
}

/// The occupied cells of a grid with their particle counts, and the rules of the layers.
#[derive(Debug, Clone)]
pub struct Cells<const D: usize> {
    /// Cell index → (particle count, whether it is `L1`).
    cells: FxHashMap<[i64; D], (u32, bool)>,
    offsets: Vec<[i64; D]>,
}

fn add<const D: usize>(a: &[i64; D], b: &[i64; D]) -> [i64; D] {
    std::array::from_fn(|k| a[k] + b[k])
}

impl<const D: usize> Cells<D> {
    /// The grid of the particles whose cell indices are `keys` (one per particle; duplicates
    /// count twice). Cell indices must stay within `±2^53` (so that their neighbours' indices
    /// do not overflow).
    pub fn new(keys: &[[i64; D]]) -> Self {
        let mut cells: FxHashMap<[i64; D], (u32, bool)> = FxHashMap::default();
        for key in keys {
            cells.entry(*key).or_insert((0, false)).0 += 1;
        }
        let offsets = neighbour_offsets::<D>();
        let occupied: Vec<[i64; D]> = cells.keys().copied().collect();
        let first: Vec<bool> = occupied
            .par_iter()
            .map(|key| offsets.iter().any(|o| !cells.contains_key(&add(key, o))))
            .collect();
        for (key, open) in occupied.iter().zip(first) {
            if let Some(cell) = cells.get_mut(key) {
                cell.1 = open;
            }
        }
        Cells { cells, offsets }
    }

    /// The occupied cells.
    pub fn keys(&self) -> impl Iterator<Item = &[i64; D]> {
        self.cells.keys()
    }

    /// The number of particles in cell `key` (0 if empty).
    pub fn count(&self, key: &[i64; D]) -> u32 {
        self.cells.get(key).map_or(0, |c| c.0)
    }

    /// The layer of the occupied cell `key`, with `delta` the largest count of a *sparse*
    /// `L1` cell; `None` for an empty cell.
    pub fn layer(&self, key: &[i64; D], delta: u32) -> Option<Layer> {
        let &(_, first) = self.cells.get(key)?;
        if first {
            return Some(Layer::First);
        }
        let sparse_first_beside = self.offsets.iter().any(|o| {
            self.cells
                .get(&add(key, o))
                .is_some_and(|&(count, first)| first && count <= delta)
        });
        Some(if sparse_first_beside {
            Layer::Second
        } else {
            Layer::Inner
        })
    }
}

/// The layer of the cell of each of the first `count` particles, given the cell index of
/// every particle (`keys`; those after `count` are ghosts, which fill cells but are not
/// classified), with `delta` the largest count of a sparse `L1` cell. Cell indices must stay
/// within `±2^53`. The same layers as [`Cells::layer`], whichever path is taken.
pub fn particle_layers<const D: usize>(keys: &[[i64; D]], count: usize, delta: u32) -> Vec<Layer> {
    debug_assert!(count <= keys.len());
    match Dense::covering(keys) {
        Some(dense) => dense.particle_layers(keys, count, delta),
        None => hashed_particle_layers(keys, count, delta),
    }
}

/// The layers through the hash map of the occupied cells.
pub fn hashed_particle_layers<const D: usize>(
    keys: &[[i64; D]],
    count: usize,
    delta: u32,
) -> Vec<Layer> {
    let cells = Cells::new(keys);
    let occupied: Vec<[i64; D]> = cells.keys().copied().collect();
    // Each cell's layer once, then one lookup per particle.
    let layers: FxHashMap<[i64; D], Layer> = occupied
        .par_iter()
        .map(|key| (*key, cells.layer(key, delta).unwrap_or(Layer::First)))
        .collect();
    keys[..count]
        .par_iter()
        .map(|key| layers.get(key).copied().unwrap_or(Layer::First))
        .collect()
}

/// A dense array of cells over the bounding box of the occupied cells, widened by one empty
/// cell on every side so that the neighbours of an occupied cell are always in the array.
#[derive(Debug, Clone)]
struct Dense<const D: usize> {
    /// The smallest cell index along each axis.
    lo: [i64; D],
    /// The step in the array of one cell along each axis (x fastest).
    strides: [usize; D],
    /// The number of cells in the array.
    total: usize,
}

impl<const D: usize> Dense<D> {
    /// The array over `keys`, or `None` when it would hold more than
    /// [`DENSE_CELLS_PER_PARTICLE`] cells per particle (plus [`DENSE_SLACK`]).
    fn covering(keys: &[[i64; D]]) -> Option<Self> {
        let (lo, hi) = keys
            .par_iter()
            .fold(
                || ([i64::MAX; D], [i64::MIN; D]),
                |(mut lo, mut hi), key| {
                    for k in 0..D {
                        lo[k] = lo[k].min(key[k]);
                        hi[k] = hi[k].max(key[k]);
                    }
                    (lo, hi)
                },
            )
            .reduce(
                || ([i64::MAX; D], [i64::MIN; D]),
                |(a, b), (c, d)| {
                    (
                        std::array::from_fn(|k| a[k].min(c[k])),
                        std::array::from_fn(|k| b[k].max(d[k])),
                    )
                },
            );
        let limit = keys
            .len()
            .checked_mul(DENSE_CELLS_PER_PARTICLE)?
            .checked_add(DENSE_SLACK)?;
        let mut strides = [0usize; D];
        let mut total = 1usize;
        for k in 0..D {
            // Indices within ±2^53: the difference fits, and so does the margin.
            let extent = usize::try_from(hi[k].checked_sub(lo[k])?.checked_add(3)?).ok()?;
            strides[k] = total;
            total = total.checked_mul(extent)?;
            if total > limit {
                return None;
            }
        }
        Some(Dense { lo, strides, total })
    }

    fn index(&self, key: &[i64; D]) -> usize {
        (0..D)
            .map(|k| (key[k] - self.lo[k] + 1) as usize * self.strides[k])
            .sum()
    }

    fn particle_layers(&self, keys: &[[i64; D]], count: usize, delta: u32) -> Vec<Layer> {
        let offsets: Vec<isize> = neighbour_offsets::<D>()
            .iter()
            .map(|o| {
                (0..D)
                    .map(|k| o[k] as isize * self.strides[k] as isize)
                    .sum()
            })
            .collect();
        let cell_of: Vec<usize> = keys.par_iter().map(|key| self.index(key)).collect();
        let counts: Vec<AtomicU32> = (0..self.total)
            .into_par_iter()
            .map(|_| AtomicU32::new(0))
            .collect();
        cell_of.par_iter().for_each(|&c| {
            counts[c].fetch_add(1, Ordering::Relaxed);
        });
        let counts: Vec<u32> = counts.into_par_iter().map(AtomicU32::into_inner).collect();
        // The margin keeps `c + o` inside the array for every occupied cell `c`.
        let first: Vec<bool> = (0..self.total)
            .into_par_iter()
            .map(|c| {
                counts[c] > 0
                    && offsets
                        .iter()
                        .any(|&o| counts[c.wrapping_add_signed(o)] == 0)
            })
            .collect();
        let layers: Vec<Layer> = (0..self.total)
            .into_par_iter()
            .map(|c| {
                if counts[c] == 0 || first[c] {
                    Layer::First
                } else if offsets.iter().any(|&o| {
                    let n = c.wrapping_add_signed(o);
                    first[n] && counts[n] <= delta
                }) {
                    Layer::Second
                } else {
                    Layer::Inner
                }
            })
            .collect();
        cell_of[..count].par_iter().map(|&c| layers[c]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn there_are_three_to_the_d_minus_one_offsets_without_the_zero() {
        assert_eq!(neighbour_offsets::<2>().len(), 8);
        let three = neighbour_offsets::<3>();
        assert_eq!(three.len(), 26);
        assert!(three.contains(&[-1, 1, 0]) && !three.contains(&[0, 0, 0]));
    }

    /// A 5 x 5 block of occupied cells (2D), each with 6 particles but the cell (1, 2) with
    /// `k`: the rim is `L1`; the 3 x 3 core is `L2` where it touches a sparse `L1` cell.
    fn block(k: u32) -> Cells<2> {
        let mut keys = Vec::new();
        for x in 0..5i64 {
            for y in 0..5i64 {
                let n = if (x, y) == (0, 2) { k } else { 6 };
                keys.extend((0..n).map(|_| [x, y]));
            }
        }
        Cells::new(&keys)
    }

    #[test]
    fn hand_made_grids_get_the_layers_of_the_rules() {
        // (0, 2) holds 4 particles: sparse for delta = 4 (the paper's (2r/r)^2), not for 3
        // (Bubbles' 2D offset).
        let cells = block(4);
        assert_eq!(cells.count(&[0, 2]), 4);
        assert_eq!(cells.layer(&[9, 9], 4), None);
        for x in 0..5i64 {
            for y in 0..5i64 {
                let rim = x == 0 || y == 0 || x == 4 || y == 4;
                let beside_sparse = !rim && x == 1 && (1..=3).contains(&y);
                let want = if rim {
                    Layer::First
                } else if beside_sparse {
                    Layer::Second
                } else {
                    Layer::Inner
                };
                assert_eq!(cells.layer(&[x, y], 4), Some(want), "cell ({x}, {y})");
                let bubbles = if rim { Layer::First } else { Layer::Inner };
                assert_eq!(
                    cells.layer(&[x, y], 3),
                    Some(bubbles),
                    "cell ({x}, {y}), delta 3"
                );
            }
        }
        // Every rim cell sparse (delta 6): the whole core's outer ring is L2, the centre too
        // (its neighbours are not L1): the centre stays inner.
        let dense = block(6);
        assert_eq!(dense.layer(&[1, 1], 6), Some(Layer::Second));
        assert_eq!(dense.layer(&[2, 2], 6), Some(Layer::Inner));
        // A lone cell is L1, whatever delta.
        let lone = Cells::<3>::new(&[[7, -3, 2]]);
        assert_eq!(lone.layer(&[7, -3, 2], 0), Some(Layer::First));
    }

    /// A seeded cloud of cell indices: a dense blob with holes, a few stray cells, and
    /// duplicates, so that every layer occurs.
    fn cloud<const D: usize>(seed: u64, n: usize, spread: i64) -> Vec<[i64; D]> {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as i64
        };
        (0..n)
            .map(|_| {
                let far = next() % 50 == 0;
                std::array::from_fn(|_| {
                    let c = next() % spread - spread / 2;
                    if far {
                        c * 2
                    } else {
                        c
                    }
                })
            })
            .collect()
    }

    #[test]
    fn the_dense_array_gives_the_layers_of_the_hashed_cells() {
        for seed in 0..6 {
            let keys2 = cloud::<2>(seed, 4000, 40);
            let keys3 = cloud::<3>(seed, 6000, 10);
            for delta in [0, 2, 4, 8] {
                for count in [keys2.len(), keys2.len() / 2] {
                    assert!(Dense::covering(&keys2).is_some());
                    let cells = Cells::new(&keys2);
                    let want: Vec<Layer> = keys2[..count]
                        .iter()
                        .map(|k| cells.layer(k, delta).unwrap())
                        .collect();
                    assert_eq!(particle_layers(&keys2, count, delta), want);
                    assert_eq!(hashed_particle_layers(&keys2, count, delta), want);
                }
                assert!(Dense::covering(&keys3).is_some());
                let cells = Cells::new(&keys3);
                let want: Vec<Layer> = keys3
                    .iter()
                    .map(|k| cells.layer(k, delta).unwrap())
                    .collect();
                assert!(want.contains(&Layer::Second) || delta < 4);
                assert_eq!(particle_layers(&keys3, keys3.len(), delta), want);
            }
        }
    }

    #[test]
    fn scattered_cells_take_the_hash_map() {
        // Two cells 2^40 apart: no dense array, the same layers as the hash map.
        let keys = [[0i64, 0, 0], [0, 0, 0], [1 << 40, 5, -3]];
        assert!(Dense::covering(&keys).is_none());
        assert_eq!(particle_layers(&keys, 3, 8), vec![Layer::First; 3]);
        assert!(particle_layers::<2>(&[], 0, 4).is_empty());
    }
}
