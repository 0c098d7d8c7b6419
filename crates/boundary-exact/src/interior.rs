//! The interior filter: a cheap, conservative proof that a particle's cell lies well inside
//! its sphere, tried before any cell is clipped (uniform radius, no solids).
//!
//! Units of `r`, coordinates relative to `p_i`. A neighbour at `q` (`|q| > 0`) bounds the
//! cell by its bisector half-space `q·x <= |q|²/2`, i.e. `a·x <= 1` with the *inverted
//! point* `a = 2q/|q|²`. The cell lies in the intersection of the half-spaces of any subset
//! of the neighbours within `2r`.
//!
//! **Claim.** Let `A` be a set of inverted points and `g > 0` such that every unit vector `e`
//! has `max_{a ∈ A} a·e >= g`. Then every `x` with `a·x <= 1` for all `a ∈ A` has
//! `|x| <= 1/g`. *Proof:* for `x = |x|e`, `|x|·g <= |x|·max a·e = max a·x <= 1`.
//!
//! **How `g` is found.** From the neighbours with `|q|² >= 1/4` (so `|a| <= 4`), six are
//! picked: for each axis direction `±e_k` the one whose inverted point reaches farthest along
//! it. In 3D they are joined as the eight triangles of an octahedron `(X^±, Y^±, Z^±)`, each
//! ordered so that it faces outward when the six points lie on their axes (the last two
//! swapped where the product of the signs is negative); in 2D as the four edges of a
//! diamond. For a triangle `(a, b, c)` with `m = (b − a) × (c − a)`, `m·a = det(a, b, c)`,
//! and the filter requires `det(a, b, c) > 0`: the origin lies strictly on the inner side of
//! the triangle's plane, at distance `d = det/|m|`.
//! - *One triangle.* For `e = αa + βb + γc` with `α, β, γ >= 0` (the triangle's cone),
//!   `m·e = (α + β + γ)·det > 0`, and `x = e·det/(m·e)` is a convex combination of `a, b, c`,
//!   so `max(a·e, b·e, c·e) >= x·e = det/(m·e) >= det/|m| = d`.
//! - *The cones cover every direction.* The triangles form a closed surface (an octahedron's
//!   combinatorics, whatever the points). Every triangle positively oriented about the origin
//!   makes the radial projection of that surface onto the unit sphere a map whose degree is
//!   the sum of the triangles' (positive) solid angles over `4π`: a positive integer, so the
//!   map is onto, and every direction lies in some triangle's closed cone.
//!
//! Hence `g = min d` over the triangles (2D: over the edges, with `m` the edge turned by a
//! right angle and the same argument), and the cell reaches at most `1/g`.
//!
//! **Rounding.** The inverted point is computed as `ã = fl(p_j − p_i)·fl(2r/d²)`, with `d²`
//! the neighbour's computed squared distance (relative error `<= 6u`): relative error
//! `<= 10u` per component, so `|ã − a| <= 64u` for `|a| <= 4` (neighbours with
//! `d² >= fl(r²)/4` only). Every vector below is then at most 8 long, `|m| <= 64`, `|det| <= 256`; the
//! errors of the computed `det` and `|m|²`, from the inputs and from their own rounding, are
//! below `3·10^4·u < 10^-11` and `6·10^5·u < 10^-10`. The filter takes `det − 10^-10` as a
//! lower bound of the exact determinant and `|m|² + 10^-9` as an upper bound of the exact
//! `|m|²` (ten times the bounds), and the reported reach `(1 + 10^-11)/√t`, with
//! `t = min (det − 10^-10)²/(|m|² + 10^-9)`, absorbs the few `u` of the last operations. The
//! particle is decided interior when that reach is at most `1 − 2·INTERIOR_BAND`: its margin is
//! then below `−INTERIOR_BAND·r` by the float cell's whole error bound, where the clipping
//! path would also have reported an upper bound (crate docs), and the filter's reach is
//! reported in its place.
//!
//! Every other particle takes the clipping path unchanged; the filter only ever answers
//! "interior", never "boundary".

use crate::{Near, INTERIOR_BAND};
use boundary_core::Point;

