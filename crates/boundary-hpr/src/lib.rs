#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Boundary particles by visibility: the hidden point removal (HPR) operator of Katz, Tal &
//! Basri (2007) with exponential flipping, applied locally from viewpoints placed on a grid,
//! after M. Sandim, *On the boundary detection for particle-based methods*, PhD thesis, USP
//! 2020, ch. 2 (Sandim et al. 2016), Alg. 1; method name `hpr`. The JCP 2020 paper (Table 1,
//! "Sandim et al. \[10\]") and the thesis (Table 2) report M between 0.92 and 0.995 for it.
//!
//! **When to use it:** to reproduce the thesis' visibility method or to compare with it. It
//! is not certified (a boundary particle in a tight concave region can be hidden from every
//! viewpoint); for the labels themselves use `exact`, the reference (accuracy and speed of
//! both on the same scenes: `BENCHMARKS.md`, written by `cargo xtask sweep`).
//!
//! # Method (Alg. 1)
//! 1. **Viewpoints** ([`viewpoint`]). A uniform grid of cells of side `2r`; a viewpoint at
//!    the centre of every empty cell adjacent to a full cell. A *cavity cell* (a full cell
//!    whose adjacent cells are all full) gives each of its particles a candidate
//!    `V_i = p_i + r·δ_i/|δ_i|` (Eq. 2.3, `δ_i = p_i −` centroid of its neighbours within
//!    `2r`), kept when no particle lies within `0.95 r` of it (Fig. 5). The grid covers the
//!    bounding box padded by one cell, since only cells adjacent to a full cell are used.
//! 2. **Visibility** ([`visibility`]). From each viewpoint `V`: the particles within `4r`
//!    (closed ball), moved so that `V` is the origin and scaled by `1/4r` into the unit ball,
//!    flipped by `p/|p|^γ` (Eq. 2.2); the vertices of the convex hull of the flipped points
//!    plus the origin are visible. The hull is our own ([`hull`]: monotone chain in 2D,
//!    incremental Quickhull in 3D) with exact orientation predicates (the `robust` crate's
//!    adaptive arithmetic): no system library, no file I/O, no panic path.
//! 3. The boundary is the union of the visible sets. Viewpoints are processed in parallel
//!    (rayon); the union does not depend on their order, so labels do not depend on the
//!    number of threads.
//!
//! # Our reading of what the thesis leaves open
//! - The grid is anchored at the origin (cell of `x`: `floor(x_k / 2r)`), not at the
//!   bounding box, so that domain-decomposed runs place the same viewpoints. Cells are
//!   half-open; "adjacent" is the `3^D − 1` cells sharing a face, an edge or a corner.
//! - Cavity candidates come from every particle of a cavity cell, and only from those:
//!   particles in full cells with at least one empty neighbour get none (their cell already
//!   has empty-cell viewpoints next to it). See [`viewpoint::place_viewpoints`].
//! - The thesis' "scaled into the unit ball" is the factor `1/4r` (the author's code uses
//!   `1/(1.1·max distance)`): any factor `s` scales all flipped points by `s^(1−γ)`, which
//!   leaves the hull's vertices unchanged.
//! - Exact duplicates share one label (they flip onto the same point).
//! - With no more distinct candidates than the dimension, all of them are visible.
//!
//! # Departures from the author's code
//! The author's reference code (`boundary.py`, marcos-sandim/boundary-detection; see
//! `../shared/data/README.md`) anchors its grid at the bounding box's minimum less one cell;
//! with that anchoring and exact hull vertices this implementation reproduces that code's
//! scores on the author's vortex frames, so the rest of Alg. 1 is as the author runs it. We
//! keep the origin anchoring (domain decomposition) and differ in two ways:
//! - **Tolerances against round-off** (section "Noise"), so that ties of a lattice do not
//!   decide labels.
//! - **Protrusion** (parameter `protrusion`, default `auto`): a hull vertex that protrudes
//!   from the hull of the other flipped points by at most a tolerance (a near-tie: within
//!   round-off or a hair of being hidden) is not visible. `auto` is
//!   [`PROTRUSION_TOLERANCE_2D`]` = 1e-3` in 2D and [`PROTRUSION_TOLERANCE_3D`]` = 1e-5`
//!   (round-off only) in 3D: with them every scene of the sweep scores at least as Alg. 1
//!   without the tolerance (but the tie lattice `cubic_lattice_tie3d`, whose particles are
//!   all boundary by a hair, at every tolerance), and the author's 2D frames at least as
//!   well as the author's code scores them. Nothing in Alg. 1 separates 2D from 3D: the
//!   split is a measured choice, and `protrusion=1e-3` in 3D hides more false positives at
//!   the price of a few boundary particles on some scenes.
//!
//! The measurements behind these choices, with the command that repeats them, are in
//! `docs/METHODS.md` (section "`hpr`").
//!
//! # Two grids (`grids=2`, not the default)
//! Where Alg. 1 puts its viewpoints depends on where the grid falls: translating a scene by a
//! fraction of a cell changes its labels, and most false positives are such accidents: an
//! empty-cell viewpoint that happens to face a gap sees the interior behind it. With
//! `grids=2` a second pass places the viewpoints of the grid shifted by `r` (half a cell) on
//! every axis, and a particle is boundary when some viewpoint sees it in **each** pass (so
//! the boundary is a subset of the default's; halo and decomposition are unchanged: each pass
//! has the same reach). It removes false positives on most scenes, adds misses on some, and
//! costs twice the time (its scores: `docs/METHODS.md`). Not the default: it departs from
//! Alg. 1.
//!
//! # Cost
//! Each viewpoint builds one hull of its `k` candidates within `4r`, so the work per
//! particle grows with `(r / spacing)^D` and with the share of the particles near a surface.
//! The work is the hull (Quickhull with exact predicates), the cavity directions `δ_i` (one
//! `2r` neighbour pass per particle of a cavity cell) and the sorting and gathering of
//! candidates. The hull's test of a point against a facet first goes through a
//! floating-point filter on the facet's stored plane, which settles "strictly inside" without
//! the full predicate, and its working memory is reused between hulls. The scans after the
//! hull (every point against every facet and corner, a norm per pair for the near-twin test)
//! exit early and visit only the cells of a box grid over the flips that can reach the level
//! in question ([`visibility::visible_from_origin`]). Its speed beside the other methods:
//! `BENCHMARKS.md` and `cargo bench -p boundary --bench methods`; a dense scene for
//! profilers: the example `profile_dense`.
//!
//! # Noise
//! A perfect lattice puts particles exactly on cell faces, exactly `2r` and `4r` from
//! viewpoints and neighbours, and flipped points exactly on hull facets; without margins,
//! round-off of the coordinates would decide labels (a perturbation of a few `1e-6`
//! spacings would change hundreds of a lattice's labels, and give the symmetric `δ_i = 0`
//! of interior particles random directions). Every such decision has a margin well above
//! round-off: a particle within `1e-4·r` of a cell
//! fills it ([`viewpoint::CELL_TOLERANCE`]), the neighbourhood of Eq. 2.3 reaches
//! `2r(1 + 1e-4)` ([`viewpoint::NEIGHBOUR_TOLERANCE`]), a `δ_i` shorter than `1e-4·r` gives no
//! cavity viewpoint ([`viewpoint::DIRECTION_TOLERANCE`]), candidates reach `4r(1 + 1e-4)`
//! ([`REACH_TOLERANCE`]) and hull vertices must protrude by `1e-3` in 2D, `1e-5` in 3D.
//! Perturbed lattices change no label at r = 0.75, 0.9, 1, 1.2, 1.5 and 2 (test
//! `lattice_round_off_does_not_change_the_labels`). What remains: a particle whose distance
//! to a cell, a viewpoint or a neighbour lies within the noise of the tolerance itself
//! (e.g. `4r(1 + 1e-4)` exactly) still flips; lattices do not put particles there.
//!
//! # Degenerate input
//! A viewpoint whose candidates all lie on one line (2D) or plane (3D) with it has no
//! full-dimensional hull, and their flips are so only up to rounding (thinner than the
//! protrusion tolerance along a facet normal): every candidate is labelled boundary (a flat set's particles are all
//! boundary by the covering definition). [`HprDetector::detect_with_stats`] counts these.
//!
//! # Parameters
//! [`HprParams`], checked by [`HprDetector::try_new`]; the `--set key=value` keys of the
//! command line and the bindings are the field names (`cavity=on|off`, `grids=1|2`,
//! `protrusion=auto|<value>`).
//!
//! | field | default | meaning |
//! |---|---|---|
//! | `gamma` | 1.3 | exponent of the exponential flipping (Eq. 2.2), `> 1`; the thesis' value |
//! | `cavity` | `on` | place the cavity viewpoints of Eq. 2.3 (`off`: empty cells only) |
//! | `grids` | 1 | viewpoint grids: 1 (Alg. 1), or 2 (see "Two grids") |
//! | `protrusion` | `auto` | hull vertices protruding by at most this are hidden: `auto` is `1e-3` in 2D, `1e-5` in 3D, or a value in `[1e-6, 0.1]` (see "Departures from the author's code") |
//!
//! No margin is returned. Not certified: a boundary particle in a concave region of high
//! curvature can be hidden from every viewpoint (thesis Sec. 2.4).
//!
//! # Halo
//! A particle's label depends on the viewpoints within `4r` of it, and a viewpoint on the
//! particles within `4r` of it (the hull) and on the occupancy of the cells around it. The
//! farthest input is a cavity viewpoint's: `V_i` lies `r` from `p_i`, whose cell and adjacent
//! cells span `4r` per axis from `p_i`. Hence [`HALO_FACTOR`]` = 5 + 4√3 ≈ 11.93` (in units
//! of `r`, the 3D bound, also used in 2D), which also covers the `8r` of the hulls.
//!
//! # Hard cases
//! What `hpr` returns on the hard cases (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`).
//! Not certified; the differences from `exact`:
//! - Degenerate sets (single particles, coincident pairs, pairs exactly `2r` apart, lines,
//!   collinear and coplanar 3D sets): every particle boundary, through the flat-hull rule.
//! - Perfect lattices: the labels of `exact` at and around the tie radius, 2D and 3D.
//! - Near-duplicates 1e-12 apart: 18 false positives (a near-twin shares the label of its
//!   visible partner, as an exact duplicate does); exact duplicates as `exact`.
//! - Jittered lattices: in 2D up to 12 false negatives of 88, in 3D 16 false positives;
//!   unchanged by scale from 1e-9 to 1e9 and by offsets 1e6 and 1e9. Empty input: empty labels.
//!
//! # Per-particle radii
//! `hpr` refuses sets with per-particle radii (`DetectError::PerParticleRadii`): Alg. 1 places its
//! viewpoint grid and flips with one radius, and a generalisation would be a new method, not HPR.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_hpr::HprDetector;
//!
//! // A jittered 14 x 14 square lattice at r = 1.2: the outer ring is boundary, the particles
//! // three or more layers deep are not.
//! let rows: Vec<[f64; 2]> = (0..196)
//!     .map(|k| [(k % 14) as f64 + 0.01 * ((k * 7 % 5) as f64), (k / 14) as f64])
//!     .collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let labels = HprDetector::default()
//!     .detect_2d(&set, Radius::new(1.2).unwrap())
//!     .unwrap()
//!     .labels;
//! for k in 0..196 {
//!     let (x, y) = (k % 14, k / 14);
//!     let depth = x.min(y).min(13 - x).min(13 - y);
//!     if depth == 0 {
//!         assert!(labels.is_boundary(k), "rim particle {k}");
//!     }
//!     if depth >= 3 {
//!         assert!(!labels.is_boundary(k), "deep particle {k}");
//!     }
//! }
//! ```

