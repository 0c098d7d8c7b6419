#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Boundary particles by a support vector machine (Sandim 2020 thesis, ch. 3), method name
//! `svm`.
//!
//! **When to use it:** to reproduce the thesis' learning method, or to compare a learned
//! classifier with the geometric ones. It is not certified (it can miss boundary
//! particles); for the labels themselves use `exact`, the reference (accuracy and speed of
//! both on the same scenes: `BENCHMARKS.md`, written by `cargo xtask sweep`).
//!
//! # Method
//! Each particle gets the thesis' six SPH features (Sec. 3.2.1, made scale-free) and one of
//! ours, all from one neighbour query per particle (see [`features`]): the Parzen density,
//! the modulus of its gradient, the SPH divergence of the position field, the neighbour
//! count within the influence radius `2r`, the smallest and largest eigenvalue of the
//! neighbourhood covariance, and (ours) the sampled cover margin: how far the least-covered
//! of a few sample points of the sphere `S_i`, and of a short ascent on the sphere from the
//! best of them, is from being uncovered. A C-SVC (thesis
//! Sec. 3.2.3) trained against the `exact` labels classifies them ([`SvmModel`]). The thesis
//! uses an RBF kernel; a model here has an RBF or a polynomial kernel of degree 1 to 3, and
//! the trainer ships, per dimension, the kernel of its grid whose decision is cheapest
//! within 0.005 of the best validation M (see *Kernel choice* below): a **polynomial kernel**,
//! which [`PackedModel`] expands once into the weights of the monomials of the standardised
//! features, so that a decision costs at most `7 + 7² + 7³` multiply-adds whatever the
//! number of support vectors (an RBF model costs one exponential per support vector).
//! One model per dimension ships inside the crate (`models/svm2d.json`,
//! `models/svm3d.json`), made by `cargo xtask train-svm` with `linfa-svm` on **generated**
//! scenes only (blobs, stretched flows, sheets and filaments one to three particles thick,
//! droplets, lattices at and off their tie radii; `crates/boundary-svm-train`), and
//! evaluated here by our own code, parallel over particles.
//!
//! **Structural safeguards (ours, not in the thesis).** A particle is boundary by a proof,
//! whatever the model says, when
//! - it has at most `D` distinct neighbours within `2r`: each ball of radius `r` centred
//!   within `2r` covers less than a hemisphere of `S_i`, and `D` such caps leave a point
//!   uncovered (a direction orthogonal to `D − 1` of the centres, signed away from the
//!   last);
//! - or its sampled cover margin exceeds [`CERTIFICATE_TOLERANCE`]: the sample point
//!   `x_i + r n` is then farther than `r` from every distinct neighbour (see [`features`]
//!   for the directions and the rounding bound), so `S_i` is not covered.
//!
//! These particles are labelled boundary without evaluating the SVM (their decision value
//! is reported as 0), and the SVM is trained only on the others.
//!
//! **Near ties go to `exact` (ours).** A particle none of whose sample points is uncovered
//! by more than the rounding bound, but one of which is within it (sampled cover margin in
//! `(−1e-12, 1e-12]`), sits at a tie that no floating-point feature can resolve: a perfect
//! lattice at, or a few ulps around, its tie radius. `exact` decides those particles (the
//! cascade's machinery, on those particles only; none on jittered or simulated sets), so
//! that perfect lattices at and around their ties get `exact`'s labels, with no false
//! negative. The trainer shifts the
//! model's threshold by the value that maximises `Rec² (1 − FPR)` on its validation
//! frames (a miss counts twice: nothing downstream recovers it, while the cascade below
//! removes false positives); the shift is part of the shipped bias.
//!
//! **Cascade** (thesis Sec. 3.4): with `refine=exact` or `refine=ge` the particles the SVM
//! calls boundary are re-tested by that method (the others, as ghosts, only serve as
//! neighbours); the particles it calls interior stay interior. The cascade's false positives
//! are those of the refiner (none for `exact`), its misses those of the SVM, so its recall is
//! the SVM's.
//!
//! # Parameters
//! [`SvmParams`], checked by [`SvmDetector::try_new`]; the `--set key=value` keys of the
//! command line and the bindings are the field names.
//!
//! | field | default | meaning | string form |
//! |---|---|---|---|
//! | `refine` | [`Refine::None`] | re-test the SVM's boundary particles with `exact` or `ge` (at its default depth) | `none`, `exact`, `ge` |
//! | `model` | [`ModelChoice::Shipped`] | the shipped model of the set's dimension, or a model of one dimension ([`ModelChoice::Custom`]) | `default` or the path of a model file (JSON, see [`SvmModel`]) |
//!
//! [`ModelChoice::from_file`] (what `model=PATH` calls) reads the file and fails with an
//! error that names the file if it cannot be read or is not a valid model: the one place
//! where a method crate touches the file system, because the model is the method's
//! parameter.
//!
//! # Policy: ties, duplicates, degenerate input
//! - A decision value of exactly 0 is boundary.
//! - Certified particles (above) are boundary with decision value 0. A sampled point at
//!   exactly distance `r` from a neighbour (a tie) is covered: the certificate needs a
//!   margin above `1e-12 r²`. A particle whose margin lies within `±1e-12` (a near tie:
//!   lattices at, or within about `1e-12` relative of, their tie radius) is decided by
//!   `exact`, not by the model.
//! - Features of isolated particles, pairs and duplicates are defined (see [`features`]);
//!   duplicates count as neighbours but cover nothing.
//! - A loaded model of the wrong dimension, or of another feature version, is an error
//!   naming the model file.
//! - Not certified as a whole: the SVM can miss boundary particles, and so can the cascade.
//!
//! # Accuracy
//! Every scene of the sweep (`fixtures/scenes.toml`: our fixtures and the public frames of
//! `../shared/data`) is held out: the models never saw them, nor any frame or rotation of
//! the simulations they come from. `cargo xtask train-svm` scores every one of them, with
//! `marrone` beside it, in its training report; `docs/METHODS.md` quotes the scores, and the
//! test `quoted_held_out_scores_are_reproduced` (`tests/svm.rs`) recomputes the quoted rows.
//!
//! Thin splash sheets (`r` ≈ 2.7 spacings, at most about four layers thick: every interior
//! particle within two spacings of a boundary one) are where fixed sample points of the
//! sphere fall short: the small uncovered caps of their boundary particles escape the 17
//! sample directions, which leaves uncertified boundary particles among interior ones with
//! shallow margins, and the model then flags those interior particles too. The ascent of the
//! cover margin (see [`features`]) certifies most of these boundary particles, so that the
//! model sees few of them among shallow margins.
//!
//! Perfect square and cubic lattices (16², 10³) at 0.6, the tie radius, `±1e-9` and `±4`
//! ulps around it, 0.8, 1, 1.2, 1.5 and 2 spacings: no false negative (training report;
//! the test `perfect_lattices_have_no_false_negative` checks 12² and 7³ lattices at the
//! tie and 4 ulps either side against `exact` label for label, and others for misses);
//! `1e-9` below the tie every particle is boundary by the definition (the certificate
//! sees the uncovered diagonal points).
//!
//! **Speed.** The thesis' case for the SVM is speed. A decision costs the feature pass (one
//! neighbour query per particle, sums over the neighbours, the cover search over 17 sample
//! directions) and at most `7 + 7² + 7³` multiply-adds of the polynomial model. Each
//! decision is taken inside the neighbour pass (`NeighbourGrid::par_map_within`), so the
//! features are never stored. The neighbour sums run two lanes at a time with their sums in
//! registers, the cover search runs lane by lane over the neighbours within `1.1r` first, and
//! the offsets are written without a branch per neighbour. To measure it against `exact` in
//! one run: `cargo run --release -p boundary-svm --example svm_throughput 1000000 1` (each
//! method twice, alternately, its faster run kept; it prints a checksum of the decision
//! values), or `cargo bench -p boundary-svm`; `BENCHMARKS.md` compares it with every method
//! on the sweep's scenes.
//!
//! # Kernel choice
//! `cargo xtask train-svm` trains every model of its grid (training-sample size 800, 1600
//! or 3200; `C` 1, 10 or 100; kernel RBF with `γ` 0.1 or 0.3, or polynomial of degree 2 or
//! 3 with `γ` 0.1) and ships, per dimension, the model whose decision is cheapest within
//! 0.005 of the best validation M. An RBF model's cost grows with its support vectors (one
//! exponential each), a polynomial model's does not, and every degree-2 model costs the
//! same: the shipped models are polynomial of degree 2. The table of support vectors
//! against validation M, held-out M and speed is in the training report
//! (`target/svm/training.md`) and, for 3D, in `docs/METHODS.md`.
//!
//! # Hard cases
//! What `svm` (default model, `refine=none`) returns on the hard cases (the test
//! `every_detector_survives_the_hard_cases` in `crates/boundary/tests/every_detector.rs` runs
//! them all and keeps the table of counts against `exact`, `+FP −FN`, in
//! `crates/boundary/tests/snapshots/every_detector__hard_cases.snap`):
//! - Degenerate sets (single particles, coincident pairs, pairs exactly `2r` apart, lines,
//!   collinear and coplanar 3D sets): every particle boundary, by the certificates.
//! - Perfect square lattices at the tie radius `a/√2` and 4 ulps either side of it, and
//!   cubic lattices at and around `a√3/2`: the labels of `exact` (their interior particles
//!   are near ties, which `exact` decides).
//! - Exact duplicates: the labels of `exact`; 1e-12 near-duplicates: no miss, 18 false
//!   positives.
//! - Jittered lattices: in 2D the labels of `exact` (75 boundary) and 3 false negatives of
//!   88, in 3D 0–1 false positive and 3–5 false negatives of 383. The counts do not change
//!   with scale (1e-9 to 1e9: the features are scale-free, `r scale` rows: the labels of
//!   `exact` in 3D, 1 miss of 38 in 2D); offsets of 1e6 and 1e9: the labels of `exact`.
//!   Empty input: empty labels.
//!
//! # Per-particle radii
//! `svm` refuses sets with per-particle radii (`DetectError::PerParticleRadii`): its models were
//! trained on features of uniform-radius sets, and a model for graded sets would need its own
//! training data.
//!
//! # Example
//! ```
//! use boundary_core::{BoundaryDetector, ParticleSet, Radius};
//! use boundary_svm::{Refine, SvmDetector, SvmParams};
//!
//! // A 20 x 20 square lattice of spacing 1 at r = 1.5: the outer ring is boundary and the
//! // centre is interior.
//! let rows: Vec<[f64; 2]> = (0..400).map(|k| [(k % 20) as f64, (k / 20) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let r = Radius::new(1.5).unwrap();
//! let labels = SvmDetector::default().detect_2d(&set, r).unwrap().labels;
//! assert!(labels.is_boundary(0) && labels.is_boundary(19));
//! assert!(!labels.is_boundary(10 * 20 + 10));
//!
//! // The cascade with `exact` keeps only true boundary particles.
//! let cascade = SvmDetector::try_new(SvmParams {
//!     refine: Refine::Exact,
//!     ..SvmParams::default()
//! })
//! .unwrap();
//! let refined = cascade.detect_2d(&set, r).unwrap().labels;
//! assert_eq!(refined.boundary_count(), 76);
//! ```

