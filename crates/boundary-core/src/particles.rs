use crate::CoreError;
use nalgebra::SVector;

/// A position in `D` dimensions.
pub type Point<const D: usize> = SVector<f64, D>;

/// The resolution `r` of a particle set: positive, finite and within
/// [`Radius::MIN`]`..=`[`Radius::MAX`] by construction.
///
/// The range keeps every squared distance the detectors compare with `4r²` (and every
/// power `r^D` a feature or kernel may form) a normal `f64`, so that a scene scaled by any
/// power of two within it gets the labels of the unscaled scene (tested for every method).
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct Radius(f64);

impl Radius {
    /// The smallest supported resolution.
    pub const MIN: f64 = 1e-100;
    /// The largest supported resolution.
    pub const MAX: f64 = 1e100;

    /// Validates `r`: finite, strictly positive, and within [`Radius::MIN`]`..=`[`Radius::MAX`].
    pub fn new(r: f64) -> Result<Self, CoreError> {
        if !(r.is_finite() && r > 0.0) {
            Err(CoreError::InvalidRadius(r))
        } else if !(Self::MIN..=Self::MAX).contains(&r) {
            Err(CoreError::RadiusOutOfRange(r))
        } else {
            Ok(Radius(r))
        }
    }

    /// The value of `r`.
    pub fn get(self) -> f64 {
        self.0
    }
}

impl std::fmt::Display for Radius {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// Particle positions in `D` dimensions (`D` = 2 or 3), every coordinate finite, and
/// optionally a radius per particle (adaptive resolution).
///
/// The empty set is valid. Duplicated positions are allowed (they are part of the problem:
/// coincident duplicates do not cover each other). At most `u32::MAX` particles, so that
/// indices fit the compact neighbour structures.
///
/// # Per-particle radii
/// A set built with [`ParticleSet::with_radii`] gives particle `i` its own radius factor
/// `s_i`; a detector called with resolution `r` then uses `r_i = r·s_i` (rounded once), so
/// `r = 1` takes the radii as they are and any other `r` scales them all (the CLI's
/// `--radius-scale`). Particle `i` is interior iff `S_i` (radius `r_i`) is covered by the
/// closed balls of radius `r_j` of the other particles (those with `|p_i − p_j| <= r_i + r_j`;
/// coincident duplicates still do not cover each other, whatever their radii). With every
/// `s_i = 1` this is the uniform definition at `r`. A set without radii is the uniform case
/// and costs nothing extra. Methods that do not support per-particle radii return
/// [`crate::DetectError::PerParticleRadii`].
///
/// `D` is 2 or 3: every constructor requires `Dim<D>: SupportedDim`, so no set of another
/// dimension can be built, and the methods without that bound only ever see sets of 2 or 3.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleSet<const D: usize> {
    pub(crate) positions: Vec<Point<D>>,
    pub(crate) radii: Option<Vec<f64>>,
}

/// The marker of a dimension `D`, for the bound [`SupportedDim`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dim<const D: usize>;

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Dim<2> {}
    impl Sealed for super::Dim<3> {}
}

/// The dimensions a [`ParticleSet`] can have: implemented for `Dim<2>` and `Dim<3>` only, and
/// sealed. The constructors of a set ([`ParticleSet::new`], [`ParticleSet::from_rows`]) and
/// [`ParticleSet::to_any`] require `Dim<D>: SupportedDim`, so no set of another dimension
/// can exist; code generic over `D` that builds sets states the same bound.
///
/// ```compile_fail
/// use boundary_core::ParticleSet;
/// // No 4D (or 1D) set can be built: `Dim<4>` is not a `SupportedDim`.
/// let set = ParticleSet::<4>::from_rows(&[[0.0, 0.0, 0.0, 0.0]]);
/// ```
pub trait SupportedDim: sealed::Sealed {}

impl SupportedDim for Dim<2> {}
impl SupportedDim for Dim<3> {}

