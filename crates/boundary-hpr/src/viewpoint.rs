//! Viewpoint placement (Sandim 2020, Sec. 2.3.1, Alg. 1 lines 2–13, Eq. 2.3, Fig. 5).
//!
//! The viewpoint grid has cells of side `2r` anchored at the origin: the cell of `x` is
//! `floor(x_k / 2r)` on every axis, so that two domain-decomposed runs (or a run on a shifted
//! subset) see the same cells. A cell is *full* when a particle lies in it (half-open cells
//! `[k·2r, (k+1)·2r)`: a particle on a shared face belongs to the upper cell), else *empty*.
//! *Adjacent* means the `3^D − 1` cells sharing a face, an edge or a corner.

use boundary_core::{NeighbourGrid, ParticleSet, Point};
use rayon::prelude::*;

/// Fraction of `r` within which a particle disqualifies a cavity viewpoint: the thesis
/// shrinks the ball `B_r(V_i)` by 0.95 "due to the non-uniform particle distribution"
/// (Sec. 2.3.1). A particle at distance `< 0.95 r` (open ball) rejects `V_i`.
pub const CAVITY_BALL_FACTOR: f64 = 0.95;

/// A particle within `CELL_TOLERANCE · r` of a cell (of side `2r`) makes it full: a particle on
/// or next to a shared face fills both cells, so that round-off of a lattice lying on the
/// cell faces does not empty a cell (see the crate documentation, "Noise").
pub const CELL_TOLERANCE: f64 = 1e-4;

/// The neighbourhood of Eq. 2.3 (`δ_i`) is the closed ball of radius `2r·(1 + 1e-4)`: lattice
/// neighbours exactly `2r` away stay in it under round-off.
pub const NEIGHBOUR_TOLERANCE: f64 = 1e-4;

/// A `δ_i` shorter than `1e-4 · r` has no direction (the neighbourhood is symmetric up to
/// round-off): no cavity viewpoint for that particle.
pub const DIRECTION_TOLERANCE: f64 = 1e-4;

/// Where a viewpoint came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewpointKind {
    /// Centre of an empty cell adjacent to a full cell (Alg. 1 line 6).
    EmptyCell,
    /// `V_i` of Eq. 2.3 for a particle of a cavity cell (Alg. 1 line 9).
    Cavity,
}

/// A viewpoint `V` and its origin.
#[derive(Debug, Clone, PartialEq)]
pub struct Viewpoint<const D: usize> {
    /// Its position.
    pub at: Point<D>,
    /// Which rule placed it.
    pub kind: ViewpointKind,
}

/// The global cell of a point in the grid shifted by `shift` on every axis:
/// `floor((x_k − shift) / cell)` per axis.
fn cell_of<const D: usize>(p: &Point<D>, cell: f64, shift: f64) -> [i64; D] {
    std::array::from_fn(|k| ((p[k] - shift) / cell).floor() as i64)
}

/// Calls `f` for each of the `3^D − 1` cells adjacent to `c`.
fn for_each_adjacent<const D: usize>(c: &[i64; D], mut f: impl FnMut([i64; D])) {
    let total = 3usize.pow(D as u32);
    for code in 0..total {
        let mut rest = code;
        let mut n = *c;
        let mut centre = true;
        for nk in n.iter_mut() {
            let off = (rest % 3) as i64 - 1;
            rest /= 3;
            *nk += off;
            centre &= off == 0;
        }
        if !centre {
            f(n);
        }
    }
}

