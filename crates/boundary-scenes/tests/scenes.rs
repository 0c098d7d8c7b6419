//! The generators are what they claim (flow fields, integrator, lattices) and `fixtures/` is
//! exactly what they generate today.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{AnyParticleSet, BoundaryDetector, Point, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::{
    all_scenes, enright, fixtures_dir, jittered_lattice_ball, rk4, single_vortex, Manifest, Origin,
    SharedData,
};

/// Central-difference divergence of a field at `p`.
fn divergence<const D: usize>(v: impl Fn(&Point<D>) -> Point<D>, p: &Point<D>) -> f64 {
    let e = 1e-5;
    (0..D)
        .map(|a| {
            let mut dp = Point::<D>::zeros();
            dp[a] = e;
            (v(&(p + dp))[a] - v(&(p - dp))[a]) / (2.0 * e)
        })
        .sum()
}

#[test]
fn flow_fields_are_divergence_free() {
    for k in 0..50 {
        let s = k as f64 / 50.0;
        let p2 = Point::<2>::new(0.1 + 0.8 * s, 0.9 - 0.7 * s * s);
        assert!(divergence(|q| single_vortex(q, 1.3, 8.0), &p2).abs() < 1e-6);
        let p3 = Point::<3>::new(0.1 + 0.8 * s, 0.3 + 0.5 * s * s, 0.8 - 0.6 * s);
        assert!(divergence(|q| enright(q, 0.4, 3.0), &p3).abs() < 1e-6);
    }
}

#[test]
fn rk4_is_fourth_order_and_the_vortex_flow_reverses() {
    // dp/dt = p: p(1) = e. Halving the step cuts the error by about 2^4.
    let err = |steps| (rk4(Point::<1>::new(1.0), 0.0, 1.0, steps, |p, _| *p)[0] - 1f64.exp()).abs();
    let ratio = err(10) / err(20);
    assert!((12.0..20.0).contains(&ratio), "ratio {ratio}");
    // The periodic fields return every particle to its start at t = T.
    let p = Point::<2>::new(0.5, 0.75 - 0.12);
    let back = rk4(p, 0.0, 8.0, 1600, |q, t| single_vortex(q, t, 8.0));
    assert!((back - p).norm() < 1e-6, "{}", (back - p).norm());
    let q = Point::<3>::new(0.35, 0.35, 0.5);
    let back = rk4(q, 0.0, 3.0, 600, |x, t| enright(x, t, 3.0));
    assert!((back - q).norm() < 1e-6);
}

#[test]
fn the_vortex_stretches_the_disk_into_a_filament_and_brings_it_back() {
    let scenes = all_scenes();
    let get = |name: &str| scenes.iter().find(|s| s.name == name).unwrap();
    let (t0, t4, t8) = (get("vortex2d_t0"), get("vortex2d_t4"), get("vortex2d_t8"));
    let r = Radius::new(t0.radius).unwrap();
    let count = |set: &AnyParticleSet| {
        ExactDetector
            .detect(set, r)
            .unwrap()
            .labels
            .boundary_count()
    };
    // At maximum stretch the filament has far more boundary particles than the disk; at T the
    // disk is back (same positions to the integrator's accuracy) and so are its labels.
    assert!(count(&t4.set) > 2 * count(&t0.set));
    assert_eq!(count(&t8.set), count(&t0.set));
}

#[test]
fn jittered_ball_has_about_the_asked_count() {
    let (set, radius) = jittered_lattice_ball(20_000, 0.15, 7);
    let n = set.len() as f64;
    assert!((n / 20_000.0 - 1.0).abs() < 0.02, "{n}");
    assert!(set
        .positions()
        .iter()
        .all(|p| p.norm() <= radius + 0.15 * 3f64.sqrt()));
}

#[test]
fn fixtures_on_disk_are_what_the_generators_make() {
    let dir = fixtures_dir();
    let manifest = Manifest::load(&dir.join("scenes.toml")).unwrap();
    let scenes = all_scenes();
    let fixtures: Vec<_> = manifest
        .scene
        .iter()
        .filter(|s| s.origin == Origin::Fixture)
        .collect();
    assert_eq!(fixtures.len(), scenes.len(), "run `cargo xtask fixtures`");
    for (entry, scene) in fixtures.iter().zip(&scenes) {
        assert_eq!(entry.name, scene.name, "run `cargo xtask fixtures`");
        assert_eq!(
            (entry.dim, entry.n, entry.radius),
            (scene.set.dim(), scene.set.len(), scene.radius)
        );
        assert_eq!(
            entry.radius_attribute.is_some(),
            scene.set.radii().is_some(),
            "{}: radii",
            entry.name
        );
        // Positions and, for graded scenes, the radii (read through the manifest's column).
        let read = entry.load(&dir, &boundary_scenes::data_dir()).unwrap();
        assert!(
            read == scene.set,
            "{}: file differs from the generator (run `cargo xtask fixtures`)",
            entry.name
        );
    }
}

#[test]
fn shared_entries_name_existing_files_with_the_stated_counts() {
    let data = SharedData::from_env();
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    for entry in manifest.scene.iter().filter(|s| s.origin == Origin::Shared) {
        let Some(set) = data.scene(entry, &fixtures_dir()).unwrap() else {
            continue;
        };
        assert_eq!(set.len(), entry.n, "{}", entry.name);
    }
}

#[test]
fn mesh_entries_sample_to_the_stated_counts() {
    let data = SharedData::from_env();
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    let meshes: Vec<_> = manifest
        .scene
        .iter()
        .filter(|s| s.origin == Origin::Mesh)
        .collect();
    assert_eq!(meshes.len(), boundary_scenes::mesh::MESH_SCENES.len());
    for entry in meshes {
        let Some(set) = data.scene(entry, &fixtures_dir()).unwrap() else {
            continue;
        };
        assert_eq!((set.dim(), set.len()), (3, entry.n), "{}", entry.name);
    }
}
