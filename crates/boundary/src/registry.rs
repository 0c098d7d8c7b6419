//! Every compiled-in method by name, with parameters as `key=value` strings: the adapter that
//! the command line (`boundary detect --method ge --set depth=4`), the Python package and the
//! C API use. Rust code that knows its method builds the typed parameters instead
//! (`IaDetector::try_new(IaParams { depth: 4 })`).
//!
//! The keys are the field names of each method's parameter struct; the values are their text
//! forms:
//!
//! | method | key | value |
//! |---|---|---|
//! | `exact`, `dilts` | `tie` | a finite number `>= 0` |
//! | `ia`, `ge` | `depth` | an integer in `1..=16` |
//! | `marrone` | `lambda_surface`, `lambda_interior` | a finite number `>= 0` |
//! | `marrone` | `cone_angle` | degrees, in `(0, 90)` |
//! | `marrone`, `muller`, `divr`, `asymmetry`, `randles` | `kernel` | `wendland` or `cubic` |
//! | `marrone`, `muller`, `divr`, `asymmetry`, `randles` | `h_over_r` | a number in `(0, 100]` |
//! | `muller` | `threshold` | a finite number `>= 0` |
//! | `divr` | `threshold` | a number `> 0`, or `dualsphysics`, `sphinxsys` or `chrono` |
//! | `divr` | `layers` | `0` or `1` |
//! | `divr` | `min_neighbours` | `auto` or a whole number in `[0, 1000]` |
//! | `asymmetry` | `threshold` | a finite number `>= 0` |
//! | `asymmetry` | `density_ratio` | a number in `[0, 1]` |
//! | `randles` | `mu_2d`, `mu_3d` | a finite number `>= 0` |
//! | `lnm` | `cell_over_r` | a number in `[0.5, 16]` |
//! | `lnm` | `delta` | `auto` or a whole number `>= 0` |
//! | `lnm` | `variant` | `refined` or `fast` |
//! | `hpr` | `gamma` | a number in `(1, 10]` |
//! | `hpr` | `cavity` | `on` or `off` (also `true`/`false`, `1`/`0`, `yes`/`no`) |
//! | `hpr` | `grids` | `1` or `2` |
//! | `hpr` | `protrusion` | `auto` or a number in `[1e-6, 0.1]` |
//! | `svm` | `refine` | `none`, `exact` or `ge` |
//! | `svm` | `model` | `default` or the path of a model file (read when the key is applied) |
//!
//! [`parameters`] lists a method's keys with their defaults and descriptions, as
//! `boundary methods` prints them.
//!
//! Each method's entry is one line: its parameters' parsing, checks and listing come from
//! their declaration in the method crate (`boundary_core::declare_params!`).
//!
//! Pairs are applied in order, each checked at once by the declared checks, so the error
//! names the first pair that fails: an unknown key lists the method's keys, an invalid value
//! says what the parameter must be, quoting the value as given. A number that does not parse
//! is reported like an out-of-range one.
//!
//! ```
//! use boundary::registry::{detector_with_params, parameters};
//!
//! let ge = detector_with_params("ge", &[("depth", "4")]).unwrap();
//! assert_eq!(ge.to_string(), "ge (depth=4)");
//! let err = detector_with_params("ge", &[("depth", "99")]).unwrap_err();
//! assert_eq!(
//!     err.to_string(),
//!     "method 'ge': invalid value '99' for 'depth': must be an integer in 1..=16"
//! );
//! let err = detector_with_params("ge", &[("dept", "4")]).unwrap_err();
//! assert_eq!(err.to_string(), "method 'ge' has no parameter 'dept' (parameters: depth)");
//! assert_eq!(parameters("ge").unwrap().0[0].default, "6");
//! ```

use boundary_core::{BoundaryDetector, Configurable, ParamError, ParamSet, Params};
use thiserror::Error;

/// Why the registry could not build a detector.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
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

/// Builds a detector from `(key, value)` pairs, applied in order.
type Build = fn(&[(&str, &str)]) -> Result<Box<dyn BoundaryDetector>, ParamError>;

/// A registry entry: name, one-line summary and the string adapter of its parameters.
struct Entry {
    name: &'static str,
    summary: &'static str,
    build: Build,
}

