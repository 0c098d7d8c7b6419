//! Brute-force exact labels for tests: an independent check of the certified reference
//! detectors on near-ties, written without any code of theirs.
//!
//! Characterisation used: particle `i` is boundary iff some point `x` with `|x − p_i| > r`
//! satisfies `|x − p_i| <= |x − p_j|` for every other particle `j` with `0 < |p_j − p_i| <= 2r`
//! (its restricted Voronoi cell leaves the ball), restricted to the box `|x_k − p_{i,k}| <= 2r`
//! (which contains the ball with room). The cell is a polytope, so this holds iff one of its
//! vertices lies beyond `r`. The vertices are found by brute force: every choice of `D` planes
//! (bisectors and box faces) whose system has a unique solution, solved by Gaussian elimination
//! over exact rationals (`num_rational::BigRational`, every `f64` converted exactly), kept if it
//! satisfies every plane. Cost `O(m^(D+1))` for `m` planes: only for small sets.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};

/// The exact value of a finite `f64`.
pub fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite input")
}

/// Whether the particle at `centre` is boundary among `others` at resolution `r`, by vertex
/// enumeration in exact rationals (module docs). `others` may contain copies of `centre`.
pub fn uncovered_by_enumeration<const D: usize>(
    centre: [f64; D],
    others: &[[f64; D]],
    r: f64,
) -> bool {
    let r = rational(r);
    let c: Vec<BigRational> = centre.iter().map(|&x| rational(x)).collect();
    let two = BigRational::from_integer(BigInt::from(2));
    // Planes a·x <= b in coordinates relative to the centre.
    let mut planes = box_planes(D, &two * &r);
    let limit = &two * &two * &r * &r;
    for p in others {
        let q: Vec<BigRational> = (0..D).map(|k| rational(p[k]) - &c[k]).collect();
        let d2: BigRational = q.iter().map(|x| x * x).sum();
        if d2.is_zero() || d2 > limit {
            continue;
        }
        // |x|² <= |x − q|²  <=>  q·x <= |q|²/2.
        planes.push((q, d2 / &two));
    }
    let r2 = &r * &r;
    let m = planes.len();
    let mut ids = vec![0usize; D];
    // Enumerate D-subsets in lexicographic order.
    fn next(ids: &mut [usize], m: usize) -> bool {
        let d = ids.len();
        for k in (0..d).rev() {
            if ids[k] < m - d + k {
                ids[k] += 1;
                for l in k + 1..d {
                    ids[l] = ids[l - 1] + 1;
                }
                return true;
            }
        }
        false
    }
    for (k, id) in ids.iter_mut().enumerate() {
        *id = k;
    }
    loop {
        if let Some(x) = solve(&planes, &ids) {
            let norm2: BigRational = x.iter().map(|v| v * v).sum();
            if norm2 > r2 {
                let feasible = planes.iter().all(|(a, b)| {
                    let s: BigRational = a.iter().zip(&x).map(|(u, v)| u * v).sum();
                    s <= *b
                });
                if feasible {
                    return true;
                }
            }
        }
        if !next(&mut ids, m) {
            return false;
        }
    }
}

/// The power-diagram oracle for per-particle radii: whether the sphere of radius `r` around
/// `centre` is **not** covered by the closed balls `others` (centre, radius), in exact
/// rationals, by brute force. Coincident balls (`p_j == centre`) are ignored.
///
/// In coordinates `y = x − centre` the power cell is `K = {2q_j·y <= |q_j|² + r² − r_j²}` over
/// the balls reaching the sphere (`|q_j| < r + r_j`), cut by the box `|y_k| <= 2r`. A point of
/// the sphere is uncovered iff it lies in the interior of `K`, so the particle is boundary iff
/// `K` is full-dimensional, has a point beyond `r` and a point within `r` (its interior is
/// connected). All three from brute force: the vertices of `K` (every `D`-subset of planes
/// solved, kept if feasible) decide the first two (the affine rank of the vertices, the
/// largest `|v|`); `min_K |y|` is attained at the projection of the origin onto the affine
/// hull of some face, i.e. the least-norm solution of some subset of at most `D` planes taken
/// as equations, so every such subset is solved and its point kept if feasible. Cost
/// `O(m^(D+1))` rational operations for `m` planes: only for a handful of balls.
pub fn power_uncovered_by_enumeration<const D: usize>(
    centre: [f64; D],
    r: f64,
    others: &[([f64; D], f64)],
) -> bool {
    solid_uncovered_by_enumeration(centre, r, others, &[])
}

