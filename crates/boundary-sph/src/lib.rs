#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! The small SPH toolbox shared by the SPH-based boundary detectors (`marrone`, `muller`, and
//! the SVM features): smoothing kernels, summation-density volumes and the kernel sums of one
//! particle.
//!
//! # Conventions
//! - **Kernels** ([`Kernel`]): Wendland C2 and the cubic spline, radial, support radius `2h`
//!   ([`SUPPORT_FACTOR`]), normalised in 2D and 3D (`∫ W dV = 1`). [`SphKernel`] holds one at a
//!   fixed `h` with value, `dW/dr` and gradient.
//! - **Gradients** are taken at the first index: `∇W_ij = ∇_i W(|x_i − x_j|)`, which points
//!   from `x_i` towards `x_j`.
//! - **Volumes** come from the summation density with a uniform mass `m`:
//!   `ρ_i = Σ_j m W_ij` (`j = i` included), `V_i = m/ρ_i = 1/Σ_j W_ij`. The mass cancels, so
//!   the detectors need positions only.
//! - **Sums** ([`LocalSums`], from [`SphContext::local_sums`]): the Shepard sum
//!   `Σ_j V_j W_ij`, the gradient of unity `Σ_j V_j ∇W_ij`, and the renormalisation matrix
//!   `B_i = Σ_j V_j (x_j − x_i) ⊗ ∇W_ij`. Inside a uniform particle distribution they are
//!   close to 1, 0 and the identity (tested on lattices); near a free surface the Shepard sum
//!   drops, the gradient grows and `B_i` loses rank along the normal.
//! - **Every particle at once** ([`SphContext::pair_sums`]): a sum over the neighbours of
//!   every particle, each pair's distance and kernel evaluated once for both of its particles,
//!   with the numbers of each particle's own pass ([`SphContext::particle_sums`]) bit for bit;
//!   [`SphContext::gradients_h`] and [`SphContext::divergences_of_position`] are built on it.
//!   A criterion classifies from it by overriding [`SphCriterion::classify_all`].
//! - **Units of `h`.** Every sum of [`SphContext`] is computed with distances divided by `h`
//!   and the kernel without its `h^-D` ([`SphKernel::reduced_value`],
//!   [`SphKernel::reduced_gradient_weight`]), so the dimensionless results (Shepard sum,
//!   [`LocalSums::gradient_h`] `= ∇c·h`, `B_i`, [`SphContext::reduced_volumes`]) are the same
//!   for a scene and its copy scaled by any `s` with `h` scaled alike (tested from 1e-150 to
//!   1e150; beyond that the neighbour grid's squared distances leave `f64`). The physical
//!   values (`SphKernel::value`, [`SphContext::volumes`], [`LocalSums::gradient`]) carry
//!   `h^-D` and are not finite for extreme `h`; the detectors use the reduced ones.
//! - **Linear algebra** ([`SymmetricEigen`]): eigen-decomposition of the `D × D` symmetric
//!   matrices, for the smallest eigenvalue of `B_i` and solves with it.
//! - **The frame** ([`frame`]): what an SPH-sum detector shares with the others. A method
//!   crate writes its criterion ([`SphCriterion`]: the verdict of one particle from the sums
//!   of a [`SphContext`]) and its listing ([`SphMethod`]); [`impl_sph_detector!`] writes its
//!   `boundary_core::Method`, as every method has one: the refusal of per-particle radii, the
//!   kernel at `h = h_over_r · r` ([`Smoothing`], whose `kernel` and `h_over_r` every method
//!   checks and lists alike), the parallel loop, the owned particles of `detect_owned` (walls
//!   and periodic images of a domain enter the sums as ghosts) and a halo of two supports.
//!
//! # A criterion on the frame
//! ```
//! use boundary_core::{BoundaryDetector, Params, ParticleSet, Radius};
//! use boundary_sph::{Smoothing, SphContext, SphCriterion, SphMethod, Verdict};
//!
//! /// Boundary iff fewer than `min` other particles lie within the kernel support.
//! #[derive(Debug)]
//! struct Crowd {
//!     min: usize,
//!     smoothing: Smoothing,
//! }
//!
//! impl SphCriterion for Crowd {
//!     const METHOD: &'static str = "crowd";
//!     const MARGIN: bool = true;
//!     fn smoothing(&self) -> Smoothing {
//!         self.smoothing
//!     }
//!     fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict {
//!         let n = ctx.local_sums(i).neighbours as f64;
//!         Verdict { boundary: n < self.min as f64, margin: self.min as f64 - n }
//!     }
//! }
//!
//! impl SphMethod for Crowd {
//!     const RADII_REFUSAL: &'static str = "a neighbour count assumes one support";
//!     const SOLID_REFUSAL: &'static str = "a half-space is no particle";
//!     fn param_list(&self) -> Params {
//!         Params(self.smoothing.param_infos().to_vec())
//!     }
//! }
//!
//! boundary_sph::impl_sph_detector!(Crowd);
//!
//! // A 9 x 9 lattice at h = r = 1.3 (support 2.6): a corner has 7 neighbours, the centre 20.
//! let rows: Vec<[f64; 2]> = (0..81).map(|k| [(k % 9) as f64, (k / 9) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let d = Crowd { min: 12, smoothing: Smoothing::default() };
//! let labels = d.detect_2d(&set, Radius::new(1.3).unwrap()).unwrap().labels;
//! assert!(labels.is_boundary(0) && !labels.is_boundary(40));
//! assert_eq!(d.to_string(), "crowd (kernel=wendland, h_over_r=1)");
//! ```
//!
//! # Example: the sums
//! ```
//! use boundary_core::ParticleSet;
//! use boundary_sph::{Kernel, SphContext, SphKernel, SymmetricEigen};
//!
//! // A 9 x 9 square lattice of spacing 1 with h = 1.3: the centre particle (index 40) has
//! // B ≈ I, the corner particle (index 0) a rank-deficient-looking B.
//! let rows: Vec<[f64; 2]> = (0..81).map(|k| [(k % 9) as f64, (k / 9) as f64]).collect();
//! let set = ParticleSet::from_rows(&rows).unwrap();
//! let ctx = SphContext::new(&set, SphKernel::new(Kernel::WendlandC2, 1.3)).unwrap();
//! let centre = ctx.local_sums(40);
//! assert!((centre.shepard - 1.0).abs() < 0.05);
//! let lambda = SymmetricEigen::new(&centre.renormalisation).min_value();
//! assert!((lambda - 1.0).abs() < 0.05);
//! let corner = SymmetricEigen::new(&ctx.local_sums(0).renormalisation).min_value();
//! assert!(corner < 0.5);
//! ```

pub mod frame;
mod kernel;
mod linalg;
mod sums;

pub use frame::{Smoothing, SphCriterion, SphMethod, Verdict};
pub use kernel::{Kernel, SphKernel, UnknownKernel, SUPPORT_FACTOR};
pub use linalg::SymmetricEigen;
pub use sums::{colour_field_normals, number_density, summation_density, LocalSums, SphContext};

#[doc(hidden)]
/// For [`impl_sph_detector!`]: the core types its expansion names.
pub use boundary_core as __core;