/// Every compiled-in method, in the order the reports list them (references first).
const REGISTRY: &[Entry] = &[
    #[cfg(feature = "exact")]
    method::<boundary_exact::ExactDetector>(
        "restricted Voronoi cell of each particle reaches beyond r: the reference labels",
    ),
    #[cfg(feature = "dilts")]
    method::<boundary_dilts::DiltsDetector>(
        "explicit covering of S_i by arcs (2D, Dilts 2000) or caps (3D, Haque & Dilts 2007)",
    ),
    #[cfg(feature = "ia")]
    method::<boundary_ia::IaDetector>(
        "interval-arithmetic quadtree/octree over S_i, rules R1-R4 (JCP 2020 Sec. 3.1)",
    ),
    #[cfg(feature = "ge")]
    method::<boundary_ge::GeDetector>(
        "geometric-enclosure slabs on a mesh of S_i, rules R1-R4 (JCP 2020 Sec. 3.2)",
    ),
    #[cfg(feature = "marrone")]
    method::<boundary_marrone::MarroneDetector>(
        "SPH renormalisation-matrix eigenvalue, then a scan cone along the normal \
                  (Marrone et al., JCP 2010)",
    ),
    #[cfg(feature = "muller")]
    method::<boundary_muller::MullerDetector>(
        "SPH colour-field gradient |grad c| h above a threshold (Mueller et al., SCA 2003)",
    ),
    #[cfg(feature = "divr")]
    method::<boundary_divr::DivrDetector>(
        "SPH divergence of position below a threshold: DualSPHysics, SPHinXsys or \
                  Chrono::FSI's value by name (Lind et al., JCP 2012)",
    ),
    #[cfg(feature = "asymmetry")]
    method::<boundary_asymmetry::AsymmetryDetector>(
        "distance to the kernel-weighted mean of the neighbourhood, or a low density \
                  (He et al., ACM TOG 2012)",
    ),
    #[cfg(feature = "randles")]
    method::<boundary_randles::RandlesDetector>(
        "smallest eigenvalue of the SPH renormalisation matrix at most mu \
                  (Randles-Doring; Marrone et al., JCP 2010, first step)",
    ),
    #[cfg(feature = "lnm")]
    method::<boundary_lnm::LnmDetector>(
        "layered neighbourhood cells: cells beside empty or sparse cells are boundary, \
                  a narrow band (Oliveira & Paiva, CGF 2022)",
    ),
    #[cfg(feature = "hpr")]
    method::<boundary_hpr::HprDetector>(
        "visibility: hidden point removal with exponential flipping from grid and \
                  cavity viewpoints (Sandim 2020, ch. 2, Alg. 1)",
    ),
    #[cfg(feature = "svm")]
    method::<boundary_svm::SvmDetector>(
        "polynomial-kernel support vector machine on six SPH features, trained on exact labels; \
                  refine=exact|ge re-tests its boundary particles (Sandim 2020, ch. 3)",
    ),
];

/// The entry of a method whose parameters are declared once
/// ([`boundary_core::declare_params!`]): its name, and its string adapter from the
/// declaration.
#[allow(dead_code)] // unused when no method is compiled in
const fn method<M: Configurable>(summary: &'static str) -> Entry {
    Entry {
        name: M::NAME,
        summary,
        build: configured::<M>,
    }
}

/// Builds `M` from `(key, value)` pairs applied in order to its declared parameters.
#[allow(dead_code)]
fn configured<M: Configurable>(
    pairs: &[(&str, &str)],
) -> Result<Box<dyn BoundaryDetector>, ParamError> {
    Ok(Box::new(M::from_params(M::Params::from_pairs(pairs)?)?))
}

fn entry(name: &str) -> Result<&'static Entry, RegistryError> {
    REGISTRY
        .iter()
        .find(|e| e.name == name)
        .ok_or_else(|| RegistryError::UnknownMethod {
            name: name.to_owned(),
            available: methods().join(", "),
        })
}

/// The names of the compiled-in methods, references first.
pub fn methods() -> Vec<&'static str> {
    REGISTRY.iter().map(|e| e.name).collect()
}

