//! The frame of the SPH-sum detectors: what `marrone`, `muller`, `divr` and every other
//! method that classifies a particle from kernel sums over its neighbours have in common.
//!
//! A method crate holds only its criterion: a type implementing [`SphCriterion`] (its sums
//! and thresholds, per particle) and [`SphMethod`] (its name, its parameter listing, why it
//! refuses per-particle radii and solids). [`impl_sph_detector!`](crate::impl_sph_detector)
//! then writes its [`Method`](boundary_core::Method) implementation, like any other method's:
//! the capabilities ([`capabilities`]: the refusals, the halo of two kernel supports) and the
//! classification ([`classify`]: the kernel and smoothing length from [`Smoothing`], the
//! [`SphContext`] of grid and summation-density volumes, the parallel loop over the owned
//! particles, so that walls and periodic images of a [`boundary_core::Domain`] enter the sums
//! as ghosts). The dimension dispatch and the checks are the core face's, as for every method.
//!
//! The parameters the frame reads, `kernel` and `h_over_r`, are checked by
//! [`Smoothing::try_new`] and listed by [`Smoothing::param_infos`], with the same rules and
//! messages in every method.

use crate::kernel::{Kernel, SphKernel, SUPPORT_FACTOR};
use crate::sums::SphContext;
use boundary_core::params::{check, Check};
use boundary_core::{
    Capabilities, CoreError, DetectError, Detection, Job, Labels, ParamError, ParamInfo, Params,
    ParticleSet, Radius, Support,
};
use rayon::prelude::*;

/// Default smoothing length `h` in units of the resolution `r`: the thesis' pairing of `r`
/// with the smoothing length (Sandim 2020, Sec. 2.4).
pub const DEFAULT_H_OVER_R: f64 = 1.0;

/// The description of the `kernel` parameter, the same in every SPH-sum method's
/// [`declare_params!`](boundary_core::declare_params).
pub const KERNEL_DOC: &str = "SPH kernel: wendland (C2) or cubic (spline), support 2h";

/// The description of the `h_over_r` parameter, the same in every SPH-sum method.
pub const H_OVER_R_DOC: &str = "smoothing length h in units of r";

/// The check of `kernel`: its name parses or is refused by [`Kernel`]'s own message.
pub fn kernel_check() -> Check<Kernel> {
    check::any("must be wendland or cubic")
}

/// The check of `h_over_r`: finite, in `(0, 100]` (as [`Smoothing::try_new`]).
pub fn h_over_r_check() -> Check<f64> {
    check::open_closed(0.0, 100.0)
}

/// The kernel and the smoothing length of an SPH-sum method: `h = h_over_r · r`, support
/// `2h`. Always valid when built by [`Smoothing::try_new`] (`h_over_r` finite, in `(0, 100]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Smoothing {
    /// Kernel shape (support `2h`).
    pub kernel: Kernel,
    /// `h / r`, in `(0, 100]`.
    pub h_over_r: f64,
}

impl Default for Smoothing {
    /// Wendland C2 at `h = r`.
    fn default() -> Self {
        Smoothing {
            kernel: Kernel::WendlandC2,
            h_over_r: DEFAULT_H_OVER_R,
        }
    }
}

impl Smoothing {
    /// The smoothing with `h_over_r` checked (finite, in `(0, 100]`); the error names
    /// `method` and the key `h_over_r`.
    pub fn try_new(
        method: &'static str,
        kernel: Kernel,
        h_over_r: f64,
    ) -> Result<Self, ParamError> {
        Ok(Smoothing {
            kernel,
            h_over_r: Self::check_h_over_r(method, h_over_r, &h_over_r.to_string())?,
        })
    }

    /// `v` if it is a valid `h_over_r`, else the error for the text `shown`.
    pub fn check_h_over_r(method: &'static str, v: f64, shown: &str) -> Result<f64, ParamError> {
        if v.is_finite() && v > 0.0 && v <= 100.0 {
            Ok(v)
        } else {
            Err(ParamError::invalid(
                method,
                "h_over_r",
                shown,
                "must be in (0, 100]",
            ))
        }
    }

