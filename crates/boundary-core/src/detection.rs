use crate::domain::DomainError;
use crate::CoreError;
use std::fmt;
use thiserror::Error;

/// Per-particle classification, in input order: `true` means boundary.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Labels {
    boundary: Vec<bool>,
}

impl Labels {
    /// Wraps a vector of flags (`true` = boundary).
    pub fn new(boundary: Vec<bool>) -> Self {
        Labels { boundary }
    }

    /// The flags, in input order.
    pub fn as_slice(&self) -> &[bool] {
        &self.boundary
    }

    /// Whether particle `i` is boundary.
    pub fn is_boundary(&self, i: usize) -> bool {
        self.boundary[i]
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.boundary.len()
    }

    /// Whether there is no particle.
    pub fn is_empty(&self) -> bool {
        self.boundary.is_empty()
    }

    /// Number of boundary particles.
    pub fn boundary_count(&self) -> usize {
        self.boundary.iter().filter(|&&b| b).count()
    }

    /// Consumes the labels, returning the flags.
    pub fn into_vec(self) -> Vec<bool> {
        self.boundary
    }

    /// A 64-bit FNV-1a hash of the label vector (length included), for snapshot tests.
    pub fn fingerprint(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |byte: u8| {
            h ^= u64::from(byte);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        };
        for byte in (self.boundary.len() as u64).to_le_bytes() {
            eat(byte);
        }
        for &b in &self.boundary {
            eat(u8::from(b));
        }
        h
    }
}

impl FromIterator<bool> for Labels {
    fn from_iter<I: IntoIterator<Item = bool>>(iter: I) -> Self {
        Labels::new(iter.into_iter().collect())
    }
}

/// What a detector returns: labels, and optionally a per-particle margin.
///
/// The margin is method-defined but always oriented the same way: positive leans boundary,
/// negative leans interior, and values near zero are near-ties. For `exact` it is the distance
/// (in units of length) by which the particle's Voronoi cell reaches beyond `r`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Detection {
    /// One label per particle, in input order.
    pub labels: Labels,
    /// Optional per-particle margin or score, in input order.
    pub margin: Option<Vec<f64>>,
}

/// Description of one detector parameter, with its current value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamInfo {
    /// The key of the string form (`--set KEY=VALUE` on the command line, the `params` of
    /// the bindings, `boundary::registry`); each method's typed parameter struct documents
    /// its fields.
    pub name: &'static str,
    /// The current value, formatted so that the string form accepts it back.
    pub value: String,
    /// The default value.
    pub default: String,
    /// One line saying what it does, with the paper's reference.
    pub description: &'static str,
}

/// A detector's parameter list; `Display` prints `key=value, key=value`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Params(pub Vec<ParamInfo>);

impl fmt::Display for Params {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, p) in self.0.iter().enumerate() {
            if k > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{}={}", p.name, p.value)?;
        }
        Ok(())
    }
}

/// A rejected parameter: a typed parameter struct that a detector's `try_new` refuses, or a
/// `key=value` pair the registry cannot apply.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ParamError {
    /// The detector has no parameter of that name.
    #[error("method '{method}' has no parameter '{key}' (parameters: {known})")]
    Unknown {
        /// Method name.
        method: &'static str,
        /// The key given.
        key: String,
        /// The keys the method knows, comma-separated (or "none").
        known: String,
    },
    /// The value does not parse or is out of range. `key` is the parameter's key (its
    /// field name in the typed struct, or its `--set` key where they differ, as documented).
    #[error("method '{method}': invalid value '{value}' for '{key}': {reason}")]
    Invalid {
        /// Method name.
        method: &'static str,
        /// The key given.
        key: String,
        /// The value given.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
}

impl ParamError {
    /// The error for an unknown key, listing the known ones.
    pub fn unknown(method: &'static str, key: &str, known: &[&str]) -> Self {
        ParamError::Unknown {
            method,
            key: key.to_owned(),
            known: if known.is_empty() {
                "none".to_owned()
            } else {
                known.join(", ")
            },
        }
    }

