#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Exact r-boundary detection by restricted Voronoi cells: the reference labels of the project.
//!
//! **When to use it:** by default. Its labels are exact for the given `f64` input (a float
//! filter with a proven bound, an exact integer fallback), every other method is scored
//! against them, and it is the fastest of the methods that never miss a boundary particle
//! (accuracy and speed of every method on the same scenes: `BENCHMARKS.md`, written by
//! `cargo xtask sweep`).
//!
//! # Definition
//! Particle `i` at `p_i` with resolution `r` is *interior* iff its sphere `S_i` (radius `r`)
//! is covered by the closed balls `B_j` of radius `r` of the other particles within `2r`;
//! otherwise it is *boundary* (Sandim et al., JCP 2020, Sec. 2; thesis Sec. 2.1).
//!
//! # Why the Voronoi cell decides it
//! Let `V_i` be the Voronoi cell of `p_i` among the particles within `2r` (exact duplicates of
//! `p_i` excluded, see below): the points at least as close to `p_i` as to any of them.
//!
//! *Claim:* `i` is boundary iff `max_{x in V_i} |x − p_i| > r`.
//!
//! - A point `x` of `S_i` is uncovered iff `|x − p_j| > r = |x − p_i|` for every `j`, i.e. iff
//!   `x` is strictly closer to `p_i` than to every other particle: `x` lies in the interior of
//!   `V_i`. (Particles farther than `2r` cannot cover a point of `S_i` anyway.)
//! - If `V_i` reaches a point `v` with `|v − p_i| > r`, the segment from `p_i` (an interior point
//!   of `V_i`, since no other particle coincides with it) to `v` crosses `S_i` at some `x`; every
//!   point of that half-open segment is interior to the convex set `V_i`, so `x` is uncovered.
//! - Conversely, an uncovered `x` on `S_i` lies in `V_i`, so `max |x − p_i| >= r`, and being
//!   interior, points slightly beyond it along the ray are in `V_i` too: the maximum exceeds `r`.
//!
//! This is the union-of-balls / alpha-shape picture: the boundary particles are those whose
//! Voronoi cell is not contained in their own ball, i.e. whose ball contributes to the boundary
//! of the union of balls of radius `r`.
//!
//! # Algorithm
//! Per particle, in coordinates relative to `p_i` and scaled by `1/r` (so scenes at `1e6` with
//! `r = 0.01` lose no precision to the offset): start from the box `[-1, 1]^D`, which contains
//! the whole ball; clip it by the bisector half-spaces `q_j·x <= |q_j|²/2` of the neighbours
//! within `2r` taken nearest first; stop when the next bisector lies beyond the farthest vertex
//! (`|q_j|/2 >= max |v|`: no remaining neighbour can cut). The margin is
//! `(max |v| − 1)·r`. Clipping also stops once every vertex is within `(1 − 1e-6)·r`
//! ([`INTERIOR_BAND`]): the particle is interior whatever comes next, so margins below
//! `−1e-6·r` are upper bounds, not exact values. The 2D cell is a polygon, the 3D cell a polyhedron
//! (see `cell.rs`). Particles are processed in parallel with rayon, in the grid's cell order
//! (neighbouring particles one after another: their queries share cached cells); each particle
//! is independent, so the labels do not depend on the number of threads.
//!
//! *The interior filter.* Before any cell is clipped, a particle at a uniform radius without
//! solids tries a cheaper proof (module `interior`, with the proof and its rounding bound):
//! each neighbour within `1.1r` (and at least `r/2` away) bounds the cell by `a·x <= 1`
//! with `a = 2q/|q|²`; the six points `a` reaching farthest along `±x, ±y, ±z`, joined as the
//! eight triangles of an octahedron (four edges of a diamond in 2D), give a lower bound `g`
//! of `min_{|e|=1} max a·e` when the origin lies strictly inside each triangle's plane (the
//! smallest distance of those planes), and then the cell reaches at most `1/g`. A bound of at
//! most `1 − 2·INTERIOR_BAND`, with every rounding accounted for, makes the particle interior
//! with that bound as its margin (an upper bound, like every margin below
//! `−INTERIOR_BAND·r`). The filter never answers "boundary"; every other particle takes the
//! path below unchanged. On the jittered ball (`r = 1.2a`) it decides about nine interior
//! particles in ten.
//!
//! *Speed, same result.* Neighbours are gathered in two stages: those within `1.1r` first,
//! whose nearest-first order is a prefix of the full order; every other neighbour has a
//! bisector offset of at least `0.55(1 − 1e-9)` (units of `r`), so a cell that lies within that
//! after them is final, and only other cells (on a jittered ball, the boundary particles)
//! gather everything within `2r` and go on in the same order. In 3D a first pass clips a
//! *simple* polyhedron (every vertex of degree 3, neighbours kept in cyclic order: a clip walks
//! the faces of the cut-off region instead of sorting the new face by angle). It computes each
//! new vertex by the same expression from the same edge endpoints as the full polyhedron, so
//! wherever that one flags no clip, the vertices, margin and bound are the same bit for bit
//! (where it flags only near-equal angles, the fast cell's are the right ones). It stops at
//! the first clip with a vertex within `PLANE_EPS` of the plane or two new vertices within
//! `1e-12` (or over 255 vertices), and such a particle is decided again by the full polyhedron
//! and the steps below, unchanged (tests: random clip sequences against the full polyhedron, and every
//! margin of whole detections against a brute-force full-list reference, 2D and 3D). Its
//! cell is the exact clip of the float cell whenever every vertex is classified correctly
//! (fact 3 below), so the bound covers it; it needs no flag for near-equal angles because it
//! orders nothing by angle. A clip scans the vertices four slots at a time in SIMD registers
//! (`wide::f64x4`: signed distances by the same expression, largest and smallest, a mask of
//! the cut-off vertices, the kept vertices' largest norm) and lists the cut-off vertices and
//! crossing edges without branches. Speed: `cargo run --release -p boundary-exact --example
//! throughput` (1M-particle jittered ball, 1 and 2 threads).
//!
//! # Exactness: a float filter with a proven bound, and an exact fallback
//! The labels are the exact answer for the given `f64` input (with the default `tie = 0`).
//! The float clipping above decides a particle when its margin is clearly away from 0; the
//! others go to [`exact_cover::sphere_uncovered`], which decides the same
//! question in exact integer arithmetic (exact differences `p_j − p_i`, rational cell
//! vertices; see its docs).
//!
//! *The bound.* Units of `r`, coordinates relative to `p_i`, `u = 2^-53`. Let `C` be the exact
//! cell (with the box), `F` the float cell after `m` clips, `ρ0 = min(1, h_min)` with `h_min`
//! the smallest bisector offset used (then `C` and every used half-space contain the ball
//! `B(0, ρ0)`). Facts, each elementary:
//! 1. *Scaling sandwich.* For half-spaces `n·x <= h` with unit `n` and `h >= ρ0`, moving the
//!    offset by `±δ` lies between the scalings by `1 ± δ/ρ0`: `H^{+δ} ⊆ (1 + δ/ρ0)H` and
//!    `(1 − δ/ρ0)H ⊆ H^{−δ}`. Exact clipping preserves a sandwich `(1+β)^{-1}C' ⊆ F ⊆
//!    (1+β)C'` (intersect both sides with `H`, and `λH ⊆ H ⊆ H/λ` for `λ <= 1`), and composing
//!    steps multiplies the factors. No condition number enters: near-parallel planes cost
//!    nothing, which is why a margin bound exists at all.
//! 2. *Planes.* `q̃ = fl(fl(p_j − p_i)/r)` has relative error `<= 2u` per component, so the used
//!    `(n, offset)` differ from the exact bisector by `<= 8u` in the normal and `<= 5u·offset`;
//!    for `|x| <= √D <= 2` that is an offset shift `<= 24u`.
//! 3. *A clip that cuts,* with every vertex's computed `s = n·v − offset` farther than
//!    `PLANE_EPS = 1e-12` from 0 (its rounding is `<= 12u`), classifies every vertex correctly;
//!    each crossing point `a + t(b − a)` lies on the edge within `4u` and within `40u` of the
//!    plane, so the new cell is sandwiched between the exact clip at offsets `∓64u`.
//!    A clip that cuts nothing changes nothing and ignores at most `PLANE_EPS` of depth.
//!    Pruned neighbours (`offset >= reach`) and the settled stop (`reach <= 1 − 1e-6`) are
//!    clips of the first kind covered by the sandwich.
//!
//! Hence `(1+β)^{-1}C ⊆ F ⊆ (1+β)C` with `β = (24u + m·(64u + PLANE_EPS))/ρ0`, and the float
//! reach is within a factor `1 + β` (plus `3u` for `max |v|`) of the exact one: the label is
//! exact whenever `|margin| > τ = 2(2β·max(reach, 1) + 8u)` (a factor 2 of safety). Typical
//! values: `m ≈ 15`, `ρ0 ≈ 0.4`, `τ ≈ 1e-10`.
//!
//! *What the bound assumes,* and is checked at run time: no clip was *near-degenerate* (one
//! that cuts while a vertex lies within `PLANE_EPS` of its plane, or that merges two cap points
//! or meets two at nearly equal angles, `cell.rs`). There the float topology could differ from
//! the exact one, so such particles always go to the exact predicate.
//!
//! *How often* (`cargo run --release -p boundary-dilts --example fallbacks`): on the
//! 1M-particle jittered ball (`r = 1.2a`) no particle needs the fallback; on the sweep scenes
//! none either, except the inner particles of the two perfect lattices at their tie radius
//! (196 of 256 in 2D, 512 of 1000 in 3D: genuine near-ties, on small integer coordinates: the
//! `i64` path; `cargo run --release -p boundary-exact --example tie_lattice` times it).
//! `pysph_case5` (15,827 particles of a body-centred cubic lattice with decimal coordinates)
//! flags nearly every clip near-degenerate; the certificates below settle all of it with no
//! fallback, where without them over a thousand of its particles would need big integers at
//! milliseconds each.
//!
//! # Certificates
//! A particle whose float decision is not covered by the bound (a flagged clip, or a margin
//! within `τ`) but whose float margin is at least `1e-6` from 0 first tries a certificate:
//! - *boundary:* one of the float cell's (up to 8) farthest vertices beyond the sphere, pulled
//!   halfway back toward it, is
//!   checked against the bisector of every neighbour within `2r(1 + 1e-12)` with `1e-11` of
//!   slack and `|x| > 1 + 1e-11`: such a point lies strictly inside the exact cell beyond `r`;
//! - *interior:* the cell is clipped again, and a clip that would be near-degenerate is
//!   retried with its plane moved outward by `1e-9`, `3.7e-9`, `1.3e-8` (units of `r`), or
//!   skipped if each try is; a moved plane bounds a larger half-space and a skipped one none,
//!   so the result contains the exact cell, and the kept clips are covered by the bound: a
//!   margin below `−τ` of that larger cell proves interior.
//!
//! Perfect lattices need them: their bisectors pass exactly through cell vertices, so nearly
//! every clip is flagged although the margins are far from 0 (`pysph_case5`, 15,827 particles
//! of a lattice, nearly all flagged: the certificates settle every one, while skipping the
//! flagged planes instead of moving them would leave over a thousand to the exact
//! predicate). Only what neither certificate settles goes to the exact predicate.
//!
//! The same decision (float cell, certificates, exact predicate) is public for a particle
//! whose neighbours the caller gathered: [`sphere_uncovered_2d`], [`sphere_uncovered_3d`].
//! `dilts` uses it for the particles its own float test leaves undecided.
//!
//! # A radius per particle: power cells
//! A set with per-particle radii ([`boundary_core::ParticleSet::with_radii`]; particle `i` has
//! `r_i = r·s_i`) is decided the same way with *power* (Laguerre) cells. Particle `i` is
//! interior iff `S_i` (radius `r_i`) is covered by the closed balls `B_j` (radius `r_j`) of the
//! other particles with `|p_i − p_j| <= r_i + r_j` (coincident particles never cover each
//! other, whatever their radii).
//!
//! - A point `x` of `S_i` is uncovered iff `|x − p_j|² − r_j² > 0 = |x − p_i|² − r_i²` for every
//!   `j`: `x` lies in the interior of the power cell `P_i = {x : |x − p_i|² − r_i² <= |x −
//!   p_j|² − r_j² ∀j}`, whose walls are the *power planes* `2q_j·y <= |q_j|² + r_i² − r_j²`
//!   (`y = x − p_i`, `q_j = p_j − p_i`): the bisectors, moved by `(r_i² − r_j²)/(2|q_j|)`.
//! - *Claim:* `i` is boundary iff `P_i` has interior points both beyond and within `r_i`
//!   (`max_{P_i} |y| > r_i` and `min_{P_i} |y| < r_i`, `P_i` full-dimensional). The interior
//!   `U` of `P_i` is open, convex and connected; `|y|` has no local maximum in `U`, and no
//!   local minimum except at `y = 0`, so `U` holds points beyond `r_i` iff the maximum over
//!   `P_i` exceeds `r_i`, and points within it iff the minimum is below `r_i`; being
//!   connected, it then meets `S_i`.
//! - When every power plane keeps `p_i` strictly inside (offset `> 0`), the minimum is 0 and
//!   this is the Voronoi test above, with the same float filter and error bound (the plane's
//!   rounding also includes that of `(1 − s²)/(2|q|)`, `s = r_j/r_i`: `16u·(|q| + (1 + s²)/|q|)`
//!   per plane, units of `r_i`). With all radii equal the planes are the bisectors exactly
//!   (the moved term is exactly 0), so a set whose radii are all equal gets the uniform labels
//!   (tested).
//! - A larger neighbour whose ball nearly holds `p_i` (a plane offset below `1e-3·r_i`: `p_i`
//!   near or outside its own power cell, which happens next to coarser particles) takes the
//!   general float test: the same error bound taken about an interior point `o` of the float
//!   cell (its vertex centroid, checked `1e-6` inside every plane), which proves interior when
//!   the cell lies within the ball (`max |v| < 1 − τ`) or outside it (a separating direction
//!   bounds `min |y| > 1 + τ`), and boundary with two points strictly inside every plane, one
//!   beyond `S_i` and one within it (the segment between them crosses `S_i` inside the cell).
//!   What it cannot prove (mostly power cells empty within the box: fine particles wholly
//!   covered by coarser balls, where no interior point exists to bound the error about) goes
//!   to [`exact_cover::sphere_uncovered_power`], which decides the claim exactly (including
//!   the minimum and a flat cell). A ball holding all of `S_i` (`|q_j| + r_i <= r_j`, with
//!   `1e-12` of slack) settles the particle first: interior. Margins are the float margins
//!   (`min(max |v| − 1, 1 − min |y|)·r_i` in the general case), `0` where the exact predicate
//!   decided without a float cell.
//! - With the opt-in `tie > 0`, a particle is boundary iff its float margin exceeds `tie·r_i`,
//!   as at a uniform radius; a particle without a float margin (no interior point to bound
//!   the error about) is decided by the exact predicate.
//! - Neighbours come from [`boundary_core::RadiusGrid`] (one grid per radius level, so radii
//!   100x apart cost no more than the neighbours that really reach). How often the exact
//!   predicate decides (`cargo run --release -p boundary-dilts --example fallbacks`): 33 of
//!   1,794 particles of `graded_column2d`, 96 of 1,567 of `graded_pool3d` (61 and 289
//!   without the general float test).
//!
//! # Solid half-spaces
//! In a [`boundary_core::Domain`] with solid half-spaces, particle `i` is interior iff every
//! point of `S_i` outside the closed solids is covered (see [`boundary_core::domain`]). With
//! `y = x − p_i`, a point of `S_i` outside the solid `x_a <= c` lies strictly inside the
//! half-space `−y_a <= p_a − c` (and for `x_a >= c` inside `y_a <= c − p_a`), so the uncovered
//! part of `S_i` is `S_i` in the interior of the cell cut by one more plane per solid: the
//! power-cell question of the previous section, with planes that may pass through or beyond
//! `p_i` (a particle on or inside a solid). It is decided by the same code: the float power
//! cell with the solid planes among its planes (their normals exact, their offsets rounded
//! twice, `2u` relative, inside the plane error of the bound), its general test where a plane
//! comes within `1e-3·r_i` of `p_i`, and the exact predicate
//! ([`exact_cover::sphere_uncovered_in`]), whose integer planes take the solids
//! as exact differences in the common unit. Only particles whose closed ball reaches a solid
//! (fluid depth at most `r_i`, with `1e-9` relative slack for the rounded depth) take this
//! path; the others cannot see a solid and keep the usual one. A solid holding the whole
//! ball (depth below `−r_i` by `1e-12` relative) makes the particle interior at once. A point
//! on a solid's surface is covered (closed solids): a tie, interior. Tested against
//! brute-force enumeration in exact rationals, near-ties included (`tests/domain.rs`).
//!
//! # Solid meshes
//! In 3D a [`boundary_core::Domain`] may also hold solids given as the inside of closed
//! triangle meshes ([`boundary_core::SolidMesh`]). They are not planes of a cell, so their
//! labels are exact away from the mesh surface and decided up to a stated tolerance near it:
//! - **Exact.** A particle whose closed ball stays clear of every mesh surface (distance
//!   above `r_i`, with `1e-9` relative slack and the mesh's rounding) gets its label without
//!   the meshes (with the half-spaces, exactly as above), or interior when a mesh holds the
//!   whole ball. A particle that is interior without the meshes stays interior: a solid only
//!   adds cover.
//! - **Tolerance.** A particle whose ball meets a mesh surface and which is boundary without
//!   the meshes is boundary iff a *witness* is found: a point of `S_i` strictly outside every
//!   neighbour ball (`|x − p_j| > r_j + 1e-9·r_i`, computed relative to `p_i`), outside every
//!   half-space by `1e-9·r_i` plus its rounding, and outside every mesh at a distance above
//!   `tol = 1e-9·r_i + ` [`boundary_core::SolidMesh::rounding`]. A witness is searched on a
//!   Fibonacci sphere of 2,048 directions, then by a compass search on the sphere (steps down
//!   to `1e-7` rad) from the 8 best of them. A boundary label found this way is certified (the
//!   witness is one); an interior one is not: **an uncovered part of `S_i` that lies within
//!   `tol` of the mesh surface, or that is too small for the sample and the local search to
//!   reach (much smaller than the sample spacing, about `0.08` rad, and not on the slope the
//!   search climbs), counts as covered.** So with meshes `exact` may call such a particle
//!   interior; elsewhere its labels stay exact.
//! - Per-particle radii work as without meshes (the witness tests each neighbour at its own
//!   radius). Margins: those without the meshes, capped at `0` where a mesh made the particle
//!   interior.
//! - Tested against the same solids as half-spaces (box meshes) and against a dense-sampling
//!   oracle around an icosphere obstacle (`tests/mesh.rs`).
//!
//! # Time steps: the incremental tracker
//! [`Tracker`] follows one particle set over the time steps of a simulation and returns at
//! every step the labels a full detection gives, bit for bit, recomputing only the particles
//! whose label may have changed: a coverage depth that moves by at most twice the largest
//! displacement, bounded below at each particle's last evaluation from its float cell (module
//! [`tracker`], with the proof). With stable particle ids ([`Tracker::update_with_ids`]) it
//! follows inflow, outflow and reordering.
//!
//! # Policy: ties, duplicates, degenerate input
//! - **Ties.** A cell that reaches exactly to `r` touches `S_i` only at points equidistant from
//!   `p_i` and another particle, which the closed ball of that particle covers: a tie is
//!   *interior*, decided exactly. Perfect lattices at `r = a/√2` (2D) and `r = a·√3/2` (3D) are
//!   exact ties for every inner particle *if `r` is the exact tie*; a float `r` is one ulp
//!   above or below it: `fl(1/√2)` lies above `1/√2` (inner particles interior), `fl(√3/2)`
//!   lies below `√3/2` (the cube corners are uncovered: every particle boundary).
//! - **Opt-in tolerance `tie`** ([`ExactParams::tie`]; `--set tie=1e-9`): a particle is
//!   boundary iff its float margin exceeds `tie·r`; margins within `±tie·r` count as ties
//!   (interior) and the exact fallback is not used. For users who want lattice round-off treated
//!   as ties; `tie = 1e-9` ([`TIE_TOLERANCE`]) gives the labels of release 0.1. Finite, `>= 0`.
//! - **Margins** are the float margins (`(max |v| − 1)·r`): meaningful to about `τ·r`; the
//!   *label*, not the margin, is exact. Near a tie the margin's sign may disagree with the label.
//! - **Duplicates.** Particles at exactly the same position as `p_i` do not cover `S_i`: they are
//!   ignored when building `V_i`. Two coincident particles alone are both boundary.
//!   Near-duplicates (distinct positions, however close) are ordinary neighbours.
//! - **Clipping tolerance.** Vertices within `1e-12·r` of a clipping plane count as on it
//!   (`cell::PLANE_EPS`); this enters the bound above.
//! - **Margins saturate.** The cell starts as the box `[p_i − r, p_i + r]`, so a particle with
//!   no neighbour has margin `(√D − 1)·r`, the largest possible.
//! - Neighbours at `2r` or more change nothing (their ball touches `S_i` at one point at most);
//!   the exact predicate excludes them exactly.
//!
//! # Hard cases
//! What `exact` returns on the hard cases (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`):
//! - Perfect lattices at the float tie radius and 4 ulps either side of it: decided exactly.
//!   Square lattice: at `fl(1/√2)` and above, inner particles interior; 4 ulps below, every
//!   particle boundary. Cubic lattice: at `fl(√3/2)` and 4 ulps below, every particle
//!   boundary; 4 ulps above, inner particles interior. (With `tie=1e-9`: inner particles
//!   interior at all of them, as in release 0.1.)
//! - Exact duplicates: each copy gets the label of the single particle (a doubled 5³ lattice at
//!   `r = 1.2`: the 98 surface positions, twice). Near-duplicates 1e-12 apart are neighbours
//!   like any other, and a twin covers the half of `S_i` facing it, so 18 of those 196 copies
//!   become interior: correct by the definition.
//! - A single particle, two particles (coincident, or exactly `2r` apart), lines, and
//!   collinear or coplanar sets in 3D: every particle boundary.
//! - Offsets of 1e6 and 1e9 at `r = 0.01`, and `r` from 1e-9 to 1e9: the labels of the same
//!   lattice at the origin and unit scale. Empty input: empty labels.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_exact::ExactDetector;
//!
//! // A 5 x 5 square lattice of spacing 1 at r = 0.8: only the centre 3 x 3 block is interior.
//! let rows: Vec<[f64; 2]> = (0..25).map(|k| [(k % 5) as f64, (k / 5) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let detection = ExactDetector::default().detect_2d(&set, Radius::new(0.8).unwrap()).unwrap();
//! assert_eq!(detection.labels.boundary_count(), 16);
//! assert!(!detection.labels.is_boundary(12)); // the centre
//! ```

