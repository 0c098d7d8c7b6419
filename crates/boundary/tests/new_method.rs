//! A new method written as `docs/ADDING_A_METHOD.md` says, with only the items of
//! `Method`: it works through the face like every registered method (dimensions, owned
//! particles, walls and periodic images of a domain, refusals, `Box<dyn BoundaryDetector>`).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary::implement::{Capabilities, Job, Method, NeighbourGrid, Support};
use boundary::{
    detector_by_name, AnyParticleSet, BoundaryDetector, DetectError, Detection, Dim, Domain,
    HalfSpace, Labels, ParamInfo, Params, ParticleSet, Periodic, Point, Radius, SupportedDim,
};

/// Boundary iff one of the `2D` axis points `p_i ± r e_k` of the sphere `S_i` lies in no
/// closed ball of radius `r` of another particle: a sampled covering test. An uncovered
/// sample proves `S_i` uncovered, so every particle it flags is boundary (no false positive
/// against `exact`); it misses the boundary particles whose gaps avoid the samples.
#[derive(Debug, Clone, PartialEq)]
struct AxisProbe {
    /// Samples at `p_i ± r e_k` pulled in by this fraction of `r`: the test is then one of
    /// the sphere of radius `(1 − inset)·r`, still a proof for `S_i` only at 0.
    inset: f64,
}

boundary::implement::impl_display_as_label!(AxisProbe);

impl Method for AxisProbe {
    const NAME: &'static str = "axis-probe";

    fn describe(&self) -> Params {
        Params(vec![ParamInfo {
            name: "inset",
            value: self.inset.to_string(),
            default: "0".to_owned(),
            description: "samples pulled in by this fraction of r",
        }])
    }

    fn capabilities(&self) -> Capabilities {
        Capabilities::DEFAULT
    }

    fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
    where
        Dim<D>: SupportedDim,
    {
        let r = job.r.get();
        let reach = (1.0 - self.inset) * r;
        let grid = NeighbourGrid::new(job.set, 2.0 * r)?;
        let p = job.set.positions();
        let labels: Labels = (0..job.owned)
            .map(|i| {
                (0..2 * D).any(|s| {
                    let mut x: Point<D> = p[i];
                    x[s / 2] += if s % 2 == 0 { reach } else { -reach };
                    let mut covered = false;
                    grid.for_each_within(&x, r, |j, _| covered |= p[j] != p[i]);
                    !covered
                })
            })
            .collect();
        Ok(Detection {
            labels,
            margin: None,
        })
    }
}

/// A jittered square block of `n × n` particles of spacing 1.
fn block(n: usize, seed: u64) -> ParticleSet<2> {
    let mut state = seed;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let rows: Vec<[f64; 2]> = (0..n * n)
        .map(|k| [(k % n) as f64 + 0.2 * next(), (k / n) as f64 + 0.2 * next()])
        .collect();
    ParticleSet::from_rows(&rows).unwrap()
}

/// `true` where `a` flags a particle that `b` does not.
fn extra(a: &Labels, b: &Labels) -> Vec<usize> {
    (0..a.len())
        .filter(|&i| a.is_boundary(i) && !b.is_boundary(i))
        .collect()
}

#[test]
fn a_new_method_finds_only_true_boundary_particles_through_the_face() {
    let probe: Box<dyn BoundaryDetector> = Box::new(AxisProbe { inset: 0.0 });
    let exact = detector_by_name("exact").unwrap();
    let set = AnyParticleSet::from(block(12, 7));
    let r = Radius::new(0.8).unwrap();
    let got = probe.detect(&set, r).unwrap();
    let want = exact.detect(&set, r).unwrap();
    assert_eq!(extra(&got.labels, &want.labels), Vec::<usize>::new());
    // The block's outer ring is found: its outward sample is uncovered.
    let n = 12;
    for k in 0..n * n {
        let (x, y) = (k % n, k / n);
        if x == 0 || y == 0 || x == n - 1 || y == n - 1 {
            assert!(got.labels.is_boundary(k), "{k}");
        }
    }
    assert_eq!(probe.to_string(), "axis-probe (inset=0)");
    assert!(!probe.certified());
}

