#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Exact r-boundary detection by restricted Voronoi cells: the reference labels of the project.
//!
//! # Definition
//! Particle `i` at `p_i` with resolution `r` is *interior* iff its sphere `S_i` (radius `r`)
//! is covered by the closed balls `B_j` of radius `r` of the other particles within `2r`;
//! otherwise it is *boundary* (Sandim et al., JCP 2020, Sec. 2; thesis Sec. 2.1).
//!
//! # Why the Voronoi cell decides it
//! Let `V_i` be the Voronoi cell of `p_i` among the particles within `2r` (exact duplicates of
//! `p_i` excluded, see below): the points at least as close to `p_i` as to any of them.
//!
//! *Claim:* `i` is boundary iff `max_{x in V_i} |x − p_i| > r`.
//!
//! - A point `x` of `S_i` is uncovered iff `|x − p_j| > r = |x − p_i|` for every `j`, i.e. iff
//!   `x` is strictly closer to `p_i` than to every other particle: `x` lies in the interior of
//!   `V_i`. (Particles farther than `2r` cannot cover a point of `S_i` anyway.)
//! - If `V_i` reaches a point `v` with `|v − p_i| > r`, the segment from `p_i` (an interior point
//!   of `V_i`, since no other particle coincides with it) to `v` crosses `S_i` at some `x`; every
//!   point of that half-open segment is interior to the convex set `V_i`, so `x` is uncovered.
//! - Conversely, an uncovered `x` on `S_i` lies in `V_i`, so `max |x − p_i| >= r`, and being
//!   interior, points slightly beyond it along the ray are in `V_i` too: the maximum exceeds `r`.
//!
//! This is the union-of-balls / alpha-shape picture: the boundary particles are those whose
//! Voronoi cell is not contained in their own ball, i.e. whose ball contributes to the boundary
//! of the union of balls of radius `r`.
//!
//! # Algorithm
//! Per particle, in coordinates relative to `p_i` and scaled by `1/r` (so scenes at `1e6` with
//! `r = 0.01` lose no precision to the offset): start from the box `[-1, 1]^D`, which contains
//! the whole ball; clip it by the bisector half-spaces `q_j·x <= |q_j|²/2` of the neighbours
//! within `2r` taken nearest first; stop when the next bisector lies beyond the farthest vertex
//! (`|q_j|/2 >= max |v|`: no remaining neighbour can cut). The margin is
//! `(max |v| − 1)·r`. Clipping also stops once every vertex is within `(1 − 1e-6)·r`
//! ([`INTERIOR_BAND`]): the particle is interior whatever comes next, so margins below
//! `−1e-6·r` are upper bounds, not exact values. The 2D cell is a polygon, the 3D cell a polyhedron
//! (see `cell.rs`). Particles are processed in parallel with rayon; each particle is
//! independent, so the labels do not depend on the number of threads.
//!
//! # Policy: ties, duplicates, degenerate input
//! - **Ties.** A cell that reaches exactly to `r` touches `S_i` only at points equidistant from
//!   `p_i` and another particle, which the closed ball of that particle covers: a tie is
//!   *interior*. In floating point a particle is boundary iff its margin exceeds
//!   [`TIE_TOLERANCE`]`·r`; margins within `±TIE_TOLERANCE·r` are near-ties, classified interior.
//!   Perfect lattices at `r = a/√2` (2D) and `r = a·√3/2` (3D) are exact ties for every
//!   interior particle, and come out interior.
//! - **Duplicates.** Particles at exactly the same position as `p_i` do not cover `S_i`: they are
//!   ignored when building `V_i`. Two coincident particles alone are both boundary.
//!   Near-duplicates (distinct positions, however close) are ordinary neighbours.
//! - **Clipping tolerance.** Vertices within `1e-12·r` of a clipping plane count as on it
//!   (`cell::PLANE_EPS`); this can shift a margin by about `1e-12·r`, well inside the tie band.
//! - **Margins saturate.** The cell starts as the box `[p_i − r, p_i + r]`, so a particle with
//!   no neighbour has margin `(√D − 1)·r`, the largest possible.
//! - Neighbours at exactly `2r` are included (closed), though their ball only touches `S_i`.
//!
//! # Hard cases
//! What `exact` returns on the hard cases of issue 11 (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`):
//! - Perfect lattices at the tie radius (`a/√2` in 2D, `a·√3/2` in 3D) and 4 ulps either side
//!   of it: interior particles are interior (near-ties, within [`TIE_TOLERANCE`]`·r`).
//! - Exact duplicates: each copy gets the label of the single particle (a doubled 5³ lattice at
//!   `r = 1.2`: the 98 surface positions, twice). Near-duplicates 1e-12 apart are neighbours
//!   like any other, and a twin covers the half of `S_i` facing it, so 18 of those 196 copies
//!   become interior: correct by the definition.
//! - A single particle, two particles (coincident, or exactly `2r` apart), lines, and
//!   collinear or coplanar sets in 3D: every particle boundary.
//! - Offsets of 1e6 and 1e9 at `r = 0.01`, and `r` from 1e-9 to 1e9: the labels of the same
//!   lattice at the origin and unit scale. Empty input: empty labels.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_exact::ExactDetector;
//!
//! // A 5 x 5 square lattice of spacing 1 at r = 0.8: only the centre 3 x 3 block is interior.
//! let rows: Vec<[f64; 2]> = (0..25).map(|k| [(k % 5) as f64, (k / 5) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let detection = ExactDetector::default().detect_2d(&set, Radius::new(0.8).unwrap()).unwrap();
//! assert_eq!(detection.labels.boundary_count(), 16);
//! assert!(!detection.labels.is_boundary(12)); // the centre
//! ```

