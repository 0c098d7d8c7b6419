//! Per-particle radii: power (Laguerre) cells instead of Voronoi cells (crate docs, "A radius
//! per particle").

use crate::cell::{self, ConvexCell};
use crate::exact_cover;
use crate::{INTERIOR_BAND, U};
use boundary_core::{DetectError, Detection, HalfSpace, ParticleSet, Point, RadiusGrid};
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
    solids: &[HalfSpace],
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
    classify(centre, r, &positions, &radii, 0.0, solids, &mut scratch).1
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
    let all: Vec<usize> = (0..count).collect();
    Ok(crate::assemble(classify_some::<D, C>(
        set,
        &all,
        radii,
        tie,
        &[],
    )?))
}

/// `(margin, label, decided by the exact predicate)` of the particles `indices` of `set`
/// (radii `radii`; every particle of `set` is a neighbour) with the closed solid half-spaces
/// `solids` covering too: each solid is one more plane of the power cell (crate docs,
/// "Solid half-spaces").
pub(crate) fn classify_some<const D: usize, C>(
    set: &ParticleSet<D>,
    indices: &[usize],
    radii: &[f64],
    tie: f64,
    solids: &[HalfSpace],
) -> Result<Vec<(f64, bool, bool)>, DetectError>
where
    C: ConvexCell<D> + Default + Send,
{
    let grid = RadiusGrid::new(set, radii)?;
    let positions = set.positions();
    Ok(indices
        .par_iter()
        .map_init(Scratch::<C, D>::default, |scratch, &i| {
            let p = positions[i];
            if boundary_core::stop::requested() {
                return Default::default();
            }
            scratch.near.clear();
            grid.for_each_reaching(&p, radii[i], |j, d2| {
                // d2 == 0: `i` itself or an exact duplicate, which does not cover.
                if d2 > 0.0 {
                    scratch.near.push((j, d2));
                }
            });
            classify(&p, radii[i], positions, radii, tie, solids, scratch)
        })
        .collect())
}

/// `(margin, label, whether the exact predicate decided)` of the particle at `p` of radius
/// `r`, whose neighbours (superset of those whose ball reaches `S_i`) are in `scratch.near`.
fn classify<const D: usize, C: ConvexCell<D>>(
    p: &Point<D>,
    r: f64,
    positions: &[Point<D>],
    radii: &[f64],
    tie: f64,
    solids: &[HalfSpace],
    scratch: &mut Scratch<C, D>,
) -> (f64, bool, bool) {
    // A solid holding the whole closed ball settles it: the sphere has no point outside it.
    for h in solids {
        let depth = h.fluid_depth(p.as_slice()) / r;
        if depth < -(1.0 + CONTAIN_SLACK) {
            return (-r, false, false);
        }
    }
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
    // A solid x_a <= c bounds the cell by −y_a <= (p_a − c)/r, x_a >= c by y_a <= (c − p_a)/r:
    // an exact normal, and an offset rounded twice (2u relative).
    for h in solids {
        let offset = h.fluid_depth(p.as_slice()) / r;
        delta = delta.max(8.0 * U * offset.abs() + 24.0 * U);
        let mut n = [0.0; D];
        n[h.axis()] = if h.solid_below() { -1.0 } else { 1.0 };
        planes.push(Plane { n, offset });
    }
    planes.sort_unstable_by(|a, b| a.offset.total_cmp(&b.offset));
    let rho0 = planes.first().map_or(1.0, |pl| pl.offset.min(1.0));
    if !(rho0 > RHO_MIN && delta < 0.25 * rho0) {
        // p_i near or outside its power cell: the general test, then the exact predicate.
        if let Some((margin, label)) = general_cell(scratch, delta, tie) {
            return (margin * r, label, false);
        }
        return exact(p, r, positions, radii, solids, scratch, 0.0);
    }
    let cell = &mut scratch.cell;
    let (reach, clips) = clip_cell(cell, planes, 1.0 - INTERIOR_BAND);
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
    exact(p, r, positions, radii, solids, scratch, margin * r)
}

