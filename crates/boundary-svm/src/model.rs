//! The serialised SVM model and its evaluation (polynomial or RBF kernel).
//!
//! A model is plain data: the standardisation of the features (`z = (f − mean) / scale`),
//! the support vectors (standardised), their signed dual coefficients `α_k y_k`, the bias and
//! the kernel: RBF of width `γ` or polynomial of degree `p` (LIBSVM's conventions). The
//! decision value of a feature vector is
//!
//! `d(f) = Σ_k coef_k · K(z, s_k) + bias`, with `K(z, s) = exp(−γ |z − s|²)` (RBF) or
//! `K(z, s) = (γ z·s + coef0)^p` (polynomial, `p` = 1, 2 or 3).
//!
//! **Evaluation cost.** An RBF model costs one exponential and one distance per support
//! vector. A polynomial model costs nothing per support vector: expanding the power,
//! `Σ_k coef_k (γ z·s_k + c)^p` is a polynomial of degree `p` in `z` whose monomial weights
//! (`Σ_k coef_k s_k ⊗ … ⊗ s_k`, a vector, a matrix and a 3-tensor) [`SvmModel::packed`]
//! computes once; a decision is then at most `7 + 7² + 7³` multiply-adds, whatever the
//! number of support vectors (the explicit feature map of a low-degree kernel).
//!
//! and the particle is boundary iff `d(f) >= 0` (a tie counts as boundary, the safe side of a
//! filter whose misses cannot be recovered by the cascade). This is the decision function of
//! a C-SVC with the kernel `K` above in LIBSVM's convention; the shipped models are trained with
//! `linfa-svm` (`cargo xtask train-svm`) and exported into this form, so inference needs no
//! machine-learning crate.
//!
//! The file format is JSON (`serde_json`): small (a few hundred support vectors), diffable and
//! read back exactly (`f64` values round-trip through their shortest decimal form).

use crate::features::{Features, FEATURE_VERSION, N_FEATURES};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The value of [`SvmModel::format`].
pub const MODEL_FORMAT: &str = "boundary-svm model";

/// The kernel of a model (JSON: `"rbf"` or `"polynomial"`; absent means RBF).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kernel {
    /// `exp(−γ |z − s|²)`.
    #[default]
    Rbf,
    /// `(γ z·s + coef0)^degree`.
    Polynomial,
}

/// The largest polynomial degree a model may have (the packed evaluation expands it).
pub const MAX_DEGREE: u32 = 3;

/// A trained SVM (RBF or polynomial kernel) over the particle features. See the module
/// documentation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SvmModel {
    /// Always [`MODEL_FORMAT`]: tells a model file from any other JSON.
    pub format: String,
    /// The [`FEATURE_VERSION`] the model was trained on.
    pub feature_version: u32,
    /// Dimension of the particle sets it classifies (2 or 3).
    pub dim: usize,
    /// The kernel.
    #[serde(default)]
    pub kernel: Kernel,
    /// RBF width `γ` in `exp(−γ |z − s|²)`, or the scale `γ` in `(γ z·s + coef0)^degree`,
    /// in standardised feature units.
    pub gamma: f64,
    /// Polynomial kernel: its degree (1 to [`MAX_DEGREE`]); unused by RBF.
    #[serde(default)]
    pub degree: u32,
    /// Polynomial kernel: its constant; unused by RBF.
    #[serde(default)]
    pub coef0: f64,
    /// The soft-margin constant `C` it was trained with (informative).
    pub c: f64,
    /// Added to the kernel sum (LIBSVM's `−ρ`).
    pub bias: f64,
    /// Feature means subtracted before scaling.
    pub feature_mean: Features,
    /// Feature standard deviations (positive) divided out.
    pub feature_scale: Features,
    /// Standardised support vectors.
    pub support_vectors: Vec<Features>,
    /// Signed dual coefficients `α_k y_k`, one per support vector (boundary = `+1`).
    pub coefficients: Vec<f64>,
    /// How the model was made (scenes, sample sizes, seed, validation scores).
    pub provenance: String,
}

/// Why a model was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelError(pub String);

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ModelError {}

impl SvmModel {
    /// Parses and validates a model from its JSON text.
    pub fn from_json(text: &str) -> Result<Self, ModelError> {
        let model: SvmModel =
            serde_json::from_str(text).map_err(|e| ModelError(format!("not a model: {e}")))?;
        model.validate()?;
        Ok(model)
    }

