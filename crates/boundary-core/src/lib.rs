#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Core types for boundary-particle detection.
//!
//! A particle `i` at `p_i` with resolution `r` is **interior** iff its sphere `S_i` (radius `r`)
//! is covered by the closed balls of radius `r` of the other particles within `2r`; otherwise it
//! is **boundary** (Sandim et al., J. Comput. Phys. 2020, Sec. 2). Coincident duplicates do not
//! cover each other.
//!
//! This crate holds what every method shares and nothing method-specific:
//!
//! - [`ParticleSet`]: validated positions (finite `f64`), generic over the dimension `D` (2 or 3),
//!   and [`AnyParticleSet`] for code that learns the dimension at run time (file readers, the CLI).
//! - [`Radius`]: a positive, finite resolution `r`.
//! - [`NeighbourGrid`]: a uniform grid for fixed-radius neighbour queries; [`RadiusGrid`] for
//!   sets with a radius per particle ([`ParticleSet::with_radii`]).
//! - [`Method`]: the small trait every method implements (its parameters, its
//!   [`Capabilities`] as data, and one `classify` of a [`Job`], generic over the dimension);
//!   [`BoundaryDetector`]: the object-safe face every method gets from it, which checks each
//!   job once for all methods and returns a [`Detection`] (see [`detect`]).
//! - [`bulk_spacing`]: the particle spacing `dp` (volume per particle in the bulk), and
//!   [`auto_radius`], [`radius_from_spacing`] (`r = k·dp`) and [`radius_concern`] from it.
//! - [`Confusion`]: accuracy metrics (Rec, FPR, M = Rec·(1−FPR), precision, F1).
//! - [`Domain`]: walls, solid regions ([`Solids`]: half-spaces, and in 3D closed triangle
//!   meshes), periodic axes and phases around a set (see [`domain`]).
//!
//! # Solid meshes
//! [`SolidMesh::new`] takes vertices and triangles (as `boundary_io::read_mesh` returns them)
//! and checks that they bound a solid: finite, indices in range, no zero-area triangle, every
//! edge shared by exactly two triangles running in opposite directions (the first bad edge is
//! named by its vertex indices); inward-facing meshes are flipped. Its queries,
//! [`SolidMesh::contains`] (closed: the surface is solid) and [`SolidMesh::distance`], are
//! floating-point projections onto the nearest triangle (parry), accurate to
//! [`SolidMesh::rounding`]: unlike a [`HalfSpace`], a mesh is not an exact input of the
//! covering predicate, so a method that honours meshes states its tolerance near the surface.
//! [`Domain::with_solid_mesh`] adds one; a method that cannot honour it refuses it by name
//! ([`Capabilities::meshes`]).
//!
//! Architecture invariant: this crate knows no file format, prints nothing and touches no file.
//!
//! ```
//! use boundary_core::{NeighbourGrid, ParticleSet, Radius};
//!
//! let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0], [5.0, 5.0]]).unwrap();
//! let r = Radius::new(0.6).unwrap();
//! let grid = NeighbourGrid::new(&set, 2.0 * r.get()).unwrap();
//! let mut near = Vec::new();
//! grid.for_each_within(&set.positions()[0], 2.0 * r.get(), |j, _d2| near.push(j));
//! near.sort();
//! assert_eq!(near, vec![0, 1]);
//! ```

mod band;
pub mod decompose;
pub mod detect;
mod detection;
pub mod domain;
mod error;
mod grid;
pub mod method;
mod metrics;
pub mod params;
mod particles;
pub mod radius_grid;
pub mod solid_mesh;
mod spacing;
pub mod stop;

pub use detect::{detect_in, write_label, BoundaryDetector, DomainDetection};
pub use detection::{DetectError, Detection, Labels, ParamError, ParamInfo, Params};
pub use domain::{Domain, DomainError, HalfSpace, Periodic, Solids};
pub use error::CoreError;
pub use grid::{NeighbourGrid, Neighbourhood};
pub use method::{Capabilities, Job, JobByDim, Method, Support};
pub use metrics::Confusion;
pub use params::{Configurable, ParamSet, ParamValue};
pub use particles::{AnyParticleSet, Dim, Flatness, ParticleSet, Point, Radius, SupportedDim};
pub use radius_grid::RadiusGrid;
pub use solid_mesh::{MeshError, SolidMesh};
pub use spacing::{
    auto_radius, bulk_spacing, bulk_spacing_of, median_nearest_neighbour_distance, radius_concern,
    radius_from_spacing, AutoRadius, RadiusConcern, BULK_COUNT_QUANTILE, BULK_PROBE_RADIUS,
    BULK_SAMPLE, PLAUSIBLE_RADIUS_PER_SPACING, RADIUS_PER_SPACING,
};

/// Re-export of the linear-algebra crate used in public signatures.
pub use nalgebra;
