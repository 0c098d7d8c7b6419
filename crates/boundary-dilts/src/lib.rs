#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Reference r-boundary detection by explicit covering: the method of Dilts (2000) in 2D and of
//! Haque & Dilts (2007) in 3D, the slow "ground truth" against which the JCP paper (Table 3)
//! and the thesis (Table 8) compare their timings.
//!
//! **When to use it:** to check `exact` by an independent argument (both are exact, by
//! different proofs), or to reproduce the papers' timing baseline. For labels, `exact` gives
//! the same ones faster (accuracy and speed on the same scenes: `BENCHMARKS.md`, written by
//! `cargo xtask sweep`).
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
//! `p_i` and three neighbours lying exactly on `S_i`). With the default `tie = 0` such a point
//! lies inside the float test's error band and the particle is decided by the exact predicate
//! (below). With `tie > 0` the closed reading is used, which makes ties interior (in a
//! degenerate arrangement whose uncovered region has only tie points as corners it would say
//! interior too; that needs cospherical points by construction).
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
//! # Exactness: the float test as a filter, the exact predicate inside its bound
//! With the default `tie = 0` the labels are the exact answer for the given `f64` input. The
//! float covering test runs with no tolerance and answers only when every comparison it makes
//! is farther from its threshold than a bound on its rounding error; otherwise (and for the
//! degenerate configurations below) the particle is decided by `exact`'s certified decision
//! ([`boundary_exact::sphere_uncovered_3d`] and `_2d`: its float Voronoi cell with a proven
//! bound, two certificates, then [`boundary_exact::exact_cover::sphere_uncovered`], exact
//! integer arithmetic on the exact differences `p_j − p_i`). `u = 2^-53`; the inputs `q_j = fl(fl(p_j −
//! p_i)/r)` carry a relative error `<= 2u` per component, so `d_j`, `u_j`, `c_j = d_j/2` carry
//! a few `u` each.
//! - **2D.** Each arc end `θ_j ± α_j` is within `e_j = 64u + 8u/sin α_j` of its exact value
//!   (`atan2` and the direction: a few `u`; `acos`: the error of `c_j` divided by `sin α_j`,
//!   valid while that error is far below `sin² α_j`, i.e. `sin α_j >= 1e-6`; `rem_euclid` and
//!   the sweep: a few `u·2π`). The margin (half the largest gap, or minus half the narrowest
//!   overlap) is then within `E = max_j e_j` of the exact one, and the label is decided by the
//!   float test iff `|margin| > 2E` and every `sin α_j >= 1e-6` (`THIN_ARC`).
//! - **3D.** An intersection point of two circles is within
//!   `err = 64u·(1 + 1/|w|² + 1/sqrt(h·|w|²)) + 16u` of the exact one (first order: `a`, `b`
//!   divide by `|w|²`, `t` by `sqrt(h·|w|²)`; see `caps.rs` for `w`, `h`), and a point on an
//!   isolated circle within `16u`. A probe point `x` is decided only if every cap value
//!   `x·u_l − c_l` is outside `±(err + 16u)`: *covered* if one exceeds it, a *witness* if all
//!   lie below it. Pairs with `h` or `|w|²` within `1e-8` of 0 (near-tangent or
//!   near-concentric circles, where the first-order bound fails), caps with `sin α < 1e-4`
//!   (neighbours near `2r`), and distinct near-twins merged by [`TWIN_TOLERANCE`] are left to
//!   the exact predicate, as is any probe inside its band.
//!
//! *How often* (`cargo run --release -p boundary-dilts --example fallbacks`): never on the
//! jittered and simulated sweep scenes; on lattice-like scenes every particle whose uncovered
//! region has only multi-circle corners (lattice symmetry): all 256 / 1000 particles of the
//! tie lattices, the 304 boundary particles of `duplicates3d`, 2,580 of 9,600 in
//! `dualsphysics_dambreak3d`, 4,307 of 15,827 in `pysph_case5`. Those go to `exact`'s
//! decision (its float path with certificates), which settles lattices in microseconds per
//! particle, where the exact predicate would take milliseconds.
//!
//! With every decision outside its band, the criterion (a)–(c) is evaluated exactly as in real
//! arithmetic, in generic position (no point on three circles: that would put a cap value
//! inside the band), where it is exact (proof above).
//!
//! # A radius per particle (ours)
//! With per-particle radii ([`boundary_core::ParticleSet::with_radii`]) the ball of `j`
//! (radius `r_j`, `s = r_j/r_i`) covers the cap `x·u_j >= h_j = (d_j² + 1 − s²)/(2d_j)` of the
//! unit sphere `S_i` (units of `r_i`); at `s = 1` exactly, `h_j = d_j/2` as above. The criterion
//! (a)–(c) holds for any caps; what changes:
//! - a cap with `h_j − err_j > 1` misses `S_i` (or touches it at one point) and is dropped;
//! - a cap with `h_j <= 1e-3` (a hemisphere or more: a larger neighbour whose ball nearly holds
//!   `p_i`) sends the particle to `exact`'s decision
//!   ([`boundary_exact::sphere_uncovered_power_2d`] and `_3d`), as do near-twin neighbours;
//! - every bound above widens by the rounding of `h_j`, `err_j = 8u·(d_j + (1 + s²)/d_j)` (the
//!   largest over the caps): 2D arc ends by `err/sin α`, 3D intersection points in proportion
//!   (`× (1 + err/8u)`), probe bands and isolated-circle points by `err` and `2err/sin α`.
//!
//! Neighbours come from [`boundary_core::RadiusGrid`]. Tested in
//! `crates/boundary/tests/radii.rs` (labels equal `exact`'s on two-level sets with radius
//! ratios 2, 4 and 100, which a sampled oracle with a Lipschitz bound confirms).
//!
//! # Solid half-spaces
//! In a [`boundary_core::Domain`] with solid half-spaces (closed, axis-aligned), particle `i`
//! is interior iff every point of `S_i` outside the solids is covered by the other balls (see
//! [`boundary_core::domain`]); [`boundary_core::BoundaryDetector::detect_in`] and `detect_owned_in` take
//! them. A solid covers a closed cap of the unit sphere, in units of `r_i`: for the solid
//! `x_a <= c` the cap `x·(−e_a) >= δ` with `δ = (p_a − c)/r_i`, the particle's fluid depth (for
//! `x_a >= c`, `x·e_a >= δ` with `δ = (c − p_a)/r_i`), the same form as a neighbour's cap
//! `x·u_j >= h_j` above, and it joins the arc sweep (2D) or the cap test (3D) with them:
//! - a solid with `δ > 1` (beyond its rounding) misses `S_i` and is left out; one with
//!   `δ < −1` (by `1e-12` relative) holds all of `S_i`: interior at once (2D margin `−π·r_i`);
//! - a solid with `δ <= 1e-3` covers a hemisphere or more (a particle on or inside the solid,
//!   or about to touch it): the particle goes to `exact`'s decision with the solids
//!   ([`boundary_exact::sphere_uncovered_in_2d`] and `_3d`, whose exact predicate takes the
//!   solid planes as exact differences), as do the particles the float test leaves undecided;
//! - the bound: a solid cap's direction `±e_a` is exact and its offset `δ = fl(fl(p_a − c)/r_i)`
//!   is rounded twice (`2u` relative); every bound of the float test widens by `4u` as for
//!   per-particle radii (`slack`), which holds that error with room.
//!
//! Two solids of the same direction count as the deeper one. Only particles whose ball reaches
//! a solid (fluid depth at most `r_i`, `1e-9` relative slack) take this path; the others are
//! classified exactly as without solids. Per-particle radii work as above, and with
//! `tie > 0` a solid cap gets the same tolerance as the neighbours' caps. Tested against
//! brute-force enumeration in exact rationals, near-ties included, and against `exact`
//! (`tests/domain.rs`).
//!
//! # Policy: tolerances, ties, duplicates, degenerate input
//! - **Ties.** A tie (a point of `S_i` at exactly `r` from the neighbours whose circles pass
//!   through it) is interior, decided exactly. Perfect lattices at the float tie radius:
//!   `fl(1/√2)` lies above `1/√2` (inner particles interior), `fl(√3/2)` below `√3/2` (every
//!   particle boundary).
//! - **Opt-in covering tolerance `tie`** ([`DiltsParams::tie`]; `--set tie=1e-12`): a
//!   point `x` of `S_i` counts as covered by cap `j` iff `x·u_j >= d_j/2 − tie`; equivalently
//!   the neighbour balls are enlarged to radius `r·sqrt(1 + 2·tie·d_j) ≈ r(1 + tie·d_j)`, so
//!   lattice round-off counts as a tie (interior), and the exact predicate is not used
//!   (ties resolved by stepping off the tie point, `caps.rs`). `tie = 1e-12`
//!   ([`COVER_TOLERANCE`]) gives the labels of release 0.1. Finite, `>= 0`.
//! - **Duplicates.** Particles at exactly `p_i` (`d = 0`) do not cover `S_i` and are skipped; two
//!   coincident particles alone are both boundary. Neighbours closer to one another than
//!   [`TWIN_TOLERANCE`]`·r` give caps that coincide within rounding (a pair of
//!   identical circles has no isolated intersection points): only the nearest of them is kept
//!   (exact copies of a neighbour change nothing; distinct near-twins go to the exact
//!   predicate when `tie = 0`).
//! - **Closedness at `2r`.** Neighbours at `2r` or more cover at most one point of `S_i` and
//!   never decide a covering. With `tie > 0`, 3D caps of angular radius below about `1e-4` are
//!   dropped (they are too thin for the step-off test); with `tie = 0` such a particle goes to
//!   the exact predicate, which drops neighbours at `2r` or more exactly.
//! - **Near-tangent circles** ([`TANGENT_TOLERANCE`], `tie > 0` only): two circles that miss
//!   each other by less than the tolerance are treated as touching at one point.
//! - **Far offsets.** Only differences `p_j − p_i` enter the geometry, scaled by `1/r`, so scenes
//!   at `1e6` with `r = 0.01` are classified as accurately as the input differences allow (and
//!   exactly, through the fallback, near ties).
//!
//! # Margins
//! In 2D, [`Detection::margin`] holds, per particle, `r · max_{x ∈ S_i} min_j (∠(x, u_j) − α_j)`
//! computed for the (tolerance-widened, if `tie > 0`) arcs: half the width of the largest
//! uncovered arc of `S_i` (as an arc length, units of length) when positive, minus half the
//! narrowest overlap between consecutive arcs when negative. It is the float margin: the
//! *label*, not the margin, is exact (near a tie the sign may disagree with the label). A
//! particle with no neighbour has margin `π·r`. In 3D no margin is reported (`None`).
//!
//! # Hard cases
//! What `dilts` returns on the hard cases (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`).
//! The same labels as `exact` on every case (both exact): lattices at the float tie radius and
//! ±4 ulps decided exactly (square: interior inner particles from `fl(1/√2)` up; cubic: every
//! particle boundary up to `fl(√3/2)`, inner particles interior above), exact
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
//! let detection = DiltsDetector::default().detect_3d(&set, Radius::new(1.2).unwrap()).unwrap();
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
    AnyParticleSet, Capabilities, DetectError, Detection, Dim, HalfSpace, Job, JobByDim, Labels,
    Method, NeighbourGrid, ParamSet, Params, ParticleSet, Point, Radius, RadiusGrid, Solids,
    Support, SupportedDim,
};
use rayon::prelude::*;
use std::f64::consts::PI;