pub mod features;
mod model;

pub use features::{
    compute_features, feature_reach, map_particle_features, particle_features, Features,
    ParticleFeatures, CERTIFICATE_TOLERANCE, FEATURE_NAMES, FEATURE_VERSION, MARGIN_FEATURE,
    N_FEATURES,
};
pub use model::{
    exp_nonpositive, Kernel, ModelError, PackedModel, SvmModel, MAX_DEGREE, MODEL_FORMAT,
};

use boundary_core::{
    BoundaryDetector, Capabilities, DetectError, Detection, Labels, Method, ParamError, ParamSet,
    ParamValue, Params, ParticleSet, Radius, Solids, Support,
};
use boundary_core::{Dim, Job, SupportedDim};
use boundary_exact::ExactDetector;
use boundary_ge::GeDetector;
use std::sync::{Arc, OnceLock};

/// Why `svm` rejects per-particle radii ([`DetectError::PerParticleRadii`]).
const NO_RADII: &str = "its models were trained on features of uniform-radius sets";

const METHOD: &str = "svm";

/// The shipped 2D model (JSON), made by `cargo xtask train-svm`.
pub const MODEL_2D_JSON: &str = include_str!("../models/svm2d.json");
/// The shipped 3D model (JSON), made by `cargo xtask train-svm`.
pub const MODEL_3D_JSON: &str = include_str!("../models/svm3d.json");