    /// The JSON text of the model: compact, with one support vector per line so that a
    /// retrained model diffs line by line.
    pub fn to_json(&self) -> String {
        // Serialising plain structs of numbers and strings cannot fail. The rows are spliced
        // in where the empty list stands: `"support_vectors":[]` cannot occur inside a JSON
        // string, whose quotes are escaped.
        let mut head = self.clone();
        head.support_vectors = vec![];
        let head = serde_json::to_string(&head).unwrap_or_default();
        let rows: Vec<String> = self
            .support_vectors
            .iter()
            .map(|row| serde_json::to_string(row).unwrap_or_default())
            .collect();
        head.replacen(
            "\"support_vectors\":[]",
            &format!("\"support_vectors\":[\n{}\n]", rows.join(",\n")),
            1,
        )
    }

    /// Checks the invariants the evaluation relies on.
    pub fn validate(&self) -> Result<(), ModelError> {
        let fail = |m: String| Err(ModelError(m));
        if self.format != MODEL_FORMAT {
            return fail(format!(
                "format is '{}', expected '{MODEL_FORMAT}'",
                self.format
            ));
        }
        if self.feature_version != FEATURE_VERSION {
            return fail(format!(
                "trained on feature version {}, this build computes version {FEATURE_VERSION}",
                self.feature_version
            ));
        }
        if self.dim != 2 && self.dim != 3 {
            return fail(format!("dimension {} (expected 2 or 3)", self.dim));
        }
        if !(self.gamma.is_finite() && self.gamma > 0.0) {
            return fail(format!("gamma {} is not positive and finite", self.gamma));
        }
        if self.kernel == Kernel::Polynomial {
            if !(1..=MAX_DEGREE).contains(&self.degree) {
                return fail(format!(
                    "polynomial degree {} (expected 1 to {MAX_DEGREE})",
                    self.degree
                ));
            }
            if !self.coef0.is_finite() {
                return fail("coef0 is not finite".into());
            }
        }
        if !self.bias.is_finite() {
            return fail("bias is not finite".into());
        }
        if self.feature_mean.iter().any(|m| !m.is_finite())
            || self
                .feature_scale
                .iter()
                .any(|s| !(s.is_finite() && *s > 0.0))
        {
            return fail("feature means must be finite and scales positive and finite".into());
        }
        if self.support_vectors.len() != self.coefficients.len() {
            return fail(format!(
                "{} support vectors but {} coefficients",
                self.support_vectors.len(),
                self.coefficients.len()
            ));
        }
        if let Some(k) = self
            .support_vectors
            .iter()
            .zip(&self.coefficients)
            .position(|(s, c)| !c.is_finite() || s.iter().any(|x| !x.is_finite()))
        {
            return fail(format!("support vector {k} is not finite"));
        }
        Ok(())
    }

    /// `(f − mean) / scale`.
    pub fn standardise(&self, f: &Features) -> Features {
        std::array::from_fn(|k| (f[k] - self.feature_mean[k]) / self.feature_scale[k])
    }

    /// The decision value `d(f)`; boundary iff `>= 0`. The sum runs over the support vectors
    /// in stored order, so the value does not depend on threads. Evaluating many particles,
    /// [`SvmModel::packed`] once and [`PackedModel::decision`] per particle is faster and
    /// gives the same value.
    pub fn decision(&self, f: &Features) -> f64 {
        self.packed().decision(f)
    }

    /// The model laid out for fast evaluation.
    pub fn packed(&self) -> PackedModel {
        let kind = match self.kernel {
            Kernel::Rbf => Packed::Rbf {
                support_vectors: self
                    .support_vectors
                    .iter()
                    .map(|s| std::array::from_fn(|k| if k < N_FEATURES { s[k] } else { 0.0 }))
                    .collect(),
                coefficients: self.coefficients.clone(),
                neg_gamma: -self.gamma,
            },
            Kernel::Polynomial => Packed::Polynomial(Box::new(self.monomials())),
        };
        PackedModel {
            mean: self.feature_mean,
            scale: self.feature_scale,
            kind,
            bias: self.bias,
        }
    }