pub mod hull;
pub mod viewpoint;
pub mod visibility;

use boundary_core::params::Check;
use boundary_core::{
    Capabilities, CoreError, DetectError, Detection, Dim, Job, Labels, Method, NeighbourGrid,
    ParamSet, ParamValue, Params, ParticleSet, Point, Radius, Support, SupportedDim,
};
use rayon::prelude::*;
use viewpoint::{place_viewpoints, ViewpointKind};
use visibility::{visible_from_origin, HullOutcome};

/// Why `hpr` rejects per-particle radii ([`DetectError::PerParticleRadii`]).
const NO_RADII: &str = "the HPR visibility test (thesis ch. 2, Alg. 1) places its viewpoints and flips with one radius";

/// The thesis' flipping exponent (Sec. 2.2: "γ = 1.3 in our implementation").
pub const DEFAULT_GAMMA: f64 = 1.3;
/// Radius of the local visibility test, in units of `r` (Sec. 2.3.2).
pub const VISIBILITY_RADIUS: f64 = 4.0;
/// The candidates of a viewpoint are the particles within `4r·(1 + REACH_TOLERANCE)`: lattice
/// particles exactly `4r` away stay candidates under round-off.
pub const REACH_TOLERANCE: f64 = 1e-4;
/// In 2D, a hull vertex is visible when it protrudes by more than this from the hull of the
/// other flipped points (flipped coordinates of order 1; see
/// [`visibility::visible_from_origin`]). The default of `protrusion=auto` in 2D.
pub const PROTRUSION_TOLERANCE_2D: f64 = 1e-3;
/// The same in 3D: round-off only (the lattice test fails at `1e-6`), so that no 3D scene of
/// the sweep loses M against Alg. 1 without the tolerance (crate docs, "Departures from the
/// author's code").
pub const PROTRUSION_TOLERANCE_3D: f64 = 1e-5;
/// The range accepted by `protrusion=<value>`.
pub const PROTRUSION_RANGE: (f64, f64) = (1e-6, 0.1);
/// The halo width in units of `r`: `5 + 4√3` (see the crate documentation).
pub const HALO_FACTOR: f64 = 5.0 + 4.0 * 1.732_050_807_568_877_2;