/// The covering tolerance of release 0.1, now the opt-in parameter `tie`: with
/// `--set tie=1e-12` a point of `S_i` counts as covered by neighbour `j` iff
/// `x·u_j >= d_j/2 − 1e-12` (near-ties interior). The default `tie = 0` gives the exact labels.
pub const COVER_TOLERANCE: f64 = 1e-12;

/// Neighbours closer than `TWIN_TOLERANCE · r` to an already kept (nearer) neighbour are
/// dropped: their caps coincide with the kept one within the covering tolerance.
pub const TWIN_TOLERANCE: f64 = 1e-11;

/// Two cap circles (3D) whose intersection equation misses a real solution by less than this
/// (in the dimensionless discriminant `1 − (a·c_j + b·c_k)`, see `caps.rs`) touch at one point.
pub const TANGENT_TOLERANCE: f64 = 1e-12;

/// Unit roundoff of `f64`.
pub(crate) const U: f64 = f64::EPSILON / 2.0;

boundary_core::declare_params! {
    /// The parameters of `dilts` (string form: `--set tie=…`, see `boundary::registry`).
    #[derive(Debug, Clone, PartialEq)]
    pub struct DiltsParams for "dilts" {
        /// Opt-in covering tolerance: a point `x` of `S_i` counts as covered by neighbour `j`
        /// iff `x·u_j >= d_j/2 − tie` (near-ties interior). `0` (the default) gives the exact
        /// labels; [`COVER_TOLERANCE`] (`1e-12`) the labels of release 0.1. Finite, `>= 0`.
        pub tie: f64 = 0.0, check::non_negative().because("a finite number >= 0"),
            "covering tolerance: x on S_i is covered by j iff x·u_j >= d_j/2 − tie (e.g. \
             1e-12 treats lattice round-off as ties); 0 = exact labels";
    }
}

