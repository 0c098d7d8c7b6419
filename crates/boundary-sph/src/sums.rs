//! Summation density, particle volumes and the per-particle kernel sums.

use crate::kernel::SphKernel;
use boundary_core::nalgebra::SMatrix;
use boundary_core::{CoreError, NeighbourGrid, ParticleSet, Point};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// The number density `n_i = Σ_j W_ij` of every particle (`j` over all particles within the
/// support, `i` itself and its duplicates included), in input order. With a uniform mass `m`
/// the summation density is `ρ_i = m n_i`; `n_i >= W(0) > 0`. In physical units (a factor
/// `h^-D`: not finite for extreme `h`; [`SphContext`] works in units of `h`).
pub fn number_density<const D: usize>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
) -> Vec<f64> {
    let scale = kernel.h().powi(-(D as i32));
    reduced_number_density(positions, grid, kernel)
        .into_iter()
        .map(|n| n * scale)
        .collect()
}

/// `n_i · h^D = Σ_j σ_D f(|x_j − x_i|/h)`: the number density in units of `h` (no power of
/// `h`, finite for every `h`). Distances are divided by `h` before their norm is taken.
fn reduced_number_density<const D: usize>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
) -> Vec<f64> {
    let support = kernel.support();
    let inv_h = 1.0 / kernel.h();
    positions
        .par_iter()
        .map(|p| {
            if boundary_core::stop::requested() {
                return 0.0;
            }
            let mut sum = 0.0;
            grid.for_each_within(p, support, |j, _| {
                let q = ((positions[j] - p) * inv_h).norm();
                sum += kernel.reduced_value(q);
            });
            sum
        })
        .collect()
}

/// The summation density `ρ_i = Σ_j m W_ij` with a uniform particle mass `m`.
pub fn summation_density<const D: usize>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
    mass: f64,
) -> Vec<f64> {
    let mut rho = number_density(positions, grid, kernel);
    rho.iter_mut().for_each(|r| *r *= mass);
    rho
}

/// The sums over the neighbours `j` of one particle `i` that the SPH detectors use, with
/// `V_j = m/ρ_j` the summation-density volumes and `∇W_ij = ∇_i W(|x_i − x_j|)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalSums<const D: usize> {
    /// Shepard sum `Σ_j V_j W_ij` (`j = i` included): the SPH interpolant of the constant 1,
    /// Müller et al.'s colour field `c_i`; close to 1 inside the fluid.
    pub shepard: f64,
    /// `Σ_j V_j ∇W_ij`: the SPH gradient of the constant 1, the colour-field gradient `∇c_i`;
    /// close to 0 inside, pointing into the fluid near its surface. Physical units (1/length):
    /// `gradient_h / h`.
    pub gradient: Point<D>,
    /// `∇c_i · h`: the same gradient in units of `1/h`, dimensionless and computed without any
    /// power of `h`, so it is the same for a scene and its scaled copy (at every scale whose
    /// squared distances are finite). The detectors use this one.
    pub gradient_h: Point<D>,
    /// The renormalisation matrix `B_i = Σ_j V_j (x_j − x_i) ⊗ ∇W_ij` (Randles & Libersky
    /// 1996; Marrone et al. 2010 write its inverse `L_i`): symmetric, positive semi-definite,
    /// close to the identity inside the fluid.
    pub renormalisation: SMatrix<f64, D, D>,
    /// Number of other particles within the support (duplicates of `x_i` included).
    pub neighbours: usize,
}

/// Particles per block of the neighbour lists: the unit of work of the parallel volume pass.
const LIST_BLOCK: usize = 1024;

/// Most neighbours per particle, on average over a block, that the neighbour lists keep (4
/// bytes each, so at most 640 bytes per particle): a block whose particles have more (a
/// cluster of duplicates, a very large `h_over_r`) is not kept, and its particles query the
/// grid again for their sums. The 3D balls of the benchmarks have about 60 at `h = r`.
const LIST_BUDGET: usize = 160;

/// Fewest blocks of [`LIST_BLOCK`] slots in a range of the parallel pair sweep: the pairs
/// across a cut are tested twice, so a range is kept much thicker than the support.
const SWEEP_MIN_BLOCKS: usize = 8;

/// The neighbours within the support of the particles of one block of [`LIST_BLOCK`] slots of
/// the grid's cell order (each particle itself included), as slots of that order, in the order
/// [`NeighbourGrid::for_each_within`] reports them.
#[derive(Debug, Default)]
struct ListBlock {
    /// `offsets[k]..offsets[k + 1]` is the range in `slots` of the block's `k`-th particle;
    /// empty when the block was over [`LIST_BUDGET`] and is not kept.
    offsets: Vec<u32>,
    slots: Vec<u32>,
}

/// Positions, the neighbour grid (cells of one support radius), the kernel and the particle
/// volumes of a set: everything the SPH kernel sums need, built once per detection.
///
/// Every sum is computed in units of `h` (distances divided by `h` first, the kernel without
/// its `h^-D`, volumes as `V/h^D`), so the dimensionless results (Shepard sum, `∇c·h`, the
/// renormalisation matrix) are the same for a scene and its scaled copy, for every `h` whose
/// squared support radius is a normal `f64` (about `1e-150 <= h <= 1e150`; the neighbour
/// grid compares squared distances).
///
/// **Neighbour lists.** The volume pass finds the neighbours of every particle once, in the
/// grid's cell order, and keeps them (4 bytes a neighbour, up to an average of 160 per
/// particle per block of 1024 particles; denser blocks are not kept and query the grid again):
/// the sums replay them instead of a second grid query. Either way a particle's neighbours
/// are visited in the order [`NeighbourGrid::for_each_within`] reports them, with the same
/// arithmetic, so the sums do not depend on which path computed them (bit for bit).
#[derive(Debug)]
pub struct SphContext<'a, const D: usize> {
    positions: &'a [Point<D>],
    grid: NeighbourGrid<D>,
    kernel: SphKernel<D>,
    /// `V_i / h^D`.
    reduced_volumes: Vec<f64>,
    /// `V_i` (physical; may be 0 or infinite for extreme `h`).
    volumes: Vec<f64>,
    /// `V/h^D` in the grid's cell order.
    sorted_volumes: Vec<f64>,
    /// The slot of each particle (input order) in the grid's cell order.
    slot_of: Vec<u32>,
    /// The neighbour lists, by blocks of [`LIST_BLOCK`] slots.
    lists: Vec<ListBlock>,
    /// Slots per range of the parallel passes over pairs (a multiple of [`LIST_BLOCK`]).
    chunk: usize,
}