const METHOD: &str = "hpr";

/// How many viewpoint grids `hpr` uses (crate docs, "Two grids").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Grids {
    /// One grid of cell side `2r` (Alg. 1). String form `grids=1`.
    #[default]
    One,
    /// Also the grid shifted by `r`: a particle is boundary when seen under both. String form
    /// `grids=2`.
    Two,
}

impl Grids {
    /// The number of grids, 1 or 2.
    pub fn count(self) -> usize {
        match self {
            Grids::One => 1,
            Grids::Two => 2,
        }
    }
}

/// The protrusion tolerance of `hpr`'s visibility test (crate docs, "Departures from the
/// author's code").
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Protrusion {
    /// Per dimension: [`PROTRUSION_TOLERANCE_2D`] in 2D, [`PROTRUSION_TOLERANCE_3D`] in 3D.
    /// String form `protrusion=auto`.
    #[default]
    Auto,
    /// This tolerance in both dimensions, within [`PROTRUSION_RANGE`].
    Value(f64),
}

boundary_core::declare_params! {
    /// The parameters of `hpr`, with the thesis' defaults (string form: the `--set` keys of
    /// the same names, see `boundary::registry`).
    #[derive(Debug, Clone, PartialEq)]
    pub struct HprParams for "hpr" {
        /// Exponent of the exponential flipping `p/|p|^γ` (Eq. 2.2), finite, in `(1, 10]`;
        /// default [`DEFAULT_GAMMA`].
        pub gamma: f64 = DEFAULT_GAMMA, check::open_closed(1.0, 10.0),
            "exponent of the exponential flipping p/|p|^gamma, > 1 (Sandim 2020, Eq. 2.2)";
        /// Whether the cavity viewpoints of Eq. 2.3 are placed (`false`: empty cells only);
        /// default `true`. String form `cavity=on|off`.
        pub cavity: bool = true, check::any("must be on or off"),
            "on: also place viewpoints in cavity cells (Sandim 2020, Eq. 2.3, Fig. 5); off: \
             empty-cell viewpoints only";
        /// Viewpoint grids; default [`Grids::One`].
        pub grids: Grids = Grids::One, check::any("must be 1 or 2"),
            "viewpoint grids: 1 (Alg. 1), or 2 (also the grid shifted by r; boundary when \
             seen under both)";
        /// Hull vertices protruding by at most this are hidden; default [`Protrusion::Auto`].
        pub protrusion: Protrusion = Protrusion::Auto, protrusion_check(),
            "a hull vertex protruding by at most this from the hull of the other flipped \
             points is hidden; auto: 1e-3 in 2D, 1e-5 in 3D";
    }
}