mod cell;
pub mod exact_cover;
mod interior;
mod mesh;
mod power;
pub mod tracker;

pub use tracker::Tracker;

use boundary_core::{
    AnyParticleSet, Capabilities, DetectError, Detection, Dim, HalfSpace, Job, JobByDim, Labels,
    Method, NeighbourGrid, ParamSet, Params, ParticleSet, Point, Radius, Solids, Support,
    SupportedDim,
};
use cell::{Clipper, ConvexCell, Polygon, Polyhedron};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

/// The tolerance of the opt-in parameter `tie` up to release 0.1: with `--set tie=1e-9` a
/// particle is boundary iff its float margin exceeds `1e-9·r` (lattice round-off counted as
/// ties). The default `tie = 0` gives the exact labels instead.
pub const TIE_TOLERANCE: f64 = 1e-9;

/// Clipping stops once every vertex lies within `(1 − INTERIOR_BAND)·r`: the particle is then
/// interior by at least `INTERIOR_BAND·r` whatever the remaining neighbours do. Reported
/// margins are exact above `−INTERIOR_BAND·r` and upper bounds below it.
pub const INTERIOR_BAND: f64 = 1e-6;

/// Neighbours are sorted lazily: the nearest `FIRST_BATCH` first, which settle most interior
/// particles (a jittered cubic lattice needs about 6 to 10), the rest only when needed.
const FIRST_BATCH: usize = 16;

