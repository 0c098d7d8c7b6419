#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Free-surface particles from the **renormalisation matrix**: the Randles–Doring criterion,
//! method name `randles`. A particle is free surface when the smallest eigenvalue of its SPH
//! renormalisation matrix is small.
//!
//! # When to use it
//! When your solver already forms the renormalisation (kernel-correction) matrix and you want
//! the flag it gives for free, or a quick first pass in 2D. It is the first step of `marrone`
//! without the scan cone, so it is cheaper and coarser: it flags a band of particles near the
//! surface rather than the surface layer. Not certified; in 3D read the measured sensitivity
//! below (and the sweep report) before you trust one `mu`.
//!
//! # Origin
//! - Randles & Libersky, *Smoothed particle hydrodynamics: some recent improvements and
//!   applications*, Comput. Methods Appl. Mech. Engrg. 139 (1996) 375–408, introduce the
//!   renormalisation matrix `B_i` that makes the SPH gradient exact for linear fields.
//! - M. Doring, *Développement d'une méthode SPH pour les applications à surface libre en
//!   hydrodynamique*, PhD thesis, École Centrale de Nantes (2005), flags free-surface
//!   particles by the smallest eigenvalue `λ_i` of `B_i`.
//! - Marrone, Colagrossi, Le Touzé & Graziani, *Fast free-surface detection and level-set
//!   function definition in SPH solvers*, J. Comput. Phys. 229 (2010) 3652–3663 (and their
//!   conference version, *A fast algorithm for free-surface particles detection in 2D and 3D
//!   SPH methods*, which felpzOliveira/Bubbles cites) take `λ_i` as their first step: `λ <= 0.2`
//!   free surface, `λ > 0.75` interior, the band between decided by a scan (our `marrone`).
//!   Used alone, the criterion needs one threshold `mu`: **free surface iff `λ_i <= mu`**.
//!
//! # Method
//! `B_i = Σ_j V_j (x_j − x_i) ⊗ ∇W_ij` over the neighbours within the support `2h`, with the
//! summation-density volumes `V_j = m/ρ_j` of a uniform mass (`boundary-sph`, the same matrix
//! as `marrone`'s first step); `λ_i` its smallest eigenvalue (symmetric: each term is a
//! positive multiple of `(x_j − x_i) ⊗ (x_j − x_i)`). `λ_i ≈ 1` inside a uniform distribution
//! and falls where the neighbourhood is one-sided.
//!
//! # Where Bubbles departs
//! Bubbles (`doring.h`) builds its tensor from the *unit* kernel-gradient directions weighted
//! by volume (dropping the kernel's radial weight), takes the smallest eigenvalue of its
//! *inverse* (of the matrix itself where the determinant is zero), rescales it by the
//! smallest and largest values over the whole set, and thresholds the rescaled value at
//! `mu = 0.45` in 2D and 0.75 in 3D, over a 3-cell neighbourhood with a kernel radius of three
//! spacings; it prints "Could not find a suitable μ for 3D". We follow the papers instead:
//! `λ_i` of `B_i` itself, compared with `mu` directly, so a particle's label depends on its
//! own neighbourhood only (the set-wide rescaling of Bubbles changes every label when one
//! far-away particle moves, and cannot be split over a decomposition).
//!
//! # The default thresholds, and 3D
//! The papers give the 0.2 and 0.75 of the two-sided test, not a single `mu`. Ours are tuned on
//! scenes **disjoint from the ones the sweep reports**: `tests/threshold.rs` takes the seeded
//! tuning scenes of `boundary_scenes::tuning` (20 in 2D, 6 in 3D; none is in
//! `fixtures/scenes.toml`), measures M = Rec·(1 − FPR) against `exact` for `mu = k/40`
//! (`k = 1..=48`) in each dimension, and fails unless [`DEFAULT_MU_2D`] and [`DEFAULT_MU_3D`]
//! have the largest mean M of their dimension (`cargo test -p boundary-randles --test
//! threshold -- --nocapture` prints the table): 0.6 in 2D, 0.625 in 3D. It also measures how
//! stable `mu` is, the question Bubbles left open: see [`DEFAULT_MU_3D`].
//!
//! # Parameters ([`RandlesParams`])
//! | key | default | meaning |
//! |---|---|---|
//! | `mu_2d` | [`DEFAULT_MU_2D`] | free surface iff `λ_i <= mu_2d` (2D sets) |
//! | `mu_3d` | [`DEFAULT_MU_3D`] | free surface iff `λ_i <= mu_3d` (3D sets) |
//! | `kernel` | `wendland` | `wendland` (C2) or `cubic` (spline), support `2h` |
//! | `h_over_r` | 1 | smoothing length `h` in units of the resolution `r` |
//!
//! Detections carry no margin: the label is decided without computing `λ_i` (`B_i − mu·I` is
//! not positive definite, by a Cholesky factorisation: [`positive_definite`]), which costs less
//! than the eigen-decomposition; [`RandlesDetector::lambdas`] gives `λ_i` for inspection.
//!
//! # Policy: ties, duplicates, degenerate input
//! - The test is closed, as Marrone et al. write it (`λ <= 0.2`): `λ_i = mu` is free surface.
//! - An isolated particle, a coincident pair, a line in 2D or a plane in 3D has a singular
//!   `B_i`, `λ_i = 0`: free surface, as under the geometric definition.
//! - Duplicates of `x_i` add to its density (halving its volume) but carry no direction, so
//!   they add nothing to `B_i`.
//! - Walls and periodic images (through `detect_in`) enter `B_i` as particles; solid
//!   half-spaces are refused (no particle to sum).
//! - Not certified. Labels do not depend on the thread count or on a decomposition.
//!
//! # Hard cases
//! Its column of `crates/boundary/tests/snapshots/every_detector__hard_cases.snap` (`+FP −FN`
//! against `exact`):
//! - Degenerate sets (single particles, pairs, lines, planes, collinear and coplanar 3D
//!   sets): all boundary, as `exact` (singular `B_i`).
//! - Perfect lattices: the labels of `exact` from `r = 0.8a` (2D) and at the 3D tie radius; at
//!   the 2D tie radius every particle is flagged (+100), and just below the 3D tie the
//!   interior's `λ` stays high (−125).
//! - Jittered lattices: +147 to +153 false positives of 75–88 in 2D (the band), +7 to +10 in
//!   3D, and at most 15 false negatives; the same counts at every scale and offset.
//!
//! Empty input: empty labels.
//!
//! # Per-particle radii
//! `randles` refuses sets with per-particle radii (`DetectError::PerParticleRadii`): the
//! renormalisation matrix of Randles & Libersky assumes one smoothing length.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_randles::RandlesDetector;
//!
//! // A 12 x 12 square lattice of spacing 1 at r = 1.5: the outer ring is free surface, the
//! // particles three or more layers deep are not.
//! let rows: Vec<[f64; 2]> = (0..144).map(|k| [(k % 12) as f64, (k / 12) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let labels = RandlesDetector::default()
//!     .detect_2d(&set, Radius::new(1.5).unwrap())
//!     .unwrap()
//!     .labels;
//! for k in 0..144 {
//!     let (x, y) = (k % 12, k / 12);
//!     let depth = x.min(y).min(11 - x).min(11 - y);
//!     if depth == 0 {
//!         assert!(labels.is_boundary(k), "particle {k}");
//!     } else if depth >= 3 {
//!         assert!(!labels.is_boundary(k), "particle {k}");
//!     }
//! }
//! ```

