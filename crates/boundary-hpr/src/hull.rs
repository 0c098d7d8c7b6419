//! Convex hulls in 2D and 3D with exact orientation predicates, written for the visibility
//! test (no system library, no file I/O, no panic path).
//!
//! Every orientation decision (left/right of a line, above/below a plane) is the exact sign
//! of a determinant of the given `f64` coordinates, from the adaptive predicates of the
//! [`robust`] crate (Shewchuk 1997). Hence the hull is the exact convex hull of its input:
//! every input point lies inside or on it, and the result does not depend on rounding,
//! only on the input and its order (which is fixed by the caller). The floating-point stage
//! of `orient3d` is inlined here ([`side`], the same value bit for bit), and the 3D hull
//! rejects points certainly inside a facet with a cheaper filter on the facet's stored plane
//! before evaluating [`side`]; neither changes a decision or a value the hull uses.
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

/// Error-bound factor of the floating-point stage of Shewchuk's `orient3d` (Shewchuk 1997,
/// `o3derrboundA = (7 + 56ε)ε`, `ε = 2^-53`): when the determinant evaluated in floating
/// point from the nine coordinate differences exceeds this factor times its permanent in
/// magnitude, its sign is exact.
const O3D_BOUND: f64 = (7.0 + 56.0 * EPS) * EPS;
/// `ε = 2^-53`, half a unit in the last place of 1.
const EPS: f64 = f64::EPSILON / 2.0;
/// The bound of [`Plane::certainly_inside`], a unit of `ε` wider than [`O3D_BOUND`]: the same
/// expression tree (a 3x3 determinant of rounded coordinate differences, expanded along one
/// row with the 2x2 minors rounded), but with the margin kept on purpose since the minors
/// are shared between tests (they are the same rounded values, so the analysis is unchanged).
const PLANE_BOUND: f64 = (8.0 + 64.0 * EPS) * EPS;

/// Exact sign of `d` against the plane through `a, b, c`: negative when `d` lies on the side
/// from which `a, b, c` appear counter-clockwise (robust's `orient3d` convention).
///
/// The returned `f64` is bit for bit the one of `robust::orient3d`: the floating-point
/// stage is evaluated here, inlined, with robust's expression (the same operations in the
/// same order) and error bound; when it does not decide the sign, robust's `orient3d` is
/// called (its adaptive stages). Tested against `robust::orient3d` on random, near-coplanar
/// and exactly coplanar input.
#[inline]
pub fn side(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    let (adx, bdx, cdx) = (a[0] - d[0], b[0] - d[0], c[0] - d[0]);
    let (ady, bdy, cdy) = (a[1] - d[1], b[1] - d[1], c[1] - d[1]);
    let (adz, bdz, cdz) = (a[2] - d[2], b[2] - d[2], c[2] - d[2]);
    let (bdxcdy, cdxbdy) = (bdx * cdy, cdx * bdy);
    let (cdxady, adxcdy) = (cdx * ady, adx * cdy);
    let (adxbdy, bdxady) = (adx * bdy, bdx * ady);
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * adz.abs()
        + (cdxady.abs() + adxcdy.abs()) * bdz.abs()
        + (adxbdy.abs() + bdxady.abs()) * cdz.abs();
    let bound = O3D_BOUND * permanent;
    if det > bound || -det > bound {
        det
    } else {
        orient3d(c3(a), c3(b), c3(c), c3(d))
    }
}

/// The plane of a facet `a, b, c`, prepared for many tests: `a`, and the rounded 2x2 minors
/// of `u = b − a`, `w = c − a` (the components of `u × w`) with their permanents.
/// `side(a, b, c, d)` is exactly `−(d − a)·(u × w)`; [`Plane::certainly_inside`] evaluates
/// that in floating point from the stored minors (three differences and three products per
/// test instead of nine and nine) and answers only when its error bound certifies the sign.
#[derive(Debug, Clone, Copy)]
struct Plane {
    a: [f64; 3],
    minor: [f64; 3],
    permanent: [f64; 3],
}

