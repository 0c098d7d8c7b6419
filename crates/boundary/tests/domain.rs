//! Every registered detector in a domain (walls, solid half-spaces, periodic axes, phases),
//! whatever `boundary::methods()` lists:
//!
//! - walls: the labels of the union of fluid and walls, on the fluid part (every method
//!   takes the walls as ghosts of `detect_owned`, whose contract this is);
//! - solids: honoured (and then, for a certified method, no false negative against `exact`
//!   with the same solids) or refused with an error naming the option;
//! - periodic axes: the labels of the set with its images written out.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary::{
    detector_by_name, methods, AnyParticleSet, DetectError, Domain, HalfSpace, ParticleSet,
    Periodic, Point, Radius,
};
use boundary::{Dim, SupportedDim};

/// A jittered block of spacing 1 with `counts` particles per axis, its lowest layer at
/// height 0.5 (axis 1), and a floor of two layers of wall particles below it.
fn tank<const D: usize>(counts: [usize; D], seed: u64) -> (ParticleSet<D>, ParticleSet<D>)
where
    Dim<D>: SupportedDim,
{
    let mut state = seed;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let total: usize = counts.iter().product();
    let mut fluid = Vec::new();
    for k in 0..total {
        let mut rest = k;
        fluid.push(Point::<D>::from_fn(|axis, _| {
            let c = rest % counts[axis];
            rest /= counts[axis];
            let base = if axis == 1 { c as f64 + 0.5 } else { c as f64 };
            base + 0.3 * next()
        }));
    }
    let mut walls = Vec::new();
    let mut floor = counts;
    floor[1] = 2;
    for (axis, count) in floor.iter_mut().enumerate() {
        if axis != 1 {
            *count += 4;
        }
    }
    let cells: usize = floor.iter().product();
    for k in 0..cells {
        let mut rest = k;
        walls.push(Point::<D>::from_fn(|axis, _| {
            let c = rest % floor[axis];
            rest /= floor[axis];
            if axis == 1 {
                -0.5 - c as f64
            } else {
                c as f64 - 2.0
            }
        }));
    }
    (
        ParticleSet::new(fluid).unwrap(),
        ParticleSet::new(walls).unwrap(),
    )
}

fn union<const D: usize>(a: &ParticleSet<D>, b: &ParticleSet<D>) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    let mut all = a.positions().to_vec();
    all.extend(b.positions());
    ParticleSet::new(all).unwrap()
}

fn check_walls<const D: usize>(counts: [usize; D], r: f64)
where
    AnyParticleSet: From<ParticleSet<D>>,
    Dim<D>: SupportedDim,
{
    let (fluid, walls) = tank(counts, 5);
    let r = Radius::new(r).unwrap();
    let both = AnyParticleSet::from(union(&fluid, &walls));
    let domain = Domain::new().with_walls(walls.clone().into());
    let fluid_any = AnyParticleSet::from(fluid.clone());
    for method in methods() {
        let detector = detector_by_name(method).unwrap();
        let expected = detector.detect(&both, r).unwrap().labels.into_vec();
        let got = detector.detect_in(&fluid_any, &domain, r).unwrap();
        assert_eq!(
            got.detection.labels.as_slice(),
            &expected[..fluid.len()],
            "{method}, {D}D: walls must give the union's labels"
        );
    }
}

#[test]
fn walls_give_every_method_the_labels_of_the_union() {
    check_walls([8, 5], 0.8);
    check_walls([5, 4, 4], 0.95);
}

fn check_solids<const D: usize>(counts: [usize; D], r: f64)
where
    AnyParticleSet: From<ParticleSet<D>>,
    Dim<D>: SupportedDim,
{
    let (fluid, _) = tank(counts, 9);
    let r = Radius::new(r).unwrap();
    let fluid = AnyParticleSet::from(fluid);
    let domain = Domain::new()
        .with_solid(HalfSpace::parse("y<0").unwrap())
        .with_solid(HalfSpace::parse("x<-0.5").unwrap());
    let truth = detector_by_name("exact")
        .unwrap()
        .detect_in(&fluid, &domain, r)
        .unwrap()
        .detection
        .labels;
    let bare = detector_by_name("exact")
        .unwrap()
        .detect(&fluid, r)
        .unwrap()
        .labels;
    assert!(
        truth.boundary_count() < bare.boundary_count(),
        "{D}D: the solids cover the particles resting on them"
    );
    for method in methods() {
        let detector = detector_by_name(method).unwrap();
        match detector.detect_in(&fluid, &domain, r) {
            Ok(got) => {
                let labels = got.detection.labels;
                assert_eq!(labels.len(), fluid.len(), "{method}");
                if detector.certified() {
                    for i in 0..labels.len() {
                        assert!(
                            labels.is_boundary(i) || !truth.is_boundary(i),
                            "{method}, {D}D: particle {i} is a false negative with solids"
                        );
                    }
                }
            }
            Err(e @ DetectError::UnsupportedOption { .. }) => {
                let text = e.to_string();
                assert!(
                    text.contains(&format!(
                        "method '{method}' cannot honour solid half-spaces:"
                    )) && !text.contains("--"),
                    "{method}: {text}"
                );
            }
            Err(e) => panic!("{method}, {D}D: unexpected error {e}"),
        }
    }
}

#[test]
fn solids_are_honoured_without_false_negatives_or_refused_by_name() {
    check_solids([8, 5], 0.8);
    check_solids([5, 4, 4], 0.95);
}

#[test]
fn periodic_images_give_every_method_the_labels_of_the_images_written_out() {
    let (fluid, _) = tank([10, 4], 3);
    let r = Radius::new(0.8).unwrap();
    for method in methods() {
        let detector = detector_by_name(method).unwrap();
        let reach = detector.halo_width(r);
        // A period of at least the method's reach (and at least the block's width plus a gap).
        let period = reach.max(10.0).ceil();
        let mut images = fluid.positions().to_vec();
        for k in [1.0, -1.0, 2.0, -2.0] {
            images.extend(
                fluid
                    .positions()
                    .iter()
                    .map(|p| Point::<2>::new(p[0] + k * period, p[1])),
            );
        }
        let images = AnyParticleSet::from(ParticleSet::new(images).unwrap());
        let expected = detector.detect(&images, r).unwrap().labels.into_vec();
        let domain = Domain::new().with_periodic(Periodic::new(0, -0.5, period - 0.5).unwrap());
        let got = detector
            .detect_in(&AnyParticleSet::from(fluid.clone()), &domain, r)
            .unwrap();
        assert_eq!(
            got.detection.labels.as_slice(),
            &expected[..fluid.len()],
            "{method}: periodic images"
        );
    }
}