use boundary_core::nalgebra::SMatrix;
use boundary_core::{CoreError, ParamSet, Params, ParticleSet, Point, Radius};
use boundary_sph::frame::{
    h_over_r_check, kernel_check, DEFAULT_H_OVER_R, H_OVER_R_DOC, KERNEL_DOC,
};
use boundary_sph::{
    Kernel, Smoothing, SphContext, SphCriterion, SphMethod, SymmetricEigen, Verdict,
};
use rayon::prelude::*;

/// Default `mu` for 2D sets: the best mean M (0.940) on the 20 2D tuning scenes; the best
/// `mu` of single scenes ranges from 0.575 to 0.7, and mean M stays within 0.05 of its best
/// for `mu` in 0.575–0.675.
pub const DEFAULT_MU_2D: f64 = 0.6;
/// Default `mu` for 3D sets: the best mean M (0.888) on the 6 3D tuning scenes.
///
/// **Is the criterion unstable in 3D?** Bubbles "could not find a suitable μ for 3D"; our
/// measurement (`tests/threshold.rs`) says a suitable `mu` exists and is as stable as in 2D:
/// the best `mu` of single 3D scenes ranges from 0.625 to 0.7 (0.575 to 0.7 in 2D), and the
/// default loses 0.007 of M on average against each scene's own best (0.006 in 2D). What is
/// true in both dimensions is that the window is narrow: mean M is within 0.05 of its best
/// only for `mu` in 0.6–0.7 (0.575–0.675 in 2D) and falls to 0.26 at 0.45 and 0.68 at 0.55 in
/// 3D, so Bubbles' 0.45 flags far too little; its 0.75 (from Marrone et al.'s interior cut)
/// gives 0.78. M is lower in 3D (0.888 against 0.940) because its band of flagged particles
/// is thicker than the exact boundary. The sweep report repeats the measurement on the
/// reported scenes.
pub const DEFAULT_MU_3D: f64 = 0.625;

const METHOD: &str = "randles";

