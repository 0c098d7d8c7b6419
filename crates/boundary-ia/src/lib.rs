#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Boundary detection with interval arithmetic on a quadtree (2D) or octree (3D): the first
//! method of Sandim, Paiva & Figueiredo, *Simple and reliable boundary detection for meshfree
//! particle methods using interval analysis*, J. Comput. Phys. 2020, Sec. 3.1, Algorithms 1–3
//! and the Appendix (Algorithm 4). Method name `ia`, one parameter `depth` (default 6).
//!
//! **When to use it:** to reproduce the paper's interval method, or where a certificate is
//! enough: it never misses a boundary particle, and may flag a few interior ones near ties
//! (fewer at a larger `depth`). For exact labels use `exact` (accuracy and speed on the same scenes: `BENCHMARKS.md`, written by `cargo xtask sweep`).
//!
//! # Method
//! Particle `i` is interior iff its sphere `S_i` is covered by the closed balls
//! `B_j = {x : f_j(x) <= 0}`, `f_j(x) = |x − p_j|² − r²`, of the particles within `2r`.
//! The bounding box of `B_i` is subdivided adaptively into *query boxes* `Q`:
//!
//! - **Boundary boxes.** Only boxes that meet `S_i` matter. At depth >= 1 (the recursion starts
//!   with the `2^D` children of the bounding box, Algorithm 2) a box meets `S_i` iff the signs of
//!   `f_i` at its vertices differ: the centre `p_i` lies on a grid line of every level, so the
//!   point of a box nearest to `p_i` is a vertex (or `p_i` is in the box), and a box with every
//!   vertex inside `B_i` lies inside it (convexity). A vertex with `f_i = 0` counts as inside.
//! - **Labels.** A boundary box is labelled against each neighbour by the exact image
//!   `f_j(Q) = [min, max]` (Appendix, Algorithm 4: per axis the square of an interval, summed):
//!   *covered* if `max f_j(Q) <= 0` for some `j` (`Q ⊂ B_j`), *uncovered* if `min f_j(Q) > 0`
//!   for every `j` (`Q` misses every ball), *partial* otherwise.
//! - **Rules** (Sec. 3.1, "Avoiding recursion"), with an explicit stack, depth first: R1 an
//!   uncovered boundary box proves a point of `S_i` uncovered: *boundary*; R2 a covered box is
//!   done; R3 a partial box above the maximum depth is split into `2^D` children; R4 a partial
//!   box at the maximum depth makes the particle *boundary*. R1/R2 are checked before R3/R4.
//!   If the stack empties, every boundary box was covered: *interior*.
//!
//! # Certification
//! *Interior* is only answered when every boundary box lies inside some neighbour ball, which
//! proves `S_i` covered; every doubtful case (R4) answers *boundary*. So `ia` never produces a
//! false negative: recall against the exact labels is 1 at every depth. Deeper trees only turn
//! false positives into true negatives: a partial box at depth `d` whose children are all
//! covered at depth `d + 1` is decided there, and a box covered at depth `d` stays covered, so
//! the set of particles labelled interior grows with depth (tested).
//!
//! # Policy: tolerances, ties, duplicates, degenerate input
//! - **Arithmetic.** The box images are computed in coordinates relative to `p_i` and scaled by
//!   `1/r` (so scenes at `1e6` with `r = 0.01` lose nothing to the offset). The interval image
//!   of `|x − q|²` is exact in real arithmetic, so there is no overestimation to tune; its
//!   floating-point rounding is bounded (`IMAGE_ERROR`, about `6e-14`) and rounded outward where
//!   a wrong answer could hide a boundary particle: a box is *covered* only if `max f_j <=
//!   −IMAGE_ERROR`, and a box counts as meeting `S_i` when a corner is within rounding of it.
//!   (The paper computes without outward rounding; near-tie lattices, `tie·(1 ± k·1e-10)` and
//!   ±4 ulps, showed no false negative either way, but only the rounded test is a proof.)
//! - **Ties.** Closed balls, rounded outward: `max f_j(Q) <= −IMAGE_ERROR` counts as covered; a box touching `S_j` from
//!   inside is covered. At an exact tie (a point of `S_i` covered only on the spheres of its
//!   neighbours, as in perfect lattices at `r = a/√2` in 2D or `a·√3/2` in 3D) boxes around the
//!   tie point stay partial at every depth, and R4 labels the particle boundary: for `ia`,
//!   ties are false positives, never false negatives (the exact reference calls them interior).
//! - **Duplicates.** Particles at exactly `p_i` do not cover `S_i` and are skipped. A particle
//!   with no other neighbour within `2r` is boundary (R1 at the first boundary box).
//! - **Neighbours.** From the core grid, closed at `2r`. Children of a box are only tested
//!   against the neighbours that were partial for their parent (a ball missing a box misses its
//!   children; a ball covering it ends the subdivision). Two orderings speed up the search for
//!   a covering ball without changing any label: the ball that covered the previous box is tried
//!   first, and a box's children try its partial balls by increasing `max f_j` over the box (the
//!   ball that came closest to holding the parent first; sorted on 20 mantissa bits). The
//!   `2^D` boxes of depth 1 are labelled in one pass over the neighbours (every box against
//!   every ball, as box by box, with the same floating-point images).
//!
//! # A radius per particle (ours)
//! With per-particle radii ([`boundary_core::ParticleSet::with_radii`]) the frame is scaled by
//! `1/r_i` and neighbour `j` has `f_j(x) = |x − q_j|² − s_j²`, `s_j = r_j/r_i`, among the
//! particles with `|p_i − p_j| <= r_i + r_j` ([`boundary_core::RadiusGrid`]); the tree, the
//! boundary boxes and the rules are unchanged, and the image stays exact in real arithmetic.
//! Its rounding bound grows with `s`: `11u·(D(2 + s)² + s²)`, times 1.5, never below
//! `IMAGE_ERROR` (so equal radii give the uniform labels). Still no false negative (tested
//! against `exact` on two-level sets with radius ratios 2, 4 and 100).
//!
//! # Solid regions
//! With solid half-spaces ([`boundary_core::Solids`], through
//! [`boundary_core::BoundaryDetector::detect_owned_in`] or a [`boundary_core::Domain`]), particle `i` is
//! interior iff every point of `S_i` outside the closed solids is covered by the balls. In the
//! frame of `p_i` a solid `x_a <= c` is `x_a <= h`, `h = (c − p_{i,a})/r_i`, and the part of a
//! query box outside it is again a box: the box with its lower bound on axis `a` raised to `h`.
//! So every box is first clipped to its part outside the solids; a box with no such part is
//! covered (R2), and the others are labelled exactly as above, with the clipped box in place of
//! the box (the boundary-box test, the images, R1–R4). This proves what the method proves
//! without solids: *interior* only when every point of `S_i` outside the solids lies in a
//! ball. No subdivision is spent on the solid's surface itself: a box straddling it is as
//! cheap as any other.
//!
//! **Rounding.** The computed `h` is within `2u` (relative) of the exact quotient, so the clip
//! uses `t = h ∓ (4ε|h| + the smallest normal f64)`, moved out of the solid: the clipped box
//! then holds the exact part outside the solid, and "in the solid" (`hi <= t` for `x_a <= c`)
//! is a proof. The clipped bounds are floats in `[-1, 1]`, so the image's rounding bound and
//! the boundary-box slack hold unchanged. A point of `S_i` exactly on the surface of a solid is
//! covered (the solids are closed), but where nothing else covers it (a sphere touching a solid
//! from inside) the boxes around it are never proven covered and the particle is labelled
//! *boundary*: like ties between balls, a false positive, never a false negative. Particles
//! whose sphere no solid reaches take the code path without solids, so a detection without
//! solids costs what it did.
//!
//! # Hard cases
//! What `ia` returns on the hard cases (the test
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
//! - Near-duplicates 1e-12 apart: their covering is too thin to certify, 18 false positives.
//! - Jittered lattices at the default depth 6: 1–7 false positives.
//!
//! Everything else (exact duplicates, single particles, pairs exactly `2r` apart, lines,
//! collinear and coplanar 3D sets, offsets 1e6 and 1e9, `r` from 1e-9 to 1e9, empty input) has
//! exactly the labels of `exact`.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_ia::{IaDetector, IaParams};
//!
//! // A 5 x 5 x 5 cubic lattice of spacing 1 at r = 1.2: the 3 x 3 x 3 core is interior.
//! let rows: Vec<[f64; 3]> = (0..125)
//!     .map(|k| [(k % 5) as f64, ((k / 5) % 5) as f64, (k / 25) as f64])
//!     .collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let detector = IaDetector::try_new(IaParams { depth: 6 }).unwrap(); // the default depth
//! let detection = detector.detect_3d(&set, Radius::new(1.2).unwrap()).unwrap();
//! assert_eq!(detection.labels.boundary_count(), 125 - 27);
//! ```