impl<const D: usize> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    /// Validates the positions: every coordinate must be finite. The error names the first
    /// offending particle by its index in input order.
    pub fn new(positions: Vec<Point<D>>) -> Result<Self, CoreError> {
        if positions.len() > u32::MAX as usize {
            return Err(CoreError::TooManyParticles(positions.len()));
        }
        // One branch-free pass (sets are validated on every call of a time loop); the
        // offending particle is looked up only when there is one.
        let finite = positions
            .iter()
            .fold(true, |ok, p| p.iter().fold(ok, |ok, v| ok & v.is_finite()));
        if !finite {
            for (index, p) in positions.iter().enumerate() {
                for axis in 0..D {
                    let value = p[axis];
                    if !value.is_finite() {
                        return Err(CoreError::NonFiniteCoordinate { index, axis, value });
                    }
                }
            }
        }
        Ok(ParticleSet {
            positions,
            radii: None,
        })
    }

    /// Builds a set from coordinate rows, validated as in [`ParticleSet::new`].
    pub fn from_rows(rows: &[[f64; D]]) -> Result<Self, CoreError> {
        Self::new(rows.iter().map(|row| Point::<D>::from(*row)).collect())
    }

    /// A copy as an [`AnyParticleSet`], for code generic over `D` that calls a
    /// [`crate::BoundaryDetector`] (whose methods are per dimension). Costs one copy of the
    /// positions.
    pub fn to_any(&self) -> AnyParticleSet {
        let copy = |k: usize| self.positions.iter().map(move |p| p[k]);
        match D {
            2 => AnyParticleSet::D2(ParticleSet {
                positions: copy(0)
                    .zip(copy(1))
                    .map(|(x, y)| Point::<2>::new(x, y))
                    .collect(),
                radii: self.radii.clone(),
            }),
            _ => AnyParticleSet::D3(ParticleSet {
                positions: self
                    .positions
                    .iter()
                    .map(|p| Point::<3>::new(p[0], p[1], p[2]))
                    .collect(),
                radii: self.radii.clone(),
            }),
        }
    }
}

impl<const D: usize> ParticleSet<D> {
    /// Gives every particle its own radius factor `s_i` (see the type's docs): one per
    /// particle, each finite, positive and within [`Radius::MIN`]`..=`[`Radius::MAX`]. The
    /// error names the first offending particle by its index in input order.
    ///
    /// ```
    /// use boundary_core::ParticleSet;
    ///
    /// let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0]]).unwrap();
    /// let set = set.with_radii(vec![0.5, 1.0]).unwrap();
    /// assert_eq!(set.radii(), Some(&[0.5, 1.0][..]));
    /// let bad = ParticleSet::<2>::from_rows(&[[0.0, 0.0]]).unwrap().with_radii(vec![-1.0]);
    /// assert_eq!(bad.unwrap_err().to_string(), "particle 0: radius must be positive and finite, got -1");
    /// ```
    pub fn with_radii(mut self, radii: Vec<f64>) -> Result<Self, CoreError> {
        if radii.len() != self.positions.len() {
            return Err(CoreError::RadiiLengthMismatch {
                particles: self.positions.len(),
                radii: radii.len(),
            });
        }
        for (index, &value) in radii.iter().enumerate() {
            check_particle_radius(index, value)?;
        }
        self.radii = Some(radii);
        Ok(self)
    }

    /// The per-particle radius factors, if the set has them.
    pub fn radii(&self) -> Option<&[f64]> {
        self.radii.as_deref()
    }

    /// Removes the per-particle radii: the uniform set of the same positions.
    pub fn without_radii(mut self) -> Self {
        self.radii = None;
        self
    }

    /// The radius of every particle at resolution `r`, `r_i = r·s_i`, or `None` for a set
    /// without radii (every particle has radius `r`). Fails, naming the particle, when a
    /// product leaves [`Radius::MIN`]`..=`[`Radius::MAX`].
    pub fn resolved_radii(&self, r: Radius) -> Result<Option<Vec<f64>>, CoreError> {
        let Some(radii) = &self.radii else {
            return Ok(None);
        };
        radii
            .iter()
            .enumerate()
            .map(|(index, &s)| {
                let value = r.get() * s;
                check_particle_radius(index, value).map(|()| value)
            })
            .collect::<Result<Vec<f64>, CoreError>>()
            .map(Some)
    }

