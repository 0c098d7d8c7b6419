//! The local HPR visibility test (Sandim 2020, Sec. 2.2 and 2.3.2; Katz, Tal & Basri 2007).

use crate::hull;
use boundary_core::Point;
use rustc_hash::FxHashMap;

/// Exponential flipping, Eq. 2.2: `f(p) = p / |p|^γ` for `0 < |p| <= 1`, and `f(0) = 0`.
///
/// For `γ > 1` it maps the unit ball onto the outside of the unit ball, reversing the order
/// of distances along each ray from the viewpoint (the origin): the nearest point goes
/// farthest.
pub fn flip_exponential<const D: usize>(p: &Point<D>, gamma: f64) -> Point<D> {
    let n = p.norm();
    if n == 0.0 {
        Point::<D>::zeros()
    } else {
        p / n.powf(gamma)
    }
}

/// Relative margin by which a cell's box must stay below a level before its points are
/// skipped (the rounding of `n·q` and of the box's support is a few ulps of `Σ_j |q_j|`).
const BOX_MARGIN: f64 = 1e-9;

/// The points (flips and the origin) sorted into a uniform grid over their bounding box,
/// about eight per cell, with each cell's own bounding box: `n·q` over a cell is at most the
/// support of its box, so a scan for points above a level along `n` visits only the cells
/// whose box reaches it.
struct FlipBoxes<const D: usize> {
    /// Point indices grouped by cell; cell `c` holds `points[start[c]..start[c + 1]]`.
    points: Vec<usize>,
    start: Vec<usize>,
    /// Per non-empty cell: its index, its box (low, high corners) and `Σ_j max(|lo_j|, |hi_j|)`.
    cells: Vec<(usize, [f64; 3], [f64; 3], f64)>,
}

impl<const D: usize> FlipBoxes<D> {
    fn new(all: &[Point<D>]) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for q in all {
            for j in 0..D {
                lo[j] = lo[j].min(q[j]);
                hi[j] = hi[j].max(q[j]);
            }
        }
        let side = ((all.len() as f64 / 8.0).powf(1.0 / D as f64).ceil() as usize).clamp(1, 32);
        let cell_of = |q: &Point<D>| {
            let mut c = 0usize;
            for j in 0..D {
                let w = hi[j] - lo[j];
                let k = if w > 0.0 {
                    (((q[j] - lo[j]) / w * side as f64) as usize).min(side - 1)
                } else {
                    0
                };
                c = c * side + k;
            }
            c
        };
        let total = side.pow(D as u32);
        let mut start = vec![0usize; total + 1];
        let ids: Vec<usize> = all.iter().map(cell_of).collect();
        for &c in &ids {
            start[c + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut points = vec![0usize; all.len()];
        for (m, &c) in ids.iter().enumerate() {
            points[fill[c]] = m;
            fill[c] += 1;
        }
        let cells = (0..total)
            .filter(|&c| start[c + 1] > start[c])
            .map(|c| {
                let mut l = [0.0; 3];
                let mut h = [0.0; 3];
                for j in 0..D {
                    l[j] = f64::INFINITY;
                    h[j] = f64::NEG_INFINITY;
                }
                for &m in &points[start[c]..start[c + 1]] {
                    for j in 0..D {
                        l[j] = l[j].min(all[m][j]);
                        h[j] = h[j].max(all[m][j]);
                    }
                }
                let size = (0..D).map(|j| l[j].abs().max(h[j].abs())).sum::<f64>();
                (c, l, h, size)
            })
            .collect();
        FlipBoxes {
            points,
            start,
            cells,
        }
    }

    /// The points of every cell whose box may reach `level` along the unit vector `n`: a
    /// superset of the points with `n·q >= level` (computed in floating point).
    fn reaching<'a>(&'a self, n: &'a [f64; 3], level: f64) -> impl Iterator<Item = usize> + 'a {
        self.cells
            .iter()
            .filter(move |(_, l, h, size)| {
                let support = (0..D).map(|j| (n[j] * l[j]).max(n[j] * h[j])).sum::<f64>();
                support + BOX_MARGIN * (size + 1.0) >= level
            })
            .flat_map(move |&(c, ..)| {
                self.points[self.start[c]..self.start[c + 1]]
                    .iter()
                    .copied()
            })
    }
}

/// How the visible set of one viewpoint was decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HullOutcome {
    /// At most `D` distinct candidates: all visible without a hull.
    Trivial,
    /// A full-dimensional hull of the flipped candidates and the viewpoint.
    Hull,
    /// The flipped candidates and the viewpoint lie on one line (2D) or plane (3D): there is
    /// no full-dimensional hull and every candidate is visible (a flat set's particles are
    /// all boundary by the covering definition: nothing covers them off the line/plane).
    Flat,
}