/// The float cell first clips by the neighbours within `FIRST_REACH·r` (nearest first): most
/// interior cells are settled by them. Every other neighbour has a bisector offset of at
/// least `FIRST_REACH/2` (units of `r`, less `1e-9` relative for the rounding of distances),
/// so a cell that lies within that after them is final; other cells gather the rest (up to
/// `2r`) and go on, in the same order. 1.1: on the jittered ball (r = 1.2 spacings) almost
/// every settled cell needs no neighbour beyond it; a larger reach reads more neighbours, a
/// smaller one (1.05) settles fewer cells in the first stage (both cost more instructions
/// under callgrind on a jittered ball).
const FIRST_REACH: f64 = 1.1;

/// Grid cell side, in units of `r`: equal to the first reach, so that its query visits
/// about `3^D` cells (cells of side `r` visit more cells for the same neighbours).
const GRID_CELL: f64 = 1.1;

/// Unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;

boundary_core::declare_params! {
    /// The parameters of `exact` (string form: `--set tie=…`, see `boundary::registry`).
    #[derive(Debug, Clone, PartialEq)]
    pub struct ExactParams for "exact" {
        /// Opt-in tie tolerance, in units of `r`: a particle is boundary iff its float margin
        /// exceeds `tie·r`, margins within `±tie·r` count as ties (interior) and the exact
        /// fallback is not used. `0` (the default) gives the exact labels; [`TIE_TOLERANCE`]
        /// (`1e-9`) the labels of release 0.1. Finite, `>= 0`.
        pub tie: f64 = 0.0, check::non_negative().because("a finite number >= 0"),
            "tie tolerance: boundary iff the float margin exceeds tie·r (e.g. 1e-9 treats \
             lattice round-off as ties); 0 = exact labels (definition, JCP Sec. 2)";
    }
}

