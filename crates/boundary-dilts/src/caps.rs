//! 3D: covering the sphere `S_i` by caps (Haque & Dilts 2007), by the criterion (a)–(c) of the
//! crate documentation.
//!
//! Cap `j`: centre `u_j`, `cos α_j = c_j = d_j/2`, `sin α_j = s_j`. A point `x` of the unit
//! sphere is covered by it iff `x·u_j >= c_j − COVER_TOLERANCE`.
//!
//! *Intersection of two circles* `x·u_j = c_j`, `x·u_k = c_k`, `|x| = 1`. With `g = u_j·u_k` and
//! `w = u_j × u_k`, write `x = a·u_j + b·u_k + t·w`: the two linear equations give
//! `a = (c_j − g·c_k)/|w|²`, `b = (c_k − g·c_j)/|w|²`, and `|x| = 1` gives
//! `t²·|w|² = 1 − (a·c_j + b·c_k) = 1 − ((c_j − c_k)² + c_j·c_k·|u_j − u_k|²)/|w|²` (the last
//! form avoids the cancellation of `1 − g` for close centres). A negative right-hand side means
//! the circles do not meet (the caps are disjoint or nested).

use crate::{Cap, SphereCover, TANGENT_TOLERANCE, U};
use boundary_core::{HalfSpace, Point, Radius};

/// Size of the first subset of caps tried (the largest ones); it doubles until the question is
/// settled. A jittered cubic lattice is covered by its 6 to 14 largest caps.
const FIRST_LEVEL: usize = 16;

/// Slack of the cheap pruning of pairs by `cos(α_j ± α_k)`, wider than its rounding, so that
/// near-tangent pairs reach the exact intersection formula.
const PRUNE_SLACK: f64 = 1e-9;

/// Centres closer than this (`|u_j × u_k|²`) are concentric for the intersection formula: such
/// circles are nested or identical, never crossing (identical caps were merged as twins).
const CONCENTRIC: f64 = 1e-28;

/// A point of `S_i` lies *inside* cap `l` with room to spare iff `x·u_l − c_l > TIE_BAND`;
/// caps within the band of `x` pass through it (a tie, e.g. a Voronoi vertex on `S_i` in a
/// perfect lattice) and are resolved by [`step_off`].
const TIE_BAND: f64 = 1e-10;

/// Angular step (radians) from a tie point into the sector its circles leave open (see
/// [`step_off`]). Uncovered regions thinner than this near a tie count as covered: near-ties.
const STEP: f64 = 1e-7;

/// Caps with `sin α` below this (a neighbour within about `1e-8·r` of `2r`) are dropped.
/// [`step_off`] leaves a cap by moving [`STEP`] radians, which lowers `x·u` by about
/// `sin α·STEP`; below the covering tolerance the stepped point still counts as covered by the
/// cap it should have left, so a neighbour at exactly `2r` (a point cap) made a lone pair
/// interior. Dropping such a cap never introduces a false negative: it only removes covered
/// points, and a cap of zero area never decides the covering (the uncovered set is open).
const POINT_CAP: f64 = 1e-4;

/// A cap with its derived quantities.
#[derive(Debug, Clone, Copy)]
struct Cap3 {
    u: Point<3>,
    /// `cos α`.
    c: f64,
    /// `sin α`.
    s: f64,
}

impl Cap3 {
    /// Closed cap with the covering tolerance `tol` (crate docs).
    fn covers(&self, x: &Point<3>, tol: f64) -> bool {
        x.dot(&self.u) >= self.c - tol
    }

    /// One point of the boundary circle.
    fn point_on_circle(&self) -> Point<3> {
        // A unit vector orthogonal to u, from the axis along which u is smallest.
        let axis = self.u.iamin();
        let e = self.u.cross(&Point::<3>::ith(axis, 1.0)).normalize();
        self.u * self.c + e * self.s
    }
}

/// In the exact mode (`tie = 0`), pairs whose discriminant `h` or `|u_p × u_q|²` is below this
/// are not decided by floating point (near-tangent or near-concentric circles): the particle
/// goes to the exact predicate.
const PAIR_BAND: f64 = 1e-8;

/// Where the circles of two caps meet.
enum Meeting {
    /// They do not cross (disjoint, nested, or concentric).
    Apart,
    /// One or two points (equal and flagged when tangent), with a bound on the error of each
    /// point (the distance to the true intersection point, crate docs "Exactness").
    Points([Point<3>; 2], bool, f64),
    /// Exact mode only: too close to tangency or concentricity for the float bound.
    Ambiguous,
}