/// The reduced number density `Σ_j σ_D f(q_ij)` of every particle in the grid's cell order,
/// and the neighbour lists of the blocks within [`LIST_BUDGET`].
fn density_and_lists<const D: usize>(
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
) -> (Vec<f64>, Vec<ListBlock>) {
    let sorted = grid.cell_sorted_positions();
    let support = kernel.support();
    let inv_h = 1.0 / kernel.h();
    let blocks: Vec<(Vec<f64>, ListBlock)> = sorted
        .par_chunks(LIST_BLOCK)
        .map_init(Vec::new, |found: &mut Vec<u32>, chunk| {
            let budget = LIST_BUDGET * chunk.len();
            let mut density = Vec::with_capacity(chunk.len());
            let mut block = ListBlock {
                offsets: vec![0],
                slots: Vec::new(),
            };
            let mut keep = true;
            for p in chunk {
                if boundary_core::stop::requested() {
                    density.push(0.0);
                    keep = false;
                    continue;
                }
                found.clear();
                grid.gather_within(p, support, found, |_, slot, _| slot as u32);
                let mut sum = 0.0;
                for &t in found.iter() {
                    let q = ((sorted[t as usize] - p) * inv_h).norm();
                    sum += kernel.reduced_value(q);
                }
                density.push(sum);
                keep &= block.slots.len() + found.len() <= budget;
                if keep {
                    block.slots.extend_from_slice(found);
                    block.offsets.push(block.slots.len() as u32);
                }
            }
            if !keep {
                block = ListBlock::default();
            }
            (density, block)
        })
        .collect();
    let mut density = Vec::with_capacity(sorted.len());
    let mut lists = Vec::with_capacity(blocks.len());
    for (d, block) in blocks {
        density.extend(d);
        lists.push(block);
    }
    (density, lists)
}

/// [`density_and_lists`] on a dense grid by a sweep over the cells in the cell order that
/// tests each pair of particles once, from the one earlier in that order, cut into
/// consecutive ranges of `chunk` slots (a multiple of [`LIST_BLOCK`]) swept in parallel.
///
/// Within a range, the pair `(a, t)`, `a < t`, adds its kernel value to both number
/// densities; a particle first receives the terms of its neighbours before its range, found
/// by its own test against them ([`sweep_range`]), so every particle receives its terms in
/// the order of its own neighbour query (earlier slots first, itself, then later slots), with
/// the same arithmetic (`x_t − x_a = −(x_a − x_t)` exactly): the densities and lists are
/// those of [`density_and_lists`], bit for bit, for any `chunk`, for about half the distance
/// tests and kernel values (the pairs across a cut are tested from both sides). `None` for
/// the hashed layout, or where the pairs of a range pass half of [`LIST_BUDGET`] per particle
/// (then the caller's per-particle pass keeps what fits).
fn density_and_lists_sweep<const D: usize>(
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
    chunk: usize,
) -> Option<(Vec<f64>, Vec<ListBlock>)> {
    debug_assert!(chunk > 0 && chunk.is_multiple_of(LIST_BLOCK));
    let n = grid.cell_sorted_positions().len();
    if grid.is_hashed() {
        return None;
    }
    let firsts: Vec<usize> = (0..n).step_by(chunk.max(LIST_BLOCK)).collect();
    let pieces: Vec<Option<(Vec<f64>, Vec<ListBlock>)>> = firsts
        .into_par_iter()
        .map(|first| sweep_range(grid, kernel, first..(first + chunk).min(n)))
        .collect();
    let mut density = Vec::with_capacity(n);
    let mut lists = Vec::with_capacity(n.div_ceil(LIST_BLOCK));
    for piece in pieces {
        let (d, l) = piece?;
        density.extend(d);
        lists.extend(l);
    }
    Some((density, lists))
}

/// Writes the slots of `slots` (of the cell order) within `r2` (squared) of `p` to `near`
/// from `found` on and returns the new count: every candidate is written and only a hit
/// advances the count, with no branch per candidate, whose outcome is a coin toss (about one
/// in six is a neighbour). `near` has room for every candidate; an empty range writes nothing.
#[inline(always)]
fn hits<const D: usize>(
    sorted: &[Point<D>],
    slots: std::ops::Range<usize>,
    p: &Point<D>,
    r2: f64,
    near: &mut [u32],
    mut found: usize,
) -> usize {
    if slots.start < slots.end {
        for (t, x) in slots.clone().zip(&sorted[slots]) {
            near[found] = t as u32;
            found += (dist2(x, p) <= r2) as usize;
        }
    }
    found
}