    /// A set of some of the particles (`indices`, in that order, repeats allowed), keeping
    /// their radii. Panics if an index is out of range.
    pub fn subset(&self, indices: &[usize]) -> ParticleSet<D> {
        ParticleSet {
            positions: indices.iter().map(|&i| self.positions[i]).collect(),
            radii: self
                .radii
                .as_ref()
                .map(|s| indices.iter().map(|&i| s[i]).collect()),
        }
    }

    /// The positions, in input order.
    pub fn positions(&self) -> &[Point<D>] {
        &self.positions
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether the set holds no particle.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The axis-aligned bounding box `(min, max)`, or `None` for an empty set.
    pub fn bounding_box(&self) -> Option<(Point<D>, Point<D>)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p))),
        )
    }

    /// Consumes the set, returning the positions (the radii, if any, are dropped).
    pub fn into_positions(self) -> Vec<Point<D>> {
        self.positions
    }
}

impl ParticleSet<3> {
    /// Whether the set is flat: `None` when its particles span all three dimensions (or
    /// when it has fewer than two particles), else how they fail to.
    ///
    /// A flat 3D set is a 2D scene stored with a constant third coordinate: read as 3D,
    /// every particle is boundary (the sphere of each sticks out of the plane), so the
    /// command line and the bindings refuse it and ask for the 2D set. The axis reported is
    /// the one a 2D reading drops (`boundary_io::ReadOptions::dim`): z, else y, else x.
    ///
    /// ```
    /// use boundary_core::{Flatness, ParticleSet};
    ///
    /// let flat = ParticleSet::<3>::from_rows(&[[0.0, 1.0, 0.0], [1.0, 1.0, 2.0]]).unwrap();
    /// assert_eq!(flat.flatness(), Some(Flatness::Plane { axis: 1, value: 1.0, n: 2 }));
    /// assert_eq!(
    ///     flat.flatness().unwrap().to_string(),
    ///     "all 2 particles have y = 1"
    /// );
    /// let solid = ParticleSet::<3>::from_rows(&[[0.0; 3], [1.0, 1.0, 1.0]]).unwrap();
    /// assert_eq!(solid.flatness(), None);
    /// ```
    pub fn flatness(&self) -> Option<Flatness> {
        let (first, rest) = self.positions.split_first()?;
        if rest.is_empty() {
            return None;
        }
        let constant: [bool; 3] =
            std::array::from_fn(|axis| rest.iter().all(|p| p[axis] == first[axis]));
        let n = self.positions.len();
        if constant.iter().all(|&c| c) {
            return Some(Flatness::Point { point: *first, n });
        }
        let axis = [2, 1, 0].into_iter().find(|&axis| constant[axis])?;
        Some(Flatness::Plane {
            axis,
            value: first[axis],
            n,
        })
    }
}

/// How a 3D set fails to span three dimensions ([`ParticleSet::flatness`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Flatness {
    /// All `n` particles have the coordinate `value` along `axis` (0 x, 1 y, 2 z).
    Plane {
        /// The constant axis: z if it is, else y, else x.
        axis: usize,
        /// The coordinate every particle has along it.
        value: f64,
        /// The number of particles (at least 2).
        n: usize,
    },
    /// All `n` particles are at one position.
    Point {
        /// The position.
        point: Point<3>,
        /// The number of particles (at least 2).
        n: usize,
    },
}

impl Flatness {
    /// The name of axis `axis`: `"x"`, `"y"` or `"z"`.
    pub fn axis_name(axis: usize) -> &'static str {
        ["x", "y", "z"].get(axis).copied().unwrap_or("?")
    }
}