/// The points where the circles of `p` and `q` meet. `strict`: the exact mode.
fn circle_intersections(p: &Cap3, q: &Cap3, strict: bool) -> Meeting {
    let g = p.u.dot(&q.u);
    // Prune: centres farther apart than α_p + α_q (disjoint caps) or closer than |α_p − α_q|
    // (nested caps) cannot give crossing circles.
    let cc = p.c * q.c;
    let ss = p.s * q.s;
    if g < cc - ss - PRUNE_SLACK || g > cc + ss + PRUNE_SLACK {
        return Meeting::Apart;
    }
    let w = p.u.cross(&q.u);
    let w2 = w.norm_squared();
    if strict && w2 < PAIR_BAND {
        return Meeting::Ambiguous;
    }
    if w2 < CONCENTRIC {
        return Meeting::Apart;
    }
    let a = (p.c - g * q.c) / w2;
    let b = (q.c - g * p.c) / w2;
    let dc = p.c - q.c;
    let h = 1.0 - (dc * dc + cc * (p.u - q.u).norm_squared()) / w2;
    if strict {
        if h.abs() <= PAIR_BAND {
            return Meeting::Ambiguous;
        }
        if h < 0.0 {
            return Meeting::Apart;
        }
    } else if h < -TANGENT_TOLERANCE {
        return Meeting::Apart;
    }
    let t = (h.max(0.0) / w2).sqrt();
    let base = p.u * a + q.u * b;
    // First-order error of the point (crate docs): the inputs u, c carry a relative error of a
    // few u; a, b divide by w2, t by sqrt(h·w2).
    let err = 64.0 * U * (1.0 + 1.0 / w2 + 1.0 / (h.max(PAIR_BAND) * w2).sqrt()) + 16.0 * U;
    Meeting::Points(
        [(base + w * t).normalize(), (base - w * t).normalize()],
        h <= TANGENT_TOLERANCE,
        err,
    )
}

/// The point at angular distance [`STEP`] from `x` (on the circle of cap `j`) in the direction
/// that leaves every cap whose circle passes through `x` fastest.
///
/// Near `x`, a cap through `x` is, to first order, the closed half-plane of tangent directions
/// `w` with `w·o_l <= 0`, `o_l` the outward normal of its circle at `x`; directions with
/// `w·o_l > 0` for every such cap exist iff the `o_l` lie in an open half-plane, and the best one
/// is the middle of the arc they occupy. Caps curve away from their tangent half-planes, so
/// that direction leaves every cap through `x` when one exists; otherwise the stepped point lies
/// inside one of them and the caller finds it covered. Used when `x` is in no cap with room to
/// spare, which in generic position means `x` is uncovered (then the step stays uncovered) and
/// in perfect lattices means a tie.
fn step_off(caps: &[Cap3], x: &Point<3>, j: usize) -> Point<3> {
    let outward = |cap: &Cap3| -> Option<Point<3>> {
        let tangential = cap.u - x * x.dot(&cap.u);
        let norm = tangential.norm();
        (norm > 0.0).then(|| -tangential / norm)
    };
    let Some(e1) = outward(&caps[j]) else {
        return *x;
    };
    let e2 = x.cross(&e1);
    let mut angles: Vec<f64> = caps
        .iter()
        .filter(|cap| (x.dot(&cap.u) - cap.c).abs() <= TIE_BAND)
        .filter_map(outward)
        .map(|o| o.dot(&e2).atan2(o.dot(&e1)))
        .collect();
    angles.push(0.0);
    angles.sort_unstable_by(f64::total_cmp);
    // The largest cyclic gap between consecutive outward normals; the occupied arc is the rest.
    let tau = std::f64::consts::TAU;
    let mut gap_end = angles[0];
    let mut largest = angles[0] + tau - angles[angles.len() - 1];
    for pair in angles.windows(2) {
        if pair[1] - pair[0] > largest {
            largest = pair[1] - pair[0];
            gap_end = pair[1];
        }
    }
    // Middle of the occupied arc [gap_end, gap_end + (τ − largest)].
    let theta = gap_end + 0.5 * (tau - largest);
    let w = e1 * theta.cos() + e2 * theta.sin();
    (x + w * STEP).normalize()
}

/// What a subset of the caps says about the sphere.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    /// The subset covers the sphere: interior.
    Covered,
    /// A witness point covered by no cap at all: boundary.
    Uncovered,
    /// The subset does not cover, but every point it leaves was covered by another cap.
    Undecided,
    /// Exact mode: a decision fell inside the float error bound; the caller asks the exact
    /// predicate.
    Ambiguous,
}