/// The densities and lists of the slots `range` (its start a multiple of [`LIST_BLOCK`]):
/// first each particle's terms from the neighbours before the range, in slot order; then the
/// sweep of the range's pairs, where a pair beyond the range counts for its earlier particle
/// only (the later one belongs to the next range, which tests the pair again).
fn sweep_range<const D: usize>(
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
    range: std::ops::Range<usize>,
) -> Option<(Vec<f64>, Vec<ListBlock>)> {
    let sorted = grid.cell_sorted_positions();
    let (s0, s1) = (range.start, range.end);
    let len = s1 - s0;
    let support = kernel.support();
    let r2 = support * support;
    let inv_h = 1.0 / kernel.h();
    let most = LIST_BUDGET / 2 * len;
    // The range's densities, and one spare term for the pairs beyond it.
    let mut density = vec![0.0; len + 1];
    // The neighbours before the range of the range's `k`-th slot,
    // `before[before_starts[k]..before_starts[k + 1]]`.
    let mut before_starts: Vec<usize> = Vec::with_capacity(len + 1);
    before_starts.push(0);
    let mut before: Vec<u32> = Vec::new();
    // The candidates of a particle within the support ([`hits`]).
    let mut near: Vec<u32> = Vec::new();
    let mut over = false;
    let room = |near: &mut Vec<u32>, rows: &[std::ops::Range<usize>]| {
        let most_candidates: usize = rows.iter().map(|r| r.len()).sum();
        if near.len() < most_candidates {
            near.resize(most_candidates, 0);
        }
    };
    if s0 == 0 {
        before_starts.resize(len + 1, 0);
    } else {
        let dense = grid.for_each_cell_block_in(range.clone(), support, |cell, rows| {
            if over || boundary_core::stop::requested() {
                over = true;
                return;
            }
            room(&mut near, rows);
            for t in cell {
                let x = sorted[t];
                let mut found = 0;
                // Rows ascend: the first that starts in the range ends the search.
                for row in rows.iter().take_while(|row| row.start < s0) {
                    found = hits(sorted, row.start..row.end.min(s0), &x, r2, &mut near, found);
                }
                let mut sum = 0.0;
                for &a in &near[..found] {
                    sum += kernel.reduced_value(((x - sorted[a as usize]) * inv_h).norm());
                }
                density[t - s0] = sum;
                before.extend_from_slice(&near[..found]);
                before_starts.push(before.len());
            }
            over |= before.len() > most;
        });
        if !dense || over {
            return None;
        }
    }
    // The later neighbours of each slot of the range, `forward[starts[k]..starts[k + 1]]`.
    let mut starts: Vec<usize> = Vec::with_capacity(len + 1);
    starts.push(0);
    let mut forward: Vec<u32> = Vec::new();
    let dense = grid.for_each_cell_block_in(range.clone(), support, |cell, rows| {
        if over || boundary_core::stop::requested() {
            over = true;
            return;
        }
        room(&mut near, rows);
        for a in cell {
            let p = sorted[a];
            let mut found = 0;
            for row in rows {
                found = hits(
                    sorted,
                    row.start.max(a + 1)..row.end,
                    &p,
                    r2,
                    &mut near,
                    found,
                );
            }
            // Itself: `x − x = 0` exactly for finite coordinates, so `q = 0` as in its query.
            let mut sum = density[a - s0] + kernel.reduced_value(0.0);
            for &t in &near[..found] {
                let w = kernel.reduced_value(((sorted[t as usize] - p) * inv_h).norm());
                sum += w;
                density[(t as usize).min(s1) - s0] += w;
            }
            density[a - s0] = sum;
            forward.extend_from_slice(&near[..found]);
            starts.push(forward.len());
        }
        over |= forward.len() > most;
    });
    if !dense || over {
        return None;
    }
    density.truncate(len);
    // Each slot's list: its neighbours before the range, its earlier neighbours in the range
    // (the slots whose forward lists hold it, in increasing order), itself, its later
    // neighbours.
    let mut earlier = vec![0u32; len];
    for &t in &forward {
        // A later neighbour is after its particle, so after `s0`; one past `s1` is not ours.
        if (t as usize) < s1 {
            earlier[t as usize - s0] += 1;
        }
    }
    let mut lists: Vec<ListBlock> = (0..len)
        .step_by(LIST_BLOCK)
        .map(|first| {
            let slots = first..(first + LIST_BLOCK).min(len);
            let mut offsets = Vec::with_capacity(slots.len() + 1);
            offsets.push(0u32);
            let mut total = 0usize;
            for k in slots.clone() {
                total += before_starts[k + 1] - before_starts[k]
                    + earlier[k] as usize
                    + 1
                    + (starts[k + 1] - starts[k]);
                offsets.push(total as u32);
            }
            if total > LIST_BUDGET * slots.len() {
                return ListBlock::default();
            }
            ListBlock {
                offsets,
                slots: vec![0; total],
            }
        })
        .collect();
    // `earlier` becomes the next free place of each slot's earlier part, after the
    // neighbours before the range.
    for (k, next) in earlier.iter_mut().enumerate() {
        let block = &mut lists[k / LIST_BLOCK];
        if block.slots.is_empty() {
            continue;
        }
        let place = block.offsets[k % LIST_BLOCK] as usize;
        let from_before = &before[before_starts[k]..before_starts[k + 1]];
        block.slots[place..place + from_before.len()].copy_from_slice(from_before);
        *next = (place + from_before.len()) as u32;
    }
    for k in 0..len {
        let a = s0 + k;
        let later = &forward[starts[k]..starts[k + 1]];
        for &t in later {
            // Ascending: the first past the range ends the range's part.
            if t as usize >= s1 {
                break;
            }
            let j = t as usize - s0;
            let block = &mut lists[j / LIST_BLOCK];
            if !block.slots.is_empty() {
                let place = &mut earlier[j];
                block.slots[*place as usize] = a as u32;
                *place += 1;
            }
        }
        let block = &mut lists[k / LIST_BLOCK];
        if !block.slots.is_empty() {
            let place = earlier[k] as usize;
            block.slots[place] = a as u32;
            block.slots[place + 1..place + 1 + later.len()].copy_from_slice(later);
        }
    }
    Some((density, lists))
}

impl<'a, const D: usize> SphContext<'a, D> {
    /// Builds the grid and the volumes `V_i = m/ρ_i = 1/n_i` (the uniform mass cancels, so
    /// only positions are needed). Fails only where the grid does (a bounding box of more
    /// than `2^52` support radii along an axis).
    pub fn new(set: &'a ParticleSet<D>, kernel: SphKernel<D>) -> Result<Self, CoreError> {
        // One range of the pair sweep per thread, of at least `SWEEP_MIN_BLOCKS` blocks.
        let blocks = set.len().div_ceil(LIST_BLOCK);
        let chunk = blocks
            .div_ceil(rayon::current_num_threads())
            .max(SWEEP_MIN_BLOCKS)
            * LIST_BLOCK;
        Self::with_sweep_ranges(set, kernel, chunk)
    }

