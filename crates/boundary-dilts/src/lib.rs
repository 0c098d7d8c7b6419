#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Reference r-boundary detection by explicit covering: the method of Dilts (2000) in 2D and of
//! Haque & Dilts (2007) in 3D, the slow "ground truth" against which the JCP paper (Table 3)
//! and the thesis (Table 8) compare their timings.
//!
//! # Definition
//! Particle `i` at `p_i` with resolution `r` is *interior* iff its sphere `S_i` (radius `r`) is
//! covered by the closed balls `B_j` of radius `r` of the other particles within `2r`; otherwise
//! it is *boundary* (Sandim et al., JCP 2020, Sec. 2). This crate decides that covering directly,
//! independently of the Voronoi-cell argument of `boundary-exact`.
//!
//! # What a neighbour covers
//! Work in coordinates relative to `p_i` and scaled by `1/r`: `S_i` is the unit sphere and
//! neighbour `j` sits at `q_j = (p_j − p_i)/r`, `d_j = |q_j| ∈ (0, 2]`. A unit vector `x` is in
//! `B_j` iff `|x − q_j|² <= 1`, i.e. `x·u_j >= d_j/2` with `u_j = q_j/d_j`: the ball covers the
//! closed *cap* (an *arc* in 2D) centred on `u_j` with angular radius `α_j = acos(d_j/2)`.
//! Every cap is smaller than a hemisphere (`d_j > 0`); a neighbour at exactly `2r` gives a
//! single point (`α_j = 0`).
//!
//! # 2D: arcs (Dilts 2000), module `arcs`
//! `S_i` is covered iff the arcs `[θ_j − α_j, θ_j + α_j]` cover the circle. The arcs are sorted
//! by start and swept twice around the circle; the sweep also gives the largest uncovered gap,
//! reported as the margin (see [`ARC_MARGIN`](crate#margins)).
//!
//! # 3D: caps (Haque & Dilts 2007), module `caps`
//! For closed caps `C_j` on the unit sphere `S`, each smaller than a hemisphere and pairwise
//! distinct, `S` is covered iff
//! - **(a)** there is at least one cap,
//! - **(b)** every point where two cap circles `∂C_j`, `∂C_k` meet lies in a third cap `C_l`,
//!   `l ∉ {j, k}`, and
//! - **(c)** every circle `∂C_j` that meets no other circle lies in another cap.
//!
//! *Proof sketch.* Let `U = S \ ∪ C_j`, the uncovered set; it is open (finitely many closed
//! caps).
//!
//! *Necessity.* (a) is clear. Near a point `v` on two circles the caps `C_j`, `C_k` leave a
//! non-empty sector outside both (a crossing splits a neighbourhood of `v` into four sectors; at a
//! tangency there are points outside both as well); if `S` is covered, points of that sector
//! arbitrarily close to `v` lie in the finitely many other caps, so one closed cap `C_l`,
//! `l ∉ {j, k}`, contains points accumulating at `v`, hence contains `v`. For (c), points just
//! outside `C_j` next to a point `w ∈ ∂C_j` are covered by caps other than `C_j`, so (same
//! argument) some `C_l ∋ w`; since `∂C_l` does not meet the connected circle `∂C_j`, the circle
//! lies entirely in the interior of `C_l` or entirely outside `C_l`, and `w ∈ C_l` rules out the
//! latter. This is also why testing **one point** of an isolated circle suffices.
//!
//! *Sufficiency (generic position).* Suppose (a) holds and `U ≠ ∅`. Then `U ≠ S`; take a point
//! `y` on the boundary of a component `W` of `U`. `y` is covered but lies in the interior of no
//! cap, so it lies on the circles of the caps containing it, and on at least one. If it lies on
//! two, it is a pairwise intersection point in no third cap's interior. Otherwise, near each such
//! `y` only one cap is present and `∂W` coincides locally with that circle `∂C_j`: the part of
//! `∂C_j` in `∂W` is open and closed in the circle, hence the whole circle, which then meets no
//! other circle transversally and lies in no other cap's interior. So a violation of (b) or (c)
//! appears, with "in a third cap" read as "in the *interior* of a third cap".
//!
//! The two readings differ only when a pairwise intersection point lies exactly on a third
//! circle: a *tie*, where three or more circles pass through one point (a Voronoi vertex of
//! `p_i` and three neighbours lying exactly on `S_i`). This crate uses the closed reading, which
//! makes ties interior, the same rule as `boundary-exact`. (In a degenerate arrangement whose
//! uncovered region has only such tie points as corners, the closed reading would say interior
//! too; that needs cospherical points by construction and never happened on the shared scenes.)
//!
//! The 3D test therefore computes, for every pair of caps whose circles meet (pairs whose
//! centres are farther apart than `α_j + α_k`, or nested caps, are pruned first), the one or two
//! intersection points and looks for a third cap containing each (early exit, largest caps
//! first); a point in no third cap is a *witness*: the particle is boundary.
//!
//! *Speed.* Caps are sorted largest first (neighbours nearest first). The test runs first on the
//! 16 largest caps, then 32, 64, … ("levels"): if the first `m` caps already cover `S` the
//! particle is interior; points left uncovered by them are tested against the remaining caps, and
//! one uncovered by every cap is a witness. Only particles whose small subsets do not decide go
//! on to the full quadratic test.
//!
//! # Policy: tolerances, ties, duplicates, degenerate input
//! - **Covering tolerance** ([`COVER_TOLERANCE`]): a point `x` of `S_i` counts as covered by cap
//!   `j` iff `x·u_j >= d_j/2 − 1e-12`; equivalently the neighbour balls are enlarged to radius
//!   `r·sqrt(1 + 2·1e-12·d_j) ≈ r(1 + 1e-12·d_j)`. Exact ties (a point of `S_i` at exactly `r`
//!   from a neighbour, as in perfect lattices at `r = a/√2` in 2D and `r = a·√3/2` in 3D) are
//!   therefore interior. In 2D the same rule widens each arc, so an arc gap narrower than about
//!   `1e-12/sin α` counts as covered.
//! - **Duplicates.** Particles at exactly `p_i` (`d = 0`) do not cover `S_i` and are skipped; two
//!   coincident particles alone are both boundary. Neighbours closer to one another than
//!   [`TWIN_TOLERANCE`]`·r` give caps that coincide within the covering tolerance (a pair of
//!   identical circles has no isolated intersection points, and a near-twin would "cover" its
//!   twin's intersection points within tolerance): only the nearest of them is kept.
//! - **Closedness at `2r`.** Neighbours at exactly `2r` are kept; their cap is a point. In 3D
//!   caps of angular radius below about `1e-4` (neighbours within about `1e-8·r` of `2r`) are
//!   then dropped: they are too thin for the covering test to step off, and a point never
//!   decides a covering (a lone pair exactly `2r` apart is boundary, as in `boundary-exact`).
//! - **Near-tangent circles** ([`TANGENT_TOLERANCE`]): two circles that miss each other by less
//!   than the tolerance are treated as touching at one point; that only adds points to test.
//! - **Floating point.** Intersection points are computed to about `1e-16/sin θ_jk` (`θ_jk` the
//!   angle between the cap centres); the covering tolerance absorbs this except for nearly
//!   concentric caps, which are near-twins or nested in practice.
//! - **Far offsets.** Only differences `p_j − p_i` enter the geometry, scaled by `1/r`, so scenes
//!   at `1e6` with `r = 0.01` are classified as accurately as the input differences allow.
//!
//! # Margins
//! In 2D, [`Detection::margin`] holds, per particle, `r · max_{x ∈ S_i} min_j (∠(x, u_j) − α_j)`
//! computed for the tolerance-widened arcs: half the width of the largest uncovered arc of `S_i`
//! (as an arc length, units of length) when positive, minus half the narrowest overlap between
//! consecutive arcs when negative. The label is exactly `margin > 0`. A particle with no
//! neighbour has margin `π·r`. In 3D no margin is reported (`None`).
//!
//! # Hard cases
//! What `dilts` returns on the hard cases of issue 11 (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`).
//! The same labels as `exact` on every case: ties and near-ties (±4 ulps) interior, exact
//! duplicates as single particles, near-duplicates 1e-12 apart as neighbours, degenerate sets
//! (single particles, pairs exactly `2r` apart, lines, collinear and coplanar 3D sets) all
//! boundary, far offsets and `r` from 1e-9 to 1e9 unchanged, empty input empty. Two false
//! negatives found on these cases were bugs and are fixed: the point cap of a neighbour exactly
//! `2r` away, and externally tangent caps counted as crossing.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_dilts::DiltsDetector;
//!
//! // A 5 x 5 x 5 cubic lattice of spacing 1 at r = 1.2: the 3 x 3 x 3 core is interior.
//! let rows: Vec<[f64; 3]> = (0..125)
//!     .map(|k| [(k % 5) as f64, ((k / 5) % 5) as f64, (k / 25) as f64])
//!     .collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let detection = DiltsDetector.detect_3d(&set, Radius::new(1.2).unwrap()).unwrap();
//! assert_eq!(detection.labels.boundary_count(), 125 - 27);
//! assert!(!detection.labels.is_boundary(62)); // the centre
//! ```
//!
//! # References
//! - G. A. Dilts, Moving least-squares particle hydrodynamics II: conservation and boundaries,
//!   Int. J. Numer. Meth. Eng. 48(10), 2000.
//! - A. Haque, G. A. Dilts, Three-dimensional boundary detection for particle methods,
//!   J. Comput. Phys. 226(2), 2007.

