//! The local HPR visibility test (Sandim 2020, Sec. 2.2 and 2.3.2; Katz, Tal & Basri 2007).

use boundary_core::Point;
use qhull::Qh;

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

/// How a hull was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HullOutcome {
    /// At most `D` distinct candidates: all visible without a hull.
    Trivial,
    /// Qhull succeeded with its default options (merged facets, `C-0`).
    Plain,
    /// The default run failed (flat or degenerate input) and `QJ` (joggled input) succeeded.
    Joggled,
    /// Both failed: every candidate is labelled visible (the conservative choice).
    Failed,
}

/// Which of the `points` (already moved so that the viewpoint is the origin, and scaled into
/// the unit ball) are visible from the origin: the vertices of the convex hull of their
/// exponential flips plus the origin. Writes one flag per point into `visible`.
///
/// Degenerate input: exact duplicates flip to the same point and share their flag (qhull
/// keeps only one of them as a vertex); with at most `D` distinct points all are visible;
/// a qhull error (a flat initial simplex from collinear or coplanar candidates, or a
/// precision error) is retried once with joggled input (`QJ`), and if that fails too every
/// point is marked visible.
pub fn visible_from_origin<const D: usize>(
    points: &[Point<D>],
    gamma: f64,
    visible: &mut Vec<bool>,
) -> HullOutcome {
    visible.clear();
    visible.resize(points.len(), false);
    // Distinct points, each with the first index that carries it.
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_unstable_by(|&a, &b| {
        let (pa, pb) = (&points[a], &points[b]);
        (0..D)
            .map(|k| pa[k].total_cmp(&pb[k]))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(a.cmp(&b))
    });
    let mut representative = vec![0usize; points.len()];
    let mut distinct: Vec<usize> = Vec::with_capacity(points.len());
    for (k, &i) in order.iter().enumerate() {
        if k == 0 || points[order[k - 1]] != points[i] {
            distinct.push(i);
        }
        representative[i] = distinct.len() - 1;
    }
    if distinct.len() <= D {
        visible.iter_mut().for_each(|v| *v = true);
        return HullOutcome::Trivial;
    }
    // Input to qhull: the origin (index 0), then the distinct flipped points.
    let mut coords = Vec::with_capacity((distinct.len() + 1) * D);
    coords.extend(std::iter::repeat_n(0.0, D));
    for &i in &distinct {
        coords.extend(flip_exponential(&points[i], gamma).iter());
    }
    let mut is_vertex = vec![false; distinct.len()];
    let outcome = if hull_vertices::<D>(&coords, false, &mut is_vertex) {
        HullOutcome::Plain
    } else if hull_vertices::<D>(&coords, true, &mut is_vertex) {
        HullOutcome::Joggled
    } else {
        is_vertex.iter_mut().for_each(|v| *v = true);
        HullOutcome::Failed
    };
    for (i, v) in visible.iter_mut().enumerate() {
        *v = is_vertex[representative[i]];
    }
    outcome
}

/// Marks `is_vertex[k]` for the hull vertices among `coords[D..]` (point `k + 1` of qhull's
/// input; point 0 is the origin). Returns false on a qhull error.
fn hull_vertices<const D: usize>(coords: &[f64], joggle: bool, is_vertex: &mut [bool]) -> bool {
    is_vertex.iter_mut().for_each(|v| *v = false);
    // Qhull keeps its own copy of the joggled input; ours is only read.
    let mut input = coords.to_vec();
    // Qhull reports errors and warnings on its error stream: captured (into a temporary
    // file), so that the library prints nothing. No output option is set, so stdout is unused.
    let builder = Qh::builder().capture_stderr(true);
    let builder = if joggle {
        match builder.qhull_args(["QJ"]) {
            Ok(b) => b,
            Err(_) => return false,
        }
    } else {
        builder
    };
    let Ok(qh) = builder.build(D, &mut input) else {
        return false;
    };
    for v in qh.vertices() {
        match v.index(&qh) {
            Some(0) => {}
            Some(k) if k <= is_vertex.len() => is_vertex[k - 1] = true,
            _ => return false,
        }
    }
    true
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
        let out = visible_from_origin(&pts, 1.3, &mut vis);
        assert_eq!(out, HullOutcome::Plain);
        assert!(vis[0] && !vis[1] && vis[2]);
    }

    #[test]
    fn duplicates_share_their_label_and_few_points_are_all_visible() {
        let pts = [
            Point::<3>::new(0.5, 0.0, 0.0),
            Point::<3>::new(0.5, 0.0, 0.0),
        ];
        let mut vis = Vec::new();
        assert_eq!(
            visible_from_origin(&pts, 1.3, &mut vis),
            HullOutcome::Trivial
        );
        assert_eq!(vis, vec![true, true]);
        assert_eq!(
            visible_from_origin::<2>(&[], 1.3, &mut vis),
            HullOutcome::Trivial
        );
        assert!(vis.is_empty());
    }

    #[test]
    fn collinear_and_coplanar_candidates_do_not_abort() {
        // Collinear with the viewpoint: qhull's initial simplex is flat.
        let line: Vec<Point<2>> = (1..6)
            .map(|k| Point::<2>::new(0.15 * k as f64, 0.0))
            .collect();
        let mut vis = Vec::new();
        let out = visible_from_origin(&line, 1.3, &mut vis);
        assert!(
            matches!(out, HullOutcome::Joggled | HullOutcome::Failed),
            "{out:?}"
        );
        assert!(vis[0], "the nearest point of the line is seen");
        // A plane through the viewpoint in 3D.
        let plane: Vec<Point<3>> = (0..25)
            .map(|k| Point::<3>::new(0.1 * (k % 5) as f64 - 0.2, 0.1 * (k / 5) as f64 + 0.1, 0.0))
            .collect();
        let out = visible_from_origin(&plane, 1.3, &mut vis);
        assert!(
            matches!(out, HullOutcome::Joggled | HullOutcome::Failed),
            "{out:?}"
        );
        assert_eq!(vis.len(), 25);
    }
}
