//! The mesh elements of the unit sphere `S_i` (frame `T_i(x) = (x − p_i)/r`) and their slabs.
//!
//! An element is a patch of `S_i`: an arc between two unit vectors in 2D, a spherical triangle
//! (bounded by great-circle arcs) between three unit vectors in 3D. Its *slab* is a convex
//! polytope enclosing the patch, given by its vertices (JCP 2020 Sec. 3.2, Figs. 3 and 5).
//! Why the slab encloses the patch is argued at each `slab` below and tested.

use boundary_core::Point;

/// A patch of the unit sphere with its slab and its refinement.
pub(crate) trait Element<const D: usize>: Copy + std::fmt::Debug {
    /// The slab's vertices.
    type Slab: AsRef<[Point<D>]> + Copy + std::fmt::Debug + Send + Sync;

    /// The roots of the refinement trees, at depth 0: the coarse inscribed mesh (triangle
    /// sides, tetrahedron faces).
    fn roots() -> Vec<Self>;

    /// The first tree level, where Algorithm 3 starts: the children of the roots, at depth 1.
    fn first_level() -> Vec<Self> {
        let mut level = Vec::new();
        for root in Self::roots() {
            root.children(&mut level);
        }
        level
    }

    /// The depth of the element in the refinement tree (the roots are depth 0).
    fn depth(&self) -> u32;

    /// The vertices of the convex slab enclosing the element's patch.
    fn slab(&self) -> Self::Slab;

    /// Children at `depth + 1`, which together cover the element's patch exactly.
    fn children(&self, out: &mut Vec<Self>);

    /// A ball `(centre, radius)` holding every slab vertex of this element **and of all its
    /// descendants**: a unit ball whose centre is farther than `1 + radius` from `centre` has
    /// every such vertex outside, so it can be dropped for the whole subtree without changing
    /// any label. The radius is infinite where no useful bound exists.
    fn reach(&self) -> (Point<D>, f64);
}

/// The radius of the ball about the unit vector `g` holding every point `t·u` with `u` a unit
/// vector within angle `θ` of `g` (`cos θ = cos_theta`) and `1 <= t <= t_max`:
/// `|t u − g|² = t² − 2t cos θ + 1` is largest at `t = t_max` and the widest angle. Padded by a
/// relative `1e-9` against rounding.
fn cone_reach(cos_theta: f64, t_max: f64) -> f64 {
    let r2 = t_max * t_max - 2.0 * t_max * cos_theta + 1.0;
    r2.max(0.0).sqrt() * (1.0 + 1e-9) + 1e-12
}

/// An arc of the unit circle from `a` to `b` (the shorter way; arcs are at most 120°).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Arc {
    pub a: Point<2>,
    pub b: Point<2>,
    pub depth: u32,
}

impl Element<2> for Arc {
    type Slab = [Point<2>; 4];

    /// The sides of an equilateral triangle inscribed in the circle (vertices at 90°, 210°,
    /// 330°): three arcs of 120°.
    fn roots() -> Vec<Self> {
        let v: Vec<Point<2>> = [90.0f64, 210.0, 330.0]
            .iter()
            .map(|deg| {
                let t = deg.to_radians();
                Point::<2>::new(t.cos(), t.sin())
            })
            .collect();
        (0..3)
            .map(|k| Arc {
                a: v[k],
                b: v[(k + 1) % 3],
                depth: 0,
            })
            .collect()
    }

    fn depth(&self) -> u32 {
        self.depth
    }

    /// The rectangle with one side on the chord `L = ab` and the opposite side on the tangent
    /// line at `m̂ = (a + b)/|a + b|`, the projection of the chord's midpoint (Fig. 3).
    ///
    /// Encloses the arc: in the frame with `m̂` as second axis the arc is
    /// `{(sin t, cos t) : |t| <= φ}` (half-angle `φ <= 60°`), so `|x| <= sin φ` (the chord's
    /// half-length) and `cos φ <= y <= 1` (between the chord and the tangent line).
    fn slab(&self) -> [Point<2>; 4] {
        let m = (self.a + self.b).normalize();
        let lift_a = 1.0 - self.a.dot(&m);
        let lift_b = 1.0 - self.b.dot(&m);
        [self.a, self.b, self.a + m * lift_a, self.b + m * lift_b]
    }

    /// Split at the midpoint projected onto the circle.
    fn children(&self, out: &mut Vec<Self>) {
        let m = (self.a + self.b).normalize();
        let depth = self.depth + 1;
        out.push(Arc {
            a: self.a,
            b: m,
            depth,
        });
        out.push(Arc {
            a: m,
            b: self.b,
            depth,
        });
    }

