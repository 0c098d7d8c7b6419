//! The exact covering predicate: is `S_i` covered, decided in exact arithmetic for the given
//! floating-point input, for one radius ([`sphere_uncovered`]) or a radius per particle
//! ([`sphere_uncovered_power`], power cells). Used by the certified reference detectors
//! (`exact`, `dilts`) for the few particles whose floating-point decision falls inside its
//! error bound.
//!
//! # The question
//! Particle `i` at `p_i` is boundary iff its restricted Voronoi cell
//! `V_i = {x : |x − p_i| <= |x − p_j| for every neighbour j}` (neighbours: the other particles
//! with `0 < |p_j − p_i| < 2r`; exact duplicates of `p_i` excluded) has a point strictly farther
//! than `r` from `p_i` (the proof is in the [crate docs](crate)). A neighbour at `2r` or
//! more changes nothing: its bisector lies at distance `>= r` from `p_i`, so it removes from
//! `V_i` no point of the closed ball of radius `r` and at most one point of `S_i`, while an
//! uncovered part of `S_i` is open. So only neighbours with `|p_j − p_i|² < 4r²` (decided
//! exactly) enter.
//!
//! # Exact arithmetic
//! Every `f64` is a dyadic rational `m·2^e`. All coordinates (of `p_i`, of the neighbours) are
//! written as integers in the unit `2^E`, `E` the smallest exponent among them, so the
//! differences `q_j = p_j − p_i` are exact integers (the subtraction is done on integers, not
//! rounded as `p_j − p_i` in `f64` would be), then divided by their common power of two. The
//! bisector of `j` is the integer half-space `2q_j·x <= |q_j|²`. The cell is intersected with the
//! box `[−R, R]^D`, `R` the power of two with `r <= R < 2r` (or the unit, if larger): the box
//! contains the closed ball of radius `r`, and an uncovered open part of `S_i` has points just
//! beyond `r` inside the box, so the answer does not change.
//!
//! A vertex of the clipped cell is the solution of `D` plane equations, kept as integer
//! numerators and a positive integer denominator (Cramer's rule, so no growth from one clip to
//! the next). Which side of a plane a vertex lies on is the sign of an integer expression;
//! whether it lies beyond `r` is `|N|²·4^t > r²·den²` in integers. The integers are machine
//! words when a bound on their size (`D·B_a + B_b + 2D + 2 <= W − 2` bits for `W`-bit words,
//! `B_a`, `B_b` the bit lengths of the plane coefficients and offsets) proves that no sum of
//! products overflows: `i64` (`W = 64`, lattices of small integers, one machine multiplication
//! per product), else `i128`; otherwise arbitrary-precision `num_bigint::BigInt`. (The
//! bound: `den` and each `N_k` are sums of `D!` products of `D` plane entries, below
//! `2^(D·B_a + 3)` and `2^((D−1)·B_a + B_b + 3)`; a side test `a·N − b·den` sums `D + 1`
//! products below `2^(D·B_a + B_b + 3)`.) With [`sphere_uncovered`] the set-up (integer
//! coordinates, differences, squared distances, order) runs in `i128` too when every
//! coordinate fits in 125 bits in the common unit and `r` in 60 bits (a neighbour with a
//! coordinate difference of `2^61` or more then lies beyond `2r` and is skipped), and the
//! final test `|N|²·4^t > r²·den²` in 256-bit integers when `|N_k| < 2^63`, `den < 2^64` and
//! `r² < 2^128`, after a float estimate that settles vertices more than 2 % inside or outside
//! `r²`. Nothing is allocated per integer on these paths.
//!
//! # Vertex enumeration
//! - **2D**: Sutherland–Hodgman clipping of the box by every bisector, nearest first; each
//!   polygon edge remembers its line, each new vertex is the intersection of two lines.
//! - **3D**: for every plane `P` (box faces and bisectors) the face `P ∩ cell` is clipped the
//!   same way inside `P`, starting from `P ∩ box` (a square in the two coordinates `P` does
//!   not eliminate). Every vertex of the cell lies on some plane and is a vertex of that face,
//!   and every face vertex is a point of the cell, so the largest `|v|` over all faces is the
//!   largest over the cell.
//!
//! Vertices exactly on a clipping plane are kept (closed half-spaces); a cell that reaches
//! exactly `r` is interior (a tie: the touching point is covered by the closed ball of the
//! neighbour whose bisector passes through it).
//!
//! # Nearest bisectors first
//! Dense sets have hundreds of neighbours within `2r` of which a few dozen bound the cell. The
//! cell is first built from the nearest 32 bisectors only: it contains the whole cell, so if it
//! stays within `r` the particle is interior; a vertex of it beyond `r` that satisfies every
//! other bisector is a vertex of the whole cell, so the particle is boundary; otherwise the
//! prefix doubles, up to all of them (which always decides).
//!
//! The cost is `O(m²·k)` exact operations in 3D for a prefix of `m` planes and faces of `k`
//! vertices: microseconds for an inner particle of the cubic lattice at its tie radius (small
//! integers, the `i64` path), a few milliseconds for generic `f64` input (big integers); callers use it only where their
//! floating-point filters and certificates cannot decide. Measure with `cargo run --release
//! -p boundary-exact --example tie_lattice`.
//!
//! # Per-particle radii: power cells ([`sphere_uncovered_power`])
//! Particle `i` (centre `c`, radius `r_c`) is interior iff its sphere `S_c` is covered by the
//! closed balls `B_j = B(p_j, r_j)` of the other particles; a particle at `p_j == c` exactly
//! never covers, whatever its radius. With `y = x − c`, `q_j = p_j − c`, a point `y` of `S_c`
//! (`|y|² = r_c²`) lies outside `B_j` iff `|y − q_j|² > r_j²`, i.e. iff
//! `2q_j·y < |q_j|² + r_c² − r_j²`: strictly inside the half-space
//! `H_j = {2q_j·y <= |q_j|² + r_c² − r_j²}` bounded by the power (Laguerre) plane of `c` and
//! `j`. So the uncovered part of `S_c` is `S_c ∩ ∩_j int H_j`. With equal radii `H_j` is the
//! bisector half-space above. Only `j` with `0 < |q_j|² < (r_c + r_j)²` enter: a ball at
//! `|q_j| >= r_c + r_j` has at most one point in common with `S_c`, and the uncovered set is
//! open in `S_c`.
//!
//! Let `K = ∩_j H_j ∩ [−R, R]^D` (`R >= r_c`: the box contains the closed ball, and a
//! non-empty open part of `S_c` has points off the box faces, so the box changes nothing)
//! and `U = int K = ∩ int H_j ∩ (−R, R)^D` (finitely many half-spaces). Then `i` is boundary
//! iff `U ∩ S_c ≠ ∅` iff
//! - (a) `K` is full-dimensional, and
//! - (b) `max_K |y| > r_c`, and
//! - (c) `min_K |y| < r_c`.
//!
//! *Proof.* A point of `U` on `S_c` has a small ball around it inside `K`: (a) holds, and
//! the ball has points on both sides of the sphere: (b), (c). Conversely a full-dimensional
//! convex `K` is the closure of `U`, so by continuity of `|y|` `U` has a point `y⁺` with
//! `|y⁺| > r_c` and a point `y⁻` with `|y⁻| < r_c`; `U` is convex, so the segment between
//! them lies in `U` and crosses the sphere. ∎
//!
//! `K` is a bounded polytope, so (b) is the uniform test: a vertex beyond `r_c`. (a): `K` is
//! full-dimensional iff its vertices affinely span `R^D` (a flat `K` is possible with power
//! planes: two opposite half-spaces with the same plane; every point of `S_c` in such a `K`
//! has power 0 with respect to some `j`, i.e. lies on `∂B_j`, covered); decided as the rank
//! of the homogeneous integer vertex rows `(N, den)`. (c): if the origin satisfies every
//! constraint the minimum is 0. Otherwise the nearest point `y*` of `K` satisfies the KKT
//! condition `−y* = Σ λ_j a_j` over the active constraints (`λ_j >= 0`), so
//! `0 < |y*|² = −Σ λ_j b_j` and some active constraint has `b_j < 0` (box faces have
//! `b = R > 0`): `y*` lies on the face `F_j` of a plane whose offset is negative. For each
//! such face it is decided exactly whether it meets the open ball: the foot
//! `f = b_j a_j/|a_j|²` of the perpendicular (integer test `b_j² < r_c²|a_j|²`), if it
//! satisfies every constraint (`b_j (a_i·a_j) <= b_i |a_j|²`), is the nearest point of `F_j`;
//! otherwise the nearest point lies on the relative boundary of `F_j`, on a segment between
//! two of its vertices, and each such segment's nearest point (clamped to its ends) is tested
//! in integers. Distances use all `D` coordinates.
//!
//! When every offset is positive (the centre strictly inside every `H_j`; always so with
//! equal radii), (a) and (c) hold and the answer is exactly that of the uniform test, by
//! the same code ([`sphere_uncovered`]'s nearest-first prefixes, planes ordered by their
//! signed distance `b_j/|a_j|` from the centre). Otherwise the planes, most negative
//! distance first, are used in doubling prefixes too: a prefix cell `K_m ⊇ K` that fails
//! (a), (b) or (c) proves interior; one that passes and whose every vertex satisfies the
//! remaining planes equals `K` and proves boundary; the full set always decides.
//!
//! The tests run in the order (b), (a), (c); an empty `K` has no vertex and fails (b)
//! (every point of `S_c` is covered).
//!
//! Ties and degenerate input, all decided by the definition: a cell that reaches exactly
//! `r_c` (b), whose nearest point is exactly at `r_c` (c: `S_c` inside a bigger ball whose
//! sphere touches it), or that is flat is interior (the touching points lie on some `∂B_j`,
//! covered by the closed ball). Duplicates (`p_j == c` exactly) are ignored whatever `r_j`;
//! a ball touching `S_c` from outside (`|q_j| = r_c + r_j`) is ignored; a repeated
//! `(p_j, r_j)` counts once. Coordinates and all radii are written as integers in one common
//! dyadic unit, so every offset `|q_j|² + r_c² − r_j²` is an exact integer; lengths are then
//! divided by the largest `2^t` that keeps `R`, every `q_j` and every `(r_c² − r_j²)/4^t`
//! integral (with equal radii the `t` of [`sphere_uncovered`]), and the enumeration runs in
//! `i128` under the same size bound, else in `BigInt`.
//!
//! Cost follows the integer width: tens of microseconds per call in `i128` (dyadic radii
//! such as the tests' two-level sets at `s = 0.875`), about ten times that in `BigInt`
//! (non-dyadic radii, jittered positions), less in 2D. Callers use it only where their
//! floating-point filters and certificates cannot decide.

use boundary_core::{HalfSpace, Point};
use num_bigint::BigInt;
use num_traits::{Signed, ToPrimitive, Zero};