    /// The listing of `kernel` and `h_over_r` for [`Method::describe`](boundary_core::Method::describe).
    pub fn param_infos(&self) -> [ParamInfo; 2] {
        [
            ParamInfo {
                name: "kernel",
                value: self.kernel.name().to_owned(),
                default: Kernel::WendlandC2.name().to_owned(),
                description: "SPH kernel: wendland (C2) or cubic (spline), support 2h",
            },
            ParamInfo {
                name: "h_over_r",
                value: self.h_over_r.to_string(),
                default: DEFAULT_H_OVER_R.to_string(),
                description: "smoothing length h in units of r",
            },
        ]
    }

    /// The smoothing length `h = h_over_r · r`.
    pub fn h(&self, r: Radius) -> f64 {
        self.h_over_r * r.get()
    }

    /// The kernel at `h`.
    pub fn kernel_at<const D: usize>(&self, r: Radius) -> SphKernel<D> {
        SphKernel::new(self.kernel, self.h(r))
    }
}

/// One particle's answer: its label and its margin (positive leans boundary; ignored unless
/// [`SphCriterion::MARGIN`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verdict {
    /// Boundary (free surface) or not.
    pub boundary: bool,
    /// The criterion's value minus its threshold, oriented like [`Detection::margin`].
    pub margin: f64,
}

impl Verdict {
    /// A verdict without a margin (`NaN`), for criteria with [`SphCriterion::MARGIN`] false.
    pub fn label(boundary: bool) -> Self {
        Verdict {
            boundary,
            margin: f64::NAN,
        }
    }
}

/// The per-particle criterion of an SPH-sum method. The frame builds one [`SphContext`] (the
/// grid, the kernel at `h`, the volumes of every particle, ghosts included) and calls
/// [`SphCriterion::classify`] for each classified particle, in parallel.
pub trait SphCriterion: Sync {
    /// The method's name, as in the registry (`marrone`, `divr`, …).
    const METHOD: &'static str;
    /// Whether [`Verdict::margin`] is meaningful and returned in [`Detection::margin`].
    const MARGIN: bool;

    /// The kernel and the smoothing length.
    fn smoothing(&self) -> Smoothing;

    /// Classifies particle `i` (a classified particle: `i < count`) from the sums of `ctx`;
    /// every particle of the context, ghosts included, may serve as its neighbour.
    fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict;

    /// The verdicts of the first `count` particles, in order: the same as
    /// [`SphCriterion::classify`] of each. Default: `classify` in parallel. A criterion whose
    /// sums are sums over pairs overrides it with [`SphContext::pair_sums`] (or one of the
    /// pair passes built on it), which evaluates each pair's kernel once for both particles.
    fn classify_all<const D: usize>(&self, ctx: &SphContext<'_, D>, count: usize) -> Vec<Verdict> {
        (0..count)
            .into_par_iter()
            .map(|i| {
                if boundary_core::stop::requested() {
                    return Verdict::label(false);
                }
                self.classify(ctx, i)
            })
            .collect()
    }

    /// A pass over the labels of the classified particles once all are known (`labels[i]`
    /// for `i < labels.len()`), for criteria that spread a label to neighbours. Default:
    /// none.
    fn finish<const D: usize>(&self, ctx: &SphContext<'_, D>, labels: &mut [bool]) {
        let _ = (ctx, labels);
    }

    /// How much farther than two kernel supports [`SphCriterion::finish`] looks, in units of
    /// `h` (added to the halo width). Default 0.
    fn extra_reach_h(&self) -> f64 {
        0.0
    }
}

/// What [`impl_sph_detector!`](crate::impl_sph_detector) needs beyond the criterion: the
/// parameter listing and the reasons of the method's refusals.
pub trait SphMethod: SphCriterion + std::fmt::Debug + Send {
    /// Why the method rejects per-particle radii ([`DetectError::PerParticleRadii`]).
    const RADII_REFUSAL: &'static str;
    /// Why it cannot honour solid half-spaces ([`Capabilities::half_spaces`]).
    const SOLID_REFUSAL: &'static str;

    /// The parameters with their current values ([`Method::describe`](boundary_core::Method::describe)).
    fn param_list(&self) -> Params;
}

