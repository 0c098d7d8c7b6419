//! Uniform grid for fixed-radius neighbour queries.
//!
//! Particles are bucketed into cubic cells of side `cell` (usually `2r`, the widest query any
//! method makes) and stored cell by cell in one compact array (a counting sort: CSR layout),
//! together with a copy of their positions so that a query streams through contiguous memory.
//!
//! Two layouts, chosen at construction:
//! - **dense**: an offset table over the full bounding box, used while it has at most
//!   `max(4n, 4096)` cells, so memory stays `O(n)`, and fewer than `u32::MAX` cells (its
//!   cell indices are `u32`: never a silent wrap);
//! - **hashed**: only occupied cells, in a hash map from cell coordinates to their range, for
//!   sparse scenes whose bounding box is huge relative to the cell (a particle at `1e6` and
//!   one at `0` with `r = 0.01`).
//!
//! Queries are exact and closed: a particle at squared distance `d2 <= radius²` (computed in
//! `f64` from the coordinates) is reported, whatever the cell size. The range of cells visited
//! is widened by a relative `1e-9` of the radius (plus rounding of the query coordinate), so
//! that no rounding in the cell computation can drop a particle at exactly `radius`.

use crate::{CoreError, ParticleSet, Point};
use rayon::prelude::*;

mod neighbourhoods;
pub use neighbourhoods::Neighbourhood;
use rustc_hash::FxHashMap;

/// Largest `extent / cell` ratio accepted: cell coordinates stay exactly representable and
/// monotone in `f64` and `i64`.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 52) as f64;

/// Most cells of a dense table: its cell indices and offsets are `u32` (a particle set holds at
/// most `u32::MAX` particles, see [`CoreError::TooManyParticles`]), so a table with more cells
/// would wrap; such a scene takes the hashed layout instead.
const MAX_DENSE_CELLS: f64 = (u32::MAX - 1) as f64;

/// Entries [`NeighbourGrid::gather_within`] adds to its output beyond the row in hand when it
/// must grow it (cut back to the particles kept at the end).
const GATHER_SLACK: usize = 64;

/// [`NeighbourGrid::move_particles`] works in pieces of this many particles (a piece takes
/// some tens of microseconds, more than handing it to another worker costs).
const MOVE_PIECE: usize = 16384;

/// Whether `n` particles take the dense layout over a bounding box of `total` cells: at most
/// `max(4n, 4096)` cells (memory `O(n)`) and at most [`MAX_DENSE_CELLS`] (`u32` indices).
fn dense_fits(n: usize, total: f64) -> bool {
    let budget = n.saturating_mul(4).max(4096) as f64;
    total <= budget && total <= MAX_DENSE_CELLS
}

/// A uniform-grid neighbour index over a [`ParticleSet`]; see the module documentation.
#[derive(Debug, Clone)]
pub struct NeighbourGrid<const D: usize> {
    cell: f64,
    origin: Point<D>,
    /// Particle indices (input order) sorted by cell.
    order: Vec<u32>,
    /// Positions in the same order as `order`.
    sorted: Vec<Point<D>>,
    layout: Layout<D>,
    /// The positions the particles were sorted into cells by, in the order of `sorted`; empty
    /// until [`NeighbourGrid::move_particles`] moves them.
    built: Vec<Point<D>>,
    /// Added to every query radius when choosing cells: the drift of the particles from
    /// `built`, rounded up (0 until they move).
    pad: f64,
}

#[derive(Debug, Clone)]
enum Layout<const D: usize> {
    /// `starts[c]..starts[c + 1]` is the range of cell `c` (x fastest).
    Dense { dims: [i64; D], starts: Vec<u32> },
    /// Occupied cells only.
    Hashed {
        ranges: FxHashMap<[i64; D], (u32, u32)>,
    },
}

impl<const D: usize> NeighbourGrid<D> {
    /// [`NeighbourGrid::new`] sorts fewer particles than this on the calling thread (a
    /// fraction of a millisecond: less than waking the workers of a pool costs, twice), and
    /// more on the rayon pool the call runs on.
    pub const SORTED_IN_PARALLEL_FROM: usize = 2 * MOVE_PIECE;

    /// Builds the grid with cells of side `cell` (finite, positive). Sets of fewer than
    /// [`NeighbourGrid::SORTED_IN_PARALLEL_FROM`] particles are sorted on the calling thread,
    /// larger ones on the rayon pool the call runs on.
    ///
    /// Fails with [`CoreError::GridTooFine`] when the bounding box spans more than `2^52`
    /// cells along an axis (e.g. coordinates `1e9` apart with `cell = 1e-9`).
    pub fn new(set: &ParticleSet<D>, cell: f64) -> Result<Self, CoreError> {
        if !(cell.is_finite() && cell > 0.0) {
            return Err(CoreError::InvalidRadius(cell));
        }
        let Some((lo, hi)) = set.bounding_box() else {
            return Ok(NeighbourGrid {
                cell,
                origin: Point::<D>::zeros(),
                order: Vec::new(),
                sorted: Vec::new(),
                layout: Layout::Dense {
                    dims: [1; D],
                    starts: vec![0, 0],
                },
                built: Vec::new(),
                pad: 0.0,
            });
        };
        let mut dims = [1i64; D];
        for k in 0..D {
            let extent = hi[k] - lo[k];
            let cells = (extent / cell).floor() + 1.0;
            if cells.is_nan() || cells > MAX_CELLS_PER_AXIS {
                return Err(CoreError::GridTooFine { extent, cell });
            }
            dims[k] = cells as i64;
        }
        let n = set.len();
        let positions = set.positions();
        let total: f64 = dims.iter().map(|&d| d as f64).product();
        let grid = NeighbourGrid {
            cell,
            origin: lo,
            order: Vec::new(),
            sorted: Vec::new(),
            layout: Layout::Hashed {
                ranges: FxHashMap::default(),
            },
            built: Vec::new(),
            pad: 0.0,
        };
        Ok(if dense_fits(n, total) {
            grid.fill_dense(positions, dims)
        } else {
            grid.fill_hashed(positions)
        })
    }

