//! The layers of LNM on the occupied cells of a voxel grid: no particle here, only cell
//! indices and counts, so the rules are tested on hand-made grids.

use rustc_hash::FxHashMap;

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
        let first: Vec<([i64; D], bool)> = cells
            .keys()
            .map(|key| {
                let open = offsets.iter().any(|o| !cells.contains_key(&add(key, o)));
                (*key, open)
            })
            .collect();
        for (key, open) in first {
            if let Some(cell) = cells.get_mut(&key) {
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
}
