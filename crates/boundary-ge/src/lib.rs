#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Boundary detection with geometric enclosures ("slabs"): the second method of Sandim, Paiva
//! & Figueiredo, *Simple and reliable boundary detection for meshfree particle methods using
//! interval analysis*, J. Comput. Phys. 2020, Sec. 3.2 and Algorithm 3. Method name `ge`, one
//! parameter `depth` (default 6).
//!
//! **When to use it:** to reproduce the paper's slab method, or where a certificate is
//! enough: it never misses a boundary particle, and may flag a few interior ones near ties
//! (fewer at a larger `depth`). For exact labels use `exact` (accuracy and speed on the same scenes: `BENCHMARKS.md`, written by `cargo xtask sweep`).
//!
//! # Method
//! Particle `i` is interior iff its sphere `S_i` is covered by the closed balls `B_j` of the
//! particles within `2r`. In the frame `T_i(x) = (x − p_i)/r`, `S_i` is the unit sphere and every
//! `B_j` a unit ball. Instead of subdividing space around `S_i` (the `ia` method), `ge` meshes
//! `S_i` itself and encloses each mesh element's patch of the sphere in a thin convex *slab*:
//!
//! - **2D.** The mesh starts as the three sides of an inscribed equilateral triangle. The slab of
//!   a chord `L` is the rectangle with one side on `L` and the opposite side on the tangent line
//!   at the projection `m̂` of `L`'s midpoint (Fig. 3). A chord is refined at `m̂`.
//! - **3D.** The mesh starts as the four faces of an inscribed regular tetrahedron. The slab of a
//!   triangle `L` with barycentre `b` is the frustum between `L` and its perspective projection
//!   `a ↦ a/(a·b̂)` onto the plane tangent at `b̂ = b/|b|` (Fig. 5). A triangle is refined by
//!   midpoint subdivision with the new vertices projected onto the sphere (hanging nodes are
//!   fine: only the patches matter).
//! - **Labels** (Sec. 3.2): by the signs of `f_j(x) = |x − q_j|² − 1` at the slab's vertices:
//!   *covered* if all vertices are inside some `B_j`, *uncovered* if all vertices are outside
//!   every `B_j`, *partial* otherwise.
//! - **Rules** R1–R4 with an explicit stack, depth first (Algorithm 3): R1 uncovered: boundary;
//!   R2 covered: done with this element; R3 partial below the maximum depth: push the children;
//!   R4 partial at the maximum depth: boundary. If the stack empties, every patch was
//!   covered: interior.
//! - **Depth.** The coarse inscribed mesh is the roots of the refinement trees (depth 0; each
//!   face is the root of a quadtree, Fig. 6), and Algorithm 3 "initializes the stack with the
//!   nodes from the first tree-level": the roots' children, depth 1 (6 arcs in 2D, 16 triangles
//!   in 3D). This mirrors `ia`, whose root (the bounding box of `B_i`) is depth 0 and whose
//!   recursion starts at its children (Algorithm 2), and gives both methods the same resolution
//!   at the same depth: at depth `d` a 3D element spans about `1.9·2^-d` rad of the unit sphere,
//!   an `ia` box `2^(1-d)`. The paper does not number the levels explicitly; this is our reading.
//!
//! # Why this is certified (Rec = 1)
//! - **The slabs enclose the sphere.** Each slab is convex and contains its element's patch
//!   (the argument is at `Arc::slab` and `Triangle::slab` in `slab.rs`, and tested); the first
//!   level's patches tile `S_i` (the radial projection of the triangle's sides / tetrahedron's
//!   faces), and the children of an element tile its patch: in 2D the two sub-arcs meet at `m̂`;
//!   in 3D the projected midpoint of an edge `ab` lies on the great-circle arc `ab`, which is
//!   the edge of the patch, so the four children's patches tile the parent's.
//! - **"All vertices inside a ball" proves coverage.** A ball is convex, so it contains the
//!   convex hull of any of its points: the slab, hence the patch.
//! - So *interior* is only answered when every patch of `S_i` lies in some `B_j`: `S_i` is
//!   covered and the exact label is interior. Every doubtful case answers *boundary*.
//! - **"All vertices outside" is only a heuristic.** A ball can cut into a slab through an edge
//!   or a face without containing any vertex, so "uncovered" (R1) may be declared for a patch
//!   that a ball does reach, even one that is in fact covered. R1 answers *boundary*, so the
//!   heuristic can only add false positives, never a false negative. (The paper uses it for
//!   speed; `ia` has no such heuristic: its interval image of `f_j` is exact.)
//!
//! # Policy: tolerances, ties, duplicates, degenerate input
//! - **Arithmetic.** Neighbour centres are taken relative to `p_i` and scaled by `1/r`, so
//!   scenes at `1e6` with `r = 0.01` lose nothing to the offset. The slab vertices carry rounding
//!   errors of a few ulps; to keep the covering proof valid under them, a vertex counts as inside
//!   `B_j` only if `|v − q_j|² <= 1 − COVER_MARGIN` (`COVER_MARGIN = 1e-12`, in units of `r²`):
//!   a ball that contains the computed slab with that margin contains the exact one.
//! - **Ties.** At an exact tie (a point of `S_i` reached only by the spheres of its neighbours,
//!   as in perfect lattices at `r = a/√2` in 2D or `a·√3/2` in 3D) the elements around the tie
//!   point stay partial at every depth and R4 labels the particle boundary: for `ge`, ties are
//!   false positives, never false negatives (the exact reference calls them interior).
//! - **Duplicates.** Particles at exactly `p_i` do not cover `S_i` and are skipped. A particle
//!   with no other neighbour within `2r` is boundary.
//! - **Neighbours.** From the core grid, closed at `2r`, nearest first. Each element is
//!   labelled against every neighbour as in Algorithm 3, with shortcuts that change the order
//!   or the number of the tests, never the label: every element has a *reach* ball holding its
//!   slab's vertices and those of all its descendants (bounded in `slab.rs`, tested), and a
//!   neighbour whose centre is beyond `1 + reach` has every such vertex outside, so it is
//!   dropped for the whole subtree (the children inherit the shorter list, as the boxes of `ia`
//!   do; where the reach is 1 or more, as on the 3D first level, the list is passed on whole:
//!   such a filter drops few balls); the children's lists start with the two balls nearest the
//!   element's reach centre, the likeliest to cover them; the ball that covered the last
//!   covered element is tried first (consecutive elements of the depth-first order are
//!   neighbours on `S_i`); a ball whose centre lies within `1 − reach` of the reach centre
//!   covers the element (every vertex is within `reach` of it). The label takes two passes
//!   over the list: first for a ball that covers the element (nearly every element below the
//!   first level is covered), which no ball whose centre is at least its radius from the reach
//!   centre (a point of the patch) can do; only if none does, for a ball with a vertex inside
//!   or on it (partial; none: uncovered), keeping the balls the children need. At a uniform
//!   radius no unit ball can hold a slab of the 3D first level (each has two vertices at least
//!   2.07 apart), so those 16 elements are only tested for a vertex inside or on some ball
//!   (partial) or none (uncovered), and their children share their list. The slabs and reach balls of the first three levels are
//!   computed once per detection by the same functions (bit for bit the same values). A test
//!   checks all of these shortcuts against Algorithm 3 written plainly (every element against
//!   every ball), particle by particle, on the hard cases, the near-tie lattices, sparse to
//!   dense jittered lattices and per-particle radii.
//!
//! # A radius per particle (ours)
//! With per-particle radii ([`boundary_core::ParticleSet::with_radii`]) the frame is scaled by
//! `1/r_i`; ball `j` has radius `s_j = r_j/r_i` and a slab vertex counts as inside it only if
//! `|v − q_j|² <= s_j² − COVER_MARGIN·max(1, s_j²)` (the rounding of `|v − q_j|²` grows with
//! `s_j²`). A ball is beyond an element's reach when its centre is farther than `s_j + reach`.
//! Neighbours: those with `|p_i − p_j| <= r_i + r_j` ([`boundary_core::RadiusGrid`]), the
//! likeliest cover (smallest `d_j − s_j`) first. Equal radii give the uniform labels; no false
//! negative (tested against `exact` on two-level sets with radius ratios 2, 4 and 100).
//!
//! # Solid regions
//! With solid half-spaces ([`boundary_core::Solids`], through
//! [`boundary_core::BoundaryDetector::detect_owned_in`] or a [`boundary_core::Domain`]), particle `i` is
//! interior iff every point of `S_i` outside the closed solids is covered by the balls. An
//! element is *covered* when some ball holds its slab, as above, or when some solid holds every
//! vertex of its slab: the slab is convex and the solid a half-space, so the slab and its patch
//! lie in the solid. An element that no ball touches but that has a vertex in a solid is
//! *partial* rather than uncovered, and is refined (its children keep its whole list of
//! balls); a patch split between a solid and a ball is covered once its elements are small
//! enough to lie wholly in one of them. So *interior* is still only answered when every patch
//! of `S_i` lies in a ball or in a solid.
//!
//! **Rounding.** In the frame of `p_i` a solid `x_a <= c` is `x_a <= h`, `h = (c −
//! p_{i,a})/r_i` computed within `2u` (relative). A vertex counts as inside the solid only if it
//! lies at least [`SOLID_MARGIN`] `+ 4ε|h|` (units of `r_i`) beyond `h`, which absorbs both that
//! rounding and that of the computed slab vertices, as [`COVER_MARGIN`] does for the balls. A
//! point of `S_i` exactly on the surface of a solid is covered (the solids are closed), but where
//! nothing else covers it (a sphere touching a solid from inside) the elements around it are
//! never proven covered and the particle is labelled *boundary*: a false positive, never a
//! false negative. Particles whose sphere no solid reaches take the code path without solids,
//! so a detection without solids costs what it did.
//!
//! # Hard cases
//! What `ge` returns on the hard cases (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`).
//! No false negative on any case (certified). The differences from `exact` are false
//! positives:
//! - Perfect lattices at the float tie radius and 4 ulps either side: every particle boundary.
//!   Where the float radius lies below the exact tie (square lattice 4 ulps below `fl(1/√2)`,
//!   cubic lattice at `fl(√3/2)` and 4 ulps below) that is the exact answer; above it the
//!   inner particles are exact ties or near-ties and stay partial at every depth: +100 of 144
//!   in 2D, +125 of 343 in 3D, false positives, never false negatives (also checked on the
//!   near-tie lattices at `tie·(1 ± k·1e-10)` of `boundary_scenes::certify::near_tie_cases`).
//! - Near-duplicates 1e-12 apart: closer than the cover margin, 18 false positives.
//! - Jittered lattices at the default depth 6: at most 1 false positive.
//!
//! Everything else (exact duplicates, single particles, pairs exactly `2r` apart, lines,
//! collinear and coplanar 3D sets, offsets 1e6 and 1e9, `r` from 1e-9 to 1e9, empty input) has
//! exactly the labels of `exact`. Labels can change under axis swaps (the inscribed simplex has
//! a fixed orientation), never into a false negative.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_ge::{GeDetector, GeParams};
//!
//! // A 5 x 5 x 5 cubic lattice of spacing 1 at r = 1.2: the 3 x 3 x 3 core is interior.
//! let rows: Vec<[f64; 3]> = (0..125)
//!     .map(|k| [(k % 5) as f64, ((k / 5) % 5) as f64, (k / 25) as f64])
//!     .collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let detector = GeDetector::try_new(GeParams { depth: 6 }).unwrap(); // the default depth
//! let detection = detector.detect_3d(&set, Radius::new(1.2).unwrap()).unwrap();
//! assert_eq!(detection.labels.boundary_count(), 125 - 27);
//! ```

