//! The object-safe face of every [`Method`], and the one place a detection runs.
//!
//! [`BoundaryDetector`] is what a registry holds (`Box<dyn BoundaryDetector>`), and every
//! [`Method`] is one through a blanket impl. Every entry point, from
//! [`BoundaryDetector::detect_2d`] to [`detect_in`] with a [`Domain`], goes through one
//! function that, once for every method:
//! - dispatches on the dimension of an [`AnyParticleSet`];
//! - checks the job: `owned` within the set, solid meshes in 3D only, half-space axes within
//!   the dimension;
//! - refuses what the method's [`Capabilities`] refuse (per-particle radii, solid half-spaces,
//!   solid meshes) with the method's reason, rather than let it ignore an input;
//! - keeps the owned labels of a method that classified every particle;
//! - turns a detection stopped through its [`StopToken`](crate::stop::StopToken) into
//!   [`DetectError::Interrupted`]: never partial labels after a stop.
//!
//! [`detect_in`] classifies a set in a [`Domain`] (walls, solids, periodic axes, phases; see
//! [`crate::domain`]) through the same function.

use crate::domain::{Domain, DomainError, Periodic, Solids, AXES};
use crate::method::{Capabilities, Job, JobByDim, Method, Support};
use crate::{
    AnyParticleSet, DetectError, Detection, Dim, Labels, Params, ParticleSet, Point, Radius,
    SupportedDim,
};
use std::fmt;

mod sealed {
    /// Only the blanket impl over [`crate::Method`] makes a [`crate::BoundaryDetector`], so
    /// that the checks of [`crate::detect`] cannot be bypassed.
    pub trait Sealed {}
    impl<M: crate::Method> Sealed for M {}
}

/// The option a refusal of solid meshes names.
const SOLID_MESH_OPTION: &str = "solid meshes";

/// The option a refusal of solid half-spaces names.
const HALF_SPACE_OPTION: &str = "solid half-spaces";

/// A boundary-particle detection method, object safe: what a registry holds
/// (`Box<dyn BoundaryDetector>`). Implemented for every [`Method`] (and only through it); see
/// the [module docs](crate::detect) for what it checks.
///
/// Contract: one label per classified particle in input order, no panic on a validated
/// [`ParticleSet`] and [`Radius`], deterministic labels (independent of the number of
/// threads), and never partial labels after a stop.
pub trait BoundaryDetector: Send + Sync + fmt::Debug + sealed::Sealed {
    /// The method's name in the registry and on the command line (`exact`, `ia`, …).
    fn name(&self) -> &'static str;

    /// The parameters with their current values and defaults, as `key=value` text for
    /// reports and labels ([`Method::describe`]; read-only: a detector's parameters are set
    /// through its typed parameter struct, whose accessor is the detector's `params()`, or
    /// by name through the facade's registry).
    fn describe(&self) -> Params;

    /// What the method supports ([`Method::capabilities`]).
    fn capabilities(&self) -> Capabilities;