/// The exact detector (`exact`): restricted Voronoi cells. See the crate documentation.
/// `ExactDetector::default()` gives the exact labels.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExactDetector {
    params: ExactParams,
}

impl ExactDetector {
    /// Like [`boundary_core::BoundaryDetector::detect`], also returning how many particles the exact
    /// fallback decided (those whose float decision fell inside its error bound).
    pub fn detect_counting_fallbacks(
        &self,
        set: &AnyParticleSet,
        r: Radius,
    ) -> Result<(Detection, usize), DetectError> {
        match set {
            AnyParticleSet::D2(s) => dispatch::<2, Polygon>(s, s.len(), r, self.params.tie),
            AnyParticleSet::D3(s) => dispatch::<3, Polyhedron>(s, s.len(), r, self.params.tie),
        }
    }
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(ExactDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(ExactDetector, ExactParams);

impl Method for ExactDetector {
    const NAME: &'static str = "exact";

    fn describe(&self) -> Params {
        self.params.listing()
    }

    /// Certified; per-particle radii (power cells), solid half-spaces exactly, like every
    /// other label (crate docs, "Solid half-spaces"), and solid meshes exactly away from their
    /// surface and up to a stated tolerance near it (crate docs, "Solid meshes"). The ghosts
    /// serve as neighbours only: a halo of `2r` gives the global labels.
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            certified: true,
            radii: Support::Honoured,
            half_spaces: Support::Honoured,
            meshes: Support::Honoured,
            ..Capabilities::DEFAULT
        }
    }

    fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        let tie = self.params.tie;
        match job.by_dim() {
            JobByDim::D2(job) => classify_cells::<2, Polygon>(job, tie),
            JobByDim::D3(job) if !job.solids.meshes().is_empty() => {
                // Crate docs, "Solid meshes": the labels with the half-spaces only, then the
                // witness search where a ball meets a mesh surface.
                let half_spaces = job.solids.without_meshes();
                let base = classify_cells::<3, Polyhedron>(
                    Job {
                        solids: &half_spaces,
                        ..job
                    },
                    tie,
                )?;
                let radii = match job.set.resolved_radii(job.r)? {
                    Some(radii) => radii,
                    None => vec![job.r.get(); job.set.len()],
                };
                mesh::apply_meshes(
                    job.set,
                    job.owned,
                    &radii,
                    job.solids.meshes(),
                    job.solids.half_spaces(),
                    base,
                )
            }
            JobByDim::D3(job) => classify_cells::<3, Polyhedron>(job, tie),
        }
    }
}

/// The cells of the owned particles of `job`, with the solid half-spaces when it has any.
fn classify_cells<const D: usize, C>(job: Job<'_, D>, tie: f64) -> Result<Detection, DetectError>
where
    C: ConvexCell<D> + Default + Send + Clone,
{
    Ok(if job.solids.is_empty() {
        dispatch::<D, C>(job.set, job.owned, job.r, tie)?.0
    } else {
        dispatch_in::<D, C>(job.set, job.owned, job.r, tie, job.solids)?.0
    })
}

/// [`dispatch`] with solid half-spaces. A particle whose closed ball stays clear of every solid
/// (fluid depth above `r_i`, with `1e-9` of slack for the rounded depth) gets the label it
/// would get without them, by the usual path; the others, the layer next to the solids, are
/// decided with each solid as one more plane of the power cell, where the float test and the
/// exact predicate take the solid planes too. Returns the detection and the number of exact
/// fallbacks of the first part.
fn dispatch_in<const D: usize, C>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    tie: f64,
    solids: &Solids,
) -> Result<(Detection, usize), DetectError>
where
    C: ConvexCell<D> + Default + Send + Clone,
{
    let half_spaces: &[HalfSpace] = solids.half_spaces();
    let radii = match set.resolved_radii(r)? {
        Some(radii) => radii,
        None => vec![r.get(); set.len()],
    };
    let positions = set.positions();
    let touches = |i: usize| solids.half_space_reaches(positions[i].as_slice(), radii[i]);
    let (near, far): (Vec<usize>, Vec<usize>) = (0..count).partition(|&i| touches(i));
    if near.is_empty() {
        return dispatch::<D, C>(set, count, r, tie);
    }
    // The particles clear of the solids first, then the rest of the set, as one reordered
    // copy: the usual path classifies its first `far.len()` particles.
    let mut order = far.clone();
    order.extend(&near);
    order.extend(count..set.len());
    let (far_detection, fallbacks) = dispatch::<D, C>(&set.subset(&order), far.len(), r, tie)?;
    let near_results = power::classify_some::<D, C>(set, &near, &radii, tie, half_spaces)?;
    let mut margins = vec![0.0; count];
    let mut boundary = vec![false; count];
    let far_margins = far_detection.margin.unwrap_or_default();
    for (slot, &i) in far.iter().enumerate() {
        boundary[i] = far_detection.labels.is_boundary(slot);
        margins[i] = far_margins.get(slot).copied().unwrap_or(0.0);
    }
    let mut near_fallbacks = 0;
    for (&i, (margin, label, exact)) in near.iter().zip(near_results) {
        boundary[i] = label;
        margins[i] = margin;
        near_fallbacks += usize::from(exact);
    }
    Ok((
        Detection {
            labels: Labels::new(boundary),
            margin: Some(margins),
        },
        fallbacks + near_fallbacks,
    ))
}

/// A neighbour: `(|p_j − p_i|²` as its bit pattern, `j`, the index of `p_j` in the positions
/// passed along with it`)`. Ordered by distance, ties by `j` (the third field never decides:
/// `j` is unique). `u32` indices: a set holds at most `u32::MAX` particles.
type Near = (u64, u32, u32);

/// Per-thread working memory.
#[derive(Default)]
struct Scratch<const D: usize, C: ConvexCell<D>> {
    cell: C,
    /// The cell of the first, fast pass (`cell::ConvexCell::Fast`).
    fast: C::Fast,
    /// The neighbours of the particle being classified ([`Near`]): every other particle within
    /// `2r(1 + 1e-12)` ([`NEAR_SLACK`]), exact duplicates of `p_i` left out.
    near: Vec<Near>,
    /// `near` holds every neighbour whose bisector offset (units of `r`) is below `beyond`;
    /// infinite: every neighbour within `2r(1 + 1e-12)`.
    beyond: f64,
}

/// The neighbours the float cell clips by, nearest first, as far as they are gathered: every
/// neighbour not in `list` has a bisector offset (units of `r`) of at least `beyond`;
/// `gather_all` replaces `list` by all of them (then `beyond` is infinite).
struct Neighbours<'a> {
    list: &'a mut Vec<Near>,
    beyond: &'a mut f64,
    gather_all: &'a dyn Fn(&mut Vec<Near>),
}