mod cell;

use boundary_core::{
    AnyParticleSet, BoundaryDetector, DetectError, Detection, Labels, NeighbourGrid, ParamError,
    Params, ParticleSet, Point, Radius,
};
use cell::{ConvexCell, Polygon, Polyhedron};
use rayon::prelude::*;

/// Relative tie band: a particle is boundary iff its margin exceeds `TIE_TOLERANCE · r`.
/// Cells reaching beyond `r` by less than this are near-ties and classified interior.
pub const TIE_TOLERANCE: f64 = 1e-9;

/// Clipping stops once every vertex lies within `(1 − INTERIOR_BAND)·r`: the particle is then
/// interior by at least `INTERIOR_BAND·r` whatever the remaining neighbours do. Reported
/// margins are exact above `−INTERIOR_BAND·r` and upper bounds below it.
pub const INTERIOR_BAND: f64 = 1e-6;

/// Neighbours are sorted lazily: the nearest `FIRST_BATCH` first, which settle most interior
/// particles (a jittered cubic lattice needs about 6 to 10), the rest only when needed.
const FIRST_BATCH: usize = 16;

/// The exact detector (`exact`): restricted Voronoi cells. See the crate documentation.
#[derive(Debug, Clone, Default)]
pub struct ExactDetector;

impl ExactDetector {
    /// The detector (it has no parameters).
    pub fn new() -> Self {
        ExactDetector
    }
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(ExactDetector);

impl BoundaryDetector for ExactDetector {
    fn name(&self) -> &'static str {
        "exact"
    }

    fn params(&self) -> Params {
        Params::default()
    }

    fn set_param(&mut self, key: &str, _value: &str) -> Result<(), ParamError> {
        Err(ParamError::unknown("exact", key, &[]))
    }

    fn certified(&self) -> bool {
        true
    }

    fn detect_2d(&self, set: &ParticleSet<2>, r: Radius) -> Result<Detection, DetectError> {
        detect_with::<2, Polygon>(set, set.len(), r)
    }

    fn detect_3d(&self, set: &ParticleSet<3>, r: Radius) -> Result<Detection, DetectError> {
        detect_with::<3, Polyhedron>(set, set.len(), r)
    }

    /// Classifies only the owned particles; the ghosts serve as neighbours only. A halo of
    /// [`BoundaryDetector::halo_width`] = `2r` gives the global labels.
    fn detect_owned(
        &self,
        set: &AnyParticleSet,
        owned: usize,
        r: Radius,
    ) -> Result<Detection, DetectError> {
        DetectError::check_owned("exact", owned, set.len())?;
        match set {
            AnyParticleSet::D2(s) => detect_with::<2, Polygon>(s, owned, r),
            AnyParticleSet::D3(s) => detect_with::<3, Polyhedron>(s, owned, r),
        }
    }
}

/// Per-thread working memory.
#[derive(Default)]
struct Scratch<C> {
    cell: C,
    neighbours: Vec<(f64, usize)>,
}

/// Classifies the first `count` particles of `set` (all of them are neighbours).
fn detect_with<const D: usize, C>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
) -> Result<Detection, DetectError>
where
    C: ConvexCell<D> + Default + Send,
{
    let r = r.get();
    // Cells of side r, queried at 2r: the 5^D visited cells hold fewer non-neighbours than
    // the 3^D cells of side 2r (1M-particle ball, 1 thread: 3.6 s -> 3.35 s).
    let grid = NeighbourGrid::new(set, r)?;
    let margins: Vec<f64> = (0..count)
        .into_par_iter()
        .map_init(Scratch::<C>::default, |scratch, i| {
            cell_margin(set.positions(), &grid, i, r, scratch) * r
        })
        .collect();
    let labels = margins
        .iter()
        .map(|&m| m > TIE_TOLERANCE * r)
        .collect::<Labels>();
    Ok(Detection {
        labels,
        margin: Some(margins),
    })
}

/// `max |v| − 1` over the vertices of particle `i`'s restricted Voronoi cell, in units of `r`.
fn cell_margin<const D: usize, C: ConvexCell<D>>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    i: usize,
    r: f64,
    scratch: &mut Scratch<C>,
) -> f64 {
    let p = positions[i];
    let neighbours = &mut scratch.neighbours;
    neighbours.clear();
    grid.for_each_within(&p, 2.0 * r, |j, d2| {
        // d2 == 0: `i` itself or an exact duplicate, which does not cover (crate docs).
        if d2 > 0.0 {
            neighbours.push((d2, j));
        }
    });
    let by_distance = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    let first = FIRST_BATCH.min(neighbours.len());
    if first < neighbours.len() {
        neighbours.select_nth_unstable_by(first, by_distance);
    }
    neighbours[..first].sort_unstable_by(by_distance);

    let cell = &mut scratch.cell;
    cell.reset_box();
    let mut reach = (D as f64).sqrt();
    let settled = 1.0 - INTERIOR_BAND;
    for k in 0..neighbours.len() {
        if k == first {
            neighbours[first..].sort_unstable_by(by_distance);
        }
        let j = neighbours[k].1;
        let q: [f64; D] = std::array::from_fn(|k| (positions[j][k] - p[k]) / r);
        let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let offset = 0.5 * len;
        if offset >= reach {
            // Sorted nearest first: no remaining bisector can reach the cell.
            break;
        }
        let n: [f64; D] = std::array::from_fn(|k| q[k] / len);
        cell.clip(&n, offset);
        reach = cell.max_norm2().sqrt();
        if reach <= settled {
            break;
        }
    }
    reach - 1.0
}
