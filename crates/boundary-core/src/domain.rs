//! Simulations as solvers see them: wall particles, solid regions, periodic axes and phases.
//!
//! # Definition
//! A [`Domain`] extends the definition of the crate docs. The particles are of two kinds:
//! - **classified**: the particle set passed to the detector (the fluid);
//! - **covering-only**: the walls ([`Domain::with_walls`]) and the periodic images
//!   ([`Domain::with_periodic`]) of every particle. They cover, and get no label.
//!
//! Particle `i` is **interior** iff every point of its sphere `S_i` that lies outside the
//! solid regions ([`Solids`]: half-spaces, [`HalfSpace`], and in 3D closed triangle meshes,
//! [`SolidMesh`]) is covered by the closed balls of the
//! other particles of both kinds. Coincident duplicates still do not cover each other, walls
//! included. A per-particle radius (see [`crate::ParticleSet::with_radii`]) applies to walls as
//! well; walls without radii have the factor 1 (radius `r`) when the fluid has radii, and the
//! other way round.
//!
//! With phases ([`Domain::with_phases`], one phase number per classified particle), particle
//! `i` of phase `k` is on the **free surface** when the test above fails, and on an
//! **interface** when it holds but fails again once only the particles of phase `k` (their
//! images, and the walls) may cover.
//!
//! # Policy
//! - **Solid regions are closed.** `y<0` is the solid `{y <= 0}` (the `<` says which side),
//!   so a point of `S_i` on the solid's surface counts as covered, as a point on the sphere of
//!   a ball does: a tie is interior. A classified particle may lie inside a solid (a solver's
//!   particle that penetrated a wall); the definition applies unchanged (a sphere wholly inside
//!   the solid is interior).
//! - **Walls** are filtered to those within the reach of the fluid's bounding box (the
//!   method's [`crate::BoundaryDetector::halo_width`]): the others cannot change a label.
//! - **Periodic images** are the float positions `p ± (max − min)` along each periodic axis
//!   (and their combinations for two or three axes), of the fluid and of the walls, kept within
//!   the reach of the box. The labels are exact for those images. Every particle must lie in
//!   `[min, max]` on a periodic axis, and the period `max − min` must be at least the method's
//!   reach (else an image of an image would be needed); both are checked, and the error names
//!   the particle or the period. An axis cannot be both periodic and bounded by a solid.
//! - **Solid meshes** ([`Domain::with_solid_mesh`], [`SolidMesh`]) are 3D only, closed like
//!   the half-spaces, and not repeated across a period: with a periodic axis every mesh must
//!   lie at least the reach inside its range (checked). A method that cannot honour a mesh
//!   refuses it ([`crate::BoundaryDetector::honours_solid_meshes`]) rather than ignore it.
//!   The geometry of a mesh is known to its [`SolidMesh::rounding`] only, so a method that
//!   honours meshes states its own tolerance (`exact`: see its crate docs).
//!
//! ```
//! use boundary_core::{AnyParticleSet, Domain, HalfSpace, ParticleSet, Radius};
//! # use boundary_core::{BoundaryDetector, Capabilities, Detection, DetectError, Dim, Job, Labels, Method, Params, SupportedDim};
//! # #[derive(Debug)] struct Lonely;
//! # impl Method for Lonely {
//! #     const NAME: &'static str = "lonely";
//! #     fn describe(&self) -> Params { Params::default() }
//! #     fn capabilities(&self) -> Capabilities { Capabilities::DEFAULT }
//! #     fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError> where Dim<D>: SupportedDim { Ok(Detection { labels: Labels::new(vec![true; job.owned]), margin: None }) }
//! # }
//! // A column of fluid on a floor of wall particles, and the floor's solid below y = -0.5.
//! let fluid = ParticleSet::<2>::from_rows(&[[0.0, 0.0], [0.0, 1.0]]).unwrap();
//! let walls = ParticleSet::<2>::from_rows(&[[-1.0, -1.0], [0.0, -1.0], [1.0, -1.0]]).unwrap();
//! let domain = Domain::new()
//!     .with_walls(walls.into())
//!     .with_solid(HalfSpace::parse("y<-0.5").unwrap());
//! let r = Radius::new(0.8).unwrap();
//! // `exact` and the other methods take it through the trait:
//! let result = Lonely.detect_in(&AnyParticleSet::from(fluid), &domain, r);
//! // (`Lonely` cannot honour a solid and says so.)
//! assert!(result.unwrap_err().to_string().contains("solid"));
//! ```