/// The 3D covering test; holds per-particle working memory.
#[derive(Debug, Default)]
pub(crate) struct Caps {
    caps: Vec<Cap3>,
    /// Whether each circle of the current subset meets another circle of the subset.
    crossed: Vec<bool>,
    /// Extra absolute error of every `cos α` (per-particle radii; 0 at a uniform radius).
    slack: f64,
}

impl SphereCover<3> for Caps {
    fn exact(centre: &Point<3>, others: &[Point<3>], r: Radius) -> bool {
        boundary_exact::sphere_uncovered_3d(centre, others, r)
    }

    fn exact_power(centre: &Point<3>, r: f64, others: &[(Point<3>, f64)]) -> bool {
        boundary_exact::sphere_uncovered_power_3d(centre, r, others)
    }

    fn set_slack(&mut self, slack: f64) {
        self.slack = slack;
    }

    fn exact_in(
        centre: &Point<3>,
        r: f64,
        others: &[(Point<3>, f64)],
        solids: &[HalfSpace],
    ) -> bool {
        boundary_exact::sphere_uncovered_in_3d(centre, r, others, solids)
    }

    const MARGIN: bool = false;

    fn classify(&mut self, caps: &[Cap<3>], tol: f64) -> (Option<bool>, Option<f64>) {
        let strict = tol == 0.0;
        if strict
            && caps
                .iter()
                .any(|cap| 1.0 - cap.half_distance * cap.half_distance < POINT_CAP * POINT_CAP)
        {
            // A cap too thin for the float test: not dropped silently in the exact mode.
            return (None, None);
        }
        self.caps.clear();
        self.caps.extend(
            caps.iter()
                .map(|cap| Cap3 {
                    u: cap.u,
                    c: cap.half_distance,
                    s: (1.0 - cap.half_distance * cap.half_distance)
                        .max(0.0)
                        .sqrt(),
                })
                .filter(|cap| cap.s >= POINT_CAP),
        );
        // (a): no cap, nothing covered.
        if self.caps.is_empty() {
            return (Some(true), None);
        }
        let n = self.caps.len();
        let mut m = FIRST_LEVEL.min(n);
        loop {
            match check_subset(&self.caps, m, &mut self.crossed, tol, self.slack) {
                Outcome::Covered => return (Some(false), None),
                Outcome::Uncovered => return (Some(true), None),
                Outcome::Ambiguous => return (None, None),
                // With m == n every point is tested against all caps: never undecided.
                Outcome::Undecided if m < n => m = (2 * m).min(n),
                Outcome::Undecided => return (Some(true), None),
            }
        }
    }
}