/// [`power_uncovered_by_enumeration`] with closed solid half-spaces covering too: each solid
/// `(axis, solid_below, c)` is `{x_axis <= c}` (`solid_below`) or `{x_axis >= c}`, and the
/// sphere's points outside every solid must be covered by the balls. A point of the sphere
/// outside the closed solid lies strictly on the fluid side, so each solid is one more
/// half-space of the cell `K` (`−y_a <= p_a − c`, or `y_a <= c − p_a`), and the same three
/// conditions decide, by the same brute force.
pub fn solid_uncovered_by_enumeration<const D: usize>(
    centre: [f64; D],
    r: f64,
    others: &[([f64; D], f64)],
    solids: &[(usize, bool, f64)],
) -> bool {
    let rc = rational(r);
    let c: Vec<BigRational> = centre.iter().map(|&x| rational(x)).collect();
    let two = BigRational::from_integer(BigInt::from(2));
    let mut planes = box_planes(D, &two * &rc);
    let r2 = &rc * &rc;
    for (p, rj) in others {
        let rj = rational(*rj);
        let q: Vec<BigRational> = (0..D).map(|k| rational(p[k]) - &c[k]).collect();
        let d2: BigRational = q.iter().map(|x| x * x).sum();
        let reach = &rc + &rj;
        if d2.is_zero() || d2 >= &reach * &reach {
            continue;
        }
        // |y|² − r² <= |y − q|² − r_j²  <=>  q·y <= (|q|² + r² − r_j²)/2.
        let b = (d2 + &r2 - &rj * &rj) / &two;
        planes.push((q, b));
    }
    for &(axis, below, value) in solids {
        let sign = if below { -1 } else { 1 };
        let a: Vec<BigRational> = (0..D)
            .map(|k| BigRational::from_integer(BigInt::from(if k == axis { sign } else { 0 })))
            .collect();
        let depth = rational(value) - &c[axis];
        planes.push((a, if below { -depth } else { depth }));
    }
    let feasible = |x: &[BigRational]| {
        planes.iter().all(|(a, b)| {
            let s: BigRational = a.iter().zip(x).map(|(u, v)| u * v).sum();
            s <= *b
        })
    };
    let norm2 = |x: &[BigRational]| -> BigRational { x.iter().map(|v| v * v).sum() };
    let m = planes.len();
    // Vertices.
    let mut vertices: Vec<Vec<BigRational>> = Vec::new();
    for ids in subsets(m, D) {
        if let Some(x) = solve(&planes, &ids) {
            if feasible(&x) {
                vertices.push(x);
            }
        }
    }
    if affine_rank(&vertices) < D || !vertices.iter().any(|v| norm2(v) > r2) {
        return false;
    }
    // A point of K within the sphere: the least-norm point of some subset of the planes.
    (0..=D).any(|k| {
        subsets(m, k)
            .into_iter()
            .any(|ids| least_norm(&planes, &ids).is_some_and(|x| norm2(&x) < r2 && feasible(&x)))
    })
}

/// The faces of the box `|x_k| <= half` as planes `a·x <= b`.
fn box_planes(d: usize, half: BigRational) -> Vec<(Vec<BigRational>, BigRational)> {
    let mut planes = Vec::new();
    for axis in 0..d {
        for sign in [1, -1] {
            let a: Vec<BigRational> = (0..d)
                .map(|k| {
                    if k == axis {
                        BigRational::from_integer(BigInt::from(sign))
                    } else {
                        BigRational::zero()
                    }
                })
                .collect();
            planes.push((a, half.clone()));
        }
    }
    planes
}