use boundary_core::{
    Capabilities, DetectError, Detection, Dim, Job, Labels, Method, NeighbourGrid, ParamSet,
    Params, ParticleSet, Point, Radius, RadiusGrid, Solids, Support, SupportedDim,
};
use rayon::prelude::*;

/// Default maximum subdivision depth (the paper's experiments use 6 for the tables).
pub const DEFAULT_DEPTH: u32 = 6;

/// Largest accepted depth: `2^-16` of `r` is far below any particle spacing.
pub const MAX_DEPTH: u32 = 16;

boundary_core::declare_params! {
    /// The parameters of `ia` (string form: `--set depth=…`, see `boundary::registry`).
    #[derive(Debug, Clone, PartialEq, Eq)]
    pub struct IaParams for "ia" {
        /// Maximum subdivision depth, in `1..=`[`MAX_DEPTH`]; default [`DEFAULT_DEPTH`].
        /// Deeper: fewer false positives, slower.
        pub depth: u32 = DEFAULT_DEPTH, check::int_in(1, MAX_DEPTH),
            "maximum quadtree/octree depth (JCP 2020 Sec. 3.1, rules R1-R4); deeper: fewer \
             false positives, slower";
    }
}

/// The interval-arithmetic detector (`ia`). See the crate documentation.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct IaDetector {
    params: IaParams,
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(IaDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(IaDetector, IaParams);

impl Method for IaDetector {
    const NAME: &'static str = "ia";

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
        Ok(detect_with(
            job.set,
            job.owned,
            job.r,
            self.params.depth,
            job.solids,
        )?)
    }
}

