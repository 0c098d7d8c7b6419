//! Convex cells clipped by half-spaces: a polygon in 2D, a polyhedron in 3D.
//!
//! Both live in the frame of particle `i` scaled by `1/r` (so `S_i` is the unit sphere) and
//! start as the box `[-1, 1]^D`. A clip keeps the half-space `n·x <= offset` with a unit normal
//! `n`, so every tolerance below is a distance in units of `r`.

/// A vertex closer than this to a clipping plane (in units of `r`) is treated as lying on it:
/// a cut that would remove less than `PLANE_EPS` of depth is ignored. Ignoring it can only make
/// the cell larger by about `PLANE_EPS`, far inside the tie band of [`crate::TIE_TOLERANCE`].
pub(crate) const PLANE_EPS: f64 = 1e-12;

/// Cap points of one clip closer than this to each other are merged into one vertex.
const MERGE_EPS2: f64 = 1e-24;

/// Cap points whose pseudo-angles around the cap centroid differ by less than this make the
/// clip near-degenerate (their order may be wrong in floating point).
const ANGLE_EPS: f64 = 1e-12;

/// Operations the cell-clipping driver needs from a cell.
pub(crate) trait ConvexCell<const D: usize> {
    /// Resets the cell to the box `[-1, 1]^D`.
    fn reset_box(&mut self);
    /// Intersects the cell with `n·x <= offset` (`n` a unit vector, `offset > 0`).
    fn clip(&mut self, n: &[f64; D], offset: f64);
    /// Largest squared distance of a vertex from the origin.
    fn max_norm2(&self) -> f64;
    /// The cell's vertices.
    fn vertices(&self) -> &[[f64; D]];
    /// Whether a clip since the last reset was near-degenerate: it cut the cell while a vertex
    /// lay within [`PLANE_EPS`] of the plane, or (3D) it merged cap points or met two cap
    /// points at nearly the same angle. The error bound of the crate docs assumes no such clip;
    /// a flagged particle is decided by the exact predicate.
    fn degenerate(&self) -> bool;
}

fn dot<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    let mut s = 0.0;
    for k in 0..D {
        s += a[k] * b[k];
    }
    s
}

fn norm2<const D: usize>(a: &[f64; D]) -> f64 {
    dot(a, a)
}

/// Point on the segment `a b` where the signed distance `s` crosses zero (`sa < 0 < sb`).
fn crossing<const D: usize>(a: &[f64; D], b: &[f64; D], sa: f64, sb: f64) -> [f64; D] {
    let t = sa / (sa - sb);
    std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
}

/// A convex polygon, vertices in counter-clockwise order.
#[derive(Debug, Default, Clone)]
pub(crate) struct Polygon {
    verts: Vec<[f64; 2]>,
    scratch: Vec<[f64; 2]>,
    degenerate: bool,
}

impl ConvexCell<2> for Polygon {
    fn reset_box(&mut self) {
        self.verts.clear();
        self.verts
            .extend_from_slice(&[[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]);
        self.degenerate = false;
    }

    fn clip(&mut self, n: &[f64; 2], offset: f64) {
        // Sutherland–Hodgman against one half-plane; on-plane vertices are kept.
        let signed = |v: &[f64; 2]| {
            let s = dot(n, v) - offset;
            if s.abs() <= PLANE_EPS {
                0.0
            } else {
                s
            }
        };
        let mut out = false;
        let mut near = false;
        for v in &self.verts {
            let s = dot(n, v) - offset;
            out |= s > PLANE_EPS;
            near |= s.abs() <= PLANE_EPS;
        }
        if !out {
            return;
        }
        self.degenerate |= near;
        self.scratch.clear();
        let m = self.verts.len();
        for k in 0..m {
            let a = self.verts[k];
            let b = self.verts[(k + 1) % m];
            let (sa, sb) = (signed(&a), signed(&b));
            if sa <= 0.0 {
                self.scratch.push(a);
            }
            if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
                self.scratch.push(crossing(&a, &b, sa, sb));
            }
        }
        std::mem::swap(&mut self.verts, &mut self.scratch);
    }

    fn max_norm2(&self) -> f64 {
        self.verts.iter().map(norm2).fold(0.0, f64::max)
    }

    fn vertices(&self) -> &[[f64; 2]] {
        &self.verts
    }

    fn degenerate(&self) -> bool {
        self.degenerate
    }
}