/// Classifies the first `count` particles of `set` with `criterion` (every particle serves as
/// a neighbour and has a volume). Fails only where the grid does.
pub fn classify_first<C: SphCriterion, const D: usize>(
    criterion: &C,
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
) -> Result<Detection, CoreError> {
    let ctx = SphContext::new(set, criterion.smoothing().kernel_at(r))?;
    let verdicts = criterion.classify_all(&ctx, count);
    let mut labels: Vec<bool> = verdicts.iter().map(|v| v.boundary).collect();
    criterion.finish(&ctx, &mut labels);
    Ok(Detection {
        labels: Labels::new(labels),
        margin: C::MARGIN.then(|| verdicts.iter().map(|v| v.margin).collect()),
    })
}

/// [`Method::capabilities`](boundary_core::Method::capabilities) of an SPH method: a uniform
/// radius only, no solid (with the method's reasons), and a halo of two kernel supports (the
/// volumes of the neighbours within `2h` come from their own neighbours within `2h`), plus
/// [`SphCriterion::extra_reach_h`].
pub fn capabilities<M: SphMethod>(method: &M) -> Capabilities {
    Capabilities {
        radii: Support::Refused(M::RADII_REFUSAL),
        half_spaces: Support::Refused(M::SOLID_REFUSAL),
        halo_over_r: (2.0 * SUPPORT_FACTOR + method.extra_reach_h()) * method.smoothing().h_over_r,
        ..Capabilities::DEFAULT
    }
}

/// [`Method::classify`](boundary_core::Method::classify) of an SPH method: classifies the
/// owned particles; the others (ghosts: a halo, walls, periodic images) are neighbours and
/// have volumes.
pub fn classify<M: SphMethod, const D: usize>(
    method: &M,
    job: Job<'_, D>,
) -> Result<Detection, DetectError> {
    Ok(classify_first(method, job.set, job.owned, job.r)?)
}

/// Flags every classified particle (`i < labels.len()`) within `reach` (closed) of a
/// classified particle flagged in `labels` on entry: one layer of expansion, as SPHinXsys
/// spreads its free-surface indication. Ghosts neither spread nor receive a flag.
pub fn spread_within<const D: usize>(ctx: &SphContext<'_, D>, reach: f64, labels: &mut [bool]) {
    let n = labels.len();
    let positions = ctx.positions();
    let flagged: &[bool] = labels;
    let spread: Vec<bool> = (0..n)
        .into_par_iter()
        .map(|i| {
            if flagged[i] || boundary_core::stop::requested() {
                return flagged[i];
            }
            let mut near = false;
            ctx.grid().for_each_within(&positions[i], reach, |j, _| {
                near |= j < n && flagged[j];
            });
            near
        })
        .collect();
    labels.copy_from_slice(&spread);
}

