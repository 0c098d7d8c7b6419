#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Free-surface detection from the **divergence of position**, the criterion production SPH
//! solvers use (method name `divr`):
//!
//! > `∇·r_i = Σ_j V_j (x_j − x_i)·∇_i W_ij`; particle `i` is **boundary** iff
//! > `∇·r_i < threshold`.
//!
//! Inside a full, uniform neighbourhood `∇·r` is close to the dimension `d` (in the continuum
//! exactly `d`: `∫ (y − x)·∇_x W(x − y) dy = d ∫ W = d` for a normalised kernel); near a free
//! surface half the neighbourhood is missing and it drops towards `d/2`. With `∇_i W_ij`
//! pointing from `x_i` to `x_j` (`boundary-sph`'s convention) every term is `>= 0`, and the
//! sum is the trace of the renormalisation matrix of `marrone`.
//!
//! # The published thresholds
//! `threshold` takes a number or the name of a code, whose value depends on the dimension:
//!
//! | name | 2D | 3D | where |
//! |---|---|---|---|
//! | `dualsphysics` (default) | 1.5 | 2.75 | DualSPHysics, shifting `ShiftTFS`, after Lind, Xu, Stansby & Rogers, J. Comput. Phys. 231 (2012) 1499–1523 |
//! | `sphinxsys` | 1.5 | 2.25 | SPHinXsys' free-surface indication, `0.75·d` |
//! | `chrono` | 2.0 | 2.0 | Chrono::FSI, `free_surface_threshold` |
//!
//! Each code pairs its value with its own smoothing length (DualSPHysics' `h` is
//! `coefh·√d·Δx`, SPHinXsys' about `1.3Δx`) and its own volumes (`m_j/ρ_j` with the solver's
//! density). Here the volumes are the summation-density volumes of `boundary-sph` (positions
//! are all the method needs) and `h = h_over_r · r`; `∇·r` at a free surface depends on
//! `h/Δx`, so a threshold carries over only where `h/Δx` matches. The sweep reports each
//! code's value as its own row against `exact` (`divr` with `threshold=dualsphysics`, …), so
//! the cost of each default in false positives and negatives is measured, not assumed. The
//! MPS criterion (particle number density below `β·n₀`) is not offered: its `n₀` is the
//! number density of the initial lattice, which a single frame does not have.
//!
//! # Parameters (`--set key=value`)
//! | key | default | meaning |
//! |---|---|---|
//! | `threshold` | `dualsphysics` | boundary iff `∇·r` is below it: a number `> 0` or `dualsphysics`, `sphinxsys`, `chrono` |
//! | `kernel` | `wendland` | `wendland` (C2) or `cubic` (spline), support `2h` |
//! | `h_over_r` | 1 | smoothing length `h` in units of the resolution `r` |
//! | `layers` | 0 | `1`: every particle within `h` of a flagged one is flagged too (SPHinXsys' second layer) |
//! | `min_neighbours` | `auto` | a particle with fewer other particles within `2h` is *isolated* and boundary; `auto` is `d + 1` |
//!
//! The margin of a [`Detection`] is `threshold − ∇·r` (positive leans boundary).
//!
//! # Isolated particles
//! DualSPHysics flags particles with too few neighbours apart from its threshold; here they
//! are the particles with fewer than `min_neighbours` other particles within the support
//! ([`DivrDetector::analyse`] returns them as [`DivrAnalysis::isolated`]). They are boundary
//! whatever their `∇·r`. The default `d + 1` has a geometric reason: `d` or fewer neighbours
//! always lie in a closed half-space through `x_i` (solve for a direction with a positive
//! product with each), so the point of `S_i` opposite to them is covered by none of them (at
//! most touched), and the particle is boundary by the definition.
//!
//! # The spatial-temporal variant
//! Zhang, Rezavand, Zhu, Yu, Wu, Zhang & Hu (J. Comput. Phys. 490 (2023) 112303) count a low
//! `∇·r` only where the particle or one of its neighbours was flagged at the previous time
//! step, which removes the spurious flags inside the fluid. [`DivrDetector::detect_following`]
//! takes the previous step's labels explicitly: a particle below the threshold is boundary
//! iff it, or a particle within the support `2h`, is boundary in `previous`. Isolated
//! particles stay boundary.
//!
//! # Policy: ties, duplicates, degenerate input
//! - `∇·r == threshold` is interior (the codes test `<`).
//! - Duplicates of `x_i` count as neighbours (for `min_neighbours`) and share its volume, but
//!   add nothing to `∇·r` (no distance).
//! - An isolated particle has `∇·r = 0`: boundary, and isolated.
//! - `layers = 1` reads the labels of the classified particles only: ghosts (walls, periodic
//!   images, a decomposition's halo) neither spread nor receive the second layer, so under a
//!   domain decomposition a flag does not spread across a subdomain border.
//! - Not certified.
//!
//! # Hard cases
//! What `divr` returns on the hard cases (the test `every_detector_survives_the_hard_cases` in
//! `crates/boundary/tests/every_detector.rs` keeps the counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`). Not certified:
//! - Single particles, coincident pairs, pairs `2r` apart, lines, planes and collinear or
//!   coplanar 3D sets: every particle boundary, as `exact` (isolated, or `∇·r` far below
//!   the threshold).
//! - Perfect lattices at `r` below the spacing (the tie radii, `r = 0.8a`; also the 2D
//!   lattice with isolated particles at `r = 0.8a`): every particle boundary (+100 of 144,
//!   +125 of 343), since at `h = r < a` the support `2h` holds the nearest shell only and
//!   `∇·r` is low everywhere (the closed form of `tests/reference.rs`). From `r = a` on:
//!   the labels of `exact`.
//! - Duplicates: exact ones as `exact`; near-duplicates 1e-12 apart, 18 false positives.
//! - Jittered lattices: a thick layer, +129 to +158 false positives and 2–4 false negatives
//!   (DualSPHysics' 1.5 and 2.75 lie close to the interior value at `h = r`); the same counts
//!   at every scale (the sums are computed in units of `h`), a few of each at offsets 1e6
//!   and 1e9 (the rounded coordinates move `∇·r` across the threshold). Empty input: empty
//!   labels.
//!
//! # Per-particle radii
//! `divr` refuses sets with per-particle radii (`DetectError::PerParticleRadii`): the
//! published thresholds assume one smoothing length.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_divr::{DivrDetector, DivrParams, Threshold};
//!
//! // A 12 x 12 square lattice of spacing 1 at r = 1.5 (h = 1.5): the outer ring is below
//! // SPHinXsys' 1.5, the particles two or more layers deep are not.
//! let rows: Vec<[f64; 2]> = (0..144).map(|k| [(k % 12) as f64, (k / 12) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let d = DivrDetector::try_new(DivrParams {
//!     threshold: Threshold::Sphinxsys,
//!     ..DivrParams::default()
//! })
//! .unwrap();
//! let labels = d.detect_2d(&set, Radius::new(1.5).unwrap()).unwrap().labels;
//! for k in 0..144 {
//!     let (x, y) = (k % 12, k / 12);
//!     let depth = x.min(y).min(11 - x).min(11 - y);
//!     if depth == 0 {
//!         assert!(labels.is_boundary(k));
//!     } else if depth >= 2 {
//!         assert!(!labels.is_boundary(k));
//!     }
//! }
//! ```