    /// The polynomial kernel's decision function as weights of the monomials of `z`:
    /// `(γ z·s + c)^p = Σ_m C(p, m) c^(p−m) γ^m (z·s)^m`, and `Σ_k coef_k (z·s_k)^m` is the
    /// contraction of `z ⊗ … ⊗ z` with `Σ_k coef_k s_k ⊗ … ⊗ s_k`.
    fn monomials(&self) -> Monomials {
        let p = self.degree.min(MAX_DEGREE);
        let (g, c) = (self.gamma, self.coef0);
        // Weight of the degree-m part: C(p, m) c^(p−m) γ^m (zero above p).
        let weight = |m: u32| -> f64 {
            if m > p {
                return 0.0;
            }
            let binomial = (0..m).fold(1.0, |b, t| b * f64::from(p - t) / f64::from(t + 1));
            binomial * c.powi((p - m) as i32) * g.powi(m as i32)
        };
        let (w0, w1, w2, w3) = (weight(0), weight(1), weight(2), weight(3));
        let mut out = Monomials {
            constant: 0.0,
            linear: [0.0; N_FEATURES],
            quadratic: [[0.0; N_FEATURES]; N_FEATURES],
            cubic: [[[0.0; LANES]; N_FEATURES]; N_FEATURES],
        };
        for (s, &a) in self.support_vectors.iter().zip(&self.coefficients) {
            out.constant += a * w0;
            for i in 0..N_FEATURES {
                out.linear[i] += a * w1 * s[i];
                for j in 0..N_FEATURES {
                    out.quadratic[i][j] += a * w2 * s[i] * s[j];
                    for k in 0..N_FEATURES {
                        out.cubic[i][k][j] += a * w3 * s[i] * s[j] * s[k];
                    }
                }
            }
        }
        out
    }
}

/// Lanes of a packed support vector: the features padded with zeros to a multiple of 4, so
/// that the distance loop vectorises.
const LANES: usize = N_FEATURES.div_ceil(4) * 4;

/// A polynomial model's decision function, `constant + Σ linear_i z_i + Σ quadratic_ij z_i
/// z_j + Σ cubic_ijk z_i z_j z_k` (the bias apart).
#[derive(Debug, Clone, PartialEq)]
struct Monomials {
    constant: f64,
    linear: [f64; N_FEATURES],
    quadratic: [[f64; N_FEATURES]; N_FEATURES],
    /// `cubic[i][k][j]` is the weight of `z_i z_j z_k` (`j` last, padded to [`LANES`] with
    /// zeros: [`PackedModel::decision`] takes the sums over `k` for every `j` at once).
    cubic: [[[f64; LANES]; N_FEATURES]; N_FEATURES],
}

#[derive(Debug, Clone, PartialEq)]
enum Packed {
    Rbf {
        support_vectors: Vec<[f64; LANES]>,
        coefficients: Vec<f64>,
        neg_gamma: f64,
    },
    Polynomial(Box<Monomials>),
}

/// An [`SvmModel`] laid out for evaluation: for RBF, padded support vectors and the
/// kernel's exponential by [`exp_nonpositive`]; for a polynomial kernel, the weights of the
/// monomials of the standardised features (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct PackedModel {
    mean: Features,
    scale: Features,
    kind: Packed,
    bias: f64,
}

impl PackedModel {
    /// The decision value `d(f)` (see [`SvmModel::decision`]).
    pub fn decision(&self, f: &Features) -> f64 {
        let z: [f64; LANES] = std::array::from_fn(|k| {
            if k < N_FEATURES {
                (f[k] - self.mean[k]) / self.scale[k]
            } else {
                0.0
            }
        });
        match &self.kind {
            Packed::Rbf {
                support_vectors,
                coefficients,
                neg_gamma,
            } => rbf_sum(self.bias, &z, support_vectors, coefficients, *neg_gamma),
            Packed::Polynomial(m) => {
                // Horner over the degrees: z_i (linear_i + z_j (quadratic_ij + z_k cubic_ijk)).
                // The sums over k, one per j, run side by side (one vector lane per j), each
                // in k order from the start value of `Iterator::sum`: the same values as one
                // sum after the other, without their chains of dependent additions.
                let start: f64 = std::iter::empty::<f64>().sum();
                let mut sum = 0.0;
                for ((zi, linear), (quadratic, cubic)) in z
                    .iter()
                    .zip(&m.linear)
                    .zip(m.quadratic.iter().zip(&m.cubic))
                {
                    let mut over_k = [start; LANES];
                    for (row, zk) in cubic.iter().zip(&z) {
                        for (acc, c) in over_k.iter_mut().zip(row) {
                            *acc += c * zk;
                        }
                    }
                    let mut inner_i = *linear;
                    for ((zj, q), over_k) in z.iter().zip(quadratic).zip(&over_k) {
                        let inner_j = q + over_k;
                        inner_i += inner_j * zj;
                    }
                    sum += inner_i * zi;
                }
                self.bias + m.constant + sum
            }
        }
    }
}