    fn fill_dense(mut self, positions: &[Point<D>], dims: [i64; D]) -> Self {
        let ncells = dims.iter().product::<i64>() as usize;
        let index = |p: &Point<D>| {
            let c = self.cell_of(p);
            let mut idx = 0i64;
            for k in (0..D).rev() {
                idx = idx * dims[k] + c[k].clamp(0, dims[k] - 1);
            }
            // In range: `idx < ncells <= MAX_DENSE_CELLS` (`dense_fits`).
            idx as u32
        };
        let parts = rayon::current_num_threads();
        if positions.len() < Self::SORTED_IN_PARALLEL_FROM || parts == 1 {
            let linear: Vec<u32> = positions.iter().map(index).collect();
            let mut starts = vec![0u32; ncells + 1];
            for &c in &linear {
                starts[c as usize + 1] += 1;
            }
            for c in 0..ncells {
                starts[c + 1] += starts[c];
            }
            let mut next = starts.clone();
            let mut order = vec![0u32; positions.len()];
            for (i, &c) in linear.iter().enumerate() {
                let slot = &mut next[c as usize];
                order[*slot as usize] = i as u32;
                *slot += 1;
            }
            self.sorted = order.iter().map(|&i| positions[i as usize]).collect();
            self.order = order;
            self.layout = Layout::Dense { dims, starts };
            return self;
        }
        // The same counting sort, on every thread: a serial sort was most of a parallel
        // detection's serial time. Each of `parts` tasks counts the particles of its range of
        // cells, then (ranges cut again to hold about as many particles each) places the
        // particles of its cells, scanning all of them in input order: the order of the
        // serial sort (by cell, then by input index), with no atomics.
        let linear: Vec<u32> = positions.par_iter().map(index).collect();
        let per = ncells.div_ceil(parts);
        let counts: Vec<Vec<u32>> = (0..parts)
            .into_par_iter()
            .map(|k| {
                let first = (k * per).min(ncells);
                let mut counts = vec![0u32; (first + per).min(ncells) - first];
                for &c in &linear {
                    if let Some(n) = counts.get_mut((c as usize).wrapping_sub(first)) {
                        *n += 1;
                    }
                }
                counts
            })
            .collect();
        let mut starts = Vec::with_capacity(ncells + 1);
        starts.push(0u32);
        let mut total = 0u32;
        for n in counts.iter().flatten() {
            total += n;
            starts.push(total);
        }
        drop(counts);
        let n = positions.len();
        // Cells `cuts[k]..cuts[k + 1]` for task `k`: the first cell starting at or after
        // `k n / parts`.
        let cuts: Vec<usize> = (0..=parts)
            .map(|k| {
                if k == parts {
                    ncells
                } else {
                    starts[..ncells].partition_point(|&s| (s as usize) < k * n / parts)
                }
            })
            .collect();
        let mut order = vec![0u32; n];
        let mut pieces = Vec::with_capacity(parts);
        let mut rest = order.as_mut_slice();
        for k in 0..parts {
            let len = (starts[cuts[k + 1]] - starts[cuts[k]]) as usize;
            let (piece, tail) = rest.split_at_mut(len);
            pieces.push((cuts[k]..cuts[k + 1], piece));
            rest = tail;
        }
        pieces.into_par_iter().for_each(|(cells, piece)| {
            let base = starts[cells.start];
            let mut next: Vec<u32> = starts[cells.clone()].iter().map(|&s| s - base).collect();
            for (i, &c) in linear.iter().enumerate() {
                if let Some(slot) = next.get_mut((c as usize).wrapping_sub(cells.start)) {
                    piece[*slot as usize] = i as u32;
                    *slot += 1;
                }
            }
        });
        self.sorted = order.par_iter().map(|&i| positions[i as usize]).collect();
        self.order = order;
        self.layout = Layout::Dense { dims, starts };
        self
    }

    fn fill_hashed(mut self, positions: &[Point<D>]) -> Self {
        let key = |(i, p): (usize, &Point<D>)| (self.cell_of(p), i as u32);
        let mut keyed: Vec<([i64; D], u32)>;
        if positions.len() < Self::SORTED_IN_PARALLEL_FROM {
            keyed = positions.iter().enumerate().map(key).collect();
            keyed.sort_unstable();
        } else {
            keyed = positions.par_iter().enumerate().map(key).collect();
            keyed.par_sort_unstable();
        }
        let mut ranges = FxHashMap::default();
        let mut start = 0usize;
        while start < keyed.len() {
            let key = keyed[start].0;
            let mut end = start + 1;
            while end < keyed.len() && keyed[end].0 == key {
                end += 1;
            }
            ranges.insert(key, (start as u32, end as u32));
            start = end;
        }
        self.order = keyed.iter().map(|&(_, i)| i).collect();
        self.sorted = self.order.iter().map(|&i| positions[i as usize]).collect();
        self.layout = Layout::Hashed { ranges };
        self
    }

    /// The particle indices (input order) sorted by cell: a traversal in this order visits
    /// neighbouring particles one after another (their queries then share cached cells).
    pub fn cell_order(&self) -> &[u32] {
        &self.order
    }

    /// The positions in [`NeighbourGrid::cell_order`]: entry `s` is the position of particle
    /// `cell_order()[s]`.
    pub fn cell_sorted_positions(&self) -> &[Point<D>] {
        &self.sorted
    }