use boundary_core::params::Check;
use boundary_core::{
    AnyParticleSet, DetectError, Detection, Labels, ParamSet, ParamValue, Params, ParticleSet,
    Radius,
};
use boundary_sph::frame::{
    self, h_over_r_check, kernel_check, spread_within, H_OVER_R_DOC, KERNEL_DOC,
};
use boundary_sph::{Kernel, Smoothing, SphContext, SphCriterion, SphMethod, Verdict};
use std::fmt;

const METHOD: &str = "divr";

/// The threshold on `∇·r`: a code's published value (per dimension) or a number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Threshold {
    /// DualSPHysics' `ShiftTFS` values after Lind et al. (2012): 1.5 in 2D, 2.75 in 3D.
    DualSphysics,
    /// SPHinXsys: `0.75·d` (1.5 in 2D, 2.25 in 3D).
    Sphinxsys,
    /// Chrono::FSI's `free_surface_threshold`: 2.0.
    Chrono,
    /// A value of one's own, finite and `> 0`.
    Value(f64),
}

impl Threshold {
    /// The named thresholds, in the order the sweep reports them.
    pub const NAMED: [Threshold; 3] = [
        Threshold::DualSphysics,
        Threshold::Sphinxsys,
        Threshold::Chrono,
    ];

    /// The value in dimension `dim` (2 or 3).
    pub fn value(self, dim: usize) -> f64 {
        match self {
            Threshold::DualSphysics if dim == 2 => 1.5,
            Threshold::DualSphysics => 2.75,
            Threshold::Sphinxsys => 0.75 * dim as f64,
            Threshold::Chrono => 2.0,
            Threshold::Value(v) => v,
        }
    }