/// The Randles–Doring criterion on the smallest eigenvalue `λ` of the renormalisation matrix:
/// free surface iff `λ <= mu`. Closed, as Marrone et al. (2010) write their first step.
pub fn is_free_surface(lambda: f64, mu: f64) -> bool {
    lambda <= mu
}

boundary_core::declare_params! {
    /// The parameters of `randles` (see the crate documentation).
    #[derive(Debug, Clone, PartialEq)]
    pub struct RandlesParams for "randles" {
        /// Free surface iff `λ <= mu_2d`, for 2D sets; finite, `>= 0`.
        pub mu_2d: f64 = DEFAULT_MU_2D, check::non_negative(),
            "2D: free surface iff the smallest eigenvalue of the renormalisation matrix is at \
             most mu (Doring 2005; Marrone et al. 2010)";
        /// Free surface iff `λ <= mu_3d`, for 3D sets; finite, `>= 0`.
        pub mu_3d: f64 = DEFAULT_MU_3D, check::non_negative(),
            "3D: free surface iff the smallest eigenvalue of the renormalisation matrix is at \
             most mu";
        /// Kernel shape (support `2h`).
        pub kernel: Kernel = Kernel::WendlandC2, kernel_check(), KERNEL_DOC;
        /// `h / r`, in `(0, 100]`.
        pub h_over_r: f64 = DEFAULT_H_OVER_R, h_over_r_check(), H_OVER_R_DOC;
    }
}

/// The Randles–Doring detector (`randles`). See the crate documentation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RandlesDetector {
    params: RandlesParams,
}

impl RandlesDetector {
    /// The threshold for `D`-dimensional sets.
    pub fn mu(&self, dim: usize) -> f64 {
        if dim == 2 {
            self.params.mu_2d
        } else {
            self.params.mu_3d
        }
    }

    /// The smallest eigenvalue `λ_i` of the renormalisation matrix of every particle, in input
    /// order (for inspection, plots and tuning).
    pub fn lambdas<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        r: Radius,
    ) -> Result<Vec<f64>, CoreError> {
        let ctx = SphContext::new(set, self.smoothing().kernel_at(r))?;
        Ok((0..set.len())
            .into_par_iter()
            .map(|i| lambda(&ctx, i))
            .collect())
    }
}

/// `λ_i`: the smallest eigenvalue of `B_i`.
fn lambda<const D: usize>(ctx: &SphContext<'_, D>, i: usize) -> f64 {
    SymmetricEigen::new(&ctx.local_sums(i).renormalisation).min_value()
}

/// The lower triangle and the diagonal of `B_i = Σ_j V_j (x_j − x_i) ⊗ ∇W_ij`, in units of
/// `h` (the entries of [`LocalSums::renormalisation`](boundary_sph::LocalSums) that
/// [`positive_definite`] reads; the upper triangle is left 0), without the Shepard sum and
/// the gradient the classification does not read.
fn renormalisation<const D: usize>(ctx: &SphContext<'_, D>, i: usize) -> SMatrix<f64, D, D> {
    let (pair, term) = renormalisation_terms(ctx);
    ctx.particle_sums(i, SMatrix::zeros(), &pair, &term)
}

/// The pair part `(|x_j − x_i|, σ_D (−f'(q)/q))` and the term `(x w) ⊗ x`, on and below the
/// diagonal (`x = (x_j − x_i)/h`, `w = V_j/h^D · σ_D (−f'(q)/q)`, for `q > 0` only), of
/// [`renormalisation`], for [`SphContext::pair_sums`].
#[allow(clippy::type_complexity)]
fn renormalisation_terms<'c, const D: usize>(
    ctx: &'c SphContext<'_, D>,
) -> (
    impl Fn(&Point<D>, f64) -> (f64, f64) + Sync + 'c,
    impl Fn(&mut SMatrix<f64, D, D>, &Point<D>, &(f64, f64), f64) + Sync + 'c,
) {
    let kernel = ctx.kernel();
    let inv_h = 1.0 / kernel.h();
    let pair = move |_: &Point<D>, d2: f64| {
        let d = d2.sqrt();
        (d, kernel.reduced_gradient_weight(d * inv_h))
    };
    let term =
        move |b: &mut SMatrix<f64, D, D>, xji: &Point<D>, &(d, weight): &(f64, f64), v: f64| {
            if d > 0.0 {
                let x = xji * inv_h;
                let xw = x * (v * weight);
                for c in 0..D {
                    for r in c..D {
                        b[(r, c)] += xw[r] * x[c];
                    }
                }
            }
        };
    (pair, term)
}