    /// Moves the particles to the positions of `set` (the same particles in the same order)
    /// without sorting them into cells again, and returns the **drift**: the largest distance
    /// of a particle from the position the grid sorted it by. Queries stay exact: they scan
    /// the cells within `radius + drift` (the drift grown by `1e-9` relative for its own
    /// rounding) and test the particles' new positions, which
    /// [`NeighbourGrid::cell_sorted_positions`] now holds. Cheaper than a new grid (no
    /// sorting) while the drift is small against the query radii: the skin of a Verlet list;
    /// build a new grid once the drift costs more than it saves.
    ///
    /// Fails with [`CoreError::GridLengthMismatch`] when `set` has another number of particles.
    ///
    /// ```
    /// use boundary_core::{NeighbourGrid, ParticleSet};
    ///
    /// let set = ParticleSet::from_rows(&[[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]]).unwrap();
    /// let mut grid = NeighbourGrid::new(&set, 1.0).unwrap();
    /// let moved = ParticleSet::from_rows(&[[0.0, 0.0], [1.0, 0.0], [1.5, 0.25]]).unwrap();
    /// let drift = grid.move_particles(&moved).unwrap();
    /// assert!((drift - (1.5f64.powi(2) + 0.0625).sqrt()).abs() < 1e-12);
    /// let mut near = vec![];
    /// grid.within_sorted(&moved.positions()[0], 1.6, &mut near);
    /// assert_eq!(near.iter().map(|x| x.0).collect::<Vec<_>>(), [0, 1, 2]);
    /// ```
    pub fn move_particles(&mut self, set: &ParticleSet<D>) -> Result<f64, CoreError> {
        let positions = set.positions();
        if positions.len() != self.order.len() {
            return Err(CoreError::GridLengthMismatch {
                indexed: self.order.len(),
                given: positions.len(),
            });
        }
        if self.built.is_empty() {
            self.built = self.sorted.clone();
        }
        // One pass: each new position stored and its squared distance from where it was
        // sorted taken, in pieces of `MOVE_PIECE` (a set of a few thousand particles, moved at
        // every step of a time loop, stays on the calling thread).
        let drift = self
            .sorted
            .par_chunks_mut(MOVE_PIECE)
            .zip(self.order.par_chunks(MOVE_PIECE))
            .zip(self.built.par_chunks(MOVE_PIECE))
            .map(|((sorted, order), built)| {
                let mut most = 0.0f64;
                for ((s, &i), b) in sorted.iter_mut().zip(order).zip(built) {
                    *s = positions[i as usize];
                    most = most.max(dist2(s, b));
                }
                most
            })
            .reduce(|| 0.0, f64::max)
            .sqrt();
        // The computed distances carry a relative rounding of a few `u`.
        self.pad = drift * (1.0 + 1e-9);
        Ok(drift)
    }

    /// The cell side.
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Whether the sparse (hashed) layout was chosen.
    pub fn is_hashed(&self) -> bool {
        matches!(self.layout, Layout::Hashed { .. })
    }

    fn axis_cell(&self, x: f64, k: usize) -> i64 {
        // Monotone in x: subtraction, division and floor are monotone in IEEE arithmetic,
        // and the saturating cast keeps far query points ordered.
        floor_to_i64((x - self.origin[k]) / self.cell)
    }

    fn cell_of(&self, p: &Point<D>) -> [i64; D] {
        std::array::from_fn(|k| self.axis_cell(p[k], k))
    }

    /// Calls `f(j, d2)` for every particle `j` (input index) with squared distance
    /// `d2 <= radius²` from `q`. `q` need not be a particle; if it is particle `i`, `i` itself
    /// is reported with `d2 = 0`, as are its exact duplicates. The order of the calls is
    /// unspecified but deterministic.
    pub fn for_each_within<F: FnMut(usize, f64)>(&self, q: &Point<D>, radius: f64, mut f: F) {
        let r2 = radius * radius;
        self.for_each_candidate_range(q, radius, |range| {
            for (p, &j) in self.sorted[range.clone()].iter().zip(&self.order[range]) {
                let d2 = dist2(p, q);
                if d2 <= r2 {
                    f(j as usize, d2);
                }
            }
        });
    }

    /// Appends `make(j, slot, d2)` to `out` for every particle `j` within `radius` of `q`:
    /// the particles [`NeighbourGrid::for_each_within`] reports, in the same order, with the
    /// same `d2`; `slot` is the particle's place in [`NeighbourGrid::cell_sorted_positions`].
    /// Faster where many candidates fail the distance test: no branch per candidate.
    pub fn gather_within<T: Copy + Default>(
        &self,
        q: &Point<D>,
        radius: f64,
        out: &mut Vec<T>,
        make: impl Fn(usize, usize, f64) -> T,
    ) {
        let r2 = radius * radius;
        // Every candidate is written; only those within the radius are kept (`len` advances
        // past them), the others are overwritten by the next. `out` is grown as needed and cut
        // to the kept ones at the end.
        let mut len = out.len();
        self.for_each_candidate_range(q, radius, |range| {
            if out.len() < len + range.len() {
                // With room for a few more rows: growing row by row took a mispredicted
                // branch and a small fill per row (callgrind, `exact` on the 50k ball).
                out.resize(len + range.len() + GATHER_SLACK, T::default());
            }
            let slots = &mut out[len..len + range.len()];
            let mut k = 0;
            let first = range.start;
            for (i, (p, &j)) in self.sorted[range.clone()]
                .iter()
                .zip(&self.order[range])
                .enumerate()
            {
                let d2 = dist2(p, q);
                slots[k] = make(j as usize, first + i, d2);
                k += (d2 <= r2) as usize;
            }
            len += k;
        });
        out.truncate(len);
    }