mod arcs;
mod caps;

use boundary_core::{
    AnyParticleSet, BoundaryDetector, DetectError, Detection, Labels, NeighbourGrid, ParamError,
    Params, ParticleSet, Point, Radius,
};
use rayon::prelude::*;

/// Covering tolerance, in units of the scaled cap test `x·u_j >= d_j/2`: a point of `S_i` is
/// covered by neighbour `j` iff `x·u_j >= d_j/2 − COVER_TOLERANCE`. Makes exact ties interior.
pub const COVER_TOLERANCE: f64 = 1e-12;

/// Neighbours closer than `TWIN_TOLERANCE · r` to an already kept (nearer) neighbour are
/// dropped: their caps coincide with the kept one within the covering tolerance.
pub const TWIN_TOLERANCE: f64 = 1e-11;

/// Two cap circles (3D) whose intersection equation misses a real solution by less than this
/// (in the dimensionless discriminant `1 − (a·c_j + b·c_k)`, see `caps.rs`) touch at one point.
pub const TANGENT_TOLERANCE: f64 = 1e-12;

/// The reference detector (`dilts`): explicit covering of `S_i` by arcs (2D) or caps (3D).
/// See the crate documentation.
#[derive(Debug, Clone, Default)]
pub struct DiltsDetector;

