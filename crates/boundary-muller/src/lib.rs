#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Boundary particles from the SPH colour field of Müller, Charypar & Gross, *Particle-based
//! fluid simulation for interactive applications*, Proc. ACM SIGGRAPH/Eurographics Symposium
//! on Computer Animation (SCA) 2003, 154–159, Sec. 4.4 (surface tension): an SPH baseline of
//! the thesis' comparison (Sandim 2020, Table 2, "Müller"), method name `muller`.
//!
//! **When to use it:** to compare with the colour-field surface test of SPH codes (one
//! kernel sum per particle, no certificate), or to reproduce the thesis' comparison. For the labels themselves use `exact` (accuracy and speed on the same scenes: `BENCHMARKS.md`, written by `cargo xtask sweep`).
//!
//! # Method
//! The colour field is 1 at particle locations and 0 elsewhere; its SPH interpolant and
//! gradient are (Müller et al. 2003, Sec. 4.4, with `V_j = m_j/ρ_j`)
//!
//! - `c_i = Σ_j V_j W(x_i − x_j, h)`,
//! - `n_i = ∇c_i = Σ_j V_j ∇W(x_i − x_j, h)`.
//!
//! `n_i` vanishes inside the fluid and is large near its surface, where it points into the
//! fluid. Müller et al. evaluate the surface force only where `|n_i|` exceeds a threshold `l`
//! (Sec. 4.4); that threshold, made dimensionless, is the detector:
//!
//! > particle `i` is **boundary** iff `|∇c_i| · h > threshold`.
//!
//! `|∇c|` has units of 1/length, so `|∇c|·h` does not depend on the units of the data; and
//! since `W` is normalised (`∫W = 1`), it depends on the particle spacing only through
//! `h/Δx`. For a particle on the flat face of a continuous half-space, `|∇c|·h` is `h` times
//! the integral of `W` over the face: `4/3 · 7/(4π) ≈ 0.74` (2D) and `0.75` (3D) for
//! Wendland C2, falling to 0 at depth `2h`.
//!
//! Volumes `V_j` come from the summation density with a uniform mass (`boundary-sph`): the
//! method needs positions only. Müller et al. used their poly6 kernel for the colour field;
//! we use the kernels of `boundary-sph` (Wendland C2 by default, a smooth bell of the same
//! kind).
//!
//! # The default threshold
//! Müller et al. (SCA 2003, Sec. 4.4) evaluate the surface force only where `|n|` exceeds "a
//! threshold parameter `l`" and give no value for it (it would be in their units, with their
//! poly6 kernel). Our default, [`DEFAULT_THRESHOLD`] = 0.375, is tuned on scenes **disjoint
//! from the ones the sweep reports**: the test `tests/threshold.rs` generates 26 seeded *tuning
//! scenes* (20 in 2D, 6 in 3D; unions of discs/balls and a flat pool with bubbles cut out and
//! droplets, on lattices of spacing 1 with jitter ±0.05 or ±0.2, at r = 1, 1.5, 2, 3, 4
//! spacings in 2D and 1, 1.5, 2 in 3D; none is in `fixtures/scenes.toml`), measures
//! M = Rec·(1 − FPR) against `exact` at `h = r` with Wendland C2 for thresholds 0.025–1 (steps
//! of 0.025), and fails unless the default is the one with the largest mean M
//! (`cargo test -p boundary-muller --test threshold -- --nocapture` prints the table). The
//! optimum is flat: mean M is 0.876 at 0.375, 0.875 at 0.4 (the value first chosen on the
//! reported scenes), 0.869 at 0.35 and 0.868 at 0.425. Single scenes are not: the best
//! threshold of a tuning scene grows with `r/Δx`, from 0.2 at `r = Δx` to 0.675 at `r = 4Δx`,
//! so data with a known `r/Δx` far from 1.5 deserves its own threshold (`boundary-sweep` also
//! runs 0.1, 0.2, 0.3, 0.5 and 0.6; the table is in the sweep report). A low threshold labels
//! a thick layer (Rec up, FPR up); a high one misses the surface particles with neighbours on
//! several sides (Rec down).
//!
//! # Parameters (`--set key=value`)
//! | key | default | meaning |
//! |---|---|---|
//! | `threshold` | [`DEFAULT_THRESHOLD`] | boundary iff `|∇c|·h` exceeds it |
//! | `kernel` | `wendland` | `wendland` (C2) or `cubic` (spline), support `2h` |
//! | `h_over_r` | 1 | smoothing length `h` in units of the resolution `r` |
//!
//! The margin of a [`Detection`](boundary_core::Detection) is `|∇c_i|·h − threshold` (positive leans boundary).
//!
//! # Policy: duplicates, degenerate input
//! - An isolated particle has `∇c = 0`: it is labelled *interior*, a known failure of the
//!   colour field (isolated droplets and symmetric configurations are invisible to it). The
//!   same holds for any perfectly symmetric neighbourhood, such as the middle particle of a
//!   line of three.
//! - Duplicates contribute nothing to the gradient (no direction) and halve the volumes.
//! - Not certified.
//!
//! # Hard cases
//! What `muller` returns on the hard cases (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`).
//! Not certified, and the colour field is blind to symmetric configurations:
//! - A single particle, a coincident pair or a pair exactly `2r` apart: interior (every one a
//!   false negative). Lines and collinear 3D sets: only particles at or near the ends are
//!   boundary; planes and coplanar 3D sets: their rims, not their middles.
//! - Perfect square lattices at the tie radius `a/√2`: no particle reaches the threshold, so
//!   every boundary particle is missed; at `r = 0.8a` only the 4 corners are found (40 of 44
//!   missed); at the 3D tie radius it misses 150 of 218.
//! - Jittered lattices: false positives and negatives both (2D: +117 to +138, −11 to −24 of
//!   75–88), a few false positives and negatives at offsets 1e6 and 1e9 and at every scale
//!   (the counts do not change with scale: the sums are computed in units of `h`).
//!   Near-duplicates 1e-12 apart: 18 false positives.
//!
//! Empty input: empty labels.
//!
//! # Per-particle radii
//! `muller` refuses sets with per-particle radii (`DetectError::PerParticleRadii`): the colour
//! field of Müller et al. (2003) and its threshold assume one smoothing length.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_muller::MullerDetector;
//!
//! // A 12 x 12 square lattice of spacing 1 at r = 1.5: the outer ring is boundary, the
//! // particles three or more layers deep are not.
//! let rows: Vec<[f64; 2]> = (0..144).map(|k| [(k % 12) as f64, (k / 12) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let labels = MullerDetector::default()
//!     .detect_2d(&set, Radius::new(1.5).unwrap())
//!     .unwrap()
//!     .labels;
//! for k in 0..144 {
//!     let (x, y) = (k % 12, k / 12);
//!     let depth = x.min(y).min(11 - x).min(11 - y);
//!     assert_eq!(labels.is_boundary(k), depth == 0, "particle {k} at depth {depth}");
//! }
//! ```

