//! What a method crate implements: [`Method`], its [`Capabilities`] as data, and the [`Job`]
//! it classifies.
//!
//! A method writes its algorithm once, generic over the dimension, and states what it
//! supports; it never checks its input itself. The object-safe face
//! [`BoundaryDetector`](crate::BoundaryDetector) comes from a blanket impl over every
//! [`Method`] (see [`crate::detect`]): it dispatches on the dimension, refuses what the
//! capabilities refuse, validates the job and checks the stop token, once for every method.
//!
//! ```
//! use boundary_core::{
//!     BoundaryDetector, Capabilities, DetectError, Detection, Dim, Job, Labels, Method, Params,
//!     ParticleSet, Radius, SupportedDim,
//! };
//!
//! /// Boundary iff the particle has no other particle within `r`.
//! #[derive(Debug)]
//! struct Lonely;
//!
//! impl Method for Lonely {
//!     const NAME: &'static str = "lonely";
//!     fn describe(&self) -> Params {
//!         Params::default()
//!     }
//!     fn capabilities(&self) -> Capabilities {
//!         Capabilities::DEFAULT
//!     }
//!     fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
//!     where
//!         Dim<D>: SupportedDim,
//!     {
//!         let p = job.set.positions();
//!         let r = job.r.get();
//!         let labels = (0..job.owned)
//!             .map(|i| !p.iter().enumerate().any(|(j, q)| j != i && (q - p[i]).norm() <= r))
//!             .collect::<Labels>();
//!         Ok(Detection { labels, margin: None })
//!     }
//! }
//!
//! let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [0.5, 0.0], [3.0, 0.0]]).unwrap();
//! let d = Lonely.detect_2d(&set, Radius::new(1.0).unwrap()).unwrap();
//! assert_eq!(d.labels.as_slice(), &[false, false, true]);
//! ```

use crate::{DetectError, Detection, Dim, ParticleSet, Radius, Solids, SupportedDim};
use std::any::Any;
use std::fmt;

/// Whether a method honours an input, or why it refuses it (in the method's terms).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Support {
    /// The method takes the input into account.
    Honoured,
    /// The method refuses the input rather than ignore it; the reason names the method's
    /// obstacle and, where there is one, the alternative.
    Refused(&'static str),
}

impl Support {
    /// Whether the input is honoured.
    pub const fn is_honoured(self) -> bool {
        matches!(self, Support::Honoured)
    }
}

/// What a method supports, as data: the face refuses the rest before the method runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Capabilities {
    /// Whether the method promises no false negatives (recall 1 against the exact labels).
    pub certified: bool,
    /// Per-particle radii ([`ParticleSet::with_radii`]).
    pub radii: Support,
    /// Solid half-spaces ([`crate::HalfSpace`]).
    pub half_spaces: Support,
    /// Solid meshes ([`crate::SolidMesh`], 3D only).
    pub meshes: Support,
    /// How far from a particle the method looks, in units of `r`
    /// ([`BoundaryDetector::halo_width`](crate::BoundaryDetector::halo_width)): the labels of
    /// the particles owned by a subdomain equal the global ones when the subdomain holds every
    /// particle within `halo_over_r · r` of an owned one.
    pub halo_over_r: f64,
}

/// The reason of [`Capabilities::DEFAULT`] for refusing solid half-spaces.
const SOLID_REFUSAL: &str = "the method has no rule for a solid covering part of a sphere; give \
     the walls as wall particles instead";

/// The reason of [`Capabilities::DEFAULT`] for refusing solid meshes.
const SOLID_MESH_REFUSAL: &str = "the method has no rule for a solid given as a triangle mesh \
     covering part of a sphere; use exact, or give the solid as half-spaces or the walls as \
     wall particles where the method takes them";

/// The reason of [`Capabilities::DEFAULT`] for refusing per-particle radii.
const RADII_REFUSAL: &str = "the method has no rule for a radius per particle";

