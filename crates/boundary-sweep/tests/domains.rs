//! Scenes with a domain end to end: every method classified in the scene's domain and scored
//! against `exact` in the same domain, the methods without a rule for solids reported `n/a`,
//! the interface counts of a two-phase scene, the report's section and the pictures.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_scenes::{data_dir, fixtures_dir, Manifest};
use boundary_sweep::{default_configs, plots, report, run, Options, SceneSpec};

fn spec(name: &str) -> SceneSpec {
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    let entry = manifest.scene.iter().find(|s| s.name == name).unwrap();
    SceneSpec {
        name: name.into(),
        dim: entry.dim,
        path: entry.path(&fixtures_dir(), &data_dir()),
        radius: entry.radius,
        expected_boundary: None,
        origin: "fixture".into(),
        about: String::new(),
        radius_attribute: None,
        domain: entry.scene_domain(&fixtures_dir(), &data_dir()).unwrap(),
    }
}

#[test]
fn domain_scenes_are_scored_in_their_domain() {
    let methods = boundary::methods();
    let opts = Options {
        scenes: vec![
            spec("pool_droplet2d_phases"),
            spec("tank_dambreak3d_solids"),
        ],
        configs: default_configs(&methods, true),
        single_thread: false,
        threads: 1,
    };
    let outcome = run(&opts, &mut |_| {}).unwrap();
    assert!(outcome.skipped.is_empty(), "{:?}", outcome.skipped);
    let row = |scene: &str, method: &str| {
        outcome
            .rows
            .iter()
            .find(|r| r.scene == scene && r.method == method && r.is_default)
            .unwrap()
    };
    // The pool: with its walls only the top of the light layer is free surface (60 columns;
    // bare, the walls' sides and floor would add hundreds), and exact's interfaces are
    // counted and scored for every method.
    let exact = row("pool_droplet2d_phases", "exact");
    let c = exact.confusion.unwrap();
    assert_eq!((c.tp, c.fp, c.fn_), (60, 0, 0));
    let interface = exact.interface.unwrap();
    assert!(interface > 100, "{interface}");
    for m in &methods {
        let r = row("pool_droplet2d_phases", m);
        assert!(
            r.interface.is_some() && r.interface_confusion.is_some(),
            "{m}"
        );
    }
    // The solid tank: a method that refuses solids is n/a with the reason, never a failure
    // of the sweep; every method that honours them is scored.
    for m in &methods {
        let r = row("tank_dambreak3d_solids", m);
        match r.confusion {
            Some(c) => assert!(!r.certified || c.fn_ == 0, "{m}"),
            None => {
                assert!(r.unsupported, "{m}: {:?}", r.error);
                assert!(r.error.as_deref().unwrap().contains("solid"), "{m}");
            }
        }
    }
    let md = report::report_md(&outcome, "test");
    let section = &md[md.find("## Scenes with a domain").unwrap()..];
    assert!(section.contains("### `pool_droplet2d_phases`"), "{section}");
    assert!(section.contains("phases (phase)") && section.contains("walls ("));
    assert!(section.contains(&format!("{interface} on an interface")));
    assert!(section.contains("solids x<0 x>0.4 y<0 y>0.3 z<0"));
    assert!(section.contains("domain_tank_dambreak3d_solids.png"));
    if methods
        .iter()
        .any(|m| row("tank_dambreak3d_solids", m).unsupported)
    {
        assert!(
            section.contains("| n/a: cannot honour solid half-spaces"),
            "{section}"
        );
    }

    plots::register_font().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let written = plots::write_all(&outcome, dir.path()).unwrap();
    for scene in ["pool_droplet2d_phases", "tank_dambreak3d_solids"] {
        let png = dir.path().join(plots::domain_file(scene, "png"));
        assert!(written.contains(&png), "{scene}");
    }
    let svg = std::fs::read_to_string(dir.path().join("domain_pool_droplet2d_phases.svg")).unwrap();
    assert!(svg.contains(&format!("{interface} interface")), "caption");
    // The 3D picture is the slab across y: one layer of the 15 (r/2 = half a spacing).
    let pic = outcome
        .domain_pictures
        .iter()
        .find(|p| p.scene == "tank_dambreak3d_solids")
        .unwrap();
    assert_eq!(pic.axes, [0, 2]);
    assert!(
        pic.points.len() * 10 < 2700 && pic.points.len() >= 150,
        "{}",
        pic.points.len()
    );
    assert_eq!(
        pic.solids.len(),
        3,
        "x<0, x>0.4 and z<0 cross the x–z plane"
    );
}
