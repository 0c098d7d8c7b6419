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
//! # use boundary_core::{BoundaryDetector, Detection, DetectError, Labels, Params};
//! # #[derive(Debug)] struct Lonely;
//! # impl BoundaryDetector for Lonely {
//! #     fn name(&self) -> &'static str { "lonely" }
//! #     fn params(&self) -> Params { Params::default() }
//! #     fn detect_2d(&self, s: &ParticleSet<2>, _: Radius) -> Result<Detection, DetectError> { Ok(Detection { labels: Labels::new(vec![true; s.len()]), margin: None }) }
//! #     fn detect_3d(&self, s: &ParticleSet<3>, _: Radius) -> Result<Detection, DetectError> { Ok(Detection { labels: Labels::new(vec![true; s.len()]), margin: None }) }
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

use crate::{
    AnyParticleSet, BoundaryDetector, DetectError, Detection, Labels, ParticleSet, Point, Radius,
    SolidMesh,
};
use crate::{Dim, SupportedDim};
use std::fmt;
use std::sync::Arc;

/// The axis names of messages and of [`HalfSpace::parse`].
const AXES: [char; 3] = ['x', 'y', 'z'];

/// An axis-aligned solid half-space: `{x_axis <= value}` (`x<value`) or `{x_axis >= value}`
/// (`x>value`). Closed (module docs, *Policy*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSpace {
    axis: usize,
    solid_below: bool,
    value: f64,
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
    half_spaces: Vec<HalfSpace>,
    meshes: Vec<Arc<SolidMesh>>,
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

    /// `Ok` when every half-space has its axis in a set of dimension `dim`, else the error a
    /// method's [`crate::BoundaryDetector::detect_owned_in`] returns, naming the solid
    /// (`detect_in` checks the same before any method runs).
    pub fn check_axes(&self, method: &'static str, dim: usize) -> Result<(), DetectError> {
        match self.half_spaces.iter().find(|h| h.axis() >= dim) {
            None => Ok(()),
            Some(h) => Err(DetectError::Method {
                method,
                message: format!("solid '{h}' has no axis in a {dim}D set"),
            }),
        }
    }
}

/// A periodic axis: particles leaving `max` re-enter at `min`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Periodic {
    axis: usize,
    min: f64,
    max: f64,
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
    fn new(message: String) -> Self {
        DomainError { message }
    }
}

/// Walls, solids, periodic axes and phases around a classified particle set (module docs).
/// The default is the bare cloud of the crate docs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Domain {
    walls: Option<AnyParticleSet>,
    solids: Solids,
    periodic: Vec<Periodic>,
    phases: Option<Vec<u32>>,
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

    /// Adds a solid mesh (3D sets only: [`detect_in`] refuses it for a 2D set). The mesh is
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

/// What a detection in a [`Domain`] returns.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DomainDetection {
    /// Free-surface labels (and margins) of the classified particles, in input order.
    pub detection: Detection,
    /// With phases: `true` for a particle on an interface between phases (not on the free
    /// surface, but uncovered by its own phase and the walls).
    pub interface: Option<Labels>,
}