/// The shipped model of dimension `dim` (2 or 3), parsed once.
pub fn shipped_model(dim: usize) -> Result<&'static SvmModel, ModelError> {
    static M2: OnceLock<Result<SvmModel, ModelError>> = OnceLock::new();
    static M3: OnceLock<Result<SvmModel, ModelError>> = OnceLock::new();
    let cell = match dim {
        2 => M2.get_or_init(|| SvmModel::from_json(MODEL_2D_JSON)),
        3 => M3.get_or_init(|| SvmModel::from_json(MODEL_3D_JSON)),
        _ => return Err(ModelError(format!("no shipped model for dimension {dim}"))),
    };
    cell.as_ref()
        .map_err(|e| ModelError(format!("shipped {dim}D model: {e}")))
}

/// What re-tests the SVM's boundary particles (thesis Sec. 3.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Refine {
    /// The SVM's labels as they are. String form `refine=none`.
    #[default]
    None,
    /// `exact` re-tests them: no false positive remains. String form `refine=exact`.
    Exact,
    /// `ge` at its default depth re-tests them. String form `refine=ge`.
    Ge,
}

impl Refine {
    /// The string form: `none`, `exact` or `ge`.
    pub fn name(self) -> &'static str {
        match self {
            Refine::None => "none",
            Refine::Exact => "exact",
            Refine::Ge => "ge",
        }
    }
}