/// Which of the `points` (already moved so that the viewpoint is the origin, and scaled into
/// the unit ball) are visible from the origin: the vertices of the convex hull of their
/// exponential flips plus the origin (Katz et al. 2007) that protrude from the hull of all
/// the other flipped points by more than `tol`. Writes one flag per point into `visible`.
///
/// The hull is exact ([`crate::hull`]: exact orientation predicates), so which points are
/// hull vertices does not depend on rounding. A point on a facet or edge that is not a corner
/// is not visible (as with Qhull's vertices). The protrusion of a corner `v` is measured along
/// its vertex normal `n` (the normalised sum of the unit normals of its facets, or edges in
/// 2D): `n·v − max_{q≠v} n·q`, a lower bound of its distance to the hull of the others,
/// computed in floating point. A corner whose protrusion is at most `tol` is a near-tie
/// (a point within round-off of a facet of the others) and counts as hidden; with `tol ≫`
/// the round-off of the input the labels do not change under it (crate documentation,
/// "Noise"). `tol = 0` keeps every corner that protrudes at all along its vertex normal.
///
/// Degenerate input: exact duplicates flip to the same point and share their flag, and
/// near-twins (flips within `tol` of a visible corner) are visible with it; with at most `D`
/// distinct points all are visible ([`HullOutcome::Trivial`]); a flat set (all on one line
/// through the origin in 2D, one plane through it in 3D, or flips at most `tol` thick along
/// a facet normal, which is what rounding makes of such a set) is all visible
/// ([`HullOutcome::Flat`]).
///
/// Cost: the hull is `O(k log k)` for `k` candidates. The flatness and protrusion tests are
/// defined by scans of all `k` points per facet and per corner (`O(k·h)` for `h` corners);
/// they are computed with early exits and a grid of cell boxes over the flips that skips the
/// cells whose box stays below the level in question, with a margin for rounding, so the
/// decisions are those of the full scans (tested against them) at a fraction of the cost on
/// dense neighbourhoods (crate documentation, "Cost").
pub fn visible_from_origin<const D: usize>(
    points: &[Point<D>],
    gamma: f64,
    tol: f64,
    visible: &mut Vec<bool>,
) -> HullOutcome {
    visible_with_scan(points, gamma, tol, visible, Scan::Pruned)
}

/// How the points are scanned after the hull: the decisions are the same (tested on dense
/// and near-tie sets against `Full`, the definition); `Pruned` visits fewer points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scan {
    /// Every point for every facet and corner (the definitions, quadratic in the number of
    /// candidates: on dense sets, with thousands of candidates per viewpoint, most of the time
    /// would go here).
    #[cfg_attr(not(test), allow(dead_code))]
    Full,
    /// Early exits, and only the cells of [`FlipBoxes`] that can reach a level.
    Pruned,
}