impl Capabilities {
    /// Not certified, uniform radius only, no solid, a halo of `2r` (the reach of the
    /// definition itself). A method states what it adds with struct update syntax:
    /// `Capabilities { certified: true, ..Capabilities::DEFAULT }`.
    pub const DEFAULT: Capabilities = Capabilities {
        certified: false,
        radii: Support::Refused(RADII_REFUSAL),
        half_spaces: Support::Refused(SOLID_REFUSAL),
        meshes: Support::Refused(SOLID_MESH_REFUSAL),
        halo_over_r: 2.0,
    };
}

impl Default for Capabilities {
    fn default() -> Self {
        Capabilities::DEFAULT
    }
}

/// One classification: the first `owned` particles of `set` get a label; the others (a halo,
/// walls, periodic images) take part as neighbours only. The closed `solids` cover too.
///
/// The face hands a method only jobs its [`Capabilities`] accept: `owned <= set.len()`, no
/// radii unless honoured, no solid of a kind it refuses, meshes only in 3D, and every
/// half-space's axis within the dimension.
#[derive(Debug, Clone, Copy)]
pub struct Job<'a, const D: usize> {
    /// The particles: the classified ones first, then the ghosts.
    pub set: &'a ParticleSet<D>,
    /// How many particles, from the first, are classified.
    pub owned: usize,
    /// The solid regions (empty for a bare cloud).
    pub solids: &'a Solids,
    /// The resolution.
    pub r: Radius,
}

/// A [`Job`] of a dimension known at run time, for the few methods whose geometry differs
/// between 2D and 3D ([`Job::by_dim`]).
#[derive(Debug, Clone, Copy)]
pub enum JobByDim<'a> {
    /// A 2D job.
    D2(Job<'a, 2>),
    /// A 3D job.
    D3(Job<'a, 3>),
}

impl<'a, const D: usize> Job<'a, D>
where
    Dim<D>: SupportedDim,
{
    /// The same job with its dimension as a value: what a method whose 2D and 3D geometry
    /// differ (a polygon clip versus a polyhedron clip) matches on.
    pub fn by_dim(self) -> JobByDim<'a> {
        let set: &'a dyn Any = self.set;
        let Job {
            owned, solids, r, ..
        } = self;
        if let Some(set) = set.downcast_ref::<ParticleSet<2>>() {
            return JobByDim::D2(Job {
                set,
                owned,
                solids,
                r,
            });
        }
        match set.downcast_ref::<ParticleSet<3>>() {
            Some(set) => JobByDim::D3(Job {
                set,
                owned,
                solids,
                r,
            }),
            None => unreachable!("Dim<D>: SupportedDim holds for D = 2 and 3 only"),
        }
    }
}

/// A boundary-particle detection method: what a method crate implements.
///
/// The algorithm is written once, generic over the dimension, in [`Method::classify`]; what
/// the method supports is data ([`Method::capabilities`]). Every [`Method`] is a
/// [`BoundaryDetector`](crate::BoundaryDetector) (the object-safe face a registry holds) through
/// a blanket impl, which checks the job against the capabilities before `classify` runs.
/// Parallelism uses rayon's current thread pool.
///
/// Contract: `classify` returns one label per owned particle in input order (a method that
/// cannot skip the ghosts may return one per particle of the set: the face keeps the owned
/// ones), never panics on a job the face accepts, and is deterministic (labels do not depend
/// on the number of threads). A method stopped through the
/// [`StopToken`](crate::stop::StopToken) may return partial labels: the face turns them into
/// [`DetectError::Interrupted`].
pub trait Method: Send + Sync + fmt::Debug {
    /// The method's name in the registry and on the command line (`exact`, `ia`, …).
    const NAME: &'static str;

    /// The parameters with their current values and defaults, as `key=value` text for
    /// reports and labels.
    fn describe(&self) -> crate::Params;

    /// What the method supports.
    fn capabilities(&self) -> Capabilities;

    /// Classifies the first `job.owned` particles of `job.set`.
    fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim;
}