#[cfg(test)]
mod reference;
mod slab;

use boundary_core::{
    Capabilities, CoreError, DetectError, Detection, Dim, Job, JobByDim, Labels, Method,
    NeighbourGrid, ParamSet, Params, ParticleSet, Point, Radius, RadiusGrid, Solids, Support,
    SupportedDim,
};
use rayon::prelude::*;
use slab::{Arc, Element, Triangle};

/// Default maximum refinement depth (the paper's tables use 6).
pub const DEFAULT_DEPTH: u32 = 6;

/// Largest accepted depth: in 3D an element at depth 16 spans about `2^-15` rad.
pub const MAX_DEPTH: u32 = 16;

/// A slab vertex counts as inside a unit ball only if `|v − q|² <= 1 − COVER_MARGIN` (units of
/// `r²`): absorbs the rounding of the computed slab vertices (see the crate docs).
pub const COVER_MARGIN: f64 = 1e-12;

/// Slack of the covered-by-distance shortcut in `label` (units of r): a ball whose centre is
/// within `1 − DEEP_SLACK − reach` of an element's reach centre covers the element. Far above
/// the rounding of the distance and of `reach` (~1e-15), so the shortcut implies what the
/// vertex test would find: every vertex at most `1 − DEEP_SLACK` from the centre, inside by
/// more than [`COVER_MARGIN`].
const DEEP_SLACK: f64 = 1e-9;