/// Neighbours closer than `√MIN_Q2·r` are not used (their inverted points would exceed 4
/// in length, beyond the rounding bound of the module docs).
const MIN_Q2: f64 = 0.25;

/// Subtracted from each computed determinant: ten times its rounding bound (module docs).
const DET_SLACK: f64 = 1e-10;

/// Added to each computed `|m|²`: ten times its rounding bound (module docs).
const NORM_SLACK: f64 = 1e-9;

/// Relative rounding allowance of the reported reach (module docs).
const REACH_SLACK: f64 = 1e-11;

/// The largest reach the filter decides (units of `r`): below `1 − INTERIOR_BAND` by a
/// further `INTERIOR_BAND`, far more than the float cell's error bound.
const MAX_REACH: f64 = 1.0 - 2.0 * INTERIOR_BAND;

/// An upper bound on how far the cell of the particle at `p` reaches (units of `r`) from the
/// neighbours in `near` (all of them within `2r`, none at `p`, each with the bit pattern of its
/// computed squared distance from `p` and its index in `positions`), when it proves the reach at
/// most `1 − 2·INTERIOR_BAND`; `None` otherwise (module docs).
pub(crate) fn interior_reach<const D: usize>(
    p: &Point<D>,
    positions: &[Point<D>],
    r: f64,
    near: &[Near],
) -> Option<f64> {
    if D != 2 && D != 3 {
        return None;
    }
    // best[2k] along +e_k, best[2k + 1] along −e_k; score 0: none yet (a point with a
    // non-positive coordinate never wins, and an axis left without one fails below).
    let mut best = [[0.0f64; 3]; 6];
    let mut score = [0.0f64; 6];
    let min_d2 = MIN_Q2 * (r * r);
    for &(d2, _, j) in near {
        // a = 2q/|q|² = (p_j − p_i)·2r/|p_j − p_i|², from the squared distance in hand.
        let d2 = f64::from_bits(d2);
        // (A NaN cannot arise: the coordinates are finite.)
        if d2 < min_d2 {
            continue;
        }
        let f = 2.0 * r / d2;
        let pj = &positions[j as usize];
        let mut a = [0.0f64; 3];
        for k in 0..D {
            a[k] = (pj[k] - p[k]) * f;
        }
        for k in 0..D {
            if a[k] > score[2 * k] {
                score[2 * k] = a[k];
                best[2 * k] = a;
            }
            if -a[k] > score[2 * k + 1] {
                score[2 * k + 1] = -a[k];
                best[2 * k + 1] = a;
            }
        }
    }
    if score[..2 * D].iter().any(|&s| s <= 0.0) {
        return None;
    }
    let mut t = f64::INFINITY;
    for pattern in 0..(1usize << D) {
        // Bit k set: the point along −e_k.
        let pick = |k: usize| best[2 * k + (pattern >> k & 1)];
        let negatives = pattern.count_ones();
        let (det, mm) = if D == 3 {
            let (a, mut b, mut c) = (pick(0), pick(1), pick(2));
            if negatives % 2 == 1 {
                std::mem::swap(&mut b, &mut c);
            }
            let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let m = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            (
                m[0] * a[0] + m[1] * a[1] + m[2] * a[2],
                m[0] * m[0] + m[1] * m[1] + m[2] * m[2],
            )
        } else {
            let (mut a, mut b) = (pick(0), pick(1));
            if negatives % 2 == 1 {
                std::mem::swap(&mut a, &mut b);
            }
            // m = (b − a) turned clockwise: m·a = a_x b_y − a_y b_x.
            let e = [b[0] - a[0], b[1] - a[1]];
            (e[1] * a[0] - e[0] * a[1], e[0] * e[0] + e[1] * e[1])
        };
        let low = det - DET_SLACK;
        if low.is_nan() || low <= 0.0 {
            return None;
        }
        t = t.min(low * low / (mm + NORM_SLACK));
    }
    let reach = (1.0 + REACH_SLACK) / t.sqrt();
    (reach <= MAX_REACH).then_some(reach)
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_rational::BigRational as Q;
    use num_traits::Zero;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    fn rat(x: f64) -> Q {
        Q::from_float(x).expect("finite")
    }

    fn dot(a: &[Q], b: &[Q]) -> Q {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    /// The largest `|x|²` over `{x : q_j·x <= |q_j|²/2 for all j}` (`p` at the origin, units of
    /// `r`), in exact rationals from the `f64` inputs: every vertex (the solution of `D` of the
    /// planes, by Cramer's rule) that satisfies all of them. Only called where the filter
    /// claims the region bounded, so its vertices span it. An independent check: it neither
    /// inverts the points nor uses the filter's triangles.
    fn exact_reach2<const D: usize>(p: &Point<D>, others: &[Point<D>], r: f64) -> Q {
        let r = rat(r);
        let planes: Vec<(Vec<Q>, Q)> = others
            .iter()
            .map(|o| {
                let q: Vec<Q> = (0..D).map(|k| (rat(o[k]) - rat(p[k])) / &r).collect();
                let h = dot(&q, &q) / Q::from_integer(2.into());
                (q, h)
            })
            .collect();
        let det = |m: &[Vec<Q>]| -> Q {
            if D == 2 {
                &m[0][0] * &m[1][1] - &m[0][1] * &m[1][0]
            } else {
                &m[0][0] * (&m[1][1] * &m[2][2] - &m[1][2] * &m[2][1])
                    - &m[0][1] * (&m[1][0] * &m[2][2] - &m[1][2] * &m[2][0])
                    + &m[0][2] * (&m[1][0] * &m[2][1] - &m[1][1] * &m[2][0])
            }
        };
        let mut best = Q::zero();
        let n = planes.len();
        let mut pick = vec![0usize; D];
        let mut visit = |pick: &[usize]| {
            let rows: Vec<Vec<Q>> = pick.iter().map(|&i| planes[i].0.clone()).collect();
            let d = det(&rows);
            if d.is_zero() {
                return;
            }
            let x: Vec<Q> = (0..D)
                .map(|col| {
                    let m: Vec<Vec<Q>> = rows
                        .iter()
                        .zip(pick)
                        .map(|(row, &i)| {
                            let mut row = row.clone();
                            row[col] = planes[i].1.clone();
                            row
                        })
                        .collect();
                    det(&m) / &d
                })
                .collect();
            if planes.iter().all(|(q, h)| dot(q, &x) <= *h) {
                let x2 = dot(&x, &x);
                if x2 > best {
                    best = x2;
                }
            }
        };
        // Every D-subset of the planes.
        fn subsets(
            n: usize,
            start: usize,
            depth: usize,
            pick: &mut [usize],
            f: &mut dyn FnMut(&[usize]),
        ) {
            if depth == pick.len() {
                f(pick);
                return;
            }
            for i in start..n {
                pick[depth] = i;
                subsets(n, i + 1, depth + 1, pick, f);
            }
        }
        subsets(n, 0, 0, &mut pick, &mut visit);
        best
    }

    fn near_of<const D: usize>(p: &Point<D>, others: &[Point<D>]) -> Vec<Near> {
        others
            .iter()
            .enumerate()
            .map(|(j, o)| ((o - p).norm_squared().to_bits(), j as u32, j as u32))
            .collect()
    }

    /// Near-ties: the axis neighbours of a (rotated, perturbed) cross whose cell reaches
    /// within a few `1e-6` of the filter's threshold `1 − 2·INTERIOR_BAND`, so that the filter
    /// accepts some and refuses others. Wherever it answers, its reach is an upper bound of the
    /// exact reach (vertex enumeration in rationals), hence below `1 − 2·INTERIOR_BAND`:
    /// the particle is interior, exactly.
    fn near_ties<const D: usize>(seed: u64) {
        let mut rng = StdRng::seed_from_u64(seed);
        let (mut accepted, mut refused) = (0, 0);
        // Axis neighbours at distance δ: reach √D·δ/2 (units of r).
        let tie = 2.0 * MAX_REACH / (D as f64).sqrt();
        for trial in 0..400 {
            let r = [1.0, 0.013, 7.5][trial % 3];
            let offset = [0.0, 3.0, -1e3][trial % 3];
            let scale = [1e-5, 1e-7, 1e-9, 1e-12][trial / 3 % 4];
            let delta = tie * (1.0 + scale * rng.gen_range(-3.0..3.0));
            // A random rotation of the axes (a random orthonormal frame).
            let angle: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
            let (c, s) = (angle.cos(), angle.sin());
            let p = Point::<D>::from_fn(|k, _| offset + 0.25 * k as f64);
            let others: Vec<Point<D>> = (0..2 * D)
                .map(|m| {
                    let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
                    let mut v = [0.0; 3];
                    v[m / 2] = sign * delta;
                    // Rotate in the (x, y) plane, then perturb.
                    let w = [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]];
                    Point::<D>::from_fn(|k, _| {
                        p[k] + r * (w[k] + scale * 0.1 * rng.gen_range(-1.0..1.0))
                    })
                })
                .collect();
            match interior_reach(&p, &others, r, &near_of(&p, &others)) {
                Some(reach) => {
                    accepted += 1;
                    assert!(reach <= MAX_REACH, "trial {trial}");
                    let exact = exact_reach2(&p, &others, r);
                    assert!(
                        exact <= rat(reach) * rat(reach),
                        "trial {trial}: exact reach² {} above {}",
                        exact,
                        reach * reach
                    );
                }
                None => refused += 1,
            }
        }
        assert!(
            accepted > 50 && refused > 50,
            "{accepted} accepted, {refused} refused"
        );
    }

    #[test]
    fn the_filter_reach_bounds_the_exact_reach_at_near_ties_in_3d() {
        near_ties::<3>(11);
    }

    #[test]
    fn the_filter_reach_bounds_the_exact_reach_at_near_ties_in_2d() {
        near_ties::<2>(12);
    }

    /// Random neighbourhoods: jittered cubic-lattice shells (spacing 0.45 to 0.8 `r`, jitter
    /// up to 0.35 spacings, each neighbour kept with probability 0.8, some very close, every
    /// fifth one flattened into the particle's plane): wherever the filter answers, the exact
    /// reach is at most its reach.
    #[test]
    fn the_filter_reach_bounds_the_exact_reach_on_random_neighbourhoods() {
        let mut rng = StdRng::seed_from_u64(3);
        let (mut accepted, mut refused) = (0, 0);
        for trial in 0..200 {
            let p = Point::<3>::new(0.5, -2.0, 1e3);
            let flat = trial % 5 == 0;
            let spacing = rng.gen_range(0.45..0.8);
            let jitter = rng.gen_range(0.0..0.35);
            let mut others = vec![];
            for k in 0..27 {
                let mut d = [
                    (k % 3) as f64 - 1.0,
                    (k / 3 % 3) as f64 - 1.0,
                    (k / 9) as f64 - 1.0,
                ];
                if k == 13 || rng.gen_bool(0.2) {
                    continue;
                }
                for x in &mut d {
                    *x += jitter * rng.gen_range(-1.0..1.0);
                }
                if flat {
                    d[2] = 0.0;
                }
                others.push(Point::<3>::from_fn(|k, _| p[k] + spacing * d[k]));
            }
            match interior_reach(&p, &others, 1.0, &near_of(&p, &others)) {
                Some(reach) => {
                    accepted += 1;
                    assert!(!flat, "a flat neighbourhood bounds nothing");
                    assert!(
                        exact_reach2(&p, &others, 1.0) <= rat(reach) * rat(reach),
                        "trial {trial}"
                    );
                }
                None => refused += 1,
            }
        }
        assert!(
            accepted > 20 && refused > 40,
            "{accepted} accepted, {refused} refused"
        );
    }

    /// Neighbours too close to bound by the rounding argument (`|q|² < 1/4`) are not used: a
    /// cross of them proves nothing, the same cross a little farther out does.
    #[test]
    fn close_neighbours_are_not_used() {
        let p = Point::<3>::new(0.0, 0.0, 0.0);
        for (dist, proves) in [(0.45, false), (0.55, true)] {
            let others: Vec<Point<3>> = (0..6)
                .map(|m| {
                    let mut v = [0.0; 3];
                    v[m / 2] = if m % 2 == 0 { dist } else { -dist };
                    Point::<3>::from(v)
                })
                .collect();
            let got = interior_reach(&p, &others, 1.0, &near_of(&p, &others));
            assert_eq!(got.is_some(), proves, "{dist}");
        }
    }
}
