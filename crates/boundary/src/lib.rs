//! Boundary particles of meshfree particle sets (SPH, PBF, FLIP/APIC, MPS).
//!
//! Particle *i* at *p_i* with resolution *r* is **interior** iff its sphere *S_i* of radius *r*
//! is covered by the closed balls of radius *r* of the other particles within *2r*; otherwise
//! it is **boundary** (Sandim, Paiva & Figueiredo, J. Comput. Phys. 2020). Coincident
//! duplicates do not cover each other.
//!
//! This facade re-exports [`boundary_core`] (particle sets, the [`BoundaryDetector`] trait,
//! the neighbour grid, the metrics) and holds the **registry**: every method compiled in (one
//! cargo feature per method crate) can be created by its name, with parameters given as
//! `key=value` strings, exactly as on the command line (`boundary detect --method ge --set
//! depth=4`). Any method's labels widen to a narrow band with [`Labels::widen`] (the
//! command line's `--band K`: every particle within `K·r` of a boundary particle).
//!
//! # Example
//! ```
//! use boundary::{detector_with_params, methods, Confusion, ParticleSet, Radius};
//!
//! // A 6 x 6 square lattice of spacing 1 at r = 0.8: the 4 x 4 core is interior.
//! let rows: Vec<[f64; 2]> = (0..36).map(|k| [(k % 6) as f64, (k / 6) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap().to_any();
//! let r = Radius::new(0.8).unwrap();
//!
//! assert!(methods().contains(&"exact"));
//! let exact = boundary::detector_by_name("exact").unwrap().detect(&set, r).unwrap();
//! assert_eq!(exact.labels.boundary_count(), 36 - 16);
//!
//! let no_params: &[(&str, &str)] = &[];
//! let dilts = detector_with_params("dilts", no_params).unwrap();
//! let dilts = dilts.detect(&set, r).unwrap();
//! let score = Confusion::from_labels(dilts.labels.as_slice(), exact.labels.as_slice()).unwrap();
//! assert_eq!(score.recall(), 1.0);
//! ```

pub use boundary_core::*;

#[cfg(feature = "asymmetry")]
pub use boundary_asymmetry::AsymmetryDetector;
#[cfg(feature = "dilts")]
pub use boundary_dilts::DiltsDetector;
#[cfg(feature = "divr")]
pub use boundary_divr::DivrDetector;
#[cfg(feature = "exact")]
pub use boundary_exact::{ExactDetector, Tracker};
#[cfg(feature = "ge")]
pub use boundary_ge::GeDetector;
#[cfg(feature = "hpr")]
pub use boundary_hpr::HprDetector;
#[cfg(feature = "ia")]
pub use boundary_ia::IaDetector;
#[cfg(feature = "lnm")]
pub use boundary_lnm::LnmDetector;
#[cfg(feature = "marrone")]
pub use boundary_marrone::MarroneDetector;
#[cfg(feature = "muller")]
pub use boundary_muller::MullerDetector;
#[cfg(feature = "randles")]
pub use boundary_randles::RandlesDetector;
#[cfg(feature = "svm")]
pub use boundary_svm::SvmDetector;

use thiserror::Error;

/// Why the registry could not build a detector.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum RegistryError {
    /// No method of that name is compiled in.
    #[error("unknown method '{name}' (available: {available})")]
    UnknownMethod {
        /// The name asked for.
        name: String,
        /// The compiled-in methods, comma-separated.
        available: String,
    },
    /// A parameter was rejected by the method.
    #[error(transparent)]
    Param(#[from] ParamError),
}

/// A registry entry: name, one-line summary and constructor at default parameters.
struct Entry {
    name: &'static str,
    summary: &'static str,
    make: fn() -> Box<dyn BoundaryDetector>,
}

/// Every compiled-in method, in the order the reports list them (references first).
const REGISTRY: &[Entry] = &[
    #[cfg(feature = "exact")]
    Entry {
        name: "exact",
        summary: "restricted Voronoi cell of each particle reaches beyond r: the reference labels",
        make: || Box::new(ExactDetector),
    },
    #[cfg(feature = "dilts")]
    Entry {
        name: "dilts",
        summary:
            "explicit covering of S_i by arcs (2D, Dilts 2000) or caps (3D, Haque & Dilts 2007)",
        make: || Box::new(DiltsDetector),
    },
    #[cfg(feature = "ia")]
    Entry {
        name: "ia",
        summary: "interval-arithmetic quadtree/octree over S_i, rules R1-R4 (JCP 2020 Sec. 3.1)",
        make: || Box::new(IaDetector::default()),
    },
    #[cfg(feature = "ge")]
    Entry {
        name: "ge",
        summary: "geometric-enclosure slabs on a mesh of S_i, rules R1-R4 (JCP 2020 Sec. 3.2)",
        make: || Box::new(GeDetector::default()),
    },
    #[cfg(feature = "marrone")]
    Entry {
        name: "marrone",
        summary: "SPH renormalisation-matrix eigenvalue, then a scan cone along the normal \
                  (Marrone et al., JCP 2010)",
        make: || Box::new(MarroneDetector::default()),
    },
    #[cfg(feature = "muller")]
    Entry {
        name: "muller",
        summary:
            "SPH colour-field gradient |grad c| h above a threshold (Mueller et al., SCA 2003)",
        make: || Box::new(MullerDetector::default()),
    },
    #[cfg(feature = "divr")]
    Entry {
        name: "divr",
        summary: "SPH divergence of position below a threshold: DualSPHysics, SPHinXsys or \
                  Chrono::FSI's value by name (Lind et al., JCP 2012)",
        make: || Box::new(DivrDetector::default()),
    },
    #[cfg(feature = "asymmetry")]
    Entry {
        name: "asymmetry",
        summary: "distance to the kernel-weighted mean of the neighbourhood, or a low density \
                  (He et al., ACM TOG 2012)",
        make: || Box::new(AsymmetryDetector::default()),
    },
    #[cfg(feature = "randles")]
    Entry {
        name: "randles",
        summary: "smallest eigenvalue of the SPH renormalisation matrix at most mu \
                  (Randles-Doring; Marrone et al., JCP 2010, first step)",
        make: || Box::new(RandlesDetector::default()),
    },
    #[cfg(feature = "lnm")]
    Entry {
        name: "lnm",
        summary: "layered neighbourhood: voxel cells beside an empty cell, and beside a sparse \
                  one of those (Oliveira & Paiva, CGF 2022)",
        make: || Box::new(LnmDetector::default()),
    },
    #[cfg(feature = "hpr")]
    Entry {
        name: "hpr",
        summary: "visibility: hidden point removal with exponential flipping from grid and \
                  cavity viewpoints (Sandim 2020, ch. 2, Alg. 1)",
        make: || Box::new(HprDetector::default()),
    },
    #[cfg(feature = "svm")]
    Entry {
        name: "svm",
        summary:
            "support vector machine (polynomial kernel) on SPH features, trained on exact labels; \
                  refine=exact|ge re-tests its boundary particles (Sandim 2020, ch. 3)",
        make: || Box::new(SvmDetector::default()),
    },
];