/// How many of the last covering balls (distinct, most recent first) are tried first on each
/// element. One: under callgrind on a jittered ball (r = 1.2a) the instruction count grows
/// with every ball added to the list (2, 3, 4, 8, 12), as the balls tried first rarely settle
/// an element the last one did not.
const RECENT: usize = 1;

/// How many balls of a partial element's list are put in order for its children (nearest
/// first); the rest of the list follows unsorted.
const NEAREST: usize = 2;

/// The neighbours are ordered by shells of equal width in `d²/(2r)²`, nearest first.
const SHELLS: usize = 16;

/// An element whose reach ball has at least this radius passes its whole list to its
/// children: balls lie within 2 of the origin (units of r) and the reach centre on the unit
/// sphere, so a filter radius `1 + reach >= 2` drops few of them, and building the filtered,
/// ordered list cost more than it saved (the 16 elements of the first level in 3D, reach
/// about 1.08; in 2D the first level has reach 0.56 and is filtered).
const WIDE_REACH: f64 = 1.0;

boundary_core::declare_params! {
    /// The parameters of `ge` (string form: `--set depth=…`, see `boundary::registry`).
    #[derive(Debug, Clone, PartialEq, Eq)]
    pub struct GeParams for "ge" {
        /// Maximum subdivision depth, in `1..=`[`MAX_DEPTH`]; default [`DEFAULT_DEPTH`].
        /// Deeper: fewer false positives, slower.
        pub depth: u32 = DEFAULT_DEPTH, check::int_in(1, MAX_DEPTH),
            "maximum refinement depth of the slab mesh on S_i (JCP 2020 Sec. 3.2, rules \
             R1-R4); deeper: fewer false positives, slower";
    }
}

/// The geometric-enclosure detector (`ge`). See the crate documentation.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct GeDetector {
    params: GeParams,
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(GeDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(GeDetector, GeParams);

impl Method for GeDetector {
    const NAME: &'static str = "ge";

    fn describe(&self) -> Params {
        self.params.listing()
    }

    /// Certified; per-particle radii and the closed solid half-spaces (crate docs, "Solid
    /// regions"); the ghosts serve as neighbours only.
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            certified: true,
            radii: Support::Honoured,
            half_spaces: Support::Honoured,
            ..Capabilities::DEFAULT
        }
    }

    fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        let depth = self.params.depth;
        Ok(match job.by_dim() {
            JobByDim::D2(j) => detect_with::<2, Arc>(j.set, j.owned, j.r, depth, j.solids)?,
            JobByDim::D3(j) => detect_with::<3, Triangle>(j.set, j.owned, j.r, depth, j.solids)?,
        })
    }
}