/// The check of `protrusion`: `auto`, or a finite number within [`PROTRUSION_RANGE`].
fn protrusion_check() -> Check<Protrusion> {
    Check::new(
        |p: &Protrusion| match *p {
            Protrusion::Auto => true,
            Protrusion::Value(t) => (PROTRUSION_RANGE.0..=PROTRUSION_RANGE.1).contains(&t),
        },
        "must be auto or a number in [1e-6, 0.1]",
    )
}

/// The text form of `grids`: `1` or `2`.
impl ParamValue for Grids {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        match text.trim().parse::<usize>() {
            Ok(1) => Ok(Grids::One),
            Ok(2) => Ok(Grids::Two),
            _ => Err(None),
        }
    }
    fn to_text(&self) -> String {
        self.count().to_string()
    }
}

/// The text form of `protrusion`: `auto` or a number.
impl ParamValue for Protrusion {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        match text.trim() {
            "auto" => Ok(Protrusion::Auto),
            number => number.parse().map(Protrusion::Value).map_err(|_| None),
        }
    }
    fn to_text(&self) -> String {
        match self {
            Protrusion::Auto => "auto".to_owned(),
            Protrusion::Value(t) => t.to_string(),
        }
    }
}

/// The HPR detector (`hpr`). See the crate documentation.
///
/// Built from a checked [`HprParams`] ([`HprDetector::try_new`]), so a detector never holds
/// an invalid exponent or tolerance.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HprDetector {
    params: HprParams,
}