/// Slack of the general case's point certificates (units of `r_i`): far above the rounding of
/// a point's plane values (a few hundred `u` for points and planes of norm at most 4).
const POINT_SLACK: f64 = 1e-11;

/// An interior point of the float cell is used as the centre of the error bound only if every
/// plane keeps it at least this far (units of `r_i`).
const CENTRE_MIN: f64 = 1e-6;

/// The general case (some power plane near or beyond `p_i`, crate docs "A radius per
/// particle"): `i` is boundary iff the power cell `C` is full-dimensional with
/// `max_C |y| > 1 > min_C |y|` (units of `r_i`). Decided from the float cell `F` where that is
/// proven, `None` otherwise:
/// - *error bound about an interior point.* `o`, the centroid of `F`'s vertices, is checked
///   against every plane; if each keeps it `s_o >= CENTRE_MIN` inside, the scaling sandwich
///   of the crate docs ("Exactness") holds about `o` with `ρ0 = s_o − δ`: `C` and `F` differ
///   by at most `β·R` in `|y|` (`R` the largest `|v − o|`), so `max_F |v| < 1 − τ` proves
///   interior (the cell within the ball);
/// - *outside the ball:* a unit `w` with `w·v >= t` for every vertex bounds `min_F |y| >= t`
///   (the vertices span `F`); `w` points at the nearest candidate (vertices, and the foot
///   `offset_j·n_j` of each plane that excludes `p_i`); `t − τ > 1` proves interior;
/// - *boundary:* two points strictly inside every plane (by `POINT_SLACK` plus the plane's
///   rounding), one beyond `S_i` and one within it: the segment between them lies in the
///   interior of `C` and crosses `S_i` there.
///
/// Returns `(margin, label)`, the margin `min(max_F |v| − 1, 1 − min bound)`.
fn general_cell<const D: usize, C: ConvexCell<D>>(
    scratch: &mut Scratch<C, D>,
    delta: f64,
    tie: f64,
) -> Option<(f64, bool)> {
    let planes = &scratch.planes;
    let cell = &mut scratch.cell;
    let (_, clips) = clip_cell(cell, planes, 0.0);
    let verts = cell.vertices();
    if cell.degenerate() || verts.len() <= D {
        return None;
    }
    let norm = |v: &[f64; D]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut o = [0.0; D];
    for v in verts {
        for k in 0..D {
            o[k] += v[k] / verts.len() as f64;
        }
    }
    let value = |pl: &Plane<D>, x: &[f64; D]| -> f64 {
        (0..D).map(|k| pl.n[k] * x[k]).sum::<f64>() - pl.offset
    };
    // Every half-space of the float cell keeps `o` inside: the planes and the box.
    let s_o = planes
        .iter()
        .map(|pl| -value(pl, &o))
        .chain(o.iter().map(|x| 1.0 - x.abs()))
        .fold(f64::INFINITY, f64::min);
    // The normal's error acts over |x − o| <= 4 (the box has diameter 2√3 < 4).
    let delta = delta + 32.0 * U;
    if s_o.is_nan() || s_o < CENTRE_MIN {
        return None;
    }
    let rho0 = s_o - delta;
    let beta = (delta + clips as f64 * (64.0 * U + cell::PLANE_EPS)) / rho0;
    let spread = verts
        .iter()
        .map(|v| norm(&std::array::from_fn(|k| v[k] - o[k])))
        .fold(0.0, f64::max);
    let tau = 2.0 * (2.0 * beta * spread * (1.0 + beta) + 8.0 * U);
    let max = verts.iter().map(norm).fold(0.0, f64::max);
    // A lower bound on min_F |y|: 0 if p_i satisfies every plane, else a separating direction.
    let min = if planes.iter().all(|pl| pl.offset >= 0.0) {
        0.0
    } else {
        let mut nearest = *verts
            .iter()
            .min_by(|a, b| norm(a).total_cmp(&norm(b)))
            .expect("the cell has vertices");
        for pl in planes.iter().filter(|pl| pl.offset < 0.0) {
            let foot: [f64; D] = std::array::from_fn(|k| pl.n[k] * pl.offset);
            if norm(&foot) < norm(&nearest) && planes.iter().all(|q| value(q, &foot) <= POINT_SLACK)
            {
                nearest = foot;
            }
        }
        let len = norm(&nearest);
        if len == 0.0 {
            0.0
        } else {
            let w: [f64; D] = std::array::from_fn(|k| nearest[k] / len);
            verts
                .iter()
                .map(|v| (0..D).map(|k| w[k] * v[k]).sum::<f64>())
                .fold(f64::INFINITY, f64::min)
                .max(0.0)
        }
    };
    let margin = (max - 1.0).min(1.0 - min);
    if tie > 0.0 {
        return Some((margin, margin > tie));
    }
    if max < 1.0 - tau || min > 1.0 + tau {
        return Some((margin, false));
    }
    // Boundary: a point beyond S_i and one within it, each strictly inside every plane.
    let inside = |x: &[f64; D]| {
        planes
            .iter()
            .all(|pl| value(pl, x) < -(POINT_SLACK + delta))
    };
    let toward_o = |v: &[f64; D], lambda: f64| -> [f64; D] {
        std::array::from_fn(|k| o[k] + lambda * (v[k] - o[k]))
    };
    let lambdas = [0.999, 0.99, 0.9, 0.5];
    let beyond = verts.iter().filter(|v| norm(v) > 1.0 + 1e-9).any(|v| {
        lambdas.iter().any(|&l| {
            let x = toward_o(v, l);
            norm(&x) > 1.0 + POINT_SLACK && inside(&x)
        })
    });
    if !beyond {
        return None;
    }

    // Within: `o`, or a vertex or the foot of a plane excluding p_i, inside the ball, pulled
    // toward `o`.
    let feet = planes
        .iter()
        .filter(|pl| pl.offset < 0.0)
        .map(|pl| -> [f64; D] { std::array::from_fn(|k| pl.n[k] * pl.offset) });
    let within = (norm(&o) < 1.0 - POINT_SLACK && inside(&o))
        || verts
            .iter()
            .copied()
            .chain(feet)
            .filter(|v| norm(v) < 1.0 - 1e-9)
            .any(|v| {
                lambdas.iter().any(|&l| {
                    let x = toward_o(&v, l);
                    norm(&x) < 1.0 - POINT_SLACK && inside(&x)
                })
            });
    within.then_some((margin, true))
}

/// Clips the box by `planes` (sorted by offset) until the next plane lies beyond every
/// vertex, or every vertex lies within `settled` (interior whatever comes next; 0: never);
/// returns the largest `|v|` and the number of clips.
fn clip_cell<const D: usize, C: ConvexCell<D>>(
    cell: &mut C,
    planes: &[Plane<D>],
    settled: f64,
) -> (f64, usize) {
    cell.reset_box();
    let mut reach = (D as f64).sqrt();
    let mut clips = 0usize;
    for pl in planes {
        if pl.offset >= reach {
            break;
        }
        cell.clip(&pl.n, pl.offset);
        clips += 1;
        reach = cell.max_norm2().sqrt();
        if reach <= settled || cell.vertices().is_empty() {
            break;
        }
    }
    (reach, clips)
}

/// The exact predicate's label, with the float margin `margin` (0 where none was measured).
fn exact<const D: usize, C>(
    p: &Point<D>,
    r: f64,
    positions: &[Point<D>],
    radii: &[f64],
    solids: &[HalfSpace],
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
        exact_cover::sphere_uncovered_in(p, r, &others, solids),
        true,
    )
}