/// Neighbours are gathered within `2r(1 + NEAR_SLACK)`: a little beyond `2r`, so that no
/// neighbour whose exact distance is below `2r` is lost to the rounding of the query (the
/// squared distances carry a relative error of a few `u`, far below `1e-12`). The float cell
/// and the certificates use them all (a bisector just beyond `r` only trims the cell there:
/// harmless); the exact predicate drops those at `2r` or more exactly.
const NEAR_SLACK: f64 = 1e-12;

/// What the float clipping says about one particle.
struct FloatCell {
    /// `max |v| − 1` over the float cell's vertices, in units of `r`.
    margin: f64,
    /// The error bound `τ` of the crate docs: the exact margin has the same sign as `margin`
    /// whenever `|margin| > tau` (and the run was not flagged degenerate).
    tau: f64,
    /// A clip was near-degenerate (see `cell::ConvexCell::degenerate`): no bound.
    degenerate: bool,
    /// How many neighbours were taken (the first `used` of the list, sorted nearest first):
    /// the exact cell of the bound is clipped by exactly their planes.
    used: usize,
}

/// Classifies the first `count` particles of `set` (all of them are neighbours): Voronoi cells
/// at a uniform radius, power cells for a set with a radius per particle. Also returns the
/// number of particles decided by the exact fallback.
fn dispatch<const D: usize, C>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    tie: f64,
) -> Result<(Detection, usize), DetectError>
where
    C: ConvexCell<D> + Default + Send + Clone,
{
    match set.resolved_radii(r)? {
        None => detect_with::<D, C>(set, count, r, tie),
        Some(radii) => power::detect_power::<D, C>(set, count, &radii, tie),
    }
}

/// Classifies the first `count` particles of `set` (all of them are neighbours) at the uniform
/// radius `r`; also returns the number of particles decided by the exact fallback.
fn detect_with<const D: usize, C>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    tie: f64,
) -> Result<(Detection, usize), DetectError>
where
    C: ConvexCell<D> + Default + Send + Clone,
{
    let r = r.get();
    // Cells of side GRID_CELL·r, queried at FIRST_REACH·r and 2r: the 3^D/5^D visited cells
    // hold fewer non-neighbours than the 3^D cells of side 2r.
    let grid = NeighbourGrid::new(set, r * GRID_CELL)?;
    let positions = set.positions();
    // Neighbours are read from the grid's copy of the positions, in cell order: the query
    // has just streamed through them (from `positions`, in input order, the first read of
    // each was a cache miss: 43 % of `classify`'s samples at 200k particles).
    let sorted_positions = grid.cell_sorted_positions();
    let key = |j: usize, slot: usize, d2: f64| (d2.to_bits(), j as u32, slot as u32);
    // The particles in the grid's cell order (consecutive queries share cached cells), each
    // result stored straight at its input index, so that no serial pass puts them back in
    // input order (on many threads such a pass is a large part of the time).
    let margins: Vec<AtomicU64> = (0..count).map(|_| AtomicU64::new(0)).collect();
    let boundary: Vec<AtomicBool> = (0..count).map(|_| AtomicBool::new(false)).collect();
    let fallbacks = AtomicUsize::new(0);
    grid.cell_order()
        .par_iter()
        .for_each_init(Scratch::<D, C>::default, |scratch, &i| {
            let i = i as usize;
            if i >= count || boundary_core::stop::requested() {
                return;
            }
            let p = positions[i];
            // The neighbours within FIRST_REACH·r first (`cell_margin` gathers the rest when
            // the cell needs them); d2 == 0 is `i` itself or an exact duplicate, which does
            // not cover (crate docs).
            scratch.near.clear();
            grid.gather_within(&p, FIRST_REACH * r, &mut scratch.near, key);
            scratch.near.retain(|x| x.0 != 0);
            // Most particles of a bulk are settled here, before any cell is clipped (crate
            // docs, "The interior filter").
            let (margin, label, exact) = if let Some(reach) =
                interior::interior_reach(&p, sorted_positions, r, &scratch.near)
            {
                ((reach - 1.0) * r, false, false)
            } else {
                scratch.beyond = 0.5 * FIRST_REACH * (1.0 - 1e-9);
                let gather_all = |near: &mut Vec<Near>| {
                    near.clear();
                    grid.gather_within(&p, 2.0 * r * (1.0 + NEAR_SLACK), near, key);
                    near.retain(|x| x.0 != 0);
                };
                classify(&p, sorted_positions, r, tie, scratch, &gather_all)
            };
            margins[i].store(margin.to_bits(), Ordering::Relaxed);
            boundary[i].store(label, Ordering::Relaxed);
            if exact {
                fallbacks.fetch_add(1, Ordering::Relaxed);
            }
        });
    // In place (same size and alignment): no copy.
    let labels: Vec<bool> = boundary.into_iter().map(AtomicBool::into_inner).collect();
    let margins: Vec<f64> = margins
        .into_iter()
        .map(|m| f64::from_bits(m.into_inner()))
        .collect();
    Ok((
        Detection {
            labels: Labels::new(labels),
            margin: Some(margins),
        },
        fallbacks.into_inner(),
    ))
}

/// The detection from per-particle `(margin, label, decided by the exact predicate)`, with the
/// number of exact-predicate decisions.
fn assemble(results: Vec<(f64, bool, bool)>) -> (Detection, usize) {
    let fallbacks = results.iter().filter(|x| x.2).count();
    let labels = results.iter().map(|x| x.1).collect::<Labels>();
    let margins = results.into_iter().map(|x| x.0).collect();
    (
        Detection {
            labels,
            margin: Some(margins),
        },
        fallbacks,
    )
}

/// The label of the particle at `p` whose neighbours are in `scratch.near`: `(margin, label,
/// whether the exact predicate decided it)`. The float cell first; where its bound does not
/// decide (or a clip was near-degenerate), the two certificates; then the exact predicate.
fn classify<const D: usize, C: ConvexCell<D> + Clone>(
    p: &Point<D>,
    positions: &[Point<D>],
    r: f64,
    tie: f64,
    scratch: &mut Scratch<D, C>,
    gather_all: &dyn Fn(&mut Vec<Near>),
) -> (f64, bool, bool) {
    if C::HAS_FAST {
        // The fast cell first: where it was not flagged it has this cell's vertices, hence
        // the same margin and bound; a particle it cannot settle takes the full path below.
        let near = Neighbours {
            list: &mut scratch.near,
            beyond: &mut scratch.beyond,
            gather_all,
        };
        let fast = cell_margin(p, positions, r, near, &mut scratch.fast, true, true);
        if !fast.degenerate && (tie > 0.0 || fast.margin.abs() > fast.tau) {
            let margin = fast.margin * r;
            let label = if tie > 0.0 {
                margin > tie * r
            } else {
                fast.margin > 0.0
            };
            return (margin, label, false);
        }
    }
    let near = Neighbours {
        list: &mut scratch.near,
        beyond: &mut scratch.beyond,
        gather_all,
    };
    let cell = cell_margin(p, positions, r, near, &mut scratch.cell, false, true);
    let margin = cell.margin * r;
    if tie > 0.0 {
        return (margin, margin > tie * r, false);
    }
    if !cell.degenerate && cell.margin.abs() > cell.tau {
        return (margin, cell.margin > 0.0, false);
    }
    // The certificates and the exact predicate need every neighbour within 2r.
    if scratch.beyond.is_finite() {
        gather_all(&mut scratch.near);
        scratch.beyond = f64::INFINITY;
    }
    // Two certificates before the exact predicate (crate docs, "Certificates"): they settle
    // the clear-cut particles of perfect lattices, whose clips are flagged near-degenerate
    // although their margins are far from 0.
    if cell.margin > CERTIFICATE_MIN_MARGIN && boundary_certificate(p, positions, r, scratch) {
        return (margin, true, false);
    }
    if cell.margin < -CERTIFICATE_MIN_MARGIN && interior_certificate(p, positions, r, scratch) {
        return (margin, false, false);
    }
    let others: Vec<Point<D>> = scratch
        .near
        .iter()
        .map(|x| positions[x.2 as usize])
        .collect();
    (margin, exact_cover::sphere_uncovered(p, &others, r), true)
}