use crate::{AnyParticleSet, SolidMesh};
use std::fmt;
use std::sync::Arc;

/// The axis names of messages and of [`HalfSpace::parse`].
pub(crate) const AXES: [char; 3] = ['x', 'y', 'z'];

/// An axis-aligned solid half-space: `{x_axis <= value}` (`x<value`) or `{x_axis >= value}`
/// (`x>value`). Closed (module docs, *Policy*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSpace {
    pub(crate) axis: usize,
    pub(crate) solid_below: bool,
    pub(crate) value: f64,
}

impl HalfSpace {
    /// The solid `{x_axis <= value}` (`solid_below`) or `{x_axis >= value}`. `axis` is 0, 1
    /// or 2 and `value` finite.
    pub fn new(axis: usize, solid_below: bool, value: f64) -> Result<Self, DomainError> {
        if axis > 2 {
            return Err(DomainError::new(format!(
                "solid half-space: axis {axis} (use 0, 1 or 2: x, y or z)"
            )));
        }
        if !value.is_finite() {
            return Err(DomainError::new(format!(
                "solid half-space: the bound {value} is not finite"
            )));
        }
        Ok(HalfSpace {
            axis,
            solid_below,
            value,
        })
    }

    /// Parses `x<1.5`, `y > -0.2`, `z<0` (an axis `x|y|z`, `<` or `>`, a number; spaces
    /// allowed): the solid lies on the side the comparison names.
    ///
    /// ```
    /// use boundary_core::HalfSpace;
    /// let floor = HalfSpace::parse("y < 0").unwrap();
    /// assert_eq!((floor.axis(), floor.solid_below(), floor.value()), (1, true, 0.0));
    /// assert_eq!(floor.to_string(), "y<0");
    /// assert!(HalfSpace::parse("w<0").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Self, DomainError> {
        let bad = |why: &str| {
            DomainError::new(format!(
                "solid '{text}': {why} (expected an axis x|y|z, '<' or '>', and a number, \
                 e.g. 'y<0')"
            ))
        };
        let compact: String = text.chars().filter(|c| !c.is_whitespace()).collect();
        let mut chars = compact.chars();
        let axis = match chars.next() {
            Some(c) => AXES
                .iter()
                .position(|&a| a == c.to_ascii_lowercase())
                .ok_or_else(|| bad("unknown axis"))?,
            None => return Err(bad("empty")),
        };
        let solid_below = match chars.next() {
            Some('<') => true,
            Some('>') => false,
            _ => return Err(bad("missing '<' or '>'")),
        };
        let rest: String = chars.collect();
        let value: f64 = rest.parse().map_err(|_| bad("the bound is not a number"))?;
        HalfSpace::new(axis, solid_below, value).map_err(|e| bad(&e.message))
    }

    /// The axis (0 = x, 1 = y, 2 = z).
    pub fn axis(&self) -> usize {
        self.axis
    }

    /// Whether the solid lies below the bound (`x<value`).
    pub fn solid_below(&self) -> bool {
        self.solid_below
    }

    /// The bound.
    pub fn value(&self) -> f64 {
        self.value
    }

    /// Whether the closed solid holds the point `x` (coordinates `x[axis]`).
    pub fn contains(&self, x: &[f64]) -> bool {
        if self.solid_below {
            x[self.axis] <= self.value
        } else {
            x[self.axis] >= self.value
        }
    }

    /// The signed depth of `x` in the fluid, `x_axis − value` for a solid below (`value −
    /// x_axis` above), rounded once: positive outside the solid.
    pub fn fluid_depth(&self, x: &[f64]) -> f64 {
        if self.solid_below {
            x[self.axis] - self.value
        } else {
            self.value - x[self.axis]
        }
    }
}

impl fmt::Display for HalfSpace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let op = if self.solid_below { '<' } else { '>' };
        write!(f, "{}{op}{}", AXES[self.axis], self.value)
    }
}