    /// The text `threshold=` takes back: the code's name, or the number.
    pub fn name(self) -> String {
        match self {
            Threshold::DualSphysics => "dualsphysics".to_owned(),
            Threshold::Sphinxsys => "sphinxsys".to_owned(),
            Threshold::Chrono => "chrono".to_owned(),
            Threshold::Value(v) => v.to_string(),
        }
    }
}

impl fmt::Display for Threshold {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

boundary_core::declare_params! {
    /// The parameters of `divr` (see the crate documentation).
    #[derive(Debug, Clone, PartialEq)]
    pub struct DivrParams for "divr" {
        /// Boundary iff `∇·r` is below it.
        pub threshold: Threshold = Threshold::DualSphysics, threshold_check(),
            "boundary iff the divergence of position is below it: a number or dualsphysics \
             (1.5 2D, 2.75 3D; Lind et al. 2012), sphinxsys (0.75 d), chrono (2.0)";
        /// Kernel shape (support `2h`).
        pub kernel: Kernel = Kernel::WendlandC2, kernel_check(), KERNEL_DOC;
        /// `h / r`, in `(0, 100]`.
        pub h_over_r: f64 = frame::DEFAULT_H_OVER_R, h_over_r_check(), H_OVER_R_DOC;
        /// 0, or 1: flag every particle within `h` of a flagged one too.
        pub layers: u8 = 0, check::at_most(1, "must be 0 or 1"),
            "1: every particle within h of a flagged one is flagged too (SPHinXsys)";
        /// Isolated (and boundary) below this many other particles within `2h`; `None`:
        /// `d + 1`.
        pub min_neighbours: Option<usize> = None,
            check::auto_or(
                check::at_most(1000, ""),
                "must be auto or a whole number in [0, 1000]",
            ),
            "fewer other particles within 2h: isolated and boundary (auto: d + 1)";
    }
}

/// The check of `threshold`: a number finite and `> 0`, or a named one.
fn threshold_check() -> Check<Threshold> {
    Check::new(
        |t: &Threshold| match *t {
            Threshold::Value(v) => v.is_finite() && v > 0.0,
            _ => true,
        },
        "must be a number > 0 or dualsphysics, sphinxsys, chrono",
    )
}

/// The text form of `threshold`: a number or a published value's name.
impl ParamValue for Threshold {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        match text.trim() {
            "dualsphysics" => Ok(Threshold::DualSphysics),
            "sphinxsys" => Ok(Threshold::Sphinxsys),
            "chrono" => Ok(Threshold::Chrono),
            number => number.parse().map(Threshold::Value).map_err(|_| None),
        }
    }
    fn to_text(&self) -> String {
        self.name()
    }
}

/// The divergence-of-position detector (`divr`). See the crate documentation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DivrDetector {
    params: DivrParams,
}