/// Classifies the first `count` particles of `set` (all of them serve as neighbours), the
/// closed half-spaces of `solids` covering too (their axes are those of the set).
fn detect_with<const D: usize, E: Element<D> + Send + Sync>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    depth: u32,
    solids: &Solids,
) -> Result<Detection, CoreError> {
    let positions = set.positions();
    let mesh = Mesh::<D, E>::new(depth.min(TABLE_DEPTH));
    let radii = set.resolved_radii(r)?;
    let r = r.get();
    let grids = match &radii {
        // Cells of side r: a query of radius 2r scans 5^D cells, (5/6)^D of the volume of
        // the 3^D cells of side 2r (fewer particles to test, the same neighbours).
        None => (Some(NeighbourGrid::new(set, r)?), None),
        Some(radii) => (None, Some(RadiusGrid::new(set, radii)?)),
    };
    let labels: Labels = (0..count)
        .into_par_iter()
        .map_init(Scratch::<D, E>::default, |scratch, i| {
            if boundary_core::stop::requested() {
                return Default::default();
            }
            match &grids {
                (Some(grid), _) => scratch.gather(positions, grid, i, r),
                (_, Some(grid)) => scratch.gather_radii(positions, grid, i),
                (None, None) => unreachable!("one grid is built"),
            }
            // A particle whose sphere no solid reaches takes the path without solids.
            if !solids.is_empty() {
                let r_i = radii.as_ref().map_or(r, |radii| radii[i]);
                scratch.cut_by(solids, &positions[i], r_i);
                if !scratch.cuts.is_empty() {
                    return if radii.is_none() {
                        scratch.is_boundary::<true, true>(&mesh, depth)
                    } else {
                        scratch.is_boundary::<false, true>(&mesh, depth)
                    };
                }
            }
            // Monomorphised twice: at a uniform radius every ball is the unit ball, as
            // constants, so that path costs what it did before per-particle radii.
            if radii.is_none() {
                scratch.is_boundary::<true, false>(&mesh, depth)
            } else {
                scratch.is_boundary::<false, false>(&mesh, depth)
            }
        })
        .collect::<Vec<bool>>()
        .into_iter()
        .collect();
    Ok(Detection {
        labels,
        margin: None,
    })
}

/// How a slab relates to the balls (Sec. 3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Label {
    Covered,
    Uncovered,
    Partial,
}

/// An element on the stack with the range of `Scratch::candidates` holding the neighbours that
/// can still reach it (those not dropped for its whole subtree by an ancestor).
#[derive(Debug, Clone, Copy)]
struct Node<E> {
    element: E,
    /// The element's entry in the [`Mesh`] table, or [`NOT_IN_TABLE`] (deeper than the table).
    entry: u32,
    start: usize,
    len: usize,
}

/// [`Node::entry`] of an element below the table's depth: its slab and reach are computed.
const NOT_IN_TABLE: u32 = u32::MAX;

/// Depth of the precomputed part of the mesh (3D: 16 + 64 + 256 elements). Deeper elements
/// (fewer than one per particle on the jittered balls) are computed when visited.
const TABLE_DEPTH: u32 = 3;

/// An element of the fixed mesh of `S_i` with what `label` needs of it, computed once per
/// detection by the same functions ([`Element::slab`], [`Element::reach`]), so the values are
/// bit for bit those computed per particle before: the labels cannot change.
#[derive(Debug, Clone, Copy)]
struct Entry<const D: usize, E: Element<D>> {
    element: E,
    slab: E::Slab,
    /// [`Element::reach`].
    centre: Point<D>,
    reach: f64,
    /// Two slab vertices lie more than `2·(1 + 1e-6)` apart, so no unit ball holds both: at a
    /// uniform radius the element can only be partial or uncovered (the 16 elements of the 3D
    /// first level, whose slabs are at least 2.07 wide).
    uncoverable: bool,
    /// Index of the first of the four (3D) or two (2D) children, [`NOT_IN_TABLE`] at the
    /// table's last level.
    children: u32,
}

/// The mesh elements from the first level to a fixed depth, each level's children stored
/// together in the order of [`Element::children`].
#[derive(Debug)]
struct Mesh<const D: usize, E: Element<D>> {
    entries: Vec<Entry<D, E>>,
    /// How many entries the first level has (they come first).
    first: usize,
    /// How many children an element has (2 in 2D, 4 in 3D).
    arity: usize,
}

impl<const D: usize, E: Element<D>> Mesh<D, E> {
    fn new(depth: u32) -> Self {
        let entry = |element: E| {
            let slab = element.slab();
            let (centre, reach) = element.reach();
            let vertices = slab.as_ref();
            let wide = vertices.iter().any(|v| {
                vertices
                    .iter()
                    .any(|w| (v - w).norm_squared() > 4.0 * (1.0 + 1e-6))
            });
            Entry {
                element,
                slab,
                centre,
                reach,
                uncoverable: wide,
                children: NOT_IN_TABLE,
            }
        };
        let level = E::first_level();
        let first = level.len();
        let mut entries: Vec<Entry<D, E>> = level.into_iter().map(entry).collect();
        let mut from = 0;
        let mut kids = Vec::new();
        E::first_level()[0].children(&mut kids);
        let arity = kids.len();
        for _ in 1..depth {
            let to = entries.len();
            for k in from..to {
                kids.clear();
                entries[k].element.children(&mut kids);
                entries[k].children = entries.len() as u32;
                entries.extend(kids.iter().map(|&c| entry(c)));
            }
            from = to;
        }
        Mesh {
            entries,
            first,
            arity,
        }
    }
}

/// A neighbour in a list of [`Scratch::candidates`]: its scaled centre and its index in
/// [`Scratch::centres`].
#[derive(Debug, Clone, Copy)]
struct Cand<const D: usize> {
    q: Point<D>,
    j: u32,
}