/// The solid regions of a detection: what covers part of a sphere without being a particle.
/// Empty for a bare particle cloud. Half-spaces ([`HalfSpace`]) in 2D and 3D, and in 3D the
/// insides of closed triangle meshes ([`SolidMesh`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Solids {
    pub(crate) half_spaces: Vec<HalfSpace>,
    pub(crate) meshes: Vec<Arc<SolidMesh>>,
}

impl Solids {
    /// No solid region.
    pub fn new() -> Self {
        Solids::default()
    }

    /// The solid half-spaces.
    pub fn half_spaces(&self) -> &[HalfSpace] {
        &self.half_spaces
    }

    /// The solid meshes (3D only).
    pub fn meshes(&self) -> &[Arc<SolidMesh>] {
        &self.meshes
    }

    /// Whether there is no solid region at all (no half-space and no mesh).
    pub fn is_empty(&self) -> bool {
        self.half_spaces.is_empty() && self.meshes.is_empty()
    }

    /// Adds a half-space.
    pub fn push(&mut self, h: HalfSpace) {
        self.half_spaces.push(h);
    }

    /// Adds a solid mesh.
    pub fn push_mesh(&mut self, mesh: Arc<SolidMesh>) {
        self.meshes.push(mesh);
    }

    /// The same solids without the meshes: what a method that honours half-spaces passes on
    /// once it has dealt with the meshes itself.
    pub fn without_meshes(&self) -> Solids {
        Solids {
            half_spaces: self.half_spaces.clone(),
            meshes: Vec::new(),
        }
    }

    /// Whether the closed ball of radius `radius` around `x` may reach some half-space: its
    /// fluid depth is at most `radius·(1 + 1e-9)` (the slack covers the rounding of the
    /// depth, so a `false` is certain). The particles for which this is `false` cannot see a
    /// half-space, and the detectors that honour solids classify them as without any.
    pub fn half_space_reaches(&self, x: &[f64], radius: f64) -> bool {
        self.half_spaces
            .iter()
            .any(|h| h.fluid_depth(x) <= radius * (1.0 + 1e-9))
    }
}

/// A periodic axis: particles leaving `max` re-enter at `min`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Periodic {
    pub(crate) axis: usize,
    pub(crate) min: f64,
    pub(crate) max: f64,
}

impl Periodic {
    /// The axis `axis` (0, 1, 2) periodic over `[min, max]`, both finite, `min < max`.
    pub fn new(axis: usize, min: f64, max: f64) -> Result<Self, DomainError> {
        if axis > 2 {
            return Err(DomainError::new(format!(
                "periodic axis {axis} (use 0, 1 or 2: x, y or z)"
            )));
        }
        if !(min.is_finite() && max.is_finite() && min < max && (max - min).is_finite()) {
            return Err(DomainError::new(format!(
                "periodic {}: the range {min}..{max} is not finite and increasing",
                AXES[axis]
            )));
        }
        Ok(Periodic { axis, min, max })
    }

    /// Parses `x:MIN:MAX` (e.g. `x:0:1.5`).
    ///
    /// ```
    /// use boundary_core::Periodic;
    /// let p = Periodic::parse("x:0:2.5").unwrap();
    /// assert_eq!((p.axis(), p.min(), p.max(), p.period()), (0, 0.0, 2.5, 2.5));
    /// assert!(Periodic::parse("x:1:0").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Self, DomainError> {
        let bad = |why: &str| {
            DomainError::new(format!(
                "periodic '{text}': {why} (expected AXIS:MIN:MAX, e.g. 'x:0:1.5')"
            ))
        };
        let parts: Vec<&str> = text.split(':').map(str::trim).collect();
        let [axis, min, max] = parts[..] else {
            return Err(bad("not three fields"));
        };
        let axis = match axis.to_ascii_lowercase().as_str() {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return Err(bad("unknown axis")),
        };
        let min: f64 = min.parse().map_err(|_| bad("MIN is not a number"))?;
        let max: f64 = max.parse().map_err(|_| bad("MAX is not a number"))?;
        Periodic::new(axis, min, max).map_err(|e| bad(&e.message))
    }

    /// The axis (0 = x, 1 = y, 2 = z).
    pub fn axis(&self) -> usize {
        self.axis
    }

    /// The lower end of the period.
    pub fn min(&self) -> f64 {
        self.min
    }

    /// The upper end of the period.
    pub fn max(&self) -> f64 {
        self.max
    }

    /// The period `max − min` (rounded once): images are shifted by it.
    pub fn period(&self) -> f64 {
        self.max - self.min
    }
}