impl DiltsDetector {
    /// The detector (it has no parameters).
    pub fn new() -> Self {
        DiltsDetector
    }
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(DiltsDetector);

impl BoundaryDetector for DiltsDetector {
    fn name(&self) -> &'static str {
        "dilts"
    }

    fn params(&self) -> Params {
        Params::default()
    }

    fn set_param(&mut self, key: &str, _value: &str) -> Result<(), ParamError> {
        Err(ParamError::unknown("dilts", key, &[]))
    }

    /// Exact up to [`COVER_TOLERANCE`], which only turns near-ties interior.
    fn certified(&self) -> bool {
        true
    }

    fn detect_2d(&self, set: &ParticleSet<2>, r: Radius) -> Result<Detection, DetectError> {
        detect_with::<2, arcs::Arcs>(set, set.len(), r)
    }

    fn detect_3d(&self, set: &ParticleSet<3>, r: Radius) -> Result<Detection, DetectError> {
        detect_with::<3, caps::Caps>(set, set.len(), r)
    }

    /// Classifies only the owned particles; the ghosts serve as neighbours only.
    fn detect_owned(
        &self,
        set: &AnyParticleSet,
        owned: usize,
        r: Radius,
    ) -> Result<Detection, DetectError> {
        DetectError::check_owned("dilts", owned, set.len())?;
        match set {
            AnyParticleSet::D2(s) => detect_with::<2, arcs::Arcs>(s, owned, r),
            AnyParticleSet::D3(s) => detect_with::<3, caps::Caps>(s, owned, r),
        }
    }
}

