#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)] // no output, no files: see clippy.toml
//! Feature classification and resampling of boundary particles (Sandim, Oe, Cedrim, Pagliosa &
//! Paiva, Computers & Graphics 2019; thesis Sec. 2.6).
//!
//! Thin features (droplets, ligaments, single-layer sheets) make surface reconstruction miss
//! parts of the fluid. Each boundary particle is labelled from the spectrum of its
//! neighbourhood covariance, and feature particles are replaced by a few particles that
//! thicken the feature.
//!
//! # Classification (thesis Eq. 2.4 and 2.5)
//! For a boundary particle `i`, `N_i` is `i` together with the other particles within
//! `neighbourhood · r` (default `2r`, the detection neighbourhood; the thesis leaves `N_i`
//! open). Its covariance `C_i = 1/|N_i| Σ (x_j − x̄)(x_j − x̄)ᵀ` (Eq. 2.4) has eigenvalues
//! `σ_1 <= … <= σ_D` with eigenvectors `u_1, …, u_D`. With `K = 4` and `α = 0.2` (the thesis's
//! values), in 3D (Eq. 2.5):
//!
//! | label | name | condition |
//! |---|---|---|
//! | 0 | droplet | `|N_i| < K` |
//! | 1 | ligament | `σ_2 <= α σ_3` (one dominant direction) |
//! | 2 | thin sheet | `σ_1 <= α σ_3 < σ_2` (one thin direction) |
//! | 3 | regular | `σ_1 > α σ_3` |
//!
//! In 2D there is a single thin-feature class: a filament of particles (`σ_1 <= α σ_2`) is a
//! ligament (label 1); label 2 does not occur.
//!
//! # Resampling
//! A feature particle is replaced by new particles at `x_i ± shift·r·d` (default
//! `shift = 0.5`), along the thin directions `d`, which is what thickens the feature:
//! - droplet: `d` runs over the standard basis (6 particles in 3D, 4 in 2D; the thesis: "when
//!   ℓ = 0 we can't use the eigenvectors");
//! - ligament: `d ∈ {u_1, u_2}` in 3D (4 particles), `d = u_1` in 2D (2 particles);
//! - sheet: `d = u_1`, the sheet's normal (2 particles).
//!
//! A regular boundary particle is kept and moved by `shift·r` along its outward normal, so
//! that the surface stays continuous with the thickened features (thesis: "shifting the
//! non-resampled boundary particles by a factor of 0.5r in the direction of their normal
//! vectors"). The text does not say which normal: we use `n_i = (x_i − x̄_i)/|x_i − x̄_i|`,
//! pointing from the neighbourhood's centroid to the particle (away from the fluid); when
//! `|x_i − x̄_i| <= 1e-9·r` the direction is undefined and the particle is not moved.
//! Interior particles are kept unchanged.
//!
//! # Example
//! ```
//! use boundary_core::{Labels, ParticleSet, Radius};
//! use boundary_resample::{resample, Feature, ResampleConfig};
//!
//! // A lone particle is a droplet: it becomes 4 particles in 2D.
//! let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0]]).unwrap();
//! let out = resample(&set, Radius::new(0.1).unwrap(), &Labels::new(vec![true]), &ResampleConfig::default()).unwrap();
//! assert_eq!(out.set.len(), 4);
//! assert!(out.feature.iter().all(|&f| f == Feature::Droplet.code()));
//! ```

use boundary_core::{CoreError, Labels, NeighbourGrid, ParticleSet, Point, Radius};
use boundary_core::{Dim, SupportedDim};
use nalgebra::{Matrix2, Matrix3, SMatrix, SymmetricEigen};
use rayon::prelude::*;
use thiserror::Error;

/// Feature label of a boundary particle (thesis Eq. 2.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Feature {
    /// Fewer than `K` particles in the neighbourhood.
    Droplet,
    /// One dominant direction.
    Ligament,
    /// One thin direction (3D only).
    Sheet,
    /// A regular boundary particle.
    Regular,
}