/// Counts of one run: viewpoints by kind and hulls by outcome (summed over the passes with
/// `grids=2`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HprStats {
    /// Viewpoints at empty-cell centres.
    pub empty_cell_viewpoints: usize,
    /// Cavity viewpoints (Eq. 2.3).
    pub cavity_viewpoints: usize,
    /// Viewpoints whose visible set came from a full-dimensional hull.
    pub hulls: usize,
    /// Viewpoints whose candidates lie on one line (2D) or plane (3D) with the viewpoint:
    /// all their candidates were labelled boundary.
    pub flat: usize,
    /// Viewpoints with at most `D` distinct candidates (all visible, no hull).
    pub trivial: usize,
}

impl HprStats {
    fn add(mut self, o: HullOutcome) -> Self {
        match o {
            HullOutcome::Trivial => self.trivial += 1,
            HullOutcome::Hull => self.hulls += 1,
            HullOutcome::Flat => self.flat += 1,
        }
        self
    }

    fn merge(mut self, o: Self) -> Self {
        self.empty_cell_viewpoints += o.empty_cell_viewpoints;
        self.cavity_viewpoints += o.cavity_viewpoints;
        self.hulls += o.hulls;
        self.flat += o.flat;
        self.trivial += o.trivial;
        self
    }
}