/// Whether the sphere of radius `r` around `centre` is **not** covered by the closed balls of
/// radius `r` around `others` (boundary), decided exactly for the given `f64` input.
///
/// `others` may hold any points: copies of `centre` (duplicates) and points at `2r` or farther
/// are ignored, exactly. Callers pass the particles a grid query within a little more than
/// `2r` returned, so that no neighbour whose exact distance is below `2r` is missed.
///
/// # Panics
/// If `r` is not positive and finite (callers pass the value of a [`boundary_core::Radius`]), or
/// if `D` is not 2 or 3.
///
/// ```
/// use boundary_core::Point;
/// use boundary_exact::exact_cover::sphere_uncovered;
///
/// // Four neighbours at distance 1 on the axes cover the unit-spaced circle iff r >= 1/√2.
/// let c = Point::<2>::new(0.0, 0.0);
/// let n = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]].map(Point::<2>::from);
/// assert!(!sphere_uncovered(&c, &n, 0.75));
/// assert!(sphere_uncovered(&c, &n, 0.7));
/// // fl(1/√2) lies above 1/√2: covered; the next float below lies under it: uncovered.
/// assert!(!sphere_uncovered(&c, &n, std::f64::consts::FRAC_1_SQRT_2));
/// assert!(sphere_uncovered(&c, &n, std::f64::consts::FRAC_1_SQRT_2.next_down()));
/// ```
pub fn sphere_uncovered<const D: usize>(centre: &Point<D>, others: &[Point<D>], r: f64) -> bool {
    assert!(D == 2 || D == 3, "exact_cover supports D = 2 and D = 3");
    assert!(r > 0.0 && r.is_finite(), "r must be positive and finite");
    // Common unit 2^E of every coordinate and of r.
    let mut e_min = i32::MAX;
    let mut note = |x: f64| {
        if let Some((_, e)) = dyadic(x) {
            e_min = e_min.min(e);
        }
    };
    note(r);
    centre.iter().for_each(|&x| note(x));
    others.iter().for_each(|p| p.iter().for_each(|&x| note(x)));
    if let Some(answer) = sphere_uncovered_small(centre, others, r, e_min) {
        return answer;
    }
    let to_int = |x: f64| -> BigInt {
        match dyadic(x) {
            None => BigInt::from(0u8),
            Some((m, e)) => BigInt::from(m) << ((e - e_min) as usize),
        }
    };
    let r_int = to_int(r);
    let four_r2 = (&r_int * &r_int) << 2usize;
    let c: [BigInt; D] = std::array::from_fn(|k| to_int(centre[k]));
    let mut near: Vec<(BigInt, [BigInt; D])> = Vec::new();
    for p in others {
        let q: [BigInt; D] = std::array::from_fn(|k| to_int(p[k]) - &c[k]);
        let d2 = norm2_big(&q);
        if !d2.is_zero() && d2 < four_r2 {
            near.push((d2, q));
        }
    }
    // Nearest first (their faces shrink the others fastest; `nearest_first` relies on the
    // order), exact duplicates once.
    near.sort_unstable();
    near.dedup();
    let qs: Vec<[BigInt; D]> = near.into_iter().map(|(_, q)| q).collect();
    // Box half-width R: the power of two with r <= R (in the unit 2^E: r_int <= 2^k).
    let k_box = box_exponent(&r_int);
    // Divide everything by the common power of two t (R = 2^k_box keeps it integral).
    let mut t = k_box;
    for q in &qs {
        for x in q {
            if let Some(z) = x.trailing_zeros() {
                t = t.min(z);
            }
        }
    }
    let qs: Vec<[BigInt; D]> = qs
        .into_iter()
        .map(|q| q.map(|x| x >> (t as usize)))
        .collect();
    let big_r = BigInt::from(1u8) << ((k_box - t) as usize);
    // Planes a·x <= b: the 2D box planes first (+x, −x, +y, −y, …), then the bisectors.
    let mut planes: Vec<([BigInt; D], BigInt)> = Vec::with_capacity(2 * D + qs.len());
    for axis in 0..D {
        for sign in [1i32, -1] {
            let a: [BigInt; D] = std::array::from_fn(|k| {
                if k == axis {
                    BigInt::from(sign)
                } else {
                    BigInt::from(0u8)
                }
            });
            planes.push((a, big_r.clone()));
        }
    }
    for q in &qs {
        planes.push((q.clone().map(|x| x << 1usize), norm2_big(q)));
    }
    let beyond = Beyond::new(&r_int * &r_int, 2 * t as usize, r, e_min, t);
    if let Some(small) = as_i128(&planes) {
        note_path(false, 128);
        nearest_first::<i128, D>(&small, &beyond)
    } else {
        note_path(false, 0);
        nearest_first::<BigInt, D>(&planes, &beyond)
    }
}

#[cfg(test)]
thread_local! {
    /// The path the last [`sphere_uncovered`] call on this thread took: whether its set-up
    /// ran in `i128`, and the width of the enumeration's integers (`0` for `BigInt`).
    static PATH: std::cell::Cell<(bool, u32)> = const { std::cell::Cell::new((false, 0)) };
}

/// Records the path of a [`sphere_uncovered`] call (tests only).
fn note_path(_small_set_up: bool, _width: u32) {
    #[cfg(test)]
    PATH.with(|p| p.set((_small_set_up, _width)));
}

/// [`sphere_uncovered`] with its set-up in `i128` (no allocation per integer): the same
/// planes in the same order, or `None` when an integer of the set-up could leave the bounds
/// below (then the caller builds them in `BigInt`).
///
/// Bounds: every coordinate in the unit `2^e_min` is `m·2^s` with `|m| < 2^53`, kept when
/// `s <= 72` (below `2^125`, so differences fit); `r < 2^60` in that unit, so `4r² < 2^122`;
/// a neighbour with some `|q_k| >= 2^61 > 2r` lies at `2r` or farther and is skipped (exactly,
/// as the `BigInt` path skips it); the others have `|q|² < 3·2^122`. The planes then go to
/// the enumeration in `i128` under the bound of [`as_i128`], else in `BigInt`.
fn sphere_uncovered_small<const D: usize>(
    centre: &Point<D>,
    others: &[Point<D>],
    r: f64,
    e_min: i32,
) -> Option<bool> {
    let to_int = |x: f64| -> Option<i128> {
        match dyadic(x) {
            None => Some(0),
            Some((m, e)) => {
                let s = (e - e_min) as u32;
                (s <= 125 - 53).then(|| i128::from(m) << s)
            }
        }
    };
    let r_int = to_int(r)?;
    if r_int >= 1 << 60 {
        return None;
    }
    let four_r2 = (r_int * r_int) << 2;
    let mut c = [0i128; D];
    for (k, x) in c.iter_mut().enumerate() {
        *x = to_int(centre[k])?;
    }
    let mut near: Vec<(i128, [i128; D])> = Vec::with_capacity(others.len());
    for p in others {
        let mut q = [0i128; D];
        let mut far = false;
        for (k, x) in q.iter_mut().enumerate() {
            *x = to_int(p[k])? - c[k];
            far |= x.unsigned_abs() >= 1 << 61;
        }
        if far {
            continue;
        }
        let d2: i128 = q.iter().map(|x| x * x).sum();
        if d2 != 0 && d2 < four_r2 {
            near.push((d2, q));
        }
    }
    // The order and the repeats of the `BigInt` path (same integers, same comparisons).
    near.sort_unstable();
    near.dedup();
    let bits = |x: i128| u64::from(128 - x.unsigned_abs().leading_zeros());
    // Box half-width R = 2^k_box >= r (module docs), as `box_exponent`.
    let k_box = bits(r_int) - u64::from(r_int.count_ones() == 1);
    let mut t = k_box;
    for (_, q) in &near {
        for &x in q {
            if x != 0 {
                t = t.min(u64::from(x.trailing_zeros()));
            }
        }
    }
    let big_r: i128 = 1 << (k_box - t);
    let mut planes: Vec<([i128; D], i128)> = Vec::with_capacity(2 * D + near.len());
    for axis in 0..D {
        for sign in [1i128, -1] {
            let mut a = [0i128; D];
            a[axis] = sign;
            planes.push((a, big_r));
        }
    }
    for (_, q) in &near {
        let q = q.map(|x| x >> t);
        planes.push((q.map(|x| x << 1), q.iter().map(|x| x * x).sum()));
    }
    let beyond = Beyond::new(BigInt::from(r_int * r_int), 2 * t as usize, r, e_min, t);
    let bits_a = planes
        .iter()
        .flat_map(|(a, _)| a.iter().map(|&x| bits(x)))
        .max()
        .unwrap_or(0);
    let bits_b = planes.iter().map(|&(_, b)| bits(b)).max().unwrap_or(0);
    Some(if fits::<D>(bits_a, bits_b, 64) {
        // Lattices of small integers: one machine multiplication per product.
        note_path(true, 64);
        let words: Vec<([i64; D], i64)> = planes
            .iter()
            .map(|(a, b)| (a.map(|x| x as i64), *b as i64))
            .collect();
        nearest_first::<i64, D>(&words, &beyond)
    } else if fits::<D>(bits_a, bits_b, 128) {
        note_path(true, 128);
        nearest_first::<i128, D>(&planes, &beyond)
    } else {
        note_path(true, 0);
        let big: Vec<([BigInt; D], BigInt)> = planes
            .iter()
            .map(|(a, b)| (a.map(BigInt::from), BigInt::from(*b)))
            .collect();
        nearest_first::<BigInt, D>(&big, &beyond)
    })
}

/// The size bound of the enumeration in signed integers of `width` bits (module docs):
/// `D·B_a + B_b + 2D + 2 <= width − 2` (`126` for `i128`, `62` for `i64`), `B_a`, `B_b` the
/// largest bit lengths of the plane coefficients and offsets.
fn fits<const D: usize>(bits_a: u64, bits_b: u64, width: u64) -> bool {
    D as u64 * bits_a + bits_b + 2 * D as u64 + 2 <= width - 2
}

/// The exponent `k` of the box half-width `R = 2^k`: the smallest power of two `>= r`
/// (`r` a positive integer in the common unit): `2^(bits−1) <= r < 2^bits`, and `r` is a
/// power of two iff it has one bit set.
fn box_exponent(r: &BigInt) -> u64 {
    let bits = r.bits();
    if r.trailing_zeros() == Some(bits - 1) {
        bits - 1
    } else {
        bits
    }
}

/// The planes as `i128` when a bound on the integers the enumeration forms
/// (`D·B_a + B_b + 2D + 2 <= 126` bits, module docs) proves that none overflows.
#[allow(clippy::type_complexity)]
fn as_i128<const D: usize>(planes: &[([BigInt; D], BigInt)]) -> Option<Vec<([i128; D], i128)>> {
    let bits_a = planes
        .iter()
        .flat_map(|(a, _)| a.iter().map(|x| x.bits()))
        .max()
        .unwrap_or(0);
    let bits_b = planes.iter().map(|(_, b)| b.bits()).max().unwrap_or(0);
    fits::<D>(bits_a, bits_b, 128).then(|| {
        planes
            .iter()
            .map(|(a, b)| {
                (
                    std::array::from_fn(|k| a[k].to_i128().unwrap_or(0)),
                    b.to_i128().unwrap_or(0),
                )
            })
            .collect()
    })
}

/// Whether the sphere of radius `r_centre` around `centre` is **not** covered by the closed
/// balls `B(p_j, r_j)` of `others` (boundary), decided exactly for the given `f64` input: the
/// per-particle-radius (power cell) generalisation of [`sphere_uncovered`] (see the module
/// docs, *Per-particle radii*).
///
/// `others` may hold any superset of the particles with `|p_j − centre| <= r_centre + r_j`:
/// exact copies of `centre` (duplicates, whatever their radii), balls that at most touch the
/// sphere from outside (`|p_j − centre| >= r_centre + r_j`) and repeated entries are ignored,
/// exactly. With every `r_j == r_centre` the answer is that of [`sphere_uncovered`].
///
/// # Panics
/// If `r_centre` or some `r_j` is not positive and finite (callers pass validated radii, as
/// [`boundary_core::ParticleSet::with_radii`] makes them), or if `D` is not 2 or 3.
///
/// ```
/// use boundary_core::Point;
/// use boundary_exact::exact_cover::sphere_uncovered_power;
///
/// let c = Point::<2>::new(0.0, 0.0);
/// // A bigger neighbour at distance 1 with radius 2 holds the unit circle: its farthest
/// // point (−1, 0) lies exactly on the neighbour's sphere, covered by the closed ball.
/// let big = |r: f64| [(Point::<2>::new(1.0, 0.0), r)];
/// assert!(!sphere_uncovered_power(&c, 1.0, &big(2.0)));
/// // One ulp less and the circle pokes out around (−1, 0).
/// assert!(sphere_uncovered_power(&c, 1.0, &big(2f64.next_down())));
/// // Equal radii: the uniform definition (four axis neighbours cover iff r >= 1/√2).
/// let n = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]].map(Point::<2>::from);
/// let same = |r: f64| n.map(|p| (p, r));
/// assert!(!sphere_uncovered_power(&c, 0.75, &same(0.75)));
/// assert!(sphere_uncovered_power(&c, 0.7, &same(0.7)));
/// // Flat power cell: two radius-5 balls at distance 4 on either side of a circle of
/// // radius 3 meet its sphere in the same two points; covered. One ulp less: uncovered.
/// let pair = |r: f64| [(Point::<2>::new(4.0, 0.0), r), (Point::<2>::new(-4.0, 0.0), 5.0)];
/// assert!(!sphere_uncovered_power(&c, 3.0, &pair(5.0)));
/// assert!(sphere_uncovered_power(&c, 3.0, &pair(5f64.next_down())));
/// ```
pub fn sphere_uncovered_power<const D: usize>(
    centre: &Point<D>,
    r_centre: f64,
    others: &[(Point<D>, f64)],
) -> bool {
    sphere_uncovered_in(centre, r_centre, others, &[])
}