/// The reference detector (`dilts`): explicit covering of `S_i` by arcs (2D) or caps (3D).
/// See the crate documentation. `DiltsDetector::default()` gives the exact labels.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DiltsDetector {
    params: DiltsParams,
}

impl DiltsDetector {
    /// Like [`boundary_core::BoundaryDetector::detect`], also returning how many particles the exact
    /// predicate decided (those the float covering test could not decide within its bound).
    pub fn detect_counting_fallbacks(
        &self,
        set: &AnyParticleSet,
        r: Radius,
    ) -> Result<(Detection, usize), DetectError> {
        match set {
            AnyParticleSet::D2(s) => detect_with::<2, arcs::Arcs>(s, s.len(), r, self.params.tie),
            AnyParticleSet::D3(s) => detect_with::<3, caps::Caps>(s, s.len(), r, self.params.tie),
        }
    }
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(DiltsDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(DiltsDetector, DiltsParams);

impl Method for DiltsDetector {
    const NAME: &'static str = "dilts";

    fn describe(&self) -> Params {
        self.params.listing()
    }

    /// Exact (so certified): the float covering test decides the clear cases, the exact
    /// predicate the rest; per-particle radii and the closed solid half-spaces (crate docs,
    /// "Solid half-spaces"); the ghosts serve as neighbours only.
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
        match job.by_dim() {
            JobByDim::D2(job) => classify_arcs::<2, arcs::Arcs>(job, self.params.tie),
            JobByDim::D3(job) => classify_arcs::<3, caps::Caps>(job, self.params.tie),
        }
    }
}

/// The owned particles of `job`, with the solid half-spaces when it has any.
fn classify_arcs<const D: usize, C: SphereCover<D>>(
    job: Job<'_, D>,
    tie: f64,
) -> Result<Detection, DetectError> {
    Ok(if job.solids.is_empty() {
        detect_with::<D, C>(job.set, job.owned, job.r, tie)?.0
    } else {
        detect_in_solids::<D, C>(job.set, job.owned, job.r, tie, job.solids)?.0
    })
}

/// The part of ball `B_j` that matters on `S_i`, in scaled coordinates: the cap (arc) centred
/// on the unit vector `u` with `cos α = half_distance`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cap<const D: usize> {
    /// `u_j = q_j / |q_j|`.
    pub u: Point<D>,
    /// `cos α_j`, in `(0, 1]` for the caps the covering test decides: `d_j / 2` at a uniform
    /// radius, `h_j` with per-particle radii, `δ` for a solid (crate docs). A solid's cap of a
    /// hemisphere or more (`δ` in `[−1, 1e-3]`) enters the 2D sweep only for the margin.
    pub half_distance: f64,
}