/// The part of ball `B_j` that matters on `S_i`, in scaled coordinates: the cap (arc) centred
/// on the unit vector `u` with `cos α = half_distance`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cap<const D: usize> {
    /// `u_j = q_j / |q_j|`.
    pub u: Point<D>,
    /// `d_j / 2 = cos α_j`, in `(0, 1]`.
    pub half_distance: f64,
}

/// The covering test of one dimension, given the caps of one particle (largest first).
pub(crate) trait SphereCover<const D: usize>: Default + Send {
    /// Whether the caps fail to cover the sphere (boundary), and the margin (in units of `r`)
    /// if the method defines one.
    fn classify(&mut self, caps: &[Cap<D>]) -> (bool, Option<f64>);
}

/// Per-thread working memory.
struct Scratch<const D: usize, C> {
    cover: C,
    neighbours: Vec<(f64, usize)>,
    /// Scaled offsets `(d_j, q_j)` of the kept caps, for the twin test.
    kept: Vec<(f64, Point<D>)>,
    caps: Vec<Cap<D>>,
}

impl<const D: usize, C: Default> Default for Scratch<D, C> {
    fn default() -> Self {
        Scratch {
            cover: C::default(),
            neighbours: Vec::new(),
            kept: Vec::new(),
            caps: Vec::new(),
        }
    }
}

/// Classifies the first `count` particles of `set` (all of them serve as neighbours).
fn detect_with<const D: usize, C: SphereCover<D>>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
) -> Result<Detection, DetectError> {
    let r = r.get();
    let grid = NeighbourGrid::new(set, 2.0 * r)?;
    let results: Vec<(bool, Option<f64>)> = (0..count)
        .into_par_iter()
        .map_init(Scratch::<D, C>::default, |scratch, i| {
            gather_caps(set.positions(), &grid, i, r, scratch);
            scratch.cover.classify(&scratch.caps)
        })
        .collect();
    let labels = results.iter().map(|&(b, _)| b).collect::<Labels>();
    let margin = results
        .iter()
        .map(|&(_, m)| m.map(|m| m * r))
        .collect::<Option<Vec<f64>>>();
    Ok(Detection { labels, margin })
}

/// Fills `scratch.caps` with the caps of particle `i` on its sphere, largest (nearest
/// neighbour) first, ties by index. Exact duplicates of `p_i` are skipped; near-twins are merged
/// (see [`TWIN_TOLERANCE`]).
fn gather_caps<const D: usize, C>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    i: usize,
    r: f64,
    scratch: &mut Scratch<D, C>,
) {
    let p = positions[i];
    let neighbours = &mut scratch.neighbours;
    neighbours.clear();
    grid.for_each_within(&p, 2.0 * r, |j, d2| {
        // d2 == 0: `i` itself or an exact duplicate, which does not cover S_i.
        if d2 > 0.0 {
            neighbours.push((d2, j));
        }
    });
    neighbours.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let (kept, caps) = (&mut scratch.kept, &mut scratch.caps);
    kept.clear();
    caps.clear();
    for &(_, j) in neighbours.iter() {
        let q = (positions[j] - p) / r;
        let d = q.norm();
        if !(d > 0.0 && d.is_finite()) {
            continue;
        }
        // Sorted by distance: a twin of `q` has |d − d_twin| <= |q − q_twin|, so only the
        // trailing kept caps with nearly the same distance need checking.
        let twin = kept
            .iter()
            .rev()
            .take_while(|(dk, _)| d - dk <= TWIN_TOLERANCE)
            .any(|(_, qk)| (q - qk).norm() <= TWIN_TOLERANCE);
        if twin {
            continue;
        }
        kept.push((d, q));
        caps.push(Cap {
            u: q / d,
            // Rounding can put a neighbour found within 2r at a scaled distance just above 2.
            half_distance: (0.5 * d).min(1.0),
        });
    }
}
