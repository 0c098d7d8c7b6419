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

/// The clipping operations of a cell (all the float cell driver needs).
pub(crate) trait Clipper<const D: usize> {
    /// Resets the cell to the box `[-1, 1]^D`.
    fn reset_box(&mut self);
    /// Intersects the cell with `n·x <= offset` (`n` a unit vector, `offset > 0`).
    fn clip(&mut self, n: &[f64; D], offset: f64);
    /// Largest squared distance of a vertex from the origin.
    fn max_norm2(&self) -> f64;
    /// A vertex farthest from the origin (the tracker's witness direction).
    fn farthest(&self) -> [f64; D];
    /// Whether a clip since the last reset was near-degenerate: it cut the cell while a vertex
    /// lay within [`PLANE_EPS`] of the plane, or (3D) it merged cap points or met two cap
    /// points at nearly the same angle. The error bound of the crate docs assumes no such clip;
    /// a flagged particle is decided by the exact predicate.
    fn degenerate(&self) -> bool;
    /// Whether [`Clipper::clip`] by `n·x <= offset` would cut the cell while a vertex lies
    /// within [`PLANE_EPS`] of the plane (the first kind of near-degenerate clip), computed
    /// with the same expressions as `clip`, without changing the cell.
    fn touches(&self, n: &[f64; D], offset: f64) -> bool;
}

/// Whether signed distances cut (one beyond [`PLANE_EPS`]) while one lies within it.
fn cuts_while_touching(sides: impl Iterator<Item = f64>) -> bool {
    let (mut out, mut near) = (false, false);
    for s in sides {
        out |= s > PLANE_EPS;
        near |= s.abs() <= PLANE_EPS;
    }
    out && near
}

/// A cell the certificates can use: clipping, and its vertices.
pub(crate) trait ConvexCell<const D: usize>: Clipper<D> {
    /// A faster cell for a first pass (`exact`'s float path at a uniform radius): it computes
    /// the same vertices for every clip sequence it does not flag, and flags at least every
    /// near-degenerate clip this cell flags except the near-equal angles of two cap points
    /// (crate docs, "Exactness"), so a decision it reaches is the decision of this cell.
    type Fast: Clipper<D> + Default + Clone + Send;
    /// Whether [`ConvexCell::Fast`] is another type (worth a first pass) rather than `Self`.
    const HAS_FAST: bool;
    /// The cell's vertices.
    fn vertices(&self) -> &[[f64; D]];
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
    type Fast = Polygon;
    const HAS_FAST: bool = false;

    fn vertices(&self) -> &[[f64; 2]] {
        &self.verts
    }
}

impl Clipper<2> for Polygon {
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

    fn farthest(&self) -> [f64; 2] {
        self.verts
            .iter()
            .copied()
            .max_by(|a, b| norm2(a).total_cmp(&norm2(b)))
            .unwrap_or_default()
    }

    fn degenerate(&self) -> bool {
        self.degenerate
    }

    fn touches(&self, n: &[f64; 2], offset: f64) -> bool {
        cuts_while_touching(self.verts.iter().map(|v| dot(n, v) - offset))
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
    type Fast = SimplePolyhedron;
    const HAS_FAST: bool = true;

    fn vertices(&self) -> &[[f64; 3]] {
        &self.verts
    }
}

impl Clipper<3> for Polyhedron {
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

    fn farthest(&self) -> [f64; 3] {
        self.verts
            .iter()
            .copied()
            .max_by(|a, b| norm2(a).total_cmp(&norm2(b)))
            .unwrap_or_default()
    }

    fn degenerate(&self) -> bool {
        self.degenerate
    }

