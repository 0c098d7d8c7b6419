//! Convex hulls in 2D and 3D with exact orientation predicates, written for the visibility
//! test (no system library, no file I/O, no panic path).
//!
//! Every orientation decision (left/right of a line, above/below a plane) is the exact sign
//! of a determinant of the given `f64` coordinates, from the adaptive predicates of the
//! [`robust`] crate (Shewchuk 1997). Hence the hull is the exact convex hull of its input:
//! every input point lies inside or on it, and the result does not depend on rounding,
//! only on the input and its order (which is fixed by the caller).
//!
//! - 2D: Andrew's monotone chain; collinear points on an edge are not vertices.
//! - 3D: incremental hull (the Quickhull scheme of Barber, Dobkin & Huhdanpaa 1996: outside
//!   sets, farthest point first, horizon of the strictly visible facets). A point on the
//!   plane of a facet is not outside it, so coplanar points are never added; the result is
//!   a triangulation of the hull's boundary in which adjacent triangles may be coplanar.
//! - Degenerate input: a 2D set whose points are all collinear (or fewer than 3 distinct),
//!   or a 3D set whose points are all coplanar, has no full-dimensional hull: `None`. (The 3D
//!   hull also answers `None` rather than panic if its surface were ever inconsistent, which
//!   exact predicates rule out; the tests check the surface is closed.)
//!   Exact duplicates are allowed (a duplicate is never strictly outside a facet).
//!
//! Input coordinates must be finite and within the predicates' range (no overflow or
//! underflow of products of four coordinates); the caller's flipped points are of order 1.

use robust::{orient2d, orient3d, Coord, Coord3D};