/// Whether the sphere of radius `r` around `centre` is **not** covered by the closed balls of
/// radius `r` around `others` (boundary): the label `exact` gives, for a particle whose
/// neighbours the caller has gathered (any superset of the points within `2r` will do; copies
/// of `centre` and points at `2r` or farther are ignored, exactly). Other certified detectors
/// use it for the particles their own float test cannot decide; it is exact for the given
/// `f64` input, as [`exact_cover::sphere_uncovered`], and far faster on lattices (crate docs,
/// "Certificates").
///
/// ```
/// use boundary_core::{Point, Radius};
///
/// // Four neighbours at distance 1 on the axes cover the circle iff r >= 1/√2.
/// let c = Point::<2>::new(0.0, 0.0);
/// let n = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]].map(Point::<2>::from);
/// let tie = Radius::new(std::f64::consts::FRAC_1_SQRT_2).unwrap();
/// assert!(!boundary_exact::sphere_uncovered_2d(&c, &n, tie));
/// assert!(boundary_exact::sphere_uncovered_2d(&c, &n, Radius::new(0.7).unwrap()));
/// ```
pub fn sphere_uncovered_2d(centre: &Point<2>, others: &[Point<2>], r: Radius) -> bool {
    sphere_uncovered::<2, Polygon>(centre, others, r.get())
}

/// [`sphere_uncovered_2d`] in 3D.
///
/// ```
/// use boundary_core::{Point, Radius};
///
/// // The cubic lattice of spacing 1 covers the sphere from r = √3/2 up (fl(√3/2) lies below).
/// let c = Point::<3>::new(0.0, 0.0, 0.0);
/// let mut n = Vec::new();
/// for k in 0..27 {
///     let q = Point::<3>::new((k % 3) as f64 - 1.0, (k / 3 % 3) as f64 - 1.0, (k / 9) as f64 - 1.0);
///     n.push(q);
/// }
/// let tie = 3f64.sqrt() / 2.0;
/// assert!(boundary_exact::sphere_uncovered_3d(&c, &n, Radius::new(tie).unwrap()));
/// assert!(!boundary_exact::sphere_uncovered_3d(&c, &n, Radius::new(tie.next_up()).unwrap()));
/// ```
pub fn sphere_uncovered_3d(centre: &Point<3>, others: &[Point<3>], r: Radius) -> bool {
    sphere_uncovered::<3, Polyhedron>(centre, others, r.get())
}

/// [`sphere_uncovered_2d`] with a radius per ball: whether the circle of radius `r` around
/// `centre` is **not** covered by the closed discs `others` (centre, radius), decided exactly
/// as `exact` decides a particle of a set with per-particle radii (crate docs, "A radius per
/// particle"). `others` may be any superset of the discs reaching the circle; copies of
/// `centre` are ignored whatever their radius. Every radius must be positive and finite.
///
/// ```
/// use boundary_core::Point;
///
/// // A unit circle inside a disc of radius 2 centred 0.5 away is covered; radius 1.4 is not.
/// let c = Point::<2>::new(0.0, 0.0);
/// assert!(!boundary_exact::sphere_uncovered_power_2d(&c, 1.0, &[(Point::<2>::new(0.5, 0.0), 2.0)]));
/// assert!(boundary_exact::sphere_uncovered_power_2d(&c, 1.0, &[(Point::<2>::new(0.5, 0.0), 1.4)]));
/// ```
pub fn sphere_uncovered_power_2d(centre: &Point<2>, r: f64, others: &[(Point<2>, f64)]) -> bool {
    power::sphere_uncovered::<2, Polygon>(centre, r, others, &[])
}

/// [`sphere_uncovered_power_2d`] in 3D.
pub fn sphere_uncovered_power_3d(centre: &Point<3>, r: f64, others: &[(Point<3>, f64)]) -> bool {
    power::sphere_uncovered::<3, Polyhedron>(centre, r, others, &[])
}

/// [`sphere_uncovered_power_2d`] where the closed solid half-spaces `solids` cover too (crate
/// docs, "Solid half-spaces"): the decision `exact` takes for a particle next to a solid.
///
/// ```
/// use boundary_core::{HalfSpace, Point};
///
/// // A lone particle resting on the floor y <= 0 at height 0.5 (r = 1) is boundary; with a
/// // row of neighbours 0.5 apart beside it and one above, it is covered.
/// let floor = [HalfSpace::parse("y<0").unwrap()];
/// let c = Point::<2>::new(0.0, 0.5);
/// assert!(boundary_exact::sphere_uncovered_in_2d(&c, 1.0, &[], &floor));
/// let n = [[0.9, 0.5], [-0.9, 0.5], [0.0, 1.4], [0.7, 1.2], [-0.7, 1.2]].map(|p| (Point::<2>::from(p), 1.0));
/// assert!(!boundary_exact::sphere_uncovered_in_2d(&c, 1.0, &n, &floor));
/// assert!(boundary_exact::sphere_uncovered_in_2d(&c, 1.0, &n, &[]));
/// ```
pub fn sphere_uncovered_in_2d(
    centre: &Point<2>,
    r: f64,
    others: &[(Point<2>, f64)],
    solids: &[HalfSpace],
) -> bool {
    power::sphere_uncovered::<2, Polygon>(centre, r, others, solids)
}

/// [`sphere_uncovered_in_2d`] in 3D.
pub fn sphere_uncovered_in_3d(
    centre: &Point<3>,
    r: f64,
    others: &[(Point<3>, f64)],
    solids: &[HalfSpace],
) -> bool {
    power::sphere_uncovered::<3, Polyhedron>(centre, r, others, solids)
}

fn sphere_uncovered<const D: usize, C: ConvexCell<D> + Default + Clone>(
    centre: &Point<D>,
    others: &[Point<D>],
    r: f64,
) -> bool {
    if u32::try_from(others.len()).is_err() {
        // Beyond the u32 indices of the neighbour lists (4·10^9 points): decide exactly.
        return exact_cover::sphere_uncovered(centre, others, r);
    }
    let mut scratch = Scratch::<D, C>::default();
    let reach2 = (2.0 * r * (1.0 + NEAR_SLACK)).powi(2);
    for (j, q) in others.iter().enumerate() {
        let d2 = (q - centre).norm_squared();
        if d2 > 0.0 && d2 <= reach2 {
            scratch.near.push((d2.to_bits(), j as u32, j as u32));
        }
    }
    scratch.beyond = f64::INFINITY;
    classify(centre, others, r, 0.0, &mut scratch, &|_| {}).1
}

/// The certificates are tried only on float margins at least this far from 0 (units of `r`):
/// closer, the exact predicate decides directly.
const CERTIFICATE_MIN_MARGIN: f64 = 1e-6;

/// Slack of the certificates' float tests (units of `r`): far above their rounding (a few
/// hundred `u` for points and planes of norm at most 2, crate docs "Exactness", fact 2).
const CERTIFICATE_SLACK: f64 = 1e-11;

/// Boundary certificate: a point `x` strictly inside every bisector half-space of the
/// neighbours within `2r(1 + 1e-12)` with `|x| > 1` (units of `r`) proves the cell reaches
/// beyond `r`, hence boundary (crate docs, "Why the Voronoi cell decides it"). The candidate is
/// each of the float cell's (up to 8) farthest vertices beyond the sphere, pulled toward `p_i`
/// halfway back to it; every
/// test holds with [`CERTIFICATE_SLACK`] to spare, so the rounding cannot fake it. The float
/// cell's topology is not trusted: only the point is checked, against every neighbour.
fn boundary_certificate<const D: usize, C: ConvexCell<D>>(
    p: &Point<D>,
    positions: &[Point<D>],
    r: f64,
    scratch: &Scratch<D, C>,
) -> bool {
    // Candidates: the vertices beyond the sphere, farthest first (the farthest may be an
    // artefact of a near-degenerate clip; another one often proves the same).
    let mut candidates: Vec<[f64; D]> = scratch
        .cell
        .vertices()
        .iter()
        .filter(|v| v.iter().map(|x| x * x).sum::<f64>() > 1.0 + 2.0 * CERTIFICATE_SLACK)
        .copied()
        .collect();
    let norm2 = |v: &[f64; D]| v.iter().map(|x| x * x).sum::<f64>();
    candidates.sort_unstable_by(|a, b| norm2(b).total_cmp(&norm2(a)));
    candidates.iter().take(8).any(|v| {
        let norm = norm2(v).sqrt();
        let lambda = (1.0 + 0.5 * (norm - 1.0)) / norm;
        let x: [f64; D] = std::array::from_fn(|k| v[k] * lambda);
        if norm2(&x) <= 1.0 + CERTIFICATE_SLACK {
            return false;
        }
        scratch.near.iter().all(|&(_, _, j)| {
            let j = j as usize;
            let q: [f64; D] = std::array::from_fn(|k| (positions[j][k] - p[k]) / r);
            let len = q.iter().map(|a| a * a).sum::<f64>().sqrt();
            let s: f64 = (0..D).map(|k| q[k] / len * x[k]).sum::<f64>() - 0.5 * len;
            s < -CERTIFICATE_SLACK
        })
    })
}