use boundary_core::{CoreError, ParamSet, Params, ParticleSet, Point, Radius};
use boundary_sph::frame::{
    h_over_r_check, kernel_check, DEFAULT_H_OVER_R as FRAME_H_OVER_R, H_OVER_R_DOC, KERNEL_DOC,
};
/// The SPH kernel shapes of [`MullerParams::kernel`].
pub use boundary_sph::Kernel;

use boundary_sph::{Smoothing, SphContext, SphCriterion, SphMethod, Verdict};

/// Default dimensionless threshold on `|∇c|·h` (see the crate documentation for how it was
/// chosen).
pub const DEFAULT_THRESHOLD: f64 = 0.375;
/// Default smoothing length in units of `r`.
pub const DEFAULT_H_OVER_R: f64 = FRAME_H_OVER_R;

const METHOD: &str = "muller";
boundary_core::declare_params! {
    /// The parameters of `muller` (string form: the `--set` keys of the same names, see
    /// `boundary::registry`).
    #[derive(Debug, Clone, PartialEq)]
    pub struct MullerParams for "muller" {
        /// Boundary iff `|∇c|·h` exceeds it; finite, `>= 0`; default [`DEFAULT_THRESHOLD`].
        pub threshold: f64 = DEFAULT_THRESHOLD, check::non_negative(),
            "boundary iff the colour-field gradient magnitude times h exceeds it (Mueller et \
             al. 2003, Sec. 4.4; dimensionless)";
        /// The kernel shape (support `2h`); default Wendland C2.
        pub kernel: Kernel = Kernel::WendlandC2, kernel_check(), KERNEL_DOC;
        /// The smoothing length `h` in units of `r`, in `(0, 100]`; default
        /// [`DEFAULT_H_OVER_R`].
        pub h_over_r: f64 = DEFAULT_H_OVER_R, h_over_r_check(), H_OVER_R_DOC;
    }
}

