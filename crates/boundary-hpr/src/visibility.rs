//! The local HPR visibility test (Sandim 2020, Sec. 2.2 and 2.3.2; Katz, Tal & Basri 2007).

use crate::hull;
use boundary_core::Point;

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
pub fn visible_from_origin<const D: usize>(
    points: &[Point<D>],
    gamma: f64,
    tol: f64,
    visible: &mut Vec<bool>,
) -> HullOutcome {
    visible.clear();
    visible.resize(points.len(), true);
    // Exact duplicates share one flip and one flag: `first[i]` is the lowest index with the
    // coordinates of point `i`; the hull's input is the distinct points in index order.
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_unstable_by(|&a, &b| {
        let (pa, pb) = (&points[a], &points[b]);
        (0..D)
            .map(|k| pa[k].total_cmp(&pb[k]))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(a.cmp(&b))
    });
    let mut first = vec![0usize; points.len()];
    for (k, &i) in order.iter().enumerate() {
        first[i] = if k > 0 && points[order[k - 1]] == points[i] {
            first[order[k - 1]]
        } else {
            i
        };
    }
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
    for (k, n) in facet_normals.iter().enumerate() {
        if *n == [0.0; 3] {
            continue;
        }
        let top = dot(n, point(facet_anchor[k]));
        let low = (0..=flipped.len())
            .map(|m| dot(n, point(m)))
            .fold(f64::INFINITY, f64::min);
        if top - low <= tol {
            return HullOutcome::Flat;
        }
    }
    // A corner is visible when it protrudes by more than `tol`, along its vertex normal (the
    // normalised sum of its facets' normals), from all the other points except its near-twins
    // (flips within `tol` of it, which share its label): a lower bound of its distance to the
    // hull of the others.
    let near = |a: &Point<D>, b: &Point<D>| (a - b).norm() <= tol;
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
            let rest = (0..=flipped.len())
                .filter(|&m| m != k && !near(point(m), &flipped[k]))
                .map(|m| dot(&n, point(m)))
                .fold(f64::NEG_INFINITY, f64::max);
            top - rest > tol
        })
        .collect();
    // Near-twins of a visible corner are visible too.
    let visible_corners: Vec<usize> = (0..flipped.len()).filter(|&k| seen[k]).collect();
    for k in 0..flipped.len() {
        if !seen[k]
            && visible_corners
                .iter()
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
}