/// [`sphere_uncovered_power`] where the closed solid half-spaces `solids` cover too: whether
/// some point of the sphere of radius `r_centre` around `centre` that lies outside every
/// solid is outside every ball of `others` (boundary), decided exactly for the given `f64`
/// input (see [`boundary_core::domain`] for the definition).
///
/// A solid `x_a <= c` is the half-space `−y_a <= p_a − c` of the cell (`y = x − centre`),
/// `x_a >= c` is `y_a <= c − p_a`: planes whose integer offsets are exact differences in the
/// common unit, like the neighbours' (module docs). With `y` in the unit `2^t` the offset is
/// divided by `2^t`, so `t` is also bounded by its trailing zeros. The centre may lie on or
/// inside a solid (a negative offset): the general test, (a), (b) and (c) of the module
/// docs, decides it; with every offset positive the uniform test does. The closed solid makes
/// a point on its surface covered: a tie, interior.
///
/// # Panics
/// As [`sphere_uncovered_power`]; a solid's axis must be below `D`.
///
/// ```
/// use boundary_core::{HalfSpace, Point};
/// use boundary_exact::exact_cover::sphere_uncovered_in;
///
/// // A lone particle at height 1 above the floor y <= 0, radius 1: its lowest point touches
/// // the floor, the rest is open: boundary. Deep in the floor: interior.
/// let floor = [HalfSpace::parse("y<0").unwrap()];
/// assert!(sphere_uncovered_in(&Point::<2>::new(0.0, 1.0), 1.0, &[], &floor));
/// assert!(!sphere_uncovered_in(&Point::<2>::new(0.0, -1.0), 1.0, &[], &floor));
/// // Four neighbours at distance 1 below and beside it (a row on the floor and one above):
/// // a particle at height 0.5 with r = 0.75 is covered where the floor does not hold it.
/// let c = Point::<2>::new(0.0, 0.5);
/// let n = [[1.0, 0.5], [-1.0, 0.5], [0.0, 1.5]].map(|p| (Point::<2>::from(p), 0.75));
/// assert!(!sphere_uncovered_in(&c, 0.75, &n, &floor));
/// assert!(sphere_uncovered_in(&c, 0.75, &n, &[]));
/// ```
pub fn sphere_uncovered_in<const D: usize>(
    centre: &Point<D>,
    r_centre: f64,
    others: &[(Point<D>, f64)],
    solids: &[HalfSpace],
) -> bool {
    assert!(D == 2 || D == 3, "exact_cover supports D = 2 and D = 3");
    for h in solids {
        assert!(h.axis() < D, "solid {h} has no axis in {D}D");
    }
    assert!(
        r_centre > 0.0 && r_centre.is_finite(),
        "r_centre must be positive and finite (it is {r_centre})"
    );
    for (j, &(_, r)) in others.iter().enumerate() {
        assert!(
            r > 0.0 && r.is_finite(),
            "the radius of others[{j}] must be positive and finite (it is {r})"
        );
    }
    // Common unit 2^E of every coordinate and every radius.
    let mut e_min = i32::MAX;
    let mut note = |x: f64| {
        if let Some((_, e)) = dyadic(x) {
            e_min = e_min.min(e);
        }
    };
    note(r_centre);
    centre.iter().for_each(|&x| note(x));
    for (p, r) in others {
        note(*r);
        p.iter().for_each(|&x| note(x));
    }
    solids.iter().for_each(|h| note(h.value()));
    let to_int = |x: f64| -> BigInt {
        match dyadic(x) {
            None => BigInt::from(0u8),
            Some((m, e)) => BigInt::from(m) << ((e - e_min) as usize),
        }
    };
    let rc = to_int(r_centre);
    let rc2 = &rc * &rc;
    let c: [BigInt; D] = std::array::from_fn(|k| to_int(centre[k]));
    // The solids' planes (a, b) in the base unit: sign·y_axis <= b, with b the exact depth
    // of the centre on the fluid side.
    let walls: Vec<(f64, usize, i32, BigInt)> = solids
        .iter()
        .map(|h| {
            let (sign, b) = if h.solid_below() {
                (-1, &c[h.axis()] - to_int(h.value()))
            } else {
                (1, to_int(h.value()) - &c[h.axis()])
            };
            (b.approx(), h.axis(), sign, b)
        })
        .collect();
    // (signed distance of the power plane from the centre, for the order only; q_j; r_j)
    let mut near: Vec<(f64, [BigInt; D], BigInt)> = Vec::new();
    for (p, r) in others {
        let q: [BigInt; D] = std::array::from_fn(|k| to_int(p[k]) - &c[k]);
        let d2 = norm2_big(&q);
        if d2.is_zero() {
            continue;
        }
        let rj = to_int(*r);
        let reach = &rc + &rj;
        if d2 >= &reach * &reach {
            continue;
        }
        let offset = &d2 + &rc2 - &rj * &rj;
        let key = offset.approx() / (2.0 * d2.approx().sqrt());
        near.push((key, q, rj));
    }
    // Strongest planes first (the power plane nearest the centre on its side, most negative
    // offsets first; with equal radii this is nearest first), exact repeats once.
    near.sort_by(|x, y| {
        x.0.total_cmp(&y.0)
            .then_with(|| x.1.cmp(&y.1))
            .then_with(|| x.2.cmp(&y.2))
    });
    near.dedup_by(|x, y| x.1 == y.1 && x.2 == y.2);
    let k_box = box_exponent(&rc);
    // Divide every length by the common power of two 2^t that keeps the planes integral:
    // t <= k_box (R), t <= the trailing zeros of every q_j component, and 4^t divides every
    // r_c² − r_j² (nothing with equal radii, so t is that of `sphere_uncovered`). Then
    // a_j = 2q_j/2^t and b_j = (|q_j|² + r_c² − r_j²)/4^t are exact integers.
    let mut t = k_box;
    for (_, q, rj) in &near {
        for x in q {
            if let Some(z) = x.trailing_zeros() {
                t = t.min(z);
            }
        }
        if let Some(z) = (&rc2 - rj * rj).trailing_zeros() {
            t = t.min(z / 2);
        }
    }
    for (_, _, _, b) in &walls {
        if let Some(z) = b.trailing_zeros() {
            t = t.min(z);
        }
    }
    let sh = t as usize;
    let big_r = BigInt::from(1u8) << ((k_box - t) as usize);
    let mut planes: Vec<([BigInt; D], BigInt)> = Vec::with_capacity(2 * D + near.len());
    for axis in 0..D {
        for sign in [1i32, -1] {
            let a: [BigInt; D] = std::array::from_fn(|k| {
                if k == axis {
                    BigInt::from(sign)
                } else {
                    BigInt::from(0u8)
                }
            });
            planes.push((a, big_r.clone()));
        }
    }
    // The neighbours' and the solids' planes merged, strongest (most negative distance) first.
    let mut keyed: Vec<(f64, ([BigInt; D], BigInt))> = Vec::with_capacity(near.len() + walls.len());
    for (key, q, rj) in near {
        let offset = (norm2_big(&q) + &rc2 - &rj * &rj) >> (2 * sh);
        keyed.push((key, (q.map(|x| (x >> sh) << 1usize), offset)));
    }
    for (key, axis, sign, b) in walls {
        let a: [BigInt; D] =
            std::array::from_fn(|k| BigInt::from(if k == axis { sign } else { 0 }));
        keyed.push((key, (a, b >> sh)));
    }
    keyed.sort_by(|x, y| x.0.total_cmp(&y.0));
    keyed.dedup_by(|x, y| x.1 == y.1);
    planes.extend(keyed.into_iter().map(|(_, plane)| plane));
    // Every offset positive: the centre lies strictly inside every power half-space, so the
    // cell is full-dimensional and its minimum is 0 (module docs): the uniform test decides.
    let fast = planes.iter().all(|(_, b)| b.is_positive());
    let beyond = Beyond::new(rc2, 2 * sh, r_centre, e_min, t);
    if let Some(small) = as_i128(&planes) {
        if fast {
            nearest_first::<i128, D>(&small, &beyond)
        } else {
            power_prefixes::<i128, D>(&small, &beyond)
        }
    } else if fast {
        nearest_first::<BigInt, D>(&planes, &beyond)
    } else {
        power_prefixes::<BigInt, D>(&planes, &beyond)
    }
}

/// The bisectors the exact cell is built from at first: the nearest ones. Dense sets have
/// hundreds of neighbours within `2r` (a lattice at `r = 2.25a`: about 380), of which the
/// nearest few dozen bound the cell; the enumeration costs the square of the plane count.
const FIRST_PLANES: usize = 32;

/// Decides the cell of `planes` (the `2D` box planes, then the bisectors nearest first) from
/// growing prefixes of its bisectors. The cell of a prefix contains the whole cell, so a prefix
/// cell within `r` proves interior; a vertex of the prefix cell beyond `r` that satisfies every
/// remaining plane is a vertex of the whole cell and proves boundary; otherwise the prefix
/// doubles. The last prefix is the whole set, which always decides.
fn nearest_first<T: Ring, const D: usize>(planes: &[([T; D], T)], beyond: &Beyond) -> bool {
    let total = planes.len() - 2 * D;
    let mut k = total.min(FIRST_PLANES);
    loop {
        let (used, rest) = planes.split_at(2 * D + k);
        let in_rest = |v: &Vertex<T, D>| rest.iter().all(|plane| side(plane, v) <= 0);
        match cell_reaches_beyond(used, beyond, in_rest) {
            Reach::Within => return false,
            Reach::Beyond => return true,
            // Unreachable with `rest` empty: every vertex then satisfies it.
            Reach::Unsure if k == total => return true,
            Reach::Unsure => k = total.min(2 * k),
        }
    }
}

/// `x = m·2^e` with `m` odd, or `None` for zero.
fn dyadic(x: f64) -> Option<(i64, i32)> {
    if x == 0.0 {
        return None;
    }
    let bits = x.to_bits();
    let exp_bits = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    let (m, e) = if exp_bits == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), exp_bits - 1075)
    };
    let z = m.trailing_zeros();
    let m = (m >> z) as i64;
    Some((if x < 0.0 { -m } else { m }, e + z as i32))
}

fn norm2_big<const D: usize>(q: &[BigInt; D]) -> BigInt {
    q.iter().map(|x| x * x).sum()
}

/// The integer ring the enumeration runs in: `i128` (when the size bound holds) or `BigInt`.
trait Ring: Clone + std::fmt::Debug {
    fn add(&self, o: &Self) -> Self;
    fn sub(&self, o: &Self) -> Self;
    fn mul(&self, o: &Self) -> Self;
    fn neg(&self) -> Self;
    fn sign(&self) -> i8;
    fn big(&self) -> BigInt;
    fn approx(&self) -> f64;
    /// The value as `i128`, when it fits.
    fn small(&self) -> Option<i128>;
}

/// The machine-word rings, used under the size bound of [`fits`] for their width.
macro_rules! word_ring {
    ($t:ty) => {
        impl Ring for $t {
            fn add(&self, o: &Self) -> Self {
                self + o
            }
            fn sub(&self, o: &Self) -> Self {
                self - o
            }
            fn mul(&self, o: &Self) -> Self {
                self * o
            }
            fn neg(&self) -> Self {
                -self
            }
            fn sign(&self) -> i8 {
                self.signum() as i8
            }
            fn big(&self) -> BigInt {
                BigInt::from(*self)
            }
            fn approx(&self) -> f64 {
                *self as f64
            }
            fn small(&self) -> Option<i128> {
                Some(i128::from(*self))
            }
        }
    };
}
word_ring!(i64);
word_ring!(i128);

impl Ring for BigInt {
    fn add(&self, o: &Self) -> Self {
        self + o
    }
    fn sub(&self, o: &Self) -> Self {
        self - o
    }
    fn mul(&self, o: &Self) -> Self {
        self * o
    }
    fn neg(&self) -> Self {
        -self
    }
    fn sign(&self) -> i8 {
        if self.is_positive() {
            1
        } else if self.is_negative() {
            -1
        } else {
            0
        }
    }
    fn big(&self) -> BigInt {
        self.clone()
    }
    fn approx(&self) -> f64 {
        self.to_f64().unwrap_or(f64::INFINITY)
    }
    fn small(&self) -> Option<i128> {
        self.to_i128()
    }
}

/// The final test `|v| > r` for a vertex `v = N/den` (in the unit `2^(E+t)`).
struct Beyond {
    /// `r²` in the unit `2^(2E)`.
    r2: BigInt,
    /// `r2` when it is below `2^128`: the exact test then runs in 256-bit integers whenever
    /// `|N_k| < 2^63` and `den < 2^64` (see [`Beyond::test`]).
    r2_small: Option<u128>,
    /// `2t`: `|v|² > r²` iff `|N|²·2^(2t) > r2·den²`.
    shift: usize,
    /// `r` and the unit `2^(E+t)` as floats, for a quick rejection of vertices well inside.
    r_f64: f64,
    unit_f64: f64,
}