    /// Every descendant vertex lies within the arc's cone (half-angle `φ` about `m̂`): chord
    /// vertices on the circle, tangent corners `m̂_c ± sin φ_c t_c` of norm `√(1 + sin²φ_c)` at
    /// angle `atan(sin φ_c) <= φ_c` from their own `m̂_c`, which is within `φ − φ_c` of `m̂`.
    /// So `t <= √(1 + sin²φ)` and the angle is at most `φ`.
    fn reach(&self) -> (Point<2>, f64) {
        let m = (self.a + self.b).normalize();
        let cos_phi = self.a.dot(&m).min(self.b.dot(&m));
        let sin2 = (1.0 - cos_phi * cos_phi).max(0.0);
        (m, cone_reach(cos_phi, (1.0 + sin2).sqrt()))
    }
}

/// A spherical triangle of the unit sphere with unit vertices `a`, `b`, `c`: the radial
/// projection of the flat triangle `abc`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Triangle {
    pub v: [Point<3>; 3],
    pub depth: u32,
}

impl Element<3> for Triangle {
    type Slab = [Point<3>; 6];

    /// The faces of the regular tetrahedron with vertices `(±1, ±1, ±1)/√3` (even number of
    /// minus signs), inscribed in the sphere.
    fn roots() -> Vec<Self> {
        let s = 1.0 / 3f64.sqrt();
        let t = [
            Point::<3>::new(s, s, s),
            Point::<3>::new(s, -s, -s),
            Point::<3>::new(-s, s, -s),
            Point::<3>::new(-s, -s, s),
        ];
        [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]
            .iter()
            .map(|f| Triangle {
                v: [t[f[0]], t[f[1]], t[f[2]]],
                depth: 0,
            })
            .collect()
    }

    fn depth(&self) -> u32 {
        self.depth
    }

    /// The frustum between the flat triangle `L = abc` and its perspective projection from the
    /// origin onto the plane `P` tangent to the sphere at `b̂ = b/|b|`, `b` the barycentre:
    /// `a ↦ a/(a·b̂)` (Fig. 5).
    ///
    /// Encloses the patch: a patch point is `s = x/|x|` for some `x` in `L`. Since the vertices
    /// of `L` are on the sphere, `|x| <= 1`, so `s` lies on the ray from the origin through `x`
    /// beyond `x`; and `s·b̂ <= |s| = 1`, so `s` lies before the ray meets `P` (at
    /// `x/(x·b̂)`, with `x·b̂ > 0` as every vertex is within 90° of `b̂`). The ray's segment
    /// between `L` and `P` is in the convex hull of `L` and its projection, which is the slab.
    fn slab(&self) -> [Point<3>; 6] {
        let [a, b, c] = self.v;
        let g = (a + b + c).normalize();
        [a, b, c, a / a.dot(&g), b / b.dot(&g), c / c.dot(&g)]
    }

