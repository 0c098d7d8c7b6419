//! 2D: covering the circle `S_i` by arcs (Dilts 2000).
//!
//! Neighbour `j` covers the closed arc of `S_i` centred on the direction `θ_j` of `p_j − p_i`
//! with half-angle `α_j = acos(d_j/2 − COVER_TOLERANCE)` (scaled distance `d_j`, crate docs):
//! exactly the points `x` with `x·u_j >= d_j/2 − COVER_TOLERANCE`. The arcs are sorted by start
//! and swept twice around the circle.
//!
//! *Margin.* Let `f(φ) = max_j (α_j − ∠(φ, θ_j))`, the depth of `φ` in its deepest arc
//! (negative outside all arcs). The margin is `−min_φ f`. An arc contained in another has a
//! smaller depth everywhere, so only the arcs that extend the sweep's reach matter; between two
//! consecutive such arcs `a` (end `e_a`) and `b` (start `s_b`), `f = max(e_a − φ, φ − s_b)`, whose
//! minimum is `(e_a − s_b)/2`. The margin is therefore the largest `(s_b − e_a)/2`: half the
//! widest gap if there is one, else minus half the narrowest overlap.

use crate::{Cap, SphereCover, U};
use boundary_core::{HalfSpace, Point, Radius};
use std::f64::consts::{PI, TAU};

/// The 2D covering test; holds the arcs of the current particle.
#[derive(Debug, Default)]
pub(crate) struct Arcs {
    /// `(start, end)` with `start ∈ [0, 2π]` and `end = start + 2α`.
    arcs: Vec<(f64, f64)>,
    /// Extra absolute error of every `cos α` (per-particle radii; 0 at a uniform radius).
    slack: f64,
}

/// In the exact mode, arcs with `sin α` below this (neighbours within about `1e-12·r` of `2r`)
/// are outside the float error analysis: the particle goes to the exact predicate.
const THIN_ARC: f64 = 1e-6;

impl SphereCover<2> for Arcs {
    fn exact(centre: &Point<2>, others: &[Point<2>], r: Radius) -> bool {
        boundary_exact::sphere_uncovered_2d(centre, others, r)
    }

    fn exact_power(centre: &Point<2>, r: f64, others: &[(Point<2>, f64)]) -> bool {
        boundary_exact::sphere_uncovered_power_2d(centre, r, others)
    }

    fn set_slack(&mut self, slack: f64) {
        self.slack = slack;
    }

    fn exact_in(
        centre: &Point<2>,
        r: f64,
        others: &[(Point<2>, f64)],
        solids: &[HalfSpace],
    ) -> bool {
        boundary_exact::sphere_uncovered_in_2d(centre, r, others, solids)
    }

    const MARGIN: bool = true;

    fn classify(&mut self, caps: &[Cap<2>], tol: f64) -> (Option<bool>, Option<f64>) {
        self.arcs.clear();
        let mut sin_min = 1.0f64;
        self.arcs.extend(caps.iter().map(|cap| {
            let theta = cap.u.y.atan2(cap.u.x);
            let c = (cap.half_distance - tol).clamp(-1.0, 1.0);
            sin_min = sin_min.min((1.0 - c * c).max(0.0).sqrt());
            let alpha = c.acos();
            let start = (theta - alpha).rem_euclid(TAU);
            (start, start + 2.0 * alpha)
        }));
        let margin = largest_half_gap(&mut self.arcs);
        if tol > 0.0 || caps.is_empty() {
            return (Some(margin > 0.0), Some(margin));
        }
        // Exact mode: every arc end is within `E` of its exact value (crate docs "Exactness"),
        // so the half gap is within `E` of the exact one.
        let e = 64.0 * U + (8.0 * U + self.slack) / sin_min.max(f64::MIN_POSITIVE);
        if sin_min < THIN_ARC || margin.abs() <= 2.0 * e {
            (None, Some(margin))
        } else {
            (Some(margin > 0.0), Some(margin))
        }
    }
}

