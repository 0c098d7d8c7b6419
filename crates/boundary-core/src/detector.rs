use crate::domain::{Domain, DomainDetection, DomainError, Solids};
use crate::{AnyParticleSet, CoreError, ParticleSet, Radius};
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
    /// The method does not support per-particle radii (see [`ParticleSet::with_radii`]).
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

/// The option a refusal of solid meshes names ([`DetectError::check_no_solid_meshes`]).
pub(crate) const SOLID_MESH_OPTION: &str = "solid meshes";

/// The reason of the default [`BoundaryDetector::solid_mesh_refusal`].
const SOLID_MESH_REFUSAL: &str = "the method has no rule for a solid given as a triangle mesh \
     covering part of a sphere; use exact, or give the solid as half-spaces or the walls as \
     wall particles where the method takes them";

impl DetectError {
    /// `Ok` when `solids` holds no mesh, else [`DetectError::UnsupportedOption`] naming the
    /// option `solid meshes` with `reason`: the first line of a
    /// [`BoundaryDetector::detect_owned_in`] that honours half-spaces but not meshes.
    pub fn check_no_solid_meshes(
        method: &'static str,
        solids: &Solids,
        reason: &'static str,
    ) -> Result<(), Self> {
        if solids.meshes().is_empty() {
            Ok(())
        } else {
            Err(DetectError::UnsupportedOption {
                method,
                option: SOLID_MESH_OPTION,
                reason,
            })
        }
    }

    /// `Ok` for a set without per-particle radii (`radii` is the set's
    /// [`ParticleSet::radii`] or [`AnyParticleSet::radii`]), else
    /// [`DetectError::PerParticleRadii`]: what a method that supports only a uniform radius
    /// calls first.
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

    /// `Ok` if `owned <= len`, else the error [`BoundaryDetector::detect_owned`] returns for
    /// more owned particles than the set holds.
    pub fn check_owned(method: &'static str, owned: usize, len: usize) -> Result<(), Self> {
        if owned > len {
            return Err(DetectError::Method {
                method,
                message: format!("{owned} owned particles in a set of {len}"),
            });
        }
        Ok(())
    }
}

/// A boundary-particle detection method.
///
/// Object safe, so that a registry can hold `Box<dyn BoundaryDetector>`. Implementations write
/// their algorithm once, generic over the dimension, and forward both `detect_2d` and
/// `detect_3d` to it. Parallelism uses rayon's current thread pool: callers choose the number
/// of threads with `rayon::ThreadPool::install`.
///
/// Contract: `detect_*` returns exactly one label per particle in input order, never panics on
/// a validated [`ParticleSet`] and [`Radius`], and is deterministic (labels do not depend on
/// the number of threads).
pub trait BoundaryDetector: Send + Sync + fmt::Debug {
    /// The method's name in the registry and on the command line (`exact`, `ia`, …).
    fn name(&self) -> &'static str;

    /// The parameters with their current values and defaults, as `key=value` text for
    /// reports and labels (read-only: a detector's parameters are set through its typed
    /// parameter struct, or by name through the facade's registry).
    fn params(&self) -> Params;

    /// Whether the method promises no false negatives (Rec = 1 against the exact labels).
    fn certified(&self) -> bool {
        false
    }

    /// Classifies a 2D particle set at resolution `r`.
    fn detect_2d(&self, set: &ParticleSet<2>, r: Radius) -> Result<Detection, DetectError>;

    /// Classifies a 3D particle set at resolution `r`.
    fn detect_3d(&self, set: &ParticleSet<3>, r: Radius) -> Result<Detection, DetectError>;

    /// How far from a particle the method looks: the labels of the particles owned by a
    /// subdomain equal the global ones when the subdomain holds every particle within this
    /// distance of an owned one (see [`crate::decompose`]). Default `2r`, the reach of the
    /// definition itself; methods that look farther (kernel supports, visibility) override it.
    fn halo_width(&self, r: Radius) -> f64 {
        2.0 * r.get()
    }

    /// Classifies only the first `owned` particles of `set`; the others are ghosts (a halo)
    /// that take part as neighbours. Returns `owned` labels (and margins). The default runs the
    /// whole set and keeps the owned part; methods may override it to skip the ghosts' work.
    fn detect_owned(
        &self,
        set: &AnyParticleSet,
        owned: usize,
        r: Radius,
    ) -> Result<Detection, DetectError> {
        DetectError::check_owned(self.name(), owned, set.len())?;
        let mut d = self.detect(set, r)?;
        let mut flags = d.labels.into_vec();
        flags.truncate(owned);
        d.labels = Labels::new(flags);
        if let Some(m) = d.margin.as_mut() {
            m.truncate(owned);
        }
        Ok(d)
    }