    /// Classifies the first `job.owned` particles of a 2D job (the others cover only).
    fn run_2d(&self, job: Job<'_, 2>) -> Result<Detection, DetectError>;

    /// Classifies the first `job.owned` particles of a 3D job (the others cover only).
    fn run_3d(&self, job: Job<'_, 3>) -> Result<Detection, DetectError>;

    /// Whether the method promises no false negatives (Rec = 1 against the exact labels).
    fn certified(&self) -> bool {
        self.capabilities().certified
    }

    /// How far from a particle the method looks: the labels of the particles owned by a
    /// subdomain equal the global ones when the subdomain holds every particle within this
    /// distance of an owned one (see [`crate::decompose`]): [`Capabilities::halo_over_r`]
    /// times `r`.
    fn halo_width(&self, r: Radius) -> f64 {
        self.capabilities().halo_over_r * r.get()
    }

    /// Whether the method honours solid meshes ([`crate::SolidMesh`]); one that does not
    /// refuses a domain with a mesh before classifying.
    fn honours_solid_meshes(&self) -> bool {
        self.capabilities().meshes.is_honoured()
    }

    /// Classifies a 2D particle set at resolution `r`.
    fn detect_2d(&self, set: &ParticleSet<2>, r: Radius) -> Result<Detection, DetectError> {
        self.run_2d(Job {
            set,
            owned: set.len(),
            solids: &Solids::new(),
            r,
        })
    }

    /// Classifies a 3D particle set at resolution `r`.
    fn detect_3d(&self, set: &ParticleSet<3>, r: Radius) -> Result<Detection, DetectError> {
        self.run_3d(Job {
            set,
            owned: set.len(),
            solids: &Solids::new(),
            r,
        })
    }

    /// Classifies a set whose dimension is known at run time.
    fn detect(&self, set: &AnyParticleSet, r: Radius) -> Result<Detection, DetectError> {
        self.detect_owned_in(set, set.len(), &Solids::new(), r)
    }

    /// Classifies only the first `owned` particles of `set`; the others are ghosts (a halo)
    /// that take part as neighbours. Returns `owned` labels (and margins).
    fn detect_owned(
        &self,
        set: &AnyParticleSet,
        owned: usize,
        r: Radius,
    ) -> Result<Detection, DetectError> {
        self.detect_owned_in(set, owned, &Solids::new(), r)
    }

    /// Classifies the first `owned` particles of `set` (the others cover only, as in
    /// [`BoundaryDetector::detect_owned`]) where the closed solid regions `solids` cover too
    /// (see [`crate::domain`]); refused with [`DetectError::UnsupportedOption`] by a method
    /// whose capabilities refuse them.
    fn detect_owned_in(
        &self,
        set: &AnyParticleSet,
        owned: usize,
        solids: &Solids,
        r: Radius,
    ) -> Result<Detection, DetectError> {
        match set {
            AnyParticleSet::D2(set) => self.run_2d(Job {
                set,
                owned,
                solids,
                r,
            }),
            AnyParticleSet::D3(set) => self.run_3d(Job {
                set,
                owned,
                solids,
                r,
            }),
        }
    }

    /// Classifies `set` in a [`Domain`]: walls, solids, periodic axes and phases (see
    /// [`crate::domain`] and [`detect_in`]). With [`Domain::new`] this is
    /// [`BoundaryDetector::detect`].
    fn detect_in(
        &self,
        set: &AnyParticleSet,
        domain: &Domain,
        r: Radius,
    ) -> Result<DomainDetection, DetectError> {
        detect_in(self, set, domain, r)
    }
}

impl<M: Method> BoundaryDetector for M {
    fn name(&self) -> &'static str {
        M::NAME
    }

    fn describe(&self) -> Params {
        Method::describe(self)
    }

    fn capabilities(&self) -> Capabilities {
        Method::capabilities(self)
    }

    fn run_2d(&self, job: Job<'_, 2>) -> Result<Detection, DetectError> {
        run(self, job)
    }

    fn run_3d(&self, job: Job<'_, 3>) -> Result<Detection, DetectError> {
        run(self, job)
    }
}

impl<const D: usize> Job<'_, D>
where
    Dim<D>: SupportedDim,
{
    /// Runs this job on `detector` (checked like every detection): what code generic over the
    /// dimension calls, a composition of methods say, without copying the set into an
    /// [`AnyParticleSet`].
    pub fn run_on<T: BoundaryDetector + ?Sized>(
        self,
        detector: &T,
    ) -> Result<Detection, DetectError> {
        match self.by_dim() {
            JobByDim::D2(job) => detector.run_2d(job),
            JobByDim::D3(job) => detector.run_3d(job),
        }
    }
}

/// The one path of every detection: checks `job` against the method's capabilities,
/// classifies, keeps the owned labels, and checks the stop token.
fn run<M: Method, const D: usize>(method: &M, job: Job<'_, D>) -> Result<Detection, DetectError>
where
    Dim<D>: SupportedDim,
{
    let caps = Method::capabilities(method);
    let name = M::NAME;
    let refuse = |support: Support, option: &'static str| match support {
        Support::Honoured => Ok(()),
        Support::Refused(reason) => Err(DetectError::UnsupportedOption {
            method: name,
            option,
            reason,
        }),
    };
    let solids = job.solids;
    if !solids.meshes().is_empty() {
        refuse(caps.meshes, SOLID_MESH_OPTION)?;
    }
    if !solids.half_spaces().is_empty() {
        refuse(caps.half_spaces, HALF_SPACE_OPTION)?;
    }
    let len = job.set.len();
    if job.owned > len {
        return Err(DetectError::Method {
            method: name,
            message: format!("{} owned particles in a set of {len}", job.owned),
        });
    }
    if !solids.meshes().is_empty() && D != 3 {
        return Err(DetectError::Method {
            method: name,
            message: "a solid mesh needs a 3D set".to_owned(),
        });
    }
    if let Some(h) = solids.half_spaces().iter().find(|h| h.axis() >= D) {
        return Err(DetectError::Method {
            method: name,
            message: format!("solid '{h}' has no axis in a {D}D set"),
        });
    }
    if let (Some(_), Support::Refused(reason)) = (job.set.radii(), caps.radii) {
        return Err(DetectError::PerParticleRadii {
            method: name,
            reason,
        });
    }
    let mut detection = method.classify(job)?;
    // A stopped method loop leaves partial labels: never return them.
    crate::stop::check()?;
    let got = detection.labels.len();
    if got != job.owned {
        if got != len {
            return Err(DetectError::Method {
                method: name,
                message: format!(
                    "{got} labels for {} owned particles in a set of {len}",
                    job.owned
                ),
            });
        }
        let mut flags = detection.labels.into_vec();
        flags.truncate(job.owned);
        detection.labels = Labels::new(flags);
        if let Some(m) = detection.margin.as_mut() {
            m.truncate(job.owned);
        }
    }
    Ok(detection)
}

/// Writes a detector's label: its name, then its parameters in parentheses when it has any,
/// e.g. `ia (depth=6)` or `exact`. `Display` of every detector type and of
/// `dyn BoundaryDetector` prints this (see [`impl_display_as_label!`](crate::impl_display_as_label)).
pub fn write_label(detector: &dyn BoundaryDetector, f: &mut fmt::Formatter<'_>) -> fmt::Result {
    let params = detector.describe();
    if params.0.is_empty() {
        f.write_str(detector.name())
    } else {
        write!(f, "{} ({params})", detector.name())
    }
}

impl fmt::Display for dyn BoundaryDetector + '_ {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_label(self, f)
    }
}