/// Every `k`-subset of `0..m`, in lexicographic order.
fn subsets(m: usize, k: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    if k > m {
        return out;
    }
    let mut ids: Vec<usize> = (0..k).collect();
    loop {
        out.push(ids.clone());
        let Some(pos) = (0..k).rev().find(|&p| ids[p] < m - k + p) else {
            return out;
        };
        ids[pos] += 1;
        for l in pos + 1..k {
            ids[l] = ids[l - 1] + 1;
        }
    }
}

/// The least-norm solution of the planes `ids` taken as equations `a·x = b`:
/// `x = Aᵀz` with `(AAᵀ)z = b`; `None` if the rows are dependent. The empty subset gives 0.
fn least_norm(
    planes: &[(Vec<BigRational>, BigRational)],
    ids: &[usize],
) -> Option<Vec<BigRational>> {
    let d = planes.first().map_or(0, |p| p.0.len());
    if ids.is_empty() {
        return Some(vec![BigRational::zero(); d]);
    }
    let dot = |a: &[BigRational], b: &[BigRational]| -> BigRational {
        a.iter().zip(b).map(|(u, v)| u * v).sum()
    };
    let gram: Vec<(Vec<BigRational>, BigRational)> = ids
        .iter()
        .map(|&i| {
            let row = ids
                .iter()
                .map(|&j| dot(&planes[i].0, &planes[j].0))
                .collect();
            (row, planes[i].1.clone())
        })
        .collect();
    let all: Vec<usize> = (0..ids.len()).collect();
    let z = solve(&gram, &all)?;
    Some(
        (0..d)
            .map(|k| {
                ids.iter()
                    .zip(&z)
                    .map(|(&i, zi)| &planes[i].0[k] * zi)
                    .sum()
            })
            .collect(),
    )
}

/// The dimension of the affine hull of `points` (`-1` as 0 for none).
fn affine_rank(points: &[Vec<BigRational>]) -> usize {
    let Some(first) = points.first() else {
        return 0;
    };
    let mut rows: Vec<Vec<BigRational>> = points[1..]
        .iter()
        .map(|p| p.iter().zip(first).map(|(a, b)| a - b).collect())
        .collect();
    let d = first.len();
    let mut rank = 0;
    for col in 0..d {
        let Some(pivot) = (rank..rows.len()).find(|&r| !rows[r][col].is_zero()) else {
            continue;
        };
        rows.swap(rank, pivot);
        let pivot_row = rows[rank].clone();
        for (i, row) in rows.iter_mut().enumerate() {
            if i != rank && !row[col].is_zero() {
                let f = &row[col] / &pivot_row[col];
                for (x, p) in row.iter_mut().zip(&pivot_row) {
                    *x = &*x - &f * p;
                }
            }
        }
        rank += 1;
    }
    rank
}

/// Gaussian elimination with exact pivoting on the rows `ids`; `None` if singular.
fn solve(planes: &[(Vec<BigRational>, BigRational)], ids: &[usize]) -> Option<Vec<BigRational>> {
    let d = ids.len();
    let mut m: Vec<Vec<BigRational>> = ids
        .iter()
        .map(|&i| {
            let mut row = planes[i].0.clone();
            row.push(planes[i].1.clone());
            row
        })
        .collect();
    for col in 0..d {
        let pivot = (col..d).find(|&r| !m[r][col].is_zero())?;
        m.swap(col, pivot);
        let inv = BigRational::one() / &m[col][col];
        for x in m[col][col..].iter_mut() {
            *x = &*x * &inv;
        }
        let pivot_row = m[col].clone();
        for (i, row) in m.iter_mut().enumerate() {
            if i != col && !row[col].is_zero() {
                let f = row[col].clone();
                for (x, p) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                    *x = &*x - &f * p;
                }
            }
        }
    }
    Some(m.into_iter().map(|row| row[d].clone()).collect())
}