impl std::fmt::Display for Flatness {
    /// `all 100 particles have z = 0` or `all 5 particles are at (1, 2, 3)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Flatness::Plane { axis, value, n } => {
                write!(
                    f,
                    "all {n} particles have {} = {value}",
                    Self::axis_name(*axis)
                )
            }
            Flatness::Point { point, n } => write!(
                f,
                "all {n} particles are at ({}, {}, {})",
                point.x, point.y, point.z
            ),
        }
    }
}

/// A particle's radius must be finite, positive and within the range of [`Radius`].
fn check_particle_radius(index: usize, value: f64) -> Result<(), CoreError> {
    if !(value.is_finite() && value > 0.0) {
        Err(CoreError::InvalidParticleRadius { index, value })
    } else if !(Radius::MIN..=Radius::MAX).contains(&value) {
        Err(CoreError::ParticleRadiusOutOfRange { index, value })
    } else {
        Ok(())
    }
}

/// A particle set whose dimension is known only at run time (files, the CLI).
#[derive(Debug, Clone, PartialEq)]
pub enum AnyParticleSet {
    /// A 2D set.
    D2(ParticleSet<2>),
    /// A 3D set.
    D3(ParticleSet<3>),
}

impl AnyParticleSet {
    /// The spatial dimension, 2 or 3.
    pub fn dim(&self) -> usize {
        match self {
            AnyParticleSet::D2(_) => 2,
            AnyParticleSet::D3(_) => 3,
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        match self {
            AnyParticleSet::D2(s) => s.len(),
            AnyParticleSet::D3(s) => s.len(),
        }
    }

    /// Whether the set holds no particle.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The per-particle radius factors, if the set has them (see [`ParticleSet::with_radii`]).
    pub fn radii(&self) -> Option<&[f64]> {
        match self {
            AnyParticleSet::D2(s) => s.radii(),
            AnyParticleSet::D3(s) => s.radii(),
        }
    }

    /// Gives every particle its own radius factor ([`ParticleSet::with_radii`]).
    pub fn with_radii(self, radii: Vec<f64>) -> Result<Self, CoreError> {
        Ok(match self {
            AnyParticleSet::D2(s) => AnyParticleSet::D2(s.with_radii(radii)?),
            AnyParticleSet::D3(s) => AnyParticleSet::D3(s.with_radii(radii)?),
        })
    }

    /// [`ParticleSet::flatness`] of a 3D set; `None` for a 2D set.
    pub fn flatness(&self) -> Option<Flatness> {
        match self {
            AnyParticleSet::D2(_) => None,
            AnyParticleSet::D3(s) => s.flatness(),
        }
    }

    /// Coordinates of particle `i` as a slice of length `dim()`.
    pub fn coords(&self, i: usize) -> &[f64] {
        match self {
            AnyParticleSet::D2(s) => s.positions()[i].as_slice(),
            AnyParticleSet::D3(s) => s.positions()[i].as_slice(),
        }
    }
}

impl From<ParticleSet<2>> for AnyParticleSet {
    fn from(s: ParticleSet<2>) -> Self {
        AnyParticleSet::D2(s)
    }
}

impl From<ParticleSet<3>> for AnyParticleSet {
    fn from(s: ParticleSet<3>) -> Self {
        AnyParticleSet::D3(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_rejects_non_positive_and_non_finite() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -0.0] {
            assert_eq!(
                Radius::new(bad).map_err(|e| matches!(e, CoreError::InvalidRadius(_))),
                Err(true),
                "{bad}"
            );
        }
        for bad in [1e-300, 0.99e-100, 1.01e100, 1e300] {
            assert_eq!(
                Radius::new(bad),
                Err(CoreError::RadiusOutOfRange(bad)),
                "{bad}"
            );
        }
        assert!(Radius::new(1e300)
            .unwrap_err()
            .to_string()
            .contains("supported range 1e-100..=1e100"));
        for good in [Radius::MIN, 1e-9, 1.0, 1e9, Radius::MAX] {
            assert_eq!(Radius::new(good).map(Radius::get), Ok(good));
        }
    }