/// A convex polyhedron stored as vertices and edges (faces are not needed: a plane meets the
/// polyhedron's surface along its edges, and the new face is the convex polygon of the
/// crossing points).
#[derive(Debug, Default, Clone)]
pub(crate) struct Polyhedron {
    verts: Vec<[f64; 3]>,
    edges: Vec<[u32; 2]>,
    // Scratch buffers reused across clips.
    side: Vec<f64>,
    remap: Vec<u32>,
    new_verts: Vec<[f64; 3]>,
    new_edges: Vec<[u32; 2]>,
    cap: Vec<u32>,
    cap_angle: Vec<(f64, u32)>,
    degenerate: bool,
}

const GONE: u32 = u32::MAX;

impl Polyhedron {
    /// Adds a cap point, merging it with an existing cap point closer than `MERGE_EPS2`.
    fn push_cap_point(&mut self, x: [f64; 3]) -> u32 {
        for &c in &self.cap {
            let y = self.new_verts[c as usize];
            if norm2(&[x[0] - y[0], x[1] - y[1], x[2] - y[2]]) <= MERGE_EPS2 {
                self.degenerate = true;
                return c;
            }
        }
        let id = self.new_verts.len() as u32;
        self.new_verts.push(x);
        self.cap.push(id);
        id
    }

    /// Joins the cap points into the boundary ring of the new face, ordered by angle around
    /// their centroid in the clipping plane.
    fn close_cap(&mut self, n: &[f64; 3]) {
        let k = self.cap.len();
        if k < 2 {
            return;
        }
        if k == 2 {
            self.new_edges.push([self.cap[0], self.cap[1]]);
            return;
        }
        // Orthonormal basis (u, w) of the plane.
        let helper = if n[0].abs() < 0.6 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let u = normalised(cross(n, &helper));
        let w = cross(n, &u);
        let mut c = [0.0; 3];
        for &id in &self.cap {
            let x = self.new_verts[id as usize];
            for a in 0..3 {
                c[a] += x[a] / k as f64;
            }
        }
        self.cap_angle.clear();
        for &id in &self.cap {
            let x = self.new_verts[id as usize];
            let d = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
            self.cap_angle
                .push((pseudo_angle(dot(&d, &u), dot(&d, &w)), id));
        }
        self.cap_angle
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for j in 0..k {
            if self.cap_angle[(j + 1) % k].0 - self.cap_angle[j].0 < ANGLE_EPS && j + 1 < k {
                self.degenerate = true;
            }
            let a = self.cap_angle[j].1;
            let b = self.cap_angle[(j + 1) % k].1;
            self.new_edges.push([a, b]);
        }
    }
}