    /// Classifies the first `owned` particles of `set` (the others cover only, as in
    /// [`BoundaryDetector::detect_owned`]) where the closed solid regions `solids` cover too
    /// (see [`crate::domain`]). The default honours an empty `solids` and refuses any other
    /// with [`DetectError::UnsupportedOption`] (naming `solid meshes` when `solids` holds a
    /// mesh, `solid half-spaces` otherwise); methods that can count a
    /// solid as covering override it, and call [`DetectError::check_no_solid_meshes`] first
    /// unless they honour meshes too.
    fn detect_owned_in(
        &self,
        set: &AnyParticleSet,
        owned: usize,
        solids: &Solids,
        r: Radius,
    ) -> Result<Detection, DetectError> {
        DetectError::check_no_solid_meshes(self.name(), solids, self.solid_refusal())?;
        if !solids.is_empty() {
            return Err(DetectError::UnsupportedOption {
                method: self.name(),
                option: "solid half-spaces",
                reason: self.solid_refusal(),
            });
        }
        self.detect_owned(set, owned, r)
    }

    /// Whether [`BoundaryDetector::detect_owned_in`] honours solid meshes
    /// ([`crate::SolidMesh`]). Default `false`: [`BoundaryDetector::detect_in`] then refuses a
    /// domain with a mesh before classifying (with
    /// [`BoundaryDetector::solid_mesh_refusal`]), so that a method that honours half-spaces
    /// only never ignores a mesh. A method that honours meshes overrides it.
    fn honours_solid_meshes(&self) -> bool {
        false
    }

    /// Why the method refuses solid meshes, in its terms (see
    /// [`BoundaryDetector::honours_solid_meshes`]).
    fn solid_mesh_refusal(&self) -> &'static str {
        SOLID_MESH_REFUSAL
    }

    /// Why the default [`BoundaryDetector::detect_owned_in`] refuses solid regions, in the
    /// method's terms (a method that honours them overrides `detect_owned_in` instead).
    fn solid_refusal(&self) -> &'static str {
        "the method has no rule for a solid covering part of a sphere; give the walls as wall \
         particles instead"
    }

    /// Classifies `set` in a [`Domain`]: walls, solids, periodic axes and phases (see
    /// [`crate::domain`]). With [`Domain::new`] this is [`BoundaryDetector::detect`].
    fn detect_in(
        &self,
        set: &AnyParticleSet,
        domain: &Domain,
        r: Radius,
    ) -> Result<DomainDetection, DetectError> {
        crate::domain::detect_in(self, set, domain, r)
    }

    /// Classifies a set whose dimension is known at run time.
    ///
    /// Under a stopped [`StopToken`](crate::stop::StopToken) this is
    /// [`DetectError::Interrupted`], never the partial labels of a stopped loop.
    fn detect(&self, set: &AnyParticleSet, r: Radius) -> Result<Detection, DetectError> {
        let detection = match set {
            AnyParticleSet::D2(s) => self.detect_2d(s, r),
            AnyParticleSet::D3(s) => self.detect_3d(s, r),
        }?;
        crate::stop::check()?;
        Ok(detection)
    }
}

/// Writes a detector's label: its name, then its parameters in parentheses when it has any,
/// e.g. `ia (depth=6)` or `exact`. `Display` of every detector type and of
/// `dyn BoundaryDetector` prints this (see [`impl_display_as_label!`](crate::impl_display_as_label)).
pub fn write_label(detector: &dyn BoundaryDetector, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    let params = detector.params();
    if params.0.is_empty() {
        f.write_str(detector.name())
    } else {
        write!(f, "{} ({params})", detector.name())
    }
}

impl fmt::Display for dyn BoundaryDetector + '_ {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_label(self, f)
    }
}

/// Implements `Display` for a detector type as its label ([`write_label`]): `name (key=value,
/// …)`. Every detector crate invokes it once for its detector.
#[macro_export]
macro_rules! impl_display_as_label {
    ($detector:ty) => {
        impl ::std::fmt::Display for $detector {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                $crate::write_label(self, f)
            }
        }
    };
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

    /// A detector with one parameter, for the label test.
    #[derive(Debug)]
    struct Knob(u32);

    impl BoundaryDetector for Knob {
        fn name(&self) -> &'static str {
            "knob"
        }
        fn params(&self) -> Params {
            Params(if self.0 == 0 {
                Vec::new()
            } else {
                vec![ParamInfo {
                    name: "turns",
                    value: self.0.to_string(),
                    default: "1".into(),
                    description: "",
                }]
            })
        }
        fn detect_2d(&self, set: &ParticleSet<2>, _r: Radius) -> Result<Detection, DetectError> {
            Ok(Detection {
                labels: Labels::new(vec![true; set.len()]),
                margin: None,
            })
        }
        fn detect_3d(&self, set: &ParticleSet<3>, _r: Radius) -> Result<Detection, DetectError> {
            Ok(Detection {
                labels: Labels::new(vec![true; set.len()]),
                margin: None,
            })
        }
    }
    crate::impl_display_as_label!(Knob);

    #[test]
    fn a_detector_displays_as_its_name_and_parameters() {
        assert_eq!(Knob(3).to_string(), "knob (turns=3)");
        assert_eq!(Knob(0).to_string(), "knob");
        let boxed: Box<dyn BoundaryDetector> = Box::new(Knob(2));
        assert_eq!(boxed.to_string(), "knob (turns=2)");
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