/// Which model `svm` evaluates.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum ModelChoice {
    /// The shipped model of the set's dimension ([`shipped_model`]). String form
    /// `model=default`.
    #[default]
    Shipped,
    /// A model of one dimension, with the label `params()` shows as the model's value (the
    /// path it was read from, for [`ModelChoice::from_file`]). A set of the other dimension
    /// is an error naming the label.
    Custom {
        /// What `params()` shows (a path, a name).
        label: String,
        /// The model.
        model: Arc<SvmModel>,
    },
}

impl ModelChoice {
    /// A custom model labelled `label`.
    pub fn custom(label: &str, model: SvmModel) -> Self {
        ModelChoice::Custom {
            label: label.to_owned(),
            model: Arc::new(model),
        }
    }

    /// Reads and validates the model file at `path` (JSON, see [`SvmModel`]), labelled by
    /// its path; the error names the file.
    pub fn from_file(path: &str) -> Result<Self, ModelError> {
        // The one documented exception to "method crates touch no file": the model is the
        // method's parameter (docs/ARCHITECTURE.md, clippy.toml).
        #[allow(clippy::disallowed_methods)]
        let text = std::fs::read_to_string(path)
            .map_err(|e| ModelError(format!("cannot read '{path}': {e}")))?;
        let model = SvmModel::from_json(&text).map_err(|e| ModelError(format!("'{path}': {e}")))?;
        Ok(ModelChoice::custom(path, model))
    }