/// A monotone stand-in for `atan2(y, x)` with values in `[0, 4)`: orders directions by angle
/// at a fraction of the cost (the "diamond angle").
fn pseudo_angle(x: f64, y: f64) -> f64 {
    let l1 = x.abs() + y.abs();
    if l1 == 0.0 {
        return 0.0;
    }
    let t = x / l1;
    if y >= 0.0 {
        1.0 - t
    } else {
        3.0 + t
    }
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalised(a: [f64; 3]) -> [f64; 3] {
    let l = norm2(&a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

impl ConvexCell<3> for Polyhedron {
    fn reset_box(&mut self) {
        self.verts.clear();
        for k in 0..8u32 {
            let c = |bit: u32| if k & bit != 0 { 1.0 } else { -1.0 };
            self.verts.push([c(1), c(2), c(4)]);
        }
        self.edges.clear();
        for a in 0..8u32 {
            for bit in [1u32, 2, 4] {
                if a & bit == 0 {
                    self.edges.push([a, a | bit]);
                }
            }
        }
        self.degenerate = false;
    }

    fn clip(&mut self, n: &[f64; 3], offset: f64) {
        self.side.clear();
        let mut any_out = false;
        let mut near = false;
        for v in &self.verts {
            let s = dot(n, v) - offset;
            let s = if s.abs() <= PLANE_EPS {
                near = true;
                0.0
            } else {
                s
            };
            any_out |= s > 0.0;
            self.side.push(s);
        }
        if !any_out {
            return;
        }
        self.degenerate |= near;
        self.new_verts.clear();
        self.new_edges.clear();
        self.cap.clear();
        self.remap.clear();
        for (v, &s) in self.verts.iter().zip(&self.side) {
            if s <= 0.0 {
                let id = self.new_verts.len() as u32;
                self.new_verts.push(*v);
                self.remap.push(id);
                if s == 0.0 {
                    // A vertex of the polyhedron on the plane is a vertex of the new face.
                    self.cap.push(id);
                }
            } else {
                self.remap.push(GONE);
            }
        }
        for e in 0..self.edges.len() {
            let [a, b] = self.edges[e];
            let (sa, sb) = (self.side[a as usize], self.side[b as usize]);
            match (sa <= 0.0, sb <= 0.0) {
                (true, true) => {
                    // An edge lying in the plane is an edge of the new face: `close_cap`
                    // recreates it, so it is dropped here rather than duplicated.
                    if !(sa == 0.0 && sb == 0.0) {
                        self.new_edges
                            .push([self.remap[a as usize], self.remap[b as usize]]);
                    }
                }
                (false, false) => {}
                (a_in, _) => {
                    let (i, o, si, so) = if a_in { (a, b, sa, sb) } else { (b, a, sb, sa) };
                    if si < 0.0 {
                        let x = crossing(&self.verts[i as usize], &self.verts[o as usize], si, so);
                        let id = self.push_cap_point(x);
                        self.new_edges.push([self.remap[i as usize], id]);
                    }
                }
            }
        }
        self.close_cap(n);
        std::mem::swap(&mut self.verts, &mut self.new_verts);
        std::mem::swap(&mut self.edges, &mut self.new_edges);
    }

    fn max_norm2(&self) -> f64 {
        self.verts.iter().map(norm2).fold(0.0, f64::max)
    }

    fn vertices(&self) -> &[[f64; 3]] {
        &self.verts
    }

    fn degenerate(&self) -> bool {
        self.degenerate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pseudo_angle_is_monotone_in_the_angle() {
        let mut last = -1.0;
        for k in 0..720 {
            let a = k as f64 * std::f64::consts::PI / 360.0;
            let p = pseudo_angle(a.cos(), a.sin());
            assert!(p > last, "{k}");
            assert!((0.0..4.0).contains(&p));
            last = p;
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn polygon_clip_halves_the_box() {
        let mut p = Polygon::default();
        p.reset_box();
        p.clip(&[1.0, 0.0], 0.5);
        assert!(close(p.max_norm2(), 2.0)); // (-1, ±1) survive
        p.clip(&[-1.0, 0.0], 0.5);
        assert!(close(p.max_norm2(), 1.25)); // (±0.5, ±1)
        assert_eq!(p.verts.len(), 4);
    }

    #[test]
    fn polygon_clip_through_vertices_keeps_them_once() {
        let mut p = Polygon::default();
        p.reset_box();
        let s = std::f64::consts::FRAC_1_SQRT_2;
        // The diagonal x + y <= 0 passes through (1, -1) and (-1, 1).
        p.clip(&[s, s], 0.0);
        assert_eq!(p.verts.len(), 3);
        assert!(close(p.max_norm2(), 2.0));
    }

    #[test]
    fn cube_clipped_to_smaller_cube() {
        let mut c = Polyhedron::default();
        c.reset_box();
        for axis in 0..3 {
            for sign in [1.0, -1.0] {
                let mut n = [0.0; 3];
                n[axis] = sign;
                c.clip(&n, 0.5);
            }
        }
        assert_eq!(c.verts.len(), 8);
        assert_eq!(c.edges.len(), 12);
        assert!(close(c.max_norm2(), 0.75));
    }

    #[test]
    fn corner_cut_makes_a_triangle_face() {
        let mut c = Polyhedron::default();
        c.reset_box();
        let s = 1.0 / 3f64.sqrt();
        // Cut the corner (1, 1, 1) off at x + y + z <= 2.
        c.clip(&[s, s, s], 2.0 * s);
        assert_eq!(c.verts.len(), 10);
        assert_eq!(c.edges.len(), 15);
        assert!(close(c.max_norm2(), 3.0)); // the opposite corners remain
    }

    #[test]
    fn plane_through_four_vertices_reuses_them() {
        let mut c = Polyhedron::default();
        c.reset_box();
        let s = std::f64::consts::FRAC_1_SQRT_2;
        // x + y <= 0 contains the edge from (1,-1,*) ... passes through 4 vertices.
        c.clip(&[s, s, 0.0], 0.0);
        assert_eq!(c.verts.len(), 6); // a triangular prism
        assert_eq!(c.edges.len(), 9);
        assert!(close(c.max_norm2(), 3.0));
    }

    #[test]
    fn repeated_clipping_stays_consistent() {
        // Clip by many tangent planes of the unit sphere: the cell converges to it and every
        // vertex stays within the circumscribed bound 1/cos(angular spacing).
        let mut c = Polyhedron::default();
        c.reset_box();
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let m = 200;
        for k in 0..m {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / m as f64;
            let rho = (1.0 - z * z).sqrt();
            let n = [
                rho * (golden * k as f64).cos(),
                rho * (golden * k as f64).sin(),
                z,
            ];
            c.clip(&n, 1.0);
        }
        let r = c.max_norm2().sqrt();
        assert!(r > 1.0 && r < 1.2, "{r}");
        // Euler: every vertex of a simple polyhedron has degree >= 3, so E >= 3V/2.
        assert!(2 * c.edges.len() >= 3 * c.verts.len());
    }
}