/// `max_φ min_j (∠(φ, θ_j) − α_j)` for arcs given as `(start, end)` (see the module docs), in
/// radians; `π` when there is no arc. Sorts `arcs`.
fn largest_half_gap(arcs: &mut [(f64, f64)]) -> f64 {
    if arcs.is_empty() {
        return PI;
    }
    // Equal starts: the longer arc first, so that the shorter one never "extends" the reach.
    arcs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    // First turn: the reach of all arcs, including those wrapping past 2π.
    let mut reach = arcs.iter().map(|a| a.1).fold(f64::NEG_INFINITY, f64::max);
    // Second turn, shifted by 2π: every arc that extends the reach closes a gap or an overlap.
    let mut largest = f64::NEG_INFINITY;
    for &(start, end) in arcs.iter() {
        let (start, end) = (start + TAU, end + TAU);
        if end > reach {
            largest = largest.max(0.5 * (start - reach));
            reach = end;
        }
    }
    largest
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundary_core::Point;
    use rand::{Rng, SeedableRng};

    fn cap(theta: f64, half_distance: f64) -> Cap<2> {
        Cap {
            u: Point::<2>::new(theta.cos(), theta.sin()),
            half_distance,
        }
    }

    /// `max_φ min_j (∠(φ, θ_j) − α_j)` by dense sampling plus the arc end points.
    fn brute_margin(caps: &[Cap<2>]) -> f64 {
        let depth = |phi: f64| {
            caps.iter()
                .map(|c| {
                    let theta = c.u.y.atan2(c.u.x);
                    let alpha = (c.half_distance - 1e-12).acos();
                    let diff = (phi - theta).rem_euclid(TAU);
                    diff.min(TAU - diff) - alpha
                })
                .fold(f64::INFINITY, f64::min)
        };
        (0..200_000)
            .map(|k| depth(k as f64 * TAU / 200_000.0))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    #[test]
    fn no_arc_and_one_arc() {
        let mut arcs = Arcs::default();
        assert_eq!(arcs.classify(&[], 1e-12), (Some(true), Some(PI)));
        assert_eq!(arcs.classify(&[], 0.0), (Some(true), Some(PI)));
        // One neighbour at distance r (d = 1): a 60° half-angle arc leaves 360° − 120° open.
        let (boundary, margin) = arcs.classify(&[cap(0.3, 0.5)], 1e-12);
        assert_eq!(boundary, Some(true));
        assert!((margin.unwrap() - (PI - PI / 3.0)).abs() < 1e-9);
    }

    #[test]
    fn three_arcs_of_sixty_degrees_cover_exactly() {
        // Half-angle 60° (d = 1) at 0°, 120°, 240°: consecutive arcs meet end to end. The tie
        // is covered thanks to the tolerance, and the overlap is about 2·1e-12/sin 60°.
        let mut arcs = Arcs::default();
        let caps: Vec<_> = (0..3).map(|k| cap(k as f64 * TAU / 3.0, 0.5)).collect();
        let (boundary, margin) = arcs.classify(&caps, 1e-12);
        assert_eq!(boundary, Some(false));
        let m = margin.unwrap();
        assert!(m < 0.0 && m > -1e-11, "margin {m}");
        // The exact mode leaves the tie to the exact predicate.
        assert_eq!(arcs.classify(&caps, 0.0).0, None);
    }

    #[test]
    fn sweep_matches_sampling() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let mut arcs = Arcs::default();
        for _ in 0..200 {
            let n = rng.gen_range(1..9);
            let caps: Vec<_> = (0..n)
                .map(|_| cap(rng.gen_range(-PI..PI), rng.gen_range(0.05..1.0)))
                .collect();
            let (boundary, margin) = arcs.classify(&caps, 1e-12);
            let m = margin.unwrap();
            let brute = brute_margin(&caps);
            assert!((m - brute).abs() < 1e-4, "{m} vs {brute} for {caps:?}");
            assert_eq!(boundary, Some(m > 0.0));
        }
    }

    #[test]
    fn arcs_wrapping_through_zero() {
        // Arcs centred near ±π wrap through the seam of atan2 and of the [0, 2π) starts.
        let mut arcs = Arcs::default();
        let caps = [cap(PI - 0.1, 0.2), cap(-PI + 0.1, 0.2), cap(0.0, 0.2)];
        let (boundary, margin) = arcs.classify(&caps, 1e-12);
        let brute = brute_margin(&caps);
        assert!((margin.unwrap() - brute).abs() < 1e-4);
        // Half-angles acos(0.2) ≈ 78.5° at 0° and ±174.3°: a gap around ±90° remains.
        assert!(boundary == Some(true) && brute > 0.0);
    }
}
