#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Free-surface detection of Marrone, Colagrossi, Le Touzé & Graziani, *Fast free-surface
//! detection and level-set function definition in SPH solvers*, J. Comput. Phys. 229 (2010)
//! 3652–3663: an SPH baseline of the JCP 2020 comparison (Tables 1–2, "Marrone et al."), method
//! name `marrone`.
//!
//! **When to use it:** to compare with the free-surface test an SPH solver already runs
//! (positions only, no certificate: it can miss boundary particles and flag interior ones),
//! or to reproduce the JCP 2020 comparison. For the labels themselves use `exact`
//! (accuracy and speed on the same scenes: `BENCHMARKS.md`, written by `cargo xtask sweep`).
//!
//! # Method
//! Every quantity is an SPH sum over the neighbours `j` within the kernel support `2h`, with
//! `∇W_ij = ∇_i W(|x_i − x_j|)` and the summation-density volumes `V_j = m/ρ_j` of a uniform
//! mass (`boundary-sph`; positions are all it needs). Equation labels (M1)–(M4) are ours; the
//! paper's text was not at hand to confirm its numbering (its Sec. 2 gives the 2D algorithm,
//! Sec. 3 the 3D one with the same first step).
//!
//! - (M1) **Renormalisation matrix** (Randles & Libersky 1996), as the paper writes it,
//!   `L_i = [Σ_j ∇W_ij ⊗ (x_j − x_i) V_j]⁻¹`. We form the matrix before inversion,
//!   `B_i = Σ_j V_j (x_j − x_i) ⊗ ∇W_ij` (the transpose of the paper's, and equal to it: each
//!   term is a positive multiple of `(x_j − x_i) ⊗ (x_j − x_i)`), which is the identity for a
//!   full, uniform neighbourhood and loses rank where the neighbourhood is one-sided.
//! - (M2) **First step**: `λ_i` is the smallest eigenvalue of `B_i`. `λ_i <= 0.2`: free
//!   surface; `λ_i > 0.75`: interior; otherwise the particle is a *candidate* ("close to the
//!   free surface") for the second step. The paper uses the same thresholds in 2D and 3D.
//! - (M3) **Normal** of a candidate: `n_i = ν_i/|ν_i|`, `ν_i = −L_i Σ_j ∇W_ij V_j`, the
//!   renormalised SPH gradient of the constant field 1 (the colour-field gradient corrected by
//!   `L_i`), pointing out of the fluid. We solve `B_i ν_i = −Σ_j V_j ∇W_ij` through the
//!   eigen-decomposition of the first step; `B_i` is well conditioned for a candidate
//!   (`λ_i > 0.2`). The issue text's "gradient of λ" is not what the paper does: the normal
//!   comes from the renormalised gradient of unity.
//! - (M4) **Second step, scan region** (the "umbrella"): with `T = x_i + h n_i`, candidate `i`
//!   is free surface iff no neighbour `j` lies in
//!   `{|x_j − x_i| >= √2h, |x_j − T| < h} ∪ {|x_j − x_i| < √2h, angle(x_j − x_i, n_i) < π/4}`.
//!   In 2D the paper writes the near part as the square `|n·(x_j − T)| + |τ·(x_j − T)| < h`;
//!   it equals the cone there (module `scan`), so one test written over `D` serves both.
//!
//! # Parameters (`--set key=value`)
//! | key | default | meaning |
//! |---|---|---|
//! | `lambda_surface` | 0.2 | (M2) `λ <= lambda_surface`: free surface |
//! | `lambda_interior` | 0.75 | (M2) `λ > lambda_interior`: interior |
//! | `cone_angle` | 45 | (M4) cone half-angle in degrees; the ball part starts at `2h cos θ` (`√2h` at 45°) |
//! | `kernel` | `wendland` | `wendland` (C2) or `cubic` (spline), both with support `2h` |
//! | `h_over_r` | 1 | smoothing length `h` in units of the resolution `r` |
//!
//! The two λ tests are applied in that order, so `lambda_surface > lambda_interior` is
//! accepted and means "no scan". The thresholds were tuned by Marrone et al. on their own SPH
//! particle distributions, where `h` is tied to the particle spacing; here `h = r` by default,
//! the thesis' pairing of `r` with the smoothing length (Sec. 2.4: "a good choice for r is the
//! smoothing length"), so `h/Δx` is whatever `r/Δx` the scene has.
//!
//! # Policy: ties, duplicates, degenerate input
//! - An isolated particle has `B_i = 0`, `λ_i = 0`: free surface. So do pairs, lines in 2D and
//!   planes in 3D (`B_i` singular).
//! - A candidate whose `ν_i` is zero or not finite (a perfectly symmetric neighbourhood) has no
//!   direction to be free in: interior.
//! - Duplicates of `x_i` add to its density (they halve its volume) but have no direction:
//!   they are skipped in the scan; they never shield `x_i`, as in the geometric definition.
//! - Both parts of the scan region are open (strict inequalities): a neighbour exactly on its
//!   surface does not shield the particle. In perfect lattices this decides the neighbours
//!   that lie exactly at 45° from the normal.
//! - Not certified: the method has no guarantee against false negatives.
//!
//! # Hard cases
//! What `marrone` returns on the hard cases (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`).
//! Not certified, so it can miss boundary particles:
//! - Degenerate sets (single particles, coincident pairs, pairs exactly `2r` apart, lines,
//!   collinear and coplanar 3D sets): every particle boundary, as `exact`.
//! - Perfect lattices: the labels of `exact` at the tie radius; 4 ulps below the 2D tie, 4
//!   false positives.
//! - Duplicates: exact and 1e-12 near-duplicates both as `exact`.
//! - Jittered lattices: 10–19 false negatives of 75–88 boundary particles in 2D, 15–18 of 383
//!   in 3D, at most 1 false positive; the same counts at every scale from 1e-9 to 1e9 and at
//!   offsets 1e6 and 1e9 (the method is scale-free). Empty input: empty labels.
//!
//! # Per-particle radii
//! `marrone` refuses sets with per-particle radii (`DetectError::PerParticleRadii`): the
//! renormalisation matrix and the scan cone of Marrone et al. (2010) assume one smoothing length;
//! variable-`h` SPH would need its own criterion.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_marrone::MarroneDetector;
//!
//! // A 12 x 12 square lattice of spacing 1 at r = 1.5: the outer ring is free surface, the
//! // particles two or more layers deep are not.
//! let rows: Vec<[f64; 2]> = (0..144).map(|k| [(k % 12) as f64, (k / 12) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let labels = MarroneDetector::default()
//!     .detect_2d(&set, Radius::new(1.5).unwrap())
//!     .unwrap()
//!     .labels;
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