/// Per-thread working memory.
#[derive(Debug)]
struct Scratch<const D: usize, E: Element<D>> {
    /// Neighbour centres `q_j = (p_j − p_i)/r`, nearest first (by shells, [`SHELLS`]).
    centres: Vec<Point<D>>,
    /// Their balls with per-particle radii: `(s, s², inner)`, `s = r_j/r_i`, `inner` the
    /// squared distance a vertex must not exceed to count as inside (`against_ball`).
    balls: Vec<(f64, f64, f64)>,
    /// Neighbours from [`RadiusGrid::scaled_neighbours`] (per-particle radii).
    scaled: Vec<(f64, Point<D>, f64)>,
    /// Arena of neighbour lists (centre and index, so that a pass streams through memory),
    /// shared by sibling elements; the first `centres.len()` entries are the whole list.
    candidates: Vec<Cand<D>>,
    stack: Vec<Node<E>>,
    children: Vec<E>,
    /// Kept balls of the current element with their distance ([`sort_key`]).
    keys: Vec<u64>,
    /// Neighbour centres with their shell, in the grid's order (`gather`).
    unsorted: Vec<(usize, Point<D>)>,
    /// The neighbour that covered the last covered element.
    last_cover: [usize; RECENT],
    /// The solid half-spaces that reach the current particle's sphere ([`Cut`]).
    cuts: Vec<Cut>,
}

impl<const D: usize, E: Element<D>> Default for Scratch<D, E> {
    fn default() -> Self {
        Scratch {
            centres: Vec::new(),
            balls: Vec::new(),
            scaled: Vec::new(),
            candidates: Vec::new(),
            stack: Vec::new(),
            children: Vec::new(),
            keys: Vec::new(),
            unsorted: Vec::new(),
            last_cover: [usize::MAX; RECENT],
            cuts: Vec::new(),
        }
    }
}

/// The label of one slab against one ball of squared radius `s2` at `q` (1 at a uniform
/// radius): `Some(true)` if every vertex is inside (`|v − q|² <= inner`, where `inner = s2 −`
/// [`COVER_MARGIN`]`·max(1, s2)`: [`inner`]), `Some(false)` if every vertex is outside,
/// `None` otherwise.
///
/// This is the label as the paper defines it, which the tests' plain Algorithm 3 uses;
/// `Scratch::label` computes the same label in two passes (first "covers?", then "touches?").
#[cfg(test)]
fn against_ball<const D: usize>(
    slab: &[Point<D>],
    q: &Point<D>,
    (s2, inner): (f64, f64),
) -> Option<bool> {
    let (mut inside, mut outside) = (false, false);
    for v in slab {
        let d2 = (v - q).norm_squared();
        if d2 <= inner {
            inside = true;
        } else if d2 > s2 {
            outside = true;
        } else {
            return None; // on the sphere (within the margin): neither
        }
        if inside && outside {
            return None;
        }
    }
    Some(inside)
}

/// Whether every vertex of the slab is inside the ball at `q` (`|v − q|² <= inner`): the
/// covered case of `against_ball`, stopping at the first vertex that is not.
#[inline]
fn covers<const D: usize>(slab: &[Point<D>], q: &Point<D>, inner: f64) -> bool {
    slab.iter().all(|v| (v - q).norm_squared() <= inner)
}

/// The key of a kept ball for ordering the children's list: the squared distance `d2 >= 0`
/// of its centre from the element's reach centre, as the high 32 bits of its f64 bits
/// (monotone for non-negative floats; truncated to 20 mantissa bits), its place `k` in the
/// element's list in the low 32. The order only speeds up the search for a covering ball; it changes no label.
#[inline]
fn sort_key(d2: f64, k: u32) -> u64 {
    (d2.to_bits() & !0xffff_ffff) | u64::from(k)
}

/// A slab vertex counts as inside a solid only if it lies at least this far (units of r) on
/// the solid side of the bound: absorbs the rounding of the computed slab vertices, as
/// [`COVER_MARGIN`] does for the balls (crate docs, "Solid regions").
pub const SOLID_MARGIN: f64 = 1e-12;

/// A solid half-space in the frame of particle `i` (scaled by `1/r_i`): on axis `axis` the
/// solid is `x <= h` (`below`) or `x >= h`, `h = fl(fl(c − p_i)/r_i)`; `t` is `h` moved by
/// [`SOLID_MARGIN`] and `4ε|h|` (the rounding of `h`) into the solid.
#[derive(Debug, Clone, Copy)]
struct Cut {
    axis: usize,
    below: bool,
    h: f64,
    t: f64,
}

impl Cut {
    /// Whether every slab vertex lies in the solid beyond `t`: then the slab (convex), hence
    /// its patch, lies in the closed solid.
    #[inline]
    fn holds<const D: usize>(&self, slab: &[Point<D>]) -> bool {
        if self.below {
            slab.iter().all(|v| v[self.axis] <= self.t)
        } else {
            slab.iter().all(|v| v[self.axis] >= self.t)
        }
    }

    /// Whether some slab vertex lies in the solid or on its bound (a heuristic, as
    /// "uncovered" is: it only decides between refining and answering boundary).
    #[inline]
    fn touches<const D: usize>(&self, slab: &[Point<D>]) -> bool {
        if self.below {
            slab.iter().any(|v| v[self.axis] <= self.h)
        } else {
            slab.iter().any(|v| v[self.axis] >= self.h)
        }
    }
}

/// Puts `j` first in the list of recent covering balls, moving the first `k` entries one place
/// down (`k = RECENT − 1` for a ball that was not in the list: the oldest drops out). A loop
/// of at most `RECENT − 1` moves: `copy_within` was a library call costing 4% of the run.
#[inline]
fn remember(recent: &mut [usize; RECENT], k: usize, j: usize) {
    for m in (1..=k).rev() {
        recent[m] = recent[m - 1];
    }
    recent[0] = j;
}

