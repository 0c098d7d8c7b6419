//! Subdomains with a 2r halo (slabs, Morton blocks, RCB boxes) give the owned particles
//! exactly the global labels.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{Dim, SupportedDim};
use boundary_scenes::shared_set;

use boundary_core::decompose::{morton_blocks, rcb, slabs, Subdomain};
use boundary_core::{BoundaryDetector, ParticleSet, Radius};
use boundary_exact::ExactDetector;

fn check<const D: usize>(set: &ParticleSet<D>, r: f64)
where
    Dim<D>: SupportedDim,
{
    let radius = Radius::new(r).unwrap();
    let global = ExactDetector::default()
        .detect(&set.to_any(), radius)
        .unwrap()
        .labels;
    let halo = ExactDetector::default().halo_width(radius);
    let mut layouts: Vec<(String, Vec<Subdomain>)> = Vec::new();
    for parts in [2, 3, 8] {
        layouts.push((
            format!("{parts} slabs"),
            slabs(set, parts, 0, halo).unwrap(),
        ));
        layouts.push((
            format!("{parts} Morton blocks"),
            morton_blocks(set, parts, halo).unwrap(),
        ));
        layouts.push((format!("{parts} RCB boxes"), rcb(set, parts, halo).unwrap()));
    }
    for (name, subs) in layouts {
        let mut merged = vec![None; set.len()];
        for sub in &subs {
            let local = sub.particles(set).to_any();
            let d = ExactDetector::default()
                .detect_owned(&local, sub.owned.len(), radius)
                .unwrap();
            assert_eq!(d.labels.len(), sub.owned.len());
            for (k, &i) in sub.owned.iter().enumerate() {
                merged[i] = Some(d.labels.is_boundary(k));
            }
        }
        let merged: Vec<bool> = merged.into_iter().map(|b| b.unwrap()).collect();
        assert_eq!(merged, global.as_slice(), "{name}");
    }
}

#[test]
fn split_scenes_match_the_global_run() {
    if let Some(set) = shared_set::<2>("particles2d/sandim_vortex_spin_frame_100_1698.csv").unwrap()
    {
        check(&set, 0.022105);
    }
    for (file, r) in [
        ("particles3d/splashsurf_dam_break_frame_9_6859.csv", 0.05),
        (
            "particles3d/dualsphysics_dambreak3d_dp0.02_fluid.csv",
            0.0346,
        ),
    ] {
        if let Some(set) = shared_set::<3>(file).unwrap() {
            check(&set, r);
        }
    }
}

#[test]
fn owned_count_larger_than_the_set_is_an_error() {
    let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0]]).unwrap().to_any();
    assert!(ExactDetector::default()
        .detect_owned(&set, 2, Radius::new(1.0).unwrap())
        .is_err());
}