/// The covering test of one dimension, given the caps of one particle (largest first).
pub(crate) trait SphereCover<const D: usize>: Default + Send {
    /// Whether the caps fail to cover the sphere (boundary), and the margin (in units of `r`)
    /// if the method defines one. `tol > 0`: covering tolerance `tol`, always decided.
    /// `tol == 0`: the exact mode; `None` when the float test cannot decide within its error
    /// bound.
    fn classify(&mut self, caps: &[Cap<D>], tol: f64) -> (Option<bool>, Option<f64>);

    /// The exact label of the sphere of radius `r` around `centre` among `others` (a superset
    /// of the neighbours within `2r`), for the particles the float test leaves undecided:
    /// `exact`'s certified decision ([`boundary_exact::sphere_uncovered_2d`] and `_3d`).
    fn exact(centre: &Point<D>, others: &[Point<D>], r: Radius) -> bool;

    /// The exact label with a radius per ball: `exact`'s certified decision
    /// ([`boundary_exact::sphere_uncovered_power_2d`] and `_3d`).
    fn exact_power(centre: &Point<D>, r: f64, others: &[(Point<D>, f64)]) -> bool;

    /// The exact label with a radius per ball and the closed solid half-spaces `solids`
    /// covering too: `exact`'s certified decision ([`boundary_exact::sphere_uncovered_in_2d`]
    /// and `_3d`).
    fn exact_in(
        centre: &Point<D>,
        r: f64,
        others: &[(Point<D>, f64)],
        solids: &[HalfSpace],
    ) -> bool;

    /// Sets the extra absolute error of every cap's `cos α` for the next [`Self::classify`]
    /// calls (0 at a uniform radius; per-particle radii and solids, crate docs).
    fn set_slack(&mut self, slack: f64);

    /// Whether [`Self::classify`] reports a margin.
    const MARGIN: bool;
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

/// Classifies the first `count` particles of `set` (all of them serve as neighbours); also
/// returns how many the exact predicate decided.
fn detect_with<const D: usize, C: SphereCover<D>>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    tie: f64,
) -> Result<(Detection, usize), DetectError> {
    if let Some(radii) = set.resolved_radii(r)? {
        return detect_radii::<D, C>(set, count, &radii, tie);
    }
    let radius = r;
    let r = r.get();
    let grid = NeighbourGrid::new(set, 2.0 * r)?;
    let results: Vec<(bool, Option<f64>, bool)> = (0..count)
        .into_par_iter()
        .map_init(Scratch::<D, C>::default, |scratch, i| {
            if boundary_core::stop::requested() {
                return Default::default();
            }
            let twins = gather_caps(set.positions(), &grid, i, r, scratch);
            let (label, margin) = scratch.cover.classify(&scratch.caps, tie);
            match label {
                Some(b) if !(twins && tie == 0.0) => (b, margin, false),
                _ => (
                    exact_label::<D, C>(set.positions(), &grid, i, radius),
                    margin,
                    true,
                ),
            }
        })
        .collect();
    let fallbacks = results.iter().filter(|x| x.2).count();
    let labels = results.iter().map(|x| x.0).collect::<Labels>();
    let margin = results
        .iter()
        .map(|x| x.1.map(|m| m * r))
        .collect::<Option<Vec<f64>>>();
    Ok((Detection { labels, margin }, fallbacks))
}