/// The exact labels of a lattice of spacing `a` (`n` per axis, origin at 0, `D` = 2 or 3)
/// near its tie radius (`a/√2 <= r < a` in 2D, `a·√3/2 <= r < a` in 3D, or just below the tie):
/// the outer layer is boundary, an inner particle is interior iff `r >= tie`, decided as
/// `2r² >= a²` (2D) or `4r² >= 3a²` (3D) in exact rationals. Valid for `r` within a relative
/// 1e-6 of the tie.
pub fn lattice_labels_near_tie(d: usize, n: usize, a: f64, r: f64) -> Vec<bool> {
    let (r, a) = (rational(r), rational(a));
    let covered = if d == 2 {
        BigRational::from_integer(2.into()) * &r * &r >= &a * &a
    } else {
        BigRational::from_integer(4.into()) * &r * &r
            >= BigRational::from_integer(3.into()) * &a * &a
    };
    (0..n.pow(d as u32))
        .map(|k| {
            let mut rest = k;
            let mut outer = false;
            for _ in 0..d {
                let c = rest % n;
                outer |= c == 0 || c == n - 1;
                rest /= n;
            }
            outer || !covered
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With equal radii the power oracle is the Voronoi oracle; a ball holding the sphere
    /// covers it, a ball that leaves a sliver does not, coincident balls never cover.
    #[test]
    fn power_oracle_agrees_with_the_voronoi_oracle_and_closed_forms() {
        let axes = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];
        for r in [0.7, 0.5f64.sqrt(), 0.75] {
            let balls: Vec<([f64; 2], f64)> = axes.iter().map(|&p| (p, r)).collect();
            assert_eq!(
                power_uncovered_by_enumeration([0.0, 0.0], r, &balls),
                uncovered_by_enumeration([0.0, 0.0], &axes, r),
                "r = {r}"
            );
        }
        let one =
            |d: f64, rj: f64| power_uncovered_by_enumeration([0.0, 0.0], 1.0, &[([d, 0.0], rj)]);
        assert!(!one(0.5, 2.0), "held");
        assert!(
            !one(0.5, 1.5),
            "touching from inside: covered by the closed ball"
        );
        assert!(
            one(0.5, 1.5f64.next_down()),
            "one ulp smaller: a sliver is uncovered"
        );
        assert!(one(0.0, 5.0), "coincident: ignored");
        assert!(one(3.0, 1.0), "a ball too far: uncovered");
        // Flat cell: balls at (±0.75, 0) of radius 1.25 have the same power plane y_x = 0, so K
        // is a segment through the origin; (0, ±1) lie on both spheres: covered (a tie). One
        // ulp smaller, they are uncovered.
        let flat = |rj: f64| {
            power_uncovered_by_enumeration(
                [0.0, 0.0],
                1.0,
                &[([0.75, 0.0], rj), ([-0.75, 0.0], rj)],
            )
        };
        assert!(!flat(1.25));
        assert!(flat(1.25f64.next_down()));
    }

    #[test]
    fn four_axis_neighbours_cover_from_the_tie_up() {
        let n = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];
        let tie = std::f64::consts::FRAC_1_SQRT_2; // fl(1/√2) > 1/√2
        assert!(!uncovered_by_enumeration([0.0, 0.0], &n, tie));
        assert!(uncovered_by_enumeration([0.0, 0.0], &n, tie.next_down()));
        assert!(uncovered_by_enumeration([0.0, 0.0], &n[..3], 0.9));
        assert!(uncovered_by_enumeration([0.0, 0.0], &[], 1.0));
    }

    #[test]
    fn six_axis_neighbours_cover_from_the_tie_up() {
        let n = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let tie = 3f64.sqrt() / 2.0; // fl(√3/2) < √3/2
        assert!(uncovered_by_enumeration([0.0; 3], &n, tie));
        assert!(!uncovered_by_enumeration([0.0; 3], &n, tie.next_up()));
    }

    #[test]
    fn lattice_labels_follow_the_exact_tie() {
        let tie = std::f64::consts::FRAC_1_SQRT_2;
        let above = lattice_labels_near_tie(2, 4, 1.0, tie);
        assert_eq!(above.iter().filter(|&&b| b).count(), 12);
        let below = lattice_labels_near_tie(2, 4, 1.0, tie.next_down());
        assert!(below.iter().all(|&b| b));
    }
}
