//! Per-particle radii: power (Laguerre) cells instead of Voronoi cells (crate docs, "A radius
//! per particle").

use crate::cell::{self, ConvexCell};
use crate::{INTERIOR_BAND, U};
use boundary_core::{exact_cover, DetectError, Detection, Labels, ParticleSet, Point, RadiusGrid};
use rayon::prelude::*;

/// The float power cell decides a particle only when every half-space it uses keeps a ball of
/// at least this radius (units of `r_i`) around `p_i`: then `p_i` lies strictly inside its
/// power cell and the Voronoi argument and error bound carry over. Closer (a larger neighbour
/// whose ball nearly holds `p_i`), the exact predicate decides.
const RHO_MIN: f64 = 1e-3;

/// A neighbour's ball holds the whole of `S_i` when `|p_j − p_i| + r_i <= r_j`; it is trusted
/// in floating point with this relative slack (far above the rounding of the distance).
const CONTAIN_SLACK: f64 = 1e-12;

/// One power plane in units of `r_i`: `n·x <= offset`, `n` a unit vector.
struct Plane<const D: usize> {
    n: [f64; D],
    offset: f64,
}

/// Per-thread working memory.
#[derive(Default)]
struct Scratch<C, const D: usize> {
    cell: C,
    near: Vec<(usize, f64)>,
    planes: Vec<Plane<D>>,
}

/// The label `exact` gives the sphere of radius `r` around `centre` covered by the closed
/// balls `others` (centre, radius): the decision of [`detect_power`] for one particle whose
/// neighbours the caller gathered (any superset of those with `|p_j − centre| <= r + r_j`).
pub(crate) fn sphere_uncovered<const D: usize, C: ConvexCell<D> + Default>(
    centre: &Point<D>,
    r: f64,
    others: &[(Point<D>, f64)],
) -> bool {
    let positions: Vec<Point<D>> = others.iter().map(|o| o.0).collect();
    let radii: Vec<f64> = others.iter().map(|o| o.1).collect();
    let mut scratch = Scratch::<C, D>::default();
    for (j, (q, rj)) in others.iter().enumerate() {
        let d2 = (q - centre).norm_squared();
        let limit = (r + rj) * (1.0 + boundary_core::radius_grid::REACH_SLACK);
        if d2 > 0.0 && d2 <= limit * limit {
            scratch.near.push((j, d2));
        }
    }
    classify(centre, r, &positions, &radii, 0.0, &mut scratch).1
}

/// Classifies the first `count` particles of `set` with radii `radii` (all particles are
/// neighbours); returns the detection and the number of particles the exact predicate decided.
pub(crate) fn detect_power<const D: usize, C>(
    set: &ParticleSet<D>,
    count: usize,
    radii: &[f64],
    tie: f64,
) -> Result<(Detection, usize), DetectError>
where
    C: ConvexCell<D> + Default + Send,
{
    let grid = RadiusGrid::new(set, radii)?;
    let positions = set.positions();
    let results: Vec<(f64, bool, bool)> = (0..count)
        .into_par_iter()
        .map_init(Scratch::<C, D>::default, |scratch, i| {
            let p = positions[i];
            scratch.near.clear();
            grid.for_each_reaching(&p, radii[i], |j, d2| {
                // d2 == 0: `i` itself or an exact duplicate, which does not cover.
                if d2 > 0.0 {
                    scratch.near.push((j, d2));
                }
            });
            classify(&p, radii[i], positions, radii, tie, scratch)
        })
        .collect();
    let fallbacks = results.iter().filter(|x| x.2).count();
    let labels = results.iter().map(|x| x.1).collect::<Labels>();
    let margins = results.into_iter().map(|x| x.0).collect();
    Ok((
        Detection {
            labels,
            margin: Some(margins),
        },
        fallbacks,
    ))
}