/// The exact label of particle `i` ([`SphereCover::exact`]) from every particle the grid
/// finds within `2r(1 + 1e-9)` (those at `2r` or more are dropped exactly there).
fn exact_label<const D: usize, C: SphereCover<D>>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    i: usize,
    r: Radius,
) -> bool {
    let p = positions[i];
    let mut near: Vec<Point<D>> = Vec::new();
    grid.for_each_within(&p, 2.0 * r.get() * (1.0 + 1e-9), |j, _| {
        if j != i {
            near.push(positions[j]);
        }
    });
    C::exact(&p, &near, r)
}

/// Fills `scratch.caps` with the caps of particle `i` on its sphere, largest (nearest
/// neighbour) first, ties by index. Exact duplicates of `p_i` are skipped; near-twins are merged
/// (see [`TWIN_TOLERANCE`]).
///
/// Returns whether a distinct near-twin was dropped (not an exact copy of a kept neighbour):
/// in the exact mode (`tie == 0`) the particle then goes to the exact predicate.
fn gather_caps<const D: usize, C>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    i: usize,
    r: f64,
    scratch: &mut Scratch<D, C>,
) -> bool {
    let mut dropped_twin = false;
    let p = positions[i];
    let neighbours = &mut scratch.neighbours;
    neighbours.clear();
    // A little beyond 2r, so that no neighbour whose exact distance is below 2r is lost to the
    // rounding of the query (the extra caps are points: the exact mode leaves them to the exact
    // predicate, the tolerant mode drops them).
    grid.for_each_within(&p, 2.0 * r * (1.0 + 1e-12), |j, d2| {
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
            .find(|(_, qk)| (q - qk).norm() <= TWIN_TOLERANCE);
        if let Some((_, qk)) = twin {
            dropped_twin |= q != *qk;
            continue;
        }
        kept.push((d, q));
        caps.push(Cap {
            u: q / d,
            // Rounding can put a neighbour found within 2r at a scaled distance just above 2.
            half_distance: (0.5 * d).min(1.0),
        });
    }
    dropped_twin
}

/// Caps of one particle closer than this to a hemisphere or larger (`cos α <= RHO_MIN`: a
/// larger neighbour whose ball nearly holds `p_i`) send the particle to `exact`'s decision,
/// which handles power cells that do not contain `p_i`.
const RHO_MIN: f64 = 1e-3;

/// [`detect_with`] for a set with a radius per particle (crate docs, "A radius per particle").
fn detect_radii<const D: usize, C: SphereCover<D>>(
    set: &ParticleSet<D>,
    count: usize,
    radii: &[f64],
    tie: f64,
) -> Result<(Detection, usize), DetectError> {
    let grid = RadiusGrid::new(set, radii)?;
    let positions = set.positions();
    let results: Vec<(bool, Option<f64>, bool)> = (0..count)
        .into_par_iter()
        .map_init(Scratch::<D, C>::default, |scratch, i| {
            if boundary_core::stop::requested() {
                return Default::default();
            }
            let r = radii[i];
            let p = positions[i];
            let found = gather_power_caps(positions, radii, &grid, i, scratch);
            let exact = |near: &[(f64, usize)]| {
                C::exact_power(&p, r, &power_others(positions, radii, near))
            };
            if found.general || (found.twins && tie == 0.0) {
                return (exact(&scratch.neighbours), None, true);
            }
            scratch.cover.set_slack(found.slack);
            let (label, margin) = scratch.cover.classify(&scratch.caps, tie);
            match label {
                Some(b) => (b, margin.map(|m| m * r), false),
                None => (exact(&scratch.neighbours), margin.map(|m| m * r), true),
            }
        })
        .collect();
    let fallbacks = results.iter().filter(|x| x.2).count();
    let labels = results.iter().map(|x| x.0).collect::<Labels>();
    let margin = results.iter().map(|x| x.1).collect::<Option<Vec<f64>>>();
    Ok((Detection { labels, margin }, fallbacks))
}

/// What [`gather_power_caps`] found besides the caps.
struct PowerCaps {
    /// A cap of a hemisphere or more (or a non-finite one): the particle goes to `exact`'s
    /// decision, and the caps gathered so far are incomplete.
    general: bool,
    /// Distinct neighbours closer than [`TWIN_TOLERANCE`] to each other.
    twins: bool,
    /// The extra absolute error of the caps' `cos α` (the largest over the caps).
    slack: f64,
}

/// Fills `scratch.neighbours` with the neighbours of particle `i` whose balls reach its sphere
/// (nearest first, exact duplicates of `p_i` left out) and `scratch.caps` with their caps on
/// `S_i`, in units of `r_i` (crate docs, "A radius per particle"), largest first, unless a cap
/// is general.
fn gather_power_caps<const D: usize, C>(
    positions: &[Point<D>],
    radii: &[f64],
    grid: &RadiusGrid<D>,
    i: usize,
    scratch: &mut Scratch<D, C>,
) -> PowerCaps {
    let r = radii[i];
    let p = positions[i];
    let near = &mut scratch.neighbours;
    near.clear();
    grid.for_each_reaching(&p, r, |j, d2| {
        // d2 == 0: `i` itself or an exact duplicate, which does not cover S_i.
        if d2 > 0.0 {
            near.push((d2, j));
        }
    });
    near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    // The cap of j on S_i (units of r): x·u >= h = (d² + 1 − s²)/(2d), s = r_j/r.
    // With s == 1 exactly, h = d/2 as at a uniform radius, with no extra error.
    let caps = &mut scratch.caps;
    caps.clear();
    let mut found = PowerCaps {
        general: false,
        twins: false,
        slack: 0.0,
    };
    let mut last: Option<(Point<D>, f64)> = None;
    for &(_, j) in near.iter() {
        let q = (positions[j] - p) / r;
        let d = q.norm();
        let s = radii[j] / r;
        if last == Some((q, s)) {
            // An exact copy of the previous neighbour (position and radius) adds nothing.
            continue;
        }
        if last.is_some_and(|(ql, _)| (q - ql).norm() <= TWIN_TOLERANCE) {
            found.twins = true;
        }
        last = Some((q, s));
        let h = 0.5 * d + 0.5 * ((1.0 - s * s) / d);
        let err = if s == 1.0 {
            0.0
        } else {
            8.0 * U * (d + (1.0 + s * s) / d)
        };
        if h - err > 1.0 {
            // The ball misses S_i (or touches it at one point): it covers nothing of
            // the open uncovered set.
            continue;
        }
        if !(h > RHO_MIN && h.is_finite()) {
            found.general = true;
            return found;
        }
        found.slack = found.slack.max(err);
        caps.push(Cap {
            u: q / d,
            half_distance: h.min(1.0),
        });
    }
    // Largest caps first, as at a uniform radius.
    caps.sort_unstable_by(|a, b| a.half_distance.total_cmp(&b.half_distance));
    found
}

/// The balls `(centre, radius)` of the neighbours `near` (as [`gather_power_caps`] lists them),
/// for `exact`'s decision.
fn power_others<const D: usize>(
    positions: &[Point<D>],
    radii: &[f64],
    near: &[(f64, usize)],
) -> Vec<(Point<D>, f64)> {
    near.iter()
        .map(|&(_, j)| (positions[j], radii[j]))
        .collect()
}

/// A solid holding all of `S_i` (fluid depth below `−r_i` by this relative slack, wider than
/// the two roundings of `δ`) makes the particle interior at once.
const HELD_SLACK: f64 = 1e-12;

/// The absolute error of a solid cap's offset `δ = fl(fl(p_a − c)/r_i)` (two roundings, `2u`
/// relative, for `|δ| <= 1 + 4u`), with room to spare.
const SOLID_ERR: f64 = 4.0 * U;

/// [`detect_with`] with the closed solid half-spaces `solids` covering too (crate docs, "Solid
/// half-spaces"). The particles whose closed ball stays clear of every solid are classified by
/// [`detect_with`] (on a reordered copy of the set, when some particles are near a solid); the
/// others by [`classify_near`]. Also returns how many the exact predicate decided.
fn detect_in_solids<const D: usize, C: SphereCover<D>>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    tie: f64,
    domain_solids: &Solids,
) -> Result<(Detection, usize), DetectError> {
    let solids: &[HalfSpace] = domain_solids.half_spaces();
    let radii = set.resolved_radii(r)?;
    let positions = set.positions();
    let radius = |i: usize| radii.as_ref().map_or(r.get(), |v| v[i]);
    let reaches = |i: usize| domain_solids.half_space_reaches(positions[i].as_slice(), radius(i));
    let (near, far): (Vec<usize>, Vec<usize>) = (0..count).partition(|&i| reaches(i));
    if near.is_empty() {
        return detect_with::<D, C>(set, count, r, tie);
    }
    let mut boundary = vec![false; count];
    let mut margin = C::MARGIN.then(|| vec![0.0; count]);
    let mut fallbacks = 0;
    if !far.is_empty() {
        // The particles clear of the solids first, then all the others as neighbours.
        let mut order = far.clone();
        order.extend(&near);
        order.extend(count..set.len());
        let (far_detection, far_fallbacks) =
            detect_with::<D, C>(&set.subset(&order), far.len(), r, tie)?;
        fallbacks += far_fallbacks;
        for (slot, &i) in far.iter().enumerate() {
            boundary[i] = far_detection.labels.is_boundary(slot);
        }
        match (margin.as_mut(), far_detection.margin) {
            (Some(all), Some(m)) => far.iter().zip(m).for_each(|(&i, m)| all[i] = m),
            _ => margin = None,
        }
    }
    let near_results = classify_near::<D, C>(set, &near, r, radii.as_deref(), tie, solids)?;
    for (&i, (label, m, exact)) in near.iter().zip(near_results) {
        boundary[i] = label;
        fallbacks += usize::from(exact);
        match (margin.as_mut(), m) {
            (Some(all), Some(m)) => all[i] = m,
            _ => margin = None,
        }
    }
    Ok((
        Detection {
            labels: Labels::new(boundary),
            margin,
        },
        fallbacks,
    ))
}