    /// [`Self::new`] with the pair sweep cut into ranges of `chunk` slots (a multiple of
    /// [`LIST_BLOCK`]): the same numbers for every `chunk`.
    fn with_sweep_ranges(
        set: &'a ParticleSet<D>,
        kernel: SphKernel<D>,
        chunk: usize,
    ) -> Result<Self, CoreError> {
        let positions = set.positions();
        let grid = NeighbourGrid::new(set, kernel.support())?;
        // The pair sweep, else a query per particle, in parallel. The same numbers either way.
        let (density, lists) = density_and_lists_sweep(&grid, &kernel, chunk)
            .unwrap_or_else(|| density_and_lists(&grid, &kernel));
        let sorted_volumes: Vec<f64> = density.par_iter().map(|n| 1.0 / n).collect();
        // The inverse of the cell order, on every thread (relaxed stores at distinct
        // indices), then plain integers in place.
        let slot_of: Vec<AtomicU32> = (0..positions.len()).map(|_| AtomicU32::new(0)).collect();
        grid.cell_order()
            .par_iter()
            .enumerate()
            .for_each(|(s, &i)| slot_of[i as usize].store(s as u32, Ordering::Relaxed));
        let slot_of: Vec<u32> = slot_of.into_iter().map(AtomicU32::into_inner).collect();
        let reduced_volumes: Vec<f64> = slot_of
            .par_iter()
            .map(|&s| sorted_volumes[s as usize])
            .collect();
        let h_d = kernel.h().powi(D as i32);
        let volumes = reduced_volumes.par_iter().map(|v| v * h_d).collect();
        Ok(SphContext {
            positions,
            grid,
            kernel,
            reduced_volumes,
            volumes,
            sorted_volumes,
            slot_of,
            lists,
            chunk,
        })
    }

    /// The positions, in input order.
    pub fn positions(&self) -> &'a [Point<D>] {
        self.positions
    }

    /// The neighbour grid (cells of one support radius).
    pub fn grid(&self) -> &NeighbourGrid<D> {
        &self.grid
    }

    /// The kernel.
    pub fn kernel(&self) -> &SphKernel<D> {
        &self.kernel
    }

    /// The volumes `V_i = m/ρ_i`, in input order (physical units: not finite for extreme
    /// `h`; see [`Self::reduced_volumes`]).
    pub fn volumes(&self) -> &[f64] {
        &self.volumes
    }

    /// The volumes in units of `h`, `V_i / h^D = 1 / Σ_j σ_D f(q_ij)`, in input order: finite
    /// and positive for every `h`.
    pub fn reduced_volumes(&self) -> &[f64] {
        &self.reduced_volumes
    }

    /// The kept neighbour list of particle `i` (slots of the cell order, `i`'s own among
    /// them) and `i`'s slot, or `None` where its block was not kept.
    #[inline]
    fn list(&self, i: usize) -> Option<(&[u32], usize)> {
        let s = self.slot_of[i] as usize;
        let block = &self.lists[s / LIST_BLOCK];
        let k = s % LIST_BLOCK;
        match (block.offsets.get(k), block.offsets.get(k + 1)) {
            (Some(&a), Some(&b)) => Some((&block.slots[a as usize..b as usize], s)),
            _ => None,
        }
    }

    /// Calls `f(x_j, V_j/h^D)` for every particle `j != i` within the support of `i`, in the
    /// order of [`NeighbourGrid::for_each_within`].
    #[inline]
    fn visit<F: FnMut(&Point<D>, f64)>(&self, i: usize, mut f: F) {
        if let Some((list, s)) = self.list(i) {
            let sorted = self.grid.cell_sorted_positions();
            for &t in list {
                let t = t as usize;
                if t != s {
                    f(&sorted[t], self.sorted_volumes[t]);
                }
            }
        } else {
            self.grid
                .for_each_within(&self.positions[i], self.kernel.support(), |j, _| {
                    if j != i {
                        f(&self.positions[j], self.reduced_volumes[j]);
                    }
                });
        }
    }

    /// Calls `f(j, x_j − x_i, |x_j − x_i|)` for every particle `j != i` within the support of
    /// particle `i` (duplicates of `x_i` come with distance 0), in an unspecified but
    /// deterministic order.
    pub fn for_each_neighbour<F: FnMut(usize, Point<D>, f64)>(&self, i: usize, mut f: F) {
        let p = self.positions[i];
        if let Some((list, s)) = self.list(i) {
            let sorted = self.grid.cell_sorted_positions();
            let order = self.grid.cell_order();
            for &t in list {
                let t = t as usize;
                if t != s {
                    let x = sorted[t];
                    f(order[t] as usize, x - p, dist2(&x, &p).sqrt());
                }
            }
        } else {
            self.grid
                .for_each_within(&p, self.kernel.support(), |j, d2| {
                    if j != i {
                        f(j, self.positions[j] - p, d2.sqrt());
                    }
                });
        }
    }

    /// Calls `f(V_j/h^D, x_j − x_i, |x_j − x_i|)` for every particle `j != i` within the
    /// support of particle `i`: [`Self::for_each_neighbour`] with the neighbour's reduced
    /// volume ([`Self::reduced_volumes`]) in place of its index, in the same order.
    pub fn for_each_neighbour_volume<F: FnMut(f64, Point<D>, f64)>(&self, i: usize, mut f: F) {
        let p = self.positions[i];
        self.visit(i, |x, v| f(v, x - p, dist2(x, &p).sqrt()));
    }

    /// The kernel sums of particle `i`; see [`LocalSums`]. Computed in units of `h`:
    /// `V_j ∇W_ij · h = (V_j/h^D) · σ_D (−f'(q)/q) · (x_j − x_i)/h`.
    pub fn local_sums(&self, i: usize) -> LocalSums<D> {
        let kernel = &self.kernel;
        let inv_h = 1.0 / kernel.h();
        let p = self.positions[i];
        let mut sums = LocalSums {
            shepard: self.reduced_volumes[i] * kernel.reduced_value(0.0),
            gradient: Point::<D>::zeros(),
            gradient_h: Point::<D>::zeros(),
            renormalisation: SMatrix::<f64, D, D>::zeros(),
            neighbours: 0,
        };
        self.visit(i, |x, v| {
            // x_j − x_i in units of h.
            let xji = (x - p) * inv_h;
            let q = xji.norm();
            sums.neighbours += 1;
            sums.shepard += v * kernel.reduced_value(q);
            if q > 0.0 {
                // ∇_i W_ij = W'(r) (x_i − x_j)/r = w (x_j − x_i) with w = −W'(r)/r >= 0.
                let g = xji * (v * kernel.reduced_gradient_weight(q));
                sums.gradient_h += g;
                sums.renormalisation += xji * g.transpose();
            }
        });
        sums.gradient = sums.gradient_h * inv_h;
        sums
    }
}

