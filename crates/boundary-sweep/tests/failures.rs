//! The failure section end to end: a sweep over two fixtures (a stretched 2D flow and a 3D
//! sheet with a filament and droplets) profiles the misses of every method without a
//! certificate, keeps its worst scene by M for the picture, lists it in the report, and
//! writes the picture files.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_scenes::fixtures_dir;
use boundary_sweep::failures::{approximate_methods, ranked};
use boundary_sweep::{default_configs, plots, report, run, Options, SceneSpec};

fn spec(name: &str, dim: usize, radius: f64) -> SceneSpec {
    SceneSpec {
        name: name.into(),
        dim,
        path: fixtures_dir().join(format!("{name}.csv")),
        radius,
        expected_boundary: None,
        origin: "fixture".into(),
        about: format!("the {name} fixture"),
        radius_attribute: None,
        domain: Default::default(),
    }
}

#[test]
fn sweep_profiles_the_misses_and_draws_each_approximate_methods_worst_scene() {
    let methods = boundary::methods();
    let opts = Options {
        scenes: vec![
            spec("vortex2d_t1", 2, 0.0075),
            spec("sheet_ligament_droplets3d", 3, 0.15),
        ],
        configs: default_configs(&methods, true),
        single_thread: false,
        threads: 1,
    };
    let outcome = run(&opts, &mut |_| {}).unwrap();
    let approximate: Vec<&str> = methods
        .iter()
        .copied()
        .filter(|m| !boundary::detector_by_name(m).unwrap().certified())
        .collect();
    assert!(!approximate.is_empty());
    assert_eq!(approximate_methods(&outcome.rows), approximate);
    for row in &outcome.rows {
        // Exactly the default rows of the approximate methods carry a miss profile, and it
        // accounts for every particle and every miss.
        assert_eq!(row.misses.is_some(), !row.certified, "{row:?}");
        if let (Some(p), Some(c)) = (row.misses, row.confusion) {
            assert_eq!(p.fn_.iter().sum::<usize>() as u64, c.fn_);
            assert_eq!(p.fp.iter().sum::<usize>() as u64, c.fp);
            let all: usize = p.boundary.iter().chain(&p.interior).sum();
            assert_eq!(all, row.n);
        }
    }
    for method in &approximate {
        let worst = ranked(&outcome.rows, method)[0];
        let pic = outcome
            .failure_pictures
            .iter()
            .find(|p| p.method == *method);
        if worst.confusion.unwrap().m() < 1.0 {
            let pic = pic.unwrap();
            assert_eq!(pic.scene, worst.scene, "{method}");
            assert_eq!(pic.m, worst.confusion.unwrap().m());
            assert_eq!(pic.coords.len(), worst.n * worst.dim);
        } else {
            assert!(pic.is_none(), "{method} has no miss but a picture");
        }
    }
    let md = report::report_md(&outcome, "test");
    assert!(md.contains("## Where the approximate methods fail"));
    for method in &approximate {
        assert!(md.contains(&format!("### `{method}`")), "{method}");
    }
    let dir = tempfile::tempdir().unwrap();
    plots::register_font().unwrap();
    let written = plots::write_failures(&outcome.failure_pictures, dir.path()).unwrap();
    assert_eq!(written.len(), 2 * outcome.failure_pictures.len());
    for pic in &outcome.failure_pictures {
        for ext in ["svg", "png"] {
            let file = dir.path().join(plots::failure_file(&pic.method, ext));
            assert!(std::fs::metadata(&file).unwrap().len() > 1000, "{file:?}");
        }
        let svg = std::fs::read_to_string(dir.path().join(plots::failure_file(&pic.method, "svg")))
            .unwrap();
        assert!(svg.contains(&pic.scene), "{}", pic.method);
    }
    // At least one approximate method misses something on these scenes, so that the picture
    // path is exercised (muller loses the single-layer sheet).
    assert!(!outcome.failure_pictures.is_empty());
    assert!(outcome.failure_pictures.iter().any(|p| p.dim == 3));
}