impl fmt::Display for Periodic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", AXES[self.axis], self.min, self.max)
    }
}

/// An invalid domain: the message names the option, the particle or the value.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct DomainError {
    message: String,
}

impl DomainError {
    pub(crate) fn new(message: String) -> Self {
        DomainError { message }
    }
}

/// Walls, solids, periodic axes and phases around a classified particle set (module docs).
/// The default is the bare cloud of the crate docs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Domain {
    pub(crate) walls: Option<AnyParticleSet>,
    pub(crate) solids: Solids,
    pub(crate) periodic: Vec<Periodic>,
    pub(crate) phases: Option<Vec<u32>>,
}

impl Domain {
    /// The bare cloud: no wall, no solid, no periodic axis, one phase.
    pub fn new() -> Self {
        Domain::default()
    }

    /// Covering-only particles (walls), of the dimension of the classified set; with radius
    /// factors if they have their own (module docs). Replaces walls set before.
    pub fn with_walls(mut self, walls: AnyParticleSet) -> Self {
        self.walls = Some(walls);
        self
    }

    /// Adds a solid half-space.
    pub fn with_solid(mut self, h: HalfSpace) -> Self {
        self.solids.push(h);
        self
    }

    /// Adds a solid mesh (3D sets only: [`crate::detect_in`] refuses it for a 2D set). The mesh is
    /// shared, so one read mesh can serve many detections.
    pub fn with_solid_mesh(mut self, mesh: Arc<SolidMesh>) -> Self {
        self.solids.push_mesh(mesh);
        self
    }

    /// Adds a periodic axis.
    pub fn with_periodic(mut self, p: Periodic) -> Self {
        self.periodic.push(p);
        self
    }

    /// One phase number per classified particle: the detection then also reports interfaces.
    pub fn with_phases(mut self, phases: Vec<u32>) -> Self {
        self.phases = Some(phases);
        self
    }

    /// The walls, if any.
    pub fn walls(&self) -> Option<&AnyParticleSet> {
        self.walls.as_ref()
    }

    /// The solid regions.
    pub fn solids(&self) -> &Solids {
        &self.solids
    }

    /// The periodic axes.
    pub fn periodic(&self) -> &[Periodic] {
        &self.periodic
    }

    /// The phases, if any.
    pub fn phases(&self) -> Option<&[u32]> {
        self.phases.as_deref()
    }

    /// Whether this is the bare cloud (nothing but the classified particles).
    pub fn is_bare(&self) -> bool {
        self.walls.as_ref().is_none_or(|w| w.is_empty())
            && self.solids.is_empty()
            && self.periodic.is_empty()
            && self.phases.is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_spaces_parse_and_print() {
        let h = HalfSpace::parse(" z > 1.25 ").unwrap();
        assert_eq!((h.axis(), h.solid_below(), h.value()), (2, false, 1.25));
        assert_eq!(h.to_string(), "z>1.25");
        assert!(
            h.contains(&[0.0, 0.0, 1.25]),
            "closed: the surface is solid"
        );
        assert!(!h.contains(&[0.0, 0.0, 1.0]));
        assert_eq!(h.fluid_depth(&[0.0, 0.0, 1.0]), 0.25);
        for bad in ["", "y", "y=0", "q<0", "y<", "y<abc", "y<inf", "y<NaN"] {
            let e = HalfSpace::parse(bad).unwrap_err().to_string();
            assert!(e.contains(&format!("'{bad}'")), "{e}");
        }
    }

    #[test]
    fn periodic_axes_parse_and_reject_empty_ranges() {
        let p = Periodic::parse("y:-1:1").unwrap();
        assert_eq!((p.axis(), p.period()), (1, 2.0));
        assert_eq!(p.to_string(), "y:-1:1");
        for bad in ["y:1:1", "y:2:1", "w:0:1", "y:0", "y:a:1", "y:0:inf"] {
            assert!(Periodic::parse(bad).is_err(), "{bad}");
        }
    }
}