/// The one-line summary of a method, if it is compiled in.
pub fn summary(name: &str) -> Option<&'static str> {
    entry(name).ok().map(|e| e.summary)
}

/// The detector called `name`, at its default parameters.
pub fn detector_by_name(name: &str) -> Result<Box<dyn BoundaryDetector>, RegistryError> {
    Ok((entry(name)?.build)(&[])?)
}

/// The detector called `name` with `params` (`(key, value)` pairs, applied in order; see the
/// module docs for the keys and the errors).
pub fn detector_with_params<K: AsRef<str>, V: AsRef<str>>(
    name: &str,
    params: &[(K, V)],
) -> Result<Box<dyn BoundaryDetector>, RegistryError> {
    let pairs: Vec<(&str, &str)> = params
        .iter()
        .map(|(k, v)| (k.as_ref(), v.as_ref()))
        .collect();
    Ok((entry(name)?.build)(&pairs)?)
}

/// The parameters of the method called `name`: its keys in order, each with its default
/// (the current value of a default detector) and a one-line description.
pub fn parameters(name: &str) -> Result<Params, RegistryError> {
    Ok(detector_by_name(name)?.describe())
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
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    /// The `(method, key)` pairs of the key table in the module docs.
    fn documented_keys() -> Vec<(String, String)> {
        let ticked = |cell: &str| -> Vec<String> {
            cell.split('`')
                .skip(1)
                .step_by(2)
                .map(str::to_owned)
                .collect()
        };
        let mut pairs = Vec::new();
        for row in include_str!("registry.rs").lines() {
            let Some(row) = row.strip_prefix("//! | `") else {
                continue;
            };
            let row = format!("`{row}");
            let cells: Vec<&str> = row.split('|').collect();
            for method in ticked(cells[0]) {
                for key in ticked(cells[1]) {
                    pairs.push((method.clone(), key));
                }
            }
        }
        pairs
    }

    /// The key table documents every parameter of every compiled-in method, and nothing else:
    /// a key added to a method's `params()` without a row fails here.
    #[test]
    fn the_key_table_lists_every_parameter_of_every_method() {
        let table = documented_keys();
        let mut listed = Vec::new();
        for name in methods() {
            for info in parameters(name).unwrap().0 {
                let pair = (name.to_owned(), info.name.to_owned());
                assert!(
                    table.contains(&pair),
                    "the key table has no row for {name}'s `{}`",
                    info.name
                );
                listed.push(pair);
            }
        }
        for (method, key) in &table {
            if methods().contains(&method.as_str()) {
                assert!(
                    listed.contains(&(method.clone(), key.clone())),
                    "the key table lists `{key}` for {method}, which has no such parameter"
                );
            }
        }
        assert!(listed.len() >= 25, "{} keys", listed.len());
    }

    #[test]
    fn every_registered_name_builds_the_detector_of_that_name() {
        let names = methods();
        assert!(!names.is_empty());
        for name in names {
            let detector = detector_by_name(name).expect("registered");
            assert_eq!(detector.name(), name);
            assert!(summary(name).is_some());
            // The defaults reported by params() are accepted back by the string adapter.
            let params = detector.describe();
            assert_eq!(parameters(name), Ok(params.clone()));
            let pairs: Vec<(&str, &str)> = params
                .0
                .iter()
                .map(|p| (p.name, p.value.as_str()))
                .collect();
            let again = detector_with_params(name, &pairs).expect("defaults round-trip");
            assert_eq!(again.describe(), params);
            for p in &params.0 {
                assert_eq!(p.value, p.default, "{name}: {}", p.name);
            }
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
        assert_eq!(
            err.to_string(),
            "method 'exact' has no parameter 'gamma' (parameters: tie)"
        );
        let Err(err) = detector_with_params("marrone", &[("depth", "3")]) else {
            panic!("marrone has no depth");
        };
        assert_eq!(
            err.to_string(),
            "method 'marrone' has no parameter 'depth' (parameters: lambda_surface, \
             lambda_interior, cone_angle, kernel, h_over_r)"
        );
    }

    /// Every value the adapter must refuse, with the message it gives (the value quoted as
    /// given, the reason of the field).
    #[test]
    fn invalid_values_are_refused_with_the_reason_and_the_value_as_given() {
        let cases: &[(&str, &str, &str, &str)] = &[
            ("exact", "tie", "-1e-9", "a finite number >= 0"),
            ("exact", "tie", "x", "a finite number >= 0"),
            ("dilts", "tie", "inf", "a finite number >= 0"),
            ("ia", "depth", "0", "must be an integer in 1..=16"),
            ("ia", "depth", "17", "must be an integer in 1..=16"),
            ("ia", "depth", "-1", "must be an integer in 1..=16"),
            ("ia", "depth", "2.5", "must be an integer in 1..=16"),
            ("ge", "depth", "x", "must be an integer in 1..=16"),
            ("marrone", "lambda_surface", "-0.1", "must be a number >= 0"),
            ("marrone", "lambda_interior", "nan", "must be a number >= 0"),
            (
                "marrone",
                "cone_angle",
                "90",
                "must be an angle in degrees in (0, 90)",
            ),
            (
                "marrone",
                "cone_angle",
                "0",
                "must be an angle in degrees in (0, 90)",
            ),
            (
                "marrone",
                "kernel",
                "gauss",
                "unknown kernel 'gauss' (kernels: wendland, cubic)",
            ),
            ("marrone", "h_over_r", "0", "must be in (0, 100]"),
            ("marrone", "h_over_r", "inf", "must be in (0, 100]"),
            ("muller", "threshold", "-1", "must be a number >= 0"),
            ("muller", "threshold", " nan", "must be a number >= 0"),
            ("muller", "threshold", "abc", "must be a number >= 0"),
            ("muller", "h_over_r", "1e3", "must be in (0, 100]"),
            ("hpr", "gamma", "1", "must be in (1, 10]"),
            ("hpr", "gamma", "nan", "must be in (1, 10]"),
            ("hpr", "cavity", "maybe", "must be on or off"),
            ("hpr", "grids", "3", "must be 1 or 2"),
            ("hpr", "grids", "0", "must be 1 or 2"),
            ("hpr", "grids", "two", "must be 1 or 2"),
            (
                "hpr",
                "protrusion",
                "0.5",
                "must be auto or a number in [1e-6, 0.1]",
            ),
            (
                "hpr",
                "protrusion",
                "none",
                "must be auto or a number in [1e-6, 0.1]",
            ),
            ("svm", "refine", "dilts", "must be none, exact or ge"),
        ];
        for &(method, key, value, reason) in cases {
            if !methods().contains(&method) {
                continue;
            }
            let err = detector_with_params(method, &[(key, value)]).unwrap_err();
            assert_eq!(
                err.to_string(),
                format!("method '{method}': invalid value '{value}' for '{key}': {reason}"),
            );
        }
    }

    #[test]
    fn the_sph_criteria_take_their_text_parameters_into_their_typed_ones() {
        use boundary_divr::Threshold;
        let built = |name: &str, pairs: &[(&str, &str)]| {
            detector_with_params(name, pairs)
                .unwrap()
                .describe()
                .to_string()
        };
        let divr = boundary_divr::DivrDetector::try_new(boundary_divr::DivrParams {
            threshold: Threshold::Sphinxsys,
            layers: 1,
            min_neighbours: Some(5),
            ..Default::default()
        })
        .unwrap();
        let pairs = [
            ("threshold", "sphinxsys"),
            ("layers", "1"),
            ("min_neighbours", "5"),
        ];
        assert_eq!(built("divr", &pairs), divr.describe().to_string());
        for name in Threshold::NAMED.map(|t| t.name()) {
            assert!(built("divr", &[("threshold", &name)]).contains(&name));
        }
        assert!(built("divr", &[("threshold", "1.25")]).contains("threshold=1.25"));
        let asym =
            boundary_asymmetry::AsymmetryDetector::try_new(boundary_asymmetry::AsymmetryParams {
                threshold: 0.4,
                density_ratio: 0.0,
                kernel: crate::Kernel::CubicSpline,
                ..Default::default()
            })
            .unwrap();
        let pairs = [
            ("threshold", "0.4"),
            ("kernel", "cubic"),
            ("density_ratio", "0"),
        ];
        assert_eq!(built("asymmetry", &pairs), asym.describe().to_string());
        let randles = boundary_randles::RandlesDetector::try_new(boundary_randles::RandlesParams {
            mu_3d: 0.3,
            ..Default::default()
        })
        .unwrap();
        assert_eq!(
            built("randles", &[("mu_3d", "0.3")]),
            randles.describe().to_string()
        );
        let lnm = boundary_lnm::LnmDetector::try_new(boundary_lnm::LnmParams {
            cell_over_r: 1.5,
            delta: Some(3),
            variant: boundary_lnm::LnmVariant::Fast,
        })
        .unwrap();
        let pairs = [("delta", "3"), ("cell_over_r", "1.5"), ("variant", "fast")];
        assert_eq!(built("lnm", &pairs), lnm.describe().to_string());
        assert!(built("lnm", &[("delta", "3"), ("delta", "auto")]).contains("delta=auto"));
        // Every bad value is refused, quoting the text as given; unknown keys list the known.
        for (name, key, bad) in [
            ("divr", "threshold", "-1"),
            ("divr", "threshold", "deep"),
            ("divr", "layers", "2"),
            ("divr", "layers", "one"),
            ("divr", "min_neighbours", "2000"),
            ("divr", "min_neighbours", "-3"),
            ("divr", "h_over_r", "0"),
            ("asymmetry", "threshold", "-0.1"),
            ("asymmetry", "density_ratio", "1.5"),
            ("asymmetry", "kernel", "gauss"),
            ("randles", "mu_2d", "nan"),
            ("randles", "h_over_r", "inf"),
            ("lnm", "cell_over_r", "0"),
            ("lnm", "delta", "-1"),
            ("lnm", "delta", "2.5"),
            ("lnm", "variant", "slow"),
        ] {
            let err = detector_with_params(name, &[(key, bad)])
                .unwrap_err()
                .to_string();
            assert!(
                err.contains(bad) && err.contains(key),
                "{name} {key}={bad}: {err}"
            );
        }
        for (name, known) in [
            ("divr", "min_neighbours"),
            ("asymmetry", "density_ratio"),
            ("randles", "mu_2d"),
            ("lnm", "cell_over_r"),
        ] {
            let err = detector_with_params(name, &[("depth", "3")])
                .unwrap_err()
                .to_string();
            assert!(err.contains(known), "{name}: {err}");
        }
    }

    #[test]
    fn pairs_apply_in_order_into_the_typed_parameters() {
        let d = detector_with_params(
            "hpr",
            &[
                ("gamma", "1.75"),
                ("cavity", "off"),
                ("grids", "2"),
                ("protrusion", "1e-3"),
                ("protrusion", "auto"),
            ],
        )
        .unwrap();
        assert_eq!(
            d.describe().to_string(),
            "gamma=1.75, cavity=off, grids=2, protrusion=auto"
        );
        let d = detector_with_params("marrone", &[("kernel", "cubic"), ("h_over_r", "1.3")]);
        assert_eq!(
            d.unwrap().describe().to_string(),
            "lambda_surface=0.2, lambda_interior=0.75, cone_angle=45, kernel=cubic, h_over_r=1.3"
        );
        // The first failing pair is reported, even when a later one would fail too.
        let err = detector_with_params("ia", &[("depth", "3"), ("depth", "x"), ("nope", "1")]);
        assert!(err.unwrap_err().to_string().contains("'x'"));
    }

    #[test]
    fn an_svm_model_path_is_read_when_applied_and_a_missing_file_is_named() {
        if !methods().contains(&"svm") {
            return;
        }
        let err = detector_with_params("svm", &[("model", "no/such/model.json")]).unwrap_err();
        let text = err.to_string();
        assert!(
            text.starts_with(
                "method 'svm': invalid value 'no/such/model.json' for 'model': cannot read \
                 'no/such/model.json': "
            ),
            "{text}"
        );
        let d = detector_with_params("svm", &[("refine", "ge"), ("model", "default")]).unwrap();
        assert_eq!(d.describe().to_string(), "refine=ge, model=default");
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