/// Classifies the first `count` particles of `set` (all of them serve as neighbours), the
/// closed half-spaces of `solids` covering too (their axes are those of the set).
fn detect_with<const D: usize>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    depth: u32,
    solids: &Solids,
) -> Result<Detection, boundary_core::CoreError> {
    let positions = set.positions();
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
        .map_init(Scratch::<D>::default, |scratch, i| {
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
                        scratch.is_boundary_in::<true>(depth)
                    } else {
                        scratch.is_boundary_in::<false>(depth)
                    };
                }
            }
            // Monomorphised twice: at a uniform radius every ball is (1, IMAGE_ERROR), as
            // constants, so that path costs what it did before per-particle radii.
            if radii.is_none() {
                scratch.is_boundary::<true>(depth)
            } else {
                scratch.is_boundary::<false>(depth)
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

/// A query box in scaled coordinates: the cube `[lo, lo + size]^D`, its depth, and the range of
/// `Scratch::candidates` holding the neighbours still to test against it.
#[derive(Debug, Clone, Copy)]
struct QueryBox<const D: usize> {
    lo: Point<D>,
    size: f64,
    depth: u32,
    start: usize,
    len: usize,
}

/// Per-thread working memory.
#[derive(Debug)]
struct Scratch<const D: usize> {
    /// Neighbour centres `q_j = (p_j − p_i)/r`, in the grid's order (the depth-1 boxes test
    /// every one; their children get the partial ones sorted).
    centres: Vec<Point<D>>,
    /// Per neighbour with per-particle radii: its squared radius in units of `r_i²` and the
    /// bound on the rounding of its box images (at a uniform radius: `(1, IMAGE_ERROR)`, not
    /// stored).
    balls: Vec<(f64, f64)>,
    /// Neighbours from [`RadiusGrid::scaled_neighbours`] (per-particle radii).
    scaled: Vec<(f64, Point<D>, f64)>,
    /// Arena of neighbour index lists, shared by sibling boxes.
    candidates: Vec<u32>,
    stack: Vec<QueryBox<D>>,
    /// Straddling neighbours of the current box with their `max f_j`, for ordering.
    keyed: Vec<u64>,
    /// Per orthant of the first level, the keys of its straddling balls ([`sort_key`]).
    orthant_keys: Vec<Vec<u64>>,
    /// Per orthant of the first level, the image of the current ball over it.
    sums: Vec<(f64, f64)>,
    /// Per orthant of the first level, whether a ball holds it.
    covered: Vec<bool>,
    /// The neighbour that covered the last covered box: tried first.
    last_cover: usize,
    /// The solid half-spaces that reach the current particle's sphere ([`Cut`]).
    cuts: Vec<Cut>,
}

impl<const D: usize> Default for Scratch<D> {
    fn default() -> Self {
        Scratch {
            centres: Vec::new(),
            balls: Vec::new(),
            scaled: Vec::new(),
            candidates: Vec::new(),
            stack: Vec::new(),
            keyed: Vec::new(),
            orthant_keys: Vec::new(),
            sums: Vec::new(),
            covered: Vec::new(),
            last_cover: usize::MAX,
            cuts: Vec::new(),
        }
    }
}

/// The image `[min, max]` of `t ↦ (t − c)²` over `[lo, hi]` (Appendix, `square`).
///
/// Branch-free: with `a = lo − c <= b = hi − c`, the point of `[a, b]` nearest 0 is
/// `max(a, 0) + min(b, 0)` (`a` if `a >= 0`, `b` if `b <= 0`, else 0) and the farthest is an
/// end. The same floating-point values as the case analysis `a >= 0`: `(a², b²)`; `b <= 0`:
/// `(b², a²)`; else `(0, max(a², b²))`.
#[inline]
fn square(lo: f64, hi: f64, c: f64) -> (f64, f64) {
    let (a, b) = (lo - c, hi - c);
    let near = max(a, 0.0) + min(b, 0.0);
    (near * near, max(a * a, b * b))
}

/// `max` and `min` of two numbers that are not NaN (one `maxsd`/`minsd`; `f64::max` also
/// handles NaN, which cannot occur here: every input is finite).
#[inline(always)]
fn max(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

#[inline(always)]
fn min(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// The key of a straddling ball for ordering a box's children: `max f_j` over the box, as
/// the high 32 bits of an order-preserving integer image of the f64 (sign-magnitude to two's
/// complement order, as `f64::total_cmp`), the neighbour index in the low 32. Sorting these
/// integers orders by `max f_j` truncated to 20 mantissa bits (ties by index); the
/// order only speeds up the search for a covering ball, it changes no label.
#[inline]
fn sort_key(max_f: f64, j: u32) -> u64 {
    let bits = max_f.to_bits();
    let ordered = if bits >> 63 == 1 {
        !bits
    } else {
        bits | (1 << 63)
    };
    (ordered & !0xffff_ffff) | u64::from(j)
}

/// How many of a box's partial balls are put in order for its children (smallest `max f_j`
/// first); the rest follow in the box's order.
const NEAREST: usize = 8;

/// Appends the neighbour indices of `keys` ([`sort_key`]) to `out`: the [`NEAREST`] smallest
/// keys in order, then the others in their order (keys are distinct: the index is in them, so
/// the others are exactly those above the last of the head). A full sort cost 17% of the run
/// on dense sets; the head holds the covering ball of nearly every child.
fn extend_nearest_first(out: &mut Vec<u32>, keys: &[u64]) {
    let mut head = [u64::MAX; NEAREST];
    for &key in keys {
        if key < head[NEAREST - 1] {
            let mut at = NEAREST - 1;
            while at > 0 && head[at - 1] > key {
                head[at] = head[at - 1];
                at -= 1;
            }
            head[at] = key;
        }
    }
    let h = keys.len().min(NEAREST);
    let Some(&last) = head[..h].last() else {
        return;
    };
    // The low 32 bits of a key: the index.
    out.extend(head[..h].iter().map(|&key| key as u32));
    out.extend(
        keys.iter()
            .filter(|&&key| key > last)
            .map(|&key| key as u32),
    );
}

/// How a box relates to one ball.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Relation {
    Inside,
    Outside,
    Straddles,
}

/// The image of `f(x) = |x − c|² − s²` over the box, classified (Appendix, Algorithm 4);
/// `ball = (s², rounding bound)`.
#[inline]
fn relation<const D: usize>(lo: &Point<D>, size: f64, c: &Point<D>, ball: (f64, f64)) -> Relation {
    classify(image(lo, size, c, ball.0), ball.1)
}

/// The image `[min, max]` of `f(x) = |x − c|² − s2` over the box (Appendix, Algorithm 4;
/// `s2 = 1` at a uniform radius).
#[inline]
fn image<const D: usize>(lo: &Point<D>, size: f64, c: &Point<D>, s2: f64) -> (f64, f64) {
    let (mut min, mut max) = (-s2, -s2);
    for a in 0..D {
        let (s_min, s_max) = square(lo[a], lo[a] + size, c[a]);
        min += s_min;
        max += s_max;
    }
    (min, max)
}

/// Bound on the rounding error of [`image`]'s `max` (and `min`) for a box in `[-1, 1]^D` and
/// a centre within distance 2 (crate docs, "Arithmetic"): every difference `lo − c` carries the
/// rounding of `c = fl(fl(p_j − p_i)/r)` (relative `2u`) and its own (`u`), so each square is
/// within a relative `7u` of `(lo − c_true)²` (at most 9 in magnitude), and the sum of `D + 1`
/// terms adds `(D + 1)u` of at most `9D + 1`: below `(9D + 1)·(7u + 4u) <= 28·11u` in 3D.
/// Taken as `512u ≈ 5.7e-14`.
///
/// With a radius per particle the ball of `j` has radius `s = r_j/r_i` and its centre lies
/// within `1 + s`: each square is at most `(2 + s)²`, `s²` carries `3u` of rounding (`s` itself
/// `u`), so the bound is `11u·(D(2 + s)² + s²)`, taken with a factor 1.5 and never below
/// `IMAGE_ERROR` ([`image_error`]).
const IMAGE_ERROR: f64 = 512.0 * (f64::EPSILON / 2.0);

/// The rounding bound of a ball of radius `s` (units of `r_i`); [`IMAGE_ERROR`] for `s <= 1`.
fn image_error(dim: usize, s: f64) -> f64 {
    let u = f64::EPSILON / 2.0;
    IMAGE_ERROR.max(1.5 * 11.0 * u * (dim as f64 * (2.0 + s) * (2.0 + s) + s * s))
}

/// The relation of a box to a ball from the image of `f` over the box. *Inside* needs
/// `max <= −error` (the ball's rounding bound): outward rounding, so that a box counted
/// covered is covered in exact arithmetic for the given input (no false negative from
/// rounding).
#[inline]
fn classify((min, max): (f64, f64), error: f64) -> Relation {
    if max <= -error {
        Relation::Inside
    } else if min > 0.0 {
        Relation::Outside
    } else {
        Relation::Straddles
    }
}

/// Whether the box meets the unit sphere `S_i` (depth >= 1 boxes only; see the crate docs):
/// the exact image `[min, max]` of `|x|²` over the box contains 1. At depth >= 1 a box lies in
/// one closed orthant (`p_i` is on a grid line of every level), so `min` and `max` are the
/// values at its nearest and farthest vertex: the same as "the signs of `f_i` at the vertices
/// differ", with 2 vertices instead of `2^D`.
#[inline]
fn is_boundary_box<const D: usize>(lo: &Point<D>, size: f64) -> bool {
    let (mut lo2, mut hi2) = (0.0, 0.0);
    for a in 0..D {
        let (s_min, s_max) = square(lo[a], lo[a] + size, 0.0);
        lo2 += s_min;
        hi2 += s_max;
    }
    // The corners are exact dyadic numbers; a sum carries at most (D + 1)u of rounding,
    // relative. A vertex within that of the sphere counts as on both sides: the box is kept.
    lo2 <= 1.0 + 8.0 * f64::EPSILON * max(lo2, 1.0)
        && hi2 > 1.0 - 8.0 * f64::EPSILON * max(hi2, 1.0)
}

/// A solid half-space in the frame of particle `i` (scaled by `1/r_i`): on axis `axis`, the
/// solid is `x <= h` (`below`) or `x >= h` for the exact `h = (c − p_i)/r_i`, and `t` is a
/// float on the fluid side of `h` or on it: `t <= h` below, `t >= h` above (crate docs,
/// "Solid regions"). The fluid part of a box, `x > h` (`x < h`), lies in the box clipped to
/// `x >= t` (`x <= t`), and a box with `hi <= t` (`lo >= t`) lies in the solid.
#[derive(Debug, Clone, Copy)]
struct Cut {
    axis: usize,
    below: bool,
    t: f64,
}

/// The relative rounding `t` is moved by, away from the solid: `h` is `fl(fl(c − p)/r)`, at
/// most `2u` relative from the exact quotient, and `t = fl(h ∓ slack)` rounds once more;
/// `4ε = 8u` relative, plus the smallest normal number against underflow, covers both.
const CUT_SLACK: f64 = 4.0 * f64::EPSILON;

/// The fluid part of the box `[lo, lo + size]^D` clipped by every cut: `None` if it is empty
/// (the box lies in the solids), else the bounds `(lo, hi)` of a box holding it.
#[inline]
fn clip<const D: usize>(lo: &Point<D>, size: f64, cuts: &[Cut]) -> Option<(Point<D>, Point<D>)> {
    let mut lo = *lo;
    let mut hi = lo.map(|x| x + size);
    for c in cuts {
        if c.below {
            lo[c.axis] = max(lo[c.axis], c.t);
        } else {
            hi[c.axis] = min(hi[c.axis], c.t);
        }
    }
    // Checked once every cut is applied: two cuts on one axis may leave nothing between them.
    let empty = cuts.iter().any(|c| {
        if c.below {
            hi[c.axis] <= c.t
        } else {
            lo[c.axis] >= c.t
        }
    });
    if empty {
        None
    } else {
        Some((lo, hi))
    }
}

/// [`image`] over the box `[lo, hi]` (a clipped box: its bounds are floats in `[-1, 1]`, so
/// the rounding bound of [`image`] holds unchanged).
#[inline]
fn image_between<const D: usize>(
    lo: &Point<D>,
    hi: &Point<D>,
    c: &Point<D>,
    s2: f64,
) -> (f64, f64) {
    let (mut min, mut max) = (-s2, -s2);
    for a in 0..D {
        let (s_min, s_max) = square(lo[a], hi[a], c[a]);
        min += s_min;
        max += s_max;
    }
    (min, max)
}

/// [`is_boundary_box`] for the box `[lo, hi]`, any box in `[-1, 1]^D`: the exact image of
/// `|x|²` over a box is the sum of the per-axis images, and a box meets `S_i` iff it contains 1.
/// The squares of clipped bounds round (relative `u` each) where dyadic corners did not; the
/// same slack of `16u` still covers the sum.
#[inline]
fn meets_sphere<const D: usize>(lo: &Point<D>, hi: &Point<D>) -> bool {
    let (mut lo2, mut hi2) = (0.0, 0.0);
    for a in 0..D {
        let (s_min, s_max) = square(lo[a], hi[a], 0.0);
        lo2 += s_min;
        hi2 += s_max;
    }
    lo2 <= 1.0 + 8.0 * f64::EPSILON * max(lo2, 1.0)
        && hi2 > 1.0 - 8.0 * f64::EPSILON * max(hi2, 1.0)
}

impl<const D: usize> Scratch<D> {
    /// Scaled neighbour centres of particle `i`, duplicates of `p_i` skipped. Not sorted: the
    /// depth-1 boxes test every neighbour, and their children get the partial ones sorted by
    /// how close they come to holding the box (sorting here cost 5% and gained nothing).
    fn gather(&mut self, positions: &[Point<D>], grid: &NeighbourGrid<D>, i: usize, r: f64) {
        let p = positions[i];
        let centres = &mut self.centres;
        centres.clear();
        grid.for_each_within(&p, 2.0 * r, |j, d2| {
            if d2 > 0.0 {
                centres.push((positions[j] - p) / r);
            }
        });
        self.last_cover = usize::MAX;
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
                .map(|&(_, _, s)| (s * s, image_error(D, s))),
        );
        self.last_cover = usize::MAX;
    }

    /// Ball `j` as `(s², rounding bound)`: constants at a uniform radius (`UNIFORM`).
    #[inline]
    fn ball<const UNIFORM: bool>(&self, j: usize) -> (f64, f64) {
        if UNIFORM {
            (1.0, IMAGE_ERROR)
        } else {
            self.balls[j]
        }
    }

    fn is_boundary<const UNIFORM: bool>(&mut self, max_depth: u32) -> bool {
        if self.centres.is_empty() {
            return true;
        }
        self.candidates.clear();
        self.stack.clear();
        // Algorithm 2: start with the 2^D children of the bounding box [-1, 1]^D.
        if self.first_level::<UNIFORM>(max_depth) {
            return true;
        }
        while let Some(q) = self.stack.pop() {
            if !is_boundary_box(&q.lo, q.size) {
                continue;
            }
            // The ball that covered the previous box first: consecutive boxes of the depth-first
            // order are neighbours, often inside the same ball. Only the order of the tests
            // changes, never the label (covered if any ball covers).
            if let Some(c) = self.centres.get(self.last_cover) {
                if relation(&q.lo, q.size, c, self.ball::<UNIFORM>(self.last_cover))
                    == Relation::Inside
                {
                    continue; // R2
                }
            }
            let list_start = self.candidates.len();
            let mut covered = false;
            self.keyed.clear();
            for k in q.start..q.start + q.len {
                let j = self.candidates[k];
                let ball = self.ball::<UNIFORM>(j as usize);
                let f = image(&q.lo, q.size, &self.centres[j as usize], ball.0);
                match classify(f, ball.1) {
                    Relation::Inside => {
                        covered = true;
                        self.last_cover = j as usize;
                        break;
                    }
                    Relation::Straddles => self.keyed.push(sort_key(f.1, j)),
                    Relation::Outside => {}
                }
            }
            if covered {
                continue; // R2
            }
            if self.keyed.is_empty() || q.depth >= max_depth {
                // R1 (uncovered) or R4 (partial at the maximum depth).
                return true;
            }
            // R3. The children try first the balls that come closest to holding this box
            // (smallest max f_j): the likeliest to cover them.
            extend_nearest_first(&mut self.candidates, &self.keyed);
            let partial = self.candidates.len() - list_start;
            self.push_children(&q.lo, q.size, q.depth, list_start, partial);
        }
        false
    }

    /// The first level of Algorithm 2, the `2^D` orthants of `[-1, 1]^D` (depth 1; each meets
    /// `S_i`), labelled against every neighbour in one pass: true if R1 or R4 decides
    /// *boundary* there, else the children of the partial orthants are on the stack with their
    /// partial balls. Every orthant is tested against every neighbour (a covering ball at this
    /// depth is rare, so the loop of [`Self::is_boundary`] would rarely stop early), and the
    /// orthants share per axis the images over the halves `[-1, 0]` and `[0, 1]`. The sums run
    /// in the order of [`image`] (`−s² + x + y + z`), so every image and label is the same
    /// floating-point value as box by box.
    fn first_level<const UNIFORM: bool>(&mut self, max_depth: u32) -> bool {
        let m = 1usize << D;
        self.orthant_keys.resize_with(m, Vec::new);
        for keys in &mut self.orthant_keys {
            keys.clear();
        }
        self.sums.resize(m, (0.0, 0.0));
        self.covered.clear();
        self.covered.resize(m, false);
        for (j, c) in self.centres.iter().enumerate() {
            let j = u32::try_from(j).expect("fewer than 2^32 neighbours");
            let (s2, error) = self.ball::<UNIFORM>(j as usize);
            // sums[o] = image over orthant o (bit a of o: the half [0, 1] on axis a), built
            // axis by axis.
            self.sums[0] = (-s2, -s2);
            for a in 0..D {
                let low = square(-1.0, 0.0, c[a]);
                let high = square(0.0, 1.0, c[a]);
                for k in 0..1usize << a {
                    let (min, max) = self.sums[k];
                    self.sums[k | 1 << a] = (min + high.0, max + high.1);
                    self.sums[k] = (min + low.0, max + low.1);
                }
            }
            for (o, &f) in self.sums.iter().enumerate() {
                match classify(f, error) {
                    Relation::Inside => {
                        self.covered[o] = true;
                        self.last_cover = j as usize;
                    }
                    Relation::Straddles => self.orthant_keys[o].push(sort_key(f.1, j)),
                    Relation::Outside => {}
                }
            }
        }
        for o in 0..m {
            if self.covered[o] {
                continue; // R2
            }
            if self.orthant_keys[o].is_empty() || max_depth <= 1 {
                return true; // R1 or R4
            }
            // R3, the children trying first the balls closest to holding the orthant.
            let start = self.candidates.len();
            extend_nearest_first(&mut self.candidates, &self.orthant_keys[o]);
            let lo = Point::<D>::from_fn(|a, _| if o >> a & 1 == 1 { 0.0 } else { -1.0 });
            let len = self.candidates.len() - start;
            self.push_children(&lo, 1.0, 1, start, len);
        }
        false
    }

    /// The cuts of the solids that reach the sphere of the particle at `p` of radius `r_i`.
    /// A half-space whose bound lies beyond the unit ball on the fluid side (`t <= -1` below)
    /// meets no box's fluid part and is left out; if none is left, the particle takes the path
    /// without solids.
    fn cut_by(&mut self, solids: &Solids, p: &Point<D>, r_i: f64) {
        self.cuts.clear();
        for h in solids.half_spaces() {
            let axis = h.axis();
            let q = (h.value() - p[axis]) / r_i;
            let slack = CUT_SLACK * q.abs() + f64::MIN_POSITIVE;
            // An infinite quotient (a bound far beyond f64 range in units of r_i) stays as it
            // is: its side is exact.
            let below = h.solid_below();
            let t = match (q.is_finite(), below) {
                (false, _) => q,
                (true, true) => q - slack,
                (true, false) => q + slack,
            };
            let reaches = if below { t > -1.0 } else { t < 1.0 };
            if reaches {
                self.cuts.push(Cut { axis, below, t });
            }
        }
    }

    /// [`Self::is_boundary`] with the solids of [`Self::cut_by`] covering too: every box is
    /// first clipped to its fluid part ([`clip`]); a box with none is covered by the solids
    /// (R2), the others are labelled as their clipped box against the balls. The first level
    /// is labelled box by box, and a particle without neighbours may be interior (its sphere in
    /// the solids).
    fn is_boundary_in<const UNIFORM: bool>(&mut self, max_depth: u32) -> bool {
        self.candidates.clear();
        self.stack.clear();
        let n = u32::try_from(self.centres.len()).expect("fewer than 2^32 neighbours");
        self.candidates.extend(0..n);
        // Algorithm 2: the 2^D children of the bounding box [-1, 1]^D.
        self.push_children(&Point::<D>::from_element(-1.0), 2.0, 0, 0, n as usize);
        while let Some(q) = self.stack.pop() {
            let Some((lo, hi)) = clip(&q.lo, q.size, &self.cuts) else {
                continue; // R2, by the solids
            };
            if !meets_sphere(&lo, &hi) {
                continue;
            }
            if let Some(c) = self.centres.get(self.last_cover) {
                let (s2, error) = self.ball::<UNIFORM>(self.last_cover);
                if classify(image_between(&lo, &hi, c, s2), error) == Relation::Inside {
                    continue; // R2
                }
            }
            let list_start = self.candidates.len();
            let mut covered = false;
            self.keyed.clear();
            for k in q.start..q.start + q.len {
                let j = self.candidates[k];
                let (s2, error) = self.ball::<UNIFORM>(j as usize);
                let f = image_between(&lo, &hi, &self.centres[j as usize], s2);
                match classify(f, error) {
                    Relation::Inside => {
                        covered = true;
                        self.last_cover = j as usize;
                        break;
                    }
                    Relation::Straddles => self.keyed.push(sort_key(f.1, j)),
                    Relation::Outside => {}
                }
            }
            if covered {
                continue; // R2
            }
            if self.keyed.is_empty() || q.depth >= max_depth {
                // R1 (the clipped box, which meets S_i, misses every ball) or R4.
                return true;
            }
            // R3: the children of the whole box, each clipped in turn.
            extend_nearest_first(&mut self.candidates, &self.keyed);
            let partial = self.candidates.len() - list_start;
            self.push_children(&q.lo, q.size, q.depth, list_start, partial);
        }
        false
    }

    fn push_children(&mut self, lo: &Point<D>, size: f64, depth: u32, start: usize, len: usize) {
        let half = 0.5 * size;
        for child in 0..(1usize << D) {
            let mut c = *lo;
            for a in 0..D {
                if child >> a & 1 == 1 {
                    c[a] += half;
                }
            }
            self.stack.push(QueryBox {
                lo: c,
                size: half,
                depth: depth + 1,
                start,
                len,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_is_the_exact_image() {
        for (lo, hi, c) in [
            (1.0, 2.0, 0.0),
            (-2.0, -1.0, 0.0),
            (-1.0, 3.0, 0.5),
            (0.0, 1.0, 1.0),
        ] {
            let (min, max) = square(lo, hi, c);
            let samples: Vec<f64> = (0..=1000)
                .map(|k| lo + (hi - lo) * k as f64 / 1000.0)
                .map(|t: f64| (t - c) * (t - c))
                .collect();
            let smin = samples.iter().copied().fold(f64::INFINITY, f64::min);
            let smax = samples.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            assert!((min - smin).abs() < 1e-5 && (max - smax).abs() < 1e-12);
            assert!(min <= smin && max >= smax);
        }
    }

    #[test]
    fn relation_of_boxes_to_the_unit_ball() {
        let o = Point::<2>::zeros();
        assert_eq!(
            relation(&Point::<2>::new(-0.5, -0.5), 1.0, &o, (1.0, IMAGE_ERROR)),
            Relation::Inside
        );
        assert_eq!(
            relation(&Point::<2>::new(1.0, 1.0), 1.0, &o, (1.0, IMAGE_ERROR)),
            Relation::Outside
        );
        assert_eq!(
            relation(&Point::<2>::new(0.5, 0.5), 1.0, &o, (1.0, IMAGE_ERROR)),
            Relation::Straddles
        );
        // Touching from outside at one point: (1, 0) is in the closed ball.
        assert_eq!(
            relation(&Point::<2>::new(1.0, -0.5), 1.0, &o, (1.0, IMAGE_ERROR)),
            Relation::Straddles
        );
    }

    #[test]
    fn boundary_boxes_are_the_boxes_meeting_the_sphere() {
        // Every dyadic box at depths 1..=5 in 2D: the vertex test agrees with a dense sampling.
        for depth in 1..=5u32 {
            let k = 1usize << depth;
            let size = 2.0 / k as f64;
            for ix in 0..k {
                for iy in 0..k {
                    let lo = Point::<2>::new(-1.0 + ix as f64 * size, -1.0 + iy as f64 * size);
                    let mut any_in = false;
                    let mut any_out = false;
                    for s in 0..=40 {
                        for t in 0..=40 {
                            let x = lo + Point::<2>::new(s as f64, t as f64) * (size / 40.0);
                            if x.norm_squared() <= 1.0 {
                                any_in = true;
                            } else {
                                any_out = true;
                            }
                        }
                    }
                    assert_eq!(
                        is_boundary_box(&lo, size),
                        any_in && any_out,
                        "{lo:?} {size}"
                    );
                }
            }
        }
    }
}