impl Feature {
    /// The thesis's code: 0 droplet, 1 ligament, 2 sheet, 3 regular.
    pub fn code(self) -> i8 {
        match self {
            Feature::Droplet => 0,
            Feature::Ligament => 1,
            Feature::Sheet => 2,
            Feature::Regular => 3,
        }
    }
}

/// Code written for interior particles in the `feature` attribute.
pub const INTERIOR_CODE: i8 = -1;

/// Parameters, with the thesis's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct ResampleConfig {
    /// `K`: fewer neighbours than this (the particle included) make a droplet. Default 4.
    pub k: usize,
    /// `α`: eigenvalue ratio below which a direction counts as thin. Default 0.2.
    pub alpha: f64,
    /// Shift of the new particles and of the regular boundary particles, in units of `r`.
    /// Default 0.5.
    pub shift: f64,
    /// Radius of the neighbourhood `N_i`, in units of `r`. Default 2.
    pub neighbourhood: f64,
}

impl Default for ResampleConfig {
    fn default() -> Self {
        ResampleConfig {
            k: 4,
            alpha: 0.2,
            shift: 0.5,
            neighbourhood: 2.0,
        }
    }
}

/// Why resampling could not run.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum ResampleError {
    /// Invalid core input.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// Labels and particles differ in number.
    #[error("{labels} labels for {particles} particles")]
    LabelCount {
        /// Number of labels.
        labels: usize,
        /// Number of particles.
        particles: usize,
    },
    /// A parameter is out of range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// Why.
        reason: &'static str,
    },
}

/// The resampled particle set.
#[derive(Debug, Clone, PartialEq)]
pub struct Resampled<const D: usize> {
    /// All particles: interior ones unchanged, regular boundary ones shifted, feature ones
    /// replaced.
    pub set: ParticleSet<D>,
    /// Per output particle: [`INTERIOR_CODE`] or the [`Feature::code`] of the particle it
    /// comes from.
    pub feature: Vec<i8>,
    /// Per output particle: the input index it comes from.
    pub source: Vec<usize>,
}

/// Per-particle classification: `None` for interior particles.
#[derive(Debug, Clone, PartialEq)]
pub struct Classification<const D: usize> {
    /// Feature of each boundary particle.
    pub feature: Option<Feature>,
    /// Eigenvectors of the covariance, smallest eigenvalue first (columns of `U_i`).
    pub axes: [Point<D>; D],
    /// `x_i − x̄_i`, pointing away from the neighbourhood's centroid.
    pub offset: Point<D>,
}

fn check(config: &ResampleConfig) -> Result<(), ResampleError> {
    let bad = |name, value: f64, reason| {
        Err(ResampleError::InvalidParameter {
            name,
            value,
            reason,
        })
    };
    if !(config.alpha.is_finite() && config.alpha > 0.0 && config.alpha <= 1.0) {
        return bad("alpha", config.alpha, "must be in (0, 1]");
    }
    if !(config.shift.is_finite() && config.shift >= 0.0) {
        return bad("shift", config.shift, "must be finite and >= 0");
    }
    if !(config.neighbourhood.is_finite() && config.neighbourhood > 0.0) {
        return bad(
            "neighbourhood",
            config.neighbourhood,
            "must be finite and > 0",
        );
    }
    Ok(())
}

/// Eigen-decomposition of a symmetric `D × D` matrix: eigenvalues ascending, eigenvectors as
/// unit vectors in the same order.
fn sym_eigen<const D: usize>(c: &SMatrix<f64, D, D>) -> ([f64; D], [Point<D>; D]) {
    let mut pairs: Vec<(f64, Point<D>)> = if D == 2 {
        let e = SymmetricEigen::new(Matrix2::from_fn(|i, j| c[(i, j)]));
        (0..2)
            .map(|k| {
                let v = e.eigenvectors.column(k);
                (e.eigenvalues[k], Point::<D>::from_fn(|a, _| v[a]))
            })
            .collect()
    } else {
        let e = SymmetricEigen::new(Matrix3::from_fn(|i, j| c[(i, j)]));
        (0..3)
            .map(|k| {
                let v = e.eigenvectors.column(k);
                (e.eigenvalues[k], Point::<D>::from_fn(|a, _| v[a]))
            })
            .collect()
    };
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    (
        std::array::from_fn(|k| pairs[k].0.max(0.0)),
        std::array::from_fn(|k| pairs[k].1),
    )
}