/// Classifies `set` in `domain` with `detector` (module docs): the classified particles come
/// first in one set, the covering-only ones after them as ghosts, and the detector's
/// [`BoundaryDetector::detect_owned_in`] classifies the first part with the solids.
pub fn detect_in<T: BoundaryDetector + ?Sized>(
    detector: &T,
    set: &AnyParticleSet,
    domain: &Domain,
    r: Radius,
) -> Result<DomainDetection, DetectError> {
    if domain.is_bare() {
        // The bare cloud: the detection itself, without a copy of the set.
        return Ok(DomainDetection {
            detection: detector.detect(set, r)?,
            interface: None,
        });
    }
    let err = |message: String| DetectError::Domain(DomainError::new(message));
    if let Some(w) = &domain.walls {
        if w.dim() != set.dim() {
            return Err(err(format!(
                "the walls are {}D and the particles {}D",
                w.dim(),
                set.dim()
            )));
        }
    }
    if let Some(phases) = &domain.phases {
        if phases.len() != set.len() {
            return Err(err(format!(
                "{} phase numbers for {} particles (one per particle)",
                phases.len(),
                set.len()
            )));
        }
    }
    for h in domain.solids.half_spaces() {
        if h.axis >= set.dim() {
            return Err(err(format!(
                "solid '{h}': a {}D set has no {} axis",
                set.dim(),
                AXES[h.axis]
            )));
        }
        if domain.periodic.iter().any(|p| p.axis == h.axis) {
            return Err(err(format!(
                "solid '{h}': the {} axis is periodic; a periodic axis has no solid bound",
                AXES[h.axis]
            )));
        }
    }
    if !domain.solids.meshes.is_empty() {
        if set.dim() != 3 {
            return Err(err(format!(
                "a solid mesh needs a 3D set; the particles are {}D",
                set.dim()
            )));
        }
        if !detector.honours_solid_meshes() {
            return Err(DetectError::UnsupportedOption {
                method: detector.name(),
                option: crate::detector::SOLID_MESH_OPTION,
                reason: detector.solid_mesh_refusal(),
            });
        }
    }
    for (k, p) in domain.periodic.iter().enumerate() {
        if p.axis >= set.dim() {
            return Err(err(format!(
                "periodic '{p}': a {}D set has no {} axis",
                set.dim(),
                AXES[p.axis]
            )));
        }
        if domain.periodic[..k].iter().any(|q| q.axis == p.axis) {
            return Err(err(format!(
                "periodic {}: the axis is given twice",
                AXES[p.axis]
            )));
        }
    }
    // The reach: the halo at the largest radius of either kind.
    let largest = |s: Option<&[f64]>| s.map_or(1.0, |s| s.iter().copied().fold(1.0, f64::max));
    let scale = largest(set.radii()).max(largest(domain.walls.as_ref().and_then(|w| w.radii())));
    let reach = detector.halo_width(Radius::new(r.get() * scale).map_err(DetectError::Core)?);
    for p in &domain.periodic {
        if p.period() < reach {
            return Err(err(format!(
                "periodic '{p}': the period {} is shorter than the reach {reach} of method \
                 '{}' at r = {r}; use a longer period or a smaller radius",
                p.period(),
                detector.name()
            )));
        }
    }
    // A mesh is not repeated across a period: it must stay clear of the ends of every
    // periodic range by the reach, where no sphere can meet an image of it.
    for mesh in domain.solids.meshes() {
        let (lo, hi) = mesh.bounds();
        for p in &domain.periodic {
            let a = p.axis;
            if !(lo[a] >= p.min + reach && hi[a] <= p.max - reach) {
                return Err(err(format!(
                    "periodic '{p}': a solid mesh spans {}..{} along {}, within the reach \
                     {reach} of the ends of the period; a mesh is not repeated across a \
                     period, so it must lie inside {}..{}",
                    lo[a],
                    hi[a],
                    AXES[a],
                    p.min + reach,
                    p.max - reach
                )));
            }
        }
    }
    let n = set.len();
    let free = match (set, &domain.walls) {
        (AnyParticleSet::D2(s), w) => {
            let w = w.as_ref().map(|w| match w {
                AnyParticleSet::D2(w) => w,
                AnyParticleSet::D3(_) => unreachable!("dimensions checked above"),
            });
            let all: Vec<usize> = (0..n).collect();
            let ext = extend(s, &all, w, &domain.periodic, reach)?;
            detector.detect_owned_in(&ext.into(), n, &domain.solids, r)?
        }
        (AnyParticleSet::D3(s), w) => {
            let w = w.as_ref().map(|w| match w {
                AnyParticleSet::D3(w) => w,
                AnyParticleSet::D2(_) => unreachable!("dimensions checked above"),
            });
            let all: Vec<usize> = (0..n).collect();
            let ext = extend(s, &all, w, &domain.periodic, reach)?;
            detector.detect_owned_in(&ext.into(), n, &domain.solids, r)?
        }
    };
    let interface = match &domain.phases {
        None => None,
        Some(phases) => Some(interfaces(
            detector,
            set,
            domain,
            phases,
            &free.labels,
            reach,
            r,
        )?),
    };
    // A stopped method loop leaves partial labels: never return them.
    crate::stop::check()?;
    Ok(DomainDetection {
        detection: free,
        interface,
    })
}