    fn touches(&self, n: &[f64; 3], offset: f64) -> bool {
        cuts_while_touching(self.verts.iter().map(|v| dot(n, v) - offset))
    }
}

/// Most vertices of a [`SimplePolyhedron`]: its vertex indices are `u8`, so its arrays of 256
/// entries are indexed without bounds checks. A clip that would exceed it flags the cell (the
/// caller then uses [`Polyhedron`]); a Voronoi cell of an ordinary particle set has a few dozen.
const SIMPLE_MAX_VERTS: usize = 255;

/// A [`SimplePolyhedron`]'s vertices are scanned this many slots at a time; the slots from its
/// last vertex up to the next multiple hold the origin.
const LANES: usize = 4;

/// `LANES` doubles.
type F64s = wide::f64x4;

/// `SELECTED[m]`: the lanes whose bits are set in the 4-bit mask `m`, ascending, one per byte
/// from the lowest (the bytes past them are unused).
const SELECTED: [u32; 16] = selected_lanes();
const _: () = assert!(LANES == 4, "SELECTED is written for groups of 4 lanes");

const fn selected_lanes() -> [u32; 16] {
    let mut t = [0u32; 16];
    let mut m = 0;
    while m < 16 {
        let (mut lane, mut k) = (0, 0);
        while lane < 4 {
            if m & (1 << lane) != 0 {
                t[m] |= (lane as u32) << (8 * k);
                k += 1;
            }
            lane += 1;
        }
        m += 1;
    }
    t
}

/// `PREVIOUS[s]`: the slot before `s` in a cyclic list of three, `(s + 2) % 3` (the fourth
/// entry is never used).
const PREVIOUS: [u8; 4] = [2, 0, 1, 0];

/// The box's neighbour lists: vertex `k` is `(±1, ±1, ±1)` with bit 0, 1, 2 of `k` set for
/// `+` in x, y, z; its neighbours differ in one bit each, in (x, y, z) order at the corners
/// with an even number of negative coordinates (counter-clockwise seen from outside there)
/// and in (x, z, y) order at the others.
const BOX_NBRS: [[u8; 3]; 8] = box_nbrs();

/// `BOX_BACK[v][i]`: the slot of `v` in the list of `BOX_NBRS[v][i]`.
const BOX_BACK: [[u8; 3]; 8] = box_back();

const fn box_nbrs() -> [[u8; 3]; 8] {
    let mut t = [[0u8; 3]; 8];
    let mut k = 0u8;
    while k < 8 {
        let negatives = (k & 1 == 0) as u8 + (k & 2 == 0) as u8 + (k & 4 == 0) as u8;
        t[k as usize] = if negatives.is_multiple_of(2) {
            [k ^ 1, k ^ 2, k ^ 4]
        } else {
            [k ^ 1, k ^ 4, k ^ 2]
        };
        k += 1;
    }
    t
}

const fn box_back() -> [[u8; 3]; 8] {
    let n = box_nbrs();
    let mut t = [[0u8; 3]; 8];
    let mut v = 0;
    while v < 8 {
        let mut i = 0;
        while i < 3 {
            let x = n[v][i] as usize;
            let mut j = 0;
            while j < 3 {
                if n[x][j] as usize == v {
                    t[v][i] = j as u8;
                }
                j += 1;
            }
            i += 1;
        }
        v += 1;
    }
    t
}

/// The fast 3D cell: a *simple* convex polyhedron (every vertex has exactly three edges),
/// stored as vertices with their three neighbours in counter-clockwise order seen from
/// outside. A clip touches only the vertices it cuts off and their neighbours: the new face is
/// found by walking the faces of the cut-off region (no sorting by angle), and the cut-off
/// vertices' slots are left free for the new vertices of later clips (nothing is moved).
/// Coordinates are stored by axis, so the signed distances of all vertices are one loop over
/// groups of [`LANES`] slots in SIMD registers.
///
/// It computes the same vertices as [`Polyhedron`] (each new vertex is the crossing point of
/// the same edge, computed by the same expression from the same endpoints), so the same
/// `max_norm2` bit for bit, for every clip sequence that [`Polyhedron`] does not flag. It stays
/// simple only while no clip is near-degenerate: a clip that would cut with a vertex within
/// [`PLANE_EPS`] of its plane, or that makes two new vertices closer than `MERGE_EPS2`, is
/// not performed; the cell is flagged [`Clipper::degenerate`] and must be discarded (the
/// caller decides the particle with [`Polyhedron`] instead). A polyhedron that starts as the
/// box and only takes such clean cuts is simple: each new vertex lies strictly inside an edge
/// and has degree 3.
#[derive(Debug, Clone)]
pub(crate) struct SimplePolyhedron {
    len: usize,
    /// Coordinates by axis: `xyz[k][v]` is coordinate `k` of vertex `v`.
    xyz: Box<[[f64; 256]; 3]>,
    /// `|v|²` of each vertex.
    norm2: Box<[f64; 256]>,
    /// The three neighbours of each vertex, counter-clockwise seen from outside.
    nbrs: Box<[[u8; 3]; 256]>,
    /// `back[v][i]`: the slot of `v` in the list of its neighbour `nbrs[v][i]` (no search).
    back: Box<[[u8; 3]; 256]>,
    /// Signed distance of each vertex from the plane of the clip in progress.
    side: Box<[f64; 256]>,
    /// Per new vertex of the clip in progress: the cut-off vertex at the outer end of its edge
    /// and the slot of the kept one in its list.
    new_out: Box<[(u8, u8); 256]>,
    /// The cut-off vertices of the clip in progress, ascending.
    outs: Box<[u8; 256 + LANES]>,
    /// The crossing edges of the clip in progress: `(o, i)`, the cut-off vertex `o` and the
    /// slot of the kept one in its list.
    crossings: Box<[(u8, u8); 3 * 256]>,
    /// The new vertices of the clip in progress.
    news: Box<[u8; 256]>,
    /// Free slots below `len` (vertices cut off by earlier clips), reused by new vertices
    /// before the arrays grow: a dead slot holds the origin (`norm2` 0, signed distance
    /// `−offset`, clearly inside every plane the cell is clipped by), which changes neither
    /// `max_norm2` nor any flag, and no live vertex points to it.
    free: Box<[u8; 256]>,
    nfree: usize,
    /// `max norm2`.
    max2: f64,
    degenerate: bool,
}

impl Default for SimplePolyhedron {
    fn default() -> Self {
        let mut cell = SimplePolyhedron {
            len: 0,
            xyz: Box::new([[0.0; 256]; 3]),
            norm2: Box::new([0.0; 256]),
            nbrs: Box::new([[0; 3]; 256]),
            back: Box::new([[0; 3]; 256]),
            side: Box::new([0.0; 256]),
            new_out: Box::new([(0, 0); 256]),
            outs: Box::new([0; 256 + LANES]),
            crossings: Box::new([(0, 0); 3 * 256]),
            news: Box::new([0; 256]),
            free: Box::new([0; 256]),
            nfree: 0,
            max2: 0.0,
            degenerate: false,
        };
        cell.reset_box();
        cell
    }
}

impl SimplePolyhedron {
    fn vertex(&self, v: u8) -> [f64; 3] {
        let v = v as usize;
        [self.xyz[0][v], self.xyz[1][v], self.xyz[2][v]]
    }