/// Classifies every boundary particle (Eq. 2.4–2.5); interior particles get `feature: None`.
pub fn classify<const D: usize>(
    set: &ParticleSet<D>,
    r: Radius,
    boundary: &Labels,
    config: &ResampleConfig,
) -> Result<Vec<Classification<D>>, ResampleError> {
    check(config)?;
    if boundary.len() != set.len() {
        return Err(ResampleError::LabelCount {
            labels: boundary.len(),
            particles: set.len(),
        });
    }
    let reach = config.neighbourhood * r.get();
    let grid = NeighbourGrid::new(set, reach)?;
    let pos = set.positions();
    Ok((0..set.len())
        .into_par_iter()
        .map(|i| {
            let mut members = Vec::new();
            grid.for_each_within(&pos[i], reach, |j, _| members.push(j));
            // Relative to x_i: no precision lost to far offsets.
            let m = members.len() as f64;
            let mean = members
                .iter()
                .fold(Point::<D>::zeros(), |acc, &j| acc + (pos[j] - pos[i]))
                / m;
            let cov = members
                .iter()
                .fold(SMatrix::<f64, D, D>::zeros(), |acc, &j| {
                    let d = pos[j] - pos[i] - mean;
                    acc + d * d.transpose()
                })
                / m;
            let (sigma, axes) = sym_eigen(&cov);
            let feature = boundary.is_boundary(i).then(|| {
                let a = config.alpha;
                if members.len() < config.k {
                    Feature::Droplet
                } else if D == 3 && sigma[1] <= a * sigma[2] {
                    Feature::Ligament
                } else if sigma[0] <= a * sigma[D - 1] {
                    if D == 3 {
                        Feature::Sheet
                    } else {
                        Feature::Ligament
                    }
                } else {
                    Feature::Regular
                }
            });
            Classification {
                feature,
                axes,
                offset: -mean,
            }
        })
        .collect())
}

/// Classifies and resamples (see the crate documentation). Output order: input order, each
/// particle's replacements in place of it.
pub fn resample<const D: usize>(
    set: &ParticleSet<D>,
    r: Radius,
    boundary: &Labels,
    config: &ResampleConfig,
) -> Result<Resampled<D>, ResampleError>
where
    Dim<D>: SupportedDim,
{
    let classes = classify(set, r, boundary, config)?;
    let step = config.shift * r.get();
    let mut points = Vec::with_capacity(set.len());
    let mut feature = Vec::with_capacity(set.len());
    let mut source = Vec::with_capacity(set.len());
    for (i, (p, class)) in set.positions().iter().zip(&classes).enumerate() {
        let mut push = |x: Point<D>, code: i8| {
            points.push(x);
            feature.push(code);
            source.push(i);
        };
        let Some(f) = class.feature else {
            push(*p, INTERIOR_CODE);
            continue;
        };
        let directions: Vec<Point<D>> = match f {
            Feature::Droplet => (0..D)
                .map(|k| Point::<D>::from_fn(|a, _| if a == k { 1.0 } else { 0.0 }))
                .collect(),
            Feature::Ligament => class.axes[..D - 1].to_vec(),
            Feature::Sheet => vec![class.axes[0]],
            Feature::Regular => {
                let len = class.offset.norm();
                let moved = if len > 1e-9 * r.get() {
                    p + class.offset * (step / len)
                } else {
                    *p
                };
                push(moved, f.code());
                continue;
            }
        };
        for d in directions {
            push(p + d * step, f.code());
            push(p - d * step, f.code());
        }
    }
    Ok(Resampled {
        set: ParticleSet::new(points)?,
        feature,
        source,
    })
}