/// The squared distance within which a slab vertex counts as inside a ball of squared radius
/// `s2`: `s2 − COVER_MARGIN·max(1, s2)` (the rounding of `|v − q|²` grows with `s2`).
fn inner(s2: f64) -> f64 {
    s2 - COVER_MARGIN * s2.max(1.0)
}

impl<const D: usize, E: Element<D>> Scratch<D, E> {
    /// Scaled neighbour centres of particle `i`, nearest first (by shells of `d²`);
    /// duplicates of `p_i` skipped.
    fn gather(&mut self, positions: &[Point<D>], grid: &NeighbourGrid<D>, i: usize, r: f64) {
        let p = positions[i];
        let unsorted = &mut self.unsorted;
        unsorted.clear();
        // Counting sort into SHELLS shells of equal width in d²/(2r)² (nearest shell first,
        // the grid's order within a shell): as fast a start as a full sort, at a tenth of its
        // cost on dense sets.
        let mut starts = [0usize; SHELLS + 1];
        let scale = SHELLS as f64 / (4.0 * r * r);
        grid.for_each_within(&p, 2.0 * r, |j, d2| {
            if d2 > 0.0 {
                let shell = ((d2 * scale) as usize).min(SHELLS - 1);
                starts[shell + 1] += 1;
                unsorted.push((shell, (positions[j] - p) / r));
            }
        });
        for k in 1..=SHELLS {
            starts[k] += starts[k - 1];
        }
        self.centres.clear();
        self.centres.resize(unsorted.len(), Point::<D>::zeros());
        for &(shell, q) in unsorted.iter() {
            self.centres[starts[shell]] = q;
            starts[shell] += 1;
        }
        self.last_cover = [usize::MAX; RECENT];
    }

    /// [`Self::gather`] with a radius per particle ([`RadiusGrid::scaled_neighbours`]):
    /// centres and balls in units of `r_i`, the likeliest cover (smallest `d_j − r_j`) first.
    fn gather_radii(&mut self, positions: &[Point<D>], grid: &RadiusGrid<D>, i: usize) {
        grid.scaled_neighbours(positions, i, &mut self.scaled);
        self.centres.clear();
        self.centres.extend(self.scaled.iter().map(|&(_, q, _)| q));
        self.balls.clear();
        self.balls.extend(
            self.scaled
                .iter()
                .map(|&(_, _, s)| (s, s * s, inner(s * s))),
        );
        self.last_cover = [usize::MAX; RECENT];
    }

    /// `label(Q, i)` of Algorithm 3 for the element of `node`: covered if some ball holds every
    /// slab vertex, uncovered if every ball misses every vertex, partial otherwise. Also leaves,
    /// from `list_start` on in `candidates`, the neighbours that may reach the element's
    /// descendants.
    ///
    /// Only the order of the tests differs from the paper's loop, never the label: balls beyond
    /// the element's reach (see [`Element::reach`]) have every vertex outside, and the ball
    /// whose centre is nearest the element is tried first as the likeliest to cover it.
    /// Ball `j` as `(s², inner)` for `against_ball`: constants at a uniform radius.
    #[inline]
    fn ball<const UNIFORM: bool>(&self, j: usize) -> (f64, f64) {
        if UNIFORM {
            (1.0, 1.0 - COVER_MARGIN)
        } else {
            (self.balls[j].1, self.balls[j].2)
        }
    }