/// What [`DivrDetector::analyse`] returns besides the labels.
#[derive(Debug, Clone, PartialEq)]
pub struct DivrAnalysis {
    /// `∇·r_i` of every particle, in input order.
    pub divergence: Vec<f64>,
    /// The number of other particles within `2h` of each particle.
    pub neighbours: Vec<usize>,
    /// The isolated particles (fewer than `min_neighbours` neighbours).
    pub isolated: Labels,
    /// The labels, as [`boundary_core::BoundaryDetector::detect`] gives them.
    pub labels: Labels,
}

impl DivrDetector {
    /// The fewest neighbours of a particle that is not isolated, in dimension `dim`.
    fn min_neighbours(&self, dim: usize) -> usize {
        self.params.min_neighbours.unwrap_or(dim + 1)
    }

    /// `∇·r`, the neighbour count, isolation and the label of particle `i` before the
    /// temporal and layer rules.
    fn evaluate<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Evaluation {
        self.evaluation::<D>(ctx.divergence_of_position(i))
    }

    /// The evaluation of the first `count` particles of `ctx`, in input order, from one pass
    /// over the pairs: the same as [`Self::evaluate`] of each.
    fn evaluate_all<const D: usize>(
        &self,
        ctx: &SphContext<'_, D>,
        count: usize,
    ) -> Vec<Evaluation> {
        ctx.divergences_of_position(count, |_, &sums| self.evaluation::<D>(sums))
    }

    /// The evaluation of a particle from `(∇·r, neighbour count)`.
    fn evaluation<const D: usize>(&self, (divergence, neighbours): (f64, usize)) -> Evaluation {
        let threshold = self.params.threshold.value(D);
        Evaluation {
            divergence,
            neighbours,
            isolated: neighbours < self.min_neighbours(D),
            low: divergence < threshold,
            margin: threshold - divergence,
        }
    }

    /// `∇·r`, the neighbour counts, the isolated particles and the labels of every particle
    /// of `set` (the labels are those of `detect`).
    pub fn analyse<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        r: Radius,
    ) -> Result<DivrAnalysis, DetectError> {
        DetectError::check_uniform(METHOD, Self::RADII_REFUSAL, set.radii())?;
        let ctx = SphContext::new(set, self.smoothing().kernel_at(r))?;
        let evaluations = self.evaluate_all(&ctx, set.len());
        let mut labels: Vec<bool> = evaluations.iter().map(|e| e.low || e.isolated).collect();
        self.finish(&ctx, &mut labels);
        boundary_core::stop::check()?;
        Ok(DivrAnalysis {
            divergence: evaluations.iter().map(|e| e.divergence).collect(),
            neighbours: evaluations.iter().map(|e| e.neighbours).collect(),
            isolated: evaluations.iter().map(|e| e.isolated).collect(),
            labels: Labels::new(labels),
        })
    }

    /// The spatial-temporal variant (Zhang et al. 2023): a particle below the threshold is
    /// boundary only if it or a particle within `2h` is boundary in `previous`, the labels
    /// of the previous time step (one per particle of `set`, in the same order). Isolated
    /// particles stay boundary; `layers` applies after.
    pub fn detect_following(
        &self,
        set: &AnyParticleSet,
        r: Radius,
        previous: &Labels,
    ) -> Result<Detection, DetectError> {
        DetectError::check_uniform(METHOD, Self::RADII_REFUSAL, set.radii())?;
        if previous.len() != set.len() {
            return Err(DetectError::Method {
                method: METHOD,
                message: format!(
                    "{} previous labels for {} particles",
                    previous.len(),
                    set.len()
                ),
            });
        }
        let following = Following {
            detector: self,
            previous: previous.as_slice(),
        };
        let detection = match set {
            AnyParticleSet::D2(s) => frame::classify_first(&following, s, s.len(), r)?,
            AnyParticleSet::D3(s) => frame::classify_first(&following, s, s.len(), r)?,
        };
        boundary_core::stop::check()?;
        Ok(detection)
    }
}

/// One particle's quantities.
#[derive(Debug, Clone, Copy, Default)]
struct Evaluation {
    divergence: f64,
    neighbours: usize,
    isolated: bool,
    low: bool,
    margin: f64,
}