    /// Calls `visit` with ranges of `sorted` that together hold every particle within
    /// `radius` of `q` (and others): the cells of the bounding box of the ball, row by row
    /// along x, each row trimmed to the cells the ball reaches within it (rows of up to 5
    /// cells: only their end cells are tested), rows it misses skipped. In a fixed order.
    ///
    /// The trimming is conservative: a particle of cell `c` along an axis has a coordinate
    /// within `slack` of the cell's slab `[o + c·s, o + (c + 1)·s]` (the cell index is
    /// `floor((x − o)/s)`, rounded: a few `ε` of `|x| + |o| + |c·s|`), so the distance from `q`
    /// to the row's slabs, each reduced by its `slack`, is a lower bound on the distance of any
    /// particle of the row; the half-width left for x is taken from `radius·(1 + 1e-9)`, whose
    /// square's surplus `2e-9·radius²` covers the rounding of the subtractions and the root.
    fn for_each_candidate_range(
        &self,
        q: &Point<D>,
        radius: f64,
        mut visit: impl FnMut(std::ops::Range<usize>),
    ) {
        if self.order.is_empty() || radius.is_nan() || radius < 0.0 {
            return;
        }
        // Moved particles lie within `pad` of the positions they were sorted by.
        let radius = radius + self.pad;
        let mut lo = [0i64; D];
        let mut hi = [0i64; D];
        for k in 0..D {
            let pad = radius * (1.0 + 1e-9) + q[k].abs() * 4.0 * f64::EPSILON;
            lo[k] = self.axis_cell(q[k] - pad, k);
            hi[k] = self.axis_cell(q[k] + pad, k);
        }
        match &self.layout {
            Layout::Dense { dims, starts } => {
                for k in 0..D {
                    lo[k] = lo[k].max(0);
                    hi[k] = hi[k].min(dims[k] - 1);
                    if lo[k] > hi[k] {
                        return;
                    }
                }
                let wide = radius * (1.0 + 1e-9);
                let wide2 = wide * wide;
                // Squared distance from `q` to the slab of cell `c` along axis `k`, less its
                // slack, for the cells of the box (axes whose box is wider than GAPS cells
                // are not trimmed: gap 0; along x such a box is trimmed per row as below).
                const GAPS: usize = 16;
                // Rows of up to WHOLE_ROW cells are trimmed along x by their two end cells
                // only, without a branch: searching for the first and last cell within reach
                // mispredicted about twice per row and cost more than the candidates it saved;
                // under callgrind (10^5 ball, `svm`'s features and `exact`, cells of `r`,
                // radius `2r`) the end cells take the fewest instructions and mispredicted
                // branches of the three (search, whole rows, end cells).
                const WHOLE_ROW: i64 = 5;
                let whole_x = hi[0] - lo[0] < WHOLE_ROW;
                let mut gaps = [[0.0f64; GAPS]; D];
                for k in 0..D {
                    if hi[k] - lo[k] < GAPS as i64 {
                        let slack = 16.0
                            * f64::EPSILON
                            * (q[k].abs() + self.origin[k].abs() + radius + self.cell);
                        for c in lo[k]..=hi[k] {
                            let below = self.origin[k] + c as f64 * self.cell - q[k];
                            let above = q[k] - (self.origin[k] + (c + 1) as f64 * self.cell);
                            let g = (below.max(above) - slack).max(0.0);
                            gaps[k][(c - lo[k]) as usize] = g * g;
                        }
                    }
                }
                let narrow_x = hi[0] - lo[0] < GAPS as i64;
                let gx = &gaps[0][..(if narrow_x { hi[0] - lo[0] + 1 } else { 0 }) as usize];
                // Cells along x are contiguous: one slice per (y, z) row.
                let mut c = lo;
                loop {
                    let mut yz2 = 0.0;
                    for k in 1..D {
                        let i = (c[k] - lo[k]) as usize;
                        if i < GAPS {
                            yz2 += gaps[k][i];
                        }
                    }
                    if yz2 <= wide2 {
                        // The cells of the row within reach: where the x gap fits in what the
                        // row's y and z gaps leave (the gaps grow away from q's cell, so these
                        // cells are contiguous); from the half-width left for a wide box.
                        let (x0, x1) = if whole_x {
                            // Only the end cells are tested, without a branch.
                            let out = |g: f64| (g + yz2 > wide2) as i64;
                            (lo[0] + out(gx[0]), hi[0] - out(gx[gx.len() - 1]))
                        } else if narrow_x {
                            let fits = |g: &f64| g + yz2 <= wide2;
                            match (gx.iter().position(fits), gx.iter().rposition(fits)) {
                                (Some(a), Some(b)) => (lo[0] + a as i64, lo[0] + b as i64),
                                _ => (1, 0),
                            }
                        } else {
                            let half = (wide2 - yz2).sqrt();
                            let pad = half * (1.0 + 1e-9) + q[0].abs() * 4.0 * f64::EPSILON;
                            (
                                self.axis_cell(q[0] - pad, 0).max(lo[0]),
                                self.axis_cell(q[0] + pad, 0).min(hi[0]),
                            )
                        };
                        if x0 <= x1 {
                            let mut row = 0i64;
                            for k in (1..D).rev() {
                                row = row * dims[k] + c[k];
                            }
                            let first = (row * dims[0] + x0) as usize;
                            let last = (row * dims[0] + x1) as usize;
                            visit(starts[first] as usize..starts[last + 1] as usize);
                        }
                    }
                    if !advance(&mut c, &lo, &hi, 1) {
                        break;
                    }
                }
            }
            Layout::Hashed { ranges } => {
                let visited: f64 = (0..D).map(|k| (hi[k] - lo[k] + 1) as f64).product();
                if visited > 2.0 * ranges.len() as f64 {
                    // A query box wider than the occupied cells: scan the occupied cells.
                    for (key, &(a, b)) in ranges {
                        if (0..D).all(|k| lo[k] <= key[k] && key[k] <= hi[k]) {
                            visit(a as usize..b as usize);
                        }
                    }
                    return;
                }
                let mut c = lo;
                loop {
                    if let Some(&(a, b)) = ranges.get(&c) {
                        visit(a as usize..b as usize);
                    }
                    if !advance(&mut c, &lo, &hi, 0) {
                        break;
                    }
                }
            }
        }
    }

    /// For a sweep over the cells: calls `visit(cell, candidates)` for every occupied cell of a
    /// dense grid, in the cell order, with `cell` the range of its particles in
    /// [`NeighbourGrid::cell_order`] and `candidates` ascending, disjoint ranges of that order
    /// that hold every particle within `radius` of any particle of the cell (and others): the
    /// rows along x of the cells that the query boxes of [`NeighbourGrid::for_each_within`]
    /// cover for the cell's particles, at their current positions. Visits nothing and returns
    /// false for the hashed layout.
    pub fn for_each_cell_block(
        &self,
        radius: f64,
        visit: impl FnMut(std::ops::Range<usize>, &[std::ops::Range<usize>]),
    ) -> bool {
        self.for_each_cell_block_in(0..self.sorted.len(), radius, visit)
    }