    fn label<const UNIFORM: bool>(
        &mut self,
        node: &Node<E>,
        slab: &[Point<D>],
        (centre, reach): (Point<D>, f64),
        uncoverable: bool,
    ) -> (Label, usize, usize) {
        let list = node.start..node.start + node.len;
        // A reach ball of radius >= WIDE_REACH drops few balls for the subtree (the first level
        // in 3D): the children then share this element's list as it is (the same range of
        // the arena), in its order, without the keys.
        let narrow = reach < WIDE_REACH;
        let whole = (Label::Partial, node.start, node.len);
        if UNIFORM && uncoverable && !narrow {
            // No unit ball holds the slab ([`Entry::uncoverable`]): the label is partial as
            // soon as one ball has a vertex inside or on it (`against_ball` gives `None`: never
            // `Some(true)`), uncovered if none has.
            let touched = self.candidates[list]
                .iter()
                .any(|c| slab.iter().any(|v| (v - c.q).norm_squared() <= 1.0));
            return if touched {
                whole
            } else {
                (Label::Uncovered, 0, 0)
            };
        }
        const COVERED: (Label, usize, usize) = (Label::Covered, 0, 0);
        // The ball that covered the previous element first: consecutive elements of the
        // depth-first order are neighbours on S_i, often inside the same ball.
        for k in 0..RECENT {
            let j = self.last_cover[k];
            let Some(q) = self.centres.get(j) else {
                break;
            };
            if covers(slab, q, self.ball::<UNIFORM>(j).1) {
                remember(&mut self.last_cover, k, j);
                return COVERED;
            }
        }
        // At a uniform radius, a ball whose centre lies within `1 − DEEP_SLACK − reach` of the
        // reach centre holds every slab vertex (they lie within `reach` of it) by more than
        // COVER_MARGIN: the label `against_ball` would give, without the vertex loop.
        let deep = 1.0 - DEEP_SLACK - reach;
        let deep2 = if UNIFORM && deep > 0.0 {
            deep * deep
        } else {
            -1.0
        };
        let far_uniform = (1.0 + reach) * (1.0 + reach);
        // Split borrows: the list is read while the keys grow.
        let Scratch {
            balls,
            candidates,
            keys,
            last_cover,
            ..
        } = self;
        let ball = |j: u32| -> (f64, f64) {
            if UNIFORM {
                (1.0, 1.0 - COVER_MARGIN)
            } else {
                (balls[j as usize].1, balls[j as usize].2)
            }
        };
        // Pass 1, for a ball that holds every vertex (the label of nearly every element below
        // the first level), in the order of the parent's list (nearest the parent first, so a
        // covering ball comes early and ends the pass). A ball whose centre is at least its
        // radius from the reach centre cannot (see [`Element::reach`]: that point is on the
        // patch, so in the slab, and a covering ball holds it by more than the rounding); for
        // the others, the vertex test of `against_ball`'s covered case, stopping at the first
        // vertex not inside.
        for &Cand { q, j } in &candidates[list.clone()] {
            let d2 = (q - centre).norm_squared();
            let (s2, inner) = ball(j);
            if d2 <= deep2 || (d2 < s2 && covers(slab, &q, inner)) {
                remember(last_cover, RECENT - 1, j as usize);
                return COVERED;
            }
        }
        // Pass 2: no ball covers, so `against_ball` gives `None` (partial) for a ball with a
        // vertex inside or on it and `Some(false)` for the others: the label is partial if
        // some ball has such a vertex, else uncovered. Balls beyond the reach filter have every
        // vertex outside (and are dropped for the subtree); the others are kept with their
        // key for the children's list.
        let mut label = Label::Uncovered;
        for (k, &Cand { q, j }) in candidates[list].iter().enumerate() {
            let d2 = (q - centre).norm_squared();
            // At a uniform radius the test of the paper, (1 + reach)²; else (s + reach)² with
            // s rounded up.
            let far = if UNIFORM {
                far_uniform
            } else {
                let s = balls[j as usize].0 * (1.0 + 1e-12);
                (s + reach) * (s + reach)
            };
            if d2 > far {
                continue; // every vertex of the subtree outside: dropped for it
            }
            if narrow {
                keys.push(sort_key(d2, k as u32));
            } else if label == Label::Partial {
                break; // the children share this list: nothing more to learn
            }
            if label == Label::Uncovered {
                let s2 = ball(j).0;
                if slab.iter().any(|v| (v - q).norm_squared() <= s2) {
                    label = Label::Partial;
                }
            }
        }
        if label != Label::Partial {
            self.keys.clear();
            return (label, 0, 0);
        }
        if !narrow {
            return whole;
        }
        let children_start = self.candidates.len();
        {
            // The children's list: the NEAREST balls to this element's reach centre first, in
            // order (a child's covering ball is nearly always among them), then the rest in the
            // parent's order (a full sort cost a quarter of the run). Keys are distinct (the
            // index is in them), so the rest are exactly the keys above the NEAREST-th.
            let mut head = [u64::MAX; NEAREST];
            for &key in &self.keys {
                if key < head[NEAREST - 1] {
                    let mut at = NEAREST - 1;
                    while at > 0 && head[at - 1] > key {
                        head[at] = head[at - 1];
                        at -= 1;
                    }
                    head[at] = key;
                }
            }
            let h = self.keys.len().min(NEAREST);
            let last = head[h - 1];
            // The low 32 bits of a key: the place in this element's list.
            for &key in head[..h]
                .iter()
                .chain(self.keys.iter().filter(|&&key| key > last))
            {
                let c = self.candidates[node.start + (key as u32) as usize];
                self.candidates.push(c);
            }
        }
        self.keys.clear();
        (
            Label::Partial,
            children_start,
            self.candidates.len() - children_start,
        )
    }

    /// The cuts of the solids that reach the sphere of the particle at `p` of radius `r_i`
    /// (crate docs, "Solid regions"). A half-space whose bound lies beyond the unit ball on
    /// the fluid side (`h <= -1` below) holds no patch and is left out; if none is left, the
    /// particle takes the path without solids.
    fn cut_by(&mut self, solids: &Solids, p: &Point<D>, r_i: f64) {
        self.cuts.clear();
        for h in solids.half_spaces() {
            let axis = h.axis();
            let q = (h.value() - p[axis]) / r_i;
            let slack = SOLID_MARGIN + 4.0 * f64::EPSILON * q.abs();
            let below = h.solid_below();
            // An infinite quotient (a bound far beyond f64 range in units of r_i) stays as it
            // is: its side is exact.
            let (t, reaches) = match (q.is_finite(), below) {
                (false, _) => (q, if below { q > 0.0 } else { q < 0.0 }),
                (true, true) => (q - slack, q > -1.0),
                (true, false) => (q + slack, q < 1.0),
            };
            if reaches {
                self.cuts.push(Cut {
                    axis,
                    below,
                    h: q,
                    t,
                });
            }
        }
    }

    /// The label of Algorithm 3 with the solids of [`Self::cut_by`] covering too (`SOLID`):
    /// covered if a solid holds every slab vertex ([`Cut::holds`]); otherwise the label
    /// against the balls, except that an element no ball touches but a solid does is partial,
    /// its children keeping this element's whole list. Without solids, [`Self::label`].
    #[inline]
    fn label_in<const UNIFORM: bool, const SOLID: bool>(
        &mut self,
        node: &Node<E>,
        slab: &[Point<D>],
        reach: (Point<D>, f64),
        uncoverable: bool,
    ) -> (Label, usize, usize) {
        if !SOLID {
            return self.label::<UNIFORM>(node, slab, reach, uncoverable);
        }
        let mut touched = false;
        for cut in &self.cuts {
            if cut.holds(slab) {
                return (Label::Covered, 0, 0);
            }
            touched |= cut.touches(slab);
        }
        match self.label::<UNIFORM>(node, slab, reach, uncoverable) {
            (Label::Uncovered, _, _) if touched => (Label::Partial, node.start, node.len),
            label => label,
        }
    }