    /// Midpoint subdivision into four, the new vertices projected onto the sphere. The
    /// projected midpoint of `ab` lies on the great-circle arc `ab`, so the four children's
    /// patches tile the parent's patch exactly (hanging nodes between neighbours do not matter:
    /// only the patches are used).
    fn children(&self, out: &mut Vec<Self>) {
        let [a, b, c] = self.v;
        let ab = (a + b).normalize();
        let bc = (b + c).normalize();
        let ca = (c + a).normalize();
        let depth = self.depth + 1;
        for v in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
            out.push(Triangle { v, depth });
        }
    }

    /// Every descendant's sphere vertices lie in this patch, within angle `θ` of `ĝ` (the
    /// largest vertex angle: a convex spherical triangle's farthest point from an inner point
    /// is a vertex). A descendant's tangent vertex is `u/(u·ĝ_c)` with `u` and `ĝ_c` in its
    /// patch, so its norm is at most `1/cos δ`, `δ` the patch's diameter (the largest angle
    /// between two vertices). With `δ` near 90° there is no useful bound.
    fn reach(&self) -> (Point<3>, f64) {
        let [a, b, c] = self.v;
        let g = (a + b + c).normalize();
        let cos_theta = a.dot(&g).min(b.dot(&g)).min(c.dot(&g));
        let cos_delta = a.dot(&b).min(b.dot(&c)).min(c.dot(&a));
        if cos_delta < 0.05 {
            return (g, f64::INFINITY);
        }
        (g, cone_reach(cos_theta, 1.0 / cos_delta))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The point of the convex polygon/polytope `slab` nearest to `x` is within `tol` of `x`:
    /// checked as membership in the convex hull by the separating-direction test over many
    /// sampled directions (enough for these small vertex sets).
    fn in_hull<const D: usize>(x: &Point<D>, slab: &[Point<D>], tol: f64) -> bool {
        // x is in the hull iff for every direction u, u·x <= max_v u·v.
        let dirs = 2000;
        for k in 0..dirs {
            let u = direction::<D>(k, dirs);
            let hx = u.dot(x);
            let hv = slab
                .iter()
                .map(|v| u.dot(v))
                .fold(f64::NEG_INFINITY, f64::max);
            if hx > hv + tol {
                return false;
            }
        }
        true
    }

    fn direction<const D: usize>(k: usize, n: usize) -> Point<D> {
        // Fibonacci sphere in 3D, uniform angles in 2D.
        let t = (k as f64 + 0.5) / n as f64;
        if D == 2 {
            let a = 2.0 * std::f64::consts::PI * t;
            Point::<D>::from_fn(|i, _| if i == 0 { a.cos() } else { a.sin() })
        } else {
            let z = 1.0 - 2.0 * t;
            let rho = (1.0 - z * z).sqrt();
            let phi = k as f64 * 2.399_963_229_728_653;
            Point::<D>::from_fn(|i, _| match i {
                0 => rho * phi.cos(),
                1 => rho * phi.sin(),
                _ => z,
            })
        }
    }

    #[test]
    fn arcs_lie_in_their_rectangles_and_children_tile_the_parent() {
        let mut level = Arc::roots();
        for _depth in 1..=5 {
            let mut next = Vec::new();
            for arc in &level {
                let slab = arc.slab();
                // Sample the arc by angle between a and b.
                let (ta, tb) = (arc.a.y.atan2(arc.a.x), arc.b.y.atan2(arc.b.x));
                let mut span = tb - ta;
                if span < 0.0 {
                    span += 2.0 * std::f64::consts::PI;
                }
                assert!(span > 0.0 && span <= 2.0 * std::f64::consts::PI / 3.0 + 1e-12);
                for s in 0..=50 {
                    let t = ta + span * s as f64 / 50.0;
                    let x = Point::<2>::new(t.cos(), t.sin());
                    assert!(in_hull(&x, &slab, 1e-12), "{arc:?} misses angle {t}");
                }
                arc.children(&mut next);
            }
            // Children cover the circle: total angle stays 2π.
            let total: f64 = next
                .iter()
                .map(|c| c.a.dot(&c.b).clamp(-1.0, 1.0).acos())
                .sum();
            assert!((total - 2.0 * std::f64::consts::PI).abs() < 1e-9);
            level = next;
        }
    }

    #[test]
    fn spherical_triangles_lie_in_their_frustums() {
        let mut level = Triangle::roots();
        for _depth in 1..=3 {
            let mut next = Vec::new();
            for tri in &level {
                let slab = tri.slab();
                let [a, b, c] = tri.v;
                // Barycentric samples of the flat triangle, projected onto the sphere.
                for i in 0..=8 {
                    for j in 0..=(8 - i) {
                        let (u, v) = (i as f64 / 8.0, j as f64 / 8.0);
                        let x = (a * u + b * v + c * (1.0 - u - v)).normalize();
                        assert!(in_hull(&x, &slab, 1e-12), "{tri:?} misses {x:?}");
                    }
                }
                tri.children(&mut next);
            }
            level = next;
        }
        // The patches tile the sphere: their solid angles sum to 4π (Van Oosterom–Strackee).
        let total: f64 = level
            .iter()
            .map(|t| {
                let [a, b, c] = t.v;
                let num = a.dot(&b.cross(&c)).abs();
                let den = 1.0 + a.dot(&b) + b.dot(&c) + c.dot(&a);
                2.0 * num.atan2(den)
            })
            .sum();
        assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-9, "{total}");
    }

    /// Every slab vertex of an element and of its descendants (to `levels` more levels) lies in
    /// the element's reach ball.
    fn check_reach<const D: usize, E: Element<D>>(e: &E, levels: u32) {
        let (centre, radius) = e.reach();
        let mut todo = vec![*e];
        for _ in 0..=levels {
            let mut next = Vec::new();
            for d in &todo {
                for v in d.slab().as_ref() {
                    assert!((v - centre).norm() <= radius, "{v:?} beyond {radius}");
                }
                d.children(&mut next);
            }
            todo = next;
        }
    }

    #[test]
    fn reach_balls_hold_every_descendant_vertex() {
        let mut arcs = Vec::new();
        for root in Arc::roots() {
            root.children(&mut arcs);
        }
        for arc in &arcs {
            check_reach(arc, 6);
            assert!(arc.reach().1 < 1.0);
        }
        let tris = Triangle::first_level();
        for tri in &tris {
            check_reach(tri, 4);
        }
        let mut kids = Vec::new();
        tris[0].children(&mut kids);
        assert!(kids.iter().all(|k| k.reach().1 < tris[0].reach().1));
    }

    #[test]
    fn slabs_shrink_with_depth() {
        let width = |slab: &[Point<3>]| {
            let mut w: f64 = 0.0;
            for p in slab {
                for q in slab {
                    w = w.max((p - q).norm());
                }
            }
            w
        };
        let mut tri = Triangle::roots()[0];
        let mut previous = f64::INFINITY;
        for _ in 0..8 {
            let w = width(&tri.slab());
            assert!(w < previous);
            previous = w;
            let mut kids = Vec::new();
            tri.children(&mut kids);
            tri = kids[3];
        }
        assert!(previous < 0.05, "{previous}");
    }
}