fn visible_with_scan<const D: usize>(
    points: &[Point<D>],
    gamma: f64,
    tol: f64,
    visible: &mut Vec<bool>,
    scan: Scan,
) -> HullOutcome {
    visible.clear();
    visible.resize(points.len(), true);
    // Exact duplicates share one flip and one flag: `first[i]` is the lowest index with the
    // coordinates of point `i`; the hull's input is the distinct points in index order.
    // (A hash of the coordinates' bits, `-0.0` read as `0.0`: equal coordinates, equal key.)
    let mut lowest: FxHashMap<[u64; D], usize> = FxHashMap::default();
    lowest.reserve(points.len());
    let first: Vec<usize> = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            *lowest
                .entry(std::array::from_fn(|k| (p[k] + 0.0).to_bits()))
                .or_insert(i)
        })
        .collect();
    let distinct: Vec<usize> = (0..points.len()).filter(|&i| first[i] == i).collect();
    if distinct.len() <= D {
        return HullOutcome::Trivial;
    }
    let mut slot = vec![0usize; points.len()];
    for (k, &i) in distinct.iter().enumerate() {
        slot[i] = k;
    }
    let flipped: Vec<Point<D>> = distinct
        .iter()
        .map(|&i| flip_exponential(&points[i], gamma))
        .collect();
    // Per hull corner, the sum of the unit outward normals of its facets (edges in 2D).
    let mut normal_sum: Vec<[f64; 3]> = vec![[0.0; 3]; flipped.len() + 1];
    let mut is_corner = vec![false; flipped.len() + 1];
    // Each facet's unit outward normal and one of its corners.
    let mut facet_normals: Vec<[f64; 3]> = Vec::new();
    let mut facet_anchor: Vec<usize> = Vec::new();
    let mut add = |i: usize, n: [f64; 3]| {
        is_corner[i] = true;
        for k in 0..3 {
            normal_sum[i][k] += n[k];
        }
    };
    match D {
        2 => {
            let mut pts: Vec<[f64; 2]> = flipped.iter().map(|f| [f[0], f[1]]).collect();
            pts.push([0.0; 2]);
            let Some(h) = hull::hull_2d(&pts) else {
                return HullOutcome::Flat;
            };
            for k in 0..h.len() {
                let (i, j) = (h[k], h[(k + 1) % h.len()]);
                let (dx, dy) = (pts[j][0] - pts[i][0], pts[j][1] - pts[i][1]);
                let len = dx.hypot(dy);
                let n = [dy / len, -dx / len, 0.0];
                add(i, n);
                add(j, n);
                facet_normals.push(n);
                facet_anchor.push(i);
            }
        }
        3 => {
            let mut pts: Vec<[f64; 3]> = flipped.iter().map(|f| [f[0], f[1], f[2]]).collect();
            pts.push([0.0; 3]);
            let Some(h) = hull::hull_3d(&pts) else {
                return HullOutcome::Flat;
            };
            for t in &h {
                let (a, b, c) = (pts[t[0]], pts[t[1]], pts[t[2]]);
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                // Counter-clockwise from outside: u × w points outward.
                let x = [
                    u[1] * w[2] - u[2] * w[1],
                    u[2] * w[0] - u[0] * w[2],
                    u[0] * w[1] - u[1] * w[0],
                ];
                let len = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                let n = if len > 0.0 {
                    [x[0] / len, x[1] / len, x[2] / len]
                } else {
                    [0.0; 3]
                };
                t.iter().for_each(|&i| add(i, n));
                facet_normals.push(n);
                facet_anchor.push(t[0]);
            }
        }
        // Only 2D and 3D particle sets exist; any other dimension is all visible.
        _ => return HullOutcome::Flat,
    }
    let origin: Point<D> = Point::<D>::zeros();
    let point = |k: usize| {
        if k == flipped.len() {
            &origin
        } else {
            &flipped[k]
        }
    };
    let dot = |n: &[f64; 3], q: &Point<D>| (0..D).map(|j| n[j] * q[j]).sum::<f64>();
    // Flat within the tolerance: a facet (edge) normal along which the whole set is at most
    // `tol` thick. The flips of candidates that are coplanar (collinear) with the viewpoint
    // in exact arithmetic are so only up to the rounding of the flip; they are the flat case.
    // `top - min_m n·q_m <= tol` is `top - n·q_m <= tol` for every m (rounded subtraction is
    // monotone), so one point farther than `tol` below the facet settles it: the origin,
    // then the flips in order.
    for (k, n) in facet_normals.iter().enumerate() {
        if *n == [0.0; 3] {
            continue;
        }
        let top = dot(n, point(facet_anchor[k]));
        let thick = match scan {
            Scan::Full => {
                let low = (0..=flipped.len())
                    .map(|m| dot(n, point(m)))
                    .fold(f64::INFINITY, f64::min);
                top - low > tol
            }
            Scan::Pruned => std::iter::once(flipped.len())
                .chain(0..flipped.len())
                .any(|m| top - dot(n, point(m)) > tol),
        };
        if !thick {
            return HullOutcome::Flat;
        }
    }
    // A corner is visible when it protrudes by more than `tol`, along its vertex normal (the
    // normalised sum of its facets' normals), from all the other points except its near-twins
    // (flips within `tol` of it, which share its label): a lower bound of its distance to the
    // hull of the others.
    //
    // `top - max_m n·q_m > tol` is `top - n·q_m > tol` for every m, so a corner is hidden by
    // the first point within `tol` of its level that is not a near-twin. Only points in a
    // cell of `boxes` whose box reaches that level along `n` can be that point: the others
    // are skipped (with a margin for rounding, so that no point the full scan would meet is
    // skipped; see [`FlipBoxes`]).
    let near = |a: &Point<D>, b: &Point<D>| (a - b).norm() <= tol;
    let boxes = (scan == Scan::Pruned).then(|| {
        let all: Vec<Point<D>> = (0..=flipped.len()).map(|m| *point(m)).collect();
        FlipBoxes::new(&all)
    });
    let mut seen: Vec<bool> = (0..flipped.len())
        .map(|k| {
            if !is_corner[k] {
                return false;
            }
            let s = normal_sum[k];
            let len = (0..D).map(|j| s[j] * s[j]).sum::<f64>().sqrt();
            if len <= 0.0 || !len.is_finite() {
                return true;
            }
            let n = [s[0] / len, s[1] / len, s[2] / len];
            let top = dot(&n, &flipped[k]);
            match &boxes {
                None => {
                    let rest = (0..=flipped.len())
                        .filter(|&m| m != k && !near(point(m), &flipped[k]))
                        .map(|m| dot(&n, point(m)))
                        .fold(f64::NEG_INFINITY, f64::max);
                    top - rest > tol
                }
                Some(boxes) => !boxes.reaching(&n, top - tol).any(|m| {
                    m != k && top - dot(&n, point(m)) <= tol && !near(point(m), &flipped[k])
                }),
            }
        })
        .collect();
    // Near-twins of a visible corner are visible too. A near-twin differs by at most `tol`
    // (2·tol after rounding) in its first coordinate: the visible corners sorted by it give
    // each point the few corners to test.
    let mut visible_corners: Vec<usize> = (0..flipped.len()).filter(|&k| seen[k]).collect();
    visible_corners.sort_unstable_by(|&a, &b| flipped[a][0].total_cmp(&flipped[b][0]));
    for k in 0..flipped.len() {
        if seen[k] {
            continue;
        }
        let x = flipped[k][0];
        let start = match scan {
            Scan::Full => 0,
            Scan::Pruned => visible_corners.partition_point(|&c| flipped[c][0] - x < -2.0 * tol),
        };
        if visible_corners[start..]
            .iter()
            .take_while(|&&c| scan == Scan::Full || flipped[c][0] - x <= 2.0 * tol)
            .any(|&c| near(&flipped[c], &flipped[k]))
        {
            seen[k] = true;
        }
    }
    for (i, v) in visible.iter_mut().enumerate() {
        *v = seen[slot[first[i]]];
    }
    HullOutcome::Hull
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn flipping_reverses_distances_along_a_ray() {
        let near = flip_exponential(&Point::<2>::new(0.1, 0.0), 1.3);
        let far = flip_exponential(&Point::<2>::new(0.9, 0.0), 1.3);
        assert!(near.norm() > far.norm() && far.norm() > 1.0);
        assert_eq!(
            flip_exponential(&Point::<3>::zeros(), 1.3),
            Point::<3>::zeros()
        );
    }

    #[test]
    fn a_point_hidden_behind_another_is_not_visible() {
        // From the origin, (0.5, 0) hides (0.9, 0); (0, 0.5) is seen.
        let pts = [
            Point::<2>::new(0.5, 0.0),
            Point::<2>::new(0.9, 0.0),
            Point::<2>::new(0.0, 0.5),
            Point::<2>::new(0.5, 0.05),
        ];
        let mut vis = Vec::new();
        let out = visible_from_origin(&pts, 1.3, 1e-3, &mut vis);
        assert_eq!(out, HullOutcome::Hull);
        assert_eq!(vis, vec![true, false, true, true]);
        // The same in 3D, with a point straight behind another.
        let pts = [
            Point::<3>::new(0.5, 0.0, 0.0),
            Point::<3>::new(0.9, 0.0, 0.0),
            Point::<3>::new(0.0, 0.5, 0.0),
            Point::<3>::new(0.0, 0.0, 0.5),
            Point::<3>::new(0.4, 0.3, 0.2),
        ];
        let out = visible_from_origin(&pts, 1.3, 1e-3, &mut vis);
        assert_eq!(out, HullOutcome::Hull);
        assert_eq!(vis, vec![true, false, true, true, true]);
    }

    #[test]
    fn a_corner_within_the_tolerance_of_the_others_hull_is_hidden() {
        // The middle of three points near x = 0.5, `e` in front of (e > 0) or behind the
        // line of the outer two. Flipped (gamma 1.3), the outer two lie on x = 1.118 and the
        // middle one at x = (0.5 - e)^-0.3.
        let mid = |e: f64| {
            [
                Point::<2>::new(0.5, -0.2),
                Point::<2>::new(0.5 - e, 0.0),
                Point::<2>::new(0.5, 0.2),
            ]
        };
        let mut vis = Vec::new();
        // e = 0.05: flipped to x = 1.27, it protrudes by about 0.15: visible.
        visible_from_origin(&mid(0.05), 1.3, 1e-3, &mut vis);
        assert_eq!(vis, vec![true, true, true]);
        // The same protrusion against a tolerance of 0.2: hidden; the outer two stay.
        visible_from_origin(&mid(0.05), 1.3, 0.2, &mut vis);
        assert_eq!(vis, vec![true, false, true]);
        // e = -0.2: flipped to x = 1.113, inside the hull: hidden at any tolerance.
        visible_from_origin(&mid(-0.2), 1.3, 0.0, &mut vis);
        assert!(!vis[1]);
        // A set thinner than the tolerance is flat: all visible.
        assert_eq!(
            visible_from_origin(&mid(0.05), 1.3, 10.0, &mut vis),
            HullOutcome::Flat
        );
        assert_eq!(vis, vec![true, true, true]);
    }

    #[test]
    fn duplicates_share_their_label_and_few_points_are_all_visible() {
        let pts = [
            Point::<3>::new(0.5, 0.0, 0.0),
            Point::<3>::new(0.5, 0.0, 0.0),
        ];
        let mut vis = Vec::new();
        assert_eq!(
            visible_from_origin(&pts, 1.3, 1e-3, &mut vis),
            HullOutcome::Trivial
        );
        assert_eq!(vis, vec![true, true]);
        assert_eq!(
            visible_from_origin::<2>(&[], 1.3, 1e-3, &mut vis),
            HullOutcome::Trivial
        );
        assert!(vis.is_empty());
        // Duplicates among more points: both copies get the same flag.
        let pts = [
            Point::<2>::new(0.5, 0.0),
            Point::<2>::new(0.9, 0.0),
            Point::<2>::new(0.0, 0.5),
            Point::<2>::new(0.9, 0.0),
            Point::<2>::new(0.0, 0.5),
        ];
        assert_eq!(
            visible_from_origin(&pts, 1.3, 1e-3, &mut vis),
            HullOutcome::Hull
        );
        assert_eq!(vis, vec![true, false, true, false, true]);
    }

    #[test]
    fn near_twins_share_the_label_of_their_corner() {
        // (0.5, 0) and its twin 1e-12 away: both visible; the hidden (0.9, 0) stays hidden.
        let pts = [
            Point::<2>::new(0.5, 0.0),
            Point::<2>::new(0.5, 1e-12),
            Point::<2>::new(0.9, 0.0),
            Point::<2>::new(0.0, 0.5),
            Point::<2>::new(0.0, -0.5),
        ];
        let mut vis = Vec::new();
        visible_from_origin(&pts, 1.3, 1e-3, &mut vis);
        assert_eq!(vis, vec![true, true, false, true, true]);
    }

    #[test]
    fn candidates_flat_up_to_rounding_are_all_visible() {
        // A line through (0.3, 0.1, 0) along (1, 2, 0) scaled by 1/3: coplanar with the
        // origin in exact arithmetic (z = 0 after a rotation), its flips only up to rounding.
        let (c, s) = (0.6f64.cos(), 0.6f64.sin());
        let line: Vec<Point<3>> = (0..8)
            .map(|k| {
                let (x, y) = (0.3 + 0.05 * k as f64, 0.1 + 0.1 * k as f64);
                // Rotate the plane z = 0 about the x axis: y' = y cos, z' = y sin.
                Point::<3>::new(x / 3.0, y * c / 3.0, y * s / 3.0)
            })
            .collect();
        let mut vis = Vec::new();
        assert_eq!(
            visible_from_origin(&line, 1.3, 1e-3, &mut vis),
            HullOutcome::Flat
        );
        assert_eq!(vis, vec![true; 8]);
    }

    #[test]
    fn flat_candidates_are_all_visible() {
        // Collinear with the viewpoint (2D) and coplanar with it (3D): no full hull.
        let line: Vec<Point<2>> = (1..6)
            .map(|k| Point::<2>::new(0.15 * k as f64, 0.0))
            .collect();
        let mut vis = Vec::new();
        assert_eq!(
            visible_from_origin(&line, 1.3, 1e-3, &mut vis),
            HullOutcome::Flat
        );
        assert!(vis.iter().all(|&v| v));
        let plane: Vec<Point<3>> = (0..25)
            .map(|k| Point::<3>::new(0.1 * (k % 5) as f64 - 0.2, 0.1 * (k / 5) as f64 + 0.1, 0.0))
            .collect();
        assert_eq!(
            visible_from_origin(&plane, 1.3, 1e-3, &mut vis),
            HullOutcome::Flat
        );
        assert_eq!(vis, vec![true; 25]);
    }
    /// The pruned scans (early exits, cell boxes, sorted near-twin search) decide as the full
    /// scans that define the test, on the candidates of viewpoints around a dense jittered
    /// block (about 360 neighbours within 2r, the cross-method bench's dense set) and on near-tie sets
    /// (jitter of the order of the tolerance), 2D and 3D, at several tolerances.
    #[test]
    fn pruned_scans_decide_as_the_full_scans() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut rnd = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut differ = 0;
        let mut compared = 0;
        let mut check = |pts3: &[Point<3>], pts2: &[Point<2>], tol: f64| {
            let (mut a, mut b) = (Vec::new(), Vec::new());
            let oa = visible_with_scan(pts3, 1.3, tol, &mut a, Scan::Full);
            let ob = visible_with_scan(pts3, 1.3, tol, &mut b, Scan::Pruned);
            differ += usize::from(oa != ob || a != b);
            let oa = visible_with_scan(pts2, 1.3, tol, &mut a, Scan::Full);
            let ob = visible_with_scan(pts2, 1.3, tol, &mut b, Scan::Pruned);
            differ += usize::from(oa != ob || a != b);
            compared += 2;
        };
        // A 14^3 block of spacing 1 (jitter 0.15) at r = 2.2, seen from viewpoints 2.2 to 4
        // outside a face, an edge and a corner: the candidates within 4r, scaled by 1/4r.
        let block: Vec<Point<3>> = (0..14 * 14 * 14)
            .map(|k| {
                Point::<3>::new(
                    (k % 14) as f64 + 0.3 * rnd(),
                    (k / 14 % 14) as f64 + 0.3 * rnd(),
                    (k / 196) as f64 + 0.3 * rnd(),
                )
            })
            .collect();
        let reach = 4.0 * 2.2;
        for v in [
            Point::<3>::new(6.5, 6.5, -2.2),
            Point::<3>::new(-2.5, 6.0, -3.0),
            Point::<3>::new(-2.2, -2.2, -2.2),
            Point::<3>::new(15.7, 7.1, 4.0),
        ] {
            let local: Vec<Point<3>> = block
                .iter()
                .filter(|p| (*p - v).norm() <= reach)
                .map(|p| (p - v) / reach)
                .collect();
            let flat: Vec<Point<2>> = local
                .iter()
                .filter(|p| p[2].abs() < 0.06)
                .map(|p| Point::<2>::new(p[0], p[1]))
                .collect();
            assert!(local.len() > 100, "{} candidates", local.len());
            for tol in [0.0, 1e-6, 1e-3, 2e-2] {
                check(&local, &flat, tol);
            }
        }
        // Exact ties: a perfect lattice, whose flips lie on hull facets up to rounding, at
        // tolerances 0 and 1e-12.
        let lattice: Vec<Point<3>> = (0..12 * 12 * 12)
            .map(|k| Point::<3>::new((k % 12) as f64, (k / 12 % 12) as f64, (k / 144) as f64))
            .collect();
        for v in [
            Point::<3>::new(5.5, 5.5, -2.0),
            Point::<3>::new(-2.0, 5.0, -2.0),
            Point::<3>::new(-1.5, -1.5, -1.5),
        ] {
            let local: Vec<Point<3>> = lattice
                .iter()
                .filter(|p| (*p - v).norm() <= 8.0)
                .map(|p| (p - v) / 8.0)
                .collect();
            let flat: Vec<Point<2>> = local
                .iter()
                .filter(|p| p[2] == local[0][2])
                .map(|p| Point::<2>::new(p[0], p[1]))
                .collect();
            for tol in [0.0, 1e-12, 1e-3] {
                check(&local, &flat, tol);
            }
        }
        // Near ties: points on a sphere cap and on a plane, moved by about the tolerance.
        for tol in [1e-6, 1e-3] {
            for _ in 0..20 {
                let cap: Vec<Point<3>> = (0..300)
                    .map(|_| {
                        let d = Point::<3>::new(rnd(), rnd(), 1.5 + rnd().abs());
                        d / d.norm() * (0.5 + tol * rnd())
                    })
                    .collect();
                let line: Vec<Point<2>> = (0..200)
                    .map(|k| Point::<2>::new(0.4 + tol * rnd(), (k as f64 - 100.0) / 300.0))
                    .collect();
                check(&cap, &line, tol);
            }
        }
        assert_eq!(differ, 0, "{differ} of {compared} sets decided differently");
    }
    /// `FlipBoxes::reaching` returns every point with `n·q >= level` (computed as the scans
    /// compute it), also when the level is exactly some point's `n·q` (a tie), for random
    /// directions and for the axes; and it skips most points for a level near the top.
    #[test]
    fn cell_boxes_return_every_point_that_reaches_the_level() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut rnd = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let pts: Vec<Point<3>> = (0..2000)
            .map(|_| Point::<3>::new(1.0 + rnd(), rnd(), 0.3 * rnd()))
            .collect();
        let boxes = FlipBoxes::new(&pts);
        let dot = |n: &[f64; 3], q: &Point<3>| (0..3).map(|j| n[j] * q[j]).sum::<f64>();
        let mut skipped = 0;
        for trial in 0..300 {
            let n = if trial < 3 {
                let mut e = [0.0; 3];
                e[trial] = 1.0;
                e
            } else {
                let v = [rnd(), rnd(), rnd()];
                let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                [v[0] / l, v[1] / l, v[2] / l]
            };
            // The level of the best point, or of a random one: exact ties.
            let best = pts
                .iter()
                .map(|q| dot(&n, q))
                .fold(f64::NEG_INFINITY, f64::max);
            let level = if trial % 2 == 0 {
                best
            } else {
                dot(&n, &pts[((rnd() + 0.5) * 1999.0) as usize])
            };
            let found: std::collections::BTreeSet<usize> = boxes.reaching(&n, level).collect();
            for (m, q) in pts.iter().enumerate() {
                if dot(&n, q) >= level {
                    assert!(
                        found.contains(&m),
                        "point {m} at level {level} along {n:?} skipped"
                    );
                }
            }
            if level == best {
                skipped += pts.len() - found.len();
            }
        }
        assert!(
            skipped > 150 * pts.len() / 2,
            "the boxes skip few points: {skipped}"
        );
    }
}