    #[test]
    fn non_finite_coordinate_names_particle_and_axis() {
        let err = ParticleSet::<3>::from_rows(&[[0.0; 3], [1.0, 2.0, 3.0], [0.0, f64::NAN, 0.0]])
            .unwrap_err();
        assert!(matches!(
            err,
            CoreError::NonFiniteCoordinate {
                index: 2,
                axis: 1,
                ..
            }
        ));
        assert!(err.to_string().contains("particle 2"));
        let err = ParticleSet::<2>::from_rows(&[[f64::NEG_INFINITY, 0.0]]).unwrap_err();
        assert!(matches!(
            err,
            CoreError::NonFiniteCoordinate {
                index: 0,
                axis: 0,
                ..
            }
        ));
    }

    #[test]
    fn empty_set_is_valid_and_has_no_bounding_box() {
        let s = ParticleSet::<2>::new(Vec::new()).unwrap();
        assert!(s.is_empty());
        assert_eq!(s.bounding_box(), None);
    }

    #[test]
    fn to_any_keeps_dimension_and_coordinates() {
        let s = ParticleSet::<2>::from_rows(&[[1.0, 2.0], [3.0, 4.0]]).unwrap();
        let a = s.to_any();
        assert_eq!((a.dim(), a.len()), (2, 2));
        assert_eq!(a.coords(1), &[3.0, 4.0]);
        let s3 = ParticleSet::<3>::from_rows(&[[1.0, 2.0, 3.0]]).unwrap();
        assert_eq!(s3.to_any().coords(0), &[1.0, 2.0, 3.0]);
    }

    #[test]
    fn flatness_names_the_axis_a_2d_reading_drops() {
        let rows = |f: fn(f64, f64) -> [f64; 3]| {
            let rows: Vec<[f64; 3]> = (0..9)
                .map(|k| f(f64::from(k / 3), f64::from(k % 3)))
                .collect();
            ParticleSet::<3>::from_rows(&rows).unwrap()
        };
        let plane = |axis, value| Some(Flatness::Plane { axis, value, n: 9 });
        assert_eq!(rows(|a, b| [a, b, 0.0]).flatness(), plane(2, 0.0));
        assert_eq!(rows(|a, b| [a, -2.5, b]).flatness(), plane(1, -2.5));
        assert_eq!(rows(|a, b| [7.0, a, b]).flatness(), plane(0, 7.0));
        // A line: z is dropped first, as `--dim 2` would.
        assert_eq!(rows(|a, _| [a, 1.0, 1.0]).flatness(), plane(2, 1.0));
        assert_eq!(rows(|a, b| [a, b, a + b]).flatness(), None);
        assert_eq!(
            rows(|_, _| [1.0, 2.0, 3.0]).flatness(),
            Some(Flatness::Point {
                point: Point::<3>::new(1.0, 2.0, 3.0),
                n: 9
            })
        );
        assert_eq!(
            rows(|_, _| [1.0, 2.0, 3.0]).flatness().unwrap().to_string(),
            "all 9 particles are at (1, 2, 3)"
        );
        assert_eq!(
            rows(|a, b| [a, -2.5, b]).flatness().unwrap().to_string(),
            "all 9 particles have y = -2.5"
        );
        // One particle, or none, is not flat.
        assert_eq!(
            ParticleSet::<3>::from_rows(&[[0.0; 3]]).unwrap().flatness(),
            None
        );
        assert_eq!(ParticleSet::<3>::new(Vec::new()).unwrap().flatness(), None);
    }

    #[test]
    fn bounding_box_spans_all_points() {
        let s = ParticleSet::<2>::from_rows(&[[1.0, -2.0], [-3.0, 4.0], [0.5, 0.5]]).unwrap();
        let (lo, hi) = s.bounding_box().unwrap();
        assert_eq!((lo.x, lo.y, hi.x, hi.y), (-3.0, -2.0, 1.0, 4.0));
    }
}