impl<const D: usize> SphContext<'_, D> {
    /// [`LocalSums::gradient_h`] of particle `i` alone (`∇c_i · h`), without the Shepard sum
    /// and the matrix: the same numbers, bit for bit, for a third of the work.
    pub fn gradient_h(&self, i: usize) -> Point<D> {
        let (pair, term) = self.gradient_terms();
        self.particle_sums(i, Point::<D>::zeros(), &pair, &term)
    }

    /// `finish(i, ∇c_i · h)` of the first `count` particles, in input order, each pair's
    /// kernel evaluated once ([`Self::pair_sums`]): [`Self::gradient_h`], bit for bit.
    pub fn gradients_h<R: Send>(
        &self,
        count: usize,
        finish: impl Fn(usize, &Point<D>) -> R + Sync,
    ) -> Vec<R> {
        let (pair, term) = self.gradient_terms();
        self.pair_sums(count, |_| Point::<D>::zeros(), pair, term, finish)
    }

    /// The pair part `(q, σ_D (−f'(q)/q))` and the term `V_j/h^D · w · (x_j − x_i)/h` of the
    /// gradient (`q > 0` only: a duplicate has no direction).
    #[allow(clippy::type_complexity)]
    fn gradient_terms(
        &self,
    ) -> (
        impl Fn(&Point<D>, f64) -> (f64, f64) + Sync + '_,
        impl Fn(&mut Point<D>, &Point<D>, &(f64, f64), f64) + Sync + '_,
    ) {
        let kernel = &self.kernel;
        let inv_h = 1.0 / kernel.h();
        let pair = move |d: &Point<D>, _: f64| {
            let q = (d * inv_h).norm();
            (q, kernel.reduced_gradient_weight(q))
        };
        let term = move |g: &mut Point<D>, d: &Point<D>, &(q, w): &(f64, f64), v: f64| {
            if q > 0.0 {
                *g += (d * inv_h) * (v * w);
            }
        };
        (pair, term)
    }

    /// [`LocalSums::renormalisation`] and [`LocalSums::gradient_h`] of particle `i`, without
    /// the Shepard sum: the same numbers, bit for bit.
    pub fn renormalisation_and_gradient_h(&self, i: usize) -> (SMatrix<f64, D, D>, Point<D>) {
        let (pair, term) = self.renormalisation_terms();
        let zero = (SMatrix::<f64, D, D>::zeros(), Point::<D>::zeros());
        self.particle_sums(i, zero, &pair, &term)
    }

    /// The pair part of [`Self::gradient_terms`] and the term of the matrix and the gradient.
    #[allow(clippy::type_complexity)]
    fn renormalisation_terms(
        &self,
    ) -> (
        impl Fn(&Point<D>, f64) -> (f64, f64) + Sync + '_,
        impl Fn(&mut (SMatrix<f64, D, D>, Point<D>), &Point<D>, &(f64, f64), f64) + Sync + '_,
    ) {
        let (pair, _) = self.gradient_terms();
        let inv_h = 1.0 / self.kernel.h();
        let term = move |(b, gradient): &mut (SMatrix<f64, D, D>, Point<D>),
                         d: &Point<D>,
                         &(q, w): &(f64, f64),
                         v: f64| {
            if q > 0.0 {
                let xji = d * inv_h;
                let g = xji * (v * w);
                *gradient += g;
                // `b += xji ⊗ g`, entry by entry.
                for c in 0..D {
                    for r in 0..D {
                        b[(r, c)] += xji[r] * g[c];
                    }
                }
            }
        };
        (pair, term)
    }

    /// The divergence of position `∇·r_i = Σ_{j≠i} V_j (x_j − x_i)·∇_i W_ij` of particle `i`
    /// (dimensionless; the trace of [`LocalSums::renormalisation`], about `D` inside a full
    /// neighbourhood) and the number of other particles within the support (duplicates of
    /// `x_i` included; they add nothing to the sum). One neighbour pass without the matrix:
    /// `Σ_j (V_j/h^D) · σ_D (−f'(q)/q) · q²` with `q = |x_j − x_i|/h`.
    pub fn divergence_of_position(&self, i: usize) -> (f64, usize) {
        let (pair, term) = self.divergence_terms();
        self.particle_sums(i, (0.0, 0), &pair, &term)
    }

    /// `finish(i, &(∇·r_i, neighbour count))` of the first `count` particles, in input order,
    /// each pair's kernel evaluated once ([`Self::pair_sums`]):
    /// [`Self::divergence_of_position`], bit for bit.
    pub fn divergences_of_position<R: Send>(
        &self,
        count: usize,
        finish: impl Fn(usize, &(f64, usize)) -> R + Sync,
    ) -> Vec<R> {
        let (pair, term) = self.divergence_terms();
        self.pair_sums(count, |_| (0.0, 0), pair, term, finish)
    }

    /// The pair part `(q², σ_D (−f'(q)/q))` and the term of the divergence.
    #[allow(clippy::type_complexity)]
    fn divergence_terms(
        &self,
    ) -> (
        impl Fn(&Point<D>, f64) -> (f64, f64) + Sync + '_,
        impl Fn(&mut (f64, usize), &Point<D>, &(f64, f64), f64) + Sync + '_,
    ) {
        let kernel = &self.kernel;
        let inv_h = 1.0 / kernel.h();
        let pair = move |d: &Point<D>, _: f64| {
            let q2 = (d * inv_h).norm_squared();
            (q2, kernel.reduced_gradient_weight(q2.sqrt()))
        };
        let term =
            |(sum, count): &mut (f64, usize), _: &Point<D>, &(q2, w): &(f64, f64), v: f64| {
                *sum += v * w * q2;
                *count += 1;
            };
        (pair, term)
    }

    /// One particle's sums of [`Self::pair_sums`] (starting from `acc`), from its own
    /// neighbours, in the same order and with the same arithmetic: for a criterion that
    /// classifies one particle alone with the terms of its pass over every particle.
    pub fn particle_sums<A, S, P, T>(&self, i: usize, mut acc: A, pair: &P, term: &T) -> A
    where
        P: Fn(&Point<D>, f64) -> S,
        T: Fn(&mut A, &Point<D>, &S, f64),
    {
        let p = self.positions[i];
        self.visit(i, |x, v| {
            let d = x - p;
            let s = pair(&d, dist2(x, &p));
            term(&mut acc, &d, &s, v);
        });
        acc
    }

    /// Sums over the neighbours of every particle, with each pair's shared part computed
    /// once, and `finish(i, &acc_i)` of the first `count` particles, in input order. For
    /// particle `i` (ghosts included) the sum starts from `init(i)` and takes
    /// `term(&mut acc, &(x_j − x_i), &pair(&(x_j − x_i), |x_j − x_i|²), V_j/h^D)` for every
    /// particle `j != i` within the support, in the order of
    /// [`Self::for_each_neighbour_volume`] (the vector and the volume are those it reports;
    /// the squared distance is the square of its distance before the root). `finish` reads
    /// the sums where they were accumulated (no copy of them in input order).
    ///
    /// **Contract:** `pair` must give the same value for `x` and `−x` (depend on `x` through
    /// its norm, its squared components or the squared distance only): within a range of the
    /// pass it is computed once, from the earlier particle of the pair in the grid's cell
    /// order, and serves both. Each side's vector is its own subtraction, as in its own query,
    /// and `fl(a − b) = −fl(b − a)` for `a ≠ b`, so the squares are those of the other side:
    /// with such a `pair` every particle receives the terms of its own neighbour query, bit
    /// for bit, in the same order; the results are those of a loop over
    /// [`Self::for_each_neighbour_volume`], whatever the number of threads.
    ///
    /// On a dense grid whose neighbour lists were all kept, the pass sweeps the pairs once,
    /// in ranges of the cell order swept in parallel: a range first gives each of its
    /// particles the terms of its neighbours before the range (from its own side), then
    /// walks each particle's later neighbours, adding the term to both particles of a pair
    /// within the range and to the earlier one only of a pair that leaves it. Otherwise
    /// (hashed grid, a block over the list budget), and where fewer than half of the
    /// particles are asked for (`2 count < n`: a large halo of ghosts, whose pairs among
    /// themselves the sweep would pay for), each particle asked for visits its own
    /// neighbours. The stop token is checked once per block of the lists.
    ///
    /// # Panics
    /// If `count` exceeds the number of particles.
    pub fn pair_sums<A, R, S, I, P, T, F>(
        &self,
        count: usize,
        init: I,
        pair: P,
        term: T,
        finish: F,
    ) -> Vec<R>
    where
        A: Send + Sync,
        R: Send,
        I: Fn(usize) -> A + Sync,
        P: Fn(&Point<D>, f64) -> S + Sync,
        T: Fn(&mut A, &Point<D>, &S, f64) + Sync,
        F: Fn(usize, &A) -> R + Sync,
    {
        let n = self.positions.len();
        assert!(count <= n, "{count} of {n} particles");
        let all_kept = self.lists.iter().all(|block| !block.offsets.is_empty());
        if self.grid.is_hashed() || !all_kept || 2 * count < n {
            return (0..count)
                .into_par_iter()
                .map(|i| {
                    let acc = if boundary_core::stop::requested() {
                        init(i)
                    } else {
                        self.particle_sums(i, init(i), &pair, &term)
                    };
                    finish(i, &acc)
                })
                .collect();
        }
        let sorted = self.grid.cell_sorted_positions();
        let order = self.grid.cell_order();
        let volumes = &self.sorted_volumes;
        let firsts: Vec<usize> = (0..n).step_by(self.chunk).collect();
        let pieces: Vec<Vec<A>> = firsts
            .into_par_iter()
            .map(|s0| {
                let s1 = (s0 + self.chunk).min(n);
                let mut acc: Vec<A> = (s0..s1).map(|s| init(order[s] as usize)).collect();
                let stopped =
                    |a: usize| a.is_multiple_of(LIST_BLOCK) && boundary_core::stop::requested();
                // The lists ascend (the cell order of the neighbour queries): first the
                // neighbours before the range, ...
                for a in s0..s1 {
                    if stopped(a) {
                        return acc;
                    }
                    let xa = sorted[a];
                    for &t in self.slot_list(a).iter().take_while(|&&t| (t as usize) < s0) {
                        let xt = sorted[t as usize];
                        let d = xt - xa;
                        let s = pair(&d, dist2(&xt, &xa));
                        term(&mut acc[a - s0], &d, &s, volumes[t as usize]);
                    }
                }
                // ... then each pair of the range from its earlier particle, whose earlier
                // partners have all given their terms by then.
                for a in s0..s1 {
                    if stopped(a) {
                        return acc;
                    }
                    let (xa, va) = (sorted[a], volumes[a]);
                    let list = self.slot_list(a);
                    let later = list.partition_point(|&t| t as usize <= a);
                    for &t in &list[later..] {
                        let t = t as usize;
                        let xt = sorted[t];
                        let d = xt - xa;
                        let s = pair(&d, dist2(&xt, &xa));
                        term(&mut acc[a - s0], &d, &s, volumes[t]);
                        if t < s1 {
                            term(&mut acc[t - s0], &(xa - xt), &s, va);
                        }
                    }
                }
                acc
            })
            .collect();
        self.slot_of[..count]
            .par_iter()
            .enumerate()
            .map(|(i, &s)| finish(i, &pieces[s as usize / self.chunk][s as usize % self.chunk]))
            .collect()
    }

    /// The kept neighbour list of slot `s` (every list kept).
    #[inline]
    fn slot_list(&self, s: usize) -> &[u32] {
        let block = &self.lists[s / LIST_BLOCK];
        let k = s % LIST_BLOCK;
        &block.slots[block.offsets[k] as usize..block.offsets[k + 1] as usize]
    }
}