/// Nearest first, ties by index. The squared distances are positive finite `f64`s, whose bit
/// patterns order as the numbers do: an integer comparison (callgrind: the neighbour
/// selection took 2.8 % more instructions with `f64::total_cmp`).
fn by_distance(a: &Near, b: &Near) -> std::cmp::Ordering {
    a.cmp(b)
}

/// How far the interior certificate moves a bisector outward (units of `r`) when clipping by
/// it would be near-degenerate: first not at all, then by these amounts, each far above
/// [`cell::PLANE_EPS`] (so a vertex the plane passed through is now clearly inside) and far
/// below the margins the certificate is tried on (at least [`CERTIFICATE_MIN_MARGIN`]).
const CERTIFICATE_SHIFTS: [f64; 4] = [0.0, 1e-9, 3.7e-9, 1.3e-8];

/// Interior certificate: the float cell clipped again, nearest neighbour first. A clip that
/// would be near-degenerate is retried with the plane moved outward ([`CERTIFICATE_SHIFTS`]),
/// and skipped if every try is. A moved plane bounds a larger half-space, and skipping one
/// only enlarges the cell too, so the result contains the exact cell; the clips kept are all
/// covered by the bound of the crate docs ("Exactness"), so a margin below `−τ` for that
/// larger cell proves the particle interior. Perfect lattices need the shifts: their bisectors
/// pass exactly through the vertices of the cell, and skipping every such plane leaves the
/// cell far too large (`pysph_case5`: 1,854 particles at margin −0.33r went to the exact
/// predicate).
fn interior_certificate<const D: usize, C: ConvexCell<D> + Clone>(
    p: &Point<D>,
    positions: &[Point<D>],
    r: f64,
    scratch: &mut Scratch<D, C>,
) -> bool {
    if C::HAS_FAST {
        if let Some(proved) =
            fast_interior_certificate(p, positions, r, &mut scratch.fast, &mut scratch.near)
        {
            return proved;
        }
    }
    full_interior_certificate(p, positions, r, &mut scratch.cell, &mut scratch.near)
}

/// The bisector of `p` and `q` in units of `r` about `p`: the unit normal `n` and the offset
/// of `n·x <= offset` (the expressions the error bound of the crate docs assumes).
fn bisector<const D: usize>(p: &Point<D>, q: &Point<D>, r: f64) -> ([f64; D], f64) {
    let d: [f64; D] = std::array::from_fn(|k| (q[k] - p[k]) / r);
    let len = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    (std::array::from_fn(|k| d[k] / len), 0.5 * len)
}

/// [`interior_certificate`] on the full cell: a near-degenerate clip is undone from a copy.
fn full_interior_certificate<const D: usize, C: Clipper<D> + Clone>(
    p: &Point<D>,
    positions: &[Point<D>],
    r: f64,
    cell: &mut C,
    near: &mut [Near],
) -> bool {
    near.sort_unstable_by(by_distance);
    cell.reset_box();
    let mut reach = (D as f64).sqrt();
    let mut rho0 = 1.0f64;
    let mut clips = 0usize;
    for &(_, _, j) in near.iter() {
        let (n, offset) = bisector(p, &positions[j as usize], r);
        if offset >= reach {
            break;
        }
        let saved = cell.clone();
        // The plane itself, then moved outward (a larger half-space) until the clip is not
        // near-degenerate; skipped if none is.
        let kept = CERTIFICATE_SHIFTS.iter().any(|&shift| {
            cell.clip(&n, offset + shift);
            if cell.degenerate() {
                cell.clone_from(&saved);
                false
            } else {
                true
            }
        });
        if !kept {
            continue;
        }
        rho0 = rho0.min(offset);
        clips += 1;
        reach = cell.max_norm2().sqrt();
    }
    reach - 1.0 < -float_bound(clips, rho0, reach)
}

/// [`interior_certificate`] on the fast cell: the same clips, nearest first, each at the first
/// shift of [`CERTIFICATE_SHIFTS`] at which it does not cut through a vertex, skipped if none,
/// where the fast cell answers that before clipping ([`cell::Clipper::touches`]), so no clip
/// is undone and the cell is never copied. Every clip kept cuts with every vertex clearly on
/// one side: the fast cell is then the exact clip of the float cell (crate docs, "Speed, same
/// result"), covered by the bound. `None` when the fast cell flags a clip for another reason
/// (merged cap points, too many vertices): the full cell decides then. On the perfect lattice
/// `pysph_case5` this path settles the particles whose first pass bailed at the lattice's
/// bisectors through vertices; the full cell's clip, cloned before every clip, took about
/// half of `exact`'s time there (perf).
fn fast_interior_certificate<const D: usize, F: Clipper<D>>(
    p: &Point<D>,
    positions: &[Point<D>],
    r: f64,
    cell: &mut F,
    near: &mut [Near],
) -> Option<bool> {
    near.sort_unstable_by(by_distance);
    cell.reset_box();
    let mut reach = (D as f64).sqrt();
    let mut rho0 = 1.0f64;
    let mut clips = 0usize;
    for &(_, _, j) in near.iter() {
        let (n, offset) = bisector(p, &positions[j as usize], r);
        if offset >= reach {
            break;
        }
        let Some(&shift) = CERTIFICATE_SHIFTS
            .iter()
            .find(|&&shift| !cell.touches(&n, offset + shift))
        else {
            continue;
        };
        cell.clip(&n, offset + shift);
        if cell.degenerate() {
            return None;
        }
        rho0 = rho0.min(offset);
        clips += 1;
        reach = cell.max_norm2().sqrt();
    }
    Some(reach - 1.0 < -float_bound(clips, rho0, reach))
}

/// The bound `τ` of the crate docs ("Exactness") after `clips` non-degenerate clips whose
/// smallest offset is `rho0` (at most 1, the box's inradius) and whose float reach is `reach`:
/// β = (24u + m·(64u + PLANE_EPS)) / ρ0, ρ0 shrunk by the offsets' relative error 8u;
/// τ = 2·β·max(reach, 1) + 8u, doubled for safety.
fn float_bound(clips: usize, rho0: f64, reach: f64) -> f64 {
    let rho0 = rho0 * (1.0 - 8.0 * U);
    let beta = (24.0 * U + clips as f64 * (64.0 * U + cell::PLANE_EPS)) / rho0;
    2.0 * (2.0 * beta * reach.max(1.0) + 8.0 * U)
}