    /// The error for a value that is not acceptable.
    pub fn invalid(
        method: &'static str,
        key: &str,
        value: &str,
        reason: impl Into<String>,
    ) -> Self {
        ParamError::Invalid {
            method,
            key: key.to_owned(),
            value: value.to_owned(),
            reason: reason.into(),
        }
    }
}

/// Why a detection could not run.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum DetectError {
    /// Invalid core input (radius, grid).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The method does not support this dimension.
    #[error("method '{method}' does not support {dim}D particle sets")]
    UnsupportedDimension {
        /// Method name.
        method: &'static str,
        /// The dimension asked for.
        dim: usize,
    },
    /// The method does not support per-particle radii (see [`crate::ParticleSet::with_radii`]).
    #[error(
        "method '{method}' does not support per-particle radii: {reason}; use exact, dilts, \
         ia or ge, or a uniform radius"
    )]
    PerParticleRadii {
        /// Method name.
        method: &'static str,
        /// Why the method has no faithful generalisation.
        reason: &'static str,
    },
    /// The method cannot honour an option of the domain (a solid region, say); it never
    /// ignores one silently.
    #[error("method '{method}' cannot honour {option}: {reason}")]
    UnsupportedOption {
        /// Method name.
        method: &'static str,
        /// The option, in library terms (`solid half-spaces`, `solid meshes`); the CLI and the
        /// bindings name it in their own spelling.
        option: &'static str,
        /// Why, in the method's terms.
        reason: &'static str,
    },
    /// The domain does not fit the particle set (dimension, phases, periodic range, …).
    #[error(transparent)]
    Domain(#[from] DomainError),
    /// A method-specific failure, described.
    #[error("method '{method}': {message}")]
    Method {
        /// Method name.
        method: &'static str,
        /// What went wrong.
        message: String,
    },
    /// The detection was stopped through its [`StopToken`](crate::stop::StopToken) before it
    /// finished; no labels.
    #[error("interrupted: the detection was stopped before it finished")]
    Interrupted,
}

impl DetectError {
    /// `Ok` for a set without per-particle radii (`radii` is the set's
    /// [`crate::ParticleSet::radii`]), else [`DetectError::PerParticleRadii`]: for a method's
    /// own entry points beside the face (which checks [`crate::Capabilities::radii`] itself).
    pub fn check_uniform(
        method: &'static str,
        reason: &'static str,
        radii: Option<&[f64]>,
    ) -> Result<(), Self> {
        match radii {
            None => Ok(()),
            Some(_) => Err(DetectError::PerParticleRadii { method, reason }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_count_boundaries_and_fingerprints_tell_vectors_apart() {
        let a = Labels::new(vec![true, false, true]);
        assert_eq!(a.boundary_count(), 2);
        assert!(a.is_boundary(0) && !a.is_boundary(1));
        let b = Labels::new(vec![true, true, false]);
        assert_ne!(a.fingerprint(), b.fingerprint());
        // The length is part of the hash: an empty vector and [false] differ.
        assert_ne!(
            Labels::new(vec![]).fingerprint(),
            Labels::new(vec![false]).fingerprint()
        );
        assert_eq!(a.fingerprint(), a.clone().fingerprint());
    }

    #[test]
    fn params_display_is_key_value_list() {
        let p = Params(vec![
            ParamInfo {
                name: "depth",
                value: "6".into(),
                default: "6".into(),
                description: "",
            },
            ParamInfo {
                name: "gamma",
                value: "1.3".into(),
                default: "1.3".into(),
                description: "",
            },
        ]);
        assert_eq!(p.to_string(), "depth=6, gamma=1.3");
        assert_eq!(Params::default().to_string(), "");
    }

    #[test]
    fn param_error_lists_known_keys() {
        let e = ParamError::unknown("ia", "dept", &["depth"]);
        assert_eq!(
            e.to_string(),
            "method 'ia' has no parameter 'dept' (parameters: depth)"
        );
        let e = ParamError::unknown("exact", "x", &[]);
        assert!(e.to_string().ends_with("(parameters: none)"));
    }
}