/// `(label, margin, decided by the exact predicate)` of the particles `indices` of `set`, each
/// near a solid: the caps of its neighbours as on the usual path (uniform radius `r`, or the
/// radii `radii`), plus one cap per solid that reaches its sphere (crate docs, "Solid
/// half-spaces").
fn classify_near<const D: usize, C: SphereCover<D>>(
    set: &ParticleSet<D>,
    indices: &[usize],
    r: Radius,
    radii: Option<&[f64]>,
    tie: f64,
    solids: &[HalfSpace],
) -> Result<Vec<(bool, Option<f64>, bool)>, DetectError> {
    enum Grid<'a, const D: usize> {
        Uniform(NeighbourGrid<D>),
        Radii(RadiusGrid<D>, &'a [f64]),
    }
    let grid = match radii {
        None => Grid::Uniform(NeighbourGrid::new(set, 2.0 * r.get())?),
        Some(radii) => Grid::Radii(RadiusGrid::new(set, radii)?, radii),
    };
    let positions = set.positions();
    Ok(indices
        .par_iter()
        .map_init(Scratch::<D, C>::default, |scratch, &i| {
            if boundary_core::stop::requested() {
                return Default::default();
            }
            let p = positions[i];
            // The neighbours' caps, largest first, exactly as on the usual path.
            let (r_i, found) = match &grid {
                Grid::Uniform(grid) => {
                    let twins = gather_caps(positions, grid, i, r.get(), scratch);
                    let found = PowerCaps {
                        general: false,
                        twins,
                        slack: 0.0,
                    };
                    (r.get(), found)
                }
                Grid::Radii(grid, radii) => (
                    radii[i],
                    gather_power_caps(positions, radii, grid, i, scratch),
                ),
            };
            let exact = |near: &[(f64, usize)]| {
                let others: Vec<(Point<D>, f64)> = near
                    .iter()
                    .map(|&(_, j)| {
                        let r_j = match &grid {
                            Grid::Uniform(_) => r.get(),
                            Grid::Radii(_, radii) => radii[j],
                        };
                        (positions[j], r_j)
                    })
                    .collect();
                C::exact_in(&p, r_i, &others, solids)
            };
            // The solids' caps `x·u >= δ`: one per direction, the deepest solid of each.
            let first = scratch.caps.len();
            let mut general = found.general;
            let mut slack = found.slack;
            for h in solids {
                let delta = h.fluid_depth(p.as_slice()) / r_i;
                if delta < -(1.0 + HELD_SLACK) {
                    // The solid holds the whole sphere: no point of it needs covering.
                    return (false, C::MARGIN.then_some(-PI * r_i), false);
                }
                if delta - SOLID_ERR * delta.abs() > 1.0 {
                    // The solid misses S_i (or touches it at one point).
                    continue;
                }
                // A hemisphere or more (or a particle on or inside the solid): exact decides.
                general |= delta <= RHO_MIN;
                slack = slack.max(SOLID_ERR);
                let sign = if h.solid_below() { -1.0 } else { 1.0 };
                let u = Point::<D>::from_fn(|k, _| if k == h.axis() { sign } else { 0.0 });
                let c = delta.clamp(-1.0, 1.0);
                match scratch.caps[first..].iter_mut().find(|cap| cap.u == u) {
                    Some(cap) => cap.half_distance = cap.half_distance.min(c),
                    None => scratch.caps.push(Cap {
                        u,
                        half_distance: c,
                    }),
                }
            }
            if found.general {
                // The neighbours' caps are incomplete: no float margin either.
                return (exact(&scratch.neighbours), None, true);
            }
            if general && !C::MARGIN {
                return (exact(&scratch.neighbours), None, true);
            }
            if scratch.caps.len() > first {
                scratch
                    .caps
                    .sort_unstable_by(|a, b| a.half_distance.total_cmp(&b.half_distance));
            }
            scratch.cover.set_slack(slack);
            let (label, margin) = scratch.cover.classify(&scratch.caps, tie);
            let margin = margin.map(|m| m * r_i);
            match label {
                Some(b) if !(general || found.twins && tie == 0.0) => (b, margin, false),
                _ => (exact(&scratch.neighbours), margin, true),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A jittered 2D block of spacing 1 whose lowest row lies at height 0.5 (± 0.25).
    fn block(nx: usize, ny: usize) -> ParticleSet<2> {
        let mut state = 7u64;
        let mut jitter = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            0.5 * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
        };
        let rows: Vec<[f64; 2]> = (0..nx * ny)
            .map(|k| [(k % nx) as f64 + jitter(), (k / nx) as f64 + 0.5 + jitter()])
            .collect();
        ParticleSet::from_rows(&rows).expect("finite rows")
    }

    /// The solids of a list of half-spaces.
    fn solids_of(half_spaces: &[HalfSpace]) -> Solids {
        let mut solids = Solids::new();
        half_spaces.iter().for_each(|&h| solids.push(h));
        solids
    }

    #[test]
    fn the_float_test_decides_the_layer_on_a_floor() {
        let set = block(20, 8);
        let r = Radius::new(0.8).expect("a radius");
        let floor = [HalfSpace::new(1, true, -0.2).expect("a floor")];
        let (with, fallbacks) =
            detect_in_solids::<2, arcs::Arcs>(&set, set.len(), r, 0.0, &solids_of(&floor))
                .expect("runs");
        let (bare, _) = detect_with::<2, arcs::Arcs>(&set, set.len(), r, 0.0).expect("runs");
        // The floor covers part of the lowest row (fewer boundary particles), and the solid
        // caps are decided by the float sweep: no particle needs the exact predicate.
        assert!(with.labels.boundary_count() < bare.labels.boundary_count());
        assert_eq!(fallbacks, 0);
        assert_eq!(with.margin.map(|m| m.len()), Some(set.len()));
        // A floor through the lowest row: the particles within 1e-3·r of it or below it go
        // to `exact`'s decision, the others stay with the float test.
        let through = [HalfSpace::new(1, true, 0.5).expect("a floor")];
        let (_, fallbacks) =
            detect_in_solids::<2, arcs::Arcs>(&set, set.len(), r, 0.0, &solids_of(&through))
                .expect("runs");
        let general = set
            .positions()
            .iter()
            .filter(|p| p.y - 0.5 <= 1e-3 * 0.8)
            .count();
        assert!(
            general > 0 && fallbacks == general,
            "{fallbacks} != {general}"
        );
    }

    #[test]
    fn the_float_test_decides_the_layer_in_a_3d_tank() {
        let mut state = 3u64;
        let mut jitter = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            0.5 * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
        };
        let rows: Vec<[f64; 3]> = (0..8 * 6 * 8)
            .map(|k| {
                let (x, y, z) = (k % 8, (k / 8) % 6, k / 48);
                [
                    x as f64 + jitter(),
                    y as f64 + 0.5 + jitter(),
                    z as f64 + jitter(),
                ]
            })
            .collect();
        let set = ParticleSet::from_rows(&rows).expect("finite rows");
        let r = Radius::new(0.95).expect("a radius");
        let tank = [
            HalfSpace::new(1, true, -0.2).expect("a floor"),
            HalfSpace::new(0, true, -0.7).expect("a wall"),
            HalfSpace::new(2, false, 7.7).expect("a wall"),
        ];
        let (with, fallbacks) =
            detect_in_solids::<3, caps::Caps>(&set, set.len(), r, 0.0, &solids_of(&tank))
                .expect("runs");
        let (bare, _) = detect_with::<3, caps::Caps>(&set, set.len(), r, 0.0).expect("runs");
        assert!(with.labels.boundary_count() < bare.labels.boundary_count());
        assert!(with.margin.is_none());
        assert_eq!(fallbacks, 0);
    }
}