    /// [`NeighbourGrid::for_each_cell_block`] over the slots `slots` of the cell order only:
    /// the cells that hold any of them, in the cell order, each with `cell` cut to `slots`
    /// (the candidates are those of the whole cell). Sweeps over consecutive ranges of slots
    /// visit each particle once, so they can run in parallel.
    pub fn for_each_cell_block_in(
        &self,
        slots: std::ops::Range<usize>,
        radius: f64,
        mut visit: impl FnMut(std::ops::Range<usize>, &[std::ops::Range<usize>]),
    ) -> bool {
        let Layout::Dense { dims, starts } = &self.layout else {
            return false;
        };
        if radius.is_nan() || radius < 0.0 || slots.start >= slots.end.min(self.sorted.len()) {
            return true;
        }
        let radius = radius + self.pad;
        let mut rows: Vec<std::ops::Range<usize>> = Vec::new();
        // The cell of the first slot: the last cell that starts at or before it.
        let first = starts.partition_point(|&s| s as usize <= slots.start) - 1;
        for cell in first..starts.len() - 1 {
            let (a, b) = (
                (starts[cell] as usize).max(slots.start),
                (starts[cell + 1] as usize).min(slots.end),
            );
            if starts[cell] as usize >= slots.end {
                break;
            }
            if a >= b {
                continue;
            }
            let whole = starts[cell] as usize..starts[cell + 1] as usize;
            // The union of the query boxes of the cell's particles: the box of their bounding
            // box, each side widened as a query at that coordinate is (monotone cells).
            let mut lo = [0i64; D];
            let mut hi = [0i64; D];
            for k in 0..D {
                let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
                for p in &self.sorted[whole.clone()] {
                    min = min.min(p[k]);
                    max = max.max(p[k]);
                }
                // At least the pad of a query at any coordinate in `[min, max]`.
                let pad = radius * (1.0 + 1e-9) + min.abs().max(max.abs()) * 4.0 * f64::EPSILON;
                lo[k] = self.axis_cell(min - pad, k).max(0);
                hi[k] = self.axis_cell(max + pad, k).min(dims[k] - 1);
            }
            rows.clear();
            if (0..D).all(|k| lo[k] <= hi[k]) {
                let mut c = lo;
                loop {
                    let mut row = 0i64;
                    for k in (1..D).rev() {
                        row = row * dims[k] + c[k];
                    }
                    let first = (row * dims[0] + lo[0]) as usize;
                    let last = (row * dims[0] + hi[0]) as usize;
                    let range = starts[first] as usize..starts[last + 1] as usize;
                    if !range.is_empty() {
                        rows.push(range);
                    }
                    if !advance(&mut c, &lo, &hi, 1) {
                        break;
                    }
                }
            }
            visit(a..b, &rows);
        }
        true
    }

    /// Collects `(j, d2)` for the particles within `radius` of `q` into `out` (cleared first),
    /// sorted by increasing distance, ties by index.
    pub fn within_sorted(&self, q: &Point<D>, radius: f64, out: &mut Vec<(usize, f64)>) {
        out.clear();
        self.for_each_within(q, radius, |j, d2| out.push((j, d2)));
        out.sort_unstable_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    }
}

/// `v.floor() as i64` (saturating; NaN gives 0), without a call to `floor` (a library call on
/// baseline x86-64, a third of the cost of a short neighbour query): the truncation, one less
/// when it lies above `v`. Exact: below `2^52` in magnitude the truncation is exact in `f64`;
/// beyond, `v` is an integer (or the cast saturates, and the comparison only lowers `i64::MIN`,
/// saturating).
fn floor_to_i64(v: f64) -> i64 {
    let t = v as i64;
    t.saturating_sub((t as f64 > v) as i64)
}

/// `|p − q|²`, summed over the axes in order from 0 (the roundings of nalgebra's
/// `norm_squared`, which the reported `d2` always had).
fn dist2<const D: usize>(p: &Point<D>, q: &Point<D>) -> f64 {
    let mut d2 = 0.0;
    for k in 0..D {
        let d = p[k] - q[k];
        d2 += d * d;
    }
    d2
}