/// The interface labels: per phase, its particles classified with only their own phase,
/// its images and the walls covering; an interface particle is boundary there and not on the
/// free surface.
fn interfaces<T: BoundaryDetector + ?Sized>(
    detector: &T,
    set: &AnyParticleSet,
    domain: &Domain,
    phases: &[u32],
    free: &Labels,
    reach: f64,
    r: Radius,
) -> Result<Labels, DetectError> {
    let mut kinds: Vec<u32> = phases.to_vec();
    kinds.sort_unstable();
    kinds.dedup();
    let mut interface = vec![false; set.len()];
    if kinds.len() < 2 {
        return Ok(Labels::new(interface));
    }
    for k in kinds {
        let members: Vec<usize> = (0..set.len()).filter(|&i| phases[i] == k).collect();
        let own = match (set, &domain.walls) {
            (AnyParticleSet::D2(s), w) => {
                let w = w.as_ref().and_then(|w| match w {
                    AnyParticleSet::D2(w) => Some(w),
                    AnyParticleSet::D3(_) => None,
                });
                let ext = extend(s, &members, w, &domain.periodic, reach)?;
                detector.detect_owned_in(&ext.into(), members.len(), &domain.solids, r)?
            }
            (AnyParticleSet::D3(s), w) => {
                let w = w.as_ref().and_then(|w| match w {
                    AnyParticleSet::D3(w) => Some(w),
                    AnyParticleSet::D2(_) => None,
                });
                let ext = extend(s, &members, w, &domain.periodic, reach)?;
                detector.detect_owned_in(&ext.into(), members.len(), &domain.solids, r)?
            }
        };
        for (slot, &i) in members.iter().enumerate() {
            interface[i] = own.labels.is_boundary(slot) && !free.is_boundary(i);
        }
    }
    Ok(Labels::new(interface))
}