mod scan;

use boundary_core::{CoreError, ParamSet, Params, ParticleSet, Radius};
use boundary_sph::frame::{
    h_over_r_check, kernel_check, DEFAULT_H_OVER_R as FRAME_H_OVER_R, H_OVER_R_DOC, KERNEL_DOC,
};
/// The SPH kernel shapes of [`MarroneParams::kernel`].
pub use boundary_sph::Kernel;

use boundary_sph::{Smoothing, SphContext, SphCriterion, SphMethod, SymmetricEigen, Verdict};
use rayon::prelude::*;
use scan::ScanRegion;

/// Default `lambda_surface` (M2): the paper's threshold for surely free-surface particles.
pub const DEFAULT_LAMBDA_SURFACE: f64 = 0.2;
/// Default `lambda_interior` (M2): the paper's threshold for surely interior particles.
pub const DEFAULT_LAMBDA_INTERIOR: f64 = 0.75;
/// Default cone half-angle of the scan region (M4), in degrees: the paper's `π/4`.
pub const DEFAULT_CONE_ANGLE_DEG: f64 = 45.0;
/// Default smoothing length in units of `r`.
pub const DEFAULT_H_OVER_R: f64 = FRAME_H_OVER_R;

const METHOD: &str = "marrone";

boundary_core::declare_params! {
    /// The parameters of `marrone`, with the paper's defaults (string form: the `--set` keys
    /// of the same names, see `boundary::registry`).
    #[derive(Debug, Clone, PartialEq)]
    pub struct MarroneParams for "marrone" {
        /// (M2) `λ <= lambda_surface`: free surface. Finite, `>= 0`; default
        /// [`DEFAULT_LAMBDA_SURFACE`].
        pub lambda_surface: f64 = DEFAULT_LAMBDA_SURFACE, check::non_negative(),
            "smallest eigenvalue of the renormalisation matrix at or below which a particle \
             is free surface (Marrone et al. 2010, first step)";
        /// (M2) `λ > lambda_interior`: interior. Finite, `>= 0`; default
        /// [`DEFAULT_LAMBDA_INTERIOR`]. The two tests are applied in that order, so
        /// `lambda_surface > lambda_interior` is accepted and means "no scan".
        pub lambda_interior: f64 = DEFAULT_LAMBDA_INTERIOR, check::non_negative(),
            "smallest eigenvalue above which a particle is interior; between the two \
             thresholds the scan region decides (second step)";
        /// (M4) half-angle of the scan cone, in degrees, in `(0, 90)`; default
        /// [`DEFAULT_CONE_ANGLE_DEG`]. The ball part of the scan region starts at `2h cos θ`.
        pub cone_angle: f64 = DEFAULT_CONE_ANGLE_DEG,
            check::open(0.0, 90.0).because("must be an angle in degrees in (0, 90)"),
            "half-angle in degrees of the scan cone around the normal; the ball of radius h \
             around x + h n takes over at 2h cos(angle)";
        /// The kernel shape (support `2h`); default Wendland C2.
        pub kernel: Kernel = Kernel::WendlandC2, kernel_check(), KERNEL_DOC;
        /// The smoothing length `h` in units of `r`, in `(0, 100]`; default
        /// [`DEFAULT_H_OVER_R`].
        pub h_over_r: f64 = DEFAULT_H_OVER_R, h_over_r_check(), H_OVER_R_DOC;
    }
}