impl HprDetector {
    /// The protrusion tolerance used in dimension `D`.
    fn protrusion_for<const D: usize>(&self) -> f64 {
        match self.params.protrusion {
            Protrusion::Value(t) => t,
            Protrusion::Auto if D == 2 => PROTRUSION_TOLERANCE_2D,
            Protrusion::Auto => PROTRUSION_TOLERANCE_3D,
        }
    }

    /// Labels of all particles and the counts of the run.
    pub fn detect_with_stats<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        r: Radius,
    ) -> Result<(Labels, HprStats), CoreError> {
        self.detect_first(set, set.len(), r)
    }

    /// Labels of the first `owned` particles; viewpoints that see no owned particle are
    /// skipped.
    fn detect_first<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        owned: usize,
        r: Radius,
    ) -> Result<(Labels, HprStats), CoreError> {
        let r = r.get();
        let mut stats = HprStats::default();
        if set.is_empty() || owned == 0 {
            return Ok((Labels::new(vec![false; owned]), stats));
        }
        let grid = NeighbourGrid::new(set, 2.0 * r)?;
        // The first viewpoint grid, and with `grids = 2` the one shifted by r (half a cell)
        // on every axis: a particle is boundary when it is seen under each of them.
        let mut flags = vec![true; owned];
        for shift in [0.0, r].into_iter().take(self.params.grids.count()) {
            let (seen, s) = self.visible_under_grid(set, &grid, owned, r, shift);
            stats = stats.merge(s);
            for (f, v) in flags.iter_mut().zip(seen) {
                *f &= v;
            }
        }
        Ok((Labels::new(flags), stats))
    }

    /// Which of the first `owned` particles some viewpoint of the grid shifted by `shift`
    /// sees (Alg. 1, steps 1–3), and the counts of that pass.
    fn visible_under_grid<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        grid: &NeighbourGrid<D>,
        owned: usize,
        r: f64,
        shift: f64,
    ) -> (Vec<bool>, HprStats) {
        let mut stats = HprStats::default();
        let viewpoints = place_viewpoints(set, grid, r, self.params.cavity, shift);
        stats.cavity_viewpoints = viewpoints
            .iter()
            .filter(|v| v.kind == ViewpointKind::Cavity)
            .count();
        stats.empty_cell_viewpoints = viewpoints.len() - stats.cavity_viewpoints;
        let positions = set.positions();
        let reach = VISIBILITY_RADIUS * r * (1.0 + REACH_TOLERANCE);
        let gamma = self.params.gamma;
        let tol = self.protrusion_for::<D>();
        let (seen, hull_stats) = viewpoints
            .par_iter()
            .map_init(
                || (Vec::<usize>::new(), Vec::<Point<D>>::new(), Vec::new()),
                |(candidates, local, visible), v| {
                    candidates.clear();
                    grid.for_each_within(&v.at, reach, |j, _| candidates.push(j));
                    if boundary_core::stop::requested()
                        || candidates.is_empty()
                        || candidates.iter().all(|&j| j >= owned)
                    {
                        return (Vec::new(), HprStats::default());
                    }
                    // Deterministic input order for the hull, whatever the grid's order.
                    candidates.sort_unstable();
                    local.clear();
                    local.extend(candidates.iter().map(|&j| (positions[j] - v.at) / reach));
                    let outcome = visible_from_origin(local, gamma, tol, visible);
                    let seen: Vec<u32> = candidates
                        .iter()
                        .zip(visible.iter())
                        .filter(|&(&j, &vis)| vis && j < owned)
                        .map(|(&j, _)| j as u32)
                        .collect();
                    (seen, HprStats::default().add(outcome))
                },
            )
            .fold(
                || (Vec::<u32>::new(), HprStats::default()),
                |(mut acc, s), (seen, t)| {
                    acc.extend(seen);
                    (acc, s.merge(t))
                },
            )
            .reduce(
                || (Vec::new(), HprStats::default()),
                |(mut a, s), (b, t)| {
                    a.extend(b);
                    (a, s.merge(t))
                },
            );
        let mut flags = vec![false; owned];
        for j in seen {
            flags[j as usize] = true;
        }
        (flags, stats.merge(hull_stats))
    }
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(HprDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(HprDetector, HprParams);

impl Method for HprDetector {
    const NAME: &'static str = METHOD;

    fn describe(&self) -> Params {
        self.params.listing()
    }

    /// A uniform radius only; no solid (hidden point removal sees points, and a solid
    /// region is none); a halo of `(5 + 4√3)·r`: a cavity viewpoint `r` from a particle whose
    /// cell neighbourhood spans `4r` per axis, seeing a particle `4r` away (crate
    /// documentation, "Halo").
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            radii: Support::Refused(NO_RADII),
            half_spaces: Support::Refused(SOLID_REFUSAL),
            halo_over_r: HALO_FACTOR,
            ..Capabilities::DEFAULT
        }
    }

    /// Classifies only the owned particles; viewpoints that see none of them are skipped.
    fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        let (labels, _) = self.detect_first(job.set, job.owned, job.r)?;
        Ok(Detection {
            labels,
            margin: None,
        })
    }
}