/// The set a detector classifies: the particles `members` of `set` first (in that order),
/// then the walls within `reach` of their bounding box, then the periodic images of both
/// within `reach` of it. Radii: each kind's own factors, 1 where a kind has none, none at all
/// when neither kind has them.
fn extend<const D: usize>(
    set: &ParticleSet<D>,
    members: &[usize],
    walls: Option<&ParticleSet<D>>,
    periodic: &[Periodic],
    reach: f64,
) -> Result<ParticleSet<D>, DetectError>
where
    Dim<D>: SupportedDim,
{
    let err = |message: String| DetectError::Domain(DomainError::new(message));
    for p in periodic {
        let a = p.axis;
        for (kind, s) in [("particle", Some(set)), ("wall particle", walls)] {
            let Some(s) = s else { continue };
            if let Some(i) = s
                .positions()
                .iter()
                .position(|x| !(x[a] >= p.min && x[a] <= p.max))
            {
                return Err(err(format!(
                    "{kind} {i}: {} = {} lies outside the periodic range {}..{}",
                    AXES[a],
                    s.positions()[i][a],
                    p.min,
                    p.max
                )));
            }
        }
    }
    let with_radii = set.radii().is_some() || walls.is_some_and(|w| w.radii().is_some());
    let factor = |s: &ParticleSet<D>, i: usize| s.radii().map_or(1.0, |f| f[i]);
    if members.is_empty() {
        return ParticleSet::new(Vec::new()).map_err(DetectError::Core);
    }
    // Room for every wall without a reallocation (the set is the largest allocation of a
    // detection in a tank); radii only when some kind has them.
    let room = members.len() + walls.map_or(0, ParticleSet::len);
    let mut positions: Vec<Point<D>> = Vec::with_capacity(room);
    positions.extend(members.iter().map(|&i| set.positions()[i]));
    let mut radii: Vec<f64> = Vec::new();
    if with_radii {
        radii.reserve(room);
        radii.extend(members.iter().map(|&i| factor(set, i)));
    }
    // The bounding box of the classified particles, widened by the reach.
    let mut lo = positions[0];
    let mut hi = positions[0];
    for x in &positions {
        for k in 0..D {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    let near = |x: &Point<D>| (0..D).all(|k| x[k] >= lo[k] - reach && x[k] <= hi[k] + reach);
    if let Some(w) = walls {
        for (i, x) in w.positions().iter().enumerate() {
            if near(x) {
                positions.push(*x);
                if with_radii {
                    radii.push(factor(w, i));
                }
            }
        }
    }
    if periodic.is_empty() {
        return finish(positions, radii, with_radii);
    }
    // Every covering candidate of the images: the members, then all the walls.
    let mut sources: Vec<(Point<D>, f64)> = members
        .iter()
        .map(|&i| (set.positions()[i], factor(set, i)))
        .collect();
    if let Some(w) = walls {
        sources.extend(
            w.positions()
                .iter()
                .enumerate()
                .map(|(i, x)| (*x, factor(w, i))),
        );
    }
    // Images: every combination of shifts in {−L, 0, +L} over the periodic axes but none.
    let combos = 3usize.pow(periodic.len() as u32);
    for combo in 1..combos {
        let mut shift = [0.0f64; D];
        let mut c = combo;
        for p in periodic {
            shift[p.axis] = match c % 3 {
                1 => p.period(),
                2 => -p.period(),
                _ => 0.0,
            };
            c /= 3;
        }
        for (x, s) in &sources {
            let image: Point<D> = Point::<D>::from_fn(|k, _| x[k] + shift[k]);
            if near(&image) {
                positions.push(image);
                if with_radii {
                    radii.push(*s);
                }
            }
        }
    }
    finish(positions, radii, with_radii)
}

/// The validated set of `positions`, with `radii` when `with_radii`.
fn finish<const D: usize>(
    positions: Vec<Point<D>>,
    radii: Vec<f64>,
    with_radii: bool,
) -> Result<ParticleSet<D>, DetectError>
where
    Dim<D>: SupportedDim,
{
    let out = ParticleSet::new(positions).map_err(DetectError::Core)?;
    if with_radii {
        out.with_radii(radii).map_err(DetectError::Core)
    } else {
        Ok(out)
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

    #[test]
    fn the_extended_set_holds_members_then_near_walls_then_images() {
        let set = ParticleSet::<2>::from_rows(&[[0.1, 0.0], [0.9, 0.0], [0.5, 0.0]]).unwrap();
        let walls = ParticleSet::<2>::from_rows(&[[0.5, -0.3], [0.5, -5.0]]).unwrap();
        let periodic = [Periodic::new(0, 0.0, 1.0).unwrap()];
        let ext = extend(&set, &[0, 1], Some(&walls), &periodic, 0.5).unwrap();
        let rows: Vec<[f64; 2]> = ext.positions().iter().map(|p| [p[0], p[1]]).collect();
        // Members 0 and 1, the near wall, then the images within 0.5 of [0.1, 0.9] x [0, 0]:
        // 0.1 + 1 and 0.9 − 1 (the walls' images at x = 1.5 and −0.5 lie beyond it).
        assert_eq!(&rows[..3], &[[0.1, 0.0], [0.9, 0.0], [0.5, -0.3]]);
        let images: Vec<[f64; 2]> = rows[3..].to_vec();
        assert!(images.contains(&[1.1, 0.0]) && images.contains(&[0.9 - 1.0, 0.0]));
        assert_eq!(images.len(), 2);
        assert!(ext.radii().is_none());
        // A particle outside the period is named.
        let out = ParticleSet::<2>::from_rows(&[[1.5, 0.0]]).unwrap();
        let e = extend(&out, &[0], None, &periodic, 0.5)
            .unwrap_err()
            .to_string();
        assert!(e.contains("particle 0: x = 1.5"), "{e}");
    }

    #[test]
    fn walls_without_radii_get_factor_one_beside_fluid_radii() {
        let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0]])
            .unwrap()
            .with_radii(vec![2.0])
            .unwrap();
        let walls = ParticleSet::<2>::from_rows(&[[0.0, -1.0]]).unwrap();
        let ext = extend(&set, &[0], Some(&walls), &[], 3.0).unwrap();
        assert_eq!(ext.radii(), Some(&[2.0, 1.0][..]));
    }
}