    /// The string form: `default`, or the custom model's label.
    pub fn label(&self) -> &str {
        match self {
            ModelChoice::Shipped => "default",
            ModelChoice::Custom { label, .. } => label,
        }
    }
}

boundary_core::declare_params! {
    /// The parameters of `svm` (string form: the `--set` keys of the same names, see
    /// `boundary::registry`).
    #[derive(Debug, Clone, PartialEq)]
    pub struct SvmParams for "svm" {
        /// The cascade's second stage; default [`Refine::None`].
        pub refine: Refine = Refine::None, check::any("must be none, exact or ge"),
            "none, exact or ge: re-test the particles the SVM calls boundary (the cascade of \
             thesis Sec. 3.4)";
        /// The model; default [`ModelChoice::Shipped`].
        pub model: ModelChoice = ModelChoice::Shipped,
            check::any("must be default or the path of a model file"),
            "default (the shipped model of the set's dimension, trained by `cargo xtask \
             train-svm`) or the path of a model file (JSON)";
    }
}

/// The text form of `refine`: its name.
impl ParamValue for Refine {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        match text.trim() {
            "none" => Ok(Refine::None),
            "exact" => Ok(Refine::Exact),
            "ge" => Ok(Refine::Ge),
            _ => Err(None),
        }
    }
    fn to_text(&self) -> String {
        self.name().to_owned()
    }
}

/// The text form of `model`: `default`, or the path of a model file, read (and validated)
/// when the text is parsed; the error names the file.
impl ParamValue for ModelChoice {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        match text.trim() {
            "default" => Ok(ModelChoice::Shipped),
            path => ModelChoice::from_file(path).map_err(|e| Some(e.0)),
        }
    }
    fn to_text(&self) -> String {
        self.label().to_owned()
    }
}

/// The SVM detector (`svm`). See the crate documentation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SvmDetector {
    params: SvmParams,
}

impl SvmDetector {
    /// The detector with `params`, checked: a [`ModelChoice::Custom`] model must pass
    /// [`SvmModel::validate`] (else [`ParamError::Invalid`] naming `model` and its label).
    pub fn try_new(params: SvmParams) -> Result<Self, ParamError> {
        params.check()?;
        if let ModelChoice::Custom { label, model } = &params.model {
            model.validate().map_err(|e| {
                ParamError::invalid(METHOD, "model", label, format!("'{label}': {e}"))
            })?;
        }
        Ok(SvmDetector { params })
    }

    /// The parameters.
    pub fn params(&self) -> &SvmParams {
        &self.params
    }

    /// The model used for `D`-dimensional sets.
    fn model_for(&self, dim: usize) -> Result<&SvmModel, DetectError> {
        let fail = |message: String| DetectError::Method {
            method: METHOD,
            message,
        };
        match &self.params.model {
            ModelChoice::Custom { model, .. } if model.dim == dim => Ok(model),
            ModelChoice::Custom { label, model } => Err(fail(format!(
                "model '{label}' is for {}D particle sets, this set is {dim}D",
                model.dim
            ))),
            ModelChoice::Shipped => shipped_model(dim).map_err(|e| fail(e.0)),
        }
    }

