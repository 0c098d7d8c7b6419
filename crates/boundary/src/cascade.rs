//! A composition of two methods: a certified method re-tests the boundary particles of
//! another, as `svm`'s cascade (thesis Sec. 3.4) does with `exact` or `ge`.

use boundary_core::{
    BoundaryDetector, Capabilities, DetectError, Detection, Dim, Job, Method, ParamError,
    ParamInfo, Params, ParticleSet, Support, SupportedDim,
};

/// `first` flags candidates, and the certified `refiner` re-tests them with every particle
/// covering: a particle is boundary iff both call it boundary. The refiner adds no false
/// negative, so the cascade misses what `first` misses and no more, and keeps none of the
/// false positives the refiner clears. It is certified when both are.
///
/// It honours per-particle radii and each kind of solid when both methods do (a refusal
/// names the method that refuses), and its halo is the larger of the two. The margins of
/// the two methods are in different units: the cascade returns labels only.
///
/// ```
/// use boundary::{detector_by_name, AnyParticleSet, BoundaryDetector, Cascade, ParticleSet, Radius};
///
/// let ia_then_exact =
///     Cascade::new(detector_by_name("ia").unwrap(), detector_by_name("exact").unwrap()).unwrap();
/// assert_eq!(ia_then_exact.to_string(), "cascade (first=ia (depth=6), refiner=exact (tie=0))");
/// let rows: Vec<[f64; 2]> = (0..49).map(|k| [(k % 7) as f64, (k / 7) as f64]).collect();
/// let set = AnyParticleSet::from(ParticleSet::<2>::from_rows(&rows).unwrap());
/// let r = Radius::new(0.75).unwrap();
/// // ia is certified, so every boundary particle is a candidate: the labels of exact.
/// let exact = detector_by_name("exact").unwrap().detect(&set, r).unwrap();
/// assert_eq!(ia_then_exact.detect(&set, r).unwrap().labels, exact.labels);
/// // A refiner that may miss boundary particles is refused.
/// assert!(Cascade::new(detector_by_name("ia").unwrap(), detector_by_name("marrone").unwrap()).is_err());
/// ```
#[derive(Debug)]
pub struct Cascade {
    first: Box<dyn BoundaryDetector>,
    refiner: Box<dyn BoundaryDetector>,
}

impl Cascade {
    /// `first`, then `refiner` on its boundary particles; `refiner` must be certified (else
    /// [`ParamError::Invalid`] naming `refiner`).
    pub fn new(
        first: Box<dyn BoundaryDetector>,
        refiner: Box<dyn BoundaryDetector>,
    ) -> Result<Self, ParamError> {
        if !refiner.certified() {
            return Err(ParamError::invalid(
                "cascade",
                "refiner",
                refiner.name(),
                "must be a certified method (exact, dilts, ia or ge): a refiner that may miss \
                 a boundary particle would add false negatives",
            ));
        }
        Ok(Cascade { first, refiner })
    }

    /// The method that flags the candidates.
    pub fn first(&self) -> &dyn BoundaryDetector {
        &*self.first
    }

    /// The certified method that re-tests them.
    pub fn refiner(&self) -> &dyn BoundaryDetector {
        &*self.refiner
    }
}

boundary_core::impl_display_as_label!(Cascade);

/// Honoured when both honour it, else the first refusal.
fn both(a: Support, b: Support) -> Support {
    match (a, b) {
        (Support::Honoured, Support::Honoured) => Support::Honoured,
        (Support::Refused(reason), _) | (_, Support::Refused(reason)) => Support::Refused(reason),
    }
}

impl Method for Cascade {
    const NAME: &'static str = "cascade";

    fn describe(&self) -> Params {
        Params(vec![
            ParamInfo {
                name: "first",
                value: self.first.to_string(),
                default: String::new(),
                description: "the method whose boundary particles are re-tested",
            },
            ParamInfo {
                name: "refiner",
                value: self.refiner.to_string(),
                default: String::new(),
                description: "the certified method that re-tests them",
            },
        ])
    }

    fn capabilities(&self) -> Capabilities {
        let (a, b) = (self.first.capabilities(), self.refiner.capabilities());
        Capabilities {
            certified: a.certified && b.certified,
            radii: both(a.radii, b.radii),
            half_spaces: both(a.half_spaces, b.half_spaces),
            meshes: both(a.meshes, b.meshes),
            halo_over_r: a.halo_over_r.max(b.halo_over_r),
        }
    }

    fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        let candidates = job.run_on(&*self.first)?;
        Ok(Detection {
            labels: refine(&*self.refiner, job, candidates.labels.as_slice())?
                .into_iter()
                .collect(),
            margin: None,
        })
    }
}

/// Re-tests the particles flagged in `candidates` (one flag per owned particle of `job`) with
/// `refiner`: the candidates go first in a reordered copy of the set (radii included), every
/// other particle follows as a ghost, and `refiner` classifies the candidates with the job's
/// solids. Returns one label per owned particle: a candidate keeps the refiner's label, any
/// other particle is interior. With a certified refiner this turns a method's false positives
/// into true negatives and adds no false negative of its own.
fn refine<T: BoundaryDetector + ?Sized, const D: usize>(
    refiner: &T,
    job: Job<'_, D>,
    candidates: &[bool],
) -> Result<Vec<bool>, DetectError>
where
    Dim<D>: SupportedDim,
{
    if candidates.len() != job.owned {
        return Err(DetectError::Method {
            method: refiner.name(),
            message: format!(
                "{} candidate flags for {} owned particles",
                candidates.len(),
                job.owned
            ),
        });
    }
    let positions = job.set.positions();
    let mut order: Vec<usize> = (0..candidates.len()).filter(|&i| candidates[i]).collect();
    let owned = order.len();
    if owned == 0 {
        return Ok(candidates.to_vec());
    }
    order.extend((0..positions.len()).filter(|&i| i >= candidates.len() || !candidates[i]));
    let mut reordered = ParticleSet::new(order.iter().map(|&i| positions[i]).collect())?;
    if let Some(radii) = job.set.radii() {
        reordered = reordered.with_radii(order.iter().map(|&i| radii[i]).collect())?;
    }
    let detection = Job {
        set: &reordered,
        owned,
        ..job
    }
    .run_on(refiner)?;
    let mut labels = vec![false; candidates.len()];
    for (k, &i) in order[..owned].iter().enumerate() {
        labels[i] = detection.labels.is_boundary(k);
    }
    Ok(labels)
}