    fn set_vertex(&mut self, v: u8, x: [f64; 3]) {
        for (axis, c) in self.xyz.iter_mut().zip(x) {
            axis[v as usize] = c;
        }
    }

    /// The vertices, for tests.
    #[cfg(test)]
    fn vertex_list(&self) -> Vec<[f64; 3]> {
        self.live().map(|v| self.vertex(v as u8)).collect()
    }

    /// The slots of the live vertices (not free), for tests.
    #[cfg(test)]
    fn live(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.len).filter(|v| !self.free[..self.nfree].contains(&(*v as u8)))
    }
}

impl Clipper<3> for SimplePolyhedron {
    fn reset_box(&mut self) {
        for k in 0..8u8 {
            let c = |bit: u8| if k & bit != 0 { 1.0 } else { -1.0 };
            self.set_vertex(k, [c(1), c(2), c(4)]);
            self.norm2[k as usize] = 3.0;
        }
        self.nbrs[..8].copy_from_slice(&BOX_NBRS);
        self.back[..8].copy_from_slice(&BOX_BACK);
        self.len = 8;
        self.nfree = 0;
        self.max2 = 3.0;
        self.degenerate = false;
    }

    fn clip(&mut self, n: &[f64; 3], offset: f64) {
        if self.degenerate {
            return;
        }
        let nv = self.len;
        // One pass over the vertices, LANES at a time (the slots up to the next multiple of
        // LANES hold the origin, as free slots do): the signed distances, as
        // `dot(n, v) - offset` (the same roundings: `0 + a` is `a`); the largest one and the
        // smallest absolute one (whether it cuts, and whether a vertex lies within PLANE_EPS
        // of the plane); a mask of the cut-off vertices; and the largest norm among the kept
        // vertices. Explicit SIMD lanes (`wide`): the compiler left the reductions and the
        // listing of cut-off vertices scalar, about half of the clip's instructions.
        let chunks = nv.div_ceil(LANES);
        let (nx, ny, nz) = (F64s::splat(n[0]), F64s::splat(n[1]), F64s::splat(n[2]));
        let (off, eps) = (F64s::splat(offset), F64s::splat(PLANE_EPS));
        let mut top = F64s::splat(f64::NEG_INFINITY);
        let mut closest = F64s::splat(f64::INFINITY);
        let mut kept = F64s::splat(0.0);
        // The cut-off vertices are listed in the same pass, ascending: per group, the slots
        // its mask selects, written four at a time from a table (a loop over the mask's bits,
        // or a second loop over the groups, mispredicted its exit once per group or per clip:
        // callgrind's branch simulation). Listed even when the plane misses the cell (cheap).
        let mut nout = 0usize;
        {
            let [xs, ys, zs] = &*self.xyz;
            let xs = &xs.as_chunks::<LANES>().0[..chunks];
            let ys = &ys.as_chunks::<LANES>().0[..chunks];
            let zs = &zs.as_chunks::<LANES>().0[..chunks];
            let norms = &self.norm2.as_chunks::<LANES>().0[..chunks];
            let sides = &mut self.side.as_chunks_mut::<LANES>().0[..chunks];
            for (c, ((((side, x), y), z), norm)) in sides
                .iter_mut()
                .zip(xs)
                .zip(ys)
                .zip(zs)
                .zip(norms)
                .enumerate()
            {
                let s = nx * F64s::from(*x) + ny * F64s::from(*y) + nz * F64s::from(*z) - off;
                *side = s.to_array();
                top = top.fast_max(s);
                closest = closest.fast_min(s.abs());
                let out = s.simd_gt(eps);
                kept = kept.fast_max(out.bitselect(F64s::splat(0.0), F64s::from(*norm)));
                let mask = out.to_bitmask() as usize & 15;
                let first = 0x0101_0101 * (c * LANES) as u32;
                let at = nout.min(256);
                self.outs[at..at + 4].copy_from_slice(&(SELECTED[mask] + first).to_le_bytes());
                nout += mask.count_ones() as usize;
            }
        }
        if top.to_array().into_iter().fold(f64::NEG_INFINITY, f64::max) <= PLANE_EPS {
            return;
        }
        if closest.to_array().into_iter().fold(f64::INFINITY, f64::min) <= PLANE_EPS {
            self.degenerate = true;
            return;
        }
        let mut max_in = kept.to_array().into_iter().fold(0.0, f64::max);
        // First the edges that cross, `(o, i)` with `u = nbrs[o][i]` kept, listed without a
        // branch (which of a cut-off vertex's neighbours are kept is hard to predict: perf
        // counted that branch among the clip's costliest).
        let mut ncross = 0usize;
        for k in 0..nout {
            let o = self.outs[k as u8 as usize];
            for (i, &u) in self.nbrs[o as usize].iter().enumerate() {
                self.crossings[ncross.min(3 * 256 - 1)] = (o, i as u8);
                ncross += (self.side[u as usize] < 0.0) as usize;
            }
        }
        let mut len = nv;
        let mut nnew = 0usize;
        // New vertices on the crossing edges `u → o`, in free slots or appended after the old
        // ones; `u` now points to the new vertex in the slot of `o`. A new vertex's signed
        // distance is set to 0, which no old slot has (all are beyond PLANE_EPS, checked above).
        for c in 0..ncross.min(3 * 256) {
            let (o, i) = self.crossings[c];
            let i = i as usize;
            let u = self.nbrs[o as usize][i];
            let su = self.side[u as usize];
            let w = if self.nfree > 0 {
                self.nfree -= 1;
                self.free[self.nfree as u8 as usize]
            } else if len < SIMPLE_MAX_VERTS {
                if len.is_multiple_of(LANES) {
                    // A new group of lanes: its other slots hold the origin.
                    for slot in len + 1..len + LANES {
                        self.set_vertex(slot as u8, [0.0; 3]);
                        self.norm2[slot] = 0.0;
                    }
                }
                len += 1;
                (len - 1) as u8
            } else {
                self.degenerate = true;
                return;
            };
            let so = self.side[o as usize];
            let x = crossing(&self.vertex(u), &self.vertex(o), su, so);
            let s = self.back[o as usize][i];
            self.nbrs[u as usize][s as usize] = w;
            self.back[u as usize][s as usize] = 0;
            self.set_vertex(w, x);
            let x2 = norm2(&x);
            self.norm2[w as usize] = x2;
            max_in = if x2 > max_in { x2 } else { max_in };
            self.nbrs[w as usize] = [u, 0, 0];
            self.back[w as usize] = [s, 0, 0];
            self.side[w as usize] = 0.0;
            self.new_out[w as usize] = (o, i as u8);
            self.news[nnew as u8 as usize] = w;
            nnew += 1;
        }
        let news = &self.news[..nnew.min(256)];
        // Two new vertices (nearly) on top of each other: near-degenerate (as `Polyhedron`).
        for (a, &wa) in news.iter().enumerate() {
            let x = self.vertex(wa);
            for &wb in &news[..a] {
                let y = self.vertex(wb);
                if norm2(&[x[0] - y[0], x[1] - y[1], x[2] - y[2]]) <= MERGE_EPS2 {
                    self.degenerate = true;
                    return;
                }
            }
        }
        // The new face: from the new vertex `w` on the edge `u → o`, walk the face left of
        // that edge (seen from outside) through cut-off vertices to the edge where it comes
        // back in, `cur → next`; the new vertex on that edge (now in `next`'s slot of `cur`)
        // follows `w` on the new face. `s` is the slot of the previous vertex in `cur`'s list.
        // (The walk never steps onto a new vertex: cut-off vertices still point to old ones.)
        for &w in news {
            let (mut cur, mut s) = self.new_out[w as usize];
            let mut steps = 0;
            let w2 = loop {
                let j = PREVIOUS[s as usize & 3] as usize;
                let next = self.nbrs[cur as usize][j];
                let back = self.back[cur as usize][j];
                if self.side[next as usize] < 0.0 {
                    break self.nbrs[next as usize][back as usize];
                }
                (cur, s) = (next, back);
                steps += 1;
                if steps > 3 * len {
                    // Not a simple polyhedron after all: give up (never seen; defensive).
                    self.degenerate = true;
                    return;
                }
            };
            if self.side[w2 as usize] != 0.0 {
                self.degenerate = true; // not a new vertex: defensive, as above
                return;
            }
            self.nbrs[w as usize][2] = w2;
            self.back[w as usize][2] = 1;
            self.nbrs[w2 as usize][1] = w;
            self.back[w2 as usize][1] = 2;
        }
        // The cut-off vertices' slots become free: the origin, which no clip cuts off.
        for k in 0..nout {
            let o = self.outs[k as u8 as usize];
            self.set_vertex(o, [0.0; 3]);
            self.norm2[o as usize] = 0.0;
            self.free[self.nfree as u8 as usize] = o;
            self.nfree += 1;
        }
        self.len = len;
        self.max2 = max_in;
    }