impl Evaluation {
    /// The verdict before the temporal and layer rules: `∇·r < threshold`, or isolated.
    fn verdict(&self) -> Verdict {
        Verdict {
            boundary: self.low || self.isolated,
            margin: self.margin,
        }
    }
}

/// The criterion: `∇·r < threshold`, or isolated; then `layers`.
impl SphCriterion for DivrDetector {
    const METHOD: &'static str = METHOD;
    const MARGIN: bool = true;

    fn smoothing(&self) -> Smoothing {
        Smoothing {
            kernel: self.params.kernel,
            h_over_r: self.params.h_over_r,
        }
    }

    fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict {
        self.evaluate(ctx, i).verdict()
    }

    fn classify_all<const D: usize>(&self, ctx: &SphContext<'_, D>, count: usize) -> Vec<Verdict> {
        ctx.divergences_of_position(count, |_, &sums| self.evaluation::<D>(sums).verdict())
    }

    fn finish<const D: usize>(&self, ctx: &SphContext<'_, D>, labels: &mut [bool]) {
        if self.params.layers == 1 {
            spread_within(ctx, ctx.kernel().h(), labels);
        }
    }
}

/// The spatial-temporal criterion: [`DivrDetector`]'s, with a low `∇·r` confirmed by the
/// previous labels.
struct Following<'a> {
    detector: &'a DivrDetector,
    previous: &'a [bool],
}

impl SphCriterion for Following<'_> {
    const METHOD: &'static str = METHOD;
    const MARGIN: bool = true;

    fn smoothing(&self) -> Smoothing {
        self.detector.smoothing()
    }

    fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict {
        self.confirm(ctx, i, &self.detector.evaluate(ctx, i))
    }

    fn classify_all<const D: usize>(&self, ctx: &SphContext<'_, D>, count: usize) -> Vec<Verdict> {
        ctx.divergences_of_position(count, |i, &sums| {
            self.confirm(ctx, i, &self.detector.evaluation::<D>(sums))
        })
    }

    fn finish<const D: usize>(&self, ctx: &SphContext<'_, D>, labels: &mut [bool]) {
        self.detector.finish(ctx, labels);
    }
}

impl Following<'_> {
    /// The verdict of particle `i` from its evaluation `e`: a low `∇·r` confirmed by the
    /// previous labels of `i` or of a neighbour, or isolated.
    fn confirm<const D: usize>(
        &self,
        ctx: &SphContext<'_, D>,
        i: usize,
        e: &Evaluation,
    ) -> Verdict {
        let confirmed = e.low && {
            let mut seen = self.previous[i];
            ctx.for_each_neighbour(i, |j, _, _| seen |= self.previous[j]);
            seen
        };
        Verdict {
            boundary: confirmed || e.isolated,
            margin: e.margin,
        }
    }
}

impl SphMethod for DivrDetector {
    const RADII_REFUSAL: &'static str =
        "the published thresholds on the divergence of position assume one smoothing length";
    const SOLID_REFUSAL: &'static str = "the divergence of position is a kernel sum over particles, and a half-space is no particle; give the walls as wall particles, which enter the sums as in DualSPHysics";

    fn param_list(&self) -> Params {
        self.params.listing()
    }
}

// `Display` and `BoundaryDetector` (dispatch, radii refusal, owned particles with walls and
// periodic images as ghosts, halo of two kernel supports) from the SPH frame.
boundary_sph::impl_sph_detector!(DivrDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(DivrDetector, DivrParams);

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    #[test]
    fn named_thresholds_have_the_published_values() {
        let got: Vec<(f64, f64)> = Threshold::NAMED
            .iter()
            .map(|t| (t.value(2), t.value(3)))
            .collect();
        assert_eq!(got, [(1.5, 2.75), (1.5, 2.25), (2.0, 2.0)]);
        let names: Vec<String> = Threshold::NAMED.iter().map(|t| t.name()).collect();
        assert_eq!(names, ["dualsphysics", "sphinxsys", "chrono"]);
    }
}