impl Beyond {
    /// The test for `r² = r2` in the unit `2^(2E)`, `E = e_min`, vertices in the unit
    /// `2^(E+t)` (`shift = 2t`).
    fn new(r2: BigInt, shift: usize, r_f64: f64, e_min: i32, t: u64) -> Self {
        Beyond {
            r2_small: r2.to_u128(),
            r2,
            shift,
            r_f64,
            unit_f64: 2f64.powi(e_min) * 2f64.powi(t as i32),
        }
    }

    fn test<T: Ring, const D: usize>(&self, n: &[T; D], den: &T) -> bool {
        // Quick decision by the float estimate when |v|² is below 0.98 r² or above 1.02 r²:
        // with every quantity a normal float, each conversion, product and quotient is
        // within a relative 2^-52, so the estimate is within a relative 1e-14 of |v|²/r²,
        // far inside the 2 % slack. Otherwise (or with a subnormal or non-finite quantity)
        // decide exactly.
        let d = den.approx();
        let n2: f64 = n.iter().map(|x| x.approx() * x.approx()).sum();
        let (d2, unit2, r2) = (
            d * d,
            self.unit_f64 * self.unit_f64,
            self.r_f64 * self.r_f64,
        );
        let ratio = n2 / d2;
        let v2 = ratio * unit2;
        if [n2, d2, ratio, unit2, v2, r2].iter().all(|x| x.is_normal()) {
            if v2 < 0.98 * r2 {
                return false;
            }
            if v2 > 1.02 * r2 {
                return true;
            }
        }
        // Exact in 256 bits: |N|² < 3·2^126 and den² < 2^128 fit in u128, r2·den² < 2^256.
        if let (Some(r2), Some(den)) = (self.r2_small, den.small()) {
            let small = |x: &T| x.small().filter(|x| x.unsigned_abs() < 1 << 63);
            if den > 0 && den < 1 << 64 && n.iter().all(|x| small(x).is_some()) {
                let n2: u128 = n
                    .iter()
                    .map(|x| small(x).map_or(0, |x| x.unsigned_abs().pow(2)))
                    .sum();
                let den = den.unsigned_abs();
                return shl_exceeds(n2, self.shift, mul_wide(r2, den * den));
            }
        }
        let den = den.big();
        let lhs: BigInt = n.iter().map(|x| x.big() * x.big()).sum::<BigInt>() << self.shift;
        lhs > &self.r2 * &den * &den
    }
}

/// The full product `a·b` as `(high, low)` 128-bit halves.
fn mul_wide(a: u128, b: u128) -> (u128, u128) {
    const LOW: u128 = (1 << 64) - 1;
    let (a1, a0) = (a >> 64, a & LOW);
    let (b1, b0) = (b >> 64, b & LOW);
    let (p00, p01, p10, p11) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
    // Below 3·2^64: no overflow.
    let mid = (p00 >> 64) + (p01 & LOW) + (p10 & LOW);
    let low = (p00 & LOW) | (mid << 64);
    let high = p11 + (p01 >> 64) + (p10 >> 64) + (mid >> 64);
    (high, low)
}

/// Whether `x·2^shift > rhs`, `rhs = (high, low)` a 256-bit integer.
fn shl_exceeds(x: u128, shift: usize, rhs: (u128, u128)) -> bool {
    if x == 0 {
        return false;
    }
    let bits = 128 - x.leading_zeros() as usize;
    if bits + shift > 256 {
        // x·2^shift >= 2^256 > rhs.
        return true;
    }
    let lhs = match shift {
        0 => (0, x),
        s if s < 128 => (x >> (128 - s), x << s),
        s => (x << (s - 128), 0),
    };
    lhs > rhs
}

/// A vertex: `N/den` with `den > 0`, and the plane of the polygon edge leaving it.
#[derive(Debug, Clone)]
struct Vertex<T, const D: usize> {
    n: [T; D],
    den: T,
    line_out: usize,
}

/// The intersection of the planes `ids` (Cramer's rule), `None` if they are not independent.
/// With rows `a_k` and offsets `b_k`: in 2D `den = det(a_0, a_1)`; in 3D `den = a_0·(a_1×a_2)`
/// and `N = b_0 (a_1×a_2) + b_1 (a_2×a_0) + b_2 (a_0×a_1)` (the cofactor expansion of each
/// Cramer numerator, so the same integers as the determinants, with fewer products).
fn solve<T: Ring, const D: usize>(planes: &[([T; D], T)], ids: [usize; D]) -> Option<([T; D], T)> {
    let a = |row: usize, col: usize| &planes[ids[row]].0[col];
    let b = |row: usize| &planes[ids[row]].1;
    let (mut n, mut den): ([T; D], T) = match D {
        2 => {
            let den = a(0, 0).mul(a(1, 1)).sub(&a(0, 1).mul(a(1, 0)));
            let x = [
                b(0).mul(a(1, 1)).sub(&a(0, 1).mul(b(1))),
                a(0, 0).mul(b(1)).sub(&b(0).mul(a(1, 0))),
            ];
            (std::array::from_fn(|k| x[k].clone()), den)
        }
        3 => {
            // cross(u, v)_k = u_{k+1} v_{k+2} − u_{k+2} v_{k+1}, written out (a closure per
            // component through `array::from_fn` was not inlined).
            let m = |u: usize, k1: usize, v: usize, k2: usize| a(u, k1).mul(a(v, k2));
            let cross = |u: usize, v: usize| -> [T; 3] {
                [
                    m(u, 1, v, 2).sub(&m(u, 2, v, 1)),
                    m(u, 2, v, 0).sub(&m(u, 0, v, 2)),
                    m(u, 0, v, 1).sub(&m(u, 1, v, 0)),
                ]
            };
            let (c12, c20, c01) = (cross(1, 2), cross(2, 0), cross(0, 1));
            let den = a(0, 0)
                .mul(&c12[0])
                .add(&a(0, 1).mul(&c12[1]))
                .add(&a(0, 2).mul(&c12[2]));
            let num = |k: usize| {
                b(0).mul(&c12[k])
                    .add(&b(1).mul(&c20[k]))
                    .add(&b(2).mul(&c01[k]))
            };
            let x = [num(0), num(1), num(2)];
            (std::array::from_fn(|k| x[k].clone()), den)
        }
        _ => unreachable!("D is 2 or 3"),
    };
    let s = den.sign();
    if s == 0 {
        return None;
    }
    if s < 0 {
        den = den.neg();
        n = n.map(|x| x.neg());
    }
    Some((n, den))
}

/// Sign of `a·v − b` for `v = N/den` (`den > 0`): `> 0` outside the half-space.
fn side<T: Ring, const D: usize>(plane: &([T; D], T), v: &Vertex<T, D>) -> i8 {
    let mut s = plane.1.mul(&v.den).neg();
    for k in 0..D {
        s = s.add(&plane.0[k].mul(&v.n[k]));
    }
    s.sign()
}

/// Clips the convex polygon `poly` (vertices in order, each with the plane of its outgoing
/// edge) by plane `h`; `fixed` is the plane the polygon lies in (3D) or none (2D).
fn clip<T: Ring, const D: usize>(
    poly: &mut Vec<Vertex<T, D>>,
    out: &mut Vec<Vertex<T, D>>,
    planes: &[([T; D], T)],
    fixed: Option<usize>,
    h: usize,
) {
    // The signs on the stack for the usual faces (a few dozen vertices at most).
    let mut stack = [0i8; 64];
    let mut heap = Vec::new();
    let signs: &mut [i8] = if poly.len() <= stack.len() {
        &mut stack[..poly.len()]
    } else {
        heap.resize(poly.len(), 0);
        &mut heap
    };
    for (s, v) in signs.iter_mut().zip(poly.iter()) {
        *s = side(&planes[h], v);
    }
    if signs.iter().all(|&s| s <= 0) {
        return;
    }
    out.clear();
    let m = poly.len();
    let crossing = |line: usize, line_out: usize| -> Option<Vertex<T, D>> {
        let ids: [usize; D] = match fixed {
            None => std::array::from_fn(|k| [line, h][k]),
            Some(p) => std::array::from_fn(|k| [p, line, h][k]),
        };
        solve(planes, ids).map(|(n, den)| Vertex { n, den, line_out })
    };
    for k in 0..m {
        let a = &poly[k];
        let (sa, sb) = (signs[k], signs[(k + 1) % m]);
        let line = a.line_out;
        if sa <= 0 {
            let mut kept = a.clone();
            if sa == 0 && sb > 0 {
                kept.line_out = h;
            }
            out.push(kept);
            if sa < 0 && sb > 0 {
                // Leaving: the crossing point starts an edge along h. Strict signs on both
                // ends make the line meet h in one point, so `solve` succeeds.
                out.extend(crossing(line, h));
            }
        } else if sb < 0 {
            // Entering: the crossing point continues along the edge's own line.
            out.extend(crossing(line, line));
        }
    }
    std::mem::swap(poly, out);
}

/// What the vertices of a cell say about its reach.
enum Reach {
    /// No vertex beyond `r`.
    Within,
    /// A vertex beyond `r` that `confirm` accepted.
    Beyond,
    /// Vertices beyond `r`, none accepted by `confirm`.
    Unsure,
}

/// Whether the cell `∩ {a·x <= b}` (planes `0..2D` the box) has a vertex beyond `r` that
/// `confirm` accepts.
fn cell_reaches_beyond<T: Ring, const D: usize>(
    planes: &[([T; D], T)],
    beyond: &Beyond,
    confirm: impl Fn(&Vertex<T, D>) -> bool,
) -> Reach {
    let mut unsure = false;
    // The verdict of one polygon's vertices, remembering a rejected one in `unsure`.
    let mut judge = |poly: &[Vertex<T, D>]| {
        for v in poly {
            if beyond.test(&v.n, &v.den) {
                if confirm(v) {
                    return true;
                }
                unsure = true;
            }
        }
        false
    };
    let mut poly: Vec<Vertex<T, D>> = Vec::new();
    let mut out: Vec<Vertex<T, D>> = Vec::new();
    if D == 2 {
        polygon_2d(planes, &mut poly, &mut out);
        return if judge(&poly) {
            Reach::Beyond
        } else if unsure {
            Reach::Unsure
        } else {
            Reach::Within
        };
    }
    for p in 0..planes.len() {
        face_3d(planes, p, &mut poly, &mut out);
        if judge(&poly) {
            return Reach::Beyond;
        }
    }
    if unsure {
        Reach::Unsure
    } else {
        Reach::Within
    }
}

/// The square of the box in axes `(b, c)` (plane ids `2b`, `2b+1` for `+`, `−`),
/// counter-clockwise, as intersections with the plane `fixed` (3D) or alone (2D).
fn box_square<T: Ring, const D: usize>(
    planes: &[([T; D], T)],
    poly: &mut Vec<Vertex<T, D>>,
    fixed: Option<usize>,
    b: usize,
    c: usize,
) {
    poly.clear();
    let (bp, bm, cp, cm) = (2 * b, 2 * b + 1, 2 * c, 2 * c + 1);
    for (l1, l2, line_out) in [(bp, cm, bp), (bp, cp, cp), (bm, cp, bm), (bm, cm, cm)] {
        let ids: [usize; D] = match fixed {
            None => std::array::from_fn(|k| [l1, l2][k]),
            Some(p) => std::array::from_fn(|k| [p, l1, l2][k]),
        };
        if let Some((n, den)) = solve(planes, ids) {
            poly.push(Vertex { n, den, line_out });
        }
    }
}

/// 2D: the cell `∩ {a·x <= b}` (planes `0..4` the box) as a polygon in `poly`: the box
/// clipped by every other plane in order.
fn polygon_2d<T: Ring, const D: usize>(
    planes: &[([T; D], T)],
    poly: &mut Vec<Vertex<T, D>>,
    out: &mut Vec<Vertex<T, D>>,
) {
    box_square(planes, poly, None, 0, 1);
    for h in 4..planes.len() {
        clip(poly, out, planes, None, h);
    }
}

/// 3D: the face `P ∩ cell` of plane `p` as a polygon in `poly` (empty if `P` misses the
/// cell): `P` over the box square in the two coordinates `P` does not eliminate, clipped by
/// the box planes of the eliminated axis and every other plane.
fn face_3d<T: Ring, const D: usize>(
    planes: &[([T; D], T)],
    p: usize,
    poly: &mut Vec<Vertex<T, D>>,
    out: &mut Vec<Vertex<T, D>>,
) {
    // The axis P eliminates: its largest coefficient (non-zero for every plane here).
    let axis = (0..D)
        .max_by(|&x, &y| {
            let (ax, ay) = (planes[p].0[x].approx().abs(), planes[p].0[y].approx().abs());
            ax.total_cmp(&ay).then(y.cmp(&x))
        })
        .unwrap_or(0);
    let (b, c) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    box_square(planes, poly, Some(p), b, c);
    for h in [2 * axis, 2 * axis + 1]
        .into_iter()
        .chain(2 * D..planes.len())
    {
        if h == p {
            continue;
        }
        clip(poly, out, planes, Some(p), h);
        if poly.is_empty() {
            break;
        }
    }
}