/// The float restricted Voronoi cell of the particle at `p`, clipped by `near` nearest first
/// (sorted here as far as needed, and completed when the gathered ones do not settle the
/// cell), with its error bound (crate docs). With `stop_if_degenerate`, clipping stops at the
/// first near-degenerate clip (the result is then flagged and only good for discarding).
fn cell_margin<const D: usize, C: Clipper<D>>(
    p: &Point<D>,
    positions: &[Point<D>],
    r: f64,
    near: Neighbours<'_>,
    cell: &mut C,
    stop_if_degenerate: bool,
    settle: bool,
) -> FloatCell {
    let neighbours = near.list;
    let mut first = FIRST_BATCH.min(neighbours.len());
    if first < neighbours.len() {
        neighbours.select_nth_unstable_by(first, by_distance);
    }
    neighbours[..first].sort_unstable_by(by_distance);

    cell.reset_box();
    let mut reach = (D as f64).sqrt();
    // Without `settle` (the tracker), clipping goes on to the final cell.
    let settled = if settle {
        1.0 - INTERIOR_BAND
    } else {
        f64::NEG_INFINITY
    };
    // ρ0: a ball around the origin inside every used half-space (the box has inradius 1).
    let mut rho0 = 1.0f64;
    let mut clips = 0usize;
    let mut k = 0;
    loop {
        if k == neighbours.len() {
            // Every neighbour not gathered has an offset of at least `beyond`: when that is
            // beyond the cell, none can cut (as the break below); otherwise gather them all.
            // Their order extends this one: all of them are farther than every gathered one.
            if reach <= *near.beyond {
                break;
            }
            (near.gather_all)(neighbours);
            *near.beyond = f64::INFINITY;
            neighbours.sort_unstable_by(by_distance);
            first = usize::MAX;
            if k == neighbours.len() {
                break;
            }
        }
        if k == first {
            neighbours[first..].sort_unstable_by(by_distance);
        }
        let j = neighbours[k].2 as usize;
        k += 1;
        let q: [f64; D] = std::array::from_fn(|k| (positions[j][k] - p[k]) / r);
        let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let offset = 0.5 * len;
        if offset >= reach {
            // Sorted nearest first: no remaining bisector can reach the cell.
            break;
        }
        rho0 = rho0.min(offset);
        let n: [f64; D] = std::array::from_fn(|k| q[k] / len);
        cell.clip(&n, offset);
        if stop_if_degenerate && cell.degenerate() {
            break;
        }
        clips += 1;
        reach = cell.max_norm2().sqrt();
        if reach <= settled {
            break;
        }
    }
    FloatCell {
        margin: reach - 1.0,
        tau: float_bound(clips, rho0, reach),
        degenerate: cell.degenerate(),
        used: k,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundary_core::BoundaryDetector;

    /// The interior certificate on the fast cell answers as the one on the full cell (or
    /// hands over) for every particle of perfect and slightly jittered cubic lattices, at
    /// radii from just above the tie (`√3/2`) to 1.5 spacings, where the bisectors pass
    /// through the cells' vertices; and it proves the inner particles interior there.
    #[test]
    fn fast_interior_certificate_agrees_with_the_full_cell() {
        let mut seed = 5u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let (mut proved, mut handed_over) = (0, 0);
        for jitter in [0.0, 1e-13, 1e-3] {
            let mut points = vec![];
            for k in 0..216 {
                let c = [(k % 6) as f64, (k / 6 % 6) as f64, (k / 36) as f64];
                points.push(Point::<3>::from(c.map(|x| x + jitter * next())));
            }
            let positions = &points[..];
            for r in [0.8661, 0.9, 1.0, 1.2, 1.5] {
                for (i, p) in positions.iter().enumerate() {
                    let mut near: Vec<Near> = positions
                        .iter()
                        .enumerate()
                        .filter(|&(j, q)| j != i && (q - p).norm() <= 2.0 * r)
                        .map(|(j, q)| ((q - p).norm_squared().to_bits(), j as u32, j as u32))
                        .collect();
                    let mut fast = cell::SimplePolyhedron::default();
                    let mut full = Polyhedron::default();
                    let full_answer =
                        full_interior_certificate(p, positions, r, &mut full, &mut near);
                    match fast_interior_certificate(p, positions, r, &mut fast, &mut near) {
                        Some(answer) => {
                            assert_eq!(answer, full_answer, "jitter {jitter}, r {r}, {i}");
                            proved += answer as usize;
                        }
                        None => handed_over += 1,
                    }
                }
            }
        }
        // The 4^3 inner particles of each lattice at each radius from 0.9 on, at least (just
        // above the tie the margin is too small to certify).
        assert!(
            proved >= 3 * 4 * 64,
            "{proved} proved, {handed_over} handed over"
        );
    }

    /// Margins of particles `0..n` by the reference path: every neighbour within 2r gathered
    /// by brute force, sorted, clipped into the full cell (`Polygon` / `Polyhedron`), no fast
    /// cell, no staged gathering. With `settle = false` every neighbour is clipped (the full
    /// float cell), else clipping stops once the cell has settled, as the detector's does.
    fn reference_margins<const D: usize, C: ConvexCell<D> + Default>(
        set: &ParticleSet<D>,
        r: f64,
        settle: bool,
    ) -> Vec<f64> {
        let positions = set.positions();
        let reach2 = (2.0 * r * (1.0 + NEAR_SLACK)).powi(2);
        let mut cell = C::default();
        positions
            .iter()
            .map(|p| {
                let mut list: Vec<Near> = positions
                    .iter()
                    .enumerate()
                    .map(|(j, q)| ((q - p).norm_squared(), j))
                    .filter(|&(d2, _)| d2 > 0.0 && d2 <= reach2)
                    .map(|(d2, j)| (d2.to_bits(), j as u32, j as u32))
                    .collect();
                let mut beyond = f64::INFINITY;
                let near = Neighbours {
                    list: &mut list,
                    beyond: &mut beyond,
                    gather_all: &|_| {},
                };
                cell_margin(p, positions, r, near, &mut cell, false, settle).margin * r
            })
            .collect()
    }

    fn jittered_lattice<const D: usize>(side: usize, jitter: f64, seed: u64) -> ParticleSet<D>
    where
        Dim<D>: SupportedDim,
    {
        let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let count = side.pow(D as u32);
        let points = (0..count)
            .map(|i| {
                Point::<D>::from_fn(|k, _| {
                    (i / side.pow(k as u32) % side) as f64 + jitter * (uniform() - 0.5)
                })
            })
            .collect();
        ParticleSet::new(points).unwrap()
    }

    /// Compares a detection's margins with the reference path's: bit for bit, except where
    /// the interior filter decided (both margins below `−INTERIOR_BAND·r` then, and the
    /// filter's reach bounds the final float cell's, which `full` gives: every neighbour
    /// clipped, no settling). Returns how many particles the filter decided.
    fn compare_with_reference(got: &[f64], reference: &[f64], full: &[f64], r: f64) -> usize {
        let mut filtered = 0;
        for (i, ((&g, &m), &f)) in got.iter().zip(reference).zip(full).enumerate() {
            if g.to_bits() == m.to_bits() {
                continue;
            }
            filtered += 1;
            assert!(g <= -INTERIOR_BAND * r, "{i}: {g} vs {m}");
            assert!(m <= -INTERIOR_BAND * r, "{i}: {g} vs {m}");
            assert!(f <= g + 1e-12 * r, "{i}: {g} below the full cell's {f}");
        }
        filtered
    }

    // The interior filter, the fast cell, the staged gathering (neighbours within
    // FIRST_REACH·r first) and the traversal in grid order change no bit of any margin the
    // filter does not decide, and the filter decides only particles deep inside: at radii
    // where the first stage settles most interior cells (1.2 spacings), where it often does
    // not (0.9: most cells gather the rest), and on dense neighbourhoods (2.1).
    #[test]
    fn detection_margins_equal_the_full_list_polyhedron_margins_bit_for_bit() {
        let set = jittered_lattice::<3>(11, 0.3, 1);
        let mut filtered = 0;
        for r in [0.9, 1.2, 2.1] {
            let d = ExactDetector::default()
                .detect_3d(&set, Radius::new(r).unwrap())
                .unwrap();
            let reference = reference_margins::<3, Polyhedron>(&set, r, true);
            let full = reference_margins::<3, Polyhedron>(&set, r, false);
            filtered += compare_with_reference(&d.margin.unwrap(), &reference, &full, r);
        }
        assert!(filtered > 100, "{filtered}");
    }

    #[test]
    fn detection_margins_in_2d_equal_the_full_list_polygon_margins_bit_for_bit() {
        let set = jittered_lattice::<2>(40, 0.3, 2);
        let mut filtered = 0;
        for r in [0.6, 0.9, 2.1] {
            let d = ExactDetector::default()
                .detect_2d(&set, Radius::new(r).unwrap())
                .unwrap();
            let reference = reference_margins::<2, Polygon>(&set, r, true);
            let full = reference_margins::<2, Polygon>(&set, r, false);
            filtered += compare_with_reference(&d.margin.unwrap(), &reference, &full, r);
        }
        assert!(filtered > 100, "{filtered}");
    }

    #[test]
    fn try_new_takes_finite_non_negative_ties_and_refuses_the_rest() {
        assert_eq!(ExactDetector::default().params(), &ExactParams::default());
        let d = ExactDetector::try_new(ExactParams { tie: 1e-9 }).unwrap();
        assert_eq!(d.params().tie, 1e-9);
        assert_eq!(d.to_string(), "exact (tie=0.000000001)");
        for bad in [-1e-9, f64::NAN, f64::INFINITY] {
            let err = ExactDetector::try_new(ExactParams { tie: bad }).unwrap_err();
            assert!(
                matches!(&err, boundary_core::ParamError::Invalid { key, .. } if key == "tie"),
                "{err}"
            );
        }
    }
}