/// The Marrone et al. (2010) detector (`marrone`). See the crate documentation.
///
/// Built from a checked [`MarroneParams`] ([`MarroneDetector::try_new`]), so a detector never
/// holds an invalid value.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MarroneDetector {
    params: MarroneParams,
}

/// The criterion: (M2) the smallest eigenvalue of `B_i`, then for a candidate (M3–M4) the
/// scan region around its normal.
impl SphCriterion for MarroneDetector {
    const METHOD: &'static str = METHOD;
    const MARGIN: bool = false;

    fn smoothing(&self) -> Smoothing {
        Smoothing {
            kernel: self.params.kernel,
            h_over_r: self.params.h_over_r,
        }
    }

    fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict {
        let theta = self.params.cone_angle.to_radians();
        Verdict::label(self.is_free_surface(ctx, i, ctx.kernel().h(), theta))
    }
}

impl SphMethod for MarroneDetector {
    const RADII_REFUSAL: &'static str = "the renormalisation matrix and the scan cone (Marrone et al. 2010) assume one smoothing length";
    const SOLID_REFUSAL: &'static str = "its renormalisation matrix and normal are kernel sums over particles, and a half-space is no particle; give the walls as wall particles, which enter the sums as in DualSPHysics";

    fn param_list(&self) -> Params {
        self.params.listing()
    }
}