/// The general power-cell decision (some offset `<= 0`) from growing prefixes of the planes
/// (strongest first). The cell `K_m` of a prefix contains the whole cell `K`, so a prefix
/// cell that is flat, stays within `r` or keeps out of the open ball proves interior; one
/// that passes all three tests and whose every vertex satisfies the remaining planes equals
/// `K` (it is the hull of its vertices) and proves boundary; otherwise the prefix doubles.
fn power_prefixes<T: Ring, const D: usize>(planes: &[([T; D], T)], beyond: &Beyond) -> bool {
    let total = planes.len() - 2 * D;
    let mut k = total.min(FIRST_PLANES);
    loop {
        let (used, rest) = planes.split_at(2 * D + k);
        match power_cell(used, rest, beyond) {
            Reach::Within => return false,
            Reach::Beyond => return true,
            // Unreachable with `rest` empty: every vertex then satisfies it.
            Reach::Unsure if k == total => return true,
            Reach::Unsure => k = total.min(2 * k),
        }
    }
}

/// Whether the open part `int K` of the cell `K = ∩ {a·x <= b}` (planes `0..2D` the box)
/// meets the sphere `|x| = r`: `Within` if not (interior), `Beyond` if it does and every
/// vertex of `K` satisfies `rest`, `Unsure` if it does but some vertex violates `rest`.
fn power_cell<T: Ring, const D: usize>(
    planes: &[([T; D], T)],
    rest: &[([T; D], T)],
    beyond: &Beyond,
) -> Reach {
    let mut poly: Vec<Vertex<T, D>> = Vec::new();
    let mut out: Vec<Vertex<T, D>> = Vec::new();
    // Face vertex lists: every vertex of K is in one of them and each is a point of K.
    let mut faces: Vec<Vec<Vertex<T, D>>> = Vec::new();
    if D == 2 {
        polygon_2d(planes, &mut poly, &mut out);
        faces.push(poly);
    } else {
        for p in 0..planes.len() {
            face_3d(planes, p, &mut poly, &mut out);
            faces.push(poly.clone());
        }
    }
    let mut all = faces.iter().flatten();
    // (b) max_K |x| > r: some vertex beyond r (K is a bounded polytope).
    if !all.clone().any(|v| beyond.test(&v.n, &v.den)) {
        return Reach::Within;
    }
    // (a) K full-dimensional: its vertices affinely span R^D.
    if !spans_space::<T, D>(&mut all) {
        return Reach::Within;
    }
    // (c) min_K |x| < r.
    if !planes.iter().all(|(_, b)| b.sign() >= 0) {
        let face_of = |j: usize| -> Vec<&Vertex<T, D>> {
            if D == 2 {
                faces[0]
                    .iter()
                    .filter(|v| side(&planes[j], v) == 0)
                    .collect()
            } else {
                faces[j].iter().collect()
            }
        };
        let near = (2 * D..planes.len())
            .filter(|&j| planes[j].1.sign() < 0)
            .any(|j| face_meets_ball(planes, j, &face_of(j), beyond));
        if !near {
            return Reach::Within;
        }
    }
    if faces
        .iter()
        .flatten()
        .all(|v| rest.iter().all(|plane| side(plane, v) <= 0))
    {
        Reach::Beyond
    } else {
        Reach::Unsure
    }
}

/// Whether the points `N/den` affinely span `R^D`: whether the homogeneous rows `(N, den)`
/// have rank `D + 1`, by fraction-free elimination against the rows kept so far.
fn spans_space<'a, T: Ring + 'a, const D: usize>(
    points: &mut impl Iterator<Item = &'a Vertex<T, D>>,
) -> bool {
    let mut basis: Vec<(Vec<BigInt>, usize)> = Vec::new();
    for v in points {
        let mut row: Vec<BigInt> = v.n.iter().map(Ring::big).collect();
        row.push(v.den.big());
        for (b, pivot) in &basis {
            if !row[*pivot].is_zero() {
                let f = row[*pivot].clone();
                for (x, y) in row.iter_mut().zip(b) {
                    *x = &*x * &b[*pivot] - y * &f;
                }
            }
        }
        if let Some(pivot) = row.iter().position(|x| !x.is_zero()) {
            basis.push((row, pivot));
            if basis.len() == D + 1 {
                return true;
            }
        }
    }
    false
}