/// Implements `Display` for a detector type as its label ([`write_label`]): `name (key=value,
/// …)`. Every detector crate invokes it once for its detector.
#[macro_export]
macro_rules! impl_display_as_label {
    ($detector:ty) => {
        impl ::std::fmt::Display for $detector {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                $crate::write_label(self, f)
            }
        }
    };
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
        if let Support::Refused(reason) = detector.capabilities().meshes {
            return Err(DetectError::UnsupportedOption {
                method: detector.name(),
                option: SOLID_MESH_OPTION,
                reason,
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

    /// A method with one parameter that labels every classified particle boundary, with a
    /// margin equal to its index; it honours whatever `caps` honours.
    #[derive(Debug)]
    struct Knob(u32, Capabilities);

    impl Method for Knob {
        const NAME: &'static str = "knob";
        fn describe(&self) -> Params {
            Params(if self.0 == 0 {
                Vec::new()
            } else {
                vec![crate::ParamInfo {
                    name: "turns",
                    value: self.0.to_string(),
                    default: "1".into(),
                    description: "",
                }]
            })
        }
        fn capabilities(&self) -> Capabilities {
            self.1
        }
        fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
        where
            Dim<D>: SupportedDim,
        {
            // Every particle, ghosts included, when turns is odd: the face keeps the owned.
            let n = if self.0 % 2 == 1 {
                job.set.len()
            } else {
                job.owned
            };
            Ok(Detection {
                labels: Labels::new(vec![true; n]),
                margin: Some((0..n).map(|i| i as f64).collect()),
            })
        }
    }
    crate::impl_display_as_label!(Knob);

    #[test]
    fn a_detector_displays_as_its_name_and_parameters() {
        assert_eq!(Knob(3, Capabilities::DEFAULT).to_string(), "knob (turns=3)");
        assert_eq!(Knob(0, Capabilities::DEFAULT).to_string(), "knob");
        let boxed: Box<dyn BoundaryDetector> = Box::new(Knob(2, Capabilities::DEFAULT));
        assert_eq!(boxed.to_string(), "knob (turns=2)");
    }

    fn line(n: usize) -> AnyParticleSet {
        let rows: Vec<[f64; 2]> = (0..n).map(|k| [k as f64, 0.0]).collect();
        ParticleSet::<2>::from_rows(&rows).unwrap().into()
    }

    #[test]
    fn the_face_keeps_the_owned_labels_whatever_the_method_returns() {
        let r = Radius::new(1.0).unwrap();
        for turns in [1, 2] {
            let d = Knob(turns, Capabilities::DEFAULT);
            let got = d.detect_owned(&line(5), 3, r).unwrap();
            assert_eq!(got.labels.len(), 3, "turns={turns}");
            assert_eq!(got.margin.unwrap(), vec![0.0, 1.0, 2.0]);
            let e = d.detect_owned(&line(5), 6, r).unwrap_err().to_string();
            assert_eq!(e, "method 'knob': 6 owned particles in a set of 5");
        }
    }

    #[test]
    fn the_face_refuses_what_the_capabilities_refuse_with_their_reasons() {
        let r = Radius::new(1.0).unwrap();
        let floor = crate::HalfSpace::parse("y<-1").unwrap();
        let mut solids = Solids::new();
        solids.push(floor);
        let plain = Knob(2, Capabilities::DEFAULT);
        let e = plain.detect_owned_in(&line(3), 3, &solids, r).unwrap_err();
        assert!(
            matches!(
                e,
                DetectError::UnsupportedOption {
                    option: "solid half-spaces",
                    ..
                }
            ),
            "{e}"
        );
        let radii: AnyParticleSet = ParticleSet::<2>::from_rows(&[[0.0, 0.0]])
            .unwrap()
            .with_radii(vec![2.0])
            .unwrap()
            .into();
        let e = plain.detect(&radii, r).unwrap_err();
        assert!(matches!(e, DetectError::PerParticleRadii { .. }), "{e}");
        let able = Knob(
            2,
            Capabilities {
                radii: Support::Honoured,
                half_spaces: Support::Honoured,
                ..Capabilities::DEFAULT
            },
        );
        assert_eq!(able.detect(&radii, r).unwrap().labels.len(), 1);
        assert_eq!(
            able.detect_owned_in(&line(3), 3, &solids, r)
                .unwrap()
                .labels
                .len(),
            3
        );
        // A half-space on an axis the set lacks is named, whatever the method.
        let mut up = Solids::new();
        up.push(crate::HalfSpace::parse("z<0").unwrap());
        let e = able.detect_owned_in(&line(3), 3, &up, r).unwrap_err();
        assert_eq!(
            e.to_string(),
            "method 'knob': solid 'z<0' has no axis in a 2D set"
        );
        assert!(!able.honours_solid_meshes() && !able.certified());
        assert_eq!(able.halo_width(Radius::new(0.5).unwrap()), 1.0);
    }

    #[test]
    fn no_entry_point_returns_labels_after_a_stop() {
        let r = Radius::new(1.0).unwrap();
        let d = Knob(1, Capabilities::DEFAULT);
        let token = crate::stop::StopToken::new();
        token.stop();
        token.scope(|| {
            let set = line(4);
            let AnyParticleSet::D2(s) = &set else {
                unreachable!()
            };
            assert_eq!(d.detect_2d(s, r), Err(DetectError::Interrupted));
            assert_eq!(d.detect(&set, r), Err(DetectError::Interrupted));
            assert_eq!(d.detect_owned(&set, 2, r), Err(DetectError::Interrupted));
            let domain = Domain::new().with_phases(vec![0, 0, 1, 1]);
            assert_eq!(
                d.detect_in(&set, &domain, r).map(|_| ()),
                Err(DetectError::Interrupted)
            );
        });
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