    /// Algorithm 3 for the gathered neighbours: true if boundary. With `SOLID`, the solids
    /// of [`Self::cut_by`] cover too ([`Self::label_in`]), and a particle without neighbours
    /// may be interior (its sphere in the solids).
    fn is_boundary<const UNIFORM: bool, const SOLID: bool>(
        &mut self,
        mesh: &Mesh<D, E>,
        max_depth: u32,
    ) -> bool {
        if !SOLID && self.centres.is_empty() {
            return true;
        }
        let n = self.centres.len();
        // `j as u32` is exact: a set holds at most `u32::MAX` particles.
        self.candidates.clear();
        self.candidates.extend(
            self.centres
                .iter()
                .enumerate()
                .map(|(j, &q)| Cand { q, j: j as u32 }),
        );
        self.stack.clear();
        self.stack.extend(
            mesh.entries[..mesh.first]
                .iter()
                .enumerate()
                .rev()
                .map(|(k, e)| Node {
                    element: e.element,
                    entry: k as u32,
                    start: 0,
                    len: n,
                }),
        );
        while let Some(node) = self.stack.pop() {
            let ((label, start, len), children) = if node.entry == NOT_IN_TABLE {
                let slab = node.element.slab();
                let reach = node.element.reach();
                let label = self.label_in::<UNIFORM, SOLID>(&node, slab.as_ref(), reach, false);
                (label, NOT_IN_TABLE)
            } else {
                let e = &mesh.entries[node.entry as usize];
                let label = self.label_in::<UNIFORM, SOLID>(
                    &node,
                    e.slab.as_ref(),
                    (e.centre, e.reach),
                    e.uncoverable,
                );
                (label, e.children)
            };
            match label {
                Label::Covered => {}                                                // R2
                Label::Uncovered => return true,                                    // R1
                Label::Partial if node.element.depth() >= max_depth => return true, // R4
                Label::Partial => {
                    // R3: the children inherit the neighbours that may still reach them
                    // (`start..start + len` of the arena, left by `label`).
                    self.children.clear();
                    if children == NOT_IN_TABLE {
                        node.element.children(&mut self.children);
                        for &element in self.children.iter().rev() {
                            self.stack.push(Node {
                                element,
                                entry: NOT_IN_TABLE,
                                start,
                                len,
                            });
                        }
                    } else {
                        let first = children as usize;
                        for k in (first..first + mesh.arity).rev() {
                            self.stack.push(Node {
                                element: mesh.entries[k].element,
                                entry: k as u32,
                                start,
                                len,
                            });
                        }
                    }
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundary_core::BoundaryDetector;

    #[test]
    fn a_ball_covers_a_slab_only_with_every_vertex_inside() {
        let slab = [Point::<2>::new(0.0, 0.0), Point::<2>::new(0.5, 0.0)];
        assert_eq!(
            against_ball(&slab, &Point::<2>::new(0.25, 0.0), (1.0, inner(1.0))),
            Some(true)
        );
        assert_eq!(
            against_ball(&slab, &Point::<2>::new(5.0, 0.0), (1.0, inner(1.0))),
            Some(false)
        );
        assert_eq!(
            against_ball(&slab, &Point::<2>::new(1.2, 0.0), (1.0, inner(1.0))),
            None
        );
        // A vertex exactly on the sphere is not inside (margin), nor outside.
        assert_eq!(
            against_ball(&slab, &Point::<2>::new(1.0, 0.0), (1.0, inner(1.0))),
            None
        );
    }

    #[test]
    fn lone_particles_and_pairs_are_boundary() {
        let r = Radius::new(1.0).unwrap_or_else(|_| unreachable!());
        let one = ParticleSet::from_rows(&[[0.0, 0.0, 0.0]]).unwrap_or_else(|_| unreachable!());
        let d = GeDetector::default().detect_3d(&one, r);
        assert!(matches!(d, Ok(d) if d.labels.boundary_count() == 1));
        let two =
            ParticleSet::from_rows(&[[0.0, 0.0], [0.5, 0.0]]).unwrap_or_else(|_| unreachable!());
        let d = GeDetector::default().detect_2d(&two, r);
        assert!(matches!(d, Ok(d) if d.labels.boundary_count() == 2));
    }

    #[test]
    fn a_circle_of_six_neighbours_at_distance_one_covers_the_centre() {
        // Hexagonal neighbours at distance 1 with r = 1: S_0 is covered (each unit ball reaches
        // ±60° around its direction... and beyond), so the centre is interior at a modest depth.
        let mut rows = vec![[0.0, 0.0]];
        for k in 0..6 {
            let t = k as f64 * std::f64::consts::PI / 3.0;
            rows.push([t.cos(), t.sin()]);
        }
        let set = ParticleSet::from_rows(&rows).unwrap_or_else(|_| unreachable!());
        let r = Radius::new(1.0).unwrap_or_else(|_| unreachable!());
        let labels = GeDetector::try_new(GeParams { depth: 8 })
            .unwrap()
            .detect_2d(&set, r)
            .map(|d| d.labels)
            .unwrap_or_else(|_| unreachable!());
        assert!(!labels.is_boundary(0));
        assert!((1..7).all(|i| labels.is_boundary(i)));
    }
}