    /// The decision values of the first `count` particles: the SVM's, except that a particle
    /// certified boundary (at most `D` distinct neighbours within `2r`, or a sampled point of
    /// its sphere uncovered) gets 0 without evaluating the SVM, and a particle at a near tie
    /// (a sampled point within rounding of being uncovered, [`ParticleFeatures::near_tie`])
    /// is decided by `exact`: 0 if boundary, `−f64::MIN_POSITIVE` if interior.
    fn decisions<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        count: usize,
        r: Radius,
    ) -> Result<Vec<f64>, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        let model = self.model_for(D)?.packed();
        // Each particle's decision right after its features (the features are not kept).
        let decided = map_particle_features(set, count, r, |p| {
            let decision = if p.certified_boundary(D) {
                0.0
            } else {
                model.decision(&p.features)
            };
            (decision, p.near_tie(D))
        })?;
        let (mut decisions, near): (Vec<f64>, Vec<bool>) = decided.into_iter().unzip();
        if near.contains(&true) {
            let exact = refine_candidates(&ExactDetector::default(), set, &near, r)?;
            for (i, d) in decisions.iter_mut().enumerate() {
                if near[i] {
                    *d = if exact[i] { 0.0 } else { -f64::MIN_POSITIVE };
                }
            }
        }
        Ok(decisions)
    }

    fn detect_first<const D: usize>(
        &self,
        set: &ParticleSet<D>,
        count: usize,
        r: Radius,
    ) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        let decisions = self.decisions(set, count, r)?;
        let labels: Vec<bool> = decisions.iter().map(|&d| d >= 0.0).collect();
        let refined = match self.params.refine {
            Refine::None => {
                return Ok(Detection {
                    labels: Labels::new(labels),
                    margin: Some(decisions),
                })
            }
            Refine::Exact => refine_candidates(&ExactDetector::default(), set, &labels, r)?,
            Refine::Ge => refine_candidates(&GeDetector::default(), set, &labels, r)?,
        };
        // The refiner's margins and the SVM's decision values are in different units: the
        // cascade reports labels only.
        Ok(Detection {
            labels: Labels::new(refined),
            margin: None,
        })
    }
}

/// Re-tests the particles flagged in `candidates` (the first `candidates.len()` of `set`)
/// with `refiner`: the candidates go first in a reordered copy of the set, every other
/// particle follows as a ghost, and the refiner classifies the owned (candidate) part.
fn refine_candidates<const D: usize>(
    refiner: &dyn BoundaryDetector,
    set: &ParticleSet<D>,
    candidates: &[bool],
    r: Radius,
) -> Result<Vec<bool>, DetectError>
where
    Dim<D>: SupportedDim,
{
    let positions = set.positions();
    let mut order: Vec<usize> = (0..candidates.len()).filter(|&i| candidates[i]).collect();
    let owned = order.len();
    if owned == 0 {
        return Ok(candidates.to_vec());
    }
    order.extend((0..positions.len()).filter(|&i| i >= candidates.len() || !candidates[i]));
    let reordered = ParticleSet::new(order.iter().map(|&i| positions[i]).collect())?;
    let detection = Job {
        set: &reordered,
        owned,
        solids: &Solids::new(),
        r,
    }
    .run_on(refiner)?;
    let mut labels = vec![false; candidates.len()];
    for (k, &i) in order[..owned].iter().enumerate() {
        labels[i] = detection.labels.is_boundary(k);
    }
    Ok(labels)
}

// `Display`: the label `name (key=value, …)`, as the CLI and the sweep print it.
boundary_core::impl_display_as_label!(SvmDetector);
// The registry builds it from `key=value` text through its declared parameters.
boundary_core::impl_configurable!(SvmDetector, SvmParams);

impl Method for SvmDetector {
    const NAME: &'static str = METHOD;

    fn describe(&self) -> Params {
        self.params.listing()
    }

    /// A uniform radius only; no solid; a halo of one kernel support (`2r`, plus `1e-9`
    /// relative, [`features::feature_reach`]): the features look no further.
    fn capabilities(&self) -> Capabilities {
        Capabilities {
            radii: Support::Refused(NO_RADII),
            half_spaces: Support::Refused(SOLID_REFUSAL),
            halo_over_r: features::REACH_OVER_R,
            ..Capabilities::DEFAULT
        }
    }

    /// Classifies only the owned particles; the ghosts serve as neighbours and for volumes.
    fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        self.detect_first(job.set, job.owned, job.r)
    }
}

/// Why `svm` refuses solid half-spaces.
const SOLID_REFUSAL: &str = "its features are sums over neighbour particles and its models were trained without solids; give the walls as wall particles, which enter the features";