    fn max_norm2(&self) -> f64 {
        self.max2
    }

    fn farthest(&self) -> [f64; 3] {
        // Dead slots hold the origin (norm2 0): never the farthest of a non-empty cell.
        let best = (0..self.len).fold(0, |b, v| if self.norm2[v] > self.norm2[b] { v } else { b });
        self.vertex(best as u8)
    }

    fn degenerate(&self) -> bool {
        self.degenerate
    }

    fn touches(&self, n: &[f64; 3], offset: f64) -> bool {
        let [xs, ys, zs] = &*self.xyz;
        let nv = self.len;
        cuts_while_touching(
            xs[..nv]
                .iter()
                .zip(&ys[..nv])
                .zip(&zs[..nv])
                .map(|((x, y), z)| n[0] * x + n[1] * y + n[2] * z - offset),
        )
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

    /// `touches` says, before clipping, whether the clip would be flagged for cutting
    /// through (within PLANE_EPS of) a vertex: checked against the flag of the clip itself, on
    /// the three cells, for planes through a corner of the box (cutting or not) and clear of
    /// every vertex.
    #[test]
    fn touches_predicts_a_clip_through_a_vertex() {
        fn check<const D: usize, C: Clipper<D> + Default + Clone>(n: [f64; D], offsets: &[f64]) {
            for &offset in offsets {
                let mut cell = C::default();
                cell.reset_box();
                let predicted = cell.touches(&n, offset);
                cell.clip(&n, offset);
                assert_eq!(predicted, cell.degenerate(), "n {n:?}, offset {offset}");
            }
        }
        let s2 = std::f64::consts::FRAC_1_SQRT_2;
        // x + y <= √2 passes through the corners (1, 1, ±1) and cuts nothing; at 0 it cuts
        // through the corners (1, −1, ±1) and (−1, 1, ±1); at 0.5 it cuts clear of every vertex.
        let offsets = [2.0 * s2, 0.0 + 1e-300, 0.5, 2.0 * s2 + 1e-13, 1e-13];
        check::<3, Polyhedron>([s2, s2, 0.0], &offsets);
        check::<3, SimplePolyhedron>([s2, s2, 0.0], &offsets);
        check::<2, Polygon>([s2, s2], &offsets);
        let mut c = SimplePolyhedron::default();
        c.reset_box();
        assert!(
            c.touches(&[s2, s2, 0.0], 1e-13),
            "through four corners, cutting two"
        );
        assert!(!c.touches(&[s2, s2, 0.0], 0.5), "clear of every vertex");
        assert!(
            !c.touches(&[s2, s2, 0.0], 2.0 * s2),
            "touches two corners, cuts nothing"
        );
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

    fn sorted_bits(v: &[[f64; 3]]) -> Vec<[u64; 3]> {
        let mut b: Vec<[u64; 3]> = v.iter().map(|x| x.map(f64::to_bits)).collect();
        b.sort_unstable();
        b
    }

    /// Checks the simple polyhedron's invariants: three distinct neighbours per vertex, each
    /// listing the vertex back.
    fn assert_simple(c: &SimplePolyhedron) {
        let live: Vec<usize> = c.live().collect();
        for v in live.iter().copied() {
            let n = c.nbrs[v];
            assert!(
                n[0] != n[1] && n[1] != n[2] && n[0] != n[2],
                "vertex {v}: {n:?}"
            );
            for (i, x) in n.into_iter().enumerate() {
                assert!(live.contains(&(x as usize)));
                assert_eq!(
                    c.nbrs[x as usize][c.back[v][i] as usize], v as u8,
                    "{v} -> {x}"
                );
            }
        }
    }

    // The fast cell computes the same vertices as `Polyhedron`, bit for bit, after every clip
    // of random sequences (random unit normals, offsets 0.2..1.3); it flags a clip only where
    // `Polyhedron` flags one too, and stops there.
    #[test]
    fn simple_polyhedron_has_the_polyhedron_vertices_bit_for_bit() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut compared = 0;
        // One fast cell for every sequence: its slots past the box hold the previous
        // sequence's vertices, which its scan must not see (the slots up to a multiple of
        // `LANES` past the last vertex hold the origin).
        let mut fast = SimplePolyhedron::default();
        for _ in 0..300 {
            let mut old = Polyhedron::default();
            old.reset_box();
            fast.reset_box();
            for _ in 0..40 {
                let z = 2.0 * uniform() - 1.0;
                let a = std::f64::consts::TAU * uniform();
                let rho = (1.0 - z * z).sqrt();
                let n = [rho * a.cos(), rho * a.sin(), z];
                let offset = 0.2 + 1.1 * uniform();
                old.clip(&n, offset);
                fast.clip(&n, offset);
                if fast.degenerate() {
                    assert!(old.degenerate());
                    break;
                }
                if old.degenerate() {
                    break;
                }
                assert_simple(&fast);
                assert_eq!(
                    sorted_bits(&fast.vertex_list()),
                    sorted_bits(old.vertices())
                );
                assert_eq!(fast.max_norm2().to_bits(), old.max_norm2().to_bits());
                compared += 1;
            }
        }
        assert!(compared > 5000, "{compared}");
    }

    // Planes through vertices (a perfect lattice's bisectors) are near-degenerate: the fast
    // cell flags one that cuts, and does not cut; one that cuts nothing changes nothing.
    #[test]
    fn simple_polyhedron_flags_a_cutting_plane_through_a_vertex() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let mut fast = SimplePolyhedron::default();
        fast.clip(&[1.0, 0.0, 0.0], 0.5);
        assert!(!fast.degenerate());
        assert_eq!(fast.vertex_list().len(), 8);
        assert!(close(fast.max_norm2(), 3.0)); // the corners at x = -1 remain
        fast.clip(&[1.0, 0.0, 0.0], 0.5); // through 4 vertices, cuts nothing
        assert!(!fast.degenerate());
        assert_eq!(fast.vertex_list().len(), 8);
        fast.clip(&[0.0, s, s], 0.0); // y + z <= 0: through (x, 1, -1), (x, -1, 1)
        assert!(fast.degenerate());
        assert_eq!(fast.vertex_list().len(), 8, "a flagged clip does not cut");
    }
}
