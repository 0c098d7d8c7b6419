//! Boundary particles of meshfree particle sets (SPH, PBF, FLIP/APIC, MPS).
//!
//! Particle *i* at *p_i* with resolution *r* is **interior** iff its sphere *S_i* of radius *r*
//! is covered by the closed balls of radius *r* of the other particles within *2r*; otherwise
//! it is **boundary** (Sandim, Paiva & Figueiredo, J. Comput. Phys. 2020). Coincident
//! duplicates do not cover each other.
//!
//! What a user needs is at the root: particle sets ([`ParticleSet`], [`AnyParticleSet`]),
//! the resolution [`Radius`], the [`Domain`] around a set (walls, [`Solids`], [`Periodic`]
//! axes, phases), the [`BoundaryDetector`] trait with its [`Detection`] and [`Labels`], the
//! detectors of the compiled-in methods (one cargo feature per method crate) with their typed
//! parameters, the metrics ([`Confusion`]) and the errors. The [`registry`] creates a method
//! by its name with `key=value` parameters, exactly as on the command line (`boundary detect
//! --method ge --set depth=4`). What only the author of a new detector needs (the neighbour
//! grids, the exact covering predicate, domain decomposition, the label helpers) is in
//! [`implement`]. Any method's labels widen to a narrow band with [`Labels::widen`] (the
//! command line's `--band K`: every particle within `K·r` of a boundary particle), and
//! [`Tracker`] labels the successive time steps of a simulation as `exact` does, recomputing
//! only the particles whose label may have changed. [`Cascade`] composes two methods: a
//! certified one re-tests the boundary particles of another.
//!
//! # Typed parameters
//! Each method has a parameter struct with public fields and the paper's defaults, and a
//! detector built from it by `try_new`, which checks it (never clamps):
//! ```
//! use boundary::{BoundaryDetector, IaDetector, IaParams, ParticleSet, Radius};
//!
//! let ia = IaDetector::try_new(IaParams { depth: 4 }).unwrap();
//! assert_eq!(ia.params().depth, 4);
//! assert!(IaDetector::try_new(IaParams { depth: 0 }).is_err());
//! let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0]]).unwrap();
//! let labels = ia.detect_2d(&set, Radius::new(0.8).unwrap()).unwrap().labels;
//! assert_eq!(labels.boundary_count(), 2);
//! ```
//!
//! # By name
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

mod cascade;
pub mod registry;

pub use cascade::Cascade;

pub use registry::{
    detector_by_name, detector_with_params, methods, parameters, parse_param, parse_param_list,
    summary, RegistryError,
};

pub use boundary_core::{
    auto_radius, bulk_spacing, bulk_spacing_of, radius_concern, radius_from_spacing, stop,
    AutoRadius, RadiusConcern, PLAUSIBLE_RADIUS_PER_SPACING, RADIUS_PER_SPACING,
};
pub use boundary_core::{
    median_nearest_neighbour_distance, AnyParticleSet, BoundaryDetector, Confusion, CoreError,
    DetectError, Detection, Dim, Domain, DomainDetection, DomainError, Flatness, HalfSpace, Labels,
    MeshError, ParamError, ParamInfo, Params, ParticleSet, Periodic, Point, Radius, SolidMesh,
    Solids, SupportedDim,
};

/// Re-export of the linear-algebra crate used in public signatures ([`Point`]).
pub use boundary_core::nalgebra;

#[cfg(feature = "asymmetry")]
pub use boundary_asymmetry::{AsymmetryDetector, AsymmetryParams};
#[cfg(feature = "dilts")]
pub use boundary_dilts::{DiltsDetector, DiltsParams};
#[cfg(feature = "divr")]
pub use boundary_divr::{DivrDetector, DivrParams, Threshold as DivrThreshold};
#[cfg(feature = "exact")]
pub use boundary_exact::{ExactDetector, ExactParams, Tracker};
#[cfg(feature = "ge")]
pub use boundary_ge::{GeDetector, GeParams};
#[cfg(feature = "hpr")]
pub use boundary_hpr::{Grids, HprDetector, HprParams, Protrusion};
#[cfg(feature = "ia")]
pub use boundary_ia::{IaDetector, IaParams};
#[cfg(feature = "lnm")]
pub use boundary_lnm::{LnmDetector, LnmParams};
#[cfg(feature = "marrone")]
pub use boundary_marrone::{MarroneDetector, MarroneParams};
#[cfg(feature = "muller")]
pub use boundary_muller::{MullerDetector, MullerParams};
#[cfg(feature = "randles")]
pub use boundary_randles::{RandlesDetector, RandlesParams};
/// The SPH kernel of the methods built on SPH sums (`marrone`, `muller`, `divr`,
/// `asymmetry`, `randles`).
#[cfg(any(
    feature = "marrone",
    feature = "muller",
    feature = "divr",
    feature = "asymmetry",
    feature = "randles"
))]
pub use boundary_sph::Kernel;
#[cfg(feature = "svm")]
pub use boundary_svm::{ModelChoice, Refine, SvmDetector, SvmModel, SvmParams};

/// For writing a detector: what an implementation of [`Method`](implement::Method) uses beyond
/// the types at the crate root. A user who runs the existing methods needs none of it
/// (`docs/ADDING_A_METHOD.md` gives the steps).
///
/// - [`Method`](implement::Method), [`Capabilities`](implement::Capabilities),
///   [`Support`](implement::Support) and [`Job`](implement::Job): the trait a method
///   implements, what it supports, and the job it classifies; every `Method` is a
///   [`BoundaryDetector`] through the core's face, which checks each job once for all;
/// - [`NeighbourGrid`](implement::NeighbourGrid) and [`RadiusGrid`](implement::RadiusGrid):
///   fixed-radius neighbour queries (uniform and per-particle radii), with
///   [`Neighbourhood`](implement::Neighbourhood);
/// - `exact_cover` (with the feature `exact`): the exact covering predicate of `exact`;
/// - [`decompose`](implement::decompose): subdomains with halos (what
///   [`BoundaryDetector::detect_owned`] classifies), as the MPI driver uses them;
/// - [`domain`](implement::domain) and [`solid_mesh`](implement::solid_mesh): the module docs of
///   the domain and of solid meshes;
/// - [`write_label`](implement::write_label) and
///   [`impl_display_as_label!`](implement::impl_display_as_label): a detector's `Display`.
pub mod implement {
    pub use boundary_core::{
        declare_params, decompose, detect, domain, impl_configurable, impl_display_as_label,
        method, params, radius_grid, solid_mesh, write_label, Capabilities, Configurable, Job,
        JobByDim, Method, NeighbourGrid, Neighbourhood, ParamSet, ParamValue, RadiusGrid, Support,
    };
    #[cfg(feature = "exact")]
    pub use boundary_exact::exact_cover;
}