#[test]
fn the_face_gives_a_new_method_owned_particles_and_domains() {
    let probe = AxisProbe { inset: 0.0 };
    let r = Radius::new(0.8).unwrap();
    let fluid = block(8, 3);
    let set = AnyParticleSet::from(fluid.clone());
    // The first 20 owned, the rest ghosts: the first 20 labels of the whole set.
    let whole = probe.detect(&set, r).unwrap();
    let owned = probe.detect_owned(&set, 20, r).unwrap();
    assert_eq!(owned.labels.as_slice(), &whole.labels.as_slice()[..20]);
    // Periodic along x: no particle at the seam of the period is flagged by its x samples,
    // and the labels are those of exact's flags or fewer (still no false positive).
    let rows: Vec<[f64; 2]> = (0..64).map(|k| [(k % 8) as f64, (k / 8) as f64]).collect();
    let lattice = AnyParticleSet::from(ParticleSet::<2>::from_rows(&rows).unwrap());
    let periodic = Domain::new().with_periodic(Periodic::new(0, -0.5, 7.5).unwrap());
    let got = probe.detect_in(&lattice, &periodic, r).unwrap().detection;
    let want = detector_by_name("exact")
        .unwrap()
        .detect_in(&lattice, &periodic, r)
        .unwrap()
        .detection;
    assert_eq!(
        got.labels, want.labels,
        "a lattice: only the top and bottom rows"
    );
    assert_eq!(got.labels.boundary_count(), 16);
    // The face refuses what the capabilities refuse, naming the option.
    let floor = Domain::new().with_solid(HalfSpace::parse("y<-0.5").unwrap());
    let e = probe.detect_in(&set, &floor, r).unwrap_err();
    assert!(
        matches!(
            e,
            DetectError::UnsupportedOption {
                method: "axis-probe",
                option: "solid half-spaces",
                ..
            }
        ),
        "{e}"
    );
    let with_radii = AnyParticleSet::from(fluid.with_radii(vec![1.0; 64]).unwrap());
    let e = probe.detect(&with_radii, r).unwrap_err();
    assert!(matches!(e, DetectError::PerParticleRadii { .. }), "{e}");
    // With radii honoured, the same method accepts the set (and reads no radius: the
    // factors are all 1, so its labels are the uniform ones).
    #[derive(Debug)]
    struct Tolerant(AxisProbe);
    impl Method for Tolerant {
        const NAME: &'static str = "tolerant";
        fn describe(&self) -> Params {
            Method::describe(&self.0)
        }
        fn capabilities(&self) -> Capabilities {
            Capabilities {
                radii: Support::Honoured,
                ..Capabilities::DEFAULT
            }
        }
        fn classify<const D: usize>(&self, job: Job<'_, D>) -> Result<Detection, DetectError>
        where
            Dim<D>: SupportedDim,
        {
            self.0.classify(job)
        }
    }
    let tolerant = Tolerant(probe.clone()).detect(&with_radii, r).unwrap();
    assert_eq!(tolerant.labels, whole.labels);
}

/// `Cascade` composes any method with a certified refiner: `svm` then `exact` is exactly
/// `svm`'s own cascade (`refine=exact`), and the new method above refined by `exact` keeps
/// only true boundary particles, none lost that it had found.
#[test]
fn a_cascade_refines_any_method_with_a_certified_one() {
    use boundary::registry::detector_with_params;
    use boundary::Cascade;
    let set = AnyParticleSet::from(block(14, 11));
    let r = Radius::new(0.75).unwrap();
    let exact = detector_by_name("exact").unwrap();
    let svm_then_exact = Cascade::new(detector_by_name("svm").unwrap(), exact).unwrap();
    let own = detector_with_params("svm", &[("refine", "exact")]).unwrap();
    assert_eq!(
        svm_then_exact.detect(&set, r).unwrap().labels,
        own.detect(&set, r).unwrap().labels
    );
    let probe = AxisProbe { inset: 0.0 };
    let alone = probe.detect(&set, r).unwrap().labels;
    let refined = Cascade::new(Box::new(probe), detector_by_name("exact").unwrap())
        .unwrap()
        .detect(&set, r)
        .unwrap()
        .labels;
    assert_eq!(
        refined, alone,
        "the probe flags only true boundary particles"
    );
    let e = Cascade::new(
        detector_by_name("ia").unwrap(),
        Box::new(AxisProbe { inset: 0.0 }),
    )
    .unwrap_err();
    assert!(e.to_string().contains("certified"), "{e}");
}