/// All viewpoints of Alg. 1, in a deterministic order: empty-cell centres sorted by cell,
/// then cavity viewpoints by particle index.
///
/// `grid` is a neighbour grid over `set` (any cell size); `r` the resolution; `shift` moves
/// the cell grid by that much on every axis (0: anchored at the origin). With
/// `cavity = false` only the empty-cell viewpoints are placed.
///
/// Our reading of the cavity rule (the thesis leaves these open):
/// - a *cavity cell* is a full cell all of whose `3^D − 1` adjacent cells are full
///   (condition (a)); condition (b), "a ball of radius `r` centred in `C` contains no
///   particle", is tested only at the candidates `V_i` of Eq. 2.3, one per particle of `C`,
///   as Alg. 1 does;
/// - `δ_i = p_i − mean(p_j)` over the particles `j ≠ i` within `2r` of `p_i` (closed ball;
///   including `i` itself would only rescale `δ_i`, which is normalised; the ball is widened
///   by [`NEIGHBOUR_TOLERANCE`]). A particle with no such neighbour or with
///   `|δ_i| <= `[`DIRECTION_TOLERANCE`]` · r` gets no candidate;
/// - `V_i` is kept when no particle lies at distance `< 0.95 r` from it, even if `V_i` falls
///   outside `C` (Fig. 5 shows cavity viewpoints at the cavity's edge; the thesis only asks
///   for the emptiness of the ball).
pub fn place_viewpoints<const D: usize>(
    set: &ParticleSet<D>,
    grid: &NeighbourGrid<D>,
    r: f64,
    cavity: bool,
    shift: f64,
) -> Vec<Viewpoint<D>> {
    let cell = 2.0 * r;
    let eps = CELL_TOLERANCE * r;
    // Every (full cell, particle) pair, sorted by cell then particle: the particles of a full
    // cell are one run. Built and sorted in parallel (no serial pass over the particles).
    let mut pairs: Vec<([i64; D], u32)> = set
        .positions()
        .par_iter()
        .enumerate()
        .flat_map_iter(|(i, p)| {
            // The cell of p, and the cells whose closure lies within eps of p (p within eps
            // of a face, edge or corner): all of them are full.
            let c = cell_of(p, cell, shift);
            let mut near = [c; 8];
            let mut len = 1;
            for k in 0..D {
                let offset = (p[k] - shift) - c[k] as f64 * cell;
                let step = if offset <= eps {
                    -1
                } else if cell - offset <= eps {
                    1
                } else {
                    continue;
                };
                for m in 0..len {
                    near[len + m] = near[m];
                    near[len + m][k] += step;
                }
                len *= 2;
            }
            near.into_iter().take(len).map(move |n| (n, i as u32))
        })
        .collect();
    pairs.par_sort_unstable();
    // The full cells (sorted, distinct) and where each one's run of particles starts.
    let starts: Vec<usize> = (0..pairs.len())
        .into_par_iter()
        .filter(|&k| k == 0 || pairs[k - 1].0 != pairs[k].0)
        .collect();
    let full: Vec<[i64; D]> = starts.par_iter().map(|&k| pairs[k].0).collect();
    let is_full = |n: &[i64; D]| full.binary_search(n).is_ok();
    // Per full cell: its empty adjacent cells, and whether it is a cavity cell (every
    // adjacent cell full).
    let (mut empty, cavity_cells): (Vec<[i64; D]>, Vec<usize>) = full
        .par_iter()
        .enumerate()
        .fold(
            || (Vec::new(), Vec::new()),
            |(mut empty, mut cavities), (k, c)| {
                let before = empty.len();
                for_each_adjacent(c, |n| {
                    if !is_full(&n) {
                        empty.push(n);
                    }
                });
                if empty.len() == before {
                    cavities.push(k);
                }
                (empty, cavities)
            },
        )
        .reduce(
            || (Vec::new(), Vec::new()),
            |(mut e, mut c), (e2, c2)| {
                e.extend(e2);
                c.extend(c2);
                (e, c)
            },
        );
    empty.par_sort_unstable();
    empty.dedup();
    let mut out: Vec<Viewpoint<D>> = empty
        .par_iter()
        .map(|c| Viewpoint {
            at: Point::<D>::from_fn(|k, _| (c[k] as f64 + 0.5) * cell + shift),
            kind: ViewpointKind::EmptyCell,
        })
        .collect();
    if cavity {
        let run = |k: usize| {
            let end = starts.get(k + 1).copied().unwrap_or(pairs.len());
            pairs[starts[k]..end].iter().map(|&(_, i)| i)
        };
        let mut members: Vec<u32> = cavity_cells.par_iter().flat_map_iter(|&k| run(k)).collect();
        members.par_sort_unstable();
        members.dedup();
        let positions = set.positions();
        let found: Vec<Point<D>> = {
            members
                .par_iter()
                .filter_map(|&i| {
                    if boundary_core::stop::requested() {
                        return None;
                    }
                    cavity_viewpoint(positions, grid, i as usize, r)
                })
                .collect()
        };
        out.extend(found.into_iter().map(|at| Viewpoint {
            at,
            kind: ViewpointKind::Cavity,
        }));
    }
    out
}