/// Whether the face `F = K ∩ {a_j·x = b_j}` (its vertices `face`, every one on the plane)
/// has a point in the open ball `|x| < r`. The point of `F` nearest the origin is the foot
/// `f = b_j a_j/|a_j|²` of the perpendicular if `f ∈ F` (for points of the plane,
/// `|x|² = |f|² + |x − f|²`), else a point of the relative boundary of `F`, which lies on a
/// segment between two of its vertices; segments between any two vertices lie in `F`.
fn face_meets_ball<T: Ring, const D: usize>(
    planes: &[([T; D], T)],
    j: usize,
    face: &[&Vertex<T, D>],
    beyond: &Beyond,
) -> bool {
    if face.is_empty() {
        return false;
    }
    let big = |x: &[T; D]| -> [BigInt; D] { std::array::from_fn(|k| x[k].big()) };
    let dot = |x: &[BigInt; D], y: &[BigInt; D]| -> BigInt { (0..D).map(|k| &x[k] * &y[k]).sum() };
    let (a, b) = (big(&planes[j].0), planes[j].1.big());
    let a2 = dot(&a, &a);
    // |f|² = b²/|a|² < r²: else the whole plane misses the open ball.
    if (&b * &b) << beyond.shift >= &beyond.r2 * &a2 {
        return false;
    }
    // f ∈ K iff a_i·f <= b_i for every plane i, i.e. b·(a_i·a) <= b_i·|a|².
    if planes
        .iter()
        .all(|(ai, bi)| &b * dot(&big(ai), &a) <= bi.big() * &a2)
    {
        return true;
    }
    let pts: Vec<([BigInt; D], BigInt)> = face.iter().map(|v| (big(&v.n), v.den.big())).collect();
    let within = |n2: BigInt, den2: BigInt| (n2 << beyond.shift) < &beyond.r2 * den2;
    if pts.iter().any(|(n, den)| within(dot(n, n), den * den)) {
        return true;
    }
    for (k, (na, da)) in pts.iter().enumerate() {
        for (nb, db) in &pts[k + 1..] {
            // Over the common denominator da·db: A' = na·db, B' = nb·da, e = B' − A'.
            let a1: [BigInt; D] = std::array::from_fn(|i| &na[i] * db);
            let b1: [BigInt; D] = std::array::from_fn(|i| &nb[i] * da);
            let e: [BigInt; D] = std::array::from_fn(|i| &b1[i] - &a1[i]);
            let (s, e2) = (dot(&a1, &e), dot(&e, &e));
            // The nearest point is interior to the segment iff A'·e < 0 < B'·e (else an
            // endpoint, tested above); its squared length is (|A'|²|e|² − (A'·e)²)/|e|².
            if e2.is_zero() || !s.is_negative() || !dot(&b1, &e).is_positive() {
                continue;
            }
            let den = da * db;
            if within(dot(&a1, &a1) * &e2 - &s * &s, &den * &den * &e2) {
                return true;
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice2(n: i32) -> Vec<Point<2>> {
        let mut v = Vec::new();
        for x in -n..=n {
            for y in -n..=n {
                if (x, y) != (0, 0) {
                    v.push(Point::<2>::new(x as f64, y as f64));
                }
            }
        }
        v
    }

    fn lattice3(n: i32) -> Vec<Point<3>> {
        let mut v = Vec::new();
        for x in -n..=n {
            for y in -n..=n {
                for z in -n..=n {
                    if (x, y, z) != (0, 0, 0) {
                        v.push(Point::<3>::new(x as f64, y as f64, z as f64));
                    }
                }
            }
        }
        v
    }

    #[test]
    fn dyadic_decomposes_exactly() {
        for x in [1.0, -3.5, 0.1, 1e-310, -1e300, f64::MIN_POSITIVE] {
            let (m, e) = dyadic(x).unwrap();
            assert!(m % 2 != 0);
            // m·2^e in two exact steps: `2f64.powi(-1074)` alone may evaluate as 1/2^1074 =
            // 1/inf = 0 at run time (it did in a non-incremental CI build).
            let first = e.max(-1000);
            assert_eq!(m as f64 * 2f64.powi(first) * 2f64.powi(e - first), x, "{x}");
        }
        assert_eq!(dyadic(0.0), None);
    }

    #[test]
    fn square_lattice_is_covered_from_the_tie_up() {
        let c = Point::<2>::zeros();
        let n = lattice2(2);
        let tie = std::f64::consts::FRAC_1_SQRT_2; // fl(1/√2) > 1/√2
        assert!(!sphere_uncovered(&c, &n, tie));
        assert!(sphere_uncovered(&c, &n, tie.next_down()));
        assert!(!sphere_uncovered(&c, &n, tie.next_up()));
        assert!(sphere_uncovered(&c, &n, tie * (1.0 - 1e-10)));
        // Without neighbours: boundary; with only duplicates: boundary.
        assert!(sphere_uncovered(&c, &[], 1.0));
        assert!(sphere_uncovered(&c, &[c, c], 1.0));
    }

    #[test]
    fn cubic_lattice_is_covered_from_the_tie_up() {
        let c = Point::<3>::zeros();
        let n = lattice3(2);
        let tie = 3f64.sqrt() / 2.0; // fl(√3/2) < √3/2
        assert!(sphere_uncovered(&c, &n, tie));
        assert!(!sphere_uncovered(&c, &n, tie.next_up()));
        assert!(!sphere_uncovered(&c, &n, 0.9));
        assert!(sphere_uncovered(&c, &n, 0.86));
        assert!(sphere_uncovered(&c, &[], 1.0));
    }

    #[test]
    fn far_bisectors_beyond_the_first_prefix_still_count() {
        // 40 near neighbours clustered around +x bound the first prefix only on that side, so
        // its cell reaches the box elsewhere; eight (or seven) neighbours at 1.5, every 45°,
        // decide: their octagon has circumradius 0.75/cos 22.5° = 0.81 < 1 (covered), and
        // without the one at 180° the cell reaches 0.75·√2 = 1.06 > 1 (uncovered).
        let c = Point::<2>::zeros();
        let mut n: Vec<Point<2>> = (0..40)
            .map(|k| {
                let a = (k as f64 / 40.0 - 0.5) * 0.3;
                let d = 1.0 + 0.01 * k as f64;
                Point::<2>::new(d * a.cos(), d * a.sin())
            })
            .collect();
        let ring = |skip: Option<usize>| {
            (0..8)
                .filter(move |&k| Some(k) != skip)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::FRAC_PI_4;
                    Point::<2>::new(1.5 * a.cos(), 1.5 * a.sin())
                })
                .collect::<Vec<_>>()
        };
        let mut all = n.clone();
        all.extend(ring(None));
        assert!(!sphere_uncovered(&c, &all, 1.0));
        n.extend(ring(Some(4)));
        assert!(sphere_uncovered(&c, &n, 1.0));
    }

    #[test]
    fn far_offsets_and_tiny_coordinates_use_exact_differences() {
        // The same lattice at 1e9 (unit 2^-23 apart from the origin's unit): same answers.
        let off = Point::<3>::new(1e9, -1e9, 1e9);
        let n: Vec<Point<3>> = lattice3(1).iter().map(|p| p + off).collect();
        assert!(!sphere_uncovered(&off, &n, 0.9));
        assert!(sphere_uncovered(&off, &n, 0.86));
        // Coordinates of wildly different exponents (BigInt path).
        let c = Point::<2>::new(1e-300, 0.0);
        let n: Vec<Point<2>> = lattice2(1).iter().map(|p| p + c).collect();
        assert!(!sphere_uncovered(&c, &n, 0.75));
        assert!(sphere_uncovered(&c, &n, 0.7));
    }

    /// The machine-word paths (set-up in `i128`, enumeration in `i64` / `i128`, the final
    /// test in 256 bits) against `BigInt` arithmetic and the rational brute force of
    /// `power`, at the bounds where the paths switch.
    mod word_paths {
        use super::super::*;
        use super::power::brute_force;
        use rand::{rngs::StdRng, Rng, SeedableRng};

        fn big256((high, low): (u128, u128)) -> BigInt {
            (BigInt::from(high) << 128usize) + BigInt::from(low)
        }

        #[test]
        fn wide_products_and_shifted_comparisons_match_bigint() {
            let mut rng = StdRng::seed_from_u64(11);
            let edges = [
                0u128,
                1,
                2,
                u64::MAX as u128,
                1 << 64,
                u128::MAX,
                u128::MAX - 1,
            ];
            let mut values: Vec<u128> = edges.to_vec();
            for _ in 0..200 {
                let bits = rng.gen_range(0..=128u32);
                let x: u128 = rng.gen();
                values.push(if bits == 128 {
                    x
                } else {
                    x & ((1 << bits) - 1)
                });
            }
            for (i, &a) in values.iter().enumerate() {
                let b = values[(i * 7 + 3) % values.len()];
                let p = mul_wide(a, b);
                assert_eq!(big256(p), BigInt::from(a) * BigInt::from(b), "{a} * {b}");
                for shift in [0usize, 1, 63, 64, 127, 128, 129, 200, 255, 256, 300] {
                    let lhs = BigInt::from(a) << shift;
                    for rhs in [p, (0, a), (a, 0), (u128::MAX, u128::MAX)] {
                        assert_eq!(
                            shl_exceeds(a, shift, rhs),
                            lhs > big256(rhs),
                            "{a} << {shift} > {rhs:?}"
                        );
                    }
                    // Equal sides: not beyond; one more on the right or the left decides.
                    if a != 0 && (128 - a.leading_zeros() as usize) + shift <= 256 {
                        let (mut high, mut low) = (0u128, 0u128);
                        let big = BigInt::from(a) << shift;
                        let (hi, lo) = (&big >> 128usize, &big - (&big >> 128usize << 128usize));
                        high += hi.to_u128().unwrap();
                        low += lo.to_u128().unwrap();
                        assert!(!shl_exceeds(a, shift, (high, low)));
                        if low > 0 {
                            assert!(shl_exceeds(a, shift, (high, low - 1)));
                        }
                    }
                }
            }
        }

        /// `Beyond::test` in every ring against `|N|²·2^shift > r²·den²` in `BigInt`, for
        /// vertices on, just inside and just outside the sphere, with `|N_k|` and `den` at
        /// the bounds of the 256-bit path (`2^63`, `2^64`) and beyond.
        #[test]
        fn the_beyond_test_is_exact_on_both_sides_of_its_word_bounds() {
            let mut rng = StdRng::seed_from_u64(12);
            let mut checked = 0;
            for case in 0..400 {
                // r = r_int·2^e (exact in f64: r_int < 2^53), vertices in the unit 2^(e+t).
                let r_bits = rng.gen_range(1..53);
                let r_int: u64 = rng.gen_range(1..1u64 << r_bits);
                let (e, t) = (rng.gen_range(-60..20), rng.gen_range(0..40u64));
                let r_f64 = r_int as f64 * 2f64.powi(e);
                let r2 = BigInt::from(r_int) * BigInt::from(r_int);
                let beyond = Beyond::new(r2.clone(), 2 * t as usize, r_f64, e, t);
                let den_bits = [1u32, 20, 62, 63, 64, 65, 70][case % 7];
                let den = BigInt::from(rng.gen_range(1u128 << (den_bits - 1)..1u128 << den_bits));
                // On the sphere along an axis when 2^t divides r_int·den, then nudged.
                let on = (BigInt::from(r_int) * &den) >> (t as usize);
                // Nudged by units (the exact path) and scaled by 1/2, 0.99, 1.01, 2 (the float
                // estimate decides the first and last, the exact path the middle ones).
                let scaled = |num: i64| (&on * num / 100) - &on;
                let nudges: Vec<BigInt> = [-2i64, -1, 0, 1, 2]
                    .map(BigInt::from)
                    .into_iter()
                    .chain([50, 99, 101, 200].map(scaled))
                    .collect();
                for nudge in nudges {
                    let mut n: [BigInt; 3] = [&on + &nudge, BigInt::from(0), BigInt::from(0)];
                    if case % 2 == 1 {
                        n = [n[1].clone(), -n[0].clone(), nudge.clone()];
                    }
                    let want = (n.iter().map(|x| x * x).sum::<BigInt>() << (2 * t as usize))
                        > &r2 * &den * &den;
                    assert_eq!(beyond.test(&n, &den), want, "BigInt case {case} {nudge}");
                    if let (Some(n128), Some(d128)) = (
                        n.iter().map(|x| x.to_i128()).collect::<Option<Vec<_>>>(),
                        den.to_i128(),
                    ) {
                        let n128 = [n128[0], n128[1], n128[2]];
                        assert_eq!(beyond.test(&n128, &d128), want, "i128 case {case} {nudge}");
                        checked += 1;
                    }
                }
            }
            assert!(checked > 1000, "{checked}");
        }

        /// A jittered lattice around the origin: points `k + j/2^m` (`|j| <= 2^(m−3)`),
        /// a radius on either side of the lattice's tie, rounded to the unit `2^-m`: the planes have about `m + 2`
        /// and `2m + 3` bits, so `m` moves the enumeration across its word bounds.
        fn jittered<const D: usize>(rng: &mut StdRng, m: i32) -> (Point<D>, f64, Vec<Point<D>>) {
            let unit = 2f64.powi(-m);
            let j = 1i64 << (m - 3);
            let mut jitter = |x: f64| x + rng.gen_range(-j..=j) as f64 * unit;
            let centre = Point::<D>::from_fn(|_, _| jitter(0.0));
            let mut others = Vec::new();
            let span = if D == 2 { 2 } else { 1 };
            let cells = (2 * span + 1usize).pow(D as u32);
            for k in 0..cells {
                let mut p = Point::<D>::zeros();
                let mut rest = k;
                for x in p.iter_mut() {
                    *x = jitter((rest % (2 * span + 1)) as f64 - span as f64);
                    rest /= 2 * span + 1;
                }
                others.push(p);
            }
            // Around the tie radius of the lattice (1/√2 in 2D, √3/2 in 3D): both answers.
            let radii = if D == 2 { [0.76, 0.66] } else { [0.9, 0.8] };
            let r = (radii[rng.gen_range(0..2)] / unit).round() * unit;
            (centre, r, others)
        }

        fn agree_with_brute_force<const D: usize>(ms: &[i32]) -> Vec<(bool, u32)> {
            let mut rng = StdRng::seed_from_u64(13 + D as u64);
            let mut paths = Vec::new();
            let mut answers = [0usize; 2];
            for &m in ms {
                for _ in 0..2 {
                    let (c, r, o) = jittered::<D>(&mut rng, m);
                    let got = sphere_uncovered(&c, &o, r);
                    paths.push(PATH.with(|p| p.get()));
                    let with: Vec<_> = o.iter().map(|&p| (p, r)).collect();
                    assert_eq!(got, brute_force(&c, r, &with), "{D}D m = {m}");
                    answers[got as usize] += 1;
                }
            }
            assert!(answers[0] > 0 && answers[1] > 0, "{D}D answers {answers:?}");
            paths
        }

        #[test]
        fn enumeration_rings_switch_at_their_bounds_with_the_same_answers() {
            // 3D: 5m + 17 bits (i64 up to m = 9, i128 up to m = 21); 2D: 4m + 13 (12, 28).
            let p3 = agree_with_brute_force::<3>(&[8, 9, 10, 11, 20, 21, 22, 23]);
            let p2 = agree_with_brute_force::<2>(&[11, 12, 13, 14, 27, 28, 29, 30]);
            for (d, paths) in [(3, p3), (2, p2)] {
                for width in [64, 128, 0] {
                    assert!(
                        paths.contains(&(true, width)),
                        "{d}D: no set enumerated at width {width}: {paths:?}"
                    );
                }
            }
        }

        #[test]
        fn set_up_falls_back_to_bigint_beyond_its_bounds_with_the_same_answers() {
            // The lattice of `jittered` (m = 6) translated by 2^k, r with a finer unit 2^-f:
            // coordinates need k + f bits in the unit of r (the i128 set-up takes up to 72
            // beyond the 53 of a mantissa), r needs f bits (up to 60).
            let mut rng = StdRng::seed_from_u64(17);
            let mut paths = Vec::new();
            for (k, f) in [
                (0, 30),
                (20, 45),
                (40, 40),
                (44, 40),
                (0, 59),
                (0, 61),
                (60, 30),
            ] {
                let (c, r, o) = jittered::<3>(&mut rng, 6);
                let off = Point::<3>::from_fn(|_, _| 2f64.powi(k));
                let r = r + 2f64.powi(-f);
                let (c, mut o) = (c + off, o.iter().map(|p| p + off).collect::<Vec<_>>());
                // A far point (2^20 away): skipped, exactly.
                o.push(c + Point::<3>::new(2f64.powi(20), 0.0, 0.0));
                let got = sphere_uncovered(&c, &o, r);
                paths.push(PATH.with(|p| p.get()).0);
                let with: Vec<_> = o.iter().map(|&p| (p, r)).collect();
                assert_eq!(got, brute_force(&c, r, &with), "k = {k}, f = {f}");
            }
            assert!(paths.contains(&true) && paths.contains(&false), "{paths:?}");
        }
    }

    /// Tests of [`sphere_uncovered_power`] against two independent checks written here: an
    /// exact brute force in rationals over the power planes (every projection of the centre
    /// onto an intersection of at most `D` planes) and dense sampling of the sphere.
    mod power {
        use super::super::*;
        use super::{lattice2, lattice3};
        use num_rational::BigRational as Q;
        use rand::{rngs::StdRng, Rng, SeedableRng};

        fn rat(x: f64) -> Q {
            Q::from_float(x).expect("finite")
        }

        fn dot(x: &[Q], y: &[Q]) -> Q {
            x.iter().zip(y).map(|(a, b)| a * b).sum()
        }

        fn idot(x: &[BigInt], y: &[BigInt]) -> BigInt {
            x.iter().zip(y).map(|(a, b)| a * b).sum()
        }

        /// Determinant by cofactor expansion (k <= 3 here).
        fn idet(m: &[Vec<BigInt>]) -> BigInt {
            match m.len() {
                0 => BigInt::from(1u8),
                1 => m[0][0].clone(),
                k => (0..k)
                    .map(|col| {
                        let minor: Vec<Vec<BigInt>> = m[1..]
                            .iter()
                            .map(|row| {
                                (0..k)
                                    .filter(|&c| c != col)
                                    .map(|c| row[c].clone())
                                    .collect()
                            })
                            .collect();
                        let t = &m[0][col] * idet(&minor);
                        if col % 2 == 0 {
                            t
                        } else {
                            -t
                        }
                    })
                    .sum(),
            }
        }

        /// The point of `∩_{i ∈ s} {a_i·y = b_i}` nearest the origin as `N/d` (`d > 0`):
        /// `y = Σ λ_i a_i` with the Gram system `G λ = b` solved by Cramer's rule; `None` if
        /// the normals are dependent.
        fn project(
            planes: &[(Vec<BigInt>, BigInt)],
            s: &[usize],
            d: usize,
        ) -> Option<(Vec<BigInt>, BigInt)> {
            let g: Vec<Vec<BigInt>> = s
                .iter()
                .map(|&i| {
                    s.iter()
                        .map(|&l| idot(&planes[i].0, &planes[l].0))
                        .collect()
                })
                .collect();
            let mut den = idet(&g);
            if den.is_zero() {
                return None;
            }
            let mut n = vec![BigInt::from(0u8); d];
            for (col, &i) in s.iter().enumerate() {
                let gi: Vec<Vec<BigInt>> = g
                    .iter()
                    .zip(s)
                    .map(|(row, &r)| {
                        let mut row = row.clone();
                        row[col] = planes[r].1.clone();
                        row
                    })
                    .collect();
                let lambda = idet(&gi);
                for (nk, ak) in n.iter_mut().zip(&planes[i].0) {
                    *nk += &lambda * ak;
                }
            }
            if den.is_negative() {
                den = -den;
                n.iter_mut().for_each(|x| *x = -&*x);
            }
            Some((n, den))
        }

        /// Exact brute force: boundary iff the power cell `K` (in the box `[−2r_c, 2r_c]^D`)
        /// is full-dimensional (the centroid of its vertices strictly satisfies every
        /// constraint), has a vertex beyond `r_c`, and has a point nearer than `r_c` (the
        /// minimum of `|y|` over `K` is a projection of the origin onto the affine hull of a
        /// face, i.e. onto an intersection of at most `D` planes, lying in `K`). Every input
        /// is a rational; all are scaled to integers by a common denominator.
        pub(super) fn brute_force<const D: usize>(
            c: &Point<D>,
            rc: f64,
            others: &[(Point<D>, f64)],
        ) -> bool {
            let mut values: Vec<Q> = vec![rat(rc)];
            values.extend(c.iter().map(|&x| rat(x)));
            for (p, r) in others {
                values.push(rat(*r));
                values.extend(p.iter().map(|&x| rat(x)));
            }
            // Denominators of floats are powers of two: the largest is a common multiple.
            let scale = values
                .iter()
                .map(|v| v.denom().clone())
                .max()
                .unwrap_or_default();
            let int = |x: f64| (rat(x) * Q::from_integer(scale.clone())).to_integer();
            let rc = int(rc);
            let rc2 = &rc * &rc;
            let big_r = &rc + &rc;
            let cc: Vec<BigInt> = c.iter().map(|&x| int(x)).collect();
            let mut planes: Vec<(Vec<BigInt>, BigInt)> = Vec::new();
            for axis in 0..D {
                for s in [1i32, -1] {
                    let a = (0..D)
                        .map(|k| BigInt::from(if k == axis { s } else { 0 }))
                        .collect();
                    planes.push((a, big_r.clone()));
                }
            }
            for (p, r) in others {
                let q: Vec<BigInt> = (0..D).map(|k| int(p[k]) - &cc[k]).collect();
                let d2 = idot(&q, &q);
                let rj = int(*r);
                let reach = &rc + &rj;
                if d2.is_zero() || d2 >= &reach * &reach {
                    continue;
                }
                let b = &d2 + &rc2 - &rj * &rj;
                planes.push((q.iter().map(|x| x + x).collect(), b));
            }
            let m = planes.len();
            let inside =
                |(n, d): &(Vec<BigInt>, BigInt)| planes.iter().all(|(a, b)| idot(a, n) <= b * d);
            let mut subsets: Vec<Vec<usize>> = vec![vec![]];
            for i in 0..m {
                subsets.push(vec![i]);
                for j in i + 1..m {
                    subsets.push(vec![i, j]);
                    if D == 3 {
                        for k in j + 1..m {
                            subsets.push(vec![i, j, k]);
                        }
                    }
                }
            }
            let mut vertices: Vec<(Vec<BigInt>, BigInt)> = Vec::new();
            let mut nearer = false;
            for s in &subsets {
                if let Some(y) = project(&planes, s, D) {
                    if inside(&y) {
                        nearer |= idot(&y.0, &y.0) < &rc2 * &y.1 * &y.1;
                        if s.len() == D {
                            vertices.push(y);
                        }
                    }
                }
            }
            if vertices.is_empty() {
                return false;
            }
            let n = Q::from_integer(vertices.len().into());
            let centroid: Vec<Q> = (0..D)
                .map(|k| {
                    vertices
                        .iter()
                        .map(|(v, d)| Q::new(v[k].clone(), d.clone()))
                        .sum::<Q>()
                        / &n
                })
                .collect();
            let full = planes.iter().all(|(a, b)| {
                let a: Vec<Q> = a.iter().map(|x| Q::from_integer(x.clone())).collect();
                dot(&a, &centroid) < Q::from_integer(b.clone())
            });
            let farther = vertices.iter().any(|(v, d)| idot(v, v) > &rc2 * d * d);
            full && farther && nearer
        }

        /// The smallest cover margin `max_j (r_j − |x − p_j|)` over `n` sample points `x` of
        /// the sphere (equal angles in 2D, a Fibonacci sphere in 3D), and a bound `h` on the
        /// distance from any point of the sphere to the nearest sample. The margin is
        /// 1-Lipschitz in `x`: a sampled minimum above `h` proves the sphere covered, a
        /// negative one proves it uncovered.
        fn sampled_margin<const D: usize>(
            c: &Point<D>,
            rc: f64,
            others: &[(Point<D>, f64)],
            n: usize,
        ) -> (f64, f64) {
            let near: Vec<&(Point<D>, f64)> = others
                .iter()
                .filter(|(p, r)| *p != *c && (p - c).norm() < rc + r + 1e-9)
                .collect();
            let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let mut worst = f64::INFINITY;
            for k in 0..n {
                let mut u = Point::<D>::zeros();
                if D == 2 {
                    let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                    u[0] = a.cos();
                    u[1] = a.sin();
                } else {
                    let z = 1.0 - (2.0 * k as f64 + 1.0) / n as f64;
                    let s = (1.0 - z * z).sqrt();
                    let a = golden * k as f64;
                    u[0] = s * a.cos();
                    u[1] = s * a.sin();
                    u[2] = z;
                }
                let x = c + u * rc;
                let m = near
                    .iter()
                    .map(|(p, r)| r - (x - p).norm())
                    .fold(f64::NEG_INFINITY, f64::max);
                worst = worst.min(m);
            }
            let h = if D == 2 {
                rc * std::f64::consts::PI / n as f64
            } else {
                2.0 * rc * (4.0 * std::f64::consts::PI / n as f64).sqrt()
            };
            (worst, h)
        }

        /// `Some(boundary)` where sampling decides clearly, `None` near a tie.
        fn sampled<const D: usize>(
            c: &Point<D>,
            rc: f64,
            others: &[(Point<D>, f64)],
        ) -> Option<bool> {
            let n = if D == 2 { 4096 } else { 16384 };
            let (m, h) = sampled_margin(c, rc, others, n);
            if m > h {
                Some(false)
            } else if m < -1e-9 * rc {
                Some(true)
            } else {
                None
            }
        }

        fn p2(x: f64, y: f64) -> Point<2> {
            Point::<2>::new(x, y)
        }

        fn p3(x: f64, y: f64, z: f64) -> Point<3> {
            Point::<3>::new(x, y, z)
        }

        /// A random centre and 1..=8 neighbours reaching its sphere, radii `r_c·{1, ratio,
        /// 1/ratio}`; `grid`: coordinates on a 1/4 grid and unjittered radii (many exact
        /// ties and degenerate cells, `i128` arithmetic), else generic floats (`BigInt`).
        fn random_set<const D: usize>(
            rng: &mut StdRng,
            ratio: f64,
            grid: bool,
        ) -> (Point<D>, f64, Vec<(Point<D>, f64)>) {
            let snap = |x: f64| if grid { (x * 4.0).round() / 4.0 } else { x };
            let centre = Point::<D>::from_fn(|_, _| snap(rng.gen_range(-2.0..2.0)));
            let rc = if grid { 1.0 } else { rng.gen_range(0.8..1.2) };
            let n = rng.gen_range(1..=8);
            let mut others = Vec::new();
            for _ in 0..n {
                let level = [1.0, ratio, 1.0 / ratio][rng.gen_range(0..3)];
                let r = if grid {
                    level
                } else {
                    level * rng.gen_range(0.9..1.1)
                };
                let dir = loop {
                    let v = Point::<D>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
                    if v.norm() > 0.1 && v.norm() <= 1.0 {
                        break v / v.norm();
                    }
                };
                let dist = rng.gen_range(0.0..1.05) * (rc + r);
                let p = (centre + dir * dist).map(snap);
                others.push((p, r));
            }
            (centre, rc, others)
        }

        #[test]
        fn random_sets_agree_with_the_rational_brute_force_and_sampling() {
            let mut rng = StdRng::seed_from_u64(22);
            let (mut counted, mut sampled_n) = ([0usize; 2], 0usize);
            for round in 0..480 {
                let ratio = [1.0, 2.0, 4.0, 100.0][round % 4];
                let grid = round % 8 < 4;
                let (got, truth, sample) = if round % 3 == 0 {
                    let (c, rc, o) = random_set::<3>(&mut rng, ratio, grid);
                    (
                        sphere_uncovered_power(&c, rc, &o),
                        brute_force(&c, rc, &o),
                        sampled(&c, rc, &o),
                    )
                } else {
                    let (c, rc, o) = random_set::<2>(&mut rng, ratio, grid);
                    (
                        sphere_uncovered_power(&c, rc, &o),
                        brute_force(&c, rc, &o),
                        sampled(&c, rc, &o),
                    )
                };
                assert_eq!(got, truth, "round {round}: predicate vs brute force");
                if let Some(s) = sample {
                    assert_eq!(got, s, "round {round}: predicate vs sampling");
                    sampled_n += 1;
                }
                counted[got as usize] += 1;
            }
            // Both answers occur often, and sampling decided most sets.
            assert!(counted[0] > 60 && counted[1] > 60, "{counted:?}");
            assert!(sampled_n > 300, "{sampled_n}");
        }

        #[test]
        fn equal_radii_give_exactly_sphere_uncovered() {
            let mut rng = StdRng::seed_from_u64(7);
            for round in 0..200 {
                let r = rng.gen_range(0.5..1.5);
                let n = rng.gen_range(0..30);
                if round % 2 == 0 {
                    let c = p2(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
                    let o: Vec<Point<2>> = (0..n)
                        .map(|_| {
                            c + p2(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0)) * (2.0 * r)
                        })
                        .collect();
                    let with: Vec<(Point<2>, f64)> = o.iter().map(|&p| (p, r)).collect();
                    assert_eq!(
                        sphere_uncovered_power(&c, r, &with),
                        sphere_uncovered(&c, &o, r)
                    );
                } else {
                    let c = p3(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 0.5);
                    let o: Vec<Point<3>> = (0..n)
                        .map(|_| {
                            let v = p3(
                                rng.gen_range(-1.0..1.0),
                                rng.gen_range(-1.0..1.0),
                                rng.gen_range(-1.0..1.0),
                            );
                            c + v * (1.3 * r)
                        })
                        .collect();
                    let with: Vec<(Point<3>, f64)> = o.iter().map(|&p| (p, r)).collect();
                    assert_eq!(
                        sphere_uncovered_power(&c, r, &with),
                        sphere_uncovered(&c, &o, r)
                    );
                }
            }
            // Lattices at their tie radii and ±4 ulps.
            let (n2, n3) = (lattice2(2), lattice3(2));
            let ulps = |x: f64, k: i32| {
                let mut y = x;
                for _ in 0..k.abs() {
                    y = if k > 0 { y.next_up() } else { y.next_down() };
                }
                y
            };
            for k in -4..=4 {
                let r = ulps(std::f64::consts::FRAC_1_SQRT_2, k);
                let w: Vec<_> = n2.iter().map(|&p| (p, r)).collect();
                assert_eq!(
                    sphere_uncovered_power(&Point::<2>::zeros(), r, &w),
                    sphere_uncovered(&Point::<2>::zeros(), &n2, r),
                    "square lattice {k} ulps"
                );
                // fl(1/√2) > 1/√2: covered from it up.
                assert_eq!(sphere_uncovered_power(&Point::<2>::zeros(), r, &w), k < 0);
                let r = ulps(3f64.sqrt() / 2.0, k);
                let w: Vec<_> = n3.iter().map(|&p| (p, r)).collect();
                assert_eq!(
                    sphere_uncovered_power(&Point::<3>::zeros(), r, &w),
                    sphere_uncovered(&Point::<3>::zeros(), &n3, r),
                    "cubic lattice {k} ulps"
                );
                // fl(√3/2) < √3/2: covered from the next float up.
                assert_eq!(sphere_uncovered_power(&Point::<3>::zeros(), r, &w), k <= 0);
            }
        }

        #[test]
        fn sphere_inside_a_bigger_ball_is_interior_up_to_the_touching_tie() {
            let c = p2(0.0, 0.0);
            let at = |x: f64, r: f64| [(p2(x, 0.0), r)];
            // B((1,0), 2) holds the unit circle; it touches at (−1, 0): covered (tie).
            assert!(!sphere_uncovered_power(&c, 1.0, &at(1.0, 2.0)));
            assert!(!sphere_uncovered_power(&c, 1.0, &at(0.5, 2.0)));
            // Shrunk by one ulp, or moved away by one ulp: the circle pokes out.
            assert!(sphere_uncovered_power(&c, 1.0, &at(1.0, 2f64.next_down())));
            assert!(sphere_uncovered_power(&c, 1.0, &at(1f64.next_up(), 2.0)));
            assert!(!sphere_uncovered_power(&c, 1.0, &at(1f64.next_down(), 2.0)));
            // Concentric bigger ball: a duplicate, never covers; the same ball 1 ulp off does.
            assert!(sphere_uncovered_power(&c, 1.0, &at(0.0, 5.0)));
            assert!(!sphere_uncovered_power(
                &c,
                1.0,
                &at(f64::MIN_POSITIVE, 5.0)
            ));
            // 3D, at a far offset (exact differences): the same answers.
            let o = p3(1e6 + 0.25, -3.0, 7.5);
            let at3 = |x: f64, r: f64| [(o + p3(x, 0.0, 0.0), r)];
            assert!(!sphere_uncovered_power(&o, 1.0, &at3(1.0, 2.0)));
            assert!(sphere_uncovered_power(&o, 1.0, &at3(1.0, 2f64.next_down())));
            for (x, r) in [(1.0, 2.0), (1.0, 2f64.next_down()), (1f64.next_up(), 2.0)] {
                assert_eq!(
                    sphere_uncovered_power(&c, 1.0, &at(x, r)),
                    brute_force(&c, 1.0, &at(x, r))
                );
                assert_eq!(
                    sphere_uncovered_power(&o, 1.0, &at3(x, r)),
                    brute_force(&o, 1.0, &at3(x, r))
                );
            }
        }

        #[test]
        fn flat_power_cells_are_interior() {
            // Balls of radius 5 at (±4, 0): both power planes are y1 = 0 (16 + 9 − 25 = 0),
            // the cell is a segment (2D) or a square (3D), every point of the sphere in it lies
            // on both spheres of radius 5: covered. One ulp less on one side: a thin slab,
            // uncovered near (0, ±3); one ulp more: the cell is empty.
            for (r, want) in [
                (5.0, false),
                (5f64.next_down(), true),
                (5f64.next_up(), false),
            ] {
                let o2 = [(p2(4.0, 0.0), r), (p2(-4.0, 0.0), 5.0)];
                let c2 = p2(0.0, 0.0);
                assert_eq!(sphere_uncovered_power(&c2, 3.0, &o2), want, "2D r = {r}");
                assert_eq!(brute_force(&c2, 3.0, &o2), want, "2D brute force r = {r}");
                let o3 = [(p3(4.0, 0.0, 0.0), r), (p3(-4.0, 0.0, 0.0), 5.0)];
                let c3 = p3(0.0, 0.0, 0.0);
                assert_eq!(sphere_uncovered_power(&c3, 3.0, &o3), want, "3D r = {r}");
                assert_eq!(brute_force(&c3, 3.0, &o3), want, "3D brute force r = {r}");
            }
            // Flat with a negative offset (the general path): around r_c = 13, a ball of
            // radius 15 at (14, 0) gives 28·y1 <= 196 + 169 − 225 = 140 (y1 <= 5) and one of
            // radius 20 at (−11, 0) gives −22·y1 <= 121 + 169 − 400 = −110 (y1 >= 5): both
            // spheres pass through (5, ±12). Exact: flat, covered. The big ball one ulp
            // bigger: empty cell, covered; one ulp smaller, or the other one ulp smaller: a
            // thin slab, uncovered.
            let c = p2(0.0, 0.0);
            let next = |x: f64| x.next_up();
            let prev = |x: f64| x.next_down();
            for (r1, r2, want) in [
                (15.0, 20.0, false),
                (15.0, next(20.0), false),
                (15.0, prev(20.0), true),
                (prev(15.0), 20.0, true),
            ] {
                let o = [(p2(14.0, 0.0), r1), (p2(-11.0, 0.0), r2)];
                assert_eq!(sphere_uncovered_power(&c, 13.0, &o), want, "{r1} {r2}");
                assert_eq!(brute_force(&c, 13.0, &o), want, "brute force {r1} {r2}");
                let o3 = o.map(|(p, r)| (p3(p[0], p[1], 0.0), r));
                assert_eq!(
                    sphere_uncovered_power(&Point::<3>::zeros(), 13.0, &o3),
                    want
                );
            }
        }

        #[test]
        fn nearest_point_ties_decide_exactly() {
            // Power planes y1 <= −3 (q = (4.5, 0), r 8.5: 20.25 + 25 − 72.25 = −27 = 9·(−3))
            // and y2 <= −4 (q = (0, 4.75), r 9.25: 22.5625 + 25 − 85.5625 = −38 = 9.5·(−4)):
            // the cell's nearest point is the corner (−3, −4) at exactly r_c = 5: covered.
            // One ulp less on either radius moves the corner inside: uncovered; more: covered.
            let c = p2(0.0, 0.0);
            let c3 = p3(0.0, 0.0, 0.0);
            for (d1, d2, want) in [
                (0, 0, false),
                (-1, 0, true),
                (0, -1, true),
                (1, 0, false),
                (0, 1, false),
            ] {
                let step = |x: f64, d: i32| match d {
                    -1 => x.next_down(),
                    1 => x.next_up(),
                    _ => x,
                };
                let (r1, r2) = (step(8.5, d1), step(9.25, d2));
                let o = [(p2(4.5, 0.0), r1), (p2(0.0, 4.75), r2)];
                assert_eq!(sphere_uncovered_power(&c, 5.0, &o), want, "2D {d1} {d2}");
                assert_eq!(brute_force(&c, 5.0, &o), want, "2D brute force {d1} {d2}");
                // 3D: the nearest point (−3, −4, 0) lies inside an edge of both faces.
                let o3 = [(p3(4.5, 0.0, 0.0), r1), (p3(0.0, 4.75, 0.0), r2)];
                assert_eq!(sphere_uncovered_power(&c3, 5.0, &o3), want, "3D {d1} {d2}");
                assert_eq!(brute_force(&c3, 5.0, &o3), want, "3D brute force {d1} {d2}");
            }
            // Farthest-vertex tie with positive offsets: balls of radius 5 at (±4, ±4) around
            // r_c = 7 give y1 ± y2 <= 7 (32 + 49 − 25 = 56 = 8·7), vertices at distance 7.
            let diag = |r: f64| {
                [(4.0, 4.0), (4.0, -4.0), (-4.0, 4.0), (-4.0, -4.0)].map(|(x, y)| (p2(x, y), r))
            };
            for (r, want) in [
                (5.0, false),
                (5f64.next_down(), true),
                (5f64.next_up(), false),
            ] {
                assert_eq!(
                    sphere_uncovered_power(&c, 7.0, &diag(r)),
                    want,
                    "diagonal r = {r}"
                );
                assert_eq!(
                    brute_force(&c, 7.0, &diag(r)),
                    want,
                    "diagonal brute force r = {r}"
                );
            }
        }

        #[test]
        fn a_face_nearest_the_centre_inside_its_interior_counts() {
            // Balls at a·(1, 1, 1) with r² = 3a² + 3a + 1 (a = 7, r = 13) or 3a² + 4a + 1
            // (a = 8, r = 15) cut the corner of the unit box by y1 + y2 + y3 <= −1.5 or −2. The
            // face is a triangle whose edges stay at distance >= 1 from the centre; the
            // nearest point of the cell is the foot −(s/3)(1, 1, 1) at s/√3: 0.87 (uncovered
            // near it) or 1.15 (covered).
            let c = p3(0.0, 0.0, 0.0);
            for (a, r, want) in [(7.0, 13.0, true), (8.0, 15.0, false)] {
                let o = [(p3(a, a, a), r)];
                assert_eq!(sphere_uncovered_power(&c, 1.0, &o), want, "a = {a}");
                assert_eq!(brute_force(&c, 1.0, &o), want, "brute force a = {a}");
                assert_eq!(sampled(&c, 1.0, &o), Some(want), "sampling a = {a}");
            }
        }

        #[test]
        fn tiny_and_touching_balls_follow_the_definition() {
            let c = p2(0.0, 0.0);
            // A tiny particle alone, or far from everything: boundary.
            assert!(sphere_uncovered_power(&c, 1e-3, &[]));
            assert!(sphere_uncovered_power(
                &c,
                1e-3,
                &[(p2(5.0, 0.0), 1.0), (p2(0.0, 3.0), 2.0)]
            ));
            // A tiny ball inside the circle's ball, not reaching the sphere, changes nothing.
            let n = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]].map(Point::<2>::from);
            let mut w: Vec<(Point<2>, f64)> = n.iter().map(|&p| (p, 0.75)).collect();
            assert!(!sphere_uncovered_power(&c, 0.75, &w));
            w.push((p2(0.1, 0.0), 0.01));
            assert!(!sphere_uncovered_power(&c, 0.75, &w));
            assert!(sphere_uncovered_power(&c, 1.0, &[(p2(0.1, 0.0), 0.01)]));
            // Balls touching the sphere at one point, from outside or inside: boundary.
            assert!(sphere_uncovered_power(&c, 1.0, &[(p2(3.0, 0.0), 2.0)]));
            assert!(sphere_uncovered_power(&c, 1.0, &[(p2(0.5, 0.0), 0.5)]));
            // Duplicates of the centre never cover, whatever their radius, and repeats count once.
            assert!(sphere_uncovered_power(&c, 1.0, &[(c, 100.0), (c, 1.0)]));
            let twice: Vec<_> = w.iter().chain(&w).copied().collect();
            assert!(!sphere_uncovered_power(&c, 0.75, &twice));
            // A tiny ball covered by a 100x bigger neighbour: interior; just outside it: boundary.
            assert!(!sphere_uncovered_power(&c, 0.01, &[(p2(50.0, 0.0), 51.0)]));
            assert!(sphere_uncovered_power(&c, 0.01, &[(p2(50.0, 0.0), 50.005)]));
        }

        /// Fine particles (spacing `a`, radius `s·a`) for `x <= 1` and coarse ones (spacing
        /// `2a`, radius `2s·a`) for `x >= 0`, overlapping (and coinciding) near the
        /// interface, optionally jittered by up to `0.1a`.
        fn two_level<const D: usize>(
            s: f64,
            jitter: bool,
            rng: &mut StdRng,
        ) -> Vec<(Point<D>, f64)> {
            let mut v = Vec::new();
            let span = if D == 2 { 4 } else { 2 };
            let mut push = |x: i32, rest: &[i32], step: f64, r: f64, rng: &mut StdRng| {
                let mut p = Point::<D>::zeros();
                p[0] = x as f64 * step;
                for (k, &y) in rest.iter().enumerate() {
                    p[k + 1] = y as f64 * step;
                }
                if jitter {
                    p = p.map(|x| x + rng.gen_range(-0.1..0.1));
                }
                v.push((p, r));
            };
            let cells = |n: i32| -> Vec<Vec<i32>> {
                let mut out = vec![vec![]];
                for _ in 1..D {
                    out = out
                        .into_iter()
                        .flat_map(|c| (-n..=n).map(move |y| [c.clone(), vec![y]].concat()))
                        .collect();
                }
                out
            };
            for x in -span..=1 {
                for rest in cells(span) {
                    push(x, &rest, 1.0, s, rng);
                }
            }
            for x in 0..=span / 2 + 1 {
                for rest in cells(span / 2) {
                    push(x, &rest, 2.0, 2.0 * s, rng);
                }
            }
            v
        }

        fn check_set<const D: usize>(set: &[(Point<D>, f64)], brute: bool) -> [usize; 3] {
            let mut n = [0usize; 3];
            for (c, rc) in set {
                let got = sphere_uncovered_power(c, *rc, set);
                if brute {
                    let near: Vec<_> = set
                        .iter()
                        .filter(|(p, r)| (p - c).norm() <= rc + r + 1e-9)
                        .copied()
                        .collect();
                    assert_eq!(got, brute_force(c, *rc, &near), "particle at {c:?}");
                }
                match sampled(c, *rc, set) {
                    Some(s) => {
                        assert_eq!(got, s, "particle at {c:?} r {rc}: predicate vs sampling");
                        n[got as usize] += 1;
                    }
                    None => n[2] += 1,
                }
            }
            n
        }

        /// 2D at `s = 0.8` (above the square lattice's 1/√2), 3D at `s = 0.9` (above the
        /// cubic lattice's √3/2, so that both answers occur); the brute force in 2D only
        /// (its cost grows as the cube of the plane count in 3D).
        #[test]
        fn two_level_lattices_agree_with_sampling_and_brute_force() {
            let mut rng = StdRng::seed_from_u64(5);
            for jitter in [false, true] {
                let set = two_level::<2>(0.8, jitter, &mut rng);
                let [inner, outer, _] = check_set(&set, true);
                assert!(
                    inner > 30 && outer > 15,
                    "2D jitter {jitter}: {inner} {outer}"
                );
                let set = two_level::<3>(0.9, jitter, &mut rng);
                let [inner, outer, _] = check_set(&set, false);
                assert!(
                    inner > 40 && outer > 40,
                    "3D jitter {jitter}: {inner} {outer}"
                );
            }
        }
    }
}