/// Odometer over the box `lo..=hi`, axes `from..D` (lower axes fixed). Returns false when done.
fn advance<const D: usize>(c: &mut [i64; D], lo: &[i64; D], hi: &[i64; D], from: usize) -> bool {
    for k in from..D {
        if c[k] < hi[k] {
            c[k] += 1;
            return true;
        }
        c[k] = lo[k];
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Dim, SupportedDim};
    use rand::{Rng, SeedableRng};

    fn brute<const D: usize>(set: &ParticleSet<D>, q: &Point<D>, radius: f64) -> Vec<usize> {
        let r2 = radius * radius;
        let mut v: Vec<usize> = (0..set.len())
            .filter(|&j| (set.positions()[j] - q).norm_squared() <= r2)
            .collect();
        v.sort_unstable();
        v
    }

    fn grid_query<const D: usize>(g: &NeighbourGrid<D>, q: &Point<D>, radius: f64) -> Vec<usize> {
        let mut v = Vec::new();
        g.for_each_within(q, radius, |j, _| v.push(j));
        v.sort_unstable();
        v
    }

    /// `n` particles uniform in the cube `[offset, offset + scale)^D` (also used by the
    /// tests of `neighbourhoods`).
    pub(super) fn random_set<const D: usize>(
        seed: u64,
        n: usize,
        scale: f64,
        offset: f64,
    ) -> ParticleSet<D>
    where
        Dim<D>: SupportedDim,
    {
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        ParticleSet::new(
            (0..n)
                .map(|_| Point::<D>::from_fn(|_, _| offset + scale * rng.gen::<f64>()))
                .collect(),
        )
        .unwrap()
    }

    fn check_against_brute<const D: usize>(set: &ParticleSet<D>, cell: f64, radii: &[f64]) {
        let g = NeighbourGrid::new(set, cell).unwrap();
        for q in set.positions() {
            for &radius in radii {
                assert_eq!(grid_query(&g, q, radius), brute(set, q, radius));
            }
        }
    }

    #[test]
    fn matches_brute_force_2d_and_3d() {
        let s2 = random_set::<2>(1, 400, 1.0, 0.0);
        check_against_brute(&s2, 0.1, &[0.0, 0.05, 0.1, 0.23]);
        let s3 = random_set::<3>(2, 400, 1.0, 0.0);
        check_against_brute(&s3, 0.2, &[0.1, 0.2, 0.5]);
    }

    #[test]
    fn far_offset_coordinates_match_brute_force() {
        let s = random_set::<3>(3, 300, 0.2, 1e6);
        check_against_brute(&s, 0.04, &[0.02, 0.04]);
    }

    #[test]
    fn radii_from_1e_minus_9_to_1e9_match_brute_force() {
        for (k, scale) in [1e-9, 1e-3, 1.0, 1e3, 1e9].into_iter().enumerate() {
            let s = random_set::<3>(10 + k as u64, 200, 10.0 * scale, -5.0 * scale);
            check_against_brute(&s, 2.0 * scale, &[scale, 2.0 * scale]);
            let s = random_set::<2>(20 + k as u64, 200, 10.0 * scale, 3.0 * scale);
            check_against_brute(&s, 2.0 * scale, &[2.0 * scale]);
        }
    }

    #[test]
    fn sparse_scene_uses_hashing_and_stays_correct() {
        let mut rows = vec![[0.0, 0.0, 0.0], [1e6, 1e6, 1e6], [0.005, 0.0, 0.0]];
        rows.push([1e6 + 0.01, 1e6, 1e6]);
        let s = ParticleSet::<3>::from_rows(&rows).unwrap();
        let g = NeighbourGrid::new(&s, 0.02).unwrap();
        assert!(g.is_hashed());
        check_against_brute(&s, 0.02, &[0.01, 0.02, 3e6]);
    }

    #[test]
    fn exactly_at_radius_is_included() {
        // Distances that are exact in binary: 2r with r = 0.5 and r = 0.375.
        let s = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0], [0.0, 0.75], [3.0, 4.0]])
            .unwrap();
        let g = NeighbourGrid::new(&s, 1.0).unwrap();
        assert_eq!(grid_query(&g, &s.positions()[0], 1.0), vec![0, 1, 2]);
        assert_eq!(grid_query(&g, &s.positions()[0], 0.75), vec![0, 2]);
        assert_eq!(grid_query(&g, &s.positions()[0], 5.0), vec![0, 1, 2, 3]);
    }

    #[test]
    fn duplicates_and_off_set_query_points_find_exactly_the_particles_in_range() {
        let s = ParticleSet::<2>::from_rows(&[[0.5, 0.5], [0.5, 0.5], [0.9, 0.5]]).unwrap();
        let g = NeighbourGrid::new(&s, 0.5).unwrap();
        assert_eq!(grid_query(&g, &s.positions()[0], 0.1), vec![0, 1]);
        assert_eq!(
            grid_query(&g, &Point::<2>::new(-10.0, 0.5), 1.0),
            Vec::<usize>::new()
        );
        assert_eq!(grid_query(&g, &Point::<2>::new(1.3, 0.5), 0.4), vec![2]);
    }

    /// A grid whose particles moved (small drifts and large, dense and hashed layouts, query
    /// points off the particles) finds exactly the particles a brute-force search finds at
    /// their new positions, with the same squared distances as a new grid; its sorted
    /// positions are the new ones.
    #[test]
    fn moved_particles_are_found_where_they_are_now() {
        fn check<const D: usize>(seed: u64, cell: f64, radii: &[f64], offset: f64)
        where
            Dim<D>: SupportedDim,
        {
            let set = random_set::<D>(seed, 300, 1.0, offset);
            let mut grid = NeighbourGrid::new(&set, cell).unwrap();
            let mut rng = rand::rngs::StdRng::seed_from_u64(seed + 100);
            let mut positions = set.positions().to_vec();
            for scale in [0.0, 1e-9, 0.01, 0.05, 0.3, 2.0] {
                for p in positions.iter_mut() {
                    *p += Point::<D>::from_fn(|_, _| scale * (rng.gen::<f64>() - 0.5));
                }
                let moved = ParticleSet::new(positions.clone()).unwrap();
                let drift = grid.move_particles(&moved).unwrap();
                let most = positions
                    .iter()
                    .zip(set.positions())
                    .map(|(a, b)| (a - b).norm())
                    .fold(0.0, f64::max);
                assert!(
                    (drift - most).abs() <= 1e-12 * (1.0 + most),
                    "{drift} {most}"
                );
                let fresh = NeighbourGrid::new(&moved, cell).unwrap();
                for (k, q) in moved.positions().iter().enumerate() {
                    let q = if k % 2 == 0 { *q } else { q.map(|x| x + 0.013) };
                    for &radius in radii {
                        assert_eq!(grid_query(&grid, &q, radius), brute(&moved, &q, radius));
                        let (mut a, mut b) = (vec![], vec![]);
                        grid.within_sorted(&q, radius, &mut a);
                        fresh.within_sorted(&q, radius, &mut b);
                        assert_eq!(a, b, "scale {scale}, radius {radius}");
                    }
                }
                for (s, &i) in grid.cell_order().iter().enumerate() {
                    assert_eq!(
                        grid.cell_sorted_positions()[s],
                        moved.positions()[i as usize]
                    );
                }
            }
            let fewer = ParticleSet::new(positions[1..].to_vec()).unwrap();
            assert!(matches!(
                grid.move_particles(&fewer),
                Err(CoreError::GridLengthMismatch {
                    indexed: 300,
                    given: 299
                })
            ));
        }
        check::<2>(7, 0.1, &[0.0, 0.05, 0.1, 0.23], 0.0);
        check::<3>(8, 0.2, &[0.1, 0.2, 0.5], 0.0);
        // Far from the origin with a fine cell: the hashed layout.
        check::<3>(9, 1e-3, &[0.01, 0.1], 1e7);
    }

    /// A set larger than one piece of `move_particles`: the drift is the largest over every
    /// piece (the farthest particle moved in each piece in turn), and every sorted position is
    /// the new one.
    #[test]
    fn moving_many_particles_takes_the_largest_drift_of_every_piece() {
        let n = 2 * MOVE_PIECE + 1000;
        let set = random_set::<2>(21, n, 10.0, 0.0);
        let mut grid = NeighbourGrid::new(&set, 0.5).unwrap();
        for (round, piece) in [0, MOVE_PIECE + 7, n - 1].into_iter().enumerate() {
            // The particle at sorted slot `piece` moves farthest.
            let far = grid.cell_order()[piece] as usize;
            let mut positions = set.positions().to_vec();
            for (k, p) in positions.iter_mut().enumerate() {
                let step = if k == far {
                    0.25 + 0.01 * round as f64
                } else {
                    1e-3
                };
                *p += Point::<2>::new(step, 0.0);
            }
            let moved = ParticleSet::new(positions).unwrap();
            let drift = grid.move_particles(&moved).unwrap();
            let most = 0.25 + 0.01 * round as f64;
            assert!((drift - most).abs() <= 1e-12, "{drift} {most}");
            for (s, &i) in grid.cell_order().iter().enumerate() {
                assert_eq!(
                    grid.cell_sorted_positions()[s],
                    moved.positions()[i as usize]
                );
            }
        }
    }

    #[test]
    fn sorted_query_orders_by_distance() {
        let s =
            ParticleSet::<2>::from_rows(&[[0.0, 0.0], [0.3, 0.0], [0.1, 0.0], [0.2, 0.0]]).unwrap();
        let g = NeighbourGrid::new(&s, 0.5).unwrap();
        let mut out = Vec::new();
        g.within_sorted(&s.positions()[0], 0.5, &mut out);
        assert_eq!(
            out.iter().map(|p| p.0).collect::<Vec<_>>(),
            vec![0, 2, 3, 1]
        );
    }

    #[test]
    fn an_empty_set_finds_nothing_and_a_bad_cell_is_an_error() {
        let s = ParticleSet::<3>::new(Vec::new()).unwrap();
        let g = NeighbourGrid::new(&s, 1.0).unwrap();
        assert!(grid_query(&g, &Point::<3>::zeros(), 1.0).is_empty());
        assert!(NeighbourGrid::new(&s, 0.0).is_err());
        assert!(NeighbourGrid::new(&s, f64::NAN).is_err());
    }

    #[test]
    fn too_fine_a_grid_is_an_error_not_a_panic() {
        let s = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1e9, 0.0]]).unwrap();
        assert!(matches!(
            NeighbourGrid::new(&s, 1e-9),
            Err(CoreError::GridTooFine { .. })
        ));
    }

    #[test]
    fn dense_layout_never_exceeds_u32_cell_indices() {
        // Without allocating: the choice alone, at and around the limit. Below 2^30 particles
        // the 4n budget binds; above it the u32 index space does.
        assert!(dense_fits(0, 4096.0));
        assert!(!dense_fits(0, 4097.0));
        assert!(dense_fits(1000, 4000.0));
        assert!(!dense_fits(1000, 4097.0));
        let n = u32::MAX as usize; // the largest set a ParticleSet holds
        assert!(dense_fits(n, MAX_DENSE_CELLS));
        assert!(!dense_fits(n, MAX_DENSE_CELLS + 1.0));
        assert!(!dense_fits(n, u32::MAX as f64 + 1.0));
        assert!(!dense_fits(usize::MAX, 1e19));
        assert!(!dense_fits(n, f64::INFINITY));
    }

    #[test]
    fn two_far_particles_with_a_tiny_cell_take_the_hashed_layout_and_are_found() {
        // 1e12 cells along x: far beyond u32 and the dense budget, so the grid is hashed,
        // and both particles are still found at their exact positions.
        let s = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.5]]).unwrap();
        let g = NeighbourGrid::new(&s, 1e-12).unwrap();
        assert!(g.is_hashed());
        assert_eq!(grid_query(&g, &Point::<2>::new(1.0, 0.5), 0.0), vec![1]);
        assert_eq!(grid_query(&g, &Point::<2>::new(0.0, 0.0), 1e-13), vec![0]);
        assert_eq!(grid_query(&g, &Point::<2>::new(0.5, 0.25), 0.6), vec![0, 1]);
    }

    /// The cell blocks of a dense grid: every cell once, in the cell order, covering every
    /// slot; candidate ranges ascending and disjoint, holding every particle within the
    /// radius of each of the cell's particles (checked by brute force, at the radius exactly,
    /// in 2D and 3D, also after the particles move). The hashed layout visits nothing.
    #[test]
    fn cell_blocks_cover_the_neighbours_of_their_particles() {
        fn check<const D: usize>(g: &NeighbourGrid<D>, set: &ParticleSet<D>, radius: f64) {
            let mut next = 0;
            let dense = g.for_each_cell_block(radius, |cell, rows| {
                assert_eq!(cell.start, next);
                next = cell.end;
                for pair in rows.windows(2) {
                    assert!(pair[0].end <= pair[1].start, "{rows:?}");
                }
                let held = |t: usize| rows.iter().any(|r| r.contains(&t));
                for s in cell {
                    let i = g.cell_order()[s] as usize;
                    for j in brute(set, &set.positions()[i], radius) {
                        let t = g
                            .cell_order()
                            .iter()
                            .position(|&k| k as usize == j)
                            .unwrap();
                        assert!(held(t), "particle {j} near {i} missed");
                    }
                }
            });
            assert!(dense, "a dense grid");
            assert_eq!(next, set.len());
        }
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        for radius in [0.3, 1.0, 2.5] {
            let rows: Vec<[f64; 3]> = (0..300)
                .map(|_| std::array::from_fn(|_| rng.gen_range(-2.0..2.0)))
                .collect();
            let set = ParticleSet::<3>::from_rows(&rows).unwrap();
            let mut g = NeighbourGrid::new(&set, radius).unwrap();
            check(&g, &set, radius);
            check(&g, &set, 0.5 * radius);
            // Lattice points exactly `radius` apart: the closed test at the cell size.
            let lattice: Vec<[f64; 2]> = (0..100)
                .map(|k| [(k % 10) as f64 * radius, (k / 10) as f64 * radius])
                .collect();
            let flat = ParticleSet::<2>::from_rows(&lattice).unwrap();
            check(&NeighbourGrid::new(&flat, radius).unwrap(), &flat, radius);
            let moved: Vec<[f64; 3]> = rows
                .iter()
                .map(|p| p.map(|x| x + rng.gen_range(-0.2..0.2)))
                .collect();
            let moved = ParticleSet::<3>::from_rows(&moved).unwrap();
            g.move_particles(&moved).unwrap();
            check(&g, &moved, radius);
        }
        let far = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.5]]).unwrap();
        let g = NeighbourGrid::new(&far, 1e-12).unwrap();
        assert!(!g.for_each_cell_block(1.0, |_, _| panic!("hashed: no block")));
        assert!(!g.for_each_cell_block_in(0..2, 1.0, |_, _| panic!("hashed: no block")));
    }

    /// The dense grid sorted on several threads is the one sorted on one (cell order, sorted
    /// positions, cell starts): random sets above the parallel threshold in 2D and 3D, one
    /// with most particles in a few cells and many empty ones, on 2, 3 and 7 threads.
    #[test]
    fn a_grid_sorted_on_several_threads_is_the_one_sorted_on_one() {
        fn parts<const D: usize>(g: &NeighbourGrid<D>) -> (Vec<u32>, Vec<Point<D>>, Vec<u32>) {
            let Layout::Dense { starts, .. } = &g.layout else {
                panic!("a dense grid");
            };
            (g.order.clone(), g.sorted.clone(), starts.clone())
        }
        fn check<const D: usize>(set: &ParticleSet<D>, cell: f64) {
            assert!(set.len() >= NeighbourGrid::<D>::SORTED_IN_PARALLEL_FROM);
            let on = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                parts(&pool.install(|| NeighbourGrid::new(set, cell)).unwrap())
            };
            let one = on(1);
            for threads in [2, 3, 7] {
                assert!(one == on(threads), "{threads} threads, cell {cell}");
            }
        }
        let n = NeighbourGrid::<3>::SORTED_IN_PARALLEL_FROM + 777;
        check(&random_set::<3>(3, n, 10.0, -4.0), 0.7);
        check(&random_set::<2>(4, n, 10.0, 1.0), 0.05);
        // Most particles in a corner cell, the others spread thinly over a large box.
        let mut rows: Vec<[f64; 3]> = vec![[0.1, 0.2, 0.3]; n / 2];
        let mut rng = rand::rngs::StdRng::seed_from_u64(8);
        rows.extend((0..n / 2).map(|_| std::array::from_fn(|_| rng.gen_range(0.0..30.0))));
        let last = rows.len() - 1;
        rows.swap(0, last);
        check(&ParticleSet::<3>::from_rows(&rows).unwrap(), 0.9);
    }

    /// Consecutive slot ranges, cut anywhere (inside cells, at their ends, empty, past the
    /// end), visit exactly the blocks of the whole sweep, each cell cut to the range and with
    /// the candidates of the whole cell.
    #[test]
    fn cell_blocks_of_slot_ranges_are_the_whole_sweep_cut() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        let rows: Vec<[f64; 3]> = (0..400)
            .map(|_| std::array::from_fn(|_| rng.gen_range(-3.0..3.0)))
            .collect();
        let set = ParticleSet::<3>::from_rows(&rows).unwrap();
        let g = NeighbourGrid::new(&set, 1.0).unwrap();
        type Block = (std::ops::Range<usize>, Vec<std::ops::Range<usize>>);
        let mut whole: Vec<Block> = Vec::new();
        g.for_each_cell_block(1.0, |cell, rows| whole.push((cell, rows.to_vec())));
        for cuts in [
            vec![0, 400],
            vec![0, 1, 2, 399, 400],
            vec![0, 17, 17, 150, 151, 260, 400, 500],
            (0..=40).map(|k| k * 10).collect(),
        ] {
            let mut got: Vec<Block> = Vec::new();
            for pair in cuts.windows(2) {
                assert!(
                    g.for_each_cell_block_in(pair[0]..pair[1], 1.0, |cell, rows| {
                        assert!(cell.start >= pair[0] && cell.end <= pair[1] && !cell.is_empty());
                        got.push((cell, rows.to_vec()));
                    })
                );
            }
            // Slot by slot: each visited once, in order, within one whole cell, with the
            // candidates of that cell.
            let of_slot = |blocks: &[Block]| -> Vec<(usize, Vec<std::ops::Range<usize>>)> {
                blocks
                    .iter()
                    .flat_map(|(cell, rows)| cell.clone().map(move |s| (s, rows.clone())))
                    .collect()
            };
            assert_eq!(of_slot(&got), of_slot(&whole), "cuts {cuts:?}");
            for (piece, _) in &got {
                assert!(
                    whole
                        .iter()
                        .any(|(c, _)| c.start <= piece.start && piece.end <= c.end),
                    "{piece:?} within one cell"
                );
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn random_queries_match_brute_force(
            seed in 0u64..1000, n in 0usize..60, cell in 0.01f64..2.0, radius in 0.0f64..3.0,
        ) {
            let s = random_set::<3>(seed, n, 1.0, -0.5);
            let g = NeighbourGrid::new(&s, cell).unwrap();
            let q = Point::<3>::new(0.1, -0.2, 0.3);
            proptest::prop_assert_eq!(grid_query(&g, &q, radius), brute(&s, &q, radius));
        }
    }
}