/// Writes `Display` (the label `name (key=value, …)`) and the
/// [`Method`](boundary_core::Method) implementation of a type that implements
/// [`SphMethod`](crate::SphMethod), through [`frame::capabilities`](crate::frame::capabilities)
/// and [`frame::classify`](crate::frame::classify).
#[macro_export]
macro_rules! impl_sph_detector {
    ($detector:ty) => {
        $crate::__core::impl_display_as_label!($detector);

        impl $crate::__core::Method for $detector {
            const NAME: &'static str = <$detector as $crate::SphCriterion>::METHOD;

            fn describe(&self) -> $crate::__core::Params {
                $crate::SphMethod::param_list(self)
            }

            fn capabilities(&self) -> $crate::__core::Capabilities {
                $crate::frame::capabilities(self)
            }

            fn classify<const D: usize>(
                &self,
                job: $crate::__core::Job<'_, D>,
            ) -> ::std::result::Result<$crate::__core::Detection, $crate::__core::DetectError>
            where
                $crate::__core::Dim<D>: $crate::__core::SupportedDim,
            {
                $crate::frame::classify(self, job)
            }
        }
    };
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use boundary_core::BoundaryDetector;

    /// A toy criterion: boundary iff the particle has fewer than `min` neighbours within the
    /// support; `spread` flags the neighbours within `h` of a flagged particle.
    #[derive(Debug, Clone)]
    struct FewNeighbours {
        min: usize,
        spread: bool,
        smoothing: Smoothing,
    }

    impl SphCriterion for FewNeighbours {
        const METHOD: &'static str = "few";
        const MARGIN: bool = true;
        fn smoothing(&self) -> Smoothing {
            self.smoothing
        }
        fn classify<const D: usize>(&self, ctx: &SphContext<'_, D>, i: usize) -> Verdict {
            let n = ctx.local_sums(i).neighbours;
            Verdict {
                boundary: n < self.min,
                margin: self.min as f64 - n as f64 - 0.5,
            }
        }
        fn finish<const D: usize>(&self, ctx: &SphContext<'_, D>, labels: &mut [bool]) {
            if self.spread {
                spread_within(ctx, ctx.kernel().h(), labels);
            }
        }
        fn extra_reach_h(&self) -> f64 {
            if self.spread {
                1.0
            } else {
                0.0
            }
        }
    }

    impl SphMethod for FewNeighbours {
        const RADII_REFUSAL: &'static str = "toy";
        const SOLID_REFUSAL: &'static str = "toy solids";
        fn param_list(&self) -> Params {
            Params(self.smoothing.param_infos().to_vec())
        }
    }

    crate::impl_sph_detector!(FewNeighbours);

    fn lattice(n: usize) -> ParticleSet<2> {
        let rows: Vec<[f64; 2]> = (0..n * n)
            .map(|k| [(k % n) as f64, (k / n) as f64])
            .collect();
        ParticleSet::from_rows(&rows).unwrap()
    }

    #[test]
    fn the_frame_dispatches_classifies_owned_particles_and_refuses_radii() {
        // h = 0.6, support 1.2: a lattice particle sees its 4 axis neighbours, an edge one 3,
        // a corner 2.
        let mut d = FewNeighbours {
            min: 4,
            spread: false,
            smoothing: Smoothing::try_new("few", Kernel::WendlandC2, 0.6).unwrap(),
        };
        let set = lattice(5);
        let r = Radius::new(1.0).unwrap();
        let got = d.detect_2d(&set, r).unwrap();
        for k in 0..25 {
            let (x, y) = (k % 5, k / 5);
            let edge = x == 0 || y == 0 || x == 4 || y == 4;
            assert_eq!(got.labels.is_boundary(k), edge, "{k}");
        }
        let margin = got.margin.unwrap();
        assert_eq!((margin[0], margin[12]), (1.5, -0.5));
        assert_eq!(d.to_string(), "few (kernel=wendland, h_over_r=0.6)");
        assert_eq!(d.halo_width(r), 2.4);
        // The first 5 owned, the rest ghosts: the same labels as the whole set's first 5.
        let owned = d.detect_owned(&set.to_any(), 5, r).unwrap();
        assert_eq!(owned.labels.as_slice(), &got.labels.as_slice()[..5]);
        assert!(d.detect_owned(&set.to_any(), 26, r).is_err());
        let radii = set.clone().with_radii(vec![1.0; 25]).unwrap();
        let err = d.detect_2d(&radii, r).unwrap_err();
        assert!(err.to_string().contains("toy"), "{err}");
        // The shared parameters' checks and messages.
        let err = Smoothing::try_new("few", Kernel::CubicSpline, 0.0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("(0, 100]"), "{err}");
        assert!(Smoothing::try_new("few", Kernel::WendlandC2, f64::NAN).is_err());
        d.smoothing = Smoothing::try_new("few", Kernel::CubicSpline, 0.6).unwrap();
        assert_eq!(d.to_string(), "few (kernel=cubic, h_over_r=0.6)");
    }

    #[test]
    fn finish_spreads_labels_within_its_reach() {
        // h = 1, support 2: a corner has 5 neighbours, the edge particles beside it 7, the
        // other edge particles 8 or more; the spread then flags the particles within 1 of
        // those.
        let d = FewNeighbours {
            min: 8,
            spread: true,
            smoothing: Smoothing::try_new("few", Kernel::WendlandC2, 1.0).unwrap(),
        };
        let set = lattice(7);
        let r = Radius::new(1.0).unwrap();
        let plain = FewNeighbours {
            spread: false,
            ..d.clone()
        };
        let base = plain.detect_2d(&set, r).unwrap().labels;
        let spread = d.detect_2d(&set, r).unwrap().labels;
        for i in 0..49 {
            let near = (0..49).any(|j| {
                base.is_boundary(j) && (set.positions()[i] - set.positions()[j]).norm() <= 1.0
            });
            assert_eq!(spread.is_boundary(i), near, "{i}");
        }
        assert!(spread.boundary_count() > base.boundary_count());
        assert_eq!(d.halo_width(r), 5.0);
    }
}