/// `(margin, label, whether the exact predicate decided)` of the particle at `p` of radius
/// `r`, whose neighbours (superset of those whose ball reaches `S_i`) are in `scratch.near`.
fn classify<const D: usize, C: ConvexCell<D>>(
    p: &Point<D>,
    r: f64,
    positions: &[Point<D>],
    radii: &[f64],
    tie: f64,
    scratch: &mut Scratch<C, D>,
) -> (f64, bool, bool) {
    // A neighbour whose ball holds all of S_i settles it.
    for &(j, d2) in &scratch.near {
        let held = radii[j] - d2.sqrt() - r;
        if held > CONTAIN_SLACK * (radii[j] + r) {
            return (-held.min(r), false, false);
        }
    }
    // The power planes in units of r: q = (p_j − p_i)/r, s = r_j/r,
    // q·x <= (|q|² + 1 − s²)/2, i.e. offset (|q| + (1 − s²)/|q|)/2 along the unit normal.
    // With s == 1 exactly the second term is exactly 0: the Voronoi bisector of `exact`.
    let planes = &mut scratch.planes;
    planes.clear();
    let mut delta = 24.0 * U;
    for &(j, _) in &scratch.near {
        let q: [f64; D] = std::array::from_fn(|k| (positions[j][k] - p[k]) / r);
        let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let s = radii[j] / r;
        let offset = 0.5 * len + 0.5 * ((1.0 - s * s) / len);
        // Rounding of the offset (relative errors of a few u in len, s, s², 1 − s², and the
        // quotient) and of the normal (8u over |x| <= 2), doubled.
        delta = delta.max(16.0 * U * (len + (1.0 + s * s) / len) + 24.0 * U);
        let n: [f64; D] = std::array::from_fn(|k| q[k] / len);
        planes.push(Plane { n, offset });
    }
    planes.sort_unstable_by(|a, b| a.offset.total_cmp(&b.offset));
    let rho0 = planes.first().map_or(1.0, |pl| pl.offset.min(1.0));
    if !(rho0 > RHO_MIN && delta < 0.25 * rho0) {
        // p_i near or outside its power cell: only the exact predicate decides (with `tie`
        // too: there is no float margin to compare). Margin 0: not measured.
        return exact(p, r, positions, radii, scratch, 0.0);
    }
    let cell = &mut scratch.cell;
    cell.reset_box();
    let mut reach = (D as f64).sqrt();
    let settled = 1.0 - INTERIOR_BAND;
    let mut clips = 0usize;
    for pl in planes.iter() {
        if pl.offset >= reach {
            break;
        }
        cell.clip(&pl.n, pl.offset);
        clips += 1;
        reach = cell.max_norm2().sqrt();
        if reach <= settled {
            break;
        }
    }
    let margin = reach - 1.0;
    if tie > 0.0 {
        return (margin * r, margin > tie, false);
    }
    // The bound of the crate docs ("Exactness") with the plane error `delta` in place of 24u.
    let rho = rho0 * (1.0 - 8.0 * U);
    let beta = (delta + clips as f64 * (64.0 * U + cell::PLANE_EPS)) / rho;
    let tau = 2.0 * (2.0 * beta * reach.max(1.0) + 8.0 * U);
    if !cell.degenerate() && margin.abs() > tau {
        return (margin * r, margin > 0.0, false);
    }
    exact(p, r, positions, radii, scratch, margin * r)
}

/// The exact predicate's label, with the float margin `margin` (0 where none was measured).
fn exact<const D: usize, C>(
    p: &Point<D>,
    r: f64,
    positions: &[Point<D>],
    radii: &[f64],
    scratch: &Scratch<C, D>,
    margin: f64,
) -> (f64, bool, bool) {
    let others: Vec<(Point<D>, f64)> = scratch
        .near
        .iter()
        .map(|&(j, _)| (positions[j], radii[j]))
        .collect();
    (
        margin,
        exact_cover::sphere_uncovered_power(p, r, &others),
        true,
    )
}