/// Criterion (b) and (c) for the first `m` caps; points they leave uncovered are tested against
/// the remaining caps, so that [`Outcome::Uncovered`] is a witness for the whole set.
///
/// `tol > 0`: the tolerant mode (covering tolerance `tol`, ties resolved by [`step_off`]).
/// `tol == 0`: the exact mode: a point is decided only when every cap value `x·u_l − c_l` is
/// farther from 0 than the point's error bound `err`; otherwise [`Outcome::Ambiguous`].
/// `slack`: the extra absolute error of every `c` (per-particle radii, crate docs); it widens
/// every band, to first order as the points' bounds scale with the error of `c`.
fn check_subset(caps: &[Cap3], m: usize, crossed: &mut Vec<bool>, tol: f64, slack: f64) -> Outcome {
    let strict = tol == 0.0;
    let (inner, outer) = caps.split_at(m);
    crossed.clear();
    crossed.resize(m, false);
    let mut undecided = false;
    let mut ambiguous = false;
    // Exact mode: `x` lies on the circles of `j` and `k` (equal for (c)), within `err`.
    let mut strict_probe = |x: &Point<3>, j: usize, k: usize, err: f64| -> Option<Outcome> {
        // x·u − c carries the point's error, plus a few u for the dot product and c.
        let band = err + 16.0 * U + slack;
        let value = |cap: &Cap3| x.dot(&cap.u) - cap.c;
        let third = |(l, cap): (usize, &Cap3)| l != j && l != k && value(cap) > band;
        if inner.iter().enumerate().any(third) {
            return None;
        }
        if outer.iter().any(|cap| value(cap) > band) {
            undecided = true;
            return None;
        }
        let touching = |(l, cap): (usize, &Cap3)| l != j && l != k && value(cap) >= -band;
        if inner.iter().enumerate().any(touching) || outer.iter().any(|c| value(c) >= -band) {
            // Undecidable here; a clear witness elsewhere may still decide the particle.
            ambiguous = true;
            return None;
        }
        Some(Outcome::Uncovered)
    };
    if strict {
        let mut ambiguous_pair = false;
        for j in 0..m {
            for k in j + 1..m {
                match circle_intersections(&inner[j], &inner[k], true) {
                    Meeting::Apart => {}
                    Meeting::Ambiguous => {
                        // Whether these circles cross is undecided: (c) cannot use them.
                        crossed[j] = true;
                        crossed[k] = true;
                        ambiguous_pair = true;
                    }
                    Meeting::Points(points, _, err) => {
                        crossed[j] = true;
                        crossed[k] = true;
                        // The point's bound scales with the error of the inputs (8u each).
                        let err = err * (1.0 + slack / (8.0 * U));
                        for x in &points {
                            if let Some(outcome) = strict_probe(x, j, k, err) {
                                return outcome;
                            }
                        }
                    }
                }
            }
        }
        for j in 0..m {
            if !crossed[j] {
                let err = 16.0 * U + 2.0 * slack / inner[j].s;
                if let Some(outcome) = strict_probe(&inner[j].point_on_circle(), j, j, err) {
                    return outcome;
                }
            }
        }
        // No clear witness: any undecidable step leaves the particle to the exact predicate.
        return if ambiguous || ambiguous_pair {
            Outcome::Ambiguous
        } else if undecided {
            Outcome::Undecided
        } else {
            Outcome::Covered
        };
    }
    // `x` lies on the circles of `j` and `k` (equal for (c)): is a neighbourhood of `x` covered?
    let mut probe = |x: &Point<3>, j: usize, k: usize| -> Option<Outcome> {
        let clear = |cap: &Cap3| x.dot(&cap.u) - cap.c > TIE_BAND;
        let third = |(l, cap): (usize, &Cap3)| l != j && l != k && clear(cap);
        if inner.iter().enumerate().any(third) {
            return None;
        }
        if outer.iter().any(clear) {
            undecided = true;
            return None;
        }
        // No cap contains `x` with room to spare: `x` is uncovered or a tie. Step off `x` into
        // the sector that the circles through it leave open, and test that point instead.
        let y = step_off(inner, x, j);
        if inner.iter().any(|cap| cap.covers(&y, tol)) {
            None
        } else if outer.iter().any(|cap| cap.covers(&y, tol)) {
            undecided = true;
            None
        } else {
            Some(Outcome::Uncovered)
        }
    };
    // (b): every pairwise intersection point of circles lies in a third cap.
    for j in 0..m {
        for k in j + 1..m {
            let Meeting::Points(points, tangent, _) =
                circle_intersections(&inner[j], &inner[k], false)
            else {
                continue;
            };
            // A tangency is not a crossing: the circles still get their own probe in (c), as
            // a step off the touching point leaves the two caps only to second order (the
            // externally tangent caps found by fuzzing, tests/agreement.rs). Extra probes can
            // only find uncovered points, never hide one.
            if !tangent {
                crossed[j] = true;
                crossed[k] = true;
            }
            for x in &points {
                if let Some(outcome) = probe(x, j, k) {
                    return outcome;
                }
            }
        }
    }
    // (c): a circle meeting no other lies inside another cap iff one of its points does.
    for j in 0..m {
        if !crossed[j] {
            if let Some(outcome) = probe(&inner[j].point_on_circle(), j, j) {
                return outcome;
            }
        }
    }
    if undecided {
        Outcome::Undecided
    } else {
        Outcome::Covered
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cap3(u: [f64; 3], c: f64) -> Cap3 {
        Cap3 {
            u: Point::<3>::from(u).normalize(),
            c,
            s: (1.0 - c * c).sqrt(),
        }
    }

    #[test]
    fn intersection_points_lie_on_both_circles() {
        let p = cap3([1.0, 0.0, 0.0], 0.5);
        let q = cap3([0.3, 1.0, -0.2], 0.4);
        let Meeting::Points(points, _, _) = circle_intersections(&p, &q, false) else {
            panic!("the circles cross");
        };
        for x in points {
            assert!((x.norm() - 1.0).abs() < 1e-14);
            assert!((x.dot(&p.u) - p.c).abs() < 1e-14);
            assert!((x.dot(&q.u) - q.c).abs() < 1e-14);
        }
        assert!((points[0] - points[1]).norm() > 0.1);
    }

    #[test]
    fn disjoint_nested_and_tangent_pairs() {
        // Caps of 60° centred 130° apart: disjoint.
        let a = cap3([1.0, 0.0, 0.0], 0.5);
        let far = cap3(
            [
                (130f64).to_radians().cos(),
                (130f64).to_radians().sin(),
                0.0,
            ],
            0.5,
        );
        assert!(matches!(
            circle_intersections(&a, &far, false),
            Meeting::Apart
        ));
        // A 10° cap 20° from the centre of a 60° cap: nested.
        let small = cap3(
            [(20f64).to_radians().cos(), (20f64).to_radians().sin(), 0.0],
            (10f64).to_radians().cos(),
        );
        assert!(matches!(
            circle_intersections(&a, &small, false),
            Meeting::Apart
        ));
        // Two 45° caps 90° apart touch at one point: (1, 1, 0)/√2.
        let c45 = std::f64::consts::FRAC_1_SQRT_2;
        let x = cap3([1.0, 0.0, 0.0], c45);
        let y = cap3([0.0, 1.0, 0.0], c45);
        let Meeting::Points(points, tangent, _) = circle_intersections(&x, &y, false) else {
            panic!("tangent circles meet");
        };
        assert!(matches!(
            circle_intersections(&x, &y, true),
            Meeting::Ambiguous
        ));
        assert!(tangent);
        let touch = Point::<3>::new(c45, c45, 0.0);
        assert!((points[0] - touch).norm() < 1e-6 && (points[1] - touch).norm() < 1e-6);
    }

    #[test]
    fn point_on_circle_is_on_it() {
        for u in [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.2, -0.7, 0.4]] {
            let cap = cap3(u, 0.3);
            let x = cap.point_on_circle();
            assert!((x.norm() - 1.0).abs() < 1e-14);
            assert!((x.dot(&cap.u) - 0.3).abs() < 1e-14);
        }
    }

    #[test]
    fn six_axis_caps_cover_iff_wider_than_the_cube_diagonal() {
        // The six caps on ±x, ±y, ±z leave the directions (±1, ±1, ±1)/√3 last: they cover iff
        // α >= acos(1/√3), i.e. c <= 1/√3.
        let axes = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let caps_of = |c: f64| -> Vec<Cap<3>> {
            axes.iter()
                .map(|&u| Cap {
                    u: Point::<3>::from(u),
                    half_distance: c,
                })
                .collect()
        };
        let mut caps = Caps::default();
        let tie = 1.0 / 3f64.sqrt();
        assert!(!caps
            .classify(&caps_of(tie * (1.0 - 1e-6)), 1e-12)
            .0
            .unwrap());
        assert!(
            !caps.classify(&caps_of(tie), 1e-12).0.unwrap(),
            "tie is interior"
        );
        assert!(caps
            .classify(&caps_of(tie * (1.0 + 1e-6)), 1e-12)
            .0
            .unwrap());
        // The exact mode decides clear cases and leaves the tie to the exact predicate.
        assert_eq!(
            caps.classify(&caps_of(tie * (1.0 - 1e-6)), 0.0).0,
            Some(false)
        );
        assert_eq!(caps.classify(&caps_of(tie), 0.0).0, None);
        assert_eq!(
            caps.classify(&caps_of(tie * (1.0 + 1e-6)), 0.0).0,
            Some(true)
        );
        // Five caps never cover: the sixth axis is free.
        assert!(caps.classify(&caps_of(0.1)[..5], 1e-12).0.unwrap());
    }

    #[test]
    fn a_neighbour_at_exactly_two_r_covers_nothing() {
        let point = |u: [f64; 3], c: f64| Cap {
            u: Point::<3>::from(u),
            half_distance: c,
        };
        let mut caps = Caps::default();
        // A lone pair exactly 2r apart, or 2r minus a rounding error: boundary.
        for c in [1.0, 1.0 - 1e-15, 1.0 - 1e-12] {
            assert!(
                caps.classify(&[point([0.0, 0.0, 1.0], c)], 1e-12)
                    .0
                    .unwrap(),
                "c = {c}"
            );
        }
        // A point cap does not spoil a covering either.
        let mut six: Vec<Cap<3>> = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ]
        .map(|u| point(u, 0.5))
        .to_vec();
        six.push(point([0.6, 0.0, 0.8], 1.0));
        assert!(!caps.classify(&six, 1e-12).0.unwrap());
    }
}
