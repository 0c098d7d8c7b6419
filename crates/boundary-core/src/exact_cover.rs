//! The exact covering predicate: is `S_i` covered, decided in exact arithmetic for the given
//! floating-point input. Used by the certified reference detectors (`exact`, `dilts`) for the
//! few particles whose floating-point decision falls inside its error bound.
//!
//! # The question
//! Particle `i` at `p_i` is boundary iff its restricted Voronoi cell
//! `V_i = {x : |x − p_i| <= |x − p_j| for every neighbour j}` (neighbours: the other particles
//! with `0 < |p_j − p_i| < 2r`; exact duplicates of `p_i` excluded) has a point strictly farther
//! than `r` from `p_i` (the proof is in the `boundary-exact` crate docs). A neighbour at `2r` or
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
//! whether it lies beyond `r` is `|N|²·4^t > r²·den²` in integers. The integers are `i128` when
//! a bound on their size (`D·B_a + B_b + 2D + 2 <= 126` bits, `B_a`, `B_b` the bit lengths of
//! the plane coefficients) proves that no product overflows, which is the case for lattices of
//! small integers; otherwise arbitrary-precision `num_bigint::BigInt`.
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
//! vertices: well below a millisecond for lattices of small integers, a few milliseconds for
//! generic `f64` input (big integers); callers use it only where their floating-point filters
//! and certificates cannot decide.

use crate::Point;
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
/// If `r` is not positive and finite (callers pass the value of a [`crate::Radius`]), or if
/// `D` is not 2 or 3.
///
/// ```
/// use boundary_core::{exact_cover::sphere_uncovered, Point};
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
    let k_box = {
        let bits = r_int.bits();
        // 2^(bits-1) <= r_int < 2^bits; r_int is a power of two iff it has one bit set.
        if r_int.trailing_zeros() == Some(bits - 1) {
            bits - 1
        } else {
            bits
        }
    };
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
    let beyond = Beyond {
        r2: &r_int * &r_int,
        shift: 2 * t as usize,
        r_f64: r,
        unit_f64: 2f64.powi(e_min) * 2f64.powi(t as i32),
    };
    let bits_a = planes
        .iter()
        .flat_map(|(a, _)| a.iter().map(|x| x.bits()))
        .max()
        .unwrap_or(0);
    let bits_b = planes.iter().map(|(_, b)| b.bits()).max().unwrap_or(0);
    if D as u64 * bits_a + bits_b + 2 * D as u64 + 2 <= 126 {
        let small: Vec<([i128; D], i128)> = planes
            .iter()
            .map(|(a, b)| {
                (
                    std::array::from_fn(|k| a[k].to_i128().unwrap_or(0)),
                    b.to_i128().unwrap_or(0),
                )
            })
            .collect();
        nearest_first::<i128, D>(&small, &beyond)
    } else {
        nearest_first::<BigInt, D>(&planes, &beyond)
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
}

impl Ring for i128 {
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
}

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
}

/// The final test `|v| > r` for a vertex `v = N/den` (in the unit `2^(E+t)`).
struct Beyond {
    /// `r²` in the unit `2^(2E)`.
    r2: BigInt,
    /// `2t`: `|v|² > r²` iff `|N|²·2^(2t) > r2·den²`.
    shift: usize,
    /// `r` and the unit `2^(E+t)` as floats, for a quick rejection of vertices well inside.
    r_f64: f64,
    unit_f64: f64,
}

impl Beyond {
    fn test<T: Ring, const D: usize>(&self, n: &[T; D], den: &T) -> bool {
        // Quick rejection: |v| below 0.99 r by the float estimate (each conversion is within a
        // relative 2^-52 of the integer, far inside the 1 % slack); otherwise decide exactly.
        let d = den.approx();
        let n2: f64 = n.iter().map(|x| x.approx() * x.approx()).sum();
        let v2 = n2 / (d * d) * self.unit_f64 * self.unit_f64;
        if v2.is_finite() && v2 > 0.0 && v2 < 0.98 * self.r_f64 * self.r_f64 && d.is_finite() {
            return false;
        }
        let den = den.big();
        let lhs: BigInt = n.iter().map(|x| x.big() * x.big()).sum::<BigInt>() << self.shift;
        lhs > &self.r2 * &den * &den
    }
}

fn det<T: Ring, const D: usize>(m: &[[T; D]; D]) -> T {
    match D {
        2 => m[0][0].mul(&m[1][1]).sub(&m[0][1].mul(&m[1][0])),
        3 => {
            let minor = |a: usize, b: usize, c: usize, d: usize| {
                m[1][a].mul(&m[2][b]).sub(&m[1][c].mul(&m[2][d]))
            };
            m[0][0]
                .mul(&minor(1, 2, 2, 1))
                .sub(&m[0][1].mul(&minor(0, 2, 2, 0)))
                .add(&m[0][2].mul(&minor(0, 1, 1, 0)))
        }
        _ => unreachable!("D is 2 or 3"),
    }
}

/// A vertex: `N/den` with `den > 0`, and the plane of the polygon edge leaving it.
#[derive(Debug, Clone)]
struct Vertex<T, const D: usize> {
    n: [T; D],
    den: T,
    line_out: usize,
}

/// The intersection of the planes `ids` (Cramer's rule), `None` if they are not independent.
fn solve<T: Ring, const D: usize>(planes: &[([T; D], T)], ids: [usize; D]) -> Option<([T; D], T)> {
    let m: [[T; D]; D] = std::array::from_fn(|row| planes[ids[row]].0.clone());
    let mut den = det(&m);
    let s = den.sign();
    if s == 0 {
        return None;
    }
    let mut n: [T; D] = std::array::from_fn(|col| {
        let mc: [[T; D]; D] = std::array::from_fn(|row| {
            let mut r = m[row].clone();
            r[col] = planes[ids[row]].1.clone();
            r
        });
        det(&mc)
    });
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
    let signs: Vec<i8> = poly.iter().map(|v| side(&planes[h], v)).collect();
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
    // The square in axes (b, c) (plane ids 2b, 2b+1 for +, −), counter-clockwise, as
    // intersections with `fixed` (3D) or alone (2D).
    let square = |poly: &mut Vec<Vertex<T, D>>, fixed: Option<usize>, b: usize, c: usize| {
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
    };
    if D == 2 {
        square(&mut poly, None, 0, 1);
        for h in 4..planes.len() {
            clip(&mut poly, &mut out, planes, None, h);
        }
        return if judge(&poly) {
            Reach::Beyond
        } else if unsure {
            Reach::Unsure
        } else {
            Reach::Within
        };
    }
    for p in 0..planes.len() {
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
        square(&mut poly, Some(p), b, c);
        for h in [2 * axis, 2 * axis + 1]
            .into_iter()
            .chain(2 * D..planes.len())
        {
            if h == p {
                continue;
            }
            clip(&mut poly, &mut out, planes, Some(p), h);
            if poly.is_empty() {
                break;
            }
        }
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
}