fn c2(p: &[f64; 2]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

fn c3(p: &[f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Exact sign of the turn `a → b → c`: positive for a left (counter-clockwise) turn.
pub fn turn(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> f64 {
    orient2d(c2(a), c2(b), c2(c))
}

/// Exact sign of `d` against the plane through `a, b, c`: negative when `d` lies on the side
/// from which `a, b, c` appear counter-clockwise (robust's `orient3d` convention).
pub fn side(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    orient3d(c3(a), c3(b), c3(c), c3(d))
}

fn lex2(a: &[f64; 2], b: &[f64; 2]) -> std::cmp::Ordering {
    a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1]))
}

/// The vertices of the convex hull of `pts` in counter-clockwise order, starting at the
/// lexicographically smallest point; points inside or on an edge (collinear) are not
/// vertices. `None` when all points are collinear (or fewer than three are distinct).
pub fn hull_2d(pts: &[[f64; 2]]) -> Option<Vec<usize>> {
    let mut order: Vec<usize> = (0..pts.len()).collect();
    order.sort_by(|&a, &b| lex2(&pts[a], &pts[b]).then(a.cmp(&b)));
    order.dedup_by(|a, b| pts[*a] == pts[*b]);
    if order.len() < 3 {
        return None;
    }
    let mut chain: Vec<usize> = Vec::with_capacity(2 * order.len());
    // Lower chain left to right, then upper chain right to left; a non-left turn pops.
    for pass in 0..2 {
        let start = chain.len();
        let iter: Box<dyn Iterator<Item = &usize>> = if pass == 0 {
            Box::new(order.iter())
        } else {
            Box::new(order.iter().rev())
        };
        for &i in iter {
            while chain.len() >= start + 2
                && turn(
                    &pts[chain[chain.len() - 2]],
                    &pts[chain[chain.len() - 1]],
                    &pts[i],
                ) <= 0.0
            {
                chain.pop();
            }
            chain.push(i);
        }
        // The last point of each chain is the first of the next.
        chain.pop();
    }
    (chain.len() >= 3).then_some(chain)
}

/// One triangle of a 3D hull: vertices counter-clockwise seen from outside, and the
/// neighbour across each edge `(v[k], v[(k+1)%3])`.
#[derive(Debug, Clone)]
struct Facet {
    v: [usize; 3],
    adj: [usize; 3],
    alive: bool,
    /// The points strictly outside, each with its height `-side(v, p) > 0` (the magnitude of
    /// the determinant, kept from the test that assigned it, so that the farthest point is
    /// chosen without evaluating the predicate again).
    outside: Vec<(usize, f64)>,
}

/// Whether `p` lies strictly outside facet `f`.
fn outside_of(pts: &[[f64; 3]], f: &[usize; 3], p: usize) -> bool {
    side(&pts[f[0]], &pts[f[1]], &pts[f[2]], &pts[p]) < 0.0
}

/// `Some(height)` (`-side > 0`) when `p` lies strictly outside facet `f`.
fn height_above(pts: &[[f64; 3]], f: &[usize; 3], p: usize) -> Option<f64> {
    let s = side(&pts[f[0]], &pts[f[1]], &pts[f[2]], &pts[p]);
    (s < 0.0).then_some(-s)
}

/// Whether `a, b, c` are collinear in 3D: exact, through the three coordinate projections.
fn collinear3(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    let proj = |p: &[f64; 3], i: usize, j: usize| [p[i], p[j]];
    [(0, 1), (0, 2), (1, 2)]
        .iter()
        .all(|&(i, j)| turn(&proj(a, i, j), &proj(b, i, j), &proj(c, i, j)) == 0.0)
}

fn dist2(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

/// The triangles of the convex hull of `pts`, each `[a, b, c]` counter-clockwise seen from
/// outside (every input point `d` has `side(a, b, c, d) >= 0`). Adjacent triangles may be
/// coplanar; points on the boundary that are not needed as corners are not used. `None`
/// when all points are coplanar.
pub fn hull_3d(pts: &[[f64; 3]]) -> Option<Vec<[usize; 3]>> {
    let n = pts.len();
    if n < 4 {
        return None;
    }
    // Initial simplex: the lexicographically smallest point, the farthest from it, the
    // point farthest from their line (floating-point choice, exact check), and the point
    // farthest from their plane (exact check).
    let lex3 = |a: &[f64; 3], b: &[f64; 3]| {
        a[0].total_cmp(&b[0])
            .then(a[1].total_cmp(&b[1]))
            .then(a[2].total_cmp(&b[2]))
    };
    let i0 = (0..n).min_by(|&a, &b| lex3(&pts[a], &pts[b]).then(a.cmp(&b)))?;
    let i1 = (0..n).filter(|&i| pts[i] != pts[i0]).max_by(|&a, &b| {
        dist2(&pts[i0], &pts[a])
            .total_cmp(&dist2(&pts[i0], &pts[b]))
            .then(b.cmp(&a))
    })?;
    let cross_norm2 = |i: usize| {
        let (a, b, c) = (&pts[i0], &pts[i1], &pts[i]);
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let x = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
    };
    let i2 = (0..n)
        .filter(|&i| !collinear3(&pts[i0], &pts[i1], &pts[i]))
        .max_by(|&a, &b| cross_norm2(a).total_cmp(&cross_norm2(b)).then(b.cmp(&a)))?;
    let i3 = (0..n)
        .filter(|&i| side(&pts[i0], &pts[i1], &pts[i2], &pts[i]) != 0.0)
        .max_by(|&a, &b| {
            side(&pts[i0], &pts[i1], &pts[i2], &pts[a])
                .abs()
                .total_cmp(&side(&pts[i0], &pts[i1], &pts[i2], &pts[b]).abs())
                .then(b.cmp(&a))
        })?;
    // Orient the base so that i3 is inside (side > 0 for every facet).
    let (a, b, c, d) = if side(&pts[i0], &pts[i1], &pts[i2], &pts[i3]) > 0.0 {
        (i0, i1, i2, i3)
    } else {
        (i0, i2, i1, i3)
    };
    // Facets: 0 = abc, 1 = adb... each listed CCW from outside; adjacency by shared edges.
    let tris = [[a, b, c], [a, d, b], [b, d, c], [c, d, a]];
    let mut facets: Vec<Facet> = tris
        .iter()
        .map(|&v| Facet {
            v,
            adj: [usize::MAX; 3],
            alive: true,
            outside: Vec::new(),
        })
        .collect();
    link_all(&mut facets, &[0, 1, 2, 3]);
    for p in 0..n {
        if p == a || p == b || p == c || p == d {
            continue;
        }
        if let Some((f, h)) =
            (0..4).find_map(|f| height_above(pts, &facets[f].v, p).map(|h| (f, h)))
        {
            facets[f].outside.push((p, h));
        }
    }
    let mut pending: Vec<usize> = (0..4).rev().collect();
    let mut visible: Vec<usize> = Vec::new();
    let mut stack: Vec<usize> = Vec::new();
    let mut mark: Vec<u32> = vec![0; 4];
    let mut round = 0u32;
    let mut horizon: Vec<(usize, usize, usize)> = Vec::new();
    let mut orphans: Vec<usize> = Vec::new();
    let mut created: Vec<usize> = Vec::new();
    while let Some(f0) = pending.pop() {
        if !facets[f0].alive || facets[f0].outside.is_empty() {
            continue;
        }
        // The farthest outside point of f0 (by the magnitude of the determinant).
        let (p, _) = *facets[f0]
            .outside
            .iter()
            .max_by(|&&(x, sx), &&(y, sy)| sx.total_cmp(&sy).then(y.cmp(&x)))?;
        // Strictly visible facets: connected, found by a search from f0.
        round += 1;
        mark.resize(facets.len(), 0);
        visible.clear();
        stack.clear();
        stack.push(f0);
        mark[f0] = round;
        while let Some(f) = stack.pop() {
            visible.push(f);
            for k in 0..3 {
                let g = facets[f].adj[k];
                if mark[g] != round && outside_of(pts, &facets[g].v, p) {
                    mark[g] = round;
                    stack.push(g);
                }
            }
        }
        // Horizon edges (u, v) of visible facets whose neighbour is not visible.
        horizon.clear();
        orphans.clear();
        for &f in &visible {
            for k in 0..3 {
                let g = facets[f].adj[k];
                if mark[g] != round {
                    horizon.push((facets[f].v[k], facets[f].v[(k + 1) % 3], g));
                }
            }
            let out = std::mem::take(&mut facets[f].outside);
            orphans.extend(out.into_iter().map(|(q, _)| q).filter(|&q| q != p));
            facets[f].alive = false;
        }
        created.clear();
        for &(u, v, g) in &horizon {
            let id = facets.len();
            facets.push(Facet {
                v: [u, v, p],
                adj: [g, usize::MAX, usize::MAX],
                alive: true,
                outside: Vec::new(),
            });
            // The kept neighbour's edge (v, u) now borders the new facet.
            let gk = (0..3).find(|&k| facets[g].v[k] == v && facets[g].v[(k + 1) % 3] == u)?;
            facets[g].adj[gk] = id;
            created.push(id);
        }
        // New facets share the edges (v, p) / (p, u) with each other.
        for &fx in &created {
            let vx = facets[fx].v[1];
            let fy = *created.iter().find(|&&fy| facets[fy].v[0] == vx)?;
            facets[fx].adj[1] = fy;
            facets[fy].adj[2] = fx;
        }
        // The horizon is one cycle (exact predicates): every new facet has both new
        // neighbours. Were it not, give up rather than walk a broken surface.
        if created.iter().any(|&f| facets[f].adj.contains(&usize::MAX)) {
            return None;
        }
        for &q in &orphans {
            if let Some((f, h)) = created
                .iter()
                .find_map(|&f| height_above(pts, &facets[f].v, q).map(|h| (f, h)))
            {
                facets[f].outside.push((q, h));
            }
        }
        pending.extend(created.iter().rev().copied());
    }
    Some(facets.iter().filter(|f| f.alive).map(|f| f.v).collect())
}

/// Sets the adjacency of the facets listed in `ids` among themselves, by shared edges.
fn link_all(facets: &mut [Facet], ids: &[usize]) {
    for &f in ids {
        for k in 0..3 {
            let (u, v) = (facets[f].v[k], facets[f].v[(k + 1) % 3]);
            if let Some(&g) = ids.iter().find(|&&g| {
                g != f && (0..3).any(|j| facets[g].v[j] == v && facets[g].v[(j + 1) % 3] == u)
            }) {
                facets[f].adj[k] = g;
            }
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift), so that the tests need no dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Brute force 2D: every point is on the inner side (or on) of every hull edge, and
    /// every hull vertex is extreme (strict left turn at it).
    fn check_2d(pts: &[[f64; 2]]) {
        let h = hull_2d(pts).unwrap();
        for k in 0..h.len() {
            let (a, b, c) = (h[k], h[(k + 1) % h.len()], h[(k + 2) % h.len()]);
            assert!(
                turn(&pts[a], &pts[b], &pts[c]) > 0.0,
                "vertex {b} not extreme"
            );
            for (i, p) in pts.iter().enumerate() {
                assert!(turn(&pts[a], &pts[b], p) >= 0.0, "point {i} outside edge");
            }
        }
    }

    /// Brute force 3D: every point on the inner side (or on) of every triangle (exact);
    /// no triangle is degenerate; every directed edge is used once and its reverse once
    /// (a closed surface); extreme points are corners.
    fn check_3d(pts: &[[f64; 3]]) {
        let h = hull_3d(pts).unwrap();
        let mut edges = std::collections::HashMap::new();
        for t in &h {
            assert!(
                !collinear3(&pts[t[0]], &pts[t[1]], &pts[t[2]]),
                "flat {t:?}"
            );
            for (i, p) in pts.iter().enumerate() {
                assert!(
                    side(&pts[t[0]], &pts[t[1]], &pts[t[2]], p) >= 0.0,
                    "point {i} outside {t:?}"
                );
            }
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(u, v), &count) in &edges {
            assert_eq!(count, 1, "edge {u}-{v} used twice");
            assert_eq!(edges.get(&(v, u)), Some(&1), "edge {u}-{v} unmatched");
        }
        // Extreme points must be corners: the unique maximiser of a random linear
        // functional is extreme (a corner adjacent only to coplanar triangles may be
        // non-extreme, which is allowed).
        let corners: std::collections::BTreeSet<usize> = h.iter().flatten().copied().collect();
        let mut rng = Rng(99);
        for _ in 0..200 {
            let w = [rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5];
            let dot = |p: &[f64; 3]| p[0] * w[0] + p[1] * w[1] + p[2] * w[2];
            let best = (0..pts.len())
                .max_by(|&a, &b| dot(&pts[a]).total_cmp(&dot(&pts[b])))
                .unwrap();
            let ties = pts.iter().filter(|p| dot(p) == dot(&pts[best])).count();
            if ties == 1 {
                assert!(corners.contains(&best), "extreme point {best} missing");
            }
        }
    }

    #[test]
    fn random_hulls_contain_every_point_and_use_extreme_corners() {
        let mut rng = Rng(7);
        for n in [3, 4, 5, 10, 50, 300] {
            for _ in 0..5 {
                let p2: Vec<[f64; 2]> = (0..n).map(|_| [rng.next(), rng.next()]).collect();
                check_2d(&p2);
                if n >= 4 {
                    let p3: Vec<[f64; 3]> = (0..n)
                        .map(|_| [rng.next(), rng.next(), rng.next()])
                        .collect();
                    check_3d(&p3);
                }
            }
        }
    }

    #[test]
    fn lattices_with_duplicates_and_coplanar_faces_are_exact() {
        // A 5x5x5 cubic lattice, every point twice: 8 extreme corners, many coplanar points.
        let mut p3 = Vec::new();
        for k in 0..125 {
            let p = [(k % 5) as f64, (k / 5 % 5) as f64, (k / 25) as f64];
            p3.push(p);
            p3.push(p);
        }
        check_3d(&p3);
        let h = hull_3d(&p3).unwrap();
        let corners: std::collections::BTreeSet<[u64; 3]> = h
            .iter()
            .flatten()
            .map(|&i| p3[i].map(f64::to_bits))
            .collect();
        assert_eq!(corners.len(), 8, "only the cube's corners are needed");
        // A 2D square lattice with duplicates: 4 vertices.
        let p2: Vec<[f64; 2]> = (0..50).map(|k| [(k % 5) as f64, (k / 10) as f64]).collect();
        check_2d(&p2);
        assert_eq!(hull_2d(&p2).unwrap().len(), 4);
        // Points on a sphere-like shell with tiny offsets (near-ties).
        let mut rng = Rng(3);
        let shell: Vec<[f64; 3]> = (0..200)
            .map(|_| {
                let v = [rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5];
                let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                v.map(|x| x / n)
            })
            .collect();
        check_3d(&shell);
    }

    #[test]
    fn flat_input_has_no_hull() {
        assert!(hull_2d(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [1.0, 1.0]]).is_none());
        assert!(hull_2d(&[[0.0, 0.0], [0.0, 0.0]]).is_none());
        assert!(hull_2d(&[]).is_none());
        let plane: Vec<[f64; 3]> = (0..20)
            .map(|k| [0.1 * k as f64, (k % 3) as f64, 0.5 * 0.1 * k as f64])
            .collect();
        assert!(hull_3d(&plane).is_none());
        let line: Vec<[f64; 3]> = (0..20).map(|k| [k as f64, 2.0 * k as f64, 1.0]).collect();
        assert!(hull_3d(&line).is_none());
        assert!(hull_3d(&[[0.0; 3]; 9]).is_none());
    }
}