/// `|p − q|²` summed axis by axis, as the neighbour grid computes it.
#[inline]
fn dist2<const D: usize>(p: &Point<D>, q: &Point<D>) -> f64 {
    let mut d2 = 0.0;
    for k in 0..D {
        let d = p[k] - q[k];
        d2 += d * d;
    }
    d2
}

/// Outward unit normals from the colour-field gradient (Müller et al., SCA 2003, Sec. 5):
/// `n_i = −∇c_i / |∇c_i|` with `∇c_i = Σ_j V_j ∇W_ij`, the gradient of unity of
/// [`LocalSums`] (it points into the fluid, so its negation points out), Wendland C2 at `h`.
///
/// Tolerance: where `|∇c_i| · h < 1e-9` (inside a symmetric neighbourhood, or an isolated
/// particle) the direction is undefined and the zero vector is returned. Exact duplicates
/// contribute nothing (their `∇W` is zero at distance 0).
///
/// ```
/// use boundary_core::ParticleSet;
/// use boundary_sph::colour_field_normals;
///
/// // A 5 x 5 lattice: the middle of the left edge points to −x, the centre has no normal.
/// let rows: Vec<[f64; 2]> = (0..25).map(|k| [(k % 5) as f64, (k / 5) as f64]).collect();
/// let set = ParticleSet::from_rows(&rows).unwrap();
/// let n = colour_field_normals(&set, 1.0).unwrap();
/// assert!((n[10].x + 1.0).abs() < 1e-12 && n[10].y.abs() < 1e-12);
/// assert_eq!(n[12].norm(), 0.0);
/// ```
pub fn colour_field_normals<const D: usize>(
    set: &ParticleSet<D>,
    h: f64,
) -> Result<Vec<Point<D>>, CoreError> {
    use crate::kernel::Kernel;
    let ctx = SphContext::new(set, SphKernel::new(Kernel::WendlandC2, h))?;
    Ok((0..set.len())
        .into_par_iter()
        .map(|i| {
            let g = ctx.local_sums(i).gradient_h;
            let norm = g.norm();
            if norm < 1e-9 {
                Point::<D>::zeros()
            } else {
                -g / norm
            }
        })
        .collect())
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use crate::kernel::Kernel;

    /// The sums as the grid's per-particle queries give them, written out independently of
    /// the context: the densities, then `(Shepard, ∇c·h, B, count, ∇·r)` of each particle.
    #[allow(clippy::type_complexity)]
    fn queried_sums<const D: usize>(
        set: &ParticleSet<D>,
        kernel: &SphKernel<D>,
    ) -> (
        Vec<f64>,
        Vec<(f64, Point<D>, SMatrix<f64, D, D>, usize, f64)>,
    ) {
        let p = set.positions();
        let grid = NeighbourGrid::new(set, kernel.support()).unwrap();
        let inv_h = 1.0 / kernel.h();
        let volumes: Vec<f64> = p
            .iter()
            .map(|x| {
                let mut n = 0.0;
                grid.for_each_within(x, kernel.support(), |j, _| {
                    n += kernel.reduced_value(((p[j] - x) * inv_h).norm());
                });
                1.0 / n
            })
            .collect();
        let sums = (0..p.len())
            .map(|i| {
                let mut s = volumes[i] * kernel.reduced_value(0.0);
                let (mut g, mut b) = (Point::<D>::zeros(), SMatrix::<f64, D, D>::zeros());
                let (mut count, mut div) = (0, 0.0);
                grid.for_each_within(&p[i], kernel.support(), |j, _| {
                    if j != i {
                        let xji = (p[j] - p[i]) * inv_h;
                        let q = xji.norm();
                        count += 1;
                        s += volumes[j] * kernel.reduced_value(q);
                        let q2 = xji.norm_squared();
                        div += volumes[j] * kernel.reduced_gradient_weight(q2.sqrt()) * q2;
                        if q > 0.0 {
                            let w = xji * (volumes[j] * kernel.reduced_gradient_weight(q));
                            g += w;
                            b += xji * w.transpose();
                        }
                    }
                });
                (s, g, b, count, div)
            })
            .collect();
        (volumes, sums)
    }

    /// The context of `set` on 1 and 2 threads, with the pair sweep's default ranges and with
    /// ranges of one block (several ranges whenever the set has more than one block).
    fn contexts<'a, const D: usize>(
        set: &'a ParticleSet<D>,
        kernel: SphKernel<D>,
    ) -> Vec<(String, SphContext<'a, D>)> {
        let mut out = Vec::new();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let ctx = pool.install(|| SphContext::new(set, kernel)).unwrap();
            out.push((format!("{threads} threads"), ctx));
            let ctx = pool
                .install(|| SphContext::with_sweep_ranges(set, kernel, LIST_BLOCK))
                .unwrap();
            out.push((format!("{threads} threads, ranges of one block"), ctx));
        }
        out
    }

    fn assert_same_as_queries<const D: usize>(set: &ParticleSet<D>, kernel: SphKernel<D>) {
        let (volumes, expected) = queried_sums(set, &kernel);
        for (threads, ctx) in contexts(set, kernel) {
            assert_eq!(ctx.reduced_volumes(), &volumes[..], "{threads}");
            // The pair passes, and the generic one recording what it gives each particle.
            let n = set.len();
            let gradients = ctx.gradients_h(n, |_, g| *g);
            let divergences = ctx.divergences_of_position(n, |_, sums| *sums);
            let recorded = ctx.pair_sums(
                set.len(),
                |_| Vec::new(),
                |_, d2| d2.sqrt(),
                |seen: &mut Vec<(f64, Point<D>, f64)>, x, &d, v| seen.push((v, *x, d)),
                |_, seen| seen.clone(),
            );
            for (i, e) in expected.iter().enumerate() {
                assert_eq!(gradients[i], e.1, "particle {i}, {threads}");
                assert_eq!(divergences[i], (e.4, e.3), "particle {i}, {threads}");
                let s = ctx.local_sums(i);
                let got = (
                    s.shepard,
                    s.gradient_h,
                    s.renormalisation,
                    s.neighbours,
                    ctx.divergence_of_position(i).0,
                );
                assert_eq!(&got, e, "particle {i}, {threads}");
                assert_eq!(ctx.gradient_h(i), e.1);
                assert_eq!(ctx.renormalisation_and_gradient_h(i), (e.2, e.1));
                let mut via_index = Vec::new();
                ctx.for_each_neighbour(i, |j, x, d| via_index.push((volumes[j], x, d)));
                let mut via_volume = Vec::new();
                ctx.for_each_neighbour_volume(i, |v, x, d| via_volume.push((v, x, d)));
                assert_eq!(via_index, via_volume);
                assert_eq!(via_index.len(), s.neighbours);
                assert_eq!(recorded[i], via_volume, "particle {i}, {threads}");
            }
        }
    }

    /// The kept neighbour lists, the one-thread pair sweep and the per-particle pass give the
    /// sums of the grid's own queries bit for bit (same neighbours, same order, same
    /// arithmetic), on a jittered 3D ball with exact duplicates and a 2D disc, both kernels.
    #[test]
    fn the_kept_neighbour_lists_give_the_queried_sums_bit_for_bit() {
        let (ball, _) = boundary_scenes::jittered_lattice_ball(3000, 0.15, 7);
        let mut rows: Vec<[f64; 3]> = ball.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
        rows.extend_from_within(100..110);
        let ball = ParticleSet::from_rows(&rows).unwrap();
        let disc = boundary_scenes::jittered_lattice_disc(25.0, 0.2, 3);
        for kernel in Kernel::ALL {
            assert_same_as_queries(&ball, SphKernel::new(kernel, 1.2));
            assert_same_as_queries(&disc, SphKernel::new(kernel, 1.3));
        }
        // Every list kept (the sums above came from the sweep's lists, not from queries).
        for (threads, ctx) in contexts(&ball, SphKernel::new(Kernel::WendlandC2, 1.2)) {
            assert!((0..ball.len()).all(|i| ctx.list(i).is_some()), "{threads}");
        }
        for (threads, ctx) in contexts(&disc, SphKernel::new(Kernel::CubicSpline, 1.3)) {
            assert!((0..disc.len()).all(|i| ctx.list(i).is_some()), "{threads}");
        }
    }

    /// A cluster of duplicates over the list budget: its block is not kept (its particles
    /// query the grid again) and the sums are still the queried ones; the other blocks are
    /// kept. 600 duplicates pass the budget of their block only (the one-thread sweep keeps
    /// the other blocks); 2048 pass half the budget of the whole set (the sweep gives way to
    /// the per-particle pass).
    #[test]
    fn a_block_over_the_list_budget_queries_the_grid_with_the_same_sums() {
        for cluster in [600, 2048] {
            let mut rows: Vec<[f64; 2]> = vec![[0.5, 0.5]; cluster];
            rows.extend((0..5000).map(|k| [(k % 64) as f64 + 10.0, (k / 64) as f64]));
            let set = ParticleSet::from_rows(&rows).unwrap();
            let kernel = SphKernel::<2>::new(Kernel::WendlandC2, 1.0);
            for (threads, ctx) in contexts(&set, kernel) {
                assert!(ctx.list(0).is_none(), "{cluster}, {threads}");
                assert!(ctx.list(rows.len() - 1).is_some(), "{threads}");
            }
            assert_same_as_queries(&set, kernel);
        }
    }

    #[test]
    fn the_divergence_of_position_is_the_trace_of_the_renormalisation_matrix() {
        let rows: Vec<[f64; 3]> = (0..216)
            .map(|k| {
                let j = (k * 7919 % 1000) as f64 * 1e-4;
                [
                    (k % 6) as f64 + j,
                    (k / 6 % 6) as f64 - j,
                    (k / 36) as f64 + 0.5 * j,
                ]
            })
            .collect();
        let set = ParticleSet::from_rows(&rows).unwrap();
        for kernel in Kernel::ALL {
            let ctx = SphContext::new(&set, SphKernel::new(kernel, 1.3)).unwrap();
            for i in 0..set.len() {
                let sums = ctx.local_sums(i);
                let (divr, n) = ctx.divergence_of_position(i);
                assert_eq!(n, sums.neighbours);
                assert!((divr - sums.renormalisation.trace()).abs() < 1e-12, "{i}");
            }
        }
    }

    #[test]
    fn isolated_particles_and_duplicates_get_the_stated_volumes_and_sums() {
        let set =
            ParticleSet::from_rows(&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [9.0, 9.0, 9.0]]).unwrap();
        let kernel = SphKernel::<3>::new(Kernel::WendlandC2, 1.0);
        let ctx = SphContext::new(&set, kernel).unwrap();
        let w0 = kernel.value(0.0);
        assert!((ctx.volumes()[0] - 0.5 / w0).abs() < 1e-15);
        assert!((ctx.volumes()[2] - 1.0 / w0).abs() < 1e-15);
        let far = ctx.local_sums(2);
        assert_eq!(far.neighbours, 0);
        assert!((far.shepard - 1.0).abs() < 1e-15);
        assert_eq!(far.gradient, Point::<3>::zeros());
        let dup = ctx.local_sums(0);
        assert_eq!(dup.neighbours, 1);
        assert_eq!(dup.renormalisation, SMatrix::<f64, 3, 3>::zeros());
        assert!((dup.shepard - 1.0).abs() < 1e-15);
        let rho = summation_density(ctx.positions(), ctx.grid(), &kernel, 2.0);
        assert_eq!(ctx.divergence_of_position(2), (0.0, 0));
        assert_eq!(ctx.divergence_of_position(0), (0.0, 1));
        assert!((rho[0] - 4.0 * w0).abs() < 1e-12);
    }
}