/// Whether the symmetric matrix `m` is positive definite, by Cholesky factorisation: every
/// pivot must be positive (Sylvester's criterion in the form that needs no determinant).
/// Reads the diagonal and the lower triangle only (the symmetric matrix they define).
/// `λ_min(B) <= mu` iff `B − mu·I` is not positive definite; the factorisation decides it
/// without the eigen-decomposition, equal to the eigenvalue test up to the rounding of a few
/// operations on the entries (a tie within that is decided either way).
pub fn positive_definite<const D: usize>(m: &SMatrix<f64, D, D>) -> bool {
    let mut l = SMatrix::<f64, D, D>::zeros();
    for k in 0..D {
        let mut pivot = m[(k, k)];
        for j in 0..k {
            pivot -= l[(k, j)] * l[(k, j)];
        }
        if pivot.is_nan() || pivot <= 0.0 {
            return false;
        }
        let root = pivot.sqrt();
        l[(k, k)] = root;
        for r in k + 1..D {
            let mut v = m[(r, k)];
            for j in 0..k {
                v -= l[(r, j)] * l[(k, j)];
            }
            l[(r, k)] = v / root;
        }
    }
    true
}

impl SphCriterion for RandlesDetector {
    const METHOD: &'static str = METHOD;
    /// No margin: the classification decides `λ_i <= mu` without computing `λ_i`
    /// ([`positive_definite`]); [`RandlesDetector::lambdas`] gives `λ_i` for inspection.
    const MARGIN: bool = false;

    fn smoothing(&self) -> Smoothing {
        Smoothing {
            kernel: self.params.kernel,
            h_over_r: self.params.h_over_r,
        }
    }

    fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict {
        self.verdict(&renormalisation(ctx, i))
    }

    fn classify_all<const D: usize>(&self, ctx: &SphContext<'_, D>, count: usize) -> Vec<Verdict> {
        let (pair, term) = renormalisation_terms(ctx);
        ctx.pair_sums(
            count,
            |_| SMatrix::zeros(),
            pair,
            term,
            |_, b| self.verdict(b),
        )
    }
}

impl RandlesDetector {
    /// The verdict from the renormalisation matrix: `λ_min(B) <= mu`.
    fn verdict<const D: usize>(&self, b: &SMatrix<f64, D, D>) -> Verdict {
        let shifted = b - SMatrix::<f64, D, D>::identity() * self.mu(D);
        Verdict::label(!positive_definite(&shifted))
    }
}

impl SphMethod for RandlesDetector {
    const RADII_REFUSAL: &'static str =
        "the renormalisation matrix (Randles & Libersky 1996) assumes one smoothing length";
    const SOLID_REFUSAL: &'static str = "its renormalisation matrix is a kernel sum over particles, and a half-space is no particle; give the walls as wall particles, which enter the sums";

    fn param_list(&self) -> Params {
        self.params.listing()
    }
}

boundary_sph::impl_sph_detector!(RandlesDetector);
// `try_new` (the declared checks), `params()`, and what the registry builds it from.
boundary_core::impl_detector_params!(RandlesDetector, RandlesParams);

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    #[test]
    fn the_cholesky_test_agrees_with_the_smallest_eigenvalue() {
        use rand::{rngs::StdRng, Rng, SeedableRng};
        let mut rng = StdRng::seed_from_u64(5);
        let mut both = [0usize; 2];
        for _ in 0..20_000 {
            let a = SMatrix::<f64, 3, 3>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            // Symmetric positive semi-definite, like B: a aᵀ, and a μ around its eigenvalues.
            let b = a * a.transpose();
            let mu = rng.gen_range(0.0..1.5);
            let lambda = SymmetricEigen::new(&b).min_value();
            if (lambda - mu).abs() < 1e-9 {
                continue;
            }
            let shifted = b - SMatrix::<f64, 3, 3>::identity() * mu;
            let free = !positive_definite(&shifted);
            assert_eq!(free, is_free_surface(lambda, mu), "λ {lambda} μ {mu}");
            // The classification accumulates the lower triangle only: the upper one is not
            // read.
            let lower =
                SMatrix::<f64, 3, 3>::from_fn(|r, c| if r >= c { shifted[(r, c)] } else { 0.0 });
            assert_eq!(positive_definite(&lower), !free, "λ {lambda} μ {mu}");
            both[usize::from(free)] += 1;
        }
        assert!(both[0] > 1000 && both[1] > 1000, "{both:?}");
        // Zero matrix at mu = 0: λ = 0 <= 0, free surface (the closed test).
        assert!(!positive_definite(&SMatrix::<f64, 2, 2>::zeros()));
        assert!(positive_definite(&SMatrix::<f64, 2, 2>::identity()));
    }

    #[test]
    fn the_criterion_is_closed() {
        assert!(is_free_surface(0.2, 0.2));
        assert!(!is_free_surface(0.2 + 1e-15, 0.2));
        assert!(is_free_surface(0.0, 0.0));
    }
}
