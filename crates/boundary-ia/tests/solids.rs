//! `ia` with solid half-spaces stays certified: on lattice blocks resting on floors, in tanks,
//! with per-particle radii and ghosts (`boundary_scenes::solids`), no particle that a dense
//! sampling of its sphere proves boundary is labelled interior, a particle wholly in a solid
//! is interior, and adding the solids never turns an interior particle boundary.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{
    BoundaryDetector, DetectError, Domain, HalfSpace, ParticleSet, Radius, Solids,
};
use boundary_ia::{IaDetector, IaParams};
use boundary_scenes::certify::jittered_lattice;
use boundary_scenes::solids::certify_with_solids;

#[test]
fn certified_with_solids_at_depths_2_4_6_8() {
    for depth in [2, 4, 6, 8] {
        let report = certify_with_solids(|case, solids| {
            IaDetector::try_new(IaParams { depth })
                .unwrap()
                .detect_owned_in(&case.set, case.owned, solids, case.r())
                .unwrap()
                .labels
        });
        match report {
            Ok(lines) => lines
                .iter()
                .for_each(|line| println!("depth {depth}: {line}")),
            Err(failures) => panic!("depth {depth}: {failures:#?}"),
        }
    }
}

#[test]
fn without_solids_the_labels_are_those_of_detect_owned() {
    let set = ParticleSet::from_rows(&jittered_lattice::<3>(6, 0.15, 4))
        .unwrap()
        .to_any();
    let r = Radius::new(1.2).unwrap();
    let ia = IaDetector::default();
    let owned = ia.detect_owned(&set, 100, r).unwrap();
    let bare = ia.detect_owned_in(&set, 100, &Solids::new(), r).unwrap();
    assert_eq!(owned, bare);
}

#[test]
fn a_floor_makes_the_bottom_row_interior_through_the_domain() {
    // A 10 x 10 square lattice at r = 1.2 on the floor y < -0.5: only the sides and the top
    // row stay boundary.
    let rows: Vec<[f64; 2]> = (0..100)
        .map(|k| [(k % 10) as f64, (k / 10) as f64])
        .collect();
    let set = ParticleSet::from_rows(&rows).unwrap().to_any();
    let r = Radius::new(1.2).unwrap();
    let domain = Domain::new().with_solid(HalfSpace::parse("y<-0.5").unwrap());
    let labels = IaDetector::default()
        .detect_in(&set, &domain, r)
        .unwrap()
        .detection
        .labels;
    let expected: Vec<bool> = rows
        .iter()
        .map(|p| p[0] == 0.0 || p[0] == 9.0 || p[1] == 9.0)
        .collect();
    assert_eq!(labels.as_slice(), &expected[..]);
}

#[test]
fn a_solid_on_a_missing_axis_is_an_error() {
    let set = ParticleSet::from_rows(&[[0.0, 0.0]]).unwrap().to_any();
    let mut solids = Solids::new();
    solids.push(HalfSpace::parse("z<0").unwrap());
    let e = IaDetector::default()
        .detect_owned_in(&set, 1, &solids, Radius::new(1.0).unwrap())
        .unwrap_err();
    assert!(matches!(e, DetectError::Method { .. }), "{e}");
    assert!(e.to_string().contains("z<0"), "{e}");
}