/// `bias + Σ_k coef_k exp(neg_gamma |z − s_k|²)`, summed in stored order from the bias.
fn rbf_sum(
    bias: f64,
    z: &[f64; LANES],
    support_vectors: &[[f64; LANES]],
    coefficients: &[f64],
    neg_gamma: f64,
) -> f64 {
    const CHUNK: usize = 8;
    let mut sum = bias;
    let mut arg = [0.0; CHUNK];
    for (svs, coefs) in support_vectors
        .chunks(CHUNK)
        .zip(coefficients.chunks(CHUNK))
    {
        for (a, s) in arg.iter_mut().zip(svs) {
            let mut d2 = 0.0;
            for k in 0..LANES {
                let t = z[k] - s[k];
                d2 += t * t;
            }
            *a = neg_gamma * d2;
        }
        for (a, c) in arg.iter().zip(coefs) {
            sum += c * exp_nonpositive(*a);
        }
    }
    sum
}

/// `e^x` for `x <= 0` (and `x` not NaN), within 2 ulps of the true value: `x = k ln 2 + t`
/// with `|t| <= ln 2 / 2`, `e^t` by its Taylor polynomial of degree 12 (truncation error
/// below `2^-60`), scaled by `2^k`; arguments below −700 are evaluated at −700 (`e^-700 < 1e-304`, far
/// under the rounding of any kernel sum). Branch-free, so the kernel loop vectorises;
/// about three times faster than the library `exp` here, and the kernel's exponential is
/// most of a prediction's cost.
#[inline]
pub fn exp_nonpositive(x: f64) -> f64 {
    const LN2_HI: f64 = 6.931_471_803_691_238e-1;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    // 1.5 · 2^52: adding it rounds to the nearest integer in the low mantissa bits.
    const SHIFTER: f64 = 6_755_399_441_055_744.0;
    let x = x.max(-700.0);
    let kf = (x * std::f64::consts::LOG2_E + SHIFTER) - SHIFTER;
    let t = (x - kf * LN2_HI) - kf * LN2_LO;
    // Horner form of Σ_{n<=12} t^n / n!.
    let mut p = 1.0 / 479_001_600.0;
    p = p * t + 1.0 / 39_916_800.0;
    p = p * t + 1.0 / 3_628_800.0;
    p = p * t + 1.0 / 362_880.0;
    p = p * t + 1.0 / 40_320.0;
    p = p * t + 1.0 / 5_040.0;
    p = p * t + 1.0 / 720.0;
    p = p * t + 1.0 / 120.0;
    p = p * t + 1.0 / 24.0;
    p = p * t + 1.0 / 6.0;
    p = p * t + 0.5;
    p = p * t + 1.0;
    p = p * t + 1.0;
    // k in [-1010, 0]: 2^k is a normal number or, below -1022, handled by two factors.
    let k = kf as i64;
    let half = k / 2;
    let scale_a = f64::from_bits(((half + 1023) as u64) << 52);
    let scale_b = f64::from_bits(((k - half + 1023) as u64) << 52);
    p * scale_a * scale_b
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    fn tiny() -> SvmModel {
        SvmModel {
            format: MODEL_FORMAT.into(),
            feature_version: FEATURE_VERSION,
            dim: 2,
            kernel: Kernel::Rbf,
            degree: 0,
            coef0: 0.0,
            gamma: 0.5,
            c: 1.0,
            bias: -0.25,
            feature_mean: [1.0; N_FEATURES],
            feature_scale: [2.0; N_FEATURES],
            support_vectors: vec![[0.0; N_FEATURES], [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]],
            coefficients: vec![1.0, -0.5],
            provenance: "unit test".into(),
        }
    }

    #[test]
    fn decision_matches_the_formula() {
        let m = tiny();
        // f = mean gives z = 0: d = 1·e^0 − 0.5·e^{−0.5} − 0.25.
        let d = m.decision(&[1.0; N_FEATURES]);
        assert!((d - (0.75 - 0.5 * (-0.5f64).exp())).abs() < 1e-15);
    }

    /// The expanded polynomial decision against the kernel sum written out, for each degree,
    /// on a model of three support vectors and a few feature vectors.
    #[test]
    fn polynomial_expansion_matches_the_kernel_sum() {
        let mut m = tiny();
        m.kernel = Kernel::Polynomial;
        m.gamma = 0.7;
        m.coef0 = 1.3;
        m.support_vectors = vec![
            [0.5, -1.0, 0.25, 2.0, -0.5, 1.5, -2.0],
            [-1.5, 0.75, 1.0, -0.25, 0.5, 0.0, 1.0],
            [0.1, 0.2, -0.3, 0.4, -0.5, 0.6, -0.7],
        ];
        m.coefficients = vec![0.8, -1.1, 0.45];
        for degree in 1..=MAX_DEGREE {
            m.degree = degree;
            m.validate().unwrap();
            for f in [
                [1.0; N_FEATURES],
                [3.0, -1.0, 0.5, 7.0, 2.0, -4.0, 0.25],
                [-2.0, 5.0, 1.5, 0.0, -3.0, 1.0, 2.5],
            ] {
                let z = m.standardise(&f);
                let direct = m.bias
                    + m.support_vectors
                        .iter()
                        .zip(&m.coefficients)
                        .map(|(s, a)| {
                            let dot: f64 = s.iter().zip(&z).map(|(s, z)| s * z).sum();
                            a * (m.gamma * dot + m.coef0).powi(degree as i32)
                        })
                        .sum::<f64>();
                let packed = m.decision(&f);
                assert!(
                    (packed - direct).abs() <= 1e-12 * (1.0 + direct.abs()),
                    "degree {degree}: {packed} vs {direct}"
                );
            }
        }
        m.degree = MAX_DEGREE + 1;
        assert!(m.validate().unwrap_err().0.contains("polynomial degree"));
    }

    /// The fast exponential against the library's, over the whole range it serves.
    #[test]
    fn exp_nonpositive_is_within_two_ulps() {
        let mut worst: f64 = 0.0;
        for k in 0..=200_000 {
            let x = -(k as f64) * 700.0 / 200_000.0;
            let (ours, lib) = (exp_nonpositive(x), x.exp());
            worst = worst.max((ours - lib).abs() / lib);
        }
        for x in [
            0.0,
            -1e-300,
            -1e-17,
            -0.5 * std::f64::consts::LN_2,
            -745.0,
            -1e6,
        ] {
            let lib = x.exp();
            let ours = exp_nonpositive(x);
            assert!(
                (ours - lib).abs() <= 4.5e-16 * lib || (x < -700.0 && ours < 1e-303),
                "x={x}: {ours} vs {lib}"
            );
        }
        assert!(worst <= 4.5e-16, "relative error {worst:e}");
        assert_eq!(exp_nonpositive(0.0), 1.0);
    }

    #[test]
    fn json_round_trip_is_exact() {
        let mut m = tiny();
        m.support_vectors[1][3] = 0.1 + 0.2;
        m.bias = -1.0 / 3.0;
        let text = m.to_json();
        assert_eq!(text.lines().count(), 4, "{text}");
        assert_eq!(SvmModel::from_json(&text).unwrap(), m);
        // The splice point cannot be faked from inside a string.
        m.provenance = "a \"support_vectors\":[] b ],[ c".into();
        assert_eq!(SvmModel::from_json(&m.to_json()).unwrap(), m);
    }

    #[test]
    fn invalid_models_are_refused_with_a_reason() {
        let mut m = tiny();
        m.coefficients.pop();
        assert!(m
            .validate()
            .unwrap_err()
            .0
            .contains("2 support vectors but 1"));
        let mut m = tiny();
        m.feature_scale[3] = 0.0;
        assert!(m.validate().is_err());
        let mut m = tiny();
        m.feature_version += 1;
        assert!(m.validate().unwrap_err().0.contains("feature version"));
        let mut m = tiny();
        m.support_vectors[1][2] = f64::NAN;
        assert!(m.validate().unwrap_err().0.contains("support vector 1"));
        assert!(SvmModel::from_json("{\"a\": 1}").is_err());
    }
}