// `Display` and `BoundaryDetector` (dispatch, radii refusal, owned particles, halo of two
// kernel supports) from the SPH frame.
boundary_sph::impl_sph_detector!(MarroneDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(MarroneDetector, MarroneParams);

impl MarroneDetector {
    /// The smallest eigenvalue `λ_i` of the renormalisation matrix (M1–M2) of every particle,
    /// in input order: the quantity of the first step, for inspection and plots.
    pub fn lambdas<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        r: Radius,
    ) -> Result<Vec<f64>, CoreError> {
        let ctx = SphContext::new(set, self.smoothing().kernel_at(r))?;
        Ok((0..set.len())
            .into_par_iter()
            .map(|i| {
                if boundary_core::stop::requested() {
                    return Default::default();
                }
                SymmetricEigen::new(&ctx.local_sums(i).renormalisation).min_value()
            })
            .collect())
    }

    /// Both steps for particle `i`.
    fn is_free_surface<const D: usize>(
        &self,
        ctx: &SphContext<'_, D>,
        i: usize,
        h: f64,
        theta: f64,
    ) -> bool {
        let (renormalisation, gradient_h) = ctx.renormalisation_and_gradient_h(i);
        // Most particles of a fluid: interior by a floor of λ_i, without the decomposition
        // (the floor is never above the decomposition's λ_i, so the label is the same). The
        // floor must clear both thresholds: the surface test comes first, and
        // `lambda_surface > lambda_interior` is accepted.
        let floor = SymmetricEigen::min_value_floor(&renormalisation);
        if floor > self.params.lambda_interior && floor > self.params.lambda_surface {
            return false;
        }
        let eigen = SymmetricEigen::new(&renormalisation);
        let lambda = eigen.min_value();
        if lambda <= self.params.lambda_surface {
            return true;
        }
        if lambda > self.params.lambda_interior {
            return false;
        }
        let nu = -eigen.solve(&gradient_h);
        let norm = nu.norm();
        if !(norm > 0.0 && norm.is_finite()) {
            return false;
        }
        // The scan in units of h (h = 1), like the sums: the same for a scene and its scaled
        // copy.
        let region = ScanRegion::new(nu / norm, 1.0, theta);
        let inv_h = 1.0 / h;
        let mut shielded = false;
        ctx.for_each_neighbour_volume(i, |_, xji, _| {
            let xji = xji * inv_h;
            let d = xji.norm();
            if !shielded && d > 0.0 && region.contains(&xji, d) {
                shielded = true;
            }
        });
        !shielded
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use boundary_core::BoundaryDetector;

    /// With `lambda_surface > lambda_interior` there is no scan: a particle is boundary
    /// exactly when its λ (the decomposition's, from `lambdas`) is at most
    /// `lambda_surface`, including those whose λ lies above `lambda_interior` (the floor that
    /// skips the decomposition must not call them interior). Jittered ball: many particles
    /// have λ between the two thresholds.
    #[test]
    fn with_the_thresholds_crossed_the_surface_test_decides_alone() {
        let (ball, _) = boundary_scenes::jittered_lattice_ball(3000, 0.15, 7);
        let r = Radius::new(1.2).unwrap();
        let d = MarroneDetector::try_new(MarroneParams {
            lambda_surface: 0.95,
            lambda_interior: 0.5,
            ..MarroneParams::default()
        })
        .unwrap();
        let lambdas = d.lambdas(&ball, r).unwrap();
        let labels = d.detect_3d(&ball, r).unwrap().labels;
        let between = lambdas.iter().filter(|&&l| l > 0.5 && l <= 0.95).count();
        assert!(between > 100, "{between} particles between the thresholds");
        for (i, &l) in lambdas.iter().enumerate() {
            assert_eq!(labels.is_boundary(i), l <= 0.95, "particle {i}, λ {l}");
        }
    }

    #[test]
    fn parameters_are_checked_and_reported() {
        let d = MarroneDetector::default();
        assert_eq!(
            d.describe().to_string(),
            "lambda_surface=0.2, lambda_interior=0.75, cone_angle=45, kernel=wendland, h_over_r=1"
        );
        assert_eq!(d.params(), &MarroneParams::default());
        let params = MarroneParams {
            lambda_surface: 0.1,
            lambda_interior: 0.9,
            cone_angle: 30.0,
            kernel: Kernel::CubicSpline,
            h_over_r: 2.0,
        };
        let d = MarroneDetector::try_new(params.clone()).unwrap();
        assert_eq!(d.params(), &params);
        assert_eq!(
            d.describe().to_string(),
            "lambda_surface=0.1, lambda_interior=0.9, cone_angle=30, kernel=cubic, h_over_r=2"
        );
        for (key, bad) in [
            ("lambda_surface", -0.1),
            ("lambda_interior", f64::NAN),
            ("cone_angle", 90.0),
            ("cone_angle", 0.0),
            ("h_over_r", 0.0),
            ("h_over_r", 100.5),
            ("h_over_r", f64::INFINITY),
        ] {
            let mut p = MarroneParams::default();
            match key {
                "lambda_surface" => p.lambda_surface = bad,
                "lambda_interior" => p.lambda_interior = bad,
                "cone_angle" => p.cone_angle = bad,
                _ => p.h_over_r = bad,
            }
            let err = MarroneDetector::try_new(p).unwrap_err();
            let boundary_core::ParamError::Invalid {
                key: named, value, ..
            } = &err
            else {
                panic!("{err}");
            };
            assert_eq!(
                (named.as_str(), value.as_str()),
                (key, bad.to_string().as_str())
            );
        }
    }
}