/// The names of the compiled-in methods, references first.
pub fn methods() -> Vec<&'static str> {
    REGISTRY.iter().map(|e| e.name).collect()
}

/// The one-line summary of a method, if it is compiled in.
pub fn summary(name: &str) -> Option<&'static str> {
    REGISTRY.iter().find(|e| e.name == name).map(|e| e.summary)
}

/// The detector called `name`, at its default parameters.
pub fn detector_by_name(name: &str) -> Result<Box<dyn BoundaryDetector>, RegistryError> {
    REGISTRY
        .iter()
        .find(|e| e.name == name)
        .map(|e| (e.make)())
        .ok_or_else(|| RegistryError::UnknownMethod {
            name: name.to_owned(),
            available: methods().join(", "),
        })
}

/// The detector called `name` with `params` (`(key, value)` pairs, applied in order).
pub fn detector_with_params<K: AsRef<str>, V: AsRef<str>>(
    name: &str,
    params: &[(K, V)],
) -> Result<Box<dyn BoundaryDetector>, RegistryError> {
    let mut detector = detector_by_name(name)?;
    for (key, value) in params {
        detector.set_param(key.as_ref(), value.as_ref())?;
    }
    Ok(detector)
}

/// Splits a `key=value` command-line parameter; the error says what was expected.
pub fn parse_param(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((key, value)) if !key.trim().is_empty() => {
            Ok((key.trim().to_owned(), value.trim().to_owned()))
        }
        _ => Err(format!("expected KEY=VALUE, got '{text}'")),
    }
}

/// Splits a comma-separated parameter list `key=value,key=value` (the syntax of the C API's
/// `params` string; each item as [`parse_param`], i.e. as one `--set`). Empty items are
/// skipped, so `""` is no parameter. A value cannot contain a comma.
pub fn parse_param_list(text: &str) -> Result<Vec<(String, String)>, String> {
    text.split(',')
        .filter(|item| !item.trim().is_empty())
        .map(parse_param)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registered_name_builds_the_detector_of_that_name() {
        let names = methods();
        assert!(!names.is_empty());
        for name in names {
            let detector = detector_by_name(name).expect("registered");
            assert_eq!(detector.name(), name);
            assert!(summary(name).is_some());
            // The defaults reported by params() are accepted back by set_param.
            let params = detector.params();
            let pairs: Vec<(&str, &str)> = params
                .0
                .iter()
                .map(|p| (p.name, p.value.as_str()))
                .collect();
            let again = detector_with_params(name, &pairs).expect("defaults round-trip");
            assert_eq!(again.params(), params);
        }
    }

    #[test]
    fn unknown_names_and_parameters_are_errors_that_say_what_exists() {
        let Err(err) = detector_by_name("nope") else {
            panic!("'nope' is not a method");
        };
        let text = err.to_string();
        assert!(text.contains("nope") && text.contains("exact"), "{text}");
        let Err(err) = detector_with_params("exact", &[("gamma", "2")]) else {
            panic!("exact has no gamma");
        };
        assert!(err.to_string().contains("gamma"), "{err}");
    }

    #[test]
    fn parse_param_list_splits_at_commas_and_skips_empty_items() {
        assert_eq!(parse_param_list(""), Ok(vec![]));
        assert_eq!(parse_param_list(" , "), Ok(vec![]));
        assert_eq!(
            parse_param_list("gamma=1.5, cavity=off,"),
            Ok(vec![
                ("gamma".into(), "1.5".into()),
                ("cavity".into(), "off".into())
            ])
        );
        let Err(err) = parse_param_list("depth=4,oops") else {
            panic!("'oops' has no '='");
        };
        assert!(err.contains("'oops'"), "{err}");
    }

    #[test]
    fn parse_param_splits_at_the_first_equals_sign() {
        assert_eq!(parse_param("depth=4"), Ok(("depth".into(), "4".into())));
        assert_eq!(
            parse_param(" model = a=b "),
            Ok(("model".into(), "a=b".into()))
        );
        assert!(parse_param("depth").is_err());
        assert!(parse_param("=4").is_err());
    }
}
