//! The generators are what they claim (flow fields, integrator, lattices) and `fixtures/` is
//! exactly what they generate today.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{AnyParticleSet, BoundaryDetector, DetectError, Domain, Point, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::{
    all_scenes, enright, fixtures_dir, jittered_lattice_ball, rk4, single_vortex, Manifest, Origin,
    SharedData,
};

/// Central-difference divergence of a field at `p`.
fn divergence<const D: usize>(v: impl Fn(&Point<D>) -> Point<D>, p: &Point<D>) -> f64
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
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
        ExactDetector::default()
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
        // Positions and, for graded scenes, the radii (read through the manifest's column);
        // walls, solids, periodic axes and phases for the scenes with a domain.
        assert_eq!(
            entry.has_domain(),
            !scene.domain.is_bare(),
            "{}",
            entry.name
        );
        let (read, domain) = entry
            .load_in_domain(&dir, &boundary_scenes::data_dir())
            .unwrap();
        assert!(
            read == scene.set,
            "{}: file differs from the generator (run `cargo xtask fixtures`)",
            entry.name
        );
        assert!(
            domain == scene.domain,
            "{}: domain differs from the generator (run `cargo xtask fixtures`)",
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

/// The generated scene `name`.
fn scene(name: &str) -> boundary_scenes::Scene {
    all_scenes().into_iter().find(|s| s.name == name).unwrap()
}

/// The coordinates of the boundary particles of `exact` on `scene` in `domain`.
fn exact_boundary(scene: &boundary_scenes::Scene, domain: &Domain) -> Vec<Vec<f64>> {
    let r = Radius::new(scene.radius).unwrap();
    let d = ExactDetector::default()
        .detect_in(&scene.set, domain, r)
        .unwrap();
    (0..scene.set.len())
        .filter(|&i| d.detection.labels.is_boundary(i))
        .map(|i| scene.set.coords(i).to_vec())
        .collect()
}

/// In the tanks the walls cover the fluid along them: the exact boundary lies at the free
/// surface only (within two spacings of the column's top or open side), while the same
/// fluid without its walls is boundary along the floor too.
#[test]
fn tank_walls_leave_only_the_free_surface() {
    for (name, h, open_side, top) in [
        ("tank_dambreak2d_walls", 0.01, 0.4, 0.6),
        ("tank_dambreak3d_walls", 0.02, 0.2, 0.36),
    ] {
        let s = scene(name);
        let up = s.set.dim() - 1;
        let walled = exact_boundary(&s, &s.domain);
        assert!(!walled.is_empty(), "{name}");
        for p in &walled {
            assert!(
                p[0] > open_side - 2.0 * h || p[up] > top - 2.0 * h,
                "{name}: boundary particle at {p:?} away from the free surface"
            );
        }
        let bare = exact_boundary(&s, &Domain::new());
        assert!(
            bare.iter().any(|p| p[up] < h && p[0] < open_side - 2.0 * h),
            "{name}: without walls the floor is boundary"
        );
    }
}

/// The solid tank holds the same fluid as the walled one: where a method honours solids, the
/// boundary lies at the free surface only; a method without a rule for solids says so rather
/// than ignoring them.
#[test]
fn the_solid_tank_is_five_half_spaces_around_the_walled_tank_fluid() {
    let solid = scene("tank_dambreak3d_solids");
    let walled = scene("tank_dambreak3d_walls");
    assert!(solid.set == walled.set);
    let faces: Vec<String> = solid
        .domain
        .solids()
        .half_spaces()
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(faces, ["x<0", "x>0.4", "y<0", "y>0.3", "z<0"]);
    // The faces along the column lie half a spacing (0.01) beyond its outermost layer
    // (jitter 0.001); the far face x>0.4 lies across the tank's empty half.
    for h in solid.domain.solids().half_spaces() {
        if h.to_string() == "x>0.4" {
            continue;
        }
        let nearest = (0..solid.set.len())
            .map(|i| h.fluid_depth(solid.set.coords(i)))
            .fold(f64::INFINITY, f64::min);
        assert!((nearest - 0.01).abs() <= 0.0011, "{h}: {nearest}");
    }
    let r = Radius::new(solid.radius).unwrap();
    match ExactDetector::default().detect_in(&solid.set, &solid.domain, r) {
        Ok(d) => {
            for i in (0..solid.set.len()).filter(|&i| d.detection.labels.is_boundary(i)) {
                let p = solid.set.coords(i);
                assert!(p[0] > 0.16 || p[2] > 0.32, "boundary particle at {p:?}");
            }
        }
        Err(e) => assert!(matches!(e, DetectError::UnsupportedOption { .. }), "{e}"),
    }
}

/// The periodic channel has no ends: with its period the boundary is the wavy free surface
/// only; cut open (walls alone), its two ends are boundary down to the floor.
#[test]
fn the_periodic_channel_has_no_ends() {
    let s = scene("channel2d_periodic");
    let h = 0.01;
    let surface = |x: f64| 0.2 + 0.03 * (2.0 * std::f64::consts::PI * x).sin();
    let periodic = exact_boundary(&s, &s.domain);
    // About one particle per column of the 100 (a few columns are covered by their
    // neighbours on the wave's slopes).
    assert!(periodic.len() >= 90, "{}", periodic.len());
    for p in &periodic {
        assert!(p[1] > surface(p[0]) - 2.0 * h, "boundary at {p:?}");
    }
    let walls = Domain::new().with_walls(s.domain.walls().unwrap().clone());
    let open = exact_boundary(&s, &walls);
    assert!(open.iter().any(|p| p[0] < h && p[1] < 0.1), "open left end");
    assert!(
        open.iter().any(|p| p[0] > 1.0 - h && p[1] < 0.1),
        "open right end"
    );
}

/// The pool's interfaces lie along the layer boundary (y = 0.2) and the droplet's circle; its
/// free surface is the top of the light layer.
#[test]
fn the_pool_has_interfaces_at_the_layers_and_the_droplet() {
    let s = scene("pool_droplet2d_phases");
    let h = 0.01;
    let phases = s.domain.phases().unwrap();
    assert_eq!(phases.len(), s.set.len());
    let heavy = phases.iter().filter(|&&k| k == 0).count();
    assert!(heavy > 1200 && heavy < s.set.len() - 1000, "{heavy}");
    let r = Radius::new(s.radius).unwrap();
    let d = ExactDetector::default()
        .detect_in(&s.set, &s.domain, r)
        .unwrap();
    let interface = d.interface.unwrap();
    let (mut at_layer, mut at_drop) = (0, 0);
    for i in 0..s.set.len() {
        let p = s.set.coords(i);
        if d.detection.labels.is_boundary(i) {
            assert!(p[1] > 0.4 - 2.0 * h, "free surface at {p:?}");
        }
        if interface.is_boundary(i) {
            let to_drop = ((p[0] - 0.3).hypot(p[1] - 0.3) - 0.05).abs();
            assert!(
                (p[1] - 0.2).abs() < 2.0 * h || to_drop < 2.0 * h,
                "interface at {p:?}"
            );
            if (p[1] - 0.2).abs() < 2.0 * h {
                at_layer += 1;
            } else {
                at_drop += 1;
            }
        }
    }
    // Both sides of the layer boundary across the pool's 60 columns, both sides of the
    // droplet's circle.
    assert!(at_layer >= 100, "{at_layer}");
    assert!(at_drop >= 40, "{at_drop}");
}