impl Plane {
    fn new(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> Self {
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let pairs = [
            (u[1] * w[2], u[2] * w[1]),
            (u[2] * w[0], u[0] * w[2]),
            (u[0] * w[1], u[1] * w[0]),
        ];
        Plane {
            a: *a,
            minor: pairs.map(|(p, q)| p - q),
            permanent: pairs.map(|(p, q)| p.abs() + q.abs()),
        }
    }

    /// True only when `side(a, b, c, d) > 0` exactly (`d` strictly on the inner side);
    /// false when that is not certain from the floating-point evaluation (the caller then
    /// evaluates [`side`]).
    #[inline]
    fn certainly_inside(&self, d: &[f64; 3]) -> bool {
        let e = [d[0] - self.a[0], d[1] - self.a[1], d[2] - self.a[2]];
        let dot = e[0] * self.minor[0] + e[1] * self.minor[1] + e[2] * self.minor[2];
        let permanent = e[0].abs() * self.permanent[0]
            + e[1].abs() * self.permanent[1]
            + e[2].abs() * self.permanent[2];
        -dot > PLANE_BOUND * permanent
    }
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
    /// The plane of `v`, for the inner-side filter.
    plane: Plane,
    adj: [usize; 3],
    alive: bool,
    /// The points strictly outside, each with its height `-side(v, p) > 0` (the magnitude of
    /// the determinant, kept from the test that assigned it, so that the farthest point is
    /// chosen without evaluating the predicate again).
    outside: Vec<(usize, f64)>,
}

/// Whether `p` lies strictly outside facet `f`.
fn outside_of(pts: &[[f64; 3]], f: &Facet, p: usize) -> bool {
    !f.plane.certainly_inside(&pts[p])
        && side(&pts[f.v[0]], &pts[f.v[1]], &pts[f.v[2]], &pts[p]) < 0.0
}

/// `Some(height)` (`-side > 0`, the value of [`side`] itself) when `p` lies strictly
/// outside facet `f`.
fn height_above(pts: &[[f64; 3]], f: &Facet, p: usize) -> Option<f64> {
    height_over(pts, &f.v, &f.plane, &pts[p])
}

/// [`height_above`] for the facet with corners `v` and plane `plane` (the filter first, then
/// the exact [`side`]).
#[inline]
fn height_over(pts: &[[f64; 3]], v: &[usize; 3], plane: &Plane, q: &[f64; 3]) -> Option<f64> {
    if plane.certainly_inside(q) {
        return None;
    }
    let s = side(&pts[v[0]], &pts[v[1]], &pts[v[2]], q);
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
///
/// The working memory (facets, their outside sets, the search's lists) is kept per thread
/// between calls and reused, so that the many small hulls of a detection do not allocate it
/// anew; the result does not depend on it.
pub fn hull_3d(pts: &[[f64; 3]]) -> Option<Vec<[usize; 3]>> {
    SCRATCH.with(|scratch| match scratch.try_borrow_mut() {
        Ok(mut scratch) => hull_3d_with(pts, &mut scratch),
        // Not reachable (no hull is built inside another), but never panic on it.
        Err(_) => hull_3d_with(pts, &mut Scratch::default()),
    })
}

/// The reusable working memory of [`hull_3d`].
#[derive(Default)]
struct Scratch {
    facets: Vec<Facet>,
    /// Emptied outside sets of dead facets, with their capacity, for new facets.
    pool: Vec<Vec<(usize, f64)>>,
    pending: Vec<usize>,
    visible: Vec<usize>,
    stack: Vec<usize>,
    mark: Vec<u32>,
    horizon: Vec<(usize, usize, usize)>,
    orphans: Vec<usize>,
    created: Vec<usize>,
    /// The new facets of a step with their corners and planes, for the orphans' tests.
    cone: Vec<(usize, [usize; 3], Plane)>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

fn hull_3d_with(pts: &[[f64; 3]], scratch: &mut Scratch) -> Option<Vec<[usize; 3]>> {
    let Scratch {
        facets,
        pool,
        pending,
        visible,
        stack,
        mark,
        horizon,
        orphans,
        created,
        cone,
    } = scratch;
    for f in facets.drain(..) {
        let mut out = f.outside;
        if out.capacity() > 0 {
            out.clear();
            pool.push(out);
        }
    }
    pending.clear();
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
    // The point of largest |side| off the plane (i0, i1, i2), the lowest index among equals;
    // each point's side is evaluated once.
    let (i3, s3) = (0..n)
        .map(|i| (i, side(&pts[i0], &pts[i1], &pts[i2], &pts[i])))
        .filter(|&(_, s)| s != 0.0)
        .max_by(|&(a, sa), &(b, sb)| sa.abs().total_cmp(&sb.abs()).then(b.cmp(&a)))?;
    // Orient the base so that i3 is inside (side > 0 for every facet).
    let (a, b, c, d) = if s3 > 0.0 {
        (i0, i1, i2, i3)
    } else {
        (i0, i2, i1, i3)
    };
    // Facets: 0 = abc, 1 = adb... each listed CCW from outside; adjacency by shared edges.
    let tris = [[a, b, c], [a, d, b], [b, d, c], [c, d, a]];
    facets.extend(tris.iter().map(|&v| Facet {
        v,
        plane: Plane::new(&pts[v[0]], &pts[v[1]], &pts[v[2]]),
        adj: [usize::MAX; 3],
        alive: true,
        outside: pool.pop().unwrap_or_default(),
    }));
    link_all(facets, &[0, 1, 2, 3]);
    for p in 0..n {
        if p == a || p == b || p == c || p == d {
            continue;
        }
        if let Some((f, h)) = (0..4).find_map(|f| height_above(pts, &facets[f], p).map(|h| (f, h)))
        {
            facets[f].outside.push((p, h));
        }
    }
    pending.extend((0..4).rev());
    mark.clear();
    mark.resize(4, 0);
    let mut round = 0u32;
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
                if mark[g] != round && outside_of(pts, &facets[g], p) {
                    mark[g] = round;
                    stack.push(g);
                }
            }
        }
        // Horizon edges (u, v) of visible facets whose neighbour is not visible.
        horizon.clear();
        orphans.clear();
        for &f in visible.iter() {
            for k in 0..3 {
                let g = facets[f].adj[k];
                if mark[g] != round {
                    horizon.push((facets[f].v[k], facets[f].v[(k + 1) % 3], g));
                }
            }
            let mut out = std::mem::take(&mut facets[f].outside);
            orphans.extend(out.iter().map(|&(q, _)| q).filter(|&q| q != p));
            if out.capacity() > 0 {
                out.clear();
                pool.push(out);
            }
            facets[f].alive = false;
        }
        created.clear();
        for &(u, v, g) in horizon.iter() {
            let id = facets.len();
            facets.push(Facet {
                v: [u, v, p],
                plane: Plane::new(&pts[u], &pts[v], &pts[p]),
                adj: [g, usize::MAX, usize::MAX],
                alive: true,
                outside: pool.pop().unwrap_or_default(),
            });
            // The kept neighbour's edge (v, u) now borders the new facet.
            let gk = (0..3).find(|&k| facets[g].v[k] == v && facets[g].v[(k + 1) % 3] == u)?;
            facets[g].adj[gk] = id;
            created.push(id);
        }
        // New facets share the edges (v, p) / (p, u) with each other.
        for &fx in created.iter() {
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
        // Each orphan joins the first new facet (in creation order) it is strictly outside
        // of; the new facets' planes and corners are read from one contiguous list.
        cone.clear();
        cone.extend(created.iter().map(|&f| (f, facets[f].v, facets[f].plane)));
        for &q in orphans.iter() {
            let pq = &pts[q];
            if let Some((f, h)) = cone
                .iter()
                .find_map(|(f, v, plane)| height_over(pts, v, plane, pq).map(|h| (*f, h)))
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

    /// Inputs for the predicate tests: random points in the unit cube, and near-coplanar
    /// and exactly coplanar ones (`d = a + s·u + t·w` with `s, t` rounded, and the same
    /// plus a few units in the last place).
    fn predicate_cases() -> Vec<[[f64; 3]; 4]> {
        let mut rng = Rng(2024);
        let mut cases = Vec::new();
        for k in 0..4000 {
            let mut p = [[0.0; 3]; 4];
            for q in &mut p {
                *q = [rng.next(), rng.next(), rng.next()];
            }
            if k % 2 == 1 {
                let (s, t) = (rng.next() * 2.0 - 0.5, rng.next() * 2.0 - 0.5);
                let [a, b, c, _] = p;
                p[3] = std::array::from_fn(|j| a[j] + s * (b[j] - a[j]) + t * (c[j] - a[j]));
                if k % 4 == 3 {
                    let j = k % 3;
                    let ulps = (k / 4 % 5) as i64 - 2;
                    p[3][j] = f64::from_bits((p[3][j].to_bits() as i64 + ulps) as u64);
                }
            }
            cases.push(p);
        }
        // Exactly coplanar: small integers and a translated copy far from the origin.
        for k in 0..200 {
            let i = |m: usize| ((k * 7 + m * 13) % 11) as f64;
            let (s, t) = ((k % 5) as f64 - 2.0, (k % 3) as f64);
            let a = [i(0), i(1), i(2)];
            let b = [i(3), i(4), i(5)];
            let c = [i(6), i(7), i(8)];
            let d: [f64; 3] = std::array::from_fn(|j| a[j] + s * (b[j] - a[j]) + t * (c[j] - a[j]));
            cases.push([a, b, c, d]);
            let shift = |p: [f64; 3]| p.map(|x| x + 1024.0);
            cases.push([shift(a), shift(b), shift(c), shift(d)]);
        }
        cases
    }

    #[test]
    fn side_returns_the_bits_of_robust_orient3d() {
        let cases = predicate_cases();
        let mut zeros = 0;
        for [a, b, c, d] in &cases {
            let ours = side(a, b, c, d);
            let theirs = orient3d(c3(a), c3(b), c3(c), c3(d));
            assert_eq!(ours.to_bits(), theirs.to_bits(), "{a:?} {b:?} {c:?} {d:?}");
            zeros += usize::from(ours == 0.0);
        }
        // The exactly coplanar cases (at least) reached the adaptive stage and gave 0.
        assert!(zeros >= 400, "only {zeros} coplanar cases");
    }

    /// Exact sign of `side` for integer coordinates, in `i128` (independent of robust).
    fn side_sign_exact(p: &[[i64; 3]; 4]) -> i128 {
        let r = |i: usize| -> [i128; 3] {
            std::array::from_fn(|j| i128::from(p[i][j]) - i128::from(p[3][j]))
        };
        let (a, b, c) = (r(0), r(1), r(2));
        let det = a[2] * (b[0] * c[1] - c[0] * b[1])
            + b[2] * (c[0] * a[1] - a[0] * c[1])
            + c[2] * (a[0] * b[1] - b[0] * a[1]);
        det.signum()
    }

    #[test]
    fn plane_filter_claims_inside_only_when_side_is_positive() {
        let mut decided = 0;
        let mut inside = 0;
        for [a, b, c, d] in &predicate_cases() {
            let s = side(a, b, c, d);
            inside += usize::from(s > 0.0);
            if Plane::new(a, b, c).certainly_inside(d) {
                decided += 1;
                assert!(s > 0.0, "{a:?} {b:?} {c:?} {d:?}: side {s}");
            }
        }
        // The filter decides the clearly inside random cases (about half of the random half).
        assert!(decided >= 800 && decided <= inside, "{decided} of {inside}");
        // Large integer coordinates (products round), near-coplanar by one unit: against an
        // exact determinant in i128.
        let mut rng = Rng(5);
        let mut checked = 0;
        for k in 0..3000 {
            let big = |rng: &mut Rng| ((rng.next() - 0.5) * (1u64 << 40) as f64) as i64;
            let mut p = [[0i64; 3]; 4];
            for q in p.iter_mut().take(3) {
                *q = [big(&mut rng), big(&mut rng), big(&mut rng)];
            }
            let (s, t) = ((k % 7) as i64 - 3, (k % 5) as i64 - 2);
            p[3] = std::array::from_fn(|j| {
                p[0][j] + s * (p[1][j] - p[0][j]) + t * (p[2][j] - p[0][j]) + (k % 3) as i64 - 1
            });
            let f = p.map(|q| q.map(|x| x as f64));
            let exact = side_sign_exact(&p);
            let s = side(&f[0], &f[1], &f[2], &f[3]);
            assert_eq!(i128::from(s > 0.0) - i128::from(s < 0.0), exact, "{p:?}");
            if Plane::new(&f[0], &f[1], &f[2]).certainly_inside(&f[3]) {
                assert_eq!(exact, 1, "{p:?}");
                checked += 1;
            }
        }
        assert!(checked > 0);
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