/// Why `hpr` refuses solid half-spaces.
const SOLID_REFUSAL: &str = "hidden point removal sees points, and a solid region is none; give the walls as wall particles: they occlude and are never reported";

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use boundary_core::BoundaryDetector;

    #[test]
    fn parameters_are_checked_and_reported() {
        let d = HprDetector::default();
        assert_eq!(
            BoundaryDetector::describe(&d).to_string(),
            "gamma=1.3, cavity=on, grids=1, protrusion=auto"
        );
        assert_eq!(d.params(), &HprParams::default());
        assert_eq!(d.protrusion_for::<2>(), PROTRUSION_TOLERANCE_2D);
        assert_eq!(d.protrusion_for::<3>(), PROTRUSION_TOLERANCE_3D);
        let params = HprParams {
            gamma: 1.75,
            cavity: false,
            grids: Grids::Two,
            protrusion: Protrusion::Value(1e-3),
        };
        let d = HprDetector::try_new(params.clone()).unwrap();
        assert_eq!(d.params(), &params);
        assert_eq!(
            BoundaryDetector::describe(&d).to_string(),
            "gamma=1.75, cavity=off, grids=2, protrusion=0.001"
        );
        assert_eq!(d.protrusion_for::<3>(), 1e-3, "a set value holds in 3D too");
        assert!(!d.certified());
    }

    #[test]
    fn try_new_rejects_invalid_gamma_and_protrusion() {
        for bad in [1.0, 0.5, -2.0, 10.5, f64::NAN, f64::INFINITY] {
            let err = HprDetector::try_new(HprParams {
                gamma: bad,
                ..HprParams::default()
            })
            .unwrap_err();
            assert!(
                matches!(&err, boundary_core::ParamError::Invalid { key, .. } if key == "gamma"),
                "{err}"
            );
        }
        for bad in [0.0, 0.5, -1e-3, 1e-7, f64::INFINITY, f64::NAN] {
            let err = HprDetector::try_new(HprParams {
                protrusion: Protrusion::Value(bad),
                ..HprParams::default()
            })
            .unwrap_err();
            assert!(
                matches!(&err, boundary_core::ParamError::Invalid { key, .. } if key == "protrusion"),
                "{err}"
            );
        }
        for ok in [PROTRUSION_RANGE.0, PROTRUSION_RANGE.1] {
            let params = HprParams {
                protrusion: Protrusion::Value(ok),
                ..HprParams::default()
            };
            assert!(HprDetector::try_new(params).is_ok(), "{ok}");
        }
    }

    #[test]
    fn halo_factor_is_five_plus_four_root_three() {
        assert!((HALO_FACTOR - (5.0 + 4.0 * 3f64.sqrt())).abs() < 1e-12);
    }
}