/// The colour-field detector of Müller et al. (2003) (`muller`). See the crate documentation.
///
/// Built from a checked [`MullerParams`] ([`MullerDetector::try_new`]), so a detector never
/// holds an invalid value.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MullerDetector {
    params: MullerParams,
}

impl MullerDetector {
    /// The dimensionless colour-field gradient magnitude `|∇c_i|·h` of every particle, in
    /// input order.
    pub fn gradient_magnitudes<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        r: Radius,
    ) -> Result<Vec<f64>, CoreError> {
        let ctx = SphContext::new(set, self.smoothing().kernel_at(r))?;
        Ok(ctx.gradients_h(set.len(), |_, g| g.norm()))
    }
}

/// The criterion: `|∇c_i|·h > threshold`, margin `|∇c_i|·h − threshold`.
impl SphCriterion for MullerDetector {
    const METHOD: &'static str = METHOD;
    const MARGIN: bool = true;

    fn smoothing(&self) -> Smoothing {
        Smoothing {
            kernel: self.params.kernel,
            h_over_r: self.params.h_over_r,
        }
    }

    fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict {
        self.verdict(&ctx.gradient_h(i))
    }

    fn classify_all<const D: usize>(&self, ctx: &SphContext<'_, D>, count: usize) -> Vec<Verdict> {
        ctx.gradients_h(count, |_, g| self.verdict(g))
    }
}

impl MullerDetector {
    /// The verdict from `∇c_i · h`.
    fn verdict<const D: usize>(&self, gradient_h: &Point<D>) -> Verdict {
        let margin = gradient_h.norm() - self.params.threshold;
        Verdict {
            boundary: margin > 0.0,
            margin,
        }
    }
}

impl SphMethod for MullerDetector {
    const RADII_REFUSAL: &'static str =
        "the colour field (Müller et al. 2003) assumes one smoothing length";
    const SOLID_REFUSAL: &'static str = "its density and colour-field gradient are kernel sums over particles, and a half-space is no particle; give the walls as wall particles, which enter the sums";

    fn param_list(&self) -> Params {
        self.params.listing()
    }
}

// `Display` and `BoundaryDetector` (dispatch, radii refusal, owned particles, halo of two
// kernel supports) from the SPH frame.
boundary_sph::impl_sph_detector!(MullerDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(MullerDetector, MullerParams);

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use boundary_core::BoundaryDetector;

    #[test]
    fn parameters_are_checked_and_reported() {
        let d = MullerDetector::default();
        assert_eq!(
            d.describe().to_string(),
            format!("threshold={DEFAULT_THRESHOLD}, kernel=wendland, h_over_r=1")
        );
        assert_eq!(d.params(), &MullerParams::default());
        let params = MullerParams {
            threshold: 0.45,
            kernel: Kernel::CubicSpline,
            h_over_r: 100.0,
        };
        let d = MullerDetector::try_new(params.clone()).unwrap();
        assert_eq!(d.params(), &params);
        assert_eq!(
            d.describe().to_string(),
            "threshold=0.45, kernel=cubic, h_over_r=100"
        );
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            let err = MullerDetector::try_new(MullerParams {
                threshold: bad,
                ..MullerParams::default()
            })
            .unwrap_err();
            assert_eq!(
                err.to_string(),
                format!(
                    "method 'muller': invalid value '{bad}' for 'threshold': must be a number >= 0"
                )
            );
        }
        for bad in [0.0, -1.0, 100.5, f64::NAN] {
            let err = MullerDetector::try_new(MullerParams {
                h_over_r: bad,
                ..MullerParams::default()
            })
            .unwrap_err();
            assert!(
                matches!(&err, boundary_core::ParamError::Invalid { key, .. } if key == "h_over_r"),
                "{err}"
            );
        }
    }
}