/// `V_i` of Eq. 2.3 when its ball of radius `0.95 r` holds no particle, else `None`.
pub fn cavity_viewpoint<const D: usize>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    i: usize,
    r: f64,
) -> Option<Point<D>> {
    let p = positions[i];
    let mut sum = Point::<D>::zeros();
    let mut count = 0usize;
    grid.for_each_within(&p, 2.0 * r * (1.0 + NEIGHBOUR_TOLERANCE), |j, _| {
        if j != i {
            sum += positions[j];
            count += 1;
        }
    });
    if count == 0 {
        return None;
    }
    let delta = p - sum / count as f64;
    let norm = delta.norm();
    if norm <= DIRECTION_TOLERANCE * r || !norm.is_finite() {
        return None;
    }
    let v = p + delta * (r / norm);
    let limit = CAVITY_BALL_FACTOR * r;
    let mut empty = true;
    grid.for_each_within(&v, limit, |_, d2| {
        if d2 < limit * limit {
            empty = false;
        }
    });
    empty.then_some(v)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_anchored_at_the_origin() {
        assert_eq!(cell_of(&Point::<2>::new(0.0, -0.1), 2.0, 0.0), [0, -1]);
        assert_eq!(cell_of(&Point::<2>::new(2.0, 3.99), 2.0, 0.0), [1, 1]);
        // Shifted by half a cell: cell 0 is [1, 3).
        assert_eq!(cell_of(&Point::<2>::new(0.99, 1.0), 2.0, 1.0), [-1, 0]);
    }

    #[test]
    fn adjacency_is_the_moore_neighbourhood() {
        let mut n2 = 0;
        for_each_adjacent(&[0i64, 0], |_| n2 += 1);
        let mut n3 = 0;
        for_each_adjacent(&[5i64, 0, -3], |c| {
            assert_ne!(c, [5, 0, -3]);
            n3 += 1;
        });
        assert_eq!((n2, n3), (8, 26));
    }

    #[test]
    fn one_particle_gets_eight_surrounding_viewpoints() {
        let set = ParticleSet::from_rows(&[[0.5, 0.5]]).unwrap();
        let grid = NeighbourGrid::new(&set, 2.0).unwrap();
        let v = place_viewpoints(&set, &grid, 1.0, true, 0.0);
        assert_eq!(v.len(), 8);
        assert!(v.iter().all(|v| v.kind == ViewpointKind::EmptyCell));
        assert!(v.iter().any(|v| v.at == Point::<2>::new(-1.0, -1.0)));
        // The grid shifted by r = 1: the particle's cell is [-1, 1)², centred at the origin;
        // its neighbours' centres are 2 away on each axis.
        let v = place_viewpoints(&set, &grid, 1.0, true, 1.0);
        assert_eq!(v.len(), 8);
        assert!(v.iter().any(|v| v.at == Point::<2>::new(-2.0, -2.0)));
        assert!(v.iter().any(|v| v.at == Point::<2>::new(2.0, 0.0)));
        assert!(!v.iter().any(|v| v.at == Point::<2>::new(0.0, 0.0)));
    }
}
